//! Nonlinear least squares for the static-pose fits: the
//! `levenberg-marquardt` crate (MINPACK's lmder on nalgebra) on a problem
//! given by two closures, the covariance σ̂² (JᵀJ)⁻¹ at the solution, and
//! central-difference Jacobians where an analytic one is not worth its code.

use levenberg_marquardt::{LeastSquaresProblem, LevenbergMarquardt};
use nalgebra::storage::Owned;
use nalgebra::{DMatrix, DVector, Dyn};

use crate::{Error, Result};

/// Residuals and Jacobian of a parameter vector (None where undefined,
/// e.g. an input beyond the model's range: the solver then shortens its step).
pub trait Residuals {
    /// The residuals at `x`.
    fn residuals(&self, x: &DVector<f64>) -> Option<DVector<f64>>;
    /// Their Jacobian at `x`.
    fn jacobian(&self, x: &DVector<f64>) -> Option<DMatrix<f64>>;
}

struct Problem<'a, R: Residuals> {
    model: &'a R,
    x: DVector<f64>,
}

impl<R: Residuals> LeastSquaresProblem<f64, Dyn, Dyn> for Problem<'_, R> {
    type ResidualStorage = Owned<f64, Dyn>;
    type JacobianStorage = Owned<f64, Dyn, Dyn>;
    type ParameterStorage = Owned<f64, Dyn>;

    fn set_params(&mut self, x: &DVector<f64>) {
        self.x.copy_from(x);
    }

    fn params(&self) -> DVector<f64> {
        self.x.clone()
    }

    fn residuals(&self) -> Option<DVector<f64>> {
        self.model.residuals(&self.x)
    }

    fn jacobian(&self) -> Option<DMatrix<f64>> {
        self.model.jacobian(&self.x)
    }
}

/// A converged fit.
#[derive(Debug, Clone)]
pub struct Fit {
    /// The parameters at convergence.
    pub x: DVector<f64>,
    /// The residuals there.
    pub residuals: DVector<f64>,
    /// The Jacobian there.
    pub jacobian: DMatrix<f64>,
    /// σ̂² (JᵀJ)⁻¹ with σ̂² = RSS / (dof).
    pub covariance: DMatrix<f64>,
    /// (JᵀJ)⁻¹.
    pub unit_covariance: DMatrix<f64>,
    /// σ̂ = √(RSS / dof), the residual std.
    pub residual_std: f64,
    /// Condition number of the column-equilibrated Jacobian.
    pub condition_number: f64,
    /// Index of the parameter that dominates the weakest direction.
    pub weakest: usize,
}

/// Minimises ‖r(x)‖² from `x0`; `dof` is the number of independent
/// residuals less the parameters (σ̂² = RSS/dof). `what` names the fit in
/// errors.
pub fn minimize<R: Residuals>(model: &R, x0: DVector<f64>, dof: usize, what: &str) -> Result<Fit> {
    let (problem, report) = LevenbergMarquardt::new()
        .with_patience(200)
        .minimize(Problem { model, x: x0 });
    if !report.termination.was_successful() {
        return Err(Error::Unobservable {
            axis: what.to_string(),
            parameter: "all".to_string(),
            reason: format!(
                "the least-squares fit did not converge ({:?})",
                report.termination
            ),
        });
    }
    let x = problem.x;
    let fail = |why: &str| Error::Unobservable {
        axis: what.to_string(),
        parameter: "all".to_string(),
        reason: why.to_string(),
    };
    let residuals = model
        .residuals(&x)
        .ok_or_else(|| fail("the residuals are undefined at the solution"))?;
    let jacobian = model
        .jacobian(&x)
        .ok_or_else(|| fail("the Jacobian is undefined at the solution"))?;
    covariance_at(x, residuals, jacobian, dof, what)
}

/// The [`Fit`] statistics at a given solution.
pub fn covariance_at(
    x: DVector<f64>,
    residuals: DVector<f64>,
    jacobian: DMatrix<f64>,
    dof: usize,
    what: &str,
) -> Result<Fit> {
    let p = jacobian.ncols();
    let norms: Vec<f64> = jacobian
        .column_iter()
        .map(|c| c.norm().max(f64::MIN_POSITIVE))
        .collect();
    let mut equilibrated = jacobian.clone();
    for (j, mut c) in equilibrated.column_iter_mut().enumerate() {
        c /= norms[j];
    }
    let svd = equilibrated.svd(false, true);
    let (imin, smin) = svd.singular_values.argmin();
    let condition_number = if smin > 0.0 {
        svd.singular_values.max() / smin
    } else {
        f64::INFINITY
    };
    let weakest = svd
        .v_t
        .as_ref()
        .map(|vt| vt.row(imin).transpose().iamax())
        .unwrap_or(0);
    // (JᵀJ)⁻¹ = D⁻¹ V S⁻² Vᵀ D⁻¹ from the equilibrated SVD.
    let vt = svd.v_t.as_ref().expect("requested");
    let mut inv = DMatrix::zeros(p, p);
    for (k, s) in svd.singular_values.iter().enumerate() {
        if *s <= 0.0 {
            return Err(Error::Unobservable {
                axis: what.to_string(),
                parameter: format!("parameter {weakest}"),
                reason: "the Jacobian is rank-deficient at the solution".to_string(),
            });
        }
        let v = vt.row(k).transpose();
        inv += &v * v.transpose() / (s * s);
    }
    for i in 0..p {
        for j in 0..p {
            inv[(i, j)] /= norms[i] * norms[j];
        }
    }
    let rss = residuals.norm_squared();
    let residual_var = if dof > 0 { rss / dof as f64 } else { f64::NAN };
    Ok(Fit {
        covariance: &inv * residual_var,
        unit_covariance: inv,
        residual_std: residual_var.sqrt(),
        condition_number,
        weakest,
        x,
        residuals,
        jacobian,
    })
}

/// Central-difference Jacobian of `f` at `x` with steps `h` (one per
/// parameter): error O(h²) for smooth f.
pub fn central_jacobian(
    f: impl Fn(&DVector<f64>) -> Option<DVector<f64>>,
    x: &DVector<f64>,
    h: &[f64],
) -> Option<DMatrix<f64>> {
    let mut columns = Vec::with_capacity(x.len());
    for (j, &step) in h.iter().enumerate() {
        let mut up = x.clone();
        let mut down = x.clone();
        up[j] += step;
        down[j] -= step;
        columns.push((f(&up)? - f(&down)?) / (2.0 * step));
    }
    Some(DMatrix::from_columns(&columns))
}

#[cfg(test)]
mod tests {
    use super::*;

    /// y = a exp(b t): a textbook nonlinear fit with an exact answer.
    struct Exponential {
        t: Vec<f64>,
        y: Vec<f64>,
    }

    impl Residuals for Exponential {
        fn residuals(&self, x: &DVector<f64>) -> Option<DVector<f64>> {
            Some(DVector::from_iterator(
                self.t.len(),
                self.t
                    .iter()
                    .zip(&self.y)
                    .map(|(t, y)| x[0] * (x[1] * t).exp() - y),
            ))
        }
        fn jacobian(&self, x: &DVector<f64>) -> Option<DMatrix<f64>> {
            central_jacobian(|x| self.residuals(x), x, &[1e-6, 1e-6])
        }
    }

    #[test]
    fn recovers_an_exact_model_and_the_linear_covariance() {
        let t: Vec<f64> = (0..30).map(|k| k as f64 * 0.1).collect();
        let exact = Exponential {
            y: t.iter().map(|t| 2.0 * (-0.7 * t).exp()).collect(),
            t: t.clone(),
        };
        let fit = minimize(&exact, DVector::from_vec(vec![1.0, 0.0]), 28, "test").unwrap();
        assert!(
            (fit.x[0] - 2.0).abs() < 1e-9 && (fit.x[1] + 0.7).abs() < 1e-9,
            "{}",
            fit.x
        );
        // With a perturbation: the covariance is σ̂² (JᵀJ)⁻¹ of the analytic
        // Jacobian at the solution.
        let noisy = Exponential {
            y: exact
                .y
                .iter()
                .enumerate()
                .map(|(k, y)| y + 1e-3 * (17.0 * k as f64).sin())
                .collect(),
            t,
        };
        let fit = minimize(&noisy, DVector::from_vec(vec![1.0, 0.0]), 28, "test").unwrap();
        let (a, b) = (fit.x[0], fit.x[1]);
        let j = DMatrix::from_fn(30, 2, |k, c| {
            let tk = k as f64 * 0.1;
            if c == 0 {
                (b * tk).exp()
            } else {
                a * tk * (b * tk).exp()
            }
        });
        let rss: f64 = fit.residuals.norm_squared();
        assert!((fit.residual_std - (rss / 28.0).sqrt()).abs() < 1e-15);
        assert!((&fit.jacobian - &j).amax() < 1e-8);
        let inv = (j.transpose() * &j).try_inverse().unwrap();
        let unit = &fit.covariance / fit.residual_std.powi(2);
        assert!((unit - &inv).amax() < 1e-6 * inv.amax());
    }
}
