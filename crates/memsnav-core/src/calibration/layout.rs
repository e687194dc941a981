//! Which parameter of which sensor axis sits at which index of a
//! calibration's parameter vector (its `covariance`, `crb` and the names of
//! [`super::accelerometer_parameter_names`] / [`super::gyroscope_parameter_names`]),
//! and the way back from a parameter vector to a model.
//!
//! | indices | accelerometer (15) | gyroscope (21) | model field |
//! |---|---|---|---|
//! | 0-2 | bias b_u, b_v, b_w (m/s²) | bias b_p, b_q, b_r (rad/s) | `bias[i]` |
//! | 3-5 | scale factor D_ii (1) | scale factor D_ii (1) | `scale_factor[i]` |
//! | 6-11 | misalignment M_ij, i ≠ j, in [`OFF_DIAGONAL`] order (1) | the same | `misalignment[(i, j)]` |
//! | 12-14 | nonlinearity N_i (s²/m) | | `nonlinearity[i]` |
//! | 12-20 | | g-sensitivity K_ij, row-major (rad/s per m/s²) | `g_sensitivity[(i, j)]` |
//!
//! The output axis of a parameter is i (u, v, w for the accelerometer; p,
//! q, r for the gyroscope); the second axis of a misalignment is an axis of
//! the same triad, that of a g-sensitivity an accelerometer axis (the
//! specific force it responds to). Its name is the group then the axes'
//! letters: `bias_u`, `misalignment_pr`, `g_sensitivity_qw`.

use std::ops::Range;

use nalgebra::{Matrix3, SVector, Vector3};

use super::{ACCELEROMETER_AXES, GYROSCOPE_AXES, OFF_DIAGONAL};
use crate::sensors::{AccelerometerModel, GyroscopeModel, NoiseModel};
use crate::Result;

/// Parameters of an accelerometer calibration.
pub const ACCELEROMETER_PARAMETERS: usize = 15;
/// Parameters of a gyroscope calibration.
pub const GYROSCOPE_PARAMETERS: usize = 21;

/// The calibrated triad.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash)]
pub enum Sensor {
    /// The accelerometer triad.
    Accelerometer,
    /// The gyroscope triad.
    Gyroscope,
}

impl Sensor {
    /// "accelerometer" or "gyroscope".
    pub const fn name(self) -> &'static str {
        match self {
            Sensor::Accelerometer => "accelerometer",
            Sensor::Gyroscope => "gyroscope",
        }
    }

    /// The sensor of a name from [`Sensor::name`].
    pub fn from_name(name: &str) -> Option<Self> {
        [Sensor::Accelerometer, Sensor::Gyroscope]
            .into_iter()
            .find(|s| s.name() == name)
    }

    /// Letters of the triad's axes: u, v, w or p, q, r (the body axes x,
    /// y, z: forward, right, down).
    pub const fn axes(self) -> [&'static str; 3] {
        match self {
            Sensor::Accelerometer => ACCELEROMETER_AXES,
            Sensor::Gyroscope => GYROSCOPE_AXES,
        }
    }
}

/// A group of parameters: one field of the sensor model.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash)]
pub enum Group {
    /// The bias, one per axis.
    Bias,
    /// The scale factor, one per axis.
    ScaleFactor,
    /// The misalignment (off-diagonal) terms.
    Misalignment,
    /// Accelerometer only.
    Nonlinearity,
    /// Gyroscope only.
    GSensitivity,
}

impl Group {
    /// The model field's name (`bias`, `scale_factor`, ...).
    pub const fn name(self) -> &'static str {
        match self {
            Group::Bias => "bias",
            Group::ScaleFactor => "scale_factor",
            Group::Misalignment => "misalignment",
            Group::Nonlinearity => "nonlinearity",
            Group::GSensitivity => "g_sensitivity",
        }
    }

    /// Entries of the group.
    const fn len(self) -> usize {
        match self {
            Group::Bias | Group::ScaleFactor | Group::Nonlinearity => 3,
            Group::Misalignment => OFF_DIAGONAL.len(),
            Group::GSensitivity => 9,
        }
    }

    /// Output axis and, for a matrix field, input axis of entry `k`.
    const fn axes(self, k: usize) -> (usize, Option<usize>) {
        match self {
            Group::Bias | Group::ScaleFactor | Group::Nonlinearity => (k, None),
            Group::Misalignment => (OFF_DIAGONAL[k].0, Some(OFF_DIAGONAL[k].1)),
            Group::GSensitivity => (k / 3, Some(k % 3)),
        }
    }
}

/// What sits at one index of the parameter vector.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct Parameter {
    /// The model field the parameter belongs to.
    pub group: Group,
    /// The axis whose output the parameter enters (0, 1, 2).
    pub output_axis: usize,
    /// For a matrix field: the column, an axis of the same triad
    /// (misalignment) or of the accelerometer (g-sensitivity).
    pub input_axis: Option<usize>,
}

/// The parameter vector of one sensor's calibration (module docs).
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct CalibrationLayout {
    /// The triad calibrated.
    pub sensor: Sensor,
}

impl CalibrationLayout {
    /// The accelerometer's 15 parameters.
    pub const ACCELEROMETER: Self = Self {
        sensor: Sensor::Accelerometer,
    };
    /// The gyroscope's 21 parameters.
    pub const GYROSCOPE: Self = Self {
        sensor: Sensor::Gyroscope,
    };

    /// The groups in parameter order.
    pub const fn groups(&self) -> [Group; 4] {
        let last = match self.sensor {
            Sensor::Accelerometer => Group::Nonlinearity,
            Sensor::Gyroscope => Group::GSensitivity,
        };
        [Group::Bias, Group::ScaleFactor, Group::Misalignment, last]
    }

    /// Length of the parameter vector.
    pub const fn len(&self) -> usize {
        match self.sensor {
            Sensor::Accelerometer => ACCELEROMETER_PARAMETERS,
            Sensor::Gyroscope => GYROSCOPE_PARAMETERS,
        }
    }

    /// Never empty (for clippy's `len_without_is_empty`).
    pub const fn is_empty(&self) -> bool {
        false
    }

    /// The indices of a group; `None` for a group the sensor lacks.
    pub fn range(&self, group: Group) -> Option<Range<usize>> {
        let mut start = 0;
        for g in self.groups() {
            if g == group {
                return Some(start..start + g.len());
            }
            start += g.len();
        }
        None
    }

    /// What sits at index `i` (< [`Self::len`]).
    pub fn parameter(&self, i: usize) -> Parameter {
        assert!(i < self.len(), "parameter index {i} of {}", self.len());
        let mut start = 0;
        for group in self.groups() {
            if i < start + group.len() {
                let (output_axis, input_axis) = group.axes(i - start);
                return Parameter {
                    group,
                    output_axis,
                    input_axis,
                };
            }
            start += group.len();
        }
        unreachable!("the groups cover 0..len")
    }

    /// The name of index `i`: group, output axis and input axis letters.
    pub fn name(&self, i: usize) -> String {
        let p = self.parameter(i);
        let axes = self.sensor.axes();
        let input = match (p.group, p.input_axis) {
            (Group::GSensitivity, Some(j)) => ACCELEROMETER_AXES[j],
            (_, Some(j)) => axes[j],
            (_, None) => "",
        };
        format!("{}_{}{input}", p.group.name(), axes[p.output_axis])
    }

    /// Every name, in index order.
    pub fn names(&self) -> Vec<String> {
        (0..self.len()).map(|i| self.name(i)).collect()
    }

    /// The index of a name from [`Self::name`].
    pub fn index(&self, name: &str) -> Option<usize> {
        (0..self.len()).find(|&i| self.name(i) == name)
    }
}

/// The accelerometer of a parameter vector in [`CalibrationLayout::ACCELEROMETER`]
/// order (the inverse of [`super::accelerometer_parameters`]), with `noise`;
/// the model's own checks apply (e.g. I − D − M non-singular).
pub fn accelerometer_from_parameters(
    p: &SVector<f64, ACCELEROMETER_PARAMETERS>,
    noise: NoiseModel,
) -> Result<AccelerometerModel> {
    let (bias, scale_factor, misalignment) = common_fields(p.as_slice());
    AccelerometerModel::new(
        bias,
        scale_factor,
        misalignment,
        p.fixed_rows::<3>(12).into_owned(),
        noise,
    )
}

/// The gyroscope of a parameter vector in [`CalibrationLayout::GYROSCOPE`]
/// order (the inverse of [`super::gyroscope_parameters`]), with `noise`.
pub fn gyroscope_from_parameters(
    p: &SVector<f64, GYROSCOPE_PARAMETERS>,
    noise: NoiseModel,
) -> Result<GyroscopeModel> {
    let (bias, scale_factor, misalignment) = common_fields(p.as_slice());
    GyroscopeModel::new(
        bias,
        scale_factor,
        misalignment,
        Matrix3::from_row_slice(&p.as_slice()[12..21]),
        noise,
    )
}

/// Bias, scale factor and misalignment: the groups both layouts share.
pub(crate) fn common_fields(p: &[f64]) -> (Vector3<f64>, Vector3<f64>, Matrix3<f64>) {
    let layout = CalibrationLayout::ACCELEROMETER;
    let mut bias = Vector3::zeros();
    let mut scale_factor = Vector3::zeros();
    let mut misalignment = Matrix3::zeros();
    for (i, &value) in p.iter().enumerate().take(12) {
        let q = layout.parameter(i);
        match (q.group, q.input_axis) {
            (Group::Bias, _) => bias[q.output_axis] = value,
            (Group::ScaleFactor, _) => scale_factor[q.output_axis] = value,
            (_, Some(j)) => misalignment[(q.output_axis, j)] = value,
            (_, None) => unreachable!("the first 12 are bias, scale factor, misalignment"),
        }
    }
    (bias, scale_factor, misalignment)
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::calibration::{
        accelerometer_parameter_names, accelerometer_parameters, gyroscope_parameter_names,
        gyroscope_parameters,
    };

    /// A model whose every parameter is distinct, so a wrong index shows.
    fn distinct_models() -> (AccelerometerModel, GyroscopeModel) {
        let off = |base: f64| {
            Matrix3::from_fn(|i, j| {
                if i == j {
                    0.0
                } else {
                    base + (3 * i + j) as f64 * 1e-4
                }
            })
        };
        let accel = AccelerometerModel::new(
            Vector3::new(0.11, 0.12, 0.13),
            Vector3::new(0.021, 0.022, 0.023),
            off(0.003),
            Vector3::new(4e-4, 5e-4, 6e-4),
            NoiseModel::default(),
        )
        .unwrap();
        let gyro = GyroscopeModel::new(
            Vector3::new(0.011, 0.012, 0.013),
            Vector3::new(0.031, 0.032, 0.033),
            off(0.005),
            Matrix3::from_fn(|i, j| 1e-3 * (1 + 3 * i + j) as f64),
            NoiseModel::default(),
        )
        .unwrap();
        (accel, gyro)
    }

    /// The names written out here group by group (method §3's parameter
    /// vector), and the calibrations report the layout's.
    #[test]
    fn names_are_the_calibrations_names() {
        let (a, g) = (["u", "v", "w"], ["p", "q", "r"]);
        let written = |axes: [&str; 3], last: &dyn Fn(&str) -> Vec<String>| {
            let mut names: Vec<String> = axes.iter().map(|x| format!("bias_{x}")).collect();
            names.extend(axes.iter().map(|x| format!("scale_factor_{x}")));
            for (i, j) in [(0, 1), (0, 2), (1, 0), (1, 2), (2, 0), (2, 1)] {
                names.push(format!("misalignment_{}{}", axes[i], axes[j]));
            }
            names.extend(axes.iter().flat_map(|x| last(x)));
            names
        };
        let accel = written(a, &|x| vec![format!("nonlinearity_{x}")]);
        let gyro = written(g, &|x| {
            a.iter().map(|u| format!("g_sensitivity_{x}{u}")).collect()
        });
        assert_eq!(CalibrationLayout::ACCELEROMETER.names(), accel);
        assert_eq!(CalibrationLayout::GYROSCOPE.names(), gyro);
        assert_eq!(accelerometer_parameter_names(), accel);
        assert_eq!(gyroscope_parameter_names(), gyro);
        let g = CalibrationLayout::GYROSCOPE;
        assert_eq!(g.index("g_sensitivity_qw"), Some(17));
        assert_eq!(g.index("bias_u"), None);
        assert_eq!(g.range(Group::GSensitivity), Some(12..21));
        assert_eq!(g.range(Group::Nonlinearity), None);
        assert_eq!(
            CalibrationLayout::ACCELEROMETER.range(Group::Misalignment),
            Some(6..12)
        );
    }

    /// Index i of the parameter vector of a model is the model field the
    /// layout names at i, for every i of both sensors; the way back is
    /// exact.
    #[test]
    fn each_index_reads_the_field_it_names() {
        let (accel, gyro) = distinct_models();
        let pa = accelerometer_parameters(&accel);
        for i in 0..ACCELEROMETER_PARAMETERS {
            let p = CalibrationLayout::ACCELEROMETER.parameter(i);
            let field = match (p.group, p.input_axis) {
                (Group::Bias, None) => accel.bias[p.output_axis],
                (Group::ScaleFactor, None) => accel.scale_factor[p.output_axis],
                (Group::Nonlinearity, None) => accel.nonlinearity[p.output_axis],
                (Group::Misalignment, Some(j)) => accel.misalignment[(p.output_axis, j)],
                other => panic!("{other:?} is not an accelerometer parameter"),
            };
            assert_eq!(pa[i], field, "index {i}");
        }
        let pg = gyroscope_parameters(&gyro);
        for i in 0..GYROSCOPE_PARAMETERS {
            let p = CalibrationLayout::GYROSCOPE.parameter(i);
            let field = match (p.group, p.input_axis) {
                (Group::Bias, None) => gyro.bias[p.output_axis],
                (Group::ScaleFactor, None) => gyro.scale_factor[p.output_axis],
                (Group::Misalignment, Some(j)) => gyro.misalignment[(p.output_axis, j)],
                (Group::GSensitivity, Some(j)) => gyro.g_sensitivity[(p.output_axis, j)],
                other => panic!("{other:?} is not a gyroscope parameter"),
            };
            assert_eq!(pg[i], field, "index {i}");
        }
        let noise = NoiseModel::default();
        assert_eq!(accelerometer_from_parameters(&pa, noise).unwrap(), accel);
        assert_eq!(gyroscope_from_parameters(&pg, noise).unwrap(), gyro);
    }

    #[test]
    fn a_singular_model_is_refused() {
        let mut p = SVector::<f64, ACCELEROMETER_PARAMETERS>::zeros();
        p[3] = 1.0; // D_uu = 1: I − D − M singular
        assert!(accelerometer_from_parameters(&p, NoiseModel::default()).is_err());
    }
}
