"""``memsnav reproduce``: the paper's study end to end (figures 3-18, and the
partial-outage study its conclusion calls for), written as ``report.html``,
``summary.json``, the figures (PNG, SVG) and the curves behind them (CSV).

``summary.json`` holds every number the report states: per experiment its
planned and completed runs and state (``completed``, ``interrupted`` or
``not run``), the experiments' summaries, and ``claims``: each paper claim
with its verdict, computed by :func:`memsnav.report.claims.evaluate_claims`
from the rest of the file.
"""

from __future__ import annotations

import json
import math
import os
import platform
import time
from collections.abc import Callable
from dataclasses import dataclass, field
from pathlib import Path
from typing import Any

import matplotlib
import numpy as np

import memsnav
from memsnav import experiments
from memsnav._files import output_folder, write_text
from memsnav._progress import ProgressBar
from memsnav.report.claims import evaluate_claims
from memsnav.report.study import build_report

# The paper's total outage: 30 s out of 600 s. It starts at 300 s, well after
# the calibration transient of the first 150 s.
OUTAGE = (300.0, 30.0, 0)

EXPERIMENTS = (
    "calibration",
    "inversion",
    "navigation_nominal",
    "navigation_outage",
    "partial_outage",
)
"""The experiments of the study, in run order."""


@dataclass(frozen=True)
class Sizes:
    """Monte Carlo sizes of the study."""

    calibration_sets: int
    calibration_runs: int
    inversion_runs: int
    navigation_runs: int
    partial_outage_runs: int

    def as_dict(self) -> dict[str, Any]:
        return {
            "calibration": {
                "parameter_sets": self.calibration_sets,
                "runs_per_set": self.calibration_runs,
            },
            "inversion": self.inversion_runs,
            "navigation": self.navigation_runs,
            "partial_outage": self.partial_outage_runs,
        }

    def planned(self, experiment: str) -> int:
        """Runs ``experiment`` is to complete."""
        return {
            "calibration": self.calibration_sets * self.calibration_runs,
            "inversion": self.inversion_runs,
            "navigation_nominal": self.navigation_runs,
            "navigation_outage": self.navigation_runs,
            "partial_outage": self.partial_outage_runs,
        }[experiment]


# Quick: readable curves in about a minute on two cores.
QUICK = Sizes(
    calibration_sets=50,
    calibration_runs=100,
    inversion_runs=300,
    navigation_runs=100,
    partial_outage_runs=30,
)
# The paper's Monte Carlo counts (§5): 1000 runs x 50 sets, 300, 200; the
# partial-outage study (not in the paper) with 100 runs.
FULL = Sizes(
    calibration_sets=50,
    calibration_runs=1000,
    inversion_runs=300,
    navigation_runs=200,
    partial_outage_runs=100,
)


@dataclass
class ReproduceResult:
    """Where the study was written and what it found."""

    out: Path
    report: Path
    summary: dict[str, Any]
    interrupted: bool = False
    figures: list[str] = field(default_factory=list)


def worker_threads(threads: int | None) -> int:
    """The threads the experiments run on: ``threads``, else every core
    this process may use (rayon's default)."""
    if threads is not None:
        return threads
    try:
        return len(os.sched_getaffinity(0))
    except AttributeError:  # not on Linux
        return os.cpu_count() or 1


def reproduce(
    out: str | Path = "results",
    *,
    full: bool = False,
    runs: int | None = None,
    seed: int = 0,
    threads: int | None = None,
    progress: bool | Callable[[str], Callable[[int, int], None]] = True,
    client: Any = None,
) -> ReproduceResult:
    """Runs the calibration, inversion and navigation experiments (nominal,
    with the 30 s total outage, and the partial-outage study) and writes
    the study into ``out``.

    ``full`` uses the paper's Monte Carlo counts; ``runs`` overrides every
    count (calibration: runs per parameter set). The nominal and the outage
    navigation experiments share ``seed``, so they fly the same trajectories
    with the same sensor draws and differ only by the outage. Ctrl-C stops
    the running experiment, keeps its completed runs, skips the rest and
    still writes the report of what ran: the summary then records each
    experiment's completed runs and state, and the claims that need an
    incomplete experiment are ``not evaluated``. ``client``: a
    ``dask.distributed.Client`` to run every experiment on its cluster
    (``docs/how-to/run-on-dask.md``; the same numbers, ``threads`` unused).
    """
    if runs is not None and runs <= 0:
        raise ValueError(f"runs: must be positive, got {runs}")
    if threads is not None and threads <= 0:
        raise ValueError(f"threads: must be positive, got {threads}")
    if client is not None and threads is not None:
        raise ValueError("threads: not used with a client (each worker uses its own threads)")
    directory = output_folder(out)
    matplotlib.use("Agg")
    sizes = FULL if full else QUICK
    if runs is not None:
        sizes = Sizes(sizes.calibration_sets, runs, runs, runs, runs)

    def bar(label: str) -> Callable[[int, int], None] | None:
        if callable(progress):
            return progress(label)
        return ProgressBar(label) if progress else None

    start = time.perf_counter()
    results: dict[str, Any] = {}
    plan: dict[str, Callable[[], Any]] = {
        "calibration": lambda: experiments.calibration(
            parameter_sets=sizes.calibration_sets,
            runs=sizes.calibration_runs,
            seed=seed,
            threads=threads,
            progress=bar("calibration"),
            client=client,
        ),
        "inversion": lambda: experiments.inversion(
            runs=sizes.inversion_runs,
            seed=seed,
            threads=threads,
            progress=bar("inversion"),
            client=client,
        ),
        "navigation_nominal": lambda: experiments.navigation(
            outage=None,
            runs=sizes.navigation_runs,
            seed=seed,
            threads=threads,
            progress=bar("navigation, nominal"),
            client=client,
        ),
        "navigation_outage": lambda: experiments.navigation(
            outage=OUTAGE,
            runs=sizes.navigation_runs,
            seed=seed,
            threads=threads,
            progress=bar("navigation, outage"),
            client=client,
        ),
        "partial_outage": lambda: experiments.partial_outage(
            runs=sizes.partial_outage_runs,
            seed=seed,
            threads=threads,
            progress=bar("partial outages"),
            client=client,
        ),
    }
    interrupted = False
    for name in EXPERIMENTS:
        result = plan[name]()
        results[name] = result
        if result.interrupted:
            interrupted = True
            break
    elapsed = time.perf_counter() - start

    summary = study_summary(results, sizes, seed=seed, full=full, threads=threads)
    summary["interrupted"] = interrupted
    summary["elapsed_s"] = elapsed
    summary = json_safe(summary)
    # The verdicts from the summary exactly as written: anyone can recompute
    # them from summary.json.
    summary["claims"] = evaluate_claims(summary)
    report = build_report(results, summary)
    report_path = report.write(directory)
    write_text(
        directory / "summary.json",
        json.dumps(json_safe(summary), indent=2, allow_nan=False) + "\n",
    )
    return ReproduceResult(directory, report_path, summary, interrupted, report.figure_names)


def _state(result: Any, planned: int) -> dict[str, Any]:
    if result is None:
        return {"planned_runs": planned, "completed_runs": 0, "state": "not run"}
    done = int(result.completed_runs)
    complete = done == planned and not result.interrupted
    return {
        "planned_runs": planned,
        "completed_runs": done,
        "state": "completed" if complete else "interrupted",
    }


def _navigation(result: Any) -> dict[str, Any] | None:
    """A navigation experiment's summary: per IMU, the raw-minus-calibrated
    MEMS paired differences, the window key names, the runs and config."""
    if result is None:
        return None
    out: dict[str, Any] = {
        "imus": result.summary(),
        "early_key": result.early_key,
        "late_key": result.late_key,
        "completed_runs": result.completed_runs,
        "interrupted": result.interrupted,
        "config": dict(result.config),
    }
    if {"mems", "calibrated_mems"} <= set(result.imus):
        out["paired_imus"] = ["mems", "calibrated_mems"]
        out["paired"] = result.paired_difference("mems", "calibrated_mems")
    return out


def sizes_label(sizes: Sizes) -> str:
    """What the Monte Carlo sizes were, in words: ``quick``, ``the paper's``,
    or the runs given (``--runs N``)."""
    if sizes == QUICK:
        return "quick"
    if sizes == FULL:
        return "the paper's"
    runs = {
        sizes.calibration_runs,
        sizes.inversion_runs,
        sizes.navigation_runs,
        sizes.partial_outage_runs,
    }
    if len(runs) == 1:
        return f"{runs.pop()} runs per experiment"
    return "custom"


def study_summary(
    results: dict[str, Any],
    sizes: Sizes,
    *,
    seed: int,
    full: bool,
    threads: int | None,
) -> dict[str, Any]:
    """The summary of the experiments that ran (``None`` for the others),
    without the claims, the elapsed time and the interruption flag."""
    get = results.get

    def summary_of(name: str) -> dict[str, Any] | None:
        result = get(name)
        return None if result is None else result.summary()

    return {
        "experiments": {name: _state(get(name), sizes.planned(name)) for name in EXPERIMENTS},
        "calibration": summary_of("calibration"),
        "inversion": summary_of("inversion"),
        "navigation": {
            "nominal": _navigation(get("navigation_nominal")),
            "outage": _navigation(get("navigation_outage")),
        },
        "partial_outage": summary_of("partial_outage"),
        "runs": sizes.as_dict(),
        "seed": seed,
        "full": full,
        "sizes": sizes_label(sizes),
        "memsnav_version": memsnav.__version__,
        "machine": {
            "platform": platform.platform(),
            "processor": platform.processor() or platform.machine(),
            "python": platform.python_version(),
            "threads": worker_threads(threads),
        },
    }


def json_safe(value: Any) -> Any:
    """Plain JSON: numpy scalars and arrays as numbers and lists, tuples as
    lists, NaN and infinities as null."""
    if isinstance(value, dict):
        return {str(k): json_safe(v) for k, v in value.items()}
    if isinstance(value, np.ndarray):
        return json_safe(value.tolist())
    if isinstance(value, list | tuple):
        return [json_safe(v) for v in value]
    if isinstance(value, np.generic):
        value = value.item()
    if isinstance(value, float) and not math.isfinite(value):
        return None
    return value
