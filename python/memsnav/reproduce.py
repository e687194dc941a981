"""``memsnav reproduce``: the paper's study end to end (figures 3-18), written
as ``report.html``, ``summary.json``, the figures (PNG, SVG) and the curves
behind them (CSV)."""

from __future__ import annotations

import json
import math
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
from memsnav._files import ensure_writable_directory, write_text
from memsnav._progress import ProgressBar
from memsnav.report.study import build_report

# The paper's total outage: 30 s out of 600 s. It starts at 300 s, well after
# the calibration transient of the first 150 s.
OUTAGE = (300.0, 30.0)


@dataclass(frozen=True)
class Sizes:
    """Monte Carlo sizes of the study."""

    calibration_sets: int
    calibration_runs: int
    inversion_runs: int
    navigation_runs: int

    def as_dict(self) -> dict[str, Any]:
        return {
            "calibration": {
                "parameter_sets": self.calibration_sets,
                "runs_per_set": self.calibration_runs,
            },
            "inversion": self.inversion_runs,
            "navigation": self.navigation_runs,
        }


# Quick: readable curves in about two minutes on two cores.
QUICK = Sizes(calibration_sets=50, calibration_runs=100, inversion_runs=300, navigation_runs=100)
# The paper's Monte Carlo counts (§5): 1000 runs x 50 sets, 300, 200.
FULL = Sizes(calibration_sets=50, calibration_runs=1000, inversion_runs=300, navigation_runs=200)


@dataclass
class ReproduceResult:
    """Where the study was written and what it found."""

    out: Path
    report: Path
    summary: dict[str, Any]
    interrupted: bool = False
    figures: list[str] = field(default_factory=list)


def reproduce(
    out: str | Path = "results",
    *,
    full: bool = False,
    runs: int | None = None,
    seed: int = 0,
    threads: int | None = None,
    progress: bool | Callable[[str], Callable[[int, int], None]] = True,
) -> ReproduceResult:
    """Runs the calibration, inversion and navigation experiments (nominal and
    with the 30 s outage) and writes the study into ``out``.

    ``full`` uses the paper's Monte Carlo counts; ``runs`` overrides every
    count (calibration: runs per parameter set). The nominal and the outage
    navigation experiments share ``seed``, so they fly the same trajectories
    with the same sensor draws and differ only by the outage. Ctrl-C stops
    the running experiment, keeps its completed runs, skips the rest and
    still writes the report of what ran.
    """
    if runs is not None and runs <= 0:
        raise ValueError(f"runs: must be positive, got {runs}")
    if threads is not None and threads <= 0:
        raise ValueError(f"threads: must be positive, got {threads}")
    directory = ensure_writable_directory(out)
    matplotlib.use("Agg")
    sizes = FULL if full else QUICK
    if runs is not None:
        sizes = Sizes(sizes.calibration_sets, runs, runs, runs)

    def bar(label: str) -> Callable[[int, int], None] | None:
        if callable(progress):
            return progress(label)
        return ProgressBar(label) if progress else None

    start = time.perf_counter()
    results: dict[str, Any] = {}
    interrupted = False
    plan: list[tuple[str, Callable[[], Any]]] = [
        (
            "calibration",
            lambda: experiments.calibration(
                parameter_sets=sizes.calibration_sets,
                runs=sizes.calibration_runs,
                seed=seed,
                threads=threads,
                progress=bar("calibration"),
            ),
        ),
        (
            "inversion",
            lambda: experiments.inversion(
                runs=sizes.inversion_runs, seed=seed, threads=threads, progress=bar("inversion")
            ),
        ),
        (
            "navigation_nominal",
            lambda: experiments.navigation(
                outage=None,
                runs=sizes.navigation_runs,
                seed=seed,
                threads=threads,
                progress=bar("navigation, nominal"),
            ),
        ),
        (
            "navigation_outage",
            lambda: experiments.navigation(
                outage=OUTAGE,
                runs=sizes.navigation_runs,
                seed=seed,
                threads=threads,
                progress=bar("navigation, outage"),
            ),
        ),
    ]
    for name, run in plan:
        result = run()
        results[name] = result
        if getattr(result, "interrupted", False):
            interrupted = True
            break
    elapsed = time.perf_counter() - start

    summary = {
        "calibration": results["calibration"].summary() if "calibration" in results else None,
        "inversion": results["inversion"].summary() if "inversion" in results else None,
        "navigation": {
            "nominal": _summary_of(results.get("navigation_nominal")),
            "outage": _summary_of(results.get("navigation_outage")),
        },
        "runs": sizes.as_dict(),
        "seed": seed,
        "full": full,
        "interrupted": interrupted,
        "elapsed_s": elapsed,
        "memsnav_version": memsnav.__version__,
        "machine": {
            "platform": platform.platform(),
            "processor": platform.processor() or platform.machine(),
            "python": platform.python_version(),
            "threads": threads,
        },
    }
    report = build_report(results, summary, outage=OUTAGE)
    report_path = report.write(directory)
    write_text(
        directory / "summary.json",
        json.dumps(_json_safe(summary), indent=2, allow_nan=False) + "\n",
    )
    return ReproduceResult(directory, report_path, summary, interrupted, report.figure_names)


def _json_safe(value: Any) -> Any:
    """Plain JSON: numpy scalars as numbers, NaN and infinities as null."""
    if isinstance(value, dict):
        return {str(k): _json_safe(v) for k, v in value.items()}
    if isinstance(value, list | tuple):
        return [_json_safe(v) for v in value]
    if isinstance(value, np.generic):
        value = value.item()
    if isinstance(value, float) and not math.isfinite(value):
        return None
    return value


def _summary_of(result: Any) -> dict[str, Any] | None:
    return None if result is None else result.summary()
