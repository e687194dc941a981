//! Warnings a run attaches to its [`Solution`]: IMU data whose
//! magnitudes do not fit the declared SI units, and the integrity alerts of
//! [`super::integrity`] (a filter whose solution can no longer be trusted).
//! They are warnings, not errors: the run's output is still returned, and
//! the bindings raise each as a Python `UserWarning`.

use nalgebra::Vector3;

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

/// Appends the run's warnings to `solution.warnings`: the IMU units (the
/// argument names the caller's), then its integrity alerts
/// ([`super::integrity`], from the records, so after `take_records`),
/// which it also keeps in `solution.integrity`.
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
    solution.integrity = super::integrity::assess(&solution.batches);
    w.extend(solution.integrity.alerts.iter().map(|a| a.message()));
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
}
