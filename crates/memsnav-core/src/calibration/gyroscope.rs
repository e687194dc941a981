//! Gyroscope calibration (method §3, paper eq. 6-7): the output is exactly
//! linear in [1, Ω^p, Ω^q, Ω^r, Γ^u, Γ^v, Γ^w], so one factorisation serves
//! the three rows and the conversion b = −A⁻¹c₀, K = −A⁻¹C is exact.

use nalgebra::{DMatrix, DVector, Matrix3, SMatrix, Vector3};

use super::determinable::{
    next_uncertain, scales, uncertainty_warnings, Estimate, POOR_CONDITIONING,
    UNDETERMINED_CONDITION,
};
use super::least_squares::{IncrementalQr, Regression};
use super::{
    block_diagonal, check_excitation, common_jacobian, constant_column, diagnose, expand_block,
    factor_column, gyroscope_parameter_names, gyroscope_std_model, row_noise_variance,
    validate_data, validate_options, Calibration, CalibrationOptions, Method, ReferenceNoise,
    ACCELEROMETER_AXES, GYROSCOPE_AXES, OFF_DIAGONAL,
};
use crate::sensors::{GyroscopeModel, NoiseModel};
use crate::{Error, Result};

/// Coefficients per row: [1, Ω^p, Ω^q, Ω^r, Γ^u, Γ^v, Γ^w].
const P: usize = 7;

fn column_names(i: usize) -> Vec<String> {
    let g = GYROSCOPE_AXES;
    let mut names = vec!["bias".to_string()];
    for (j, axis) in g.iter().enumerate() {
        names.push(if j == i {
            "scale_factor".to_string()
        } else {
            format!("misalignment_{}{axis}", g[i])
        });
    }
    names.extend(
        ACCELEROMETER_AXES
            .iter()
            .map(|u| format!("g_sensitivity_{}{u}", g[i])),
    );
    names
}

/// Columns of the factored data X: [1, Ω^p, Ω^q, Ω^r, Γ^u, Γ^v, Γ^w, S^p, S^q, S^r]:
/// the regressors (shared by the three rows), then the outputs.
const COLUMNS: usize = P + 3;

/// The regressors [1, Ω, Γ] in compressed form: the first P columns of R.
fn regressors<const C: usize>(r: &SMatrix<f64, C, C>) -> DMatrix<f64> {
    DMatrix::from_fn(C, P, |i, j| r[(i, j)])
}

fn model_from_rows(rows: &[DVector<f64>; 3]) -> Result<GyroscopeModel> {
    let a = Matrix3::from_fn(|i, j| rows[i][1 + j]);
    let a_inv = a.try_inverse().ok_or_else(|| Error::Unobservable {
        axis: "p".into(),
        parameter: "scale_factor".into(),
        reason: "the estimated I − D − M is singular".into(),
    })?;
    let c0 = Vector3::from_fn(|i, _| rows[i][0]);
    let c = Matrix3::from_fn(|i, j| rows[i][4 + j]);
    let mut misalignment = -a;
    misalignment.fill_diagonal(0.0);
    Ok(GyroscopeModel {
        bias: -(a_inv * c0),
        scale_factor: Vector3::from_fn(|i, _| 1.0 - a[(i, i)]),
        misalignment,
        g_sensitivity: -(a_inv * c),
        noise: NoiseModel::default(),
    })
}

/// ∂(parameters)/∂(coefficients), 21 × 21, at a model.
fn jacobian(m: &GyroscopeModel) -> DMatrix<f64> {
    let a_inv = m
        .output_matrix()
        .try_inverse()
        .unwrap_or_else(Matrix3::zeros);
    let mut jac = DMatrix::zeros(21, 3 * P);
    common_jacobian(&a_inv, &m.bias, P, &mut jac);
    let k = &m.g_sensitivity;
    for r in 0..3 {
        for l in 0..3 {
            for i in 0..3 {
                // K = −A⁻¹C: dK = −A⁻¹ dC for dC = E_il; dK = −A⁻¹ dA K for dA = E_ij.
                jac[(12 + 3 * r + l, P * i + 4 + l)] = -a_inv[(r, i)];
                for j in 0..3 {
                    jac[(12 + 3 * r + l, P * i + 1 + j)] = -a_inv[(r, i)] * k[(j, l)];
                }
            }
        }
    }
    jac
}

/// Cramér-Rao bound (21 × 21) of the gyroscope parameters at the true
/// angular rates (rad/s) and specific forces (m/s²), for white sensor noise
/// of std `noise_std` (rad/s) per sample and references carrying
/// `reference` (the errors-in-variables bound of the module docs of
/// [`crate::calibration`]; exact references for zeros).
pub fn gyroscope_crb(
    true_angular_rate: &[Vector3<f64>],
    true_specific_force: &[Vector3<f64>],
    model: &GyroscopeModel,
    noise_std: f64,
    reference: &ReferenceNoise,
) -> Result<DMatrix<f64>> {
    crate::validate::positive("noise_std", noise_std)?;
    reference.validate()?;
    crate::validate::same_length(
        "true_specific_force",
        true_specific_force.len(),
        "true_angular_rate",
        true_angular_rate.len(),
    )?;
    // One pass over the true inputs; no outputs (module docs of
    // [`crate::calibration`]).
    let mut qr = IncrementalQr::<P>::new();
    for (w, f) in true_angular_rate.iter().zip(true_specific_force) {
        qr.push(&[1.0, w.x, w.y, w.z, f.x, f.y, f.z]);
    }
    let n = qr.rows();
    let reg = Regression::new(regressors(&qr.finish()), n);
    Ok(crb_from(
        &reg.unit_covariance(),
        model,
        noise_std,
        reference,
    ))
}

/// J diag(σ_i² (GᵀG)⁻¹) Jᵀ with the errors-in-variables row variances;
/// `unit` is (GᵀG)⁻¹ over all P columns (zero rows for held ones).
fn crb_from(
    unit: &DMatrix<f64>,
    model: &GyroscopeModel,
    noise_std: f64,
    reference: &ReferenceNoise,
) -> DMatrix<f64> {
    let a = model.output_matrix();
    let variance = row_noise_variance(
        &a,
        &(a * model.g_sensitivity),
        noise_std,
        reference.angular_rate_std,
        reference.specific_force_std,
    );
    let blocks: Vec<DMatrix<f64>> = (0..3).map(|i| unit * variance[i]).collect();
    let jac = jacobian(model);
    &jac * block_diagonal(&blocks) * jac.transpose()
}

/// Gyroscope calibration data reduced by one pass over the samples to the
/// factor R_X of X = [1, Ω, Γ, S] (module docs of [`crate::calibration`]),
/// from which [`Self::calibrate`] solves any [`CalibrationOptions`] (plain
/// LS and EIV from the same pass) without touching the samples again.
#[derive(Debug, Clone)]
pub struct FactoredGyroscope {
    r: SMatrix<f64, COLUMNS, COLUMNS>,
    samples: usize,
    /// Σ_k Ω_k (the excitation check).
    sum_angular_rate: Vector3<f64>,
}

impl FactoredGyroscope {
    /// Factors the outputs `measured` (rad/s) against the reference angular
    /// rate (rad/s) and the reference specific force (m/s²), body axes.
    pub fn new(
        measured: &[Vector3<f64>],
        reference_angular_rate: &[Vector3<f64>],
        reference_specific_force: &[Vector3<f64>],
    ) -> Result<Self> {
        validate_data(
            measured,
            &[
                ("reference_angular_rate", reference_angular_rate),
                ("reference_specific_force", reference_specific_force),
            ],
            P,
        )?;
        let mut qr = IncrementalQr::<COLUMNS>::new();
        let mut sum_angular_rate = Vector3::zeros();
        for ((s, w), f) in measured
            .iter()
            .zip(reference_angular_rate)
            .zip(reference_specific_force)
        {
            qr.push(&[1.0, w.x, w.y, w.z, f.x, f.y, f.z, s.x, s.y, s.z]);
            sum_angular_rate += w;
        }
        Ok(Self {
            samples: qr.rows(),
            r: qr.finish(),
            sum_angular_rate,
        })
    }

    /// Calibrates from the factored data. See [`crate::calibration`];
    /// under [`Estimate::Determinable`] only what the data determine
    /// ([`super::determinable`]): a held regressor column keeps its
    /// parameters at the ideal sensor's (D = M = 0 for an Ω column, K = 0
    /// for a Γ column).
    pub fn calibrate(&self, options: &CalibrationOptions) -> Result<Calibration<GyroscopeModel>> {
        validate_options(options)?;
        let (r, n) = (&self.r, self.samples);
        if options.estimate == Estimate::All {
            check_excitation(
                r,
                n,
                1,
                &self.sum_angular_rate,
                GYROSCOPE_AXES,
                "angular rate",
            )?;
            return self.fit(options, &[], Regression::new(regressors(r), n));
        }
        let mut held: Vec<(usize, String)> = (1..P)
            .filter_map(|c| {
                constant_column(r, n, c)
                    .map(|mean| (c, format!("its input never varies (constant {mean:.6e})")))
            })
            .collect();
        loop {
            let free: Vec<usize> = (0..P).filter(|c| !held.iter().any(|h| h.0 == *c)).collect();
            let reg = Regression::new(regressors(r).select_columns(free.iter()), n);
            if reg.condition_number > UNDETERMINED_CONDITION || !reg.condition_number.is_finite() {
                let c = free[reg.weakest_column(0)];
                held.push((
                    c,
                    format!(
                        "the data do not separate it from the others (condition number {:.2e})",
                        reg.condition_number
                    ),
                ));
                continue;
            }
            let cal = self.fit(options, &held, reg)?;
            match next_uncertain("gyroscope", &gyroscope_parameter_names(), &cal.covariance) {
                Some((k, why)) => held.push((parameter_column(k), why)),
                None => return Ok(cal),
            }
        }
    }

    /// The fit with the regressor columns `held` (with their reasons) at
    /// the ideal sensor's coefficients and `reg` the free columns' regression.
    fn fit(
        &self,
        options: &CalibrationOptions,
        held: &[(usize, String)],
        reg: Regression,
    ) -> Result<Calibration<GyroscopeModel>> {
        let (r, n) = (&self.r, self.samples);
        let free: Vec<usize> = (0..P).filter(|c| !held.iter().any(|h| h.0 == *c)).collect();
        let mut warnings = Vec::new();
        for (i, axis) in GYROSCOPE_AXES.iter().enumerate() {
            let names: Vec<String> = free.iter().map(|&c| column_names(i)[c].clone()).collect();
            diagnose(&reg, axis, &names, &mut warnings)?;
            if reg.condition_number > POOR_CONDITIONING {
                break; // the three rows share the regressors: one report suffices
            }
        }
        let noise = (options.method == Method::ErrorsInVariables).then(|| {
            // White reference noise: uncorrelated columns, Σ_k E[e eᵀ] = n diag(σ_Ω², σ_Γ²).
            let n = n as f64;
            let so2 = options.reference_noise_std.unwrap_or(0.0).powi(2);
            let sf2 = options
                .reference_specific_force_noise_std
                .unwrap_or(0.0)
                .powi(2);
            DMatrix::from_diagonal(&DVector::from_vec(vec![
                0.0,
                n * so2,
                n * so2,
                n * so2,
                n * sf2,
                n * sf2,
                n * sf2,
            ]))
            .select_rows(free.iter())
            .select_columns(free.iter())
        });
        let mut solutions = Vec::with_capacity(3);
        let mut rows: [DVector<f64>; 3] = std::array::from_fn(|_| DVector::zeros(P));
        for (i, axis) in GYROSCOPE_AXES.iter().enumerate() {
            // A held Ω column j keeps A_ij = δ_ij: row i's own rate moves to
            // the left-hand side.
            let mut y = factor_column(r, P + i);
            if held.iter().any(|h| h.0 == 1 + i) {
                y -= factor_column(r, 1 + i);
                rows[i][1 + i] = 1.0;
            }
            let solution = reg.solve(&y, noise.as_ref(), axis)?;
            for (k, &c) in free.iter().enumerate() {
                rows[i][c] = solution.coefficients[k];
            }
            solutions.push(solution);
        }
        let mut model = model_from_rows(&rows)?;
        let jac = jacobian(&model);
        let blocks: Vec<DMatrix<f64>> = solutions
            .iter()
            .map(|s| expand_block(&s.covariance, &free, P))
            .collect();
        let covariance = &jac * block_diagonal(&blocks) * jac.transpose();
        let reference = ReferenceNoise {
            specific_force_std: options.reference_specific_force_noise_std.unwrap_or(0.0),
            angular_rate_std: options.reference_noise_std.unwrap_or(0.0),
        };
        let crb = options.noise_std.map(|sigma| {
            let unit = expand_block(&reg.unit_covariance(), &free, P);
            crb_from(&unit, &model, sigma, &reference)
        });
        let residual_std = Vector3::from_fn(|i, _| solutions[i].residual_std);
        model.noise.white_std = (residual_std.norm_squared() / 3.0).sqrt();
        let names = gyroscope_parameter_names();
        let std: Vec<f64> = covariance
            .diagonal()
            .iter()
            .map(|v| v.max(0.0).sqrt())
            .collect();
        let held_parameters: Vec<bool> = (0..names.len())
            .map(|k| held.iter().any(|h| h.0 == parameter_column(k)))
            .collect();
        uncertainty_warnings(
            "gyroscope",
            &names,
            &std,
            &scales("gyroscope", &names, None),
            &held_parameters,
            &mut warnings,
        );
        Ok(Calibration {
            model,
            std: gyroscope_std_model(&covariance),
            covariance,
            residual_std,
            condition_number: Vector3::repeat(reg.condition_number),
            crb,
            warnings,
            held: names
                .iter()
                .enumerate()
                .filter_map(|(k, name)| {
                    held.iter()
                        .find(|h| h.0 == parameter_column(k))
                        .map(|h| (name.clone(), h.1.clone()))
                })
                .collect(),
        })
    }
}

/// The regressor column of a gyroscope parameter (its index in
/// [`gyroscope_parameter_names`]): bias 0, D_j and M_ij the Ω column 1 + j,
/// K_il the Γ column 4 + l.
fn parameter_column(k: usize) -> usize {
    match k {
        0..=2 => 0,
        3..=5 => 1 + (k - 3),
        6..=11 => 1 + OFF_DIAGONAL[k - 6].1,
        _ => 4 + (k - 12) % 3,
    }
}

/// Calibrates a gyroscope triad from its outputs `measured` (rad/s), the
/// reference angular rate (rad/s) and the reference specific force (m/s²),
/// all in body axes: [`FactoredGyroscope`] then
/// [`FactoredGyroscope::calibrate`]. See [`crate::calibration`].
pub fn calibrate_gyroscope(
    measured: &[Vector3<f64>],
    reference_angular_rate: &[Vector3<f64>],
    reference_specific_force: &[Vector3<f64>],
    options: &CalibrationOptions,
) -> Result<Calibration<GyroscopeModel>> {
    FactoredGyroscope::new(measured, reference_angular_rate, reference_specific_force)?
        .calibrate(options)
}

#[cfg(test)]
pub(super) mod tests_support {
    use super::*;

    pub fn jacobian(m: &GyroscopeModel) -> DMatrix<f64> {
        super::jacobian(m)
    }

    pub fn model_from_rows(rows: &[DVector<f64>; 3]) -> GyroscopeModel {
        super::model_from_rows(rows).unwrap()
    }
}
