"""Monte Carlo sets on a Dask cluster (``docs/how-to/run-on-dask.md``).

Every experiment binding of ``memsnav._memsnav`` runs a whole set when
called plainly, computes the runs ``run_range=(start, end)`` and returns
them encoded when asked, and folds ``chunks=[...]`` of such encoded runs in
run order. :func:`run_set` uses the three: with no client it calls the
binding once (rayon threads here); with a ``dask.distributed.Client`` it
submits one task per chunk of runs (each one GIL-free Rust call on a
worker), gathers them as they complete and folds them here. Run i draws
only from ``(seed, i)`` and the fold takes runs in run order, so the
numbers are bit for bit those of local threads, whatever the workers or
the chunk size.

Dask is imported only when a client is given: the local default needs no
Dask installed.
"""

from __future__ import annotations

import uuid
from collections.abc import Callable, Mapping
from typing import Any

from memsnav import _memsnav

CHUNKS_PER_THREAD = 4
"""Default chunking: about this many chunks per worker thread, so a slow or
lost worker holds back a small share of the set and the progress bar moves."""


def chunk_ranges(runs: int, chunk_runs: int) -> list[tuple[int, int]]:
    """``[(0, c), (c, 2c), ...]`` covering ``range(runs)``."""
    return [(start, min(start + chunk_runs, runs)) for start in range(0, runs, chunk_runs)]


def _worker_threads() -> int | None:
    """The threads of the Dask worker running this task (rayon would
    otherwise take every core of its machine, once per worker process)."""
    from distributed import get_worker

    threads = getattr(get_worker().state, "nthreads", None)
    return int(threads) if threads else None


def run_chunk(binding: str, kwargs: Mapping[str, Any], run_range: tuple[int, int]) -> Any:
    """One Dask task: the runs ``run_range`` of the set ``binding(**kwargs)``
    describes (encoded for the fold, or the binding's arrays of those runs)."""
    function = getattr(_memsnav, binding)
    return function(**kwargs, run_range=run_range, threads=_worker_threads())


def _chunk_runs(client: Any, runs: int, chunk_runs: int | None) -> int:
    """``chunk_runs`` checked, or the default for ``runs`` on the cluster."""
    if chunk_runs is None:
        total_threads = sum(client.nthreads().values()) or 1
        return max(1, -(-runs // (CHUNKS_PER_THREAD * total_threads)))
    if not isinstance(chunk_runs, int) or isinstance(chunk_runs, bool) or chunk_runs < 1:
        raise ValueError(f"chunk_runs: must be a positive integer, got {chunk_runs!r}")
    return chunk_runs


def gather_ranges(
    client: Any,
    binding: str,
    kwargs: Mapping[str, Any],
    ranges: list[tuple[int, int]],
    progress: Callable[[int, int], object] | None = None,
) -> tuple[dict[int, Any], bool]:
    """Runs ``binding(**kwargs, run_range=r)`` for every range ``r`` on the
    client's cluster, one task each. Returns the results by range start
    and whether it was interrupted: ``progress(done, total)`` is called as
    ranges complete; Ctrl-C (or a ``KeyboardInterrupt`` from ``progress``)
    cancels the ranges not done and keeps the completed ones; any other
    exception from ``progress`` cancels them and is raised. A worker lost
    mid-range is retried by the scheduler on another worker (Dask
    reschedules the tasks of a lost worker, up to
    ``distributed.scheduler.allowed-failures`` times); the range is
    recomputed from its seeds, so the result does not change."""
    from distributed import as_completed

    total = sum(end - start for start, end in ranges)
    token = uuid.uuid4().hex[:12]
    futures = [
        client.submit(run_chunk, binding, dict(kwargs), r, key=f"memsnav-{binding}-{token}-{r[0]}")
        for r in ranges
    ]
    done: dict[int, Any] = {}
    completed = 0
    interrupted = False
    try:
        for future in as_completed(futures):  # type: ignore[no-untyped-call]
            start, end = ranges[futures.index(future)]
            done[start] = future.result()
            completed += end - start
            if progress is not None:
                progress(completed, total)
    except KeyboardInterrupt:
        interrupted = True
    finally:
        pending = [f for f in futures if not f.done()]
        if pending:
            client.cancel(pending)
    # Ranges that finished while the loop was being interrupted are kept too.
    for future, (start, _) in zip(futures, ranges, strict=True):
        if start not in done and future.status == "finished":
            done[start] = future.result()
    return done, interrupted


def run_set(
    binding: str,
    kwargs: Mapping[str, Any],
    runs: int,
    *,
    client: Any = None,
    threads: int | None = None,
    progress: Callable[[int, int], object] | None = None,
    chunk_runs: int | None = None,
) -> Any:
    """The binding's result dict for the whole set: run here (``client``
    None) or as chunks of ``chunk_runs`` runs on the client's cluster
    (:func:`gather_ranges`), folded here in run order; an interrupted set
    folds the chunks completed.
    """
    function = getattr(_memsnav, binding)
    if client is None:
        return function(**kwargs, threads=threads, progress=progress)
    if threads is not None:
        raise ValueError("threads: not used with a client (each worker uses its own threads)")
    chunk_runs = _chunk_runs(client, runs, chunk_runs)
    # Refuse a bad configuration here, before shipping it: the fold of no
    # chunk validates it as the whole set would.
    function(**kwargs, chunks=[])
    done, interrupted = gather_ranges(
        client, binding, kwargs, chunk_ranges(runs, chunk_runs), progress
    )
    raw = function(**kwargs, chunks=[done[start] for start in sorted(done)])
    raw["interrupted"] = bool(raw["interrupted"]) or interrupted
    return raw


def run_ranges(
    binding: str,
    kwargs: Mapping[str, Any],
    run_range: tuple[int, int],
    *,
    client: Any = None,
    threads: int | None = None,
    progress: Callable[[int, int], object] | None = None,
    chunk_runs: int | None = None,
) -> tuple[list[Any], bool]:
    """The binding's results for the runs ``run_range`` of a set whose
    binding computes any range and returns its arrays
    (``outage_study_runs``): one call here, or chunks of ``chunk_runs`` runs
    on the client's cluster; and whether Ctrl-C interrupted them. In run
    order: of an interrupted set, the completed ranges up to the first
    missing one."""
    if client is None:
        raw = getattr(_memsnav, binding)(
            **kwargs, run_range=run_range, threads=threads, progress=progress
        )
        return [raw], bool(raw["interrupted"])
    if threads is not None:
        raise ValueError("threads: not used with a client (each worker uses its own threads)")
    first, last = run_range
    chunk_runs = _chunk_runs(client, last - first, chunk_runs)
    ranges = [(first + a, first + b) for a, b in chunk_ranges(last - first, chunk_runs)]
    done, interrupted = gather_ranges(client, binding, kwargs, ranges, progress)
    out = []
    for start, _ in ranges:
        if start not in done:
            break
        out.append(done[start])
    return out, interrupted


def connect(address: str) -> Any:
    """A ``dask.distributed.Client`` of the scheduler at ``address``
    (``tcp://host:8786``); a clear error when Dask is not installed."""
    try:
        from distributed import Client
    except ImportError:
        raise ValueError(
            "scheduler: running on a Dask cluster needs Dask: pip install 'memsnav[dask]'"
        ) from None
    try:
        return Client(address, timeout="20s")  # type: ignore[no-untyped-call]
    except (OSError, TimeoutError) as e:
        raise ValueError(f"scheduler: cannot reach the Dask scheduler at {address!r}: {e}") from e
