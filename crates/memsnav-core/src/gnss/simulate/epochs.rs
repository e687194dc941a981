//! The measurement epochs of a simulation: which track samples carry one.

use crate::{Error, Result};

/// The epoch grid t0 + k / rate must be representable at the track's
/// times: a period below a few units in the last place of the largest
/// time stamp rounds the grid onto itself, and the search for the next
/// epoch would crawl one target at a time (issue 30: 1e18 Hz on a 1 s
/// track). Such a rate asks for more than one epoch per track sample
/// anyway, which the simulator never gives.
pub(super) fn check_resolution(time_s: &[f64], rate_hz: f64) -> Result<()> {
    let largest = time_s
        .first()
        .into_iter()
        .chain(time_s.last())
        .fold(1.0f64, |m, t| m.max(t.abs()));
    let resolution = 16.0 * f64::EPSILON * largest;
    if 1.0 / rate_hz < resolution {
        return Err(Error::invalid(
            "rate",
            format!(
                "{rate_hz} Hz: its period is below the resolution of the track's time stamps \
                 ({resolution:.1e} s); at most one epoch per track sample is simulated, so \
                 give at most the track's sample rate"
            ),
        ));
    }
    Ok(())
}

/// Indices of the track samples nearest to t0 + k / rate (k = 0, 1, ...),
/// each at most half a period from its target and none twice. `time_s`
/// must be non-empty and strictly increasing, `rate_hz` positive.
pub(super) fn epoch_samples(time_s: &[f64], rate_hz: f64) -> Vec<usize> {
    let n = time_s.len();
    let (t0, t_end) = (time_s[0], time_s[n - 1]);
    let step = 1.0 / rate_hz;
    // At most one epoch per track sample: the output and the loop are
    // bounded by the track, whatever the time span or the rate (a 1e20 s
    // span at 1 Hz must not visit 1e20 targets). `k` is a float for spans
    // beyond 2⁶⁴ periods.
    let mut samples: Vec<usize> = Vec::new();
    let mut k = 0.0f64;
    loop {
        let target = t0 + k * step;
        if target > t_end + 0.5 * step {
            break;
        }
        let j = time_s.partition_point(|&t| t < target);
        let nearest = if j == 0 {
            0
        } else if j == n || (target - time_s[j - 1]) <= (time_s[j] - target) {
            j - 1
        } else {
            j
        };
        if samples.last() != Some(&nearest) && (time_s[nearest] - target).abs() <= 0.5 * step {
            samples.push(nearest);
        }
        // Later targets select a new sample only if one lies within half a
        // period of them: skip the targets before the first sample after
        // this target (less half a period).
        let after = time_s.partition_point(|&t| t <= target);
        if after == n {
            break;
        }
        let first_useful = ((time_s[after] - 0.5 * step - t0) / step).ceil();
        k = (k + 1.0).max(first_useful);
    }
    samples
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn one_sample_per_period_nearest_to_its_target() {
        let time: Vec<f64> = (0..=1000).map(|k| 0.3 + k as f64 * 0.01).collect();
        let s = epoch_samples(&time, 1.0);
        assert_eq!(s, (0..=10).map(|k| 100 * k).collect::<Vec<_>>());
        // A 3 Hz grid on a 100 Hz track: the nearest samples to k/3 s.
        let s = epoch_samples(&time, 3.0);
        assert_eq!(&s[..4], &[0, 33, 67, 100]);
        // A gap longer than half a period leaves its targets out.
        let gappy = [0.0, 0.1, 2.9, 3.0];
        assert_eq!(epoch_samples(&gappy, 1.0), vec![0, 3]);
    }

    #[test]
    fn a_period_below_the_time_resolution_is_refused() {
        let time: Vec<f64> = (0..=100).map(|k| k as f64 * 0.01).collect();
        let err = check_resolution(&time, 1e18).unwrap_err().to_string();
        assert!(
            err.starts_with("rate: 1000000000000000000 Hz: its period"),
            "{err}"
        );
        assert!(check_resolution(&time, 1e12).is_ok());
        // The resolution scales with the time stamps (GPS times ~1e9 s).
        let gps: Vec<f64> = time.iter().map(|t| 1.4e9 + t).collect();
        assert!(check_resolution(&gps, 1e9).is_err());
        assert!(check_resolution(&gps, 1e3).is_ok());
    }

    #[test]
    fn huge_spans_and_rates_cost_no_more_than_the_track() {
        // Issue 15: a 1e20 s span at 1 Hz hung, 1e12 Hz aborted on allocation.
        assert_eq!(epoch_samples(&[0.0, 1e20], 1.0), vec![0, 1]);
        let time: Vec<f64> = (0..=100).map(|k| k as f64 * 0.01).collect();
        assert_eq!(epoch_samples(&time, 1e12), (0..=100).collect::<Vec<_>>());
        // The skip leaves the ordinary grid unchanged.
        let time: Vec<f64> = (0..=1000).map(|k| 0.3 + k as f64 * 0.01).collect();
        let naive: Vec<usize> = (0..=(10.0 * 7.0) as usize)
            .map(|k| 0.3 + k as f64 / 7.0)
            .map(|target| {
                (0..time.len())
                    .min_by(|&a, &b| {
                        (time[a] - target)
                            .abs()
                            .total_cmp(&(time[b] - target).abs())
                    })
                    .unwrap()
            })
            .collect();
        let mut expected = naive;
        expected.dedup();
        assert_eq!(epoch_samples(&time, 7.0), expected);
    }
}
