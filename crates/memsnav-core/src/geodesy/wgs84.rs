//! WGS84 defining and derived constants (NIMA TR8350.2, 3rd ed., tables 3.1
//! and 3.3; the same values as Groves, *Principles of GNSS, Inertial, and
//! Multisensor Integrated Navigation Systems*, 2nd ed., §2.4).

/// Semi-major axis a, m.
pub const SEMI_MAJOR_AXIS_M: f64 = 6_378_137.0;
/// Flattening f.
pub const FLATTENING: f64 = 1.0 / 298.257_223_563;
/// Semi-minor axis b = a (1 − f), m.
pub const SEMI_MINOR_AXIS_M: f64 = SEMI_MAJOR_AXIS_M * (1.0 - FLATTENING);
/// First eccentricity squared e² = f (2 − f).
pub const ECCENTRICITY_SQUARED: f64 = FLATTENING * (2.0 - FLATTENING);
/// Earth's gravitational constant μ = GM (with atmosphere), m³/s².
pub const GM_M3_S2: f64 = 3.986_004_418e14;
/// Earth rotation rate ω_ie, rad/s (also the value of IS-GPS-200).
pub const EARTH_RATE_RAD_S: f64 = 7.292_115e-5;
/// Second degree zonal harmonic J2 (Groves eq. 2.142's value).
pub const J2: f64 = 1.082_627e-3;
/// Standard gravity g0, m/s² (the unit "g" of the paper's figures).
pub const STANDARD_GRAVITY_M_S2: f64 = 9.806_65;
/// Speed of light in vacuum, m/s.
pub const SPEED_OF_LIGHT_M_S: f64 = 299_792_458.0;
/// Normal gravity at the equator γ_e, m/s² (Somigliana, TR8350.2 eq. 4-1).
pub const GRAVITY_EQUATOR_M_S2: f64 = 9.780_325_335_9;
/// Somigliana's constant k = (b γ_p) / (a γ_e) − 1 (TR8350.2 table 3.4).
pub const SOMIGLIANA_K: f64 = 0.001_931_852_652_41;
