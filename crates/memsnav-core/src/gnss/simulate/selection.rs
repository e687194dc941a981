//! Which satellites a simulated receiver tracks: visibility above the
//! elevation mask and the selection of N satellites kept while visible.

use nalgebra::{Matrix4, Vector3, Vector4};

/// Elevation of a satellite at `sat` seen from `rx` with local up `up`, rad.
pub(super) fn elevation(sat: &Vector3<f64>, rx: &Vector3<f64>, up: &Vector3<f64>) -> f64 {
    let d = sat - rx;
    (d.dot(up) / d.norm()).clamp(-1.0, 1.0).asin()
}

/// GDOP of a set of lines of sight (∞ when fewer than 4 or singular).
fn gdop(los: impl Iterator<Item = Vector3<f64>>) -> f64 {
    let mut g = Matrix4::zeros();
    let mut n = 0;
    for u in los {
        let h = Vector4::new(-u.x, -u.y, -u.z, 1.0);
        g += h * h.transpose();
        n += 1;
    }
    if n < 4 {
        return f64::INFINITY;
    }
    g.try_inverse()
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
    /// (NaN without an orbit) and approximate line of sight.
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
                                .map(|(_, &i)| los[i]),
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
                        let d = gdop(selected.iter().chain(std::iter::once(&i)).map(|&j| los[j]));
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
