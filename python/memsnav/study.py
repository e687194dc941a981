"""The outage study (:func:`memsnav.experiments.outage_study`) from a TOML
file, written as ``report.html``, ``summary.json`` and the figures (PNG,
SVG, CSV), like ``memsnav reproduce``: what ``memsnav study --config
study.toml`` runs.

The configuration (``examples/study_land_vehicle.toml``)::

    output = "../out/study_land_vehicle"   # folder, relative to the file
    [study]                            # the keywords of outage_study
    grades = ["consumer", "paper-mems", "industrial", "tactical", "navigation"]
    outage_lengths = [10, 30, 60, 120]
    visible_satellites = [0, 2, 3]
    runs = 20
    [requirement]                      # optional: what "good enough" means
    max_error_m = 10.0
    percentile = 95

Unknown keys are refused with the file and the key named: a typo must not
silently drop a setting.
"""

from __future__ import annotations

import json
import time
from collections.abc import Callable
from dataclasses import dataclass
from pathlib import Path
from typing import Any

import matplotlib

from memsnav._config import (
    ABSENT,
    Check,
    flag,
    integer,
    list_of,
    load_toml,
    number,
    pathname,
    read_table,
    resolve_path,
    split_tables,
    text,
)
from memsnav._files import output_folder, write_text
from memsnav._progress import ProgressBar
from memsnav.experiments.outage_study import METRICS, OutageStudyResult, outage_study
from memsnav.report.document import Report
from memsnav.reproduce import json_safe

CONFIG: dict[str, dict[str, tuple[Check, Any]]] = {
    "": {"output": (pathname(), "study")},
    "study": {
        "grades": (list_of(text(), min_length=1), ABSENT),
        "outage_lengths": (list_of(number(above=0.0), min_length=1), ABSENT),
        "visible_satellites": (list_of(integer(0, 3), min_length=1), ABSENT),
        "runs": (integer(1), ABSENT),
        "duration": (number(above=0.0), ABSENT),
        "outage_start": (number(above=0.0), ABSENT),
        "seed": (integer(0), ABSENT),
        "calibrated": (flag(), ABSENT),
        "smooth": (flag(), ABSENT),
        "calibration_duration": (number(above=0.0), ABSENT),
        "chunk_runs": (integer(1), ABSENT),
    },
    "requirement": {
        "max_error_m": (number(above=0.0), ABSENT),
        "percentile": (number(0.0, 100.0), ABSENT),
        "metric": (text(*METRICS), ABSENT),
    },
}
"""The tables and keys (``[study]``: the keywords of outage_study; a key
left out keeps its default), read by :mod:`memsnav._config`."""


@dataclass(frozen=True)
class StudyRun:
    """What ``memsnav study`` wrote and found."""

    files: dict[str, Path]
    result: OutageStudyResult
    summary: dict[str, Any]
    interrupted: bool


def read_config(path: str | Path) -> dict[str, Any]:
    """The configuration: ``output``, ``study`` (outage_study keywords)
    and ``requirement`` (may be empty); errors name the file and the key."""
    path = Path(path)
    tables = split_tables(path, load_toml(path), [t for t in CONFIG if t])
    if "study" not in tables:
        raise ValueError(f"{path}: missing the [study] table")
    values = {t: read_table(path, t, tables.get(t, {}), keys) for t, keys in CONFIG.items()}
    return {
        "output": resolve_path(values[""]["output"], path.parent),
        "study": values["study"],
        "requirement": values["requirement"],
    }


def _report(result: OutageStudyResult, requirement: dict[str, Any], elapsed_s: float) -> Report:
    report = Report("memsnav outage study")
    c = result.config
    report.paragraph(
        f"{len(result.grades)} IMU grades x {len(result.outage_lengths)} outage lengths x "
        f"{len(result.visible_satellites)} satellite counts, {result.completed_runs} runs per "
        f"set of {c['duration']:.0f} s (outage from {c['outage_start']:.0f} s), seed "
        f"{c['seed']}; paired draws across grades and lengths; {elapsed_s:.0f} s of wall time"
        + (" (interrupted: partial results)." if result.interrupted else ".")
    )
    percentile = float(requirement.get("percentile", 95.0))
    metric = str(requirement.get("metric", "horizontal_end"))
    max_error = requirement.get("max_error_m")
    for smoothed in (False, True) if c["smooth"] else (False,):
        solution = "smoothed" if smoothed else "forward filter"
        for n in result.visible_satellites:
            report.section(f"{n} satellite{'' if n == 1 else 's'} kept, {solution}")
            rows = []
            for grade, per_length in result.summary(n, smoothed).items():
                for length, f in per_length.items():
                    rows.append(
                        [grade, length]
                        + [f[m][k] for m in METRICS for k in ("p50_m", "p95_m", "max_m")]
                    )
            header = ["grade", "outage [s]"] + [
                f"{m} {k[:-2]} [m]" for m in METRICS for k in ("p50_m", "p95_m", "max_m")
            ]
            report.table(header, rows)
    report.section("Error vs outage length")
    report.figure(
        "outage_study",
        result.plot(max_error_m=max_error, percentile=percentile, metric=metric),
        f"p{percentile:g} of {metric.replace('_', ' ')} error over the runs, per grade; "
        + (f"requirement {max_error} m dotted." if max_error is not None else "no requirement."),
    )
    if max_error is not None:
        report.section(f"Which grades meet {max_error} m (p{percentile:g}, {metric})")
        rows = []
        for n in result.visible_satellites:
            meets = result.meets(float(max_error), percentile, n_visible=n, metric=metric)
            for grade, lengths in meets.items():
                rows.append([grade, n, ", ".join(f"{v:g} s" for v in lengths) or "none"])
        report.table(["grade", "satellites kept", "outage lengths met"], rows)
    return report


def run_study(
    config_path: str | Path,
    *,
    output: str | Path | None = None,
    threads: int | None = None,
    progress: bool | Callable[[int, int], object] = True,
    client: Any = None,
) -> StudyRun:
    """Runs the study of ``config_path`` and writes its report."""
    config = read_config(config_path)
    directory = output_folder(output if output is not None else config["output"])
    matplotlib.use("Agg")
    bar = progress if callable(progress) else (ProgressBar("outage study") if progress else None)
    start = time.perf_counter()
    try:
        result = outage_study(**config["study"], threads=threads, client=client, progress=bar)
    except ValueError as e:
        # outage_study names its keyword: the [study] key of the same name.
        raise ValueError(f"{config_path}: study: {e}") from None
    elapsed = time.perf_counter() - start
    requirement = config["requirement"]
    summary: dict[str, Any] = {
        "config": result.config,
        "completed_runs": result.completed_runs,
        "interrupted": result.interrupted,
        "elapsed_s": elapsed,
        "forward": {n: result.summary(n) for n in result.visible_satellites},
        "requirement": requirement,
    }
    if result.config["smooth"]:
        summary["smoothed"] = {n: result.summary(n, True) for n in result.visible_satellites}
    if "max_error_m" in requirement:
        summary["meets"] = {
            n: result.meets(
                float(requirement["max_error_m"]),
                float(requirement.get("percentile", 95.0)),
                n_visible=n,
                metric=str(requirement.get("metric", "horizontal_end")),
            )
            for n in result.visible_satellites
        }
    summary = json_safe(summary)
    report = _report(result, requirement, elapsed).write(directory)
    summary_path = directory / "summary.json"
    write_text(summary_path, json.dumps(summary, indent=2, allow_nan=False) + "\n")
    return StudyRun(
        {"report": report, "summary": summary_path}, result, summary, result.interrupted
    )
