//! Broadcast ephemerides as Python dicts under the RINEX record's names:
//! the one form ``UbxLog`` and ``BroadcastEphemerides`` hand them out in.

use memsnav_core::gnss::{self, BroadcastOrbit};
use pyo3::prelude::*;
use pyo3::types::PyDict;

/// A dict with a broadcast ephemeris's satellite name and its orbit and
/// clock polynomial under the RINEX record's names (SI units, angles rad,
/// times GPS s since 1980-01-06): what every system's dict starts from.
pub(crate) fn orbit_dict<'py>(
    py: Python<'py>,
    sat: String,
    o: &BroadcastOrbit,
) -> PyResult<Bound<'py, PyDict>> {
    let d = PyDict::new(py);
    d.set_item("sat", sat)?;
    for (k, v) in [
        ("toc", o.toc_gps_s),
        ("toe", o.toe_gps_s),
        ("af0", o.af0_s),
        ("af1", o.af1_s_s),
        ("af2", o.af2_s_s2),
        ("crs", o.crs_m),
        ("delta_n", o.delta_n_rad_s),
        ("m0", o.m0_rad),
        ("cuc", o.cuc_rad),
        ("eccentricity", o.eccentricity),
        ("cus", o.cus_rad),
        ("sqrt_a", o.sqrt_a_sqrt_m),
        ("cic", o.cic_rad),
        ("omega0", o.omega0_rad),
        ("cis", o.cis_rad),
        ("i0", o.i0_rad),
        ("crc", o.crc_m),
        ("omega", o.omega_rad),
        ("omega_dot", o.omega_dot_rad_s),
        ("idot", o.idot_rad_s),
    ] {
        d.set_item(k, v)?;
    }
    Ok(d)
}

/// A GPS CNAV ephemeris as the dict ``UbxLog.gps_cnav_ephemerides``
/// describes (also ``BroadcastEphemerides.gps_cnav_ephemerides``).
pub(crate) fn cnav_dict<'py>(
    py: Python<'py>,
    e: &gnss::CnavEphemeris,
) -> PyResult<Bound<'py, PyDict>> {
    let d = orbit_dict(py, format!("G{:02}", e.prn), &e.orbit)?;
    for (k, v) in [
        ("a_dot", e.orbit.a_dot_m_s),
        ("delta_n_dot", e.orbit.delta_n_dot_rad_s2),
        (
            "ura_ed_m",
            gnss::cnav_ura_m(e.ura_ed_index).unwrap_or(f64::NAN),
        ),
        ("top", e.top_gps_s),
        ("transmission_time", e.transmission_gps_s),
    ] {
        d.set_item(k, v)?;
    }
    for (k, v) in [
        ("prn", i32::from(e.prn)),
        ("l1_health", i32::from(e.l1_health)),
        ("l2_health", i32::from(e.l2_health)),
        ("l5_health", i32::from(e.l5_health)),
        ("ura_ed_index", i32::from(e.ura_ed_index)),
        ("ura_ned0_index", i32::from(e.ura_ned0_index)),
        ("ura_ned1_index", i32::from(e.ura_ned1_index)),
        ("ura_ned2_index", i32::from(e.ura_ned2_index)),
        ("week", i32::from(e.week)),
    ] {
        d.set_item(k, v)?;
    }
    d.set_item("integrity_status_flag", e.integrity_status_flag)?;
    d.set_item("l2c_phasing", e.l2c_phasing)?;
    let g = e.group_delays;
    for (k, v) in [
        ("tgd", g.and_then(|g| g.tgd_s)),
        ("isc_l1ca", g.and_then(|g| g.isc_l1ca_s)),
        ("isc_l2c", g.and_then(|g| g.isc_l2c_s)),
        ("isc_l5i5", g.and_then(|g| g.isc_l5i5_s)),
        ("isc_l5q5", g.and_then(|g| g.isc_l5q5_s)),
    ] {
        d.set_item(k, v)?;
    }
    Ok(d)
}
