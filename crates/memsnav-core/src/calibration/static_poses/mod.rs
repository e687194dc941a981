//! Multi-position ("no turntable") calibration of an IMU from static poses
//! (Tedaldi, Pretto and Menegatti, ICRA 2014; the multi-position idea of
//! Syed et al., Meas. Sci. Technol. 18, 2007, which the paper cites), in
//! the sensor models of method §2.
//!
//! 1. The raw readings become nominal readings s = scale ⊙ (raw − offset)
//!    (the nominal scale and offset per count; 1 and 0 for readings already
//!    near SI). The models describe these nominal readings, so their scale
//!    factor and bias are the corrections to the nominal values.
//! 2. [`StaticDetector`] finds the initial rest and the poses.
//! 3. The accelerometer from the gravity magnitude ([`magnitude`]):
//!    b, D, the three misalignments below the diagonal (the body frame is the
//!    accelerometer's: x along u, y in the u-v plane) and, when the poses
//!    determine it, N.
//! 4. The gyroscope's offsets c₀ + CΓ from the rests ([`rests`]): its bias
//!    and, when the poses determine it, its g-sensitivity.
//! 5. The gyroscope's T = A⁻¹ (scale factors and all six misalignments,
//!    relative to that body frame) from the rotations between poses against
//!    the change of the measured gravity direction ([`rotation`]).
//!
//! ## Uncertainty
//!
//! Each stage's covariance is σ̂² (JᵀJ)⁻¹ of its own residuals (pose
//! magnitudes; rest means per axis; turn directions), and the later stages
//! inherit the earlier ones' errors to first order: with ĉ = c(θ_a) + noise
//! and T̂ the minimiser given (θ_a, ĉ), δT = −(JᵀJ)⁻¹Jᵀ(J_a δθ_a + J_c δĉ) +
//! noise, so the covariance of z = [θ_a, ĉ, T] is Φ diag(Σ_a, Σ_c, Σ_T) Φᵀ
//! with Φ the Jacobian of that chain (central differences). The physical
//! parameters (b_a, D_a, M_a, N_a; b_g, D_g, M_g, K_g) are functions of z:
//! their 36 × 36 covariance follows through the Jacobian of that map.
//!
//! The Cramér-Rao bound runs the same chain with each stage's inverse
//! Fisher information for white noise of the level measured at the initial
//! rest (half the variance of first differences): pose magnitudes with
//! variance dᵀ diag(σ_a²) d / n_k, rest means σ_g,i²/n_k, turn directions
//! σ_ω² Σ Δt² + σ_a²/g² (1/n_k + 1/n_{k+1}). Where the covariance is well
//! above the bound, the session's errors are not white: hand tremor,
//! settling, the Earth's rate at rest, bias drift.
//!
//! ## Hold-out
//!
//! `holdout_every = h` leaves poses h−1, 2h−1, … (never the initial rest)
//! out of the accelerometer and rest fits, and every turn into or out of
//! them out of the rotation fit; their errors are reported apart.

pub mod magnitude;
pub mod rests;
pub mod rotation;
pub mod solver;

use nalgebra::{DMatrix, DVector, Matrix3, Vector3};

use super::determinable::{
    conditioning_warning, degrees_of_freedom_warning, physical_size, uncertainty_warnings,
    worst_uncertain, Estimate, UNDETERMINED_CONDITION,
};
use super::static_detector::{Pose, StaticDetection, StaticDetector};
use super::{
    accelerometer_parameter_names, accelerometer_parameters, accelerometer_std_model,
    gyroscope_parameter_names, gyroscope_parameters, gyroscope_std_model,
};
use crate::ins::increments_from_samples;
use crate::sensors::{AccelerometerModel, GyroscopeModel, NoiseModel};
use crate::{validate, Error, Result};
use rotation::{t_from_vector, t_to_vector, Offsets, Rotations, Segment};
use solver::{central_jacobian, Fit};

/// Nominal scale and offset of the raw readings: s = scale ⊙ (raw − offset).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Nominal {
    /// Accelerometer (m/s²) per count.
    pub accel_scale: Vector3<f64>,
    /// Accelerometer reading at zero input, counts.
    pub accel_offset: Vector3<f64>,
    /// Gyroscope (rad/s) per count.
    pub gyro_scale: Vector3<f64>,
    /// Gyroscope reading at zero input, counts.
    pub gyro_offset: Vector3<f64>,
}

impl Default for Nominal {
    /// Readings already in SI: scale 1, offset 0.
    fn default() -> Self {
        Self {
            accel_scale: Vector3::repeat(1.0),
            accel_offset: Vector3::zeros(),
            gyro_scale: Vector3::repeat(1.0),
            gyro_offset: Vector3::zeros(),
        }
    }
}

impl Nominal {
    fn validate(&self) -> Result<()> {
        for (name, v) in [
            ("accel_scale", &self.accel_scale),
            ("gyro_scale", &self.gyro_scale),
        ] {
            validate::finite_vectors(name, std::slice::from_ref(v))?;
            if v.iter().any(|x| *x == 0.0) {
                return Err(Error::invalid(name, "a scale per count must not be zero"));
            }
        }
        validate::finite_vectors("accel_offset", std::slice::from_ref(&self.accel_offset))?;
        validate::finite_vectors("gyro_offset", std::slice::from_ref(&self.gyro_offset))
    }

    /// The nominal accelerometer reading of a raw one.
    pub fn accel(&self, raw: &Vector3<f64>) -> Vector3<f64> {
        self.accel_scale.component_mul(&(raw - self.accel_offset))
    }

    /// The nominal gyroscope reading of a raw one.
    pub fn gyro(&self, raw: &Vector3<f64>) -> Vector3<f64> {
        self.gyro_scale.component_mul(&(raw - self.gyro_offset))
    }
}

/// Settings of [`calibrate_static`].
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct StaticCalibrationOptions {
    /// Local gravity magnitude, m/s² (required: 9.78-9.83 on the Earth's
    /// surface; use a gravity model at the site, e.g. [`crate::geodesy`]).
    pub gravity_m_s2: f64,
    pub nominal: Nominal,
    pub detector: StaticDetector,
    /// [`Estimate::Determinable`]: N and K only when the poses determine
    /// them, T only when there are turns enough; [`Estimate::All`]: every
    /// parameter, an error when the data cannot.
    pub estimate: Estimate,
    /// Leave every h-th pose out of the fits (module docs); None: use all.
    pub holdout_every: Option<usize>,
}

/// A pose and its gravity-magnitude error before (nominal readings) and
/// after the calibration, m/s².
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct PoseCheck {
    pub pose: Pose,
    pub held_out: bool,
    pub magnitude_error_before: f64,
    pub magnitude_error_after: f64,
}

/// A turn between poses `from` and `from + 1` and the angle between the
/// carried and the measured gravity direction, rad, before (nominal
/// readings, no offsets) and after the calibration.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct TurnCheck {
    pub from: usize,
    pub held_out: bool,
    pub angle_error_before: f64,
    pub angle_error_after: f64,
}

/// The result of [`calibrate_static`].
#[derive(Debug, Clone)]
pub struct StaticCalibration {
    /// The models of the nominal readings (SI), method §2.
    pub accelerometer: AccelerometerModel,
    pub gyroscope: GyroscopeModel,
    /// One-sigma values in the models' layout (zero where held or fixed).
    pub accelerometer_std: AccelerometerModel,
    pub gyroscope_std: GyroscopeModel,
    /// Covariance of [accelerometer parameters (15), gyroscope parameters
    /// (21)] in the order of [`accelerometer_parameter_names`] then
    /// [`gyroscope_parameter_names`].
    pub covariance: DMatrix<f64>,
    /// Cramér-Rao bound of the same parameters for white sensor noise of
    /// the level measured at the initial rest (module docs): the floor the
    /// covariance would reach if drift, tremor and the Earth's rate were
    /// absent.
    pub crb: DMatrix<f64>,
    /// White noise variance per sample and axis at the initial rest, in
    /// nominal units squared: accelerometer, gyroscope.
    pub white_noise_variance: [Vector3<f64>; 2],
    pub nominal: Nominal,
    pub gravity_m_s2: f64,
    pub detection: StaticDetection,
    pub poses: Vec<PoseCheck>,
    pub turns: Vec<TurnCheck>,
    /// Parameters not estimated, "accelerometer misalignment_uv" style,
    /// with the reason.
    pub held: Vec<(String, String)>,
    pub warnings: Vec<String>,
    /// RMS residual of the magnitude fit, m/s².
    pub accelerometer_residual_std: f64,
    /// RMS residual of the rest fit per gyro axis, rad/s.
    pub rest_residual_std: Vector3<f64>,
    /// RMS residual of the rotation fit per direction component, rad.
    pub turn_residual_std: f64,
    /// Condition numbers of the equilibrated magnitude, rest and rotation
    /// problems.
    pub condition_number: [f64; 3],
}

/// Specific force (m/s²) and angular rate (rad/s) per sample.
pub type CorrectedSeries = (Vec<Vector3<f64>>, Vec<Vector3<f64>>);

impl StaticCalibration {
    /// SI specific force and angular rate of raw readings (see [`correct`]).
    pub fn correct(
        &self,
        accel: &[Vector3<f64>],
        gyro: &[Vector3<f64>],
    ) -> Result<CorrectedSeries> {
        correct(
            &self.nominal,
            &self.accelerometer,
            &self.gyroscope,
            accel,
            gyro,
        )
    }
}

/// SI specific force Γ and angular rate Ω of raw readings: the nominal
/// readings through the exact inverses of eq. 2 and eq. 3
/// ([`AccelerometerModel::correct`], then [`GyroscopeModel::correct`] with
/// that Γ for the g-sensitivity).
pub fn correct(
    nominal: &Nominal,
    accelerometer: &AccelerometerModel,
    gyroscope: &GyroscopeModel,
    accel: &[Vector3<f64>],
    gyro: &[Vector3<f64>],
) -> Result<CorrectedSeries> {
    nominal.validate()?;
    accelerometer.validate()?;
    gyroscope.validate()?;
    validate::finite_vectors("accel", accel)?;
    validate::finite_vectors("gyro", gyro)?;
    validate::same_length("gyro", gyro.len(), "accel", accel.len())?;
    let mut f = Vec::with_capacity(accel.len());
    let mut w = Vec::with_capacity(accel.len());
    for (k, (a, g)) in accel.iter().zip(gyro).enumerate() {
        let fk = accelerometer
            .correct(&nominal.accel(a))
            .map_err(|e| Error::invalid("accel", format!("row {k}: {e}")))?;
        w.push(gyroscope.correct(&nominal.gyro(g), &fk)?);
        f.push(fk);
    }
    Ok((f, w))
}

/// Mean of samples `pose.start..pose.end`.
fn mean(samples: &[Vector3<f64>], pose: &Pose) -> Vector3<f64> {
    samples[pose.start..pose.end].iter().sum::<Vector3<f64>>() / pose.len() as f64
}

/// Everything the gyroscope stages need from the accelerometer model.
struct GyroData {
    /// Pose means of the nominal gyro readings and of the corrected
    /// specific force.
    gyro_means: Vec<Vector3<f64>>,
    force_means: Vec<Vector3<f64>>,
    /// One segment per consecutive pair of poses.
    segments: Vec<Segment>,
}

fn gyro_data(
    time: &[f64],
    accel_nominal: &[Vector3<f64>],
    gyro_nominal: &[Vector3<f64>],
    poses: &[Pose],
    accel_model: &AccelerometerModel,
) -> Option<GyroData> {
    let force_means: Vec<Vector3<f64>> = poses
        .iter()
        .map(|p| accel_model.correct(&mean(accel_nominal, p)).ok())
        .collect::<Option<_>>()?;
    let gyro_means = poses.iter().map(|p| mean(gyro_nominal, p)).collect();
    let mut segments = Vec::with_capacity(poses.len().saturating_sub(1));
    for (k, pair) in poses.windows(2).enumerate() {
        // From the last sample of pose k to the first of pose k + 1.
        let (first, last) = (pair[0].end - 1, pair[1].start);
        let force: Vec<Vector3<f64>> = accel_nominal[first..=last]
            .iter()
            .map(|s| accel_model.correct(s).ok())
            .collect::<Option<_>>()?;
        let increments =
            increments_from_samples(&time[first..=last], &force, &gyro_nominal[first..=last])
                .ok()?
                .into_iter()
                .zip(time[first..=last].windows(2))
                .map(|(inc, t)| (inc.delta_angle_b, inc.delta_velocity_b, t[1] - t[0]))
                .collect();
        segments.push(Segment {
            from: k,
            increments,
            up_from: force_means[k].normalize(),
            up_to: force_means[k + 1].normalize(),
        });
    }
    Some(GyroData {
        gyro_means,
        force_means,
        segments,
    })
}

/// The gyroscope model of T and the offsets: A = T⁻¹, b = −T c₀, K = −T C.
fn gyroscope_model(t: &Matrix3<f64>, offsets: &Offsets) -> Option<GyroscopeModel> {
    let a = t.try_inverse()?;
    let mut misalignment = -a;
    misalignment.fill_diagonal(0.0);
    Some(GyroscopeModel {
        bias: -(t * offsets.c0),
        scale_factor: Vector3::from_fn(|i, _| 1.0 - a[(i, i)]),
        misalignment,
        g_sensitivity: -(t * offsets.c),
        noise: NoiseModel::default(),
    })
}

fn offsets_from(c: &DVector<f64>) -> Offsets {
    Offsets {
        c0: Vector3::new(c[0], c[1], c[2]),
        c: Matrix3::from_row_slice(&c.as_slice()[3..12]),
    }
}

fn offsets_to(o: &Offsets) -> DVector<f64> {
    let mut v = DVector::zeros(12);
    v.rows_mut(0, 3).copy_from(&o.c0);
    for i in 0..3 {
        for l in 0..3 {
            v[rests::c_index(i, l)] = o.c[(i, l)];
        }
    }
    v
}

/// Root mean square of the entries selected by `keep`.
pub fn rms(values: impl Iterator<Item = (f64, bool)>, keep: bool) -> f64 {
    let (sum, n) = values
        .filter(|(_, k)| *k == keep)
        .fold((0.0, 0usize), |(s, n), (v, _)| (s + v * v, n + 1));
    if n == 0 {
        f64::NAN
    } else {
        (sum / n as f64).sqrt()
    }
}

/// Calibrates an IMU from a multi-position session (module docs): `time`
/// (s, increasing), raw `accel` and `gyro` readings (counts or any unit,
/// see [`Nominal`]). Errors name the argument (`time`, `accel`, `gyro`,
/// `gravity`, `holdout_every`, the detector's settings, `poses` when too
/// few were found) or, under [`Estimate::All`], the parameter the data do
/// not determine.
pub fn calibrate_static(
    time: &[f64],
    accel: &[Vector3<f64>],
    gyro: &[Vector3<f64>],
    options: &StaticCalibrationOptions,
) -> Result<StaticCalibration> {
    validate::positive("gravity", options.gravity_m_s2)?;
    options.nominal.validate()?;
    validate::same_length("gyro", gyro.len(), "time", time.len())?;
    validate::finite_vectors("gyro", gyro)?;
    if let Some(h) = options.holdout_every {
        if h < 2 {
            return Err(Error::invalid(
                "holdout_every",
                format!("must be at least 2 (every h-th pose is held out), got {h}"),
            ));
        }
    }
    let nominal = &options.nominal;
    let accel_nominal: Vec<Vector3<f64>> = accel.iter().map(|a| nominal.accel(a)).collect();
    let gyro_nominal: Vec<Vector3<f64>> = gyro.iter().map(|g| nominal.gyro(g)).collect();
    let detection = options
        .detector
        .detect(time, &accel_nominal, &gyro_nominal)?;
    let poses = &detection.poses;
    let held_out: Vec<bool> = (0..poses.len())
        .map(|k| options.holdout_every.is_some_and(|h| k % h == h - 1))
        .collect();
    let fit_poses: Vec<usize> = (0..poses.len()).filter(|&k| !held_out[k]).collect();
    let g = options.gravity_m_s2;
    let determinable = options.estimate == Estimate::Determinable;
    let mut warnings = Vec::new();
    let mut held = Vec::new();

    // 3. The accelerometer.
    let accel_means: Vec<Vector3<f64>> = poses.iter().map(|p| mean(&accel_nominal, p)).collect();
    let fit_means: Vec<Vector3<f64>> = fit_poses.iter().map(|&k| accel_means[k]).collect();
    if fit_means.len() <= magnitude::NONLINEARITY {
        return Err(Error::invalid(
            "poses",
            format!(
                "the accelerometer needs at least {} static poses in the fit (9 parameters plus \
                 one), the detector found {} ({} held out)",
                magnitude::NONLINEARITY + 1,
                poses.len(),
                poses.len() - fit_means.len()
            ),
        ));
    }
    let linear: Vec<usize> = (0..magnitude::NONLINEARITY).collect();
    let start = magnitude::first_guess(&fit_means, g);
    let linear_fit = magnitude::fit(&fit_means, g, &start, &linear)?;
    let mut theta_a = start.clone();
    for (k, &i) in linear.iter().enumerate() {
        theta_a[i] = linear_fit.x[k];
    }
    let mut free_a: Vec<usize> = (0..magnitude::PARAMETERS).collect();
    let names_a = accelerometer_parameter_names();
    // θ_a index → name in the 15-parameter layout.
    let theta_name = |i: usize| -> String {
        match i {
            0..=5 => names_a[i].clone(),
            6..=8 => {
                let (r, c) = magnitude::LOWER[i - 6];
                let axes = super::ACCELEROMETER_AXES;
                format!("misalignment_{}{}", axes[r], axes[c])
            }
            _ => names_a[i + 3].clone(),
        }
    };
    let accel_fit: Fit = loop {
        let fit = if free_a.len() == linear.len() {
            Ok(linear_fit.clone())
        } else {
            magnitude::fit(&fit_means, g, &theta_a, &free_a)
        };
        let fit = match (fit, determinable) {
            (Ok(f), _) => f,
            (Err(e), false) => return Err(e),
            (Err(_), true) => {
                // The nonlinearity made the fit fail: hold all of it.
                for i in magnitude::NONLINEARITY..magnitude::PARAMETERS {
                    held.push((
                        format!("accelerometer {}", theta_name(i)),
                        "the fit with it does not converge".to_string(),
                    ));
                }
                free_a.truncate(magnitude::NONLINEARITY);
                continue;
            }
        };
        let std: Vec<f64> = (0..free_a.len())
            .map(|k| fit.covariance[(k, k)].max(0.0).sqrt())
            .collect();
        let names: Vec<String> = free_a.iter().map(|&i| theta_name(i)).collect();
        let scale: Vec<f64> = names
            .iter()
            .map(|n| physical_size("accelerometer", n))
            .collect();
        // Rule 2 then rule 3, for the nonlinearity only (b, D, M are the
        // magnitude's minimum).
        let nonlinear = |k: usize| free_a[k] >= magnitude::NONLINEARITY;
        let drop = if fit.condition_number > UNDETERMINED_CONDITION && nonlinear(fit.weakest) {
            Some((
                fit.weakest,
                format!(
                    "the poses do not separate it from the others (condition number {:.2e})",
                    fit.condition_number
                ),
            ))
        } else {
            let fixed: Vec<bool> = (0..free_a.len()).map(|k| !nonlinear(k)).collect();
            worst_uncertain(&names, &std, &scale, &fixed).map(|k| {
                (
                    k,
                    format!(
                        "its sigma {:.3e} would exceed its physical size {:.3e}",
                        std[k], scale[k]
                    ),
                )
            })
        };
        match drop {
            Some((k, why)) if determinable => {
                held.push((format!("accelerometer {}", names[k]), why));
                theta_a[free_a[k]] = 0.0;
                free_a.remove(k);
            }
            _ => {
                for (k, &i) in free_a.iter().enumerate() {
                    theta_a[i] = fit.x[k];
                }
                break fit;
            }
        }
    };
    let accel_model = magnitude::model(&theta_a);
    let mut sigma_a = DMatrix::zeros(magnitude::PARAMETERS, magnitude::PARAMETERS);
    for (a, &i) in free_a.iter().enumerate() {
        for (b, &j) in free_a.iter().enumerate() {
            sigma_a[(i, j)] = accel_fit.covariance[(a, b)];
        }
    }
    conditioning_warning(
        "accelerometer (gravity magnitude)",
        accel_fit.condition_number,
        &theta_name(free_a[accel_fit.weakest]),
        &mut warnings,
    );
    degrees_of_freedom_warning(
        "accelerometer (static poses)",
        fit_means.len(),
        free_a.len(),
        &mut warnings,
    );

    // 4-5. The gyroscope.
    let data =
        gyro_data(time, &accel_nominal, &gyro_nominal, poses, &accel_model).ok_or_else(|| {
            Error::invalid("accel", "a reading is beyond the range of the fitted model")
        })?;
    let fit_segments: Vec<Segment> = data
        .segments
        .iter()
        .filter(|s| !held_out[s.from] && !held_out[s.from + 1])
        .cloned()
        .collect();
    let rest_poses = |d: &GyroData| -> (Vec<Vector3<f64>>, Vec<Vector3<f64>>) {
        (
            fit_poses.iter().map(|&k| d.gyro_means[k]).collect(),
            fit_poses.iter().map(|&k| d.force_means[k]).collect(),
        )
    };
    let (rest_gyro, rest_force) = rest_poses(&data);
    let names_g = gyroscope_parameter_names();
    let mut free_columns: Vec<usize> = vec![0, 1, 2];
    // The rest fit needs more poses than its columns.
    while rest_gyro.len() <= 1 + free_columns.len() && !free_columns.is_empty() {
        if !determinable {
            return Err(Error::invalid(
                "poses",
                format!(
                    "the gyroscope's g-sensitivity needs at least 5 poses in the fit, got {}",
                    rest_gyro.len()
                ),
            ));
        }
        let l = free_columns.pop().expect("non-empty");
        hold_column(&mut held, &names_g, l, "too few poses");
    }
    let t_start = Matrix3::identity();
    let (rest_fit, t_fit, t) = loop {
        let rest_fit = rests::fit(&rest_gyro, &rest_force, &free_columns)?;
        if rest_fit.condition_number > UNDETERMINED_CONDITION && rest_fit.weakest_column > 0 {
            let l = rest_fit.weakest_column - 1;
            if !determinable {
                return Err(Error::Unobservable {
                    axis: super::ACCELEROMETER_AXES[l].to_string(),
                    parameter: "g_sensitivity".into(),
                    reason: "the poses do not vary the specific force on this axis".into(),
                });
            }
            free_columns.retain(|&c| c != l);
            hold_column(
                &mut held,
                &names_g,
                l,
                "the poses do not vary this specific-force axis",
            );
            continue;
        }
        let problem = Rotations {
            segments: &fit_segments,
            offsets: rest_fit.offsets,
        };
        let turns_enough = 2 * fit_segments.len() > 9;
        let t_fit = if turns_enough {
            let start = t_to_vector(&problem.scan(&t_start));
            match solver::minimize(&problem, start, 2 * fit_segments.len() - 9, "gyroscope") {
                Ok(f) if f.condition_number <= UNDETERMINED_CONDITION || !determinable => Some(f),
                Ok(_) | Err(_) if determinable => None,
                Ok(f) => Some(f),
                Err(e) => return Err(e),
            }
        } else if determinable {
            None
        } else {
            return Err(Error::invalid(
                "poses",
                format!(
                    "the gyroscope's scale factors and misalignments need at least 5 turns between \
                     poses in the fit, got {}",
                    fit_segments.len()
                ),
            ));
        };
        let t = t_fit
            .as_ref()
            .map(|f| t_from_vector(&f.x))
            .unwrap_or(t_start);
        // Rule 3 for the g-sensitivity columns: σ(K) = σ(T C) ≈ from T σ(C).
        let worst = free_columns
            .iter()
            .map(|&l| {
                let sd = (0..3)
                    .map(|r| {
                        (0..3)
                            .map(|i| {
                                t[(r, i)].powi(2)
                                    * rest_fit.covariance
                                        [(rests::c_index(i, l), rests::c_index(i, l))]
                            })
                            .sum::<f64>()
                            .sqrt()
                    })
                    .fold(0.0, f64::max);
                (l, sd)
            })
            .filter(|(_, sd)| *sd > physical_size("gyroscope", "g_sensitivity_pu"))
            .max_by(|a, b| a.1.total_cmp(&b.1));
        match worst {
            Some((l, sd)) if determinable => {
                free_columns.retain(|&c| c != l);
                hold_column(
                    &mut held,
                    &names_g,
                    l,
                    &format!("its sigma {sd:.3e} would exceed its physical size 1e-3"),
                );
            }
            _ => break (rest_fit, t_fit, t),
        }
    };
    if t_fit.is_none() {
        for name in names_g.iter().skip(3).take(9) {
            held.push((
                format!("gyroscope {name}"),
                "too few or too similar turns between poses: held at the nominal scale".into(),
            ));
        }
    }
    let gyro_model = gyroscope_model(&t, &rest_fit.offsets)
        .ok_or_else(|| Error::invalid("gyro", "the fitted T = A⁻¹ is singular"))?;

    // White noise per sample and axis, from the initial rest: half the
    // variance of first differences (immune to slow drift).
    let white_accel = white_variance(&accel_nominal[poses[0].start..poses[0].end]);
    let white_gyro = white_variance(&gyro_nominal[poses[0].start..poses[0].end]);

    // Uncertainty (module docs).
    let c_hat = offsets_to(&rest_fit.offsets);
    let (covariance, crb) = {
        let free_c = free_columns.clone();
        let c_of = |theta: &DVector<f64>| -> Option<DVector<f64>> {
            let d = gyro_data(
                time,
                &accel_nominal,
                &gyro_nominal,
                poses,
                &magnitude::model(theta),
            )?;
            let (s, f) = rest_poses(&d);
            let fit = rests::fit(&s, &f, &free_c).ok()?;
            Some(offsets_to(&fit.offsets))
        };
        let h_a: Vec<f64> = (0..magnitude::PARAMETERS)
            .map(|i| 1e-6 * (theta_a[i].abs() + physical_size("accelerometer", &theta_name(i))))
            .collect();
        let h1 = central_jacobian(c_of, &theta_a, &h_a)
            .ok_or_else(|| Error::invalid("accel", "the rest fit fails near the solution"))?;
        let mut phi = DMatrix::identity(33, 33);
        phi.view_mut((12, 0), (12, 12)).copy_from(&h1);
        let mut blocks = DMatrix::zeros(33, 33);
        blocks.view_mut((0, 0), (12, 12)).copy_from(&sigma_a);
        blocks
            .view_mut((12, 12), (12, 12))
            .copy_from(&rest_fit.covariance);
        // The Cramér-Rao bound: the same chain with each stage's inverse
        // Fisher information for white sensor noise (module docs).
        let mut bound_blocks = DMatrix::zeros(33, 33);
        {
            let a_inv = accel_model
                .output_matrix()
                .try_inverse()
                .unwrap_or_else(Matrix3::zeros);
            let weights: Vec<f64> = fit_poses
                .iter()
                .map(|&k| {
                    let d = a_inv.transpose() * data.force_means[k].normalize();
                    poses[k].len() as f64 / d.component_mul(&d).dot(&white_accel)
                })
                .collect();
            let fisher = weighted_gram(&accel_fit.jacobian, &weights);
            let bound = fisher.try_inverse().unwrap_or_else(|| DMatrix::zeros(0, 0));
            for (a, &i) in free_a.iter().enumerate() {
                for (b, &j) in free_a.iter().enumerate() {
                    bound_blocks[(i, j)] = bound.get((a, b)).copied().unwrap_or(0.0);
                }
            }
            let counts: Vec<f64> = fit_poses.iter().map(|&k| poses[k].len() as f64).collect();
            bound_blocks
                .view_mut((12, 12), (12, 12))
                .copy_from(&rests::bound(
                    &rest_force,
                    &counts,
                    &free_columns,
                    &white_gyro,
                ));
        }
        if let Some(f) = &t_fit {
            let t_vec = t_to_vector(&t);
            let residuals_of = |theta: &DVector<f64>, c: &DVector<f64>| -> Option<DVector<f64>> {
                let segments: Vec<Segment> = if theta == &theta_a {
                    fit_segments.clone()
                } else {
                    gyro_data(
                        time,
                        &accel_nominal,
                        &gyro_nominal,
                        poses,
                        &magnitude::model(theta),
                    )?
                    .segments
                    .into_iter()
                    .filter(|s| !held_out[s.from] && !held_out[s.from + 1])
                    .collect()
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
                |c| residuals_of(&theta_a, c),
                &c_hat,
                &[scale_c_of(&c_hat, &t); 12],
            );
            let j_a = central_jacobian(|th| residuals_of(th, &c_hat), &theta_a, &h_a);
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
            phi.view_mut((24, 0), (9, 12))
                .copy_from(&(&g_a + &g_c * &h1));
            phi.view_mut((24, 12), (9, 12)).copy_from(&g_c);
            blocks.view_mut((24, 24), (9, 9)).copy_from(&f.covariance);
            // A turn's direction error: the gyro noise integrated over its
            // m intervals (σ_ω² Σ Δt² per axis) plus the two poses' gravity
            // directions (σ_a²/g² (1/n_k + 1/n_{k+1})).
            let rate_var = (t * Matrix3::from_diagonal(&white_gyro) * t.transpose()).trace() / 3.0;
            let direction_var = white_accel.mean() / (g * g);
            let weights: Vec<f64> = fit_segments
                .iter()
                .flat_map(|s| {
                    let gyro_part: f64 = s.increments.iter().map(|(_, _, dt)| dt * dt).sum();
                    let v = rate_var * gyro_part
                        + direction_var
                            * (1.0 / poses[s.from].len() as f64
                                + 1.0 / poses[s.from + 1].len() as f64);
                    [1.0 / v, 1.0 / v]
                })
                .collect();
            if let Some(bound) = weighted_gram(&f.jacobian, &weights).try_inverse() {
                bound_blocks.view_mut((24, 24), (9, 9)).copy_from(&bound);
            }
        } else {
            // T held: it neither varies nor depends on the other stages.
            phi.view_mut((24, 24), (9, 9)).fill(0.0);
        }
        // Held entries of θ_a and C have zero variance: no propagation either.
        let sigma_z = &phi * blocks * phi.transpose();
        let bound_z = &phi * bound_blocks * phi.transpose();
        let z = {
            let mut z = DVector::zeros(33);
            z.rows_mut(0, 12).copy_from(&theta_a);
            z.rows_mut(12, 12).copy_from(&c_hat);
            z.rows_mut(24, 9).copy_from(&t_to_vector(&t));
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
        let mut h_z = h_a.clone();
        h_z.extend([scale_c_of(&c_hat, &t); 12]);
        h_z.extend([1e-6 * t.amax(); 9]);
        let jac = central_jacobian(physical, &z, &h_z)
            .ok_or_else(|| Error::invalid("gyro", "the fitted T = A⁻¹ is singular"))?;
        (
            &jac * sigma_z * jac.transpose(),
            &jac * bound_z * jac.transpose(),
        )
    };
    let accelerometer_std =
        accelerometer_std_model(&covariance.view((0, 0), (15, 15)).into_owned());
    let gyroscope_std = gyroscope_std_model(&covariance.view((15, 15), (21, 21)).into_owned());

    // Checks before and after.
    let nominal_offsets = Offsets {
        c0: Vector3::zeros(),
        c: Matrix3::zeros(),
    };
    let pose_checks: Vec<PoseCheck> = poses
        .iter()
        .enumerate()
        .map(|(k, p)| PoseCheck {
            pose: *p,
            held_out: held_out[k],
            magnitude_error_before: accel_means[k].norm() - g,
            magnitude_error_after: data.force_means[k].norm() - g,
        })
        .collect();
    let turns: Vec<TurnCheck> = data
        .segments
        .iter()
        .map(|s| {
            let before = Segment {
                up_from: accel_means[s.from].normalize(),
                up_to: accel_means[s.from + 1].normalize(),
                ..s.clone()
            };
            TurnCheck {
                from: s.from,
                held_out: held_out[s.from] || held_out[s.from + 1],
                angle_error_before: before.angle_error(&Matrix3::identity(), &nominal_offsets),
                angle_error_after: s.angle_error(&t, &rest_fit.offsets),
            }
        })
        .collect();

    // Warnings (module docs of `determinable`).
    let std_all: Vec<f64> = covariance
        .diagonal()
        .iter()
        .map(|v| v.max(0.0).sqrt())
        .collect();
    let is_held =
        |prefix: &str, name: &str| held.iter().any(|(h, _)| h == &format!("{prefix} {name}"));
    let held_a: Vec<bool> = names_a
        .iter()
        .enumerate()
        .map(|(k, n)| is_held("accelerometer", n) || std_all[k] == 0.0)
        .collect();
    let held_g: Vec<bool> = names_g
        .iter()
        .enumerate()
        .map(|(k, n)| is_held("gyroscope", n) || std_all[15 + k] == 0.0)
        .collect();
    let scale_a: Vec<f64> = names_a
        .iter()
        .map(|n| physical_size("accelerometer", n))
        .collect();
    let scale_g: Vec<f64> = names_g
        .iter()
        .map(|n| physical_size("gyroscope", n))
        .collect();
    uncertainty_warnings(
        "accelerometer",
        &names_a,
        &std_all[..15],
        &scale_a,
        &held_a,
        &mut warnings,
    );
    uncertainty_warnings(
        "gyroscope",
        &names_g,
        &std_all[15..],
        &scale_g,
        &held_g,
        &mut warnings,
    );
    conditioning_warning(
        "gyroscope (rests)",
        rest_fit.condition_number,
        [
            "bias",
            "g-sensitivity to u",
            "g-sensitivity to v",
            "g-sensitivity to w",
        ][rest_fit.weakest_column],
        &mut warnings,
    );
    degrees_of_freedom_warning(
        "gyroscope (rests)",
        rest_gyro.len(),
        1 + free_columns.len(),
        &mut warnings,
    );
    if let Some(f) = &t_fit {
        conditioning_warning(
            "gyroscope (turns)",
            f.condition_number,
            &format!("T entry {}", f.weakest),
            &mut warnings,
        );
        degrees_of_freedom_warning(
            "gyroscope (turns)",
            2 * fit_segments.len(),
            9,
            &mut warnings,
        );
    }
    for (sensor, d, scale) in [
        (
            "accelerometer",
            accel_model.scale_factor,
            nominal.accel_scale,
        ),
        ("gyroscope", gyro_model.scale_factor, nominal.gyro_scale),
    ] {
        for i in 0..3 {
            if d[i].abs() > 0.2 {
                warnings.push(format!(
                    "{sensor} axis {i}: the fitted scale per count, {:.6e}, differs from the \
                     nominal by {:+.0} % (scale factor {:.3}, far outside a MEMS's range): \
                     pass it as the nominal scale",
                    scale[i] / (1.0 - d[i]),
                    100.0 * d[i] / (1.0 - d[i]),
                    d[i]
                ));
            }
        }
    }
    Ok(StaticCalibration {
        accelerometer: accel_model,
        gyroscope: gyro_model,
        accelerometer_std,
        gyroscope_std,
        covariance,
        crb,
        white_noise_variance: [white_accel, white_gyro],
        nominal: *nominal,
        gravity_m_s2: g,
        detection: detection.clone(),
        poses: pose_checks,
        turns,
        held,
        warnings,
        accelerometer_residual_std: accel_fit.residual_std,
        rest_residual_std: rest_fit.residual_std,
        turn_residual_std: t_fit.as_ref().map(|f| f.residual_std).unwrap_or(f64::NAN),
        condition_number: [
            accel_fit.condition_number,
            rest_fit.condition_number,
            t_fit
                .as_ref()
                .map(|f| f.condition_number)
                .unwrap_or(f64::NAN),
        ],
    })
}

/// Half the variance of first differences per axis: the white-noise
/// variance of a still sensor, free of slow drift.
fn white_variance(samples: &[Vector3<f64>]) -> Vector3<f64> {
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

/// Records the g-sensitivity column `l` (all three gyro rows) as held.
fn hold_column(held: &mut Vec<(String, String)>, names_g: &[String], l: usize, why: &str) {
    for i in 0..3 {
        held.push((
            format!("gyroscope {}", names_g[12 + 3 * i + l]),
            why.to_string(),
        ));
    }
}

#[cfg(test)]
mod tests;
