//! The tight filter with time-differenced carrier phase on simulated
//! measurements whose carriers slip silently (no loss-of-lock flag): the
//! filter finds the injected slips itself, stays consistent with its
//! covariance, and navigates no worse than on the code and Doppler alone.
//!
//! Truth is the INS itself fed error-free samples, as in `coupling.rs`;
//! the slips' truth is the simulator's list ([`GnssSimulation::cycle_slips`]).

use memsnav_core::coupling::{
    self, FilterTuning, InitialState, MeasurementKind, MeasurementStatus, RunRecords,
};
use memsnav_core::filter::chi_square::mean_per_dof_band;
use memsnav_core::filter::nees;
use memsnav_core::gnss::{
    simulate_with_truth, Constellation, CycleSlip, GnssEpoch, ReceiverTrack, SimulationConfig,
    WalkerConfig, DEFAULT_CARRIER_PHASE_STD_M,
};
use memsnav_core::ins::ImuData;
use memsnav_core::random::{stream, Rng};
use memsnav_core::sensors::ImuModel;
use nalgebra::SMatrix;

mod common;
use common::*;

/// Seconds per run; runs; satellites tracked.
const DURATION_S: f64 = 600.0;
const RUNS: u64 = 8;
const SATELLITES: usize = 10;
/// Chance of a slip per satellite and epoch: ~0.01 × 7 visible × 600 = 42
/// per run.
const SLIP_PROBABILITY: f64 = 0.01;

/// The simulated measurements with their slips along `truth`.
fn measurements(
    truth: &Truth,
    config: &SimulationConfig,
    rng: &mut Rng,
) -> (Vec<GnssEpoch>, Vec<CycleSlip>) {
    let pos: Vec<_> = truth.nav.iter().map(|s| s.position_ecef).collect();
    let vel: Vec<_> = truth.nav.iter().map(|s| s.velocity_ecef).collect();
    let track = ReceiverTrack {
        time_s: &truth.time_s,
        position_ecef: &pos,
        velocity_ecef: &vel,
    };
    let sky = Constellation::walker(&WalkerConfig::default()).unwrap();
    let sim = simulate_with_truth(&track, &sky, config, rng).unwrap();
    (sim.epochs, sim.cycle_slips)
}

/// A short drive with carrier phase for the model's checks: the tuning
/// with carrier phase on, the epochs (silent slips at `slip_probability`),
/// the perturbed start and the IMU's readings along the truth.
struct CarrierRun {
    truth: Truth,
    tuning: FilterTuning,
    epochs: Vec<GnssEpoch>,
    init: InitialState,
    f: Vec<nalgebra::Vector3<f64>>,
    w: Vec<nalgebra::Vector3<f64>>,
}

impl CarrierRun {
    fn new(duration_s: f64, seed: u64, slip_probability: f64) -> Self {
        let truth = drive(duration_s, 100.0, true);
        let spec = bias_and_noise_spec(1e-2, 1e-4, 1e-3, 1e-4);
        let tuning = FilterTuning {
            use_carrier_phase: true,
            ..FilterTuning::from_imu_spec(&spec, 100.0, false).unwrap()
        };
        let config = SimulationConfig {
            n_satellites: SATELLITES,
            carrier_phase_std_m: DEFAULT_CARRIER_PHASE_STD_M,
            cycle_slip_probability: slip_probability,
            ..SimulationConfig::default()
        };
        let mut rng = stream(seed, 0);
        let imu = ImuModel::from_spec(&spec, 100.0, &mut rng).unwrap();
        let (epochs, _) = measurements(&truth, &config, &mut rng);
        let init = perturbed_initial(&truth, &tuning.initial_std, &mut rng);
        let (f, w) = readings(&truth, &imu, &mut rng);
        Self {
            truth,
            tuning,
            epochs,
            init,
            f,
            w,
        }
    }

    fn data(&self) -> ImuData<'_> {
        imu_data(&self.truth, &self.f, &self.w)
    }
}

/// What one filter run gave, at the GNSS epochs (every 100th IMU sample).
#[derive(Default)]
struct Errors {
    /// Sum of squared position errors, m², and their count.
    position_sq: f64,
    samples: usize,
    /// Position error components beyond 3σ, and components checked.
    beyond_3_sigma: usize,
    components: usize,
    /// Per GNSS epoch: NEES/dof of (ψ, δv, δr).
    nees_per_dof: Vec<f64>,
}

impl Errors {
    fn rms_m(&self) -> f64 {
        (self.position_sq / self.samples as f64).sqrt()
    }
}

/// The 17-state tight filter along `truth` on `epochs`.
fn filter_run(
    truth: &Truth,
    data: &ImuData<'_>,
    epochs: &[GnssEpoch],
    init: &InitialState,
    tuning: &FilterTuning,
) -> (RunRecords, Errors) {
    let mut errors = Errors::default();
    let records = coupling::run::<17, _, _>(data, epochs, init, tuning, |k, s| {
        if k % 100 != 0 {
            return;
        }
        let e = nav_error(&s.nav, &truth.nav[k]);
        let p: SMatrix<f64, 9, 9> = s.kf.p.fixed_view::<9, 9>(0, 0).into_owned();
        errors.nees_per_dof.push(nees(&e, &p).unwrap() / 9.0);
        for i in 6..9 {
            errors.position_sq += e[i] * e[i];
            errors.beyond_3_sigma += usize::from(e[i].abs() > 3.0 * p[(i, i)].sqrt());
            errors.components += 1;
        }
        errors.samples += 1;
    })
    .unwrap();
    (records, errors)
}

/// Seeded runs of a 600 s drive, 10 GPS satellites, 3 mm carrier noise and
/// a 1 % chance per satellite and epoch of a silent slip (±1 and ±2 cycles
/// common). At least 99 % of the slips show as a carrier record of their
/// satellite and epoch that was not applied (slip, excluded or gated); no
/// run diverges; position errors lie within 3σ for ≥ 99 % of the
/// components; the mean NEES/dof over the runs stays in its 95 % band; and
/// the position RMS is no worse than the code-and-Doppler filter's.
#[test]
fn silent_cycle_slips_are_found_and_carrier_phase_helps() {
    let truth = drive(DURATION_S, 100.0, true);
    let spec = bias_and_noise_spec(1e-2, 1e-4, 1e-3, 1e-4);
    let code_only = FilterTuning::from_imu_spec(&spec, 100.0, false).unwrap();
    // The simulated changes err by their phase noise alone, so no floor
    // (the default 2 cm is for what a real INS's displacement gets wrong:
    // with it the velocity NEES/dof here is 0.3).
    let mut with_carrier = FilterTuning {
        use_carrier_phase: true,
        ..code_only
    };
    with_carrier.floor.carrier_phase_m = 0.0;
    let config = SimulationConfig {
        n_satellites: SATELLITES,
        carrier_phase_std_m: DEFAULT_CARRIER_PHASE_STD_M,
        cycle_slip_probability: SLIP_PROBABILITY,
        ..SimulationConfig::default()
    };
    let (mut slips, mut found, mut carrier_records, mut false_alarms) = (0, 0, 0, 0);
    let mut small = (0, 0); // (±1-2 cycle slips, found)
                            // False alarms (slip, excluded, gate) at epochs without / with a slip.
    let mut false_kinds = [[0usize; 3]; 2];
    let mut nees_sum: Vec<f64> = Vec::new();
    let (mut beyond, mut components) = (0, 0);
    let (mut sq_carrier, mut sq_clean, mut sq_code, mut samples) = (0.0, 0.0, 0.0, 0);
    for i in 0..RUNS {
        let mut rng = stream(2024, i);
        let imu = ImuModel::from_spec(&spec, 100.0, &mut rng).unwrap();
        // The same code, Doppler and carrier noise without slips: the side
        // stream's slip draws aside, the same numbers (a reference).
        let mut rng_slip_free = rng.clone();
        let (epochs, injected) = measurements(&truth, &config, &mut rng);
        let slip_free = SimulationConfig {
            cycle_slip_probability: 0.0,
            ..config.clone()
        };
        let (clean_epochs, _) = measurements(&truth, &slip_free, &mut rng_slip_free);
        let init = perturbed_initial(&truth, &code_only.initial_std, &mut rng);
        let (f, w) = readings(&truth, &imu, &mut rng);
        let data = imu_data(&truth, &f, &w);

        let (records, errors) = filter_run(&truth, &data, &epochs, &init, &with_carrier);
        let integrity = records.integrity();
        assert!(!integrity.diverged(), "run {i}: {:?}", integrity.alerts);
        let not_applied = |status| {
            matches!(
                status,
                MeasurementStatus::CycleSlip
                    | MeasurementStatus::Excluded
                    | MeasurementStatus::RejectedByGate
            )
        };
        let carrier: Vec<_> = records
            .measurements
            .iter()
            .filter(|r| r.kind == MeasurementKind::CarrierPhase)
            .collect();
        let is_slip = |time_s: f64, id: u16| {
            injected
                .iter()
                .any(|s| s.time_s == time_s && s.sat_id == id)
        };
        let was_found = |s: &&CycleSlip| {
            carrier
                .iter()
                .any(|r| r.time_s == s.time_s && r.id == s.sat_id && not_applied(r.status))
        };
        let run_found = injected.iter().filter(was_found).count();
        let run_small: Vec<&CycleSlip> = injected.iter().filter(|s| s.cycles.abs() <= 2).collect();
        small.0 += run_small.len();
        small.1 += run_small.into_iter().filter(was_found).count();
        let run_false: Vec<_> = carrier
            .iter()
            .filter(|r| not_applied(r.status) && !is_slip(r.time_s, r.id))
            .collect();
        for r in &run_false {
            let at_a_slip = injected.iter().any(|s| s.time_s == r.time_s);
            false_kinds[usize::from(at_a_slip)][match r.status {
                MeasurementStatus::CycleSlip => 0,
                MeasurementStatus::Excluded => 1,
                _ => 2,
            }] += 1;
        }
        let run_false = run_false.len();
        slips += injected.len();
        found += run_found;
        carrier_records += carrier.len();
        false_alarms += run_false;
        beyond += errors.beyond_3_sigma;
        components += errors.components;
        if nees_sum.is_empty() {
            nees_sum = vec![0.0; errors.nees_per_dof.len()];
        }
        for (sum, x) in nees_sum.iter_mut().zip(&errors.nees_per_dof) {
            *sum += x;
        }

        let (_, clean) = filter_run(&truth, &data, &clean_epochs, &init, &with_carrier);
        sq_clean += clean.position_sq;
        let (code_records, code) = filter_run(&truth, &data, &epochs, &init, &code_only);
        assert!(!code_records.integrity().diverged());
        assert!(!code_records
            .measurements
            .iter()
            .any(|r| r.kind == MeasurementKind::CarrierPhase));
        println!(
            "run {i}: {run_found}/{} slips found, {run_false} false alarms of {} carrier changes; \
             position RMS {:.3} m with carrier, {:.3} m code and Doppler",
            injected.len(),
            carrier.len(),
            errors.rms_m(),
            code.rms_m()
        );
        sq_carrier += errors.position_sq;
        sq_code += code.position_sq;
        samples += errors.samples;
    }
    let share = found as f64 / slips as f64;
    let rms = |sq: f64| (sq / samples as f64).sqrt();
    let (rms_carrier, rms_code) = (rms(sq_carrier), rms(sq_code));
    let (lo, hi) = mean_per_dof_band(9.0, RUNS as usize, 0.95);
    let mean = nees_sum.iter().sum::<f64>() / (nees_sum.len() as f64 * RUNS as f64);
    println!(
        "{found}/{slips} slips found ({:.2} %; ±1-2 cycles: {}/{}), {false_alarms} false alarms \
         of {carrier_records} carrier changes; {beyond}/{components} position components beyond 3σ; \
         mean NEES/dof {mean:.3} in [{lo:.3}, {hi:.3}]; position RMS {rms_carrier:.3} m with \
         carrier, {rms_code:.3} m without",
        100.0 * share,
        small.1,
        small.0
    );
    println!(
        "false alarms (slip, excluded, gate): {:?} at epochs without a slip, {:?} at epochs with one",
        false_kinds[0], false_kinds[1]
    );
    println!(
        "position RMS with carrier and no slips: {:.3} m",
        rms(sq_clean)
    );
    assert!(slips >= 300, "{slips} slips");
    assert!(share >= 0.99, "{found}/{slips}");
    assert!(
        (beyond as f64) <= 0.01 * components as f64,
        "{beyond}/{components}"
    );
    assert!(mean > lo && mean < hi, "mean NEES/dof {mean}");
    assert!(rms_carrier <= rms_code, "{rms_carrier} vs {rms_code}");
}

/// The carrier changes carry neither the ambiguities nor the receiver
/// clock: adding a constant per satellite (whole cycles and a fraction) to
/// every carrier range and a different offset per epoch to all of an
/// epoch's carrier ranges leaves the filter's solution as it was, to
/// rounding. This is what eliminating the clock's change (rather than
/// estimating it) must give; a model that tied it to the clock states, or
/// used a carrier range by itself, would not.
#[test]
fn carrier_changes_are_blind_to_ambiguities_and_the_receiver_clock() {
    let run = CarrierRun::new(120.0, 77, SLIP_PROBABILITY);
    let (data, epochs, init, tuning) = (run.data(), &run.epochs, &run.init, &run.tuning);
    let shifted: Vec<GnssEpoch> = epochs
        .iter()
        .enumerate()
        .map(|(k, e)| {
            let clock_m = 1e4 * (k as f64).sin() + 3.0 * k as f64;
            let mut e = e.clone();
            for m in &mut e.measurements {
                if let Some(c) = &mut m.carrier {
                    c.range_m += clock_m + 0.1903 * (17.0 * f64::from(m.sat_id) + 0.37);
                }
            }
            e
        })
        .collect();
    let final_state = |epochs: &[GnssEpoch]| {
        let mut last = None;
        let records = coupling::run::<17, _, _>(&data, epochs, init, tuning, |_, s| {
            last = Some((s.nav.position_ecef, s.nav.velocity_ecef));
        })
        .unwrap();
        let used = records
            .measurements
            .iter()
            .filter(|r| r.kind == MeasurementKind::CarrierPhase)
            .map(|r| r.status)
            .collect::<Vec<_>>();
        (last.unwrap(), used)
    };
    let ((position, velocity), used) = final_state(epochs);
    let ((position_shifted, velocity_shifted), used_shifted) = final_state(&shifted);
    assert!(used.contains(&MeasurementStatus::Accepted));
    assert_eq!(
        used, used_shifted,
        "the slip and residual tests decided alike"
    );
    assert!((position - position_shifted).norm() < 1e-6);
    assert!((velocity - velocity_shifted).norm() < 1e-8);
}

/// A satellite whose state no range can be predicted from (here at the
/// Earth's centre) has its carrier change recorded as invalid, and its
/// carrier is not remembered for the next change; the others' changes are
/// still applied, and the solution stays finite.
#[test]
fn a_satellite_without_a_usable_state_spoils_only_its_own_changes() {
    let mut run = CarrierRun::new(60.0, 78, 0.0);
    let epochs = &mut run.epochs;
    let broken = epochs[10].measurements[0].sat_id;
    for e in epochs.iter_mut().skip(10).step_by(2) {
        if let Some(m) = e.measurements.iter_mut().find(|m| m.sat_id == broken) {
            m.position_ecef = nalgebra::Vector3::zeros();
        }
    }
    let mut finite = true;
    let records =
        coupling::run::<17, _, _>(&run.data(), &run.epochs, &run.init, &run.tuning, |_, s| {
            finite &= s.nav.position_ecef.iter().all(|x| x.is_finite());
        })
        .unwrap();
    assert!(finite);
    let carrier = |id: u16, status| {
        records
            .measurements
            .iter()
            .filter(|r| r.kind == MeasurementKind::CarrierPhase && r.id == id && r.status == status)
            .count()
    };
    // Every other epoch from the 10th breaks it: the changes into a broken
    // epoch are invalid, the ones out of it have nothing to start from.
    assert!(carrier(broken, MeasurementStatus::RejectedInvalid) >= 20);
    assert_eq!(carrier(broken, MeasurementStatus::Accepted), 9);
    let other = run.epochs[10].measurements[1].sat_id;
    assert!(carrier(other, MeasurementStatus::Accepted) > 50);
}
