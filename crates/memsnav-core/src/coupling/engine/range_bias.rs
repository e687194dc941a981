//! Per-satellite pseudorange-bias states: which satellite holds which
//! slot of a filter with range-bias states (see [`crate::coupling::RangeBiasModel`]
//! for the process).
//!
//! A satellite seen for the first time takes a free slot, or the slot of
//! the satellite seen longest ago when none is free (not one seen at this
//! epoch); the slot's state restarts from zero with the initial range-bias
//! variance and no correlation with anything (a new, independent bias).
//! A satellite that finds no slot (more satellites at one epoch than
//! slots) is used with its bias variance added to its noise instead.

use nalgebra::{Matrix1, Vector3};

use super::FilterState;
use crate::filter::state::{Layout, MAX_RANGE_BIAS_SLOTS};

/// The satellite in each slot and when it was last used (the layout's
/// first `range_bias_slots` entries are the slots).
#[derive(Debug, Clone, Copy)]
pub(crate) struct RangeBiasSlots {
    holder: [Option<(u16, f64)>; MAX_RANGE_BIAS_SLOTS],
}

impl Default for RangeBiasSlots {
    /// Every slot free.
    fn default() -> Self {
        Self {
            holder: [None; MAX_RANGE_BIAS_SLOTS],
        }
    }
}

impl<const N: usize> FilterState<N> {
    /// The state index of `sat_id`'s range bias at `time_s` (a slot taken
    /// or assigned) and its current estimate, m; `None` when the filter has
    /// no range-bias states or every slot is held by a satellite used at
    /// this epoch.
    pub(crate) fn range_bias_state(&mut self, sat_id: u16, time_s: f64) -> Option<(usize, f64)> {
        let layout = Layout::for_size::<N>();
        let first = layout.range_bias?;
        let holders = &mut self.slots.holder[..layout.range_bias_slots];
        if let Some(k) = holders
            .iter()
            .position(|h| h.is_some_and(|(s, _)| s == sat_id))
        {
            holders[k] = Some((sat_id, time_s));
            return Some((first + k, self.range_bias_m[k]));
        }
        let k = match holders.iter().position(Option::is_none) {
            Some(k) => k,
            None => {
                let (k, (_, last)) = holders
                    .iter()
                    .enumerate()
                    .filter_map(|(k, h)| h.map(|h| (k, h)))
                    .min_by(|a, b| a.1 .1.total_cmp(&b.1 .1))?;
                if last >= time_s {
                    return None;
                }
                k
            }
        };
        holders[k] = Some((sat_id, time_s));
        self.range_bias_m[k] = 0.0;
        let variance = self.tuning.initial_std.range_bias_m.powi(2);
        self.kf.reset_block::<1>(first + k, &Matrix1::new(variance));
        Some((first + k, 0.0))
    }

    /// Loose coupling's fix-error states: the state index of the error of
    /// each ECEF axis (slot holders 0, 1, 2) and the estimate, m; `None`
    /// without range-bias states. Three of the slots, never contested.
    pub(crate) fn fix_error_states(&mut self, time_s: f64) -> Option<([usize; 3], Vector3<f64>)> {
        let mut states = [0; 3];
        let mut estimate = Vector3::zeros();
        for axis in 0..3 {
            let (state, value) = self.range_bias_state(axis as u16, time_s)?;
            states[axis] = state;
            estimate[axis] = value;
        }
        Some((states, estimate))
    }

    /// The satellite holding each range-bias slot and its bias estimate, m
    /// (loose coupling: the fix error of ECEF axis 0, 1, 2).
    pub fn range_biases(&self) -> impl Iterator<Item = (u16, f64)> + '_ {
        self.slots
            .holder
            .iter()
            .zip(self.range_bias_m)
            .filter_map(|(h, b)| h.map(|(s, _)| (s, b)))
    }
}
