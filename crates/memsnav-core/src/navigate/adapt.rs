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
//!    per [`EVIDENCE_BLOCK_S`] block that holds by Wilcoxon's signed-rank
//!    test at [`MAX_EVIDENCE_P`] over at least [`MIN_EVIDENCE_BLOCKS`]
//!    blocks (a short walk whose few hundred correlated pseudoranges
//!    slightly prefer another grade keeps the default). The candidates are drawn from the
//!    presets a user would otherwise choose by hand; the choice never
//!    leaves them.
//! 2. **The fixes' error model** (`[gnss] fix_error_states = "auto"`,
//!    loose coupling, the default): in a pass with the IMU model chosen
//!    each fix's covariance is inflated as if its errors were correlated
//!    over [`FIRST_PASS_CORRELATION_TIME_S`] (the longest the method
//!    reports), so the filter follows the fixes slowly and its position
//!    innovations are the fixes' own errors less a slow average of them.
//!    Their autocorrelation over the fix epochs, for each of the three
//!    whitened components, falls to 1/e of its lag-one value after the
//!    correlation time ([`correlation_time_from_innovations`]); the
//!    longest of the components is kept. The reading is valid only where
//!    the fixes' errors make a good part of the innovations: a component
//!    whose (robust) innovation variance is more than
//!    [`MAX_INNOVATION_TO_FIX_VARIANCE`] times the fixes' own (the dead
//!    reckoning between fixes erring more than the fixes, as with RTK) is
//!    not determined, and with none determined the fixes stay white.
//!    The same innovations bound the fixes' error variance: the first
//!    pass barely follows them, so their variance is the fixes' error
//!    variance plus the dead reckoning's, a ratio to what the receiver
//!    reports (innovation-based covariance matching, Mohamed & Schwarz,
//!    J. Geodesy 73, 1999, with the dead reckoning's share taken as zero:
//!    an upper bound; a receiver's accuracy estimate is often optimistic).
//!    A correlated error is then modelled as it is: first-order
//!    Gauss-Markov states of the fixes' position error
//!    ([`RangeBiasModel`], the fix-error states) with the correlation
//!    time read off and a steady-state variance of the ratio (at least 1)
//!    times the fixes' typical variance, the receiver's own covariance
//!    staying as the white part. States, not an inflation of each fix's
//!    covariance: a smoother's forward and backward passes both see one
//!    slow error, and only as a state do they share it instead of
//!    averaging it twice (with the inflation, the smoothed bounds at the
//!    foreign drive's standstills held 0.78-0.85 of the errors; with the
//!    states 0.96-1.00: docs/results/foreign-drive.md).
//!
//! The run that is reported is a last pass with what was learnt; the
//! learning passes keep no solution, only their measurement records.

use rayon::prelude::*;

use crate::coupling::{
    FilterTuning, MeasurementKind, MeasurementRecord, PositionFix, RangeBiasModel,
};
use crate::filter::chi_square::normal_quantile;
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

/// ... and gain by Wilcoxon's signed-rank test at this one-sided level
/// (the batch sums of a correlated series are nearly independent: Law &
/// Kelton, *Simulation Modeling and Analysis*, §9.5.3; the innovations of
/// one slow error are not independent evidence, a minute apart they
/// nearly are). A rank test, not the blocks' mean over its standard
/// error: one block that gains much (a reset, a turn after a coast)
/// neither decides alone nor, by its spread, hides a gain every other
/// block shows. 0.00135: a normal mean's 3σ.
pub const MAX_EVIDENCE_P: f64 = 0.00135;

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

/// The fixes' error correlation read off the first pass.
#[derive(Debug, Clone, PartialEq)]
pub struct FixCorrelation {
    /// Per whitened component (in the order of the fixes' covariance
    /// factor: about north, east, down): the correlation time, s, or None
    /// where not determined.
    pub component_s: [Option<f64>; 3],
    /// Per component: the innovation variance over the fixes' own (the
    /// test of [`MAX_INNOVATION_TO_FIX_VARIANCE`]).
    pub innovation_to_fix_variance: [f64; 3],
    /// The longest determined correlation time, s (0: white, no states).
    pub correlation_time_s: f64,
    /// The largest variance ratio of a determined component, at least 1:
    /// the fixes' error variance over what the receiver reports.
    pub variance_ratio: f64,
}

/// One candidate std of the non-holonomic constraint and how likely the
/// log's GNSS measurements are under it.
#[derive(Debug, Clone, PartialEq)]
pub struct NhcCandidate {
    /// The constraint's std, m/s.
    pub std_m_s: f64,
    /// Σ −½ (min(ν²/s², [`NIS_CAP`]) + ln s²) over the GNSS measurements.
    pub log_likelihood: f64,
    /// The scalar GNSS measurements it counts.
    pub measurements: usize,
    /// The resets the candidate's first pass made.
    pub resets: usize,
}

/// What a run learnt from its log.
#[derive(Debug, Clone, PartialEq, Default)]
pub struct Adaptation {
    /// The IMU candidates, in [`IMU_CANDIDATES`] order (empty when the
    /// configuration names its IMU).
    pub imu_candidates: Vec<ImuCandidate>,
    /// The preset of the tuning the run used, when it was chosen.
    pub imu_preset: Option<String>,
    /// The non-holonomic constraint's candidate stds (empty when the
    /// configuration gives its std or has no constraint).
    pub nhc_candidates: Vec<NhcCandidate>,
    /// The constraint's std the run used, m/s, when it was chosen.
    pub nhc_std_m_s: Option<f64>,
    /// The fixes' error correlation, when it was learnt.
    pub fix_correlation: Option<FixCorrelation>,
    /// The fix-error states learnt from it (None: the fixes stay white).
    pub fix_error: Option<RangeBiasModel>,
}

/// What one pass over the log runs with.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct PassModel {
    /// The filter's tuning.
    pub tuning: FilterTuning,
    /// The non-holonomic constraint's std, m/s (used when the
    /// configuration applies the constraint).
    pub nhc_std_m_s: f64,
    /// The fixes' error states (None: none).
    pub fix_error: Option<RangeBiasModel>,
}

/// The non-holonomic constraint's candidate stds, as factors on the
/// configured one (the first, the default, is kept without evidence). A
/// vehicle's lateral and vertical velocity is not zero: the wheels slip,
/// the suspension and the road's camber move the body, and a mounting the
/// installation states have not yet found leaves a slow part; how much
/// differs from car to car, and the GNSS measurements tell (a std too
/// tight for the vehicle bends the height and the cross-track position
/// away from the fixes between them, one too loose lets them drift).
pub const NHC_STD_FACTORS: [f64; 3] = [1.0, 2.0, 4.0];

/// What to learn: the candidate tunings (one: nothing to choose), whether
/// to choose the non-holonomic constraint's std, and whether to learn the
/// fixes' error model.
pub struct Plan<'a> {
    /// (preset name, tuning); the first is used when there is one.
    pub candidates: &'a [(String, FilterTuning)],
    /// The rest of the model every pass starts from: the configured
    /// constraint's std and fix-error states.
    pub nhc_std_m_s: f64,
    /// The configured fix-error states (None: none).
    pub fix_error: Option<RangeBiasModel>,
    /// Choose the constraint's std among [`NHC_STD_FACTORS`] times the
    /// configured one.
    pub learn_nhc_std: bool,
    /// Learn the fixes' error model (loose coupling): the fixes' typical
    /// position std, m (the median of √(trace/3) of their covariances),
    /// which the learnt variance ratio scales.
    pub fix_typical_std_m: Option<f64>,
}

/// A first pass: the run of a model, returning its measurement records
/// and the number of resets it made.
pub type FirstPass<'a> = dyn Fn(&PassModel) -> Result<(Vec<MeasurementRecord>, usize)> + Sync + 'a;

/// How one candidate's first pass scored.
struct Scored {
    log_likelihood: f64,
    measurements: usize,
    resets: usize,
}

/// Each model's first pass (in parallel: they are independent) scored,
/// and the index of the most likely ([`most_likely`]: the first without
/// strong evidence).
fn choose(models: &[PassModel], first_pass: &FirstPass<'_>) -> Result<(usize, Vec<Scored>)> {
    let passes: Vec<(Vec<MeasurementRecord>, usize)> =
        models.par_iter().map(first_pass).collect::<Result<_>>()?;
    let scored: Vec<Scored> = passes
        .iter()
        .map(|(records, resets)| {
            let (log_likelihood, measurements) = gnss_log_likelihood(records);
            Scored {
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
    let likelihoods: Vec<f64> = scored.iter().map(|s| s.log_likelihood).collect();
    Ok((most_likely(&likelihoods, &blocks), scored))
}

impl Plan<'_> {
    /// The model of the run to report and what was learnt, in turn: the
    /// IMU candidates on the fixes as the receiver reports them (the
    /// measurements every candidate would face without learning), the
    /// constraint's std with the IMU chosen, each the most likely of its
    /// candidates; then the fixes' error model read off a pass with both
    /// ([`Adaptation::fix_error`]). Nothing to learn: the configured
    /// model, no first pass.
    pub fn learn(&self, first_pass: &FirstPass<'_>) -> Result<(PassModel, Adaptation)> {
        let mut adaptation = Adaptation::default();
        let mut model = PassModel {
            tuning: self.candidates[0].1,
            nhc_std_m_s: self.nhc_std_m_s,
            fix_error: self.fix_error,
        };
        if self.candidates.len() > 1 {
            let models: Vec<PassModel> = self
                .candidates
                .iter()
                .map(|(_, tuning)| PassModel {
                    tuning: *tuning,
                    ..model
                })
                .collect();
            let (best, scored) = choose(&models, first_pass)?;
            model = models[best];
            adaptation.imu_preset = Some(self.candidates[best].0.clone());
            adaptation.imu_candidates = self
                .candidates
                .iter()
                .zip(scored)
                .map(|((preset, _), s)| ImuCandidate {
                    preset: preset.clone(),
                    log_likelihood: s.log_likelihood,
                    measurements: s.measurements,
                    resets: s.resets,
                })
                .collect();
        }
        if self.learn_nhc_std {
            let models: Vec<PassModel> = NHC_STD_FACTORS
                .iter()
                .map(|k| PassModel {
                    nhc_std_m_s: k * self.nhc_std_m_s,
                    ..model
                })
                .collect();
            let (best, scored) = choose(&models, first_pass)?;
            model = models[best];
            adaptation.nhc_std_m_s = Some(model.nhc_std_m_s);
            adaptation.nhc_candidates = models
                .iter()
                .zip(scored)
                .map(|(m, s)| NhcCandidate {
                    std_m_s: m.nhc_std_m_s,
                    log_likelihood: s.log_likelihood,
                    measurements: s.measurements,
                    resets: s.resets,
                })
                .collect();
        }
        if let Some(typical_std_m) = self.fix_typical_std_m {
            // With the IMU model chosen, a pass that follows the fixes
            // slowly shows their errors in its innovations.
            let mut slow = model;
            slow.tuning.fix_correlation_time_s = FIRST_PASS_CORRELATION_TIME_S;
            let (records, _) = first_pass(&slow)?;
            let c = correlation_time_from_innovations(&records, FIRST_PASS_CORRELATION_TIME_S);
            adaptation.fix_error = (c.correlation_time_s > 0.0).then(|| RangeBiasModel {
                std_m: typical_std_m * c.variance_ratio.sqrt(),
                correlation_time_s: c.correlation_time_s,
            });
            model.fix_error = adaptation.fix_error;
            adaptation.fix_correlation = Some(c);
        }
        Ok((model, adaptation))
    }
}

/// The fixes' typical position std, m: the median over the fixes the run
/// uses (`used`, one flag per fix) of √(trace/3) of their position
/// covariance (None without one). A median, not a mean: the few fixes a
/// receiver flags with metres (the first after a tunnel) do not set the
/// scale of the rest.
pub fn typical_position_std_m(fixes: &[PositionFix], used: &[bool]) -> Option<f64> {
    let mut stds: Vec<f64> = fixes
        .iter()
        .zip(used)
        .filter(|(_, &u)| u)
        .map(|(f, _)| (f.position_covariance.trace() / 3.0).sqrt())
        .filter(|s| s.is_finite() && *s > 0.0)
        .collect();
    if stds.is_empty() {
        return None;
    }
    let mid = stds.len() / 2;
    Some(*stds.select_nth_unstable_by(mid, f64::total_cmp).1)
}

/// The candidate to keep: the most likely (`log_likelihoods`), when it
/// beats the first (the default) by [`MIN_LOG_LIKELIHOOD_GAIN`] in all and
/// by block gains that hold by the signed-rank test
/// ([`signed_rank_gain_holds`]) over at least [`MIN_EVIDENCE_BLOCKS`]
/// blocks; the first otherwise. `blocks`: each candidate's log-likelihood per block
/// ([`block_log_likelihoods`]).
fn most_likely(log_likelihoods: &[f64], blocks: &[Vec<(i64, f64)>]) -> usize {
    let best = log_likelihoods
        .iter()
        .enumerate()
        .max_by(|a, b| a.1.total_cmp(b.1))
        .map_or(0, |(i, _)| i);
    if best == 0 || log_likelihoods[best] - log_likelihoods[0] <= MIN_LOG_LIKELIHOOD_GAIN {
        return 0;
    }
    let default: std::collections::HashMap<i64, f64> = blocks[0].iter().copied().collect();
    let gains: Vec<f64> = blocks[best]
        .iter()
        .filter_map(|(b, ll)| default.get(b).map(|d| ll - d))
        .collect();
    if gains.len() < MIN_EVIDENCE_BLOCKS {
        return 0;
    }
    if signed_rank_gain_holds(&gains) {
        best
    } else {
        0
    }
}

/// Whether `gains` show a gain by Wilcoxon's signed-rank test, one-sided
/// at [`MAX_EVIDENCE_P`]: W⁺, the sum of the ranks of |gain| over the
/// positive gains (zero gains left out, ties given their mean rank), is
/// improbably large were each gain's sign a fair coin (Hollander & Wolfe,
/// *Nonparametric Statistical Methods*, §3.1). The exact distribution
/// ([`signed_rank_p`]) up to [`EXACT_SIGNED_RANK_MAX_N`] gains, the normal
/// approximation, (W⁺ − n(n+1)/4) / √(n(n+1)(2n+1)/24), beyond.
fn signed_rank_gain_holds(gains: &[f64]) -> bool {
    let (double_ranks, double_w_plus) = signed_ranks(gains);
    let n = double_ranks.len();
    if n == 0 {
        return false;
    }
    if n <= EXACT_SIGNED_RANK_MAX_N {
        return signed_rank_p(&double_ranks, double_w_plus) < MAX_EVIDENCE_P;
    }
    let nf = n as f64;
    let z = (double_w_plus as f64 / 2.0 - nf * (nf + 1.0) / 4.0)
        / (nf * (nf + 1.0) * (2.0 * nf + 1.0) / 24.0).sqrt();
    z > normal_quantile(1.0 - MAX_EVIDENCE_P)
}

/// Twice the ranks of |gain| over the non-zero gains (mean ranks of ties
/// are then whole numbers), and twice W⁺.
fn signed_ranks(gains: &[f64]) -> (Vec<usize>, usize) {
    let mut by_size: Vec<f64> = gains.iter().copied().filter(|g| *g != 0.0).collect();
    by_size.sort_by(|a, b| a.abs().total_cmp(&b.abs()));
    let n = by_size.len();
    let mut double_ranks = vec![0usize; n];
    let mut i = 0;
    while i < n {
        let mut j = i + 1;
        while j < n && by_size[j].abs() == by_size[i].abs() {
            j += 1;
        }
        double_ranks[i..j].fill(i + 1 + j);
        i = j;
    }
    let double_w_plus = (0..n)
        .filter(|&k| by_size[k] > 0.0)
        .map(|k| double_ranks[k])
        .sum();
    (double_ranks, double_w_plus)
}

/// P(W⁺ ≥ observed) over the 2ⁿ equally likely signs of the ranks
/// (doubled, as [`signed_ranks`] gives them): the distribution of 2W⁺
/// built one rank at a time.
fn signed_rank_p(double_ranks: &[usize], double_w_plus: usize) -> f64 {
    let total: usize = double_ranks.iter().sum();
    let mut p = vec![0.0; total + 1];
    p[0] = 1.0;
    let mut reach = 0;
    for &r in double_ranks {
        for s in (0..=reach).rev() {
            p[s + r] += 0.5 * p[s];
            p[s] *= 0.5;
        }
        reach += r;
    }
    p[double_w_plus.min(total + 1)..].iter().sum()
}

/// Gains up to which [`signed_rank_gain_holds`] is exact (n · n(n+1) steps).
const EXACT_SIGNED_RANK_MAX_N: usize = 100;

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
            correlation_time_s: 0.0,
            variance_ratio: 1.0,
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
    let correlation_time_s = component_s.iter().flatten().copied().fold(0.0, f64::max);
    let variance_ratio = (0..3)
        .filter(|&c| component_s[c].is_some())
        .map(|c| ratio[c])
        .fold(1.0, f64::max);
    FixCorrelation {
        component_s,
        innovation_to_fix_variance: ratio,
        correlation_time_s,
        variance_ratio,
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
            (c.correlation_time_s - c.component_s[0].unwrap().max(c.component_s[1].unwrap())).abs()
                < 1e-12
        );
        // The determined components' variance matches the fixes' own:
        // a scale near 1, never below.
        assert!(c.variance_ratio >= 1.0 && c.variance_ratio < 1.15);
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
        assert_eq!(c.correlation_time_s, 0.0);
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
            (c.variance_ratio / 1.69 - 1.0).abs() < 0.05,
            "{}",
            c.variance_ratio
        );
        let c = scaled(1.5);
        assert_eq!((c.component_s[0], c.variance_ratio), (None, 1.0));
    }

    /// Another grade is chosen only on evidence that holds over the log: a
    /// gain of 2 per block over 20 blocks (spread 1) is; the same total
    /// gain from one block, or from 5 blocks, is not; a gain under the
    /// total threshold is not.
    #[test]
    fn another_grade_needs_evidence_that_holds_over_the_log() {
        let default_blocks: Vec<(i64, f64)> = (0..20).map(|b| (b, -100.0)).collect();
        let spread = |b: i64| if b % 2 == 0 { 1.0 } else { -1.0 };
        let steady: Vec<(i64, f64)> = (0..20).map(|b| (b, -98.0 + spread(b))).collect();
        let one_block: Vec<(i64, f64)> = (0..20)
            .map(|b| (b, if b == 7 { -60.0 } else { -100.0 + spread(b) }))
            .collect();
        let scored = [-2000.0, -1960.0];
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
        let close = [-2000.0, -1996.0];
        assert_eq!(most_likely(&close, &[default_blocks, steady]), 0);
    }

    /// The signed-rank test against values written out by hand and by
    /// scipy (`scipy.stats.wilcoxon(g, alternative="greater",
    /// method="exact")`): all four positive, P = 1/16; ten positive, P =
    /// 1/1024, which holds at 0.00135 (the normal approximation, z = 2.80,
    /// would not); a tie of |−1| and |1| shares rank 1.5: P(W⁺ ≥ 4.5) =
    /// 3/8 (scipy: 0.375); a foreign-drive series of 21 non-zero block
    /// gains with one of +66 holds (P = 0.000113 with its tied gains at
    /// their mean ranks, scipy's exact 0.000121 ranking them apart), where
    /// the blocks' mean over its standard error is 1.88.
    #[test]
    fn the_signed_rank_test_is_wilcoxons() {
        let p = |g: &[f64]| {
            let (r, w) = signed_ranks(g);
            signed_rank_p(&r, w)
        };
        let close = |a: f64, b: f64| (a - b).abs() < 1e-9;
        assert!(close(p(&[1.0, 2.0, 3.0, 4.0]), 1.0 / 16.0));
        let ten: Vec<f64> = (1..=10).map(f64::from).collect();
        assert!(close(p(&ten), 1.0 / 1024.0));
        assert!(signed_rank_gain_holds(&ten));
        assert!(!signed_rank_gain_holds(&ten[..9]));
        assert!(close(p(&[-1.0, 1.0, 2.0, 0.0]), 3.0 / 8.0));
        let blocks = [
            0., 0., 1.8, 5.2, 66.2, 3.7, 2.8, 5.8, 6.1, 3.7, 4.7, -3.6, 4.1, 4.2, -1.1, 9.4, 2.2,
            1.8, 1., -0.3, 2.8, 1.8, -0.2,
        ];
        assert!((p(&blocks) - 0.000_113_487).abs() < 1e-9, "{}", p(&blocks));
        assert!(signed_rank_gain_holds(&blocks));
        // Beyond the exact range: 150 gains, all positive, hold; signs
        // alternating with growing size do not.
        let many: Vec<f64> = (1..=150).map(f64::from).collect();
        assert!(signed_rank_gain_holds(&many));
        let alternating: Vec<f64> = many
            .iter()
            .enumerate()
            .map(|(i, g)| if i % 2 == 0 { *g } else { -g })
            .collect();
        assert!(!signed_rank_gain_holds(&alternating));
        assert!(!signed_rank_gain_holds(&[0.0, 0.0]));
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
