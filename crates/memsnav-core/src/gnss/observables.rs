//! Filter-ready pseudoranges and rates from a RINEX (or UBX) observation
//! file and broadcast ephemerides, for GPS, Galileo, BeiDou and GLONASS
//! (each GLONASS satellite on its own FDMA carrier): satellite
//! position and velocity at transmission time, pseudorange corrected for
//! the satellite clock (with relativity and the signal's group delay), the
//! Klobuchar ionosphere scaled to the signal's frequency and the
//! Saastamoinen troposphere, and the pseudorange rate from the Doppler
//! (Groves §9.3, eqs. 9.3-9.4 and 8.48). Each system's pseudoranges keep
//! the receiver's inter-system bias: the tight filter estimates it.

use std::collections::{BTreeMap, HashMap};

use nalgebra::Vector3;

use super::atmosphere::{saastamoinen_delay_m, Klobuchar};
use super::beidou_ephemeris::BeidouEphemeris;
use super::cnav_ephemeris::CnavGroupDelays;
use super::constellation::{Constellation, Orbit, EPHEMERIS_VALIDITY_S};
use super::dual_frequency::{geometry_free_delay_m, DelayMeasurement, IonosphereTracks};
use super::ephemeris::ura_m;
use super::galileo_ephemeris::{sisa_m, InavEphemeris};
use super::glonass_ephemeris::{GlonassEphemeris, GLONASS_VALIDITY_S};
use super::observation_file::ObservationFile;
use super::pseudorange_weights::{
    rtklib_variance_m2, signal_strength_scale, PseudorangeWeighting, RangeCorrections,
    RTKLIB_GLONASS_EPHEMERIS_ERROR_M,
};
use super::rinex_nav::BroadcastNav;
use super::rinex_obs::{LLI_HALF_CYCLE, LLI_LOST_LOCK};
use super::satellite_state::SatelliteState;
use super::system::{satellite_number, GnssSystem};
use super::{CarrierPhase, GnssEpoch, SatelliteMeasurement};
use crate::geodesy::wgs84::SPEED_OF_LIGHT_M_S;
use crate::geodesy::{c_n_e, ecef_to_geodetic};
use crate::{validate, Error, Result};

/// GPS L1 (and Galileo E1, BeiDou B1C) carrier frequency, Hz.
const L1_FREQUENCY_HZ: f64 = 1_575.42e6;
/// GPS L2 carrier frequency, Hz (IS-GPS-200 §3.3.1.1).
const L2_FREQUENCY_HZ: f64 = 1_227.60e6;
/// GPS L5 and Galileo E5a carrier frequency, Hz (IS-GPS-705 §3.3.1.1,
/// Galileo OS SIS ICD §2.3).
const L5_FREQUENCY_HZ: f64 = 1_176.45e6;
/// Galileo E5b and BeiDou B2I carrier frequency, Hz.
const E5B_FREQUENCY_HZ: f64 = 1_207.14e6;

/// GPS L1 carrier wavelength, m (c / 1575.42 MHz).
pub const GPS_L1_WAVELENGTH_M: f64 = SPEED_OF_LIGHT_M_S / L1_FREQUENCY_HZ;

/// The signals each system's measurements are taken from, in order of
/// preference: RINEX 3 band and attribute, the carrier frequency and the
/// signal's name.
/// GPS L1 C/A; Galileo E1 (pilot C, else data B, else both); BeiDou B1I, B2I, B3I
/// (the D1 ephemeris's group delays are for these three; B1C and B2a
/// need the CNAV1/2 ones, not decoded). Frequencies: IS-GPS-200 §3.3.1.1,
/// Galileo OS SIS ICD §2.3, BeiDou B1I ICD §4.2 and B3I ICD §4.2.
fn signals(system: GnssSystem) -> &'static [(&'static str, f64, &'static str)] {
    match system {
        GnssSystem::Gps => &[("1C", L1_FREQUENCY_HZ, "L1 C/A")],
        GnssSystem::Galileo => &[
            ("1C", L1_FREQUENCY_HZ, "E1 C"),
            ("1B", L1_FREQUENCY_HZ, "E1 B"),
            // B+C, as RINEX 2 files' C1 are read.
            ("1X", L1_FREQUENCY_HZ, "E1 B+C"),
        ],
        GnssSystem::Beidou => &[
            ("2I", 1_561.098e6, "B1I"),
            ("7I", E5B_FREQUENCY_HZ, "B2I"),
            ("6I", 1_268.52e6, "B3I"),
        ],
        // G1 C/A on channel 0; each satellite's own carrier is its
        // channel's ([`SelectedOrbit::carrier_hz`]).
        GnssSystem::Glonass => &[("1C", 1_602.0e6, "G1 C/A")],
    }
}

/// The signals whose pseudorange, beside the measurement's, gives a
/// satellite's ionospheric delay
/// ([`ObservableOptions::dual_frequency_ionosphere`]), in order of
/// preference (the widest frequency gap first: the least noise): GPS L5
/// or L2C (their group delays are CNAV's inter-signal corrections),
/// Galileo E5a or E5b (I/NAV's two BGDs), BeiDou the D1 signals of
/// another band (TGD1, TGD2).
fn second_signals(system: GnssSystem) -> &'static [(&'static str, f64, &'static str)] {
    match system {
        GnssSystem::Gps => &[
            ("5Q", L5_FREQUENCY_HZ, "L5 Q"),
            ("5I", L5_FREQUENCY_HZ, "L5 I"),
            ("2L", L2_FREQUENCY_HZ, "L2C (L)"),
            ("2S", L2_FREQUENCY_HZ, "L2C (M)"),
            ("2X", L2_FREQUENCY_HZ, "L2C (M+L)"),
        ],
        GnssSystem::Galileo => &[
            ("5Q", L5_FREQUENCY_HZ, "E5a Q"),
            ("5I", L5_FREQUENCY_HZ, "E5a I"),
            ("7Q", E5B_FREQUENCY_HZ, "E5b Q"),
            ("7I", E5B_FREQUENCY_HZ, "E5b I"),
            ("5X", L5_FREQUENCY_HZ, "E5a I+Q"),
            ("7X", E5B_FREQUENCY_HZ, "E5b I+Q"),
        ],
        GnssSystem::Beidou => signals(GnssSystem::Beidou),
        // G2's group delay relative to G1 is not taken from the files.
        GnssSystem::Glonass => &[],
    }
}

/// What one measurement of [`broadcast_epochs_with_signals`] was made
/// from, kept beside it (the per-satellite tables of a report): the
/// signal, its strength and where the satellite stood.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct ReceivedSignal {
    /// The signal's name ("L1 C/A", "E1 C", "B3I").
    pub name: &'static str,
    /// Its C/N0 (the S observation), dB-Hz; NaN when the file has none
    /// (the noise model then takes 45 dB-Hz).
    pub cn0_db_hz: f64,
    /// The satellite's elevation at the reference position, rad.
    pub elevation_rad: f64,
    /// The second signal the ionospheric delay was measured with (see
    /// [`ObservableOptions::dual_frequency_ionosphere`]); `None` when the
    /// broadcast model gave it.
    pub ionosphere_signal: Option<&'static str>,
}

/// Each epoch's [`ReceivedSignal`]s, in the order of its measurements.
pub type EpochSignals = Vec<Vec<ReceivedSignal>>;

/// How raw observations become measurements.
#[derive(Debug, Clone, PartialEq)]
pub struct ObservableOptions {
    /// Receiver position for elevations and atmospheric delays, ECEF m
    /// (a few km off changes the delays by millimetres).
    pub reference_position_ecef: Vector3<f64>,
    /// A moving receiver's position at each observation epoch, ECEF m
    /// (one per epoch, in file order), used instead of
    /// `reference_position_ecef` where given; empty: that one point.
    pub reference_track_ecef: Vec<Vector3<f64>>,
    /// Satellites below this elevation are left out, rad.
    pub elevation_mask_rad: f64,
    /// Satellites whose C/N0 is below this are left out, dB-Hz.
    pub min_cn0_db_hz: f64,
    /// Broadcast ionosphere; `None` leaves the ionospheric delay in.
    pub ionosphere: Option<Klobuchar>,
    /// Measure each satellite's ionospheric delay from a second signal's
    /// pseudorange where the file has one whose group delay the ephemeris
    /// gives (`second_signals`), smoothed per satellite
    /// ([`super::IonosphereTracks`]); the other satellites keep
    /// `ionosphere`. The carrier phase keeps `ionosphere` too: its changes
    /// between epochs are all the filter uses, and the smooth model's
    /// are nearer the truth's (millimetres) than the estimate's steps.
    pub dual_frequency_ionosphere: bool,
    /// Apply the Saastamoinen troposphere.
    pub troposphere: bool,
    /// How each pseudorange's σ is set ([`PseudorangeWeighting`]; default
    /// RTKLIB's single-point error model).
    pub weighting: PseudorangeWeighting,
    /// Pseudorange one-sigma at 45 dB-Hz and the zenith, m, of the
    /// [`PseudorangeWeighting::SignalStrength`] model (the RTKLIB model
    /// does not read it); the rates' and carrier's σ scale with C/N0 and
    /// elevation alike in both models.
    pub pseudorange_std_m: f64,
    /// Pseudorange-rate one-sigma at 45 dB-Hz, m/s (0: no rates used).
    pub pseudorange_rate_std_m_s: f64,
    /// Carrier-range one-sigma at 45 dB-Hz and the zenith, m (0: no
    /// carrier phase kept).
    pub carrier_phase_std_m: f64,
    /// The systems whose satellites are used (default GPS alone).
    pub systems: Vec<GnssSystem>,
    /// Only these satellites, by number ([`satellite_number`]: a GPS PRN
    /// is its own number, E n is 100 + n, C n is 200 + n); empty: every
    /// satellite of `systems` with an ephemeris.
    pub satellites: Vec<u16>,
}

/// Default pseudorange one-sigma at 45 dB-Hz and the zenith, m: a u-blox
/// class receiver's code noise with the broadcast models' residuals (the
/// simulator draws its noise with it too).
pub const DEFAULT_PSEUDORANGE_STD_M: f64 = 3.0;
/// Default pseudorange-rate one-sigma at 45 dB-Hz, m/s (Doppler).
pub const DEFAULT_PSEUDORANGE_RATE_STD_M_S: f64 = 0.1;
/// Default carrier-range one-sigma at 45 dB-Hz and the zenith, m: the
/// tracking loop's thermal noise is below a millimetre there (Kaplan &
/// Hegarty 2017, eq. 8.40: λ/2π · √(B_n / C/N0) = 0.5 mm at 10 Hz); carrier
/// multipath and the antenna's phase centre add a few.
pub const DEFAULT_CARRIER_PHASE_STD_M: f64 = 0.003;
/// Default elevation mask, degrees.
pub const DEFAULT_ELEVATION_MASK_DEG: f64 = 10.0;
/// Lowest elevation mask with the troposphere applied, degrees: the
/// Saastamoinen delay's 1/sin(el) mapping grows without bound at the
/// horizon (2.3 m at the zenith, 26 m at 5°, 33 km at 0.004°), where the
/// real delay stays under about 100 m; RTKLIB's default mask is 15°.
pub const MIN_TROPOSPHERE_MASK_DEG: f64 = 5.0;

impl ObservableOptions {
    /// Defaults for a u-blox class receiver: 10° mask, 25 dB-Hz, Klobuchar
    /// with RTKLIB's default coefficients, troposphere on, 3 m and 0.1 m/s.
    pub fn new(reference_position_ecef: Vector3<f64>) -> Self {
        Self {
            reference_position_ecef,
            reference_track_ecef: Vec::new(),
            elevation_mask_rad: DEFAULT_ELEVATION_MASK_DEG.to_radians(),
            min_cn0_db_hz: 25.0,
            ionosphere: Some(Klobuchar::RTKLIB_DEFAULT),
            dual_frequency_ionosphere: false,
            troposphere: true,
            weighting: PseudorangeWeighting::default(),
            pseudorange_std_m: DEFAULT_PSEUDORANGE_STD_M,
            pseudorange_rate_std_m_s: DEFAULT_PSEUDORANGE_RATE_STD_M_S,
            carrier_phase_std_m: DEFAULT_CARRIER_PHASE_STD_M,
            systems: vec![GnssSystem::Gps],
            satellites: Vec::new(),
        }
    }

    fn validate(&self) -> Result<()> {
        validate::finite_vectors("reference_position_ecef", &[self.reference_position_ecef])?;
        crate::geodesy::domain::check_position_ecef(
            "reference_position_ecef",
            &[self.reference_position_ecef],
        )?;
        validate::finite_vectors("reference_position_ecef", &self.reference_track_ecef)?;
        crate::geodesy::domain::check_position_ecef(
            "reference_position_ecef",
            &self.reference_track_ecef,
        )?;
        validate::finite_scalars("elevation_mask", &[self.elevation_mask_rad])?;
        if self.troposphere && self.elevation_mask_rad < MIN_TROPOSPHERE_MASK_DEG.to_radians() {
            return Err(Error::invalid(
                "elevation_mask",
                format!(
                    "{:.2}° is below {MIN_TROPOSPHERE_MASK_DEG}°, the lowest mask with the troposphere applied: its 1/sin(el) mapping grows without bound at the horizon (33 km at 0.004°); raise the mask or turn the troposphere off",
                    self.elevation_mask_rad.to_degrees()
                ),
            ));
        }
        validate::finite_scalars("min_cn0", &[self.min_cn0_db_hz])?;
        if let Some(klobuchar) = &self.ionosphere {
            klobuchar.validate("klobuchar")?;
        }
        validate::positive("pseudorange_std", self.pseudorange_std_m)?;
        validate::non_negative("pseudorange_rate_std", self.pseudorange_rate_std_m_s)?;
        validate::non_negative("carrier_phase_std", self.carrier_phase_std_m)?;
        if self.systems.is_empty() {
            return Err(Error::invalid(
                "systems",
                "is empty: name at least one of G (GPS), E (Galileo), C (BeiDou), R (GLONASS)",
            ));
        }
        Ok(())
    }
}

/// One satellite's broadcast orbit and clock, selected for an epoch.
#[derive(Debug, Clone, Copy)]
enum SelectedOrbit<'a> {
    /// GPS LNAV (the L1 C/A clock) or a Walker slot, with the satellite's
    /// CNAV group delays when there are any.
    Gps(Orbit<'a>, Option<&'a CnavGroupDelays>),
    /// Galileo I/NAV (the E1 clock).
    Galileo(&'a InavEphemeris),
    /// BeiDou D1 (the B3I clock).
    Beidou(&'a BeidouEphemeris),
    /// GLONASS (the G1 clock, τ_n).
    Glonass(&'a GlonassEphemeris),
}

impl SelectedOrbit<'_> {
    fn state_at(&self, gps_time_s: f64, offset_s: f64) -> SatelliteState {
        match self {
            SelectedOrbit::Gps(o, _) => o.state_at(gps_time_s, offset_s),
            SelectedOrbit::Galileo(e) => e.state_at(gps_time_s, offset_s),
            SelectedOrbit::Beidou(e) => e.state_at(gps_time_s, offset_s),
            SelectedOrbit::Glonass(e) => e.state_at(gps_time_s, offset_s),
        }
    }

    /// The ephemeris' broadcast ranging accuracy, m, for the RTKLIB error
    /// model: Galileo's SISA (500 m without a prediction, RTKLIB's
    /// `STD_GAL_NAPA`), BeiDou's URA, 5 m for GLONASS (RTKLIB's
    /// `ERREPH_GLO`: its records carry no accuracy), and URA index 0's
    /// 2.4 m for GPS (the RINEX reader keeps no accuracy; healthy GPS
    /// satellites broadcast index 0) and for Walker slots.
    fn ranging_accuracy_m(&self) -> f64 {
        match self {
            SelectedOrbit::Gps(..) => ura_m(0),
            SelectedOrbit::Galileo(e) => sisa_m(e.sisa_index).unwrap_or(500.0),
            SelectedOrbit::Beidou(e) => ura_m(e.urai),
            SelectedOrbit::Glonass(_) => RTKLIB_GLONASS_EPHEMERIS_ERROR_M,
        }
    }

    /// The carrier of `signal` from this satellite, Hz: the table's, or a
    /// GLONASS satellite's channel's (1602 + 0.5625 k MHz on G1).
    fn carrier_hz(&self, signal: &SignalTypes) -> f64 {
        match (self, signal.signal.as_bytes().first()) {
            (SelectedOrbit::Glonass(e), Some(b'1')) => e.g1_frequency_hz(),
            (SelectedOrbit::Glonass(e), Some(b'2')) => e.g2_frequency_hz(),
            _ => signal.frequency_hz,
        }
    }

    /// The group delay of the signal of RINEX band and attribute `signal`
    /// beyond the one `state_at`'s clock already holds, s; `None` when the
    /// ephemeris has none for it. GPS: L1 C/A's is in the clock; another
    /// signal's differs from it by ISC_L1CA − ISC_X (IS-GPS-200
    /// §30.3.3.3.1.1.1).
    fn extra_group_delay_s(&self, signal: &str) -> Option<f64> {
        let band = signal.chars().next()?;
        match self {
            SelectedOrbit::Gps(_, delays) => match (signal, delays) {
                ("1C", _) => Some(0.0),
                (_, Some(d)) => Some(d.group_delay_s(signal)? - d.group_delay_s("1C")?),
                (_, None) => None,
            },
            SelectedOrbit::Galileo(e) => Some(e.group_delay_s(band)? - e.group_delay_s('1')?),
            SelectedOrbit::Beidou(e) => e.group_delay_s(band),
            // τ_n is the G1 clock (ICD §4.4); no other band's delay is read.
            SelectedOrbit::Glonass(_) => (band == '1').then_some(0.0),
        }
    }
}

/// The healthy record of `records` with t_oe nearest `gps_time_s`, within
/// `validity_s` ([`EPHEMERIS_VALIDITY_S`], GLONASS's [`GLONASS_VALIDITY_S`]).
fn nearest<T>(
    records: &[T],
    keep: impl Fn(&T) -> bool,
    toe_gps_s: impl Fn(&T) -> f64,
    gps_time_s: f64,
    validity_s: f64,
) -> Option<&T> {
    records
        .iter()
        .filter(|r| keep(r) && (gps_time_s - toe_gps_s(r)).abs() <= validity_s)
        .min_by(|a, b| {
            (gps_time_s - toe_gps_s(a))
                .abs()
                .total_cmp(&(gps_time_s - toe_gps_s(b)).abs())
        })
}

/// The ephemerides the measurements are built from.
struct Ephemerides<'a> {
    gps: &'a Constellation,
    gps_group_delays: Option<&'a BTreeMap<u16, CnavGroupDelays>>,
    galileo: &'a [InavEphemeris],
    beidou: &'a [BeidouEphemeris],
    glonass: &'a [GlonassEphemeris],
}

impl<'a> Ephemerides<'a> {
    /// The ephemerides of `nav`, its GPS ones as `gps`.
    fn of(nav: &'a BroadcastNav, gps: &'a Constellation) -> Self {
        Self {
            gps,
            gps_group_delays: Some(&nav.gps_group_delays),
            galileo: &nav.galileo,
            beidou: &nav.beidou,
            glonass: &nav.glonass,
        }
    }

    fn select(&self, system: GnssSystem, prn: u16, gps_time_s: f64) -> Option<SelectedOrbit<'_>> {
        match system {
            GnssSystem::Gps => {
                let i = (0..self.gps.len()).find(|&i| self.gps.sat_id(i) == prn)?;
                let delays = self.gps_group_delays.and_then(|d| d.get(&prn));
                self.gps
                    .orbit(i, gps_time_s)
                    .map(|o| SelectedOrbit::Gps(o, delays))
            }
            GnssSystem::Galileo => nearest(
                self.galileo,
                |e| e.svid == prn && e.is_healthy(),
                |e| e.orbit.toe_gps_s,
                gps_time_s,
                EPHEMERIS_VALIDITY_S,
            )
            .map(SelectedOrbit::Galileo),
            GnssSystem::Beidou => nearest(
                self.beidou,
                |e| e.prn == prn && e.is_healthy(),
                |e| e.orbit.toe_gps_s,
                gps_time_s,
                EPHEMERIS_VALIDITY_S,
            )
            .map(SelectedOrbit::Beidou),
            GnssSystem::Glonass => nearest(
                self.glonass,
                |e| e.slot == prn && e.is_healthy(),
                |e| e.tb_gps_s,
                gps_time_s,
                GLONASS_VALIDITY_S,
            )
            .map(SelectedOrbit::Glonass),
        }
    }
}

/// Builds one [`GnssEpoch`] per observation epoch (time = GPS time, s) from
/// the GPS `C1C` pseudoranges, `D1C` Dopplers and `S1C` signal strengths
/// and the satellites of `constellation` (broadcast ephemerides or a
/// Walker pattern); `options.systems` is not consulted. A satellite without
/// a valid ephemeris, below the mask or too weak is left out; an epoch may
/// end up empty.
pub fn gps_l1_epochs(
    observations: &ObservationFile,
    constellation: &Constellation,
    options: &ObservableOptions,
) -> Result<Vec<GnssEpoch>> {
    let options = ObservableOptions {
        systems: vec![GnssSystem::Gps],
        ..options.clone()
    };
    let ephemerides = Ephemerides {
        gps: constellation,
        gps_group_delays: None,
        galileo: &[],
        beidou: &[],
        glonass: &[],
    };
    epochs_from(observations, &ephemerides, &options).map(|(epochs, _)| epochs)
}

/// [`gps_l1_epochs`] for the systems of `options.systems` with the
/// broadcast ephemerides of `nav`: GPS L1 C/A with LNAV, Galileo E1 with
/// I/NAV (the E1 clock: BGD(E1, E5b) applied), BeiDou B1I, B2I or B3I
/// (whichever the file has first, in that order) with D1 (TGD1, TGD2 or
/// none: B3I is the clock's reference), GLONASS G1 C/A with its broadcast
/// state (t_b within 30 min) on the satellite's channel; unhealthy
/// ephemerides are not used. The Klobuchar delay, given for L1, is scaled
/// by (f_L1 / f)² (IS-GPS-200 §20.3.3.5.2.5). Satellite numbers as
/// [`satellite_number`].
pub fn broadcast_epochs(
    observations: &ObservationFile,
    nav: &BroadcastNav,
    options: &ObservableOptions,
) -> Result<Vec<GnssEpoch>> {
    broadcast_epochs_with_signals(observations, nav, options).map(|(epochs, _)| epochs)
}

/// [`broadcast_epochs`] with, beside each measurement, the signal it was
/// taken from, its C/N0 and the satellite's elevation.
pub fn broadcast_epochs_with_signals(
    observations: &ObservationFile,
    nav: &BroadcastNav,
    options: &ObservableOptions,
) -> Result<(Vec<GnssEpoch>, EpochSignals)> {
    let gps = Constellation::from_ephemerides(nav.gps.clone());
    epochs_from(observations, &Ephemerides::of(nav, &gps), options)
}

/// Each satellite's broadcast state at each time, row-major
/// `[k * satellites.len() + j]` for time `gps_time_s[k]` and satellite
/// `satellites[j]` (system, PRN or GLONASS slot): the healthy ephemeris
/// the measurements would use (t_oe nearest within ±2 h, GLONASS t_b
/// within 30 min), its clock for the signal [`broadcast_epochs`] measures
/// (GPS L1 C/A, Galileo E1, BeiDou B3I, GLONASS G1); `None` where no
/// ephemeris covers the time.
pub fn broadcast_states(
    nav: &BroadcastNav,
    satellites: &[(GnssSystem, u16)],
    gps_time_s: &[f64],
) -> Vec<Option<SatelliteState>> {
    let gps = Constellation::from_ephemerides(nav.gps.clone());
    let ephemerides = Ephemerides::of(nav, &gps);
    gps_time_s
        .iter()
        .flat_map(|&t| {
            let ephemerides = &ephemerides;
            satellites.iter().map(move |&(system, prn)| {
                ephemerides
                    .select(system, prn, t)
                    .map(|orbit| orbit.state_at(t, 0.0))
            })
        })
        .collect()
}

/// How far broadcast ephemerides cover an observation file, for the
/// systems and satellites `options` asks for.
#[derive(Debug, Clone, Default, PartialEq)]
pub struct EphemerisCoverage {
    /// Epochs with satellites of those systems, none with an ephemeris.
    pub epochs_without_ephemeris: usize,
    /// Epochs with satellites of those systems.
    pub epochs_observed: usize,
    /// Satellites observed but never covered by an ephemeris, RINEX names.
    pub satellites_without_ephemeris: Vec<String>,
}

/// The [`EphemerisCoverage`] of `observations` by `nav`.
pub fn ephemeris_coverage(
    observations: &ObservationFile,
    nav: &BroadcastNav,
    options: &ObservableOptions,
) -> EphemerisCoverage {
    let gps = Constellation::from_ephemerides(nav.gps.clone());
    let ephemerides = Ephemerides::of(nav, &gps);
    let mut coverage = EphemerisCoverage::default();
    let mut covered: BTreeMap<u16, bool> = BTreeMap::new();
    for e in &observations.epochs {
        let mut observed = false;
        let mut any = false;
        for s in &e.satellites {
            let Some(system) =
                GnssSystem::from_letter(s.system).filter(|x| options.systems.contains(x))
            else {
                continue;
            };
            let number = satellite_number(system, s.prn);
            if !options.satellites.is_empty() && !options.satellites.contains(&number) {
                continue;
            }
            observed = true;
            let has = ephemerides.select(system, s.prn, e.gps_time_s).is_some();
            any |= has;
            *covered.entry(number).or_default() |= has;
        }
        coverage.epochs_observed += usize::from(observed);
        coverage.epochs_without_ephemeris += usize::from(observed && !any);
    }
    coverage.satellites_without_ephemeris = covered
        .iter()
        .filter(|(_, &c)| !c)
        .map(|(&n, _)| super::system::satellite_name(n))
        .collect();
    coverage
}

/// The observation types of one system's chosen signal: (C, L, D, S) type
/// indices, the RINEX band and attribute and the carrier frequency.
struct SignalTypes {
    code: usize,
    carrier: Option<usize>,
    doppler: Option<usize>,
    strength: Option<usize>,
    signal: &'static str,
    frequency_hz: f64,
    name: &'static str,
}

/// The signals of `table` (`system`'s) the file has pseudoranges for, in
/// the table's order.
fn signal_types(
    observations: &ObservationFile,
    system: GnssSystem,
    table: &[(&'static str, f64, &'static str)],
) -> Vec<SignalTypes> {
    let letter = system.letter();
    table
        .iter()
        .filter_map(|&(signal, frequency_hz, name)| {
            let idx = |kind: char| observations.type_index(letter, &format!("{kind}{signal}"));
            Some(SignalTypes {
                code: idx('C')?,
                carrier: idx('L'),
                doppler: idx('D'),
                strength: idx('S'),
                signal,
                frequency_hz,
                name,
            })
        })
        .collect()
}

fn epochs_from(
    observations: &ObservationFile,
    ephemerides: &Ephemerides<'_>,
    options: &ObservableOptions,
) -> Result<(Vec<GnssEpoch>, EpochSignals)> {
    options.validate()?;
    // Each system's signals to measure with, and to measure the
    // ionosphere with.
    let types: Vec<(GnssSystem, Vec<SignalTypes>, Vec<SignalTypes>)> = options
        .systems
        .iter()
        .map(|&system| {
            let second = if options.dual_frequency_ionosphere {
                signal_types(observations, system, second_signals(system))
            } else {
                Vec::new()
            };
            (
                system,
                signal_types(observations, system, signals(system)),
                second,
            )
        })
        .collect();
    if types.iter().all(|(_, t, _)| t.is_empty()) {
        let wanted: Vec<String> = options
            .systems
            .iter()
            .map(|s| {
                let codes: Vec<String> =
                    signals(*s).iter().map(|(c, ..)| format!("C{c}")).collect();
                format!("{} {}", s.letter(), codes.join("/"))
            })
            .collect();
        return Err(Error::invalid(
            "observations",
            format!(
                "the file declares no pseudorange of the systems asked for ({}; SYS / # / OBS TYPES)",
                wanted.join(", ")
            ),
        ));
    }
    let track = &options.reference_track_ecef;
    if !track.is_empty() && track.len() != observations.epochs.len() {
        return Err(Error::invalid(
            "reference_position_ecef",
            format!(
                "has {} positions for {} observation epochs: give one per epoch, or one for all",
                track.len(),
                observations.epochs.len()
            ),
        ));
    }
    let mut r = options.reference_position_ecef;
    let mut geo = ecef_to_geodetic(&r);
    let mut c_e_n = c_n_e(geo.latitude_rad, geo.longitude_rad).transpose();
    let mut epochs = Vec::with_capacity(observations.epochs.len());
    let mut epoch_signals = Vec::with_capacity(observations.epochs.len());
    // Each satellite's half-cycle state (LLI bit 1) at its last epoch.
    let mut half_cycle_unresolved: HashMap<u16, bool> = HashMap::new();
    let mut ionosphere_tracks = IonosphereTracks::default();
    for (k, e) in observations.epochs.iter().enumerate() {
        if let Some(&position) = track.get(k) {
            r = position;
            geo = ecef_to_geodetic(&r);
            c_e_n = c_n_e(geo.latitude_rad, geo.longitude_rad).transpose();
        }
        let mut measurements = Vec::new();
        let mut received = Vec::new();
        for s in &e.satellites {
            let Some((system, signal_types, second_types)) = GnssSystem::from_letter(s.system)
                .and_then(|system| types.iter().find(|(t, ..)| *t == system))
            else {
                continue;
            };
            let number = satellite_number(*system, s.prn);
            if !options.satellites.is_empty() && !options.satellites.contains(&number) {
                continue;
            }
            let Some(orbit) = ephemerides.select(*system, s.prn, e.gps_time_s) else {
                continue;
            };
            // The first signal with a pseudorange whose group delay the
            // ephemeris gives.
            let Some((signal, pseudorange, group_delay_s)) = signal_types
                .iter()
                .find_map(|t| Some((t, s.values[t.code]?, orbit.extra_group_delay_s(t.signal)?)))
            else {
                continue;
            };
            let measured_cn0 = signal.strength.and_then(|j| s.values[j]);
            let cn0 = measured_cn0.unwrap_or(45.0);
            if cn0 < options.min_cn0_db_hz {
                continue;
            }
            // Transmission time t_st = t_sa − ρ/c − Δt_sv (IS-GPS-200 §20.3.3.3.3.1),
            // as a small offset from the reception time to keep full precision.
            let mut offset = -pseudorange / SPEED_OF_LIGHT_M_S;
            let mut state = orbit.state_at(e.gps_time_s, offset);
            for _ in 0..2 {
                offset = -pseudorange / SPEED_OF_LIGHT_M_S - state.clock_bias_s;
                state = orbit.state_at(e.gps_time_s, offset);
            }
            let los_ned = c_e_n * (state.position_ecef - r).normalize();
            let elevation = (-los_ned.z).asin();
            if elevation < options.elevation_mask_rad {
                continue;
            }
            let azimuth = los_ned.y.atan2(los_ned.x);
            let carrier_hz = orbit.carrier_hz(signal);
            let iono_scale = (L1_FREQUENCY_HZ / carrier_hz).powi(2);
            let model_iono = options.ionosphere.map_or(0.0, |k| {
                iono_scale
                    * k.delay_m(
                        e.gps_time_s,
                        geo.latitude_rad,
                        geo.longitude_rad,
                        azimuth,
                        elevation,
                    )
            });
            let tropo = if options.troposphere {
                saastamoinen_delay_m(geo.latitude_rad, geo.height_m, elevation, 0.7)
            } else {
                0.0
            };
            let scale = signal_strength_scale(cn0, elevation);
            let signal_strength_std_m = options.pseudorange_std_m * scale;
            // The delay from a second signal (see `dual_frequency`): both
            // codes corrected for their group delays; the estimate's own
            // uncertainty goes into the pseudorange's.
            let measured = second_types
                .iter()
                .filter(|t| t.frequency_hz != signal.frequency_hz)
                .find_map(|t| {
                    let cn0 = t.strength.and_then(|j| s.values[j]).unwrap_or(45.0);
                    let second_m = s.values[t.code].filter(|_| cn0 >= options.min_cn0_db_hz)?
                        - SPEED_OF_LIGHT_M_S * orbit.extra_group_delay_s(t.signal)?;
                    let (delay_m, noise_factor) = geometry_free_delay_m(
                        pseudorange - SPEED_OF_LIGHT_M_S * group_delay_s,
                        signal.frequency_hz,
                        second_m,
                        t.frequency_hz,
                    );
                    let second_std_m =
                        options.pseudorange_std_m * signal_strength_scale(cn0, elevation);
                    Some(DelayMeasurement {
                        delay_m,
                        variance_m2: (signal_strength_std_m.powi(2) + second_std_m.powi(2))
                            * noise_factor.powi(2),
                        signal: t.name,
                    })
                });
            let estimate = if options.dual_frequency_ionosphere {
                ionosphere_tracks.estimate(number, e.gps_time_s, measured)
            } else {
                None
            };
            let (code_iono, iono_variance_m2) =
                estimate.map_or((model_iono, 0.0), |d| (d.delay_m, d.variance_m2));
            let pseudorange_std_m = match options.weighting {
                PseudorangeWeighting::Rtklib => rtklib_variance_m2(
                    *system,
                    elevation,
                    &RangeCorrections {
                        ephemeris_error_m: orbit.ranging_accuracy_m(),
                        // RTKLIB takes the L1 delay's error for every signal.
                        klobuchar_delay_m: options.ionosphere.map(|_| model_iono / iono_scale),
                        measured_ionosphere_variance_m2: estimate.map(|d| d.variance_m2),
                        troposphere: options.troposphere,
                    },
                )
                .sqrt(),
                PseudorangeWeighting::SignalStrength => {
                    (signal_strength_std_m.powi(2) + iono_variance_m2).sqrt()
                }
            };
            let wavelength_m = SPEED_OF_LIGHT_M_S / carrier_hz;
            // RINEX Doppler is positive for an approaching satellite: ρ̇ = −λ D.
            let (rate, rate_std) = match signal.doppler.and_then(|j| s.values[j]) {
                Some(d) if options.pseudorange_rate_std_m_s > 0.0 => (
                    -wavelength_m * d + SPEED_OF_LIGHT_M_S * state.clock_drift_s_s,
                    options.pseudorange_rate_std_m_s * scale,
                ),
                _ => (f64::NAN, 0.0),
            };
            let clock_bias_s = state.clock_bias_s - group_delay_s;
            let carrier = signal
                .carrier
                .and_then(|j| Some((s.values[j]?, s.lli[j])))
                .filter(|_| options.carrier_phase_std_m > 0.0)
                .map(|(cycles, lli)| {
                    let unresolved = lli & LLI_HALF_CYCLE != 0;
                    let changed = half_cycle_unresolved
                        .insert(number, unresolved)
                        .is_some_and(|before| before != unresolved);
                    CarrierPhase {
                        // The phase carries the satellite clock and the
                        // troposphere as the code does, and the ionosphere
                        // with the opposite sign (Groves eq. 9.13).
                        range_m: wavelength_m * cycles
                            + SPEED_OF_LIGHT_M_S * clock_bias_s
                            + model_iono
                            - tropo,
                        std_m: options.carrier_phase_std_m * scale,
                        loss_of_lock: lli & LLI_LOST_LOCK != 0 || changed,
                    }
                });
            measurements.push(SatelliteMeasurement {
                sat_id: number,
                system: *system,
                position_ecef: state.position_ecef,
                velocity_ecef: state.velocity_ecef,
                pseudorange_m: pseudorange + SPEED_OF_LIGHT_M_S * clock_bias_s - code_iono - tropo,
                pseudorange_rate_m_s: rate,
                pseudorange_std_m,
                pseudorange_rate_std_m_s: rate_std,
                carrier,
            });
            received.push(ReceivedSignal {
                name: signal.name,
                cn0_db_hz: measured_cn0.unwrap_or(f64::NAN),
                elevation_rad: elevation,
                ionosphere_signal: estimate.map(|d| d.signal),
            });
        }
        epochs.push(GnssEpoch {
            time_s: e.gps_time_s,
            measurements,
        });
        epoch_signals.push(received);
    }
    Ok((epochs, epoch_signals))
}
