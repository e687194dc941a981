//! Deciding a quantile against a requirement in looks: how often a
//! sequence of order-statistic bounds errs, and the per-look error that
//! keeps a decision, whichever look makes it, wrong at most 1 − confidence.
//!
//! A cell of a study meets a requirement R on its p-quantile when the
//! one-sided upper bound X₍ₛ₎ of [`super::quantile_interval`] is at most
//! R, and fails when the one-sided lower bound X₍ᵣ₎ is above R. Both read
//! only B, the count of runs at or below R: meets ⇔ B ≥ s, fails ⇔ B ≤ r − 1.
//! A decision is wrong with the largest probability when the quantile sits
//! at R, where each run falls at or below R with probability p and B is a
//! binomial count that grows look by look (the looks share their runs).
//! The probability that some look decides is then a boundary-crossing
//! probability of that count, computed exactly by carrying the distribution
//! of B over the cells still open from look to look (Jennison & Turnbull,
//! *Group Sequential Methods*, 2000, §12.1, for binomial data). A cell that
//! decides stops, so its mass leaves the recursion.
//!
//! Bonferroni's per-look error (1 − confidence)/K bounds the same
//! probability by a sum over the K looks; the looks share their runs, so
//! the sum overstates it. [`sequential_look_error`] is instead the largest
//! common per-look error whose exact crossing probability stays within
//! 1 − confidence on both sides (a constant nominal level, like Pocock's
//! boundaries): each look decides from tighter bounds for the same error.

use super::order_statistics::{binomial_terms, bound_ranks};
use crate::{Error, Result};

/// Probability below which a state's mass is dropped from the recursion
/// (far below any error a confidence level reads).
const NEGLIGIBLE: f64 = 1e-300;

/// The probability that a cell decided in looks after `looks` runs
/// (cumulative, increasing) wrongly decides (meets, fails) at some look,
/// for the `p`-quantile at the requirement, each look's bounds at
/// one-sided error `look_error` (module docs). Every look's decision stops
/// the cell.
pub fn sequential_error(looks: &[usize], p: f64, look_error: f64) -> Result<(f64, f64)> {
    check(looks, p)?;
    if !(look_error > 0.0 && look_error < 0.5) {
        return Err(Error::invalid(
            "look_error",
            format!("must be within (0, 0.5), got {look_error}"),
        ));
    }
    let last = *looks.last().expect("checked non-empty");
    // open[b]: probability that the cell is still open with b runs at or
    // below the requirement.
    let mut open = vec![0.0; last + 1];
    open[0] = 1.0;
    let (mut meets, mut fails) = (0.0, 0.0);
    let mut runs = 0;
    for &n in looks {
        let step: Vec<f64> = binomial_terms(n - runs, p).collect();
        let mut next = vec![0.0; last + 1];
        for (b, &mass) in open[..=runs].iter().enumerate() {
            if mass < NEGLIGIBLE {
                continue;
            }
            for (j, &term) in step.iter().enumerate() {
                next[b + j] += mass * term;
            }
        }
        runs = n;
        open = next;
        let (lower, upper) = bound_ranks(n, p, look_error);
        // Fails: fewer than r runs at or below the requirement.
        if let Some(r) = lower {
            fails += open[..r].iter().sum::<f64>();
            open[..r].fill(0.0);
        }
        // Meets: s or more runs at or below it.
        if let Some(s) = upper {
            meets += open[s..=n].iter().sum::<f64>();
            open[s..=n].fill(0.0);
        }
    }
    Ok((meets, fails))
}

/// The largest per-look one-sided error at which a cell decided in
/// `looks` errs, on either side, with probability at most
/// `1 − confidence` (module docs): never below Bonferroni's
/// (1 − confidence)/K, and 1 − confidence itself for one look.
pub fn sequential_look_error(looks: &[usize], p: f64, confidence: f64) -> Result<f64> {
    check(looks, p)?;
    if !(confidence > 0.5 && confidence < 1.0) {
        return Err(Error::invalid(
            "confidence",
            format!("must be within (0.5, 1), got {confidence}"),
        ));
    }
    let allowed = 1.0 - confidence;
    let holds = |e: f64| -> Result<bool> {
        let (meets, fails) = sequential_error(looks, p, e)?;
        Ok(meets.max(fails) <= allowed)
    };
    // Bonferroni's level holds (the union bound); the crossing
    // probability only grows with the level, so bisect between the two.
    let (mut good, mut bad) = (allowed / looks.len() as f64, allowed);
    if holds(bad)? {
        return Ok(bad);
    }
    // The ranks, hence the errors, change at discrete levels: stop when
    // the bracket is far narrower than any level anyone reads.
    while bad - good > 1e-9 * allowed {
        let middle = 0.5 * (good + bad);
        if holds(middle)? {
            good = middle;
        } else {
            bad = middle;
        }
    }
    Ok(good)
}

fn check(looks: &[usize], p: f64) -> Result<()> {
    if looks.is_empty() || looks[0] == 0 {
        return Err(Error::invalid(
            "looks",
            "needs at least one look of at least one run",
        ));
    }
    if let Some(w) = looks.windows(2).find(|w| w[1] <= w[0]) {
        return Err(Error::invalid(
            "looks",
            format!(
                "runs must grow from look to look, got {} then {}",
                w[0], w[1]
            ),
        ));
    }
    if !(p > 0.0 && p < 1.0) {
        return Err(Error::invalid(
            "p",
            format!("must be within (0, 1), got {p}"),
        ));
    }
    Ok(())
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::montecarlo::{binomial_cdf, quantile_interval};
    use crate::random;
    use rand::Rng;

    /// One look errs exactly as its two one-sided bounds do.
    #[test]
    fn one_look_errs_as_its_bounds() {
        let (n, p, e) = (120, 0.95, 0.01);
        let (meets, fails) = sequential_error(&[n], p, e).unwrap();
        let (r, s) = bound_ranks(n, p, e);
        let (r, s) = (r.unwrap(), s.unwrap());
        assert!((fails - binomial_cdf(r - 1, n, p)).abs() < 1e-15);
        assert!((meets - (1.0 - binomial_cdf(s - 1, n, p))).abs() < 1e-12);
        assert!(meets <= e && fails <= e);
        assert_eq!(sequential_look_error(&[n], p, 0.95).unwrap(), 1.0 - 0.95);
    }

    /// The recursion against the procedure itself: runs drawn uniform on
    /// (0, 1), so the 0.95-quantile is 0.95, decided against a requirement
    /// of 0.95 by quantile_interval's bounds look after look, stopping at
    /// the first decision.
    #[test]
    fn the_crossing_probability_is_what_the_looks_do() {
        let (looks, p, e) = ([20, 60, 120], 0.95, 0.02);
        let (meets, fails) = sequential_error(&looks, p, e).unwrap();
        let mut rng = random::stream(5, 0);
        let trials = 20_000;
        let (mut wrong_meets, mut wrong_fails) = (0usize, 0usize);
        let mut values = vec![0.0; 120];
        for _ in 0..trials {
            values.iter_mut().for_each(|v| *v = rng.random::<f64>());
            for &n in &looks {
                let i = quantile_interval(&values[..n], p, 1.0 - 2.0 * e).unwrap();
                if i.upper <= p {
                    wrong_meets += 1;
                    break;
                }
                if i.lower > p {
                    wrong_fails += 1;
                    break;
                }
            }
        }
        for (count, exact) in [(wrong_meets, meets), (wrong_fails, fails)] {
            let share = count as f64 / trials as f64;
            let sigma = (exact * (1.0 - exact) / trials as f64).sqrt();
            assert!((share - exact).abs() < 4.0 * sigma, "{share} vs {exact}");
        }
        // The looks share their runs: the union bound overstates the error.
        assert!(meets.max(fails) < 0.8 * 3.0 * e, "{meets} {fails}");
    }

    /// The exact level keeps the error within the confidence and gives
    /// each look more than Bonferroni's share.
    #[test]
    fn the_exact_level_holds_and_beats_bonferroni() {
        let looks = [20, 90, 180, 360, 640];
        let e = sequential_look_error(&looks, 0.95, 0.95).unwrap();
        let (meets, fails) = sequential_error(&looks, 0.95, e).unwrap();
        assert!(meets <= 0.05 && fails <= 0.05, "{meets} {fails}");
        assert!(e > 1.3 * 0.05 / 5.0, "{e}");
        // A level a little higher breaks it on one side (the largest level).
        let (meets, fails) = sequential_error(&looks, 0.95, e * 1.0001).unwrap();
        assert!(meets.max(fails) > 0.05 || e == 0.05, "{meets} {fails}");
    }

    #[test]
    fn refuses_looks_that_do_not_grow() {
        assert!(sequential_error(&[], 0.95, 0.01).is_err());
        assert!(sequential_error(&[20, 20], 0.95, 0.01).is_err());
        assert!(sequential_error(&[20, 40], 1.0, 0.01).is_err());
        assert!(sequential_error(&[20, 40], 0.95, 0.0).is_err());
        assert!(sequential_look_error(&[20, 40], 0.95, 1.0).is_err());
    }
}
