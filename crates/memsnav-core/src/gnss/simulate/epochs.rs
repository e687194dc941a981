//! The measurement epochs of a simulation: which track samples carry one.

/// Indices of the track samples nearest to t0 + k / rate (k = 0, 1, ...),
/// each at most half a period from its target and none twice. `time_s`
/// must be non-empty and strictly increasing, `rate_hz` positive.
pub(super) fn epoch_samples(time_s: &[f64], rate_hz: f64) -> Vec<usize> {
    let t0 = time_s[0];
    let step = 1.0 / rate_hz;
    // Each target k is served by the sample nearest to it, which lies
    // within half a period of it exactly when its offset in periods,
    // r = (t − t0) / step, rounds to k. So the samples are grouped by
    // round(r), consecutive since the times increase, and each group's
    // nearest (the first on a tie) is an epoch: one pass over the track,
    // bounded by it whatever the span or the rate (a 1e20 s span at 1 Hz
    // must not visit 1e20 targets; stepping targets through a span whose
    // float spacing exceeds the period never advanced). A period
    // below every sample spacing puts each sample in a group of its own,
    // so every sample is an epoch (1e18 Hz on a 1 s track).
    let mut samples: Vec<usize> = Vec::new();
    let mut best: Option<(f64, usize, f64)> = None; // (target k, sample, |r − k|)
    for (i, &t) in time_s.iter().enumerate() {
        let r = (t - t0) / step;
        let (k, distance) = (r.round(), (r - r.round()).abs());
        match best {
            Some((current, _, d)) if current == k => {
                if distance < d {
                    best = Some((k, i, distance));
                }
            }
            _ => {
                samples.extend(best.map(|b| b.1));
                best = Some((k, i, distance));
            }
        }
    }
    samples.extend(best.map(|b| b.1));
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
    fn a_period_finer_than_the_time_stamps_gives_every_sample_at_once() {
        // 1e18 Hz on a 1 s track crawled one target per pass.
        let time: Vec<f64> = (0..=100).map(|k| k as f64 * 0.01).collect();
        assert_eq!(epoch_samples(&time, 1e18), (0..=100).collect::<Vec<_>>());
        let gps: Vec<f64> = time.iter().map(|t| 1.4e9 + t).collect();
        assert_eq!(epoch_samples(&gps, 1e15), (0..=100).collect::<Vec<_>>());
    }

    #[test]
    fn huge_spans_and_rates_cost_no_more_than_the_track() {
        // A 1e20 s span at 1 Hz hung, 1e12 Hz aborted on allocation.
        assert_eq!(epoch_samples(&[0.0, 1e20], 1.0), vec![0, 1]);
        // A first time of -2.7e16 s: the float spacing there (4 s) exceeds
        // the period, and stepping the targets never advanced.
        let mut far: Vec<f64> = (0..=1000).map(|k| k as f64 * 0.01).collect();
        far[0] = -2.742_103_583_849_717e16;
        let s = epoch_samples(&far, 1.0);
        assert!(s[0] == 0 && s.len() <= far.len(), "{s:?}");
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
