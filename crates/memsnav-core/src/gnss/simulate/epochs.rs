//! The measurement epochs of a simulation: which track samples carry one.

/// Indices of the track samples nearest to t0 + k / rate (k = 0, 1, ...),
/// each at most half a period from its target and none twice. `time_s`
/// must be non-empty and strictly increasing, `rate_hz` positive.
pub(super) fn epoch_samples(time_s: &[f64], rate_hz: f64) -> Vec<usize> {
    let n = time_s.len();
    let (t0, t_end) = (time_s[0], time_s[n - 1]);
    let step = 1.0 / rate_hz;
    let mut samples: Vec<usize> = Vec::with_capacity(((t_end - t0) * rate_hz) as usize + 2);
    let mut k = 0usize;
    loop {
        let target = t0 + k as f64 * step;
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
        k += 1;
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
}
