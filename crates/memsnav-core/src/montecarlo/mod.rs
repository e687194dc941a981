//! Seeded, parallel, reproducible Monte Carlo runs.
//!
//! Run i draws only from [`crate::random::stream`]`(seed, i)`; results come
//! back in run order. So the numbers do not depend on the thread count, the
//! order in which runs finish, or how the runs are batched — nor where
//! they run: [`MonteCarlo`] splits an experiment into its runs and its
//! fold, so chunks of runs computed in other processes ([`run_chunk`], e.g.
//! on Dask workers) fold ([`fold_chunks`]) to the numbers of [`execute`].

use std::ops::Range;
use std::sync::atomic::{AtomicBool, AtomicUsize, Ordering};

use rayon::prelude::*;

mod chunks;
mod order_statistics;
mod quantile;
mod sequential;
mod stats;

pub use chunks::{execute, fold_chunks, run_chunk, MonteCarlo};
pub use order_statistics::{binomial_cdf, quantile_interval, QuantileInterval, DEFAULT_CONFIDENCE};
pub use quantile::P2Quantile;
pub use sequential::{sequential_error, sequential_look_error};
pub use stats::{CurveStats, PERCENTILES};

use crate::random::{self, Rng};
use crate::{Error, Result};

/// How a Monte Carlo set runs: threads, progress reporting and cancellation.
#[derive(Default)]
pub struct RunOptions<'a> {
    /// Worker threads; `None` uses every core.
    pub threads: Option<usize>,
    /// Called with the number of completed runs after each run (from any thread).
    pub progress: Option<&'a (dyn Fn(usize) + Sync)>,
    /// When set, runs not yet started are skipped; completed runs are kept.
    pub cancel: Option<&'a AtomicBool>,
}

/// The results of a Monte Carlo set: `runs[i]` is run i, `None` when the set
/// was cancelled before it started.
#[derive(Debug)]
pub struct Runs<T> {
    /// Each run's result, in run order; `None` for a run skipped.
    pub runs: Vec<Option<T>>,
    /// Whether the cancel flag skipped some runs.
    pub cancelled: bool,
}

impl<T> Runs<T> {
    /// The completed runs, in run order.
    pub fn completed(self) -> Vec<T> {
        self.runs.into_iter().flatten().collect()
    }
}

/// Runs `run(i, rng_i)` for i in `0..runs` over a rayon pool and keeps
/// every result.
///
/// The first error (by run index) is returned; a cancelled set returns the
/// completed runs with `cancelled = true`.
pub fn run<T, F>(seed: u64, runs: usize, options: &RunOptions<'_>, run: F) -> Result<Runs<T>>
where
    T: Send,
    F: Fn(usize, &mut Rng) -> Result<T> + Sync,
{
    let mut out = Vec::with_capacity(runs);
    let summary = fold(seed, runs, runs.max(1), options, run, |i, result| {
        out.resize_with(i, || None);
        out.push(Some(result));
        Ok(())
    })?;
    out.resize_with(runs, || None);
    Ok(Runs {
        runs: out,
        cancelled: summary.cancelled,
    })
}

/// What [`fold`] did.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct FoldSummary {
    /// Runs completed and handed to `consume`.
    pub completed: usize,
    /// Whether the cancel flag skipped some runs.
    pub cancelled: bool,
}

/// Runs `run(i, rng_i)` for i in `0..runs`, `batch` runs at a time in
/// parallel, and hands each result to `consume(i, result)` in increasing
/// run order. Memory holds one batch of results, so aggregates (e.g.
/// [`CurveStats`]) stay bounded for any number of runs; because results are
/// consumed in run order, the aggregate does not depend on the thread count
/// or the batch size.
pub fn fold<T, F, C>(
    seed: u64,
    runs: usize,
    batch: usize,
    options: &RunOptions<'_>,
    run: F,
    consume: C,
) -> Result<FoldSummary>
where
    T: Send,
    F: Fn(usize, &mut Rng) -> Result<T> + Sync,
    C: FnMut(usize, T) -> Result<()>,
{
    fold_range(seed, 0..runs, batch, options, run, consume)
}

/// [`fold`] over the runs `range` of a set: run i still draws from
/// `stream(seed, i)`, so a range gives the same runs as the whole set.
pub fn fold_range<T, F, C>(
    seed: u64,
    range: Range<usize>,
    batch: usize,
    options: &RunOptions<'_>,
    run: F,
    mut consume: C,
) -> Result<FoldSummary>
where
    T: Send,
    F: Fn(usize, &mut Rng) -> Result<T> + Sync,
    C: FnMut(usize, T) -> Result<()>,
{
    if batch == 0 {
        return Err(Error::invalid("batch", "must be at least 1"));
    }
    crate::limits::monte_carlo(options.threads, &[])?;
    let pool = match options.threads {
        None => None,
        Some(n) => Some(
            rayon::ThreadPoolBuilder::new()
                .num_threads(n.max(1))
                .build()
                .map_err(|e| Error::invalid("threads", e.to_string()))?,
        ),
    };
    let done = AtomicUsize::new(0);
    let cancelled = || options.cancel.is_some_and(|c| c.load(Ordering::Relaxed));
    let run_one = |i: usize| -> Result<Option<T>> {
        if cancelled() {
            return Ok(None);
        }
        let mut rng = random::stream(seed, i as u64);
        let out = run(i, &mut rng)?;
        let n = done.fetch_add(1, Ordering::Relaxed) + 1;
        if let Some(progress) = options.progress {
            progress(n);
        }
        Ok(Some(out))
    };
    let mut completed = 0;
    let (mut start, runs) = (range.start, range.end);
    while start < runs {
        let end = (start + batch).min(runs);
        let body = || {
            (start..end)
                .into_par_iter()
                .map(run_one)
                .collect::<Vec<_>>()
        };
        let results = match &pool {
            None => body(),
            Some(pool) => pool.install(body),
        };
        for (i, result) in (start..end).zip(results) {
            if let Some(value) = result? {
                consume(i, value)?;
                completed += 1;
            }
        }
        if cancelled() {
            break;
        }
        start = end;
    }
    Ok(FoldSummary {
        completed,
        cancelled: completed < range.len(),
    })
}

#[cfg(test)]
mod tests {
    use super::*;
    use rand::Rng as _;

    #[test]
    fn same_numbers_whatever_the_thread_count() {
        let f = |i: usize, rng: &mut Rng| Ok((i, rng.random::<f64>()));
        let one = run(
            5,
            64,
            &RunOptions {
                threads: Some(1),
                ..Default::default()
            },
            f,
        )
        .unwrap();
        let two = run(
            5,
            64,
            &RunOptions {
                threads: Some(2),
                ..Default::default()
            },
            f,
        )
        .unwrap();
        let fewer = run(5, 10, &RunOptions::default(), f).unwrap();
        let one = one.completed();
        assert_eq!(one, two.completed());
        assert_eq!(one[..10], fewer.completed()[..]);
        assert!(one.iter().enumerate().all(|(i, (j, _))| i == *j));
    }

    #[test]
    fn cancel_keeps_completed_runs_and_errors_propagate() {
        let cancel = AtomicBool::new(false);
        let options = RunOptions {
            threads: Some(1),
            cancel: Some(&cancel),
            ..Default::default()
        };
        let r = run(0, 20, &options, |i, _| {
            if i == 4 {
                cancel.store(true, Ordering::Relaxed);
            }
            Ok(i)
        })
        .unwrap();
        assert!(r.cancelled);
        let done = r.completed();
        assert!(done.contains(&4) && done.len() < 20);
        let e = run(0, 8, &RunOptions::default(), |i, _| {
            if i >= 3 {
                Err(Error::invalid("x", format!("run {i}")))
            } else {
                Ok(i)
            }
        })
        .unwrap_err();
        assert_eq!(e, Error::invalid("x", "run 3"));
    }

    #[test]
    fn folded_statistics_do_not_depend_on_batch_or_threads() {
        let curve =
            |_: usize, rng: &mut Rng| Ok((0..3).map(|_| rng.random::<f64>()).collect::<Vec<f64>>());
        let stats_with = |batch: usize, threads: usize| {
            let mut stats = CurveStats::new(3);
            let options = RunOptions {
                threads: Some(threads),
                ..Default::default()
            };
            let summary = fold(9, 37, batch, &options, curve, |_, c| stats.push(&c)).unwrap();
            assert_eq!(
                summary,
                FoldSummary {
                    completed: 37,
                    cancelled: false
                }
            );
            (stats.mean().to_vec(), stats.std(), stats.percentile(2))
        };
        let reference = stats_with(1, 1);
        assert_eq!(reference, stats_with(8, 2));
        assert_eq!(reference, stats_with(100, 2));
    }
}
