//! A run's solution as people read it: at the antenna, in local terms
//! ([`LocalSolution`]).

use super::run::LogRun;
use crate::output::LocalSolution;

impl LogRun {
    /// The solution at the antenna in local terms (see [`LocalSolution`]).
    pub fn local_solution(&self) -> LocalSolution {
        LocalSolution::new(&self.solution, self.antenna_lever_arm_b_m)
    }

    /// The smoothed solution at the antenna in local terms, when there is one.
    pub fn local_smoothed(&self) -> Option<LocalSolution> {
        self.smoothed
            .as_ref()
            .map(|s| LocalSolution::new(s, self.antenna_lever_arm_b_m))
    }
}
