//! `geodetic_to_ecef`, `ecef_to_geodetic`, `ecef_to_ned`, `gravity_ecef`:
//! vectorised over `(..., 3)`.

use memsnav_core::geodesy::{self, domain, Geodetic};
use memsnav_py_macros::catch_panics;
use nalgebra::Vector3;
use numpy::PyArrayDyn;
use pyo3::prelude::*;

use crate::convert;
use crate::errors::IntoPyResult;

/// Positions relative to a checked origin may be anywhere.
fn no_check(_: &str, _: &[Vector3<f64>]) -> memsnav_core::Result<()> {
    Ok(())
}

/// `f` over every vector of `obj` (`(..., 3)`) after the domain check
/// `check` of the core.
fn map_nd<'py>(
    obj: &Bound<'py, PyAny>,
    argument: &str,
    check: fn(&str, &[Vector3<f64>]) -> memsnav_core::Result<()>,
    f: impl Fn(&Vector3<f64>) -> Vector3<f64>,
) -> PyResult<Bound<'py, PyArrayDyn<f64>>> {
    let (vectors, leading) = convert::vectors_nd(obj, argument)?;
    check(argument, &vectors).py()?;
    let out: Vec<Vector3<f64>> = vectors.iter().map(f).collect();
    convert::vectors_to_numpy_nd(obj.py(), &out, &leading)
}

/// ECEF position, m, of `lla`: geodetic [latitude rad, longitude rad,
/// height m] (3,) or (N, 3), WGS84.
#[catch_panics]
#[pyfunction]
fn geodetic_to_ecef<'py>(lla: &Bound<'py, PyAny>) -> PyResult<Bound<'py, PyArrayDyn<f64>>> {
    map_nd(lla, "lla", domain::check_geodetic, |v| {
        geodesy::geodetic_to_ecef(Geodetic::new(v.x, v.y, v.z))
    })
}

/// Geodetic [latitude rad, longitude rad, height m] of `xyz`: ECEF
/// positions, m, (3,) or (N, 3), WGS84.
#[catch_panics]
#[pyfunction]
fn ecef_to_geodetic<'py>(xyz: &Bound<'py, PyAny>) -> PyResult<Bound<'py, PyArrayDyn<f64>>> {
    map_nd(xyz, "xyz", domain::check_position_ecef, |r| {
        let g = geodesy::ecef_to_geodetic(r);
        Vector3::new(g.latitude_rad, g.longitude_rad, g.height_m)
    })
}

/// Gravity (J2 gravitation plus centrifugal) in ECEF, m/s², at
/// `position_ecef` (3,) or (N, 3), m.
#[catch_panics]
#[pyfunction]
fn gravity_ecef<'py>(position_ecef: &Bound<'py, PyAny>) -> PyResult<Bound<'py, PyArrayDyn<f64>>> {
    map_nd(
        position_ecef,
        "position_ecef",
        domain::check_position_ecef,
        geodesy::gravity_ecef,
    )
}

/// `position_ecef` (..., 3) minus `origin_ecef` (3,) in the local
/// north, east, down axes at the origin, m.
#[catch_panics]
#[pyfunction]
fn ecef_to_ned<'py>(
    position_ecef: &Bound<'py, PyAny>,
    origin_ecef: &Bound<'py, PyAny>,
) -> PyResult<Bound<'py, PyArrayDyn<f64>>> {
    let origin = convert::vector3(origin_ecef, "origin_ecef")?;
    domain::check_position_ecef("origin_ecef", &[origin]).py()?;
    map_nd(position_ecef, "position_ecef", no_check, |r| {
        geodesy::ned_offset(r, &origin)
    })
}

pub fn register(m: &Bound<'_, PyModule>) -> PyResult<()> {
    m.add_function(wrap_pyfunction!(ecef_to_ned, m)?)?;
    m.add_function(wrap_pyfunction!(geodetic_to_ecef, m)?)?;
    m.add_function(wrap_pyfunction!(ecef_to_geodetic, m)?)?;
    m.add_function(wrap_pyfunction!(gravity_ecef, m)?)?;
    Ok(())
}
