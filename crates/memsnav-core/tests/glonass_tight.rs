//! GLONASS in the tight filter, on the simulator's GPS + GLONASS
//! measurements: the navigation errors stay consistent with the covariance
//! (NEES over seeded runs, NIS of the accepted pseudoranges and rates), the
//! solution reaches the truth from error-free IMU samples, and the GLONASS
//! inter-system bias the simulator puts in is estimated inside its σ.
//! GLONASS carrier phase (each slot's own wavelength) passes the
//! time-differenced carrier updates.
//!
//! Truth is the INS itself fed error-free samples, as in `coupling.rs`.

use memsnav_core::coupling::{self, FilterTuning, MeasurementKind, MeasurementStatus};
use memsnav_core::filter::chi_square::mean_per_dof_band;
use memsnav_core::filter::state::RangeBiasSlots;
use memsnav_core::filter::{nees, Layout};
use memsnav_core::gnss::{
    g1_wavelength_m, nominal_channel, Constellation, GnssSystem, SimulationConfig,
};
use memsnav_core::random::stream;
use memsnav_core::sensors::ImuModel;
use nalgebra::{SMatrix, Vector3};

mod common;
use common::*;

/// 17 base states + the 3 inter-system biases (Galileo, BeiDou, GLONASS).
const WITH_ISB: usize = Layout::size(false, false, true, RangeBiasSlots::None);
/// GLONASS's index among the inter-system biases.
const GLONASS: usize = 2;
/// The simulated GLONASS bias against GPS, m (a receiver's GLONASS group
/// delay and mean inter-frequency bias: metres to tens of metres).
const TRUE_GLONASS_ISB_M: f64 = 12.0;

fn gps_and_glonass() -> Constellation {
    Constellation::nominal_walkers(&[GnssSystem::Gps, GnssSystem::Glonass]).unwrap()
}

fn config() -> SimulationConfig {
    SimulationConfig {
        n_satellites: 40,
        inter_system_bias_m: [0.0, 0.0, TRUE_GLONASS_ISB_M],
        ..SimulationConfig::default()
    }
}

/// Five seeded runs of 150 s with every GPS and GLONASS satellite above
/// the mask: mean NEES/dof of (ψ, δv, δr) inside its 95 % band, mean NIS
/// of the accepted pseudoranges and rates in theirs, every measurement
/// accepted, and the GLONASS bias within 3σ of the truth with σ below
/// 0.5 m (from 10 m).
#[test]
fn gps_and_glonass_are_consistent_and_estimate_the_glonass_bias() {
    let truth = drive(150.0, 100.0, true);
    let spec = bias_and_noise_spec(1e-2, 1e-4, 1e-3, 1e-4);
    let mut tuning = FilterTuning::from_imu_spec(&spec, 100.0, false).unwrap();
    tuning.initial_std.attitude_ned_rad = Vector3::new(0.2, 0.2, 0.5).map(f64::to_radians);
    let sky = gps_and_glonass();
    let first = Layout::for_size::<WITH_ISB>().inter_system_bias.unwrap();
    let runs = 5;
    let mut nees_sum = vec![0.0; 151];
    let (mut nis_sum, mut nis_n) = (0.0, 0usize);
    let mut isb_nees = 0.0;
    for i in 0..runs {
        let mut rng = stream(31, i);
        let imu = ImuModel::from_spec(&spec, 100.0, &mut rng).unwrap();
        let epochs = gnss_from(&truth, &sky, &config(), &mut rng);
        let glonass = epochs[0]
            .measurements
            .iter()
            .filter(|m| m.system == GnssSystem::Glonass)
            .count();
        assert!(glonass >= 4, "{glonass} GLONASS satellites");
        let init = perturbed_initial(&truth, &tuning.initial_std, &mut rng);
        let (f, w) = readings(&truth, &imu, &mut rng);
        let data = imu_data(&truth, &f, &w);
        let mut k_nees = 0;
        let mut end = None;
        let records = coupling::run::<WITH_ISB, _, _>(&data, &epochs, &init, &tuning, |k, s| {
            if k % 100 == 0 {
                let e = nav_error(&s.nav, &truth.nav[k]);
                let p: SMatrix<f64, 9, 9> = s.kf.p.fixed_view::<9, 9>(0, 0).into_owned();
                nees_sum[k_nees] += nees(&e, &p).unwrap() / 9.0;
                k_nees += 1;
            }
            if k + 1 == truth.time_s.len() {
                let j = first + GLONASS;
                end = Some((s.inter_system_bias_m[GLONASS], s.kf.p[(j, j)].sqrt()));
            }
        })
        .unwrap();
        assert!(records
            .measurements
            .iter()
            .all(|r| r.status == MeasurementStatus::Accepted));
        for r in &records.measurements {
            nis_sum += r.nis;
            nis_n += 1;
        }
        let (estimate, sigma) = end.unwrap();
        let error = estimate - TRUE_GLONASS_ISB_M;
        println!(
            "run {i}: {glonass} GLONASS of {} satellites; GLONASS ISB {estimate:+.3} m (truth {TRUE_GLONASS_ISB_M:+}), σ {sigma:.3} m",
            epochs[0].measurements.len()
        );
        assert!(error.abs() < 3.0 * sigma, "{error} vs σ {sigma}");
        assert!(sigma < 0.5, "σ {sigma}");
        isb_nees += (error / sigma).powi(2);
    }
    let (lo, hi) = mean_per_dof_band(9.0, runs as usize, 0.95);
    let mean = nees_sum.iter().sum::<f64>() / (nees_sum.len() as f64 * runs as f64);
    println!("mean NEES/dof = {mean:.3}, band [{lo:.3}, {hi:.3}]");
    assert!(mean > lo && mean < hi, "mean NEES/dof {mean}");
    let nis = nis_sum / nis_n as f64;
    // Scalar records of correlated epochs: the band of a tenth of them.
    let (lo, hi) = mean_per_dof_band(1.0, nis_n / 10, 0.95);
    println!("mean NIS = {nis:.3} over {nis_n}, band [{lo:.3}, {hi:.3}]");
    assert!(nis > lo && nis < hi, "mean NIS {nis}");
    let (lo, hi) = mean_per_dof_band(1.0, runs as usize, 0.99);
    let isb = isb_nees / runs as f64;
    println!("GLONASS ISB NEES at the end = {isb:.3}, band [{lo:.3}, {hi:.3}]");
    assert!(isb > lo && isb < hi, "ISB NEES {isb}");
}

/// Error-free IMU samples and noise-free GPS + GLONASS pseudoranges and
/// rates carrying the GLONASS bias, from an exact start: the filter stays
/// on the truth (centimetres) and its GLONASS bias on the simulated one.
#[test]
fn error_free_samples_reach_the_truth_with_glonass() {
    let truth = drive(120.0, 100.0, true);
    let spec = bias_and_noise_spec(0.0, 0.0, 0.0, 0.0);
    let tuning =
        FilterTuning::from_imu_spec(&bias_and_noise_spec(1e-2, 1e-4, 1e-3, 1e-4), 100.0, false)
            .unwrap();
    let mut rng = stream(32, 0);
    let imu = ImuModel::from_spec(&spec, 100.0, &mut rng).unwrap();
    let noise_free = SimulationConfig {
        pseudorange_std_m: 1e-3,
        pseudorange_rate_std_m_s: 1e-4,
        ..config()
    };
    let epochs = gnss_from(&truth, &gps_and_glonass(), &noise_free, &mut rng);
    let (f, w) = readings(&truth, &imu, &mut rng);
    let data = imu_data(&truth, &f, &w);
    let sol =
        coupling::solution::<WITH_ISB, _>(&data, &epochs, &exact_initial(&truth), &tuning).unwrap();
    let last = sol.time_s.len() - 1;
    let worst = sol
        .position_ecef
        .iter()
        .zip(&truth.nav)
        .map(|(p, t)| (p - t.position_ecef).norm())
        .fold(0.0, f64::max);
    let isb = sol.inter_system_bias_m[last][GLONASS];
    println!("largest position error {worst:.4} m; GLONASS ISB {isb:.4} m");
    assert!(worst < 0.05, "{worst} m");
    assert!((isb - TRUE_GLONASS_ISB_M).abs() < 0.05, "{isb}");
    assert_eq!(sol.rejected().count(), 0);
}

/// Simulated GLONASS carrier phase holds whole cycles of its slot's own
/// wavelength (no cycle of GPS L1's), and the time-differenced carrier
/// updates of GPS and GLONASS together pass their tests (GPS satellite 5
/// rises into the selection at 17 s: its new arc is flagged).
#[test]
fn glonass_carrier_phase_on_its_slot_wavelength() {
    let truth = drive(60.0, 100.0, true);
    let spec = bias_and_noise_spec(1e-2, 1e-4, 1e-3, 1e-4);
    let mut tuning = FilterTuning::from_imu_spec(&spec, 100.0, false).unwrap();
    tuning.use_carrier_phase = true;
    let mut rng = stream(33, 0);
    let imu = ImuModel::from_spec(&spec, 100.0, &mut rng).unwrap();
    let with_carrier = SimulationConfig {
        carrier_phase_std_m: 0.003,
        ..config()
    };
    let epochs = gnss_from(&truth, &gps_and_glonass(), &with_carrier, &mut rng);
    // Carrier minus code minus the noise-free parts leaves N·λ + noise: the
    // ambiguity of a GLONASS satellite is a whole number of its λ.
    let clean = SimulationConfig {
        pseudorange_std_m: 1e-9,
        carrier_phase_std_m: 1e-9,
        ..with_carrier.clone()
    };
    let exact = gnss_from(&truth, &gps_and_glonass(), &clean, &mut stream(33, 1));
    for m in exact[0]
        .measurements
        .iter()
        .filter(|m| m.system == GnssSystem::Glonass)
    {
        let lambda = g1_wavelength_m(nominal_channel(m.sat_id - 300).unwrap());
        let cycles = (m.carrier.unwrap().range_m - m.pseudorange_m) / lambda;
        assert!((cycles - cycles.round()).abs() < 1e-3, "{} cycles", cycles);
        assert!(
            (lambda - 0.190_293_672_798_365).abs() > 1e-4,
            "a GLONASS slot on GPS L1's wavelength"
        );
    }
    let (f, w) = readings(&truth, &imu, &mut rng);
    let data = imu_data(&truth, &f, &w);
    let sol =
        coupling::solution::<WITH_ISB, _>(&data, &epochs, &exact_initial(&truth), &tuning).unwrap();
    let carrier: Vec<_> = sol
        .measurements
        .iter()
        .filter(|r| r.kind == MeasurementKind::CarrierPhase)
        .collect();
    let glonass = carrier.iter().filter(|r| r.id > 300).count();
    println!("{} carrier changes, {glonass} of GLONASS", carrier.len());
    assert!(glonass > 100);
    // Every GLONASS change applied; a satellite that rises into the
    // selection starts a new arc (flagged, not applied) and nothing else
    // is refused.
    for r in &carrier {
        let fresh_arc = r.status == MeasurementStatus::CycleSlip && r.id < 300;
        assert!(
            r.status == MeasurementStatus::Accepted || fresh_arc,
            "{:.1} s satellite {}: {:?}",
            r.time_s,
            r.id,
            r.status
        );
    }
}
