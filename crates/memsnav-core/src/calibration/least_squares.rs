//! One output axis of a calibration: a linear regression y = G c + e solved
//! by QR on column-equilibrated regressors (method §3; never through GᵀG).
//!
//! ## The samples are read once, into a small triangle
//!
//! Every regressor and right-hand side of a calibration is a column of one
//! tall matrix X (n × C, C ≤ 10: e.g. [1, Γ, Γ², S] for the accelerometer),
//! or a linear combination of its columns. [`IncrementalQr`] reduces X to
//! its C × C upper-triangular factor R_X (X = U R_X with UᵀU = I) block by
//! block, a tall-skinny QR: each block of [`BLOCK_ROWS`] rows is stacked
//! under the current R_X and folded in by C Householder reflections
//! (Golub & Van Loan §5.2), so the n × C matrix never exists and the
//! samples are read once. Everything a regression needs is invariant under
//! the isometry U: for G = X L and y = X l (L, l select or combine columns),
//! G = U (R_X L), so the column norms of G, its R factor, Qᵀy and the
//! residual norm ‖y − G c‖ = ‖R_X (l − L c)‖ are those of the small
//! C × p matrix R_X L and the C-vector R_X l. [`Regression`] works on those
//! compressed forms and needs n only for the degrees of freedom. The
//! residual is formed from the final coefficients in the compressed space
//! (C entries) rather than as ‖y‖² − ‖Qᵀy‖², which would cancel.
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

use nalgebra::{DMatrix, DVector, SMatrix};

use crate::{Error, Result};

/// Rows per block of [`IncrementalQr`]: enough to amortise the reflections'
/// set-up over long, vectorisable inner loops, small enough that a block of
/// 10 columns (5 KB) stays in L1.
pub const BLOCK_ROWS: usize = 64;

/// Length of the partial sums of the block dot products: independent
/// accumulators the compiler keeps in vector registers (a single running
/// sum would serialise the additions).
const LANES: usize = 8;

/// Upper-triangular factor R_X (C × C) of a tall matrix X fed one row at a
/// time (module docs). Fixed size: no allocation per row or per block.
#[derive(Debug, Clone)]
pub struct IncrementalQr<const C: usize> {
    r: SMatrix<f64, C, C>,
    /// The pending rows, column-major; rows past `filled` are zero.
    block: [[f64; BLOCK_ROWS]; C],
    filled: usize,
    rows: usize,
}

impl<const C: usize> Default for IncrementalQr<C> {
    fn default() -> Self {
        Self {
            r: SMatrix::zeros(),
            block: [[0.0; BLOCK_ROWS]; C],
            filled: 0,
            rows: 0,
        }
    }
}

impl<const C: usize> IncrementalQr<C> {
    /// An empty factorisation.
    pub fn new() -> Self {
        Self::default()
    }

    /// Appends one row of X.
    #[inline]
    pub fn push(&mut self, row: &[f64; C]) {
        // `filled` < BLOCK_ROWS always (a full block is folded at once); the
        // remainder says so to the compiler, which then keeps the index in a
        // register with no bounds check per column.
        let i = self.filled % BLOCK_ROWS;
        for (column, &x) in self.block.iter_mut().zip(row) {
            column[i] = x;
        }
        self.filled = i + 1;
        self.rows += 1;
        if self.filled == BLOCK_ROWS {
            self.fold_block();
        }
    }

    /// Rows pushed so far.
    pub fn rows(&self) -> usize {
        self.rows
    }

    /// R_X of all the rows pushed (its diagonal may carry either sign).
    pub fn finish(mut self) -> SMatrix<f64, C, C> {
        if self.filled > 0 {
            self.fold_block();
        }
        self.r
    }

    /// Triangularises [R; block] in place: for column j, the reflector
    /// H = I − τ v vᵀ with v = [1 (row j of R); block column j / v₀] maps
    /// (R_jj, block_j) onto (β, 0), β = −sign(R_jj) ‖(R_jj, block_j)‖
    /// (the sign that avoids cancellation in v₀ = R_jj − β), and is applied to
    /// the later columns. Rows of R other than j are untouched: their
    /// entries in column j are already zero. The zero padding of a partial
    /// block stays zero.
    fn fold_block(&mut self) {
        for j in 0..C {
            let (head, rest) = self.block.split_at_mut(j + 1);
            let v = &mut head[j];
            let sigma = dot(v, v);
            if sigma == 0.0 {
                continue; // nothing below the diagonal to annihilate
            }
            let alpha = self.r[(j, j)];
            let norm = (alpha * alpha + sigma).sqrt();
            let beta = if alpha > 0.0 { -norm } else { norm };
            let tau = (beta - alpha) / beta;
            let inv_v0 = 1.0 / (alpha - beta);
            v.iter_mut().for_each(|x| *x *= inv_v0);
            // Two columns per sweep: each load of v serves both (the loops
            // are bound by loads, not arithmetic).
            for (pair, columns) in rest.chunks_mut(2).enumerate() {
                let k = j + 1 + 2 * pair;
                match columns {
                    [a, b] => {
                        let (da, db) = dot2(v, a, b);
                        let wa = tau * (self.r[(j, k)] + da);
                        let wb = tau * (self.r[(j, k + 1)] + db);
                        self.r[(j, k)] -= wa;
                        self.r[(j, k + 1)] -= wb;
                        for ((x, y), &vi) in a.iter_mut().zip(b.iter_mut()).zip(v.iter()) {
                            *x -= wa * vi;
                            *y -= wb * vi;
                        }
                    }
                    [a] => {
                        let w = tau * (self.r[(j, k)] + dot(v, a));
                        self.r[(j, k)] -= w;
                        for (x, &vi) in a.iter_mut().zip(v.iter()) {
                            *x -= w * vi;
                        }
                    }
                    _ => unreachable!("chunks of at most two columns"),
                }
            }
            self.r[(j, j)] = beta;
        }
        // Every column now holds its (spent) reflector: clear for the next block.
        self.block = [[0.0; BLOCK_ROWS]; C];
        self.filled = 0;
    }
}

/// v·a and v·b in one sweep, each summed exactly as [`dot`] sums it.
#[inline(always)]
fn dot2(v: &[f64; BLOCK_ROWS], a: &[f64; BLOCK_ROWS], b: &[f64; BLOCK_ROWS]) -> (f64, f64) {
    let mut acc_a = [0.0; LANES];
    let mut acc_b = [0.0; LANES];
    for ((x, y), z) in v
        .chunks_exact(LANES)
        .zip(a.chunks_exact(LANES))
        .zip(b.chunks_exact(LANES))
    {
        for l in 0..LANES {
            acc_a[l] += x[l] * y[l];
            acc_b[l] += x[l] * z[l];
        }
    }
    (acc_a.iter().sum(), acc_b.iter().sum())
}

/// Dot product of two blocks with [`LANES`] independent partial sums.
#[inline(always)]
fn dot(a: &[f64; BLOCK_ROWS], b: &[f64; BLOCK_ROWS]) -> f64 {
    let mut acc = [0.0; LANES];
    for (x, y) in a.chunks_exact(LANES).zip(b.chunks_exact(LANES)) {
        for l in 0..LANES {
            acc[l] += x[l] * y[l];
        }
    }
    acc.iter().sum()
}

/// Above this equilibrated condition number the regression is treated as
/// rank-deficient: fewer than ~6 significant digits survive in double precision.
pub const UNOBSERVABLE_CONDITION: f64 = 1e10;
/// Above this equilibrated condition number a parameter is reported as poorly
/// determined (its estimate is sensitive to small regressor errors).
pub const POORLY_DETERMINED_CONDITION: f64 = 1e6;

/// A factored regression matrix, held in compressed form (module docs).
pub struct Regression {
    /// R_X L: the regressors in the coordinates of the data's factor (m × p).
    g: DMatrix<f64>,
    /// Number of samples n behind the compressed form.
    samples: usize,
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
    /// The estimated coefficients.
    pub coefficients: DVector<f64>,
    /// Covariance of the coefficients from the residual variance (LS:
    /// σ̂² (GᵀG)⁻¹; EIV: the sandwich σ̂² M⁻¹ GᵀG M⁻¹ with M = GᵀG − C).
    pub covariance: DMatrix<f64>,
    /// σ̂ = √(RSS / (n − p)).
    pub residual_std: f64,
}

impl Regression {
    /// Factors the regressors G of `samples` samples (n > p) given in
    /// compressed form: any m × p matrix `g` (m ≥ p) with G = U g for some U
    /// with orthonormal columns, typically columns of the factor R_X of
    /// [`IncrementalQr`]. An all-zero column is reported through the
    /// condition number (infinite).
    pub fn new(g: DMatrix<f64>, samples: usize) -> Self {
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
            samples,
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

    /// Solves for the right-hand side y given in the same compressed form as
    /// the regressors (y = U `y`, an m-vector). `regressor_noise` =
    /// Σ_k E[e_k e_kᵀ] of the regressor errors (p × p, physical units)
    /// selects the errors-in-variables estimator; `None` is plain least
    /// squares.
    pub fn solve(
        &self,
        y: &DVector<f64>,
        regressor_noise: Option<&DMatrix<f64>>,
        axis: &str,
    ) -> Result<Solution> {
        let (n, p) = (self.samples, self.g.ncols());
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
        // ‖y − G c‖ = ‖U (y_c − g c)‖ = ‖y_c − g c‖: m entries, not n.
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
    use crate::random::stream;
    use rand::Rng as _;
    use rand_distr::StandardNormal;

    /// R_X of a dense matrix through [`IncrementalQr`].
    fn factor<const C: usize>(x: &DMatrix<f64>) -> SMatrix<f64, C, C> {
        let mut qr = IncrementalQr::<C>::new();
        for row in x.row_iter() {
            qr.push(&std::array::from_fn(|c| row[c]));
        }
        assert_eq!(qr.rows(), x.nrows());
        qr.finish()
    }

    /// Columns `cols` of R_X as a dense matrix (the compressed regressors).
    fn columns<const C: usize>(r: &SMatrix<f64, C, C>, cols: &[usize]) -> DMatrix<f64> {
        DMatrix::from_fn(C, cols.len(), |i, j| r[(i, cols[j])])
    }

    #[test]
    fn matches_the_normal_equations_on_a_well_conditioned_problem() {
        // y = 2 + 3 x − x² sampled exactly: recovered to rounding.
        let n = 50;
        let x = DMatrix::from_fn(n, 4, |k, j| {
            let t = k as f64 * 0.1;
            if j < 3 {
                t.powi(j as i32)
            } else {
                2.0 + 3.0 * t - t * t
            }
        });
        let r = factor::<4>(&x);
        let g = x.columns(0, 3).into_owned();
        let reg = Regression::new(columns(&r, &[0, 1, 2]), n);
        let y = columns(&r, &[3]).column(0).into_owned();
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
        let x = DMatrix::from_fn(n, 3, |k, j| {
            if j == 2 {
                4.0
            } else {
                (k as f64).powi(j as i32)
            }
        });
        let reg = Regression::new(columns(&factor::<3>(&x), &[0, 1, 2]), n);
        assert!(reg.condition_number > UNOBSERVABLE_CONDITION);
        assert_eq!(reg.weakest_column(0), 2);
    }

    /// The block factorisation, and every quantity derived from it, against
    /// a dense QR and SVD of the whole n × p matrix written here: several
    /// blocks plus a partial one, columns of very different scales, a
    /// right-hand side that is a combination of columns, both estimators.
    #[test]
    fn the_compressed_path_equals_a_dense_solve() {
        let mut rng = stream(11, 0);
        let n = 64 * 15 + 40;
        let mut gauss = || rng.sample::<f64, _>(StandardNormal);
        // X = [1, a, b, a², y₁, y₂]: a quadratic model, two right-hand sides.
        let x = DMatrix::from_fn(n, 6, |_, _| gauss());
        let x = DMatrix::from_fn(n, 6, |k, j| {
            let a = 3.0 + 0.5 * x[(k, 0)];
            let b = 1e-3 * x[(k, 1)];
            match j {
                0 => 1.0,
                1 => a,
                2 => b,
                3 => a * a,
                4 => 0.7 - 2.0 * a + 40.0 * b + 0.01 * a * a + 0.05 * x[(k, 2)],
                _ => 1.5 * a + 0.2 * x[(k, 3)],
            }
        });
        let r = factor::<6>(&x);
        // RᵀR = XᵀX: the factor carries all second moments.
        let xtx = x.transpose() * &x;
        let rtr = DMatrix::from_fn(6, 6, |i, j| r.column(i).dot(&r.column(j)));
        assert!((&rtr - &xtx).amax() < 1e-12 * xtx.amax());

        // Regressors [1, a, b, a² − 0.5] (a shifted column, as the EIV squares)
        // and the right-hand side y₁ + 0.3 y₂.
        let shift = |m: &DMatrix<f64>, c0: usize, c3: usize| -> DMatrix<f64> {
            let mut g = DMatrix::from_fn(m.nrows(), 4, |i, j| m[(i, [c0, 1, 2, c3][j])]);
            let col = g.column(3) - g.column(0) * 0.5;
            g.set_column(3, &col);
            g
        };
        let g_dense = shift(&x.columns(0, 4).into_owned(), 0, 3);
        let y_dense = x.column(4) + x.column(5) * 0.3;
        let r_dense = DMatrix::from_fn(6, 6, |i, j| r[(i, j)]);
        let reg = Regression::new(shift(&r_dense, 0, 3), n);
        let y = r_dense.column(4) + r_dense.column(5) * 0.3;

        // Dense LS by SVD; covariance σ̂² V S⁻² Vᵀ.
        let svd = g_dense.clone().svd(true, true);
        let c_ls = svd.solve(&y_dense, 0.0).unwrap();
        let dof = (n - 4) as f64;
        let rss_ls = (&y_dense - &g_dense * &c_ls).norm_squared();
        let v = svd.v_t.as_ref().unwrap().transpose();
        let s_inv2 = DMatrix::from_diagonal(&svd.singular_values.map(|s| 1.0 / (s * s)));
        let cov_ls = &v * s_inv2 * v.transpose() * (rss_ls / dof);
        // Dense EIV with a known regressor-noise moment, by a dense QR of G:
        // c = R⁻¹ (I − R⁻ᵀ C R⁻¹)⁻¹ Qᵀ y.
        let noise =
            DMatrix::from_diagonal(&DVector::from_vec(vec![0.0, 1e-3, 1e-8, 0.02])) * n as f64;
        let qr = g_dense.clone().qr();
        let rd_inv = qr.r().try_inverse().unwrap();
        let m_inv = (DMatrix::identity(4, 4) - rd_inv.transpose() * &noise * &rd_inv)
            .try_inverse()
            .unwrap();
        let c_eiv = &rd_inv * &m_inv * (qr.q().transpose() * &y_dense);
        let rss_eiv = (&y_dense - &g_dense * &c_eiv).norm_squared();
        let cov_eiv = &rd_inv * &m_inv * &m_inv * rd_inv.transpose() * (rss_eiv / dof);
        // Condition number of the equilibrated dense regressors.
        let norms = DVector::from_fn(4, |j, _| g_dense.column(j).norm());
        let mut gs = g_dense.clone();
        for j in 0..4 {
            gs.column_mut(j).scale_mut(1.0 / norms[j]);
        }
        let sv = gs.singular_values();
        let cond = sv.max() / sv.min();

        let close = |a: &DVector<f64>, b: &DVector<f64>| (a - b).amax() <= 1e-10 * b.amax();
        let ls = reg.solve(&y, None, "u").unwrap();
        assert!(
            close(&ls.coefficients, &c_ls),
            "{} vs {}",
            ls.coefficients,
            c_ls
        );
        assert!((ls.residual_std / (rss_ls / dof).sqrt() - 1.0).abs() < 1e-10);
        assert!((&ls.covariance - &cov_ls).amax() <= 1e-10 * cov_ls.amax());
        let eiv = reg.solve(&y, Some(&noise), "u").unwrap();
        assert!(
            close(&eiv.coefficients, &c_eiv),
            "{} vs {}",
            eiv.coefficients,
            c_eiv
        );
        assert!((eiv.residual_std / (rss_eiv / dof).sqrt() - 1.0).abs() < 1e-10);
        assert!((&eiv.covariance - &cov_eiv).amax() <= 1e-10 * cov_eiv.amax());
        assert!((reg.condition_number / cond - 1.0).abs() < 1e-10);
        // The EIV correction matters here (else the comparison proves little).
        assert!((&eiv.coefficients - &ls.coefficients).amax() > 1e-6 * c_ls.amax());
    }
}
