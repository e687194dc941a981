//! The IMUs of a navigation run: drawn from a spec, a fixed sensor, or
//! the paper's "calibrated MEMS" (the readings of an earlier IMU passed
//! through calibration and inversion).

use crate::random::{self, Rng};
use crate::sensors::{presets, ImuModel, ImuReadings, ImuSpec};
use crate::trajectory::Trajectory;
use crate::validate::SeriesCheck;
use crate::{Error, Result};

use super::super::calibrate_invert::{InversionProcess, SegmentCalibration};
use super::super::motion;

/// Where an IMU of the experiment comes from.
#[derive(Debug, Clone, PartialEq)]
pub enum NavigationImu {
    /// A new IMU drawn from this spec in every run (the paper's presets).
    Drawn(ImuSpec),
    /// This very sensor in every run (its noise is drawn per run); its
    /// sample rate must equal the trajectory rate.
    Fixed(Box<ImuModel>),
    /// The sensor and readings of IMU `source` (an earlier, non-calibrated
    /// entry) passed through calibration and inversion (module docs).
    Calibrated {
        /// The index of the IMU calibrated.
        source: usize,
    },
}

/// The paper's three IMUs: "ins" (tactical preset), "mems" (paper-mems,
/// raw) and "calibrated_mems" (the same MEMS, calibrated and inverted).
pub fn paper_imus() -> Vec<(String, NavigationImu)> {
    vec![
        ("ins".into(), NavigationImu::Drawn(presets::tactical())),
        ("mems".into(), NavigationImu::Drawn(presets::paper_mems())),
        (
            "calibrated_mems".into(),
            NavigationImu::Calibrated { source: 1 },
        ),
    ]
}

/// Checks the IMU list against the trajectory rate: unique names, valid
/// specs, matching sample rates, calibrated entries after their raw source.
pub(super) fn validate(imus: &[(String, NavigationImu)], rate_hz: f64) -> Result<()> {
    if imus.is_empty() {
        return Err(Error::invalid("imus", "needs at least one IMU"));
    }
    for (j, (name, imu)) in imus.iter().enumerate() {
        if imus[..j].iter().any(|(n, _)| n == name) {
            return Err(Error::invalid(
                "imus",
                format!("name {name:?} appears twice"),
            ));
        }
        match imu {
            NavigationImu::Drawn(spec) => spec.validate()?,
            NavigationImu::Fixed(model) => {
                if (model.sample_rate_hz - rate_hz).abs() > 1e-9 {
                    return Err(Error::invalid(
                        "imus",
                        format!(
                            "{name:?} samples at {} Hz but the trajectory at {rate_hz} Hz",
                            model.sample_rate_hz
                        ),
                    ));
                }
            }
            NavigationImu::Calibrated { source } => {
                let ok =
                    *source < j && !matches!(imus[*source].1, NavigationImu::Calibrated { .. });
                if !ok {
                    return Err(Error::invalid(
                        "imus",
                        format!(
                            "{name:?}: calibrated IMUs need an earlier raw IMU as source, got index {source}"
                        ),
                    ));
                }
            }
        }
    }
    Ok(())
}

/// What a filter gets from one IMU: its readings along the truth and the
/// spec its tuning comes from.
pub(super) struct ImuInput {
    pub readings: ImuReadings,
    pub spec: ImuSpec,
}

/// The inputs of the IMUs of a run that are `needed` (all when None; a
/// calibrated IMU's source is drawn with it), None for the others. IMU j
/// draws from its own stream `random::stream(imu_seed, j)`: its sensor
/// (when drawn), its noise and, for a calibrated IMU, its calibration
/// segment (land-vehicle motion, outputs with their own noise
/// realisation, references). So an IMU's numbers do not depend on the
/// other IMUs of the set, nor on which of them are drawn.
pub(super) fn imu_inputs(
    imus: &[(String, NavigationImu)],
    truth: &Trajectory,
    rate: f64,
    calibration: &SegmentCalibration,
    imu_seed: u64,
    needed: Option<&[bool]>,
) -> Result<Vec<Option<ImuInput>>> {
    let mut drawn: Vec<bool> = needed.map_or_else(|| vec![true; imus.len()], <[bool]>::to_vec);
    // Sources come before the IMUs calibrated from them (validated).
    for j in (0..imus.len()).rev() {
        if let (true, NavigationImu::Calibrated { source }) = (drawn[j], &imus[j].1) {
            drawn[*source] = true;
        }
    }
    // Per IMU: its sensor, when drawn or fixed (a calibrated IMU reads the
    // sensor here and its readings in `inputs`, not a copy).
    let mut sensors: Vec<Option<ImuModel>> = Vec::with_capacity(imus.len());
    let mut inputs: Vec<Option<ImuInput>> = Vec::with_capacity(imus.len());
    for (j, (_, kind)) in imus.iter().enumerate() {
        if !drawn[j] {
            sensors.push(None);
            inputs.push(None);
            continue;
        }
        let mut r: Rng = random::stream(imu_seed, j as u64);
        let input = match kind {
            NavigationImu::Drawn(_) | NavigationImu::Fixed(_) => {
                let model = match kind {
                    NavigationImu::Drawn(spec) => ImuModel::from_spec(spec, rate, &mut r)?,
                    NavigationImu::Fixed(model) => model.as_ref().clone(),
                    NavigationImu::Calibrated { .. } => unreachable!("matched above"),
                };
                // The truth is ours (finite): not checked again.
                let readings = model.measure_series(
                    &truth.specific_force_b,
                    &truth.angular_rate_b,
                    &mut r,
                    SeriesCheck::Trusted,
                )?;
                let spec = model.spec;
                sensors.push(Some(model));
                ImuInput { readings, spec }
            }
            NavigationImu::Calibrated { source } => {
                let model = sensors[*source]
                    .as_ref()
                    .expect("validated: the source is an earlier raw IMU");
                let raw = &inputs[*source]
                    .as_ref()
                    .expect("a needed IMU's source is drawn")
                    .readings;
                let calibrated = calibration.calibrate(model, &motion::land_vehicle, &mut r)?;
                let input = ImuInput {
                    readings: calibrated.invert(model, raw, &InversionProcess::default())?,
                    spec: calibrated.spec(&model.spec),
                };
                sensors.push(None);
                input
            }
        };
        inputs.push(Some(input));
    }
    Ok(inputs)
}
