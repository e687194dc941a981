//! Fixed-interval smoothing of an error-state filter: the modified
//! Bryson-Frazier form of the Rauch-Tung-Striebel smoother (Bierman,
//! *Factorization Methods for Discrete Sequential Estimation*, 1977, §X;
//! Simon, *Optimal State Estimation*, 2006, §9.4.3), which runs backward on
//! adjoint variables and never inverts a covariance.
//!
//! The forward filter records what it does to its covariance, in order:
//! each propagation step (what rebuilds its Φ), each applied scalar
//! measurement (row h, innovation ν = y − h x⁻, its variance s, gain
//! k = P⁻hᵀ/s, noise r), each reset (a linear map of the error state plus
//! an independent new part), and each output sample. The backward pass,
//! from λ = 0, Λ = 0 after the last sample:
//!
//! ```text
//! output k:       x̂ˢ_k = x̂⁺_k − P⁺_k λ,   Pˢ_k = P⁺_k − P⁺_k Λ P⁺_k
//! measurement:    λ ← (I − k h)ᵀ λ − hᵀ ν / s
//!                 Λ ← (I − k h)ᵀ Λ (I − k h) + hᵀ h / s
//! reset x ← T x + w:   λ ← Tᵀ λ,   Λ ← Tᵀ Λ T
//! propagation:    λ ← Φᵀ λ,   Λ ← Φᵀ Λ Φ
//! ```
//!
//! **Closed-loop feedback.** After each accepted batch the filter moves its
//! estimated errors into the nominal state and zeroes the error state, so
//! x̂⁺_k = 0 at every output and each recorded innovation is the one the
//! update used, relative to the nominal of its time: the filter is, to
//! first order, the linear filter of the error state about a moving
//! nominal, and the recursion above smooths that linear filter. The
//! smoothed error of output k is −P⁺_k λ, and the smoothed state is the
//! forward nominal corrected by it the way feedback corrects it
//! (`coupling`).
//!
//! **Resets.** A reset of states S to a new, independent value is
//! x ← T x + w with T the identity with the rows of S zeroed (a component
//! reset: T = I − d dᵀ on its block): information does not flow back through
//! it for those states. A covariance inflation, or the variance a clock jump
//! adds, changes no error (T = I) and only enters through P⁺.
//!
//! **Memory.** The backward pass needs P⁺ at every output. Storing it would
//! take N² numbers per sample (2.3 kB for 17 states); the log keeps a full
//! P only every `checkpoint_every` outputs and replays the covariance
//! forward from the checkpoint over each segment during the backward pass
//! (one more propagation of P, the cost of the forward filter's). Per IMU
//! step the log holds the propagation's inputs (19 numbers) and an op tag;
//! per applied measurement its row, gain and scalars.

use nalgebra::{SMatrix, SVector, Vector3};

use super::update::ScalarMeasurement;

/// How one propagation step acts on P (forward, for the replay) and on the
/// adjoints (backward): the filter's own structured ECEF model, or any
/// other linear model.
pub trait StepModel<const N: usize> {
    /// What a step needs to rebuild its Φ and Q.
    type Step: Copy;
    /// P ← Φ P Φᵀ + Q.
    fn propagate(&mut self, step: &Self::Step, p: &mut SMatrix<f64, N, N>);
    /// λ ← Φᵀ λ, Λ ← Φᵀ Λ Φ.
    fn adjoint(
        &mut self,
        step: &Self::Step,
        lambda: &mut SVector<f64, N>,
        big_lambda: &mut SMatrix<f64, N, N>,
    );
}

/// An applied scalar measurement as the smoother needs it.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct ScalarStep<const N: usize> {
    /// Its row, prediction minus measurement and noise variance.
    pub measurement: ScalarMeasurement,
    /// Innovation ν = y − h x⁻.
    pub innovation: f64,
    /// Its variance s = h P⁻ hᵀ + r.
    pub innovation_variance: f64,
    /// Gain k = P⁻ hᵀ / s.
    pub gain: SVector<f64, N>,
}

/// A change of the error state and its covariance other than propagation
/// and measurement.
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum ResetStep {
    /// States `first..first + len` (len ≤ 3) replaced by new values of
    /// covariance `covariance` (column-major, len × len).
    Block {
        first: usize,
        len: usize,
        covariance: [f64; 9],
    },
    /// The component along `direction` of the three states at `first`
    /// replaced by a new value of variance `variance`.
    Component {
        first: usize,
        direction: Vector3<f64>,
        variance: f64,
    },
    /// Variances of `states[..count]` multiplied by `factor`.
    Inflate {
        states: [usize; 8],
        count: usize,
        factor: f64,
    },
    /// `variance` added to state `state`'s variance.
    AddVariance { state: usize, variance: f64 },
}

#[derive(Debug, Clone, Copy, PartialEq, Eq)]
enum Op {
    Step(u32),
    Scalar(u32),
    Reset(u32),
    Output,
}

/// What the forward filter did to its covariance, for the backward pass.
#[derive(Debug, Clone)]
pub struct SmootherLog<const N: usize, M: StepModel<N>> {
    model: M,
    ops: Vec<Op>,
    steps: Vec<M::Step>,
    scalars: Vec<ScalarStep<N>>,
    resets: Vec<ResetStep>,
    /// (index into `ops` of an output, P⁺ at that output).
    checkpoints: Vec<(usize, SMatrix<f64, N, N>)>,
    checkpoint_every: usize,
    outputs: usize,
}

/// A smoothed output: the error-state estimate and, on demand, entries of
/// its covariance Pˢ = P⁺ − P⁺ Λ P⁺. The product W = Λ P⁺ is formed once
/// per output; an entry is then P⁺ᵢⱼ − P⁺ᵢ· W·ⱼ, so a caller that keeps the
/// diagonal and a few blocks pays one N×N×N product instead of the two of
/// the full Pˢ (the dominant cost of the backward pass at every IMU sample).
#[derive(Debug, Clone, Copy)]
pub struct Smoothed<'a, const N: usize> {
    /// Output index (the order in which outputs were recorded).
    pub output: usize,
    /// Smoothed error estimate x̂ˢ (estimate − truth of the forward nominal).
    pub error: SVector<f64, N>,
    forward_covariance: &'a SMatrix<f64, N, N>,
    adjoint_times_covariance: &'a SMatrix<f64, N, N>,
    /// diag(P⁺ Λ P⁺), formed with W.
    quadratic_forms: &'a SVector<f64, N>,
}

impl<const N: usize> Smoothed<'_, N> {
    /// Pˢᵢⱼ. P⁺ is symmetric, so its row i is its (contiguous) column i.
    pub fn covariance_entry(&self, i: usize, j: usize) -> f64 {
        if i == j {
            return self.forward_covariance[(i, i)] - self.quadratic_forms[i];
        }
        let column = |m: &SMatrix<f64, N, N>, k: usize| -> [f64; N] {
            m.as_slice()[k * N..(k + 1) * N]
                .try_into()
                .expect("a column has N rows")
        };
        let (p_i, w_j) = (
            column(self.forward_covariance, i),
            column(self.adjoint_times_covariance, j),
        );
        self.forward_covariance[(i, j)] - p_i.iter().zip(&w_j).map(|(a, b)| a * b).sum::<f64>()
    }

    /// The diagonal of Pˢ.
    pub fn covariance_diagonal(&self) -> SVector<f64, N> {
        self.forward_covariance.diagonal() - self.quadratic_forms
    }

    /// The R×R diagonal block of Pˢ at states `first..first + R`.
    pub fn covariance_block<const R: usize>(&self, first: usize) -> SMatrix<f64, R, R> {
        SMatrix::from_fn(|a, b| {
            if a <= b {
                self.covariance_entry(first + a, first + b)
            } else {
                self.covariance_entry(first + b, first + a)
            }
        })
    }

    /// The whole Pˢ (symmetrised).
    pub fn covariance(&self) -> SMatrix<f64, N, N> {
        let full =
            self.forward_covariance - self.forward_covariance * self.adjoint_times_covariance;
        0.5 * (full + full.transpose())
    }
}

impl<const N: usize, M: StepModel<N>> SmootherLog<N, M> {
    /// An empty log for `model`, a full P kept every `checkpoint_every`
    /// outputs (at least 1).
    pub fn new(model: M, checkpoint_every: usize) -> Self {
        Self {
            model,
            ops: Vec::new(),
            steps: Vec::new(),
            scalars: Vec::new(),
            resets: Vec::new(),
            checkpoints: Vec::new(),
            checkpoint_every: checkpoint_every.max(1),
            outputs: 0,
        }
    }

    /// Records a propagation step.
    pub fn step(&mut self, step: M::Step) {
        self.ops.push(Op::Step(self.steps.len() as u32));
        self.steps.push(step);
    }

    /// Records an applied scalar measurement.
    pub fn scalar(&mut self, s: ScalarStep<N>) {
        self.ops.push(Op::Scalar(self.scalars.len() as u32));
        self.scalars.push(s);
    }

    /// Records a reset.
    pub fn reset(&mut self, r: ResetStep) {
        self.ops.push(Op::Reset(self.resets.len() as u32));
        self.resets.push(r);
    }

    /// Records an output sample with the filter's covariance there.
    pub fn output(&mut self, p: &SMatrix<f64, N, N>) {
        if self.outputs % self.checkpoint_every == 0 {
            self.checkpoints.push((self.ops.len(), *p));
        }
        self.ops.push(Op::Output);
        self.outputs += 1;
    }

    /// Number of outputs recorded.
    pub fn outputs(&self) -> usize {
        self.outputs
    }

    /// Bytes the log holds (for the documented memory figure).
    pub fn bytes(&self) -> usize {
        use std::mem::size_of;
        self.ops.capacity() * size_of::<Op>()
            + self.steps.capacity() * size_of::<M::Step>()
            + self.scalars.capacity() * size_of::<ScalarStep<N>>()
            + self.resets.capacity() * size_of::<ResetStep>()
            + self.checkpoints.capacity() * size_of::<(usize, SMatrix<f64, N, N>)>()
    }

    /// The backward pass: calls `emit` for every output, last first, with
    /// its smoothed error estimate and covariance.
    pub fn smooth(&mut self, mut emit: impl FnMut(&Smoothed<'_, N>)) {
        let mut lambda = SVector::<f64, N>::zeros();
        let mut big = SMatrix::<f64, N, N>::zeros();
        let mut big_times_p = SMatrix::<f64, N, N>::zeros();
        let mut quadratic_forms = SVector::<f64, N>::zeros();
        let mut covariances: Vec<SMatrix<f64, N, N>> = Vec::with_capacity(self.checkpoint_every);
        let mut output = self.outputs;
        let mut end = self.ops.len();
        for c in (0..self.checkpoints.len()).rev() {
            let (start, p0) = self.checkpoints[c];
            // Forward replay of the segment: P⁺ at each of its outputs.
            covariances.clear();
            let mut p = p0;
            for op in &self.ops[start..end] {
                match *op {
                    Op::Output => covariances.push(p),
                    Op::Step(i) => self.model.propagate(&self.steps[i as usize], &mut p),
                    Op::Scalar(i) => replay_scalar(&self.scalars[i as usize], &mut p),
                    Op::Reset(i) => replay_reset(&self.resets[i as usize], &mut p),
                }
            }
            let first_output = output - covariances.len();
            // Backward through the segment.
            for op in self.ops[start..end].iter().rev() {
                match *op {
                    Op::Output => {
                        output -= 1;
                        // The segment's outputs, last first (no copy out).
                        let p = &covariances[output - first_output];
                        adjoint_product(&big, p, &mut big_times_p, &mut quadratic_forms);
                        emit(&Smoothed {
                            output,
                            error: -(p * lambda),
                            forward_covariance: p,
                            adjoint_times_covariance: &big_times_p,
                            quadratic_forms: &quadratic_forms,
                        });
                    }
                    Op::Step(i) => {
                        self.model
                            .adjoint(&self.steps[i as usize], &mut lambda, &mut big)
                    }
                    Op::Scalar(i) => {
                        adjoint_scalar(&self.scalars[i as usize], &mut lambda, &mut big)
                    }
                    Op::Reset(i) => adjoint_reset(&self.resets[i as usize], &mut lambda, &mut big),
                }
            }
            end = start;
        }
    }
}

/// W = Λ P⁺ and the diagonal of P⁺ W (the quadratic forms p_jᵀ Λ p_j, P⁺
/// symmetric): column j of W accumulated in registers as Σₖ Λ·ₖ Pₖⱼ, then
/// dotted with column j of P⁺ while at hand. It is the backward pass's
/// dominant cost (one per output), so it is also compiled for AVX2 with FMA
/// and that version chosen at run time: the wheel targets baseline x86-64,
/// and nalgebra's generic product is not inlined into code compiled for
/// other features.
#[multiversion::multiversion(targets("x86_64+avx2+fma"))]
fn adjoint_product<const N: usize>(
    big_lambda: &SMatrix<f64, N, N>,
    p: &SMatrix<f64, N, N>,
    w: &mut SMatrix<f64, N, N>,
    p_w_diagonal: &mut SVector<f64, N>,
) {
    let (big_lambda, p) = (big_lambda.as_slice(), p.as_slice());
    for (j, w_column) in w.as_mut_slice().chunks_exact_mut(N).enumerate() {
        let p_column = &p[j * N..(j + 1) * N];
        let mut column = [0.0; N];
        for (lambda_column, p_kj) in big_lambda.chunks_exact(N).zip(p_column) {
            for (c, lambda_ik) in column.iter_mut().zip(lambda_column) {
                *c += lambda_ik * p_kj;
            }
        }
        p_w_diagonal[j] = column.iter().zip(p_column).map(|(a, b)| a * b).sum();
        w_column.copy_from_slice(&column);
    }
}

/// P ← (I − k h) P (I − k h)ᵀ + k r kᵀ, as the forward update did.
fn replay_scalar<const N: usize>(s: &ScalarStep<N>, p: &mut SMatrix<f64, N, N>) {
    let mut x = SVector::<f64, N>::zeros();
    let m = &s.measurement;
    super::update::scalar_joseph(&mut x, p, &m.h, 0.0, m.variance, f64::INFINITY);
}

/// λ ← (I − k h)ᵀ λ − hᵀ ν / s; Λ ← (I − k h)ᵀ Λ (I − k h) + hᵀ h / s, the
/// latter as Λ − h wᵀ − w hᵀ + (k·w) h hᵀ + hᵀh/s with w = Λ k (h sparse).
fn adjoint_scalar<const N: usize>(
    s: &ScalarStep<N>,
    lambda: &mut SVector<f64, N>,
    big: &mut SMatrix<f64, N, N>,
) {
    let h = s.measurement.h.to_dense::<N>();
    let k = &s.gain;
    let kl = k.dot(lambda);
    *lambda -= h * (kl + s.innovation / s.innovation_variance);
    let w = *big * k;
    let kw = k.dot(&w);
    big.ger(-1.0, &h, &w, 1.0);
    big.ger(-1.0, &w, &h, 1.0);
    big.ger(kw + 1.0 / s.innovation_variance, &h, &h, 1.0);
}

fn replay_reset<const N: usize>(r: &ResetStep, p: &mut SMatrix<f64, N, N>) {
    match *r {
        ResetStep::Block {
            first,
            len,
            covariance,
        } => {
            for i in first..first + len {
                p.row_mut(i).fill(0.0);
                p.column_mut(i).fill(0.0);
            }
            for a in 0..len {
                for b in 0..len {
                    p[(first + a, first + b)] = covariance[a + 3 * b];
                }
            }
        }
        ResetStep::Component {
            first,
            direction,
            variance,
        } => {
            let t = nalgebra::Matrix3::identity() - direction * direction.transpose();
            let rows = t * p.fixed_rows::<3>(first);
            p.fixed_rows_mut::<3>(first).copy_from(&rows);
            let cols = p.fixed_columns::<3>(first) * t;
            p.fixed_columns_mut::<3>(first).copy_from(&cols);
            let block =
                p.fixed_view::<3, 3>(first, first) + variance * direction * direction.transpose();
            p.fixed_view_mut::<3, 3>(first, first).copy_from(&block);
        }
        ResetStep::Inflate {
            states,
            count,
            factor,
        } => {
            let s = factor.max(1.0).sqrt();
            for &i in &states[..count] {
                p.row_mut(i).scale_mut(s);
                p.column_mut(i).scale_mut(s);
            }
        }
        ResetStep::AddVariance { state, variance } => p[(state, state)] += variance,
    }
}

/// λ ← Tᵀ λ, Λ ← Tᵀ Λ T for the reset's map T (the identity for changes
/// of the covariance alone).
fn adjoint_reset<const N: usize>(
    r: &ResetStep,
    lambda: &mut SVector<f64, N>,
    big: &mut SMatrix<f64, N, N>,
) {
    match *r {
        ResetStep::Block { first, len, .. } => {
            for i in first..first + len {
                lambda[i] = 0.0;
                big.row_mut(i).fill(0.0);
                big.column_mut(i).fill(0.0);
            }
        }
        ResetStep::Component {
            first, direction, ..
        } => {
            let t = nalgebra::Matrix3::identity() - direction * direction.transpose();
            let l = t * lambda.fixed_rows::<3>(first);
            lambda.fixed_rows_mut::<3>(first).copy_from(&l);
            let rows = t * big.fixed_rows::<3>(first);
            big.fixed_rows_mut::<3>(first).copy_from(&rows);
            let cols = big.fixed_columns::<3>(first) * t;
            big.fixed_columns_mut::<3>(first).copy_from(&cols);
        }
        ResetStep::Inflate { .. } | ResetStep::AddVariance { .. } => {}
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::filter::SparseRow;
    use nalgebra::{DMatrix, DVector};

    /// A dense linear model x_{k+1} = Φ x_k + w, Q.
    struct Dense<const N: usize> {
        phi: SMatrix<f64, N, N>,
        q: SMatrix<f64, N, N>,
    }

    impl<const N: usize> StepModel<N> for Dense<N> {
        type Step = ();
        fn propagate(&mut self, _: &(), p: &mut SMatrix<f64, N, N>) {
            *p = self.phi * *p * self.phi.transpose() + self.q;
        }
        fn adjoint(&mut self, _: &(), l: &mut SVector<f64, N>, b: &mut SMatrix<f64, N, N>) {
            *l = self.phi.transpose() * *l;
            *b = self.phi.transpose() * *b * self.phi;
        }
    }

    #[test]
    fn adjoint_product_matches_nalgebra() {
        let big = SMatrix::<f64, 17, 17>::from_fn(|i, j| ((i * 7 + j * 3) % 11) as f64 - 5.0);
        let p = SMatrix::<f64, 17, 17>::from_fn(|i, j| ((i * 5 + j * 2) % 13) as f64 * 0.25);
        let p = p + p.transpose();
        let (mut w, mut forms) = (SMatrix::<f64, 17, 17>::zeros(), SVector::<f64, 17>::zeros());
        adjoint_product(&big, &p, &mut w, &mut forms);
        assert!((w - big * p).abs().max() < 1e-12);
        assert!((forms - (p * big * p).diagonal()).abs().max() < 1e-9);
    }

    /// A constant-velocity target observed in position, some epochs
    /// missing: the smoothed states must equal the batch maximum a
    /// posteriori solution of the whole problem (the smoother's closed form
    /// for a linear Gaussian model: minimise the prior, process and
    /// measurement misfits jointly), and its covariance the inverse of that
    /// problem's information matrix.
    #[test]
    fn matches_the_batch_solution_of_a_linear_model() {
        const N: usize = 2;
        let dt = 0.5;
        let phi = SMatrix::<f64, N, N>::new(1.0, dt, 0.0, 1.0);
        let q = SMatrix::<f64, N, N>::new(dt.powi(3) / 3.0, dt * dt / 2.0, dt * dt / 2.0, dt) * 0.1;
        let p0 = SMatrix::<f64, N, N>::new(4.0, 0.0, 0.0, 1.0);
        let r = 0.25;
        let steps = 12;
        let z: Vec<Option<f64>> = (0..=steps)
            .map(|k| (!(5..=8).contains(&k)).then(|| 0.3 * k as f64 + 0.2 * ((k * 7) % 5) as f64))
            .collect();
        // Forward filter, recording.
        let mut log = SmootherLog::new(Dense { phi, q }, 3);
        let (mut x, mut p) = (SVector::<f64, N>::zeros(), p0);
        let mut forward = Vec::new();
        let h = SparseRow::new(&[(0, 1.0)]);
        for (k, zk) in z.iter().enumerate() {
            if k > 0 {
                x = phi * x;
                p = phi * p * phi.transpose() + q;
                log.step(());
            }
            if let Some(zk) = *zk {
                // y = h x + v in the filter's convention: y is the measurement here.
                let hd = h.to_dense::<N>();
                let s = (hd.transpose() * p * hd)[0] + r;
                let gain = p * hd / s;
                let nu = zk - hd.dot(&x);
                log.scalar(ScalarStep {
                    measurement: ScalarMeasurement {
                        h,
                        y: zk,
                        variance: r,
                    },
                    innovation: nu,
                    innovation_variance: s,
                    gain,
                });
                x += gain * nu;
                let ikh = SMatrix::<f64, N, N>::identity() - gain * hd.transpose();
                p = ikh * p * ikh.transpose() + gain * r * gain.transpose();
            }
            log.output(&p);
            forward.push((x, p));
        }
        let mut smoothed = vec![None; steps + 1];
        log.smooth(|s| {
            let full = s.covariance();
            assert!((s.covariance_diagonal() - full.diagonal()).norm() < 1e-12);
            assert!((s.covariance_block::<2>(0) - full).norm() < 1e-12);
            smoothed[s.output] = Some((forward[s.output].0 + s.error, full));
        });
        // Batch: unknowns x_0..x_K (2(K+1)); rows whitened by their covariance.
        let n = N * (steps + 1);
        let mut a = DMatrix::<f64>::zeros(0, n);
        let mut b = DVector::<f64>::zeros(0);
        let mut push = |rows: DMatrix<f64>, rhs: DVector<f64>, cov: DMatrix<f64>| {
            let w = cov.cholesky().unwrap().l().try_inverse().unwrap();
            let (r0, c) = (a.nrows(), a.ncols());
            let rr = rows.nrows();
            a = a.clone().resize_vertically(r0 + rr, 0.0);
            b = b.clone().resize_vertically(r0 + rr, 0.0);
            a.view_mut((r0, 0), (rr, c)).copy_from(&(&w * rows));
            b.rows_mut(r0, rr).copy_from(&(&w * rhs));
        };
        let block = |m: &SMatrix<f64, N, N>| DMatrix::from_column_slice(N, N, m.as_slice());
        let mut prior = DMatrix::<f64>::zeros(N, n);
        prior.view_mut((0, 0), (N, N)).fill_with_identity();
        push(prior, DVector::zeros(N), block(&p0));
        for k in 1..=steps {
            let mut rows = DMatrix::<f64>::zeros(N, n);
            rows.view_mut((0, N * k), (N, N)).fill_with_identity();
            rows.view_mut((0, N * (k - 1)), (N, N))
                .copy_from(&(-block(&phi)));
            push(rows, DVector::zeros(N), block(&q));
        }
        for (k, zk) in z.iter().enumerate() {
            if let Some(zk) = zk {
                let mut rows = DMatrix::<f64>::zeros(1, n);
                rows[(0, N * k)] = 1.0;
                push(
                    rows,
                    DVector::from_element(1, *zk),
                    DMatrix::from_element(1, 1, r),
                );
            }
        }
        let info = a.transpose() * &a;
        let cov = info.clone().try_inverse().unwrap();
        let xb = &cov * (a.transpose() * &b);
        for k in 0..=steps {
            let (xs, ps) = smoothed[k].unwrap();
            for i in 0..N {
                assert!((xs[i] - xb[N * k + i]).abs() < 1e-10, "x {k} {i}");
                for j in 0..N {
                    assert!(
                        (ps[(i, j)] - cov[(N * k + i, N * k + j)]).abs() < 1e-10,
                        "P {k}"
                    );
                }
            }
        }
        // Smoothing never loses information; it gains most in the gap.
        assert!(smoothed[6].unwrap().1[(0, 0)] < 0.5 * forward[6].1[(0, 0)]);
        assert!(smoothed
            .iter()
            .zip(&forward)
            .all(|(s, f)| s.unwrap().1[(0, 0)] <= f.1[(0, 0)] + 1e-12));
    }
}
