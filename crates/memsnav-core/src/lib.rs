//! # memsnav-core
//!
//! The numerics of memsnav: MEMS inertial sensor error models, their
//! calibration and inversion, a strapdown INS in ECEF, GNSS simulation and
//! GNSS/INS coupled filters (de Boer et al., ION GNSS 2008; the method is
//! restated in `design/method.md`).
//!
//! ## Frames, units and conventions
//!
//! - Everything is SI: m, m/s, m/s², rad, rad/s, s. Degrees, g and °/s
//!   appear only at the edges (presets, reports), in names that say so.
//! - Frames: `e` = ECEF (WGS84), `b` = body (x forward, y right, z down),
//!   `n` = local NED. Vectors carry their frame in their name
//!   (`position_ecef`, `f_ib_b`); a matrix `c_b_e` maps body vectors to ECEF.
//! - IMU samples are instantaneous values at their time stamps.
//! - Every random draw comes from an RNG the caller seeds.
//! - Fallible functions return [`Result`] with a typed [`Error`] that names
//!   the argument or the parameter at fault.

// Every public item says what it is; CI's clippy -D warnings enforces it.
#![warn(missing_docs)]

pub mod allan;
pub mod allan_fit;
pub mod attitude;
pub mod calibration;
pub mod chi_square;
pub mod coupling;
pub mod error;
pub mod experiments;
pub mod filter;
pub mod gauss_markov;
pub mod geodesy;
pub mod gnss;
pub mod ins;
pub mod inversion;
pub mod known_keys;
pub mod limits;
pub mod logs;
pub mod montecarlo;
pub mod navigate;
pub mod output;
pub mod random;
pub mod sensors;
pub mod text;
pub mod timing;
pub mod trajectory;
pub mod validate;

pub use error::{Error, Result};
