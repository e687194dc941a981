//! Named indices of the error state (method §5) and its typed wrapper.
//!
//! | indices | state | unit |
//! |---|---|---|
//! | 0-2 | attitude error ψ (Ĉ = (I + [ψ×]) C), ECEF axes | rad |
//! | 3-5 | velocity error δv^e | m/s |
//! | 6-8 | position error δr^e | m |
//! | 9-11 | accelerometer bias b_a, body axes | m/s² |
//! | 12-14 | gyro bias b_g, body axes | rad/s |
//! | 15 | receiver clock offset δc (c·δt) | m |
//! | 16 | receiver clock drift δċ | m/s |
//! | 17-19 | accelerometer scale-factor error s_a (optional) | 1 |
//! | 20-22 | gyro scale-factor error s_g (optional) | 1 |
//!
//! The optional scale-factor states are a compile-time extension: a filter
//! of size [`WITH_SCALE_FACTORS`] has them, one of size [`BASE_STATES`]
//! does not. Misalignments and nonlinearity are not states; how the
//! filters absorb them is documented in `coupling`.

use nalgebra::{SVector, Vector3};

/// Attitude error ψ, rad.
pub const ATTITUDE: usize = 0;
/// Velocity error δv^e, m/s.
pub const VELOCITY: usize = 3;
/// Position error δr^e, m.
pub const POSITION: usize = 6;
/// Accelerometer bias, m/s².
pub const ACCEL_BIAS: usize = 9;
/// Gyro bias, rad/s.
pub const GYRO_BIAS: usize = 12;
/// Receiver clock offset, m.
pub const CLOCK_OFFSET: usize = 15;
/// Receiver clock drift, m/s.
pub const CLOCK_DRIFT: usize = 16;
/// Accelerometer scale-factor error (only when `N` = [`WITH_SCALE_FACTORS`]).
pub const ACCEL_SCALE_FACTOR: usize = 17;
/// Gyro scale-factor error (only when `N` = [`WITH_SCALE_FACTORS`]).
pub const GYRO_SCALE_FACTOR: usize = 20;
/// Size of the base state.
pub const BASE_STATES: usize = 17;
/// Size of the state with accelerometer and gyro scale factors.
pub const WITH_SCALE_FACTORS: usize = 23;

/// Names of the states, for messages and for the Python solution.
pub struct StateLayout;

impl StateLayout {
    const NAMES: [&'static str; WITH_SCALE_FACTORS] = [
        "attitude_x",
        "attitude_y",
        "attitude_z",
        "velocity_x",
        "velocity_y",
        "velocity_z",
        "position_x",
        "position_y",
        "position_z",
        "accel_bias_x",
        "accel_bias_y",
        "accel_bias_z",
        "gyro_bias_x",
        "gyro_bias_y",
        "gyro_bias_z",
        "clock_offset",
        "clock_drift",
        "accel_scale_factor_x",
        "accel_scale_factor_y",
        "accel_scale_factor_z",
        "gyro_scale_factor_x",
        "gyro_scale_factor_y",
        "gyro_scale_factor_z",
    ];

    /// The names of the first `n` states (17, or 23 with scale factors).
    pub fn names(n: usize) -> &'static [&'static str] {
        &Self::NAMES[..n.min(WITH_SCALE_FACTORS)]
    }

    /// The name of state `i`.
    pub fn name(i: usize) -> &'static str {
        Self::NAMES.get(i).copied().unwrap_or("unknown")
    }
}

/// The error-state vector with named accessors (estimate minus truth).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct ErrorState<const N: usize>(pub SVector<f64, N>);

impl<const N: usize> ErrorState<N> {
    /// All zero (the state after each closed-loop feedback).
    pub fn zero() -> Self {
        Self(SVector::zeros())
    }
    fn block(&self, i: usize) -> Vector3<f64> {
        self.0.fixed_rows::<3>(i).into_owned()
    }
    /// ψ, rad.
    pub fn attitude(&self) -> Vector3<f64> {
        self.block(ATTITUDE)
    }
    /// δv^e, m/s.
    pub fn velocity(&self) -> Vector3<f64> {
        self.block(VELOCITY)
    }
    /// δr^e, m.
    pub fn position(&self) -> Vector3<f64> {
        self.block(POSITION)
    }
    /// Accelerometer bias error, m/s².
    pub fn accel_bias(&self) -> Vector3<f64> {
        self.block(ACCEL_BIAS)
    }
    /// Gyro bias error, rad/s.
    pub fn gyro_bias(&self) -> Vector3<f64> {
        self.block(GYRO_BIAS)
    }
    /// Clock offset error, m.
    pub fn clock_offset(&self) -> f64 {
        self.0[CLOCK_OFFSET]
    }
    /// Clock drift error, m/s.
    pub fn clock_drift(&self) -> f64 {
        self.0[CLOCK_DRIFT]
    }
    /// Scale-factor errors (accelerometer, gyro), when the state has them.
    pub fn scale_factors(&self) -> Option<(Vector3<f64>, Vector3<f64>)> {
        (N >= WITH_SCALE_FACTORS).then(|| {
            (
                self.block(ACCEL_SCALE_FACTOR),
                self.block(GYRO_SCALE_FACTOR),
            )
        })
    }
}
