//! Calibration against analytic truths: exact recovery on noise-free data,
//! the Monte Carlo spread against the reported sigma and the Cramér-Rao
//! bound, the bias of the first-order shortcut and of plain LS with noisy
//! references, and the observability diagnostics.

use nalgebra::{DMatrix, DVector, Matrix3, SVector, Vector3};
use rand::Rng as _;
use rand_distr::StandardNormal;

use super::*;
use crate::random::{stream, Rng};
use crate::sensors::NoiseModel;

const G0: f64 = 9.80665;

fn gauss3(rng: &mut Rng) -> Vector3<f64> {
    Vector3::from_fn(|_, _| rng.sample(StandardNormal))
}

/// A calibration-table-like motion: specific force of gravity in random
/// attitudes plus accelerations, angular rates of a few tens of °/s.
fn motion(n: usize, rng: &mut Rng) -> (Vec<Vector3<f64>>, Vec<Vector3<f64>>) {
    let f = (0..n).map(|_| gauss3(rng) * 6.0).collect();
    let w = (0..n).map(|_| gauss3(rng) * 0.5).collect();
    (f, w)
}

/// Parameters ten times the paper's magnitudes (method §2), so that every
/// conversion term is visible above rounding.
fn accel_truth(rng: &mut Rng) -> AccelerometerModel {
    let mut m = Matrix3::from_fn(|_, _| rng.sample::<f64, _>(StandardNormal) * 0.1);
    m.fill_diagonal(0.0);
    AccelerometerModel {
        bias: gauss3(rng) * 0.1 * G0,
        scale_factor: gauss3(rng) * 1e-2,
        misalignment: m,
        nonlinearity: gauss3(rng) * 1e-3 / G0,
        noise: NoiseModel::default(),
    }
}

fn gyro_truth(rng: &mut Rng) -> GyroscopeModel {
    let mut m = Matrix3::from_fn(|_, _| rng.sample::<f64, _>(StandardNormal) * 0.1);
    m.fill_diagonal(0.0);
    GyroscopeModel {
        bias: gauss3(rng) * 0.1f64.to_radians(),
        scale_factor: gauss3(rng) * 1e-2,
        misalignment: m,
        g_sensitivity: Matrix3::from_fn(|_, _| {
            rng.sample::<f64, _>(StandardNormal) * 1e-2f64.to_radians() / G0
        }),
        noise: NoiseModel::default(),
    }
}

fn accel_measure(
    m: &AccelerometerModel,
    f: &[Vector3<f64>],
    sigma: f64,
    rng: &mut Rng,
) -> Vec<Vector3<f64>> {
    f.iter()
        .map(|f| m.output_with_input_noise(f, &(gauss3(rng) * sigma)))
        .collect()
}

fn gyro_measure(
    m: &GyroscopeModel,
    w: &[Vector3<f64>],
    f: &[Vector3<f64>],
    sigma: f64,
    rng: &mut Rng,
) -> Vec<Vector3<f64>> {
    w.iter()
        .zip(f)
        .map(|(w, f)| m.output_with_input_noise(w, f, &(gauss3(rng) * sigma)))
        .collect()
}

#[test]
fn noise_free_accelerometer_parameters_are_recovered_exactly() {
    let mut rng = stream(1, 0);
    let truth = accel_truth(&mut rng);
    let (f, _) = motion(400, &mut rng);
    let s = accel_measure(&truth, &f, 0.0, &mut rng);
    let cal = calibrate_accelerometer(&s, &f, &CalibrationOptions::default()).unwrap();
    let err = accelerometer_parameters(&cal.model) - accelerometer_parameters(&truth);
    let scale = accelerometer_parameters(&truth).abs();
    for (k, name) in accelerometer_parameter_names().iter().enumerate() {
        // Rounding of a 5-column regression of 400 rows: ~1e-11 of the
        // parameter's typical size (the omitted cross squares alone would
        // leave |M N Γ²| ≈ 4e-4 m/s² on the bias).
        let typical = if k >= 12 { 1e-5 } else { 1e-2 };
        assert!(
            err[k].abs() < 1e-9 * scale[k].max(typical),
            "{name}: {:e}",
            err[k]
        );
    }
    assert!(cal.residual_std.max() < 1e-11, "{}", cal.residual_std);
    assert!(cal.warnings.is_empty());
}

#[test]
fn noise_free_gyroscope_parameters_are_recovered_exactly() {
    let mut rng = stream(2, 0);
    let truth = gyro_truth(&mut rng);
    let (f, w) = motion(400, &mut rng);
    let s = gyro_measure(&truth, &w, &f, 0.0, &mut rng);
    let cal = calibrate_gyroscope(&s, &w, &f, &CalibrationOptions::default()).unwrap();
    let err = gyroscope_parameters(&cal.model) - gyroscope_parameters(&truth);
    let scale = gyroscope_parameters(&truth).abs();
    for (k, name) in gyroscope_parameter_names().iter().enumerate() {
        assert!(
            err[k].abs() < 1e-10 * scale[k].max(1e-5),
            "{name}: {:e}",
            err[k]
        );
    }
}

#[test]
fn conversion_jacobians_match_finite_differences() {
    let mut rng = stream(3, 0);
    let acc = accel_truth(&mut rng);
    let a = acc.output_matrix();
    let ab = a * acc.bias;
    let rows: [DVector<f64>; 3] = std::array::from_fn(|i| {
        DVector::from_vec(vec![
            -ab[i],
            a[(i, 0)],
            a[(i, 1)],
            a[(i, 2)],
            -a[(i, i)] * acc.nonlinearity[i],
        ])
    });
    check_jacobian(&rows, &accelerometer::tests_support::jacobian(&acc), |r| {
        accelerometer_parameters(&accelerometer::tests_support::model_from_rows(r))
            .as_slice()
            .to_vec()
    });
    let gyr = gyro_truth(&mut rng);
    let a = gyr.output_matrix();
    let ab = a * gyr.bias;
    let ak = a * gyr.g_sensitivity;
    let rows: [DVector<f64>; 3] = std::array::from_fn(|i| {
        DVector::from_vec(vec![
            -ab[i],
            a[(i, 0)],
            a[(i, 1)],
            a[(i, 2)],
            -ak[(i, 0)],
            -ak[(i, 1)],
            -ak[(i, 2)],
        ])
    });
    check_jacobian(&rows, &gyroscope::tests_support::jacobian(&gyr), |r| {
        gyroscope_parameters(&gyroscope::tests_support::model_from_rows(r))
            .as_slice()
            .to_vec()
    });
}

fn check_jacobian(
    rows: &[DVector<f64>; 3],
    jac: &DMatrix<f64>,
    f: impl Fn(&[DVector<f64>; 3]) -> Vec<f64>,
) {
    let p = rows[0].len();
    for i in 0..3 {
        for c in 0..p {
            let h = 1e-6;
            let mut plus = rows.clone();
            plus[i][c] += h;
            let mut minus = rows.clone();
            minus[i][c] -= h;
            let (fp, fm) = (f(&plus), f(&minus));
            for k in 0..fp.len() {
                let numeric = (fp[k] - fm[k]) / (2.0 * h);
                assert!(
                    (numeric - jac[(k, p * i + c)]).abs() < 1e-6 * (1.0 + numeric.abs()),
                    "param {k}, row {i}, coefficient {c}: {numeric} vs {}",
                    jac[(k, p * i + c)]
                );
            }
        }
    }
}

/// Monte Carlo over noise draws (fixed motion and truth): the spread of each
/// estimate matches its reported sigma and, LS being efficient for this
/// linear Gaussian model, the MSE matches the Cramér-Rao bound.
#[test]
fn spread_matches_reported_sigma_and_the_cramer_rao_bound() {
    let mut rng = stream(4, 0);
    let acc = accel_truth(&mut rng);
    let gyr = gyro_truth(&mut rng);
    let (f, w) = motion(300, &mut rng);
    let (sa, sg) = (0.05, 2e-3);
    let runs = 400;
    let truth_a = accelerometer_parameters(&acc);
    let truth_g = gyroscope_parameters(&gyr);
    let (mut mse_a, mut var_a) = (vec![0.0; 15], vec![0.0; 15]);
    let (mut mse_g, mut var_g) = (vec![0.0; 21], vec![0.0; 21]);
    let (mut crb_a, mut crb_g) = (vec![0.0; 15], vec![0.0; 21]);
    for r in 0..runs {
        let mut rng = stream(5, r);
        let s = accel_measure(&acc, &f, sa, &mut rng);
        let opts = CalibrationOptions {
            noise_std: Some(sa),
            ..Default::default()
        };
        let cal = calibrate_accelerometer(&s, &f, &opts).unwrap();
        let e = accelerometer_parameters(&cal.model) - truth_a;
        for k in 0..15 {
            mse_a[k] += e[k] * e[k] / runs as f64;
            var_a[k] += cal.covariance[(k, k)] / runs as f64;
            crb_a[k] += cal.crb.as_ref().unwrap()[(k, k)] / runs as f64;
        }
        let s = gyro_measure(&gyr, &w, &f, sg, &mut rng);
        let opts = CalibrationOptions {
            noise_std: Some(sg),
            ..Default::default()
        };
        let cal = calibrate_gyroscope(&s, &w, &f, &opts).unwrap();
        let e = gyroscope_parameters(&cal.model) - truth_g;
        for k in 0..21 {
            mse_g[k] += e[k] * e[k] / runs as f64;
            var_g[k] += cal.covariance[(k, k)] / runs as f64;
            crb_g[k] += cal.crb.as_ref().unwrap()[(k, k)] / runs as f64;
        }
    }
    // The MSE of 400 runs has a relative std of √(2/400) ≈ 7 %: ±25 % is 3.5σ.
    for (names, mse, var, crb) in [
        (accelerometer_parameter_names(), &mse_a, &var_a, &crb_a),
        (gyroscope_parameter_names(), &mse_g, &var_g, &crb_g),
    ] {
        for k in 0..names.len() {
            assert!(
                (mse[k] / var[k] - 1.0).abs() < 0.25,
                "{}: mse {:e} vs sigma² {:e}",
                names[k],
                mse[k],
                var[k]
            );
            assert!(
                (mse[k] / crb[k] - 1.0).abs() < 0.25,
                "{}: mse {:e} vs crb {:e}",
                names[k],
                mse[k],
                crb[k]
            );
        }
    }
}

/// The first-order shortcut (b ≈ −c₀, K ≈ −C) leaves a bias (D + M) b far
/// above the statistical error, which the exact conversion does not.
#[test]
fn first_order_shortcut_is_biased_beyond_the_statistical_error() {
    let mut rng = stream(6, 0);
    let acc = accel_truth(&mut rng);
    let (f, _) = motion(20_000, &mut rng);
    let s = accel_measure(&acc, &f, 0.03, &mut rng);
    let cal = calibrate_accelerometer(&s, &f, &CalibrationOptions::default()).unwrap();
    // First order: c₀ = −A b read as −b.
    let c0 = -(cal.model.output_matrix() * cal.model.bias);
    for i in 0..3 {
        let sigma = cal.std.bias[i];
        let exact_err = (cal.model.bias[i] - acc.bias[i]).abs();
        let shortcut_err = (-c0[i] - acc.bias[i]).abs();
        assert!(
            exact_err < 4.0 * sigma,
            "axis {i}: exact error {exact_err:e}, sigma {sigma:e}"
        );
        assert!(
            shortcut_err > 10.0 * sigma,
            "axis {i}: shortcut error {shortcut_err:e}, sigma {sigma:e}"
        );
    }
}

/// Noisy references bias plain LS towards zero (attenuation σ²/var); the
/// errors-in-variables estimator removes it.
#[test]
fn errors_in_variables_removes_the_attenuation_bias() {
    let mut rng = stream(7, 0);
    let gyr = gyro_truth(&mut rng);
    let acc = accel_truth(&mut rng);
    let n = 20_000;
    let (f, w) = motion(n, &mut rng);
    let (sw, sf) = (0.15, 1.5); // reference noise: 30 % of the motion's std
    let sg = gyro_measure(&gyr, &w, &f, 1e-3, &mut rng);
    let sa = accel_measure(&acc, &f, 0.01, &mut rng);
    let w_ref: Vec<_> = w.iter().map(|x| x + gauss3(&mut rng) * sw).collect();
    let f_ref: Vec<_> = f.iter().map(|x| x + gauss3(&mut rng) * sf).collect();
    let ls = calibrate_gyroscope(&sg, &w_ref, &f_ref, &CalibrationOptions::default()).unwrap();
    let eiv_opts = CalibrationOptions {
        method: Method::ErrorsInVariables,
        reference_noise_std: Some(sw),
        reference_specific_force_noise_std: Some(sf),
        ..Default::default()
    };
    let eiv = calibrate_gyroscope(&sg, &w_ref, &f_ref, &eiv_opts).unwrap();
    // Attenuation of the gain 1 − D: (1 − D) var/(var + σ²) ⇒ D pulled up by ≈ σ²/(0.25 + σ²).
    let expected = sw * sw / (0.25 + sw * sw);
    for i in 0..3 {
        let ls_err = ls.model.scale_factor[i] - gyr.scale_factor[i];
        let eiv_err = eiv.model.scale_factor[i] - gyr.scale_factor[i];
        assert!(
            (ls_err / expected - 1.0).abs() < 0.1,
            "LS bias {ls_err:e} vs {expected:e}"
        );
        assert!(
            eiv_err.abs() < 4.0 * eiv.std.scale_factor[i] && eiv_err.abs() < 0.05 * expected,
            "EIV error {eiv_err:e}"
        );
    }
    let ls = calibrate_accelerometer(&sa, &f_ref, &CalibrationOptions::default()).unwrap();
    let eiv_opts = CalibrationOptions {
        method: Method::ErrorsInVariables,
        reference_noise_std: Some(sf),
        ..Default::default()
    };
    let eiv = calibrate_accelerometer(&sa, &f_ref, &eiv_opts).unwrap();
    let e_ls = accelerometer_parameters(&ls.model) - accelerometer_parameters(&acc);
    let e_eiv = accelerometer_parameters(&eiv.model) - accelerometer_parameters(&acc);
    for k in [3, 4, 5, 12, 13, 14] {
        let sigma = eiv.covariance[(k, k)].sqrt();
        assert!(
            e_eiv[k].abs() < 4.0 * sigma,
            "EIV param {k}: {:e} vs sigma {sigma:e}",
            e_eiv[k]
        );
        if k < 6 {
            // Scale factors: attenuation far beyond the noise (the poorly
            // determined nonlinearity hides its own bias in its spread).
            assert!(
                e_ls[k].abs() > 10.0 * sigma,
                "LS param {k}: {:e} vs sigma {sigma:e}",
                e_ls[k]
            );
        }
    }
}

#[test]
fn an_axis_that_never_moves_is_named() {
    let mut rng = stream(8, 0);
    let (f, mut w) = motion(200, &mut rng);
    for x in &mut w {
        x.y = 0.0; // no pitch rate at all
    }
    let s = gyro_measure(&gyro_truth(&mut rng), &w, &f, 1e-3, &mut rng);
    match calibrate_gyroscope(&s, &w, &f, &CalibrationOptions::default()) {
        Err(Error::Unobservable {
            axis, parameter, ..
        }) => {
            assert_eq!((axis.as_str(), parameter.as_str()), ("q", "scale_factor"));
        }
        other => panic!("expected Unobservable, got {other:?}"),
    }
    // Only two distinct values of Γ^w: its square is a combination of 1 and Γ^w.
    let (mut f, _) = motion(200, &mut rng);
    for (k, x) in f.iter_mut().enumerate() {
        x.z = if k % 2 == 0 { -G0 } else { -G0 + 1.0 };
    }
    let s = accel_measure(&accel_truth(&mut rng), &f, 1e-3, &mut rng);
    match calibrate_accelerometer(&s, &f, &CalibrationOptions::default()) {
        Err(Error::Unobservable {
            axis, parameter, ..
        }) => {
            assert_eq!(axis, "w");
            assert!(
                parameter == "nonlinearity" || parameter == "scale_factor",
                "{parameter}"
            );
        }
        other => panic!("expected Unobservable, got {other:?}"),
    }
}

#[test]
fn bad_inputs_name_the_argument() {
    let mut rng = stream(9, 0);
    let (f, w) = motion(10, &mut rng);
    let opts = CalibrationOptions::default();
    let e = calibrate_accelerometer(&f[..9], &f, &opts).unwrap_err();
    assert!(
        e.to_string().starts_with("reference_specific_force:"),
        "{e}"
    );
    let e = calibrate_accelerometer(&f[..5], &f[..5], &opts).unwrap_err();
    assert!(e.to_string().starts_with("measured:"), "{e}");
    let mut bad = f.clone();
    bad[3].x = f64::NAN;
    let e = calibrate_gyroscope(&f, &w, &bad, &opts).unwrap_err();
    assert!(
        e.to_string().starts_with("reference_specific_force:"),
        "{e}"
    );
    let e = calibrate_gyroscope(
        &w,
        &w,
        &f,
        &CalibrationOptions {
            noise_std: Some(0.0),
            ..opts
        },
    )
    .unwrap_err();
    assert!(e.to_string().starts_with("noise_std:"), "{e}");
    let e = calibrate_accelerometer(
        &f,
        &f,
        &CalibrationOptions {
            method: Method::ErrorsInVariables,
            ..opts
        },
    )
    .unwrap_err();
    assert!(e.to_string().starts_with("reference_noise_std:"), "{e}");
}

/// One row solved densely on the whole n × p matrix: LS by SVD, EIV by a
/// dense QR (c = R⁻¹ (I − R⁻ᵀ C R⁻¹)⁻¹ Qᵀ y); coefficients, their covariance
/// (σ̂² (GᵀG)⁻¹, or the EIV sandwich) and σ̂.
fn dense_solve(
    g: &DMatrix<f64>,
    y: &DVector<f64>,
    noise: Option<&DMatrix<f64>>,
) -> (DVector<f64>, DMatrix<f64>, f64) {
    let (n, p) = g.shape();
    let qr = g.clone().qr();
    let r_inv = qr.r().try_inverse().unwrap();
    let (c, m) = match noise {
        None => (
            g.clone().svd(true, true).solve(y, 0.0).unwrap(),
            r_inv.clone(),
        ),
        Some(noise) => {
            let inv = (DMatrix::identity(p, p) - r_inv.transpose() * noise * &r_inv)
                .try_inverse()
                .unwrap();
            let m = &r_inv * inv;
            (&m * (qr.q().transpose() * y), m)
        }
    };
    let var = (y - g * &c).norm_squared() / (n - p) as f64;
    (c, &m * m.transpose() * var, var.sqrt())
}

fn block_diag(blocks: &[DMatrix<f64>]) -> DMatrix<f64> {
    let p = blocks[0].nrows();
    let mut out = DMatrix::zeros(3 * p, 3 * p);
    for (i, b) in blocks.iter().enumerate() {
        out.view_mut((p * i, p * i), (p, p)).copy_from(b);
    }
    out
}

/// The parameters, their covariance and the residual std of a calibration
/// against those of the dense solve, to 1e-10 relative.
fn assert_matches_dense<const N: usize>(
    what: &str,
    estimate: &SVector<f64, N>,
    dense: &SVector<f64, N>,
    covariance: &DMatrix<f64>,
    dense_covariance: &DMatrix<f64>,
    residual_std: &Vector3<f64>,
    dense_residual_std: &Vector3<f64>,
) {
    for k in 0..N {
        let scale = dense[k].abs().max(dense_covariance[(k, k)].sqrt());
        assert!(
            (estimate[k] - dense[k]).abs() <= 1e-10 * scale,
            "{what} parameter {k}: {:e} vs {:e}",
            estimate[k],
            dense[k]
        );
        let (v, d) = (covariance[(k, k)], dense_covariance[(k, k)]);
        assert!(
            (v / d - 1.0).abs() < 1e-10,
            "{what} variance {k}: {v:e} vs {d:e}"
        );
    }
    for i in 0..3 {
        let (s, d) = (residual_std[i], dense_residual_std[i]);
        assert!(
            (s / d - 1.0).abs() < 1e-10,
            "{what} residual {i}: {s:e} vs {d:e}"
        );
    }
}

/// The factored path (one pass, compressed solves, the cross-square
/// refinement by superposition) against the textbook procedure written
/// here on the dense n × p matrices: a straightforward fixed-point
/// iteration of full dense solves for the accelerometer, one dense solve
/// per row for the gyroscope, both estimators, noisy references, several
/// blocks of rows plus a partial one.
#[test]
fn factored_calibration_equals_a_dense_solve() {
    let mut rng = stream(12, 0);
    let acc = accel_truth(&mut rng);
    let gyr = gyro_truth(&mut rng);
    let n = 64 * 40 + 17;
    let (f, w) = motion(n, &mut rng);
    let (sf, sw) = (0.5, 0.02);
    let sa = accel_measure(&acc, &f, 0.01, &mut rng);
    let sg = gyro_measure(&gyr, &w, &f, 1e-3, &mut rng);
    let f_ref: Vec<_> = f.iter().map(|x| x + gauss3(&mut rng) * sf).collect();
    let w_ref: Vec<_> = w.iter().map(|x| x + gauss3(&mut rng) * sw).collect();

    for eiv in [false, true] {
        // Accelerometer: G_i = [1, Γ, Γ_i² − s2], y_i = S_i + Σ_{j≠i} A_ij N_j (Γ_j² − s2).
        let s2 = if eiv { sf * sf } else { 0.0 };
        let sq = |k: usize, j: usize| f_ref[k][j] * f_ref[k][j] - s2;
        let gs: Vec<DMatrix<f64>> = (0..3)
            .map(|i| {
                DMatrix::from_fn(n, 5, |k, c| match c {
                    0 => 1.0,
                    1..=3 => f_ref[k][c - 1],
                    _ => sq(k, i),
                })
            })
            .collect();
        let noise: Vec<Option<DMatrix<f64>>> = (0..3)
            .map(|i| {
                eiv.then(|| {
                    let mut c = DMatrix::zeros(5, 5);
                    for j in 1..4 {
                        c[(j, j)] = n as f64 * s2;
                    }
                    let sum_g: f64 = f_ref.iter().map(|v| v[i]).sum();
                    let sum_g2: f64 = (0..n).map(|k| sq(k, i)).sum();
                    c[(4, 4)] = 4.0 * s2 * sum_g2 + 2.0 * n as f64 * s2 * s2;
                    c[(1 + i, 4)] = 2.0 * s2 * sum_g;
                    c[(4, 1 + i)] = c[(1 + i, 4)];
                    c
                })
            })
            .collect();
        let mut an = Matrix3::zeros();
        let mut dense = Vec::new();
        for _ in 0..30 {
            dense = (0..3)
                .map(|i| {
                    let y = DVector::from_fn(n, |k, _| {
                        sa[k][i]
                            + (0..3)
                                .filter(|&j| j != i)
                                .map(|j| an[(i, j)] * sq(k, j))
                                .sum::<f64>()
                    });
                    dense_solve(&gs[i], &y, noise[i].as_ref())
                })
                .collect();
            let rows: [DVector<f64>; 3] = std::array::from_fn(|i| dense[i].0.clone());
            let m = accelerometer::tests_support::model_from_rows(&rows);
            an = m.output_matrix() * Matrix3::from_diagonal(&m.nonlinearity);
        }
        let rows: [DVector<f64>; 3] = std::array::from_fn(|i| dense[i].0.clone());
        let model = accelerometer::tests_support::model_from_rows(&rows);
        let jac = accelerometer::tests_support::jacobian(&model);
        let blocks: Vec<DMatrix<f64>> = dense.iter().map(|d| d.1.clone()).collect();
        let options = CalibrationOptions {
            method: if eiv {
                Method::ErrorsInVariables
            } else {
                Method::LeastSquares
            },
            reference_noise_std: Some(sf),
            ..Default::default()
        };
        let cal = calibrate_accelerometer(&sa, &f_ref, &options).unwrap();
        assert_matches_dense(
            &format!("accelerometer (EIV {eiv})"),
            &accelerometer_parameters(&cal.model),
            &accelerometer_parameters(&model),
            &cal.covariance,
            &(&jac * block_diag(&blocks) * jac.transpose()),
            &cal.residual_std,
            &Vector3::from_fn(|i, _| dense[i].2),
        );

        // Gyroscope: G = [1, Ω, Γ] for every row, y_i = S_i.
        let g = DMatrix::from_fn(n, 7, |k, c| match c {
            0 => 1.0,
            1..=3 => w_ref[k][c - 1],
            _ => f_ref[k][c - 4],
        });
        let noise = eiv.then(|| {
            let (so2, sf2) = (n as f64 * sw * sw, n as f64 * sf * sf);
            DMatrix::from_diagonal(&DVector::from_vec(vec![0.0, so2, so2, so2, sf2, sf2, sf2]))
        });
        let dense: Vec<_> = (0..3)
            .map(|i| dense_solve(&g, &DVector::from_fn(n, |k, _| sg[k][i]), noise.as_ref()))
            .collect();
        let rows: [DVector<f64>; 3] = std::array::from_fn(|i| dense[i].0.clone());
        let model = gyroscope::tests_support::model_from_rows(&rows);
        let jac = gyroscope::tests_support::jacobian(&model);
        let blocks: Vec<DMatrix<f64>> = dense.iter().map(|d| d.1.clone()).collect();
        let options = CalibrationOptions {
            method: if eiv {
                Method::ErrorsInVariables
            } else {
                Method::LeastSquares
            },
            reference_noise_std: Some(sw),
            reference_specific_force_noise_std: Some(sf),
            ..Default::default()
        };
        let cal = calibrate_gyroscope(&sg, &w_ref, &f_ref, &options).unwrap();
        assert_matches_dense(
            &format!("gyroscope (EIV {eiv})"),
            &gyroscope_parameters(&cal.model),
            &gyroscope_parameters(&model),
            &cal.covariance,
            &(&jac * block_diag(&blocks) * jac.transpose()),
            &cal.residual_std,
            &Vector3::from_fn(|i, _| dense[i].2),
        );
        // Condition number of the equilibrated gyroscope regressors, by SVD.
        let mut gs = g.clone();
        for mut col in gs.column_iter_mut() {
            let norm = col.norm();
            col /= norm;
        }
        let sv = gs.singular_values();
        assert!((cal.condition_number[0] / (sv.max() / sv.min()) - 1.0).abs() < 1e-10);
    }
}

// The determinable rule (`determinable.rs`) end to end.

/// A gyro at rest in 40 orientations (Ω = 0): the bias and the
/// g-sensitivity are determined, the scale factors and misalignments not.
#[test]
fn a_static_gyro_gives_bias_and_g_sensitivity_only() {
    let mut rng = stream(3, 0);
    let truth = GyroscopeModel {
        bias: Vector3::new(0.01, -0.02, 0.005),
        scale_factor: Vector3::new(0.01, 0.02, -0.01),
        misalignment: Matrix3::new(0.0, 0.01, 0.0, 0.0, 0.0, 0.02, 0.0, -0.01, 0.0),
        g_sensitivity: Matrix3::from_fn(|i, j| 2e-4 * (1.0 + i as f64 - j as f64)),
        noise: NoiseModel::default(),
    };
    let mut w = Vec::new();
    let mut f = Vec::new();
    let mut s = Vec::new();
    for _ in 0..40 {
        let up = gauss3(&mut rng).normalize() * 9.8;
        for _ in 0..50 {
            let nu = gauss3(&mut rng) * 1e-4;
            w.push(Vector3::zeros());
            f.push(up);
            s.push(truth.output_with_input_noise(&Vector3::zeros(), &up, &nu));
        }
    }
    let all = calibrate_gyroscope(&s, &w, &f, &CalibrationOptions::default());
    assert!(all.unwrap_err().to_string().contains("scale_factor"));
    let options = CalibrationOptions {
        estimate: Estimate::Determinable,
        ..Default::default()
    };
    let cal = calibrate_gyroscope(&s, &w, &f, &options).unwrap();
    let held: Vec<&str> = cal.held.iter().map(|h| h.0.as_str()).collect();
    assert_eq!(held.len(), 9, "{held:?}");
    assert!(held
        .iter()
        .all(|h| h.starts_with("scale_factor") || h.starts_with("misalignment")));
    assert!(cal.held[0].1.contains("never varies"), "{:?}", cal.held);
    // Held at the ideal sensor's values, with zero variance.
    assert_eq!(cal.model.scale_factor, Vector3::zeros());
    assert_eq!(cal.std.misalignment, Matrix3::zeros());
    // At rest S = A(−b − KΓ): with A held at I the estimates are A b and
    // A K, the truth seen through the unmodelled A (a ~2 % effect).
    let a = truth.output_matrix();
    assert!((cal.model.bias - a * truth.bias).amax() < 5.0 * cal.std.bias.amax());
    assert!(
        (cal.model.g_sensitivity - a * truth.g_sensitivity).amax()
            < 5.0 * cal.std.g_sensitivity.amax()
    );
    assert!(cal.std.g_sensitivity.amax() > 0.0);
}

/// The how-to's case: a land vehicle hardly varies the vertical
/// specific force. Estimating everything warns (conditioning and
/// sigma); the determinable rule holds the vertical scale factor and
/// the bias of that axis comes out well determined.
#[test]
fn a_weak_vertical_axis_warns_and_is_held_when_asked() {
    let mut rng = stream(4, 0);
    let truth = AccelerometerModel {
        bias: Vector3::new(0.1, 0.2, 0.3),
        scale_factor: Vector3::new(1e-3, 0.0, 2e-3),
        misalignment: Matrix3::zeros(),
        nonlinearity: Vector3::zeros(),
        noise: NoiseModel::default(),
    };
    let f: Vec<Vector3<f64>> = (0..2000)
        .map(|_| {
            let v = gauss3(&mut rng);
            Vector3::new(3.0 * v.x, 3.0 * v.y, -9.8 + 0.01 * v.z)
        })
        .collect();
    let s: Vec<Vector3<f64>> = f
        .iter()
        .map(|g| truth.output_with_input_noise(g, &(gauss3(&mut rng) * 0.03)))
        .collect();
    let all = calibrate_accelerometer(&s, &f, &CalibrationOptions::default()).unwrap();
    assert!(all.held.is_empty());
    assert!(
        all.warnings
            .iter()
            .any(|w| w.contains("w axis") && w.contains("condition")),
        "{:?}",
        all.warnings
    );
    assert!(
        all.warnings.iter().any(|w| w.contains("bias_w: sigma")),
        "{:?}",
        all.warnings
    );
    let options = CalibrationOptions {
        estimate: Estimate::Determinable,
        ..Default::default()
    };
    let cal = calibrate_accelerometer(&s, &f, &options).unwrap();
    let held: Vec<&str> = cal.held.iter().map(|h| h.0.as_str()).collect();
    assert!(held.contains(&"scale_factor_w"), "{:?}", cal.held);
    assert!(cal.std.bias.z < 0.05 && cal.std.bias.z < all.std.bias.z / 10.0);
    // Holding D_w = 0 against a true 2e-3 moves the bias by D_w g ≈ 0.02 m/s².
    assert!((cal.model.bias.z - truth.bias.z).abs() < 0.03);
}
