//! GNSS measurement simulation along a trajectory (method §5), one job
//! per file:
//! - [`epochs`]: which track samples carry a measurement epoch;
//! - [`selection`]: visibility above the elevation mask and the selection of
//!   N satellites kept while visible;
//! - [`measure`]: pseudoranges and rates from the exact signal travel time
//!   with the Earth's rotation, plus a two-state receiver clock, each
//!   system's constant inter-system bias, white noise and an optional
//!   slowly varying atmospheric/multipath residual;
//! - [`carrier`]: optionally the carrier phase, with its ambiguities and
//!   cycle slips, from a stream of its own;
//! - [`outage`]: windows with fewer satellites, applied to the finished
//!   measurements (the satellites they keep are documented there);
//! - [`track`]: the receiver's motion, which the simulation and the
//!   outages read.
//!
//! [`simulate_with_truth`] runs them in that order.

mod carrier;
mod epochs;
mod measure;
mod outage;
mod selection;
mod track;

pub use carrier::CycleSlip;
pub use outage::{apply_outages, keep_highest, Outage};
pub use track::ReceiverTrack;

use nalgebra::Vector3;

use super::clock::{ClockState, ReceiverClockModel};
use super::constellation::Constellation;
use super::observables::{
    DEFAULT_ELEVATION_MASK_DEG, DEFAULT_PSEUDORANGE_RATE_STD_M_S, DEFAULT_PSEUDORANGE_STD_M,
};
use super::system::{GnssSystem, INTER_SYSTEM_BIAS_SYSTEMS};
use super::GnssEpoch;
use crate::gauss_markov::GaussMarkov;
use crate::geodesy::domain::{MAX_DISTANCE_M, MAX_SPEED_M_S};
use crate::geodesy::ecef_to_geodetic;
use crate::random::Rng;
use crate::validate::{self, SeriesCheck};
use crate::{Error, Result};
use carrier::CarrierTracking;
use measure::{MeasurementErrors, Receiver};
use selection::{elevation, Selection};

/// First-order Gauss-Markov residual per satellite (unmodelled atmosphere
/// and multipath, [`crate::gauss_markov`]), stationary std `std_m`.
/// Default: 1 m with a 300 s correlation time (a slowly varying
/// tropospheric/ionospheric residual after broadcast corrections).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct AtmosphericResidual {
    /// Stationary one-sigma, m.
    pub std_m: f64,
    /// Correlation time τ, s.
    pub correlation_time_s: f64,
}

impl Default for AtmosphericResidual {
    fn default() -> Self {
        Self {
            std_m: 1.0,
            correlation_time_s: 300.0,
        }
    }
}

/// Settings of [`simulate`]. Defaults: 1 Hz, 6 satellites, 10° mask,
/// 3 m and 0.1 m/s white noise, no residual, a TCXO clock, no outage, no
/// inter-system bias, no carrier phase.
#[derive(Debug, Clone, PartialEq)]
pub struct SimulationConfig {
    /// Measurement rate, Hz (epochs fall on the track samples nearest to
    /// t0 + k / rate).
    pub rate_hz: f64,
    /// Number of satellites tracked (the paper's 6), of every system the
    /// constellation holds.
    pub n_satellites: usize,
    /// Elevation mask, rad.
    pub elevation_mask_rad: f64,
    /// White pseudorange noise, one sigma, m.
    pub pseudorange_std_m: f64,
    /// White pseudorange-rate noise, one sigma, m/s.
    pub pseudorange_rate_std_m_s: f64,
    /// Optional slowly varying residual added to the pseudoranges.
    pub residual: Option<AtmosphericResidual>,
    /// Receiver clock model.
    pub clock: ReceiverClockModel,
    /// Outage windows.
    pub outages: Vec<Outage>,
    /// GPS time (s since 1980-01-06) of the track's first sample; `None`:
    /// the constellation's default (earliest t_oe of a broadcast file, 0 for
    /// a Walker constellation).
    pub start_gps_time_s: Option<f64>,
    /// Inter-system biases of the Galileo and BeiDou pseudoranges against
    /// GPS's ([`INTER_SYSTEM_BIAS_SYSTEMS`] order), m, constant: the
    /// receiver's different group delays per system (and GST, BDT against
    /// GPS time) that the tight filter's inter-system-bias states estimate.
    pub inter_system_bias_m: [f64; INTER_SYSTEM_BIAS_SYSTEMS.len()],
    /// White carrier-range noise, one sigma, m; 0: no carrier phase
    /// (module `carrier`).
    pub carrier_phase_std_m: f64,
    /// Probability that a satellite's carrier slips at an epoch (after
    /// its first of an arc), in [0, 1].
    pub cycle_slip_probability: f64,
}

impl Default for SimulationConfig {
    fn default() -> Self {
        SimulationConfig {
            rate_hz: 1.0,
            n_satellites: 6,
            elevation_mask_rad: DEFAULT_ELEVATION_MASK_DEG.to_radians(),
            pseudorange_std_m: DEFAULT_PSEUDORANGE_STD_M,
            pseudorange_rate_std_m_s: DEFAULT_PSEUDORANGE_RATE_STD_M_S,
            residual: None,
            clock: ReceiverClockModel::default(),
            outages: Vec::new(),
            start_gps_time_s: None,
            inter_system_bias_m: [0.0; INTER_SYSTEM_BIAS_SYSTEMS.len()],
            carrier_phase_std_m: 0.0,
            cycle_slip_probability: 0.0,
        }
    }
}

/// The measurements and the truth they were made from.
#[derive(Debug, Clone, PartialEq)]
pub struct GnssSimulation {
    /// The measurements, one epoch per receiver epoch.
    pub epochs: Vec<GnssEpoch>,
    /// True receiver clock at each epoch.
    pub clock: Vec<ClockState>,
    /// GPS time of the track's first sample, s.
    pub start_gps_time_s: f64,
    /// The inter-system biases in the pseudoranges (Galileo, BeiDou
    /// minus GPS), m: the configuration's.
    pub inter_system_bias_m: [f64; INTER_SYSTEM_BIAS_SYSTEMS.len()],
    /// The cycle slips in the carrier phases, in epoch order (empty
    /// without carrier phase).
    pub cycle_slips: Vec<CycleSlip>,
}

impl SimulationConfig {
    /// Checks every setting; errors name the Python keyword.
    pub fn validate(&self) -> Result<()> {
        validate::positive("rate", self.rate_hz)?;
        if self.n_satellites == 0 {
            return Err(Error::invalid("n_satellites", "must be at least 1"));
        }
        crate::limits::at_most(
            "n_satellites",
            self.n_satellites,
            crate::limits::MAX_SATELLITES,
            "satellites",
        )?;
        if !(self.elevation_mask_rad.is_finite()
            && (0.0..std::f64::consts::FRAC_PI_2).contains(&self.elevation_mask_rad))
        {
            return Err(Error::invalid(
                "elevation_mask",
                format!(
                    "must be within [0°, 90°), got {}°",
                    self.elevation_mask_rad.to_degrees()
                ),
            ));
        }
        // Range errors no larger than the ranges of the geodesy's domain,
        // rate errors no faster than its speeds: beyond them no receiver
        // measures, and the simulated sums overflow.
        validate::magnitude("pseudorange_std", self.pseudorange_std_m, MAX_DISTANCE_M)?;
        validate::magnitude(
            "pseudorange_rate_std",
            self.pseudorange_rate_std_m_s,
            MAX_SPEED_M_S,
        )?;
        if let Some(r) = self.residual {
            validate::magnitude("residual_std", r.std_m, MAX_DISTANCE_M)?;
        }
        self.residual_process()?;
        self.clock.validate()?;
        for (k, o) in self.outages.iter().enumerate() {
            if !o.start_s.is_finite() {
                return Err(Error::invalid(
                    "outages",
                    format!("outage {k}: start must be finite, got {}", o.start_s),
                ));
            }
            if !(o.duration_s.is_finite() && o.duration_s > 0.0) {
                return Err(Error::invalid(
                    "outages",
                    format!(
                        "outage {k}: length must be finite and positive, got {}",
                        o.duration_s
                    ),
                ));
            }
        }
        if let Some(t) = self.start_gps_time_s {
            validate::finite_scalars("start_gps_time", &[t])?;
        }
        // A bias no larger than the geodesy's ranges, as the noise above.
        validate::finite_scalars("inter_system_bias", &self.inter_system_bias_m)?;
        if let Some(b) = self
            .inter_system_bias_m
            .iter()
            .find(|b| b.abs() > MAX_DISTANCE_M)
        {
            return Err(Error::invalid(
                "inter_system_bias",
                format!("must be within ±{MAX_DISTANCE_M:e} m, got {b:e}"),
            ));
        }
        validate::magnitude(
            "carrier_phase_std",
            self.carrier_phase_std_m,
            MAX_DISTANCE_M,
        )?;
        let p = self.cycle_slip_probability;
        if !(0.0..=1.0).contains(&p) {
            return Err(Error::invalid(
                "cycle_slip_probability",
                format!("must be within [0, 1], got {p}"),
            ));
        }
        Ok(())
    }

    /// The residual as a validated Gauss-Markov process.
    fn residual_process(&self) -> Result<Option<GaussMarkov>> {
        self.residual
            .map(|r| {
                GaussMarkov::stationary(
                    r.std_m,
                    r.correlation_time_s,
                    ["residual_std", "residual_correlation_time"],
                )
            })
            .transpose()
    }
}

/// Simulates the measurements; see [`simulate_with_truth`] for the clock truth.
pub fn simulate(
    track: &ReceiverTrack<'_>,
    constellation: &Constellation,
    config: &SimulationConfig,
    rng: &mut Rng,
) -> Result<Vec<GnssEpoch>> {
    simulate_with_truth(track, constellation, config, rng).map(|s| s.epochs)
}

/// Simulates measurements along `track` at `config.rate_hz` (module docs):
/// per epoch the receiver clock steps, the selection is updated, every
/// selected satellite is measured, and finally the outages remove
/// satellites. Draw order: the initial clock (2), then per epoch the clock
/// step (2, from the second epoch) and per selected satellite its residual
/// (if enabled), pseudorange and rate noise. The carrier phases draw from
/// a side stream of `rng` (module `carrier`), which they leave as it was.
pub fn simulate_with_truth(
    track: &ReceiverTrack<'_>,
    constellation: &Constellation,
    config: &SimulationConfig,
    rng: &mut Rng,
) -> Result<GnssSimulation> {
    simulate_track(track, constellation, config, rng, SeriesCheck::Finite)
}

/// [`simulate_with_truth`] with the track's times and vectors checked as
/// `check` says ([`SeriesCheck::Trusted`]: a trajectory this crate
/// generated, increasing and finite by construction).
pub(crate) fn simulate_track(
    track: &ReceiverTrack<'_>,
    constellation: &Constellation,
    config: &SimulationConfig,
    rng: &mut Rng,
    check: SeriesCheck,
) -> Result<GnssSimulation> {
    config.validate()?;
    let n = track.time_s.len();
    if n == 0 {
        return Err(Error::invalid("time", "must hold at least one sample"));
    }
    validate::same_length("position_ecef", track.position_ecef.len(), "time", n)?;
    validate::same_length("velocity_ecef", track.velocity_ecef.len(), "time", n)?;
    if check == SeriesCheck::Finite {
        validate::increasing_times("time", track.time_s)?;
        validate::finite_vectors("position_ecef", track.position_ecef)?;
        validate::finite_vectors("velocity_ecef", track.velocity_ecef)?;
        // A receiver at the Earth's centre gave every pseudorange NaN:
        // the one ECEF position and speed checks.
        crate::geodesy::domain::check_position_ecef("position_ecef", track.position_ecef)?;
        crate::geodesy::domain::check_speed("velocity_ecef", track.velocity_ecef)?;
    }
    if constellation.is_empty() {
        return Err(Error::invalid("constellation", "has no satellites"));
    }
    let start_gps = config
        .start_gps_time_s
        .unwrap_or_else(|| constellation.default_start_gps_time_s());
    if (0..constellation.len()).all(|i| constellation.orbit(i, start_gps).is_none()) {
        return Err(Error::invalid(
            "start_gps_time",
            format!("no satellite has a valid ephemeris (within ±2 h of its t_oe) at GPS time {start_gps} s"),
        ));
    }
    let t0 = track.time_s[0];
    let samples = epochs::epoch_samples(track.time_s, config.rate_hz);
    let n_sat = constellation.len();
    let systems: Vec<GnssSystem> = (0..n_sat).map(|i| constellation.system(i)).collect();
    let mut elevations = vec![f64::NAN; n_sat];
    let mut approx_los = vec![Vector3::zeros(); n_sat];
    let mut positions = Vec::with_capacity(n_sat);
    let mut selection = Selection::default();
    let mut errors = MeasurementErrors::new(
        config.pseudorange_std_m,
        config.pseudorange_rate_std_m_s,
        config.residual_process()?,
        n_sat,
    );
    let mut carrier = CarrierTracking::new(
        config.carrier_phase_std_m,
        config.cycle_slip_probability,
        n_sat,
        rng,
    );
    let mut epochs: Vec<GnssEpoch> = Vec::with_capacity(samples.len());
    let mut clocks = Vec::with_capacity(samples.len());
    let mut clock = config.clock.initial(rng);
    let mut previous_t: Option<f64> = None;

    for &s in &samples {
        let t = track.time_s[s];
        let rx = track.position_ecef[s];
        if let Some(tp) = previous_t {
            // The time stamps set the step: a span too long for the clock
            // model is the time argument's fault.
            clock = config.clock.step(&clock, t - tp, rng).map_err(|e| {
                Error::invalid("time", format!("GNSS epochs at {tp:e} s and {t:e} s: {e}"))
            })?;
        }
        previous_t = Some(t);
        let receiver = Receiver {
            epoch: epochs.len(),
            time_s: t,
            gps_time_s: start_gps + (t - t0),
            position_ecef: rx,
            velocity_ecef: track.velocity_ecef[s],
            clock,
        };

        // Visibility at the reception time (the elevation is insensitive to
        // the light time at the mask's precision).
        let g = ecef_to_geodetic(&rx);
        let (sl, cl) = g.latitude_rad.sin_cos();
        let (so, co) = g.longitude_rad.sin_cos();
        let up = Vector3::new(cl * co, cl * so, sl);
        constellation.positions_into(receiver.gps_time_s, &mut positions);
        for (i, position) in positions.iter().enumerate() {
            match position {
                Some(p) => {
                    elevations[i] = elevation(p, &rx, &up);
                    approx_los[i] = (p - rx).normalize();
                }
                None => elevations[i] = f64::NAN,
            }
        }
        selection.update(
            epochs.is_empty(),
            config.n_satellites,
            &elevations,
            &approx_los,
            &systems,
            config.elevation_mask_rad,
        );

        let measurements = selection
            .selected
            .iter()
            .map(|&i| {
                let orbit = constellation
                    .orbit(i, receiver.gps_time_s)
                    .expect("visible satellites have an orbit");
                let bias_m = systems[i]
                    .inter_system_bias_index()
                    .map_or(0.0, |k| config.inter_system_bias_m[k]);
                errors.measure(
                    (i, constellation.sat_id(i), systems[i]),
                    bias_m,
                    &orbit,
                    &receiver,
                    rng,
                    carrier.as_mut(),
                )
            })
            .collect();
        let mut epoch = GnssEpoch {
            time_s: t,
            measurements,
        };
        outage::apply(&config.outages, &mut epoch, &rx);
        if let Some(c) = carrier.as_mut() {
            c.finish_epoch(epochs.last(), &mut epoch);
        }
        epochs.push(epoch);
        clocks.push(clock);
    }
    Ok(GnssSimulation {
        epochs,
        clock: clocks,
        start_gps_time_s: start_gps,
        inter_system_bias_m: config.inter_system_bias_m,
        cycle_slips: carrier.map_or_else(Vec::new, |c| c.slips),
    })
}
