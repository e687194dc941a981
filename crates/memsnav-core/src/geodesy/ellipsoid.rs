//! Geodetic ↔ ECEF and the local NED frame on the WGS84 ellipsoid.

use nalgebra::{Matrix3, Vector3};

use super::wgs84::{ECCENTRICITY_SQUARED as E2, SEMI_MAJOR_AXIS_M as A, SEMI_MINOR_AXIS_M as B};

/// Geodetic coordinates: latitude and longitude in rad, ellipsoidal height in m.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Geodetic {
    /// Geodetic latitude, rad.
    pub latitude_rad: f64,
    /// Longitude, rad.
    pub longitude_rad: f64,
    /// Height above the ellipsoid, m.
    pub height_m: f64,
}

impl Geodetic {
    /// The coordinates as given.
    pub fn new(latitude_rad: f64, longitude_rad: f64, height_m: f64) -> Self {
        Self {
            latitude_rad,
            longitude_rad,
            height_m,
        }
    }
}

/// Transverse (prime vertical) radius of curvature R_E(φ), m (Groves eq. 2.106).
pub fn transverse_radius(latitude_rad: f64) -> f64 {
    A / (1.0 - E2 * latitude_rad.sin().powi(2)).sqrt()
}

/// Meridian radius of curvature R_N(φ), m (Groves eq. 2.105).
pub fn meridian_radius(latitude_rad: f64) -> f64 {
    A * (1.0 - E2) / (1.0 - E2 * latitude_rad.sin().powi(2)).powf(1.5)
}

/// Geodetic → ECEF position, m (Groves eq. 2.112).
pub fn geodetic_to_ecef(g: Geodetic) -> Vector3<f64> {
    geodetic_to_ecef_with(
        g.latitude_rad.sin_cos(),
        g.longitude_rad.sin_cos(),
        transverse_radius(g.latitude_rad),
        g.height_m,
    )
}

/// [`geodetic_to_ecef`] from (sin, cos) of the latitude and longitude and
/// the transverse radius R_E at the latitude (same arithmetic).
pub fn geodetic_to_ecef_with(
    (sin_lat, cos_lat): (f64, f64),
    (sin_lon, cos_lon): (f64, f64),
    r_e: f64,
    height_m: f64,
) -> Vector3<f64> {
    Vector3::new(
        (r_e + height_m) * cos_lat * cos_lon,
        (r_e + height_m) * cos_lat * sin_lon,
        ((1.0 - E2) * r_e + height_m) * sin_lat,
    )
}

/// ECEF → geodetic.
///
/// Bowring's (1976) closed-form start, then fixed-point refinement of the
/// latitude with the height written as h = p cos φ + z sin φ − a √(1 − e² sin² φ),
/// which stays well conditioned at the poles (p → 0) where the usual
/// h = p / cos φ − R_E does not. Three iterations reach 1e-15 rad from the
/// centre of the Earth out to GNSS orbits; the loop stops at convergence.
pub fn ecef_to_geodetic(r: &Vector3<f64>) -> Geodetic {
    let (x, y, z) = (r.x, r.y, r.z);
    let p = x.hypot(y);
    let longitude_rad = y.atan2(x);
    let ep2 = (A * A - B * B) / (B * B);
    // Bowring's start via the parametric (reduced) latitude β.
    let beta = z.atan2(p * (1.0 - super::wgs84::FLATTENING));
    let (sin_b, cos_b) = beta.sin_cos();
    let mut latitude_rad = (z + ep2 * B * sin_b.powi(3)).atan2(p - E2 * A * cos_b.powi(3));
    for _ in 0..8 {
        let r_e = transverse_radius(latitude_rad);
        let height_m = ellipsoidal_height(p, z, latitude_rad);
        let next = z.atan2(p * (1.0 - E2 * r_e / (r_e + height_m)));
        let converged = (next - latitude_rad).abs() < 1e-15;
        latitude_rad = next;
        if converged {
            break;
        }
    }
    let height_m = ellipsoidal_height(p, z, latitude_rad);
    Geodetic::new(latitude_rad, longitude_rad, height_m)
}

/// h = p cos φ + z sin φ − a √(1 − e² sin² φ): the distance from the
/// ellipsoid along its normal, valid at every latitude including ±90°.
fn ellipsoidal_height(p: f64, z: f64, latitude_rad: f64) -> f64 {
    let (sin_lat, cos_lat) = latitude_rad.sin_cos();
    p * cos_lat + z * sin_lat - A * (1.0 - E2 * sin_lat * sin_lat).sqrt()
}

/// Rotation from local NED to ECEF, C_n^e (Groves eq. 2.150, transposed).
pub fn c_n_e(latitude_rad: f64, longitude_rad: f64) -> Matrix3<f64> {
    c_n_e_with(latitude_rad.sin_cos(), longitude_rad.sin_cos())
}

/// [`c_n_e`] from (sin, cos) of the latitude and of the longitude.
pub fn c_n_e_with((sl, cl): (f64, f64), (so, co): (f64, f64)) -> Matrix3<f64> {
    Matrix3::new(
        -sl * co,
        -so,
        -cl * co, //
        -sl * so,
        co,
        -cl * so, //
        cl,
        0.0,
        -sl,
    )
}

/// `position_ecef − origin_ecef` in the local NED axes at `origin_ecef`
/// (a tangent-plane offset: north, east, down metres from the origin).
pub fn ned_offset(position_ecef: &Vector3<f64>, origin_ecef: &Vector3<f64>) -> Vector3<f64> {
    let g = ecef_to_geodetic(origin_ecef);
    c_n_e(g.latitude_rad, g.longitude_rad).transpose() * (position_ecef - origin_ecef)
}

#[cfg(test)]
mod tests {
    use super::*;
    use std::f64::consts::FRAC_PI_2;

    #[test]
    fn round_trip_everywhere() {
        for lat_deg in [-90.0, -89.999_999, -60.0, -1e-9, 0.0, 33.3, 89.999_99, 90.0] {
            for lon_deg in [-180.0, -45.0, 0.0, 120.0] {
                for h in [-5_000.0, 0.0, 300.0, 20_200_000.0] {
                    let g = Geodetic::new(f64::to_radians(lat_deg), f64::to_radians(lon_deg), h);
                    let r = geodetic_to_ecef(g);
                    let back = geodetic_to_ecef(ecef_to_geodetic(&r));
                    assert!(
                        (back - r).norm() < 1e-6,
                        "{lat_deg} {lon_deg} {h}: {}",
                        (back - r).norm()
                    );
                }
            }
        }
    }

    #[test]
    fn poles_and_equator_are_exact() {
        let north = ecef_to_geodetic(&Vector3::new(0.0, 0.0, B + 100.0));
        assert!((north.latitude_rad - FRAC_PI_2).abs() < 1e-15);
        assert!((north.height_m - 100.0).abs() < 1e-9);
        let equator = ecef_to_geodetic(&Vector3::new(A + 10.0, 0.0, 0.0));
        assert!(equator.latitude_rad.abs() < 1e-15);
        assert!((equator.height_m - 10.0).abs() < 1e-9);
    }

    /// A point moved 10 m north, 5 m east and 2 m up from the origin.
    #[test]
    fn ned_offsets_of_a_nearby_point() {
        let (lat, lon) = (0.7_f64, -1.2_f64);
        let origin = geodetic_to_ecef(Geodetic::new(lat, lon, 100.0));
        let p = origin + c_n_e(lat, lon) * Vector3::new(10.0, 5.0, -2.0);
        assert!((ned_offset(&p, &origin) - Vector3::new(10.0, 5.0, -2.0)).norm() < 1e-9);
    }

    #[test]
    fn ned_axes_point_where_they_should() {
        let lat = 0.7_f64;
        let lon = -1.2_f64;
        let c = c_n_e(lat, lon);
        assert!((c.transpose() * c - Matrix3::identity()).abs().max() < 1e-15);
        assert!((c.determinant() - 1.0).abs() < 1e-15);
        // Down is minus the ellipsoid normal; north follows increasing latitude.
        let g = Geodetic::new(lat, lon, 0.0);
        let up = geodetic_to_ecef(Geodetic::new(lat, lon, 1.0)) - geodetic_to_ecef(g);
        assert!((c.column(2) + up).norm() < 1e-9);
        let north = geodetic_to_ecef(Geodetic::new(lat + 1e-7, lon, 0.0)) - geodetic_to_ecef(g);
        assert!((c.column(0) - north.normalize()).norm() < 1e-6);
    }
}
