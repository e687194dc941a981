//! Calibration of the accelerometer and gyroscope models (method §3, paper
//! eq. 4-7): per-axis linear least squares on reference inputs, converted
//! back to the physical parameters exactly, with uncertainties, the
//! Cramér-Rao bound and observability diagnostics.
//!
//! ## Regression models and their exact conversion
//!
//! Write A = I − D − M. The gyroscope output (method §2) is *exactly*
//! linear in the regressors [1, Ω^p, Ω^q, Ω^r, Γ^u, Γ^v, Γ^w]: row i of
//! S_g = A Ω − A b − A K Γ − A ν has coefficients [−(A b)_i, A_i·, −(A K)_i·].
//! From the three rows, A is read directly and b = −A⁻¹ c₀, K = −A⁻¹ C.
//!
//! The accelerometer row i is S_a^i = −(A b)_i + A_i·Γ − Σ_j A_ij N_j (Γ^j)²;
//! the paper's regressors [1, Γ^u, Γ^v, Γ^w, (Γ^i)²] (method §3) carry only the
//! j = i square, with coefficient −A_ii N_i, so N_i = −c₄/A_ii. The j ≠ i
//! squares, of size |M_ij N_j (Γ^j)²| ≈ 1e-2 · 1e-5/g · g² = 1e-7 g for the
//! paper's MEMS, are what "the accuracy the regression model allows" would
//! leave. They are not left: after each solve the omitted terms are
//! evaluated with the current estimates and moved to the left-hand side
//! (y_i = S_i + Σ_{j≠i} Â_ij N̂_j (Γ^j)²), and the same factorisation is
//! re-used; each pass multiplies the error by about |M| ≈ 1e-2, so noise-free
//! data give the parameters to rounding. (Adding the squares of every axis
//! to every row would make the model exactly linear too, but on a land
//! vehicle (Γ^w)² ≈ g² is nearly the constant column, which would ruin the
//! bias of every axis.)
//!
//! The first-order shortcut (b ≈ −c₀, K ≈ −C) is off by (D + M) b ≈ 1e-4 g
//! for the paper's magnitudes, far above the statistical error of a few
//! minutes of data; the exact conversion is used throughout.
//!
//! ## Uncertainties and the Cramér-Rao bound
//!
//! Each row is solved independently; the coefficient covariance is
//! σ̂_i² (G_iᵀG_i)⁻¹ with σ̂_i² = RSS_i/(n − p) and is propagated through the
//! Jacobian J of the conversion (covariance = J Σ_c Jᵀ). The output noise
//! A ν is correlated across axes only through M (≈ 1 %), which is neglected
//! (a correlation ρ changes a row's information by O(ρ²) ≈ 1e-4).
//!
//! The Cramér-Rao bound is that of the problem actually solved: the true
//! inputs x_k (Γ_k, and Ω_k for the gyroscope) are unknown and observed
//! only through references z_k = x_k + η_k with white noise of covariance
//! R_z (the errors-in-variables model, in its functional form: the x_k are
//! nuisance parameters). Per sample the data are the output
//! y_k = h(x_k; θ) + e_k, cov R_y, and z_k. With J = ∂h/∂θ and H = ∂h/∂x,
//! the Fisher information of (θ, x_k) has blocks JᵀR_y⁻¹J, JᵀR_y⁻¹H and
//! HᵀR_y⁻¹H + R_z⁻¹; eliminating x_k (Schur complement) and Woodbury's
//! identity leave
//!
//! ```text
//! I(θ) = Σ_k Jᵀ (R_y + H R_z Hᵀ)⁻¹ J,
//! ```
//!
//! the exact-reference information with the output noise raised by the
//! reference noise pushed through the model. Here J at the true inputs is
//! the regression G (through the conversion Jacobian), R_y = σ² A Aᵀ, and
//! H = A (I − 2 N diag Γ) for the accelerometer, [A, −A K] on (Ω, Γ) for
//! the gyroscope, so row i's output variance is
//!
//! ```text
//! accelerometer  σ_i² = (σ² + σ_Γ²) ‖A_i‖²                       (2NΓ ≈ 2e-5 neglected)
//! gyroscope      σ_i² = (σ² + σ_Ω²) ‖A_i‖² + σ_Γ² ‖(A K)_i‖²
//! ```
//!
//! and the bound is σ_i² (G_iᵀG_i)⁻¹ per row with G_i from the *true*
//! inputs, propagated through J (the bound of a function of the parameters
//! is J I⁻¹ Jᵀ). With exact references (σ_Γ = σ_Ω = 0) it is the linear
//! Gaussian bound, which plain LS attains. With noisy references plain LS
//! is biased (attenuation) and does not attain it; the corrected-score
//! estimator of [`Method::ErrorsInVariables`] is consistent and its
//! asymptotic covariance is the bound plus (GᵀG)⁻¹ C σ_i² (GᵀG)⁻¹ (Fuller,
//! *Measurement Error Models*, 1987, thm. 2.2.1), C the regressor-noise
//! moment: a share σ_Γ²/var(Γ) ≈ 1e-3 of it for land-vehicle motion, so
//! it attains the bound to that order (test
//! `errors_in_variables_attains_the_noisy_reference_bound`).
//!
//! ## Errors in the references
//!
//! References from GNSS are noisy, so the regressors carry errors and plain
//! LS is biased towards zero (attenuation: a scale factor is pulled by
//! σ²/var(input)). [`Method::ErrorsInVariables`] removes that bias with the
//! corrected-score estimator of [`least_squares`], given the reference
//! noise standard deviation.
//!
//! ## One pass over the samples
//!
//! Every regressor and right-hand side of a triad is a column of one tall
//! matrix X, reduced once to its 10 × 10 triangular factor R_X
//! ([`least_squares::IncrementalQr`]; [`FactoredAccelerometer`],
//! [`FactoredGyroscope`]); nothing of size n is formed or kept. From R_X:
//! - each axis' regressors and right-hand sides are columns of R_X or
//!   combinations of them (the accelerometer's EIV squares Γ² − σ² are
//!   column Γ² minus σ² times the constant column), so LS and EIV, with or
//!   without `noise_std`, are solved from the same factor by p × p algebra;
//! - the accelerometer's refinement of the omitted cross squares changes
//!   only y, whose columns are in X: every pass costs O(p²);
//! - the excitation check reads each input's variance from R_X.
//!
//! The Cramér-Rao bound of [`accelerometer_crb`] and [`gyroscope_crb`]
//! needs (GᵀG)⁻¹ of the true inputs, a different matrix from the noisy
//! references' (by the regressor-noise moment C): it takes its own pass
//! over those inputs, with 7 columns and no right-hand side. The bound in
//! [`Calibration::crb`] (from `noise_std`) uses the calibration's own
//! regressors — the references, in place of the unknown true inputs; they
//! differ by the share σ_Γ²/var(Γ) — and costs nothing more.

mod accelerometer;
pub mod determinable;
pub mod draws;
mod gyroscope;
pub mod inflation;
pub mod information;
pub mod layout;
pub mod least_squares;
pub mod static_detector;
pub mod static_poses;

pub use accelerometer::{accelerometer_crb, calibrate_accelerometer, FactoredAccelerometer};
pub use determinable::Estimate;
pub use gyroscope::{calibrate_gyroscope, gyroscope_crb, FactoredGyroscope};

use nalgebra::{DMatrix, DVector, Matrix3, SMatrix, SVector, Vector3};

use crate::sensors::{AccelerometerModel, GyroscopeModel, NoiseModel};
use crate::{limits, validate, Error, Result};

/// Axis names of the accelerometer (u, v, w) and gyroscope (p, q, r) triads.
pub const ACCELEROMETER_AXES: [&str; 3] = ["u", "v", "w"];
/// Axis names of the gyroscope triad (p, q, r).
pub const GYROSCOPE_AXES: [&str; 3] = ["p", "q", "r"];

/// The off-diagonal elements of a misalignment matrix in parameter order.
pub const OFF_DIAGONAL: [(usize, usize); 6] = [(0, 1), (0, 2), (1, 0), (1, 2), (2, 0), (2, 1)];

/// Estimator of the regression coefficients.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default)]
pub enum Method {
    /// Ordinary least squares (the paper's eq. 5 and 7, solved by QR).
    #[default]
    LeastSquares,
    /// Bias-corrected least squares for noisy references (errors in variables).
    ErrorsInVariables,
}

/// What the calibration knows about the noise.
#[derive(Debug, Clone, Copy, Default, PartialEq)]
pub struct CalibrationOptions {
    /// Plain least squares or errors-in-variables.
    pub method: Method,
    /// Std per sample of the main reference input (specific force m/s² for
    /// the accelerometer, angular rate rad/s for the gyroscope). Required by
    /// [`Method::ErrorsInVariables`].
    pub reference_noise_std: Option<f64>,
    /// Gyroscope only: std per sample of the reference specific force, m/s²
    /// (errors-in-variables correction of the g-sensitivity columns).
    pub reference_specific_force_noise_std: Option<f64>,
    /// Std per sample of the sensor's own white noise (input-referred, SI):
    /// when given, the Cramér-Rao bound is computed.
    pub noise_std: Option<f64>,
    /// Every parameter (the paper's setting, the default) or only what the
    /// data determine ([`determinable`]).
    pub estimate: Estimate,
}

/// White noise of the references of a calibration, one sigma per sample
/// and component; zero for exact references. The errors-in-variables
/// Cramér-Rao bound (module docs) depends on it.
#[derive(Debug, Clone, Copy, PartialEq, Default)]
pub struct ReferenceNoise {
    /// Specific force, m/s².
    pub specific_force_std: f64,
    /// Angular rate, rad/s (the gyroscope's main input).
    pub angular_rate_std: f64,
}

impl ReferenceNoise {
    fn validate(&self) -> Result<()> {
        for (name, std) in [
            ("reference_specific_force_std", self.specific_force_std),
            ("reference_angular_rate_std", self.angular_rate_std),
        ] {
            validate::non_negative(name, std)?;
            validate::at_most(name, std, limits::MAX_SENSOR_MAGNITUDE)?;
        }
        Ok(())
    }
}

/// Output-noise variance of each row of the errors-in-variables model
/// (module docs): σ_i² = (σ² + σ_x²) ‖A_i‖² + σ_Γ² ‖(A K)_i‖² for output
/// matrix `a` = A, sensor noise σ = `noise_std`, main-input reference noise
/// σ_x = `input_std` and, for the gyroscope's g-sensitivity regressors,
/// specific-force reference noise σ_Γ = `specific_force_std` with
/// `a_k` = A K (zero for the accelerometer).
fn row_noise_variance(
    a: &Matrix3<f64>,
    a_k: &Matrix3<f64>,
    noise_std: f64,
    input_std: f64,
    specific_force_std: f64,
) -> Vector3<f64> {
    let white = noise_std * noise_std + input_std * input_std;
    Vector3::from_fn(|i, _| {
        white * a.row(i).norm_squared()
            + specific_force_std * specific_force_std * a_k.row(i).norm_squared()
    })
}

/// A calibrated sensor model with its uncertainties.
#[derive(Debug, Clone)]
pub struct Calibration<M> {
    /// The estimated model; its `noise.white_std` is the RMS residual
    /// (an upper estimate of the sensor noise: it also holds reference errors).
    pub model: M,
    /// One-sigma uncertainties in the fields of the model (zero where a
    /// field is not a parameter, e.g. the misalignment diagonal).
    pub std: M,
    /// Covariance of the parameter vector (order: [`accelerometer_parameter_names`]
    /// or [`gyroscope_parameter_names`]).
    pub covariance: DMatrix<f64>,
    /// Residual standard deviation per output axis (SI).
    pub residual_std: Vector3<f64>,
    /// Condition number of the column-equilibrated regressors, per axis.
    pub condition_number: Vector3<f64>,
    /// Cramér-Rao bound of the parameter vector (when `noise_std` is given),
    /// evaluated at the estimate, for references with the noise given in
    /// the options (`reference_noise_std`, and for the gyroscope
    /// `reference_specific_force_noise_std`; exact references without).
    pub crb: Option<DMatrix<f64>>,
    /// Parameters that are determined only poorly.
    pub warnings: Vec<String>,
    /// Parameters not estimated (held at the ideal sensor's value, zero
    /// variance) with the reason ([`Estimate::Determinable`]).
    pub held: Vec<(String, String)>,
}

/// Names of the 15 accelerometer parameters, in covariance order.
pub fn accelerometer_parameter_names() -> Vec<String> {
    layout::CalibrationLayout::ACCELEROMETER.names()
}

/// Names of the 21 gyroscope parameters, in covariance order.
pub fn gyroscope_parameter_names() -> Vec<String> {
    layout::CalibrationLayout::GYROSCOPE.names()
}

/// The accelerometer parameter vector [b, D, M (off-diagonal), N].
pub fn accelerometer_parameters(m: &AccelerometerModel) -> SVector<f64, 15> {
    let mut p = SVector::<f64, 15>::zeros();
    common_parameters(&m.bias, &m.scale_factor, &m.misalignment, &mut p);
    p.fixed_rows_mut::<3>(12).copy_from(&m.nonlinearity);
    p
}

/// The gyroscope parameter vector [b, D, M (off-diagonal), K (row-major)].
pub fn gyroscope_parameters(m: &GyroscopeModel) -> SVector<f64, 21> {
    let mut p = SVector::<f64, 21>::zeros();
    common_parameters(&m.bias, &m.scale_factor, &m.misalignment, &mut p);
    for i in 0..3 {
        for j in 0..3 {
            p[12 + 3 * i + j] = m.g_sensitivity[(i, j)];
        }
    }
    p
}

fn common_parameters<const P: usize>(
    bias: &Vector3<f64>,
    scale_factor: &Vector3<f64>,
    misalignment: &Matrix3<f64>,
    p: &mut SVector<f64, P>,
) {
    p.fixed_rows_mut::<3>(0).copy_from(bias);
    p.fixed_rows_mut::<3>(3).copy_from(scale_factor);
    for (m, &(i, j)) in OFF_DIAGONAL.iter().enumerate() {
        p[6 + m] = misalignment[(i, j)];
    }
}

/// Checks of the data shared by both calibrations.
fn validate_data(
    measured: &[Vector3<f64>],
    references: &[(&str, &[Vector3<f64>])],
    parameters_per_axis: usize,
) -> Result<()> {
    validate::finite_vectors("measured", measured)?;
    validate::bounded_vectors("measured", measured, limits::MAX_SENSOR_MAGNITUDE)?;
    for (name, r) in references {
        validate::same_length(name, r.len(), "measured", measured.len())?;
        validate::finite_vectors(name, r)?;
        validate::bounded_vectors(name, r, limits::MAX_SENSOR_MAGNITUDE)?;
    }
    if measured.len() <= parameters_per_axis {
        return Err(Error::invalid(
            "measured",
            format!(
                "needs at least {} samples ({parameters_per_axis} parameters per axis plus one \
                 for the residual), got {}",
                parameters_per_axis + 1,
                measured.len()
            ),
        ));
    }
    Ok(())
}

/// Checks of the options shared by both calibrations.
fn validate_options(options: &CalibrationOptions) -> Result<()> {
    for (name, v) in [
        ("reference_noise_std", options.reference_noise_std),
        (
            "reference_specific_force_noise_std",
            options.reference_specific_force_noise_std,
        ),
        ("noise_std", options.noise_std),
    ] {
        if let Some(x) = v {
            validate::positive(name, x)?;
            validate::at_most(name, x, limits::MAX_SENSOR_MAGNITUDE)?;
        }
    }
    if options.method == Method::ErrorsInVariables && options.reference_noise_std.is_none() {
        return Err(Error::invalid(
            "reference_noise_std",
            "the errors-in-variables method needs the reference noise standard deviation",
        ));
    }
    Ok(())
}

/// An input component that never varies makes its own axis' scale factor
/// inseparable from the bias (method §3: excitation).
///
/// Read from the data's factor R_X (column 0 the constant): the part of
/// column c orthogonal to the constant has squared norm Σ_{k≥1} R_kc²
/// = n · variance, free of the cancellation of Σx² − n x̄². The reference
/// components are columns `first .. first + 3`; `sums` are their sums.
fn check_excitation<const C: usize>(
    r: &SMatrix<f64, C, C>,
    samples: usize,
    first: usize,
    sums: &Vector3<f64>,
    axes: [&str; 3],
    what: &str,
) -> Result<()> {
    let n = samples as f64;
    for j in 0..3 {
        let mean = sums[j] / n;
        let var = r.column(first + j).rows(1, C - 1).norm_squared() / n;
        if var.sqrt() <= 1e-9 * mean.abs() || var == 0.0 {
            return Err(Error::Unobservable {
                axis: axes[j].to_string(),
                parameter: "scale_factor".to_string(),
                reason: format!(
                    "the reference {what} on this axis never varies (constant {mean:.6e}), so its \
                     scale factor cannot be separated from its bias"
                ),
            });
        }
    }
    Ok(())
}

/// Condition-number diagnostics of one row: an error when rank-deficient,
/// a warning when poorly determined.
fn diagnose(
    regression: &least_squares::Regression,
    axis: &str,
    column_names: &[String],
    warnings: &mut Vec<String>,
) -> Result<()> {
    let cond = regression.condition_number;
    if cond > determinable::POOR_CONDITIONING || !cond.is_finite() {
        let parameter = &column_names[regression.weakest_column(0)];
        if cond > least_squares::UNOBSERVABLE_CONDITION || !cond.is_finite() {
            return Err(Error::Unobservable {
                axis: axis.to_string(),
                parameter: parameter.clone(),
                reason: format!(
                    "the regressors are rank-deficient (condition number {cond:.2e}): the motion \
                     does not excite this parameter independently of the others"
                ),
            });
        }
        warnings.push(format!(
            "{axis} axis: {parameter} is poorly determined (condition number {cond:.2e} of the \
             equilibrated regressors)"
        ));
    }
    Ok(())
}

/// The mean of column c of the data behind a factor R_X (column 0 the
/// constant) when the column never varies (the check of
/// [`check_excitation`]), else None.
fn constant_column<const C: usize>(
    r: &SMatrix<f64, C, C>,
    samples: usize,
    c: usize,
) -> Option<f64> {
    // R_0c / R_00 = Σx/√n / √n: the mean.
    let mean = r[(0, c)] / r[(0, 0)];
    let var = r.column(c).rows(1, C - 1).norm_squared() / samples as f64;
    (var.sqrt() <= 1e-9 * mean.abs() || var == 0.0).then_some(mean)
}

/// A p_free × p_free block in the rows and columns `free` of a p × p zero matrix.
fn expand_block(block: &DMatrix<f64>, free: &[usize], p: usize) -> DMatrix<f64> {
    let mut out = DMatrix::zeros(p, p);
    for (a, &i) in free.iter().enumerate() {
        for (b, &j) in free.iter().enumerate() {
            out[(i, j)] = block[(a, b)];
        }
    }
    out
}

/// Column c of a factor R_X as a compressed column (see [`least_squares`]).
fn factor_column<const C: usize>(r: &SMatrix<f64, C, C>, c: usize) -> DVector<f64> {
    DVector::from_iterator(C, r.column(c).iter().copied())
}

/// Block-diagonal coefficient covariance from per-row blocks.
fn block_diagonal(blocks: &[DMatrix<f64>]) -> DMatrix<f64> {
    let n: usize = blocks.iter().map(|b| b.nrows()).sum();
    let mut out = DMatrix::zeros(n, n);
    let mut k = 0;
    for b in blocks {
        out.view_mut((k, k), b.shape()).copy_from(b);
        k += b.nrows();
    }
    out
}

/// Partial derivatives common to both conversions: bias b = −A⁻¹c₀ and the
/// diagonal/off-diagonal reading of A (D_i = 1 − A_ii, M_ij = −A_ij).
/// `row_len` is the number of coefficients per row; coefficient 0 of a row
/// is c₀, coefficients 1..4 are the row of A.
fn common_jacobian(
    a_inv: &Matrix3<f64>,
    bias: &Vector3<f64>,
    row_len: usize,
    jac: &mut DMatrix<f64>,
) {
    for k in 0..3 {
        for i in 0..3 {
            jac[(k, row_len * i)] = -a_inv[(k, i)];
            for j in 0..3 {
                // db = −A⁻¹ dA b for dA = E_ij.
                jac[(k, row_len * i + 1 + j)] = -a_inv[(k, i)] * bias[j];
            }
        }
    }
    for i in 0..3 {
        jac[(3 + i, row_len * i + 1 + i)] = -1.0;
    }
    for (m, &(i, j)) in OFF_DIAGONAL.iter().enumerate() {
        jac[(6 + m, row_len * i + 1 + j)] = -1.0;
    }
}

/// √diag of a covariance.
fn std_of(cov: &DMatrix<f64>) -> Vec<f64> {
    cov.diagonal().iter().map(|v| v.max(0.0).sqrt()).collect()
}

/// One-sigma values of a covariance of the accelerometer parameter vector
/// ([`accelerometer_parameters`] order), laid out as a model (noise zero).
pub fn accelerometer_std_model(covariance: &DMatrix<f64>) -> AccelerometerModel {
    let sd = std_of(covariance);
    let (bias, scale_factor, misalignment) = layout::common_fields(&sd);
    AccelerometerModel {
        bias,
        scale_factor,
        misalignment,
        nonlinearity: Vector3::new(sd[12], sd[13], sd[14]),
        noise: NoiseModel::default(),
    }
}

/// One-sigma values of a covariance of the gyroscope parameter vector
/// ([`gyroscope_parameters`] order), laid out as a model (noise zero).
pub fn gyroscope_std_model(covariance: &DMatrix<f64>) -> GyroscopeModel {
    let sd = std_of(covariance);
    let (bias, scale_factor, misalignment) = layout::common_fields(&sd);
    GyroscopeModel {
        bias,
        scale_factor,
        misalignment,
        g_sensitivity: Matrix3::from_row_slice(&sd[12..21]),
        noise: NoiseModel::default(),
    }
}

#[cfg(test)]
mod tests;
