//! Which satellites a simulated receiver tracks: visibility above the
//! elevation mask and the selection of N satellites kept while visible.

use nalgebra::{SMatrix, SVector, Vector3};

use crate::gnss::GnssSystem;

/// Unknowns of a snapshot fix: position, clock and one inter-system bias
/// per system other than GPS.
const UNKNOWNS: usize = 4 + crate::gnss::INTER_SYSTEM_BIAS_SYSTEMS.len();

/// Elevation of a satellite at `sat` seen from `rx` with local up `up`, rad.
pub(super) fn elevation(sat: &Vector3<f64>, rx: &Vector3<f64>, up: &Vector3<f64>) -> f64 {
    let d = sat - rx;
    (d.dot(up) / d.norm()).clamp(-1.0, 1.0).asin()
}

/// GDOP of a set of lines of sight, each with its satellite's system
/// (∞ when fewer satellites than unknowns, or singular): √tr (HᵀH)⁻¹ with
/// rows H = (−uᵀ, 1, e_k) over position, clock and the inter-system bias
/// k of each system other than GPS that the set holds (without GPS, the
/// first system the set holds is the clock's reference and has no bias
/// column, as in `solve_fix`). A system's lone satellite thus adds nothing
/// to the position, as in the tight filter before the bias is known.
fn gdop(rows: impl Iterator<Item = (Vector3<f64>, GnssSystem)>) -> f64 {
    let mut g = SMatrix::<f64, UNKNOWNS, UNKNOWNS>::zeros();
    let mut used = [true; UNKNOWNS];
    used[4..].fill(false);
    let mut n = 0;
    let mut gps = false;
    for (u, system) in rows {
        gps |= system == GnssSystem::Gps;
        let mut h = SVector::<f64, UNKNOWNS>::zeros();
        h.fixed_rows_mut::<3>(0).copy_from(&-u);
        h[3] = 1.0;
        if let Some(k) = system.inter_system_bias_index() {
            h[4 + k] = 1.0;
            used[4 + k] = true;
        }
        g += h * h.transpose();
        n += 1;
    }
    // Without GPS the clock column is the first system's own: its bias
    // column would repeat it (a singular HᵀH).
    if !gps {
        if let Some(first) = (4..UNKNOWNS).find(|&j| used[j]) {
            used[first] = false;
        }
    }
    // The unknowns the set observes: with GPS alone the 4 × 4 of position
    // and clock, inverted as before the systems were added.
    let columns: Vec<usize> = (0..UNKNOWNS).filter(|&j| used[j]).collect();
    if n < columns.len() {
        return f64::INFINITY;
    }
    g.select_rows(&columns)
        .select_columns(&columns)
        .try_inverse()
        .map_or(f64::INFINITY, |inv| inv.trace().max(0.0).sqrt())
}

/// The satellites selected so far (indices into the constellation), in
/// the order they were selected.
#[derive(Debug, Default)]
pub(super) struct Selection {
    pub selected: Vec<usize>,
}

impl Selection {
    /// Updates the selection at one epoch, given each satellite's elevation
    /// (NaN without an orbit), approximate line of sight and system.
    ///
    /// At the first epoch: the `n` satellites with the best GDOP, by greedy
    /// elimination from all visible ones (drop, one at a time, the
    /// satellite whose removal leaves the lowest GDOP; ties: the lower).
    /// Later: a selected satellite is kept while it stays above the mask,
    /// and one that sets is replaced by the visible satellite that gives the
    /// lowest GDOP (ties: the higher).
    pub fn update(
        &mut self,
        first: bool,
        n: usize,
        elevations: &[f64],
        los: &[Vector3<f64>],
        systems: &[GnssSystem],
        mask_rad: f64,
    ) {
        let visible = |i: usize| elevations[i] >= mask_rad;
        let selected = &mut self.selected;
        if first {
            selected.extend((0..elevations.len()).filter(|&i| visible(i)));
            while selected.len() > n {
                let worst = (0..selected.len())
                    .map(|drop| {
                        let d = gdop(
                            selected
                                .iter()
                                .enumerate()
                                .filter(|&(j, _)| j != drop)
                                .map(|(_, &i)| (los[i], systems[i])),
                        );
                        (drop, d, elevations[selected[drop]])
                    })
                    .min_by(|a, b| a.1.total_cmp(&b.1).then(a.2.total_cmp(&b.2)))
                    .map(|(drop, _, _)| drop)
                    .expect("selection is not empty");
                selected.remove(worst);
            }
        } else {
            selected.retain(|&i| visible(i));
            while selected.len() < n {
                let best = (0..elevations.len())
                    .filter(|&i| visible(i) && !selected.contains(&i))
                    .map(|i| {
                        let d = gdop(
                            selected
                                .iter()
                                .chain(std::iter::once(&i))
                                .map(|&j| (los[j], systems[j])),
                        );
                        (i, d, elevations[i])
                    })
                    .min_by(|a, b| a.1.total_cmp(&b.1).then(b.2.total_cmp(&a.2)));
                match best {
                    Some((i, _, _)) => selected.push(i),
                    None => break,
                }
            }
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// The GDOP of a set depends on its geometry, not on which single
    /// system it belongs to: Galileo-only lines of sight give GPS's GDOP
    /// (not ∞ from a bias column that repeats the clock), and two systems
    /// without GPS give what GPS with the second system gives.
    #[test]
    fn gdop_without_gps_takes_the_first_system_as_the_reference() {
        let los: Vec<Vector3<f64>> = [
            (0.0, 0.0, 1.0),
            (0.8, 0.0, 0.6),
            (-0.4, 0.7, 0.6),
            (-0.4, -0.7, 0.6),
            (0.3, 0.9, 0.3),
            (0.6, -0.7, 0.4),
        ]
        .iter()
        .map(|&(x, y, z)| Vector3::new(x, y, z).normalize())
        .collect();
        let of = |systems: [GnssSystem; 6]| gdop(los.iter().copied().zip(systems));
        let (g, e, c) = (GnssSystem::Gps, GnssSystem::Galileo, GnssSystem::Beidou);
        let gps = of([g; 6]);
        assert!(gps.is_finite() && gps > 1.0);
        assert!((of([e; 6]) - gps).abs() < 1e-12 * gps);
        let mixed = of([g, g, g, c, c, c]);
        assert!(mixed.is_finite() && mixed > gps);
        assert!((of([e, e, e, c, c, c]) - mixed).abs() < 1e-9 * mixed);
    }
}
