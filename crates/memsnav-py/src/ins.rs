//! `strapdown`, `strapdown_increments`, `imu_increments`: whole series in
//! one call, with the GIL released.

use memsnav_core::ins::{self, NavState};
use memsnav_py_macros::catch_panics;
use nalgebra::Vector3;
use numpy::{PyArray1, PyArray2, PyArray3};
use pyo3::exceptions::PyValueError;
use pyo3::prelude::*;

use crate::convert;
use crate::errors::IntoPyResult;

/// An INS solution: the state at every input time.
#[pyclass(frozen, name = "NavSolution", module = "memsnav._memsnav")]
pub struct PyNavSolution {
    time_s: Vec<f64>,
    states: Vec<NavState>,
}

#[catch_panics]
#[pymethods]
impl PyNavSolution {
    /// Times, s, shape (N,).
    #[getter]
    fn time<'py>(&self, py: Python<'py>) -> Bound<'py, PyArray1<f64>> {
        PyArray1::from_slice(py, &self.time_s)
    }

    /// ECEF position, m, shape (N, 3).
    #[getter]
    fn position_ecef<'py>(&self, py: Python<'py>) -> Bound<'py, PyArray2<f64>> {
        let v: Vec<Vector3<f64>> = self.states.iter().map(|s| s.position_ecef).collect();
        convert::vectors_to_numpy(py, &v)
    }

    /// ECEF velocity, m/s, shape (N, 3).
    #[getter]
    fn velocity_ecef<'py>(&self, py: Python<'py>) -> Bound<'py, PyArray2<f64>> {
        let v: Vec<Vector3<f64>> = self.states.iter().map(|s| s.velocity_ecef).collect();
        convert::vectors_to_numpy(py, &v)
    }

    /// Body-to-ECEF rotation matrices, shape (N, 3, 3).
    #[getter]
    fn attitude<'py>(&self, py: Python<'py>) -> Bound<'py, PyArray3<f64>> {
        let c: Vec<_> = self.states.iter().map(|s| s.c_b_e).collect();
        convert::matrices3_to_numpy(py, &c)
    }

    fn __len__(&self) -> usize {
        self.states.len()
    }

    fn __repr__(&self) -> String {
        format!("NavSolution({} epochs)", self.states.len())
    }
}

fn initial_state(
    position_ecef: &Bound<'_, PyAny>,
    velocity_ecef: &Bound<'_, PyAny>,
    attitude: &Bound<'_, PyAny>,
) -> PyResult<NavState> {
    Ok(NavState {
        position_ecef: convert::vector3(position_ecef, "position_ecef")?,
        velocity_ecef: convert::vector3(velocity_ecef, "velocity_ecef")?,
        c_b_e: convert::matrix3(attitude, "attitude")?,
    })
}

/// Strapdown INS in ECEF (Earth rate, Coriolis, J2 gravity) from
/// instantaneous samples (Groves ch. 5).
///
/// - ``time`` (N,) s, increasing.
/// - ``specific_force`` (N, 3) m/s² and ``angular_rate`` (N, 3) rad/s: the
///   IMU's samples in body axes (x forward, y right, z down).
/// - ``position_ecef`` (3,) m, ``velocity_ecef`` (3,) m/s and ``attitude``
///   (3, 3) C_b^e (body to ECEF): the state at ``time[0]``.
/// - ``scheme`` ["cubic"]: "cubic" interpolates the samples with coning
///   and sculling, fourth order; "trapezoid" is the two-sample
///   second-order step the filters chain.
///
/// Returns a ``NavSolution`` (position, velocity and attitude per sample).
#[catch_panics]
#[pyfunction]
#[pyo3(signature = (time, specific_force, angular_rate, position_ecef, velocity_ecef, attitude, *, scheme="cubic"))]
fn strapdown(
    py: Python<'_>,
    time: &Bound<'_, PyAny>,
    specific_force: &Bound<'_, PyAny>,
    angular_rate: &Bound<'_, PyAny>,
    position_ecef: &Bound<'_, PyAny>,
    velocity_ecef: &Bound<'_, PyAny>,
    attitude: &Bound<'_, PyAny>,
    scheme: &str,
) -> PyResult<PyNavSolution> {
    let time_s = convert::scalars(time, "time")?;
    let f = convert::vectors(specific_force, "specific_force")?;
    let w = convert::vectors(angular_rate, "angular_rate")?;
    let s0 = initial_state(position_ecef, velocity_ecef, attitude)?;
    let run = match scheme {
        "cubic" => ins::integrate,
        "trapezoid" => ins::integrate_steps,
        other => {
            return Err(PyValueError::new_err(format!(
                "scheme: expected \"cubic\" or \"trapezoid\", got {other:?}"
            )))
        }
    };
    let states = py.detach(|| run(&time_s, &f, &w, &s0)).py()?;
    Ok(PyNavSolution { time_s, states })
}

/// Strapdown INS from increments with coning and sculling corrections.
///
/// - `time` (N + 1,) s, increasing.
/// - `delta_velocity` (N, 3) m/s and `delta_angle` (N, 3) rad: row k
///   integrated over [time[k], time[k + 1]], in body axes.
/// - `position_ecef` (3,) m, `velocity_ecef` (3,) m/s and `attitude`
///   (3, 3) C_b^e: the state at `time[0]`, as for `strapdown`.
#[catch_panics]
#[pyfunction]
#[pyo3(signature = (time, delta_velocity, delta_angle, position_ecef, velocity_ecef, attitude))]
fn strapdown_increments(
    py: Python<'_>,
    time: &Bound<'_, PyAny>,
    delta_velocity: &Bound<'_, PyAny>,
    delta_angle: &Bound<'_, PyAny>,
    position_ecef: &Bound<'_, PyAny>,
    velocity_ecef: &Bound<'_, PyAny>,
    attitude: &Bound<'_, PyAny>,
) -> PyResult<PyNavSolution> {
    let time_s = convert::scalars(time, "time")?;
    let dv = convert::vectors(delta_velocity, "delta_velocity")?;
    let da = convert::vectors(delta_angle, "delta_angle")?;
    let s0 = initial_state(position_ecef, velocity_ecef, attitude)?;
    let states = py
        .detach(|| ins::integrate_increments(&time_s, &dv, &da, &s0))
        .py()?;
    Ok(PyNavSolution { time_s, states })
}

/// Two `(N, 3)` arrays.
type ArrayPair<'py> = (Bound<'py, PyArray2<f64>>, Bound<'py, PyArray2<f64>>);

/// (delta_velocity m/s, delta_angle rad), each (N - 1, 3): the integrals
/// of the cubic through the samples over each interval (fourth order).
#[catch_panics]
#[pyfunction]
#[pyo3(signature = (time, specific_force, angular_rate))]
fn imu_increments<'py>(
    py: Python<'py>,
    time: &Bound<'py, PyAny>,
    specific_force: &Bound<'py, PyAny>,
    angular_rate: &Bound<'py, PyAny>,
) -> PyResult<ArrayPair<'py>> {
    let time_s = convert::scalars(time, "time")?;
    let f = convert::vectors(specific_force, "specific_force")?;
    let w = convert::vectors(angular_rate, "angular_rate")?;
    let inc = py
        .detach(|| ins::increments_from_samples(&time_s, &f, &w))
        .py()?;
    let dv: Vec<_> = inc.iter().map(|i| i.delta_velocity_b).collect();
    let da: Vec<_> = inc.iter().map(|i| i.delta_angle_b).collect();
    Ok((
        convert::vectors_to_numpy(py, &dv),
        convert::vectors_to_numpy(py, &da),
    ))
}

pub fn register(m: &Bound<'_, PyModule>) -> PyResult<()> {
    m.add_class::<PyNavSolution>()?;
    m.add_function(wrap_pyfunction!(strapdown, m)?)?;
    m.add_function(wrap_pyfunction!(strapdown_increments, m)?)?;
    m.add_function(wrap_pyfunction!(imu_increments, m)?)?;
    Ok(())
}
