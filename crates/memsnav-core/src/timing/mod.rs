//! Time alignment of real logs: the GPS time of IMU samples from an
//! RTKLIB time tag ([`tag_clock`]), the offset between IMU and GNSS found
//! from the data ([`estimate_time_offset`]) and the latency of a GNSS
//! solution's velocity behind its positions ([`estimate_velocity_latency`]).

mod gnss_track;
mod imu_gnss_offset;
mod integral;
mod lag_search;
mod tag_clock;
mod velocity_latency;

pub use imu_gnss_offset::{estimate_time_offset, OffsetSignal, TimeOffsetOptions};
pub use lag_search::LagEstimate;
pub use tag_clock::{tag_clock, LineEnds, TagClock};
pub use velocity_latency::{estimate_velocity_latency, VelocityLatencyOptions};
