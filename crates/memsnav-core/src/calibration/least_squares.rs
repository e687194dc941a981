//! One output axis of a calibration: a linear regression y = G c + e solved
//! by QR on column-equilibrated regressors (method §3; never through GᵀG).
//!
//! Two estimators share the factorisation G_s = Q R (G_s = G diag(1/s), s the
//! column norms):
//! - ordinary least squares, c_s = R⁻¹ Qᵀ y;
//! - the errors-in-variables (corrected-score, method-of-moments) estimator
//!   for regressors observed with zero-mean noise of known second moments
//!   Σ_k E[e_k e_kᵀ] = C: it solves (GᵀG − C) c = Gᵀy, consistent where plain
//!   LS is biased towards zero (attenuation). Written in the whitened space,
//!   (GᵀG − C) = Rᵀ (I − W) R with W = R⁻ᵀ C_s R⁻¹, so
//!   c_s = R⁻¹ (I − W)⁻¹ Qᵀ y and the normal equations are never formed.

use nalgebra::{DMatrix, DVector};

use crate::{Error, Result};

/// Above this equilibrated condition number the regression is treated as
/// rank-deficient: fewer than ~6 significant digits survive in double precision.
pub const UNOBSERVABLE_CONDITION: f64 = 1e10;
/// Above this equilibrated condition number a parameter is reported as poorly
/// determined (its estimate is sensitive to small regressor errors).
pub const POORLY_DETERMINED_CONDITION: f64 = 1e6;

/// A factored regression matrix.
pub struct Regression {
    g: DMatrix<f64>,
    scale: DVector<f64>,
    qr: nalgebra::linalg::QR<f64, nalgebra::Dyn, nalgebra::Dyn>,
    r_inv: DMatrix<f64>,
    /// Condition number of the column-equilibrated regressors (unit-free).
    pub condition_number: f64,
    /// Right singular vector of the smallest singular value (equilibrated
    /// coordinates): the combination of parameters the data determine worst.
    pub weakest_direction: DVector<f64>,
}

/// Coefficients of one axis and their covariance.
pub struct Solution {
    pub coefficients: DVector<f64>,
    /// Covariance of the coefficients from the residual variance (LS:
    /// σ̂² (GᵀG)⁻¹; EIV: the sandwich σ̂² M⁻¹ GᵀG M⁻¹ with M = GᵀG − C).
    pub covariance: DMatrix<f64>,
    /// σ̂ = √(RSS / (n − p)).
    pub residual_std: f64,
}

impl Regression {
    /// Factors G (n × p, n > p). `None` from the closure names no column:
    /// an all-zero column is reported by the caller through the returned
    /// condition number (infinite).
    pub fn new(g: DMatrix<f64>) -> Self {
        let p = g.ncols();
        let scale = DVector::from_iterator(
            p,
            g.column_iter().map(|c| {
                let n = c.norm();
                if n > 0.0 {
                    n
                } else {
                    1.0
                }
            }),
        );
        let mut gs = g.clone();
        for (j, mut col) in gs.column_iter_mut().enumerate() {
            col /= scale[j];
        }
        let qr = gs.qr();
        let r = qr.r();
        let svd = r.clone().svd(false, true);
        let (imin, smin) = svd.singular_values.argmin();
        let smax = svd.singular_values.max();
        let condition_number = if smin > 0.0 {
            smax / smin
        } else {
            f64::INFINITY
        };
        let weakest_direction = svd
            .v_t
            .as_ref()
            .map(|vt| vt.row(imin).transpose())
            .unwrap_or_else(|| DVector::zeros(p));
        let r_inv = r
            .solve_upper_triangular(&DMatrix::identity(p, p))
            .unwrap_or_else(|| DMatrix::from_element(p, p, f64::INFINITY));
        Self {
            g,
            scale,
            qr,
            r_inv,
            condition_number,
            weakest_direction,
        }
    }

    /// Number of parameters.
    pub fn parameters(&self) -> usize {
        self.g.ncols()
    }

    /// The column that dominates the weakest direction, skipping column
    /// `skip` (the constant column, which is part of every collinearity
    /// with a constant input).
    pub fn weakest_column(&self, skip: usize) -> usize {
        let mut best = 0;
        let mut best_abs = -1.0;
        for (j, v) in self.weakest_direction.iter().enumerate() {
            if j != skip && v.abs() > best_abs {
                best = j;
                best_abs = v.abs();
            }
        }
        best
    }

    /// (GᵀG)⁻¹ in physical (unscaled) coordinates.
    pub fn unit_covariance(&self) -> DMatrix<f64> {
        self.unscale(&(&self.r_inv * self.r_inv.transpose()))
    }

    fn unscale(&self, m: &DMatrix<f64>) -> DMatrix<f64> {
        let d = DMatrix::from_diagonal(&self.scale.map(|s| 1.0 / s));
        &d * m * &d
    }

    /// Solves for `y`. `regressor_noise` = Σ_k E[e_k e_kᵀ] of the regressor
    /// errors (p × p, physical units) selects the errors-in-variables
    /// estimator; `None` is plain least squares.
    pub fn solve(
        &self,
        y: &DVector<f64>,
        regressor_noise: Option<&DMatrix<f64>>,
        axis: &str,
    ) -> Result<Solution> {
        let (n, p) = self.g.shape();
        let mut qty = y.clone();
        self.qr.q_tr_mul(&mut qty);
        let qty = qty.rows(0, p).into_owned();
        let (cs, cov_s) = match regressor_noise {
            None => (&self.r_inv * &qty, &self.r_inv * self.r_inv.transpose()),
            Some(c) => {
                let d = DMatrix::from_diagonal(&self.scale.map(|s| 1.0 / s));
                let cs = &d * c * &d;
                let w = self.r_inv.transpose() * cs * &self.r_inv;
                let i_minus_w = DMatrix::identity(p, p) - w;
                // The corrected moment matrix must stay positive definite:
                // otherwise the regressor noise swamps the motion.
                let chol = i_minus_w
                    .clone()
                    .cholesky()
                    .ok_or_else(|| Error::Unobservable {
                        axis: axis.to_string(),
                        parameter: "all".to_string(),
                        reason: "the reference noise is as large as the motion: the \
                             errors-in-variables correction is not positive definite"
                            .to_string(),
                    })?;
                let inv = chol.inverse();
                (
                    &self.r_inv * &inv * &qty,
                    &self.r_inv * &inv * &inv * self.r_inv.transpose(),
                )
            }
        };
        let coefficients = cs.component_div(&self.scale);
        let residual = y - &self.g * &coefficients;
        let residual_var = residual.norm_squared() / (n - p) as f64;
        Ok(Solution {
            covariance: self.unscale(&cov_s) * residual_var,
            coefficients,
            residual_std: residual_var.sqrt(),
        })
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn matches_the_normal_equations_on_a_well_conditioned_problem() {
        // y = 2 + 3 x − x² sampled exactly: recovered to rounding.
        let n = 50;
        let g = DMatrix::from_fn(n, 3, |k, j| (k as f64 * 0.1).powi(j as i32));
        let y = DVector::from_fn(n, |k, _| {
            let x = k as f64 * 0.1;
            2.0 + 3.0 * x - x * x
        });
        let reg = Regression::new(g.clone());
        let s = reg.solve(&y, None, "u").unwrap();
        assert!((s.coefficients - DVector::from_vec(vec![2.0, 3.0, -1.0])).amax() < 1e-12);
        assert!(s.residual_std < 1e-12);
        let gtg_inv = (g.transpose() * &g).try_inverse().unwrap();
        assert!((reg.unit_covariance() - &gtg_inv).amax() < 1e-9 * gtg_inv.amax());
        // Zero regressor noise: the EIV estimator is plain LS.
        let z = reg.solve(&y, Some(&DMatrix::zeros(3, 3)), "u").unwrap();
        assert!((z.coefficients - DVector::from_vec(vec![2.0, 3.0, -1.0])).amax() < 1e-12);
    }

    #[test]
    fn a_repeated_column_is_rank_deficient_and_named() {
        let n = 20;
        let g = DMatrix::from_fn(n, 3, |k, j| {
            if j == 2 {
                4.0
            } else {
                (k as f64).powi(j as i32)
            }
        });
        let reg = Regression::new(g);
        assert!(reg.condition_number > UNOBSERVABLE_CONDITION);
        assert_eq!(reg.weakest_column(0), 2);
    }
}
