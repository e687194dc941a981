//! What a log run learns about its sensors from the log itself, before the
//! run that is reported: which IMU model its GNSS measurements support,
//! and how slowly its fixes' position errors change.
//!
//! Both are learnt from a first pass over the whole log, bounded, and
//! reported ([`Adaptation`] in the run's summary):
//!
//! 1. **The IMU model** (`[filter] imu_preset = "auto"`, the default):
//!    the log is run once per candidate grade ([`IMU_CANDIDATES`]), each a
//!    complete tuning built the same way from its preset and the user's
//!    keys, on the fixes as the receiver reports them, and the candidate
//!    whose GNSS innovations are the most likely is kept: Σ −½ (ν²/s² + ln s²) over every scalar GNSS measurement,
//!    ν the innovation and s² its predicted variance h P hᵀ + r, the
//!    log-likelihood of the measurements under the candidate's model
//!    (the innovations of a Kalman filter are independent with those
//!    variances when its model is right: Schweppe 1965; Maybeck,
//!    *Stochastic Models, Estimation and Control* vol. 2 §10.3, the
//!    multiple-model adaptive estimator's hypothesis test). A model too
//!    loose for the IMU pays in ln s², one too tight in ν²/s² (and in the
//!    resets it provokes); each term is capped at [`NIS_CAP`] so that one
//!    outlier does not decide, and the default grade (the first
//!    candidate) is left only on very strong evidence that holds over
//!    the log: a total gain of [`MIN_LOG_LIKELIHOOD_GAIN`], and a gain
//!    per [`EVIDENCE_BLOCK_S`] block whose mean is [`MIN_EVIDENCE_Z`]
//!    standard errors above zero over at least [`MIN_EVIDENCE_BLOCKS`]
//!    blocks (a short walk whose few hundred correlated pseudoranges
//!    slightly prefer another grade keeps the default). The candidates are drawn from the
//!    presets a user would otherwise choose by hand; the choice never
//!    leaves them.
//! 2. **The fixes' error correlation time** (`[gnss]
//!    fix_correlation_time_s = "auto"`, loose coupling, the default): in
//!    a pass with the IMU model chosen each fix's covariance is inflated as if its errors
//!    were correlated over [`FIRST_PASS_CORRELATION_TIME_S`] (the longest
//!    the method reports), so the filter follows the fixes slowly and its
//!    position innovations are the fixes' own errors less a slow average
//!    of them. Their autocorrelation over the fix epochs, for each of the
//!    three whitened components, falls to 1/e of its lag-one value after
//!    the correlation time ([`correlation_time_from_innovations`]); the
//!    longest of the components is kept. The reading is valid only where
//!    the fixes' errors make a good part of the innovations: a component
//!    whose (robust) innovation variance is more than
//!    [`MAX_INNOVATION_TO_FIX_VARIANCE`] times the fixes' own (the dead
//!    reckoning between fixes erring more than the fixes, as with RTK) is
//!    not determined, and with none determined the fixes stay white.
//!    The same innovations bound the fixes' variance from above: the
//!    first pass barely follows them, so their variance is the fixes'
//!    error variance plus the dead reckoning's. Where it exceeds what the
//!    receiver reports, the fixes' covariance is scaled up by the largest
//!    ratio among the determined components (innovation-based covariance
//!    matching, Mohamed & Schwarz, J. Geodesy 73, 1999, with the dead
//!    reckoning's share taken as zero: an upper bound, never below the
//!    receiver's own covariance; a receiver's accuracy estimate is often
//!    optimistic at a standstill, where multipath stays put).
//!    The correlation time then inflates each fix's covariance by
//!    (1 + ρ)/(1 − ρ), ρ = e^(−Δt/τ) ([`crate::gauss_markov::correlated_sample_inflation`]):
//!    consecutive fixes that sample one slow error carry it once.
//!
//! The run that is reported is a last pass with what was learnt; the
//! learning passes keep no solution, only their measurement records.

use rayon::prelude::*;

use crate::coupling::{FilterTuning, MeasurementKind, MeasurementRecord};
use crate::Result;

/// The IMU grades an `"auto"` run chooses from (preset names), from the
/// loosest: consumer MEMS (a Bosch BMI088 class), industrial MEMS (an
/// ADIS16465 class), tactical (an HG1700 class). A navigation-grade IMU
/// is named by hand: no low-cost log needs it, and every candidate costs
/// a pass over the log.
pub const IMU_CANDIDATES: [&str; 3] = ["consumer", "industrial", "tactical"];

/// Largest normalised innovation squared one scalar measurement adds to
/// the negative log-likelihood of a candidate: 25, a 5σ innovation. An
/// outlier the gate rejects costs every candidate alike; a candidate that
/// is wrong for the IMU keeps paying, epoch after epoch.
pub const NIS_CAP: f64 = 25.0;

/// How much more likely (natural log) another candidate's measurements
/// must be than the first candidate's (the default grade, `"consumer"`)
/// for the run to leave it: 5, "very strong" evidence on Kass & Raftery's
/// scale (J. Am. Stat. Assoc. 90, 1995: 2 ln B > 10).
pub const MIN_LOG_LIKELIHOOD_GAIN: f64 = 5.0;

/// The gain must also hold over the log, not in one stretch of it: the
/// log-likelihood differences summed over blocks of this length, s, ...
pub const EVIDENCE_BLOCK_S: f64 = 60.0;

/// ... are at least this many blocks (a log shorter than ten minutes of
/// GNSS keeps the default grade) ...
pub const MIN_EVIDENCE_BLOCKS: usize = 10;

/// ... and their mean is this many standard errors above zero (the batch
/// means of a correlated series are nearly independent: Law & Kelton,
/// *Simulation Modeling and Analysis*, §9.5.3; the innovations of one
/// slow error are not independent evidence, a minute apart they nearly
/// are). 3: one-sided 0.13 % for a normal mean.
pub const MIN_EVIDENCE_Z: f64 = 3.0;

/// The fixes' error correlation time the first pass assumes, s: the
/// longest the method reports. A receiver's standalone position errors
/// (multipath, the ionosphere and troposphere models, the satellites in
/// view) decorrelate within minutes; the first pass must follow the fixes
/// slowly enough for its innovations to show their errors, not their
/// differences.
pub const FIRST_PASS_CORRELATION_TIME_S: f64 = 120.0;

/// A component's correlation time is read off the innovations only when
/// their variance is at most this many times the fixes' own (after the
/// first pass's inflation): the fixes' errors make at least half of the
/// innovations; beyond, the dead reckoning between fixes (or an IMU model
/// too tight for the IMU) makes most of them, and their correlation and
/// spread are the dead reckoning's.
pub const MAX_INNOVATION_TO_FIX_VARIANCE: f64 = 2.0;

/// Innovations beyond this many robust standard deviations are clipped
/// before their variance and autocorrelation are taken.
const CLIP_SIGMAS: f64 = 4.0;

/// Fewest fixes a component's correlation time is read from.
const MIN_FIXES: usize = 50;

/// One candidate IMU model and how likely the log's GNSS measurements
/// are under it.
#[derive(Debug, Clone, PartialEq)]
pub struct ImuCandidate {
    /// The preset the candidate's tuning was built from.
    pub preset: String,
    /// Σ −½ (min(ν²/s², [`NIS_CAP`]) + ln s²) over the GNSS measurements.
    pub log_likelihood: f64,
    /// The scalar GNSS measurements it counts.
    pub measurements: usize,
    /// The resets the candidate's first pass made.
    pub resets: usize,
}

/// The fixes' error correlation time read off the first pass.
#[derive(Debug, Clone, PartialEq)]
pub struct FixCorrelation {
    /// Per whitened component (in the order of the fixes' covariance
    /// factor: about north, east, down): the correlation time, s, or None
    /// where not determined.
    pub component_s: [Option<f64>; 3],
    /// Per component: the innovation variance over the fixes' own (the
    /// test of [`MAX_INNOVATION_TO_FIX_VARIANCE`]).
    pub innovation_to_fix_variance: [f64; 3],
    /// The correlation time the run used, s (0: white).
    pub used_s: f64,
    /// The factor on the fixes' covariance the run used: the largest
    /// ratio of a determined component, at least 1.
    pub covariance_scale: f64,
}

/// What a run learnt from its log.
#[derive(Debug, Clone, PartialEq, Default)]
pub struct Adaptation {
    /// The IMU candidates, in [`IMU_CANDIDATES`] order (empty when the
    /// configuration names its IMU).
    pub imu_candidates: Vec<ImuCandidate>,
    /// The preset of the tuning the run used, when it was chosen.
    pub imu_preset: Option<String>,
    /// The fixes' correlation time, when it was learnt.
    pub fix_correlation: Option<FixCorrelation>,
}

/// What to learn: the candidate tunings (one: nothing to choose) and
/// whether to learn the fixes' correlation time.
pub struct Plan<'a> {
    /// (preset name, tuning); the first is used when there is one.
    pub candidates: &'a [(String, FilterTuning)],
    /// Learn the fixes' correlation time (loose coupling).
    pub fix_correlation: bool,
}

/// A first pass: the run of a tuning, returning its measurement records
/// and the number of resets it made.
pub type FirstPass<'a> =
    dyn Fn(&FilterTuning) -> Result<(Vec<MeasurementRecord>, usize)> + Sync + 'a;

impl Plan<'_> {
    /// The tuning of the run to report and what was learnt: the
    /// candidates run in parallel (their first passes are independent),
    /// the most likely kept, the fixes' correlation time read off its
    /// records. Nothing to learn: the first candidate, no first pass.
    pub fn learn(&self, first_pass: &FirstPass<'_>) -> Result<(FilterTuning, Adaptation)> {
        let mut adaptation = Adaptation::default();
        let mut tuning = self.candidates[0].1;
        if self.candidates.len() > 1 {
            // The candidates are judged on the fixes as the receiver
            // reports them (the measurements every candidate would face
            // without learning), in parallel: their passes are independent.
            let passes: Vec<(Vec<MeasurementRecord>, usize)> = self
                .candidates
                .par_iter()
                .map(|(_, tuning)| first_pass(tuning))
                .collect::<Result<_>>()?;
            let scored: Vec<ImuCandidate> = self
                .candidates
                .iter()
                .zip(&passes)
                .map(|((preset, _), (records, resets))| {
                    let (log_likelihood, measurements) = gnss_log_likelihood(records);
                    ImuCandidate {
                        preset: preset.clone(),
                        log_likelihood,
                        measurements,
                        resets: *resets,
                    }
                })
                .collect();
            let blocks: Vec<Vec<(i64, f64)>> = passes
                .iter()
                .map(|(records, _)| block_log_likelihoods(records))
                .collect();
            let best = most_likely(&scored, &blocks);
            tuning = self.candidates[best].1;
            adaptation.imu_preset = Some(scored[best].preset.clone());
            adaptation.imu_candidates = scored;
        }
        if self.fix_correlation {
            // With the IMU model chosen, a pass that follows the fixes
            // slowly shows their errors in its innovations.
            let mut slow = tuning;
            slow.fix_correlation_time_s = FIRST_PASS_CORRELATION_TIME_S;
            let (records, _) = first_pass(&slow)?;
            let c = correlation_time_from_innovations(&records, FIRST_PASS_CORRELATION_TIME_S);
            tuning.fix_correlation_time_s = c.used_s;
            tuning.fix_covariance_scale = c.covariance_scale;
            adaptation.fix_correlation = Some(c);
        }
        Ok((tuning, adaptation))
    }
}

/// The candidate to keep: the most likely, when it beats the first (the
/// default grade) by [`MIN_LOG_LIKELIHOOD_GAIN`] in all and by a block
/// gain whose mean is [`MIN_EVIDENCE_Z`] standard errors above zero over
/// at least [`MIN_EVIDENCE_BLOCKS`] blocks; the first otherwise. `blocks`:
/// each candidate's log-likelihood per block ([`block_log_likelihoods`]).
fn most_likely(scored: &[ImuCandidate], blocks: &[Vec<(i64, f64)>]) -> usize {
    let best = scored
        .iter()
        .enumerate()
        .max_by(|a, b| a.1.log_likelihood.total_cmp(&b.1.log_likelihood))
        .map_or(0, |(i, _)| i);
    if best == 0
        || scored[best].log_likelihood - scored[0].log_likelihood <= MIN_LOG_LIKELIHOOD_GAIN
    {
        return 0;
    }
    let default: std::collections::HashMap<i64, f64> = blocks[0].iter().copied().collect();
    let gains: Vec<f64> = blocks[best]
        .iter()
        .filter_map(|(b, ll)| default.get(b).map(|d| ll - d))
        .collect();
    let m = gains.len();
    if m < MIN_EVIDENCE_BLOCKS {
        return 0;
    }
    let mean = gains.iter().sum::<f64>() / m as f64;
    let variance = gains.iter().map(|g| (g - mean).powi(2)).sum::<f64>() / (m - 1) as f64;
    if mean > MIN_EVIDENCE_Z * (variance / m as f64).sqrt() {
        best
    } else {
        0
    }
}

/// The GNSS log-likelihood ([`gnss_log_likelihood`]) summed over blocks
/// of [`EVIDENCE_BLOCK_S`] of the records' time (block index, sum), in
/// time order; blocks without a GNSS measurement are left out.
pub fn block_log_likelihoods(records: &[MeasurementRecord]) -> Vec<(i64, f64)> {
    let mut out: Vec<(i64, f64)> = Vec::new();
    for r in records.iter().filter(|r| counts(r)) {
        let block = (r.time_s / EVIDENCE_BLOCK_S).floor() as i64;
        let ll = log_likelihood_term(r);
        match out.last_mut() {
            Some((b, sum)) if *b == block => *sum += ll,
            _ => out.push((block, ll)),
        }
    }
    out
}

/// Whether a measurement kind is a GNSS measurement (the ones the
/// candidates are judged on; the aids are the vehicle's, not the IMU's).
fn is_gnss(kind: MeasurementKind) -> bool {
    matches!(
        kind,
        MeasurementKind::Pseudorange
            | MeasurementKind::PseudorangeRate
            | MeasurementKind::CarrierPhase
            | MeasurementKind::Position
            | MeasurementKind::Velocity
    )
}

/// Σ −½ (min(ν²/s², [`NIS_CAP`]) + ln s²) over the GNSS records with a
/// finite innovation and a positive predicted variance, and their number.
/// The constant −½ ln 2π per measurement is left out: every candidate
/// counts the same measurements.
pub fn gnss_log_likelihood(records: &[MeasurementRecord]) -> (f64, usize) {
    records
        .iter()
        .filter(|r| counts(r))
        .fold((0.0, 0), |(sum, n), r| {
            (sum + log_likelihood_term(r), n + 1)
        })
}

/// Whether a record counts towards the log-likelihood: a GNSS
/// measurement with a finite innovation and a positive predicted std.
fn counts(r: &MeasurementRecord) -> bool {
    is_gnss(r.kind) && r.innovation.is_finite() && r.innovation_std > 0.0
}

/// −½ (min(ν²/s², [`NIS_CAP`]) + ln s²) of one record.
fn log_likelihood_term(r: &MeasurementRecord) -> f64 {
    let nis = (r.innovation / r.innovation_std).powi(2);
    -0.5 * (nis.min(NIS_CAP) + 2.0 * r.innovation_std.ln())
}

/// The fixes' error correlation time from the position innovations of a
/// first pass run with the fixes inflated for a correlation time
/// `first_pass_s` (see the module docs). Each whitened component's
/// innovations (in units of the inflated σ) are paired at every lag of
/// whole fix intervals, the autocorrelation ρ(L) computed, and the
/// correlation time taken where ρ falls to ρ(1)/e (linearly
/// interpolated between lags; a lag-one value of 0.1 or less: white),
/// at most `first_pass_s`.
pub fn correlation_time_from_innovations(
    records: &[MeasurementRecord],
    first_pass_s: f64,
) -> FixCorrelation {
    let position: Vec<&MeasurementRecord> = records
        .iter()
        .filter(|r| r.kind == MeasurementKind::Position && r.innovation.is_finite())
        .collect();
    let mut times: Vec<f64> = position.iter().map(|r| r.time_s).collect();
    times.dedup();
    let interval_s = median_interval(&times);
    let mut component_s = [None; 3];
    let mut ratio = [f64::NAN; 3];
    let Some(dt) = interval_s else {
        return FixCorrelation {
            component_s,
            innovation_to_fix_variance: ratio,
            used_s: 0.0,
            covariance_scale: 1.0,
        };
    };
    // The inflation of the first pass: a fix's own variance is 1/k of
    // the whitened unit variance.
    let k = crate::gauss_markov::correlated_sample_inflation(first_pass_s, Some(dt));
    let max_lag = (first_pass_s / dt).ceil() as usize;
    for c in 0..3u16 {
        let series: Vec<(f64, f64)> = position
            .iter()
            .filter(|r| r.id == c)
            .map(|r| (r.time_s, r.innovation))
            .collect();
        if series.len() < MIN_FIXES {
            continue;
        }
        let x = robust_centred(&series);
        let variance = x.iter().map(|s| s.1 * s.1).sum::<f64>() / x.len() as f64;
        ratio[c as usize] = variance * k;
        if variance.is_nan()
            || variance <= 0.0
            || ratio[c as usize] > MAX_INNOVATION_TO_FIX_VARIANCE
        {
            continue;
        }
        component_s[c as usize] = Some(e_folding_time(&x, variance, dt, max_lag).min(first_pass_s));
    }
    let used_s = component_s.iter().flatten().copied().fold(0.0, f64::max);
    let covariance_scale = (0..3)
        .filter(|&c| component_s[c].is_some())
        .map(|c| ratio[c])
        .fold(1.0, f64::max);
    FixCorrelation {
        component_s,
        innovation_to_fix_variance: ratio,
        used_s,
        covariance_scale,
    }
}

/// `series` (time, value) less its median, each value clipped to
/// [`CLIP_SIGMAS`] robust standard deviations (1.4826 × the median
/// absolute deviation, the σ of a normal distribution; Huber & Ronchetti,
/// *Robust Statistics*, 2nd ed., §5.1): the innovations of the first fixes
/// after an outage or at the start, metres where the rest are decimetres,
/// would otherwise decide both the variance and the autocorrelation.
fn robust_centred(series: &[(f64, f64)]) -> Vec<(f64, f64)> {
    let median = |mut v: Vec<f64>| {
        let mid = v.len() / 2;
        *v.select_nth_unstable_by(mid, f64::total_cmp).1
    };
    let centre = median(series.iter().map(|s| s.1).collect());
    let sigma = 1.4826 * median(series.iter().map(|s| (s.1 - centre).abs()).collect());
    let bound = CLIP_SIGMAS * sigma;
    series
        .iter()
        .map(|&(t, v)| (t, (v - centre).clamp(-bound, bound)))
        .collect()
}

/// The median interval between consecutive times (None with fewer than
/// two, or no positive interval).
fn median_interval(times: &[f64]) -> Option<f64> {
    let mut d: Vec<f64> = times
        .windows(2)
        .map(|w| w[1] - w[0])
        .filter(|d| *d > 0.0)
        .collect();
    if d.is_empty() {
        return None;
    }
    let mid = d.len() / 2;
    d.select_nth_unstable_by(mid, f64::total_cmp);
    Some(d[mid])
}

/// The lag at which the autocorrelation of the zero-mean series `x`
/// (time, value; variance `variance`) falls to its lag-one value over e,
/// s: pairs at whole multiples of `dt` (within a quarter interval), lags
/// 1 to `max_lag`; the last lag when it never does, 0 when the lag-one
/// correlation is 0.1 or less.
fn e_folding_time(x: &[(f64, f64)], variance: f64, dt: f64, max_lag: usize) -> f64 {
    let acf = |lag: usize| -> Option<f64> {
        let target = lag as f64 * dt;
        let (mut sum, mut n, mut j) = (0.0, 0usize, 0usize);
        for i in 0..x.len() {
            j = j.max(i + 1);
            while j < x.len() && x[j].0 - x[i].0 < target - 0.25 * dt {
                j += 1;
            }
            if j < x.len() && (x[j].0 - x[i].0 - target).abs() <= 0.25 * dt {
                sum += x[i].1 * x[j].1;
                n += 1;
            }
        }
        (n >= 10).then(|| sum / (n as f64 * variance))
    };
    let Some(first) = acf(1) else { return 0.0 };
    if first <= 0.1 {
        return 0.0;
    }
    let threshold = first / std::f64::consts::E;
    let mut previous = (1usize, first);
    for lag in 2..=max_lag {
        let Some(rho) = acf(lag) else { break };
        if rho <= threshold {
            let (l0, r0) = previous;
            let frac = (r0 - threshold) / (r0 - rho);
            return (l0 as f64 + frac * (lag - l0) as f64) * dt;
        }
        previous = (lag, rho);
    }
    previous.0 as f64 * dt
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::coupling::MeasurementStatus;
    use crate::random::stream;
    use rand::Rng as _;
    use rand_distr::StandardNormal;

    fn record(time_s: f64, id: u16, innovation: f64, std: f64) -> MeasurementRecord {
        MeasurementRecord {
            time_s,
            id,
            kind: MeasurementKind::Position,
            innovation,
            innovation_std: std,
            nis: (innovation / std).powi(2),
            status: MeasurementStatus::Accepted,
        }
    }

    /// An AR(1) series of known correlation time, in the first pass's
    /// whitened units (its variance 1/k of the inflated unit): the
    /// e-folding time comes back within the estimate's spread; a white
    /// series gives 0; a series far larger than the fixes' own variance
    /// (dead-reckoning error) is not determined.
    #[test]
    fn the_correlation_time_of_an_ar1_series_comes_back() {
        let (dt, tau, n) = (1.0, 30.0, 20_000);
        let k = crate::gauss_markov::correlated_sample_inflation(
            FIRST_PASS_CORRELATION_TIME_S,
            Some(dt),
        );
        let rho: f64 = (-dt / tau).exp();
        let mut rng = stream(5, 0);
        let mut records = Vec::new();
        let mut x = [0.0f64; 3];
        for i in 0..n {
            for (c, xc) in x.iter_mut().enumerate() {
                let w: f64 = rng.sample(StandardNormal);
                *xc = rho * *xc + (1.0 - rho * rho).sqrt() * w;
                let scale = if c == 2 { 3.0 } else { 1.0 };
                records.push(record(i as f64 * dt, c as u16, scale * *xc / k.sqrt(), 1.0));
            }
        }
        let c = correlation_time_from_innovations(&records, FIRST_PASS_CORRELATION_TIME_S);
        for comp in 0..2 {
            let got = c.component_s[comp].expect("determined");
            assert!((got / tau - 1.0).abs() < 0.15, "{comp}: {got} vs {tau}");
            assert!((c.innovation_to_fix_variance[comp] - 1.0).abs() < 0.15);
        }
        // Nine times the fixes' variance: the dead reckoning's, not theirs.
        assert_eq!(c.component_s[2], None);
        assert!(
            (c.used_s - c.component_s[0].unwrap().max(c.component_s[1].unwrap())).abs() < 1e-12
        );
        // The determined components' variance matches the fixes' own:
        // a scale near 1, never below.
        assert!(c.covariance_scale >= 1.0 && c.covariance_scale < 1.15);
        let white: Vec<MeasurementRecord> = (0..n)
            .map(|i| {
                record(
                    i as f64,
                    0,
                    rng.sample::<f64, _>(StandardNormal) / k.sqrt(),
                    1.0,
                )
            })
            .collect();
        let c = correlation_time_from_innovations(&white, FIRST_PASS_CORRELATION_TIME_S);
        assert_eq!(c.component_s[0], Some(0.0));
        assert_eq!(c.used_s, 0.0);
        // Fixes erring 1.3 times what their σ says (in std): their
        // covariance scaled by 1.69. At 1.5 times (2.25 in variance, beyond
        // MAX_INNOVATION_TO_FIX_VARIANCE) the innovations are taken for the
        // dead reckoning's: not determined, nothing scaled.
        let scaled = |factor: f64| {
            let records: Vec<MeasurementRecord> = white
                .iter()
                .map(|r| MeasurementRecord {
                    innovation: factor * r.innovation,
                    ..*r
                })
                .collect();
            correlation_time_from_innovations(&records, FIRST_PASS_CORRELATION_TIME_S)
        };
        let c = scaled(1.3);
        assert!(
            (c.covariance_scale / 1.69 - 1.0).abs() < 0.05,
            "{}",
            c.covariance_scale
        );
        let c = scaled(1.5);
        assert_eq!((c.component_s[0], c.covariance_scale), (None, 1.0));
    }

    /// Another grade is chosen only on evidence that holds over the log: a
    /// gain of 2 per block over 20 blocks (spread 1) is; the same total
    /// gain from one block, or from 5 blocks, is not; a gain under the
    /// total threshold is not.
    #[test]
    fn another_grade_needs_evidence_that_holds_over_the_log() {
        let candidate = |preset: &str, log_likelihood: f64| ImuCandidate {
            preset: preset.into(),
            log_likelihood,
            measurements: 1000,
            resets: 0,
        };
        let default_blocks: Vec<(i64, f64)> = (0..20).map(|b| (b, -100.0)).collect();
        let spread = |b: i64| if b % 2 == 0 { 1.0 } else { -1.0 };
        let steady: Vec<(i64, f64)> = (0..20).map(|b| (b, -98.0 + spread(b))).collect();
        let one_block: Vec<(i64, f64)> = (0..20)
            .map(|b| (b, if b == 7 { -60.0 } else { -100.0 + spread(b) }))
            .collect();
        let scored = [
            candidate("consumer", -2000.0),
            candidate("industrial", -1960.0),
        ];
        assert_eq!(
            most_likely(&scored, &[default_blocks.clone(), steady.clone()]),
            1
        );
        assert_eq!(
            most_likely(&scored, &[default_blocks.clone(), one_block]),
            0
        );
        let short = [default_blocks[..5].to_vec(), steady[..5].to_vec()];
        assert_eq!(most_likely(&scored, &short), 0);
        let close = [
            candidate("consumer", -2000.0),
            candidate("industrial", -1996.0),
        ];
        assert_eq!(most_likely(&close, &[default_blocks, steady]), 0);
    }

    /// The log-likelihood against the Gaussian density written out, with
    /// the cap, and only GNSS kinds counted.
    #[test]
    fn the_log_likelihood_is_the_gaussian_one_capped() {
        let mut r = vec![record(0.0, 0, 0.5, 2.0), record(1.0, 1, 30.0, 1.0)];
        r.push(MeasurementRecord {
            kind: MeasurementKind::ZeroVelocity,
            ..record(2.0, 0, 100.0, 1.0)
        });
        let (ll, n) = gnss_log_likelihood(&r);
        assert_eq!(n, 2);
        let expected = -0.5 * ((0.5f64 / 2.0).powi(2) + 2.0 * 2f64.ln()) - 0.5 * NIS_CAP;
        assert!((ll - expected).abs() < 1e-12, "{ll} vs {expected}");
    }
}
