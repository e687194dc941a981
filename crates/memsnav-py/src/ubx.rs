//! u-blox UBX logs: RXM-RAWX as observations and as the receiver gives
//! them, GPS (LNAV and CNAV), Galileo, BeiDou and GLONASS ephemerides and the CNAV
//! Klobuchar coefficients from RXM-SFRBX, NAV-PVT fixes; RINEX 3 out.

use std::collections::BTreeMap;
use std::path::PathBuf;

use memsnav_core::gnss::{self, Constellation, RinexProvenance};
use memsnav_core::logs::{self, UbxLog};
use memsnav_py_macros::catch_panics;
use numpy::{PyArray1, PyArray2};
use pyo3::prelude::*;
use pyo3::types::PyDict;

use crate::broadcast_nav::PyBroadcastEphemerides;
use crate::convert;
use crate::ephemeris_dicts::{cnav_dict, orbit_dict};
use crate::errors::IntoPyResult;
use crate::gnss::{PyConstellation, PyRinexObservations};
use crate::logs::PyPosSolution;

/// What a u-blox UBX log holds (``read_ubx``).
#[pyclass(name = "UbxLog", module = "memsnav._memsnav", frozen)]
pub struct PyUbxLog {
    inner: UbxLog,
    /// The log's path as given, for the headers of the files written.
    source: String,
}

/// The header of files this binding writes.
fn provenance(log: &str) -> RinexProvenance {
    RinexProvenance {
        program: format!("memsnav {}", env!("CARGO_PKG_VERSION")),
        receiver: "u-blox".into(),
        created: String::new(),
        comments: vec![format!("converted from the u-blox UBX log {log}")],
    }
}

#[catch_panics]
#[pymethods]
impl PyUbxLog {
    /// RXM-RAWX as observations (the class ``read_rinex_obs`` returns):
    /// per signal ``C`` pseudorange m (``prValid`` only), ``L`` carrier
    /// cycles (``cpValid`` only), ``D`` Doppler Hz, ``S`` C/N0 dB-Hz, RINEX
    /// 3 codes (``C1C``, ``C2L``, ``C5Q``, ``C6B``, ...), epochs on the
    /// receiver's GPS time; the approximate position is the first NAV-PVT fix.
    #[getter]
    fn observations(&self) -> PyRinexObservations {
        PyRinexObservations {
            inner: self.inner.observations.clone(),
        }
    }

    /// The GPS satellites of the decoded LNAV ephemerides, for
    /// ``observations.gps_l1`` and ``solve_fix``.
    #[getter]
    fn constellation(&self) -> PyConstellation {
        PyConstellation {
            inner: Constellation::from_ephemerides(
                self.inner
                    .gps_ephemerides
                    .iter()
                    .map(|e| e.ephemeris)
                    .collect(),
            ),
        }
    }

    /// Every decoded ephemeris (GPS LNAV and CNAV, Galileo, BeiDou) as one
    /// set, for ``observations.measurements``.
    #[getter]
    fn broadcast_ephemerides(&self) -> PyBroadcastEphemerides {
        PyBroadcastEphemerides {
            inner: self.inner.broadcast_nav(),
        }
    }

    /// The GPS LNAV ephemerides decoded from RXM-SFRBX, one dict each with
    /// the RINEX navigation record's fields (SI units, angles rad, times
    /// GPS s since 1980-01-06) and the message's flags.
    #[getter]
    fn ephemerides<'py>(&self, py: Python<'py>) -> PyResult<Vec<Bound<'py, PyDict>>> {
        self.inner
            .gps_ephemerides
            .iter()
            .map(|l| {
                let e = &l.ephemeris;
                let d = orbit_dict(py, format!("G{:02}", e.prn), &e.orbit)?;
                for (k, v) in [
                    ("tgd", e.tgd_s),
                    ("fit_interval_h", e.fit_interval_h),
                    ("ura_m", gnss::ura_m(l.ura_index)),
                    ("transmission_time", l.transmission_gps_s),
                ] {
                    d.set_item(k, v)?;
                }
                for (k, v) in [
                    ("prn", u32::from(e.prn)),
                    ("health", e.health),
                    ("iode", u32::from(l.iode)),
                    ("iodc", u32::from(l.iodc)),
                    ("ura_index", u32::from(l.ura_index)),
                    ("l2_codes", u32::from(l.l2_codes)),
                    ("l2p_data_flag", u32::from(l.l2p_data_flag)),
                    ("week", u32::from(l.toe_week)),
                ] {
                    d.set_item(k, v)?;
                }
                Ok(d)
            })
            .collect()
    }

    /// The GPS CNAV ephemerides decoded from RXM-SFRBX (L2C or L5, CRC
    /// checked), one dict each with the orbit and clock under the RINEX
    /// record's names (SI units, angles rad, times GPS s since 1980-01-06;
    /// ``sqrt_a`` is √(A_REF + ΔA), ``omega_dot`` Ω̇_REF + ΔΩ̇), CNAV's
    /// rates ``a_dot`` m/s and ``delta_n_dot`` rad/s², the health bits
    /// ``l1_health``, ``l2_health``, ``l5_health``, the accuracy indices
    /// ``ura_ed_index`` (and its nominal ``ura_ed_m``, NaN for none),
    /// ``ura_ned0_index``, ``ura_ned1_index``, ``ura_ned2_index``, ``top``,
    /// ``week`` (13 bits), ``integrity_status_flag``, ``l2c_phasing``, and
    /// type 30's ``tgd``, ``isc_l1ca``, ``isc_l2c``, ``isc_l5i5``,
    /// ``isc_l5q5`` s (None when not available). The clock is referred to
    /// L1/L2 P(Y) ionosphere-free, as LNAV's; a signal's user subtracts
    /// T_GD − ISC.
    #[getter]
    fn gps_cnav_ephemerides<'py>(&self, py: Python<'py>) -> PyResult<Vec<Bound<'py, PyDict>>> {
        self.inner
            .gps_cnav_ephemerides
            .iter()
            .map(|e| cnav_dict(py, e))
            .collect()
    }

    /// The Klobuchar coefficients ``(alpha, beta)`` of the latest GPS CNAV
    /// message type 30 (s, s/semicircleⁿ), or None when the log has none;
    /// what ``klobuchar=`` of the fix and the observables takes.
    #[getter]
    fn klobuchar(&self) -> Option<([f64; 4], [f64; 4])> {
        self.inner.klobuchar.map(|k| (k.alpha, k.beta))
    }

    /// The Galileo I/NAV ephemerides decoded from RXM-SFRBX (E1-B), one
    /// dict each with the RINEX navigation record's fields (SI units,
    /// angles rad, times GPS s since 1980-01-06) and the health, data
    /// validity and accuracy (SISA) flags.
    #[getter]
    fn galileo_ephemerides<'py>(&self, py: Python<'py>) -> PyResult<Vec<Bound<'py, PyDict>>> {
        self.inner
            .galileo_ephemerides
            .iter()
            .map(|e| {
                let d = orbit_dict(py, format!("E{:02}", e.svid), &e.orbit)?;
                for (k, v) in [
                    ("bgd_e1_e5a", e.bgd_e1_e5a_s),
                    ("bgd_e1_e5b", e.bgd_e1_e5b_s),
                    ("sisa_m", gnss::sisa_m(e.sisa_index).unwrap_or(f64::NAN)),
                    ("transmission_time", e.transmission_gps_s),
                ] {
                    d.set_item(k, v)?;
                }
                for (k, v) in [
                    ("svid", u32::from(e.svid)),
                    ("iod_nav", u32::from(e.iod_nav)),
                    ("sisa_index", u32::from(e.sisa_index)),
                    ("e1b_health", u32::from(e.e1b_health)),
                    ("e5b_health", u32::from(e.e5b_health)),
                    ("e1b_data_validity", u32::from(e.e1b_data_validity)),
                    ("e5b_data_validity", u32::from(e.e5b_data_validity)),
                    ("gst_week", u32::from(e.gst_week)),
                ] {
                    d.set_item(k, v)?;
                }
                d.set_item("healthy", e.is_healthy())?;
                Ok(d)
            })
            .collect()
    }

    /// The BeiDou D1 ephemerides (MEO and IGSO satellites) decoded from
    /// RXM-SFRBX, one dict each with the RINEX navigation record's fields
    /// (SI units, angles rad, times GPS s since 1980-01-06: BDT + 14 s),
    /// the group delays ``tgd1`` (B1I) and ``tgd2`` (B2I) to B3I, the clock's
    /// reference, and the health (SatH1) and accuracy (URAI) flags.
    #[getter]
    fn beidou_ephemerides<'py>(&self, py: Python<'py>) -> PyResult<Vec<Bound<'py, PyDict>>> {
        self.inner
            .beidou_ephemerides
            .iter()
            .map(|e| {
                let d = orbit_dict(py, format!("C{:02}", e.prn), &e.orbit)?;
                for (k, v) in [
                    ("tgd1", e.tgd1_s),
                    ("tgd2", e.tgd2_s),
                    ("ura_m", gnss::ura_m(e.urai)),
                    ("transmission_time", e.transmission_gps_s),
                ] {
                    d.set_item(k, v)?;
                }
                for (k, v) in [
                    ("prn", u32::from(e.prn)),
                    ("aode", u32::from(e.aode)),
                    ("aodc", u32::from(e.aodc)),
                    ("urai", u32::from(e.urai)),
                    ("sat_h1", u32::from(e.sat_h1)),
                    ("bdt_week", u32::from(e.bdt_week)),
                ] {
                    d.set_item(k, v)?;
                }
                d.set_item("healthy", e.is_healthy())?;
                Ok(d)
            })
            .collect()
    }

    /// The GLONASS ephemerides decoded from RXM-SFRBX (L1OF/L2OF strings
    /// 1-4, Hamming checked), one dict each: ``sat`` (``"R05"``),
    /// ``slot``, ``frequency_channel`` k, ``tb`` (GPS s), ``tau_n`` (s),
    /// ``gamma_n``, ``position``, ``velocity`` and ``lunisolar_acceleration``
    /// (PZ-90 at t_b, m, m/s, m/s²), ``health`` (RINEX's), ``age_days``,
    /// ``healthy``.
    #[getter]
    fn glonass_ephemerides<'py>(&self, py: Python<'py>) -> PyResult<Vec<Bound<'py, PyDict>>> {
        self.inner
            .glonass_ephemerides
            .iter()
            .map(|e| {
                let d = PyDict::new(py);
                d.set_item("sat", format!("R{:02}", e.slot))?;
                d.set_item("slot", u32::from(e.slot))?;
                d.set_item("frequency_channel", i32::from(e.frequency_channel))?;
                for (k, v) in [
                    ("tb", e.tb_gps_s),
                    ("tau_n", e.tau_n_s),
                    ("gamma_n", e.gamma_n),
                ] {
                    d.set_item(k, v)?;
                }
                for (k, v) in [
                    ("position", e.position_ecef),
                    ("velocity", e.velocity_ecef),
                    ("lunisolar_acceleration", e.lunisolar_m_s2),
                ] {
                    d.set_item(k, [v.x, v.y, v.z])?;
                }
                d.set_item("health", u32::from(e.health))?;
                d.set_item("age_days", u32::from(e.age_days))?;
                d.set_item("healthy", e.is_healthy())?;
                Ok(d)
            })
            .collect()
    }

    /// RXM-RAWX as the receiver reports it, one row per epoch and signal:
    /// ``epoch`` (index into ``epoch_gps_time``), ``sat`` ("G10"),
    /// ``code`` (RINEX band and attribute), ``gnss_id``, ``sv_id``,
    /// ``sig_id``, ``pseudorange`` m, ``carrier_phase`` cycles, ``doppler``
    /// Hz, ``cn0`` dB-Hz, ``lock_time`` s, the receiver's σ
    /// (``pseudorange_std`` m, ``carrier_phase_std`` cycles,
    /// ``doppler_std`` Hz), the tracking flags (``pseudorange_valid``,
    /// ``carrier_phase_valid``, ``half_cycle_resolved``,
    /// ``half_cycle_subtracted``); per epoch ``epoch_gps_time``,
    /// ``receiver_tow`` s, ``week``, ``leap_seconds`` (-1: not known yet),
    /// ``clock_reset``.
    #[getter]
    fn rawx<'py>(&self, py: Python<'py>) -> PyResult<Bound<'py, PyDict>> {
        let rows: Vec<(usize, &logs::RawxSignal)> = self
            .inner
            .rawx
            .iter()
            .enumerate()
            .flat_map(|(k, e)| e.signals.iter().map(move |s| (k, s)))
            .collect();
        let d = PyDict::new(py);
        let column = |f: &dyn Fn(&logs::RawxSignal) -> f64| -> Bound<'py, PyArray1<f64>> {
            PyArray1::from_iter(py, rows.iter().map(|(_, s)| f(s)))
        };
        let flag = |f: &dyn Fn(&logs::RawxSignal) -> bool| -> Bound<'py, PyArray1<bool>> {
            PyArray1::from_iter(py, rows.iter().map(|(_, s)| f(s)))
        };
        let small = |f: &dyn Fn(&logs::RawxSignal) -> u8| -> Bound<'py, PyArray1<i64>> {
            PyArray1::from_iter(py, rows.iter().map(|(_, s)| i64::from(f(s))))
        };
        d.set_item(
            "epoch",
            PyArray1::from_iter(py, rows.iter().map(|(k, _)| *k as i64)),
        )?;
        d.set_item(
            "sat",
            rows.iter()
                .map(|(_, s)| format!("{}{:02}", s.system, s.prn))
                .collect::<Vec<_>>(),
        )?;
        d.set_item(
            "code",
            rows.iter().map(|(_, s)| s.rinex_code).collect::<Vec<_>>(),
        )?;
        d.set_item("gnss_id", small(&|s| s.gnss_id))?;
        d.set_item("sv_id", small(&|s| s.sv_id))?;
        d.set_item("sig_id", small(&|s| s.sig_id))?;
        d.set_item("pseudorange", column(&|s| s.pseudorange_m))?;
        d.set_item("carrier_phase", column(&|s| s.carrier_phase_cycles))?;
        d.set_item("doppler", column(&|s| s.doppler_hz))?;
        d.set_item("cn0", column(&|s| s.cn0_db_hz))?;
        d.set_item("lock_time", column(&|s| s.lock_time_s))?;
        d.set_item("pseudorange_std", column(&|s| s.pseudorange_std_m))?;
        d.set_item("carrier_phase_std", column(&|s| s.carrier_phase_std_cycles))?;
        d.set_item("doppler_std", column(&|s| s.doppler_std_hz))?;
        d.set_item("pseudorange_valid", flag(&|s| s.tracking.pseudorange_valid))?;
        d.set_item(
            "carrier_phase_valid",
            flag(&|s| s.tracking.carrier_phase_valid),
        )?;
        d.set_item(
            "half_cycle_resolved",
            flag(&|s| s.tracking.half_cycle_resolved),
        )?;
        d.set_item(
            "half_cycle_subtracted",
            flag(&|s| s.tracking.half_cycle_subtracted),
        )?;
        let epochs = &self.inner.rawx;
        d.set_item(
            "epoch_gps_time",
            PyArray1::from_iter(py, epochs.iter().map(|e| e.gps_time_s())),
        )?;
        d.set_item(
            "receiver_tow",
            PyArray1::from_iter(py, epochs.iter().map(|e| e.receiver_tow_s)),
        )?;
        d.set_item(
            "week",
            PyArray1::from_iter(py, epochs.iter().map(|e| i64::from(e.week))),
        )?;
        d.set_item(
            "leap_seconds",
            PyArray1::from_iter(
                py,
                epochs.iter().map(|e| e.leap_seconds.map_or(-1, i64::from)),
            ),
        )?;
        d.set_item(
            "clock_reset",
            PyArray1::from_iter(py, epochs.iter().map(|e| e.clock_reset)),
        )?;
        Ok(d)
    }

    /// Every NAV-PVT solution, fix or not, as arrays: ``gps_time`` s,
    /// ``lla`` (N, 3) rad, rad, m ellipsoidal, ``height_msl`` m,
    /// ``velocity_ned`` (N, 3) m/s, ``horizontal_accuracy``,
    /// ``vertical_accuracy`` m, ``speed_accuracy`` m/s, ``fix_type``,
    /// ``fix_ok``, ``carrier_solution`` (0 none, 1 float, 2 fixed),
    /// ``n_satellites``, ``quality`` (RTKLIB's Q).
    #[getter]
    fn nav_pvt<'py>(&self, py: Python<'py>) -> PyResult<Bound<'py, PyDict>> {
        let s = &self.inner.nav_pvt;
        let d = PyDict::new(py);
        let column = |f: &dyn Fn(&logs::NavPvt) -> f64| PyArray1::from_iter(py, s.iter().map(f));
        let integer = |f: &dyn Fn(&logs::NavPvt) -> u8| {
            PyArray1::from_iter(py, s.iter().map(|x| i64::from(f(x))))
        };
        d.set_item("gps_time", column(&|x| x.gps_time_s))?;
        let lla: Vec<_> = s.iter().map(|x| x.lla).collect();
        d.set_item("lla", convert::vectors_to_numpy(py, &lla))?;
        d.set_item("height_msl", column(&|x| x.height_msl_m))?;
        let v: Vec<_> = s.iter().map(|x| x.velocity_ned_m_s).collect();
        let v: Bound<'py, PyArray2<f64>> = convert::vectors_to_numpy(py, &v);
        d.set_item("velocity_ned", v)?;
        d.set_item("horizontal_accuracy", column(&|x| x.horizontal_accuracy_m))?;
        d.set_item("vertical_accuracy", column(&|x| x.vertical_accuracy_m))?;
        d.set_item("speed_accuracy", column(&|x| x.speed_accuracy_m_s))?;
        d.set_item("fix_type", integer(&|x| x.fix_type))?;
        d.set_item(
            "fix_ok",
            PyArray1::from_iter(py, s.iter().map(|x| x.fix_ok)),
        )?;
        d.set_item("carrier_solution", integer(&|x| x.carrier_solution))?;
        d.set_item("n_satellites", integer(&|x| x.n_satellites))?;
        d.set_item("quality", integer(&logs::NavPvt::quality))?;
        Ok(d)
    }

    /// The NAV-PVT position fixes as the other fix readers give them
    /// (σ north and east hAcc/√2, down vAcc; velocity σ sAcc per axis).
    #[getter]
    fn fixes(&self) -> PyPosSolution {
        PyPosSolution {
            inner: self.inner.fixes.clone(),
        }
    }

    /// Messages read, by name (``RXM-RAWX``, ``NAV-PVT``, ``RXM-SFRBX``,
    /// ``0xCC-0xII`` for the others).
    #[getter]
    fn messages(&self) -> BTreeMap<String, usize> {
        self.inner.messages.clone()
    }

    /// What was left out, by reason, with counts.
    #[getter]
    fn skipped(&self) -> BTreeMap<String, usize> {
        self.inner.skipped.clone()
    }

    /// Non-fatal problems met while reading.
    #[getter]
    fn warnings(&self) -> Vec<String> {
        self.inner.warnings.clone()
    }

    /// Writes the observations as a RINEX 3.04 observation file at ``path``.
    fn write_rinex_obs(&self, py: Python<'_>, path: PathBuf) -> PyResult<()> {
        let header = provenance(&self.source);
        py.detach(|| gnss::write_rinex_obs(&path, &self.inner.observations, &header))
            .py()
    }

    /// Writes the decoded ephemerides as a RINEX navigation file at
    /// ``path``: RINEX 4.00 by default (GPS LNAV and CNAV, Galileo I/NAV,
    /// BeiDou D1 records), or ``rinex_version="3.04"``, which has no CNAV
    /// record (the CNAV ephemerides are then not written). The file is
    /// written once memsnav's reader reads every record back.
    #[pyo3(signature = (path, rinex_version=None))]
    fn write_rinex_nav(
        &self,
        py: Python<'_>,
        path: PathBuf,
        rinex_version: Option<&str>,
    ) -> PyResult<()> {
        let version = match rinex_version {
            Some(text) => gnss::RinexNavVersion::parse(text, "rinex_version").py()?,
            None => gnss::RinexNavVersion::default(),
        };
        let header = provenance(&self.source);
        py.detach(|| {
            gnss::write_rinex_nav(&path, &self.inner.nav_file_ephemerides(), version, &header)
        })
        .py()
    }

    fn __repr__(&self) -> String {
        format!(
            "UbxLog({} RAWX epochs, {} GPS LNAV, {} GPS CNAV, {} Galileo, {} BeiDou, {} GLONASS \
             ephemerides, {} NAV-PVT fixes)",
            self.inner.rawx.len(),
            self.inner.gps_ephemerides.len(),
            self.inner.gps_cnav_ephemerides.len(),
            self.inner.galileo_ephemerides.len(),
            self.inner.beidou_ephemerides.len(),
            self.inner.glonass_ephemerides.len(),
            self.inner.fixes.gps_time_s.len()
        )
    }
}

/// Reads a u-blox UBX log: RXM-RAWX, GPS LNAV (parity checked), GPS
/// CNAV and Galileo I/NAV (CRC checked) and BeiDou D1 (BCH checked)
/// ephemerides and the CNAV Klobuchar from RXM-SFRBX, NAV-PVT; frames
/// with a bad checksum, a cut last frame and messages not decoded are
/// skipped and counted; a file without a UBX
/// frame is a ParseError naming it.
///
/// `path`: the file to read (str or path-like).
#[catch_panics]
#[pyfunction]
fn read_ubx(py: Python<'_>, path: PathBuf) -> PyResult<PyUbxLog> {
    Ok(PyUbxLog {
        inner: py.detach(|| logs::read_ubx(&path)).py()?,
        source: path.file_name().map_or_else(
            || path.display().to_string(),
            |n| n.to_string_lossy().into(),
        ),
    })
}

pub fn register(m: &Bound<'_, PyModule>) -> PyResult<()> {
    m.add_class::<PyUbxLog>()?;
    m.add_function(wrap_pyfunction!(read_ubx, m)?)?;
    Ok(())
}
