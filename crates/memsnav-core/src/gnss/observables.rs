//! Filter-ready GPS L1 C/A measurements from a RINEX observation file and
//! broadcast ephemerides: satellite position and velocity at transmission
//! time, pseudorange corrected for the satellite clock (with relativity and
//! T_GD), the Klobuchar ionosphere and the Saastamoinen troposphere, and the
//! pseudorange rate from the Doppler (Groves §9.3, eqs. 9.3-9.4 and 8.48).

use nalgebra::Vector3;

use super::atmosphere::{saastamoinen_delay_m, Klobuchar};
use super::constellation::Constellation;
use super::rinex_obs::ObservationFile;
use super::{GnssEpoch, SatelliteMeasurement};
use crate::geodesy::wgs84::SPEED_OF_LIGHT_M_S;
use crate::geodesy::{c_n_e, ecef_to_geodetic};
use crate::{validate, Error, Result};

/// GPS L1 carrier wavelength, m (c / 1575.42 MHz).
pub const GPS_L1_WAVELENGTH_M: f64 = SPEED_OF_LIGHT_M_S / 1_575.42e6;

/// How raw observations become measurements.
#[derive(Debug, Clone, PartialEq)]
pub struct ObservableOptions {
    /// Receiver position for elevations and atmospheric delays, ECEF m
    /// (a few km off changes the delays by millimetres).
    pub reference_position_ecef: Vector3<f64>,
    /// Satellites below this elevation are left out, rad.
    pub elevation_mask_rad: f64,
    /// Satellites whose C/N0 is below this are left out, dB-Hz.
    pub min_cn0_db_hz: f64,
    /// Broadcast ionosphere; `None` leaves the ionospheric delay in.
    pub ionosphere: Option<Klobuchar>,
    /// Apply the Saastamoinen troposphere.
    pub troposphere: bool,
    /// Pseudorange one-sigma at 45 dB-Hz and the zenith, m.
    pub pseudorange_std_m: f64,
    /// Pseudorange-rate one-sigma at 45 dB-Hz, m/s (0: no rates used).
    pub pseudorange_rate_std_m_s: f64,
    /// Only these PRNs (empty: every GPS satellite with an ephemeris).
    pub satellites: Vec<u16>,
}

/// Default pseudorange one-sigma at 45 dB-Hz and the zenith, m: a u-blox
/// class receiver's code noise with the broadcast models' residuals (the
/// simulator draws its noise with it too).
pub const DEFAULT_PSEUDORANGE_STD_M: f64 = 3.0;
/// Default pseudorange-rate one-sigma at 45 dB-Hz, m/s (Doppler).
pub const DEFAULT_PSEUDORANGE_RATE_STD_M_S: f64 = 0.1;
/// Default elevation mask, degrees.
pub const DEFAULT_ELEVATION_MASK_DEG: f64 = 10.0;

impl ObservableOptions {
    /// Defaults for a u-blox class receiver: 10° mask, 25 dB-Hz, Klobuchar
    /// with RTKLIB's default coefficients, troposphere on, 3 m and 0.1 m/s.
    pub fn new(reference_position_ecef: Vector3<f64>) -> Self {
        Self {
            reference_position_ecef,
            elevation_mask_rad: DEFAULT_ELEVATION_MASK_DEG.to_radians(),
            min_cn0_db_hz: 25.0,
            ionosphere: Some(Klobuchar::RTKLIB_DEFAULT),
            troposphere: true,
            pseudorange_std_m: DEFAULT_PSEUDORANGE_STD_M,
            pseudorange_rate_std_m_s: DEFAULT_PSEUDORANGE_RATE_STD_M_S,
            satellites: Vec::new(),
        }
    }

    fn validate(&self) -> Result<()> {
        validate::finite_vectors("reference_position_ecef", &[self.reference_position_ecef])?;
        crate::geodesy::domain::check_position_ecef(
            "reference_position_ecef",
            &[self.reference_position_ecef],
        )?;
        validate::finite_scalars("elevation_mask", &[self.elevation_mask_rad])?;
        validate::finite_scalars("min_cn0", &[self.min_cn0_db_hz])?;
        if let Some(klobuchar) = &self.ionosphere {
            klobuchar.validate("klobuchar")?;
        }
        validate::positive("pseudorange_std", self.pseudorange_std_m)?;
        validate::non_negative("pseudorange_rate_std", self.pseudorange_rate_std_m_s)
    }
}

/// σ² scaling with signal strength and elevation: σ(C/N0, el) =
/// σ₄₅ · √(10^((45 − C/N0)/10)) / sin(el) (a C/N0-weighted form of the
/// elevation weighting of RTKLIB; Groves eq. 9.168 for the C/N0 part).
fn noise_scale(cn0_db_hz: f64, elevation_rad: f64) -> f64 {
    (10f64.powf((45.0 - cn0_db_hz) / 10.0)).sqrt() / elevation_rad.sin().max(0.1)
}

/// Builds one [`GnssEpoch`] per observation epoch (time = GPS time, s) from
/// the GPS `C1C` pseudoranges, `D1C` Dopplers and `S1C` signal strengths.
/// A satellite without a valid ephemeris, below the mask or too weak is left
/// out; an epoch may end up empty.
pub fn gps_l1_epochs(
    observations: &ObservationFile,
    constellation: &Constellation,
    options: &ObservableOptions,
) -> Result<Vec<GnssEpoch>> {
    options.validate()?;
    let idx = |code: &str| observations.type_index('G', code);
    let c1c = idx("C1C").ok_or_else(|| {
        Error::invalid(
            "observations",
            "the file declares no GPS C1C pseudorange (SYS / # / OBS TYPES)",
        )
    })?;
    let (d1c, s1c) = (idx("D1C"), idx("S1C"));
    let sat_index: Vec<(u16, usize)> = (0..constellation.len())
        .map(|i| (constellation.sat_id(i), i))
        .filter(|(prn, _)| options.satellites.is_empty() || options.satellites.contains(prn))
        .collect();
    let r = options.reference_position_ecef;
    let geo = ecef_to_geodetic(&r);
    let c_e_n = c_n_e(geo.latitude_rad, geo.longitude_rad).transpose();
    let mut epochs = Vec::with_capacity(observations.epochs.len());
    for e in &observations.epochs {
        let mut measurements = Vec::new();
        for s in e.satellites.iter().filter(|s| s.system == 'G') {
            let Some(&(_, i)) = sat_index.iter().find(|(p, _)| *p == s.prn) else {
                continue;
            };
            let Some(pseudorange) = s.values[c1c] else {
                continue;
            };
            let Some(orbit) = constellation.orbit(i, e.gps_time_s) else {
                continue;
            };
            let cn0 = s1c.and_then(|j| s.values[j]).unwrap_or(45.0);
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
            let iono = options.ionosphere.map_or(0.0, |k| {
                k.delay_m(
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
            let scale = noise_scale(cn0, elevation);
            // RINEX Doppler is positive for an approaching satellite: ρ̇ = −λ D.
            let (rate, rate_std) = match d1c.and_then(|j| s.values[j]) {
                Some(d) if options.pseudorange_rate_std_m_s > 0.0 => (
                    -GPS_L1_WAVELENGTH_M * d + SPEED_OF_LIGHT_M_S * state.clock_drift_s_s,
                    options.pseudorange_rate_std_m_s * scale,
                ),
                _ => (f64::NAN, 0.0),
            };
            measurements.push(SatelliteMeasurement {
                sat_id: s.prn,
                system: super::GnssSystem::Gps,
                position_ecef: state.position_ecef,
                velocity_ecef: state.velocity_ecef,
                pseudorange_m: pseudorange + SPEED_OF_LIGHT_M_S * state.clock_bias_s - iono - tropo,
                pseudorange_rate_m_s: rate,
                pseudorange_std_m: options.pseudorange_std_m * scale,
                pseudorange_rate_std_m_s: rate_std,
            });
        }
        epochs.push(GnssEpoch {
            time_s: e.gps_time_s,
            measurements,
        });
    }
    Ok(epochs)
}
