//! The accelerometer from the gravity magnitude (Tedaldi et al. 2014
//! §III-B, in the model of method §2): at rest the true specific force has
//! the magnitude of local gravity g in every pose, so the parameters θ_a
//! minimise Σ_k (‖Γ(s̄_k; θ_a)‖ − g)² over the pose means s̄_k, with Γ(s; θ)
//! the exact inverse of eq. 2 ([`AccelerometerModel::correct`]).
//!
//! ## What the magnitude determines
//!
//! A rotation of the body frame leaves every magnitude unchanged, so three
//! of the nine entries of A = I − D − M are fixed by a convention (Tedaldi's):
//! the body x axis is the accelerometer's u axis and the body y axis lies
//! in the u-v plane, i.e. A is lower triangular, M_uv = M_uw = M_vw = 0.
//! The magnitude then determines b (3), D (3), M_vu, M_wu, M_wv and, when
//! the poses are not all aligned with the axes, the nonlinearity N (3): the
//! parameter vector θ_a = [b, D, M_vu, M_wu, M_wv, N] (12).
//!
//! ## First guess
//!
//! An ellipsoid fitted linearly to the pose means (yᵀQy + lᵀy = 1 about
//! their centroid; 9 coefficients, at least 10 poses) gives the offset and
//! a symmetric shape Q' whose lower-triangular factor T (TᵀT = g²Q') is A⁻¹
//! in the convention above; with fewer poses, or an ellipsoid that is not
//! one, the axis-aligned ellipsoid (6 coefficients); with fewer still, the
//! nominal model (A = I, b = 0).

use nalgebra::{DMatrix, DVector, Matrix3, Vector3};

use super::solver::{minimize, Fit, Residuals};
use crate::calibration::{accelerometer_parameter_names, ACCELEROMETER_AXES};
use crate::sensors::{AccelerometerModel, NoiseModel};
use crate::Result;

/// Number of entries of θ_a.
pub const PARAMETERS: usize = 12;
/// The estimated misalignments (row, column): below the diagonal.
pub const LOWER: [(usize, usize); 3] = [(1, 0), (2, 0), (2, 1)];
/// First index of N in θ_a.
pub const NONLINEARITY: usize = 9;

/// The name of entry `i` of θ_a in the 15-parameter layout of
/// [`accelerometer_parameter_names`].
pub fn parameter_name(i: usize) -> String {
    match i {
        0..=5 => accelerometer_parameter_names()[i].clone(),
        6..=8 => {
            let (r, c) = LOWER[i - 6];
            let axes = ACCELEROMETER_AXES;
            format!("misalignment_{}{}", axes[r], axes[c])
        }
        _ => accelerometer_parameter_names()[i + 3].clone(),
    }
}

/// The model of a parameter vector θ_a.
pub fn model(theta: &DVector<f64>) -> AccelerometerModel {
    let mut misalignment = Matrix3::zeros();
    for (k, &(i, j)) in LOWER.iter().enumerate() {
        misalignment[(i, j)] = theta[6 + k];
    }
    AccelerometerModel {
        bias: Vector3::new(theta[0], theta[1], theta[2]),
        scale_factor: Vector3::new(theta[3], theta[4], theta[5]),
        misalignment,
        nonlinearity: Vector3::new(theta[9], theta[10], theta[11]),
        noise: NoiseModel::default(),
    }
}

/// θ_a of a model in the convention of the module docs (the misalignments
/// above the diagonal are not part of it).
pub fn parameters(m: &AccelerometerModel) -> DVector<f64> {
    let mut theta = DVector::zeros(PARAMETERS);
    theta.rows_mut(0, 3).copy_from(&m.bias);
    theta.rows_mut(3, 3).copy_from(&m.scale_factor);
    for (k, &(i, j)) in LOWER.iter().enumerate() {
        theta[6 + k] = m.misalignment[(i, j)];
    }
    theta.rows_mut(NONLINEARITY, 3).copy_from(&m.nonlinearity);
    theta
}

/// The gravity-magnitude problem over the free entries of θ_a.
pub struct Magnitude<'a> {
    /// The accelerometer's mean reading in each pose, nominal units.
    pub means: &'a [Vector3<f64>],
    /// The local gravity magnitude, m/s².
    pub gravity: f64,
    /// The full θ_a; the entries not in `free` are held at these values.
    pub theta: DVector<f64>,
    /// The indices of θ_a that are estimated.
    pub free: Vec<usize>,
}

impl Magnitude<'_> {
    fn full(&self, x: &DVector<f64>) -> DVector<f64> {
        let mut theta = self.theta.clone();
        for (k, &i) in self.free.iter().enumerate() {
            theta[i] = x[k];
        }
        theta
    }

    /// ‖Γ_k‖ − g per pose for a full θ_a (None when a pose is beyond the
    /// model's range).
    pub fn magnitude_errors(&self, theta: &DVector<f64>) -> Option<DVector<f64>> {
        let m = model(theta);
        let mut out = DVector::zeros(self.means.len());
        for (k, s) in self.means.iter().enumerate() {
            out[k] = m.correct(s).ok()?.norm() - self.gravity;
        }
        Some(out)
    }

    /// ∂(‖Γ_k‖ − g)/∂θ_a, all 12 columns (module docs; derivation inline).
    pub fn full_jacobian(&self, theta: &DVector<f64>) -> Option<DMatrix<f64>> {
        let m = model(theta);
        let a_inv = m.output_matrix().try_inverse()?;
        let mut jac = DMatrix::zeros(self.means.len(), PARAMETERS);
        for (k, s) in self.means.iter().enumerate() {
            let gamma = m.correct(s).ok()?;
            let norm = gamma.norm();
            // Γ_i − N_i Γ_i² = x_i: ∂Γ_i/∂x_i = 1/√(1 − 4 N_i x_i) = 1/(1 − 2 N_i Γ_i),
            // ∂Γ_i/∂N_i = Γ_i²/(1 − 2 N_i Γ_i).
            let q = Vector3::from_fn(|i, _| 1.0 / (1.0 - 2.0 * m.nonlinearity[i] * gamma[i]));
            // ∂‖Γ‖/∂x = (Γ/‖Γ‖) ⊙ q.
            let g = gamma.component_mul(&q) / norm;
            // x = A⁻¹ s + b, dA = −dD − dM: ∂x/∂A_ij = −A⁻¹ e_i (A⁻¹ s)_j, so
            // ∂x/∂D_j = A⁻¹ e_j (A⁻¹s)_j and ∂x/∂M_ij = A⁻¹ e_i (A⁻¹s)_j.
            let y = a_inv * s;
            let row_g_a_inv = g.transpose() * a_inv;
            for i in 0..3 {
                jac[(k, i)] = g[i];
                jac[(k, 3 + i)] = row_g_a_inv[i] * y[i];
                jac[(k, NONLINEARITY + i)] = gamma[i] * gamma[i] * q[i] * gamma[i] / norm;
            }
            for (c, &(i, j)) in LOWER.iter().enumerate() {
                jac[(k, 6 + c)] = row_g_a_inv[i] * y[j];
            }
        }
        Some(jac)
    }
}

impl Residuals for Magnitude<'_> {
    fn residuals(&self, x: &DVector<f64>) -> Option<DVector<f64>> {
        self.magnitude_errors(&self.full(x))
    }

    fn jacobian(&self, x: &DVector<f64>) -> Option<DMatrix<f64>> {
        let jac = self.full_jacobian(&self.full(x))?;
        Some(jac.select_columns(self.free.iter()))
    }
}

/// Fits the free entries of θ_a (starting from `theta`), returning the fit
/// of those entries.
pub fn fit(
    means: &[Vector3<f64>],
    gravity: f64,
    theta: &DVector<f64>,
    free: &[usize],
) -> Result<Fit> {
    let problem = Magnitude {
        means,
        gravity,
        theta: theta.clone(),
        free: free.to_vec(),
    };
    let x0 = DVector::from_iterator(free.len(), free.iter().map(|&i| theta[i]));
    let dof = means.len().saturating_sub(free.len());
    minimize(&problem, x0, dof, "accelerometer")
}

/// The first guess of θ_a (module docs), N = 0.
pub fn first_guess(means: &[Vector3<f64>], gravity: f64) -> DVector<f64> {
    let n = means.len();
    let centroid = means.iter().sum::<Vector3<f64>>() / n as f64;
    // Columns: y_x², y_y², y_z², 2y_xy_y, 2y_xy_z, 2y_yy_z, y_x, y_y, y_z.
    let row = |y: &Vector3<f64>| -> [f64; 9] {
        [
            y.x * y.x,
            y.y * y.y,
            y.z * y.z,
            2.0 * y.x * y.y,
            2.0 * y.x * y.z,
            2.0 * y.y * y.z,
            y.x,
            y.y,
            y.z,
        ]
    };
    for columns in [vec![0, 1, 2, 3, 4, 5, 6, 7, 8], vec![0, 1, 2, 6, 7, 8]] {
        if n <= columns.len() {
            continue;
        }
        let design = DMatrix::from_fn(n, columns.len(), |k, c| {
            row(&(means[k] - centroid))[columns[c]]
        });
        let Ok(coefficients) = design
            .svd(true, true)
            .solve(&DVector::repeat(n, 1.0), 1e-12)
        else {
            continue;
        };
        let mut full = [0.0; 9];
        for (c, &col) in columns.iter().enumerate() {
            full[col] = coefficients[c];
        }
        if let Some(theta) = from_ellipsoid(&full, &centroid, gravity) {
            return theta;
        }
    }
    DVector::zeros(PARAMETERS)
}

/// θ_a from the quadric yᵀQy + lᵀy = 1 about `centroid`, when it is an
/// ellipsoid: (y − o)ᵀQ(y − o) = 1 + oᵀQo with o = −Q⁻¹l/2; T lower
/// triangular with TᵀT = g² Q/(1 + oᵀQo) is A⁻¹ and b = −T (centroid + o).
fn from_ellipsoid(c: &[f64; 9], centroid: &Vector3<f64>, gravity: f64) -> Option<DVector<f64>> {
    let q = Matrix3::new(c[0], c[3], c[4], c[3], c[1], c[5], c[4], c[5], c[2]);
    let l = Vector3::new(c[6], c[7], c[8]);
    let o = -q.try_inverse()? * l / 2.0;
    let k = 1.0 + o.dot(&(q * o));
    if k.is_nan() || k <= 0.0 {
        return None;
    }
    let shape = q * (gravity * gravity / k);
    // TᵀT = shape with T lower triangular: the Cholesky factor of the
    // reversed matrix, reversed (P shape P = L Lᵀ ⇒ shape = (P L P)(P L P)ᵀ,
    // P L P upper triangular, so T = (P L P)ᵀ).
    let p = Matrix3::new(0.0, 0.0, 1.0, 0.0, 1.0, 0.0, 1.0, 0.0, 0.0);
    let l_factor = (p * shape * p).cholesky()?.l();
    let t = (p * l_factor * p).transpose();
    let a = t.try_inverse()?;
    let mut misalignment = -a;
    misalignment.fill_diagonal(0.0);
    let m = AccelerometerModel {
        bias: -(t * (centroid + o)),
        scale_factor: Vector3::from_fn(|i, _| 1.0 - a[(i, i)]),
        misalignment,
        nonlinearity: Vector3::zeros(),
        noise: NoiseModel::default(),
    };
    Some(parameters(&m))
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::calibration::static_poses::solver::central_jacobian;

    fn truth() -> DVector<f64> {
        DVector::from_vec(vec![
            0.3, -0.2, 0.1, 0.01, -0.02, 0.015, 0.004, -0.006, 0.003, 2e-4, -1e-4, 3e-4,
        ])
    }

    /// Pose means of a model at 20 orientations spread over the sphere.
    fn poses(theta: &DVector<f64>, g: f64) -> Vec<Vector3<f64>> {
        let m = model(theta);
        (0..20)
            .map(|k| {
                let z = -1.0 + (2 * k + 1) as f64 / 20.0;
                let phi = k as f64 * 2.399_963;
                let r = (1.0 - z * z).sqrt();
                m.output(&(Vector3::new(r * phi.cos(), r * phi.sin(), z) * g))
            })
            .collect()
    }

    #[test]
    fn the_analytic_jacobian_matches_central_differences() {
        let theta = truth();
        let means = poses(&theta, 9.81);
        let problem = Magnitude {
            means: &means,
            gravity: 9.81,
            theta: theta.clone(),
            free: (0..PARAMETERS).collect(),
        };
        let x = &theta * 1.1;
        let analytic = problem.full_jacobian(&x).unwrap();
        let numeric = central_jacobian(|x| problem.magnitude_errors(x), &x, &[1e-6; 12]).unwrap();
        assert!(
            (&analytic - &numeric).amax() < 1e-6,
            "{}",
            analytic - numeric
        );
    }

    #[test]
    fn noise_free_poses_give_the_parameters_from_the_first_guess() {
        let theta = truth();
        let means = poses(&theta, 9.81);
        let guess = first_guess(&means, 9.81);
        // The linear ellipsoid lands near the truth (N aside).
        assert!(
            (guess.rows(0, 9) - theta.rows(0, 9)).amax() < 0.05,
            "{guess}"
        );
        let fit = fit(&means, 9.81, &guess, &(0..PARAMETERS).collect::<Vec<_>>()).unwrap();
        assert!((&fit.x - &theta).amax() < 1e-8, "{}", &fit.x - &theta);
        assert!(fit.residuals.amax() < 1e-10);
    }
}
