//! Shared, seeded inputs of the memsnav-core benchmarks (run them with
//! `cargo bench -p memsnav-benches`; commands and figures in
//! `docs/results/performance.md`).
//!
//! Every input is drawn from a fixed seed, so two runs of a bench time the
//! same arithmetic.

use memsnav_core::coupling::{self, initial_state_from_fix, FilterTuning, InitialState, Solution};
use memsnav_core::filter::state::BASE_STATES;
use memsnav_core::gnss::{
    self, Constellation, GnssEpoch, ReceiverTrack, SimulationConfig, WalkerConfig,
};
use memsnav_core::ins::ImuData;
use memsnav_core::random::stream;
use memsnav_core::sensors::{ImuModel, ImuReadings};
use memsnav_core::trajectory::{RandomTrajectoryConfig, Trajectory};

/// Seed of every benchmark input.
pub const SEED: u64 = 2008;

/// The reference workload: a random land-vehicle trajectory
/// (Toulouse), the paper's MEMS IMU at 100 Hz, 1 Hz GNSS with a fixed
/// number of satellites (pseudorange and pseudorange rate), the filter
/// tuned from the IMU's specification and started from the first fix.
pub struct TightScenario {
    pub truth: Trajectory,
    pub readings: ImuReadings,
    pub epochs: Vec<GnssEpoch>,
    pub tuning: FilterTuning,
    pub initial: InitialState,
}

impl TightScenario {
    /// `duration_s` of motion at 100 Hz with `n_satellites` tracked (a
    /// 24-satellite Walker constellation up to 6, 48 above).
    pub fn new(duration_s: f64, n_satellites: usize) -> Self {
        let mut rng = stream(SEED, 0);
        let truth = Trajectory::random(
            &RandomTrajectoryConfig {
                duration_s,
                ..Default::default()
            },
            &mut rng,
        )
        .expect("random trajectory");
        let imu = ImuModel::preset("paper-mems", &mut rng).expect("preset");
        let readings = imu
            .measure(&truth.specific_force_b, &truth.angular_rate_b, &mut rng)
            .expect("IMU readings");
        // 24 satellites (GPS-like) leave 7-10 in view; 12 tracked need a
        // second constellation's worth.
        let sky = Constellation::walker(&WalkerConfig {
            n_satellites: if n_satellites > 6 { 48 } else { 24 },
            ..Default::default()
        })
        .expect("walker constellation");
        let epochs = gnss::simulate(
            &ReceiverTrack {
                time_s: &truth.time_s,
                position_ecef: &truth.position_ecef,
                velocity_ecef: &truth.velocity_ecef,
            },
            &sky,
            &SimulationConfig {
                n_satellites,
                ..Default::default()
            },
            &mut rng,
        )
        .expect("GNSS simulation");
        let tuning = FilterTuning::from_imu_spec(&imu.spec, imu.sample_rate_hz, false)
            .expect("tuning from the IMU spec");
        let initial = initial_state_from_fix(&epochs, &Self::imu_of(&truth, &readings), None)
            .expect("initial fix");
        Self {
            truth,
            readings,
            epochs,
            tuning,
            initial,
        }
    }

    fn imu_of<'a>(truth: &'a Trajectory, readings: &'a ImuReadings) -> ImuData<'a> {
        ImuData {
            time_s: &truth.time_s,
            specific_force_b: &readings.specific_force_b,
            angular_rate_b: &readings.angular_rate_b,
            increments: None,
        }
    }

    /// The IMU series as the filters take it.
    pub fn imu(&self) -> ImuData<'_> {
        Self::imu_of(&self.truth, &self.readings)
    }

    /// IMU epochs (samples) in the run.
    pub fn imu_epochs(&self) -> usize {
        self.truth.time_s.len()
    }

    /// The 17-state tight filter over the run with an empty observer
    /// (nothing stored per sample).
    pub fn run_records_only(&self) {
        coupling::run::<BASE_STATES, _, _>(
            &self.imu(),
            &self.epochs,
            &self.initial,
            &self.tuning,
            |_, _| {},
        )
        .expect("the reference run");
    }

    /// The 17-state tight filter's whole solution (what the Python API returns).
    pub fn run_solution(&self) -> Solution {
        coupling::solution::<BASE_STATES, _>(&self.imu(), &self.epochs, &self.initial, &self.tuning)
            .expect("the reference run")
    }

    /// The forward solution and the smoothed one (`smooth=True`).
    pub fn run_smoothed(&self) -> (Solution, Solution) {
        coupling::smoothed_solution::<BASE_STATES, _>(
            &self.imu(),
            &self.epochs,
            &self.initial,
            &self.tuning,
        )
        .expect("the reference run")
    }
}
