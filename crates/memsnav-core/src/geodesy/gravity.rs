//! Gravity in ECEF: gravitation from the J2 model plus the centrifugal term.
//!
//! The INS and the trajectory generator use this one model, so an INS fed
//! the generator's exact IMU truth closes on the trajectory.

use nalgebra::Vector3;

use super::wgs84::{
    EARTH_RATE_RAD_S, ECCENTRICITY_SQUARED, GM_M3_S2, GRAVITY_EQUATOR_M_S2, J2, SEMI_MAJOR_AXIS_M,
    SOMIGLIANA_K,
};

/// Gravitational acceleration γ^e (no centrifugal term), m/s², from the
/// J2 (oblateness) model, Groves eq. 2.142.
pub fn gravitation_ecef(r: &Vector3<f64>) -> Vector3<f64> {
    let r2 = r.norm_squared();
    let norm = r2.sqrt();
    let z_ratio2 = r.z * r.z / r2;
    let j2_term = 1.5 * J2 * SEMI_MAJOR_AXIS_M * SEMI_MAJOR_AXIS_M / r2;
    let horizontal = 1.0 + j2_term * (1.0 - 5.0 * z_ratio2);
    let vertical = 1.0 + j2_term * (3.0 - 5.0 * z_ratio2);
    -GM_M3_S2 / (r2 * norm) * Vector3::new(r.x * horizontal, r.y * horizontal, r.z * vertical)
}

/// Gravity g^e = γ^e − ω_ie × (ω_ie × r^e), m/s² (Groves eq. 2.133): the
/// acceleration a plumb bob at rest on the rotating Earth feels.
pub fn gravity_ecef(r: &Vector3<f64>) -> Vector3<f64> {
    let w2 = EARTH_RATE_RAD_S * EARTH_RATE_RAD_S;
    gravitation_ecef(r) + Vector3::new(w2 * r.x, w2 * r.y, 0.0)
}

/// Magnitude of normal gravity on the ellipsoid surface by Somigliana's
/// closed formula (NIMA TR8350.2 eq. 4-1; Groves eq. 2.134). An independent
/// model used to check [`gravity_ecef`].
pub fn normal_gravity_somigliana(latitude_rad: f64) -> f64 {
    let s2 = latitude_rad.sin().powi(2);
    GRAVITY_EQUATOR_M_S2 * (1.0 + SOMIGLIANA_K * s2) / (1.0 - ECCENTRICITY_SQUARED * s2).sqrt()
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::geodesy::{c_n_e, geodetic_to_ecef, Geodetic};

    #[test]
    fn j2_gravity_matches_somigliana_on_the_ellipsoid() {
        for lat_deg in [-90.0_f64, -45.0, 0.0, 10.0, 45.0, 60.0, 89.0] {
            let lat = lat_deg.to_radians();
            let r = geodetic_to_ecef(Geodetic::new(lat, 0.3, 0.0));
            let g = gravity_ecef(&r);
            // The J2-truncated field differs from normal gravity by the
            // neglected J4 and higher terms: at most 1.2e-4 m/s² (12 µg,
            // at the poles; 4e-5 at the equator).
            assert!(
                (g.norm() - normal_gravity_somigliana(lat)).abs() < 1.3e-4,
                "{lat_deg}: {}",
                g.norm()
            );
            // Normal gravity is perpendicular to the ellipsoid: along NED down
            // to within the deflection of the J2-only field, whose level
            // surface is not exactly the WGS84 ellipsoid (second-order terms
            // in f and the neglected J4): at most 6.3e-6 rad (1.3 arcsec) over
            // all latitudes.
            let down = c_n_e(lat, 0.3).column(2).into_owned();
            let deflection = g.normalize().cross(&down).norm();
            assert!(
                deflection < 6.5e-6 && g.dot(&down) > 0.0,
                "{lat_deg}: {deflection:e}"
            );
        }
    }

    #[test]
    fn free_air_gradient() {
        let lat = 0.8;
        let g0 = gravity_ecef(&geodetic_to_ecef(Geodetic::new(lat, 0.0, 0.0))).norm();
        let g1 = gravity_ecef(&geodetic_to_ecef(Geodetic::new(lat, 0.0, 1000.0))).norm();
        // ≈ −3.086e-6 s⁻² (textbook free-air gradient).
        assert!(((g1 - g0) / 1000.0 + 3.086e-6).abs() < 0.01e-6);
    }
}
