//! The residual test of a single-point fix (receiver autonomous integrity
//! monitoring by fault detection and exclusion; Groves 2013, §17.4.2;
//! Teunissen 2003, §4.5).
//!
//! Detection: with n pseudoranges and p unknowns, the weighted post-fit
//! residuals' sum of squares T = Σ (vᵢ/σᵢ)² is χ²(n − p) when each σᵢ is
//! right and no pseudorange is faulty; T above the χ²(n − p) quantile
//! 1 − P_fa flags a fault with false-alarm probability P_fa per epoch.
//! Exclusion: the satellite with the largest normalized residual
//! |vᵢ| / (σᵢ √rᵢ) (Baarda's w-test; rᵢ its redundancy number) is left
//! out and the fix and test are made again, while the redundancy allows
//! a test after the exclusion (n − p ≥ 2 before it). A fix whose last
//! test still fails is returned with the statistic above its threshold:
//! the caller decides (RTKLIB rejects such a solution; memsnav keeps it
//! and says so).
//!
//! The test is as good as the σ it is given: with RTKLIB's error model
//! (`super::pseudorange_weights`) the statistic per degree of freedom on
//! clean real epochs is below one, so false alarms stay below P_fa.

use nalgebra::Vector3;

use super::fix::{post_fit_residuals, solve_fix_all_satellites, Fix};
use super::GnssEpoch;
use crate::chi_square::chi_square_quantile;
use crate::{Error, Result};

/// Default false-alarm probability of the residual test per epoch (RTKLIB's
/// `valsol` threshold, `chisqr[]` at α = 0.001).
pub const DEFAULT_FALSE_ALARM_PROBABILITY: f64 = 1e-3;

/// The residual test's setting.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct ResidualTest {
    /// Probability that a fault-free epoch fails the test; `None` turns
    /// the test (and exclusion) off.
    pub false_alarm_probability: Option<f64>,
}

impl Default for ResidualTest {
    fn default() -> Self {
        Self {
            false_alarm_probability: Some(DEFAULT_FALSE_ALARM_PROBABILITY),
        }
    }
}

impl ResidualTest {
    fn validate(&self) -> Result<()> {
        match self.false_alarm_probability {
            Some(p) if !(p > 0.0 && p < 1.0) => Err(Error::invalid(
                "false_alarm_probability",
                format!("must be in (0, 1), got {p}"),
            )),
            _ => Ok(()),
        }
    }
}

/// [`solve_fix_with`] with the default residual test (P_fa = 10⁻³).
pub fn solve_fix(epoch: &GnssEpoch, prior: Option<Vector3<f64>>) -> Result<Fix> {
    solve_fix_with(epoch, prior, &ResidualTest::default())
}

/// The least-squares fix of [`solve_fix_all_satellites`] (its errors), then
/// the residual test of the module docs; the satellites left out are in
/// `Fix::excluded`, the final statistic, its degrees of freedom and
/// threshold in `Fix::residual_chi_square`, `residual_dof`,
/// `residual_threshold`.
pub fn solve_fix_with(
    epoch: &GnssEpoch,
    prior: Option<Vector3<f64>>,
    test: &ResidualTest,
) -> Result<Fix> {
    test.validate()?;
    let mut fix = solve_fix_all_satellites(epoch, prior)?;
    let Some(p_fa) = test.false_alarm_probability else {
        return Ok(fix);
    };
    let mut kept = epoch.clone();
    let mut excluded = fix.excluded;
    while let Some((residuals, chi_square)) = post_fit_residuals(&kept, &fix) {
        let dof = fix.residual_dof;
        if dof == 0 {
            break;
        }
        fix.residual_chi_square = chi_square;
        fix.residual_threshold = chi_square_quantile(dof as f64, 1.0 - p_fa);
        if chi_square <= fix.residual_threshold || dof < 2 {
            break;
        }
        let Some(worst) = residuals
            .iter()
            .filter(|r| r.normalized.is_finite())
            .max_by(|a, b| a.normalized.abs().total_cmp(&b.normalized.abs()))
        else {
            break;
        };
        let mut rest = kept.clone();
        rest.measurements.retain(|s| s.sat_id != worst.sat_id);
        // Leaving out the last satellite of a system drops its bias too:
        // the redundancy must still allow a test.
        let Ok(next) = solve_fix_all_satellites(&rest, Some(fix.position_ecef)) else {
            break;
        };
        if next.residual_dof == 0 || !excluded.push(worst.sat_id) {
            break;
        }
        kept = rest;
        fix = next;
    }
    fix.excluded = excluded;
    Ok(fix)
}
