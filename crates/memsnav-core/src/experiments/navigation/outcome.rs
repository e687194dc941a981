//! What a navigation Monte Carlo keeps of each IMU: per-epoch statistics
//! of the error curves over the runs, folded in run order, and per-run
//! scalars.

use crate::montecarlo::{CurveStats, PERCENTILES};
use crate::Result;

use super::filters::{ImuRun, NEES_DOF};

/// One IMU's results over the completed runs.
#[derive(Debug, Clone, PartialEq)]
pub struct ImuOutcome {
    /// The IMU's name in the configuration.
    pub name: String,
    /// Per epoch: mean over runs of the position error norm, m.
    pub position_error_mean: Vec<f64>,
    /// Per epoch: its sample standard deviation over runs (NaN for one run), m.
    pub position_error_std: Vec<f64>,
    /// Per epoch: its percentiles [`PERCENTILES`] (P² estimates), m.
    pub position_error_percentiles: Vec<Vec<f64>>,
    /// Per epoch: mean over runs of the NEES (9 dof).
    pub nees_mean: Vec<f64>,
    /// Per epoch: mean over runs of the position NEES (3 dof).
    pub position_nees_mean: Vec<f64>,
    /// Every run's position error norm per epoch (only with `keep_runs`).
    pub position_error_runs: Vec<Vec<f64>>,
    /// Every run's NEES per epoch (only with `keep_runs`).
    pub nees_runs: Vec<Vec<f64>>,
    /// Per run: RMS of the position error norm over the whole run, m.
    pub run_rms: Vec<f64>,
    /// Per run: RMS over the epochs t ≤ `early_window_s`, m.
    pub run_rms_early: Vec<f64>,
    /// Per run: RMS over the epochs after the early window, m (NaN when
    /// the run has none).
    pub run_rms_late: Vec<f64>,
    /// Per run: position error norm at the last epoch, m.
    pub run_final: Vec<f64>,
    /// Per run: largest error norm at the epochs inside the outage window
    /// [start, start + length) — before the first update after it (NaN
    /// without outage), m.
    pub run_max_in_outage: Vec<f64>,
    /// Per run: the same for the horizontal part of the error (local NED
    /// of the true position), m.
    pub run_max_horizontal_in_outage: Vec<f64>,
    /// Per run: the same for the vertical part, m.
    pub run_max_vertical_in_outage: Vec<f64>,
    /// Per run: the error norm at the last epoch inside the outage window,
    /// before GNSS returns (NaN without outage), m.
    pub run_at_outage_end: Vec<f64>,
    /// Per run: its horizontal part, m.
    pub run_horizontal_at_outage_end: Vec<f64>,
    /// Per run: mean NEES per degree of freedom over the epochs.
    pub run_mean_nees_per_dof: Vec<f64>,
    /// Per run: position NEES per degree of freedom at the last epoch
    /// inside the outage window (NaN without outage).
    pub run_position_nees_per_dof_at_outage_end: Vec<f64>,
    /// Per run: whether the run raised an integrity alert (its solution
    /// flagged as not trustworthy, `coupling::integrity`).
    pub run_diverged: Vec<bool>,
    /// Per run: measurements rejected by the gate or as invalid.
    pub run_rejected: Vec<usize>,
    /// Per run: scalar measurements applied (pseudoranges, and rates when
    /// used; fix components for loose coupling).
    pub run_accepted: Vec<usize>,
    /// The same statistics of the smoothed solution (NEES NaN), when the
    /// set was run with `smooth`.
    pub smoothed: Option<Box<ImuOutcome>>,
}

fn rms(values: &[f64]) -> f64 {
    (values.iter().map(|v| v * v).sum::<f64>() / values.len() as f64).sqrt()
}

/// Folds the runs of one IMU into an [`ImuOutcome`].
pub struct OutcomeFold {
    outcome: ImuOutcome,
    position: CurveStats,
    nees: CurveStats,
    position_nees: CurveStats,
    /// Epochs of the early window (t ≤ early window): the first `early`.
    early: usize,
    /// Epochs inside the outage window.
    in_outage: Vec<usize>,
    keep_runs: bool,
    /// The fold of the smoothed curves, created by the first smoothed run.
    smoothed: Option<Box<OutcomeFold>>,
    /// What [`Self::new`] was given, to create `smoothed` alike.
    time_s: Vec<f64>,
    early_window_s: f64,
    outage_window: Option<(f64, f64)>,
}

impl OutcomeFold {
    /// A fold over curves of `epochs` epochs at times `time_s`.
    pub(super) fn new(
        name: &str,
        time_s: &[f64],
        early_window_s: f64,
        outage_window: Option<(f64, f64)>,
        keep_runs: bool,
    ) -> Self {
        let epochs = time_s.len();
        Self {
            outcome: ImuOutcome {
                name: name.to_string(),
                position_error_mean: Vec::new(),
                position_error_std: Vec::new(),
                position_error_percentiles: Vec::new(),
                nees_mean: Vec::new(),
                position_nees_mean: Vec::new(),
                position_error_runs: Vec::new(),
                nees_runs: Vec::new(),
                run_rms: Vec::new(),
                run_rms_early: Vec::new(),
                run_rms_late: Vec::new(),
                run_final: Vec::new(),
                run_max_in_outage: Vec::new(),
                run_max_horizontal_in_outage: Vec::new(),
                run_max_vertical_in_outage: Vec::new(),
                run_at_outage_end: Vec::new(),
                run_horizontal_at_outage_end: Vec::new(),
                run_mean_nees_per_dof: Vec::new(),
                run_position_nees_per_dof_at_outage_end: Vec::new(),
                run_diverged: Vec::new(),
                run_rejected: Vec::new(),
                run_accepted: Vec::new(),
                smoothed: None,
            },
            position: CurveStats::new(epochs),
            nees: CurveStats::new(epochs),
            position_nees: CurveStats::new(epochs),
            early: time_s.iter().take_while(|t| **t <= early_window_s).count(),
            in_outage: match outage_window {
                Some((start, length)) => (0..epochs)
                    .filter(|&m| time_s[m] >= start && time_s[m] < start + length)
                    .collect(),
                None => Vec::new(),
            },
            keep_runs,
            smoothed: None,
            time_s: time_s.to_vec(),
            early_window_s,
            outage_window,
        }
    }

    /// Adds the next run (runs come in run order).
    pub(super) fn push(&mut self, mut r: ImuRun) -> Result<()> {
        if let Some(smoothed) = r.smoothed.take() {
            let (name, time_s) = (&self.outcome.name, &self.time_s);
            let (early, window, keep) = (self.early_window_s, self.outage_window, self.keep_runs);
            self.smoothed
                .get_or_insert_with(|| Box::new(Self::new(name, time_s, early, window, keep)))
                .push(*smoothed)?;
        }
        let o = &mut self.outcome;
        let epochs = r.position_error.len();
        self.position.push(&r.position_error)?;
        self.nees.push(&r.nees)?;
        self.position_nees.push(&r.position_nees)?;
        o.run_rms.push(rms(&r.position_error));
        o.run_rms_early.push(rms(&r.position_error[..self.early]));
        o.run_rms_late.push(rms(&r.position_error[self.early..]));
        o.run_final.push(r.position_error[epochs - 1]);
        let max_in_outage = |curve: &[f64]| {
            self.in_outage
                .iter()
                .map(|&m| curve[m])
                .fold(f64::NAN, f64::max)
        };
        o.run_max_in_outage.push(max_in_outage(&r.position_error));
        o.run_max_horizontal_in_outage
            .push(max_in_outage(&r.horizontal_error));
        o.run_max_vertical_in_outage
            .push(max_in_outage(&r.vertical_error));
        let at_end = |curve: &[f64]| self.in_outage.last().map_or(f64::NAN, |&m| curve[m]);
        o.run_at_outage_end.push(at_end(&r.position_error));
        o.run_horizontal_at_outage_end
            .push(at_end(&r.horizontal_error));
        o.run_mean_nees_per_dof
            .push(r.nees.iter().sum::<f64>() / (epochs * NEES_DOF) as f64);
        o.run_position_nees_per_dof_at_outage_end
            .push(at_end(&r.position_nees) / 3.0);
        o.run_diverged.push(r.diverged);
        o.run_rejected.push(r.rejected);
        o.run_accepted.push(r.accepted);
        if self.keep_runs {
            o.position_error_runs.push(r.position_error);
            o.nees_runs.push(r.nees);
        }
        Ok(())
    }

    /// The outcome with its per-epoch statistics.
    pub(super) fn finish(self) -> ImuOutcome {
        let mut o = self.outcome;
        o.position_error_mean = self.position.mean().to_vec();
        o.position_error_std = self.position.std();
        o.position_error_percentiles = (0..PERCENTILES.len())
            .map(|i| self.position.percentile(i))
            .collect();
        o.nees_mean = self.nees.mean().to_vec();
        o.position_nees_mean = self.position_nees.mean().to_vec();
        o.smoothed = self.smoothed.map(|f| Box::new(f.finish()));
        o
    }
}
