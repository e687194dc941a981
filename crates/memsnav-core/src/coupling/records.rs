//! What a coupled filter reports besides its state: every scalar
//! measurement with its innovation and fate, every batch test, and every
//! reset. Nothing a filter does to its measurements or its state is silent.

/// Which measurement a record is about.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum MeasurementKind {
    /// A pseudorange, m.
    Pseudorange,
    /// A pseudorange rate, m/s.
    PseudorangeRate,
    /// A carrier range's change since the previous epoch (time-differenced
    /// carrier phase), m.
    CarrierPhase,
    /// One whitened component of a position fix (dimensionless, unit variance).
    Position,
    /// One whitened component of a velocity fix (dimensionless).
    Velocity,
    /// One axis of a zero-velocity update (ZUPT), m/s.
    ZeroVelocity,
    /// One axis of a zero-angular-rate update (ZARU), rad/s.
    ZeroRate,
    /// The lateral or vertical body velocity of a non-holonomic constraint, m/s.
    NonHolonomic,
    /// The forward speed of an odometer (wheel speed), m/s.
    Speed,
    /// An ellipsoidal height (barometer), m.
    Height,
    /// A heading (yaw), rad.
    Heading,
}

impl MeasurementKind {
    /// Every kind, in a fixed order (for per-kind counts).
    pub const ALL: [MeasurementKind; 11] = [
        MeasurementKind::Pseudorange,
        MeasurementKind::PseudorangeRate,
        MeasurementKind::CarrierPhase,
        MeasurementKind::Position,
        MeasurementKind::Velocity,
        MeasurementKind::ZeroVelocity,
        MeasurementKind::ZeroRate,
        MeasurementKind::NonHolonomic,
        MeasurementKind::Speed,
        MeasurementKind::Height,
        MeasurementKind::Heading,
    ];

    /// A short name (`"pseudorange"`, `"zero_velocity"`, ...).
    pub fn name(self) -> &'static str {
        match self {
            MeasurementKind::Pseudorange => "pseudorange",
            MeasurementKind::PseudorangeRate => "pseudorange_rate",
            MeasurementKind::CarrierPhase => "carrier_phase",
            MeasurementKind::Position => "position",
            MeasurementKind::Velocity => "velocity",
            MeasurementKind::ZeroVelocity => "zero_velocity",
            MeasurementKind::ZeroRate => "zero_rate",
            MeasurementKind::NonHolonomic => "non_holonomic",
            MeasurementKind::Speed => "speed",
            MeasurementKind::Height => "height",
            MeasurementKind::Heading => "heading",
        }
    }
}

/// What the filter did with a measurement.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum MeasurementStatus {
    /// Applied.
    Accepted,
    /// Its batch (the epoch's measurements of its kind) failed the
    /// chi-square test, so none of them was applied.
    RejectedByGate,
    /// Left out of its batch by fault exclusion (its innovation was the
    /// largest when the batch failed); the rest of the batch was applied.
    Excluded,
    /// Rejected because a value (measurement, satellite state, std) was NaN,
    /// infinite or a non-positive standard deviation.
    RejectedInvalid,
    /// Its batch failed, and the filter was reset from this epoch's
    /// measurements instead (see [`ResetRecord`]).
    UsedForReset,
    /// A carrier change that holds a cycle slip (flagged by the receiver or
    /// found against the Doppler), not used.
    CycleSlip,
    /// A carrier change that passed the slip tests but was not applied: its
    /// epoch had fewer clean changes than a batch needs (five: velocity,
    /// the clock's change and one more for the residual test).
    TooFewCarrierChanges,
}

impl MeasurementStatus {
    /// A short name (`"accepted"`, `"gate"`, `"excluded"`, `"invalid"`,
    /// `"reset"`, `"slip"`, `"too-few"`).
    pub fn name(self) -> &'static str {
        match self {
            MeasurementStatus::Accepted => "accepted",
            MeasurementStatus::RejectedByGate => "gate",
            MeasurementStatus::Excluded => "excluded",
            MeasurementStatus::RejectedInvalid => "invalid",
            MeasurementStatus::UsedForReset => "reset",
            MeasurementStatus::CycleSlip => "slip",
            MeasurementStatus::TooFewCarrierChanges => "too-few",
        }
    }
}

/// One scalar measurement's innovation and fate.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct MeasurementRecord {
    /// Epoch time, s.
    pub time_s: f64,
    /// Satellite id (tight), fix component 0-2 (loose) or axis 0-2 (aids).
    pub id: u16,
    /// Which measurement.
    pub kind: MeasurementKind,
    /// Innovation z − ẑ (measurement minus the prediction of the filter
    /// before this epoch's updates), in the measurement's unit (m, m/s;
    /// whitened units for fixes).
    pub innovation: f64,
    /// Predicted innovation std √(h P hᵀ + r), same unit.
    pub innovation_std: f64,
    /// Normalised innovation squared ν²/s.
    pub nis: f64,
    /// Applied or why not.
    pub status: MeasurementStatus,
}

/// The chi-square test of one batch (an epoch's measurements of one kind).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct BatchRecord {
    /// Epoch time, s.
    pub time_s: f64,
    /// The measurements' kind.
    pub kind: MeasurementKind,
    /// Batch NIS νᵀ S⁻¹ ν of the measurements finally tested.
    pub nis: f64,
    /// Its degrees of freedom.
    pub dof: usize,
    /// The chi-square quantile it was compared with.
    pub threshold: f64,
    /// Measurements left out by fault exclusion.
    pub excluded: usize,
    /// Whether the batch was applied.
    pub accepted: bool,
    /// How far the batch's measurement model is from linear over the
    /// filter's uncertainty: for pseudoranges the largest expected
    /// curvature term E[|δr⊥|²] / (2ρ) in units of the measurement std
    /// (`super::integrity`); NaN for measurements linear in the state.
    pub nonlinearity: f64,
}

/// What a reset changed.
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum ResetKind {
    /// Position (and velocity, when the epoch gives one) set to a GNSS
    /// fix after the measurements kept failing their test.
    PositionToFix,
    /// Velocity (and clock drift for tight coupling) set to a GNSS velocity
    /// after the velocity measurements kept failing their test.
    VelocityToFix,
    /// Velocity set to zero at a standstill after the zero-velocity
    /// updates kept failing their test.
    VelocityToZero,
    /// The receiver clock offset jumped: the common part of all
    /// pseudorange innovations was moved into the clock.
    ClockJump,
    /// The receiver clock drift jumped (the common part of all
    /// pseudorange-rate innovations).
    ClockDriftJump,
    /// Position, velocity and clock covariance inflated (too few
    /// satellites for a fix to reset to).
    Inflation,
    /// Heading set from the GNSS course over ground (alignment).
    Heading,
    /// The whole covariance multiplied (fading memory): a kind's resets
    /// followed each other with no accepted batch between, so the model
    /// is wrong beyond the position and velocity the resets replace
    /// (attitude, sensor biases: an IMU worse than its tuning says).
    Fading,
}

impl ResetKind {
    /// A short name (`"position_to_fix"`, `"clock_jump"`, ...).
    pub fn name(self) -> &'static str {
        match self {
            ResetKind::PositionToFix => "position_to_fix",
            ResetKind::VelocityToFix => "velocity_to_fix",
            ResetKind::VelocityToZero => "velocity_to_zero",
            ResetKind::ClockJump => "clock_jump",
            ResetKind::ClockDriftJump => "clock_drift_jump",
            ResetKind::Inflation => "inflation",
            ResetKind::Heading => "heading",
            ResetKind::Fading => "fading",
        }
    }

    /// The unit of a reset's [`ResetRecord::change`] ("" for the
    /// inflation's factor).
    pub fn change_unit(self) -> &'static str {
        match self {
            ResetKind::PositionToFix | ResetKind::ClockJump => "m",
            ResetKind::VelocityToFix | ResetKind::VelocityToZero | ResetKind::ClockDriftJump => {
                "m/s"
            }
            ResetKind::Inflation | ResetKind::Fading => "",
            ResetKind::Heading => "rad",
        }
    }
}

/// One reset.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct ResetRecord {
    /// When, s.
    pub time_s: f64,
    /// What.
    pub kind: ResetKind,
    /// How much the state moved, in [`ResetKind::change_unit`]: metres for
    /// a position or clock reset, m/s for velocity and drift, radians for
    /// the heading, the factor for an inflation.
    pub change: f64,
    /// Consecutive epochs whose test had failed before it (0 for jumps and
    /// the heading).
    pub failed_epochs: usize,
}

/// Everything a run recorded besides its solution: what the records-only
/// runs ([`super::run`], [`super::run_smoothed`]) return; their
/// integrity: `RunRecords::integrity` ([`super::integrity`]).
#[derive(Debug, Clone, PartialEq, Default)]
pub struct RunRecords {
    /// Every scalar measurement, in time order.
    pub measurements: Vec<MeasurementRecord>,
    /// Every batch test, in time order.
    pub batches: Vec<BatchRecord>,
    /// Every reset, in time order.
    pub resets: Vec<ResetRecord>,
}
