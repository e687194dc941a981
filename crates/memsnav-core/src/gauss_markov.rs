//! The first-order Gauss-Markov process, once: its parameters, their
//! validation and its exact discretisation, shared by every place memsnav
//! uses it — the sensors' bias instability ([`crate::sensors::NoiseProcess`]),
//! the simulated atmospheric/multipath residual of the pseudoranges
//! ([`crate::gnss::simulate`]), the smoothed drivers of the calibration
//! motion ([`crate::experiments::motion`]) and the bias states of the
//! navigation filters' process noise ([`crate::filter`]).
//!
//! ## The model
//!
//! ```text
//! dx/dt = −x/τ + w(t),   E[w(t) w(t + s)] = q δ(s)
//! ```
//!
//! with driving power spectral density q and correlation time τ; its
//! stationary variance is σ² = q τ / 2, so a process given by (σ, τ) has
//! q = 2σ²/τ (Brown & Hwang, *Introduction to Random Signals and Applied
//! Kalman Filtering*, 4th ed., §2.9 and §4.2; Groves 2nd ed. §14.2.4).
//! τ = ∞ is the random walk (q the squared random-walk coefficient).
//!
//! ## Exact discretisation over Δt
//!
//! ```text
//! x_{k+1} = φ x_k + w_k,   φ = e^{−Δt/τ},
//! Var w_k = (q τ / 2)(1 − e^{−2Δt/τ}) = σ² (1 − φ²)
//! ```
//!
//! (Brown & Hwang eq. 4.2.11 and the Q of §4.2; τ = ∞: φ = 1, Var w_k = q Δt).
//! 1 − e^{−2Δt/τ} is computed as −expm1(−2Δt/τ), which keeps its precision
//! when Δt ≪ τ (a 100 Hz step of a 1 h bias: 2Δt/τ ≈ 6e-6). A stationary
//! start draws x₀ ~ N(0, σ²), so Var x_k = σ² for every k.
//!
//! ## Its Allan variance
//!
//! Averaged over T, the stationary process of (σ, τ) has the Allan
//! variance (IEEE Std 952-1997 annex C, "exponentially correlated
//! (Markov) noise"; El-Sheimy et al., *IEEE Trans. Instrum. Meas.* 57,
//! 2008, table 1, with q_c² = 2σ²/τ)
//!
//! ```text
//! σ_A²(T) = (2σ²τ/T) [1 − (τ/2T)(3 − 4e^{−T/τ} + e^{−2T/τ})]
//! ```
//!
//! a random walk of rate q (σ_A² = q T/3) for T ≪ τ, white noise of
//! density σ√(2τ) (σ_A² = 2σ²τ/T) for T ≫ τ, and between them a single
//! maximum σ_A = [`ALLAN_PEAK_PER_STD`] σ at T = [`ALLAN_PEAK_TIME_PER_TAU`] τ.

use crate::{validate, Error, Result};

/// A first-order Gauss-Markov process (module docs), validated at
/// construction.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct GaussMarkov {
    psd: f64,
    correlation_time_s: f64,
}

/// One step of a [`GaussMarkov`] process over a fixed Δt:
/// `x ← decay · x + drive_std · z`, z ~ N(0, 1).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct GaussMarkovStep {
    /// φ = e^{−Δt/τ} (1 for a random walk).
    pub decay: f64,
    /// Variance of the driving noise over the step, Var w_k.
    pub drive_variance: f64,
}

impl GaussMarkovStep {
    /// Standard deviation of the driving noise over the step.
    pub fn drive_std(&self) -> f64 {
        self.drive_variance.sqrt()
    }

    /// The next value from `x` and a standard normal draw `z`.
    #[inline]
    pub fn next(&self, x: f64, z: f64) -> f64 {
        self.decay * x + self.drive_std() * z
    }
}

/// The variance of the mean of n samples of a stationary first-order
/// Gauss-Markov (AR(1)) series of lag-one correlation ρ, over σ²/n, for
/// large n: (1 + ρ)/(1 − ρ), n over the effective number of independent
/// samples (Bayley & Hammersley 1946; Wilks, *Statistical Methods in the
/// Atmospheric Sciences*, 3rd ed., eq. 5.12). Sampled Δt apart,
/// ρ = e^{−Δt/τ}.
pub fn mean_variance_factor(lag_one_correlation: f64) -> f64 {
    (1.0 + lag_one_correlation) / (1.0 - lag_one_correlation)
}

/// The factor a measurement's variance is inflated by when its errors
/// are correlated over `correlation_time_s` and it is sampled `interval_s`
/// after the previous one: [`mean_variance_factor`] of ρ = e^(−Δt/τ), so
/// that samples of one slowly varying error, taken as white with the
/// inflated variance, carry what they hold about it once, not once each.
/// 1 for white errors (τ = 0) and without a previous sample.
pub fn correlated_sample_inflation(correlation_time_s: f64, interval_s: Option<f64>) -> f64 {
    match interval_s {
        Some(dt) if correlation_time_s > 0.0 && dt > 0.0 => {
            mean_variance_factor((-dt / correlation_time_s).exp())
        }
        _ => 1.0,
    }
}

/// The step of the process of driving PSD `psd` and correlation time
/// `correlation_time_s` (∞: random walk) over `dt_s` (module docs). The one
/// formula every discretisation in memsnav uses; the arguments are taken as
/// valid (a [`GaussMarkov`] checks them, and so does a filter's tuning).
pub fn discretise(psd: f64, correlation_time_s: f64, dt_s: f64) -> GaussMarkovStep {
    if correlation_time_s.is_finite() {
        let ratio = dt_s / correlation_time_s;
        GaussMarkovStep {
            decay: (-ratio).exp(),
            drive_variance: 0.5 * psd * correlation_time_s * -(-2.0 * ratio).exp_m1(),
        }
    } else {
        GaussMarkovStep {
            decay: 1.0,
            drive_variance: psd * dt_s,
        }
    }
}

/// [`discretise`] of the stationary process of std `std` and correlation
/// time `correlation_time_s`, written with σ² (1 − φ²) instead of q τ / 2
/// (1 − φ²): the same value, without forming q = 2σ²/τ, which overflows
/// for a τ near zero (a sensor's bias instability went NaN).
pub fn stationary_step(std: f64, correlation_time_s: f64, dt_s: f64) -> GaussMarkovStep {
    let ratio = dt_s / correlation_time_s;
    GaussMarkovStep {
        decay: (-ratio).exp(),
        drive_variance: std * std * -(-2.0 * ratio).exp_m1(),
    }
}

/// The driving PSD q = 2σ²/τ of a stationary process of std σ and
/// correlation time τ (0 for τ = ∞: no stationary process has it).
pub fn psd_of_stationary(std: f64, correlation_time_s: f64) -> f64 {
    if correlation_time_s.is_finite() {
        2.0 * std * std / correlation_time_s
    } else {
        0.0
    }
}

/// The maximum of the Allan deviation of a stationary process, per unit
/// of its std σ: 0.617364 (module docs; the maximum of √h(x) with h as in
/// [`allan_variance`], found numerically and checked by a test).
pub const ALLAN_PEAK_PER_STD: f64 = 0.617_364_283;

/// Where that maximum lies: T = 1.892618 τ.
pub const ALLAN_PEAK_TIME_PER_TAU: f64 = 1.892_618;

/// The Allan variance σ_A²(T) of the stationary process of std `std` and
/// correlation time `correlation_time_s` at averaging time
/// `averaging_time_s` (module docs). For T < τ/100 the bracket is taken
/// from its series, x²/3 − x³/4 + 7x⁴/60 − x⁵/24 (x = T/τ), whose first
/// terms the closed form would lose to cancellation.
pub fn allan_variance(std: f64, correlation_time_s: f64, averaging_time_s: f64) -> f64 {
    let x = averaging_time_s / correlation_time_s;
    let bracket = if x < 1e-2 {
        x * x * (1.0 / 3.0 - x * (0.25 - x * (7.0 / 60.0 - x / 24.0)))
    } else {
        1.0 - (3.0 - 4.0 * (-x).exp() + (-2.0 * x).exp()) / (2.0 * x)
    };
    2.0 * std * std * bracket / x
}

impl GaussMarkov {
    /// The stationary process of standard deviation `std` (≥ 0) and finite
    /// correlation time `correlation_time_s` (> 0). `names` are the
    /// caller-visible names of the two values, for the error message.
    pub fn stationary(std: f64, correlation_time_s: f64, names: [&str; 2]) -> Result<Self> {
        validate::non_negative(names[0], std)?;
        validate::positive(names[1], correlation_time_s)?;
        let psd = psd_of_stationary(std, correlation_time_s);
        if !psd.is_finite() {
            return Err(Error::invalid(
                names[1],
                format!(
                    "{correlation_time_s:e} s is too short for {} = {std:e}: the driving PSD 2σ²/τ overflows",
                    names[0]
                ),
            ));
        }
        Ok(Self {
            psd,
            correlation_time_s,
        })
    }

    /// The process of driving PSD `psd` (≥ 0) and correlation time
    /// `correlation_time_s` (> 0, `f64::INFINITY` for a random walk).
    pub fn from_psd(psd: f64, correlation_time_s: f64, names: [&str; 2]) -> Result<Self> {
        validate::non_negative(names[0], psd)?;
        if correlation_time_s.is_nan() || correlation_time_s <= 0.0 {
            return Err(Error::invalid(
                names[1],
                format!("must be positive (inf for a random walk), got {correlation_time_s}"),
            ));
        }
        Ok(Self {
            psd,
            correlation_time_s,
        })
    }

    /// Driving PSD q.
    pub fn psd(&self) -> f64 {
        self.psd
    }

    /// Correlation time τ, s (∞ for a random walk).
    pub fn correlation_time_s(&self) -> f64 {
        self.correlation_time_s
    }

    /// Stationary standard deviation √(q τ / 2) (∞ for a driven random walk).
    pub fn stationary_std(&self) -> f64 {
        (0.5 * self.psd * self.correlation_time_s).sqrt()
    }

    /// The exact step over `dt_s` (module docs).
    pub fn step(&self, dt_s: f64) -> GaussMarkovStep {
        discretise(self.psd, self.correlation_time_s, dt_s)
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::random::stream;
    use rand::Rng as _;
    use rand_distr::StandardNormal;

    /// The discrete variance is the integral of the continuous model:
    /// Var w = ∫₀^Δt e^{−2s/τ} q ds, checked by a midpoint sum, and it
    /// keeps its precision for Δt ≪ τ (where 1 − e^{−2Δt/τ} would cancel).
    #[test]
    fn discrete_variance_is_the_integral_of_the_driving_noise() {
        let (q, tau, dt) = (0.3, 2.0, 0.7);
        let m = 200_000;
        let h = dt / m as f64;
        let integral: f64 = (0..m)
            .map(|i| (-2.0 * (i as f64 + 0.5) * h / tau).exp() * q * h)
            .sum();
        let step = discretise(q, tau, dt);
        assert!((step.drive_variance / integral - 1.0).abs() < 1e-9);
        assert_eq!(step.decay, (-dt / tau).exp());
        // Δt ≪ τ: Var w → q Δt (1 − Δt/τ).
        let (dt, tau) = (0.01, 3600.0);
        let small = discretise(q, tau, dt).drive_variance;
        let expected = q * dt * (1.0 - dt / tau);
        assert!(
            (small / expected - 1.0).abs() < 1e-10,
            "{small} vs {expected}"
        );
        // τ = ∞ is the random walk.
        assert_eq!(
            discretise(q, f64::INFINITY, dt),
            GaussMarkovStep {
                decay: 1.0,
                drive_variance: q * dt
            }
        );
    }

    /// Stationary start and exact steps keep Var x = σ² at every step, for
    /// any step length (unequal steps, as between GNSS epochs).
    #[test]
    fn stationary_variance_is_kept_by_unequal_steps() {
        let (sigma, tau) = (2.0, 5.0);
        let p = GaussMarkov::stationary(sigma, tau, ["std", "tau"]).unwrap();
        assert!((p.stationary_std() - sigma).abs() < 1e-12);
        let steps = [0.01, 3.0, 0.5, 12.0];
        let runs = 40_000;
        let mut rng = stream(11, 0);
        let mut var = [0.0; 4];
        for _ in 0..runs {
            let mut x = sigma * rng.sample::<f64, _>(StandardNormal);
            for (v, dt) in var.iter_mut().zip(steps) {
                x = p.step(dt).next(x, rng.sample(StandardNormal));
                *v += x * x / runs as f64;
            }
        }
        for v in var {
            // 5σ of a variance estimate from 40 000 draws: 3.5 %.
            assert!((v / (sigma * sigma) - 1.0).abs() < 0.035, "{var:?}");
        }
    }

    #[test]
    fn invalid_parameters_name_the_argument() {
        let e = GaussMarkov::stationary(-1.0, 1.0, ["residual_std", "tau"]).unwrap_err();
        assert!(e.to_string().starts_with("residual_std:"), "{e}");
        let e = GaussMarkov::stationary(1.0, 0.0, ["s", "residual_correlation_time"]).unwrap_err();
        assert!(
            e.to_string().starts_with("residual_correlation_time:"),
            "{e}"
        );
        let e = GaussMarkov::from_psd(1.0, f64::NAN, ["q", "correlation_time"]).unwrap_err();
        assert!(e.to_string().starts_with("correlation_time:"), "{e}");
        let walk = GaussMarkov::from_psd(4.0, f64::INFINITY, ["q", "t"]).unwrap();
        assert_eq!(walk.stationary_std(), f64::INFINITY);
        assert_eq!(walk.step(0.25).drive_variance, 1.0);
    }

    /// The Allan variance's limits (random walk of q = 2σ²/τ below τ, white
    /// noise of density σ√(2τ) above it), the series and the closed form
    /// meeting at x = 1e-2, and the maximum where the constants say.
    #[test]
    fn allan_variance_limits_and_peak() {
        let (sigma, tau) = (2.0, 50.0);
        let q = 2.0 * sigma * sigma / tau;
        let short = allan_variance(sigma, tau, 1e-4 * tau);
        assert!((short / (q * 1e-4 * tau / 3.0) - 1.0).abs() < 1e-3);
        let long = allan_variance(sigma, tau, 1e4 * tau);
        assert!((long / (2.0 * sigma * sigma * tau / (1e4 * tau)) - 1.0).abs() < 1e-3);
        let below = allan_variance(sigma, tau, (1e-2 - 1e-12) * tau);
        let above = allan_variance(sigma, tau, (1e-2 + 1e-12) * tau);
        assert!((below / above - 1.0).abs() < 1e-9, "{below} {above}");
        let mut best = (0.0, 0.0);
        for i in 0..200_000 {
            let t = tau * (0.5 + 3.0 * i as f64 / 200_000.0);
            let a = allan_variance(sigma, tau, t).sqrt();
            if a > best.0 {
                best = (a, t);
            }
        }
        assert!(
            (best.0 / sigma - ALLAN_PEAK_PER_STD).abs() < 1e-9,
            "{best:?}"
        );
        assert!(
            (best.1 / tau - ALLAN_PEAK_TIME_PER_TAU).abs() < 1e-4,
            "{best:?}"
        );
    }

    /// The closed form against the overlapping Allan deviation of a long
    /// simulated process (the estimator of [`crate::allan`], independent
    /// of the formula): within the estimate's own error, 4/√(2(K − 1))
    /// with K = N/m clusters (IEEE Std 952-1997 annex C). Clusters of 20
    /// samples and more: the formula averages the process continuously,
    /// the estimator its point samples (at m = 2 they differ by 6 %).
    #[test]
    fn allan_variance_matches_a_simulated_process() {
        let (sigma, tau, rate, n) = (0.5, 2.0, 20.0, 400_000);
        let step = stationary_step(sigma, tau, 1.0 / rate);
        let mut rng = stream(21, 0);
        let mut x = sigma * rng.sample::<f64, _>(StandardNormal);
        let series: Vec<f64> = (0..n)
            .map(|_| {
                x = step.next(x, rng.sample(StandardNormal));
                x
            })
            .collect();
        let clusters = [20, 76, 400, 2000];
        let adev = crate::allan::overlapping_allan_deviation(&series, 1, rate, &clusters).unwrap();
        for (&m, a) in clusters.iter().zip(adev) {
            let t = m as f64 / rate;
            let expected = allan_variance(sigma, tau, t).sqrt();
            let tolerance = 4.0 / (2.0 * (n as f64 / m as f64 - 1.0)).sqrt();
            assert!(
                (a / expected - 1.0).abs() < tolerance,
                "T {t}: {a} vs {expected}"
            );
        }
    }

    /// The inflated variance against the variance of the mean of n samples
    /// of a simulated first-order Gauss-Markov error (AR(1), unit
    /// variance), over many seeded draws: σ² k² / n within the Monte
    /// Carlo spread; white noise and the first epoch are not inflated.
    #[test]
    fn inflation_gives_the_variance_of_the_mean_of_correlated_samples() {
        assert_eq!(correlated_sample_inflation(0.0, Some(0.25)), 1.0);
        assert_eq!(correlated_sample_inflation(10.0, None), 1.0);
        let (tau, dt, n, draws): (f64, f64, usize, usize) = (5.0, 0.25, 2000, 2000);
        let rho = (-dt / tau).exp();
        let drive = (1.0 - rho * rho).sqrt();
        let mut rng = stream(77, 0);
        let mut means = Vec::with_capacity(draws);
        for _ in 0..draws {
            let mut x: f64 = rng.sample(StandardNormal);
            let mut sum = 0.0;
            for _ in 0..n {
                sum += x;
                let w: f64 = rng.sample(StandardNormal);
                x = rho * x + drive * w;
            }
            means.push(sum / n as f64);
        }
        let variance = means.iter().map(|m| m * m).sum::<f64>() / draws as f64;
        let predicted = correlated_sample_inflation(tau, Some(dt)) / n as f64;
        // 2000 draws: the variance estimate's relative std is √(2/2000) = 3 %;
        // the finite-n correction is 2ρ/(n(1−ρ)) ≈ 2 %.
        assert!(
            (variance / predicted - 1.0).abs() < 0.1,
            "{variance} vs {predicted}"
        );
        // Taken as white, the same samples would claim 1/n: far too little.
        assert!(variance > 20.0 / n as f64);
    }
}
