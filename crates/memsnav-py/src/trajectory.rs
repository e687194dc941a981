//! `Trajectory`: random, scripted and profile trajectories with their exact
//! IMU truth, as numpy arrays.

use std::path::PathBuf;

use memsnav_core::geodesy::Geodetic;
use memsnav_core::random;
use memsnav_core::sensors::DEFAULT_SAMPLE_RATE_HZ;
use memsnav_core::trajectory::{RandomTrajectoryConfig, Segment, Trajectory};
use memsnav_py_macros::catch_panics;
use nalgebra::Vector3;
use numpy::{PyArray1, PyArray2, PyArray3};
use pyo3::exceptions::PyValueError;
use pyo3::prelude::*;
use pyo3::types::PySequence;

use crate::convert;
use crate::errors::IntoPyResult;

/// Truth of a vehicle's motion at the IMU rate: position, velocity and
/// attitude in ECEF, and the exact specific force and angular rate in body
/// axes (Earth rotation and the gravity model of ``gravity_ecef`` included).
#[pyclass(frozen, name = "Trajectory", module = "memsnav._memsnav")]
pub struct PyTrajectory {
    pub inner: Trajectory,
}

fn origin_from(obj: Option<&Bound<'_, PyAny>>) -> PyResult<Geodetic> {
    match obj {
        None => Ok(RandomTrajectoryConfig::default().origin),
        Some(o) => {
            let v = convert::vector3(o, "origin")?;
            Ok(Geodetic::new(v.x, v.y, v.z))
        }
    }
}

fn segment_from(item: &Bound<'_, PyAny>, i: usize) -> PyResult<Segment> {
    let name = format!("segments[{i}]");
    let bad = |reason: &str| PyValueError::new_err(format!("{name}: {reason}"));
    let seq = item
        .cast::<PySequence>()
        .map_err(|_| bad("expected a tuple (kind, duration_s[, value])"))?;
    let len = seq.len()?;
    if len == 0 {
        return Err(bad("expected a tuple (kind, duration_s[, value])"));
    }
    let kind: String = seq
        .get_item(0)?
        .extract()
        .map_err(|_| bad("the first element must be the kind, a string"))?;
    let number = |k: usize, what: &str| -> PyResult<f64> {
        seq.get_item(k)?
            .extract::<f64>()
            .map_err(|_| bad(&format!("{what} must be a number")))
    };
    let expect = |n: usize, form: &str| {
        if len == n {
            Ok(())
        } else {
            Err(bad(&format!("{kind:?} takes {form}, got {} elements", len)))
        }
    };
    let segment = match kind.as_str() {
        "accelerate" => {
            expect(3, "(\"accelerate\", duration_s, target_speed_m_s)")?;
            Segment::Accelerate {
                duration_s: number(1, "duration_s")?,
                target_speed_m_s: number(2, "target_speed_m_s")?,
            }
        }
        "cruise" => {
            expect(2, "(\"cruise\", duration_s)")?;
            Segment::Cruise {
                duration_s: number(1, "duration_s")?,
            }
        }
        "turn" => {
            expect(3, "(\"turn\", duration_s, heading_change_rad)")?;
            Segment::Turn {
                duration_s: number(1, "duration_s")?,
                heading_change_rad: number(2, "heading_change_rad")?,
            }
        }
        "climb" => {
            expect(3, "(\"climb\", duration_s, path_angle_rad)")?;
            Segment::Climb {
                duration_s: number(1, "duration_s")?,
                path_angle_rad: number(2, "path_angle_rad")?,
            }
        }
        "stop" => {
            expect(2, "(\"stop\", duration_s)")?;
            Segment::Stop {
                duration_s: number(1, "duration_s")?,
            }
        }
        other => {
            return Err(bad(&format!(
                "unknown kind {other:?}; expected accelerate, cruise, turn, climb or stop"
            )))
        }
    };
    Ok(segment)
}

#[catch_panics]
#[pymethods]
impl PyTrajectory {
    /// Random land-vehicle motion: cruises, speed changes (sometimes to a
    /// stop), turns, road slope, body lean and squat; C² smooth.
    ///
    /// Arguments; ``None`` takes the core's default
    /// (``RandomTrajectoryConfig``), given in brackets:
    ///
    /// - ``duration``, s [600]; ``rate``, Hz [100].
    /// - ``seed``: the random stream, an integer in [0, 2**64) [0: the same
    ///   trajectory every call].
    /// - ``origin``: [latitude rad, longitude rad, height m] of the start
    ///   [Toulouse, 43.6° N 1.44° E 150 m].
    /// - ``heading``: the initial heading, rad from north [random].
    /// - ``max_speed``, m/s [30]; ``max_longitudinal_acceleration``, m/s²
    ///   [2]; ``max_lateral_acceleration``, m/s² [3]; ``max_yaw_rate``, rad/s
    ///   [0.4]; ``max_slope``, rad [0.05].
    /// - ``stationary_start``: seconds at rest before moving off [0].
    #[staticmethod]
    #[pyo3(signature = (
        duration=None, rate=None, seed=None, origin=None, *, heading=None,
        max_speed=None, max_longitudinal_acceleration=None,
        max_lateral_acceleration=None, max_yaw_rate=None, max_slope=None,
        stationary_start=None
    ))]
    fn random(
        py: Python<'_>,
        duration: Option<f64>,
        rate: Option<f64>,
        seed: Option<&Bound<'_, PyAny>>,
        origin: Option<&Bound<'_, PyAny>>,
        heading: Option<f64>,
        max_speed: Option<f64>,
        max_longitudinal_acceleration: Option<f64>,
        max_lateral_acceleration: Option<f64>,
        max_yaw_rate: Option<f64>,
        max_slope: Option<f64>,
        stationary_start: Option<f64>,
    ) -> PyResult<Self> {
        // None: the core's default (RandomTrajectoryConfig).
        let d = RandomTrajectoryConfig::default();
        let config = RandomTrajectoryConfig {
            duration_s: duration.unwrap_or(d.duration_s),
            rate_hz: rate.unwrap_or(d.rate_hz),
            origin: origin_from(origin)?,
            initial_heading_rad: heading,
            max_speed_m_s: max_speed.unwrap_or(d.max_speed_m_s),
            max_longitudinal_acceleration_m_s2: max_longitudinal_acceleration
                .unwrap_or(d.max_longitudinal_acceleration_m_s2),
            max_lateral_acceleration_m_s2: max_lateral_acceleration
                .unwrap_or(d.max_lateral_acceleration_m_s2),
            max_yaw_rate_rad_s: max_yaw_rate.unwrap_or(d.max_yaw_rate_rad_s),
            max_slope_rad: max_slope.unwrap_or(d.max_slope_rad),
            stationary_start_s: stationary_start.unwrap_or(d.stationary_start_s),
            ..d
        };
        let mut rng = random::from_optional_seed(convert::seed(seed)?);
        let inner = py.detach(|| Trajectory::random(&config, &mut rng)).py()?;
        Ok(Self { inner })
    }

    /// Scripted motion from rest.
    ///
    /// - `segments`: a list of manoeuvres, each a tuple:
    ///   ``("accelerate", duration_s, target_speed_m_s)``,
    ///   ``("cruise", duration_s)``, ``("turn", duration_s,
    ///   heading_change_rad)`` (positive right), ``("climb", duration_s,
    ///   path_angle_rad)`` (ramps up and back to level),
    ///   ``("stop", duration_s)``.
    /// - `origin`: [latitude rad, longitude rad, height m] of the start
    ///   [Toulouse, as `Trajectory.random`].
    /// - `heading`: the initial heading, rad from north [0].
    /// - `rate`: Hz [100].
    #[staticmethod]
    #[pyo3(signature = (segments, origin=None, heading=0.0, rate=None))]
    fn from_segments(
        py: Python<'_>,
        segments: &Bound<'_, PyAny>,
        origin: Option<&Bound<'_, PyAny>>,
        heading: f64,
        rate: Option<f64>,
    ) -> PyResult<Self> {
        let rate = rate.unwrap_or(DEFAULT_SAMPLE_RATE_HZ);
        let items = segments
            .try_iter()
            .map_err(|_| PyValueError::new_err("segments: expected a list of tuples"))?;
        let mut parsed = Vec::new();
        for (i, item) in items.enumerate() {
            parsed.push(segment_from(&item?, i)?);
        }
        let origin = origin_from(origin)?;
        let inner = py
            .detach(|| Trajectory::from_segments(origin, heading, &parsed, rate))
            .py()?;
        Ok(Self { inner })
    }

    /// A profile of Groves' book software, smoothed by splines through
    /// knots 0.5 s apart.
    ///
    /// - `path`: the CSV file (t, lat, lon deg, h m, v_NED m/s, roll, pitch,
    ///   yaw deg); a ParseError names its file and line.
    /// - `rate`: the samples' rate, Hz [100].
    #[staticmethod]
    #[pyo3(signature = (path, rate=None))]
    fn from_profile(py: Python<'_>, path: PathBuf, rate: Option<f64>) -> PyResult<Self> {
        let rate = rate.unwrap_or(DEFAULT_SAMPLE_RATE_HZ);
        let inner = py.detach(|| Trajectory::from_profile(&path, rate)).py()?;
        Ok(Self { inner })
    }

    /// Sample times, s, shape (N,).
    #[getter]
    fn time<'py>(&self, py: Python<'py>) -> Bound<'py, PyArray1<f64>> {
        PyArray1::from_slice(py, &self.inner.time_s)
    }

    /// ECEF position, m, shape (N, 3).
    #[getter]
    fn position_ecef<'py>(&self, py: Python<'py>) -> Bound<'py, PyArray2<f64>> {
        convert::vectors_to_numpy(py, &self.inner.position_ecef)
    }

    /// ECEF velocity, m/s, shape (N, 3).
    #[getter]
    fn velocity_ecef<'py>(&self, py: Python<'py>) -> Bound<'py, PyArray2<f64>> {
        convert::vectors_to_numpy(py, &self.inner.velocity_ecef)
    }

    /// Body-to-ECEF rotation matrices, shape (N, 3, 3).
    #[getter]
    fn attitude<'py>(&self, py: Python<'py>) -> Bound<'py, PyArray3<f64>> {
        convert::matrices3_to_numpy(py, &self.inner.c_b_e)
    }

    /// True specific force f_ib^b, m/s², shape (N, 3).
    #[getter]
    fn specific_force<'py>(&self, py: Python<'py>) -> Bound<'py, PyArray2<f64>> {
        convert::vectors_to_numpy(py, &self.inner.specific_force_b)
    }

    /// True angular rate ω_ib^b, rad/s, shape (N, 3).
    #[getter]
    fn angular_rate<'py>(&self, py: Python<'py>) -> Bound<'py, PyArray2<f64>> {
        convert::vectors_to_numpy(py, &self.inner.angular_rate_b)
    }

    /// [latitude rad, longitude rad, height m] of each sample, shape (N, 3).
    fn position_geodetic<'py>(&self, py: Python<'py>) -> Bound<'py, PyArray2<f64>> {
        let g: Vec<Vector3<f64>> = self
            .inner
            .position_geodetic()
            .iter()
            .map(|g| Vector3::new(g.latitude_rad, g.longitude_rad, g.height_m))
            .collect();
        convert::vectors_to_numpy(py, &g)
    }

    /// NED velocity at each sample, m/s, shape (N, 3).
    fn velocity_ned<'py>(&self, py: Python<'py>) -> Bound<'py, PyArray2<f64>> {
        convert::vectors_to_numpy(py, &self.inner.velocity_ned())
    }

    /// [roll, pitch, yaw] of the body relative to local NED, rad, shape (N, 3).
    fn euler_ned<'py>(&self, py: Python<'py>) -> Bound<'py, PyArray2<f64>> {
        convert::vectors_to_numpy(py, &self.inner.euler_ned())
    }

    fn __len__(&self) -> usize {
        self.inner.len()
    }

    fn __repr__(&self) -> String {
        let t = &self.inner.time_s;
        format!(
            "Trajectory({} samples, {:.3} s to {:.3} s)",
            t.len(),
            t[0],
            t[t.len() - 1]
        )
    }
}

pub fn register(m: &Bound<'_, PyModule>) -> PyResult<()> {
    m.add_class::<PyTrajectory>()?;
    Ok(())
}
