//! The receiver's motion the simulator measures from and the outages are
//! applied along.

use nalgebra::Vector3;

/// The receiver's motion: times (s, strictly increasing) with ECEF
/// positions (m) and velocities (m/s), e.g. a trajectory's truth at the IMU
/// rate.
#[derive(Debug, Clone, Copy)]
pub struct ReceiverTrack<'a> {
    /// The track's times, s.
    pub time_s: &'a [f64],
    /// The receiver's ECEF position at each, m.
    pub position_ecef: &'a [Vector3<f64>],
    /// Its ECEF velocity at each, m/s.
    pub velocity_ecef: &'a [Vector3<f64>],
}
