//! Streaming quantile estimate in O(1) memory: the P² algorithm of Jain and
//! Chlamtac, "The P² algorithm for dynamic calculation of quantiles and
//! histograms without storing observations", CACM 28(10), 1985.

/// One quantile of a stream of values, kept with five markers.
#[derive(Debug, Clone)]
pub struct P2Quantile {
    p: f64,
    /// Marker heights q_i.
    heights: [f64; 5],
    /// Actual marker positions n_i (1-based, as in the paper).
    positions: [f64; 5],
    /// Desired marker positions n'_i.
    desired: [f64; 5],
    /// Increments of the desired positions dn'_i.
    increments: [f64; 5],
    count: usize,
}

impl P2Quantile {
    /// A tracker of the p-quantile, 0 < p < 1.
    pub fn new(p: f64) -> Self {
        Self {
            p,
            heights: [0.0; 5],
            positions: [1.0, 2.0, 3.0, 4.0, 5.0],
            desired: [1.0, 1.0 + 2.0 * p, 1.0 + 4.0 * p, 3.0 + 2.0 * p, 5.0],
            increments: [0.0, p / 2.0, p, (1.0 + p) / 2.0, 1.0],
            count: 0,
        }
    }

    /// Adds one observation.
    pub fn push(&mut self, x: f64) {
        if self.count < 5 {
            self.heights[self.count] = x;
            self.count += 1;
            if self.count == 5 {
                self.heights.sort_by(f64::total_cmp);
            }
            return;
        }
        self.count += 1;
        // B1: find the cell k holding x, extending the extremes.
        let k = if x < self.heights[0] {
            self.heights[0] = x;
            0
        } else if x >= self.heights[4] {
            self.heights[4] = x;
            3
        } else {
            (0..4).find(|&i| x < self.heights[i + 1]).unwrap_or(3)
        };
        // B2: shift the positions above the cell and all desired positions.
        for i in k + 1..5 {
            self.positions[i] += 1.0;
        }
        for i in 0..5 {
            self.desired[i] += self.increments[i];
        }
        // B3: adjust the three middle markers with the parabolic (P²)
        // formula, falling back to linear when it would break monotonicity.
        for i in 1..4 {
            let d = self.desired[i] - self.positions[i];
            if (d >= 1.0 && self.positions[i + 1] - self.positions[i] > 1.0)
                || (d <= -1.0 && self.positions[i - 1] - self.positions[i] < -1.0)
            {
                let s = d.signum();
                let q = self.parabolic(i, s);
                self.heights[i] = if self.heights[i - 1] < q && q < self.heights[i + 1] {
                    q
                } else {
                    self.linear(i, s)
                };
                self.positions[i] += s;
            }
        }
    }

    fn parabolic(&self, i: usize, s: f64) -> f64 {
        let (q, n) = (&self.heights, &self.positions);
        q[i] + s / (n[i + 1] - n[i - 1])
            * ((n[i] - n[i - 1] + s) * (q[i + 1] - q[i]) / (n[i + 1] - n[i])
                + (n[i + 1] - n[i] - s) * (q[i] - q[i - 1]) / (n[i] - n[i - 1]))
    }

    fn linear(&self, i: usize, s: f64) -> f64 {
        let j = if s > 0.0 { i + 1 } else { i - 1 };
        self.heights[i]
            + s * (self.heights[j] - self.heights[i]) / (self.positions[j] - self.positions[i])
    }

    /// The current estimate; exact (interpolated order statistic) for fewer
    /// than five observations; NaN when empty.
    pub fn value(&self) -> f64 {
        match self.count {
            0 => f64::NAN,
            n if n < 5 => {
                let mut v = self.heights[..n].to_vec();
                v.sort_by(f64::total_cmp);
                let r = self.p * (n - 1) as f64;
                let (lo, frac) = (r.floor() as usize, r.fract());
                if lo + 1 < n {
                    v[lo] + frac * (v[lo + 1] - v[lo])
                } else {
                    v[lo]
                }
            }
            _ => self.heights[2],
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::random;
    use rand_distr::{Distribution, Exp, StandardNormal};

    fn exact(mut v: Vec<f64>, p: f64) -> f64 {
        v.sort_by(f64::total_cmp);
        let r = p * (v.len() - 1) as f64;
        let lo = r.floor() as usize;
        v[lo] + r.fract() * (v[(lo + 1).min(v.len() - 1)] - v[lo])
    }

    #[test]
    fn tracks_quantiles_of_skewed_and_symmetric_streams() {
        let mut rng = random::stream(3, 0);
        let normal: Vec<f64> = (0..20_000)
            .map(|_| StandardNormal.sample(&mut rng))
            .collect();
        let exp = Exp::new(1.0).unwrap();
        let skewed: Vec<f64> = (0..20_000).map(|_| exp.sample(&mut rng)).collect();
        for data in [normal, skewed] {
            for p in [0.05, 0.5, 0.95] {
                let mut q = P2Quantile::new(p);
                data.iter().for_each(|x| q.push(*x));
                let truth = exact(data.clone(), p);
                assert!(
                    (q.value() - truth).abs() < 0.03 * (1.0 + truth.abs()),
                    "p={p}: {} vs {truth}",
                    q.value()
                );
            }
        }
    }

    #[test]
    fn small_counts_are_exact() {
        let mut q = P2Quantile::new(0.5);
        assert!(q.value().is_nan());
        [3.0, 1.0, 2.0].iter().for_each(|x| q.push(*x));
        assert_eq!(q.value(), 2.0);
    }
}
