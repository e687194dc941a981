//! Step 3 of the module docs, the accelerometer: the gravity-magnitude fit
//! of θ_a ([`super::magnitude`]; Tedaldi et al. 2014 §III-B), first of
//! b, D and the lower misalignments (the magnitude's minimum, always
//! estimated), then with the nonlinearity N, whose entries are held under
//! [`Estimate::Determinable`] by rules 2 and 3 of
//! [`crate::calibration::determinable`].
//!
//! [`Estimate::Determinable`]: crate::calibration::determinable::Estimate

use nalgebra::{DMatrix, DVector, Vector3};

use super::magnitude::{self, parameter_name};
use super::solver::Fit;
use crate::calibration::determinable::{physical_size, worst_uncertain, UNDETERMINED_CONDITION};
use crate::sensors::AccelerometerModel;
use crate::{Error, Result};

/// The fitted accelerometer.
pub struct AccelerometerStage {
    /// θ_a at the solution (held entries zero).
    pub theta: DVector<f64>,
    /// The entries of θ_a that were fitted, in the order of the fit's.
    pub free: Vec<usize>,
    /// The fit of those entries.
    pub fit: Fit,
    /// Covariance of θ_a, 12 × 12 (zero for held entries): the fit's
    /// σ̂² (JᵀJ)⁻¹ placed at the free entries.
    pub covariance: DMatrix<f64>,
    /// The model of θ_a.
    pub model: AccelerometerModel,
}

/// Fits θ_a to the pose means `fit_means` (nominal units; the poses in the
/// fit of `pose_count` detected) for gravity `gravity` (m/s²): from the
/// first guess ([`magnitude::first_guess`]), the nine linear-model entries,
/// then all twelve, holding N's entries (recorded in `held`) while the
/// rules fail under `determinable`. Errors: fewer fit poses than ten
/// (`poses`), or a fit that fails to converge when not `determinable`.
pub fn fit(
    fit_means: &[Vector3<f64>],
    pose_count: usize,
    gravity: f64,
    determinable: bool,
    held: &mut Vec<(String, String)>,
) -> Result<AccelerometerStage> {
    let g = gravity;
    if fit_means.len() <= magnitude::NONLINEARITY {
        return Err(Error::invalid(
            "poses",
            format!(
                "the accelerometer needs at least {} static poses in the fit (9 parameters plus \
                 one), the detector found {} ({} held out)",
                magnitude::NONLINEARITY + 1,
                pose_count,
                pose_count - fit_means.len()
            ),
        ));
    }
    let linear: Vec<usize> = (0..magnitude::NONLINEARITY).collect();
    let start = magnitude::first_guess(fit_means, g);
    let linear_fit = magnitude::fit(fit_means, g, &start, &linear)?;
    let mut theta_a = start.clone();
    for (k, &i) in linear.iter().enumerate() {
        theta_a[i] = linear_fit.x[k];
    }
    let mut free_a: Vec<usize> = (0..magnitude::PARAMETERS).collect();
    let accel_fit: Fit = loop {
        let fit = if free_a.len() == linear.len() {
            Ok(linear_fit.clone())
        } else {
            magnitude::fit(fit_means, g, &theta_a, &free_a)
        };
        let fit = match (fit, determinable) {
            (Ok(f), _) => f,
            (Err(e), false) => return Err(e),
            (Err(_), true) => {
                // The nonlinearity made the fit fail: hold all of it.
                for i in magnitude::NONLINEARITY..magnitude::PARAMETERS {
                    held.push((
                        format!("accelerometer {}", parameter_name(i)),
                        "the fit with it does not converge".to_string(),
                    ));
                }
                free_a.truncate(magnitude::NONLINEARITY);
                continue;
            }
        };
        match nonlinearity_to_hold(&fit, &free_a) {
            Some((k, why)) if determinable => {
                held.push((format!("accelerometer {}", parameter_name(free_a[k])), why));
                theta_a[free_a[k]] = 0.0;
                free_a.remove(k);
            }
            _ => {
                for (k, &i) in free_a.iter().enumerate() {
                    theta_a[i] = fit.x[k];
                }
                break fit;
            }
        }
    };
    let mut sigma_a = DMatrix::zeros(magnitude::PARAMETERS, magnitude::PARAMETERS);
    for (a, &i) in free_a.iter().enumerate() {
        for (b, &j) in free_a.iter().enumerate() {
            sigma_a[(i, j)] = accel_fit.covariance[(a, b)];
        }
    }
    Ok(AccelerometerStage {
        model: magnitude::model(&theta_a),
        theta: theta_a,
        free: free_a,
        fit: accel_fit,
        covariance: sigma_a,
    })
}

/// The entry of N the poses do not determine, with the reason, if any:
/// rule 2 (the weakest direction of `fit`, whose free entries are `free`,
/// is an N entry and the condition number exceeds
/// [`UNDETERMINED_CONDITION`]), then rule 3 (the N entry whose σ most
/// exceeds its physical size). b, D and M are the magnitude's minimum and
/// never held. Returns the index into `free`.
fn nonlinearity_to_hold(fit: &Fit, free: &[usize]) -> Option<(usize, String)> {
    let std: Vec<f64> = (0..free.len())
        .map(|k| fit.covariance[(k, k)].max(0.0).sqrt())
        .collect();
    let names: Vec<String> = free.iter().map(|&i| parameter_name(i)).collect();
    let scale: Vec<f64> = names
        .iter()
        .map(|n| physical_size("accelerometer", n))
        .collect();
    // Rule 2 then rule 3, for the nonlinearity only (b, D, M are the
    // magnitude's minimum).
    let nonlinear = |k: usize| free[k] >= magnitude::NONLINEARITY;
    if fit.condition_number > UNDETERMINED_CONDITION && nonlinear(fit.weakest) {
        Some((
            fit.weakest,
            format!(
                "the poses do not separate it from the others (condition number {:.2e})",
                fit.condition_number
            ),
        ))
    } else {
        let fixed: Vec<bool> = (0..free.len()).map(|k| !nonlinear(k)).collect();
        worst_uncertain(&names, &std, &scale, &fixed).map(|k| {
            (
                k,
                format!(
                    "its sigma {:.3e} would exceed its physical size {:.3e}",
                    std[k], scale[k]
                ),
            )
        })
    }
}
