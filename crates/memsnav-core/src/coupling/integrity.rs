//! The integrity of a run: whether the solution and its
//! covariance can be trusted, judged from what the filter itself recorded.
//! Four signals, each an [`IntegrityAlert`] that marks the run diverged:
//!
//! - **Gated batches**: a quarter of the GNSS batches (at least 10, over
//!   10 s or more) failed their chi-square gate: the filter no longer
//!   accepts its aiding.
//! - **Inconsistent innovations**: the innovations of one GNSS kind,
//!   summed over a window of [`WINDOW_S`], exceed the upper edge of their
//!   chi-square band (probability [`BAND_PROBABILITY`] for the window's
//!   degrees of freedom; Bar-Shalom et al. 2001 §5.4 on the time-averaged
//!   NIS test) by more than [`DIVERGED_BAND_RATIO`] in two windows in a
//!   row: the innovations are twice their predicted std or more, for a
//!   minute. A window just above its band (ratio 1-4) is a mismatch of the
//!   tuning, not a divergence: it is counted in [`KindConsistency`] and
//!   reported, not alerted (the drive_0708 example's 4 Hz RTK velocities,
//!   whose errors are correlated in time, reach 1.8).
//! - **Beyond the linear model**: through a whole window every pseudorange
//!   batch had a [`BatchRecord::nonlinearity`] above [`NONLINEARITY_LIMIT`]:
//!   the position is so uncertain across the lines of sight that the
//!   pseudorange's curvature, which the filter's first-order model drops,
//!   is a tenth of its noise or more. With 1-2 satellites a MEMS drifts
//!   there within minutes (kilometres across the lines of sight); from then
//!   on no linearised filter keeps its covariance honest, and the innovations
//!   cannot show it, since with so few satellites they see nothing of the
//!   unobserved directions (docs/explanation/few-satellites.md).
//! - **Applied outliers**: a GNSS batch was applied although its NIS was
//!   beyond the chi-square quantile of probability [`OUTLIER_PROBABILITY`]
//!   (one consistent batch in 10⁹ gets there): with the gate off
//!   (`gate_probability = 1`) nothing else stops it, and a single 10⁹ m
//!   fix or pseudorange used to move the solution by kilometres with no
//!   word. With the gate on, every applied batch is within a
//!   lower quantile and this never fires.

use super::records::{BatchRecord, MeasurementKind, RunRecords};
use crate::filter::chi_square::chi_square_quantile;
use crate::text::number;

/// Length of the windows the innovations are summed over, s.
pub const WINDOW_S: f64 = 30.0;
/// Probability of the chi-square band a window's summed NIS is tested
/// against (its upper edge): a consistent filter exceeds it in one window
/// of 10 000.
pub const BAND_PROBABILITY: f64 = 0.9999;
/// Summed NIS over the band's upper edge beyond which, in two windows in
/// a row, the innovations count as inconsistent.
pub const DIVERGED_BAND_RATIO: f64 = 4.0;
/// Largest pseudorange nonlinearity the first-order model is trusted at
/// (the expected curvature term in units of the measurement std).
pub const NONLINEARITY_LIMIT: f64 = 0.1;
/// Share of GNSS batches that may fail their gate before a run counts as
/// divergent (a consistent filter fails 1 − gate probability of them).
pub const DIVERGENCE_REJECTED_SHARE: f64 = 0.25;
/// ... and how many at least, over how long at least (s).
pub const DIVERGENCE_MIN_REJECTED: usize = 10;
/// See [`DIVERGENCE_MIN_REJECTED`].
pub const DIVERGENCE_MIN_SPAN_S: f64 = 10.0;
/// Tail probability beyond which an applied batch is an outlier.
pub const OUTLIER_PROBABILITY: f64 = 1.0 - 1e-9;
/// Fewest pseudorange batches a window needs to judge the nonlinearity.
const MIN_BATCHES_FOR_NONLINEARITY: usize = 5;

/// The GNSS kinds whose innovations test the solution.
const GNSS_KINDS: [MeasurementKind; 4] = [
    MeasurementKind::Pseudorange,
    MeasurementKind::PseudorangeRate,
    MeasurementKind::Position,
    MeasurementKind::Velocity,
];

/// How the innovations of one kind sat in their chi-square band.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct KindConsistency {
    /// The measurement kind.
    pub kind: MeasurementKind,
    /// Windows with at least one batch.
    pub windows: usize,
    /// Windows whose summed NIS exceeded the band's upper edge.
    pub above_band: usize,
    /// The largest summed NIS over the band's upper edge, and the start of
    /// its window (s).
    pub max_band_ratio: f64,
    /// The start of the window with the largest ratio, s.
    pub max_at_s: f64,
}

/// Something that makes the solution untrustworthy (module docs).
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum IntegrityAlert {
    /// Too many GNSS batches failed their gate.
    GatedBatches {
        /// Time of the first failed batch, s.
        first_s: f64,
        /// Time of the last failed batch, s.
        last_s: f64,
        /// Batches that failed their gate.
        rejected: usize,
        /// Batches tested.
        total: usize,
        /// Median NIS over the gate of the failed batches.
        median_ratio: f64,
    },
    /// The innovations of `kind` were far above their band in the window
    /// starting at `time_s` and the next.
    InconsistentInnovations {
        /// The measurement kind.
        kind: MeasurementKind,
        /// The start of the first of the two windows, s.
        time_s: f64,
        /// The second window's summed NIS over the band's upper edge.
        band_ratio: f64,
    },
    /// From `time_s` on the pseudoranges' curvature over the position
    /// uncertainty stayed above [`NONLINEARITY_LIMIT`] (`nonlinearity`: the
    /// smallest of the window).
    BeyondLinearModel {
        /// The start of the span, s.
        time_s: f64,
        /// The smallest expected curvature over the measurement std in the window.
        nonlinearity: f64,
    },
    /// `count` GNSS batches were applied with a NIS beyond the quantile of
    /// [`OUTLIER_PROBABILITY`], the first (of `kind`) at `time_s` with
    /// `ratio` times that quantile.
    AppliedOutliers {
        /// The kind of the first outlier applied.
        kind: MeasurementKind,
        /// Time of the first outlier applied, s.
        time_s: f64,
        /// Its NIS over the outlier quantile.
        ratio: f64,
        /// How many batches were applied beyond the quantile.
        count: usize,
    },
}

impl IntegrityAlert {
    /// When it was first seen, s.
    pub fn time_s(&self) -> f64 {
        match *self {
            IntegrityAlert::GatedBatches { first_s, .. } => first_s,
            IntegrityAlert::InconsistentInnovations { time_s, .. }
            | IntegrityAlert::BeyondLinearModel { time_s, .. }
            | IntegrityAlert::AppliedOutliers { time_s, .. } => time_s,
        }
    }

    /// A short name: `gated_batches`, `inconsistent_innovations`,
    /// `beyond_linear_model`, `applied_outliers`.
    pub fn name(&self) -> &'static str {
        match self {
            IntegrityAlert::GatedBatches { .. } => "gated_batches",
            IntegrityAlert::InconsistentInnovations { .. } => "inconsistent_innovations",
            IntegrityAlert::BeyondLinearModel { .. } => "beyond_linear_model",
            IntegrityAlert::AppliedOutliers { .. } => "applied_outliers",
        }
    }

    /// The sentence a user reads: what was seen, and what it means.
    pub fn message(&self) -> String {
        match *self {
            IntegrityAlert::GatedBatches {
                first_s,
                last_s,
                rejected,
                total,
                median_ratio,
            } => format!(
                "the filter diverged from its GNSS aiding: {rejected} of {total} GNSS batches ({:.0} %) failed their chi-square gate between t = {first_s:.1} s and {last_s:.1} s (median NIS {} times the gate): the solution and its covariance are not trustworthy; check the GNSS input (offsets, outliers, units) and the IMU units",
                100.0 * rejected as f64 / total as f64,
                number(median_ratio, 3)
            ),
            IntegrityAlert::InconsistentInnovations {
                kind,
                time_s,
                band_ratio,
            } => format!(
                "the filter is inconsistent with its {} measurements from t = {time_s:.1} s: their NIS summed over {WINDOW_S:.0} s was {band_ratio:.1} times the upper edge of its chi-square band ({BAND_PROBABILITY}) for two windows in a row, so the errors are larger than the covariance says: the solution and its covariance are not trustworthy",
                kind.name()
            ),
            IntegrityAlert::BeyondLinearModel {
                time_s,
                nonlinearity,
            } => format!(
                "from t = {time_s:.1} s the position is too uncertain across the satellites' lines of sight for the filter's first-order pseudorange model: the expected curvature term was {nonlinearity:.2} of the measurement noise or more for {WINDOW_S:.0} s (limit {NONLINEARITY_LIMIT}); with this few satellites the innovations cannot show the errors in the unobserved directions, and the covariance no longer bounds them: the solution is not trustworthy (docs/explanation/few-satellites.md)"
            ),
            IntegrityAlert::AppliedOutliers {
                kind,
                time_s,
                ratio,
                count,
            } => format!(
                "{count} GNSS batches were applied although their NIS was beyond the chi-square quantile of {OUTLIER_PROBABILITY} (the first, {} at t = {time_s:.1} s, {} times it): the gate let them through (gate_probability of 1, or above that quantile), so outliers moved the solution, which is not trustworthy; keep the gate on",
                kind.name(),
                number(ratio, 3)
            ),
        }
    }
}

/// The integrity of a run: the consistency of each GNSS kind's
/// innovations and the alerts.
#[derive(Debug, Clone, PartialEq, Default)]
pub struct Integrity {
    /// Per GNSS kind that has batches.
    pub consistency: Vec<KindConsistency>,
    /// In time order; any alert makes the run diverged.
    pub alerts: Vec<IntegrityAlert>,
}

impl Integrity {
    /// Whether the solution and its covariance are not trustworthy.
    pub fn diverged(&self) -> bool {
        !self.alerts.is_empty()
    }
}

impl RunRecords {
    /// The run's integrity ([`assess`] of its batches).
    pub fn integrity(&self) -> Integrity {
        assess(&self.batches)
    }
}

/// Judges a run from its batch records (in time order).
pub fn assess(batches: &[BatchRecord]) -> Integrity {
    let mut out = Integrity::default();
    out.alerts.extend(gated_batches(batches));
    out.alerts.extend(applied_outliers(batches));
    for kind in GNSS_KINDS {
        let of_kind: Vec<&BatchRecord> = batches.iter().filter(|b| b.kind == kind).collect();
        if of_kind.is_empty() {
            continue;
        }
        let (consistency, alert) = innovation_consistency(kind, &of_kind);
        out.consistency.push(consistency);
        out.alerts.extend(alert);
        if kind == MeasurementKind::Pseudorange {
            out.alerts.extend(beyond_linear_model(&of_kind));
        }
    }
    out.alerts.sort_by(|a, b| a.time_s().total_cmp(&b.time_s()));
    out
}

/// The batches grouped into consecutive windows of [`WINDOW_S`] from the
/// first one's time.
fn windows<'a>(
    batches: &'a [&'a BatchRecord],
) -> impl Iterator<Item = (f64, &'a [&'a BatchRecord])> {
    let t0 = batches[0].time_s;
    let index = move |b: &BatchRecord| ((b.time_s - t0) / WINDOW_S).floor();
    batches
        .chunk_by(move |a, b| index(a) == index(b))
        .map(move |w| (t0 + index(w[0]) * WINDOW_S, w))
}

fn innovation_consistency(
    kind: MeasurementKind,
    batches: &[&BatchRecord],
) -> (KindConsistency, Option<IntegrityAlert>) {
    let mut c = KindConsistency {
        kind,
        windows: 0,
        above_band: 0,
        max_band_ratio: 0.0,
        max_at_s: f64::NAN,
    };
    let mut alert = None;
    let mut previous_far: Option<f64> = None;
    for (start, w) in windows(batches) {
        let dof: usize = w.iter().map(|b| b.dof).sum();
        if dof == 0 {
            continue;
        }
        let nis: f64 = w.iter().map(|b| b.nis).filter(|v| v.is_finite()).sum();
        let ratio = nis / chi_square_quantile(dof as f64, BAND_PROBABILITY);
        c.windows += 1;
        c.above_band += usize::from(ratio > 1.0);
        if ratio > c.max_band_ratio {
            (c.max_band_ratio, c.max_at_s) = (ratio, start);
        }
        let far = ratio > DIVERGED_BAND_RATIO;
        if let (true, Some(first), None) = (far, previous_far, alert) {
            alert = Some(IntegrityAlert::InconsistentInnovations {
                kind,
                time_s: first,
                band_ratio: ratio,
            });
        }
        previous_far = far.then_some(start);
    }
    (c, alert)
}

fn beyond_linear_model(pseudoranges: &[&BatchRecord]) -> Option<IntegrityAlert> {
    windows(pseudoranges).find_map(|(start, w)| {
        // NaN: nothing noted (no usable satellite): linear, as far as known.
        let smallest = w
            .iter()
            .map(|b| {
                if b.nonlinearity.is_nan() {
                    0.0
                } else {
                    b.nonlinearity
                }
            })
            .fold(f64::INFINITY, f64::min);
        (w.len() >= MIN_BATCHES_FOR_NONLINEARITY && smallest > NONLINEARITY_LIMIT).then_some(
            IntegrityAlert::BeyondLinearModel {
                time_s: start,
                nonlinearity: smallest,
            },
        )
    })
}

/// The applied-outliers alert (module docs): batches applied by a gate
/// whose threshold was at or beyond the outlier quantile, with a NIS
/// beyond it.
fn applied_outliers(batches: &[BatchRecord]) -> Option<IntegrityAlert> {
    let quantile = |b: &BatchRecord| chi_square_quantile(b.dof as f64, OUTLIER_PROBABILITY);
    let ratio = |b: &BatchRecord| b.nis / quantile(b);
    let mut outliers = batches.iter().filter(|b| {
        GNSS_KINDS.contains(&b.kind)
            && b.accepted
            && b.dof > 0
            && b.threshold >= quantile(b)
            && ratio(b) > 1.0
    });
    let first = outliers.next()?;
    Some(IntegrityAlert::AppliedOutliers {
        kind: first.kind,
        time_s: first.time_s,
        ratio: ratio(first),
        count: 1 + outliers.count(),
    })
}

/// The gated-batches alert (module docs).
fn gated_batches(batches: &[BatchRecord]) -> Option<IntegrityAlert> {
    let gnss: Vec<&BatchRecord> = batches
        .iter()
        .filter(|b| GNSS_KINDS.contains(&b.kind))
        .collect();
    let rejected: Vec<&&BatchRecord> = gnss.iter().filter(|b| !b.accepted).collect();
    let (first, last) = (rejected.first()?, rejected.last()?);
    let share = rejected.len() as f64 / gnss.len() as f64;
    if share < DIVERGENCE_REJECTED_SHARE
        || rejected.len() < DIVERGENCE_MIN_REJECTED
        || last.time_s - first.time_s < DIVERGENCE_MIN_SPAN_S
    {
        return None;
    }
    let mut ratios: Vec<f64> = rejected
        .iter()
        .map(|b| b.nis / b.threshold)
        .filter(|r| r.is_finite())
        .collect();
    ratios.sort_by(f64::total_cmp);
    Some(IntegrityAlert::GatedBatches {
        first_s: first.time_s,
        last_s: last.time_s,
        rejected: rejected.len(),
        total: gnss.len(),
        median_ratio: ratios.get(ratios.len() / 2).copied().unwrap_or(f64::NAN),
    })
}

#[cfg(test)]
mod tests {
    use super::*;

    fn batch(t: f64, kind: MeasurementKind, nis: f64, dof: usize, accepted: bool) -> BatchRecord {
        BatchRecord {
            time_s: t,
            kind,
            nis,
            dof,
            threshold: chi_square_quantile(dof as f64, 0.999),
            excluded: 0,
            accepted,
            nonlinearity: f64::NAN,
        }
    }

    /// Batches of `dof` whose NIS is the chi-square mean times `scale`,
    /// one per second over `seconds`.
    fn series(kind: MeasurementKind, scale: f64, seconds: usize) -> Vec<BatchRecord> {
        (0..seconds)
            .map(|k| batch(k as f64, kind, 6.0 * scale, 6, true))
            .collect()
    }

    #[test]
    fn consistent_innovations_raise_nothing() {
        let i = assess(&series(MeasurementKind::Pseudorange, 1.0, 300));
        assert!(!i.diverged(), "{:?}", i.alerts);
        let c = i.consistency[0];
        assert_eq!((c.windows, c.above_band), (10, 0));
        assert!(
            (c.max_band_ratio - 180.0 / chi_square_quantile(180.0, BAND_PROBABILITY)).abs() < 1e-12
        );
    }

    /// Innovations twice their predicted variance: above the band, counted,
    /// no alert (a tuning mismatch); ten times: an alert at the first of
    /// the two windows, with its ratio.
    #[test]
    fn the_band_ratio_separates_mismatch_from_divergence() {
        let i = assess(&series(MeasurementKind::Velocity, 2.0, 300));
        assert!(!i.diverged());
        assert_eq!(i.consistency[0].above_band, 10);
        let mut b = series(MeasurementKind::Velocity, 1.0, 300);
        for x in &mut b[120..180] {
            x.nis *= 10.0;
        }
        let i = assess(&b);
        assert_eq!(i.alerts.len(), 1, "{:?}", i.alerts);
        let IntegrityAlert::InconsistentInnovations {
            time_s,
            band_ratio,
            kind,
        } = i.alerts[0]
        else {
            panic!("{:?}", i.alerts[0]);
        };
        assert_eq!((kind, time_s), (MeasurementKind::Velocity, 120.0));
        assert!(band_ratio > DIVERGED_BAND_RATIO);
        assert!(i.alerts[0]
            .message()
            .contains("velocity measurements from t = 120.0 s"));
    }

    /// One window far off (a burst of bad measurements) is not a divergence.
    /// One batch applied with the gate off (threshold ∞) beyond the outlier
    /// quantile is an alert; the same NIS under a finite gate's threshold
    /// is a batch the gate judged, so not.
    #[test]
    fn an_outlier_applied_with_the_gate_off_is_an_alert() {
        let mut b = series(MeasurementKind::Position, 1.0, 60);
        b[30].threshold = f64::INFINITY;
        assert!(!assess(&b).diverged());
        b[30].nis = 1e12;
        let alerts = assess(&b).alerts;
        assert!(
            matches!(
                alerts.as_slice(),
                [IntegrityAlert::AppliedOutliers { count: 1, .. }, ..]
            ),
            "{alerts:?}"
        );
        b[30].threshold = chi_square_quantile(3.0, 0.999);
        assert!(!assess(&b)
            .alerts
            .iter()
            .any(|a| a.name() == "applied_outliers"));
    }

    #[test]
    fn a_single_bad_window_is_not_an_alert() {
        let mut b = series(MeasurementKind::Pseudorange, 1.0, 300);
        for x in &mut b[60..90] {
            x.nis *= 50.0;
        }
        assert!(!assess(&b).diverged());
    }

    #[test]
    fn persistent_nonlinearity_is_an_alert() {
        let mut b = series(MeasurementKind::Pseudorange, 1.0, 300);
        for (k, x) in b.iter_mut().enumerate() {
            x.nonlinearity = 1e-3 * k as f64;
        }
        let i = assess(&b);
        // The first window whose every batch is above 0.1: [120, 150).
        let alert = i.alerts.first().expect("an alert");
        assert_eq!(alert.name(), "beyond_linear_model");
        assert_eq!(alert.time_s(), 120.0);
        // Loose-coupling kinds carry no nonlinearity (NaN): never an alert.
        assert!(!assess(&series(MeasurementKind::Position, 1.0, 300)).diverged());
    }

    #[test]
    fn gated_batches_need_a_sustained_share() {
        let ok: Vec<_> = (0..100)
            .map(|k| batch(k as f64, MeasurementKind::Position, 2.0, 3, k % 20 != 0))
            .collect();
        assert!(!assess(&ok).diverged());
        let bad: Vec<_> = (0..100)
            .map(|k| {
                batch(
                    k as f64,
                    MeasurementKind::Position,
                    if k < 10 { 2.0 } else { 1e12 },
                    3,
                    k < 10,
                )
            })
            .collect();
        let i = assess(&bad);
        let w = i
            .alerts
            .iter()
            .find(|a| a.name() == "gated_batches")
            .expect("diverged");
        assert!(
            w.message().contains("90 of 100 GNSS batches (90 %)"),
            "{}",
            w.message()
        );
        // A short burst (5 s) is not divergence.
        let burst: Vec<_> = (0..20)
            .map(|k| batch(k as f64 * 0.5, MeasurementKind::Position, 1e12, 3, k < 10))
            .collect();
        assert!(assess(&burst)
            .alerts
            .iter()
            .all(|a| a.name() != "gated_batches"));
    }
}
