//! Position fixes from a solution file's geodetic rows (an RTKLIB `.pos`,
//! a fixes CSV, NMEA: [`crate::logs::PosSolution`]): thinned to a rate,
//! optionally degraded by seeded white noise (to play a metre-class
//! receiver from an RTK solution), with their NED covariance (full, or
//! diagonal from the stds) rotated into ECEF.

use nalgebra::{Matrix3, Vector3};
use rand_distr::{Distribution, StandardNormal};

use crate::coupling::PositionFix;
use crate::geodesy::{c_n_e, geodetic_to_ecef, Geodetic};
use crate::random::Rng;
use crate::{validate, Error, Result};

/// Velocity std used where a solution gives a velocity without its std,
/// m/s (a Doppler velocity's usual accuracy).
pub const MISSING_VELOCITY_STD_M_S: f64 = 0.1;

/// The rows of a geodetic solution.
#[derive(Debug, Clone, Copy)]
pub struct GeodeticSolution<'a> {
    /// Epoch times, s (GNSS time), increasing.
    pub time_s: &'a [f64],
    /// Latitude, longitude (rad), ellipsoidal height (m).
    pub geodetic: &'a [Vector3<f64>],
    /// Position covariance north, east, down, m² (diag(σ²) where a file
    /// gives only the stds: [`crate::logs::diagonal_covariances`]).
    pub covariance_ned_m2: &'a [Matrix3<f64>],
    /// Velocity north, east, down, m/s (NaN where absent), if any. North
    /// and east with a NaN down is a horizontal-only velocity (NMEA's speed
    /// and course over ground): its fix measures nothing along the vertical
    /// ([`PositionFix::velocity_horizontal_only`]).
    pub velocity_ned_m_s: Option<&'a [Vector3<f64>]>,
    /// Its covariance, (m/s)²; an axis whose variance is NaN stands for
    /// [`MISSING_VELOCITY_STD_M_S`] (the down axis of a horizontal-only
    /// velocity is not read).
    pub velocity_covariance_ned_m2_s2: Option<&'a [Matrix3<f64>]>,
}

/// `covariance` with every axis whose variance is not a finite
/// non-negative number replaced by [`MISSING_VELOCITY_STD_M_S`]² (its row
/// and column zeroed); None if another entry is not finite.
fn velocity_covariance_or_default(covariance: &Matrix3<f64>) -> Option<Matrix3<f64>> {
    let mut c = *covariance;
    for i in 0..3 {
        if !(c[(i, i)].is_finite() && c[(i, i)] >= 0.0) {
            for j in 0..3 {
                c[(i, j)] = 0.0;
                c[(j, i)] = 0.0;
            }
            c[(i, i)] = MISSING_VELOCITY_STD_M_S * MISSING_VELOCITY_STD_M_S;
        }
    }
    c.iter().all(|x| x.is_finite()).then_some(c)
}

/// Whether `c` is a finite symmetric matrix with non-negative variances.
fn plausible_covariance(c: &Matrix3<f64>) -> bool {
    c.iter().all(|x| x.is_finite())
        && c.diagonal().min() >= 0.0
        && (c - c.transpose()).abs().max() <= 1e-9 * c.abs().max()
}

/// How the rows become fixes.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct FixOptions {
    /// Keep only epochs on this rate's grid (within 20 ms, RTKLIB rounds
    /// its times to the millisecond); `None` keeps every epoch.
    pub rate_hz: Option<f64>,
    /// White noise added to the positions, north, east, down one-sigma, m.
    pub added_position_noise_ned_m: Vector3<f64>,
    /// White noise added to each velocity component, m/s.
    pub added_velocity_noise_m_s: f64,
    /// Use the velocities (when the solution has them).
    pub use_velocity: bool,
}

impl Default for FixOptions {
    fn default() -> Self {
        Self {
            rate_hz: None,
            added_position_noise_ned_m: Vector3::zeros(),
            added_velocity_noise_m_s: 0.0,
            use_velocity: true,
        }
    }
}

/// The fixes of `solution` with `options`; noise drawn from `rng`. The
/// covariance of each fix is its stated NED covariance plus the added
/// noise² on the diagonal, rotated from NED into ECEF (C_n^e P_n C_e^n).
pub fn fixes_from_geodetic(
    solution: &GeodeticSolution,
    options: &FixOptions,
    rng: &mut Rng,
) -> Result<Vec<PositionFix>> {
    let n = solution.time_s.len();
    validate::same_length("geodetic", solution.geodetic.len(), "time", n)?;
    validate::same_length(
        "covariance_ned",
        solution.covariance_ned_m2.len(),
        "time",
        n,
    )?;
    validate::increasing_times("time", solution.time_s)?;
    if let Some(v) = solution.velocity_ned_m_s {
        validate::same_length("velocity_ned", v.len(), "time", n)?;
    }
    if let Some(c) = solution.velocity_covariance_ned_m2_s2 {
        validate::same_length("velocity_covariance_ned", c.len(), "time", n)?;
    }
    validate::finite_vectors(
        "added_position_noise",
        &[options.added_position_noise_ned_m],
    )?;
    if options.added_position_noise_ned_m.min() < 0.0 {
        return Err(Error::invalid(
            "added_position_noise",
            "must not be negative",
        ));
    }
    validate::non_negative("added_velocity_noise", options.added_velocity_noise_m_s)?;
    if let Some(r) = options.rate_hz {
        validate::positive("rate_hz", r)?;
    }
    let on_grid = |t: f64| match options.rate_hz {
        Some(rate) => {
            let step = 1.0 / rate;
            ((t / step) - (t / step).round()).abs() * step < 0.02
        }
        None => true,
    };
    let noise = options.added_position_noise_ned_m;
    let mut out = Vec::new();
    for k in 0..n {
        let t = solution.time_s[k];
        let g = solution.geodetic[k];
        let covariance = solution.covariance_ned_m2[k];
        if !on_grid(t) {
            continue;
        }
        if !(g.iter().all(|v| v.is_finite()) && plausible_covariance(&covariance)) {
            return Err(Error::invalid(
                "solution",
                format!("epoch {k} (t = {t} s) has a non-finite position, or a covariance that is not finite and symmetric with non-negative variances (a negative or non-finite std)"),
            ));
        }
        let cne = c_n_e(g.x, g.y);
        let draw =
            |rng: &mut Rng| -> Vector3<f64> { Vector3::from_fn(|_, _| StandardNormal.sample(rng)) };
        let dn = draw(rng).component_mul(&noise);
        let position_ecef = geodetic_to_ecef(Geodetic::new(g.x, g.y, g.z)) + cne * dn;
        let p_ned = covariance + Matrix3::from_diagonal(&noise.component_mul(&noise));
        let position_covariance = cne * p_ned * cne.transpose();
        // North and east without down: a horizontal-only velocity (NMEA's
        // speed and course over ground), whose down component is not
        // measured and is given no value or variance.
        let velocity = solution
            .velocity_ned_m_s
            .map(|v| v[k])
            .filter(|v| options.use_velocity && v.x.is_finite() && v.y.is_finite());
        let horizontal_only = velocity.is_some_and(|v| !v.z.is_finite());
        let (velocity_ecef, velocity_covariance) = match velocity {
            Some(mut v) => {
                let vn = options.added_velocity_noise_m_s;
                let mut given = solution
                    .velocity_covariance_ned_m2_s2
                    .map_or(Matrix3::repeat(f64::NAN), |c| c[k]);
                let mut noise_std = Vector3::repeat(vn);
                if horizontal_only {
                    v.z = 0.0;
                    noise_std.z = 0.0;
                    given.row_mut(2).fill(0.0);
                    given.column_mut(2).fill(0.0);
                }
                let c = velocity_covariance_or_default(&given).ok_or_else(|| {
                    Error::invalid(
                        "velocity_covariance_ned",
                        format!("epoch {k} (t = {t} s) has a non-finite covariance term"),
                    )
                })?;
                let dv = draw(rng).component_mul(&noise_std);
                let noise = Matrix3::from_diagonal(&noise_std.component_mul(&noise_std));
                (Some(cne * (v + dv)), cne * (c + noise) * cne.transpose())
            }
            None => (None, Matrix3::zeros()),
        };
        out.push(PositionFix {
            time_s: t,
            position_ecef,
            position_covariance,
            velocity_ecef,
            velocity_covariance,
            velocity_horizontal_only: horizontal_only,
        });
    }
    Ok(out)
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::logs::diagonal_covariances;
    use crate::random::stream;

    /// Thinning keeps the rate's grid; without noise the fix is the point
    /// and its covariance has the NED stds along the local axes.
    #[test]
    fn fixes_keep_the_grid_and_rotate_the_covariance() {
        let t: Vec<f64> = (0..12).map(|k| 100.0 + k as f64 * 0.25 + 0.001).collect();
        let g = vec![Vector3::new(0.7, 0.2, 50.0); t.len()];
        let s = diagonal_covariances(&vec![Vector3::new(0.01, 0.02, 0.03); t.len()]);
        let v = vec![Vector3::new(1.0, 2.0, 0.0); t.len()];
        let sol = GeodeticSolution {
            time_s: &t,
            geodetic: &g,
            covariance_ned_m2: &s,
            velocity_ned_m_s: Some(&v),
            velocity_covariance_ned_m2_s2: None,
        };
        let opts = FixOptions {
            rate_hz: Some(1.0),
            ..Default::default()
        };
        let fixes = fixes_from_geodetic(&sol, &opts, &mut stream(1, 0)).unwrap();
        assert_eq!(fixes.len(), 3);
        let cne = c_n_e(0.7, 0.2);
        let f = &fixes[0];
        assert!((f.position_ecef - geodetic_to_ecef(Geodetic::new(0.7, 0.2, 50.0))).norm() < 1e-9);
        let ned = cne.transpose() * f.position_covariance * cne;
        assert!(
            (ned - Matrix3::from_diagonal(&Vector3::new(1e-4, 4e-4, 9e-4)))
                .abs()
                .max()
                < 1e-15
        );
        let vned = cne.transpose() * f.velocity_ecef.unwrap();
        assert!((vned - Vector3::new(1.0, 2.0, 0.0)).norm() < 1e-12);
        let vcov = cne.transpose() * f.velocity_covariance * cne;
        assert!((vcov[(0, 0)] - MISSING_VELOCITY_STD_M_S.powi(2)).abs() < 1e-15);
    }

    /// Added noise has the requested std in each NED direction.
    #[test]
    fn added_noise_has_its_std() {
        let n = 4000;
        let t: Vec<f64> = (0..n).map(|k| k as f64).collect();
        let g = vec![Vector3::new(-0.3, 2.0, 10.0); n];
        let s = vec![Matrix3::zeros(); n];
        let sol = GeodeticSolution {
            time_s: &t,
            geodetic: &g,
            covariance_ned_m2: &s,
            velocity_ned_m_s: None,
            velocity_covariance_ned_m2_s2: None,
        };
        let opts = FixOptions {
            added_position_noise_ned_m: Vector3::new(1.0, 2.0, 3.0),
            ..Default::default()
        };
        let fixes = fixes_from_geodetic(&sol, &opts, &mut stream(5, 0)).unwrap();
        let cne = c_n_e(-0.3, 2.0);
        let origin = geodetic_to_ecef(Geodetic::new(-0.3, 2.0, 10.0));
        let e: Vec<Vector3<f64>> = fixes
            .iter()
            .map(|f| cne.transpose() * (f.position_ecef - origin))
            .collect();
        for (axis, want) in [1.0, 2.0, 3.0].into_iter().enumerate() {
            let std = (e.iter().map(|x| x[axis] * x[axis]).sum::<f64>() / n as f64).sqrt();
            assert!((std / want - 1.0).abs() < 0.05, "axis {axis}: {std}");
        }
        assert!(fixes[0].velocity_ecef.is_none());
    }

    /// A full NED covariance reaches the fix whole (rotated), a velocity
    /// covariance with one unknown axis gets the default there, and a
    /// velocity without its down component is horizontal only.
    #[test]
    fn full_covariances_are_kept() {
        let t = [0.0, 1.0];
        let g = [Vector3::new(0.7, 0.2, 50.0); 2];
        let p = Matrix3::new(4.0, 1.5, -0.5, 1.5, 9.0, 0.3, -0.5, 0.3, 16.0);
        let nan = f64::NAN;
        let pv = Matrix3::new(0.04, 0.01, nan, 0.01, 0.09, nan, nan, nan, nan);
        let v = [Vector3::new(1.0, 2.0, 0.5); 2];
        let sol = GeodeticSolution {
            time_s: &t,
            geodetic: &g,
            covariance_ned_m2: &[p; 2],
            velocity_ned_m_s: Some(&v),
            velocity_covariance_ned_m2_s2: Some(&[pv; 2]),
        };
        let fixes = fixes_from_geodetic(&sol, &FixOptions::default(), &mut stream(1, 0)).unwrap();
        let cne = c_n_e(0.7, 0.2);
        let back = cne.transpose() * fixes[0].position_covariance * cne;
        assert!((back - p).abs().max() < 1e-12, "{back}");
        let vback = cne.transpose() * fixes[0].velocity_covariance * cne;
        let want = Matrix3::new(0.04, 0.01, 0.0, 0.01, 0.09, 0.0, 0.0, 0.0, 0.01);
        assert!((vback - want).abs().max() < 1e-15, "{vback}");
        assert!(!fixes[0].velocity_horizontal_only);
        // North and east with a NaN down: a horizontal-only velocity, its
        // NE covariance kept and nothing along the vertical.
        let horizontal = [Vector3::new(1.0, 2.0, nan); 2];
        let only_h = GeodeticSolution {
            velocity_ned_m_s: Some(&horizontal),
            ..sol
        };
        let fixes =
            fixes_from_geodetic(&only_h, &FixOptions::default(), &mut stream(1, 0)).unwrap();
        assert!(fixes[0].velocity_horizontal_only);
        let vned = cne.transpose() * fixes[0].velocity_ecef.unwrap();
        assert!(
            (vned - Vector3::new(1.0, 2.0, 0.0)).norm() < 1e-12,
            "{vned}"
        );
        let vback = cne.transpose() * fixes[0].velocity_covariance * cne;
        let want = Matrix3::new(0.04, 0.01, 0.0, 0.01, 0.09, 0.0, 0.0, 0.0, 0.0);
        assert!((vback - want).abs().max() < 1e-15, "{vback}");
        let skew = Matrix3::new(1.0, 0.5, 0.0, -0.5, 1.0, 0.0, 0.0, 0.0, 1.0);
        let bad = GeodeticSolution {
            covariance_ned_m2: &[skew; 2],
            ..sol
        };
        assert!(fixes_from_geodetic(&bad, &FixOptions::default(), &mut stream(1, 0)).is_err());
    }
}
