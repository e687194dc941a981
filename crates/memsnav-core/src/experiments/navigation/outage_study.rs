//! The outage study's runs: every IMU grade through outages of several
//! lengths with several satellite counts kept, one figure set per cell
//! (IMU, length, count) and run.
//!
//! A run draws once (`super::run::draw_run`: trajectory, GNSS, initial
//! errors, every IMU's readings) for the longest outage, and each cell
//! filters its own cut of it: its window's satellites removed
//! ([`crate::gnss::apply_outages`]), and the run ended `tail_s` after the
//! window. The filter is causal, so the forward figures inside the window
//! are those of the whole run, bit for bit; the smoother sees GNSS for
//! `tail_s` after the window (what pins its error there).
//!
//! Every window starts at the same time, so each IMU's filter runs to the
//! sample before it once; the windows of one satellite count agree up to
//! the shorter one's end, so one pass along the longest window serves
//! them all, each cell going on from a copy at its window's end for its
//! tail (`super::filters::navigate_branches`). The smoother's backward
//! pass covers the window and the tail only (a fixed-interval smoother's
//! estimate at a sample depends on the forward filter from that sample
//! on). Per IMU and run the filter covers the time before the windows
//! once and each count's longest window once, plus the tails.
//!
//! The cells of a call are the caller's: an adaptive study asks only for
//! the cells still undecided. A cell's figures in run i do not depend on
//! which other cells run (every IMU draws from its own stream), so a cell
//! run at any look holds the same numbers.

use std::ops::Range;

use crate::gnss::{apply_outages, GnssEpoch, Outage, ReceiverTrack};
use crate::montecarlo::{fold_range, RunOptions};
use crate::random::Rng;
use crate::{validate, Error, Result};

use super::filters::{navigate_branches, Branch, Coupling, ImuRun};
use super::{run, NavigationExperimentConfig, Prepared};

/// What [`outage_study_runs`] runs.
#[derive(Debug, Clone, PartialEq)]
pub struct OutageStudyConfig {
    /// Seed, IMUs and every filter and simulation setting; its `outage`
    /// must be `None`, its `runs` is not used, and its `duration_s` must
    /// cover the longest window plus `tail_s`.
    pub navigation: NavigationExperimentConfig,
    /// Start of every window, s.
    pub outage_start_s: f64,
    /// The windows' lengths, s.
    pub outage_lengths_s: Vec<f64>,
    /// Satellites kept in the windows, 0 (total outage) to 3.
    pub visible_satellites: Vec<usize>,
    /// How long each cell's run goes on after its window, s (0: it ends
    /// at the window's end; the smoother needs GNSS after it).
    pub tail_s: f64,
}

/// One cell: indices into the configuration's IMUs, lengths and counts.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct StudyCell {
    /// Index into the configuration's IMUs.
    pub imu: usize,
    /// Index into its outage lengths.
    pub length: usize,
    /// Index into its counts of satellites kept.
    pub visible: usize,
}

/// One solution's figures in one cell's window, m: the horizontal and 3D
/// error at the window's last output epoch (before GNSS returns) and the
/// largest inside it; whether the run raised an integrity alert; the
/// measurements rejected and accepted over the run.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct WindowFigures {
    /// Horizontal error at the window's last output epoch, m.
    pub horizontal_end_m: f64,
    /// Largest horizontal error inside the window, m.
    pub horizontal_max_m: f64,
    /// 3D error at the window's last output epoch, m.
    pub error_3d_end_m: f64,
    /// Largest 3D error inside the window, m.
    pub error_3d_max_m: f64,
    /// Whether the run raised an integrity alert.
    pub diverged: bool,
    /// Measurement records not accepted over the run.
    pub rejected: usize,
    /// Measurement records accepted over the run.
    pub accepted: usize,
}

impl WindowFigures {
    /// From a run whose curves hold the window's output epochs only.
    fn of(run: &ImuRun) -> Self {
        let largest = |curve: &[f64]| curve.iter().copied().fold(f64::NAN, f64::max);
        let last = |curve: &[f64]| curve.last().copied().unwrap_or(f64::NAN);
        Self {
            horizontal_end_m: last(&run.horizontal_error),
            horizontal_max_m: largest(&run.horizontal_error),
            error_3d_end_m: last(&run.position_error),
            error_3d_max_m: largest(&run.position_error),
            diverged: run.diverged,
            rejected: run.rejected,
            accepted: run.accepted,
        }
    }
}

/// One cell's figures in one run: the forward filter's, and the
/// smoother's when the navigation settings ask for it.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct CellRun {
    /// The forward filter's figures.
    pub forward: WindowFigures,
    /// The smoother's figures, when the navigation settings smooth.
    pub smoothed: Option<WindowFigures>,
}

/// Runs of [`outage_study_runs`]: `runs[i][c]` is cell c in the i-th run
/// of the range that completed (all of them unless cancelled).
#[derive(Debug, Clone, PartialEq)]
pub struct StudyRuns {
    /// Per completed run, each cell's figures in cell order.
    pub runs: Vec<Vec<CellRun>>,
    /// Whether the range stopped early on the caller's cancel flag.
    pub cancelled: bool,
}

impl OutageStudyConfig {
    /// Checks every setting before any run starts.
    pub fn validate(&self) -> Result<()> {
        if self.navigation.outage.is_some() {
            return Err(Error::invalid(
                "outage",
                "the study sets its own windows: leave the navigation outage None",
            ));
        }
        self.navigation.validate()?;
        validate::non_negative("tail", self.tail_s)?;
        if self.outage_lengths_s.is_empty() || self.visible_satellites.is_empty() {
            return Err(Error::invalid(
                "outage_lengths",
                "needs at least one length and one satellites count",
            ));
        }
        for (k, &n) in self.visible_satellites.iter().enumerate() {
            if n > 3 || self.visible_satellites[..k].contains(&n) {
                return Err(Error::invalid(
                    "visible_satellites",
                    format!(
                        "needs distinct counts from 0 to 3, got {:?}",
                        self.visible_satellites
                    ),
                ));
            }
        }
        for &length in &self.outage_lengths_s {
            validate::positive("outage_lengths", length)?;
            let end = self.outage_start_s + length + self.tail_s;
            if end > self.navigation.duration_s {
                return Err(Error::invalid(
                    "duration",
                    format!(
                        "{} s does not hold the {length} s window from {} s and the {} s after it",
                        self.navigation.duration_s, self.outage_start_s, self.tail_s
                    ),
                ));
            }
            super::validate_outage(&self.window(length, 0), self.navigation.duration_s)?;
        }
        Ok(())
    }

    fn window(&self, length_s: f64, n_visible: usize) -> Outage {
        Outage {
            start_s: self.outage_start_s,
            duration_s: length_s,
            n_satellites: n_visible,
        }
    }
}

/// The study's runs `range` (run i from `random::stream(seed, i)`, as
/// every navigation set) for `cells`, over a rayon pool; cancelling keeps
/// the runs completed in order before it.
pub fn outage_study_runs(
    config: &OutageStudyConfig,
    cells: &[StudyCell],
    range: Range<usize>,
    options: &RunOptions<'_>,
) -> Result<StudyRuns> {
    config.validate()?;
    for c in cells {
        if c.imu >= config.navigation.imus.len()
            || c.length >= config.outage_lengths_s.len()
            || c.visible >= config.visible_satellites.len()
        {
            return Err(Error::invalid(
                "cells",
                format!(
                    "(imu, length, satellites) indices out of range: {:?} with {} IMUs, {} lengths, {} counts",
                    (c.imu, c.length, c.visible),
                    config.navigation.imus.len(),
                    config.outage_lengths_s.len(),
                    config.visible_satellites.len()
                ),
            ));
        }
    }
    let prepared = Prepared::new(&config.navigation)?;
    let mut runs = Vec::with_capacity(range.len());
    let summary = fold_range(
        config.navigation.seed,
        range.clone(),
        16,
        options,
        |_, rng| run_cells(config, &prepared, cells, rng),
        |_, run| {
            runs.push(run);
            Ok(())
        },
    )?;
    Ok(StudyRuns {
        runs,
        cancelled: summary.cancelled,
    })
}

/// One (length, count) of a run: the epochs its window leaves, cut
/// `tail_s` after it, the IMU samples up to there and its output epochs.
struct Cut<'a> {
    length: usize,
    visible: usize,
    epochs: Vec<GnssEpoch>,
    samples: usize,
    out: &'a [usize],
}

impl Cut<'_> {
    /// Whether `cell` asks for this cut of IMU `imu`.
    fn serves(&self, cell: &StudyCell, imu: usize) -> bool {
        cell.imu == imu && cell.length == self.length && cell.visible == self.visible
    }
}

/// One run's figures for every cell.
fn run_cells(
    config: &OutageStudyConfig,
    prepared: &Prepared,
    cells: &[StudyCell],
    rng: &mut Rng,
) -> Result<Vec<CellRun>> {
    let nav = &config.navigation;
    let mut needed = vec![false; nav.imus.len()];
    for c in cells {
        needed[c.imu] = true;
    }
    let draws = run::draw_run(
        nav,
        &prepared.trajectory,
        &prepared.gnss,
        &prepared.sky,
        rng,
        Some(&needed),
    )?;
    let track = ReceiverTrack {
        time_s: &draws.truth.time_s,
        position_ecef: &draws.truth.position_ecef,
        velocity_ecef: &draws.truth.velocity_ecef,
    };
    // One branch per (length, count) a cell asks for: the epochs its
    // window leaves, cut `tail_s` after it, and its output epochs (whole
    // seconds inside [start, start + length), as the navigation sets'
    // folds take them).
    let mut groups = Vec::new();
    for length in 0..config.outage_lengths_s.len() {
        for visible in 0..config.visible_satellites.len() {
            if !cells
                .iter()
                .any(|c| c.length == length && c.visible == visible)
            {
                continue;
            }
            let length_s = config.outage_lengths_s[length];
            let window = config.window(length_s, config.visible_satellites[visible]);
            let end_s = config.outage_start_s + length_s + config.tail_s;
            let mut epochs = draws.epochs.clone();
            epochs.truncate(epochs.partition_point(|e| e.time_s <= end_s));
            apply_outages(&mut epochs, &track, &[window]);
            let inside = |t: &f64| *t >= window.start_s && *t < window.start_s + length_s;
            let first = prepared.time_s.iter().position(inside).unwrap_or(0);
            let count = prepared.time_s[first..]
                .iter()
                .take_while(|t| inside(t))
                .count();
            groups.push(Cut {
                length,
                visible,
                samples: draws.truth.time_s.partition_point(|&t| t <= end_s),
                epochs,
                out: &prepared.out[first..first + count],
            });
        }
    }
    // Every window starts at the same time: each IMU's filter runs to the
    // sample before it once, and on from there. The windows of one count
    // agree up to the shorter one's end, so one pass along the longest
    // serves them all, each cell going on from a copy at its window's end.
    let split = groups
        .iter()
        .filter_map(|g| g.out.first())
        .min()
        .map_or(0, |&k| k.saturating_sub(1));
    let time_s = &draws.truth.time_s;
    let window_end = |length: usize| {
        let end_s = config.outage_start_s + config.outage_lengths_s[length];
        // The last sample before GNSS comes back.
        time_s
            .partition_point(|&t| t < end_s - 1e-6)
            .saturating_sub(1)
            .max(split)
    };
    let setup = nav.filter_setup(Coupling::Tight, &[]);
    let mut out = vec![None; cells.len()];
    for (imu, input) in draws.inputs.iter().enumerate() {
        let Some(input) = input.as_ref() else {
            continue;
        };
        let mut chains = Vec::new();
        for visible in 0..config.visible_satellites.len() {
            let mut mine: Vec<usize> = (0..groups.len())
                .filter(|&g| {
                    groups[g].visible == visible && cells.iter().any(|c| groups[g].serves(c, imu))
                })
                .collect();
            mine.sort_by(|&a, &b| {
                let length = |g: usize| config.outage_lengths_s[groups[g].length];
                length(a).total_cmp(&length(b))
            });
            if !mine.is_empty() {
                chains.push(mine);
            }
        }
        if chains.is_empty() {
            continue;
        }
        let branches: Vec<Vec<Branch>> = chains
            .iter()
            .map(|chain| {
                chain
                    .iter()
                    .map(|&g| Branch {
                        epochs: &groups[g].epochs,
                        samples: groups[g].samples,
                        out: groups[g].out,
                        agrees_until: window_end(groups[g].length),
                    })
                    .collect()
            })
            .collect();
        let runs = navigate_branches(
            &draws.truth,
            &draws.epochs,
            input,
            &draws.start,
            &setup,
            split,
            &branches,
        )?;
        for (chain, chain_runs) in chains.iter().zip(&runs) {
            for (&g, r) in chain.iter().zip(chain_runs) {
                for (c, cell) in cells.iter().enumerate() {
                    if groups[g].serves(cell, imu) {
                        out[c] = Some(CellRun {
                            forward: WindowFigures::of(r),
                            smoothed: r.smoothed.as_deref().map(WindowFigures::of),
                        });
                    }
                }
            }
        }
    }
    Ok(out
        .into_iter()
        .map(|c| c.expect("every cell has a length and a count"))
        .collect())
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::experiments::navigation::paper_imus;
    use crate::experiments::navigation::partial_outage::{
        partial_outage_experiment, PartialOutageConfig,
    };

    fn navigation(smooth: bool) -> NavigationExperimentConfig {
        NavigationExperimentConfig {
            runs: 2,
            duration_s: 70.0,
            seed: 5,
            imus: paper_imus()[..2].to_vec(),
            smooth,
            ..Default::default()
        }
    }

    fn study(smooth: bool) -> OutageStudyConfig {
        OutageStudyConfig {
            navigation: navigation(smooth),
            outage_start_s: 30.0,
            outage_lengths_s: vec![10.0, 30.0],
            visible_satellites: vec![0, 2],
            tail_s: if smooth { 10.0 } else { 0.0 },
        }
    }

    fn all_cells(config: &OutageStudyConfig) -> Vec<StudyCell> {
        let mut cells = Vec::new();
        for imu in 0..config.navigation.imus.len() {
            for length in 0..config.outage_lengths_s.len() {
                for visible in 0..config.visible_satellites.len() {
                    cells.push(StudyCell {
                        imu,
                        length,
                        visible,
                    });
                }
            }
        }
        cells
    }

    /// The forward figures of a cut run are the partial-outage set's on
    /// the whole run (the filter is causal), bit for bit.
    #[test]
    fn forward_figures_equal_the_whole_runs() {
        let config = study(false);
        let cells = all_cells(&config);
        let runs = outage_study_runs(&config, &cells, 0..2, &RunOptions::default()).unwrap();
        assert!(!runs.cancelled);
        for (l, &length_s) in config.outage_lengths_s.iter().enumerate() {
            let whole = partial_outage_experiment(
                &PartialOutageConfig {
                    navigation: navigation(false),
                    outage_start_s: 30.0,
                    outage_length_s: length_s,
                    satellites: config.visible_satellites.clone(),
                    loose: false,
                },
                &RunOptions::default(),
            )
            .unwrap();
            for (c, cell) in cells.iter().enumerate().filter(|(_, c)| c.length == l) {
                let o = &whole.scenarios[cell.visible].imus[cell.imu];
                for (i, run) in runs.runs.iter().enumerate() {
                    let f = run[c].forward;
                    assert_eq!(f.horizontal_end_m, o.run_horizontal_at_outage_end[i]);
                    assert_eq!(f.horizontal_max_m, o.run_max_horizontal_in_outage[i]);
                    assert_eq!(f.error_3d_end_m, o.run_at_outage_end[i]);
                    assert_eq!(f.error_3d_max_m, o.run_max_in_outage[i]);
                    assert!(run[c].smoothed.is_none());
                }
            }
        }
    }

    /// A cell's numbers do not depend on the other cells of the call, nor
    /// on the range the run comes in; through a total outage the MEMS
    /// IMU's smoother, which sees GNSS after the window, stays below the
    /// forward filter's largest error in it (the INS grade's errors there
    /// are the GNSS noise's, both ways).
    #[test]
    fn cells_and_runs_are_independent_and_smoothing_helps() {
        let config = study(true);
        let cells = all_cells(&config);
        let all = outage_study_runs(&config, &cells, 0..2, &RunOptions::default()).unwrap();
        let one = [cells[5]];
        let alone = outage_study_runs(&config, &one, 1..2, &RunOptions::default()).unwrap();
        assert_eq!(alone.runs[0][0], all.runs[1][5]);
        for run in &all.runs {
            for (cell, c) in run.iter().zip(&cells) {
                let s = cell.smoothed.expect("smooth asked");
                if c.imu == 1 && config.visible_satellites[c.visible] == 0 {
                    assert!(s.error_3d_max_m < cell.forward.error_3d_max_m, "{c:?}");
                }
            }
        }
    }

    /// A cell filtered from a copy of the shared beginning equals the
    /// whole run of its epochs from the first sample: the forward figures
    /// bit for bit, the smoothed ones to rounding (the backward pass of the
    /// copy starts after the split; a fixed-interval smoother's estimate
    /// depends on the forward filter from its sample on).
    #[test]
    fn a_branch_equals_the_whole_run_of_its_epochs() {
        let config = study(true);
        let nav = &config.navigation;
        let prepared = Prepared::new(nav).unwrap();
        let mut rng = crate::random::stream(nav.seed, 0);
        let draws = run::draw_run(
            nav,
            &prepared.trajectory,
            &prepared.gnss,
            &prepared.sky,
            &mut rng,
            None,
        )
        .unwrap();
        let track = ReceiverTrack {
            time_s: &draws.truth.time_s,
            position_ecef: &draws.truth.position_ecef,
            velocity_ecef: &draws.truth.velocity_ecef,
        };
        let length_s = config.outage_lengths_s[1];
        let end_s = config.outage_start_s + length_s + config.tail_s;
        let mut epochs = draws.epochs.clone();
        epochs.truncate(epochs.partition_point(|e| e.time_s <= end_s));
        apply_outages(&mut epochs, &track, &[config.window(length_s, 0)]);
        let samples = draws.truth.time_s.partition_point(|&t| t <= end_s);
        let window = |&k: &usize| {
            let t = draws.truth.time_s[k];
            t >= config.outage_start_s && t < config.outage_start_s + length_s
        };
        let out: Vec<usize> = prepared.out.iter().copied().filter(window).collect();
        let mut setup = nav.filter_setup(Coupling::Tight, &out);
        setup.samples = Some(samples);
        for input in draws.inputs.iter().flatten() {
            let whole = super::super::filters::navigate(
                &draws.truth,
                &epochs,
                &[],
                input,
                &draws.start,
                &setup,
            )
            .unwrap();
            let branch = Branch {
                epochs: &epochs,
                samples,
                out: &out,
                agrees_until: samples - 1,
            };
            let split = out[0] - 1;
            let copy = navigate_branches(
                &draws.truth,
                &draws.epochs,
                input,
                &draws.start,
                &setup,
                split,
                &[vec![branch]],
            )
            .unwrap()
            .remove(0)
            .remove(0);
            assert_eq!(copy.position_error, whole.position_error);
            assert_eq!(copy.nees, whole.nees);
            assert_eq!(
                (copy.accepted, copy.rejected),
                (whole.accepted, whole.rejected)
            );
            let (a, b) = (copy.smoothed.unwrap(), whole.smoothed.unwrap());
            for (x, y) in a.position_error.iter().zip(&b.position_error) {
                assert!((x - y).abs() < 1e-6 * (1.0 + y), "{x} against {y}");
            }
            assert_eq!(a.position_error.len(), out.len());
            // The split may not be at or after an output epoch.
            let late = Branch {
                epochs: &epochs,
                samples,
                out: &out,
                agrees_until: samples - 1,
            };
            let e = navigate_branches(
                &draws.truth,
                &draws.epochs,
                input,
                &draws.start,
                &setup,
                out[0],
                &[vec![late]],
            )
            .unwrap_err();
            assert!(e.to_string().contains("branches"), "{e}");
        }
    }

    #[test]
    fn bad_settings_name_the_argument() {
        let mut config = study(false);
        config.navigation.duration_s = 50.0;
        let e = outage_study_runs(&config, &[], 0..1, &RunOptions::default()).unwrap_err();
        assert!(e.to_string().contains("duration"), "{e}");
        let config = study(false);
        let cell = StudyCell {
            imu: 9,
            length: 0,
            visible: 0,
        };
        let e = outage_study_runs(&config, &[cell], 0..1, &RunOptions::default()).unwrap_err();
        assert!(e.to_string().contains("cells"), "{e}");
        let mut config = study(false);
        config.visible_satellites = vec![2, 2];
        let e = outage_study_runs(&config, &[], 0..1, &RunOptions::default()).unwrap_err();
        assert!(e.to_string().contains("visible_satellites"), "{e}");
    }
}
