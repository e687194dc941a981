//! Each satellite's slant ionospheric delay measured from two code
//! pseudoranges on different carriers, in place of the broadcast model.
//!
//! The delay scales with 1/f² (IS-GPS-200 §20.3.3.3.3.3), so two
//! pseudoranges corrected for their satellite group delays differ by
//! (γ − 1) I₁ plus the receiver's inter-frequency bias, γ = (f₁/f₂)² and
//! I₁ the delay on f₁: the geometry-free combination (Misra & Enge 2011,
//! §5.3.2). Its noise is the two codes' together over γ − 1 (about 1.8×
//! one code's for L1/L5), too much to use epoch by epoch; the delay
//! changes by centimetres a minute, so each satellite's is estimated by a
//! scalar Kalman filter with a random-walk process (the smoothing that
//! level-to-code ionosphere estimates use, without carrier arcs that
//! cycle slips would cut).
//!
//! The receiver's inter-frequency bias is the same for every satellite of
//! a system and signal pair: it shifts all their corrected pseudoranges
//! alike, and the receiver clock (or the system's inter-system bias)
//! takes it up.

use std::collections::HashMap;

/// The random-walk intensity of a slant ionospheric delay, m²/s: 1 cm
/// after 1 s, 10 cm after 100 s, the rate of a quiet mid-latitude
/// ionosphere seen from a slowly moving satellite (a few cm per minute,
/// Misra & Enge 2011 §5.3.2). It sets the smoothing: with 0.25 s epochs and
/// 1 m of geometry-free noise the estimate settles to about 7 cm within a
/// minute.
pub const IONOSPHERE_RANDOM_WALK_M2_S: f64 = 1e-4;

/// The largest slant delay on L1 a measurement may give, m: the worst
/// storm-time ionosphere at low elevation is about 100 m (Klobuchar 1996,
/// in Parkinson & Spilker vol. I, ch. 12); a larger geometry-free value is a
/// broken code, not a delay, and never starts or moves an estimate.
const MAX_SLANT_DELAY_M: f64 = 200.0;

/// Geometry-free measurements further than this many σ from the estimate
/// (their noise and the estimate's together) are left out: a multipath
/// spike on either code.
const GATE_SIGMA: f64 = 5.0;

/// The delay on `primary_frequency_hz` of two group-delay-corrected
/// pseudoranges of one satellite, m: I₁ = (ρ₂ − ρ₁) / (γ − 1), γ =
/// (f₁/f₂)² (module documentation), and the factor 1/(γ − 1) the codes'
/// noise is scaled by.
pub fn geometry_free_delay_m(
    primary_m: f64,
    primary_frequency_hz: f64,
    second_m: f64,
    second_frequency_hz: f64,
) -> (f64, f64) {
    let gamma = (primary_frequency_hz / second_frequency_hz).powi(2);
    let scale = 1.0 / (gamma - 1.0);
    ((second_m - primary_m) * scale, scale)
}

/// One satellite's estimate: the delay, its variance, when it was last
/// updated and the second signal that measured it.
#[derive(Debug, Clone, Copy)]
struct Track {
    delay_m: f64,
    variance_m2: f64,
    time_s: f64,
    signal: &'static str,
}

/// One geometry-free measurement of a satellite's delay: the delay, its
/// variance and the second signal's name.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct DelayMeasurement {
    /// Slant ionospheric delay on the primary signal's carrier, m.
    pub delay_m: f64,
    /// Its variance, m².
    pub variance_m2: f64,
    /// The second signal's name (`"L5 Q"`).
    pub signal: &'static str,
}

/// The per-satellite delay estimates of one pass through a file, in time
/// order (causal: a forward filter can use every epoch's value).
#[derive(Debug, Default)]
pub struct IonosphereTracks {
    tracks: HashMap<u16, Track>,
}

impl IonosphereTracks {
    /// Satellite `number`'s delay estimate at `time_s`, m, its variance and
    /// the signal that measured it: the random walk propagated since the
    /// last epoch, then updated with `measurement` when there is one
    /// (left out beyond `GATE_SIGMA`); the first measurement of a
    /// satellite starts its estimate; one that is not finite, beyond
    /// `MAX_SLANT_DELAY_M` or without a positive variance counts as none.
    /// An epoch without a second signal
    /// keeps the propagated estimate (a momentary loss of the second signal
    /// does not switch the satellite to another model); `None` for a
    /// satellite never measured.
    pub fn estimate(
        &mut self,
        number: u16,
        time_s: f64,
        measurement: Option<DelayMeasurement>,
    ) -> Option<DelayMeasurement> {
        let measurement = measurement.filter(|m| {
            m.delay_m.abs() <= MAX_SLANT_DELAY_M && m.variance_m2.is_finite() && m.variance_m2 > 0.0
        });
        let track = match (self.tracks.get_mut(&number), measurement) {
            (Some(track), _) => track,
            (None, Some(m)) => self.tracks.entry(number).or_insert(Track {
                delay_m: m.delay_m,
                variance_m2: m.variance_m2,
                time_s,
                signal: m.signal,
            }),
            (None, None) => return None,
        };
        track.variance_m2 += IONOSPHERE_RANDOM_WALK_M2_S * (time_s - track.time_s).max(0.0);
        track.time_s = time_s;
        if let Some(m) = measurement {
            let innovation = m.delay_m - track.delay_m;
            let innovation_variance = track.variance_m2 + m.variance_m2;
            if innovation * innovation <= GATE_SIGMA * GATE_SIGMA * innovation_variance {
                let gain = track.variance_m2 / innovation_variance;
                track.delay_m += gain * innovation;
                track.variance_m2 *= 1.0 - gain;
                track.signal = m.signal;
            }
        }
        Some(DelayMeasurement {
            delay_m: track.delay_m,
            variance_m2: track.variance_m2,
            signal: track.signal,
        })
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn geometry_free_combination_recovers_a_1_over_f_squared_delay() {
        // L1 and L5: a 4 m delay on L1 is 4 (f1/f5)² on L5 (IS-GPS-200
        // §20.3.3.3.3.3); the range and any common term cancel.
        let (f1, f5): (f64, f64) = (1575.42e6, 1176.45e6);
        let (range, common, delay_l1) = (21_000_000.0, 123.4, 4.0);
        let l1 = range + common + delay_l1;
        let l5 = range + common + delay_l1 * (f1 / f5).powi(2);
        let (delay, scale) = geometry_free_delay_m(l1, f1, l5, f5);
        assert!((delay - delay_l1).abs() < 1e-6, "{delay}");
        assert!((scale - 1.0 / ((f1 / f5).powi(2) - 1.0)).abs() < 1e-12);
    }

    #[test]
    fn a_constant_delay_is_averaged_to_the_white_noise_bound() {
        // Measurements of a constant with σ = 1 m at 4 Hz: after n of them
        // the estimate's variance is at most σ²/n (a random walk only adds),
        // and its error is within a few of its own σ.
        use rand::SeedableRng;
        use rand_distr::{Distribution, Normal};
        let mut rng = rand::rngs::StdRng::seed_from_u64(7);
        let noise = Normal::new(0.0, 1.0).unwrap();
        let mut tracks = IonosphereTracks::default();
        let mut last = None;
        for k in 0..400 {
            let measured = measurement(5.0 + noise.sample(&mut rng), 1.0);
            last = tracks.estimate(3, 0.25 * f64::from(k), Some(measured));
        }
        let DelayMeasurement {
            delay_m: delay,
            variance_m2: variance,
            ..
        } = last.unwrap();
        assert!(variance < 0.01 && variance > 1.0 / 400.0, "{variance}");
        assert!(
            (delay - 5.0).abs() < 3.0 * variance.sqrt(),
            "{delay} ± {}",
            variance.sqrt()
        );
    }

    #[test]
    fn a_spike_is_gated_a_gap_is_bridged_and_satellites_are_kept_apart() {
        let mut tracks = IonosphereTracks::default();
        let mut at = |number: u16, time: f64, delay: Option<f64>| {
            let m = delay.map(|d| measurement(d, 0.25));
            tracks
                .estimate(number, time, m)
                .map(|e| (e.delay_m, e.variance_m2))
        };
        for k in 0..100 {
            at(1, f64::from(k), Some(3.0));
            at(2, f64::from(k), Some(7.0));
        }
        let (before, variance) = at(1, 100.0, Some(3.0)).unwrap();
        let (spiked, _) = at(1, 101.0, Some(300.0)).unwrap();
        assert_eq!(before, spiked);
        // Without a measurement: the same delay, its variance grown by the
        // random walk over the gap.
        let (bridged, grown) = at(1, 111.0, None).unwrap();
        assert_eq!(bridged, before);
        let expected = variance + 11.0 * IONOSPHERE_RANDOM_WALK_M2_S;
        assert!((grown - expected).abs() < 1e-12, "{grown} {expected}");
        assert!((at(2, 101.0, Some(7.0)).unwrap().0 - 7.0).abs() < 1e-9);
        assert_eq!(at(3, 0.0, None), None);
        // A broken code neither starts nor moves an estimate.
        for broken in [f64::NAN, 1e300, -5e3] {
            assert_eq!(at(4, 0.0, Some(broken)), None);
            assert_eq!(at(2, 102.0, Some(broken)).unwrap().0, 7.0);
        }
    }

    fn measurement(delay_m: f64, variance_m2: f64) -> DelayMeasurement {
        DelayMeasurement {
            delay_m,
            variance_m2,
            signal: "L5 Q",
        }
    }
}
