//! A Monte Carlo experiment as its runs and its fold, so that chunks of
//! runs can be computed in other processes (Dask workers,
//! `docs/how-to/run-on-dask.md`) and folded here in run order.
//!
//! A chunk is the runs `start..end` of a set, encoded with postcard: f64
//! values travel as their bits, so a folded chunk is bit for bit the run
//! computed locally. Folding consumes runs in increasing run order, as
//! [`super::fold`] does; the result therefore does not depend on the chunk
//! size, the number of workers or the order in which chunks come back.

use std::ops::Range;

use serde::de::DeserializeOwned;
use serde::{Deserialize, Serialize};

use super::{fold_range, FoldSummary, RunOptions};
use crate::random::Rng;
use crate::{Error, Result};

/// An experiment split into independent runs and a fold over them.
pub trait MonteCarlo: Sync {
    /// What one run leaves for the fold.
    type Run: Send + Serialize + DeserializeOwned;
    /// The running aggregate.
    type Fold;
    /// The experiment's result.
    type Output;

    /// Base seed: run i draws from `random::stream(seed, i)`.
    fn seed(&self) -> u64;
    /// Runs in the whole set.
    fn runs(&self) -> usize;
    /// Runs computed at a time between folds (bounds the memory).
    fn batch(&self) -> usize;
    /// Run i from its own stream.
    fn run(&self, i: usize, rng: &mut Rng) -> Result<Self::Run>;
    /// An empty fold.
    fn start(&self) -> Self::Fold;
    /// Adds run i (runs come in increasing order).
    fn push(&self, fold: &mut Self::Fold, i: usize, run: Self::Run) -> Result<()>;
    /// The result from the fold of the completed runs.
    fn finish(&self, fold: Self::Fold, summary: FoldSummary) -> Result<Self::Output>;
}

/// The whole set here, over a rayon pool.
pub fn execute<M: MonteCarlo>(experiment: &M, options: &RunOptions<'_>) -> Result<M::Output> {
    let mut fold = experiment.start();
    let summary = super::fold(
        experiment.seed(),
        experiment.runs(),
        experiment.batch(),
        options,
        |i, rng| experiment.run(i, rng),
        |i, run| experiment.push(&mut fold, i, run),
    )?;
    experiment.finish(fold, summary)
}

#[derive(Serialize, Deserialize)]
struct Chunk<T> {
    /// The memsnav version that computed the runs: the fold refuses another
    /// (its runs may not mean the same).
    version: String,
    start: usize,
    runs: Vec<T>,
}

const VERSION: &str = env!("CARGO_PKG_VERSION");

/// The runs `range` of the set (every one; a worker is not cancelled
/// mid-chunk), encoded for [`fold_chunks`].
pub fn run_chunk<M: MonteCarlo>(
    experiment: &M,
    range: Range<usize>,
    options: &RunOptions<'_>,
) -> Result<Vec<u8>> {
    if range.start >= range.end || range.end > experiment.runs() {
        return Err(Error::invalid(
            "run_range",
            format!(
                "needs start < end ≤ runs ({}), got {}..{}",
                experiment.runs(),
                range.start,
                range.end
            ),
        ));
    }
    let mut runs = Vec::with_capacity(range.len());
    let worker = RunOptions {
        threads: options.threads,
        progress: options.progress,
        cancel: None,
    };
    let start = range.start;
    fold_range(
        experiment.seed(),
        range.clone(),
        range.len(),
        &worker,
        |i, rng| experiment.run(i, rng),
        |_, run| {
            runs.push(run);
            Ok(())
        },
    )?;
    postcard::to_stdvec(&Chunk {
        version: VERSION.to_string(),
        start,
        runs,
    })
    .map_err(|e| Error::invalid("run_range", format!("cannot encode the runs: {e}")))
}

/// Folds chunks of [`run_chunk`] in run order (any order given; they must
/// not overlap). Runs no chunk covers are missing: the result then covers
/// the chunks given and says it was cancelled, like an interrupted local
/// set.
pub fn fold_chunks<M: MonteCarlo>(experiment: &M, chunks: &[&[u8]]) -> Result<M::Output> {
    let mut decoded: Vec<Chunk<M::Run>> = chunks
        .iter()
        .enumerate()
        .map(|(k, bytes)| {
            postcard::from_bytes(bytes).map_err(|e| {
                Error::invalid(
                    "chunks",
                    format!("chunk {k} is not a chunk of this experiment: {e}"),
                )
            })
        })
        .collect::<Result<_>>()?;
    if let Some(c) = decoded.iter().find(|c| c.version != VERSION) {
        return Err(Error::invalid(
            "chunks",
            format!(
                "runs computed by memsnav {} cannot be folded by memsnav {VERSION}: install the same version on the workers",
                c.version
            ),
        ));
    }
    decoded.sort_by_key(|c| c.start);
    let mut fold = experiment.start();
    let mut next = 0;
    let mut completed = 0;
    for chunk in decoded {
        let end = chunk.start + chunk.runs.len();
        if chunk.start < next || end > experiment.runs() {
            return Err(Error::invalid(
                "chunks",
                format!(
                    "runs {}..{end} overlap another chunk or lie beyond the set's {} runs",
                    chunk.start,
                    experiment.runs()
                ),
            ));
        }
        for (i, run) in (chunk.start..end).zip(chunk.runs) {
            experiment.push(&mut fold, i, run)?;
        }
        completed += end - chunk.start;
        next = end;
    }
    experiment.finish(
        fold,
        FoldSummary {
            completed,
            cancelled: completed < experiment.runs(),
        },
    )
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::montecarlo::CurveStats;
    use rand::Rng as _;

    /// Curves of random numbers folded into P² percentiles and Welford
    /// means: statistics that depend on the order of the runs.
    struct Curves;

    impl MonteCarlo for Curves {
        type Run = Vec<f64>;
        type Fold = CurveStats;
        type Output = (Vec<f64>, Vec<f64>, FoldSummary);
        fn seed(&self) -> u64 {
            11
        }
        fn runs(&self) -> usize {
            23
        }
        fn batch(&self) -> usize {
            4
        }
        fn run(&self, _: usize, rng: &mut Rng) -> Result<Vec<f64>> {
            Ok((0..3).map(|_| rng.random::<f64>()).collect())
        }
        fn start(&self) -> CurveStats {
            CurveStats::new(3)
        }
        fn push(&self, fold: &mut CurveStats, _: usize, run: Vec<f64>) -> Result<()> {
            fold.push(&run)
        }
        fn finish(&self, f: CurveStats, s: FoldSummary) -> Result<Self::Output> {
            Ok((f.mean().to_vec(), f.percentile(3), s))
        }
    }

    #[test]
    fn chunks_in_any_order_fold_to_the_local_numbers() {
        let options = RunOptions::default();
        let local = execute(&Curves, &options).unwrap();
        let chunk = |r: Range<usize>| run_chunk(&Curves, r, &options).unwrap();
        let (a, b, c) = (chunk(0..5), chunk(5..6), chunk(6..23));
        let folded = fold_chunks(&Curves, &[&c, &a, &b]).unwrap();
        // Bit for bit: compare the bits, not within a tolerance.
        let bits = |v: &[f64]| v.iter().map(|x| x.to_bits()).collect::<Vec<_>>();
        assert_eq!(bits(&local.0), bits(&folded.0));
        assert_eq!(bits(&local.1), bits(&folded.1));
        assert!(!folded.2.cancelled);
        // A missing chunk: the rest folds, marked cancelled.
        let partial = fold_chunks(&Curves, &[&a, &c]).unwrap();
        assert_eq!(
            partial.2,
            FoldSummary {
                completed: 22,
                cancelled: true
            }
        );
    }

    #[test]
    fn bad_ranges_and_chunks_are_refused() {
        let options = RunOptions::default();
        assert!(run_chunk(&Curves, 5..5, &options).is_err());
        assert!(run_chunk(&Curves, 20..24, &options).is_err());
        let a = run_chunk(&Curves, 0..5, &options).unwrap();
        let b = run_chunk(&Curves, 3..8, &options).unwrap();
        let e = fold_chunks(&Curves, &[&a, &b]).unwrap_err();
        assert!(e.to_string().contains("overlap"), "{e}");
        let e = fold_chunks(&Curves, &[&[1u8, 2, 3][..]]).unwrap_err();
        assert!(e.to_string().starts_with("chunks"), "{e}");
    }
}
