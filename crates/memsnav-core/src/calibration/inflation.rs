//! The covariance of a calibration from correlated samples: the drive
//! calibration's references are window means of a smoothed GNSS/INS
//! solution, whose errors are correlated over a few windows, while the
//! fit's covariance σ̂²(GᵀG)⁻¹ assumes independent samples.
//!
//! Each output axis' block is scaled by the AR(1) variance factor of its
//! residuals, f = (1 + ρ)/(1 − ρ) with ρ their lag-one autocorrelation:
//! the ratio n/n′ of the effective sample size of the mean of an AR(1)
//! series, n′ = n (1 − ρ)/(1 + ρ) (Wilks, *Statistical Methods in the
//! Atmospheric Sciences*, 3rd ed., eq. 5.12). A covariance entry of
//! parameters on output axes a and b is scaled by √(f_a f_b), so each
//! block's correlations are kept. Negative ρ (which would shrink the
//! covariance) counts as none, f ≥ 1, and ρ is capped at
//! [`MAX_LAG_ONE_CORRELATION`].

use nalgebra::{DMatrix, Matrix3, Vector3};

use super::layout::{CalibrationLayout, Group};
use crate::gauss_markov::mean_variance_factor;
use crate::{validate, Error, Result};

/// Cap of the lag-one autocorrelation: a factor of at most 19, against
/// the unbounded (1 + ρ)/(1 − ρ) of a residual dominated by a trend.
pub const MAX_LAG_ONE_CORRELATION: f64 = 0.9;

/// The AR(1) variance factor (module docs) of a residual series: 1 when
/// it is constant or has a single sample.
pub fn ar1_variance_factor(residual: &[f64]) -> f64 {
    let n = residual.len() as f64;
    let mean = residual.iter().sum::<f64>() / n;
    let centred = || residual.iter().map(|x| x - mean);
    let variance: f64 = centred().map(|r| r * r).sum();
    if variance == 0.0 || residual.len() < 2 {
        return 1.0;
    }
    let lag_one: f64 = centred().zip(centred().skip(1)).map(|(a, b)| a * b).sum();
    let rho = (lag_one / variance).min(MAX_LAG_ONE_CORRELATION);
    mean_variance_factor(rho).max(1.0)
}

/// The factor of each output axis of a triad's residuals (one row per
/// sample); the error names `argument` when a value is not finite.
pub fn axis_factors(argument: &str, residual: &[Vector3<f64>]) -> Result<Vector3<f64>> {
    validate::finite_vectors(argument, residual)?;
    let mut column = Vec::with_capacity(residual.len());
    Ok(Vector3::from_fn(|axis, _| {
        column.clear();
        column.extend(residual.iter().map(|r| r[axis]));
        ar1_variance_factor(&column)
    }))
}

/// What the references of a calibration inherit from the solution they
/// came from: its covariance of the sensor's biases and scale factors, per
/// output axis (`LogRun.calibration_references`).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct InheritedCovariance {
    /// Covariance of the three biases (per output axis), sensor units squared.
    pub bias: Matrix3<f64>,
    /// Covariance of the three scale factors (per output axis).
    pub scale_factor: Matrix3<f64>,
}

/// The covariance of a calibration of the `layout`'s sensor with each
/// output axis scaled by its factor in `factors` (module docs), plus the
/// `inherited` covariance on the bias and scale-factor blocks. `held`: the
/// indices of parameters the calibration did not estimate: they keep zero
/// variance.
pub fn inflate_covariance(
    layout: CalibrationLayout,
    covariance: &DMatrix<f64>,
    factors: &Vector3<f64>,
    held: &[usize],
    inherited: &InheritedCovariance,
) -> Result<DMatrix<f64>> {
    let p = layout.len();
    if covariance.shape() != (p, p) {
        return Err(Error::invalid(
            "covariance",
            format!(
                "expected ({p}, {p}) for the {}, got {:?}",
                layout.sensor.name(),
                covariance.shape()
            ),
        ));
    }
    validate::finite_array("covariance", covariance.as_slice(), &[p, p])?;
    for (name, m) in [
        ("bias_covariance", &inherited.bias),
        ("scale_factor_covariance", &inherited.scale_factor),
    ] {
        validate::finite_matrix(name, m)?;
    }
    if let Some(&i) = held.iter().find(|&&i| i >= p) {
        return Err(Error::invalid(
            "held",
            format!("index {i} is beyond the {p} parameters"),
        ));
    }
    if let Some(k) = factors.iter().position(|f| !(f.is_finite() && *f >= 1.0)) {
        return Err(Error::invalid(
            "factors",
            format!(
                "element {k} is {}: a variance factor is at least 1",
                factors[k]
            ),
        ));
    }
    let scale = |i: usize| factors[layout.parameter(i).output_axis].sqrt();
    let mut out = DMatrix::from_fn(p, p, |i, j| covariance[(i, j)] * scale(i) * scale(j));
    for (group, m) in [
        (Group::Bias, &inherited.bias),
        (Group::ScaleFactor, &inherited.scale_factor),
    ] {
        let range = layout
            .range(group)
            .expect("both sensors have biases and scale factors");
        for i in range.clone().filter(|i| !held.contains(i)) {
            for j in range.clone().filter(|j| !held.contains(j)) {
                let (a, b) = (layout.parameter(i), layout.parameter(j));
                out[(i, j)] += m[(a.output_axis, b.output_axis)];
            }
        }
    }
    Ok(out)
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::random::stream;
    use rand::Rng as _;
    use rand_distr::StandardNormal;

    /// The factor of an AR(1) series x_k = φ x_{k−1} + e_k is (1 + φ)/(1 − φ)
    /// (Wilks eq. 5.12); white noise gives 1; a negative correlation counts
    /// as none; a trend is capped.
    #[test]
    fn factor_of_an_ar1_series_is_its_variance_inflation() {
        let mut rng = stream(4, 0);
        let phi = 0.5;
        let mut x = 0.0;
        let series: Vec<f64> = (0..200_000)
            .map(|_| {
                x = phi * x + rng.sample::<f64, _>(StandardNormal);
                x
            })
            .collect();
        let f = ar1_variance_factor(&series);
        assert!((f - 3.0).abs() < 0.05, "{f}");
        let white: Vec<f64> = (0..200_000)
            .map(|_| rng.sample::<f64, _>(StandardNormal))
            .collect();
        assert!((ar1_variance_factor(&white) - 1.0).abs() < 0.02);
        let alternating: Vec<f64> = (0..100).map(|k| f64::from(1 - 2 * (k % 2))).collect();
        assert_eq!(ar1_variance_factor(&alternating), 1.0);
        let trend: Vec<f64> = (0..1000).map(f64::from).collect();
        let cap = (1.0 + MAX_LAG_ONE_CORRELATION) / (1.0 - MAX_LAG_ONE_CORRELATION);
        assert!((ar1_variance_factor(&trend) - cap).abs() < 1e-12);
        assert_eq!(ar1_variance_factor(&[2.0; 10]), 1.0);
        assert_eq!(ar1_variance_factor(&[2.0]), 1.0);
    }

    /// A hand-computed case: lag-one sum and variance of [1, 2, 0, 1]
    /// (centred: [0, 1, −1, 0]) are −1 and 2: ρ = −0.5, factor 1; of
    /// [0, 1, 2, 1] (centred [−1, 0, 1, 0]): 0 and 2, factor 1; of
    /// [0, 0, 1, 1] (centred ±½): ¼ and 1, ρ = ¼, factor 5/3.
    #[test]
    fn factor_by_hand() {
        assert_eq!(ar1_variance_factor(&[1.0, 2.0, 0.0, 1.0]), 1.0);
        assert_eq!(ar1_variance_factor(&[0.0, 1.0, 2.0, 1.0]), 1.0);
        assert!((ar1_variance_factor(&[0.0, 0.0, 1.0, 1.0]) - 5.0 / 3.0).abs() < 1e-15);
    }

    #[test]
    fn inflation_scales_by_output_axis_and_adds_the_inherited_blocks() {
        let layout = CalibrationLayout::GYROSCOPE;
        let p = layout.len();
        let covariance = DMatrix::from_fn(p, p, |i, j| if i == j { 1.0 } else { 0.1 });
        let factors = Vector3::new(1.0, 4.0, 9.0);
        let inherited = InheritedCovariance {
            bias: Matrix3::from_fn(|i, j| 10.0 * (i + 1) as f64 + (j + 1) as f64),
            scale_factor: Matrix3::from_element(0.5),
        };
        // Held: the scale factor of q (index 4).
        let out = inflate_covariance(layout, &covariance, &factors, &[4], &inherited).unwrap();
        let m_pr = layout.index("misalignment_pr").unwrap(); // output p: √1
        let k_rw = layout.index("g_sensitivity_rw").unwrap(); // output r: √9
        assert_eq!(out[(m_pr, k_rw)], 0.1 * 3.0);
        assert_eq!(out[(k_rw, k_rw)], 9.0);
        // bias_q, bias_r: 0.1·2·3 + inherited (q, r) = 23.
        assert!((out[(1, 2)] - (0.6 + 23.0)).abs() < 1e-12);
        assert!((out[(2, 1)] - (0.6 + 32.0)).abs() < 1e-12);
        // Scale factor of q held: nothing added in its row and column.
        assert_eq!(out[(4, 4)], 4.0);
        assert_eq!(out[(3, 4)], 0.1 * 2.0);
        assert_eq!(out[(3, 5)], 0.1 * 3.0 + 0.5);
        // Bias and scale factor of different axes: no inherited term.
        assert_eq!(out[(0, 5)], 0.1 * 3.0);
        let wrong = DMatrix::zeros(15, 15);
        let e = inflate_covariance(layout, &wrong, &factors, &[], &inherited).unwrap_err();
        assert!(e.to_string().contains("covariance"), "{e}");
        let e = inflate_covariance(layout, &covariance, &factors, &[21], &inherited).unwrap_err();
        assert!(e.to_string().contains("held"), "{e}");
        let low = Vector3::new(1.0, 0.5, 1.0);
        let e = inflate_covariance(layout, &covariance, &low, &[], &inherited).unwrap_err();
        assert!(e.to_string().contains("factors"), "{e}");
    }
}
