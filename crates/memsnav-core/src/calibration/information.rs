//! Which optional terms a fit estimates: the small-sample Akaike
//! information criterion.
//!
//! ## The rule
//!
//! The terms a calibration may add to its minimal model (the
//! accelerometer's nonlinearity N in a static session, the gyroscope's
//! g-sensitivity K there) are chosen among every combination that the
//! determinability rules allow ([`super::determinable`]: excited, separable,
//! σ below the physical size) by the smallest
//!
//! ```text
//! AICc = n ln(RSS/n) + 2K + 2K(K + 1)/(n − K − 1)
//! ```
//!
//! (Hurvich and Tsai, *Biometrika* 76, 1989, eq. 4; Burnham and Anderson,
//! *Model Selection and Multimodel Inference*, 2002, eq. 2.14) of the fit:
//! n residuals, RSS their sum of squares, K the estimated parameters plus
//! one for the residual variance. AIC, n ln(RSS/n) + 2K, estimates the
//! expected log-likelihood of new data, i.e. the held-out error (it is
//! asymptotically leave-one-out cross-validation: Stone, *JRSS B* 39,
//! 1977); the third term corrects its bias when n is not large against K
//! (Burnham and Anderson advise it when n/K < 40; a static session has
//! n/K ≈ 2-4). A term is thus estimated only when it lowers the RSS by more
//! than it is expected to add to the error on poses the fit has not seen.
//! A model with n ≤ K + 1 has no estimate of its error and is never chosen
//! over one with fewer parameters. Equal values keep the smaller model.
//!
//! Fits whose rows are independent regressions, each with its own residual
//! variance (the gyroscope's three rest rows), add their rows' AICc: the
//! log-likelihood is the sum of the rows'.

/// AICc (module docs) of a fit with `observations` residuals whose sum of
/// squares is `rss` and `parameters` estimated parameters (the residual
/// variance is counted here); +∞ when `observations` ≤ `parameters` + 2
/// (or the RSS is NaN), −∞ for an exact fit.
pub fn aicc(rss: f64, observations: usize, parameters: usize) -> f64 {
    if observations <= parameters + 2 || rss.is_nan() {
        return f64::INFINITY;
    }
    let n = observations as f64;
    let k = (parameters + 1) as f64;
    n * (rss / n).ln() + 2.0 * k + 2.0 * k * (k + 1.0) / (n - k - 1.0)
}

/// One model a selection considered.
#[derive(Debug, Clone, PartialEq)]
pub struct Candidate {
    /// The optional terms it estimates (parameter names).
    pub terms: Vec<String>,
    /// Estimated parameters in all (the residual variance not counted).
    pub parameters: usize,
    /// Residuals of its fit.
    pub observations: usize,
    /// RMS residual of its fit (SI), NaN when it was not fitted.
    pub residual_rms: f64,
    /// Its AICc; None when the determinability rules refused it.
    pub aicc: Option<f64>,
    /// Why it was refused (empty when admissible).
    pub refused: String,
}

/// The models a stage considered and the one it chose.
#[derive(Debug, Clone, PartialEq)]
pub struct ModelSelection {
    /// The stage ("accelerometer nonlinearity", "gyroscope g-sensitivity").
    pub stage: String,
    /// The models considered, with their criteria.
    pub candidates: Vec<Candidate>,
    /// Index of the chosen candidate.
    pub chosen: usize,
}

impl ModelSelection {
    /// The admissible candidate of smallest AICc (the first on a tie:
    /// list smaller models first); None when none is admissible.
    pub fn choose(stage: &str, candidates: Vec<Candidate>) -> Option<Self> {
        let mut chosen: Option<(usize, f64)> = None;
        for (k, c) in candidates.iter().enumerate() {
            if let Some(v) = c.aicc {
                if chosen.is_none_or(|(_, best)| v < best) {
                    chosen = Some((k, v));
                }
            }
        }
        chosen.map(|(chosen, _)| Self {
            stage: stage.to_string(),
            candidates,
            chosen,
        })
    }

    /// The chosen candidate.
    pub fn best(&self) -> &Candidate {
        &self.candidates[self.chosen]
    }

    /// Why `term` is not in the chosen model: the refusal of the smallest
    /// candidate that adds it to the chosen one's terms, or the AICc of
    /// both.
    pub fn why_not(&self, term: &str) -> String {
        let best = self.best();
        let with = self.candidates.iter().find(|c| {
            c.terms.iter().any(|t| t == term)
                && best.terms.iter().all(|t| c.terms.contains(t))
                && c.terms.len() == best.terms.len() + 1
        });
        match with {
            Some(c) if c.aicc.is_none() => format!("with it, {}", c.refused),
            Some(c) => format!(
                "the information criterion prefers the model without it (AICc {:.1} with it, \
                 {:.1} without)",
                c.aicc.unwrap_or(f64::NAN),
                best.aicc.unwrap_or(f64::NAN)
            ),
            None => "not among the candidates".to_string(),
        }
    }
}

/// Every subset of `items`, smaller ones first (the order of
/// [`ModelSelection::choose`]'s ties), each in the order of `items`.
pub fn subsets<T: Clone>(items: &[T]) -> Vec<Vec<T>> {
    let mut masks: Vec<u32> = (0..1u32 << items.len()).collect();
    masks.sort_by_key(|m| (m.count_ones(), *m));
    masks
        .into_iter()
        .map(|m| {
            items
                .iter()
                .enumerate()
                .filter(|(i, _)| m & (1 << i) != 0)
                .map(|(_, x)| x.clone())
                .collect()
        })
        .collect()
}

#[cfg(test)]
mod tests {
    use super::*;

    fn candidate(terms: &[&str], parameters: usize, rss: f64, n: usize) -> Candidate {
        Candidate {
            terms: terms.iter().map(|t| t.to_string()).collect(),
            parameters,
            observations: n,
            residual_rms: (rss / n as f64).sqrt(),
            aicc: Some(aicc(rss, n, parameters)),
            refused: String::new(),
        }
    }

    #[test]
    fn aicc_matches_its_definition_and_refuses_saturated_fits() {
        // n = 18, 9 parameters + σ²: 18 ln(RSS/18) + 20 + 2·10·11/7.
        let v = aicc(1.8e-5, 18, 9);
        assert!((v - (18.0 * (1e-6f64).ln() + 20.0 + 220.0 / 7.0)).abs() < 1e-9);
        assert_eq!(aicc(1.0, 11, 9), f64::INFINITY);
        assert!(aicc(1.0, 12, 9).is_finite());
    }

    #[test]
    fn a_term_must_pay_for_itself() {
        // One more parameter at n = 30 costs about 2 + 1.6 in AICc: a 1 %
        // drop of the RSS (30 ln 0.99 ≈ −0.3) does not pay, a 20 % drop
        // (−6.7) does.
        let base = candidate(&[], 9, 1.0, 30);
        let small = candidate(&["n_u"], 10, 0.99, 30);
        let large = candidate(&["n_u"], 10, 0.8, 30);
        let s = ModelSelection::choose("t", vec![base.clone(), small]).unwrap();
        assert_eq!(s.chosen, 0);
        assert!(s.why_not("n_u").starts_with("the information criterion"));
        let s = ModelSelection::choose("t", vec![base, large]).unwrap();
        assert_eq!(s.chosen, 1);
    }

    #[test]
    fn refused_candidates_are_never_chosen_and_say_why() {
        let base = candidate(&[], 9, 1.0, 30);
        let mut better = candidate(&["n_u"], 10, 0.1, 30);
        better.aicc = None;
        better.refused = "its sigma would exceed its physical size".into();
        let s = ModelSelection::choose("t", vec![base, better]).unwrap();
        assert_eq!(s.chosen, 0);
        assert_eq!(
            s.why_not("n_u"),
            "with it, its sigma would exceed its physical size"
        );
    }

    #[test]
    fn subsets_come_smallest_first() {
        let s = subsets(&[0, 1, 2]);
        assert_eq!(s.len(), 8);
        assert_eq!(s[0], Vec::<i32>::new());
        assert_eq!(&s[1..4], &[vec![0], vec![1], vec![2]]);
        assert_eq!(s[7], vec![0, 1, 2]);
    }
}
