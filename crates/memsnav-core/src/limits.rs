//! Size and range limits checked up front at the public entry points, so
//! that no argument can make memsnav allocate more than a machine holds,
//! loop for ever or overflow a float (`docs/reference/robustness.md` lists
//! them). Each check names the argument and gives the figure.

use crate::{Error, Result};

/// Worker threads of a Monte Carlo set: far above any machine's cores;
/// more would only exhaust the operating system's thread limit.
pub const MAX_THREADS: usize = 1024;

/// Monte Carlo runs per set (`runs`, `parameter_sets`): 10⁶ runs of the
/// shortest experiment take hours; larger studies are split by seed.
pub const MAX_RUNS: usize = 1_000_000;

/// Runs of a whole experiment (sets × runs per set).
pub const MAX_TOTAL_RUNS: usize = 10_000_000;

/// Satellites tracked at once: every GNSS constellation together has fewer
/// than 150; the simulated arrays are `(epochs, n_satellites)`.
pub const MAX_SATELLITES: usize = 256;

/// Largest magnitude of anything a sensor reads or a sensor model holds,
/// SI units (10⁶ m/s² ≈ 10⁵ g, 10⁶ rad/s): IMU series given to `strapdown`
/// and the filters, calibration inputs (outputs, references and their
/// noise), sensor-model parameters and their noise. Far beyond any
/// sensor, and far enough below the float range that the products of the
/// mechanization, the error models and the least-squares factorisation
/// stay finite (10³⁰⁰ used to hang the calibration's SVD).
pub const MAX_SENSOR_MAGNITUDE: f64 = 1e6;

/// Longest median sample period of an IMU series, s: IMUs sample at
/// 1 Hz or (far) faster; beyond it the strapdown integration's
/// extrapolation over an interval has no meaning.
pub const MAX_IMU_PERIOD_S: f64 = 1.0;

/// Largest sample rate of a simulated sensor, Hz (10⁶: a thousand times a
/// MEMS output rate); the per-sample noise grows with its square root.
pub const MAX_SAMPLE_RATE_HZ: f64 = 1e6;

/// Smallest sample rate of a simulated sensor, Hz (a sample every 11.6
/// days); below it the sample period leaves the float range's useful part.
pub const MIN_SAMPLE_RATE_HZ: f64 = 1e-6;

/// Samples of one simulated trajectory or motion: 10⁸ (several GB of
/// vectors; 11.6 days at 100 Hz).
pub const MAX_SAMPLES: usize = 100_000_000;

/// Longest simulated trajectory or motion, s (11.6 days). A trajectory's
/// position is integrated in sub-steps of 0.01 s whatever its sample rate,
/// so this also bounds that work to 10⁸ sub-steps: a 10³⁰⁰ s trajectory at
/// 10⁻²⁹⁸ Hz (100 samples) never finished, and a 10¹⁰ s calibration
/// segment aborted the interpreter on allocation.
pub const MAX_DURATION_S: f64 = 1.0e6;

/// A simulated span `duration_s` (named `argument`) is at most
/// [`MAX_DURATION_S`].
pub fn duration(argument: &str, duration_s: f64) -> Result<()> {
    if duration_s <= MAX_DURATION_S {
        Ok(())
    } else {
        Err(Error::invalid(
            argument,
            format!("{duration_s:e} s is longer than the limit of {MAX_DURATION_S:e} s"),
        ))
    }
}

/// `duration_s` (named `argument`) sampled at `rate_hz` is at most
/// [`MAX_SAMPLES`] samples.
pub fn samples(argument: &str, duration_s: f64, rate_hz: f64) -> Result<()> {
    let samples = duration_s * rate_hz;
    if samples <= MAX_SAMPLES as f64 {
        Ok(())
    } else {
        Err(Error::invalid(
            argument,
            format!(
                "{duration_s:e} s at {rate_hz:e} Hz is {samples:.3e} samples, more than the \
                 limit of {MAX_SAMPLES}"
            ),
        ))
    }
}

/// Elements (f64) of one output array: 2³⁰, 8 GiB.
pub const MAX_OUTPUT_ELEMENTS: f64 = 1_073_741_824.0;

/// `value` of `argument` is at most `max`.
pub fn at_most(argument: &str, value: usize, max: usize, what: &str) -> Result<()> {
    if value <= max {
        Ok(())
    } else {
        Err(Error::invalid(
            argument,
            format!("{value} is more than the limit of {max} {what}"),
        ))
    }
}

/// An output of `elements` f64 values (computed in floating point so that
/// the product cannot overflow) fits [`MAX_OUTPUT_ELEMENTS`].
pub fn output_size(argument: &str, elements: f64, what: &str) -> Result<()> {
    if elements <= MAX_OUTPUT_ELEMENTS {
        Ok(())
    } else {
        Err(Error::invalid(
            argument,
            format!(
                "would need {what}: {elements:.3e} values ({:.3e} bytes), more than the limit \
                 of {MAX_OUTPUT_ELEMENTS:.0} values",
                elements * 8.0
            ),
        ))
    }
}

/// Monte Carlo sizes: `threads` and the run counts of an experiment
/// (`(argument, count)` pairs, whose product is the total).
pub fn monte_carlo(threads: Option<usize>, counts: &[(&str, usize)]) -> Result<()> {
    if let Some(t) = threads {
        at_most("threads", t, MAX_THREADS, "threads")?;
    }
    let mut total = 1usize;
    for &(argument, n) in counts {
        at_most(argument, n, MAX_RUNS, "runs per set")?;
        total = total.saturating_mul(n);
    }
    let names: Vec<&str> = counts.iter().map(|c| c.0).collect();
    at_most(
        &names.join(" × "),
        total,
        MAX_TOTAL_RUNS,
        "Monte Carlo runs in one experiment",
    )
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn limits_name_the_argument_and_the_figure() {
        let e = monte_carlo(Some(1 << 31), &[("runs", 1)]).unwrap_err();
        assert!(e.to_string().contains("threads") && e.to_string().contains("1024"));
        let e = monte_carlo(None, &[("parameter_sets", 1 << 31)]).unwrap_err();
        assert!(e.to_string().contains("parameter_sets"));
        let e = monte_carlo(None, &[("parameter_sets", 1000), ("runs", 100_000)]).unwrap_err();
        assert!(e.to_string().contains("parameter_sets × runs"));
        assert!(monte_carlo(Some(4), &[("parameter_sets", 50), ("runs", 20)]).is_ok());
        let e = output_size("n_satellites", 1e12 * 8.0, "the pseudorange array").unwrap_err();
        assert!(e.to_string().contains("8.000e12"));
    }
}
