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
    runs = 20                          # per cell, the first look
    max_runs = 640                     # run open cells on, doubling, up to this
    # systems = ["G", "E", "C"]        # optional: GPS, Galileo, BeiDou MEO (R: GLONASS)
    # n_satellites = 20                # tracked outside the outage
    # inter_system_bias = [3.0, -25.0] # Galileo, BeiDou[, GLONASS] minus GPS, m
    # carrier_phase_std = 0.003        # carrier phase for the tight filter, m
    # cycle_slip_probability = 0.01    # silent slips per satellite and epoch
    [requirement]                      # optional: what "good enough" means
    max_error_m = 10.0
    percentile = 95
    confidence = 0.95                  # of each cell's decision

Unknown keys are refused with the file and the key named: a typo must not
silently drop a setting.
"""

from __future__ import annotations

import html
import json
import time
from collections.abc import Callable
from dataclasses import dataclass
from pathlib import Path
from typing import Any

import matplotlib
import numpy as np

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
from memsnav.experiments.outage_study import (
    CONFIDENCE,
    METRICS,
    OutageStudyResult,
    outage_study,
)
from memsnav.report import numbers as fmt
from memsnav.report.document import Report
from memsnav.reproduce import json_safe

CONFIG: dict[str, dict[str, tuple[Check, Any]]] = {
    "": {"output": (pathname(), "study")},
    "study": {
        "grades": (list_of(text(), min_length=1), ABSENT),
        "outage_lengths": (list_of(number(above=0.0), min_length=1), ABSENT),
        "visible_satellites": (list_of(integer(0, 3), min_length=1), ABSENT),
        "runs": (integer(1), ABSENT),
        "max_runs": (integer(1), ABSENT),
        "duration": (number(above=0.0), ABSENT),
        "outage_start": (number(above=0.0), ABSENT),
        "seed": (integer(0), ABSENT),
        "calibrated": (flag(), ABSENT),
        "smooth": (flag(), ABSENT),
        "calibration_duration": (number(above=0.0), ABSENT),
        "chunk_runs": (integer(1), ABSENT),
        "n_satellites": (integer(4), ABSENT),
        "systems": (list_of(text("G", "E", "C", "R"), min_length=1), ABSENT),
        "inter_system_bias": (list_of(number(), lengths=(2, 3)), ABSENT),
        "carrier_phase_std": (number(0.0), ABSENT),
        "cycle_slip_probability": (number(0.0, 1.0), ABSENT),
    },
    "requirement": {
        "max_error_m": (number(above=0.0), ABSENT),
        "percentile": (number(0.0, 100.0), ABSENT),
        "metric": (text(*METRICS), ABSENT),
        "confidence": (number(0.5, 0.9999), ABSENT),
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


HEAVY_TAIL = 10.0
"""A set of runs is flagged when its largest error exceeds this many times
its median: a few runs far from the rest (a filter or smoother that lost
its way), which a percentile of a few runs may hide."""

METRIC_WORDS = {
    "horizontal_end": "horizontal error at the outage end",
    "horizontal_max": "largest horizontal error in the outage",
    "error_3d_end": "3D error at the outage end",
    "error_3d_max": "largest 3D error in the outage",
}
"""Each metric of the requirement in words."""


@dataclass(frozen=True)
class Requirement:
    """What "good enough" means: a ``percentile`` of ``metric`` over the
    runs at most ``max_error_m`` (None: no requirement, only the figures),
    decided at ``confidence``."""

    max_error_m: float | None
    percentile: float
    metric: str
    confidence: float = CONFIDENCE

    @classmethod
    def of(cls, table: dict[str, Any]) -> Requirement:
        """From the configuration's ``[requirement]`` table."""
        max_error = table.get("max_error_m")
        return cls(
            None if max_error is None else float(max_error),
            float(table.get("percentile", 95.0)),
            str(table.get("metric", "horizontal_end")),
            float(table.get("confidence", CONFIDENCE)),
        )

    @property
    def words(self) -> str:
        """ "horizontal error at the outage end within 10 m in 95 % of runs"."""
        limit = "" if self.max_error_m is None else f" within {self.max_error_m:g} m"
        return f"{METRIC_WORDS[self.metric]}{limit} in {self.percentile:g} % of runs"


def answer(result: OutageStudyResult, requirement: Requirement) -> dict[int, dict[str, Any]]:
    """Per satellites count and grade: the longest outage met with every
    shorter one, each cell decided at the study's confidence
    (``longest_met_s``, None when not even the shortest), whether the
    answer is settled (``decided``: the next length failed, or it is the
    longest studied), and the cell that shows it (``length_s``: the
    longest met, else the open or failed one) with its ``decision``, its
    percentile (``percentile_m``), the one-sided bounds the decision rests
    on (``interval_m``, each at the per-look error) and its ``runs``."""
    if requirement.max_error_m is None:
        return {}
    out: dict[int, dict[str, Any]] = {}
    for n in result.visible_satellites:
        out[n] = {}
        for grade in result.grades:
            cells = [result.cell(grade, length, n) for length in result.outage_lengths]
            longest = None
            shown = cells[-1]
            decided = True
            for cell in cells:
                if cell.decision != "meets":
                    decided = cell.decision == "fails"
                    # A settled answer shows the longest outage met, if any;
                    # an open one the cell still open.
                    if not decided or longest is None:
                        shown = cell
                    break
                longest = cell.length_s
                shown = cell
            values = result.per_run(grade, shown.length_s, n, requirement.metric)
            out[n][grade] = {
                "longest_met_s": longest,
                "decided": decided,
                "length_s": shown.length_s,
                "decision": shown.decision,
                "percentile_m": float(np.percentile(values, requirement.percentile)),
                "interval_m": None if shown.interval_m is None else list(shown.interval_m),
                "runs": shown.runs,
            }
    return out


def _answer_cell(entry: dict[str, Any], requirement: Requirement) -> str:
    met = entry["longest_met_s"]
    percentile = fmt.beside(entry["percentile_m"], requirement.max_error_m)
    figure = f"p{requirement.percentile:g} {percentile} m"
    if entry["interval_m"] is not None:
        lower, upper = entry["interval_m"]
        figure += " " + fmt.interval(lower, upper, digits=2, limit=requirement.max_error_m)
    figure += f", {entry['runs']} runs"
    length = f"{fmt.number(entry['length_s'], 4)} s"
    if not entry["decided"]:
        where = "none" if met is None else f"{fmt.number(met, 4)} s"
        return f"{where}, {length} open: {figure}"
    if met is None:
        return f"none ({length}: {figure})"
    return f"{length}: {figure}"


def answer_lines(summary: dict[str, Any]) -> list[str]:
    """The answer in a few lines: per grade, the longest outage it meets
    with each satellites count, decided at the study's confidence, with the
    percentile there, its interval and runs; then which answers are
    decided and what is left open."""
    table = summary.get("answer") or {}
    if not table:
        return ["memsnav study: no [requirement] max_error_m: the report has the figures only"]
    requirement = Requirement.of(summary["requirement"])
    config = summary["config"]
    counts = list(table)
    grades = list(table[counts[0]])
    cells = [[_answer_cell(table[n][g], requirement) for n in counts] for g in grades]
    width = max(len(g) for g in grades)
    column = max(len(c) for row in cells for c in row)
    header = (
        "  "
        + " " * width
        + "  "
        + "  ".join(
            f"{int(n)} satellite{'' if int(n) == 1 else 's'} kept".ljust(column) for n in counts
        )
    )
    confidence = f"{requirement.confidence * 100:g} %"
    lines = [
        f"Longest outage with the {requirement.words}, decided at {confidence} confidence "
        "(forward filter; interval and runs of the cell shown):",
        header.rstrip(),
    ]
    lines += [
        "  " + g.ljust(width) + "  " + "  ".join(c.ljust(column) for c in row).rstrip()
        for g, row in zip(grades, cells, strict=True)
    ]
    entries = [(n, g, table[n][g]) for n in counts for g in grades]
    open_ = [
        f"{g} with {int(n)} kept ({fmt.number(e['length_s'], 4)} s)"
        for n, g, e in entries
        if not e["decided"]
    ]
    looks = config.get("looks") or []
    if not open_:
        lines.append(
            f"  All {len(entries)} answers decided at {confidence} confidence "
            f"({len(looks)} look{'' if len(looks) == 1 else 's'}, each bound at "
            f"{(1 - config['look_error']) * 100:.3g} %)."
        )
    else:
        why = (
            f"the cap of {config['max_runs']} runs per cell reached"
            if config.get("max_runs") and not summary.get("interrupted")
            else "interrupted"
            if summary.get("interrupted")
            else "give [study] max_runs to run them until decided"
        )
        lines.append(
            f"  {len(entries) - len(open_)} of {len(entries)} answers decided at {confidence} "
            f"confidence; open: {', '.join(open_)} ({why})."
        )
    return lines


def flags(result: OutageStudyResult, metric: str) -> list[str]:
    """The sets a percentile may hide something in: runs that raised an
    integrity alert, and runs far from the rest (the largest error more than
    :data:`HEAVY_TAIL` times the median), forward and smoothed (whose
    largest error in the outage is the figure: GNSS pins its end)."""
    out = []
    views = (
        [(False, metric), (True, metric.replace("_end", "_max"))]
        if result.config["smooth"]
        else [(False, metric)]
    )
    for n in result.visible_satellites:
        for grade in result.grades:
            for length in result.outage_lengths:
                for smoothed, shown in views:
                    cell = result.cell(grade, length, n)
                    runs = cell.smoothed if smoothed and cell.smoothed else cell.forward
                    values = result.per_run(grade, length, n, shown, smoothed)
                    where = (
                        f"{grade}, {fmt.number(length, 4)} s, {n} satellite"
                        f"{'' if n == 1 else 's'} kept{', smoothed' if smoothed else ''}"
                    )
                    alerts = int(np.sum(runs["diverged"]))
                    if alerts:
                        out.append(
                            f"{where}: {alerts} of {len(values)} runs raised an integrity alert"
                        )
                    median, largest = np.median(values), np.max(values)
                    if largest > HEAVY_TAIL * median:
                        p95 = fmt.number(np.percentile(values, 95.0))
                        out.append(
                            f"{where}: largest run {fmt.number(largest)} m against a median of "
                            f"{fmt.number(median, 2)} m (p95 {p95} m): a few runs far from the rest"
                        )
    return out


def table_cells(
    result: OutageStudyResult, n: int, requirement: Requirement
) -> dict[str, list[str]]:
    """Per grade, one cell per outage length: "median / percentile" of the
    requirement's metric over the runs (the percentile on the side of the
    requirement it is on: :func:`memsnav.report.numbers.beside`), and in
    brackets the smoothed solution's percentile of its largest error in
    the outage (when smoothed); then the cell's runs and decision."""
    metric, percentile = requirement.metric, requirement.percentile
    out: dict[str, list[str]] = {}
    for grade in result.grades:
        row = []
        for length in result.outage_lengths:
            values = result.per_run(grade, length, n, metric)
            cell = (
                f"{fmt.number(np.percentile(values, 50.0), 2)} / "
                f"{fmt.beside(np.percentile(values, percentile), requirement.max_error_m)}"
            )
            if result.config["smooth"]:
                smoothed = result.per_run(grade, length, n, metric.replace("_end", "_max"), True)
                cell += f" ({fmt.number(np.percentile(smoothed, percentile), 2)})"
            decided = result.cell(grade, length, n)
            cell += f" · {decided.runs} runs" + (
                f", {decided.decision}" if decided.decision else ""
            )
            row.append(cell)
        out[grade] = row
    return out


def _report(
    result: OutageStudyResult, requirement: Requirement, summary: dict[str, Any], elapsed_s: float
) -> Report:
    report = Report("memsnav outage study")
    c = result.config
    report.section("The answer")
    table = summary.get("answer") or {}
    if table:
        lines = answer_lines(summary)
        report.paragraph(lines[0])
        counts = list(table)
        report.table(
            ["grade"] + [f"{n} satellite{'' if int(n) == 1 else 's'} kept" for n in counts],
            [
                [grade] + [_answer_cell(table[n][grade], requirement) for n in counts]
                for grade in table[counts[0]]
            ],
        )
        report.paragraph(
            "Each cell: the longest outage the grade meets with every shorter one, each "
            f"decided at {requirement.confidence * 100:g} % confidence, and there the "
            f"p{requirement.percentile:g} over the runs with the one-sided bounds the decision "
            "rests on, from the runs' order statistics (distribution-free: with n runs the k-th "
            "smallest lies above the percentile with the binomial probability of at most k − 1 "
            "runs below it; ∞: too few runs to bound it from above). A cell meets the "
            "requirement when its upper bound is within it and fails when its lower bound is "
            "beyond; the study runs the cells still open in looks up to max_runs, each look's "
            "bounds erring with the largest common probability that keeps a decision, whichever "
            "look makes it, wrong with at most the complementary probability (counted exactly: "
            "the looks share their runs). "
            '"open": the cell shown is not decided yet. ' + lines[-1].strip()
        )
    else:
        report.paragraph("No [requirement] max_error_m: the figures below, without a verdict.")
    runs = [cell.runs for cell in result.cells.values()]
    report.paragraph(
        f"{len(result.grades)} IMU grades x {len(result.outage_lengths)} outage lengths x "
        f"{len(result.visible_satellites)} satellite counts, {min(runs)}-{max(runs)} runs per "
        f"cell ({sum(runs)} cell runs) drawn for {c['duration']:.0f} s (outage from "
        f"{c['outage_start']:.0f} s), seed {c['seed']}; paired draws across grades, lengths "
        f"and counts; {elapsed_s:.0f} s of wall time"
        + (" (interrupted: partial results)." if result.interrupted else ".")
    )
    report.section("Runs a percentile may hide")
    flagged = flags(result, requirement.metric)
    if flagged:
        report.html("<ul>" + "".join(f"<li>{html.escape(f)}</li>" for f in flagged) + "</ul>")
    else:
        report.paragraph(
            "None: no run raised an integrity alert, and in every set the largest error is "
            f"within {HEAVY_TAIL:g} times the median."
        )
    report.section("Error vs outage length")
    report.figure(
        "outage_study",
        result.plot(
            max_error_m=requirement.max_error_m,
            percentile=requirement.percentile,
            metric=requirement.metric,
        ),
        f"p{requirement.percentile:g} of the {METRIC_WORDS[requirement.metric]} over the runs, "
        "per grade, log-log; "
        + (
            f"requirement {requirement.max_error_m:g} m dotted."
            if requirement.max_error_m is not None
            else "no requirement."
        ),
    )
    metric = METRIC_WORDS[requirement.metric]
    for n in result.visible_satellites:
        report.section(f"{n} satellite{'' if n == 1 else 's'} kept")
        cells = table_cells(result, n, requirement)
        report.table(
            ["grade"] + [f"{fmt.number(length, 4)} s" for length in result.outage_lengths],
            [[grade, *row] for grade, row in cells.items()],
        )
    report.paragraph(
        f"Each cell: median / p{requirement.percentile:g} of the {metric} over the cell's runs, "
        "m"
        + (
            f"; in brackets the smoothed solution's p{requirement.percentile:g} of its largest "
            "error in the outage (the GNSS epoch that ends the outage pins its error at the end)"
            if c["smooth"]
            else ""
        )
        + "; then the cell's runs and its decision. Every metric's median, p95 and maximum "
        "(horizontal and 3D, at the end and the largest in the outage, forward and smoothed) "
        "are in summary.json; the smoothed figures come from the first look's runs."
    )
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
    requirement = Requirement.of(config["requirement"])
    decision_keys: dict[str, Any] = (
        {}
        if requirement.max_error_m is None
        else {
            "max_error_m": requirement.max_error_m,
            "percentile": requirement.percentile,
            "metric": requirement.metric,
            "confidence": requirement.confidence,
        }
    )
    try:
        result = outage_study(
            **config["study"], **decision_keys, threads=threads, client=client, progress=bar
        )
    except ValueError as e:
        # outage_study names its keyword: the [study] key of the same name.
        raise ValueError(f"{config_path}: study: {e}") from None
    elapsed = time.perf_counter() - start
    summary: dict[str, Any] = {
        "config": result.config,
        "completed_runs": result.completed_runs,
        "interrupted": result.interrupted,
        "elapsed_s": elapsed,
        "forward": {n: result.summary(n) for n in result.visible_satellites},
        "requirement": config["requirement"],
    }
    if result.config["smooth"]:
        summary["smoothed"] = {n: result.summary(n, True) for n in result.visible_satellites}
    if requirement.max_error_m is not None:
        summary["meets"] = {
            n: result.meets(
                requirement.max_error_m,
                requirement.percentile,
                n_visible=n,
                metric=requirement.metric,
            )
            for n in result.visible_satellites
        }
        summary["answer"] = answer(result, requirement)
    summary = json_safe(summary)
    report = _report(result, requirement, summary, elapsed).write(directory)
    summary_path = directory / "summary.json"
    write_text(summary_path, json.dumps(summary, indent=2, allow_nan=False) + "\n")
    return StudyRun(
        {"report": report, "summary": summary_path}, result, summary, result.interrupted
    )
