//! Step 3 of the module docs, the accelerometer: the gravity-magnitude fit
//! of θ_a ([`super::magnitude`]; Tedaldi et al. 2014 §III-B), first of
//! b, D and the lower misalignments (the magnitude's minimum, always
//! estimated), then, under [`Estimate::Determinable`], of every combination
//! of the nonlinearity's entries that rules 2 and 3 of
//! [`crate::calibration::determinable`] allow, the one of smallest AICc
//! chosen ([`crate::calibration::information`]); under [`Estimate::All`]
//! with all of N.
//!
//! [`Estimate::Determinable`]: crate::calibration::determinable::Estimate
//! [`Estimate::All`]: crate::calibration::determinable::Estimate

use nalgebra::{DMatrix, DVector, Vector3};

use super::magnitude::{self, parameter_name};
use super::solver::Fit;
use crate::calibration::determinable::{physical_size, worst_uncertain, UNDETERMINED_CONDITION};
use crate::calibration::information::{aicc, subsets, Candidate, ModelSelection};
use crate::sensors::AccelerometerModel;
use crate::text::number;
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
    /// The models of N considered and the one chosen (`determinable` only).
    pub selection: Option<ModelSelection>,
}

/// Fits θ_a to the pose means `fit_means` (nominal units; the poses in the
/// fit of `pose_count` detected) for gravity `gravity` (m/s²): from the
/// first guess ([`magnitude::first_guess`]), the nine linear-model entries,
/// then those with the entries of N of the module docs (the others recorded
/// in `held`). Errors: fewer fit poses than ten (`poses`), or a fit with N
/// that fails to converge when not `determinable`.
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
    let mut theta_a = start;
    for (k, &i) in linear.iter().enumerate() {
        theta_a[i] = linear_fit.x[k];
    }
    let (free_a, accel_fit, selection) = if determinable {
        let (free, fit, selection) = select(fit_means, g, &theta_a, linear_fit);
        for i in magnitude::NONLINEARITY..magnitude::PARAMETERS {
            if !free.contains(&i) {
                let name = parameter_name(i);
                held.push((format!("accelerometer {name}"), selection.why_not(&name)));
            }
        }
        (free, fit, Some(selection))
    } else {
        let all: Vec<usize> = (0..magnitude::PARAMETERS).collect();
        let fit = magnitude::fit(fit_means, g, &theta_a, &all)?;
        (all, fit, None)
    };
    for (k, &i) in free_a.iter().enumerate() {
        theta_a[i] = accel_fit.x[k];
    }
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
        selection,
    })
}

/// The model of N of smallest AICc among the combinations of its entries
/// that rules 2 and 3 allow, each fitted from `theta` (the linear fit's
/// solution, N = 0; `linear_fit` is that fit): its free entries, its fit
/// and the record of every candidate.
fn select(
    fit_means: &[Vector3<f64>],
    gravity: f64,
    theta: &DVector<f64>,
    linear_fit: Fit,
) -> (Vec<usize>, Fit, ModelSelection) {
    let n = fit_means.len();
    let nonlinear: Vec<usize> = (magnitude::NONLINEARITY..magnitude::PARAMETERS).collect();
    let mut fits = Vec::new();
    let mut candidates = Vec::new();
    for extra in subsets(&nonlinear) {
        let free: Vec<usize> = (0..magnitude::NONLINEARITY).chain(extra.clone()).collect();
        let result = if extra.is_empty() {
            Ok(linear_fit.clone())
        } else {
            magnitude::fit(fit_means, gravity, theta, &free)
        };
        let mut candidate = Candidate {
            terms: extra.iter().map(|&i| parameter_name(i)).collect(),
            parameters: free.len(),
            observations: n,
            residual_rms: f64::NAN,
            aicc: None,
            refused: String::new(),
        };
        match &result {
            Err(_) => candidate.refused = "the fit does not converge".to_string(),
            Ok(f) => {
                let rss = f.residuals.norm_squared();
                candidate.residual_rms = (rss / n as f64).sqrt();
                match nonlinearity_to_hold(f, &free) {
                    Some((k, why)) => {
                        candidate.refused = format!("{}: {why}", parameter_name(free[k]))
                    }
                    None => candidate.aicc = Some(aicc(rss, n, free.len())),
                }
            }
        }
        candidates.push(candidate);
        fits.push(result.ok().map(|f| (free, f)));
    }
    let selection = ModelSelection::choose("accelerometer nonlinearity", candidates)
        .expect("the linear model, fitted, is always admissible");
    let (free, fit) = fits[selection.chosen].take().expect("admissible: fitted");
    (free, fit, selection)
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
                    "its sigma {} would exceed its physical size {}",
                    number(std[k], 3),
                    number(scale[k], 3)
                ),
            )
        })
    }
}
