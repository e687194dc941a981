//! The measurements of one tracked satellite at one epoch: the exact range
//! by light-time iteration with the Earth's rotation, its rate by a central
//! difference, and the errors added to them (module docs of [`super`]).
//!
//! Independent of [`crate::gnss::predicted_range`], so the tests can
//! compare the two.

use nalgebra::Vector3;
use rand_distr::{Distribution, StandardNormal};

use super::super::clock::ClockState;
use super::super::constellation::Orbit;
use super::super::satellite_state::SatelliteState;
use super::super::{GnssSystem, SatelliteMeasurement};
use super::carrier::CarrierTracking;
use crate::gauss_markov::GaussMarkov;
use crate::geodesy::wgs84::{EARTH_RATE_RAD_S, SPEED_OF_LIGHT_M_S};
use crate::random::Rng;

/// Half step of the central difference of the range, s: the rate's
/// truncation error is below 1e-6 m/s.
const RATE_HALF_STEP_S: f64 = 0.05;

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
) -> (f64, SatelliteState) {
    let mut tau = 0.07;
    let mut pass = 0;
    loop {
        pass += 1;
        let state = orbit.state_at(rx_gps_s, rx_offset_s - tau);
        let (s, c) = (EARTH_RATE_RAD_S * tau).sin_cos();
        let p = state.position_ecef;
        let in_rx_frame = Vector3::new(c * p.x + s * p.y, -s * p.x + c * p.y, p.z);
        let range = (in_rx_frame - rx_pos).norm();
        let next = range / SPEED_OF_LIGHT_M_S;
        if (next - tau).abs() < 1e-15 || pass == LIGHT_TIME_PASSES {
            return (range, state);
        }
        tau = next;
    }
}

/// Most passes of the light-time iteration (it converges in 3-5).
const LIGHT_TIME_PASSES: usize = 12;

/// The receiver at one epoch.
pub(super) struct Receiver {
    /// Index of the epoch.
    pub epoch: usize,
    pub time_s: f64,
    pub gps_time_s: f64,
    pub position_ecef: Vector3<f64>,
    pub velocity_ecef: Vector3<f64>,
    pub clock: ClockState,
}

/// The errors the simulator adds: white noise and the optional
/// Gauss-Markov residual of each satellite, continued between the epochs
/// at which it is measured.
pub(super) struct MeasurementErrors {
    pub pseudorange_std_m: f64,
    pub pseudorange_rate_std_m_s: f64,
    residual: Option<GaussMarkov>,
    /// Per satellite: (value m, time s) of its residual at its last epoch.
    residual_state: Vec<Option<(f64, f64)>>,
}

impl MeasurementErrors {
    pub fn new(
        pseudorange_std_m: f64,
        pseudorange_rate_std_m_s: f64,
        residual: Option<GaussMarkov>,
        satellites: usize,
    ) -> Self {
        Self {
            pseudorange_std_m,
            pseudorange_rate_std_m_s,
            residual: residual.filter(|p| p.psd() > 0.0),
            residual_state: vec![None; satellites],
        }
    }

    /// The residual of satellite `i` at `t` (one draw when enabled): a
    /// stationary start, then exact steps over the time since its last value.
    fn residual(&mut self, i: usize, t: f64, rng: &mut Rng) -> f64 {
        let Some(process) = self.residual else {
            return 0.0;
        };
        let z: f64 = StandardNormal.sample(rng);
        let value = match self.residual_state[i] {
            None => process.stationary_std() * z,
            Some((x, tp)) => process.step(t - tp).next(x, z),
        };
        self.residual_state[i] = Some((value, t));
        value
    }

    /// Pseudorange ρ + b + ISB + residual + noise and rate ρ̇ + ḃ + noise
    /// of satellite `i` of `system` on `orbit` (satellite clock errors
    /// taken as corrected; `inter_system_bias_m` is its system's bias
    /// against GPS, 0 for GPS), and with `carrier` its carrier phase (the
    /// same geometry, clock and bias, the residual's sign reversed: see
    /// [`super::carrier`]). Draws from `rng`: residual (if enabled),
    /// pseudorange noise, rate noise; the carrier's from its own stream.
    pub fn measure(
        &mut self,
        (i, sat_id, system): (usize, u16, GnssSystem),
        inter_system_bias_m: f64,
        orbit: &Orbit<'_>,
        rx: &Receiver,
        rng: &mut Rng,
        carrier: Option<&mut CarrierTracking>,
    ) -> SatelliteMeasurement {
        let (r, v, h) = (rx.position_ecef, rx.velocity_ecef, RATE_HALF_STEP_S);
        let (range, tx_state) = light_time(orbit, rx.gps_time_s, 0.0, &r);
        let (range_plus, _) = light_time(orbit, rx.gps_time_s, h, &(r + v * h));
        let (range_minus, _) = light_time(orbit, rx.gps_time_s, -h, &(r - v * h));
        let range_rate = (range_plus - range_minus) / (2.0 * h);
        let residual = self.residual(i, rx.time_s, rng);
        let z_range: f64 = StandardNormal.sample(rng);
        let z_rate: f64 = StandardNormal.sample(rng);
        let common_m = range + rx.clock.offset_m + inter_system_bias_m;
        SatelliteMeasurement {
            sat_id,
            system,
            position_ecef: tx_state.position_ecef,
            velocity_ecef: tx_state.velocity_ecef,
            pseudorange_m: common_m + residual + self.pseudorange_std_m * z_range,
            pseudorange_rate_m_s: range_rate
                + rx.clock.drift_m_s
                + self.pseudorange_rate_std_m_s * z_rate,
            pseudorange_std_m: self.pseudorange_std_m,
            pseudorange_rate_std_m_s: self.pseudorange_rate_std_m_s,
            carrier: carrier
                .map(|c| c.measure(i, sat_id, rx.epoch, rx.time_s, common_m - residual)),
        }
    }
}
