//! Per-epoch statistics of Monte Carlo curves in bounded memory: mean and
//! standard deviation by Welford's update, percentiles by P².

use super::quantile::P2Quantile;
use crate::{Error, Result};

/// The percentiles every [`CurveStats`] tracks.
pub const PERCENTILES: [f64; 5] = [0.05, 0.25, 0.5, 0.75, 0.95];

/// Statistics of a family of curves sampled on the same epochs, one curve
/// per Monte Carlo run, updated run by run: memory is O(epochs), whatever
/// the number of runs. Runs must be added in a fixed order (run index) for
/// the percentiles to be reproducible.
#[derive(Debug, Clone)]
pub struct CurveStats {
    count: usize,
    mean: Vec<f64>,
    m2: Vec<f64>,
    quantiles: Vec<[P2Quantile; PERCENTILES.len()]>,
}

impl CurveStats {
    /// No run yet, curves of `epochs` epochs.
    pub fn new(epochs: usize) -> Self {
        Self {
            count: 0,
            mean: vec![0.0; epochs],
            m2: vec![0.0; epochs],
            quantiles: (0..epochs)
                .map(|_| PERCENTILES.map(P2Quantile::new))
                .collect(),
        }
    }

    /// Adds one run's curve (Welford 1962 / Knuth TAOCP vol. 2 §4.2.2).
    pub fn push(&mut self, curve: &[f64]) -> Result<()> {
        if curve.len() != self.mean.len() {
            return Err(Error::invalid(
                "curve",
                format!("has {} epochs, expected {}", curve.len(), self.mean.len()),
            ));
        }
        self.count += 1;
        let n = self.count as f64;
        for (k, &x) in curve.iter().enumerate() {
            let delta = x - self.mean[k];
            self.mean[k] += delta / n;
            self.m2[k] += delta * (x - self.mean[k]);
            self.quantiles[k].iter_mut().for_each(|q| q.push(x));
        }
        Ok(())
    }

    /// Runs added.
    pub fn count(&self) -> usize {
        self.count
    }

    /// Mean over the runs, per epoch.
    pub fn mean(&self) -> &[f64] {
        &self.mean
    }

    /// Sample standard deviation (n − 1); NaN with fewer than two runs.
    pub fn std(&self) -> Vec<f64> {
        let dof = self.count as f64 - 1.0;
        self.m2
            .iter()
            .map(|m2| {
                if dof > 0.0 {
                    (m2 / dof).sqrt()
                } else {
                    f64::NAN
                }
            })
            .collect()
    }

    /// The curve of percentile `PERCENTILES[index]`.
    pub fn percentile(&self, index: usize) -> Vec<f64> {
        self.quantiles.iter().map(|q| q[index].value()).collect()
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn matches_two_pass_formulas() {
        let curves: Vec<Vec<f64>> = (0..50)
            .map(|i| {
                (0..4)
                    .map(|k| ((i * 7 + k * 3) % 11) as f64 + 1e6)
                    .collect()
            })
            .collect();
        let mut s = CurveStats::new(4);
        curves.iter().for_each(|c| s.push(c).unwrap());
        for k in 0..4 {
            let col: Vec<f64> = curves.iter().map(|c| c[k]).collect();
            let mean = col.iter().sum::<f64>() / 50.0;
            let var = col.iter().map(|x| (x - mean).powi(2)).sum::<f64>() / 49.0;
            assert!((s.mean()[k] - mean).abs() < 1e-9);
            assert!((s.std()[k] - var.sqrt()).abs() < 1e-9);
        }
        assert!(s.push(&[1.0]).is_err());
    }
}
