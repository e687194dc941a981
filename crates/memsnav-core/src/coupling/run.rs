//! One coupled-filter run over any kind of aiding: the loosely coupled
//! filter on position fixes ([`PositionFix`], [`super::loose`]) and the
//! tightly coupled one on GNSS epochs ([`GnssEpoch`], [`super::tight`])
//! share everything but how an epoch is checked and applied, which the
//! [`Aiding`] trait carries; the kind is inferred from the epochs given.
//!
//! - [`solution`]: the whole forward solution at every IMU sample;
//!   [`smoothed_solution`]: with its fixed-interval smoothed solution
//!   ([`crate::filter::smoother`]).
//! - [`run`], [`run_smoothed`]: the same, calling `observe(k, state)` after
//!   each IMU sample k instead of storing the solution (the Monte Carlo
//!   keeps only what it scores: of the smoothed solution, the positions).
//! - [`run_paused`]: a run stopped after one sample, continued by
//!   [`Paused::advance`] and [`Paused::finish`] on each of several aidings
//!   that share its beginning (an outage study's cells).

use nalgebra::Vector3;

use super::engine::{self, AidingEpoch, FilterState, InitialState, Observe, SampleAid, SampleHook};
use super::engine::{smoothed_positions, Solution};
use super::records::RunRecords;
use super::tuning::FilterTuning;
use crate::ins::ImuData;
use crate::Result;

/// An aiding epoch kind: what a run over such epochs checks and sets up
/// once, and how one epoch updates the filter.
pub trait Aiding: AidingEpoch + Sized {
    /// The argument the epochs come in, for error messages.
    const ARGUMENT: &'static str;
    /// What [`Self::prepare`] computes once per run for the updates.
    type Prepared: Clone;
    /// Checks the epochs and returns what the updates need, with the
    /// initial state and tuning the run starts from (the loose filter
    /// fixes the unobserved clock, for instance).
    fn prepare(
        epochs: &[Self],
        initial: &InitialState,
        tuning: &FilterTuning,
    ) -> Result<(Self::Prepared, InitialState, FilterTuning)>;
    /// Whether these epochs need the inter-system-bias states (they hold
    /// satellites of a system other than GPS); false for position fixes.
    fn needs_inter_system_biases(_epochs: &[Self]) -> bool {
        false
    }
    /// Applies epoch `i` of the run.
    fn update<const N: usize>(
        state: &mut FilterState<N>,
        prepared: &Self::Prepared,
        i: usize,
        epoch: &Self,
    ) -> Result<()>;
}

/// Runs the filter with `N` error states over the IMU series and the
/// aiding epochs, calling `hook` at every IMU sample; returns the final
/// filter state (its records: measurements, batches, resets).
pub(crate) fn run_with_hook<const N: usize, E: Aiding, H: SampleHook<N>>(
    imu: &ImuData,
    epochs: &[E],
    initial: &InitialState,
    tuning: &FilterTuning,
    smooth: bool,
    hook: &mut H,
) -> Result<FilterState<N>> {
    let (state, stopped) = run_until_error(imu, epochs, initial, tuning, smooth, hook)?;
    stopped.map_or(Ok(state), Err)
}

/// [`run_with_hook`] that keeps what a run that stops on an error had
/// done: an error before the first sample (the arguments, the initial
/// state) is returned as such; one during the run comes with the filter
/// state as it was when it stopped (its records up to there; `hook` has
/// seen every sample before it).
pub(crate) fn run_until_error<const N: usize, E: Aiding, H: SampleHook<N>>(
    imu: &ImuData,
    epochs: &[E],
    initial: &InitialState,
    tuning: &FilterTuning,
    smooth: bool,
    hook: &mut H,
) -> Result<(FilterState<N>, Option<crate::Error>)> {
    imu.validate()?;
    engine::validate_epoch_times(E::ARGUMENT, epochs, imu.time_s, tuning.time_tolerance_s)?;
    let (prepared, initial, tuning) = E::prepare(epochs, initial, tuning)?;
    let mut state = FilterState::<N>::new(&initial, &tuning)?;
    if smooth {
        state.enable_smoother(imu.time_s.len());
    }
    let stopped = engine::run(
        imu,
        epochs,
        &mut state,
        tuning.time_tolerance_s,
        |s, i, e| E::update(s, &prepared, i, e),
        hook,
    )
    .err();
    Ok((state, stopped))
}

/// IMU positions (m, ECEF) of consecutive samples, and the IMU sample of
/// the first.
pub(crate) type PositionsFrom = (Vec<Vector3<f64>>, usize);

/// A run paused after one IMU sample ([`run_paused`]): the filter state
/// there and what its updates need. [`Paused::advance`] and
/// [`Paused::finish`] continue a copy of it, so runs that share their
/// beginning filter it once.
pub(crate) struct Paused<const N: usize, E: Aiding> {
    state: FilterState<N>,
    prepared: E::Prepared,
    progress: engine::Progress,
    tolerance_s: f64,
    /// Once a copy smooths: the forward positions since its smoother's log
    /// began, and the IMU sample of the first.
    recorded: Option<PositionsFrom>,
}

/// The filter over `imu` and `epochs` up to IMU sample `last`, paused
/// there; `observe(k, state)` sees the samples up to it.
pub(crate) fn run_paused<const N: usize, E: Aiding, O>(
    imu: &ImuData,
    epochs: &[E],
    initial: &InitialState,
    tuning: &FilterTuning,
    last: usize,
    observe: O,
) -> Result<Paused<N, E>>
where
    O: FnMut(usize, &FilterState<N>),
{
    imu.validate()?;
    engine::validate_epoch_times(E::ARGUMENT, epochs, imu.time_s, tuning.time_tolerance_s)?;
    let (prepared, initial, tuning) = E::prepare(epochs, initial, tuning)?;
    let mut state = FilterState::<N>::new(&initial, &tuning)?;
    let tolerance_s = tuning.time_tolerance_s;
    let progress = {
        let mut update = |s: &mut FilterState<N>, i, e: &E| E::update(s, &prepared, i, e);
        let mut hook = Observe(observe);
        let at = engine::begin(imu, epochs, &mut state, tolerance_s, &mut update, &mut hook)?;
        engine::run_to(
            imu,
            epochs,
            &mut state,
            tolerance_s,
            update,
            &mut hook,
            at,
            last,
        )?
    };
    Ok(Paused {
        state,
        prepared,
        progress,
        tolerance_s,
        recorded: None,
    })
}

impl<const N: usize, E: Aiding> Paused<N, E> {
    /// A copy of the paused run continued to IMU sample `last` of `imu`
    /// and paused again. `imu` and `epochs` must hold the paused run's
    /// samples and epochs up to the pause; what follows may differ (the
    /// run is causal: the copy is the run [`run`] makes on them, bit for
    /// bit). `observe(k, state)` sees each sample after the pause. With
    /// `smooth` the copy records for the smoother from the pause on (if
    /// it does not already).
    pub(crate) fn advance<O>(
        &self,
        imu: &ImuData,
        epochs: &[E],
        last: usize,
        smooth: bool,
        observe: O,
    ) -> Result<Self>
    where
        O: FnMut(usize, &FilterState<N>),
    {
        let (state, progress, recorded) = self.go_on(imu, epochs, last, smooth, observe)?;
        Ok(Self {
            state,
            prepared: self.prepared.clone(),
            progress,
            tolerance_s: self.tolerance_s,
            recorded,
        })
    }

    /// A copy of the paused run continued to the end of `imu` and `epochs`
    /// (as [`Self::advance`]). Returns the whole run's measurement records
    /// and, when it smooths (`smooth`, or an earlier copy began to), the
    /// smoothed IMU positions of the samples after the pause the smoothing
    /// began at, with the IMU sample of the first (the backward pass needs
    /// nothing before them).
    pub(crate) fn finish<O>(
        &self,
        imu: &ImuData,
        epochs: &[E],
        smooth: bool,
        observe: O,
    ) -> Result<(RunRecords, Option<PositionsFrom>)>
    where
        O: FnMut(usize, &FilterState<N>),
    {
        let last = imu.time_s.len() - 1;
        let (mut state, _, recorded) = self.go_on(imu, epochs, last, smooth, observe)?;
        let smoothed = match (recorded, state.kf.take_smoother()) {
            (Some((positions, first)), Some(mut log)) => {
                Some((smoothed_positions(&positions, &mut log)?, first))
            }
            _ => None,
        };
        Ok((state.take_records(), smoothed))
    }

    /// The copy's state, where it stands and what it recorded, after
    /// running on to `last`.
    fn go_on<O>(
        &self,
        imu: &ImuData,
        epochs: &[E],
        last: usize,
        smooth: bool,
        mut observe: O,
    ) -> Result<(FilterState<N>, engine::Progress, Option<PositionsFrom>)>
    where
        O: FnMut(usize, &FilterState<N>),
    {
        imu.validate()?;
        engine::validate_epoch_times(E::ARGUMENT, epochs, imu.time_s, self.tolerance_s)?;
        let mut state = self.state.clone();
        let mut recorded = self.recorded.clone();
        if smooth && recorded.is_none() {
            let remaining = last.saturating_sub(self.progress.sample);
            state.enable_smoother(remaining);
            recorded = Some((Vec::with_capacity(remaining), self.progress.sample + 1));
        }
        let mut hook = Observe(|k, s: &FilterState<N>| {
            observe(k, s);
            if let Some((positions, _)) = recorded.as_mut() {
                positions.push(s.nav.position_ecef);
            }
        });
        let update = |s: &mut FilterState<N>, i, e: &E| E::update(s, &self.prepared, i, e);
        let progress = engine::run_to(
            imu,
            epochs,
            &mut state,
            self.tolerance_s,
            update,
            &mut hook,
            self.progress,
            last,
        )?;
        Ok((state, progress, recorded))
    }
}

/// Runs the filter with `N` error states (17, 23, 29 or 35);
/// `observe(k, state)` sees the state after IMU sample k. Returns the
/// measurement records.
pub fn run<const N: usize, E: Aiding, O>(
    imu: &ImuData,
    epochs: &[E],
    initial: &InitialState,
    tuning: &FilterTuning,
    observe: O,
) -> Result<RunRecords>
where
    O: FnMut(usize, &FilterState<N>),
{
    let mut state = run_with_hook(imu, epochs, initial, tuning, false, &mut Observe(observe))?;
    Ok(state.take_records())
}

/// [`run`] and the smoothed positions: `observe(k, state)` sees the
/// forward filter after each IMU sample k; returns the forward measurement
/// records and the fixed-interval smoothed IMU position at every sample,
/// m (those of [`smoothed_solution`], bit for bit, without smoothing the
/// covariance).
pub fn run_smoothed<const N: usize, E: Aiding, O>(
    imu: &ImuData,
    epochs: &[E],
    initial: &InitialState,
    tuning: &FilterTuning,
    mut observe: O,
) -> Result<(RunRecords, Vec<Vector3<f64>>)>
where
    O: FnMut(usize, &FilterState<N>),
{
    let mut positions = Vec::with_capacity(imu.time_s.len());
    let mut state = run_with_hook::<N, E, _>(
        imu,
        epochs,
        initial,
        tuning,
        true,
        &mut Observe(|k, s: &FilterState<N>| {
            observe(k, s);
            positions.push(s.nav.position_ecef);
        }),
    )?;
    let mut log = state
        .kf
        .take_smoother()
        .expect("the run records for the smoother");
    let smoothed = smoothed_positions(&positions, &mut log)?;
    Ok((state.take_records(), smoothed))
}

/// The filter's whole solution at every IMU sample.
pub fn solution<const N: usize, E: Aiding>(
    imu: &ImuData,
    epochs: &[E],
    initial: &InitialState,
    tuning: &FilterTuning,
) -> Result<Solution> {
    Ok(aided_solution::<N, E, _>(imu, epochs, initial, tuning, false, &mut ())?.0)
}

/// The filter's forward solution and its fixed-interval smoothed solution.
pub fn smoothed_solution<const N: usize, E: Aiding>(
    imu: &ImuData,
    epochs: &[E],
    initial: &InitialState,
    tuning: &FilterTuning,
) -> Result<(Solution, Solution)> {
    let (forward, smoothed) =
        aided_solution::<N, E, _>(imu, epochs, initial, tuning, true, &mut ())?;
    Ok((forward, smoothed.expect("asked for")))
}

/// The forward solution (and the smoothed one with `smooth`), with `aid`
/// applied after the updates at each IMU sample.
pub fn aided_solution<const N: usize, E: Aiding, A: SampleAid>(
    imu: &ImuData,
    epochs: &[E],
    initial: &InitialState,
    tuning: &FilterTuning,
    smooth: bool,
    aid: &mut A,
) -> Result<(Solution, Option<Solution>)> {
    let mut sol = Solution::with_capacity(imu.time_s.len(), N);
    let mut state = run_with_hook::<N, E, _>(
        imu,
        epochs,
        initial,
        tuning,
        smooth,
        &mut AidThenRecord {
            aid,
            solution: &mut sol,
            time_s: imu.time_s,
        },
    )?;
    sol.take_records(&mut state);
    super::diagnose(
        &mut sol,
        ("specific_force", imu.specific_force_b),
        ("angular_rate", imu.angular_rate_b),
    );
    let smoothed = state
        .kf
        .take_smoother()
        .map(|mut log| sol.smoothed(&mut log))
        .transpose()?;
    Ok((sol, smoothed))
}

/// The hook of [`aided_solution`]: the aid, then the sample's record.
struct AidThenRecord<'a, A> {
    aid: &'a mut A,
    solution: &'a mut Solution,
    time_s: &'a [f64],
}

impl<const N: usize, A: SampleAid> SampleHook<N> for AidThenRecord<'_, A> {
    fn at_sample(&mut self, k: usize, state: &mut FilterState<N>) -> Result<()> {
        self.aid.at_sample(k, state)?;
        self.solution.push(self.time_s[k], state);
        Ok(())
    }
}
