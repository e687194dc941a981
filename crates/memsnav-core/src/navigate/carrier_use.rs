//! What a run did with the carrier phase it was asked to use: its carrier
//! changes between epochs counted by fate, and a warning when none was
//! applied (carrier phase on and doing nothing must not pass unsaid).

use crate::coupling::{MeasurementKind, MeasurementRecord, MeasurementStatus};

/// A run's carrier changes by fate (one per satellite and epoch that had a
/// carrier at the previous epoch too).
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default)]
pub struct CarrierUse {
    /// Every carrier change recorded.
    pub changes: usize,
    /// Applied to the filter.
    pub used: usize,
    /// Held a cycle slip (receiver flag, or the Doppler test).
    pub slips: usize,
    /// Left out by the residual test against the INS.
    pub excluded: usize,
    /// Clean, but their epoch had too few clean changes for a batch.
    pub too_few: usize,
    /// Any other fate: their batch failed its gate, an invalid value, a
    /// reset.
    pub rejected: usize,
}

impl CarrierUse {
    /// The counts of the carrier-phase records among `records`.
    pub fn of(records: &[MeasurementRecord]) -> Self {
        let mut u = Self::default();
        for r in records
            .iter()
            .filter(|r| r.kind == MeasurementKind::CarrierPhase)
        {
            u.changes += 1;
            match r.status {
                MeasurementStatus::Accepted => u.used += 1,
                MeasurementStatus::CycleSlip => u.slips += 1,
                MeasurementStatus::Excluded => u.excluded += 1,
                MeasurementStatus::TooFewCarrierChanges => u.too_few += 1,
                _ => u.rejected += 1,
            }
        }
        u
    }

    /// The warning of a run that asked for carrier phase and applied none,
    /// naming the main reason.
    pub fn warning(&self) -> Option<String> {
        if self.used > 0 {
            return None;
        }
        let reason = if self.changes == 0 {
            "the measurements hold no carrier phase (carrier_phase_std = 0, no L observation, \
             or no satellite tracked over two epochs)"
                .to_string()
        } else if self.too_few >= self.slips.max(self.excluded).max(self.rejected) {
            format!(
                "{} of the {} changes passed the slip tests but no epoch had the 5 clean \
                 changes a batch needs (velocity, the clock's change and one to test them): \
                 use more satellites (other systems, or no satellite selection)",
                self.too_few, self.changes
            )
        } else {
            format!(
                "{} of the {} changes held cycle slips, {} failed the residual test, {} were \
                 rejected by their batch",
                self.slips, self.changes, self.excluded, self.rejected
            )
        };
        Some(format!(
            "carrier phase was asked for (gnss.carrier_phase) but no carrier change was used: \
             {reason}; the solution is the code-only one"
        ))
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn record(kind: MeasurementKind, status: MeasurementStatus) -> MeasurementRecord {
        MeasurementRecord {
            time_s: 0.0,
            id: 10,
            kind,
            innovation: 0.0,
            innovation_std: 1.0,
            nis: 0.0,
            status,
        }
    }

    #[test]
    fn counts_each_fate_and_only_carrier_records() {
        use MeasurementStatus as S;
        let records = [
            record(MeasurementKind::CarrierPhase, S::Accepted),
            record(MeasurementKind::CarrierPhase, S::CycleSlip),
            record(MeasurementKind::CarrierPhase, S::TooFewCarrierChanges),
            record(MeasurementKind::CarrierPhase, S::TooFewCarrierChanges),
            record(MeasurementKind::CarrierPhase, S::RejectedByGate),
            record(MeasurementKind::Pseudorange, S::CycleSlip),
        ];
        let u = CarrierUse::of(&records);
        assert_eq!(
            u,
            CarrierUse {
                changes: 5,
                used: 1,
                slips: 1,
                excluded: 0,
                too_few: 2,
                rejected: 1,
            }
        );
        assert_eq!(u.warning(), None);
    }

    #[test]
    fn a_run_with_none_used_is_told_why() {
        let too_few = CarrierUse {
            changes: 10,
            too_few: 8,
            slips: 2,
            ..Default::default()
        };
        let w = too_few.warning().unwrap();
        assert!(w.contains("no epoch had the 5 clean changes"), "{w}");
        let none = CarrierUse::default().warning().unwrap();
        assert!(none.contains("hold no carrier phase"), "{none}");
        let slips = CarrierUse {
            changes: 10,
            slips: 9,
            too_few: 1,
            ..Default::default()
        };
        assert!(slips
            .warning()
            .unwrap()
            .contains("9 of the 10 changes held cycle slips"));
    }
}
