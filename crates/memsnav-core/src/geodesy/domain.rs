//! Where the geodesy is defined: the ranges the public entry points accept.
//!
//! Geodetic latitude is undefined on the polar axis near the centre (every
//! latitude fits the origin) and the series of the inverse lose meaning
//! deep inside the Earth, so positions are accepted from 100 km below the
//! ellipsoid (ten times the deepest ocean) to 10⁹ m above it (beyond the
//! Moon's orbit, so GNSS orbits and their propagation stay inside).

use nalgebra::Vector3;

use super::wgs84::{SEMI_MAJOR_AXIS_M, SEMI_MINOR_AXIS_M};
use crate::{Error, Result};

/// Lowest height accepted, m below the ellipsoid.
pub const MIN_HEIGHT_M: f64 = -1e5;
/// Highest height accepted, m above the ellipsoid.
pub const MAX_HEIGHT_M: f64 = 1e9;

/// `[latitude rad, longitude rad, height m]` rows within the ranges: the
/// latitude in [−90°, 90°], the height in [[`MIN_HEIGHT_M`], [`MAX_HEIGHT_M`]].
pub fn check_geodetic(argument: &str, rows: &[Vector3<f64>]) -> Result<()> {
    for (k, g) in rows.iter().enumerate() {
        if g.x.is_nan() || g.x.abs() > std::f64::consts::FRAC_PI_2 {
            return Err(Error::invalid(
                argument,
                format!(
                    "row {k}: latitude {}° is outside [-90°, 90°] (radians expected)",
                    g.x.to_degrees()
                ),
            ));
        }
        if !(MIN_HEIGHT_M..=MAX_HEIGHT_M).contains(&g.z) {
            return Err(Error::invalid(
                argument,
                format!(
                    "row {k}: height {} m is outside [{MIN_HEIGHT_M:e}, {MAX_HEIGHT_M:e}] m",
                    g.z
                ),
            ));
        }
    }
    Ok(())
}

/// The largest distance from the Earth's centre of any position, m (the
/// height range's top at the equator). Beyond it a line of sight's
/// square overflows long before 1e154 m and the geometry of a fix stops
/// being a number (a `solve_fix` prior of 1e200 m hung).
pub const MAX_DISTANCE_M: f64 = SEMI_MAJOR_AXIS_M + MAX_HEIGHT_M;

/// ECEF positions whose distance from the centre fits the height range
/// (the bound below is taken at the pole, the one above at the equator).
pub fn check_position_ecef(argument: &str, rows: &[Vector3<f64>]) -> Result<()> {
    let (low, high) = (SEMI_MINOR_AXIS_M + MIN_HEIGHT_M, MAX_DISTANCE_M);
    match rows.iter().position(|r| !(low..=high).contains(&r.norm())) {
        None => Ok(()),
        Some(k) => Err(Error::invalid(
            argument,
            format!(
                "row {k}: {} m from the Earth's centre, outside [{low:.0}, {high:e}] m \
                 (heights from {MIN_HEIGHT_M:e} to {MAX_HEIGHT_M:e} m; ECEF metres expected)",
                rows[k].norm()
            ),
        )),
    }
}

/// The largest speed of anything navigated or simulated, m/s (10⁵: nine
/// times the Earth's escape velocity). Beyond it a second of motion leaves
/// the position domain's scale and its products overflow.
pub const MAX_SPEED_M_S: f64 = 1e5;

/// Velocities (ECEF or NED: the speed is the same) of at most
/// [`MAX_SPEED_M_S`]; NaN fails too.
pub fn check_speed(argument: &str, rows: &[Vector3<f64>]) -> Result<()> {
    match rows
        .iter()
        .position(|v| v.norm().is_nan() || v.norm() > MAX_SPEED_M_S)
    {
        None => Ok(()),
        Some(k) => Err(Error::invalid(
            argument,
            format!(
                "row {k}: a speed of {} m/s, beyond the limit of {MAX_SPEED_M_S:e} m/s \
                 (m/s expected)",
                rows[k].norm()
            ),
        )),
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_centre_poles_and_depths_are_refused_with_the_row() {
        let ok = Vector3::new(SEMI_MAJOR_AXIS_M, 0.0, 0.0);
        assert!(check_position_ecef("xyz", &[ok]).is_ok());
        for bad in [
            Vector3::zeros(),
            Vector3::new(1e-3, 0.0, 0.0),
            Vector3::new(2e9, 0.0, 0.0),
        ] {
            let e = check_position_ecef("xyz", &[ok, bad])
                .unwrap_err()
                .to_string();
            assert!(e.contains("xyz") && e.contains("row 1"), "{e}");
        }
        assert!(check_geodetic(
            "lla",
            &[Vector3::new(std::f64::consts::FRAC_PI_2, 3.0, -1e4)]
        )
        .is_ok());
        for bad in [
            Vector3::new(1.6, 0.0, 0.0),
            Vector3::new(0.0, 0.0, -1e7),
            Vector3::new(0.0, 0.0, f64::NAN),
        ] {
            assert!(check_geodetic("lla", &[bad])
                .unwrap_err()
                .to_string()
                .contains("row 0"));
        }
    }
}
