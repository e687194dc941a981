//! GNSS measurement simulation along a trajectory (method §5): visibility
//! with an elevation mask, selection of N satellites kept while visible,
//! pseudoranges and pseudorange rates from the exact signal travel time
//! with the Earth's rotation, a two-state receiver clock, white noise, an
//! optional slowly varying atmospheric/multipath residual, and outages.
//!
//! The true ranges are computed here by iterating the light time with the
//! orbit re-evaluated at each transmission time, and the rates by a central
//! difference of that exact range: independently of
//! [`super::predicted_range`], so the tests can compare the two.

use nalgebra::{Matrix4, Vector3};
use rand_distr::{Distribution, StandardNormal};

use super::clock::{ClockState, ReceiverClockModel};
use super::constellation::{Constellation, Orbit};
use super::{GnssEpoch, SatelliteMeasurement};
use crate::geodesy::ecef_to_geodetic;
use crate::geodesy::wgs84::{EARTH_RATE_RAD_S, SPEED_OF_LIGHT_M_S};
use crate::random::Rng;
use crate::{validate, Error, Result};

/// The receiver's motion: times (s, strictly increasing) with ECEF
/// positions (m) and velocities (m/s), e.g. a trajectory's truth at the IMU
/// rate.
#[derive(Debug, Clone, Copy)]
pub struct ReceiverTrack<'a> {
    pub time_s: &'a [f64],
    pub position_ecef: &'a [Vector3<f64>],
    pub velocity_ecef: &'a [Vector3<f64>],
}

/// A time window with fewer satellites: none (total outage) or at most
/// `n_satellites` (partial; the highest of the selected ones are kept).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Outage {
    /// Start on the trajectory's time axis, s.
    pub start_s: f64,
    /// Length, s (the window is [start, start + duration)).
    pub duration_s: f64,
    /// Satellites still tracked during the window (0: total outage).
    pub n_satellites: usize,
}

/// First-order Gauss-Markov residual per satellite (unmodelled atmosphere
/// and multipath): x_{k+1} = e^{−Δt/τ} x_k + w, stationary std `std_m`.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct AtmosphericResidual {
    /// Stationary one-sigma, m.
    pub std_m: f64,
    /// Correlation time τ, s.
    pub correlation_time_s: f64,
}

/// Settings of [`simulate`]. Defaults: 1 Hz, 6 satellites, 10° mask,
/// 3 m and 0.1 m/s white noise, no residual, a TCXO clock, no outage.
#[derive(Debug, Clone, PartialEq)]
pub struct SimulationConfig {
    /// Measurement rate, Hz (epochs fall on the track samples nearest to
    /// t0 + k / rate).
    pub rate_hz: f64,
    /// Number of satellites tracked (the paper's 6).
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
}

impl Default for SimulationConfig {
    fn default() -> Self {
        SimulationConfig {
            rate_hz: 1.0,
            n_satellites: 6,
            elevation_mask_rad: 10f64.to_radians(),
            pseudorange_std_m: 3.0,
            pseudorange_rate_std_m_s: 0.1,
            residual: None,
            clock: ReceiverClockModel::default(),
            outages: Vec::new(),
            start_gps_time_s: None,
        }
    }
}

/// The measurements and the truth they were made from.
#[derive(Debug, Clone, PartialEq)]
pub struct GnssSimulation {
    pub epochs: Vec<GnssEpoch>,
    /// True receiver clock at each epoch.
    pub clock: Vec<ClockState>,
    /// GPS time of the track's first sample, s.
    pub start_gps_time_s: f64,
}

impl SimulationConfig {
    fn validate(&self) -> Result<()> {
        validate::positive("rate", self.rate_hz)?;
        if self.n_satellites == 0 {
            return Err(Error::invalid("n_satellites", "must be at least 1"));
        }
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
        validate::non_negative("pseudorange_std", self.pseudorange_std_m)?;
        validate::non_negative("pseudorange_rate_std", self.pseudorange_rate_std_m_s)?;
        if let Some(r) = self.residual {
            validate::non_negative("residual_std", r.std_m)?;
            validate::positive("residual_correlation_time", r.correlation_time_s)?;
        }
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
        Ok(())
    }

    /// Satellites allowed at trajectory time `t` (the tightest active outage).
    fn allowed(&self, t: f64) -> usize {
        self.outages
            .iter()
            .filter(|o| t >= o.start_s && t < o.start_s + o.duration_s)
            .fold(self.n_satellites, |n, o| n.min(o.n_satellites))
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

/// Light-time solution: the satellite state at transmission time t_r − τ,
/// with τ iterated until |Δτ| < 1e-15 s and the satellite position turned
/// into the ECEF frame of the reception time by the Earth angle ω_ie τ.
/// Returns (range at reception, state at transmission). The reception time
/// is `rx_gps_s + rx_offset_s` (see [`Orbit::state_at`] for why the offset
/// is separate).
fn light_time(
    orbit: &Orbit<'_>,
    rx_gps_s: f64,
    rx_offset_s: f64,
    rx_pos: &Vector3<f64>,
) -> (f64, super::SatelliteState) {
    let mut tau = 0.07;
    let mut state = orbit.state_at(rx_gps_s, rx_offset_s - tau);
    let mut range = 0.0;
    for _ in 0..12 {
        state = orbit.state_at(rx_gps_s, rx_offset_s - tau);
        let (s, c) = (EARTH_RATE_RAD_S * tau).sin_cos();
        let p = state.position_ecef;
        let in_rx_frame = Vector3::new(c * p.x + s * p.y, -s * p.x + c * p.y, p.z);
        range = (in_rx_frame - rx_pos).norm();
        let next = range / SPEED_OF_LIGHT_M_S;
        let converged = (next - tau).abs() < 1e-15;
        tau = next;
        if converged {
            break;
        }
    }
    (range, state)
}

/// Elevation of a satellite seen from `rx` with local up `up`, rad.
fn elevation(sat: &Vector3<f64>, rx: &Vector3<f64>, up: &Vector3<f64>) -> f64 {
    let d = sat - rx;
    (d.dot(up) / d.norm()).clamp(-1.0, 1.0).asin()
}

/// GDOP of a set of lines of sight (∞ when fewer than 4 or singular).
fn gdop(los: impl Iterator<Item = Vector3<f64>>) -> f64 {
    let mut g = Matrix4::zeros();
    let mut n = 0;
    for u in los {
        let h = nalgebra::Vector4::new(-u.x, -u.y, -u.z, 1.0);
        g += h * h.transpose();
        n += 1;
    }
    if n < 4 {
        return f64::INFINITY;
    }
    g.try_inverse()
        .map_or(f64::INFINITY, |inv| inv.trace().max(0.0).sqrt())
}

/// Simulates measurements along `track` at `config.rate_hz`.
///
/// Satellite selection (the paper keeps 6 all along): at the first epoch
/// the N satellites with the best GDOP, by greedy elimination from all
/// visible ones (drop, one at a time, the satellite whose removal leaves
/// the lowest GDOP); a selected satellite is kept while it stays above the
/// mask, and one that sets is replaced by the visible satellite that gives
/// the lowest GDOP. Pseudoranges are ρ + b + residual + noise and rates
/// ρ̇ + ḃ + noise, where ρ is the exact light-time range (satellite clock
/// errors are taken as corrected). Draw order per epoch: clock (2), then
/// per tracked satellite residual (if enabled), pseudorange and rate noise.
pub fn simulate_with_truth(
    track: &ReceiverTrack<'_>,
    constellation: &Constellation,
    config: &SimulationConfig,
    rng: &mut Rng,
) -> Result<GnssSimulation> {
    config.validate()?;
    let n = track.time_s.len();
    if n == 0 {
        return Err(Error::invalid("time", "must hold at least one sample"));
    }
    validate::increasing_times("time", track.time_s)?;
    validate::same_length("position_ecef", track.position_ecef.len(), "time", n)?;
    validate::same_length("velocity_ecef", track.velocity_ecef.len(), "time", n)?;
    validate::finite_vectors("position_ecef", track.position_ecef)?;
    validate::finite_vectors("velocity_ecef", track.velocity_ecef)?;
    if constellation.is_empty() {
        return Err(Error::invalid("constellation", "has no satellites"));
    }
    let start_gps = config
        .start_gps_time_s
        .unwrap_or_else(|| constellation.default_start_gps_time_s());
    let t0 = track.time_s[0];
    if (0..constellation.len()).all(|i| constellation.orbit(i, start_gps).is_none()) {
        return Err(Error::invalid(
            "start_gps_time",
            format!("no satellite has a valid ephemeris (within ±2 h of its t_oe) at GPS time {start_gps} s"),
        ));
    }

    // Epoch samples: the track sample nearest to each t0 + k / rate.
    let t_end = track.time_s[n - 1];
    let step = 1.0 / config.rate_hz;
    let mut samples: Vec<usize> = Vec::with_capacity(((t_end - t0) * config.rate_hz) as usize + 2);
    let mut k = 0usize;
    loop {
        let target = t0 + k as f64 * step;
        if target > t_end + 0.5 * step {
            break;
        }
        let j = track.time_s.partition_point(|&t| t < target);
        let nearest = if j == 0 {
            0
        } else if j == n || (target - track.time_s[j - 1]) <= (track.time_s[j] - target) {
            j - 1
        } else {
            j
        };
        if samples.last() != Some(&nearest) && (track.time_s[nearest] - target).abs() <= 0.5 * step
        {
            samples.push(nearest);
        }
        k += 1;
    }

    let n_sat = constellation.len();
    let h = 0.05; // central-difference half step for the rate, s (error < 1e-6 m/s)
    let mut elevations = vec![f64::NAN; n_sat];
    let mut approx_los = vec![Vector3::zeros(); n_sat];
    let mut residual: Vec<Option<(f64, f64)>> = vec![None; n_sat]; // (value m, time s)
    let mut selected: Vec<usize> = Vec::with_capacity(n_sat);
    let mut tracked: Vec<usize> = Vec::with_capacity(n_sat);
    let mut epochs = Vec::with_capacity(samples.len());
    let mut clocks = Vec::with_capacity(samples.len());
    let mut clock = config.clock.initial(rng);
    let mut previous_t: Option<f64> = None;

    for &s in &samples {
        let t = track.time_s[s];
        let rx = track.position_ecef[s];
        let rx_vel = track.velocity_ecef[s];
        let rx_gps = start_gps + (t - t0);
        if let Some(tp) = previous_t {
            clock = config.clock.step(&clock, t - tp, rng)?;
        }
        previous_t = Some(t);

        // Visibility at the reception time (the elevation is insensitive to
        // the light time at the mask's precision).
        let g = ecef_to_geodetic(&rx);
        let (sl, cl) = g.latitude_rad.sin_cos();
        let (so, co) = g.longitude_rad.sin_cos();
        let up = Vector3::new(cl * co, cl * so, sl);
        for i in 0..n_sat {
            match constellation.state(i, rx_gps) {
                Some(st) => {
                    elevations[i] = elevation(&st.position_ecef, &rx, &up);
                    approx_los[i] = (st.position_ecef - rx).normalize();
                }
                None => elevations[i] = f64::NAN,
            }
        }
        let visible = |i: usize| elevations[i] >= config.elevation_mask_rad;

        // Selection: keep while visible; fill up by best GDOP.
        if epochs.is_empty() {
            selected.extend((0..n_sat).filter(|&i| visible(i)));
            while selected.len() > config.n_satellites {
                let worst = (0..selected.len())
                    .map(|drop| {
                        let d = gdop(
                            selected
                                .iter()
                                .enumerate()
                                .filter(|&(j, _)| j != drop)
                                .map(|(_, &i)| approx_los[i]),
                        );
                        (drop, d, elevations[selected[drop]])
                    })
                    .min_by(|a, b| a.1.total_cmp(&b.1).then(a.2.total_cmp(&b.2)))
                    .map(|(drop, _, _)| drop)
                    .expect("selection is not empty");
                selected.remove(worst);
            }
        } else {
            selected.retain(|&i| visible(i));
            while selected.len() < config.n_satellites {
                let best = (0..n_sat)
                    .filter(|&i| visible(i) && !selected.contains(&i))
                    .map(|i| {
                        let d = gdop(
                            selected
                                .iter()
                                .chain(std::iter::once(&i))
                                .map(|&j| approx_los[j]),
                        );
                        (i, d, elevations[i])
                    })
                    .min_by(|a, b| a.1.total_cmp(&b.1).then(b.2.total_cmp(&a.2)));
                match best {
                    Some((i, _, _)) => selected.push(i),
                    None => break,
                }
            }
        }

        // Outages: keep the `allowed` highest of the selected satellites.
        let allowed = config.allowed(t);
        tracked.clear();
        tracked.extend_from_slice(&selected);
        if allowed < tracked.len() {
            tracked.sort_by(|&a, &b| elevations[b].total_cmp(&elevations[a]));
            tracked.truncate(allowed);
            tracked.sort_by_key(|i| selected.iter().position(|j| j == i));
        }

        let mut measurements = Vec::with_capacity(tracked.len());
        for &i in &tracked {
            let orbit = constellation
                .orbit(i, rx_gps)
                .expect("visible satellites have an orbit");
            let (range, tx_state) = light_time(&orbit, rx_gps, 0.0, &rx);
            let (range_plus, _) = light_time(&orbit, rx_gps, h, &(rx + rx_vel * h));
            let (range_minus, _) = light_time(&orbit, rx_gps, -h, &(rx - rx_vel * h));
            let range_rate = (range_plus - range_minus) / (2.0 * h);
            let atmosphere = match config.residual {
                Some(r) if r.std_m > 0.0 => {
                    let z: f64 = StandardNormal.sample(rng);
                    let value = match residual[i] {
                        None => r.std_m * z,
                        Some((x, tp)) => {
                            let phi = (-(t - tp) / r.correlation_time_s).exp();
                            phi * x + r.std_m * (1.0 - phi * phi).sqrt() * z
                        }
                    };
                    residual[i] = Some((value, t));
                    value
                }
                _ => 0.0,
            };
            let z_range: f64 = StandardNormal.sample(rng);
            let z_rate: f64 = StandardNormal.sample(rng);
            measurements.push(SatelliteMeasurement {
                sat_id: constellation.sat_id(i),
                position_ecef: tx_state.position_ecef,
                velocity_ecef: tx_state.velocity_ecef,
                pseudorange_m: range
                    + clock.offset_m
                    + atmosphere
                    + config.pseudorange_std_m * z_range,
                pseudorange_rate_m_s: range_rate
                    + clock.drift_m_s
                    + config.pseudorange_rate_std_m_s * z_rate,
                pseudorange_std_m: config.pseudorange_std_m,
                pseudorange_rate_std_m_s: config.pseudorange_rate_std_m_s,
            });
        }
        epochs.push(GnssEpoch {
            time_s: t,
            measurements,
        });
        clocks.push(clock);
    }
    Ok(GnssSimulation {
        epochs,
        clock: clocks,
        start_gps_time_s: start_gps,
    })
}
