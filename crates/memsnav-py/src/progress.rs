//! Long Monte Carlo work from Python: run it on a worker thread with the GIL
//! released, while the calling (main) thread reports progress to an optional
//! Python callback and watches for Ctrl-C. Python only delivers signals to the
//! main thread, so this is where `check_signals` must run.

use std::sync::atomic::{AtomicBool, AtomicUsize, Ordering};
use std::sync::{Condvar, Mutex};
use std::time::Duration;

use memsnav_core::montecarlo::{self, MonteCarlo, RunOptions};
use pyo3::exceptions::{PyKeyboardInterrupt, PyValueError};
use pyo3::prelude::*;
use pyo3::types::PyBytes;

use crate::errors::IntoPyResult;

/// How often the main thread wakes to report progress and check signals.
const POLL: Duration = Duration::from_millis(100);

/// Sets the flag and wakes the waiting thread when dropped (when the
/// worker returns or unwinds).
struct SignalOnDrop<'a>(&'a (Mutex<bool>, Condvar));

impl Drop for SignalOnDrop<'_> {
    fn drop(&mut self) {
        let (flag, wake) = self.0;
        *flag.lock().unwrap_or_else(|e| e.into_inner()) = true;
        wake.notify_all();
    }
}

/// Runs `work(options)` on a worker thread. `progress(done, total)` is called
/// from this thread when the count of completed runs changes. Ctrl-C (or an
/// exception raised by the callback) sets the cancel flag: runs not yet
/// started are skipped and `work` returns what completed. Returns the work's
/// output and whether it was interrupted by Ctrl-C; a callback exception is
/// re-raised after the work stops.
pub fn run_interruptible<T, W>(
    py: Python<'_>,
    progress: Option<&Bound<'_, PyAny>>,
    total: usize,
    threads: Option<usize>,
    work: W,
) -> PyResult<(T, bool)>
where
    T: Send,
    W: FnOnce(&RunOptions<'_>) -> T + Send,
{
    let done = AtomicUsize::new(0);
    let cancel = AtomicBool::new(false);
    let count = |n: usize| {
        done.fetch_max(n, Ordering::Relaxed);
    };
    let options = RunOptions {
        threads,
        progress: Some(&count),
        cancel: Some(&cancel),
    };
    let mut interrupted = false;
    let mut callback_error = None;
    let mut reported = usize::MAX;
    // The worker says when it is done, so the wait below ends then and not
    // at the next poll (a whole POLL added to every call otherwise).
    let done_signal = (Mutex::new(false), Condvar::new());
    let mut finished = false;
    let output = std::thread::scope(|scope| {
        let worker = scope.spawn(|| {
            // Signalled also when `work` panics (on drop).
            let _signal = SignalOnDrop(&done_signal);
            work(&options)
        });
        loop {
            finished |= worker.is_finished();
            if let Err(e) = py.check_signals() {
                cancel.store(true, Ordering::Relaxed);
                if e.is_instance_of::<PyKeyboardInterrupt>(py) {
                    interrupted = true;
                } else {
                    callback_error.get_or_insert(e);
                }
            }
            let n = done.load(Ordering::Relaxed);
            if let Some(cb) = progress.filter(|_| n != reported && callback_error.is_none()) {
                reported = n;
                if let Err(e) = cb.call1((n, total)) {
                    cancel.store(true, Ordering::Relaxed);
                    if e.is_instance_of::<PyKeyboardInterrupt>(py) {
                        interrupted = true;
                    } else {
                        callback_error = Some(e);
                    }
                }
            }
            if finished {
                break;
            }
            finished = py.detach(|| {
                let (flag, wake) = &done_signal;
                let guard = flag.lock().unwrap_or_else(|e| e.into_inner());
                let (guard, _) = wake
                    .wait_timeout_while(guard, POLL, |done| !*done)
                    .unwrap_or_else(|e| e.into_inner());
                *guard
            });
        }
        worker.join()
    });
    let output = output.map_err(|payload| crate::errors::panic_error(payload.as_ref()))?;
    match callback_error {
        Some(e) => Err(e),
        None => Ok((output, interrupted)),
    }
}

/// How a Monte Carlo binding was asked to run: the whole set here, one
/// chunk of runs (a Dask task), or a fold of chunks computed elsewhere.
pub enum Ran<'py, T> {
    /// The runs `run_range` encoded for a later fold.
    Chunk(Bound<'py, PyBytes>),
    /// The result and whether Ctrl-C interrupted it.
    Done(T, bool),
}

/// Runs `experiment` as its binding's keywords ask: `run_range=(start,
/// end)` computes those runs (every one, GIL released) and returns them
/// encoded; `chunks=[...]` folds such encoded runs in run order; neither
/// runs the whole set through [`run_interruptible`]. The numbers are the
/// same bit for bit whichever way (`memsnav_core::montecarlo::fold_chunks`).
pub fn run_monte_carlo<'py, M: MonteCarlo>(
    py: Python<'py>,
    experiment: &M,
    run_range: Option<(usize, usize)>,
    chunks: Option<Vec<Bound<'py, PyBytes>>>,
    threads: Option<usize>,
    progress: Option<&Bound<'py, PyAny>>,
) -> PyResult<Ran<'py, M::Output>>
where
    M::Output: Send,
{
    if threads == Some(0) {
        return Err(PyValueError::new_err(
            "threads: must be at least 1 (or None)",
        ));
    }
    match (run_range, chunks) {
        (Some(_), Some(_)) => Err(PyValueError::new_err(
            "run_range, chunks: give one or the other",
        )),
        (Some((start, end)), None) => {
            let options = RunOptions {
                threads,
                ..Default::default()
            };
            let bytes = py
                .detach(|| montecarlo::run_chunk(experiment, start..end, &options))
                .py()?;
            Ok(Ran::Chunk(PyBytes::new(py, &bytes)))
        }
        (None, Some(chunks)) => {
            let slices: Vec<&[u8]> = chunks.iter().map(|c| c.as_bytes()).collect();
            let out = montecarlo::fold_chunks(experiment, &slices).py()?;
            Ok(Ran::Done(out, false))
        }
        (None, None) => {
            let (out, interrupted) =
                run_interruptible(py, progress, experiment.runs(), threads, |o| {
                    montecarlo::execute(experiment, o)
                })?;
            Ok(Ran::Done(out.py()?, interrupted))
        }
    }
}
