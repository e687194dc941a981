//! Which parameters the data determine, and the warnings of a calibration.
//!
//! ## The rule
//!
//! Under [`Estimate::Determinable`] a parameter is estimated when
//!
//! 1. its regressor is excited: the input it multiplies varies over the
//!    data (a constant input makes a scale factor, a misalignment, a
//!    g-sensitivity or a nonlinearity indistinguishable from the bias);
//! 2. with it, the column-equilibrated regressors (or Jacobian) keep a
//!    condition number below [`least_squares::POORLY_DETERMINED_CONDITION`]
//!    (1e6): the data separate it from the other parameters;
//! 3. its one-sigma uncertainty is below its scale: the prior's σ when one
//!    is given, else the physical size of [`physical_size`] (the largest
//!    value of the term in consumer-grade MEMS): the data say more about it
//!    than the prior or the physics already did.
//!
//! Parameters that fail are held at the prior's value (or zero) one at a
//! time, worst first (for 2: the parameter that dominates the weakest
//! direction; for 3: the largest σ/scale), and the rest are fitted again.
//! Biases are always estimated. Held parameters have zero variance in the
//! covariance and are listed with the reason.
//!
//! Passing these rules makes a term determinable, not worth estimating: in
//! a static session the second-order terms that pass them (the
//! nonlinearity, the g-sensitivity) are then chosen by the small-sample
//! information criterion of [`super::information`], which asks whether a
//! term lowers the error on poses the fit has not seen.
//!
//! ## Warnings
//!
//! Whatever is estimated, a calibration warns when
//! - the equilibrated condition number of a row exceeds
//!   [`POOR_CONDITIONING`] (1e3; Belsley, Kuh and Welsch, *Regression
//!   Diagnostics*, 1980, count condition indices above 30 as strong
//!   collinearity, so 1000 flags only severe cases);
//! - an estimated parameter's σ exceeds its scale (rule 3);
//! - the data hold fewer residual degrees of freedom than parameters
//!   (n − p < p: the residual σ̂ behind every σ is itself uncertain by more
//!   than about 1/√(2p)).

use nalgebra::DMatrix;

use super::least_squares;
use crate::text::number;

/// What a calibration estimates.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default)]
pub enum Estimate {
    /// Every parameter of the model; data that cannot determine one are an
    /// error (the paper's setting, method §3).
    #[default]
    All,
    /// Only what the data determine (module docs); the rest is held.
    Determinable,
}

/// Above this equilibrated condition number a calibration warns of poor
/// conditioning (module docs).
pub const POOR_CONDITIONING: f64 = 1e3;

/// Rule 2's threshold (module docs).
pub const UNDETERMINED_CONDITION: f64 = least_squares::POORLY_DETERMINED_CONDITION;

/// Physical size of a parameter (SI) by its name in the covariance order of
/// [`super::accelerometer_parameter_names`] / [`super::gyroscope_parameter_names`]
/// (`sensor` "accelerometer" or "gyroscope"): the largest value of the term
/// in consumer-grade MEMS, the scale of rule 3 when no prior σ is given.
///
/// | term | accelerometer | gyroscope |
/// |---|---|---|
/// | bias | 0.5 m/s² (≈ 50 mg) | 0.1 rad/s (≈ 6 °/s) |
/// | scale factor | 0.05 (5 %) | 0.05 |
/// | misalignment | 0.05 (≈ 3°) | 0.05 |
/// | nonlinearity | 1e-3 per m/s² (1 % of the reading at 10 m/s²) | — |
/// | g-sensitivity | — | 1e-3 (rad/s)/(m/s²) (≈ 0.6 °/s per g) |
///
/// These bound, by an order of magnitude, the datasheet figures of consumer
/// parts (e.g. bias ±40-60 mg and ±3-5 °/s, sensitivity ±1-3 %, cross-axis
/// ±1-2 %, g-sensitivity ≈ 0.1 °/s/g for the MPU-6000 family and its
/// successors).
pub fn physical_size(sensor: &str, parameter: &str) -> f64 {
    let accelerometer = sensor == "accelerometer";
    match parameter.rsplit_once('_').map(|(group, _)| group) {
        Some("bias") if accelerometer => 0.5,
        Some("bias") => 0.1,
        Some("scale_factor") | Some("misalignment") => 0.05,
        Some("nonlinearity") | Some("g_sensitivity") => 1e-3,
        _ => f64::INFINITY,
    }
}

/// Rule 3's and the warnings' scale of each parameter: `prior_std` where
/// given and positive, else [`physical_size`].
pub fn scales(sensor: &str, names: &[String], prior_std: Option<&[f64]>) -> Vec<f64> {
    names
        .iter()
        .enumerate()
        .map(|(k, name)| match prior_std.map(|p| p[k]) {
            Some(s) if s > 0.0 => s,
            _ => physical_size(sensor, name),
        })
        .collect()
}

/// The estimated parameter whose σ/scale is largest, when above 1 (rule 3):
/// its index. `held[k]` parameters and biases are skipped.
pub fn worst_uncertain(
    names: &[String],
    std: &[f64],
    scale: &[f64],
    held: &[bool],
) -> Option<usize> {
    let mut worst = None;
    let mut worst_ratio = 1.0;
    for k in 0..names.len() {
        if held[k] || names[k].starts_with("bias") {
            continue;
        }
        let ratio = std[k] / scale[k];
        if ratio > worst_ratio {
            worst = Some(k);
            worst_ratio = ratio;
        }
    }
    worst
}

/// Rule 3 on a fit's covariance of the parameters `names` of `sensor`
/// (zero variance: held or fixed): the parameter to hold next, with the
/// reason.
pub fn next_uncertain(
    sensor: &str,
    names: &[String],
    covariance: &DMatrix<f64>,
) -> Option<(usize, String)> {
    let std: Vec<f64> = covariance
        .diagonal()
        .iter()
        .map(|v| v.max(0.0).sqrt())
        .collect();
    let scale = scales(sensor, names, None);
    let fixed: Vec<bool> = std.iter().map(|s| *s == 0.0).collect();
    worst_uncertain(names, &std, &scale, &fixed).map(|k| {
        (
            k,
            format!(
                "{}'s sigma {} would exceed its physical size {}",
                names[k],
                number(std[k], 3),
                number(scale[k], 3)
            ),
        )
    })
}

/// The warnings of rule 3 and of the residual degrees of freedom (module
/// docs), appended to `warnings`. `what` names the fit ("accelerometer").
pub fn uncertainty_warnings(
    what: &str,
    names: &[String],
    std: &[f64],
    scale: &[f64],
    held: &[bool],
    warnings: &mut Vec<String>,
) {
    for k in 0..names.len() {
        if !held[k] && std[k] > scale[k] {
            warnings.push(format!(
                "{what} {}: sigma {} exceeds its scale {} (prior sigma or physical size): \
                 the data hardly determine it",
                names[k],
                number(std[k], 3),
                number(scale[k], 3)
            ));
        }
    }
}

/// The warning for fewer residual degrees of freedom than parameters.
pub fn degrees_of_freedom_warning(
    what: &str,
    observations: usize,
    parameters: usize,
    warnings: &mut Vec<String>,
) {
    if observations < 2 * parameters {
        warnings.push(format!(
            "{what}: too few observations ({observations}) for {parameters} parameters: fewer \
             residual degrees of freedom than parameters, so the sigmas are themselves uncertain \
             (use at least {})",
            2 * parameters
        ));
    }
}

/// The poor-conditioning warning of one row or fit.
pub fn conditioning_warning(
    what: &str,
    condition_number: f64,
    weakest: &str,
    warnings: &mut Vec<String>,
) {
    if condition_number > POOR_CONDITIONING {
        warnings.push(format!(
            "{what}: poorly conditioned (condition number {condition_number:.2e} of the \
             equilibrated regressors); {weakest} is the least determined"
        ));
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn sizes_follow_the_table_and_priors_override_them() {
        assert_eq!(physical_size("accelerometer", "bias_u"), 0.5);
        assert_eq!(physical_size("gyroscope", "bias_p"), 0.1);
        assert_eq!(physical_size("gyroscope", "misalignment_pq"), 0.05);
        assert_eq!(physical_size("gyroscope", "g_sensitivity_pu"), 1e-3);
        let names: Vec<String> = ["bias_u", "scale_factor_u"].map(String::from).to_vec();
        assert_eq!(
            scales("accelerometer", &names, Some(&[0.0, 0.01])),
            vec![0.5, 0.01]
        );
        let std = [10.0, 0.02];
        // The bias is never the one held; the scale factor exceeds 0.01.
        assert_eq!(
            worst_uncertain(&names, &std, &[0.5, 0.01], &[false, false]),
            Some(1)
        );
        assert_eq!(
            worst_uncertain(&names, &std, &[0.5, 0.01], &[false, true]),
            None
        );
        let mut w = Vec::new();
        uncertainty_warnings(
            "accelerometer",
            &names,
            &std,
            &[0.5, 0.01],
            &[false, false],
            &mut w,
        );
        assert_eq!(w.len(), 2, "{w:?}");
        degrees_of_freedom_warning("accelerometer", 20, 12, &mut w);
        conditioning_warning("u axis", 1.8e4, "scale_factor", &mut w);
        conditioning_warning("v axis", 10.0, "scale_factor", &mut w);
        assert_eq!(w.len(), 4, "{w:?}");
    }
}
