//! Whole-series drivers: validate once, then run the pure steps.

use nalgebra::Vector3;

use super::increments::cubic_increment;
use super::ImuData;
use super::{step, step_increments, ImuIncrement, ImuSample, NavState};
use crate::limits::MAX_SENSOR_MAGNITUDE;
use crate::{validate, Error, Result};

/// The one check of a sample series and its start (`super::series`).
fn validate_samples(
    time_s: &[f64],
    specific_force_b: &[Vector3<f64>],
    angular_rate_b: &[Vector3<f64>],
    initial: &NavState,
) -> Result<()> {
    ImuData {
        time_s,
        specific_force_b,
        angular_rate_b,
        increments: None,
    }
    .validate()?;
    initial.validate("")
}

/// Integrates a whole series of instantaneous samples and returns the
/// state at every sample time (the first is `initial`).
///
/// Seeing the whole series, it does better than chaining [`step`]: over
/// each interval the samples are replaced by the cubic through the four
/// around it, integrated exactly into angle and velocity increments
/// ([`increments_from_samples`](super::increments_from_samples)), and those
/// go through [`step_increments`] with coning and sculling corrections.
/// Fed a trajectory's error-free truth at 100 Hz this closes to about
/// 1 cm over 600 s, where the two-sample [`step`] reaches about 0.1 m (its
/// trapezoidal rate integral leaves O(dt²) attitude errors of ~1e-6 rad).
///
/// Errors (naming the argument), from the checks every IMU consumer runs
/// ([`ImuData::validate`], [`NavState::validate`]): fewer than two
/// samples, `time` not finite, not strictly increasing or with a gap the
/// integration cannot bridge; `specific_force` / `angular_rate` of another
/// length, non-finite or beyond ±10⁶; a `position_ecef` off the geodesy's
/// domain, a `velocity_ecef` beyond its speed limit, an `attitude` that is
/// not a rotation.
pub fn integrate(
    time_s: &[f64],
    specific_force_b: &[Vector3<f64>],
    angular_rate_b: &[Vector3<f64>],
    initial: &NavState,
) -> Result<Vec<NavState>> {
    validate_samples(time_s, specific_force_b, angular_rate_b, initial)?;
    let mut out = Vec::with_capacity(time_s.len());
    out.push(*initial);
    let mut state = *initial;
    let mut prev = ImuIncrement::default();
    for k in 0..time_s.len() - 1 {
        let curr = cubic_increment(time_s, specific_force_b, angular_rate_b, k);
        state = step_increments(&state, &prev, &curr, time_s[k + 1] - time_s[k]);
        out.push(state);
        prev = curr;
    }
    Ok(out)
}

/// Chains the two-sample [`step`] over a whole series (what a filter does
/// epoch by epoch), with the same validation as [`integrate`].
pub fn integrate_steps(
    time_s: &[f64],
    specific_force_b: &[Vector3<f64>],
    angular_rate_b: &[Vector3<f64>],
    initial: &NavState,
) -> Result<Vec<NavState>> {
    validate_samples(time_s, specific_force_b, angular_rate_b, initial)?;
    let mut out = Vec::with_capacity(time_s.len());
    out.push(*initial);
    let mut state = *initial;
    for k in 1..time_s.len() {
        let prev = ImuSample {
            specific_force_b: specific_force_b[k - 1],
            angular_rate_b: angular_rate_b[k - 1],
        };
        let curr = ImuSample {
            specific_force_b: specific_force_b[k],
            angular_rate_b: angular_rate_b[k],
        };
        state = step(&state, &prev, &curr, time_s[k] - time_s[k - 1]);
        out.push(state);
    }
    Ok(out)
}

/// Runs [`step_increments`] over a series of increments: `time_s` has one
/// more element than the increments, increment k covering
/// `[time[k], time[k+1]]`. The first interval has no previous increments
/// (zero coning/sculling history). Returns the state at every time.
///
/// Errors (naming the argument) as [`integrate`], with `delta_velocity`
/// and `delta_angle` for the increments.
pub fn integrate_increments(
    time_s: &[f64],
    delta_velocity_b: &[Vector3<f64>],
    delta_angle_b: &[Vector3<f64>],
    initial: &NavState,
) -> Result<Vec<NavState>> {
    if time_s.len() < 2 {
        return Err(Error::invalid(
            "time",
            format!("needs at least two times, got {}", time_s.len()),
        ));
    }
    validate::increasing_times("time", time_s)?;
    validate::imu_time_gaps("time", time_s)?;
    let intervals = time_s.len() - 1;
    validate::same_length(
        "delta_velocity",
        delta_velocity_b.len(),
        "time minus one",
        intervals,
    )?;
    validate::same_length(
        "delta_angle",
        delta_angle_b.len(),
        "time minus one",
        intervals,
    )?;
    // Increments over at most 100 s of at most 10⁶ SI: the bound of the
    // rates and forces they integrate.
    let max_increment = 100.0 * MAX_SENSOR_MAGNITUDE;
    validate::bounded_vectors("delta_velocity", delta_velocity_b, max_increment)?;
    validate::bounded_vectors("delta_angle", delta_angle_b, max_increment)?;
    initial.validate("")?;
    let mut out = Vec::with_capacity(time_s.len());
    out.push(*initial);
    let mut state = *initial;
    let mut prev = ImuIncrement::default();
    for k in 0..intervals {
        let curr = ImuIncrement {
            delta_velocity_b: delta_velocity_b[k],
            delta_angle_b: delta_angle_b[k],
        };
        state = step_increments(&state, &prev, &curr, time_s[k + 1] - time_s[k]);
        out.push(state);
        prev = curr;
    }
    Ok(out)
}
