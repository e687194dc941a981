//! Seeded, parallel, reproducible Monte Carlo runs.
//!
//! Run i draws only from [`crate::random::stream`]`(seed, i)`; results come
//! back in run order. So the numbers do not depend on the thread count, the
//! order in which runs finish, or how the runs are batched.

use std::sync::atomic::{AtomicBool, AtomicUsize, Ordering};

use rayon::prelude::*;

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
    pub runs: Vec<Option<T>>,
    pub cancelled: bool,
}

impl<T> Runs<T> {
    /// The completed runs, in run order.
    pub fn completed(self) -> Vec<T> {
        self.runs.into_iter().flatten().collect()
    }
}

/// Runs `run(i, rng_i)` for i in `0..runs` over a rayon pool.
///
/// The first error (by run index) is returned; a cancelled set returns the
/// completed runs with `cancelled = true`.
pub fn run<T, F>(seed: u64, runs: usize, options: &RunOptions<'_>, run: F) -> Result<Runs<T>>
where
    T: Send,
    F: Fn(usize, &mut Rng) -> Result<T> + Sync,
{
    let done = AtomicUsize::new(0);
    let body = || {
        (0..runs)
            .into_par_iter()
            .map(|i| {
                if options.cancel.is_some_and(|c| c.load(Ordering::Relaxed)) {
                    return Ok(None);
                }
                let mut rng = random::stream(seed, i as u64);
                let out = run(i, &mut rng)?;
                let n = done.fetch_add(1, Ordering::Relaxed) + 1;
                if let Some(progress) = options.progress {
                    progress(n);
                }
                Ok(Some(out))
            })
            .collect::<Vec<Result<Option<T>>>>()
    };
    let results = match options.threads {
        None => body(),
        Some(n) => rayon::ThreadPoolBuilder::new()
            .num_threads(n.max(1))
            .build()
            .map_err(|e| Error::invalid("threads", e.to_string()))?
            .install(body),
    };
    let mut out = Vec::with_capacity(runs);
    for r in results {
        out.push(r?);
    }
    let cancelled = out.iter().any(Option::is_none);
    Ok(Runs {
        runs: out,
        cancelled,
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
}
