//! The warnings of a static calibration (module docs of
//! [`crate::calibration::determinable`]): poor conditioning and too few
//! residual degrees of freedom of each fit, estimated parameters whose σ
//! exceeds their physical size, and fitted scales per count far from the
//! nominal ones.

use nalgebra::{DMatrix, Vector3};

use super::accelerometer::AccelerometerStage;
use super::gyroscope::GyroscopeStage;
use super::magnitude::parameter_name;
use super::nominal::Nominal;
use crate::calibration::determinable::{
    conditioning_warning, degrees_of_freedom_warning, physical_size, uncertainty_warnings,
};
use crate::calibration::{accelerometer_parameter_names, gyroscope_parameter_names};
use crate::sensors::{AccelerometerModel, GyroscopeModel};

/// The magnitude fit's conditioning and degrees of freedom (`fit_poses`
/// pose magnitudes for its free entries).
pub fn accelerometer_fit(accel: &AccelerometerStage, fit_poses: usize, warnings: &mut Vec<String>) {
    conditioning_warning(
        "accelerometer (gravity magnitude)",
        accel.fit.condition_number,
        &parameter_name(accel.free[accel.fit.weakest]),
        warnings,
    );
    degrees_of_freedom_warning(
        "accelerometer (static poses)",
        fit_poses,
        accel.free.len(),
        warnings,
    );
}

/// Rule 3 over the 36 parameters of `covariance`: an estimated parameter
/// (not in `held`, non-zero variance) whose σ exceeds its physical size.
pub fn parameters(
    covariance: &DMatrix<f64>,
    held: &[(String, String)],
    warnings: &mut Vec<String>,
) {
    let names_a = accelerometer_parameter_names();
    let names_g = gyroscope_parameter_names();
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
        warnings,
    );
    uncertainty_warnings(
        "gyroscope",
        &names_g,
        &std_all[15..],
        &scale_g,
        &held_g,
        warnings,
    );
}

/// The rest fit's conditioning and degrees of freedom (`rest_poses` rest
/// means for the bias and the free g-sensitivity columns), then the
/// rotation fit's, when T was fitted (two residuals per turn of
/// `fit_turns`, nine entries).
pub fn gyroscope_fits(
    gyro: &GyroscopeStage,
    rest_poses: usize,
    fit_turns: usize,
    warnings: &mut Vec<String>,
) {
    let rest_fit = &gyro.rest_fit;
    conditioning_warning(
        "gyroscope (rests)",
        rest_fit.condition_number,
        [
            "bias",
            "g-sensitivity to u",
            "g-sensitivity to v",
            "g-sensitivity to w",
        ][rest_fit.weakest_column],
        warnings,
    );
    degrees_of_freedom_warning(
        "gyroscope (rests)",
        rest_poses,
        1 + gyro.free_columns.len(),
        warnings,
    );
    if let Some(f) = &gyro.t_fit {
        conditioning_warning(
            "gyroscope (turns)",
            f.condition_number,
            &format!("T entry {}", f.weakest),
            warnings,
        );
        degrees_of_freedom_warning("gyroscope (turns)", 2 * fit_turns, 9, warnings);
    }
}

/// A fitted scale factor beyond ±0.2 on an axis: the nominal scale per
/// count is far off, and the fitted one, scale / (1 − d), should be passed
/// instead. One warning per sensor, saying that the calibration corrected
/// it: three per-axis warnings read like a failed calibration.
pub fn scales(
    accel_model: &AccelerometerModel,
    gyro_model: &GyroscopeModel,
    nominal: &Nominal,
    warnings: &mut Vec<String>,
) {
    let sensors: [(&str, Vector3<f64>, Vector3<f64>); 2] = [
        (
            "accelerometer",
            accel_model.scale_factor,
            nominal.accel_scale,
        ),
        ("gyroscope", gyro_model.scale_factor, nominal.gyro_scale),
    ];
    for (sensor, d, scale) in sensors {
        let axes: Vec<usize> = (0..3).filter(|&i| d[i].abs() > 0.2).collect();
        if axes.is_empty() {
            continue;
        }
        let list =
            |f: &dyn Fn(usize) -> String| axes.iter().map(|&i| f(i)).collect::<Vec<_>>().join(", ");
        warnings.push(format!(
            "{sensor}: the fitted scale per count differs from the nominal by {} on {} {} \
             (fitted {} against {}; scale factor {}, far outside a MEMS's range). The \
             calibration corrects it and holds; pass the fitted scale as the nominal scale to \
             keep the scale factors within a MEMS's range",
            list(&|i| format!("{:+.0} %", 100.0 * d[i] / (1.0 - d[i]))),
            if axes.len() > 1 { "axes" } else { "axis" },
            list(&|i| i.to_string()),
            list(&|i| format!("{:.6e}", scale[i] / (1.0 - d[i]))),
            list(&|i| format!("{:.6e}", scale[i])),
            list(&|i| format!("{:.3}", d[i])),
        ));
    }
}
