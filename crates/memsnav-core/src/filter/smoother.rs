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
//! **Factored adjoint.** Λ is kept as Λ = Rᵀ R with R square (the
//! square-root information form of Λ, as in Bierman's square-root
//! information smoother, 1977 §X): a step is R ← R Φ (one sparse product
//! instead of the two of Φᵀ Λ Φ), a measurement R ← R (I − k h) (rank one)
//! plus a new row h/√s, and the rows a batch of measurements adds are folded
//! back into a square R by a QR factorisation (R ← the triangle of
//! QR([R; rows]), which keeps Rᵀ R).
//!
//! **Carried forward, not replayed.** What smoothing removes from the
//! forward covariance is P⁺ Λ P⁺ = Zᵀ Z with Z = R P⁺, and the smoothed
//! error is −y with y = P⁺ λ. Over a step with no measurement or reset,
//! P⁺′ = Φ P⁺ Φᵀ + Q, R = R′ Φ and λ = Φᵀ λ′ (primes: after the step), so
//!
//! ```text
//! Z′ = R′ P⁺′ = R′ Φ P⁺ Φᵀ + R′ Q = Z Φᵀ + R′ Q,
//! y′ = P⁺′ λ′ = Φ P⁺ Φᵀ λ′ + Q λ′ = Φ y + Q λ′
//! ```
//!
//! (the second is the smoothed error's own dynamics, x̂ˢ′ = Φ x̂ˢ − Q λ′,
//! the smoothed process noise being −Q λ′). Neither needs P⁺ between its
//! starts: the log keeps P⁺ at the first output after any measurement or
//! reset (once per GNSS epoch) and every `checkpoint_every` outputs, and Z
//! and y are formed there densely (R P⁺, P⁺ λ). The caller keeps the
//! entries of P⁺ it wants smoothed (a filter's solution stores them) and
//! subtracts the reduction. Per IMU step the pass costs two sparse products
//! (R′ Φ backward, Z Φᵀ forward) and a few vector products; the
//! unfactored form replays P⁺ (two sparse products), propagates Λ (two)
//! and forms Λ P⁺ densely (N³) at every output (docs/explanation/smoother.md).

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
//! adds, changes no error (T = I) and only enters through P⁺. A position
//! reset to a fix is preceded in the log by the fix's rows as measurements
//! the forward filter did not apply (`ErrorStateKf::record_for_smoother_only`),
//! so what the fix says about the state before the reset flows back.
//!
//! **Memory.** Each segment between two kept covariances is run backward
//! (λ and R, keeping R′ after each step and λ at each output) and then
//! forward from its covariance (Z and y, emitting the outputs). Per IMU
//! step the log holds the propagation's inputs (19 numbers) and an op tag;
//! per applied measurement its row, gain and scalars; per kept covariance
//! N² numbers.

use nalgebra::{DMatrix, SMatrix, SVector, Vector3};

pub use super::measurement::ScalarStep;

/// How one propagation step acts on the adjoints (backward) and on what
/// is carried forward from them: the filter's own structured ECEF model, or
/// any other linear model.
pub trait StepModel<const N: usize> {
    /// What a step needs to rebuild its Φ and Q.
    type Step: Copy;
    /// λ ← Φᵀ λ and, with `factor` = (R′, R), R = R′ Φ from the factor R′
    /// after the step (None: the error estimate alone).
    fn adjoint(
        &mut self,
        step: &Self::Step,
        lambda: &mut SVector<f64, N>,
        factor: Option<Factor<'_, N>>,
    );
    /// Over the step: y ← Φ y + Q λ′, λ′ the adjoint after the step, and
    /// with `root` = (Z, R′, Z′), Z′ = Z Φᵀ + R′ Q (None: the error
    /// estimate alone).
    fn carry(
        &mut self,
        step: &Self::Step,
        root: Option<Root<'_, N>>,
        y: &mut SVector<f64, N>,
        lambda_after: &SVector<f64, N>,
    );
}

/// The factor R′ after a step and where the factor R = R′ Φ before it goes.
pub type Factor<'a, const N: usize> = (&'a SMatrix<f64, N, N>, &'a mut SMatrix<f64, N, N>);

/// The root Z = R P⁺ before a step, the factor R′ after it, and where Z′
/// goes.
pub type Root<'a, const N: usize> = (
    &'a SMatrix<f64, N, N>,
    &'a SMatrix<f64, N, N>,
    &'a mut SMatrix<f64, N, N>,
);

/// A change of the error state and its covariance other than propagation
/// and measurement.
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum ResetStep {
    /// States `first..first + len` (len ≤ 3) replaced by new values of
    /// covariance `covariance` (column-major, len × len).
    Block {
        /// The first state replaced.
        first: usize,
        /// How many states, at most 3.
        len: usize,
        /// Their new covariance, column-major, `len` × `len`.
        covariance: [f64; 9],
    },
    /// The component along `direction` of the three states at `first`
    /// replaced by a new value of variance `variance`.
    Component {
        /// The first of the three states.
        first: usize,
        /// The unit direction whose component is replaced.
        direction: Vector3<f64>,
        /// The new component's variance.
        variance: f64,
    },
    /// The whole covariance multiplied by `factor` (fading memory).
    Fade {
        /// The factor, at least 1 (`FilterState::fade`).
        factor: f64,
    },
    /// Variances of `states[..count]` multiplied by `factor`.
    Inflate {
        /// The states, the first `count` of them used.
        states: [usize; 8],
        /// How many of `states` are inflated.
        count: usize,
        /// The factor their variances are multiplied by.
        factor: f64,
    },
    /// `variance` added to state `state`'s variance.
    AddVariance {
        /// The state.
        state: usize,
        /// The variance added.
        variance: f64,
    },
    /// States `target..target + 3` moved by `matrix` times states
    /// `source..source + 3` (a change of variables, nothing new).
    Shear {
        /// The first of the three states moved.
        target: usize,
        /// The first of the three states they move with.
        source: usize,
        /// The 3 × 3 coupling.
        matrix: nalgebra::Matrix3<f64>,
    },
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
    /// (index into `ops` of an output, P⁺ at that output): at the first
    /// output after a measurement or a reset, and every `checkpoint_every`.
    checkpoints: Vec<(usize, SMatrix<f64, N, N>)>,
    checkpoint_every: usize,
    outputs: usize,
    /// Outputs since the last kept covariance.
    since_checkpoint: usize,
    /// A measurement or reset since the last output.
    changed: bool,
}

/// A smoothed output: the error-state estimate and, on demand, entries of
/// what smoothing removes from the forward covariance,
/// P⁺ − Pˢ = P⁺ Λ P⁺ = Zᵀ Z (Z = R P⁺, Λ = Rᵀ R): an entry is zᵢ · zⱼ over two
/// columns of Z (the diagonal, every caller's, formed once per output).
#[derive(Debug, Clone, Copy)]
pub struct Smoothed<'a, const N: usize> {
    /// Output index (the order in which outputs were recorded).
    pub output: usize,
    /// Smoothed error estimate x̂ˢ (estimate − truth of the forward nominal).
    pub error: SVector<f64, N>,
    root: &'a SMatrix<f64, N, N>,
    /// diag(Zᵀ Z).
    reduction_diagonal: SVector<f64, N>,
}

impl<const N: usize> Smoothed<'_, N> {
    /// (P⁺ Λ P⁺)ᵢⱼ = zᵢ · zⱼ, columns of Z (contiguous).
    pub fn reduction_entry(&self, i: usize, j: usize) -> f64 {
        if i == j {
            return self.reduction_diagonal[i];
        }
        let column = |k: usize| -> &[f64; N] {
            self.root.as_slice()[k * N..(k + 1) * N]
                .try_into()
                .expect("a column has N rows")
        };
        dot::<N, false>(column(i), column(j))
    }

    /// diag(P⁺ Λ P⁺): Pˢ's diagonal is P⁺'s minus this.
    pub fn reduction_diagonal(&self) -> SVector<f64, N> {
        self.reduction_diagonal
    }

    /// The R×R diagonal block of P⁺ Λ P⁺ at states `first..first + R` (each
    /// entry computed once, the lower triangle mirrored).
    pub fn reduction_block<const R: usize>(&self, first: usize) -> SMatrix<f64, R, R> {
        let mut block = SMatrix::<f64, R, R>::zeros();
        for b in 0..R {
            for a in 0..=b {
                let v = self.reduction_entry(first + a, first + b);
                block[(a, b)] = v;
                block[(b, a)] = v;
            }
        }
        block
    }

    /// The whole P⁺ Λ P⁺.
    pub fn reduction(&self) -> SMatrix<f64, N, N> {
        self.root.transpose() * self.root
    }
}

impl<const N: usize, M: StepModel<N>> SmootherLog<N, M> {
    /// An empty log for `model`, a full P kept every `checkpoint_every`
    /// outputs (at least 1) and after every measurement or reset.
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
            since_checkpoint: 0,
            changed: false,
        }
    }

    /// Room for `outputs` more outputs, a step each, without regrowing
    /// (measurements and resets are not known in advance).
    pub fn reserve(&mut self, outputs: usize) {
        self.ops.reserve(2 * outputs);
        self.steps.reserve(outputs);
        self.checkpoints
            .reserve(outputs.div_ceil(self.checkpoint_every));
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
        self.changed = true;
    }

    /// Records a reset.
    pub fn reset(&mut self, r: ResetStep) {
        self.ops.push(Op::Reset(self.resets.len() as u32));
        self.resets.push(r);
        self.changed = true;
    }

    /// Records an output sample with the filter's covariance there.
    pub fn output(&mut self, p: &SMatrix<f64, N, N>) {
        if self.outputs == 0 || self.changed || self.since_checkpoint == self.checkpoint_every {
            self.checkpoints.push((self.ops.len(), *p));
            self.since_checkpoint = 0;
        }
        self.ops.push(Op::Output);
        self.outputs += 1;
        self.since_checkpoint += 1;
        self.changed = false;
    }

    /// Number of outputs recorded.
    pub fn outputs(&self) -> usize {
        self.outputs
    }

    /// The smoother: calls `emit` for every output with its smoothed error
    /// estimate and covariance, segment by segment from the last (outputs
    /// in recorded order within a segment).
    pub fn smooth(&mut self, mut emit: impl FnMut(&Smoothed<'_, N>)) {
        self.pass(true, |output, error, root| {
            let root = root.expect("the covariance pass carries Z");
            emit(&Smoothed {
                output,
                error,
                root,
                reduction_diagonal: column_norms(root),
            })
        });
    }

    /// The smoothed error estimates alone, in the order of
    /// [`Self::smooth`] and equal to its bit for bit: `emit(output,
    /// error)`. The pass carries λ and y only, neither the factor R nor
    /// Z, so each step costs a sparse matrix-vector product instead of
    /// two sparse matrix products.
    pub fn smooth_errors(&mut self, mut emit: impl FnMut(usize, &SVector<f64, N>)) {
        self.pass(false, |output, error, _| emit(output, &error));
    }

    /// The backward and forward passes (module docs), with the covariance's
    /// factor and root when `covariance`: `emit(output, error, Z)`.
    fn pass(
        &mut self,
        covariance: bool,
        mut emit: impl FnMut(usize, SVector<f64, N>, Option<&SMatrix<f64, N, N>>),
    ) {
        let mut lambda = SVector::<f64, N>::zeros();
        let (mut roots, mut current) = ([SMatrix::<f64, N, N>::zeros(); 2], 0);
        let mut rows: Vec<SVector<f64, N>> = Vec::new();
        // Per segment: λ at each output (last first), and the chain of
        // factors: R′ after each step, each step's R = R′ Φ written into the
        // next slot (no copies), `factor` the slot of the current R. An
        // output not preceded by a step keeps the current slot and the pass
        // goes on with a copy. Slots are reused from segment to segment.
        let mut lambdas: Vec<SVector<f64, N>> = Vec::with_capacity(self.checkpoint_every);
        let mut factors: Vec<SMatrix<f64, N, N>> = vec![SMatrix::zeros()];
        let mut factor = 0;
        let mut factor_of_op: Vec<u32> = Vec::new();
        let mut output = self.outputs;
        let mut end = self.ops.len();
        for c in (0..self.checkpoints.len()).rev() {
            let (start, p0) = self.checkpoints[c];
            let ops = &self.ops[start..end];
            // Backward through the segment: the adjoints.
            lambdas.clear();
            if factor != 0 {
                let (head, tail) = factors.split_at_mut(factor);
                head[0].copy_from(&tail[0]);
                factor = 0;
            }
            factor_of_op.clear();
            factor_of_op.resize(ops.len(), u32::MAX);
            for (i, op) in ops.iter().enumerate().rev() {
                if covariance && !matches!(op, Op::Scalar(_)) {
                    fold_rows(&mut factors[factor], &mut rows);
                }
                match *op {
                    Op::Output => {
                        lambdas.push(lambda);
                        if covariance && (i == 0 || !matches!(ops[i - 1], Op::Step(_))) {
                            factor_of_op[i] = factor as u32;
                            if i > 0 {
                                let next = next_slot(&mut factors, factor);
                                let (head, tail) = factors.split_at_mut(next);
                                tail[0].copy_from(&head[factor]);
                                factor = next;
                            }
                        }
                    }
                    Op::Step(s) if covariance => {
                        factor_of_op[i] = factor as u32;
                        let next = next_slot(&mut factors, factor);
                        let (head, tail) = factors.split_at_mut(next);
                        self.model.adjoint(
                            &self.steps[s as usize],
                            &mut lambda,
                            Some((&head[factor], &mut tail[0])),
                        );
                        factor = next;
                    }
                    Op::Step(s) => self
                        .model
                        .adjoint(&self.steps[s as usize], &mut lambda, None),
                    Op::Scalar(s) => adjoint_scalar(
                        &self.scalars[s as usize],
                        &mut lambda,
                        covariance.then_some((&mut factors[factor], &mut rows)),
                    ),
                    Op::Reset(r) => adjoint_reset(
                        &self.resets[r as usize],
                        &mut lambda,
                        covariance.then_some(&mut factors[factor]),
                    ),
                }
            }
            // Forward through the segment from its kept covariance: Z and y
            // (Z in one of two buffers, each step writing the other). The
            // segment's measurements and resets, if any, come after its last
            // output: the next segment starts from the covariance after them.
            let first_output = output - lambdas.len();
            let lambda_at = |k: usize| &lambdas[lambdas.len() - 1 - (k - first_output)];
            let mut y = p0 * lambda_at(first_output);
            if covariance {
                roots[current] = factors[factor_of_op[0] as usize] * p0;
            }
            let mut k = first_output;
            for (i, op) in ops.iter().enumerate() {
                match *op {
                    Op::Step(s) if k < output && covariance => {
                        let after = &factors[factor_of_op[i] as usize];
                        let (first, second) = roots.split_at_mut(1);
                        let (z, next) = match current {
                            0 => (&first[0], &mut second[0]),
                            _ => (&second[0], &mut first[0]),
                        };
                        self.model.carry(
                            &self.steps[s as usize],
                            Some((z, after, next)),
                            &mut y,
                            lambda_at(k),
                        );
                        current = 1 - current;
                    }
                    Op::Step(s) if k < output => {
                        self.model
                            .carry(&self.steps[s as usize], None, &mut y, lambda_at(k));
                    }
                    Op::Output => {
                        emit(k, -y, covariance.then_some(&roots[current]));
                        k += 1;
                    }
                    _ => {}
                }
            }
            debug_assert_eq!(k, output, "every output of the segment emitted");
            output = first_output;
            end = start;
        }
    }
}

/// a · b in four independent partial sums (vectorised; a single running sum
/// would be one dependent chain of N additions); `FMA`: fused multiply-adds.
#[inline(always)]
fn dot<const N: usize, const FMA: bool>(a: &[f64; N], b: &[f64; N]) -> f64 {
    let mut lanes = [0.0; 4];
    let whole = N - N % 4;
    for i in (0..whole).step_by(4) {
        for l in 0..4 {
            lanes[l] = if FMA {
                a[i + l].mul_add(b[i + l], lanes[l])
            } else {
                lanes[l] + a[i + l] * b[i + l]
            };
        }
    }
    let tail: f64 = (whole..N).map(|i| a[i] * b[i]).sum();
    (lanes[0] + lanes[1]) + (lanes[2] + lanes[3]) + tail
}

/// diag(Zᵀ Z), the squared norms of the columns of Z: at every output, so
/// also compiled for AVX2 with FMA and chosen at run time.
#[multiversion::multiversion(targets("x86_64+avx2+fma"))]
fn column_norms<const N: usize>(z: &SMatrix<f64, N, N>) -> SVector<f64, N> {
    const FMA: bool = multiversion::target::selected_target!().supports_feature_str("fma");
    let mut norms = SVector::<f64, N>::zeros();
    for (norm, column) in norms.iter_mut().zip(z.as_slice().chunks_exact(N)) {
        let column: &[f64; N] = column.try_into().expect("a column has N rows");
        *norm = dot::<N, FMA>(column, column);
    }
    norms
}

/// The slot after `factor` in the chain, added when the chain is longer
/// than any before.
fn next_slot<const N: usize>(factors: &mut Vec<SMatrix<f64, N, N>>, factor: usize) -> usize {
    if factor + 1 == factors.len() {
        factors.push(SMatrix::zeros());
    }
    factor + 1
}

/// R ← the upper triangle of QR([R; rows]), and no rows left: the same
/// Λ = Rᵀ R + Σ rowᵀ row (QᵀQ = I), in a square factor again. Once per
/// batch of measurements (a GNSS epoch), so the stacked matrix is allocated
/// here rather than kept.
fn fold_rows<const N: usize>(factor: &mut SMatrix<f64, N, N>, rows: &mut Vec<SVector<f64, N>>) {
    if rows.is_empty() {
        return;
    }
    let stacked = DMatrix::from_fn(N + rows.len(), N, |i, j| {
        if i < N {
            factor[(i, j)]
        } else {
            rows[i - N][j]
        }
    });
    factor.copy_from(&stacked.qr().r());
    rows.clear();
}

/// λ ← (I − k h)ᵀ λ − hᵀ ν / s; Λ ← (I − k h)ᵀ Λ (I − k h) + hᵀ h / s as
/// R ← R (I − k h) = R − (R k) h and the pending rows alike, plus the new
/// row h/√s (folded into R by [`fold_rows`] at the end of the batch).
fn adjoint_scalar<const N: usize>(
    s: &ScalarStep<N>,
    lambda: &mut SVector<f64, N>,
    factor: Option<(&mut SMatrix<f64, N, N>, &mut Vec<SVector<f64, N>>)>,
) {
    let h = s.measurement.h.to_dense::<N>();
    let k = &s.gain;
    let kl = k.dot(lambda);
    *lambda -= h * (kl + s.innovation / s.innovation_variance);
    let Some((factor, rows)) = factor else {
        return;
    };
    let rk = *factor * k;
    super::add_outer(factor, -1.0, &rk, &h);
    for row in rows.iter_mut() {
        let a = row.dot(k);
        row.axpy(-a, &h, 1.0);
    }
    rows.push(h / s.innovation_variance.sqrt());
}

/// λ ← Tᵀ λ, Λ ← Tᵀ Λ T (R ← R T, with the `factor`) for the reset's map
/// T (the identity for changes of the covariance alone).
fn adjoint_reset<const N: usize>(
    r: &ResetStep,
    lambda: &mut SVector<f64, N>,
    mut factor: Option<&mut SMatrix<f64, N, N>>,
) {
    match *r {
        ResetStep::Block { first, len, .. } => {
            for i in first..first + len {
                lambda[i] = 0.0;
                if let Some(f) = factor.as_deref_mut() {
                    f.column_mut(i).fill(0.0);
                }
            }
        }
        ResetStep::Component {
            first, direction, ..
        } => {
            let t = nalgebra::Matrix3::identity() - direction * direction.transpose();
            let l = t * lambda.fixed_rows::<3>(first);
            lambda.fixed_rows_mut::<3>(first).copy_from(&l);
            if let Some(f) = factor {
                let cols = f.fixed_columns::<3>(first) * t;
                f.fixed_columns_mut::<3>(first).copy_from(&cols);
            }
        }
        ResetStep::Shear {
            target,
            source,
            matrix,
        } => {
            // Tᵀ λ: the source's multiplier gains mᵀ times the target's;
            // R T: the source's columns gain the target's times m.
            let l = matrix.transpose() * lambda.fixed_rows::<3>(target);
            let mut ls = lambda.fixed_rows_mut::<3>(source);
            ls += l;
            if let Some(f) = factor {
                let cols = f.fixed_columns::<3>(target) * matrix;
                let mut fs = f.fixed_columns_mut::<3>(source);
                fs += cols;
            }
        }
        ResetStep::Inflate { .. } | ResetStep::Fade { .. } | ResetStep::AddVariance { .. } => {}
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::filter::{ScalarMeasurement, SparseRow};
    use nalgebra::{DMatrix, DVector};

    /// A dense linear model x_{k+1} = Φ x_k + w, Q.
    struct Dense<const N: usize> {
        phi: SMatrix<f64, N, N>,
        q: SMatrix<f64, N, N>,
    }

    impl<const N: usize> StepModel<N> for Dense<N> {
        type Step = ();
        fn adjoint(&mut self, _: &(), l: &mut SVector<f64, N>, factor: Option<Factor<'_, N>>) {
            *l = self.phi.transpose() * *l;
            if let Some((after, r)) = factor {
                *r = after * self.phi;
            }
        }
        fn carry(
            &mut self,
            _: &(),
            root: Option<Root<'_, N>>,
            y: &mut SVector<f64, N>,
            lambda_after: &SVector<f64, N>,
        ) {
            if let Some((z, r, next)) = root {
                *next = z * self.phi.transpose() + r * self.q;
            }
            *y = self.phi * *y + self.q * lambda_after;
        }
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
            let reduction = s.reduction();
            assert!((s.reduction_diagonal() - reduction.diagonal()).norm() < 1e-12);
            assert!((s.reduction_block::<2>(0) - reduction).norm() < 1e-12);
            let (x, p) = forward[s.output];
            smoothed[s.output] = Some((x + s.error, p - reduction));
        });
        // The estimates alone are the same, bit for bit.
        let mut outputs = 0;
        log.smooth_errors(|k, error| {
            let (x, _) = forward[k];
            assert_eq!(smoothed[k].unwrap().0, x + error);
            outputs += 1;
        });
        assert_eq!(outputs, steps + 1);
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

    /// A change of variables x ← T x in the middle of a run (a shear, T =
    /// I + E) changes nothing the smoother knows: the same problem run
    /// without it, with the later measurement rows written in the old
    /// variables (h T), smooths to the same states, T times them after it,
    /// and the same covariances, T P Tᵀ after it.
    #[test]
    fn a_shear_carries_the_information_through() {
        const N: usize = 6;
        // Constant states: with process noise the two problems would differ
        // after the shear (Q in the new variables is T Q Tᵀ in the old).
        let phi = SMatrix::<f64, N, N>::identity();
        let q = SMatrix::<f64, N, N>::zeros();
        let p0 = SMatrix::<f64, N, N>::identity() * 4.0;
        let m = nalgebra::Matrix3::new(0.2, -0.5, 0.1, 0.4, 0.0, -0.3, 0.1, 0.2, 0.6);
        let mut t = SMatrix::<f64, N, N>::identity();
        t.fixed_view_mut::<3, 3>(0, 3).copy_from(&m);
        let (steps, shear_at) = (10, 4);
        // Row k of the problem in the variables before the shear.
        let row = |k: usize| {
            SMatrix::<f64, 1, N>::from_fn(|_, j| (((k * 7 + j * 3) % 5) as f64 - 2.0) * 0.5)
        };
        let run = |sheared: bool| {
            let mut log = SmootherLog::new(Dense { phi, q }, 3);
            let (mut x, mut p) = (SVector::<f64, N>::zeros(), p0);
            let mut forward = Vec::new();
            for k in 0..=steps {
                if k > 0 {
                    p = phi * p * phi.transpose() + q;
                    log.step(());
                }
                if sheared && k == shear_at {
                    x = t * x;
                    p = t * p * t.transpose();
                    log.reset(ResetStep::Shear {
                        target: 0,
                        source: 3,
                        matrix: m,
                    });
                }
                // The same physical measurement: in the new variables its
                // row is h T⁻¹.
                let h_old = row(k);
                let h = if sheared && k >= shear_at {
                    h_old * t.try_inverse().unwrap()
                } else {
                    h_old
                };
                let entries: Vec<(usize, f64)> = (0..N).map(|j| (j, h[j])).collect();
                let hs = SparseRow::new(&entries);
                let z = 0.3 * k as f64 - 1.0;
                let hd = h.transpose();
                let sv = (h * p * hd)[0] + 0.5;
                let gain = p * hd / sv;
                let nu = z - (h * x)[0];
                log.scalar(ScalarStep {
                    measurement: ScalarMeasurement {
                        h: hs,
                        y: z,
                        variance: 0.5,
                    },
                    innovation: nu,
                    innovation_variance: sv,
                    gain,
                });
                x += gain * nu;
                let ikh = SMatrix::<f64, N, N>::identity() - gain * h;
                p = ikh * p * ikh.transpose() + gain * 0.5 * gain.transpose();
                log.output(&p);
                forward.push((x, p));
            }
            let mut smoothed = vec![None; steps + 1];
            log.smooth(|s| {
                let (x, p) = forward[s.output];
                smoothed[s.output] = Some((x + s.error, p - s.reduction()));
            });
            // The estimates alone, through the shear too, bit for bit.
            log.smooth_errors(|k, error| {
                assert_eq!(smoothed[k].unwrap().0, forward[k].0 + error);
            });
            smoothed
        };
        let (plain, sheared) = (run(false), run(true));
        for k in 0..=steps {
            let (xa, pa) = plain[k].unwrap();
            let (xb, pb) = sheared[k].unwrap();
            let (xa, pa) = if k >= shear_at {
                (t * xa, t * pa * t.transpose())
            } else {
                (xa, pa)
            };
            assert!((xa - xb).norm() < 1e-9, "x {k}: {xa} {xb}");
            assert!((pa - pb).norm() < 1e-9, "P {k}");
        }
    }
}
