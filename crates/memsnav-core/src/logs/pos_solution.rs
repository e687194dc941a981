//! The one geodetic solution every fix reader gives ([`PosSolution`]):
//! RTKLIB `.pos` ([`super::parse_pos`]), the fixes CSV
//! ([`super::parse_fixes_csv`]) and NMEA ([`super::parse_nmea`]); loose
//! coupling ([`crate::navigate::fixes_from_geodetic`]) and the truth read
//! it whatever the file was.

use nalgebra::{Matrix3, Vector3};

/// Largest standard deviation or covariance term accepted, m or m/s.
pub const MAX_STD: f64 = 1.0e7;

/// RTKLIB's solution quality flags: 0 none, 1 fix, 2 float, 3 SBAS,
/// 4 DGPS, 5 single, 6 PPP, 7 dead reckoning (demo5).
pub(super) const QUALITY_RANGE: std::ops::RangeInclusive<f64> = 0.0..=7.0;

/// A GNSS solution in geodetic form, one row per epoch.
#[derive(Debug, Clone, PartialEq)]
pub struct PosSolution {
    /// Epochs, GPS s since 1980-01-06, strictly increasing.
    pub gps_time_s: Vec<f64>,
    /// [latitude rad, longitude rad, ellipsoidal height m].
    pub lla: Vec<Vector3<f64>>,
    /// RTKLIB's Q (1 fix, 2 float, 3 SBAS, 4 DGPS, 5 single, 6 PPP,
    /// 7 dead reckoning); other formats' flags are mapped onto it.
    pub quality: Vec<u8>,
    /// Satellites used.
    pub n_satellites: Vec<u16>,
    /// One-sigma position uncertainty north, east, down (RTKLIB's sdn,
    /// sde, sdu), m; NaN when the file gives none (a fixes CSV truth).
    pub std_ned_m: Vec<Vector3<f64>>,
    /// The full position covariance north, east, down, m², when the file
    /// gives one (its diagonal is `std_ned_m`²); None: the stds only.
    pub covariance_ned_m2: Option<Vec<Matrix3<f64>>>,
    /// NED velocity, m/s; NaN when the file has no velocity (or, NMEA, no
    /// vertical velocity).
    pub velocity_ned_m_s: Vec<Vector3<f64>>,
    /// One-sigma velocity uncertainty north, east, down, m/s; NaN likewise.
    pub velocity_std_ned_m_s: Vec<Vector3<f64>>,
    /// The full velocity covariance, (m/s)², when the file gives one.
    pub velocity_covariance_ned_m2_s2: Option<Vec<Matrix3<f64>>>,
    /// The attitude C_b^n (body to local NED) of every epoch, when the
    /// file gives one (a fixes CSV from an INS: the truth's attitude, to
    /// move it by a lever arm).
    pub attitude_c_b_n: Option<Vec<Matrix3<f64>>>,
    /// Lines skipped, one sentence each.
    pub warnings: Vec<String>,
}

impl PosSolution {
    /// An empty solution with room for `n` epochs.
    pub(super) fn with_capacity(n: usize) -> Self {
        Self {
            gps_time_s: Vec::with_capacity(n),
            lla: Vec::with_capacity(n),
            quality: Vec::with_capacity(n),
            n_satellites: Vec::with_capacity(n),
            std_ned_m: Vec::with_capacity(n),
            covariance_ned_m2: None,
            velocity_ned_m_s: Vec::with_capacity(n),
            velocity_std_ned_m_s: Vec::with_capacity(n),
            velocity_covariance_ned_m2_s2: None,
            attitude_c_b_n: None,
            warnings: Vec::new(),
        }
    }

    /// The position covariance of every epoch, NED, m²: the file's full
    /// one, else diag(std²).
    pub fn position_covariance_ned_m2(&self) -> Vec<Matrix3<f64>> {
        full_or_diagonal(self.covariance_ned_m2.as_deref(), &self.std_ned_m)
    }

    /// The velocity covariance of every epoch, NED, (m/s)²: the file's
    /// full one, else diag(std²) (NaN where the std is).
    pub fn velocity_covariance_ned_m2_s2(&self) -> Vec<Matrix3<f64>> {
        full_or_diagonal(
            self.velocity_covariance_ned_m2_s2.as_deref(),
            &self.velocity_std_ned_m_s,
        )
    }
}

/// `full` when given, else [`diagonal_covariances`] of `std`.
fn full_or_diagonal(full: Option<&[Matrix3<f64>]>, std: &[Vector3<f64>]) -> Vec<Matrix3<f64>> {
    match full {
        Some(c) => c.to_vec(),
        None => diagonal_covariances(std),
    }
}

/// diag(σ²) of each row of stds (NaN stays NaN).
pub fn diagonal_covariances(std: &[Vector3<f64>]) -> Vec<Matrix3<f64>> {
    std.iter()
        .map(|s| Matrix3::from_diagonal(&s.component_mul(s)))
        .collect()
}

/// The stds of a covariance (√ of its diagonal).
pub(super) fn std_of(covariance: &Matrix3<f64>) -> Vector3<f64> {
    covariance.diagonal().map(f64::sqrt)
}

/// `Err` naming `what` unless `covariance` is symmetric positive
/// semi-definite (its smallest eigenvalue not below −1e-12 of its trace:
/// rounding in a file's digits).
pub(super) fn check_covariance(
    covariance: &Matrix3<f64>,
    what: &str,
    unit: &str,
) -> std::result::Result<(), String> {
    let min = covariance.symmetric_eigenvalues().min();
    if min < -1e-12 * covariance.trace().abs() {
        return Err(format!(
            "{what} is not a covariance (not positive semi-definite: smallest eigenvalue {min:.3e} {unit})"
        ));
    }
    Ok(())
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn covariance_checks_and_diagonal_fallback() {
        let ok = Matrix3::new(4.0, 1.0, 0.0, 1.0, 9.0, 0.0, 0.0, 0.0, 1.0);
        assert!(check_covariance(&ok, "c", "m²").is_ok());
        // |ρ| = 4 / (1·2) > 1: eigenvalues 2.5 ± √(1.5² + 16), one negative.
        let bad = Matrix3::new(1.0, 4.0, 0.0, 4.0, 4.0, 0.0, 0.0, 0.0, 1.0);
        let e = check_covariance(&bad, "position covariance", "m²").unwrap_err();
        assert!(e.contains("not positive semi-definite"), "{e}");
        assert_eq!(std_of(&ok), Vector3::new(2.0, 3.0, 1.0));
        let mut s = PosSolution::with_capacity(1);
        s.std_ned_m.push(Vector3::new(1.0, 2.0, 3.0));
        s.velocity_std_ned_m_s.push(Vector3::repeat(f64::NAN));
        assert_eq!(
            s.position_covariance_ned_m2()[0],
            Matrix3::from_diagonal(&Vector3::new(1.0, 4.0, 9.0))
        );
        assert!(s.velocity_covariance_ned_m2_s2()[0][(0, 0)].is_nan());
    }
}
