//! Real-log readers and writers (`memsnav_core::logs`) and the time
//! alignment of logs (`memsnav_core::timing`). The Python faces with their
//! defaults are in `memsnav/realdata/readers.py` and `timing.py`.

use std::path::PathBuf;

use memsnav_core::logs::{
    self, AccelUnit, FixTimeReference, FixesCsvLayout, GyroUnit, ImuColumns, ImuCsvLayout, TimeUnit,
};
use memsnav_core::timing::{self, LineEnds, OffsetSignal};
use memsnav_py_macros::catch_panics;
use numpy::{PyArray1, PyArray2, PyArray3};
use pyo3::exceptions::PyValueError;
use pyo3::prelude::*;
use pyo3::types::{PyDict, PyString};

use crate::convert;
use crate::errors::IntoPyResult;

/// IMU samples read from a CSV log, SI units, sensor axes.
#[pyclass(name = "ImuLog", module = "memsnav._memsnav", frozen)]
pub struct PyImuLog {
    pub(crate) inner: logs::ImuLog,
}

#[catch_panics]
#[pymethods]
impl PyImuLog {
    /// The log's own clock, s, ``(N,)``.
    #[getter]
    fn time<'py>(&self, py: Python<'py>) -> Bound<'py, PyArray1<f64>> {
        PyArray1::from_slice(py, &self.inner.time_s)
    }

    /// Specific force, m/s², ``(N, 3)``.
    #[getter]
    fn specific_force<'py>(&self, py: Python<'py>) -> Bound<'py, PyArray2<f64>> {
        convert::vectors_to_numpy(py, &self.inner.specific_force_m_s2)
    }

    /// Angular rate, rad/s, ``(N, 3)``.
    #[getter]
    fn angular_rate<'py>(&self, py: Python<'py>) -> Bound<'py, PyArray2<f64>> {
        convert::vectors_to_numpy(py, &self.inner.angular_rate_rad_s)
    }

    /// The time stamp written on each sample's line, s, ``(N,)``: ``time``
    /// for rates, the end of the interval for increments.
    #[getter]
    fn line_time<'py>(&self, py: Python<'py>) -> Bound<'py, PyArray1<f64>> {
        PyArray1::from_slice(py, &self.inner.line_time_s)
    }

    /// The sampling of the lines: ``median_interval_s``,
    /// ``interval_std_s`` (jitter, gaps left out), ``min_interval_s``,
    /// ``max_interval_s``, ``gap_threshold_s``, ``gap_count``,
    /// ``largest_gap_s``, ``largest_gap_line``.
    #[getter]
    fn timing<'py>(&self, py: Python<'py>) -> PyResult<Bound<'py, PyDict>> {
        let t = self.inner.timing();
        let d = PyDict::new(py);
        d.set_item("median_interval_s", t.median_interval_s)?;
        d.set_item("interval_std_s", t.interval_std_s)?;
        d.set_item("min_interval_s", t.min_interval_s)?;
        d.set_item("max_interval_s", t.max_interval_s)?;
        d.set_item("gap_threshold_s", t.gap_threshold_s)?;
        d.set_item("gap_count", t.gap_count)?;
        d.set_item("largest_gap_s", t.largest_gap_s)?;
        d.set_item("largest_gap_line", t.largest_gap_line)?;
        Ok(d)
    }

    /// The 1-based line of each sample, ``(N,)``.
    #[getter]
    fn line<'py>(&self, py: Python<'py>) -> Bound<'py, PyArray1<i64>> {
        PyArray1::from_iter(py, self.inner.line.iter().map(|&l| l as i64))
    }

    /// Byte offset of each sample line's newline, ``(N,)``.
    #[getter]
    fn line_end_offset<'py>(&self, py: Python<'py>) -> Bound<'py, PyArray1<i64>> {
        PyArray1::from_iter(py, self.inner.line_end_offset.iter().map(|&o| o as i64))
    }

    /// Size of the file, bytes.
    #[getter]
    fn file_bytes(&self) -> u64 {
        self.inner.file_bytes
    }

    /// Newline characters in the file.
    #[getter]
    fn newline_count(&self) -> u64 {
        self.inner.newline_count
    }

    /// Lines skipped and implausible contents, one sentence each.
    #[getter]
    fn warnings(&self) -> Vec<String> {
        self.inner.warnings.clone()
    }

    fn __len__(&self) -> usize {
        self.inner.time_s.len()
    }

    fn __repr__(&self) -> String {
        format!(
            "ImuLog({} samples, lines {}-{})",
            self.inner.time_s.len(),
            self.inner.line.first().unwrap_or(&0),
            self.inner.line.last().unwrap_or(&0)
        )
    }
}

/// Where each quantity is: a list of every column's name in order, or a
/// dict from each quantity to its header name (str) or 1-based number (int).
fn imu_columns(columns: &Bound<'_, PyAny>) -> PyResult<ImuColumns> {
    let Ok(map) = columns.cast::<PyDict>() else {
        return columns
            .extract::<Vec<String>>()
            .map(ImuColumns::Names)
            .map_err(|_| {
                PyValueError::new_err(format!(
                    "columns: expected a list of column names or a dict from each of ax ay az gx gy gz t to a header name or a 1-based column number, got {}",
                    columns.repr().map_or_else(|_| "?".into(), |r| r.to_string())
                ))
            });
    };
    let mut names = Vec::new();
    let mut numbers = Vec::new();
    for (key, value) in map.iter() {
        let key: String = key
            .extract()
            .map_err(|_| PyValueError::new_err("columns: the keys must be strings"))?;
        if value.is_instance_of::<PyString>() {
            names.push((key, value.extract::<String>()?));
        } else if let Ok(n) = value.extract::<i64>() {
            let n = usize::try_from(n).map_err(|_| {
                PyValueError::new_err(format!(
                    "columns: {key:?} = {n}: columns are numbered from 1"
                ))
            })?;
            numbers.push((key, n));
        } else {
            return Err(PyValueError::new_err(format!(
                "columns: {key:?}: expected a header name (str) or a 1-based column number (int), got {}",
                value.repr().map_or_else(|_| "?".into(), |r| r.to_string())
            )));
        }
    }
    match (names.is_empty(), numbers.is_empty()) {
        (false, false) => Err(PyValueError::new_err(
            "columns: give every quantity by header name or every one by column number, not both",
        )),
        (true, false) => Ok(ImuColumns::Numbers(numbers)),
        _ => Ok(ImuColumns::Header(names)),
    }
}

/// Reads an IMU CSV log with a declared layout (see ``memsnav.read_imu_csv``).
#[catch_panics]
#[pyfunction]
#[allow(clippy::too_many_arguments)]
fn read_imu_csv(
    py: Python<'_>,
    path: PathBuf,
    columns: &Bound<'_, PyAny>,
    accel_unit: &str,
    gyro_unit: &str,
    time_unit: &str,
    skip_first_line: bool,
    header_lines: usize,
    axes: &Bound<'_, PyAny>,
) -> PyResult<PyImuLog> {
    let axes = match axes.extract::<String>() {
        Ok(name) => logs::axes_from_name(&name).py()?,
        Err(_) => convert::matrix3(axes, "axes")?,
    };
    let layout = ImuCsvLayout {
        columns: imu_columns(columns)?,
        accel_unit: AccelUnit::from_name(accel_unit).py()?,
        gyro_unit: GyroUnit::from_name(gyro_unit).py()?,
        time_unit: TimeUnit::from_name(time_unit).py()?,
        axes,
        header_lines,
        skip_first_line,
    };
    Ok(PyImuLog {
        inner: py.detach(|| logs::read_imu_csv(&path, &layout)).py()?,
    })
}

/// An RTKLIB time-tag file.
#[pyclass(name = "TimeTag", module = "memsnav._memsnav", frozen)]
pub struct PyTimeTag {
    inner: logs::TimeTag,
}

#[catch_panics]
#[pymethods]
impl PyTimeTag {
    fn __repr__(&self) -> String {
        format!(
            "TimeTag({} tags from GPS time {:.3} s, {} warnings)",
            self.inner.tick_ms.len(),
            self.inner.start_gps_time_s,
            self.inner.warnings.len()
        )
    }

    /// GPS time of the log's opening, s since 1980-01-06.
    #[getter]
    fn start_gps_time(&self) -> f64 {
        self.inner.start_gps_time_s
    }

    /// The logger's absolute tick at the opening, ms.
    #[getter]
    fn start_tick_ms(&self) -> u32 {
        self.inner.start_tick_ms
    }

    /// Per write: ms since the opening, ``(M,)``.
    #[getter]
    fn tick_ms<'py>(&self, py: Python<'py>) -> Bound<'py, PyArray1<f64>> {
        PyArray1::from_iter(py, self.inner.tick_ms.iter().map(|&t| f64::from(t)))
    }

    /// Per write: size of the log after it, bytes, ``(M,)``.
    #[getter]
    fn file_offset<'py>(&self, py: Python<'py>) -> Bound<'py, PyArray1<i64>> {
        PyArray1::from_iter(py, self.inner.file_offset.iter().map(|&o| o as i64))
    }

    /// A cut last record, one sentence.
    #[getter]
    fn warnings(&self) -> Vec<String> {
        self.inner.warnings.clone()
    }

    /// GPS time (s since 1980-01-06) at which the write holding each byte
    /// of the log (counted as the logger counted them) began; NaN past the
    /// last tagged write or for a negative offset.
    fn arrival_gps_time<'py>(
        &self,
        py: Python<'py>,
        byte_offset: &Bound<'py, PyAny>,
    ) -> PyResult<Bound<'py, PyArray1<f64>>> {
        let offsets = convert::scalars(byte_offset, "byte_offset")?;
        Ok(PyArray1::from_iter(
            py,
            offsets.iter().map(|&b| {
                if b >= 0.0 && b.fract() == 0.0 && b <= u64::MAX as f64 {
                    self.inner.arrival_gps_time(b as u64).unwrap_or(f64::NAN)
                } else {
                    f64::NAN
                }
            }),
        ))
    }

    fn __len__(&self) -> usize {
        self.inner.tick_ms.len()
    }
}

/// Reads an RTKLIB ``.tag`` file (see ``memsnav.read_time_tag``).
#[catch_panics]
#[pyfunction]
fn read_time_tag(py: Python<'_>, path: PathBuf) -> PyResult<PyTimeTag> {
    Ok(PyTimeTag {
        inner: py.detach(|| logs::read_time_tag(&path)).py()?,
    })
}

/// The GPS times of a log's samples from its time tag, and how they were found.
#[pyclass(name = "TagClock", module = "memsnav._memsnav", frozen)]
pub struct PyTagClock {
    inner: timing::TagClock,
}

#[catch_panics]
#[pymethods]
impl PyTagClock {
    fn __repr__(&self) -> String {
        let c = &self.inner;
        format!(
            "TagClock({} samples, offset {:.6} s, rate {:+.3} ppm, {} warnings)",
            c.gps_time_s.len(),
            c.offset_s,
            c.rate_ppm,
            c.warnings.len()
        )
    }

    /// GPS time of every sample, s since 1980-01-06, ``(N,)``.
    #[getter]
    fn gps_time<'py>(&self, py: Python<'py>) -> Bound<'py, PyArray1<f64>> {
        PyArray1::from_slice(py, &self.inner.gps_time_s)
    }

    /// GPS time minus IMU time at the first sample, s.
    #[getter]
    fn offset_s(&self) -> f64 {
        self.inner.offset_s
    }

    /// Rate of the mapped time against the IMU clock, minus one, ppm.
    #[getter]
    fn rate_ppm(&self) -> f64 {
        self.inner.rate_ppm
    }

    /// Largest arrival lag above the fitted line, s (the logger's buffering).
    #[getter]
    fn arrival_lag_spread_s(&self) -> f64 {
        self.inner.arrival_lag_spread_s
    }

    /// How the tag counted line ends: ``"as_in_file"`` or ``"crlf_counted"``.
    #[getter]
    fn line_ends(&self) -> &'static str {
        line_ends_name(self.inner.line_ends)
    }

    /// Samples inside the tagged part of the log.
    #[getter]
    fn tagged_samples(&self) -> usize {
        self.inner.tagged_samples
    }

    /// Implausible results, one sentence each.
    #[getter]
    fn warnings(&self) -> Vec<String> {
        self.inner.warnings.clone()
    }
}

fn line_ends_name(l: LineEnds) -> &'static str {
    match l {
        LineEnds::AsInFile => "as_in_file",
        LineEnds::CrLfCounted => "crlf_counted",
    }
}

/// Maps the IMU clock of ``imu`` to GPS time with its time tag (see
/// ``memsnav.fit_tag_clock``).
#[catch_panics]
#[pyfunction]
fn fit_tag_clock(
    py: Python<'_>,
    imu: &PyImuLog,
    tag: &PyTimeTag,
    line_ends: Option<&str>,
) -> PyResult<PyTagClock> {
    let line_ends = match line_ends {
        None => None,
        Some("as_in_file") => Some(LineEnds::AsInFile),
        Some("crlf_counted") => Some(LineEnds::CrLfCounted),
        Some(other) => {
            return Err(PyValueError::new_err(format!(
                "line_ends: unknown convention '{other}'; expected None, 'as_in_file' or 'crlf_counted'"
            )))
        }
    };
    Ok(PyTagClock {
        inner: py
            .detach(|| timing::tag_clock(&imu.inner, &tag.inner, line_ends))
            .py()?,
    })
}

/// A GNSS solution in geodetic form (RTKLIB ``.pos``, fixes CSV, NMEA).
#[pyclass(name = "PosSolution", module = "memsnav._memsnav", frozen)]
pub struct PyPosSolution {
    pub(crate) inner: logs::PosSolution,
}

#[catch_panics]
#[pymethods]
impl PyPosSolution {
    fn __repr__(&self) -> String {
        let t = &self.inner.gps_time_s;
        match (t.first(), t.last()) {
            (Some(a), Some(b)) => {
                format!("PosSolution({} epochs, GPS time {a:.3}-{b:.3} s)", t.len())
            }
            _ => "PosSolution(no epoch)".to_string(),
        }
    }

    /// Epochs, GPS s since 1980-01-06, ``(N,)``.
    #[getter]
    fn gps_time<'py>(&self, py: Python<'py>) -> Bound<'py, PyArray1<f64>> {
        PyArray1::from_slice(py, &self.inner.gps_time_s)
    }

    /// [latitude rad, longitude rad, ellipsoidal height m], ``(N, 3)``.
    #[getter]
    fn lla<'py>(&self, py: Python<'py>) -> Bound<'py, PyArray2<f64>> {
        convert::vectors_to_numpy(py, &self.inner.lla)
    }

    /// RTKLIB's Q (1 fix, 2 float, 5 single, ...), ``(N,)``.
    #[getter]
    fn quality<'py>(&self, py: Python<'py>) -> Bound<'py, PyArray1<i64>> {
        PyArray1::from_iter(py, self.inner.quality.iter().map(|&q| i64::from(q)))
    }

    /// Satellites used, ``(N,)``.
    #[getter]
    fn n_satellites<'py>(&self, py: Python<'py>) -> Bound<'py, PyArray1<i64>> {
        PyArray1::from_iter(py, self.inner.n_satellites.iter().map(|&n| i64::from(n)))
    }

    /// One-sigma position uncertainty N, E, D, m, ``(N, 3)``; NaN when the
    /// file gives none (a fixes CSV truth).
    #[getter]
    fn std_ned<'py>(&self, py: Python<'py>) -> Bound<'py, PyArray2<f64>> {
        convert::vectors_to_numpy(py, &self.inner.std_ned_m)
    }

    /// NED velocity, m/s, ``(N, 3)``; NaN when the file has none.
    #[getter]
    fn velocity_ned<'py>(&self, py: Python<'py>) -> Bound<'py, PyArray2<f64>> {
        convert::vectors_to_numpy(py, &self.inner.velocity_ned_m_s)
    }

    /// One-sigma velocity uncertainty N, E, D, m/s, ``(N, 3)``; NaN likewise.
    #[getter]
    fn velocity_std_ned<'py>(&self, py: Python<'py>) -> Bound<'py, PyArray2<f64>> {
        convert::vectors_to_numpy(py, &self.inner.velocity_std_ned_m_s)
    }

    /// Position covariance N, E, D, m², ``(N, 3, 3)``: the file's full one,
    /// else diag(std²).
    #[getter]
    fn covariance_ned<'py>(&self, py: Python<'py>) -> Bound<'py, PyArray3<f64>> {
        convert::matrices3_to_numpy(py, &self.inner.position_covariance_ned_m2())
    }

    /// Velocity covariance N, E, D, (m/s)², ``(N, 3, 3)``: the file's full
    /// one, else diag(std²); NaN where the std is.
    #[getter]
    fn velocity_covariance_ned<'py>(&self, py: Python<'py>) -> Bound<'py, PyArray3<f64>> {
        convert::matrices3_to_numpy(py, &self.inner.velocity_covariance_ned_m2_s2())
    }

    /// The attitude C_b^n (body to local NED) of every epoch, ``(N, 3,
    /// 3)``, when the file gives one (a fixes CSV's quaternion or Euler
    /// columns), else None.
    #[getter]
    fn attitude<'py>(&self, py: Python<'py>) -> Option<Bound<'py, PyArray3<f64>>> {
        self.inner
            .attitude_c_b_n
            .as_deref()
            .map(|c| convert::matrices3_to_numpy(py, c))
    }

    /// Whether the file gives full position covariances (not only stds).
    #[getter]
    fn has_full_covariance(&self) -> bool {
        self.inner.covariance_ned_m2.is_some()
    }

    /// Lines skipped, one sentence each.
    #[getter]
    fn warnings(&self) -> Vec<String> {
        self.inner.warnings.clone()
    }

    fn __len__(&self) -> usize {
        self.inner.gps_time_s.len()
    }
}

/// Reads an RTKLIB ``.pos`` file (see ``memsnav.read_pos``).
#[catch_panics]
#[pyfunction]
fn read_pos(py: Python<'_>, path: PathBuf) -> PyResult<PyPosSolution> {
    Ok(PyPosSolution {
        inner: py.detach(|| logs::read_pos(&path)).py()?,
    })
}

/// Reads a fixes CSV (see ``memsnav.read_fixes_csv``): ``columns`` a dict
/// from memsnav's column names to the file's header names (None: the
/// header names memsnav's), ``time_reference`` what the time column
/// counts (None: ``"column_gps"``).
#[catch_panics]
#[pyfunction]
#[pyo3(signature = (path, columns=None, time_reference=None))]
fn read_fixes_csv(
    py: Python<'_>,
    path: PathBuf,
    columns: Option<&Bound<'_, PyDict>>,
    time_reference: Option<&str>,
) -> PyResult<PyPosSolution> {
    let mut layout = FixesCsvLayout::default();
    if let Some(map) = columns {
        for (key, value) in map.iter() {
            let key: String = key
                .extract()
                .map_err(|_| PyValueError::new_err("columns: the keys must be strings"))?;
            let header: String = value.extract().map_err(|_| {
                PyValueError::new_err(format!(
                    "columns: {key:?}: expected the file's header name (str), got {}",
                    value.repr().map_or_else(|_| "?".into(), |r| r.to_string())
                ))
            })?;
            layout.columns.push((key, header));
        }
    }
    if let Some(name) = time_reference {
        layout.time_reference = FixTimeReference::from_name(name).py()?;
    }
    Ok(PyPosSolution {
        inner: py.detach(|| logs::read_fixes_csv(&path, &layout)).py()?,
    })
}

/// Reads an NMEA 0183 log (see ``memsnav.read_nmea``).
#[catch_panics]
#[pyfunction]
fn read_nmea(py: Python<'_>, path: PathBuf) -> PyResult<PyPosSolution> {
    Ok(PyPosSolution {
        inner: py.detach(|| logs::read_nmea(&path)).py()?,
    })
}

/// An integer argument in the range of `T`, or an error naming it.
fn integer<T: TryFrom<i64>>(value: f64, argument: &str, k: usize) -> PyResult<T> {
    let as_int = value as i64;
    if as_int as f64 != value {
        return Err(PyValueError::new_err(format!(
            "{argument}: element {k} = {value} is not an integer"
        )));
    }
    T::try_from(as_int).map_err(|_| {
        PyValueError::new_err(format!("{argument}: element {k} = {value} is out of range"))
    })
}

/// Writes an RTKLIB-compatible ``.pos`` (see ``memsnav.realdata.readers.write_pos``).
#[catch_panics]
#[pyfunction]
fn write_pos(
    py: Python<'_>,
    path: PathBuf,
    gps_time: &Bound<'_, PyAny>,
    lla: &Bound<'_, PyAny>,
    std_ned: &Bound<'_, PyAny>,
    velocity_ned: &Bound<'_, PyAny>,
    velocity_std_ned: &Bound<'_, PyAny>,
    quality: i64,
    n_satellites: &Bound<'_, PyAny>,
    program: &str,
) -> PyResult<()> {
    let gps_time_s = convert::scalars(gps_time, "gps_time")?;
    let n = gps_time_s.len();
    let quality: u8 = integer(quality as f64, "quality", 0)?;
    let n_satellites = convert::scalars(n_satellites, "n_satellites")?
        .iter()
        .enumerate()
        .map(|(k, &x)| integer::<u16>(x, "n_satellites", k))
        .collect::<PyResult<Vec<u16>>>()?;
    let solution = logs::PosSolution {
        gps_time_s,
        lla: convert::vectors(lla, "lla")?,
        quality: vec![quality; n],
        n_satellites,
        std_ned_m: convert::vectors(std_ned, "std_ned")?,
        covariance_ned_m2: None,
        velocity_ned_m_s: convert::vectors(velocity_ned, "velocity_ned")?,
        velocity_std_ned_m_s: convert::vectors(velocity_std_ned, "velocity_std_ned")?,
        velocity_covariance_ned_m2_s2: None,
        attitude_c_b_n: None,
        warnings: Vec::new(),
    };
    py.detach(|| logs::write_pos(&path, &solution, program))
        .py()
}

/// A lag found by a search: the best lag, its score and spread, the curve.
#[pyclass(name = "LagEstimate", module = "memsnav._memsnav", frozen)]
pub struct PyLagEstimate {
    inner: timing::LagEstimate,
}

#[catch_panics]
#[pymethods]
impl PyLagEstimate {
    fn __repr__(&self) -> String {
        format!(
            "LagEstimate({:.4} s ± {:.4} s over {} blocks)",
            self.inner.lag_s,
            self.inner.std_s,
            self.inner.block_lag_s.len()
        )
    }

    /// The refined best lag, s.
    #[getter]
    fn lag_s(&self) -> f64 {
        self.inner.lag_s
    }

    /// The score there: the correlation, or the RMS difference.
    #[getter]
    fn score(&self) -> f64 {
        self.inner.score
    }

    /// Second derivative of the correlation (or mean square) at the best lag, per s².
    #[getter]
    fn curvature(&self) -> f64 {
        self.inner.curvature
    }

    /// Standard error of the lag from its spread over the blocks, s.
    #[getter]
    fn std_s(&self) -> f64 {
        self.inner.std_s
    }

    /// Best lag of each consecutive block of the data, s.
    #[getter]
    fn block_lag_s<'py>(&self, py: Python<'py>) -> Bound<'py, PyArray1<f64>> {
        PyArray1::from_slice(py, &self.inner.block_lag_s)
    }

    /// The searched lags, s.
    #[getter]
    fn curve_lag_s<'py>(&self, py: Python<'py>) -> Bound<'py, PyArray1<f64>> {
        PyArray1::from_slice(py, &self.inner.curve_lag_s)
    }

    /// The score at each searched lag.
    #[getter]
    fn curve_score<'py>(&self, py: Python<'py>) -> Bound<'py, PyArray1<f64>> {
        PyArray1::from_slice(py, &self.inner.curve_score)
    }

    /// Epochs that entered the score.
    #[getter]
    fn samples(&self) -> usize {
        self.inner.samples
    }
}

/// The offset to add to IMU times that aligns them with GNSS positions
/// (see ``memsnav.estimate_time_offset``).
#[catch_panics]
#[pyfunction]
fn estimate_time_offset(
    py: Python<'_>,
    imu_time: &Bound<'_, PyAny>,
    specific_force: &Bound<'_, PyAny>,
    angular_rate: &Bound<'_, PyAny>,
    gnss_time: &Bound<'_, PyAny>,
    lla: &Bound<'_, PyAny>,
    signal: &str,
    max_offset_s: f64,
    step_s: f64,
    min_speed_m_s: f64,
    blocks: usize,
) -> PyResult<PyLagEstimate> {
    let imu_time = convert::scalars(imu_time, "imu_time")?;
    let force = convert::vectors(specific_force, "specific_force")?;
    let rate = convert::vectors(angular_rate, "angular_rate")?;
    let gnss_time = convert::scalars(gnss_time, "gnss_time")?;
    let lla = convert::vectors(lla, "lla")?;
    let options = timing::TimeOffsetOptions {
        signal: OffsetSignal::from_name(signal).py()?,
        max_offset_s,
        step_s,
        min_speed_m_s,
        blocks,
    };
    let inner = py
        .detach(|| {
            timing::estimate_time_offset(&imu_time, &force, &rate, &gnss_time, &lla, &options)
        })
        .py()?;
    Ok(PyLagEstimate { inner })
}

/// The latency of a GNSS solution's velocity behind its positions (see
/// ``memsnav.estimate_velocity_latency``).
#[catch_panics]
#[pyfunction]
fn estimate_velocity_latency(
    py: Python<'_>,
    gnss_time: &Bound<'_, PyAny>,
    lla: &Bound<'_, PyAny>,
    velocity_ned: &Bound<'_, PyAny>,
    max_latency_s: f64,
    step_s: f64,
    blocks: usize,
) -> PyResult<PyLagEstimate> {
    let gnss_time = convert::scalars(gnss_time, "gnss_time")?;
    let lla = convert::vectors(lla, "lla")?;
    // NaN rows mean "no velocity in the file": the core says so by name.
    let velocity = convert::vectors_allowing_nan(velocity_ned, "velocity_ned")?;
    let options = timing::VelocityLatencyOptions {
        max_latency_s,
        step_s,
        blocks,
    };
    let inner = py
        .detach(|| timing::estimate_velocity_latency(&gnss_time, &lla, &velocity, &options))
        .py()?;
    Ok(PyLagEstimate { inner })
}

pub fn register(m: &Bound<'_, PyModule>) -> PyResult<()> {
    m.add_class::<PyImuLog>()?;
    m.add_class::<PyTimeTag>()?;
    m.add_class::<PyTagClock>()?;
    m.add_class::<PyPosSolution>()?;
    m.add_class::<PyLagEstimate>()?;
    m.add_function(wrap_pyfunction!(read_imu_csv, m)?)?;
    m.add_function(wrap_pyfunction!(read_time_tag, m)?)?;
    m.add_function(wrap_pyfunction!(fit_tag_clock, m)?)?;
    m.add_function(wrap_pyfunction!(read_pos, m)?)?;
    m.add_function(wrap_pyfunction!(read_fixes_csv, m)?)?;
    m.add_function(wrap_pyfunction!(read_nmea, m)?)?;
    m.add_function(wrap_pyfunction!(write_pos, m)?)?;
    m.add_function(wrap_pyfunction!(estimate_time_offset, m)?)?;
    m.add_function(wrap_pyfunction!(estimate_velocity_latency, m)?)?;
    m.add("UNIX_TO_GPS_S", memsnav_core::gnss::UNIX_TO_GPS_S)?;
    Ok(())
}
