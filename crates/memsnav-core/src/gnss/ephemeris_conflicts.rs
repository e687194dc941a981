//! One ephemeris per satellite and t_oc, and per satellite and issue of
//! data: the rule every reader of broadcast ephemerides (RINEX navigation
//! files, UBX logs) applies, so they keep the same set.
//!
//! A merged file or a long log holds the same ephemeris more than once:
//! copies whose values all agree (the transmission time, and Galileo's data
//! sources, apart) are one ephemeris, kept once. Two that disagree cannot
//! both have been broadcast: a satellite sends one set per t_oc, and GPS
//! and Galileo change the issue of data (IODE, IODnav) with every new set
//! (IS-GPS-200 §20.3.4.4, Galileo OS SIS ICD §5.1.9.2). Choosing one would
//! be a guess of which was, and the ephemeris selection would silently take
//! whichever came first; so every member of such a conflict is left out and
//! counted. BeiDou's AODE is the data's age, not a name: sets of one age
//! with different t_oe are normal, and only the t_oc rule applies.

use std::collections::{BTreeMap, HashMap};

use super::nav_record::NavRecord;

/// Index of the transmission time in a record, the one value two copies of
/// the same ephemeris may disagree on: a merged file keeps the time each
/// station received it.
const TRANSMISSION_TIME: usize = 27;

/// Galileo's data sources, which copies of one ephemeris received on E1-B
/// and on E5b differ in.
const GALILEO_DATA_SOURCES: usize = 20;

/// Two sets of one issue of data whose t_oe lie this close (s) are in
/// conflict: 4 h, the shortest fit interval (IS-GPS-200 §20.3.4.4), in
/// which a receiver could be using either. Further apart, an issue of data
/// may come back.
pub(crate) const ISSUE_OF_DATA_WINDOW_S: f64 = 4.0 * 3600.0;

/// Reason counted for records sharing satellite and t_oc with other values.
pub(crate) const SAME_TOC: &str =
    "ephemerides in conflict (same satellite and t_oc, other values): none of them used";

/// Reason counted for records sharing satellite and issue of data with
/// another t_oe.
pub(crate) const SAME_ISSUE_OF_DATA: &str =
    "ephemerides in conflict (same satellite and issue of data, another t_oe): none of them used";

/// The index of the first value two records of one satellite disagree on
/// (the transmission time, and Galileo's data sources, apart).
fn first_difference(a: &NavRecord, b: &NavRecord) -> Option<usize> {
    let galileo = a.system.letter == 'E';
    (0..a.values.len().max(b.values.len())).find(|&i| {
        i != TRANSMISSION_TIME
            && !(galileo && i == GALILEO_DATA_SOURCES)
            && a.values.get(i) != b.values.get(i)
    })
}

/// The records to keep (`true`), in the order given, and the records left
/// out by reason: later copies of one ephemeris are dropped without a
/// count, every member of a conflict is dropped and counted.
pub(crate) fn resolve(records: &[NavRecord]) -> (Vec<bool>, BTreeMap<String, usize>) {
    let mut keep = vec![true; records.len()];
    let mut in_conflict = vec![false; records.len()];
    // First record of each satellite and t_oc.
    let mut by_toc: HashMap<(&str, u64), usize> = HashMap::new();
    for (k, r) in records.iter().enumerate() {
        match by_toc.get(&(r.sat.as_str(), r.toc_gps_s.to_bits())) {
            None => {
                by_toc.insert((r.sat.as_str(), r.toc_gps_s.to_bits()), k);
            }
            Some(&first) => {
                keep[k] = false;
                if first_difference(&records[first], r).is_some() {
                    in_conflict[first] = true;
                    in_conflict[k] = true;
                }
            }
        }
    }
    let mut counts = BTreeMap::new();
    let toc_conflicts = in_conflict.iter().filter(|&&c| c).count();
    if toc_conflicts > 0 {
        counts.insert(SAME_TOC.to_string(), toc_conflicts);
    }
    // Among the distinct ephemerides, those of one issue of data.
    let mut by_issue: HashMap<(&str, u16), Vec<usize>> = HashMap::new();
    for (k, r) in records.iter().enumerate() {
        if let (true, Some(iod)) = (keep[k], r.issue_of_data) {
            by_issue.entry((r.sat.as_str(), iod)).or_default().push(k);
        }
    }
    let mut iod_conflicts = 0;
    for members in by_issue.values() {
        for (n, &a) in members.iter().enumerate() {
            for &b in &members[n + 1..] {
                let dt = (records[a].toe_gps_s - records[b].toe_gps_s).abs();
                if dt > 0.0 && dt <= ISSUE_OF_DATA_WINDOW_S {
                    for k in [a, b] {
                        if !in_conflict[k] {
                            in_conflict[k] = true;
                            iod_conflicts += 1;
                        }
                    }
                }
            }
        }
    }
    if iod_conflicts > 0 {
        counts.insert(SAME_ISSUE_OF_DATA.to_string(), iod_conflicts);
    }
    for (k, c) in in_conflict.iter().enumerate() {
        if *c {
            keep[k] = false;
        }
    }
    (keep, counts)
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::gnss::{BEIDOU, GPS};

    fn record(sat: &str, toc: f64, toe: f64, iod: Option<u16>, crs: f64) -> NavRecord {
        let mut values = vec![0.0; 29];
        values[4] = crs;
        values[TRANSMISSION_TIME] = toc - 30.0 + crs;
        NavRecord {
            sat: sat.into(),
            system: if sat.starts_with('C') { &BEIDOU } else { &GPS },
            toc_gps_s: toc,
            toe_gps_s: toe,
            issue_of_data: iod,
            values,
        }
    }

    #[test]
    fn copies_are_kept_once_and_conflicts_left_out() {
        let t = 1.4e9;
        let mut copy = record("G23", t, t, Some(77), 10.0);
        copy.values[TRANSMISSION_TIME] += 6.0;
        let records = [
            record("G23", t, t, Some(77), 10.0),
            copy,
            // Same t_oc, another Crs: both G05 records are left out.
            record("G05", t, t, Some(3), 10.0),
            record("G05", t, t, Some(3), 11.0),
            // Same IODE, t_oe 2 h later: both left out; 8 h later: kept.
            record("G07", t, t, Some(9), 10.0),
            record("G07", t + 7200.0, t + 7200.0, Some(9), 10.0),
            record("G08", t, t, Some(9), 10.0),
            record("G08", t + 28_800.0, t + 28_800.0, Some(9), 10.0),
            // BeiDou's AODE is an age: one AODE, two t_oe, both kept.
            record("C21", t, t, None, 10.0),
            record("C21", t + 3600.0, t + 3600.0, None, 12.0),
        ];
        let (keep, counts) = resolve(&records);
        assert_eq!(
            keep,
            [true, false, false, false, false, false, true, true, true, true]
        );
        assert_eq!(counts[SAME_TOC], 2);
        assert_eq!(counts[SAME_ISSUE_OF_DATA], 2);
    }
}
