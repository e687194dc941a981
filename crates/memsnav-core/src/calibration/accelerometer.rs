//! Accelerometer calibration (method §3, paper eq. 4-5), exact conversion.

use nalgebra::{DMatrix, DVector, Matrix3, SMatrix, Vector3};

use super::determinable::{
    next_uncertain, scales, uncertainty_warnings, Estimate, UNDETERMINED_CONDITION,
};
use super::least_squares::{IncrementalQr, Regression};
use super::{
    accelerometer_parameter_names, accelerometer_std_model, block_diagonal, check_excitation,
    common_jacobian, constant_column, diagnose, expand_block, factor_column, row_noise_variance,
    validate_data, validate_options, Calibration, CalibrationOptions, Method, ReferenceNoise,
    ACCELEROMETER_AXES, OFF_DIAGONAL,
};
use crate::sensors::{AccelerometerModel, NoiseModel};
use crate::{Error, Result};

/// Coefficients per row: [1, Γ^u, Γ^v, Γ^w, (Γ^i)²].
const P: usize = 5;
/// At most this many passes of the cross-square refinement. Each pass
/// multiplies the error of the omitted terms by about the misalignment
/// (≈ 1e-2), so a handful reach rounding.
const MAX_REFINEMENT_PASSES: usize = 20;

fn column_names(i: usize) -> Vec<String> {
    let a = ACCELEROMETER_AXES;
    let mut names = vec!["bias".to_string()];
    for (j, axis) in a.iter().enumerate() {
        names.push(if j == i {
            "scale_factor".to_string()
        } else {
            format!("misalignment_{}{axis}", a[i])
        });
    }
    names.push("nonlinearity".to_string());
    names
}

/// Columns of the factored data X: [1, Γ^u, Γ^v, Γ^w, (Γ^u)², (Γ^v)², (Γ^w)², S^u, S^v, S^w].
const COLUMNS: usize = 10;
/// First column of the squares and of the outputs in X.
const SQUARES: usize = 4;
const OUTPUTS: usize = 7;

/// Columns of the factor of the noise-free inputs for the Cramér-Rao bound:
/// [1, Γ^u, Γ^v, Γ^w, (Γ^u)², (Γ^v)², (Γ^w)²].
const CRB_COLUMNS: usize = 7;

/// The regressors of row i in compressed form: [1, Γ, (Γ^i)² − s2].
fn regressors<const C: usize>(r: &SMatrix<f64, C, C>, i: usize, s2: f64) -> DMatrix<f64> {
    let mut g = DMatrix::zeros(C, P);
    for c in 0..4 {
        g.set_column(c, &r.column(c));
    }
    g.set_column(4, &square(r, i, s2));
    g
}

/// (Γ^j)² − s2 in compressed form: the square column less s2 times the
/// constant (E[(Γ+η)²] = Γ² + σ²).
fn square<const C: usize>(r: &SMatrix<f64, C, C>, j: usize, s2: f64) -> DVector<f64> {
    factor_column(r, SQUARES + j) - factor_column(r, 0) * s2
}

/// Coefficient rows → model: A from the Γ columns, b = −A⁻¹c₀, N_i = −c₄/A_ii.
fn model_from_rows(rows: &[DVector<f64>; 3]) -> Result<AccelerometerModel> {
    let a = Matrix3::from_fn(|i, j| rows[i][1 + j]);
    let a_inv = a.try_inverse().ok_or_else(|| Error::Unobservable {
        axis: "u".into(),
        parameter: "scale_factor".into(),
        reason: "the estimated I − D − M is singular".into(),
    })?;
    let c0 = Vector3::from_fn(|i, _| rows[i][0]);
    let mut misalignment = -a;
    misalignment.fill_diagonal(0.0);
    Ok(AccelerometerModel {
        bias: -(a_inv * c0),
        scale_factor: Vector3::from_fn(|i, _| 1.0 - a[(i, i)]),
        misalignment,
        nonlinearity: Vector3::from_fn(|i, _| -rows[i][4] / a[(i, i)]),
        noise: NoiseModel::default(),
    })
}

/// ∂(parameters)/∂(coefficients), 15 × 15, at a model (method §3 conversion).
fn jacobian(m: &AccelerometerModel) -> DMatrix<f64> {
    let a = m.output_matrix();
    let a_inv = a.try_inverse().unwrap_or_else(Matrix3::zeros);
    let mut jac = DMatrix::zeros(15, 3 * P);
    common_jacobian(&a_inv, &m.bias, P, &mut jac);
    for i in 0..3 {
        // N_i = −c₄/A_ii.
        jac[(12 + i, P * i + 4)] = -1.0 / a[(i, i)];
        jac[(12 + i, P * i + 1 + i)] = -m.nonlinearity[i] / a[(i, i)];
    }
    jac
}

/// Cramér-Rao bound (15 × 15) of the accelerometer parameters at the true
/// specific forces `true_specific_force` (m/s²), for white sensor noise of
/// std `noise_std` (m/s²) per sample and references carrying
/// `reference.specific_force_std` (the errors-in-variables bound of the
/// module docs of [`crate::calibration`]; exact references for 0). One
/// pass over the inputs.
pub fn accelerometer_crb(
    true_specific_force: &[Vector3<f64>],
    model: &AccelerometerModel,
    noise_std: f64,
    reference: &ReferenceNoise,
) -> Result<DMatrix<f64>> {
    crate::validate::positive("noise_std", noise_std)?;
    reference.validate()?;
    crate::validate::finite_vectors("true_specific_force", true_specific_force)?;
    let mut qr = IncrementalQr::<CRB_COLUMNS>::new();
    for g in true_specific_force {
        let sq = g.component_mul(g);
        qr.push(&[1.0, g.x, g.y, g.z, sq.x, sq.y, sq.z]);
    }
    let n = qr.rows();
    let r = qr.finish();
    let regressions: Vec<Regression> = (0..3)
        .map(|i| Regression::new(regressors(&r, i, 0.0), n))
        .collect();
    let all_columns: Vec<Vec<usize>> = vec![(0..P).collect(); 3];
    Ok(crb(
        &regressions,
        &all_columns,
        model,
        noise_std,
        reference.specific_force_std,
    ))
}

/// J diag(σ_i² (G_iᵀG_i)⁻¹) Jᵀ with the errors-in-variables row variances;
/// row i's regression covers its columns `free[i]` (held ones carry zero).
fn crb(
    regressions: &[Regression],
    free: &[Vec<usize>],
    model: &AccelerometerModel,
    noise_std: f64,
    reference_std: f64,
) -> DMatrix<f64> {
    let variance = row_noise_variance(
        &model.output_matrix(),
        &Matrix3::zeros(),
        noise_std,
        reference_std,
        0.0,
    );
    let blocks: Vec<DMatrix<f64>> = regressions
        .iter()
        .enumerate()
        .map(|(i, reg)| expand_block(&(reg.unit_covariance() * variance[i]), &free[i], P))
        .collect();
    let jac = jacobian(model);
    &jac * block_diagonal(&blocks) * jac.transpose()
}

/// Accelerometer calibration data reduced by one pass over the samples to
/// the factor R_X of X = [1, Γ, Γ², S] (module docs of
/// [`crate::calibration`]), from which [`Self::calibrate`] solves any
/// [`CalibrationOptions`] (plain LS and EIV from the same pass) without
/// touching the samples again.
#[derive(Debug, Clone)]
pub struct FactoredAccelerometer {
    r: SMatrix<f64, COLUMNS, COLUMNS>,
    samples: usize,
    /// Σ_k Γ_k and Σ_k (Γ_k)² per axis (the EIV noise moments).
    sum_reference: Vector3<f64>,
    sum_square: Vector3<f64>,
    /// Smallest and largest (Γ^j)² over all samples and axes, and the
    /// largest |S| (the refinement's stopping tolerance).
    square_range: (f64, f64),
    largest_output: f64,
}

impl FactoredAccelerometer {
    /// Factors the outputs `measured` (m/s²) against the reference specific
    /// forces (m/s², body axes).
    pub fn new(
        measured: &[Vector3<f64>],
        reference_specific_force: &[Vector3<f64>],
    ) -> Result<Self> {
        validate_data(
            measured,
            &[("reference_specific_force", reference_specific_force)],
            P,
        )?;
        let mut qr = IncrementalQr::<COLUMNS>::new();
        let mut sum_reference = Vector3::zeros();
        let mut sum_square = Vector3::zeros();
        let (mut smallest, mut largest) = (f64::INFINITY, 0.0f64);
        let mut largest_output = 0.0f64;
        for (s, g) in measured.iter().zip(reference_specific_force) {
            let sq = g.component_mul(g);
            qr.push(&[1.0, g.x, g.y, g.z, sq.x, sq.y, sq.z, s.x, s.y, s.z]);
            sum_reference += g;
            sum_square += sq;
            smallest = smallest.min(sq.min());
            largest = largest.max(sq.max());
            largest_output = largest_output.max(s.amax());
        }
        Ok(Self {
            samples: qr.rows(),
            r: qr.finish(),
            sum_reference,
            sum_square,
            square_range: (smallest, largest),
            largest_output,
        })
    }

    /// Σ_k E[e_k e_kᵀ] of the regressor errors of row i when every reference
    /// component carries white noise η of variance s2: η on the Γ columns,
    /// 2Γη + η² − σ² on the square column (variance 4Γ²σ² + 2σ⁴, covariance
    /// 2Γσ² with η), with Γ² estimated without bias by Γ_obs² − σ².
    fn regressor_noise(&self, i: usize, s2: f64) -> DMatrix<f64> {
        let n = self.samples as f64;
        let mut c = DMatrix::zeros(P, P);
        for j in 0..3 {
            c[(1 + j, 1 + j)] = n * s2;
        }
        let sum_g2 = self.sum_square[i] - n * s2;
        c[(4, 4)] = 4.0 * s2 * sum_g2 + 2.0 * n * s2 * s2;
        c[(1 + i, 4)] = 2.0 * s2 * self.sum_reference[i];
        c[(4, 1 + i)] = c[(1 + i, 4)];
        c
    }

    /// Calibrates from the factored data. See the module docs of
    /// [`crate::calibration`] for the model, the exact conversion and the
    /// uncertainties; under [`Estimate::Determinable`] only what the data
    /// determine ([`super::determinable`]): a held Γ column keeps D_j and
    /// M_ij at zero (A's column j is the identity's), a held square keeps
    /// N_i at zero.
    pub fn calibrate(
        &self,
        options: &CalibrationOptions,
    ) -> Result<Calibration<AccelerometerModel>> {
        validate_options(options)?;
        let (r, n) = (&self.r, self.samples);
        if options.estimate == Estimate::All {
            check_excitation(
                r,
                n,
                1,
                &self.sum_reference,
                ACCELEROMETER_AXES,
                "specific force",
            )?;
            return self.fit(options, &[]);
        }
        // Held (row, column): row None for a Γ column held in every row.
        let mut held: Vec<Held> = Vec::new();
        for j in 0..3 {
            if let Some(mean) = constant_column(r, n, 1 + j) {
                let why = format!("its input never varies (constant {mean:.6e})");
                held.push((None, 1 + j, why.clone()));
                held.push((Some(j), 4, why));
            }
        }
        let s2 = self.reference_variance(options);
        'refit: loop {
            for i in 0..3 {
                let free = free_columns(&held, i);
                let reg = Regression::new(regressors(r, i, s2).select_columns(free.iter()), n);
                if reg.condition_number > UNDETERMINED_CONDITION
                    || !reg.condition_number.is_finite()
                {
                    let c = free[reg.weakest_column(0)];
                    held.push((
                        (c == 4).then_some(i),
                        c,
                        format!(
                            "the data do not separate it from the others (condition number {:.2e})",
                            reg.condition_number
                        ),
                    ));
                    continue 'refit;
                }
            }
            let cal = self.fit(options, &held)?;
            match next_uncertain(
                "accelerometer",
                &accelerometer_parameter_names(),
                &cal.covariance,
            ) {
                Some((k, why)) => {
                    let (row, c) = parameter_column(k);
                    held.push((row, c, why))
                }
                None => return Ok(cal),
            }
        }
    }

    /// s2, the reference noise variance of the EIV estimator (0 for LS).
    fn reference_variance(&self, options: &CalibrationOptions) -> f64 {
        if options.method == Method::ErrorsInVariables {
            options.reference_noise_std.unwrap_or(0.0).powi(2)
        } else {
            0.0
        }
    }

    /// The fit with the coefficients `held` at the ideal sensor's.
    fn fit(
        &self,
        options: &CalibrationOptions,
        held: &[Held],
    ) -> Result<Calibration<AccelerometerModel>> {
        let (r, n) = (&self.r, self.samples);
        let eiv = options.method == Method::ErrorsInVariables;
        let s2 = self.reference_variance(options);
        let free: [Vec<usize>; 3] = std::array::from_fn(|i| free_columns(held, i));
        let mut warnings = Vec::new();
        let mut regressions = Vec::with_capacity(3);
        let mut noise = Vec::with_capacity(3);
        for (i, axis) in ACCELEROMETER_AXES.iter().enumerate() {
            let reg = Regression::new(regressors(r, i, s2).select_columns(free[i].iter()), n);
            let names: Vec<String> = free[i]
                .iter()
                .map(|&c| column_names(i)[c].clone())
                .collect();
            diagnose(&reg, axis, &names, &mut warnings)?;
            regressions.push(reg);
            noise.push(eiv.then(|| {
                self.regressor_noise(i, s2)
                    .select_rows(free[i].iter())
                    .select_columns(free[i].iter())
            }));
        }
        let squares: [DVector<f64>; 3] = std::array::from_fn(|j| square(r, j, s2));
        let mut solutions = Vec::with_capacity(3);
        // The refinement stops when the omitted terms change by less than
        // rounding of the outputs. Γ² − s2 is monotone in Γ², so its largest
        // magnitude is at one end of the range of Γ².
        let (smallest, largest) = self.square_range;
        let largest_square = (largest - s2).abs().max((smallest - s2).abs());
        let tolerance = 1e-15 * (1.0 + self.largest_output) / largest_square.max(f64::MIN_POSITIVE);
        // Both estimators are linear in y, and y_i = S_i + Σ_{j≠i} (A N)_ij (Γ^j)²
        // changes between passes only through the 3×3 matrix A N. So each row's
        // coefficients are solved once for S_i and once per omitted square, and a
        // pass combines them (O(p)); the final solve with the converged y gives
        // the residuals and covariance. Every y is a combination of columns of
        // X, so each solve is O(p²) on the factor.
        let mut parts: Vec<[DVector<f64>; 3]> = Vec::with_capacity(3);
        for i in 0..3 {
            let part = |y: &DVector<f64>| -> Result<DVector<f64>> {
                Ok(regressions[i]
                    .solve(y, noise[i].as_ref(), ACCELEROMETER_AXES[i])?
                    .coefficients)
            };
            let (j1, j2) = ((i + 1) % 3, (i + 2) % 3);
            // A held Γ column i keeps A_ii = 1: the row's own input moves to
            // the left-hand side.
            let mut y = factor_column(r, OUTPUTS + i);
            if held.iter().any(|h| h.0.is_none() && h.1 == 1 + i) {
                y -= factor_column(r, 1 + i);
            }
            parts.push([part(&y)?, part(&squares[j1])?, part(&squares[j2])?]);
        }
        let mut an = Matrix3::zeros();
        let mut converged_an = an;
        for _ in 0..MAX_REFINEMENT_PASSES {
            let rows: [DVector<f64>; 3] = std::array::from_fn(|i| {
                let (j1, j2) = ((i + 1) % 3, (i + 2) % 3);
                let part = &parts[i][0] + &parts[i][1] * an[(i, j1)] + &parts[i][2] * an[(i, j2)];
                full_row(&part, &free[i], held, i)
            });
            let m = model_from_rows(&rows)?;
            // A_ij N_j at the new estimate, for the next pass.
            let next = m.output_matrix() * Matrix3::from_diagonal(&m.nonlinearity);
            let change = (next - an).amax();
            converged_an = an;
            an = next;
            if change <= tolerance {
                break;
            }
        }
        // The last pass's right-hand side, solved in full.
        for i in 0..3 {
            // y_i = S_i + Σ_{j≠i} A_ij N_j (Γ^j)²: the squares the row's
            // regressors omit, evaluated at the converged estimate.
            let mut y = factor_column(r, OUTPUTS + i);
            if held.iter().any(|h| h.0.is_none() && h.1 == 1 + i) {
                y -= factor_column(r, 1 + i);
            }
            for j in (0..3).filter(|&j| j != i) {
                y += &squares[j] * converged_an[(i, j)];
            }
            solutions.push(regressions[i].solve(&y, noise[i].as_ref(), ACCELEROMETER_AXES[i])?);
        }
        let rows: [DVector<f64>; 3] =
            std::array::from_fn(|i| full_row(&solutions[i].coefficients, &free[i], held, i));
        let mut model = model_from_rows(&rows)?;
        let jac = jacobian(&model);
        let blocks: Vec<DMatrix<f64>> = (0..3)
            .map(|i| expand_block(&solutions[i].covariance, &free[i], P))
            .collect();
        let covariance = &jac * block_diagonal(&blocks) * jac.transpose();
        let crb = options.noise_std.map(|sigma| {
            crb(
                &regressions,
                &free,
                &model,
                sigma,
                options.reference_noise_std.unwrap_or(0.0),
            )
        });
        let residual_std = Vector3::from_fn(|i, _| solutions[i].residual_std);
        model.noise.white_std = (residual_std.norm_squared() / 3.0).sqrt();
        let names = accelerometer_parameter_names();
        let std: Vec<f64> = covariance
            .diagonal()
            .iter()
            .map(|v| v.max(0.0).sqrt())
            .collect();
        let held_reason = |k: usize| {
            let (row, c) = parameter_column(k);
            held.iter()
                .find(|h| h.1 == c && (h.0.is_none() || h.0 == row))
                .map(|h| h.2.clone())
        };
        let held_parameters: Vec<bool> =
            (0..names.len()).map(|k| held_reason(k).is_some()).collect();
        uncertainty_warnings(
            "accelerometer",
            &names,
            &std,
            &scales("accelerometer", &names, None),
            &held_parameters,
            &mut warnings,
        );
        Ok(Calibration {
            model,
            std: accelerometer_std_model(&covariance),
            covariance,
            residual_std,
            condition_number: Vector3::from_fn(|i, _| regressions[i].condition_number),
            crb,
            warnings,
            held: names
                .iter()
                .enumerate()
                .filter_map(|(k, name)| held_reason(k).map(|why| (name.clone(), why)))
                .collect(),
        })
    }
}

/// A held coefficient: (row, or None for every row; column; reason).
type Held = (Option<usize>, usize, String);

/// The free columns of row i.
fn free_columns(held: &[Held], i: usize) -> Vec<usize> {
    (0..P)
        .filter(|&c| {
            !held
                .iter()
                .any(|h| h.1 == c && (h.0.is_none() || h.0 == Some(i)))
        })
        .collect()
}

/// Row i's full coefficients: the free ones, A_ii = 1 for a held Γ column
/// i, zero for every other held one.
fn full_row(
    free_coefficients: &DVector<f64>,
    free: &[usize],
    held: &[Held],
    i: usize,
) -> DVector<f64> {
    let mut row = DVector::zeros(P);
    for (k, &c) in free.iter().enumerate() {
        row[c] = free_coefficients[k];
    }
    if held.iter().any(|h| h.0.is_none() && h.1 == 1 + i) {
        row[1 + i] = 1.0;
    }
    row
}

/// The coefficient of an accelerometer parameter (its index in
/// [`accelerometer_parameter_names`]): (row or None for every row, column).
/// D_j and M_ij: the Γ column 1 + j in every row; N_i: row i's square.
fn parameter_column(k: usize) -> (Option<usize>, usize) {
    match k {
        0..=2 => (None, 0),
        3..=5 => (None, 1 + (k - 3)),
        6..=11 => (None, 1 + OFF_DIAGONAL[k - 6].1),
        _ => (Some(k - 12), 4),
    }
}

/// Calibrates an accelerometer triad from its outputs `measured` (m/s²) and
/// reference specific forces (m/s², body axes): [`FactoredAccelerometer`]
/// then [`FactoredAccelerometer::calibrate`]. See the module docs of
/// [`crate::calibration`] for the model, the exact conversion and the
/// uncertainties.
pub fn calibrate_accelerometer(
    measured: &[Vector3<f64>],
    reference_specific_force: &[Vector3<f64>],
    options: &CalibrationOptions,
) -> Result<Calibration<AccelerometerModel>> {
    FactoredAccelerometer::new(measured, reference_specific_force)?.calibrate(options)
}

#[cfg(test)]
pub(super) mod tests_support {
    use super::*;

    pub fn jacobian(m: &AccelerometerModel) -> DMatrix<f64> {
        super::jacobian(m)
    }

    pub fn model_from_rows(rows: &[DVector<f64>; 3]) -> AccelerometerModel {
        super::model_from_rows(rows).unwrap()
    }
}
