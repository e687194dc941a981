//! The tight filter on pseudoranges whose errors are correlated over
//! seconds (a Gauss-Markov residual per satellite, as a hand-held
//! antenna's multipath): taken as white with their full variance, the
//! epochs confirm each other's error and the filter is overconfident;
//! with `pseudorange_correlation_time_s` set to the errors' correlation
//! time, its position errors agree with its covariance.

use memsnav_core::coupling::{self, FilterTuning};
use memsnav_core::filter::chi_square::mean_per_dof_band;
use memsnav_core::filter::nees;
use memsnav_core::gnss::{AtmosphericResidual, SimulationConfig};
use memsnav_core::random::stream;
use memsnav_core::sensors::ImuModel;
use nalgebra::{SMatrix, SVector};

mod common;
mod figures;
use common::*;
use figures::Figures;

const RUNS: u64 = 8;
/// The code errors: white 0.3 m plus 2 m correlated over 10 s, at 4 Hz.
const WHITE_STD_M: f64 = 0.3;
const CORRELATED_STD_M: f64 = 2.0;
const CORRELATION_TIME_S: f64 = 10.0;

/// Mean position NEES per dof over the runs and seconds 60-300 (after the
/// start's transient), and the position RMS, for a filter that takes the
/// code errors' correlation time as `correlation_time_s`.
fn position_consistency(correlation_time_s: f64) -> (f64, f64, usize) {
    let truth = drive(300.0, 100.0, true);
    let spec = bias_and_noise_spec(1e-2, 1e-4, 1e-3, 1e-4);
    let tuning = FilterTuning {
        pseudorange_correlation_time_s: correlation_time_s,
        ..FilterTuning::from_imu_spec(&spec, 100.0, false).unwrap()
    };
    let config = SimulationConfig {
        rate_hz: 4.0,
        n_satellites: 8,
        pseudorange_std_m: WHITE_STD_M,
        residual: Some(AtmosphericResidual {
            std_m: CORRELATED_STD_M,
            correlation_time_s: CORRELATION_TIME_S,
        }),
        ..SimulationConfig::default()
    };
    let (mut nees_sum, mut squared, mut samples) = (0.0, 0.0, 0);
    for run in 0..RUNS {
        let mut rng = stream(4242, run);
        let imu = ImuModel::from_spec(&spec, 100.0, &mut rng).unwrap();
        let mut epochs = gnss_for(&truth, &config, &mut rng);
        // The receiver reports the errors' whole std, as a C/N0 model would.
        for m in epochs.iter_mut().flat_map(|e| e.measurements.iter_mut()) {
            m.pseudorange_std_m = WHITE_STD_M.hypot(CORRELATED_STD_M);
        }
        let init = perturbed_initial(&truth, &tuning.initial_std, &mut rng);
        let (f, w) = readings(&truth, &imu, &mut rng);
        let data = imu_data(&truth, &f, &w);
        coupling::run::<17, _, _>(&data, &epochs, &init, &tuning, |k, s| {
            if k % 100 != 0 || truth.time_s[k] < 60.0 {
                return;
            }
            let e: SVector<f64, 3> = nav_error(&s.nav, &truth.nav[k]).fixed_rows::<3>(6).into();
            let p: SMatrix<f64, 3, 3> = s.kf.p.fixed_view::<3, 3>(6, 6).into();
            nees_sum += nees(&e, &p).unwrap() / 3.0;
            squared += e.norm_squared();
            samples += 1;
        })
        .unwrap();
    }
    (
        nees_sum / samples as f64,
        (squared / samples as f64).sqrt(),
        samples,
    )
}

#[test]
fn correlated_code_errors_need_their_correlation_time() {
    let (white, white_rms, samples) = position_consistency(0.0);
    let (modelled, modelled_rms, _) = position_consistency(CORRELATION_TIME_S);
    // Per run the epochs of one second are far from independent; the band
    // is that of the runs (each run's NEES averaged over its seconds).
    let (lo, hi) = mean_per_dof_band(3.0, RUNS as usize, 0.95);
    println!(
        "position NEES/dof: white {white:.2}, correlation time {CORRELATION_TIME_S} s \
         {modelled:.2} (band of the runs [{lo:.2}, {hi:.2}]); RMS {white_rms:.2} / \
         {modelled_rms:.2} m over {samples} samples"
    );
    assert!(white > hi, "white: {white}");
    assert!(modelled > lo && modelled < hi, "modelled: {modelled}");
    assert!(modelled_rms < white_rms, "{modelled_rms} vs {white_rms}");
    // docs/how-to/multi-gnss.md, "Correlated code errors", shows this run
    // (the white NEES to 0.1, the rest to 0.01).
    Figures::new("correlated_code")
        .add("runs", RUNS as f64, 0.0)
        .add("correlation_time_s", CORRELATION_TIME_S, 0.0)
        .add("nees_per_dof_white", white, 0.05)
        .add("nees_per_dof_modelled", modelled, 0.005)
        .add("band_low", lo, 0.005)
        .add("band_high", hi, 0.005)
        .add("rms_white_m", white_rms, 0.005)
        .add("rms_modelled_m", modelled_rms, 0.005)
        .check_or_write();
}
