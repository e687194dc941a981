//! Overlapping Allan deviation of inertial sensor samples (IEEE Std
//! 952-1997, annex C; El-Sheimy et al., *IEEE Trans. Instrum. Meas.* 57,
//! 2008): the white noise density, bias instability and rate random walk
//! of a static record are read off its slopes.
//!
//! For N samples y_k at rate f_s the integrated signal (the "phase" of
//! Riley, *Handbook of Frequency Stability Analysis*, NIST SP 1065, 2008)
//! has N + 1 points θ_0 = 0, θ_k = Σ_{j<k} y_j / f_s, and at cluster size m
//! (τ = m / f_s) the overlapping Allan variance is (Riley eq. 11)
//!
//! ```text
//! σ²(τ) = Σ_{k=0}^{N−2m} (θ_{k+2m} − 2 θ_{k+m} + θ_k)² / (2 τ² (N + 1 − 2m)),
//! ```
//!
//! the mean of the squared difference of adjacent τ-averages over every
//! start. White noise of density q (unit·√s) gives σ(τ) = q/√τ; a random
//! walk of rate K (unit/√s) gives σ(τ) = K √(τ/3) (IEEE Std 952, table C.1).
//!
//! The record's mean is removed before integrating: it adds a straight
//! line to θ, which the second difference cancels exactly but which would
//! cost precision on a long record with a large bias.

use crate::{validate, Error, Result};

/// Cluster sizes when the caller gives none: 40 logarithmically spaced
/// values from 1 sample to a ninth of the record (fewer once rounding to
/// whole samples merges some), so the longest τ still averages 7 pairs.
pub fn default_cluster_sizes(samples: usize) -> Vec<usize> {
    const POINTS: usize = 40;
    let stop = ((samples / 9).max(1) as f64).log10();
    let mut sizes: Vec<usize> = (0..POINTS)
        .map(|i| {
            let exponent = if i == POINTS - 1 {
                stop
            } else {
                i as f64 * (stop / (POINTS - 1) as f64)
            };
            10f64.powf(exponent).round_ties_even() as usize
        })
        .collect();
    sizes.dedup();
    sizes
}

/// The cluster sizes m = round(τ f_s) of averaging times `taus_s`; each
/// must give 1 ≤ m and 2m < `samples` (at least two clusters).
pub fn cluster_sizes(taus_s: &[f64], rate_hz: f64, samples: usize) -> Result<Vec<usize>> {
    validate::positive("rate_hz", rate_hz)?;
    validate::finite_scalars("taus", taus_s)?;
    taus_s
        .iter()
        .map(|&tau| {
            let m = (tau * rate_hz).round_ties_even();
            if m < 1.0 || 2.0 * m >= samples as f64 {
                Err(Error::invalid(
                    "taus",
                    format!(
                        "each must lie between 1/rate_hz and half the record ({:.1} s), got {tau}",
                        samples as f64 / rate_hz / 2.0
                    ),
                ))
            } else {
                Ok(m as usize)
            }
        })
        .collect()
}

/// The overlapping Allan deviation (module docs) of `columns` series
/// sampled at `rate_hz`, given row-major as `samples` (N × columns), at
/// each cluster size of `clusters` (from [`cluster_sizes`] or
/// [`default_cluster_sizes`]). Returns the deviations row-major,
/// (clusters × columns), in the samples' unit.
pub fn overlapping_allan_deviation(
    samples: &[f64],
    columns: usize,
    rate_hz: f64,
    clusters: &[usize],
) -> Result<Vec<f64>> {
    validate::positive("rate_hz", rate_hz)?;
    if columns == 0 || samples.len() % columns != 0 {
        return Err(Error::invalid(
            "samples",
            format!("{} values do not make rows of {columns}", samples.len()),
        ));
    }
    let n = samples.len() / columns;
    if n < 3 {
        return Err(Error::invalid(
            "samples",
            format!("needs at least 3 samples, got {n}"),
        ));
    }
    validate::finite_array("samples", samples, &[n, columns])?;
    if let Some(&m) = clusters.iter().find(|&&m| m == 0 || 2 * m >= n) {
        return Err(Error::invalid(
            "clusters",
            format!(
                "a cluster size must lie in 1..{} (two clusters), got {m}",
                n.div_ceil(2)
            ),
        ));
    }
    let mut deviation = vec![0.0; clusters.len() * columns];
    let mut theta = vec![0.0; n + 1];
    for c in 0..columns {
        let column = samples.iter().skip(c).step_by(columns);
        let mean = column.clone().sum::<f64>() / n as f64;
        for (k, y) in column.enumerate() {
            theta[k + 1] = theta[k] + (y - mean) / rate_hz;
        }
        for (row, &m) in clusters.iter().enumerate() {
            let tau = m as f64 / rate_hz;
            let terms = n + 1 - 2 * m;
            let sum: f64 = (0..terms)
                .map(|k| {
                    let d = theta[k + 2 * m] - 2.0 * theta[k + m] + theta[k];
                    d * d
                })
                .sum();
            deviation[row * columns + c] = (sum / (2.0 * tau * tau * terms as f64)).sqrt();
        }
    }
    Ok(deviation)
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::random::stream;
    use rand::Rng as _;
    use rand_distr::StandardNormal;

    /// The definition read literally: the averages of the clusters starting
    /// at every sample, and half the mean squared difference of each with
    /// the one m samples later.
    fn by_definition(y: &[f64], m: usize) -> f64 {
        let averages: Vec<f64> = (0..=y.len() - m)
            .map(|k| y[k..k + m].iter().sum::<f64>() / m as f64)
            .collect();
        let d: Vec<f64> = (0..averages.len() - m)
            .map(|k| averages[k + m] - averages[k])
            .collect();
        (d.iter().map(|x| x * x).sum::<f64>() / (2.0 * d.len() as f64)).sqrt()
    }

    #[test]
    fn matches_the_definition() {
        let mut rng = stream(2, 0);
        let y: Vec<f64> = (0..500)
            .map(|k| 0.3 + 1e-3 * k as f64 + rng.sample::<f64, _>(StandardNormal))
            .collect();
        let clusters = [1, 2, 7, 50, 249];
        let adev = overlapping_allan_deviation(&y, 1, 10.0, &clusters).unwrap();
        for (a, &m) in adev.iter().zip(&clusters) {
            let expected = by_definition(&y, m);
            assert!(
                (a - expected).abs() <= 1e-12 * expected,
                "m {m}: {a} vs {expected}"
            );
        }
    }

    /// White noise of std σ per sample at f_s: density q = σ/√f_s and
    /// σ(τ) = q/√τ; a random walk whose steps have std σ: K = σ√f_s and
    /// σ(τ) = K√(τ/3). 4·10⁵ samples put the estimate within a few % at
    /// these τ (its relative error is about 1/√(2 N/m)).
    #[test]
    fn white_noise_and_random_walk_have_their_slopes() {
        let (rate, sigma, n) = (100.0, 0.02, 400_000);
        let mut rng = stream(3, 0);
        let white: Vec<f64> = (0..n)
            .map(|_| sigma * rng.sample::<f64, _>(StandardNormal))
            .collect();
        let mut walk = Vec::with_capacity(n);
        let mut x = 0.0;
        for _ in 0..n {
            x += sigma * rng.sample::<f64, _>(StandardNormal);
            walk.push(x);
        }
        // Two columns: white noise and the random walk, row-major.
        let rows: Vec<f64> = white
            .iter()
            .zip(&walk)
            .flat_map(|(a, b)| [*a, *b])
            .collect();
        let taus = [0.1, 1.0, 10.0];
        let clusters = cluster_sizes(&taus, rate, n).unwrap();
        assert_eq!(clusters, [10, 100, 1000]);
        let adev = overlapping_allan_deviation(&rows, 2, rate, &clusters).unwrap();
        let q = sigma / f64::sqrt(rate);
        let k = sigma * f64::sqrt(rate);
        for (i, tau) in taus.iter().enumerate() {
            let white_expected = q / tau.sqrt();
            let walk_expected = k * (tau / 3.0).sqrt();
            let tolerance = 4.0 / (2.0 * n as f64 / clusters[i] as f64).sqrt();
            let (w, r) = (adev[2 * i], adev[2 * i + 1]);
            assert!(
                (w / white_expected - 1.0).abs() < tolerance,
                "white τ {tau}: {w} vs {white_expected}"
            );
            assert!(
                (r / walk_expected - 1.0).abs() < tolerance.max(0.1),
                "walk τ {tau}: {r} vs {walk_expected}"
            );
        }
    }

    #[test]
    fn cluster_sizes_by_default_and_checked() {
        assert_eq!(default_cluster_sizes(3), [1]);
        let sizes = default_cluster_sizes(90_000);
        assert_eq!((sizes[0], *sizes.last().unwrap()), (1, 10_000));
        assert!(sizes.windows(2).all(|w| w[0] < w[1]));
        assert!(cluster_sizes(&[1000.0], 100.0, 60_000).is_err());
        assert!(cluster_sizes(&[0.001], 100.0, 60_000).is_err());
        assert!(cluster_sizes(&[f64::NAN], 100.0, 60_000).is_err());
        let e = overlapping_allan_deviation(&[1.0, 2.0], 1, 1.0, &[1]).unwrap_err();
        assert!(e.to_string().contains("samples"), "{e}");
        let e = overlapping_allan_deviation(&[1.0, 2.0, f64::NAN, 3.0], 1, 1.0, &[1]).unwrap_err();
        assert!(e.to_string().contains("samples"), "{e}");
        let e = overlapping_allan_deviation(&[1.0; 6], 1, 1.0, &[3]).unwrap_err();
        assert!(e.to_string().contains("clusters"), "{e}");
    }
}
