//! Errors of a solution against a truth trajectory, the way they are
//! reported: in local north, east, down at the truth's epochs, summarised
//! while aided, in each outage and per outage length, with the share of
//! errors inside the filter's own ±3σ and their NEES per degree of freedom
//! (a share of 1 says little when the bounds are ten times the errors).

use nalgebra::Vector3;

use crate::geodesy::{c_n_e, ecef_to_geodetic};
use crate::{validate, Error, Result};

/// Summary of a set of NED errors.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct ErrorStats {
    /// Number of truth epochs.
    pub epochs: usize,
    /// √(mean(e_N² + e_E²)), m.
    pub rms_horizontal_m: f64,
    /// √(mean(e_D²)), m.
    pub rms_vertical_m: f64,
    /// max √(e_N² + e_E²), m.
    pub max_horizontal_m: f64,
    /// Share of the N, E and D errors within ±3σ of the solution (NaN when
    /// no σ was given).
    pub within_3sigma_share: f64,
    /// Share of the N and E errors within ±3σ: the horizontal bounds'
    /// coverage, which a vertical axis with loose bounds would otherwise
    /// flatter (NaN when no σ was given).
    pub within_3sigma_share_horizontal: f64,
    /// mean((e_i / σ_i)²) over the epochs and the N, E, D axes: the NEES
    /// per degree of freedom of the diagonal covariance (correlations
    /// ignored). 1 when the σ's describe the errors, 0.01 when they are
    /// ten times the errors (NaN when no σ was given).
    pub nees_per_dof: f64,
}

impl ErrorStats {
    /// The statistics of `errors` with one-sigmas `std` (empty: no σ).
    pub fn of(errors: &[Vector3<f64>], std: &[Vector3<f64>]) -> Self {
        let n = errors.len();
        if n == 0 {
            return Self {
                epochs: 0,
                rms_horizontal_m: f64::NAN,
                rms_vertical_m: f64::NAN,
                max_horizontal_m: f64::NAN,
                within_3sigma_share: f64::NAN,
                within_3sigma_share_horizontal: f64::NAN,
                nees_per_dof: f64::NAN,
            };
        }
        let h2: Vec<f64> = errors.iter().map(|e| e.x * e.x + e.y * e.y).collect();
        let inside_axes = |axes: std::ops::Range<usize>| {
            errors
                .iter()
                .zip(std)
                .map(|(e, s)| axes.clone().filter(|&i| e[i].abs() <= 3.0 * s[i]).count())
                .sum::<usize>()
        };
        let (inside, inside_horizontal) = (inside_axes(0..3), inside_axes(0..2));
        let normalized_squared = errors
            .iter()
            .zip(std)
            .map(|(e, s)| (0..3).map(|i| (e[i] / s[i]).powi(2)).sum::<f64>())
            .sum::<f64>();
        let with_std = std.len() == n;
        Self {
            epochs: n,
            rms_horizontal_m: (h2.iter().sum::<f64>() / n as f64).sqrt(),
            rms_vertical_m: (errors.iter().map(|e| e.z * e.z).sum::<f64>() / n as f64).sqrt(),
            max_horizontal_m: h2.iter().copied().fold(0.0, f64::max).sqrt(),
            within_3sigma_share: if with_std {
                inside as f64 / (3 * n) as f64
            } else {
                f64::NAN
            },
            within_3sigma_share_horizontal: if with_std {
                inside_horizontal as f64 / (2 * n) as f64
            } else {
                f64::NAN
            },
            nees_per_dof: if with_std {
                normalized_squared / (3 * n) as f64
            } else {
                f64::NAN
            },
        }
    }
}

/// The errors of a solution at the truth's epochs.
#[derive(Debug, Clone, PartialEq)]
pub struct Score {
    /// Truth epochs inside the solution's span, s.
    pub time_s: Vec<f64>,
    /// Solution minus truth, local NED at the truth, m.
    pub error_ned: Vec<Vector3<f64>>,
    /// The solution's one-sigma NED at those epochs (interpolated), m.
    pub std_ned: Vec<Vector3<f64>>,
    /// The outage (index into the windows) each epoch lies in.
    pub outage: Vec<Option<usize>>,
    /// Every epoch.
    pub all: ErrorStats,
    /// Epochs outside the outages.
    pub aided: ErrorStats,
    /// Epochs inside any outage.
    pub in_outages: ErrorStats,
    /// Each outage window.
    pub outages: Vec<ErrorStats>,
    /// The epochs of the outages of each length that the vehicle spent
    /// mostly moving (lengths in increasing order), s: an outage at a
    /// standstill tests the zero-velocity updates, not the coast through
    /// it, and would lower the average unmarked.
    pub by_outage_length: Vec<(f64, ErrorStats)>,
    /// The outage windows scored, absolute (start, end) times, s.
    pub windows: Vec<(f64, f64)>,
    /// The time each window spent in a detected standstill, s.
    pub outage_standstill_s: Vec<f64>,
    /// The constant NED offset taken out of `error_ned` before the
    /// statistics (zero for an accuracy score; see
    /// [`Score::less_mean_offset`]), m.
    pub offset_removed_ned: Vector3<f64>,
}

impl Score {
    /// Whether outage window `w` was spent mostly at a standstill (at least
    /// half of it): such windows are left out of [`Score::by_outage_length`].
    pub fn at_standstill(&self, w: usize) -> bool {
        let (a, b) = self.windows[w];
        self.outage_standstill_s[w] >= 0.5 * (b - a)
    }

    /// Statistics of errors already paired with the truth epochs: overall,
    /// while aided, in each window and per window length (windows spent
    /// mostly moving).
    fn summarise(
        time_s: Vec<f64>,
        error_ned: Vec<Vector3<f64>>,
        std_ned: Vec<Vector3<f64>>,
        outage: Vec<Option<usize>>,
        windows: &[(f64, f64)],
        outage_standstill_s: Vec<f64>,
        offset_removed_ned: Vector3<f64>,
    ) -> Self {
        let moving = |w: usize| outage_standstill_s[w] < 0.5 * (windows[w].1 - windows[w].0);
        let pick = |keep: &dyn Fn(Option<usize>) -> bool| {
            let idx: Vec<usize> = (0..time_s.len()).filter(|&i| keep(outage[i])).collect();
            let e: Vec<Vector3<f64>> = idx.iter().map(|&i| error_ned[i]).collect();
            let s: Vec<Vector3<f64>> = idx.iter().map(|&i| std_ned[i]).collect();
            ErrorStats::of(&e, &s)
        };
        let mut lengths: Vec<f64> = windows.iter().map(|(a, b)| b - a).collect();
        lengths.sort_by(f64::total_cmp);
        lengths.dedup_by(|a, b| (*a - *b).abs() < 1e-6);
        let by_outage_length = lengths
            .into_iter()
            .map(|l| {
                let same: Vec<usize> = (0..windows.len())
                    .filter(|&w| ((windows[w].1 - windows[w].0) - l).abs() < 1e-6 && moving(w))
                    .collect();
                (l, pick(&|o| o.is_some_and(|w| same.contains(&w))))
            })
            .collect();
        Self {
            all: pick(&|_| true),
            aided: pick(&|o| o.is_none()),
            in_outages: pick(&|o| o.is_some()),
            outages: (0..windows.len())
                .map(|w| pick(&|o| o == Some(w)))
                .collect(),
            by_outage_length,
            windows: windows.to_vec(),
            outage_standstill_s,
            offset_removed_ned,
            time_s,
            error_ned,
            std_ned,
            outage,
        }
    }

    /// The precision score: the same errors less their mean over the aided
    /// epochs (over every epoch when none is aided), for a truth known to
    /// sit a constant, unknown offset from the datum the solution is in
    /// (the walk_0827 truth's ~8 m: the data README scores it by the
    /// horizontal RMS after removing the run's own mean offset). The mean
    /// over the aided epochs only, so that the drift of the outages does
    /// not move it. With no epoch scored there is nothing to remove.
    pub fn less_mean_offset(&self) -> Self {
        let aided: Vec<Vector3<f64>> = self
            .error_ned
            .iter()
            .zip(&self.outage)
            .filter(|(_, o)| o.is_none())
            .map(|(e, _)| *e)
            .collect();
        let offset = mean(if aided.is_empty() {
            &self.error_ned
        } else {
            &aided
        });
        Self::summarise(
            self.time_s.clone(),
            self.error_ned.iter().map(|e| e - offset).collect(),
            self.std_ned.clone(),
            self.outage.clone(),
            &self.windows,
            self.outage_standstill_s.clone(),
            self.offset_removed_ned + offset,
        )
    }
}

/// The mean of `vectors` (zero when there are none).
fn mean(vectors: &[Vector3<f64>]) -> Vector3<f64> {
    vectors.iter().sum::<Vector3<f64>>() / vectors.len().max(1) as f64
}

/// Interpolates the solution (`time_s`, `position_ecef`, `std_ned`: a
/// dense series, e.g. at the IMU rate) linearly at each truth epoch inside
/// its span and returns the NED errors, with statistics overall, while
/// aided, per outage window (absolute (start, end) times) and per outage
/// length over the windows not spent mostly in the `standstills`
/// ((start, end) times, s).
pub fn score_solution(
    time_s: &[f64],
    position_ecef: &[Vector3<f64>],
    std_ned: &[Vector3<f64>],
    truth_time_s: &[f64],
    truth_position_ecef: &[Vector3<f64>],
    outages: &[(f64, f64)],
    standstills: &[(f64, f64)],
) -> Result<Score> {
    validate::same_length("position_ecef", position_ecef.len(), "time", time_s.len())?;
    validate::same_length("std_ned", std_ned.len(), "time", time_s.len())?;
    validate::same_length(
        "truth_position_ecef",
        truth_position_ecef.len(),
        "truth_time",
        truth_time_s.len(),
    )?;
    if time_s.len() < 2 {
        return Err(Error::invalid("time", "needs at least two samples"));
    }
    validate::increasing_times("time", time_s)?;
    validate::increasing_times("truth_time", truth_time_s)?;
    let (mut times, mut errors, mut stds, mut outage) = (vec![], vec![], vec![], vec![]);
    let (t0, t1) = (time_s[0], time_s[time_s.len() - 1]);
    for (t, truth) in truth_time_s.iter().zip(truth_position_ecef) {
        if *t < t0 || *t > t1 || !truth.iter().all(|v| v.is_finite()) {
            continue;
        }
        let j = time_s
            .partition_point(|x| x <= t)
            .clamp(1, time_s.len() - 1);
        let w = (t - time_s[j - 1]) / (time_s[j] - time_s[j - 1]);
        let r = position_ecef[j - 1].lerp(&position_ecef[j], w);
        times.push(*t);
        errors.push(ned_error(&r, truth));
        stds.push(std_ned[j - 1].lerp(&std_ned[j], w));
        outage.push(outages.iter().position(|&(a, b)| *t >= a && *t < b));
    }
    let standstill_s = outages
        .iter()
        .map(|&(a, b)| {
            standstills
                .iter()
                .map(|&(c, d)| (b.min(d) - a.max(c)).max(0.0))
                .sum()
        })
        .collect();
    Ok(Score::summarise(
        times,
        errors,
        stds,
        outage,
        outages,
        standstill_s,
        Vector3::zeros(),
    ))
}

/// The errors of sparse fixes at their truth epochs.
#[derive(Debug, Clone, PartialEq)]
pub struct FixScore {
    /// The fixes' times that found a truth epoch, s.
    pub time_s: Vec<f64>,
    /// Fix minus truth, local NED at the truth, m.
    pub error_ned: Vec<Vector3<f64>>,
    /// Their statistics (no σ).
    pub stats: ErrorStats,
    /// The constant NED offset taken out of `error_ned` (zero for an
    /// accuracy score), m.
    pub offset_removed_ned: Vector3<f64>,
}

impl FixScore {
    /// The precision score: the errors less their mean (as
    /// [`Score::less_mean_offset`]).
    pub fn less_mean_offset(&self) -> Self {
        let offset = mean(&self.error_ned);
        let error_ned: Vec<Vector3<f64>> = self.error_ned.iter().map(|e| e - offset).collect();
        Self {
            time_s: self.time_s.clone(),
            stats: ErrorStats::of(&error_ned, &[]),
            error_ned,
            offset_removed_ned: self.offset_removed_ned + offset,
        }
    }
}

/// The longest gap between two truth epochs that [`truth_at`] bridges,
/// s: a reference at 1 Hz or faster. Across a longer gap a car's turn
/// (3 m/s² lateral) leaves the chord a ⋅ gap² / 8 from the path: 0.4 m at
/// 1 s, and growing with its square.
pub const TRUTH_MAX_GAP_S: f64 = 1.0;

/// How far from a fix the truth epoch it is paired with may be when none
/// is asked for ([`FixPairing::Nearest`]), s: time stamps of the same
/// instant rounded differently pair, and a reference at 25 Hz or slower
/// pairs each fix with one truth epoch at most.
pub const DEFAULT_TRUTH_TOLERANCE_S: f64 = 0.02;

/// How [`score_fixes`] finds the truth of each fix.
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum FixPairing {
    /// The truth epoch nearest to the fix, within `tolerance_s`: a truth
    /// recorded at the fixes' own epochs (the same receiver's RTK).
    Nearest {
        /// Largest time difference to the nearest truth epoch, s.
        tolerance_s: f64,
    },
    /// The truth interpolated at the fix's time ([`truth_at`], gaps up to
    /// `max_gap_s`): a truth at its own rate and on its own clock ticks
    /// (another system's reference).
    Interpolated {
        /// Longest gap between truth epochs interpolated across, s.
        max_gap_s: f64,
    },
}

/// The truth at time `t`: interpolated linearly between the truth epochs
/// on either side of it when they are at most `max_gap_s` apart (a truth
/// epoch at `t` itself: that epoch); None outside the truth's span, across
/// a longer gap, or next to a non-finite epoch. At 10 Hz a car's 3 m/s²
/// leaves the chord within a ⋅ Δt² / 8 = 4 mm of the path.
pub fn truth_at(
    truth_time_s: &[f64],
    truth_position_ecef: &[Vector3<f64>],
    t: f64,
    max_gap_s: f64,
) -> Option<Vector3<f64>> {
    let j = truth_time_s.partition_point(|x| *x < t);
    let finite = |r: &Vector3<f64>| r.iter().all(|v| v.is_finite());
    if j < truth_time_s.len() && truth_time_s[j] == t {
        return Some(truth_position_ecef[j]).filter(finite);
    }
    if j == 0 || j == truth_time_s.len() {
        return None;
    }
    let (a, b) = (truth_time_s[j - 1], truth_time_s[j]);
    if b - a > max_gap_s {
        return None;
    }
    let (ra, rb) = (truth_position_ecef[j - 1], truth_position_ecef[j]);
    (finite(&ra) && finite(&rb)).then(|| ra.lerp(&rb, (t - a) / (b - a)))
}

/// Fix minus truth in the local NED at the truth, m.
fn ned_error(position_ecef: &Vector3<f64>, truth_ecef: &Vector3<f64>) -> Vector3<f64> {
    let geo = ecef_to_geodetic(truth_ecef);
    c_n_e(geo.latitude_rad, geo.longitude_rad).transpose() * (position_ecef - truth_ecef)
}

/// Errors of sparse fixes (e.g. single-point solutions, or a loose run's
/// input fixes) against the truth found by `pairing`; fixes without one,
/// or NaN, are left out.
pub fn score_fixes(
    time_s: &[f64],
    position_ecef: &[Vector3<f64>],
    truth_time_s: &[f64],
    truth_position_ecef: &[Vector3<f64>],
    pairing: FixPairing,
) -> Result<FixScore> {
    validate::same_length("position_ecef", position_ecef.len(), "time", time_s.len())?;
    validate::same_length(
        "truth_position_ecef",
        truth_position_ecef.len(),
        "truth_time",
        truth_time_s.len(),
    )?;
    match pairing {
        FixPairing::Nearest { tolerance_s } => validate::non_negative("tolerance_s", tolerance_s)?,
        FixPairing::Interpolated { max_gap_s } => {
            validate::non_negative("max_gap_s", max_gap_s)?;
            validate::increasing_times("truth_time", truth_time_s)?;
        }
    }
    let nearest = |t: f64, tolerance_s: f64| {
        let j = truth_time_s.partition_point(|x| *x < t);
        let best = [j.saturating_sub(1), j.min(truth_time_s.len() - 1)]
            .into_iter()
            .min_by(|&a, &b| {
                (truth_time_s[a] - t)
                    .abs()
                    .total_cmp(&(truth_time_s[b] - t).abs())
            })
            .expect("two candidates");
        ((truth_time_s[best] - t).abs() <= tolerance_s).then_some(truth_position_ecef[best])
    };
    let (mut times, mut errors) = (Vec::new(), Vec::new());
    for (t, r) in time_s.iter().zip(position_ecef) {
        if !r.iter().all(|v| v.is_finite()) || truth_time_s.is_empty() {
            continue;
        }
        let truth = match pairing {
            FixPairing::Nearest { tolerance_s } => nearest(*t, tolerance_s),
            FixPairing::Interpolated { max_gap_s } => {
                truth_at(truth_time_s, truth_position_ecef, *t, max_gap_s)
            }
        };
        if let Some(truth) = truth {
            times.push(*t);
            errors.push(ned_error(r, &truth));
        }
    }
    Ok(FixScore {
        stats: ErrorStats::of(&errors, &[]),
        time_s: times,
        error_ned: errors,
        offset_removed_ned: Vector3::zeros(),
    })
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::geodesy::{geodetic_to_ecef, Geodetic};

    /// A solution offset by a known NED vector scores exactly that error;
    /// outage and per-length statistics pick the right epochs.
    #[test]
    fn known_offsets_score_as_themselves() {
        // A slow northward drive; offsets in the local NED of each point.
        let (lat0, lon) = (0.7, -1.8);
        let point = |t: f64, ned: Vector3<f64>| {
            let lat = lat0 + t * 1e-7;
            geodetic_to_ecef(Geodetic::new(lat, lon, 100.0)) + c_n_e(lat, lon) * ned
        };
        let truth_t: Vec<f64> = (0..101).map(|k| k as f64 * 0.25).collect();
        let truth: Vec<Vector3<f64>> = truth_t
            .iter()
            .map(|t| point(*t, Vector3::zeros()))
            .collect();
        let sol_t: Vec<f64> = (0..2501).map(|k| k as f64 * 0.01).collect();
        let offset = |t: f64| {
            if (5.0..10.0).contains(&t) {
                Vector3::new(3.6, 4.8, -1.0)
            } else {
                Vector3::new(0.0, 0.1, 0.2)
            }
        };
        let sol: Vec<Vector3<f64>> = sol_t.iter().map(|t| point(*t, offset(*t))).collect();
        let cne = c_n_e(lat0, lon);
        let std = vec![Vector3::new(1.0, 1.0, 1.0); sol_t.len()];
        let s = score_solution(
            &sol_t,
            &sol,
            &std,
            &truth_t,
            &truth,
            &[(5.0, 10.0), (15.0, 15.5), (20.0, 22.0)],
            &[(0.0, 1.0), (9.0, 12.0), (19.0, 21.5)],
        )
        .unwrap();
        assert_eq!(s.all.epochs, 101);
        // Inside the first outage the error is (3.6, 4.8, −1): 6 m horizontal.
        assert_eq!(s.outages[0].epochs, 20);
        assert!((s.outages[0].rms_horizontal_m - 6.0).abs() < 1e-6);
        assert!((s.outages[0].rms_vertical_m - 1.0).abs() < 1e-6);
        // 3.6 and 4.8 exceed 3σ = 3: only D inside.
        assert!((s.outages[0].within_3sigma_share - 1.0 / 3.0).abs() < 1e-12);
        assert_eq!(s.outages[0].within_3sigma_share_horizontal, 0.0);
        assert_eq!(s.aided.within_3sigma_share_horizontal, 1.0);
        assert!((s.aided.rms_horizontal_m - 0.1).abs() < 1e-6);
        assert_eq!(s.in_outages.epochs, s.all.epochs - s.aided.epochs);
        // σ = 1 m: the NEES per axis is the squared error, (3.6² + 4.8² +
        // 1²) / 3 in the first outage, (0.1² + 0.2²) / 3 outside.
        let nees = (3.6f64.powi(2) + 4.8f64.powi(2) + 1.0) / 3.0;
        assert!((s.outages[0].nees_per_dof - nees).abs() < 1e-5);
        assert!((s.aided.nees_per_dof - 0.05 / 3.0).abs() < 1e-6);
        // Standstill time per window; the third (1.5 of its 2 s) is left
        // out of its length's statistics, the first (1 of 5 s) is not.
        assert_eq!(s.outage_standstill_s, vec![1.0, 0.0, 1.5]);
        assert!(!s.at_standstill(0) && s.at_standstill(2));
        assert_eq!(s.by_outage_length.len(), 3);
        assert_eq!(s.by_outage_length[0].0, 0.5);
        assert_eq!(s.by_outage_length[1].1.epochs, 0);
        assert_eq!(s.outages[2].epochs, 8);
        assert_eq!(s.by_outage_length[2].1.epochs, 20);
        // Fixes paired with the nearest truth epoch within the tolerance.
        let fix_t = [5.001, 7.3, 30.0];
        let fixes: Vec<Vector3<f64>> = fix_t
            .iter()
            .map(|t| truth[(t * 4.0_f64).round() as usize] + cne * Vector3::new(0.0, 2.0, 0.0))
            .take(2)
            .chain([truth[0]])
            .collect();
        let fixed = score_fixes(
            &fix_t,
            &fixes,
            &truth_t,
            &truth,
            FixPairing::Nearest { tolerance_s: 0.02 },
        )
        .unwrap();
        assert_eq!(fixed.time_s, vec![5.001]);
        assert!((fixed.error_ned[0] - Vector3::new(0.0, 2.0, 0.0)).norm() < 1e-6);
        assert_eq!(fixed.stats.epochs, 1);
        // Its precision: one fix is its own mean.
        let precise = fixed.less_mean_offset();
        assert!((precise.offset_removed_ned - Vector3::new(0.0, 2.0, 0.0)).norm() < 1e-6);
        assert!(precise.stats.rms_horizontal_m < 1e-6);
    }

    /// A solution a constant offset plus a zero-mean wobble from the truth
    /// while aided, and drifting in an outage: the precision score removes
    /// exactly the constant (the mean over the aided epochs, not moved by
    /// the drift) and keeps the wobble and the drift.
    #[test]
    fn precision_removes_the_aided_mean_offset() {
        let (lat0, lon) = (0.7, -1.8);
        let lat = |t: f64| lat0 + t * 1e-8;
        let at = |t: f64| geodetic_to_ecef(Geodetic::new(lat(t), lon, 100.0));
        let truth_t: Vec<f64> = (0..400).map(|k| k as f64 * 0.25).collect();
        let truth: Vec<Vector3<f64>> = truth_t.iter().map(|t| at(*t)).collect();
        let constant = Vector3::new(2.8, 8.3, -0.8);
        let outage = (40.0, 60.0);
        // ±0.3 m alternating per truth epoch: zero mean over the aided epochs.
        let error = |k: usize, t: f64| {
            let wobble = if k % 2 == 0 { 0.3 } else { -0.3 };
            let drift = if (outage.0..outage.1).contains(&t) {
                Vector3::new(0.5 * (t - outage.0), 0.0, 0.0)
            } else {
                Vector3::zeros()
            };
            constant + Vector3::new(0.0, wobble, 0.0) + drift
        };
        let sol: Vec<Vector3<f64>> = truth_t
            .iter()
            .enumerate()
            .map(|(k, t)| at(*t) + c_n_e(lat(*t), lon) * error(k, *t))
            .collect();
        let std = vec![Vector3::new(1.0, 1.0, 1.0); sol.len()];
        let raw = score_solution(&truth_t, &sol, &std, &truth_t, &truth, &[outage], &[]).unwrap();
        assert_eq!(raw.offset_removed_ned, Vector3::zeros());
        assert!(raw.aided.rms_horizontal_m > 8.0);
        let precise = raw.less_mean_offset();
        assert!((precise.offset_removed_ned - constant).norm() < 1e-6);
        assert!((precise.aided.rms_horizontal_m - 0.3).abs() < 1e-6);
        assert!(precise.aided.rms_vertical_m < 1e-6);
        // The drift is kept: 0.5 m/s over 20 s, RMS of 0.5 t with the wobble.
        let drift_rms = (truth_t
            .iter()
            .filter(|t| (outage.0..outage.1).contains(*t))
            .map(|t| (0.5 * (t - outage.0)).powi(2) + 0.09)
            .sum::<f64>()
            / 80.0)
            .sqrt();
        assert!((precise.in_outages.rms_horizontal_m - drift_rms).abs() < 1e-6);
        assert_eq!(precise.outages.len(), 1);
        assert_eq!(precise.by_outage_length[0].1.epochs, 80);
        // Removing it twice changes nothing more.
        let twice = precise.less_mean_offset();
        assert!((twice.offset_removed_ned - constant).norm() < 1e-6);
    }

    /// A 10 Hz truth of a drive at 20 m/s on its own clock ticks and 1 Hz
    /// fixes between them, each a known NED offset from the path: the
    /// interpolated pairing finds every offset (the nearest epoch would be
    /// up to 0.05 s, a metre, away); fixes past the truth's end, across a
    /// gap longer than the limit, or NaN, find none.
    #[test]
    fn fixes_between_truth_epochs_find_the_interpolated_truth() {
        let (lat0, lon) = (0.7, -1.8);
        // 20 m/s north: 20 / 6.37e6 rad/s of latitude.
        let at = |t: f64, ned: Vector3<f64>| {
            let lat = lat0 + t * 20.0 / 6.37e6;
            geodetic_to_ecef(Geodetic::new(lat, lon, 100.0)) + c_n_e(lat, lon) * ned
        };
        let mut truth_t: Vec<f64> = (0..200).map(|k| 0.043 + k as f64 * 0.1).collect();
        // A 3 s gap from 12.0 to 15.0 s.
        truth_t.retain(|t| !(12.0..15.0).contains(t));
        let truth: Vec<Vector3<f64>> = truth_t.iter().map(|t| at(*t, Vector3::zeros())).collect();
        let fix_t: Vec<f64> = (0..22).map(|k| 0.3 + k as f64).collect();
        let offset = |k: usize| Vector3::new(0.1 * k as f64, -1.0, 1.5);
        let mut fixes: Vec<Vector3<f64>> = fix_t
            .iter()
            .enumerate()
            .map(|(k, t)| at(*t, offset(k)))
            .collect();
        fixes[3] = Vector3::repeat(f64::NAN);
        let pairing = FixPairing::Interpolated {
            max_gap_s: TRUTH_MAX_GAP_S,
        };
        let s = score_fixes(&fix_t, &fixes, &truth_t, &truth, pairing).unwrap();
        // Fix 3 NaN, fixes 12, 13, 14 in the gap, 20 and 21 after the end
        // (the last truth epoch is at 19.943 s).
        let want: Vec<f64> = (0..20)
            .filter(|k| ![3, 12, 13, 14].contains(k))
            .map(|k| 0.3 + k as f64)
            .collect();
        assert_eq!(s.time_s, want);
        for (t, e) in s.time_s.iter().zip(&s.error_ned) {
            let k = (t - 0.3).round() as usize;
            // The path's chord between two epochs 0.1 s apart: curvature
            // of the meridian only, far below a millimetre.
            assert!((e - offset(k)).norm() < 1e-6, "fix {k}: {e}");
        }
        // Nearest pairing within 0.02 s finds none of them (0.043 s off).
        let nearest = score_fixes(
            &fix_t,
            &fixes,
            &truth_t,
            &truth,
            FixPairing::Nearest { tolerance_s: 0.02 },
        )
        .unwrap();
        assert!(nearest.time_s.is_empty());
        // A truth epoch at the fix's time is taken as it is.
        assert_eq!(truth_at(&truth_t, &truth, truth_t[5], 0.0), Some(truth[5]));
        assert_eq!(truth_at(&truth_t, &truth, 0.0, TRUTH_MAX_GAP_S), None);
    }
}
