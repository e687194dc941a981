//! The simulated receiver's carrier phase and its cycle slips.
//!
//! The carrier range of a satellite is the pseudorange's geometry, clock
//! and inter-system bias, plus an integer ambiguity N·λ (λ of the
//! simulator's signal: GPS L1's for GPS, Galileo and BeiDou, a GLONASS
//! slot's own G1 wavelength c / (1602 + 0.5625 k) MHz, k its channel in
//! [`crate::gnss::nominal_channel`]) constant over a lock arc, plus white
//! noise. The
//! atmospheric residual enters with the *opposite* sign: the simulator's
//! residual stands for what broadcast corrections leave of the atmosphere,
//! mostly ionospheric (Klobuchar removes about half of a delay of metres;
//! the troposphere's model leaves centimetres), and the ionosphere advances
//! the phase by as much as it delays the code (Groves eq. 9.13, as
//! [`crate::gnss::broadcast_epochs`] corrects it). Code minus carrier thus
//! drifts by twice the residual over an arc, the real code-carrier
//! divergence. The first-order Gauss-Markov residual changes by
//! σ·√(2(1 − e^(−Δt/τ))) between epochs (8 cm in 1 s for 1 m and 300 s),
//! more than a real ionosphere at 1 Hz: a study of time-differenced
//! carrier phase wants no residual or a long correlation time.
//!
//! An arc starts when the selection takes a satellite up (its ambiguity
//! drawn then) and continues while the satellite stays selected. A cycle
//! slip adds a nonzero whole number of cycles to the ambiguity from its
//! epoch on, silently (the receiver's loss-of-lock flag stays clear: the
//! filter must find the slip itself). `loss_of_lock` is set where a
//! satellite was not in the previous epoch's output: a new arc, or the end
//! of an outage that hid it (the ambiguity runs on through an outage, so
//! that scenarios differing only by outages share their draws; the flag
//! makes the constant irrelevant there).
//!
//! Every draw comes from a side stream of the caller's generator
//! ([`crate::random::side_stream`]): carrier phase on or off, the
//! pseudoranges, rates and clock are the same numbers.

use rand::Rng as _;
use rand_distr::{Distribution, StandardNormal};

use super::super::observables::GPS_L1_WAVELENGTH_M;
use super::super::{CarrierPhase, GnssEpoch};
use crate::gnss::{g1_wavelength_m, nominal_channel, system_of_number, GnssSystem};
use crate::random::{side_stream, Rng};

/// The simulated carrier's wavelength of satellite number `sat_id`, m: a
/// GLONASS slot's G1 on its channel (FDMA: each slot its own), else GPS
/// L1's (a GLONASS slot beyond 24 takes channel 0).
pub fn wavelength_m(sat_id: u16) -> f64 {
    match system_of_number(sat_id) {
        GnssSystem::Glonass => g1_wavelength_m(nominal_channel(sat_id % 100).unwrap_or(0)),
        _ => GPS_L1_WAVELENGTH_M,
    }
}

/// A cycle slip the simulator put in: from epoch `time_s` on, the carrier
/// range of satellite `sat_id` holds `cycles` more cycles of its
/// wavelength (`wavelength_m`).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct CycleSlip {
    /// Epoch time on the trajectory's time axis, s (the epoch's own
    /// `time_s`).
    pub time_s: f64,
    /// Satellite number.
    pub sat_id: u16,
    /// Cycles added (nonzero).
    pub cycles: i64,
}

/// Largest initial ambiguity, cycles (≈ 190 km): a receiver starts its
/// phase count anywhere.
const MAX_AMBIGUITY_CYCLES: i64 = 1_000_000;
/// Largest slip, cycles (≈ 190 m).
const MAX_SLIP_CYCLES: i64 = 1000;

/// Carrier phase of every tracked satellite: the arcs' ambiguities, the
/// noise and the slips, all drawn from the side stream.
pub(super) struct CarrierTracking {
    std_m: f64,
    slip_probability: f64,
    rng: Rng,
    /// Per satellite: its ambiguity, cycles, and the index of the last
    /// epoch it was measured at.
    arcs: Vec<Option<(i64, usize)>>,
    /// Slips drawn at the current epoch, not yet checked against its output.
    pending: Vec<CycleSlip>,
    /// Slips in the output, in epoch order.
    pub slips: Vec<CycleSlip>,
}

impl CarrierTracking {
    /// The tracking of `satellites` satellites, or `None` when `std_m` is 0
    /// (no carrier phase; no draw made). `rng`: the simulation's generator
    /// before its first draw.
    pub fn new(std_m: f64, slip_probability: f64, satellites: usize, rng: &Rng) -> Option<Self> {
        (std_m > 0.0).then(|| Self {
            std_m,
            slip_probability,
            rng: side_stream(rng, "gnss carrier phase"),
            arcs: vec![None; satellites],
            pending: Vec::new(),
            slips: Vec::new(),
        })
    }

    /// The carrier phase of satellite `i` (number `sat_id`, of wavelength
    /// [`wavelength_m`]) at epoch
    /// `epoch` (time `time_s`), whose noise-free carrier range without
    /// ambiguity is `range_m` (module docs). Draws: the ambiguity at an
    /// arc's first epoch, else (with a nonzero slip probability) whether it
    /// slips and by how much; then the noise.
    pub fn measure(
        &mut self,
        i: usize,
        sat_id: u16,
        epoch: usize,
        time_s: f64,
        range_m: f64,
    ) -> CarrierPhase {
        let ambiguity = match self.arcs[i] {
            Some((n, last)) if last + 1 == epoch => {
                if self.slip_probability > 0.0 && self.rng.random::<f64>() < self.slip_probability {
                    let cycles = self.slip_cycles();
                    self.pending.push(CycleSlip {
                        time_s,
                        sat_id,
                        cycles,
                    });
                    n + cycles
                } else {
                    n
                }
            }
            _ => self
                .rng
                .random_range(-MAX_AMBIGUITY_CYCLES..=MAX_AMBIGUITY_CYCLES),
        };
        self.arcs[i] = Some((ambiguity, epoch));
        let z: f64 = StandardNormal.sample(&mut self.rng);
        CarrierPhase {
            range_m: range_m + ambiguity as f64 * wavelength_m(sat_id) + self.std_m * z,
            std_m: self.std_m,
            loss_of_lock: false,
        }
    }

    /// A slip's size: ±1 cycle with probability 0.4, ±2 with 0.3, else
    /// ±3..=[`MAX_SLIP_CYCLES`] uniformly: the small slips a Doppler test
    /// misses are common, as on a receiver whose loop jumps a cycle or
    /// two under vibration or a brief blockage.
    fn slip_cycles(&mut self) -> i64 {
        let u: f64 = self.rng.random();
        let size = if u < 0.4 {
            1
        } else if u < 0.7 {
            2
        } else {
            self.rng.random_range(3..=MAX_SLIP_CYCLES)
        };
        if self.rng.random::<bool>() {
            size
        } else {
            -size
        }
    }

    /// Completes `epoch` once the outages have removed satellites: sets
    /// `loss_of_lock` where a satellite was not in `previous` (the previous
    /// output epoch), and keeps in [`Self::slips`] the epoch's slips that
    /// the output shows (a slip of a satellite the outage hid, or at the
    /// start of an arc, is lost in the new arc).
    pub fn finish_epoch(&mut self, previous: Option<&GnssEpoch>, epoch: &mut GnssEpoch) {
        for m in &mut epoch.measurements {
            let tracked_before =
                previous.is_some_and(|p| p.measurements.iter().any(|q| q.sat_id == m.sat_id));
            if let Some(c) = &mut m.carrier {
                c.loss_of_lock = !tracked_before;
            }
        }
        for slip in self.pending.drain(..) {
            let shown = epoch
                .measurements
                .iter()
                .any(|m| m.sat_id == slip.sat_id && m.carrier.is_some_and(|c| !c.loss_of_lock));
            if shown {
                self.slips.push(slip);
            }
        }
    }
}
