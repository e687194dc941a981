//! Range-bias states on a four-system sky (GPS, Galileo, BeiDou, GLONASS:
//! more than 30 satellites above 10°) whose pseudoranges carry a slow
//! per-satellite error (first-order Gauss-Markov, the process the states
//! model): with a slot for every satellite each one holds a state; the
//! shared slots hold 12 and leave the rest to noise inflation. The
//! every-satellite filter's position errors agree with its covariance
//! (NEES over seeded runs).
//!
//! Truth is the INS itself fed error-free samples, as in `coupling.rs`.

use std::collections::BTreeSet;

use memsnav_core::coupling::{self, FilterState, FilterTuning, RangeBiasModel};
use memsnav_core::filter::chi_square::mean_per_dof_band;
use memsnav_core::filter::state::{RangeBiasSlots, EVERY_SATELLITE_SLOTS, RANGE_BIAS_SLOTS};
use memsnav_core::filter::{nees, Layout};
use memsnav_core::gnss::{AtmosphericResidual, Constellation, GnssSystem, SimulationConfig};
use memsnav_core::random::stream;
use memsnav_core::sensors::ImuModel;
use nalgebra::SMatrix;

mod common;
mod figures;
use common::*;
use figures::Figures;

const EVERY: usize = Layout::size(false, false, true, RangeBiasSlots::EverySatellite);
const SHARED: usize = Layout::size(false, false, true, RangeBiasSlots::Shared);

/// The simulated per-satellite residual, which the filter's range-bias
/// model matches.
const RESIDUAL: AtmosphericResidual = AtmosphericResidual {
    std_m: 2.0,
    correlation_time_s: 600.0,
};

struct Sky {
    truth: Truth,
    sky: Constellation,
    config: SimulationConfig,
    tuning: FilterTuning,
}

fn four_systems() -> Sky {
    let truth = drive(120.0, 100.0, true);
    let spec = bias_and_noise_spec(1e-2, 1e-4, 1e-3, 1e-4);
    let mut tuning = FilterTuning::from_imu_spec(&spec, 100.0, false).unwrap();
    tuning.set_range_bias_model(&RangeBiasModel {
        std_m: RESIDUAL.std_m,
        correlation_time_s: RESIDUAL.correlation_time_s,
    });
    Sky {
        truth,
        sky: Constellation::nominal_walkers(&GnssSystem::ALL).unwrap(),
        config: SimulationConfig {
            n_satellites: 60,
            residual: Some(RESIDUAL),
            inter_system_bias_m: [3.0, -25.0, 10.0],
            ..SimulationConfig::default()
        },
        tuning,
    }
}

/// With a slot for every satellite, every satellite of the last epoch
/// holds one (more than 30, of four systems); with the shared slots, 12
/// of them do.
#[test]
fn every_tracked_satellite_holds_a_range_bias_state() {
    let s = four_systems();
    let mut rng = stream(31, 0);
    let spec = bias_and_noise_spec(1e-2, 1e-4, 1e-3, 1e-4);
    let imu = ImuModel::from_spec(&spec, 100.0, &mut rng).unwrap();
    let epochs = gnss_from(&s.truth, &s.sky, &s.config, &mut rng);
    let last: BTreeSet<u16> = epochs
        .last()
        .unwrap()
        .measurements
        .iter()
        .map(|m| m.sat_id)
        .collect();
    let systems: BTreeSet<_> = epochs[0].measurements.iter().map(|m| m.system).collect();
    assert_eq!(systems.len(), 4, "{systems:?}");
    assert!(last.len() > 30, "{} satellites", last.len());
    assert!(last.len() <= EVERY_SATELLITE_SLOTS);
    let init = perturbed_initial(&s.truth, &s.tuning.initial_std, &mut rng);
    let (f, w) = readings(&s.truth, &imu, &mut rng);
    let data = imu_data(&s.truth, &f, &w);
    let held = |state: &FilterState<EVERY>| -> BTreeSet<u16> {
        state.range_biases().map(|(sat, _)| sat).collect()
    };
    let mut every = None;
    coupling::run::<EVERY, _, _>(&data, &epochs, &init, &s.tuning, |k, st| {
        if k + 1 == s.truth.time_s.len() {
            every = Some(held(st));
        }
    })
    .unwrap();
    let every = every.unwrap();
    assert!(last.is_subset(&every), "{last:?} not all in {every:?}");
    let mut shared = 0;
    coupling::run::<SHARED, _, _>(&data, &epochs, &init, &s.tuning, |k, st| {
        if k + 1 == s.truth.time_s.len() {
            shared = st.range_biases().count();
        }
    })
    .unwrap();
    assert_eq!(shared, RANGE_BIAS_SLOTS);
}

/// The position NEES/dof at the end of each of `runs` seeded runs of the
/// filter with `N` states, and its position RMS there, m.
fn end_nees<const N: usize>(s: &Sky, runs: u64) -> (Vec<f64>, f64) {
    let spec = bias_and_noise_spec(1e-2, 1e-4, 1e-3, 1e-4);
    let mut out = Vec::new();
    let mut sq = 0.0;
    for i in 0..runs {
        let mut rng = stream(31, 1 + i);
        let imu = ImuModel::from_spec(&spec, 100.0, &mut rng).unwrap();
        let epochs = gnss_from(&s.truth, &s.sky, &s.config, &mut rng);
        let init = perturbed_initial(&s.truth, &s.tuning.initial_std, &mut rng);
        let (f, w) = readings(&s.truth, &imu, &mut rng);
        let data = imu_data(&s.truth, &f, &w);
        let end = s.truth.time_s.len() - 1;
        coupling::run::<N, _, _>(&data, &epochs, &init, &s.tuning, |k, st| {
            if k == end {
                let e = nav_error(&st.nav, &s.truth.nav[k])
                    .fixed_rows::<3>(6)
                    .into_owned();
                let p: SMatrix<f64, 3, 3> = st.kf.p.fixed_view::<3, 3>(6, 6).into_owned();
                out.push(nees(&e, &p).unwrap());
                sq += e.norm_squared();
            }
        })
        .unwrap();
    }
    (out, (sq / runs as f64).sqrt())
}

/// Twenty seeded runs: with a state for every satellite, the position
/// NEES at the end (3 dof per run, independent runs) lies in its 95 %
/// band; the shared slots, which count the slow errors of the satellites
/// beyond them as white noise, are overconfident.
#[test]
fn every_satellite_filter_is_consistent_on_slow_pseudorange_errors() {
    let s = four_systems();
    let runs = 20;
    let (lo, hi) = mean_per_dof_band(3.0, runs as usize, 0.95);
    let mean = |v: &[f64]| v.iter().sum::<f64>() / (3.0 * v.len() as f64);
    let (every, every_rms) = end_nees::<EVERY>(&s, runs);
    let (shared, shared_rms) = end_nees::<SHARED>(&s, runs);
    println!(
        "NEES/dof every satellite {:.3} (RMS {every_rms:.3} m), shared {:.3} (RMS {shared_rms:.3} m), band [{lo:.3}, {hi:.3}]",
        mean(&every),
        mean(&shared)
    );
    assert!(mean(&every) > lo && mean(&every) < hi);
    assert!(mean(&shared) > hi);
    assert!(every_rms < shared_rms);
    // docs/how-to/multi-gnss.md quotes these (NEES to 0.01, RMS to 0.01 m).
    Figures::new("range_bias_slots")
        .add("every_satellite_nees_per_dof", mean(&every), 0.005)
        .add("shared_nees_per_dof", mean(&shared), 0.05)
        .add("every_satellite_rms_m", every_rms, 0.005)
        .add("shared_rms_m", shared_rms, 0.005)
        .add("runs", runs as f64, 0.0)
        .check_or_write();
}
