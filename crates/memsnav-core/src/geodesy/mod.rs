//! WGS84 geodesy: the ellipsoid, geodetic ↔ ECEF, the NED frame, gravity.

pub mod domain;
mod ellipsoid;
mod gravity;
pub mod wgs84;

pub use ellipsoid::{
    c_n_e, c_n_e_with, ecef_to_geodetic, geodetic_to_ecef, geodetic_to_ecef_with, meridian_radius,
    ned_offset, transverse_radius, Geodetic,
};
pub use gravity::{gravitation_ecef, gravity_ecef, normal_gravity_somigliana};
