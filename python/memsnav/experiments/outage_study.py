"""Which IMU is good enough for my outages: a Monte Carlo sweep over IMU
grades, outage lengths and satellites kept through the outage.

For each outage length the study is one partial-outage set
(:mod:`memsnav.experiments.partial_outage`, tightly coupled): every grade
flies the same trajectories, GNSS draws and initial errors (paired draws
across grades), and the satellite counts differ only by the satellites the
window removes. Every length uses the same seed and run duration, so the
trajectories are shared across lengths too: the error at 30 s and at 60 s
come from the same runs. The numerics (every run) are in Rust; this module
chooses the sets, folds the per-run errors into distributions and reports.

Figures per grade, outage length and satellites kept, over the runs: the
horizontal and 3D position error at the end of the outage (the last epoch
before GNSS returns) and the largest during it, each as median, 95th
percentile and maximum. Percentiles are numpy's linear interpolation of
the per-run values; with ``runs`` runs the 95th percentile rests on the
``0.05 * runs`` worst runs: :meth:`OutageStudyResult.interval` says how
sure it is (from 20 runs it has no upper bound at 95 % confidence).

Every run is drawn once, for the longest outage, and each cell (grade,
length, count) filters its cut of it: the run ends at its outage's end, or
``TAIL_S`` after it when smoothing (the smoother needs GNSS after the
window). The filter is causal, so the forward figures are those of the
whole run, bit for bit.

Answering with confidence (``max_error_m`` and ``max_runs``): the study
runs in looks (:func:`looks`): ``runs`` per cell, then from the fewest
runs that can show a cell meets, doubling up to ``max_runs``. After each
look every cell still needed is decided from its runs' order statistics
(:func:`memsnav.quantile_interval`): it **meets** the requirement when the
percentile's one-sided upper confidence bound is at most ``max_error_m``,
**fails** when its one-sided lower bound is above, and runs on otherwise.
Every look's bounds err with the same probability (:func:`look_error`),
the largest that keeps a decision, whatever look makes it, wrong with
probability at most ``1 - confidence``: computed exactly from the
binomial count of runs within the requirement, which the looks share
(:func:`memsnav.sequential_look_error`); Bonferroni's
``(1 - confidence) / K`` over K looks would be safe but needlessly strict. A cell is needed while
no shorter outage of its grade and count has failed (the answer is the
longest outage met with every shorter one); the cells left are "not
needed". Run i draws from ``(seed, i)`` whichever cells and looks compute
it, so the figures are bit-identical across thread counts, looks and Dask
chunks; the smoothed figures come from the first look's runs.
"""

from __future__ import annotations

import math
from collections.abc import Callable, Mapping, Sequence
from dataclasses import dataclass
from typing import Any

import numpy as np
import numpy.typing as npt

import memsnav._memsnav as _mn
from memsnav._distributed import run_ranges
from memsnav.experiments.navigation import _imu_sources

GRADES = ("consumer", "paper-mems", "industrial", "tactical", "navigation")
"""The five presets, cheapest first."""

METRICS = {
    "horizontal_end": "horizontal_at_outage_end",
    "horizontal_max": "max_horizontal_in_outage",
    "error_3d_end": "at_outage_end",
    "error_3d_max": "max_in_outage",
}
"""Figure name → the per-run value of the navigation result it summarises:
horizontal or 3D error at the end of the outage, or the largest during it."""

CALIBRATED_SUFFIX = " calibrated"
"""Name of a grade's calibrated twin (same sensor, calibrated and inverted)."""

TAIL_S = 10.0
"""GNSS after each outage a smoothed cell's run keeps, s (and the default
run length beyond the longest outage)."""

DECISIONS = ("meets", "fails", "undecided", "not needed")
"""A cell's verdict on the requirement: its percentile's interval wholly
within it, wholly beyond it, neither yet, or not run on because a shorter
outage of its grade and satellites count failed."""

CONFIDENCE: float = _mn.defaults()["quantile_interval"]["confidence"]
"""The confidence of the decisions and intervals when none is given (the
core's, ``memsnav.defaults()``)."""

RUN_FIELDS = (*METRICS, "diverged", "rejected", "accepted")
"""The per-run values a cell keeps: the metrics (m), whether the run
raised an integrity alert, and the measurements rejected and accepted."""


def looks(
    runs: int, max_runs: int | None, percentile: float = 95.0, confidence: float | None = None
) -> list[int]:
    """The runs per cell after each look: ``runs``; then from the fewest
    runs that can show a cell meets the requirement (none of them beyond
    it, at the schedule's per-look error :func:`look_error`), doubling up
    to ``max_runs`` (the last look). ``[runs]`` without ``max_runs``.
    ``confidence`` None: :data:`CONFIDENCE`."""
    confidence = CONFIDENCE if confidence is None else confidence
    if max_runs is None or max_runs <= runs:
        return [runs]

    def schedule(error: float) -> list[int]:
        fewest = math.ceil(math.log(error) / math.log(percentile / 100.0))
        out = [runs]
        n = max(fewest, 2 * runs)
        while n < max_runs:
            out.append(n)
            n *= 2
        return [*out, max_runs]

    # Bonferroni's level over K looks gives a schedule of at most K looks
    # (the fewest such K). The schedule's exact level is higher, so fewer
    # runs can show a cell meets: bring the second look forward to them
    # while the moved schedule's own exact level still allows it.
    count = 2
    while len(out := schedule((1.0 - confidence) / count)) > count:
        count += 1
    while len(out) > 2:
        moved = schedule(look_error(out, percentile, confidence))
        can_meet = (percentile / 100.0) ** moved[1] <= look_error(moved, percentile, confidence)
        if moved[1] >= out[1] or not can_meet:
            break
        out = moved
    return out


def look_error(
    schedule: list[int], percentile: float = 95.0, confidence: float | None = None
) -> float:
    """The error each look's one-sided bounds may make so that a decision,
    whichever look of ``schedule`` makes it, errs with probability at most
    ``1 - confidence``: the largest such constant level, from the exact
    probability that the count of runs within the requirement crosses a
    look's bound (:func:`memsnav.sequential_look_error`). It is never below
    Bonferroni's ``(1 - confidence) / len(schedule)``. ``confidence`` None:
    :data:`CONFIDENCE`."""
    return _mn.sequential_look_error(schedule, percentile / 100.0, confidence)


@dataclass(frozen=True)
class StudyCell:
    """One cell of the study: a grade through one outage length with one
    satellites count kept. ``forward`` and ``smoothed`` (None without
    ``smooth``) hold per-run arrays of :data:`RUN_FIELDS`; ``decision`` is
    one of :data:`DECISIONS` (None without a requirement) and
    ``interval_m`` the percentile's one-sided bounds it rests on, each at
    the per-look error (None without a requirement)."""

    grade: str
    length_s: float
    n_visible: int
    forward: dict[str, npt.NDArray[Any]]
    smoothed: dict[str, npt.NDArray[Any]] | None
    decision: str | None
    interval_m: tuple[float, float] | None

    @property
    def runs(self) -> int:
        """The runs of the cell's forward figures."""
        return len(self.forward["horizontal_end"])

    def __repr__(self) -> str:
        verdict = "" if self.decision is None else f", {self.decision}"
        return (
            f"StudyCell({self.grade!r}, {self.length_s:g} s, {self.n_visible} satellites kept: "
            f"{self.runs} runs{verdict})"
        )


def _interval(
    values: npt.NDArray[np.float64], percentile: float, confidence: float | None
) -> dict[str, float]:
    """The ``confidence`` interval of the ``percentile`` from the finite runs."""
    finite = values[np.isfinite(values)]
    return _mn.quantile_interval(finite, percentile / 100.0, confidence).to_dict()


def decide(
    values: npt.NDArray[np.float64], max_error_m: float, percentile: float, error: float
) -> tuple[str, tuple[float, float]]:
    """A cell's verdict from its runs: "meets" when the ``percentile``'s
    one-sided upper confidence bound at ``1 - error`` is at most
    ``max_error_m``, "fails" when the one-sided lower bound at ``1 -
    error`` is above it, else "undecided"; with the two bounds (lower,
    upper), m: the equal-tailed interval at ``1 - 2 error``."""
    interval = _interval(values, percentile, 1.0 - 2.0 * error)
    lower, upper = float(interval["lower"]), float(interval["upper"])
    if upper <= max_error_m:
        return "meets", (lower, upper)
    if lower > max_error_m:
        return "fails", (lower, upper)
    return "undecided", (lower, upper)


def _distribution(values: npt.NDArray[np.float64]) -> dict[str, float]:
    values = values[np.isfinite(values)]
    if values.size == 0:
        return {"p50_m": math.nan, "p95_m": math.nan, "max_m": math.nan}
    return {
        "p50_m": float(np.percentile(values, 50.0)),
        "p95_m": float(np.percentile(values, 95.0)),
        "max_m": float(np.max(values)),
    }


@dataclass(frozen=True)
class OutageStudyResult:
    """Result of :func:`outage_study`.

    ``cells[(grade, length, n_visible)]`` is each :class:`StudyCell` (every
    grade's forward filter, and its smoothed solution when run with
    ``smooth=True``); ``grades`` the names in the set's order (calibrated
    twins included); ``completed_runs`` the runs every cell has (the
    first look's); ``config`` the settings that ran, with ``looks`` the
    runs per cell after each look and ``look_error`` the error each
    look's one-sided bounds may make.
    """

    cells: dict[tuple[str, float, int], StudyCell]
    grades: list[str]
    completed_runs: int
    interrupted: bool
    config: dict[str, Any]

    def __repr__(self) -> str:
        runs = [c.runs for c in self.cells.values()] or [0]
        decided = [c.decision for c in self.cells.values() if c.decision is not None]
        verdicts = (
            ", " + ", ".join(f"{decided.count(d)} {d}" for d in DECISIONS if d in decided)
            if decided
            else ""
        )
        return (
            f"OutageStudyResult({len(self.grades)} grades x {len(self.outage_lengths)} lengths x "
            f"{len(self.visible_satellites)} satellite counts, {min(runs)}-{max(runs)} runs "
            f"per cell{verdicts}" + (", interrupted" if self.interrupted else "") + ")"
        )

    @property
    def outage_lengths(self) -> list[float]:
        """The outage lengths that ran, s, in run order."""
        return [float(v) for v in self.config["outage_lengths"]]

    @property
    def visible_satellites(self) -> list[int]:
        """The satellite counts kept during each outage, in run order."""
        return [int(n) for n in self.config["visible_satellites"]]

    def cell(self, grade: str, length: float, n_visible: int) -> StudyCell:
        """The cell of ``grade`` through the ``length`` s outage with
        ``n_visible`` satellites kept."""
        key = (grade, float(length), int(n_visible))
        if key not in self.cells:
            raise ValueError(
                f"cell: the study ran grades {self.grades}, lengths {self.outage_lengths} s and "
                f"satellite counts {self.visible_satellites}, not {key!r}"
            )
        return self.cells[key]

    def per_run(
        self, grade: str, length: float, n_visible: int, metric: str, smoothed: bool = False
    ) -> npt.NDArray[np.float64]:
        """The per-run values (m) of one ``metric`` of :data:`METRICS`."""
        if metric not in METRICS:
            raise ValueError(f"metric: expected one of {sorted(METRICS)}, got {metric!r}")
        cell = self.cell(grade, length, n_visible)
        if smoothed:
            if cell.smoothed is None:
                raise ValueError("smoothed: the study ran without smooth=True")
            return np.asarray(cell.smoothed[metric], dtype=float)
        return np.asarray(cell.forward[metric], dtype=float)

    def summary(self, n_visible: int | None = None, smoothed: bool = False) -> dict[str, Any]:
        """``{grade: {length: {"p50_m", "p95_m", "max_m", "runs",
        "decision", "horizontal_end", "horizontal_max", "error_3d_end",
        "error_3d_max"}}}`` for the satellites count ``n_visible`` (default:
        the fewest of the study, the worst case). ``p50_m``, ``p95_m`` and
        ``max_m`` are those of the horizontal error at the end of the
        outage (what a horizontal accuracy requirement bounds); each named
        metric holds its own ``{"p50_m", "p95_m", "max_m"}``; ``runs`` and
        ``decision`` are the cell's. ``smoothed``: the smoothed solution's
        figures (needs ``smooth=True``; from the first look's runs)."""
        n = min(self.visible_satellites) if n_visible is None else n_visible
        if n not in self.visible_satellites:
            raise ValueError(f"n_visible: the study kept {self.visible_satellites}, not {n!r}")
        out: dict[str, Any] = {}
        for grade in self.grades:
            per_length: dict[float, Any] = {}
            for length in self.outage_lengths:
                figures = {
                    metric: _distribution(self.per_run(grade, length, n, metric, smoothed))
                    for metric in METRICS
                }
                cell = self.cell(grade, length, n)
                per_length[length] = {
                    **figures["horizontal_end"],
                    "runs": len(self.per_run(grade, length, n, "horizontal_end", smoothed)),
                    "decision": cell.decision,
                    **figures,
                }
            out[grade] = per_length
        return out

    def meets(
        self,
        max_error_m: float,
        percentile: float = 95.0,
        *,
        n_visible: int | None = None,
        metric: str = "horizontal_end",
        smoothed: bool = False,
    ) -> dict[str, list[float]]:
        """Per grade, the outage lengths whose ``percentile`` of ``metric``
        over the runs (default: the 95th percentile of the horizontal
        error at the end of the outage) is at most ``max_error_m``, with
        ``n_visible`` satellites kept (default the fewest): the point
        estimates, with no confidence (the cells' ``decision`` has it)."""
        if not (math.isfinite(max_error_m) and max_error_m > 0):
            raise ValueError(f"max_error_m: must be finite and positive, got {max_error_m!r}")
        if not 0.0 <= percentile <= 100.0:
            raise ValueError(f"percentile: must be within 0-100, got {percentile!r}")
        n = min(self.visible_satellites) if n_visible is None else n_visible
        out: dict[str, list[float]] = {}
        for grade in self.grades:
            out[grade] = [
                length
                for length in self.outage_lengths
                if float(
                    np.percentile(self.per_run(grade, length, n, metric, smoothed), percentile)
                )
                <= max_error_m
            ]
        return out

    def interval(
        self,
        grade: str,
        length: float,
        percentile: float = 95.0,
        *,
        n_visible: int | None = None,
        metric: str = "horizontal_end",
        smoothed: bool = False,
        confidence: float | None = None,
    ) -> dict[str, float]:
        """How sure a ``percentile`` of ``metric`` over the runs is: the
        equal-tailed ``confidence`` interval for it from the runs' order
        statistics (distribution-free; :func:`memsnav.quantile_interval`): ``lower``,
        ``upper`` (inf when the runs are too few to bound it from above: a
        95th percentile needs 72 runs at 95 %), ``coverage``,
        ``runs_for_upper``. ``percentile`` strictly between 0 and 100;
        ``confidence`` None: :data:`CONFIDENCE`."""
        n = min(self.visible_satellites) if n_visible is None else n_visible
        values = self.per_run(grade, length, n, metric, smoothed)
        return _interval(values, percentile, confidence)

    def plot(
        self,
        max_error_m: float | None = None,
        percentile: float = 95.0,
        metric: str = "horizontal_end",
    ) -> Any:
        """Error vs outage length per grade, log-log, one panel per
        satellites count: the ``percentile`` of ``metric`` over the runs
        (solid), with the requirement ``max_error_m`` as a horizontal line.
        Run with ``smooth``, the smoothed solution is dashed, with the
        largest error during the outage for an ``_end`` metric: the GNSS
        epoch that ends the outage pins the smoothed error at the end."""
        import matplotlib.pyplot as plt
        from matplotlib.ticker import NullLocator

        counts = self.visible_satellites
        # Narrow panels: the page shows the figure about 9 inches wide, and
        # wider ones shrink their labels below reading size.
        fig, panels = plt.subplots(
            1, len(counts), figsize=(3.4 * len(counts), 4.2), sharey=True, squeeze=False
        )
        lengths = np.asarray(self.outage_lengths, dtype=float)
        smoothed = bool(self.config["smooth"])
        for ax, n in zip(panels[0], counts, strict=True):
            for k, grade in enumerate(self.grades):
                for smooth in (False, True) if smoothed else (False,):
                    # The smoothed solution is pinned by the GNSS epoch that
                    # ends the outage: its error peaks inside, not at the end.
                    shown = metric.replace("_end", "_max") if smooth else metric
                    values = [
                        float(np.percentile(self.per_run(grade, L, n, shown, smooth), percentile))
                        for L in self.outage_lengths
                    ]
                    ax.plot(
                        lengths,
                        values,
                        "--" if smooth else "-o",
                        color=f"C{k}",
                        ms=4,
                        label=f"{grade} (smoothed, largest in outage)" if smooth else grade,
                    )
            if max_error_m is not None:
                ax.axhline(max_error_m, color="k", lw=1.2, ls=":", label="requirement", gid="bound")
            ax.set_xscale("log")
            ax.set_yscale("log")
            # The lengths studied as the ticks, in seconds (not 10¹, 10²).
            ax.set_xticks(lengths, [f"{v:g}" for v in lengths])
            ax.xaxis.set_minor_locator(NullLocator())
            ax.set_title(f"{n} satellite{'' if n == 1 else 's'} kept")
            ax.set_xlabel("outage length [s]")
            ax.grid(True, which="both", alpha=0.3)
        panels[0][0].set_ylabel(f"{metric.replace('_', ' ')} error, p{percentile:g} [m]")
        runs = [c.runs for c in self.cells.values()]
        per_point = f"{min(runs)}" if min(runs) == max(runs) else f"{min(runs)}-{max(runs)}"
        fig.suptitle(f"Outage study ({per_point} runs per point)")
        handles, labels = panels[0][0].get_legend_handles_labels()
        fig.legend(handles, labels, loc="lower center", ncol=3, fontsize="small", frameon=False)
        fig.tight_layout(rect=(0.0, 0.2, 1.0, 1.0))
        return fig


def outage_study(
    grades: Sequence[str] | Mapping[str, Any] = GRADES,
    outage_lengths: Sequence[float] = (10.0, 30.0, 60.0, 120.0),
    visible_satellites: Sequence[int] = (0, 2, 3),
    *,
    runs: int = 20,
    duration: float | None = None,
    outage_start: float = 100.0,
    seed: int = 0,
    calibrated: bool = False,
    smooth: bool = False,
    calibration_duration: float | None = None,
    client: Any = None,
    chunk_runs: int | None = None,
    threads: int | None = None,
    progress: Callable[[int, int], object] | None = None,
    n_satellites: int = 6,
    systems: Sequence[str] = ("G",),
    inter_system_bias: Sequence[float] = (0.0, 0.0),
    carrier_phase_std: float = 0.0,
    cycle_slip_probability: float = 0.0,
    max_error_m: float | None = None,
    percentile: float = 95.0,
    metric: str = "horizontal_end",
    confidence: float | None = None,
    max_runs: int | None = None,
) -> OutageStudyResult:
    """Runs the outage study (module docs).

    ``grades``: preset names (default the five presets, cheapest first) or
    a dict name → ``ImuModel`` / preset name. ``outage_lengths`` (s);
    ``visible_satellites``: satellites kept through the outage (0 a total
    outage, up to 3; ``n_satellites`` tracked otherwise). ``runs`` per cell
    (the first look); ``duration`` of every run's draw, s (default: the
    outage start plus the longest outage plus :data:`TAIL_S`);
    ``outage_start``: s after the start (the filters converge within about
    30 s). ``calibrated``: add each grade's calibrated twin (``"<grade>
    calibrated"``: the same sensor and readings, calibrated on its own
    segment of ``calibration_duration`` s and inverted). ``smooth``: also
    the fixed-interval smoothed solution, over the first look's runs
    (``summary(smoothed=True)``).

    The requirement: ``percentile`` (default 95) of ``metric`` (one of
    :data:`METRICS`) at most ``max_error_m`` (m; None: figures only). With
    it every cell gets a decision at ``confidence``; with ``max_runs`` too
    the study runs the cells still needed in doubling looks up to
    ``max_runs`` runs each until they are decided (module docs).

    ``client``/``chunk_runs``: run on a Dask cluster
    (``docs/how-to/run-on-dask.md``); the numbers do not change.
    ``progress(done, total)`` counts the runs of the current look. Ctrl-C stops the study:
    the looks done are kept, the interrupted look's completed runs are
    kept undecided (``interrupted=True``). ``n_satellites``: tracked
    outside the outage, of every system in ``systems`` ("G" GPS, "E"
    Galileo, "C" BeiDou MEO, "R" GLONASS, nominal Walker constellations;
    with E, C or R the filters estimate the pseudoranges'
    ``inter_system_bias``, Galileo, BeiDou and (a third value, else 0)
    GLONASS against GPS, m). ``carrier_phase_std`` (m, one sigma; 0: none)
    and ``cycle_slip_probability``: the simulated carrier phase, whose
    changes between epochs the filters use, and its silent cycle slips per
    satellite and epoch (:func:`~memsnav.experiments.navigation`).
    Raises ValueError naming the argument.
    """
    lengths = [float(v) for v in outage_lengths]
    if not lengths or any(not (math.isfinite(v) and v > 0) for v in lengths):
        raise ValueError(f"outage_lengths: needs positive lengths in s, got {outage_lengths!r}")
    if len(set(lengths)) != len(lengths):
        raise ValueError(f"outage_lengths: lengths must be distinct, got {outage_lengths!r}")
    counts = [int(n) for n in visible_satellites]
    if isinstance(runs, bool) or not isinstance(runs, int) or runs < 1:
        raise ValueError(f"runs: must be a positive integer, got {runs!r}")
    if max_runs is not None and (
        isinstance(max_runs, bool) or not isinstance(max_runs, int) or max_runs < runs
    ):
        raise ValueError(
            f"max_runs: must be an integer of at least runs ({runs}), got {max_runs!r}"
        )
    if metric not in METRICS:
        raise ValueError(f"metric: expected one of {sorted(METRICS)}, got {metric!r}")
    confidence = CONFIDENCE if confidence is None else confidence
    if not 0.0 < confidence < 1.0:
        raise ValueError(f"confidence: must be within (0, 1), got {confidence!r}")
    if max_error_m is not None:
        if not (math.isfinite(max_error_m) and max_error_m > 0):
            raise ValueError(f"max_error_m: must be finite and positive, got {max_error_m!r}")
        if not 0.0 < percentile < 100.0:
            raise ValueError(
                f"percentile: a decision needs one strictly within 0-100, got {percentile!r}"
            )
    elif max_runs is not None:
        raise ValueError("max_runs: runs on until decided, which needs max_error_m")
    sources = _imu_sources(grades)
    imus: dict[str, Any] = dict(sources)
    if calibrated:
        for name, _ in sources:
            imus[name + CALIBRATED_SUFFIX] = f"calibrated:{name}"
    names = list(imus)
    if duration is None:
        duration = outage_start + max(lengths) + TAIL_S
    schedule = looks(runs, max_runs, percentile, confidence)
    error = look_error(schedule, percentile, confidence)
    keys = [
        (g, li, vi)
        for g in range(len(names))
        for li in range(len(lengths))
        for vi in range(len(counts))
    ]
    forward: dict[tuple[int, int, int], list[dict[str, npt.NDArray[Any]]]] = {k: [] for k in keys}
    smoothed: dict[tuple[int, int, int], list[dict[str, npt.NDArray[Any]]]] = {k: [] for k in keys}
    decisions: dict[tuple[int, int, int], str] = {}
    intervals: dict[tuple[int, int, int], tuple[float, float]] = {}
    base: dict[str, Any] = {
        "imus": list(imus.items()),
        "outage_lengths": lengths,
        "visible_satellites": counts,
        "outage_start": float(outage_start),
        "duration": float(duration),
        "tail": TAIL_S if smooth else 0.0,
        "seed": seed,
        "calibration_duration": calibration_duration,
        "n_satellites": n_satellites,
        "systems": list(systems),
        "inter_system_bias": tuple(float(b) for b in inter_system_bias),
        "carrier_phase_std": float(carrier_phase_std),
        "cycle_slip_probability": float(cycle_slip_probability),
    }
    active = list(keys)
    done = 0
    interrupted = False
    for look_end in schedule:
        if not active:
            break
        kwargs: dict[str, Any] = {**base, "cells": active, "smooth": smooth and done == 0}
        # Check the settings here, before any run (or any chunk shipped).
        _mn.outage_study_runs(**kwargs, run_range=(done, done))
        before = done

        def counted(d: int, _: int, before: int = before, end: int = look_end) -> object:
            return None if progress is None else progress(d, end - before)

        parts, interrupted = run_ranges(
            "outage_study_runs",
            kwargs,
            (done, look_end),
            client=client,
            threads=threads,
            progress=counted,
            chunk_runs=chunk_runs,
        )
        for part in parts:
            for column, key in enumerate(active):
                forward[key].append({f: part["forward"][f][:, column] for f in RUN_FIELDS})
                if part["smoothed"] is not None:
                    smoothed[key].append({f: part["smoothed"][f][:, column] for f in RUN_FIELDS})
        if interrupted:
            break
        done = look_end
        if max_error_m is not None:
            active = _decide_looks(
                forward,
                active,
                max_error_m,
                percentile,
                metric,
                error,
                decisions,
                intervals,
            )
    cells: dict[tuple[str, float, int], StudyCell] = {}
    for g, li, vi in keys:
        key = (g, li, vi)
        cells[(names[g], lengths[li], counts[vi])] = StudyCell(
            grade=names[g],
            length_s=lengths[li],
            n_visible=counts[vi],
            forward=_joined(forward[key]),
            smoothed=_joined(smoothed[key]) if smooth else None,
            decision=None if max_error_m is None else decisions.get(key, "undecided"),
            interval_m=intervals.get(key),
        )
    return OutageStudyResult(
        cells=cells,
        grades=names,
        completed_runs=min(c.runs for c in cells.values()),
        interrupted=interrupted,
        config={
            "grades": names,
            "outage_lengths": lengths,
            "visible_satellites": counts,
            "runs": runs,
            "max_runs": max_runs,
            "looks": schedule[: schedule.index(done) + 1] if done in schedule else [],
            "look_error": error,
            "confidence": confidence,
            "max_error_m": max_error_m,
            "percentile": percentile,
            "metric": metric,
            "duration": float(duration),
            "outage_start": float(outage_start),
            "seed": seed,
            "calibrated": bool(calibrated),
            "smooth": bool(smooth),
            "n_satellites": n_satellites,
            "systems": list(systems),
            "inter_system_bias": [float(b) for b in inter_system_bias],
            "carrier_phase_std": float(carrier_phase_std),
            "cycle_slip_probability": float(cycle_slip_probability),
        },
    )


def _joined(parts: list[dict[str, npt.NDArray[Any]]]) -> dict[str, npt.NDArray[Any]]:
    """The per-run arrays of a cell's looks, in run order."""
    if not parts:
        return {f: np.empty(0) for f in RUN_FIELDS}
    return {f: np.concatenate([p[f] for p in parts]) for f in RUN_FIELDS}


def _decide_looks(
    forward: dict[tuple[int, int, int], list[dict[str, npt.NDArray[Any]]]],
    active: list[tuple[int, int, int]],
    max_error_m: float,
    percentile: float,
    metric: str,
    error: float,
    decisions: dict[tuple[int, int, int], str],
    intervals: dict[tuple[int, int, int], tuple[float, float]],
) -> list[tuple[int, int, int]]:
    """Decides the ``active`` cells after a look (``decisions`` and
    ``intervals`` updated) and returns the cells to run on: undecided, with
    no shorter outage of their grade and count failed ("not needed"
    otherwise)."""
    for key in active:
        values = np.asarray(_joined(forward[key])[metric], dtype=float)
        decisions[key], intervals[key] = decide(values, max_error_m, percentile, error)
    failed: dict[tuple[int, int], float] = {}
    for (g, li, vi), verdict in decisions.items():
        if verdict == "fails":
            failed[(g, vi)] = min(li, failed.get((g, vi), math.inf))
    for (g, li, vi), verdict in decisions.items():
        if verdict == "undecided" and li > failed.get((g, vi), math.inf):
            decisions[(g, li, vi)] = "not needed"
    return [key for key in active if decisions[key] == "undecided"]
