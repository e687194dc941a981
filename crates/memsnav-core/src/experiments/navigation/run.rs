//! The draws of one navigation run, shared by every IMU and every filter
//! of the run (a paired comparison): the trajectory, its GNSS
//! measurements, the initial errors and each IMU's readings.

use nalgebra::{Matrix3, Vector3};
use rand::Rng as _;
use rand_distr::StandardNormal;

use crate::attitude::rotation_vector_to_dcm;
use crate::geodesy::{c_n_e, ecef_to_geodetic};
use crate::gnss::{self, Constellation, GnssEpoch, ReceiverTrack, SimulationConfig};
use crate::ins::NavState;
use crate::random::Rng;
use crate::trajectory::{RandomTrajectoryConfig, Trajectory};
use crate::validate::SeriesCheck;
use crate::Result;

use super::filters::Start;
use super::imus::{imu_inputs, ImuInput};
use super::{InitialStateSource, NavigationExperimentConfig};

/// Everything one run draws.
pub(super) struct RunDraws {
    pub truth: Trajectory,
    pub epochs: Vec<GnssEpoch>,
    pub start: Start,
    /// Per IMU of the set: its readings, when it was needed.
    pub inputs: Vec<Option<ImuInput>>,
}

/// A draw of N(0, diag(std²)).
fn normal3(std: &Vector3<f64>, rng: &mut Rng) -> Vector3<f64> {
    Vector3::from_fn(|i, _| std[i] * rng.sample::<f64, _>(StandardNormal))
}

/// Draws one run from its stream, in this order: the random land-vehicle
/// trajectory, its GNSS measurements, the initial attitude error (NED, the
/// filters' P₀ attitude block), the initial position and velocity errors
/// when the initial state is given, and the seed of the IMUs' streams,
/// from which the `needed` IMUs draw their readings (all when None).
pub(super) fn draw_run(
    config: &NavigationExperimentConfig,
    trajectory_config: &RandomTrajectoryConfig,
    gnss_config: &SimulationConfig,
    sky: &Constellation,
    rng: &mut Rng,
    needed: Option<&[bool]>,
) -> Result<RunDraws> {
    let truth = Trajectory::random(trajectory_config, rng)?;
    // The truth is ours (increasing times, finite): not checked again.
    let epochs = gnss::simulate_track(
        &ReceiverTrack {
            time_s: &truth.time_s,
            position_ecef: &truth.position_ecef,
            velocity_ecef: &truth.velocity_ecef,
        },
        sky,
        gnss_config,
        rng,
        SeriesCheck::Trusted,
    )?
    .epochs;
    // ψ ~ N(0, diag(σ_N², σ_E², σ_D²)) in NED, Ĉ = R(ψ) C.
    let geo = ecef_to_geodetic(&truth.position_ecef[0]);
    let c_n_e = c_n_e(geo.latitude_rad, geo.longitude_rad);
    let psi = c_n_e * normal3(&config.initial_attitude_std_rad, rng);
    let attitude: Matrix3<f64> = rotation_vector_to_dcm(&psi) * truth.c_b_e[0];
    let start = match config.initial_state {
        InitialStateSource::FirstFix => Start::FirstFix { attitude },
        InitialStateSource::Given {
            position_std_m,
            velocity_std_m_s,
        } => Start::Given {
            nav: NavState {
                position_ecef: truth.position_ecef[0]
                    + normal3(&Vector3::repeat(position_std_m), rng),
                velocity_ecef: truth.velocity_ecef[0]
                    + normal3(&Vector3::repeat(velocity_std_m_s), rng),
                c_b_e: attitude,
            },
        },
    };
    let imu_seed: u64 = rng.random();
    let inputs = imu_inputs(
        &config.imus,
        &truth,
        trajectory_config.rate_hz,
        &config.segment_calibration(),
        imu_seed,
        needed,
    )?;
    Ok(RunDraws {
        truth,
        epochs,
        start,
        inputs,
    })
}
