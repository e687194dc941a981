//! GNSS: satellite orbits from broadcast ephemerides (GPS, Galileo and
//! BeiDou, one Keplerian user algorithm; GLONASS by Runge-Kutta
//! integration of its PZ-90 state vector) or a
//! synthetic Walker constellation, precise orbits (SP3) for checking them,
//! predicted ranges with the Sagnac correction, a two-state receiver clock,
//! the measurement simulator (method §5) and the least-squares fix.
//!
//! Time is GPS time in seconds since 1980-01-06 00:00:00 GPST
//! (`gps_time_s`); positions and velocities are in ECEF (WGS84), m and m/s;
//! receiver clock offset and drift are in metres and m/s (c × seconds).

mod atmosphere;
mod beidou_ephemeris;
mod broadcast_orbit;
pub(crate) mod broadcast_ranges;
mod clock;
mod cnav_ephemeris;
mod constellation;
mod dual_frequency;
mod ephemeris;
pub(crate) mod ephemeris_conflicts;
mod fix;
mod galileo_ephemeris;
mod glonass_ephemeris;
mod glonass_orbit;
mod glonass_slots;
mod measurement_rows;
pub(crate) mod nav_record;
mod observables;
mod observation_file;
pub mod plausible;
mod pseudorange_weights;
mod range;
mod residual_test;
mod rinex2_obs;
mod rinex4_nav;
mod rinex_fields;
mod rinex_nav;
mod rinex_nav_cnav;
mod rinex_nav_glonass;
mod rinex_obs;
mod rinex_write;
mod satellite_state;
mod simulate;
mod sp3;
mod sp3_interpolation;
mod system;
mod time;
mod utc;
mod walker;

pub use atmosphere::{parse_klobuchar, read_klobuchar, saastamoinen_delay_m, Klobuchar};
pub use beidou_ephemeris::BeidouEphemeris;
pub use broadcast_orbit::{BroadcastOrbit, BroadcastSystem, OrbitFrame, BEIDOU, GALILEO, GPS};
pub use clock::{ClockState, ReceiverClockModel};
pub use cnav_ephemeris::{cnav_ura_m, CnavEphemeris, CnavGroupDelays};
pub use constellation::{
    Constellation, Orbit, SystemWalker, EPHEMERIS_VALIDITY_S, MAX_SATELLITES_PER_SYSTEM,
};
pub use dual_frequency::{
    geometry_free_delay_m, DelayMeasurement, IonosphereTracks, IONOSPHERE_RANDOM_WALK_M2_S,
};
pub use ephemeris::{
    ura_index, ura_m, GpsEphemeris, LnavEphemeris, GPS_EARTH_RATE_RAD_S, GPS_GM_M3_S2,
};
pub use fix::{
    post_fit_residuals, solve_fix_all_satellites, Dops, ExcludedSatellites, Fix, PostFitResidual,
};
pub use galileo_ephemeris::{sisa_index, sisa_m, InavEphemeris};
pub use glonass_ephemeris::{GlonassEphemeris, GLONASS_VALIDITY_S};
pub use glonass_orbit::{
    propagate_glonass, GLONASS_EARTH_RATE_RAD_S, GLONASS_EQUATORIAL_RADIUS_M, GLONASS_GM_M3_S2,
    GLONASS_J2,
};
pub use glonass_slots::{g1_wavelength_m, nominal_channel};
pub use measurement_rows::{
    carrier_of, check_measurement, epochs_from_rows, sat_id, MAX_SATELLITE_RADIUS_M,
    MAX_SATELLITE_SPEED_M_S,
};
pub use observables::{
    broadcast_epochs, broadcast_epochs_with_signals, broadcast_states, ephemeris_coverage,
    gps_l1_epochs, EphemerisCoverage, EpochSignals, ObservableOptions, ReceivedSignal,
    DEFAULT_CARRIER_PHASE_STD_M, DEFAULT_ELEVATION_MASK_DEG, DEFAULT_PSEUDORANGE_RATE_STD_M_S,
    DEFAULT_PSEUDORANGE_STD_M, GPS_L1_WAVELENGTH_M, MIN_TROPOSPHERE_MASK_DEG,
};
pub use observation_file::{event_kind, ObservationEpoch, ObservationFile, SatelliteObservations};
pub use pseudorange_weights::{
    rtklib_system_factor, rtklib_variance_m2, PseudorangeWeighting, RangeCorrections,
};
pub use range::{predicted_range, RangePrediction};
pub use residual_test::{solve_fix, solve_fix_with, ResidualTest, DEFAULT_FALSE_ALARM_PROBABILITY};
pub use rinex2_obs::rinex3_code;
pub use rinex_nav::{
    parse_broadcast_nav, parse_rinex_nav, read_broadcast_nav, read_rinex_nav, BroadcastNav,
};
pub use rinex_obs::{parse_rinex_obs, read_rinex_obs};
pub(crate) use rinex_obs::{SignalLayout, LLI_HALF_CYCLE, LLI_LOST_LOCK};
pub use rinex_write::{
    format_rinex_nav, format_rinex_obs, write_rinex_nav, write_rinex_obs, NavFileEphemerides,
    RinexNavVersion, RinexProvenance,
};
pub use satellite_state::SatelliteState;
pub(crate) use simulate::simulate_track;
pub use simulate::{
    apply_outages, keep_highest, simulate, simulate_with_truth, AtmosphericResidual, CycleSlip,
    GnssSimulation, Outage, ReceiverTrack, SimulationConfig,
};
pub use sp3::{parse_sp3, read_sp3, Sp3};
pub use system::{
    inter_system_biases, satellite_name, satellite_number, system_of_number, GnssSystem,
    FIX_BIAS_SYSTEMS, INTER_SYSTEM_BIAS_SYSTEMS,
};
pub use time::{
    calendar_from_gps_time, checked_gps_time_from_calendar, gps_minus_utc_s,
    gps_time_from_calendar, utc_text_from_gps_time, CALENDAR_YEARS, LEAP_SECONDS_KNOWN_UNTIL,
    SECONDS_PER_WEEK, UNIX_TO_GPS_S,
};
pub use utc::{checked_gps_time_from_utc, leap_seconds_on};
pub use walker::{Walker, WalkerConfig};

use nalgebra::Vector3;

/// One satellite's measurements at one epoch, as the coupled filters use them.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct SatelliteMeasurement {
    /// Satellite number, unique across systems ([`satellite_number`]: the
    /// GPS PRN, 100 + the Galileo PRN, 200 + the BeiDou PRN, 300 + the
    /// GLONASS slot; a simulated Walker slot 1..N).
    pub sat_id: u16,
    /// The satellite's system: its pseudorange carries the system's
    /// inter-system bias (none for GPS, the clock's reference).
    pub system: GnssSystem,
    /// Satellite position at signal transmission time, in the ECEF frame of
    /// the transmission time, m (apply [`predicted_range`] for the Sagnac
    /// rotation to the reception frame).
    pub position_ecef: Vector3<f64>,
    /// Satellite velocity at transmission time, ECEF, m/s.
    pub velocity_ecef: Vector3<f64>,
    /// Pseudorange, m (satellite clock already corrected).
    pub pseudorange_m: f64,
    /// Pseudorange rate, m/s (satellite clock drift already corrected).
    pub pseudorange_rate_m_s: f64,
    /// One-sigma pseudorange noise the measurement was simulated with, m.
    pub pseudorange_std_m: f64,
    /// One-sigma pseudorange-rate noise, m/s.
    pub pseudorange_rate_std_m_s: f64,
    /// The carrier phase, when the receiver tracks it.
    pub carrier: Option<CarrierPhase>,
}

impl SatelliteMeasurement {
    /// Whether a range can be predicted from the satellite's state: finite,
    /// and beyond 10 000 km of the Earth's centre (the filters record a
    /// measurement of a satellite without one as invalid).
    pub fn has_usable_satellite_state(&self) -> bool {
        self.position_ecef.iter().all(|x| x.is_finite())
            && self.velocity_ecef.iter().all(|x| x.is_finite())
            && self.position_ecef.norm() > 1.0e7
    }
}

/// A satellite's carrier phase at one epoch, as a range.
///
/// The carrier range holds an unknown constant per continuous lock (the
/// ambiguity), so only its change between consecutive epochs is used: the
/// time-differenced carrier phase of [`crate::coupling`]'s tight filter.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct CarrierPhase {
    /// Accumulated carrier range λ·φ, m, corrected as the pseudorange is
    /// (satellite clock, troposphere) and with the ionosphere's sign
    /// reversed (the phase advances where the code is delayed).
    pub range_m: f64,
    /// One-sigma noise of the carrier range, m.
    pub std_m: f64,
    /// The receiver reports lock lost (or the half-cycle state changed)
    /// since its previous epoch: the change from that epoch may hold a
    /// cycle slip and is not used.
    pub loss_of_lock: bool,
}

/// All measurements at one receiver epoch.
#[derive(Debug, Clone, PartialEq)]
pub struct GnssEpoch {
    /// Reception time on the trajectory's time axis, s.
    pub time_s: f64,
    /// The satellites tracked at this epoch (empty during a total outage).
    pub measurements: Vec<SatelliteMeasurement>,
}
