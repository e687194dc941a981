//! Steps 4-5 of the module docs, the gyroscope: the offsets c₀ + CΓ from
//! the rests ([`super::rests`]) and T = A⁻¹ from the turns between poses
//! ([`super::rotation`]; Tedaldi et al. 2014 §III-C), fitted in turn until
//! the rules of [`crate::calibration::determinable`] hold: under
//! [`Estimate::Determinable`] a column of C (a g-sensitivity to one
//! specific-force axis, all three gyro rows) is held when the poses do not
//! vary that axis (rule 2), when the rest fit's AICc is smaller without it
//! (the combination of columns of smallest AICc is kept,
//! [`crate::calibration::information`]) or when its σ(K) ≈ σ(T C) would
//! exceed its physical size (rule 3), and T is held at the nominal scale
//! (the identity) with too few or too similar turns.
//!
//! [`Estimate::Determinable`]: crate::calibration::determinable::Estimate

use nalgebra::{Matrix3, Vector3};

use super::rests::{self, RestFit};
use super::rotation::{t_from_vector, t_to_vector, Offsets, Rotations, Segment};
use super::solver::{self, Fit};
use crate::calibration::determinable::{physical_size, UNDETERMINED_CONDITION};
use crate::calibration::information::{aicc, subsets, Candidate, ModelSelection};
use crate::calibration::{gyroscope_parameter_names, ACCELEROMETER_AXES};
use crate::sensors::{GyroscopeModel, NoiseModel};
use crate::text::number;
use crate::{Error, Result};

/// The fitted gyroscope.
pub struct GyroscopeStage {
    /// The offsets c₀ + CΓ and their covariance.
    pub rest_fit: RestFit,
    /// The fit of T; None when T is held at the identity.
    pub t_fit: Option<Fit>,
    /// T = A⁻¹ (the identity when held).
    pub t: Matrix3<f64>,
    /// The columns of C (specific-force axes 0, 1, 2) that were fitted.
    pub free_columns: Vec<usize>,
    /// The model of T and the offsets ([`gyroscope_model`]).
    pub model: GyroscopeModel,
    /// The columns of C considered and the ones chosen (`determinable` only).
    pub selection: Option<ModelSelection>,
}

/// Fits the gyroscope to the rest means of the poses in the fit
/// (`rest_gyro`, nominal units; `rest_force`, corrected specific force,
/// m/s²) and the turns between them (`fit_segments`), holding what the
/// data do not determine under `determinable` (recorded in `held`; module
/// docs). Errors without `determinable`: too few poses or turns (`poses`),
/// a g-sensitivity the poses do not vary, a rotation fit that fails; and a
/// singular fitted T (`gyro`).
pub fn fit(
    rest_gyro: &[Vector3<f64>],
    rest_force: &[Vector3<f64>],
    fit_segments: &[Segment],
    determinable: bool,
    held: &mut Vec<(String, String)>,
) -> Result<GyroscopeStage> {
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
        hold_column(held, &names_g, l, "too few poses");
    }
    let t_start = Matrix3::identity();
    let mut selection = None;
    let (rest_fit, t_fit, t) = loop {
        let rest_fit = rests::fit(rest_gyro, rest_force, &free_columns)?;
        if rest_fit.condition_number > UNDETERMINED_CONDITION && rest_fit.weakest_column > 0 {
            let l = rest_fit.weakest_column - 1;
            if !determinable {
                return Err(Error::Unobservable {
                    axis: ACCELEROMETER_AXES[l].to_string(),
                    parameter: "g_sensitivity".into(),
                    reason: "the poses do not vary the specific force on this axis".into(),
                });
            }
            free_columns.retain(|&c| c != l);
            hold_column(
                held,
                &names_g,
                l,
                "the poses do not vary this specific-force axis",
            );
            continue;
        }
        if determinable {
            let (chosen, s) = select_columns(rest_gyro, rest_force, &free_columns)?;
            let dropped: Vec<usize> = free_columns
                .iter()
                .copied()
                .filter(|l| !chosen.contains(l))
                .collect();
            for &l in &dropped {
                hold_column(held, &names_g, l, &s.why_not(&column_term(l)));
            }
            selection = Some(s);
            if !dropped.is_empty() {
                free_columns = chosen;
                continue;
            }
        }
        let t_fit = fit_rotations(fit_segments, &rest_fit.offsets, &t_start, determinable)?;
        let t = t_fit
            .as_ref()
            .map(|f| t_from_vector(&f.x))
            .unwrap_or(t_start);
        match most_uncertain_column(&t, &rest_fit, &free_columns) {
            Some((l, sd)) if determinable => {
                free_columns.retain(|&c| c != l);
                hold_column(
                    held,
                    &names_g,
                    l,
                    &format!(
                        "its sigma {} would exceed its physical size 0.001",
                        number(sd, 3)
                    ),
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
    let model = gyroscope_model(&t, &rest_fit.offsets)
        .ok_or_else(|| Error::invalid("gyro", "the fitted T = A⁻¹ is singular"))?;
    Ok(GyroscopeStage {
        rest_fit,
        t_fit,
        t,
        free_columns,
        model,
        selection,
    })
}

/// The optional term of column l of C: the g-sensitivity of every gyro
/// axis to specific force along accelerometer axis l.
fn column_term(l: usize) -> String {
    format!("g_sensitivity to {}", ACCELEROMETER_AXES[l])
}

/// The columns of C among the subsets of `free_columns` whose rest fit
/// rule 2 allows, of smallest AICc summed over the three gyro rows (each
/// an independent regression with its own residual variance;
/// [`crate::calibration::information`]): the columns and the record.
fn select_columns(
    rest_gyro: &[Vector3<f64>],
    rest_force: &[Vector3<f64>],
    free_columns: &[usize],
) -> Result<(Vec<usize>, ModelSelection)> {
    let mut columns = Vec::new();
    let mut candidates = Vec::new();
    for subset in subsets(free_columns) {
        let f = rests::fit(rest_gyro, rest_force, &subset)?;
        let n = f.poses;
        let per_row = 1 + subset.len();
        let mut candidate = Candidate {
            terms: subset.iter().map(|&l| column_term(l)).collect(),
            parameters: 3 * per_row,
            observations: 3 * n,
            residual_rms: (f.rss.sum() / (3 * n) as f64).sqrt(),
            aicc: None,
            refused: String::new(),
        };
        if f.condition_number > UNDETERMINED_CONDITION || !f.condition_number.is_finite() {
            candidate.refused = format!(
                "the poses do not separate the columns (condition number {:.2e})",
                f.condition_number
            );
        } else {
            candidate.aicc = Some(f.rss.iter().map(|&rss| aicc(rss, n, per_row)).sum());
        }
        candidates.push(candidate);
        columns.push(subset);
    }
    let selection = ModelSelection::choose("gyroscope g-sensitivity", candidates)
        .ok_or_else(|| Error::invalid("poses", "the gyro rest fit has no admissible model"))?;
    Ok((columns[selection.chosen].clone(), selection))
}

/// The rotation fit of T for the `offsets` over the turns `fit_segments`,
/// from the best multiple of `t_start` ([`Rotations::scan`]); 2 residuals
/// per turn, 9 entries. None under `determinable` when there are no more
/// residuals than entries, the fit fails, or its condition number exceeds
/// [`UNDETERMINED_CONDITION`] (rule 2); otherwise those are errors.
fn fit_rotations(
    fit_segments: &[Segment],
    offsets: &Offsets,
    t_start: &Matrix3<f64>,
    determinable: bool,
) -> Result<Option<Fit>> {
    let problem = Rotations {
        segments: fit_segments,
        offsets: *offsets,
    };
    let turns_enough = 2 * fit_segments.len() > 9;
    if turns_enough {
        let start = t_to_vector(&problem.scan(t_start));
        match solver::minimize(&problem, start, 2 * fit_segments.len() - 9, "gyroscope") {
            Ok(f) if f.condition_number <= UNDETERMINED_CONDITION || !determinable => Ok(Some(f)),
            Ok(_) | Err(_) if determinable => Ok(None),
            Ok(f) => Ok(Some(f)),
            Err(e) => Err(e),
        }
    } else if determinable {
        Ok(None)
    } else {
        Err(Error::invalid(
            "poses",
            format!(
                "the gyroscope's scale factors and misalignments need at least 5 turns between \
                 poses in the fit, got {}",
                fit_segments.len()
            ),
        ))
    }
}

/// Rule 3 for the g-sensitivity columns: the free column l of C whose
/// σ(K_rl) = σ(T C)_rl ≈ (Σ_i T_ri² σ²(C_il))^½, largest over the rows r,
/// most exceeds the physical size of a g-sensitivity, with that σ; None
/// when none exceeds it.
fn most_uncertain_column(
    t: &Matrix3<f64>,
    rest_fit: &RestFit,
    free_columns: &[usize],
) -> Option<(usize, f64)> {
    free_columns
        .iter()
        .map(|&l| {
            let sd = (0..3)
                .map(|r| {
                    (0..3)
                        .map(|i| {
                            t[(r, i)].powi(2)
                                * rest_fit.covariance[(rests::c_index(i, l), rests::c_index(i, l))]
                        })
                        .sum::<f64>()
                        .sqrt()
                })
                .fold(0.0, f64::max);
            (l, sd)
        })
        .filter(|(_, sd)| *sd > physical_size("gyroscope", "g_sensitivity_pu"))
        .max_by(|a, b| a.1.total_cmp(&b.1))
}

/// The gyroscope model of T and the offsets: A = T⁻¹, b = −T c₀, K = −T C
/// (eq. 3 in the nominal reading, [`super::rotation`]); None when T is
/// singular.
pub fn gyroscope_model(t: &Matrix3<f64>, offsets: &Offsets) -> Option<GyroscopeModel> {
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

/// Records the g-sensitivity column `l` (all three gyro rows) as held.
fn hold_column(held: &mut Vec<(String, String)>, names_g: &[String], l: usize, why: &str) {
    for i in 0..3 {
        held.push((
            format!("gyroscope {}", names_g[12 + 3 * i + l]),
            why.to_string(),
        ));
    }
}
