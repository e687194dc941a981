//! A solution's uncertainties in local north-east-down axes: the filter's
//! covariance is in ECEF axes, but 3σ bounds against a local-level truth
//! (north, east, height) need it rotated into the NED frame of each sample.

use nalgebra::{Matrix3, Vector3};

use super::engine::Solution;
use crate::geodesy::{c_n_e, ecef_to_geodetic};

/// `covariance_ecef` expressed in the local NED axes at `position_ecef`:
/// P^n = C_e^n P^e C_n^e (a covariance transforms as R P Rᵀ with R = C_e^n;
/// C_n^e of Groves eq. 2.150 at the geodetic latitude and longitude).
pub fn covariance_ned(
    position_ecef: &Vector3<f64>,
    covariance_ecef: &Matrix3<f64>,
) -> Matrix3<f64> {
    let geo = ecef_to_geodetic(position_ecef);
    let cne = c_n_e(geo.latitude_rad, geo.longitude_rad);
    cne.transpose() * covariance_ecef * cne
}

impl Solution {
    /// One-sigma position uncertainty along north, east, down, m, per sample.
    pub fn position_std_ned(&self) -> Vec<Vector3<f64>> {
        self.std_ned(Self::position_covariance_ecef)
    }

    /// One-sigma velocity uncertainty along north, east, down, m/s, per sample.
    pub fn velocity_std_ned(&self) -> Vec<Vector3<f64>> {
        self.std_ned(Self::velocity_covariance_ecef)
    }

    /// One-sigma attitude uncertainty about north, east, down, rad, per sample.
    pub fn attitude_std_ned(&self) -> Vec<Vector3<f64>> {
        self.std_ned(Self::attitude_covariance_ecef)
    }

    /// Square roots of the NED diagonal of each sample's block, at the
    /// sample's own position (negative round-off variances read as zero).
    fn std_ned(&self, block: fn(&Self, usize) -> Matrix3<f64>) -> Vec<Vector3<f64>> {
        self.position_ecef
            .iter()
            .enumerate()
            .map(|(k, r)| {
                covariance_ned(r, &block(self, k))
                    .diagonal()
                    .map(|v| v.max(0.0).sqrt())
            })
            .collect()
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::geodesy::{geodetic_to_ecef, Geodetic};

    /// On the equator at longitude 0, north is +z, east +y and down −x of
    /// ECEF, so a diagonal ECEF covariance permutes.
    #[test]
    fn equator_axes_permute() {
        let r = geodetic_to_ecef(Geodetic::new(0.0, 0.0, 0.0));
        let p = Matrix3::from_diagonal(&Vector3::new(1.0, 4.0, 9.0));
        let n = covariance_ned(&r, &p);
        assert!(
            (n - Matrix3::from_diagonal(&Vector3::new(9.0, 4.0, 1.0)))
                .abs()
                .max()
                < 1e-12
        );
    }

    /// A rotation keeps the trace and the eigenvalues' product, and an
    /// isotropic covariance stays isotropic.
    #[test]
    fn rotation_invariants() {
        let r = geodetic_to_ecef(Geodetic::new(0.76, 0.025, 150.0));
        let a = Matrix3::new(2.0, 0.3, -0.1, 0.0, 1.5, 0.4, 0.2, 0.0, 3.0);
        let p = a * a.transpose();
        let n = covariance_ned(&r, &p);
        assert!((n.trace() - p.trace()).abs() < 1e-12);
        assert!((n.determinant() - p.determinant()).abs() < 1e-9);
        let iso = covariance_ned(&r, &(Matrix3::identity() * 4.0));
        assert!((iso - Matrix3::identity() * 4.0).abs().max() < 1e-12);
    }
}
