//! Multi-position ("no turntable") calibration of an IMU from static poses
//! (Tedaldi, Pretto and Menegatti, ICRA 2014; the multi-position idea of
//! Syed et al., Meas. Sci. Technol. 18, 2007, which the paper cites), in
//! the sensor models of method §2.
//!
//! 1. The raw readings become nominal readings s = scale ⊙ (raw − offset)
//!    (the nominal scale and offset per count; 1 and 0 for readings already
//!    near SI; [`Nominal`]). The models describe these nominal readings, so
//!    their scale factor and bias are the corrections to the nominal values.
//! 2. [`StaticDetector`] finds the initial rest and the poses (`session.rs`
//!    holds both, with the hold-out below).
//! 3. The accelerometer from the gravity magnitude ([`magnitude`]; the
//!    stage with its rule for N in `accelerometer.rs`):
//!    b, D, the three misalignments below the diagonal (the body frame is the
//!    accelerometer's: x along u, y in the u-v plane) and, when the poses
//!    determine it, N.
//! 4. The gyroscope's offsets c₀ + CΓ from the rests ([`rests`]): its bias
//!    and, when the poses determine it, its g-sensitivity.
//! 5. The gyroscope's T = A⁻¹ (scale factors and all six misalignments,
//!    relative to that body frame) from the rotations between poses against
//!    the change of the measured gravity direction ([`rotation`]). Steps 4
//!    and 5 are fitted in turn, with their rules, in `gyroscope.rs`.
//!
//! Then the uncertainty (`uncertainty.rs`), the checks before and after
//! (`checks.rs`) and the warnings (`warnings.rs`).
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
//! `holdout_every = h` leaves poses h−1, 2h−1, … and `holdout_from_s = t`
//! every pose that ends at or after t (never the initial rest) out of the
//! accelerometer and rest fits, and every turn into or out of them out of
//! the rotation fit; their errors are reported apart. With t the middle
//! of the log the fit sees only its first half.
//!
//! ## Model selection
//!
//! Under [`Estimate::Determinable`] the second-order terms (the
//! accelerometer's nonlinearity N, the gyroscope's g-sensitivity K) are
//! chosen by the small-sample AICc among the combinations the
//! determinability rules allow ([`crate::calibration::information`]); each
//! stage's candidates with their AICc are in
//! [`StaticCalibration::model_selection`].

mod accelerometer;
mod checks;
mod gyroscope;
pub mod magnitude;
mod nominal;
pub mod rests;
pub mod rotation;
mod session;
pub mod solver;
mod uncertainty;
mod warnings;

pub use checks::{PoseCheck, TurnCheck};
pub use nominal::Nominal;
pub use session::Holdout;

use nalgebra::{DMatrix, Vector3};

use super::determinable::Estimate;
use super::information::ModelSelection;
use super::static_detector::{StaticDetection, StaticDetector};
use super::{accelerometer_std_model, gyroscope_std_model};
use crate::sensors::{AccelerometerModel, GyroscopeModel};
use crate::{validate, Error, Result};
use session::Session;
use uncertainty::{white_variance, Chain};

/// Settings of [`calibrate_static`].
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct StaticCalibrationOptions {
    /// Local gravity magnitude, m/s² (required: 9.78-9.83 on the Earth's
    /// surface; use a gravity model at the site, e.g. [`crate::geodesy`]).
    pub gravity_m_s2: f64,
    /// How raw readings become SI readings (scale × (counts − offset)).
    pub nominal: Nominal,
    /// The rest detector that finds the poses.
    pub detector: StaticDetector,
    /// [`Estimate::Determinable`]: N and K only when the poses determine
    /// them, T only when there are turns enough; [`Estimate::All`]: every
    /// parameter, an error when the data cannot.
    pub estimate: Estimate,
    /// The poses left out of the fits (module docs); default: none.
    pub holdout: Holdout,
}

/// The result of [`calibrate_static`].
#[derive(Debug, Clone)]
pub struct StaticCalibration {
    /// The models of the nominal readings (SI), method §2.
    pub accelerometer: AccelerometerModel,
    /// The gyroscope's model of the nominal readings (SI), method §2.
    pub gyroscope: GyroscopeModel,
    /// One-sigma values in the models' layout (zero where held or fixed).
    pub accelerometer_std: AccelerometerModel,
    /// One-sigma values of the gyroscope's parameters, in its layout.
    pub gyroscope_std: GyroscopeModel,
    /// Covariance of [accelerometer parameters (15), gyroscope parameters
    /// (21)] in the order of [`super::accelerometer_parameter_names`] then
    /// [`super::gyroscope_parameter_names`].
    pub covariance: DMatrix<f64>,
    /// Cramér-Rao bound of the same parameters for white sensor noise of
    /// the level measured at the initial rest (module docs): the floor the
    /// covariance would reach if drift, tremor and the Earth's rate were
    /// absent.
    pub crb: DMatrix<f64>,
    /// White noise variance per sample and axis at the initial rest, in
    /// nominal units squared: accelerometer, gyroscope.
    pub white_noise_variance: [Vector3<f64>; 2],
    /// The nominal conversion the fit started from.
    pub nominal: Nominal,
    /// The local gravity magnitude used, m/s².
    pub gravity_m_s2: f64,
    /// The rests found and the turns between them.
    pub detection: StaticDetection,
    /// Each pose's gravity-magnitude check before and after the calibration.
    pub poses: Vec<PoseCheck>,
    /// Each turn's angle check before and after the calibration.
    pub turns: Vec<TurnCheck>,
    /// Parameters not estimated, "accelerometer misalignment_uv" style,
    /// with the reason.
    pub held: Vec<(String, String)>,
    /// The models of the second-order terms each stage considered and the
    /// one it chose (module docs; empty under [`Estimate::All`]).
    pub model_selection: Vec<ModelSelection>,
    /// Poor conditioning or too few degrees of freedom of a fit, σ above a
    /// parameter's physical size, fitted scales far from the nominal ones
    /// (`warnings.rs`).
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
/// `gravity`, `holdout_every`, `holdout_from_s`, the detector's settings,
/// `poses` when too few were found) or, under [`Estimate::All`], the
/// parameter the data do not determine.
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
    if let Some(h) = options.holdout.every {
        if h < 2 {
            return Err(Error::invalid(
                "holdout_every",
                format!("must be at least 2 (every h-th pose is held out), got {h}"),
            ));
        }
    }
    if let Some(t) = options.holdout.from_s {
        if !t.is_finite() {
            return Err(Error::invalid(
                "holdout_from_s",
                format!("must be a finite time, got {t}"),
            ));
        }
    }
    // 1-2. The nominal readings and the poses.
    let nominal = &options.nominal;
    let accel_nominal: Vec<Vector3<f64>> = accel.iter().map(|a| nominal.accel(a)).collect();
    let gyro_nominal: Vec<Vector3<f64>> = gyro.iter().map(|g| nominal.gyro(g)).collect();
    let detection = options
        .detector
        .detect(time, &accel_nominal, &gyro_nominal)?;
    let session = Session::new(
        time,
        accel_nominal,
        gyro_nominal,
        &detection.poses,
        options.holdout,
        options.gravity_m_s2,
        options.estimate == Estimate::Determinable,
    );
    let mut warnings = Vec::new();
    let mut held = Vec::new();

    // 3. The accelerometer.
    let accel_means = session.accel_means();
    let fit_means: Vec<Vector3<f64>> = session.fit_poses.iter().map(|&k| accel_means[k]).collect();
    let accel_stage = accelerometer::fit(
        &fit_means,
        session.poses.len(),
        session.gravity,
        session.determinable,
        &mut held,
    )?;
    warnings::accelerometer_fit(&accel_stage, fit_means.len(), &mut warnings);

    // 4-5. The gyroscope.
    let data = session.gyro_data(&accel_stage.model).ok_or_else(|| {
        Error::invalid("accel", "a reading is beyond the range of the fitted model")
    })?;
    let fit_segments = session.fit_turns(&data.segments);
    let (rest_gyro, rest_force) = session.rest_poses(&data);
    let gyro_stage = gyroscope::fit(
        &rest_gyro,
        &rest_force,
        &fit_segments,
        session.determinable,
        &mut held,
    )?;

    // White noise per sample and axis, from the initial rest: half the
    // variance of first differences (immune to slow drift).
    let (accel_rest, gyro_rest) = session.initial_rest();
    let white = [white_variance(accel_rest), white_variance(gyro_rest)];

    // Uncertainty (module docs).
    let (covariance, crb) = uncertainty::covariance_and_bound(&Chain {
        session: &session,
        accelerometer: &accel_stage,
        gyro_data: &data,
        fit_segments: &fit_segments,
        gyroscope: &gyro_stage,
        white,
    })?;
    let accelerometer_std =
        accelerometer_std_model(&covariance.view((0, 0), (15, 15)).into_owned());
    let gyroscope_std = gyroscope_std_model(&covariance.view((15, 15), (21, 21)).into_owned());

    // Checks before and after.
    let poses = checks::pose_checks(&session, &accel_means, &data);
    let turns = checks::turn_checks(&session, &accel_means, &data, &gyro_stage);

    // Warnings (module docs of `determinable`).
    warnings::parameters(&covariance, &held, &mut warnings);
    warnings::gyroscope_fits(
        &gyro_stage,
        rest_gyro.len(),
        fit_segments.len(),
        &mut warnings,
    );
    warnings::scales(
        &accel_stage.model,
        &gyro_stage.model,
        nominal,
        &mut warnings,
    );
    let gravity_m_s2 = session.gravity;
    let model_selection = [accel_stage.selection.clone(), gyro_stage.selection.clone()]
        .into_iter()
        .flatten()
        .collect();
    Ok(StaticCalibration {
        accelerometer: accel_stage.model,
        gyroscope: gyro_stage.model,
        accelerometer_std,
        gyroscope_std,
        covariance,
        crb,
        white_noise_variance: white,
        nominal: *nominal,
        gravity_m_s2,
        detection,
        poses,
        turns,
        held,
        model_selection,
        warnings,
        accelerometer_residual_std: accel_stage.fit.residual_std,
        rest_residual_std: gyro_stage.rest_fit.residual_std,
        turn_residual_std: gyro_stage
            .t_fit
            .as_ref()
            .map(|f| f.residual_std)
            .unwrap_or(f64::NAN),
        condition_number: [
            accel_stage.fit.condition_number,
            gyro_stage.rest_fit.condition_number,
            gyro_stage
                .t_fit
                .as_ref()
                .map(|f| f.condition_number)
                .unwrap_or(f64::NAN),
        ],
    })
}

#[cfg(test)]
mod tests;
