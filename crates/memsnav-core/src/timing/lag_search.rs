//! The lag that best aligns two series: a score evaluated on a grid of
//! lags, its extremum refined by a parabola through the best grid point
//! and its neighbours (the usual sub-sample refinement of a correlation
//! peak; Jacovitti & Scarano, "Discrete time techniques for time delay
//! estimation", IEEE Trans. Signal Processing 41(2), 1993), and the same
//! search repeated on consecutive stretches of the data to show how much
//! the answer moves.

use crate::{Error, Result};

/// Most grid points a search may have (a 1 ms step over ±50 s).
const MAX_GRID_POINTS: usize = 100_001;

/// What is optimised.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Criterion {
    /// Pearson correlation of predicted and observed values, maximised
    /// (the two may differ in scale and offset).
    Correlation,
    /// Root mean square of observed − predicted, minimised (the same
    /// quantity on both sides).
    RootMeanSquare,
}

/// A lag estimate with its score curve.
#[derive(Debug, Clone, PartialEq)]
pub struct LagEstimate {
    /// The refined best lag, s.
    pub lag_s: f64,
    /// The score there (correlation, or RMS in the data's unit).
    pub score: f64,
    /// |d² c / d lag²| at the best lag, with c the correlation or the mean
    /// square (the RMS squared, which is smooth at its minimum), per s²:
    /// the sharper the extremum, the better the lag is determined.
    pub curvature: f64,
    /// Standard error of the lag from its spread over the stretches,
    /// `std(block_lag_s) / √blocks`, s; NaN with a single stretch.
    pub std_s: f64,
    /// The best lag of each consecutive stretch of the data, s.
    pub block_lag_s: Vec<f64>,
    /// The grid, s.
    pub curve_lag_s: Vec<f64>,
    /// The score at each grid lag.
    pub curve_score: Vec<f64>,
    /// Samples (epochs) that entered the score.
    pub samples: usize,
}

/// Running sums of (predicted, observed) pairs.
#[derive(Debug, Clone, Copy, Default)]
struct Sums {
    n: f64,
    x: f64,
    y: f64,
    xx: f64,
    yy: f64,
    xy: f64,
}

impl Sums {
    fn add(&mut self, x: f64, y: f64) {
        self.n += 1.0;
        self.x += x;
        self.y += y;
        self.xx += x * x;
        self.yy += y * y;
        self.xy += x * y;
    }

    /// The searched value: the correlation, or the mean square of y − x.
    fn score(&self, criterion: Criterion) -> f64 {
        match criterion {
            Criterion::Correlation => {
                let sxx = self.xx - self.x * self.x / self.n;
                let syy = self.yy - self.y * self.y / self.n;
                let sxy = self.xy - self.x * self.y / self.n;
                sxy / (sxx * syy).sqrt()
            }
            Criterion::RootMeanSquare => ((self.xx - 2.0 * self.xy + self.yy) / self.n).max(0.0),
        }
    }
}

impl Criterion {
    /// The reported score of a searched value (the RMS of a mean square).
    fn reported(self, value: f64) -> f64 {
        match self {
            Criterion::Correlation => value,
            Criterion::RootMeanSquare => value.sqrt(),
        }
    }
}

/// Lags from −`max_lag_s` to `max_lag_s` every `step_s`.
pub(super) fn lag_grid(max_lag_s: f64, step_s: f64, names: [&str; 2]) -> Result<Vec<f64>> {
    crate::validate::positive(names[0], max_lag_s)?;
    crate::validate::positive(names[1], step_s)?;
    let half = (max_lag_s / step_s).round();
    if half < 1.0 || 2.0 * half + 1.0 > MAX_GRID_POINTS as f64 {
        return Err(Error::invalid(
            names[1],
            format!(
                "{} / {} = {:.0} gives {} grid lags; use between 3 and {MAX_GRID_POINTS}",
                names[0],
                names[1],
                max_lag_s / step_s,
                2.0 * half + 1.0
            ),
        ));
    }
    let half = half as i64;
    Ok((-half..=half).map(|i| i as f64 * step_s).collect())
}

/// Index of the best value of `curve` (NaN never best).
fn best(curve: &[f64], criterion: Criterion) -> Option<usize> {
    let better = |a: f64, b: f64| match criterion {
        Criterion::Correlation => a > b,
        Criterion::RootMeanSquare => a < b,
    };
    let mut best: Option<usize> = None;
    for (i, &v) in curve.iter().enumerate() {
        if v.is_finite() && best.is_none_or(|b| better(v, curve[b])) {
            best = Some(i);
        }
    }
    best
}

/// The parabola through the best grid point and its neighbours: (lag,
/// value, |second derivative|); the grid point itself at an edge.
fn refine(grid: &[f64], curve: &[f64], i: usize) -> (f64, f64, f64) {
    if i == 0 || i + 1 == curve.len() {
        return (grid[i], curve[i], f64::NAN);
    }
    let (a, b, c) = (curve[i - 1], curve[i], curve[i + 1]);
    let step = grid[1] - grid[0];
    let second = a - 2.0 * b + c;
    if second.is_nan() || second == 0.0 {
        return (grid[i], b, 0.0);
    }
    let delta = (0.5 * (a - c) / second).clamp(-0.5, 0.5);
    (
        grid[i] + delta * step,
        b - 0.25 * (a - c) * delta,
        second.abs() / (step * step),
    )
}

/// Searches `grid` for the lag whose `pairs(lag)` — (sample index,
/// predicted, observed) for every usable sample, the same samples at every
/// lag — score best under `criterion`, over all `n_samples` samples and
/// over `blocks` consecutive stretches of them. `what` names the quantity
/// in errors.
pub(super) fn search(
    grid: &[f64],
    n_samples: usize,
    blocks: usize,
    criterion: Criterion,
    what: &str,
    mut pairs: impl FnMut(f64, &mut Vec<(usize, f64, f64)>),
) -> Result<LagEstimate> {
    if blocks == 0 || blocks > n_samples.max(1) {
        return Err(Error::invalid(
            "blocks",
            format!("must be between 1 and the {n_samples} usable epochs, got {blocks}"),
        ));
    }
    let mut curve = Vec::with_capacity(grid.len());
    let mut block_curves = vec![Vec::with_capacity(grid.len()); blocks];
    let mut buffer = Vec::new();
    let mut used = 0;
    for &lag in grid {
        buffer.clear();
        pairs(lag, &mut buffer);
        used = used.max(buffer.iter().map(|p| p.0 + 1).max().unwrap_or(0));
        let mut total = Sums::default();
        let mut per_block = vec![Sums::default(); blocks];
        for &(k, x, y) in &buffer {
            total.add(x, y);
            per_block[(k * blocks / n_samples).min(blocks - 1)].add(x, y);
        }
        curve.push(total.score(criterion));
        for (c, s) in block_curves.iter_mut().zip(&per_block) {
            c.push(s.score(criterion));
        }
    }
    let samples = n_samples.min(used);
    let Some(i) = best(&curve, criterion) else {
        return Err(Error::invalid(
            what,
            format!("no usable epochs to compare ({samples} found): the series do not overlap or do not vary"),
        ));
    };
    if i == 0 || i + 1 == grid.len() {
        return Err(Error::invalid(
            what,
            format!(
                "the best lag lies at the edge of the search window ({:+.3} s): widen the window",
                grid[i]
            ),
        ));
    }
    // Refined on the correlation or the mean square: both are smooth
    // (parabolic) at their extremum, where an RMS has a corner.
    let (lag_s, value, curvature) = refine(grid, &curve, i);
    let score = criterion.reported(value);
    let block_lag_s: Vec<f64> = block_curves
        .iter()
        .map(|c| best(c, criterion).map_or(f64::NAN, |j| refine(grid, c, j).0))
        .collect();
    let std_s = if blocks > 1 {
        let m = block_lag_s.iter().sum::<f64>() / blocks as f64;
        let var = block_lag_s.iter().map(|x| (x - m).powi(2)).sum::<f64>() / (blocks - 1) as f64;
        (var / blocks as f64).sqrt()
    } else {
        f64::NAN
    };
    Ok(LagEstimate {
        lag_s,
        score,
        curvature,
        std_s,
        block_lag_s,
        curve_lag_s: grid.to_vec(),
        curve_score: curve.into_iter().map(|v| criterion.reported(v)).collect(),
        samples,
    })
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_parabola_is_refined_exactly_and_blocks_agree() {
        // Observed y = sin(t_k), predicted sin(t_k + 0.0123 − lag): the
        // correlation peaks at lag 0.0123, between grid points.
        let t: Vec<f64> = (0..2000).map(|k| k as f64 * 0.05).collect();
        let grid = lag_grid(0.2, 0.01, ["max", "step"]).unwrap();
        assert_eq!(grid.len(), 41);
        let e = search(
            &grid,
            t.len(),
            4,
            Criterion::Correlation,
            "x",
            |lag, out| {
                for (k, &tk) in t.iter().enumerate() {
                    out.push((
                        k,
                        (tk + 0.0123 - lag).sin() + 0.3 * (2.1 * (tk + 0.0123 - lag)).cos(),
                        tk.sin() + 0.3 * (2.1 * tk).cos(),
                    ));
                }
            },
        )
        .unwrap();
        assert!((e.lag_s - 0.0123).abs() < 2e-4, "{}", e.lag_s);
        assert!((e.score - 1.0).abs() < 1e-6);
        assert!(e.curvature > 0.0 && e.std_s < 1e-3, "{e:?}");
        assert_eq!(e.samples, 2000);
        // RMS criterion on the same data: the minimum at the same lag.
        let e = search(
            &grid,
            t.len(),
            1,
            Criterion::RootMeanSquare,
            "x",
            |lag, out| {
                for (k, &tk) in t.iter().enumerate() {
                    out.push((k, (tk + 0.0123 - lag).sin(), tk.sin()));
                }
            },
        )
        .unwrap();
        assert!(
            (e.lag_s - 0.0123).abs() < 1e-4 && e.score < 1e-3 && e.std_s.is_nan(),
            "{e:?}"
        );
    }

    #[test]
    fn edges_empty_data_and_bad_grids_are_errors() {
        let grid = lag_grid(0.1, 0.01, ["max", "step"]).unwrap();
        let e = search(&grid, 10, 1, Criterion::RootMeanSquare, "x", |lag, out| {
            out.extend((0..10).map(|k| (k, lag, 1.0)));
        })
        .unwrap_err();
        assert!(
            e.to_string()
                .contains("edge of the search window (+0.100 s)"),
            "{e}"
        );
        let e = search(&grid, 10, 1, Criterion::Correlation, "x", |_, _| {}).unwrap_err();
        assert!(e.to_string().contains("no usable epochs"), "{e}");
        assert!(search(&grid, 10, 0, Criterion::Correlation, "x", |_, _| {}).is_err());
        assert!(lag_grid(1.0, 1e-9, ["max", "step"]).is_err());
        assert!(lag_grid(f64::NAN, 0.1, ["max", "step"]).is_err());
        assert!(lag_grid(0.01, 0.1, ["max", "step"]).is_err());
    }
}
