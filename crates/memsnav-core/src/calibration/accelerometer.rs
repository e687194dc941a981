//! Accelerometer calibration (method §3, paper eq. 4-5), exact conversion.

use nalgebra::{DMatrix, DVector, Matrix3, Vector3};

use super::least_squares::Regression;
use super::{
    block_diagonal, check_excitation, common_from_vector, common_jacobian, diagnose, std_of,
    validate_inputs, Calibration, CalibrationOptions, Method, ACCELEROMETER_AXES,
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

/// The squared references, less the noise variance `s2` (E[(Γ+η)²] = Γ² + σ²).
fn squares(reference: &[Vector3<f64>], s2: f64) -> [Vec<f64>; 3] {
    std::array::from_fn(|j| reference.iter().map(|v| v[j] * v[j] - s2).collect())
}

fn regressors(reference: &[Vector3<f64>], square: &[f64]) -> DMatrix<f64> {
    DMatrix::from_fn(reference.len(), P, |k, c| match c {
        0 => 1.0,
        1..=3 => reference[k][c - 1],
        _ => square[k],
    })
}

/// Σ_k E[e_k e_kᵀ] of the regressor errors of row i when every reference
/// component carries white noise η of variance s2: η on the Γ columns,
/// 2Γη + η² − σ² on the square column (variance 4Γ²σ² + 2σ⁴, covariance
/// 2Γσ² with η), with Γ² estimated without bias by Γ_obs² − σ².
fn regressor_noise(reference: &[Vector3<f64>], i: usize, s2: f64) -> DMatrix<f64> {
    let n = reference.len() as f64;
    let mut c = DMatrix::zeros(P, P);
    for j in 0..3 {
        c[(1 + j, 1 + j)] = n * s2;
    }
    let sum_g: f64 = reference.iter().map(|v| v[i]).sum();
    let sum_g2: f64 = reference.iter().map(|v| v[i] * v[i] - s2).sum();
    c[(4, 4)] = 4.0 * s2 * sum_g2 + 2.0 * n * s2 * s2;
    c[(1 + i, 4)] = 2.0 * s2 * sum_g;
    c[(4, 1 + i)] = c[(1 + i, 4)];
    c
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

/// Cramér-Rao bound (15 × 15) of the accelerometer parameters for exact
/// references and white input noise of std `noise_std` (m/s²) per sample.
pub fn accelerometer_crb(
    reference_specific_force: &[Vector3<f64>],
    model: &AccelerometerModel,
    noise_std: f64,
) -> Result<DMatrix<f64>> {
    crate::validate::positive("noise_std", noise_std)?;
    crate::validate::finite_vectors("reference_specific_force", reference_specific_force)?;
    let sq = squares(reference_specific_force, 0.0);
    let blocks: Vec<DMatrix<f64>> = (0..3)
        .map(|i| {
            let reg = Regression::new(regressors(reference_specific_force, &sq[i]));
            crb_block(&reg, model.output_matrix().row(i).norm(), noise_std)
        })
        .collect();
    let jac = jacobian(model);
    Ok(&jac * block_diagonal(&blocks) * jac.transpose())
}

/// σ_i² (GᵀG)⁻¹: the inverse Fisher information of one row whose output
/// noise is the input noise σ scaled by ‖A_i‖.
fn crb_block(reg: &Regression, row_norm: f64, noise_std: f64) -> DMatrix<f64> {
    reg.unit_covariance() * (noise_std * row_norm).powi(2)
}

/// Calibrates an accelerometer triad from its outputs `measured` (m/s²) and
/// reference specific forces (m/s², body axes). See the module docs of
/// [`crate::calibration`] for the model, the exact conversion and the
/// uncertainties.
pub fn calibrate_accelerometer(
    measured: &[Vector3<f64>],
    reference_specific_force: &[Vector3<f64>],
    options: &CalibrationOptions,
) -> Result<Calibration<AccelerometerModel>> {
    let reference = reference_specific_force;
    validate_inputs(
        measured,
        &[("reference_specific_force", reference)],
        P,
        options,
    )?;
    check_excitation(reference, ACCELEROMETER_AXES, "specific force")?;
    let eiv = options.method == Method::ErrorsInVariables;
    let s2 = if eiv {
        options.reference_noise_std.unwrap_or(0.0).powi(2)
    } else {
        0.0
    };
    let sq = squares(reference, s2);
    let mut warnings = Vec::new();
    let mut regressions = Vec::with_capacity(3);
    let mut noise = Vec::with_capacity(3);
    for i in 0..3 {
        let reg = Regression::new(regressors(reference, &sq[i]));
        diagnose(&reg, ACCELEROMETER_AXES[i], &column_names(i), &mut warnings)?;
        regressions.push(reg);
        noise.push(eiv.then(|| regressor_noise(reference, i, s2)));
    }
    let n = measured.len();
    let mut solutions = Vec::with_capacity(3);
    // The refinement stops when the omitted terms change by less than
    // rounding of the outputs.
    let largest_square = sq.iter().flatten().fold(0.0f64, |m, x| m.max(x.abs()));
    let largest_output = measured.iter().fold(0.0f64, |m, v| m.max(v.amax()));
    let tolerance = 1e-15 * (1.0 + largest_output) / largest_square.max(f64::MIN_POSITIVE);
    // Both estimators are linear in y, and y_i = S_i + Σ_{j≠i} (A N)_ij (Γ^j)²
    // changes between passes only through the 3×3 matrix A N. So each row's
    // coefficients are solved once for S_i and once per omitted square, and a
    // pass combines them (O(p) instead of a solve over all n samples); the
    // final solve with the converged y gives the residuals and covariance.
    let mut parts: Vec<[DVector<f64>; 3]> = Vec::with_capacity(3);
    for i in 0..3 {
        let part = |column: &dyn Fn(usize) -> f64| -> Result<DVector<f64>> {
            let y = DVector::from_fn(n, |k, _| column(k));
            Ok(regressions[i]
                .solve(&y, noise[i].as_ref(), ACCELEROMETER_AXES[i])?
                .coefficients)
        };
        let (j1, j2) = ((i + 1) % 3, (i + 2) % 3);
        parts.push([
            part(&|k| measured[k][i])?,
            part(&|k| sq[j1][k])?,
            part(&|k| sq[j2][k])?,
        ]);
    }
    let mut an = Matrix3::zeros();
    let mut converged_an = an;
    for _ in 0..MAX_REFINEMENT_PASSES {
        let rows: [DVector<f64>; 3] = std::array::from_fn(|i| {
            let (j1, j2) = ((i + 1) % 3, (i + 2) % 3);
            &parts[i][0] + &parts[i][1] * an[(i, j1)] + &parts[i][2] * an[(i, j2)]
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
        let y = DVector::from_fn(n, |k, _| {
            let mut y = measured[k][i];
            for j in (0..3).filter(|&j| j != i) {
                y += converged_an[(i, j)] * sq[j][k];
            }
            y
        });
        solutions.push(regressions[i].solve(&y, noise[i].as_ref(), ACCELEROMETER_AXES[i])?);
    }
    let rows: [DVector<f64>; 3] = std::array::from_fn(|i| solutions[i].coefficients.clone());
    let mut model = model_from_rows(&rows)?;
    let jac = jacobian(&model);
    let blocks: Vec<DMatrix<f64>> = solutions.iter().map(|s| s.covariance.clone()).collect();
    let covariance = &jac * block_diagonal(&blocks) * jac.transpose();
    let crb = options.noise_std.map(|sigma| {
        let blocks: Vec<DMatrix<f64>> = (0..3)
            .map(|i| crb_block(&regressions[i], model.output_matrix().row(i).norm(), sigma))
            .collect();
        &jac * block_diagonal(&blocks) * jac.transpose()
    });
    let residual_std = Vector3::from_fn(|i, _| solutions[i].residual_std);
    model.noise.white_std = (residual_std.norm_squared() / 3.0).sqrt();
    let sd = std_of(&covariance);
    let (bias, scale_factor, misalignment) = common_from_vector(&sd);
    Ok(Calibration {
        model,
        std: AccelerometerModel {
            bias,
            scale_factor,
            misalignment,
            nonlinearity: Vector3::new(sd[12], sd[13], sd[14]),
            noise: NoiseModel::default(),
        },
        covariance,
        residual_std,
        condition_number: Vector3::from_fn(|i, _| regressions[i].condition_number),
        crb,
        warnings,
    })
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
