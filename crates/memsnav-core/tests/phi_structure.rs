//! A figure docs/results/performance.md shows about the filter's structure,
//! counted from the code: the covariance products visit one term per
//! non-zero of Φ, and the page's floating-point count is built on how many
//! there are for 17 states (the record docs/data/phi_structure.json).

use memsnav_core::attitude::euler_to_dcm;
use memsnav_core::filter::input_noise::InputErrorNoise;
use memsnav_core::filter::{system_matrix, ProcessNoise, SystemInputs};
use memsnav_core::geodesy::{geodetic_to_ecef, Geodetic};
use nalgebra::{SMatrix, Vector3};

mod figures;
use figures::Figures;

/// Φ = I + FΔt over a generic state (no input on an axis, finite bias
/// correlation times) has no zero the structure does not force: its
/// non-zeros are the terms the sparse products list
/// (`propagation::Transition::columns_into`).
#[test]
fn phi_has_the_non_zeros_the_flop_count_uses() {
    let inputs = SystemInputs {
        c_b_e: euler_to_dcm(0.3, -0.2, 1.1),
        specific_force_b: Vector3::new(1.2, -0.4, -9.7),
        angular_rate_b: Vector3::new(0.05, -0.02, 0.3),
        position_ecef: geodetic_to_ecef(Geodetic::new(0.76, 0.025, 150.0)),
    };
    let noise = ProcessNoise {
        accel_white_psd: 1e-4,
        gyro_white_psd: 1e-8,
        accel_bias_psd: 1e-7,
        accel_bias_correlation_time_s: 100.0,
        gyro_bias_psd: 1e-11,
        gyro_bias_correlation_time_s: 200.0,
        clock_phase_psd: 0.01,
        clock_frequency_psd: 0.04,
        accel_scale_factor_psd: 0.0,
        gyro_scale_factor_psd: 0.0,
        range_bias_psd: 0.0,
        range_bias_correlation_time_s: 60.0,
        inter_system_bias_psd: 0.0,
        input_errors: InputErrorNoise::default(),
    };
    let phi = SMatrix::<f64, 17, 17>::identity() + system_matrix::<17>(&inputs, &noise) * 0.01;
    let non_zeros = phi.iter().filter(|&&x| x != 0.0).count();
    Figures::new("phi_structure")
        .add("non_zeros_17_states", non_zeros as f64, 0.0)
        .check_or_write();
}
