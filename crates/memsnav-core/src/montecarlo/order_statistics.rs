//! How sure a quantile from a few Monte Carlo runs is: a distribution-free
//! confidence interval from the order statistics (David and Nagaraja,
//! *Order Statistics*, 3rd ed., §7.1). For n independent runs of a
//! continuous error, the k-th smallest run X₍ₖ₎ lies above the p-quantile
//! ξ_p exactly when at most k − 1 runs fall below ξ_p, so
//! P(X₍ₖ₎ ≥ ξ_p) = P(Bin(n, p) ≤ k − 1) whatever the distribution.
//!
//! With 20 runs no run bounds a 95th percentile from above at 95 %
//! confidence (even the largest only with 1 − 0.95²⁰ = 64 %): a p95 from 20
//! runs is a point estimate whose interval is open upwards.

use crate::{Error, Result};

/// A confidence interval for the p-quantile from the order statistics.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct QuantileInterval {
    /// The lower bound, −∞ when no run bounds the quantile from below at
    /// the confidence.
    pub lower: f64,
    /// The upper bound, +∞ when no run bounds it from above (too few runs).
    pub upper: f64,
    /// The interval's exact coverage for a continuous distribution (at
    /// least the confidence asked for).
    pub coverage: f64,
    /// The fewest runs whose largest bounds the quantile from above at the
    /// confidence's upper tail.
    pub runs_for_upper: usize,
}

/// P(Bin(n, p) ≤ k), summing the terms in log space (no overflow of the
/// binomial coefficients for any n; terms below 1e-308 vanish, which does
/// not change a sum the confidence levels read at the 1e-3 level).
pub fn binomial_cdf(k: usize, n: usize, p: f64) -> f64 {
    if k >= n {
        return 1.0;
    }
    binomial_terms(n, p).take(k + 1).sum::<f64>().min(1.0)
}

/// P(Bin(n, p) = j) for j = 0, 1, …, n, each from the previous one's
/// logarithm (the ratio of consecutive terms), so no binomial coefficient
/// is formed.
pub(super) fn binomial_terms(n: usize, p: f64) -> impl Iterator<Item = f64> {
    let (ln_p, ln_q) = (p.ln(), (-p).ln_1p());
    let mut ln_term = n as f64 * ln_q;
    (0..=n).map(move |j| {
        if j > 0 {
            ln_term += ((n - j + 1) as f64 / j as f64).ln() + ln_p - ln_q;
        }
        ln_term.exp()
    })
}

/// The 1-based ranks (lower, upper) of the order statistics of `n` runs
/// that bound the p-quantile from below and from above, each wrong with
/// probability at most `tail`; None where no run does.
pub(super) fn bound_ranks(n: usize, p: f64, tail: f64) -> (Option<usize>, Option<usize>) {
    // cdf[k] = P(Bin(n, p) ≤ k), k < n, summed as binomial_cdf sums it.
    let cdf: Vec<f64> = binomial_terms(n, p)
        .take(n)
        .scan(0.0, |sum, term| {
            *sum += term;
            Some(sum.min(1.0))
        })
        .collect();
    let below = |rank: usize| cdf[rank - 1];
    // Rank r bounds from below when P(X₍ᵣ₎ > ξ_p) = P(Bin ≤ r − 1) ≤ tail:
    // the largest such r.
    let lower = (1..=n).rev().find(|&r| below(r) <= tail);
    // Rank s bounds from above when P(X₍ₛ₎ < ξ_p) = 1 − P(Bin ≤ s − 1) ≤
    // tail: the smallest such s.
    let upper = (1..=n).find(|&s| below(s) >= 1.0 - tail);
    (lower, upper)
}

/// The confidence a quantile interval or a sequential decision is given
/// at when none is asked for: 95 %, the usual two-sided interval.
pub const DEFAULT_CONFIDENCE: f64 = 0.95;

/// The equal-tailed `confidence` interval for the `p`-quantile of the
/// distribution `values` were drawn from (independent runs; non-finite
/// values are errors): the largest order statistic that lies below the
/// quantile with probability at most (1 − confidence)/2 and the smallest
/// that lies above it with that probability.
pub fn quantile_interval(values: &[f64], p: f64, confidence: f64) -> Result<QuantileInterval> {
    if !(p > 0.0 && p < 1.0) {
        return Err(Error::invalid(
            "p",
            format!("must be within (0, 1), got {p}"),
        ));
    }
    if !(confidence > 0.0 && confidence < 1.0) {
        return Err(Error::invalid(
            "confidence",
            format!("must be within (0, 1), got {confidence}"),
        ));
    }
    crate::validate::finite_scalars("values", values)?;
    if values.is_empty() {
        return Err(Error::invalid("values", "needs at least one run"));
    }
    let mut sorted = values.to_vec();
    sorted.sort_by(f64::total_cmp);
    let n = sorted.len();
    let tail = 0.5 * (1.0 - confidence);
    let (lower_rank, upper_rank) = bound_ranks(n, p, tail);
    let below = lower_rank.map_or(0.0, |r| binomial_cdf(r - 1, n, p));
    let above = upper_rank.map_or(1.0, |s| binomial_cdf(s - 1, n, p));
    // The largest run bounds from above once p^n ≤ tail.
    let runs_for_upper = (tail.ln() / p.ln()).ceil().max(1.0) as usize;
    Ok(QuantileInterval {
        lower: lower_rank.map_or(f64::NEG_INFINITY, |r| sorted[r - 1]),
        upper: upper_rank.map_or(f64::INFINITY, |s| sorted[s - 1]),
        coverage: above - below,
        runs_for_upper,
    })
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::random;
    use rand_distr::{Distribution, Exp};

    #[test]
    fn binomial_cdf_matches_the_closed_forms() {
        // P(Bin(20, 0.95) ≤ 19) = 1 − 0.95²⁰; ≤ 0 is 0.05²⁰.
        assert!((binomial_cdf(19, 20, 0.95) - (1.0 - 0.95f64.powi(20))).abs() < 1e-12);
        assert!((binomial_cdf(0, 20, 0.95) - 0.05f64.powi(20)).abs() < 1e-35);
        // Bin(4, 0.5): 1, 4, 6, 4, 1 sixteenths.
        assert!((binomial_cdf(2, 4, 0.5) - 11.0 / 16.0).abs() < 1e-12);
        assert_eq!(binomial_cdf(20, 20, 0.95), 1.0);
        // A large n does not overflow: the median of Bin(10⁵, 0.5).
        assert!((binomial_cdf(50_000, 100_000, 0.5) - 0.5).abs() < 0.002);
    }

    #[test]
    fn twenty_runs_leave_a_p95_open_above() {
        let values: Vec<f64> = (1..=20).map(f64::from).collect();
        let i = quantile_interval(&values, 0.95, 0.95).unwrap();
        assert_eq!(i.upper, f64::INFINITY);
        // P(Bin(20, 0.95) ≤ 16) = 0.016 ≤ 0.025 < P(≤ 17) = 0.075: X₍₁₇₎.
        assert_eq!(i.lower, 17.0);
        assert!((i.coverage - (1.0 - binomial_cdf(16, 20, 0.95))).abs() < 1e-12);
        // 0.95^n ≤ 0.025 from n = 72 on.
        assert_eq!(i.runs_for_upper, 72);
        let many: Vec<f64> = (1..=72).map(f64::from).collect();
        assert!(quantile_interval(&many, 0.95, 0.95)
            .unwrap()
            .upper
            .is_finite());
    }

    /// The interval covers the true quantile in at least the stated share of
    /// repeated experiments (and not far more: it is not needlessly wide).
    #[test]
    fn covers_the_true_quantile_as_often_as_it_says() {
        let exp = Exp::new(1.0).unwrap();
        let truth = -(0.05f64).ln(); // the exponential's p95
        let mut rng = random::stream(11, 0);
        let (mut covered, trials) = (0, 4000);
        let mut coverage = 0.0;
        for _ in 0..trials {
            let values: Vec<f64> = (0..100).map(|_| exp.sample(&mut rng)).collect();
            let i = quantile_interval(&values, 0.95, 0.9).unwrap();
            coverage = i.coverage;
            covered += usize::from(i.lower <= truth && truth <= i.upper);
        }
        let share = covered as f64 / trials as f64;
        assert!(coverage >= 0.9);
        // Binomial spread of 4000 trials: ±0.015 at three sigma.
        assert!((share - coverage).abs() < 0.015, "{share} vs {coverage}");
    }

    #[test]
    fn refuses_what_has_no_quantile() {
        assert!(quantile_interval(&[], 0.95, 0.95).is_err());
        assert!(quantile_interval(&[1.0, f64::NAN], 0.95, 0.95).is_err());
        assert!(quantile_interval(&[1.0], 1.0, 0.95).is_err());
        assert!(quantile_interval(&[1.0], 0.5, 1.0).is_err());
    }
}
