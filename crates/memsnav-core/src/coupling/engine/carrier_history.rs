//! The tight filter's memory of the previous GNSS epoch's carrier phases,
//! for the time-differenced carrier phase of [`crate::coupling`]'s
//! `carrier` module (which holds the model and the tests).

use nalgebra::Vector3;

/// One satellite's carrier at the previous epoch.
#[derive(Debug, Clone, Copy)]
pub(crate) struct CarrierThen {
    pub(crate) sat_id: u16,
    pub(crate) carrier_range_m: f64,
    pub(crate) carrier_std_m: f64,
    /// The range predicted from the corrected antenna position then, m.
    pub(crate) predicted_range_m: f64,
    /// The pseudorange rate then, m/s (NaN: none), and its std.
    pub(crate) rate_m_s: f64,
    pub(crate) rate_std_m_s: f64,
}

/// A carrier change at this epoch that passed the receiver's flags.
#[derive(Debug, Clone, Copy)]
pub(crate) struct Change {
    /// Index of the measurement in the epoch.
    pub(crate) index: usize,
    /// Carrier change less the Doppler-predicted change, m (NaN: no rates).
    pub(crate) doppler_misfit_m: f64,
    /// Its std without the clock's common part, m.
    pub(crate) doppler_misfit_std_m: f64,
    /// Predicted minus measured change (the clock's change still in), m.
    pub(crate) residual_m: f64,
    /// The change's std (floored), m.
    pub(crate) std_m: f64,
    /// Line of sight from the antenna to the satellite, ECEF.
    pub(crate) line_of_sight_ecef: Vector3<f64>,
}

/// The carriers of the filter's previous GNSS epoch, and buffers reused
/// from epoch to epoch (no allocation once grown).
#[derive(Debug, Clone, Default)]
pub(crate) struct CarrierHistory {
    pub(crate) then: Vec<CarrierThen>,
    pub(crate) next: Vec<CarrierThen>,
    pub(crate) changes: Vec<Change>,
    pub(crate) scratch: Vec<f64>,
}
