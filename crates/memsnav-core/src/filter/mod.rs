//! Shared pieces of the GNSS/INS error-state Kalman filters (method §5):
//! named state indices, the ECEF error-state system model and its
//! structured covariance propagation, the sequential scalar Joseph-form
//! update with chi-square gating, NIS/NEES and divergence checks.
//!
//! ## Error-state convention
//!
//! Every error is *estimate minus truth*: δv = v̂ − v, δr = r̂ − r, δb = b̂ − b,
//! δc = ĉ − c, and the attitude error ψ is the small rotation with
//! Ĉ_b^e = (I + [ψ×]) C_b^e (Groves eq. 5.109 / 14.5, closed-loop form). The
//! IMU error model the filter assumes is f̃ = f + b_a + w_a and
//! ω̃ = ω + b_g + w_g; with scale-factor states also f̃ = (I + diag(s_a)) f + …
//! (see [`state`]). A correction is therefore *subtracted* when fed back
//! ([`ErrorState`] carries the convention in one place).
//!
//! ## Sizes
//!
//! The filters are generic over the state size `N`: [`state::BASE_STATES`]
//! (17: attitude, velocity, position, accelerometer bias, gyro bias, clock
//! offset and drift), [`state::WITH_SCALE_FACTORS`] (23: plus accelerometer
//! and gyro scale-factor errors), each with optional installation,
//! inter-system-bias and per-satellite pseudorange-bias blocks (12 shared
//! slots or 40, [`state::RangeBiasSlots`]); [`state::Layout`] says which
//! blocks a size has, and [`state::StateBlocks::dispatch`] picks the size
//! for the blocks a run chose. Everything is fixed-size nalgebra, so no
//! per-epoch allocation happens.
//!
//! ## Measurements in batches
//!
//! The measurements of one epoch (a fix, a satellite set, a zero-velocity
//! update) are tested together: they are applied one by one to a copy of
//! the filter, and the sum of their NIS — the batch νᵀ S⁻¹ ν — is compared
//! with a chi-square quantile of as many degrees of freedom; the copy is
//! kept only when the batch passes ([`ErrorStateKf::update_batch`]). A fix
//! is never half accepted.

pub use crate::chi_square;
pub mod input_noise;
mod measurement;
mod propagation;
mod reset;
pub mod smoother;
pub mod state;
mod update;

pub use measurement::{ScalarMeasurement, SparseRow, MAX_ROW_ENTRIES};
pub use propagation::{system_matrix, InsStepModel, ProcessNoise, SystemInputs};
pub use state::{ErrorState, Layout, StateLayout};
pub use update::{BatchOutcome, ScalarOutcome};

use nalgebra::SMatrix;

use crate::{Error, Result};

/// The state and covariance of an error-state filter of size `N`, with the
/// pieces every filter shares: propagation, scalar update, health checks.
#[derive(Debug, Clone)]
pub struct ErrorStateKf<const N: usize> {
    /// The error-state estimate (zero after each closed-loop feedback).
    pub x: ErrorState<N>,
    /// Its covariance, symmetric positive definite.
    pub p: SMatrix<f64, N, N>,
    /// Epochs propagated since the last Cholesky check.
    since_check: usize,
    /// The last interval's Δt-dependent constants (reused at a fixed rate).
    discretisation: Option<propagation::Discretisation>,
    /// Working storage of the propagation (nothing zeroed per epoch).
    scratch: Box<propagation::Scratch<N>>,
    /// What the filter did to P, for a smoother (when one was asked for).
    smoother: Option<Box<Recorder<N>>>,
}

/// The smoother's log of a filter and the scratch list of a batch's gains.
#[derive(Debug, Clone)]
struct Recorder<const N: usize> {
    log: smoother::SmootherLog<N, InsStepModel>,
    gains: Vec<smoother::ScalarStep<N>>,
}

/// Most outputs between two full covariances the smoother's log keeps (2 s
/// of a 100 Hz IMU: 2.3 kB each for 17 states; it also keeps one after each
/// measurement batch or reset).
pub const SMOOTHER_CHECKPOINT_EVERY: usize = 200;

/// Propagation epochs between two full (Cholesky) positive-definiteness
/// checks; the cheap diagonal check runs every epoch.
pub const CHOLESKY_CHECK_INTERVAL: usize = 1000;

impl<const N: usize> ErrorStateKf<N> {
    /// A filter with zero error state and covariance `p0` (checked for
    /// finiteness, symmetry and positive definiteness).
    pub fn new(p0: SMatrix<f64, N, N>) -> Result<Self> {
        const { Layout::for_size::<N>() };
        if !p0.iter().all(|v| v.is_finite()) {
            return Err(Error::invalid(
                "initial_covariance",
                "contains NaN or infinite values",
            ));
        }
        if (p0 - p0.transpose()).abs().max() > 1e-9 * p0.abs().max() {
            return Err(Error::invalid("initial_covariance", "is not symmetric"));
        }
        if p0.cholesky().is_none() {
            return Err(Error::invalid(
                "initial_covariance",
                "is not positive definite",
            ));
        }
        Ok(Self {
            x: ErrorState::zero(),
            p: p0,
            since_check: 0,
            discretisation: None,
            scratch: Box::new(propagation::Scratch::new()),
            smoother: None,
        })
    }

    /// Starts recording what the filter does to P, for [`Self::take_smoother`],
    /// with room for `samples` output samples (the log grows past them).
    pub fn record_for_smoother(&mut self, noise: &ProcessNoise, samples: usize) {
        let mut log =
            smoother::SmootherLog::new(InsStepModel::new(*noise), SMOOTHER_CHECKPOINT_EVERY);
        log.reserve(samples);
        self.smoother = Some(Box::new(Recorder {
            log,
            gains: Vec::new(),
        }));
    }

    /// Marks an output sample of the filter's solution (for the smoother).
    pub fn mark_output(&mut self) {
        if let Some(r) = self.smoother.as_mut() {
            r.log.output(&self.p);
        }
    }

    /// The smoother's log recorded since [`Self::record_for_smoother`].
    pub fn take_smoother(&mut self) -> Option<smoother::SmootherLog<N, InsStepModel>> {
        self.smoother.take().map(|r| r.log)
    }

    fn record_reset(&mut self, step: smoother::ResetStep) {
        if let Some(r) = self.smoother.as_mut() {
            r.log.reset(step);
        }
    }

    /// Adds `variance` to state `state`'s variance (a clock jump estimated
    /// from one epoch).
    pub fn add_variance(&mut self, state: usize, variance: f64) {
        self.p[(state, state)] += variance;
        self.record_reset(smoother::ResetStep::AddVariance { state, variance });
    }

    /// Propagates P over one IMU interval (and x, which is normally zero in
    /// closed loop): P ← Φ P Φᵀ + Q with Φ = I + F Δt applied block-wise
    /// (see [`propagation`](self::system_matrix)). Cheap health check each
    /// epoch; a Cholesky factorisation every [`CHOLESKY_CHECK_INTERVAL`].
    pub fn propagate(
        &mut self,
        inputs: &SystemInputs,
        noise: &ProcessNoise,
        dt: f64,
        time_s: f64,
    ) -> Result<()> {
        let d = match self.discretisation {
            Some(d) if d.is_for(noise, dt) => d,
            _ => {
                let d = propagation::Discretisation::new(noise, dt);
                self.discretisation = Some(d);
                d
            }
        };
        propagation::propagate_with(&mut self.x.0, &mut self.p, inputs, &d, &mut self.scratch);
        if let Some(r) = self.smoother.as_mut() {
            r.log.step((*inputs, dt));
        }
        self.since_check += 1;
        if self.since_check >= CHOLESKY_CHECK_INTERVAL {
            self.check_health(time_s)?;
        } else {
            self.check_diagonal(time_s)?;
        }
        Ok(())
    }

    /// One scalar measurement y = h·x + v, var(v) = `variance`, where `y` is
    /// prediction minus measurement (the convention of [`ErrorState`]).
    /// Gated: rejected when its NIS exceeds `gate` (a chi-square(1)
    /// quantile; `f64::INFINITY` disables the gate). A non-finite `y` is
    /// rejected, never applied. Joseph form, rank one.
    pub fn update_scalar(
        &mut self,
        h: &SparseRow,
        y: f64,
        variance: f64,
        gate: f64,
    ) -> ScalarOutcome {
        update::scalar_joseph(&mut self.x.0, &mut self.p, h, y, variance, gate)
    }

    /// Tests `measurements` (those with `active[i]`) as one batch: applies
    /// them sequentially, ungated, to a copy of the filter and keeps the
    /// copy when the batch NIS (see `update::sequential`'s note) is at
    /// most `threshold` (a chi-square quantile for as many degrees of
    /// freedom as active measurements; `f64::INFINITY` accepts any finite
    /// batch). Each measurement's outcome is written to `outcomes`, its
    /// `accepted` flag saying whether it was applied.
    pub fn update_batch(
        &mut self,
        measurements: &[ScalarMeasurement],
        active: &[bool],
        threshold: f64,
        outcomes: &mut [ScalarOutcome],
    ) -> BatchOutcome {
        let (mut x, mut p) = (self.x.0, self.p);
        let mut recorder = self.smoother.as_mut();
        let gains = recorder.as_mut().map(|r| {
            r.gains.clear();
            &mut r.gains
        });
        let nis = update::sequential(&mut x, &mut p, measurements, active, outcomes, gains);
        let dof = active.iter().filter(|a| **a).count();
        let accepted = dof > 0 && nis.is_finite() && nis <= threshold;
        if accepted {
            (self.x.0, self.p) = (x, p);
            if let Some(r) = recorder {
                for g in r.gains.drain(..) {
                    r.log.scalar(g);
                }
            }
        }
        for (o, &on) in outcomes.iter_mut().zip(active) {
            o.accepted = accepted && on;
        }
        BatchOutcome { nis, dof, accepted }
    }

    /// Records `measurements` for the smoother as though they had been
    /// applied here, leaving the filter as it is: the fix a reset is about
    /// to replace a block of states by. A reset alone cuts the adjoint's
    /// path through that block (its new value is independent of the past),
    /// so the smoother could not carry what the fix says back into the
    /// span before it (an outage that drifted far enough to need a reset
    /// kept its whole drift when smoothed); recorded before the reset, the
    /// fix is also a measurement of the state the reset replaces, and the
    /// backward pass spreads its innovation over that span by the forward
    /// covariance, as it does for an accepted fix. Nothing without a
    /// smoother.
    pub fn record_for_smoother_only(&mut self, measurements: &[ScalarMeasurement]) {
        let Some(r) = self.smoother.as_mut() else {
            return;
        };
        let (mut x, mut p) = (self.x.0, self.p);
        let active = vec![true; measurements.len()];
        let mut outcomes = vec![ScalarOutcome::default(); measurements.len()];
        r.gains.clear();
        update::sequential(
            &mut x,
            &mut p,
            measurements,
            &active,
            &mut outcomes,
            Some(&mut r.gains),
        );
        for g in r.gains.drain(..) {
            if g.innovation.is_finite() && g.innovation_variance > 0.0 {
                r.log.scalar(g);
            }
        }
    }

    /// The innovation y − h x of `m` against the current state and its
    /// predicted variance h P hᵀ + r (before any update).
    pub fn innovation(&self, m: &ScalarMeasurement) -> (f64, f64) {
        let u = m.h.times(&self.p);
        (m.y - m.h.dot(&self.x.0), m.h.dot(&u) + m.variance)
    }

    /// The full check: finite state, finite positive diagonal and a Cholesky
    /// factorisation of P; symmetrises P on the way.
    pub fn check_health(&mut self, time_s: f64) -> Result<()> {
        self.since_check = 0;
        self.p = (self.p + self.p.transpose()) * 0.5;
        self.check_diagonal(time_s)?;
        if self.p.cholesky().is_none() {
            return Err(Error::Divergence {
                time_s,
                reason: "state covariance is no longer positive definite".into(),
            });
        }
        Ok(())
    }

    fn check_diagonal(&self, time_s: f64) -> Result<()> {
        // The common case in one branch-free sweep; the slow search below
        // only names the culprit.
        // (|v| ≤ MAX is false for NaN and ±∞; P and x read through their
        // fixed-size arrays, so without index checks.)
        let (columns, x) = (&self.p.data.0, &self.x.0.data.0[0]);
        let mut healthy = true;
        for i in 0..N {
            let v = columns[i][i];
            healthy &= (x[i].abs() <= f64::MAX) & (v > 0.0) & (v <= f64::MAX);
        }
        if healthy {
            return Ok(());
        }
        if let Some(i) = (0..N).find(|&i| !self.x.0[i].is_finite()) {
            return Err(Error::Divergence {
                time_s,
                reason: format!("error state {} is not finite", StateLayout::name_in(N, i)),
            });
        }
        if let Some(i) = (0..N).find(|&i| !(self.p[(i, i)] > 0.0 && self.p[(i, i)].is_finite())) {
            return Err(Error::Divergence {
                time_s,
                reason: format!(
                    "variance of {} is {} (not finite and positive)",
                    StateLayout::name_in(N, i),
                    self.p[(i, i)]
                ),
            });
        }
        Ok(())
    }
}

/// M ← M + α x yᵀ, column by column over contiguous slices: the loops
/// vectorise where nalgebra's `ger` (a strided axpy per column) does not.
/// Each entry gets the same sum, (α yⱼ) xᵢ + Mᵢⱼ, so results are bitwise
/// those of `ger(α, x, y, 1)`.
pub(crate) fn add_outer<const N: usize>(
    m: &mut SMatrix<f64, N, N>,
    alpha: f64,
    x: &nalgebra::SVector<f64, N>,
    y: &nalgebra::SVector<f64, N>,
) {
    for (column, &yj) in m.as_mut_slice().chunks_exact_mut(N).zip(y.iter()) {
        let a = alpha * yj;
        for (t, &xi) in column.iter_mut().zip(x.iter()) {
            *t += a * xi;
        }
    }
}

/// Normalised estimation error squared eᵀ P⁻¹ e (Bar-Shalom et al. 2001,
/// §5.4.2) of an error `e` with covariance `p`; `None` when `p` is not
/// positive definite. Its expectation is the dimension `K` for a consistent
/// filter.
pub fn nees<const K: usize>(e: &nalgebra::SVector<f64, K>, p: &SMatrix<f64, K, K>) -> Option<f64> {
    let chol = p.cholesky()?;
    let z = chol.l().solve_lower_triangular(e)?;
    Some(z.norm_squared())
}

#[cfg(test)]
mod tests {
    use super::*;
    use nalgebra::{SVector, Vector3};

    #[test]
    fn nees_matches_the_explicit_inverse() {
        let a = SMatrix::<f64, 3, 3>::new(2.0, 0.3, 0.1, 0.3, 1.0, -0.2, 0.1, -0.2, 0.5);
        let e = Vector3::new(0.4, -1.0, 0.7);
        let explicit = (e.transpose() * a.try_inverse().unwrap() * e)[0];
        assert!((nees(&e, &a).unwrap() - explicit).abs() < 1e-12);
        assert!(nees(&e, &(-a)).is_none());
    }

    /// The Δt-dependent constants are cached: a change of Δt or of the
    /// noise settings between epochs must give what a fresh filter gives.
    #[test]
    fn a_change_of_interval_or_noise_is_not_served_from_the_cache() {
        let inputs = SystemInputs {
            c_b_e: crate::attitude::euler_to_dcm(0.1, 0.2, 0.3),
            specific_force_b: Vector3::new(0.3, -0.1, -9.8),
            angular_rate_b: Vector3::new(0.01, 0.02, -0.03),
            position_ecef: Vector3::new(4.6e6, 1.2e5, 4.4e6),
        };
        let noise = ProcessNoise {
            accel_white_psd: 1e-4,
            gyro_white_psd: 1e-8,
            accel_bias_psd: 1e-7,
            accel_bias_correlation_time_s: 100.0,
            gyro_bias_psd: 1e-11,
            gyro_bias_correlation_time_s: 200.0,
            clock_phase_psd: 0.01,
            clock_frequency_psd: 0.04,
            accel_scale_factor_psd: 0.0,
            gyro_scale_factor_psd: 0.0,
            range_bias_psd: 0.0,
            range_bias_correlation_time_s: f64::INFINITY,
            inter_system_bias_psd: 0.0,
            input_errors: input_noise::InputErrorNoise::default(),
        };
        let other = ProcessNoise {
            accel_bias_correlation_time_s: 5.0,
            ..noise
        };
        let fresh = |n: &ProcessNoise, dt: f64| {
            let mut kf = ErrorStateKf::<17>::new(SMatrix::identity()).unwrap();
            kf.propagate(&inputs, n, dt, 0.0).unwrap();
            kf.p
        };
        let mut kf = ErrorStateKf::<17>::new(SMatrix::identity()).unwrap();
        kf.propagate(&inputs, &noise, 0.01, 0.0).unwrap();
        kf.p = SMatrix::identity();
        kf.propagate(&inputs, &noise, 0.005, 0.0).unwrap();
        assert_eq!(kf.p, fresh(&noise, 0.005));
        kf.p = SMatrix::identity();
        kf.propagate(&inputs, &other, 0.005, 0.0).unwrap();
        assert_eq!(kf.p, fresh(&other, 0.005));
        assert_ne!(kf.p, fresh(&noise, 0.005));
    }

    #[test]
    fn divergence_is_a_typed_error() {
        let mut kf = ErrorStateKf::<17>::new(SMatrix::identity()).unwrap();
        kf.p[(7, 7)] = -1.0;
        let e = kf.check_health(12.0).unwrap_err();
        assert!(
            matches!(e, Error::Divergence { time_s, .. } if time_s == 12.0),
            "{e}"
        );
        assert!(e.to_string().contains("position_y"), "{e}");
        let mut kf = ErrorStateKf::<17>::new(SMatrix::identity()).unwrap();
        kf.x.0[3] = f64::NAN;
        assert!(matches!(
            kf.check_health(0.0),
            Err(Error::Divergence { .. })
        ));
        // A symmetric matrix with a positive diagonal that is not positive definite.
        let mut kf = ErrorStateKf::<17>::new(SMatrix::identity()).unwrap();
        kf.p[(0, 1)] = 2.0;
        kf.p[(1, 0)] = 2.0;
        assert!(matches!(
            kf.check_health(0.0),
            Err(Error::Divergence { .. })
        ));
        let bad = SMatrix::<f64, 17, 17>::from_diagonal(&SVector::from_element(-1.0));
        assert!(matches!(
            ErrorStateKf::<17>::new(bad),
            Err(Error::InvalidArgument { .. })
        ));
    }
}
