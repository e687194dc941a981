//! One constellation type for the simulator: GPS broadcast ephemerides or
//! synthetic Walker patterns, one per satellite system.

use std::path::Path;

use nalgebra::Vector3;

use super::ephemeris::GpsEphemeris;
use super::rinex_nav::read_rinex_nav;
use super::satellite_state::SatelliteState;
use super::system::{satellite_number, GnssSystem};
use super::walker::{Walker, WalkerConfig};
use crate::{validate, Error, Result};

/// Half-width of the window around t_oe in which a broadcast ephemeris is
/// used, s (IS-GPS-200: a 4 h fit interval centred on t_oe).
pub const EPHEMERIS_VALIDITY_S: f64 = 7_200.0;

/// Satellite ECEF positions (m) and velocities (m/s), one row per satellite.
pub type PositionsVelocities = (Vec<Vector3<f64>>, Vec<Vector3<f64>>);

/// One satellite's orbit: a broadcast ephemeris or a Walker slot.
#[derive(Debug, Clone, Copy)]
pub enum Orbit<'a> {
    /// A GPS broadcast ephemeris ([`Constellation::select_ephemeris`]'s).
    Broadcast(&'a GpsEphemeris),
    /// A Walker constellation and the satellite's slot index in it.
    Walker(&'a Walker, usize),
}

impl Orbit<'_> {
    /// The satellite's state at `gps_time_s`.
    pub fn state(&self, gps_time_s: f64) -> SatelliteState {
        self.state_at(gps_time_s, 0.0)
    }

    /// The state at `gps_time_s + offset_s`, precise for small offsets at
    /// large GPS times (see [`GpsEphemeris::state_at`]).
    pub fn state_at(&self, gps_time_s: f64, offset_s: f64) -> SatelliteState {
        match *self {
            Orbit::Broadcast(e) => e.state_at(gps_time_s, offset_s),
            Orbit::Walker(w, i) => {
                let (position_ecef, velocity_ecef) =
                    w.position_velocity_at(i, gps_time_s, offset_s);
                SatelliteState {
                    position_ecef,
                    velocity_ecef,
                    clock_bias_s: 0.0,
                    clock_drift_s_s: 0.0,
                    relativistic_s: 0.0,
                }
            }
        }
    }
}

/// One system's synthetic Walker constellation: its slots 1..N are its
/// satellites' PRNs.
#[derive(Debug, Clone, PartialEq)]
pub struct SystemWalker {
    /// The system the satellites belong to.
    pub system: GnssSystem,
    /// Its constellation.
    pub walker: Walker,
}

/// Most satellites of one system in a constellation of several: the
/// satellite numbers of a system span 99 PRNs ([`satellite_number`]).
pub const MAX_SATELLITES_PER_SYSTEM: usize = 99;

/// Satellites the simulator can see.
#[derive(Debug, Clone, PartialEq)]
pub enum Constellation {
    /// GPS broadcast ephemerides, grouped per PRN and sorted by t_oe.
    Broadcast {
        /// The PRNs, one per satellite.
        prns: Vec<u16>,
        /// Each PRN's ephemerides, sorted by t_oe.
        ephemerides: Vec<Vec<GpsEphemeris>>,
    },
    /// Synthetic Walker delta constellations, one per system, each
    /// system's satellites after the previous one's.
    Walker(Vec<SystemWalker>),
}

impl Constellation {
    /// The GPS satellites of a RINEX 2 or 3 navigation file.
    pub fn from_rinex_nav(path: impl AsRef<Path>) -> Result<Self> {
        let path = path.as_ref();
        let records = read_rinex_nav(path)?;
        if records.is_empty() {
            return Err(Error::Parse {
                file: path.display().to_string(),
                line: 0,
                reason: "no GPS ephemeris in the file".into(),
            });
        }
        Ok(Self::from_ephemerides(records))
    }

    /// From ephemeris records (any order).
    pub fn from_ephemerides(mut records: Vec<GpsEphemeris>) -> Self {
        records.sort_by(|a, b| {
            a.prn
                .cmp(&b.prn)
                .then(a.orbit.toe_gps_s.total_cmp(&b.orbit.toe_gps_s))
        });
        let mut prns: Vec<u16> = Vec::new();
        let mut ephemerides: Vec<Vec<GpsEphemeris>> = Vec::new();
        for r in records {
            if prns.last() != Some(&r.prn) {
                prns.push(r.prn);
                ephemerides.push(Vec::new());
            }
            ephemerides.last_mut().expect("pushed above").push(r);
        }
        Constellation::Broadcast { prns, ephemerides }
    }

    /// A synthetic GPS Walker constellation (its slots numbered 1..N).
    pub fn walker(config: &WalkerConfig) -> Result<Self> {
        Self::walkers(&[(GnssSystem::Gps, *config)])
    }

    /// Synthetic Walker constellations of several systems, in this order,
    /// each satellite numbered by its system ([`satellite_number`] of its
    /// slot 1..N: GPS 1.., Galileo 101.., BeiDou 201.., GLONASS 301..). A system appears
    /// once; with more than one, each has at most
    /// [`MAX_SATELLITES_PER_SYSTEM`] satellites so that the numbers stay
    /// within their system's range.
    pub fn walkers(parts: &[(GnssSystem, WalkerConfig)]) -> Result<Self> {
        if parts.is_empty() {
            return Err(Error::invalid("systems", "must name at least one system"));
        }
        let mut walkers: Vec<SystemWalker> = Vec::with_capacity(parts.len());
        for (system, config) in parts {
            if walkers.iter().any(|w| w.system == *system) {
                return Err(Error::invalid("systems", format!("{system} appears twice")));
            }
            let walker = Walker::new(config)?;
            if parts.len() > 1 && walker.len() > MAX_SATELLITES_PER_SYSTEM {
                return Err(Error::invalid(
                    "n_satellites",
                    format!(
                        "{system}: at most {MAX_SATELLITES_PER_SYSTEM} satellites per system when \
                         several systems are combined, got {}",
                        walker.len()
                    ),
                ));
            }
            walkers.push(SystemWalker {
                system: *system,
                walker,
            });
        }
        Ok(Constellation::Walker(walkers))
    }

    /// The nominal Walker constellations of these systems
    /// ([`WalkerConfig::nominal`]).
    pub fn nominal_walkers(systems: &[GnssSystem]) -> Result<Self> {
        let parts: Vec<_> = systems
            .iter()
            .map(|&s| (s, WalkerConfig::nominal(s)))
            .collect();
        Self::walkers(&parts)
    }

    /// Number of satellites.
    pub fn len(&self) -> usize {
        match self {
            Constellation::Broadcast { prns, .. } => prns.len(),
            Constellation::Walker(parts) => parts.iter().map(|p| p.walker.len()).sum(),
        }
    }

    /// The Walker part that satellite `i` belongs to and its slot there
    /// (0-based); `None` for broadcast ephemerides.
    fn walker_slot(&self, mut i: usize) -> Option<(&SystemWalker, usize)> {
        let Constellation::Walker(parts) = self else {
            return None;
        };
        for part in parts {
            if i < part.walker.len() {
                return Some((part, i));
            }
            i -= part.walker.len();
        }
        panic!(
            "satellite index beyond the constellation's {} satellites",
            self.len()
        )
    }

    /// The system of satellite `i`.
    pub fn system(&self, i: usize) -> GnssSystem {
        self.walker_slot(i)
            .map_or(GnssSystem::Gps, |(part, _)| part.system)
    }

    /// The systems of the constellation, in its order.
    pub fn systems(&self) -> Vec<GnssSystem> {
        match self {
            Constellation::Broadcast { .. } => vec![GnssSystem::Gps],
            Constellation::Walker(parts) => parts.iter().map(|p| p.system).collect(),
        }
    }

    /// Whether it has no satellite.
    pub fn is_empty(&self) -> bool {
        self.len() == 0
    }

    /// Satellite number of index `i` (the GPS PRN, or the
    /// [`satellite_number`] of its system's Walker slot 1..N).
    pub fn sat_id(&self, i: usize) -> u16 {
        match self {
            Constellation::Broadcast { prns, .. } => prns[i],
            // At most u16::MAX slots (Walker::new) and, with several
            // systems, 99 per system: the number fits.
            Constellation::Walker(_) => {
                let (part, slot) = self.walker_slot(i).expect("a Walker constellation");
                satellite_number(part.system, (slot + 1) as u16)
            }
        }
    }

    /// Identifiers as RINEX names: "G01", ..., "E01", ..., "C01", ...
    /// (Walker slots are named like their system's PRNs, 1..N).
    pub fn prns(&self) -> Vec<String> {
        (0..self.len())
            .map(|i| match self.walker_slot(i) {
                Some((part, slot)) => format!("{}{:02}", part.system.letter(), slot + 1),
                None => format!("G{:02}", self.sat_id(i)),
            })
            .collect()
    }

    /// A sensible default start time: the earliest t_oe of the file, or 0
    /// for a Walker constellation.
    pub fn default_start_gps_time_s(&self) -> f64 {
        match self {
            Constellation::Broadcast { ephemerides, .. } => ephemerides
                .iter()
                .filter_map(|e| e.first().map(|r| r.orbit.toe_gps_s))
                .fold(f64::INFINITY, f64::min),
            Constellation::Walker(_) => 0.0,
        }
    }

    /// The healthy broadcast ephemeris of satellite `i` with t_oe nearest
    /// to `gps_time_s`, if one lies within ±2 h.
    pub fn select_ephemeris(&self, i: usize, gps_time_s: f64) -> Option<&GpsEphemeris> {
        match self {
            Constellation::Broadcast { ephemerides, .. } => ephemerides[i]
                .iter()
                .filter(|e| {
                    e.health == 0 && (gps_time_s - e.orbit.toe_gps_s).abs() <= EPHEMERIS_VALIDITY_S
                })
                .min_by(|a, b| {
                    (gps_time_s - a.orbit.toe_gps_s)
                        .abs()
                        .total_cmp(&(gps_time_s - b.orbit.toe_gps_s).abs())
                }),
            Constellation::Walker(_) => None,
        }
    }

    /// The orbit of satellite `i` that applies at `gps_time_s` (the
    /// selected ephemeris), to be evaluated at nearby times without
    /// switching ephemeris; `None` when no valid ephemeris.
    pub fn orbit(&self, i: usize, gps_time_s: f64) -> Option<Orbit<'_>> {
        match self {
            Constellation::Broadcast { .. } => {
                self.select_ephemeris(i, gps_time_s).map(Orbit::Broadcast)
            }
            Constellation::Walker(_) => {
                let (part, slot) = self.walker_slot(i).expect("a Walker constellation");
                Some(Orbit::Walker(&part.walker, slot))
            }
        }
    }

    /// State of satellite `i` at `gps_time_s`; `None` when no valid ephemeris.
    pub fn state(&self, i: usize, gps_time_s: f64) -> Option<SatelliteState> {
        self.orbit(i, gps_time_s).map(|o| o.state(gps_time_s))
    }

    /// ECEF positions of every satellite at `gps_time_s` into `out`
    /// (cleared first), `None` where no valid ephemeris: bitwise the
    /// positions of [`Self::state`], cheaper for a Walker constellation
    /// ([`Walker::positions`]).
    pub fn positions_into(&self, gps_time_s: f64, out: &mut Vec<Option<Vector3<f64>>>) {
        out.clear();
        match self {
            Constellation::Walker(parts) => {
                for part in parts {
                    out.extend(part.walker.positions(gps_time_s).map(Some));
                }
            }
            Constellation::Broadcast { .. } => out.extend(
                (0..self.len()).map(|i| self.state(i, gps_time_s).map(|s| s.position_ecef)),
            ),
        }
    }

    /// Positions and velocities of every satellite (in `prns()` order) at
    /// `gps_time_s`; NaN rows where no valid ephemeris.
    pub fn position_velocity(&self, gps_time_s: f64) -> Result<PositionsVelocities> {
        validate::finite_scalars("gps_time", &[gps_time_s])?;
        let nan = Vector3::repeat(f64::NAN);
        Ok((0..self.len())
            .map(|i| match self.state(i, gps_time_s) {
                Some(s) => (s.position_ecef, s.velocity_ecef),
                None => (nan, nan),
            })
            .unzip())
    }

    /// Satellite clock corrections Δt_sv (s) at `gps_time_s`; NaN where no
    /// valid ephemeris.
    pub fn clock_correction(&self, gps_time_s: f64) -> Result<Vec<f64>> {
        validate::finite_scalars("gps_time", &[gps_time_s])?;
        Ok((0..self.len())
            .map(|i| {
                self.state(i, gps_time_s)
                    .map_or(f64::NAN, |s| s.clock_bias_s)
            })
            .collect())
    }
}
