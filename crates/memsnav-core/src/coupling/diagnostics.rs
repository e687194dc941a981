//! Warnings a run attaches to its [`Solution`] (issue 15): IMU data whose
//! magnitudes do not fit the declared SI units, and a filter whose GNSS
//! innovations stay far outside their covariance (divergence). They are
//! warnings, not errors: the run's output is still returned, and the
//! bindings raise each as a Python `UserWarning`.

use nalgebra::Vector3;

use super::records::{BatchRecord, MeasurementKind};
use super::Solution;

/// Share of samples whose |ω| may exceed [`RATE_LIMIT_RAD_S`] before the
/// rates look like deg/s given as rad/s.
pub const RATE_SHARE: f64 = 0.05;
/// 5 rad/s = 286 deg/s: a land vehicle or aircraft being navigated does not
/// turn that fast for 5 % of a log; a car's 20 deg/s turn read as 20 rad/s does.
pub const RATE_LIMIT_RAD_S: f64 = 5.0;
/// Median |f| between these (m/s²) suggests specific force in g.
pub const G_UNITS_RANGE: (f64, f64) = (0.5, 1.5);

/// The unit-plausibility warnings of IMU data declared SI (m/s², rad/s);
/// each names the argument and the likely mistake. Empty for plausible data.
pub fn imu_unit_warnings(
    specific_force_name: &str,
    specific_force: &[Vector3<f64>],
    angular_rate_name: &str,
    angular_rate: &[Vector3<f64>],
) -> Vec<String> {
    let mut out = Vec::new();
    if median_within(specific_force.iter().map(|v| v.norm()), G_UNITS_RANGE) {
        if let Some(f) = median(specific_force.iter().map(|v| v.norm())) {
            out.push(format!(
                "{specific_force_name}: the median magnitude is {f:.3}, near 1 where gravity alone gives 9.8 m/s²: it looks like g given as m/s² (multiply by 9.80665)"
            ));
        }
    }
    let n = angular_rate.len();
    if n > 0 {
        let fast = angular_rate
            .iter()
            .filter(|w| w.norm() > RATE_LIMIT_RAD_S)
            .count();
        let share = fast as f64 / n as f64;
        if share >= RATE_SHARE {
            let largest = angular_rate.iter().map(|w| w.norm()).fold(0.0, f64::max);
            out.push(format!(
                "{angular_rate_name}: {:.0} % of the samples turn faster than {RATE_LIMIT_RAD_S} rad/s ({:.0} deg/s), up to {largest:.3} rad/s: it looks like deg/s given as rad/s (multiply by π/180)",
                100.0 * share,
                RATE_LIMIT_RAD_S.to_degrees()
            ));
        }
    }
    out
}

/// A GNSS batch kind (the aiding whose innovations test the solution).
fn is_gnss(kind: MeasurementKind) -> bool {
    matches!(
        kind,
        MeasurementKind::Pseudorange
            | MeasurementKind::PseudorangeRate
            | MeasurementKind::Position
            | MeasurementKind::Velocity
    )
}

/// Share of GNSS batches that may fail their gate before a run counts as
/// divergent (a consistent filter fails 1 − gate probability of them).
pub const DIVERGENCE_REJECTED_SHARE: f64 = 0.25;
/// ... and how many at least, over how long at least (s).
pub const DIVERGENCE_MIN_REJECTED: usize = 10;
/// See [`DIVERGENCE_MIN_REJECTED`].
pub const DIVERGENCE_MIN_SPAN_S: f64 = 10.0;

/// The divergence warning of a run, when its GNSS innovations stay far
/// outside their covariance: at least [`DIVERGENCE_REJECTED_SHARE`] of the
/// GNSS batches (and [`DIVERGENCE_MIN_REJECTED`], spread over
/// [`DIVERGENCE_MIN_SPAN_S`]) fail their chi-square gate.
pub fn divergence_warning(batches: &[BatchRecord]) -> Option<String> {
    let gnss: Vec<&BatchRecord> = batches.iter().filter(|b| is_gnss(b.kind)).collect();
    let rejected: Vec<&&BatchRecord> = gnss.iter().filter(|b| !b.accepted).collect();
    let (first, last) = (rejected.first()?, rejected.last()?);
    let share = rejected.len() as f64 / gnss.len() as f64;
    let span = last.time_s - first.time_s;
    if share < DIVERGENCE_REJECTED_SHARE
        || rejected.len() < DIVERGENCE_MIN_REJECTED
        || span < DIVERGENCE_MIN_SPAN_S
    {
        return None;
    }
    let mut ratios: Vec<f64> = rejected
        .iter()
        .map(|b| b.nis / b.threshold)
        .filter(|r| r.is_finite())
        .collect();
    ratios.sort_by(f64::total_cmp);
    let median_ratio = ratios.get(ratios.len() / 2).copied().unwrap_or(f64::NAN);
    Some(format!(
        "the filter diverged from its GNSS aiding: {} of {} GNSS batches ({:.0} %) failed their chi-square gate between t = {:.1} s and {:.1} s (median NIS {median_ratio:.3e} times the gate): the solution and its covariance are not trustworthy; check the GNSS input (offsets, outliers, units) and the IMU units",
        rejected.len(),
        gnss.len(),
        100.0 * share,
        first.time_s,
        last.time_s
    ))
}

/// Appends the run's warnings to `solution.warnings`: the IMU units (the
/// argument names the caller's), then divergence (from the records, so
/// after `take_records`).
pub(crate) fn diagnose(
    solution: &mut Solution,
    specific_force: (&str, &[Vector3<f64>]),
    angular_rate: (&str, &[Vector3<f64>]),
) {
    let mut w = imu_unit_warnings(
        specific_force.0,
        specific_force.1,
        angular_rate.0,
        angular_rate.1,
    );
    w.extend(divergence_warning(&solution.batches));
    solution.warnings.extend(w);
}

/// Whether [`median`] of `values` lies strictly inside `(lo, hi)`, by
/// counting (no sort, no allocation): with m finite values and the median
/// their order statistic mid = ⌊m/2⌋ (from 0), median > lo exactly when at
/// most mid of them are ≤ lo, and median < hi exactly when more than mid
/// are < hi.
fn median_within(values: impl Iterator<Item = f64>, (lo, hi): (f64, f64)) -> bool {
    let (mut m, mut at_most_lo, mut below_hi) = (0_usize, 0_usize, 0_usize);
    for x in values.filter(|x| x.is_finite()) {
        m += 1;
        at_most_lo += usize::from(x <= lo);
        below_hi += usize::from(x < hi);
    }
    let mid = m / 2;
    m > 0 && at_most_lo <= mid && below_hi > mid
}

fn median(values: impl Iterator<Item = f64>) -> Option<f64> {
    let mut v: Vec<f64> = values.filter(|x| x.is_finite()).collect();
    if v.is_empty() {
        return None;
    }
    let mid = v.len() / 2;
    Some(*v.select_nth_unstable_by(mid, f64::total_cmp).1)
}

#[cfg(test)]
mod tests {
    use super::*;

    fn batch(t: f64, accepted: bool) -> BatchRecord {
        BatchRecord {
            time_s: t,
            kind: MeasurementKind::Position,
            nis: if accepted { 2.0 } else { 1e12 },
            dof: 3,
            threshold: 16.3,
            excluded: 0,
            accepted,
        }
    }

    /// The count agrees with the median itself, also at the bounds, for
    /// odd and even lengths, with ties and non-finite values.
    #[test]
    fn median_within_agrees_with_the_median() {
        use rand::Rng as _;
        let mut rng = crate::random::stream(17, 0);
        for len in 0..40 {
            for _ in 0..50 {
                let v: Vec<f64> = (0..len)
                    .map(|_| match rng.random_range(0..12) {
                        0 => f64::NAN,
                        1 => f64::INFINITY,
                        2 => 0.5,
                        3 => 1.5,
                        _ => f64::from(rng.random_range(0..9_u8)) * 0.25,
                    })
                    .collect();
                let expected = median(v.iter().copied()).is_some_and(|m| m > 0.5 && m < 1.5);
                assert_eq!(
                    median_within(v.iter().copied(), (0.5, 1.5)),
                    expected,
                    "{v:?}"
                );
            }
        }
    }

    #[test]
    fn units_warn_on_g_and_deg_per_s_only() {
        let still = vec![Vector3::new(0.0, 0.0, -9.81); 100];
        let slow = vec![Vector3::new(0.0, 0.0, 0.3); 100];
        assert!(imu_unit_warnings("f", &still, "w", &slow).is_empty());
        let in_g: Vec<_> = still.iter().map(|v| v / 9.80665).collect();
        let w = imu_unit_warnings("f", &in_g, "w", &slow);
        assert_eq!(w.len(), 1);
        assert!(w[0].starts_with("f: the median magnitude is 1.000") && w[0].contains("g given"));
        let deg: Vec<_> = slow.iter().map(|v| v * 57.3).collect();
        let w = imu_unit_warnings("f", &still, "w", &deg);
        assert_eq!(w.len(), 1);
        assert!(
            w[0].starts_with("w: 100 % of the samples") && w[0].contains("deg/s given as rad/s")
        );
    }

    #[test]
    fn divergence_needs_a_sustained_share_of_gated_batches() {
        let ok: Vec<_> = (0..100).map(|k| batch(k as f64, k % 20 != 0)).collect();
        assert_eq!(divergence_warning(&ok), None);
        let bad: Vec<_> = (0..100).map(|k| batch(k as f64, k < 10)).collect();
        let w = divergence_warning(&bad).expect("diverged");
        assert!(w.contains("90 of 100 GNSS batches (90 %)"), "{w}");
        // A short burst (5 s) is not divergence.
        let burst: Vec<_> = (0..20).map(|k| batch(k as f64 * 0.5, k >= 10)).collect();
        assert_eq!(divergence_warning(&burst), None);
    }
}
