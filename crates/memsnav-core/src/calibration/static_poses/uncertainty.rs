//! The covariance of the calibration and its Cramér-Rao bound (module docs
//! of [`super`], "Uncertainty"): the chain z = [θ_a (12), ĉ (12), T (9)]
//! whose covariance is Φ diag(Σ_a, Σ_c, Σ_T) Φᵀ, with Φ the Jacobian of
//! the chain (central differences), carried to the 36 physical parameters
//! [accelerometer (15), gyroscope (21)] through the Jacobian of that map.
//! The bound runs the same chain with each stage's inverse Fisher
//! information for white noise of the level measured at the initial rest.

use nalgebra::{DMatrix, DVector, Matrix3, Vector3};

use super::accelerometer::AccelerometerStage;
use super::gyroscope::{gyroscope_model, GyroscopeStage};
use super::magnitude::{self, parameter_name};
use super::rests::{self, offsets_from, offsets_to};
use super::rotation::{t_from_vector, t_to_vector, Rotations, Segment};
use super::session::{GyroData, Session};
use super::solver::{self, central_jacobian, Fit};
use crate::calibration::determinable::physical_size;
use crate::calibration::{accelerometer_parameters, gyroscope_parameters};
use crate::{Error, Result};

/// The fitted stages and the data the chain differentiates through.
pub struct Chain<'a> {
    pub session: &'a Session<'a>,
    pub accelerometer: &'a AccelerometerStage,
    /// The pose means and turns under the fitted accelerometer model.
    pub gyro_data: &'a GyroData,
    /// The turns of `gyro_data` in the rotation fit.
    pub fit_segments: &'a [Segment],
    pub gyroscope: &'a GyroscopeStage,
    /// White noise variance per sample and axis at the initial rest, in
    /// nominal units squared: accelerometer, gyroscope ([`white_variance`]).
    pub white: [Vector3<f64>; 2],
}

/// The covariance of the 36 physical parameters and its Cramér-Rao bound,
/// both 36 × 36 in the order of the accelerometer then the gyroscope
/// parameter names. Held entries of θ_a and C have zero variance and are
/// not propagated; a held T neither varies nor depends on the other
/// stages. Errors when the rest or rotation fit fails near the solution
/// (`accel`, `gyro`) or T is singular there (`gyro`).
pub fn covariance_and_bound(chain: &Chain<'_>) -> Result<(DMatrix<f64>, DMatrix<f64>)> {
    let (accel, gyro) = (chain.accelerometer, chain.gyroscope);
    let theta_a = &accel.theta;
    let c_hat = offsets_to(&gyro.rest_fit.offsets);
    let h_a = accelerometer_steps(theta_a);
    let h1 = rest_offsets_jacobian(chain.session, &gyro.free_columns, theta_a, &h_a)?;
    let mut phi = DMatrix::identity(33, 33);
    phi.view_mut((12, 0), (12, 12)).copy_from(&h1);
    let mut blocks = DMatrix::zeros(33, 33);
    blocks
        .view_mut((0, 0), (12, 12))
        .copy_from(&accel.covariance);
    blocks
        .view_mut((12, 12), (12, 12))
        .copy_from(&gyro.rest_fit.covariance);
    let mut bound_blocks = accelerometer_and_rest_bounds(chain);
    if let Some(f) = &gyro.t_fit {
        let (phi_a, phi_c) = rotation_sensitivity(chain, f, &c_hat, &h_a, &h1)?;
        phi.view_mut((24, 0), (9, 12)).copy_from(&phi_a);
        phi.view_mut((24, 12), (9, 12)).copy_from(&phi_c);
        blocks.view_mut((24, 24), (9, 9)).copy_from(&f.covariance);
        if let Some(bound) = turn_bound(chain, f) {
            bound_blocks.view_mut((24, 24), (9, 9)).copy_from(&bound);
        }
    } else {
        // T held: it neither varies nor depends on the other stages.
        phi.view_mut((24, 24), (9, 9)).fill(0.0);
    }
    // Held entries of θ_a and C have zero variance: no propagation either.
    let sigma_z = &phi * blocks * phi.transpose();
    let bound_z = &phi * bound_blocks * phi.transpose();
    let jac = physical_jacobian(theta_a, &c_hat, &gyro.t, &h_a)?;
    Ok((
        &jac * sigma_z * jac.transpose(),
        &jac * bound_z * jac.transpose(),
    ))
}

/// Central-difference steps of θ_a: a millionth of each entry's size plus
/// its physical size.
fn accelerometer_steps(theta_a: &DVector<f64>) -> Vec<f64> {
    (0..magnitude::PARAMETERS)
        .map(|i| 1e-6 * (theta_a[i].abs() + physical_size("accelerometer", &parameter_name(i))))
        .collect()
}

/// H₁ = ∂ĉ/∂θ_a (12 × 12): the rest fit of the columns `free_columns`
/// redone with the pose means of the accelerometer model of θ_a, by
/// central differences with steps `h_a`.
fn rest_offsets_jacobian(
    session: &Session<'_>,
    free_columns: &[usize],
    theta_a: &DVector<f64>,
    h_a: &[f64],
) -> Result<DMatrix<f64>> {
    let c_of = |theta: &DVector<f64>| -> Option<DVector<f64>> {
        let d = session.gyro_data(&magnitude::model(theta))?;
        let (s, f) = session.rest_poses(&d);
        let fit = rests::fit(&s, &f, free_columns).ok()?;
        Some(offsets_to(&fit.offsets))
    };
    central_jacobian(c_of, theta_a, h_a)
        .ok_or_else(|| Error::invalid("accel", "the rest fit fails near the solution"))
}

/// The bound blocks of θ_a and ĉ in the 33 × 33 layout of z (T's block
/// zero): for θ_a the inverse of Jᵀ W J with, per pose k, W_k = n_k / dᵀ
/// diag(σ_a²) d, d = A⁻ᵀ Γ̄_k/‖Γ̄_k‖ (the variance of the pose's magnitude);
/// for ĉ [`rests::bound`] with σ_g².
fn accelerometer_and_rest_bounds(chain: &Chain<'_>) -> DMatrix<f64> {
    let (session, accel) = (chain.session, chain.accelerometer);
    let (poses, fit_poses) = (session.poses, &session.fit_poses);
    let [white_accel, white_gyro] = chain.white;
    let mut bound_blocks = DMatrix::zeros(33, 33);
    let a_inv = accel
        .model
        .output_matrix()
        .try_inverse()
        .unwrap_or_else(Matrix3::zeros);
    let weights: Vec<f64> = fit_poses
        .iter()
        .map(|&k| {
            let d = a_inv.transpose() * chain.gyro_data.force_means[k].normalize();
            poses[k].len() as f64 / d.component_mul(&d).dot(&white_accel)
        })
        .collect();
    let fisher = weighted_gram(&accel.fit.jacobian, &weights);
    let bound = fisher.try_inverse().unwrap_or_else(|| DMatrix::zeros(0, 0));
    for (a, &i) in accel.free.iter().enumerate() {
        for (b, &j) in accel.free.iter().enumerate() {
            bound_blocks[(i, j)] = bound.get((a, b)).copied().unwrap_or(0.0);
        }
    }
    let counts: Vec<f64> = fit_poses.iter().map(|&k| poses[k].len() as f64).collect();
    let (_, rest_force) = session.rest_poses(chain.gyro_data);
    bound_blocks
        .view_mut((12, 12), (12, 12))
        .copy_from(&rests::bound(
            &rest_force,
            &counts,
            &chain.gyroscope.free_columns,
            &white_gyro,
        ));
    bound_blocks
}

/// T's rows of Φ (9 × 12 each): with T̂ the minimiser of the rotation fit
/// `f` given (θ_a, ĉ), δT = −(JᵀJ)⁻¹Jᵀ(J_a δθ_a + J_c δĉ), and ĉ itself
/// moving with θ_a through H₁ (`h1`): returns (G_a + G_c H₁, G_c) with
/// G = −(JᵀJ)⁻¹Jᵀ J_·, the residual Jacobians J_a (turns and gravity
/// directions redone under θ_a, steps `h_a`) and J_c by central
/// differences.
fn rotation_sensitivity(
    chain: &Chain<'_>,
    f: &Fit,
    c_hat: &DVector<f64>,
    h_a: &[f64],
    h1: &DMatrix<f64>,
) -> Result<(DMatrix<f64>, DMatrix<f64>)> {
    let session = chain.session;
    let theta_a = &chain.accelerometer.theta;
    let t = chain.gyroscope.t;
    let t_vec = t_to_vector(&t);
    let residuals_of = |theta: &DVector<f64>, c: &DVector<f64>| -> Option<DVector<f64>> {
        let segments: Vec<Segment> = if theta == theta_a {
            chain.fit_segments.to_vec()
        } else {
            session.fit_turns(&session.gyro_data(&magnitude::model(theta))?.segments)
        };
        solver::Residuals::residuals(
            &Rotations {
                segments: &segments,
                offsets: offsets_from(c),
            },
            &t_vec,
        )
    };
    let j_c = central_jacobian(
        |c| residuals_of(theta_a, c),
        c_hat,
        &[scale_c_of(c_hat, &t); 12],
    );
    let j_a = central_jacobian(|th| residuals_of(th, c_hat), theta_a, h_a);
    let (Some(j_c), Some(j_a)) = (j_c, j_a) else {
        return Err(Error::invalid(
            "gyro",
            "the rotation fit fails near the solution",
        ));
    };
    // −(JᵀJ)⁻¹Jᵀ = −(covariance/σ̂²) Jᵀ.
    let gain = -(&f.unit_covariance * f.jacobian.transpose());
    let g_c = &gain * j_c;
    let g_a = &gain * j_a;
    Ok((&g_a + &g_c * h1, g_c))
}

/// The bound block of T (9 × 9): the inverse of Jᵀ W J of the rotation fit
/// `f`, both direction components of a turn weighted by the inverse of its
/// direction error's variance, σ_ω² Σ Δt² (the gyro noise integrated over
/// its intervals, σ_ω² the mean of diag(T diag(σ_g²) Tᵀ)) plus σ_a²/g²
/// (1/n_k + 1/n_{k+1}) (the two poses' gravity directions); None when
/// singular.
fn turn_bound(chain: &Chain<'_>, f: &Fit) -> Option<DMatrix<f64>> {
    let [white_accel, white_gyro] = chain.white;
    let (poses, g) = (chain.session.poses, chain.session.gravity);
    let t = chain.gyroscope.t;
    // A turn's direction error: the gyro noise integrated over its
    // m intervals (σ_ω² Σ Δt² per axis) plus the two poses' gravity
    // directions (σ_a²/g² (1/n_k + 1/n_{k+1})).
    let rate_var = (t * Matrix3::from_diagonal(&white_gyro) * t.transpose()).trace() / 3.0;
    let direction_var = white_accel.mean() / (g * g);
    let weights: Vec<f64> = chain
        .fit_segments
        .iter()
        .flat_map(|s| {
            let gyro_part: f64 = s.increments.iter().map(|(_, _, dt)| dt * dt).sum();
            let v = rate_var * gyro_part
                + direction_var
                    * (1.0 / poses[s.from].len() as f64 + 1.0 / poses[s.from + 1].len() as f64);
            [1.0 / v, 1.0 / v]
        })
        .collect();
    weighted_gram(&f.jacobian, &weights).try_inverse()
}

/// ∂(physical parameters)/∂z (36 × 33) at z = [θ_a, ĉ, T] by central
/// differences: the accelerometer parameters of θ_a's model and the
/// gyroscope parameters of [`gyroscope_model`] (steps `h_a`, then a
/// millionth of the offsets' and of T's size).
fn physical_jacobian(
    theta_a: &DVector<f64>,
    c_hat: &DVector<f64>,
    t: &Matrix3<f64>,
    h_a: &[f64],
) -> Result<DMatrix<f64>> {
    let z = {
        let mut z = DVector::zeros(33);
        z.rows_mut(0, 12).copy_from(theta_a);
        z.rows_mut(12, 12).copy_from(c_hat);
        z.rows_mut(24, 9).copy_from(&t_to_vector(t));
        z
    };
    let physical = |z: &DVector<f64>| -> Option<DVector<f64>> {
        let a = accelerometer_parameters(&magnitude::model(&z.rows(0, 12).into_owned()));
        let g = gyroscope_parameters(&gyroscope_model(
            &t_from_vector(&z.rows(24, 9).into_owned()),
            &offsets_from(&z.rows(12, 12).into_owned()),
        )?);
        Some(DVector::from_iterator(
            36,
            a.iter().chain(g.iter()).copied(),
        ))
    };
    let mut h_z = h_a.to_vec();
    h_z.extend([scale_c_of(c_hat, t); 12]);
    h_z.extend([1e-6 * t.amax(); 9]);
    central_jacobian(physical, &z, &h_z)
        .ok_or_else(|| Error::invalid("gyro", "the fitted T = A⁻¹ is singular"))
}

/// Half the variance of first differences per axis: the white-noise
/// variance of a still sensor, free of slow drift.
pub fn white_variance(samples: &[Vector3<f64>]) -> Vector3<f64> {
    let n = samples.len().saturating_sub(1).max(1) as f64;
    samples
        .windows(2)
        .map(|w| (w[1] - w[0]).component_mul(&(w[1] - w[0])))
        .sum::<Vector3<f64>>()
        / (2.0 * n)
}

/// Jᵀ diag(w) J.
fn weighted_gram(jacobian: &DMatrix<f64>, weights: &[f64]) -> DMatrix<f64> {
    let mut weighted = jacobian.clone();
    for (k, mut row) in weighted.row_iter_mut().enumerate() {
        row *= weights[k];
    }
    jacobian.transpose() * weighted
}

/// Central-difference step of the offsets: a millionth of their size.
fn scale_c_of(c: &DVector<f64>, t: &Matrix3<f64>) -> f64 {
    1e-6 * (c.amax() + 1e-3 / t.amax())
}
