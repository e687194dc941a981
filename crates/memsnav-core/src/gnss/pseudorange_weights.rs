//! How much each pseudorange is believed: the error model that weights a
//! single-point fix (and feeds the coupled filters' measurement noise).
//!
//! Two models:
//!
//! - [`PseudorangeWeighting::Rtklib`] (the default): RTKLIB 2.4.3's
//!   single-point variance (manual app. E.6, eq. E.6.24; `pntpos.c`,
//!   `rescode`), the sum of independent terms
//!
//!   σ² = F_s² (a² + b² / sin el) + σ_eph² + σ_bias² + σ_iono² + σ_tropo²
//!
//!   with a = b = 0.3 m (RTKLIB's code/phase error ratio 100 × 0.003 m),
//!   F_s = 1.5 for GLONASS and 1 for GPS, Galileo and BeiDou, σ_eph the
//!   ephemeris' broadcast ranging accuracy (GPS/BeiDou URA, Galileo SISA,
//!   5 m for GLONASS), σ_bias = 0.3 m (code bias), σ_iono = 0.5 × the
//!   Klobuchar delay (5 m without a correction; the measured delay's own
//!   variance with two frequencies) and σ_tropo = 0.3 m / (sin el + 0.1)
//!   (3 m without a correction). RTKLIB's code divides b² by sin el, not
//!   sin² el as the manual writes: the code is what its solutions come
//!   from, so it is followed. The ranging accuracy and the atmosphere
//!   dominate above 30° elevation: the weights are flat there and fall
//!   only towards the horizon.
//! - [`PseudorangeWeighting::SignalStrength`]: σ = σ₄₅ √(10^((45 − C/N0)/10))
//!   / sin el (Groves 2013, eq. 9.168 for the C/N0 part, times the 1/sin el
//!   of an elevation model). It weights a 10° satellite 33 times (in σ²)
//!   below a zenith one at equal C/N0: the low satellites that separate
//!   height from the receiver clock hardly count, and the vertical error
//!   of a multi-system fix is 20-30 % worse than RTKLIB's. Kept for the
//!   coupled filters, whose process noise was tuned with it.

use super::system::GnssSystem;

/// How a pseudorange's standard deviation follows the satellite and signal.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default)]
pub enum PseudorangeWeighting {
    /// RTKLIB's single-point error model (see the module docs).
    #[default]
    Rtklib,
    /// σ₄₅ √(10^((45 − C/N0)/10)) / sin el, σ₄₅ the options'
    /// `pseudorange_std_m` (see the module docs).
    SignalStrength,
}

impl PseudorangeWeighting {
    /// The model named `name` ("rtklib", "signal-strength").
    pub fn from_name(name: &str) -> Option<Self> {
        match name {
            "rtklib" => Some(Self::Rtklib),
            "signal-strength" => Some(Self::SignalStrength),
            _ => None,
        }
    }

    /// The name [`Self::from_name`] reads.
    pub fn name(self) -> &'static str {
        match self {
            Self::Rtklib => "rtklib",
            Self::SignalStrength => "signal-strength",
        }
    }
}

/// RTKLIB's receiver error terms a = b, m (`stats-eratio1` 100 ×
/// `stats-errphase` 0.003 m, its defaults).
pub const RTKLIB_CODE_ERROR_M: f64 = 0.3;
/// RTKLIB's code bias error, m (`ERR_CBIAS`).
pub const RTKLIB_CODE_BIAS_ERROR_M: f64 = 0.3;
/// Share of the Klobuchar delay taken as its error (`ERR_BRDCI`).
pub const RTKLIB_KLOBUCHAR_ERROR_FRACTION: f64 = 0.5;
/// Ionospheric error without a correction, m (`ERR_ION`).
pub const RTKLIB_NO_IONOSPHERE_ERROR_M: f64 = 5.0;
/// Saastamoinen error at the zenith scale, m (`ERR_SAAS`).
pub const RTKLIB_SAASTAMOINEN_ERROR_M: f64 = 0.3;
/// Tropospheric error without a correction, m (`ERR_TROP`).
pub const RTKLIB_NO_TROPOSPHERE_ERROR_M: f64 = 3.0;
/// GLONASS broadcast orbit and clock error, m (`ERREPH_GLO`).
pub const RTKLIB_GLONASS_EPHEMERIS_ERROR_M: f64 = 5.0;
/// Lowest elevation the 1/sin el terms are evaluated at, rad (5°, as later
/// RTKLIB versions' `MIN_EL`): a mask of 0° with the troposphere off must
/// not give an infinite variance.
const MIN_WEIGHT_ELEVATION_RAD: f64 = 5.0 * std::f64::consts::PI / 180.0;

/// RTKLIB's system factor F_s (`EFACT_GLO` 1.5; GPS, Galileo and BeiDou
/// share `EFACT_GPS` 1 in `varerr`).
pub fn rtklib_system_factor(system: GnssSystem) -> f64 {
    match system {
        GnssSystem::Glonass => 1.5,
        GnssSystem::Gps | GnssSystem::Galileo | GnssSystem::Beidou => 1.0,
    }
}

/// The corrections a pseudorange carries, for its error terms.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct RangeCorrections {
    /// The ephemeris' ranging accuracy (URA, SISA), m.
    pub ephemeris_error_m: f64,
    /// The broadcast (Klobuchar) ionospheric delay on L1, m, whatever the
    /// signal (RTKLIB's `ionocorr` variance); `None`: no model applied.
    pub klobuchar_delay_m: Option<f64>,
    /// The variance of a measured (two-frequency) ionospheric delay, m²,
    /// used instead of the Klobuchar term when given.
    pub measured_ionosphere_variance_m2: Option<f64>,
    /// Whether the Saastamoinen delay was applied.
    pub troposphere: bool,
}

/// RTKLIB's single-point pseudorange variance, m² (module docs; RTKLIB
/// manual eq. E.6.24 with `pntpos.c`'s `varerr` and `rescode`).
pub fn rtklib_variance_m2(
    system: GnssSystem,
    elevation_rad: f64,
    corrections: &RangeCorrections,
) -> f64 {
    let sin_el = elevation_rad.max(MIN_WEIGHT_ELEVATION_RAD).sin();
    let a = RTKLIB_CODE_ERROR_M;
    let receiver = rtklib_system_factor(system).powi(2) * (a * a + a * a / sin_el);
    let ionosphere = match (
        corrections.measured_ionosphere_variance_m2,
        corrections.klobuchar_delay_m,
    ) {
        (Some(v), _) => v,
        (None, Some(d)) => (RTKLIB_KLOBUCHAR_ERROR_FRACTION * d).powi(2),
        (None, None) => RTKLIB_NO_IONOSPHERE_ERROR_M.powi(2),
    };
    let troposphere = if corrections.troposphere {
        (RTKLIB_SAASTAMOINEN_ERROR_M / (sin_el + 0.1)).powi(2)
    } else {
        RTKLIB_NO_TROPOSPHERE_ERROR_M.powi(2)
    };
    receiver
        + corrections.ephemeris_error_m.powi(2)
        + RTKLIB_CODE_BIAS_ERROR_M.powi(2)
        + ionosphere
        + troposphere
}

/// The signal-strength model's scale of σ₄₅: √(10^((45 − C/N0)/10)) /
/// sin el (sin el floored at 0.1, 5.7°).
pub fn signal_strength_scale(cn0_db_hz: f64, elevation_rad: f64) -> f64 {
    (10f64.powf((45.0 - cn0_db_hz) / 10.0)).sqrt() / elevation_rad.sin().max(0.1)
}

#[cfg(test)]
mod tests {
    use super::*;

    fn corrections(klobuchar_delay_m: Option<f64>, troposphere: bool) -> RangeCorrections {
        RangeCorrections {
            ephemeris_error_m: 2.4,
            klobuchar_delay_m,
            measured_ionosphere_variance_m2: None,
            troposphere,
        }
    }

    #[test]
    fn the_zenith_variance_is_the_sum_of_rtklibs_terms() {
        // At 90°: 0.09 + 0.09 (receiver) + 5.76 (URA 2.4 m) + 0.09 (bias)
        // + (0.5 × 4 m)² + (0.3 / 1.1)².
        let v = rtklib_variance_m2(
            GnssSystem::Gps,
            std::f64::consts::FRAC_PI_2,
            &corrections(Some(4.0), true),
        );
        let expected = 0.18 + 5.76 + 0.09 + 4.0 + (0.3f64 / 1.1).powi(2);
        assert!((v - expected).abs() < 1e-12, "{v} vs {expected}");
    }

    #[test]
    fn glonass_receiver_term_is_scaled_by_one_and_a_half_squared() {
        let c = RangeCorrections {
            ephemeris_error_m: 0.0,
            klobuchar_delay_m: Some(0.0),
            measured_ionosphere_variance_m2: None,
            troposphere: true,
        };
        let el = 30f64.to_radians();
        let rest = 0.09 + (0.3 / (0.5 + 0.1f64)).powi(2);
        let gps = rtklib_variance_m2(GnssSystem::Gps, el, &c) - rest;
        let glo = rtklib_variance_m2(GnssSystem::Glonass, el, &c) - rest;
        assert!((gps - (0.09 + 0.09 / 0.5)).abs() < 1e-12);
        assert!((glo / gps - 2.25).abs() < 1e-12);
    }

    #[test]
    fn uncorrected_atmosphere_takes_rtklibs_fixed_errors() {
        let el = 1.0;
        let with = rtklib_variance_m2(GnssSystem::Gps, el, &corrections(Some(0.0), true));
        let without = rtklib_variance_m2(GnssSystem::Gps, el, &corrections(None, false));
        let tropo = (0.3 / (el.sin() + 0.1)).powi(2);
        assert!((without - with - (25.0 + 9.0 - tropo)).abs() < 1e-12);
    }

    #[test]
    fn the_weights_fall_towards_the_horizon_and_stay_finite_at_zero() {
        let c = corrections(Some(3.0), true);
        let high = rtklib_variance_m2(GnssSystem::Gps, 1.2, &c);
        let low = rtklib_variance_m2(GnssSystem::Gps, 0.2, &c);
        assert!(low > high);
        assert!(rtklib_variance_m2(GnssSystem::Gps, 0.0, &c).is_finite());
    }

    #[test]
    fn names_round_trip() {
        for w in [
            PseudorangeWeighting::Rtklib,
            PseudorangeWeighting::SignalStrength,
        ] {
            assert_eq!(PseudorangeWeighting::from_name(w.name()), Some(w));
        }
        assert_eq!(PseudorangeWeighting::from_name("elevation"), None);
    }
}
