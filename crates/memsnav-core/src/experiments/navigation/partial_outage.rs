//! The partial-outage study: the urban canyon the paper's conclusion
//! names as the critical case. Through one window of `outage_length_s`
//! the receiver keeps 0, 1, 2 or 3 satellites (the highest: the worst
//! horizontal geometry, [`crate::gnss::simulate`]); every IMU of the set
//! crosses it with the tightly coupled filter for each count, and with the
//! loosely coupled filter, which has no fix below 4 satellites.
//!
//! All scenarios of a run share its draws (`super::run::draw_run`: the
//! trajectory, one GNSS simulation, the initial errors and each IMU's
//! readings); they differ only by the satellites the window removes from
//! that simulation ([`crate::gnss::apply_outages`]), so the comparison is
//! paired and the study costs one trajectory per run.

use crate::gnss::{apply_outages, Outage, ReceiverTrack};
use crate::montecarlo::{self, FoldSummary, MonteCarlo, RunOptions};
use crate::random::Rng;
use crate::{validate, Error, Result};

use super::filters::{navigate, position_fixes, Coupling, ImuRun};
use super::outcome::{ImuOutcome, OutcomeFold};
use super::{run, NavigationExperimentConfig, Prepared};

/// What [`partial_outage_experiment`] runs.
#[derive(Debug, Clone, PartialEq)]
pub struct PartialOutageConfig {
    /// Runs, seed, IMUs and every filter and simulation setting; its
    /// `outage` must be `None` and its `coupling` is not used (default:
    /// the navigation defaults with 180 s runs).
    pub navigation: NavigationExperimentConfig,
    /// Start of the window, s (default 100: the filters converge within
    /// about 30 s).
    pub outage_start_s: f64,
    /// Length of the window, s (default 60).
    pub outage_length_s: f64,
    /// Satellites kept in the window, one tightly coupled scenario each
    /// (default 0, 1, 2, 3).
    pub satellites: Vec<usize>,
    /// Whether to add the loosely coupled scenario (3 satellites kept: no
    /// fix, so the filter is blind through the window; default true).
    pub loose: bool,
}

impl Default for PartialOutageConfig {
    fn default() -> Self {
        Self {
            navigation: NavigationExperimentConfig {
                duration_s: 180.0,
                ..Default::default()
            },
            outage_start_s: 100.0,
            outage_length_s: 60.0,
            satellites: vec![0, 1, 2, 3],
            loose: true,
        }
    }
}

/// One scenario: a coupling and the satellites kept in the window.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Scenario {
    /// Tight or loose coupling.
    pub coupling: Coupling,
    /// Satellites kept in the outage window (0: a total outage).
    pub n_visible: usize,
}

impl PartialOutageConfig {
    /// Checks every setting before any run starts.
    pub fn validate(&self) -> Result<()> {
        if self.navigation.outage.is_some() {
            return Err(Error::invalid(
                "outage",
                "the study sets its own window: leave the navigation outage None",
            ));
        }
        self.navigation.validate()?;
        if self.satellites.is_empty() && !self.loose {
            return Err(Error::invalid("satellites", "no scenario to run"));
        }
        for (k, &n) in self.satellites.iter().enumerate() {
            if n > 3 || self.satellites[..k].contains(&n) {
                return Err(Error::invalid(
                    "satellites",
                    format!(
                        "needs distinct counts from 0 to 3, got {:?}",
                        self.satellites
                    ),
                ));
            }
        }
        validate::positive("outage_length", self.outage_length_s)?;
        let o = self.outage(0);
        super::validate_outage(&o, self.navigation.duration_s)
    }

    fn outage(&self, n_visible: usize) -> Outage {
        Outage {
            start_s: self.outage_start_s,
            duration_s: self.outage_length_s,
            n_satellites: n_visible,
        }
    }

    /// The scenarios in result order: tight for each count, then loose.
    pub fn scenarios(&self) -> Vec<Scenario> {
        let mut out: Vec<Scenario> = self
            .satellites
            .iter()
            .map(|&n_visible| Scenario {
                coupling: Coupling::Tight,
                n_visible,
            })
            .collect();
        if self.loose {
            out.push(Scenario {
                coupling: Coupling::Loose,
                n_visible: 3,
            });
        }
        out
    }
}

/// One scenario's results, per IMU in the configuration's order.
#[derive(Debug, Clone, PartialEq)]
pub struct ScenarioOutcome {
    /// The scenario.
    pub scenario: Scenario,
    /// Each IMU's results.
    pub imus: Vec<ImuOutcome>,
}

/// Results of [`partial_outage_experiment`].
#[derive(Debug, Clone, PartialEq)]
pub struct PartialOutageExperiment {
    /// Output epochs, s from the start (0, 1, …).
    pub time_s: Vec<f64>,
    /// Each scenario's results.
    pub scenarios: Vec<ScenarioOutcome>,
    /// Runs completed (all unless cancelled).
    pub completed_runs: usize,
    /// Whether the set was cancelled before the end.
    pub cancelled: bool,
}

/// The partial-outage study as runs and a fold ([`MonteCarlo`]).
pub struct PartialOutageRuns<'a> {
    config: &'a PartialOutageConfig,
    prepared: Prepared,
    scenarios: Vec<Scenario>,
}

impl<'a> PartialOutageRuns<'a> {
    /// Checks the configuration and prepares what the runs share.
    pub fn new(config: &'a PartialOutageConfig) -> Result<Self> {
        config.validate()?;
        Ok(Self {
            prepared: Prepared::new(&config.navigation)?,
            scenarios: config.scenarios(),
            config,
        })
    }
}

impl MonteCarlo for PartialOutageRuns<'_> {
    /// Per scenario, per IMU.
    type Run = Vec<Vec<ImuRun>>;
    type Fold = Vec<Vec<OutcomeFold>>;
    type Output = PartialOutageExperiment;

    fn seed(&self) -> u64 {
        self.config.navigation.seed
    }
    fn runs(&self) -> usize {
        self.config.navigation.runs
    }
    fn batch(&self) -> usize {
        16
    }
    fn run(&self, _: usize, rng: &mut Rng) -> Result<Self::Run> {
        let (nav, p) = (&self.config.navigation, &self.prepared);
        let draws = run::draw_run(nav, &p.trajectory, &p.gnss, &p.sky, rng, None)?;
        let track = ReceiverTrack {
            time_s: &draws.truth.time_s,
            position_ecef: &draws.truth.position_ecef,
            velocity_ecef: &draws.truth.velocity_ecef,
        };
        self.scenarios
            .iter()
            .map(|s| {
                let mut epochs = draws.epochs.clone();
                apply_outages(&mut epochs, &track, &[self.config.outage(s.n_visible)]);
                let fixes = match s.coupling {
                    Coupling::Tight => Vec::new(),
                    Coupling::Loose => position_fixes(&epochs),
                };
                let setup = nav.filter_setup(s.coupling, &p.out);
                draws
                    .inputs
                    .iter()
                    .flatten()
                    .map(|input| {
                        navigate(&draws.truth, &epochs, &fixes, input, &draws.start, &setup)
                    })
                    .collect()
            })
            .collect()
    }
    fn start(&self) -> Self::Fold {
        let window = Some((self.config.outage_start_s, self.config.outage_length_s));
        self.scenarios
            .iter()
            .map(|_| self.prepared.folds(&self.config.navigation, window))
            .collect()
    }
    fn push(&self, folds: &mut Self::Fold, _: usize, runs: Self::Run) -> Result<()> {
        for (scenario, scenario_runs) in folds.iter_mut().zip(runs) {
            for (fold, r) in scenario.iter_mut().zip(scenario_runs) {
                fold.push(r)?;
            }
        }
        Ok(())
    }
    fn finish(&self, folds: Self::Fold, summary: FoldSummary) -> Result<PartialOutageExperiment> {
        Ok(PartialOutageExperiment {
            time_s: self.prepared.time_s.clone(),
            scenarios: self
                .scenarios
                .iter()
                .zip(folds)
                .map(|(&scenario, f)| ScenarioOutcome {
                    scenario,
                    imus: f.into_iter().map(OutcomeFold::finish).collect(),
                })
                .collect(),
            completed_runs: summary.completed,
            cancelled: summary.cancelled,
        })
    }
}

/// Runs the partial-outage study (module docs).
pub fn partial_outage_experiment(
    config: &PartialOutageConfig,
    options: &RunOptions<'_>,
) -> Result<PartialOutageExperiment> {
    montecarlo::execute(&PartialOutageRuns::new(config)?, options)
}

#[cfg(test)]
mod tests {
    use super::*;

    /// A 60 s window on 100 s runs: the tight scenarios keep their counts
    /// through the window (pseudoranges and rates), the loose filter gets
    /// no fix inside it, and keeping 3 satellites holds the raw MEMS error
    /// far below the total outage's.
    #[test]
    fn satellites_in_the_window_hold_the_error_down() {
        let config = PartialOutageConfig {
            navigation: NavigationExperimentConfig {
                runs: 3,
                duration_s: 100.0,
                imus: super::super::paper_imus()[1..2].to_vec(),
                ..Default::default()
            },
            outage_start_s: 30.0,
            outage_length_s: 60.0,
            ..Default::default()
        };
        let r = partial_outage_experiment(
            &config,
            &RunOptions {
                threads: Some(2),
                ..Default::default()
            },
        )
        .unwrap();
        assert_eq!(r.scenarios.len(), 5);
        let max = |k: usize| {
            let runs = &r.scenarios[k].imus[0].run_max_in_outage;
            runs.iter().sum::<f64>() / runs.len() as f64
        };
        let accepted = |k: usize| r.scenarios[k].imus[0].run_accepted[0];
        // Outside the window all 6 satellites; inside n: 2 measurements each
        // per epoch (41 epochs outside, 60 inside), accepted or gated.
        for (k, n) in [0usize, 1, 2, 3].iter().enumerate() {
            let total = accepted(k) + r.scenarios[k].imus[0].run_rejected[0];
            assert_eq!(total, 2 * (6 * 41 + n * 60), "{n} satellites");
        }
        assert!(
            max(3) < 0.3 * max(0),
            "3 satellites {} vs none {}",
            max(3),
            max(0)
        );
        // Loose: blind in the window, like the total outage of the tight filter.
        assert!(
            max(4) > 0.5 * max(0),
            "loose {} vs tight none {}",
            max(4),
            max(0)
        );
    }
}
