//! Errors of a solution against a truth trajectory, the way they are
//! reported: in local north, east, down at the truth's epochs, summarised
//! while aided, in each outage and per outage length, with the share of
//! errors inside the filter's own ±3σ.

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
            };
        }
        let h2: Vec<f64> = errors.iter().map(|e| e.x * e.x + e.y * e.y).collect();
        let inside = errors
            .iter()
            .zip(std)
            .map(|(e, s)| (0..3).filter(|&i| e[i].abs() <= 3.0 * s[i]).count())
            .sum::<usize>();
        Self {
            epochs: n,
            rms_horizontal_m: (h2.iter().sum::<f64>() / n as f64).sqrt(),
            rms_vertical_m: (errors.iter().map(|e| e.z * e.z).sum::<f64>() / n as f64).sqrt(),
            max_horizontal_m: h2.iter().copied().fold(0.0, f64::max).sqrt(),
            within_3sigma_share: if std.len() == n {
                inside as f64 / (3 * n) as f64
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
    /// The epochs of all outages of each length (lengths in increasing
    /// order), s.
    pub by_outage_length: Vec<(f64, ErrorStats)>,
}

/// Interpolates the solution (`time_s`, `position_ecef`, `std_ned`: a
/// dense series, e.g. at the IMU rate) linearly at each truth epoch inside
/// its span and returns the NED errors, with statistics overall, while
/// aided, per outage window (absolute (start, end) times) and per outage
/// length.
pub fn score_solution(
    time_s: &[f64],
    position_ecef: &[Vector3<f64>],
    std_ned: &[Vector3<f64>],
    truth_time_s: &[f64],
    truth_position_ecef: &[Vector3<f64>],
    outages: &[(f64, f64)],
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
    let mut score = Score {
        time_s: Vec::new(),
        error_ned: Vec::new(),
        std_ned: Vec::new(),
        outage: Vec::new(),
        all: ErrorStats::of(&[], &[]),
        aided: ErrorStats::of(&[], &[]),
        in_outages: ErrorStats::of(&[], &[]),
        outages: Vec::new(),
        by_outage_length: Vec::new(),
    };
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
        let s = std_ned[j - 1].lerp(&std_ned[j], w);
        let geo = ecef_to_geodetic(truth);
        let cne = c_n_e(geo.latitude_rad, geo.longitude_rad);
        score.time_s.push(*t);
        score.error_ned.push(cne.transpose() * (r - truth));
        score.std_ned.push(s);
        score
            .outage
            .push(outages.iter().position(|&(a, b)| *t >= a && *t < b));
    }
    let pick = |keep: &dyn Fn(Option<usize>) -> bool| {
        let idx: Vec<usize> = (0..score.time_s.len())
            .filter(|&i| keep(score.outage[i]))
            .collect();
        let e: Vec<Vector3<f64>> = idx.iter().map(|&i| score.error_ned[i]).collect();
        let s: Vec<Vector3<f64>> = idx.iter().map(|&i| score.std_ned[i]).collect();
        ErrorStats::of(&e, &s)
    };
    score.all = pick(&|_| true);
    score.aided = pick(&|o| o.is_none());
    score.in_outages = pick(&|o| o.is_some());
    score.outages = (0..outages.len())
        .map(|w| pick(&|o| o == Some(w)))
        .collect();
    let mut lengths: Vec<f64> = outages.iter().map(|(a, b)| b - a).collect();
    lengths.sort_by(f64::total_cmp);
    lengths.dedup_by(|a, b| (*a - *b).abs() < 1e-6);
    score.by_outage_length = lengths
        .into_iter()
        .map(|l| {
            let windows: Vec<usize> = (0..outages.len())
                .filter(|&w| ((outages[w].1 - outages[w].0) - l).abs() < 1e-6)
                .collect();
            (l, pick(&|o| o.is_some_and(|w| windows.contains(&w))))
        })
        .collect();
    Ok(score)
}

/// Errors of sparse fixes (e.g. single-point solutions) against the truth
/// epoch nearest to each, within `tolerance_s`; fixes with no truth epoch
/// that close, or NaN, are left out. Returns the paired fix times and NED
/// errors, and their statistics.
pub fn score_fixes(
    time_s: &[f64],
    position_ecef: &[Vector3<f64>],
    truth_time_s: &[f64],
    truth_position_ecef: &[Vector3<f64>],
    tolerance_s: f64,
) -> Result<(Vec<f64>, Vec<Vector3<f64>>, ErrorStats)> {
    validate::same_length("position_ecef", position_ecef.len(), "time", time_s.len())?;
    validate::same_length(
        "truth_position_ecef",
        truth_position_ecef.len(),
        "truth_time",
        truth_time_s.len(),
    )?;
    validate::non_negative("tolerance_s", tolerance_s)?;
    let (mut times, mut errors) = (Vec::new(), Vec::new());
    for (t, r) in time_s.iter().zip(position_ecef) {
        if !r.iter().all(|v| v.is_finite()) || truth_time_s.is_empty() {
            continue;
        }
        let j = truth_time_s.partition_point(|x| x < t);
        let best = [j.saturating_sub(1), j.min(truth_time_s.len() - 1)]
            .into_iter()
            .min_by(|&a, &b| {
                (truth_time_s[a] - t)
                    .abs()
                    .total_cmp(&(truth_time_s[b] - t).abs())
            })
            .expect("two candidates");
        if (truth_time_s[best] - t).abs() > tolerance_s {
            continue;
        }
        let truth = truth_position_ecef[best];
        let geo = ecef_to_geodetic(&truth);
        let cne = c_n_e(geo.latitude_rad, geo.longitude_rad);
        times.push(*t);
        errors.push(cne.transpose() * (r - truth));
    }
    let stats = ErrorStats::of(&errors, &[]);
    Ok((times, errors, stats))
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
            &[(5.0, 10.0), (15.0, 15.5)],
        )
        .unwrap();
        assert_eq!(s.all.epochs, 101);
        // Inside the first outage the error is (3.6, 4.8, −1): 6 m horizontal.
        assert_eq!(s.outages[0].epochs, 20);
        assert!((s.outages[0].rms_horizontal_m - 6.0).abs() < 1e-6);
        assert!((s.outages[0].rms_vertical_m - 1.0).abs() < 1e-6);
        // 3.6 and 4.8 exceed 3σ = 3: only D inside.
        assert!((s.outages[0].within_3sigma_share - 1.0 / 3.0).abs() < 1e-12);
        assert!((s.aided.rms_horizontal_m - 0.1).abs() < 1e-6);
        assert_eq!(s.in_outages.epochs, s.all.epochs - s.aided.epochs);
        assert_eq!(s.by_outage_length.len(), 2);
        assert_eq!(s.by_outage_length[0].0, 0.5);
        assert_eq!(s.by_outage_length[1].1.epochs, 20);
        // Fixes paired with the nearest truth epoch within the tolerance.
        let fix_t = [5.001, 7.3, 30.0];
        let fixes: Vec<Vector3<f64>> = fix_t
            .iter()
            .map(|t| truth[(t * 4.0_f64).round() as usize] + cne * Vector3::new(0.0, 2.0, 0.0))
            .take(2)
            .chain([truth[0]])
            .collect();
        let (t, e, st) = score_fixes(&fix_t, &fixes, &truth_t, &truth, 0.02).unwrap();
        assert_eq!(t, vec![5.001]);
        assert!((e[0] - Vector3::new(0.0, 2.0, 0.0)).norm() < 1e-6);
        assert_eq!(st.epochs, 1);
    }
}
