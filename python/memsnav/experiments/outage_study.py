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
"""

from __future__ import annotations

import math
from collections.abc import Callable, Mapping, Sequence
from dataclasses import dataclass
from typing import Any

import numpy as np
import numpy.typing as npt

import memsnav._memsnav as _mn
from memsnav.experiments.navigation import NavigationResult, _imu_sources
from memsnav.experiments.partial_outage import partial_outage

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

    ``results[length][n_visible]`` is the partial-outage scenario's
    :class:`~memsnav.experiments.NavigationResult` (every grade, forward
    filter; its ``.smoothed`` the smoothed solution when run with
    ``smooth=True``); ``grades`` the names in the set's order (calibrated
    twins included); ``config`` the settings that ran.
    """

    results: dict[float, dict[int, NavigationResult]]
    grades: list[str]
    completed_runs: int
    interrupted: bool
    config: dict[str, Any]

    @property
    def outage_lengths(self) -> list[float]:
        """The outage lengths that ran, s, in run order."""
        return list(self.results)

    @property
    def visible_satellites(self) -> list[int]:
        """The satellite counts kept during each outage, in run order."""
        return list(next(iter(self.results.values())))

    def per_run(
        self, grade: str, length: float, n_visible: int, metric: str, smoothed: bool = False
    ) -> npt.NDArray[np.float64]:
        """The per-run values (m) of one ``metric`` of :data:`METRICS`."""
        if metric not in METRICS:
            raise ValueError(f"metric: expected one of {sorted(METRICS)}, got {metric!r}")
        result = self.results[length][n_visible]
        if smoothed:
            if result.smoothed is None:
                raise ValueError("smoothed: the study ran without smooth=True")
            result = result.smoothed
        return np.asarray(result.runs_summary[grade][METRICS[metric]], dtype=float)

    def summary(self, n_visible: int | None = None, smoothed: bool = False) -> dict[str, Any]:
        """``{grade: {length: {"p50_m", "p95_m", "max_m", "runs",
        "horizontal_end", "horizontal_max", "error_3d_end",
        "error_3d_max"}}}`` for the satellites count ``n_visible`` (default:
        the fewest of the study, the worst case). ``p50_m``, ``p95_m`` and
        ``max_m`` are those of the horizontal error at the end of the
        outage (what a horizontal accuracy requirement bounds); each named
        metric holds its own ``{"p50_m", "p95_m", "max_m"}``. ``smoothed``:
        the smoothed solution's figures (needs ``smooth=True``)."""
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
                per_length[length] = {
                    **figures["horizontal_end"],
                    "runs": self.completed_runs,
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
        ``n_visible`` satellites kept (default the fewest)."""
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
        confidence: float = 0.95,
    ) -> dict[str, float]:
        """How sure a ``percentile`` of ``metric`` over the runs is: the
        equal-tailed ``confidence`` interval for it from the runs' order
        statistics (distribution-free; :func:`memsnav.quantile_interval`): ``lower``,
        ``upper`` (inf when the runs are too few to bound it from above: a
        95th percentile needs 72 runs at 95 %), ``coverage``,
        ``runs_for_upper``. ``percentile`` strictly between 0 and 100."""
        n = min(self.visible_satellites) if n_visible is None else n_visible
        values = self.per_run(grade, length, n, metric, smoothed)
        return dict(
            _mn.quantile_interval(values[np.isfinite(values)], percentile / 100.0, confidence)
        )

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
        smoothed = next(iter(next(iter(self.results.values())).values())).smoothed is not None
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
        fig.suptitle(f"Outage study ({self.completed_runs} runs per point)")
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
    inter_system_bias: tuple[float, float] = (0.0, 0.0),
    carrier_phase_std: float = 0.0,
    cycle_slip_probability: float = 0.0,
) -> OutageStudyResult:
    """Runs the outage study (module docs).

    ``grades``: preset names (default the five presets, cheapest first) or
    a dict name → ``ImuModel`` / preset name. ``outage_lengths`` (s), one
    partial-outage set each; ``visible_satellites``: satellites kept
    through the outage (0 a total outage, up to 3; 6 tracked otherwise).
    ``runs`` per set; ``duration`` of every run, s (default: the outage
    start plus the longest outage plus 10 s); ``outage_start``: s after the
    start (the filters converge within about 30 s). ``calibrated``: add
    each grade's calibrated twin (``"<grade> calibrated"``: the same
    sensor and readings, calibrated on its own segment of
    ``calibration_duration`` s and inverted). ``smooth``: also the
    fixed-interval smoothed solution (``summary(smoothed=True)``).
    ``client``/``chunk_runs``: run on a Dask cluster
    (``docs/how-to/run-on-dask.md``); the numbers do not change. ``progress(done,
    total)`` counts runs over the whole study. Ctrl-C stops the study:
    the lengths done are kept, and the result covers the completed runs of
    the one interrupted (``interrupted=True``); later lengths are skipped.
    ``n_satellites``: tracked outside the outage, of every system in
    ``systems`` ("G" GPS, "E" Galileo, "C" BeiDou MEO, nominal Walker
    constellations; with E or C the filters estimate the pseudoranges'
    ``inter_system_bias``, Galileo and BeiDou against GPS, m).
    ``carrier_phase_std`` (m, one sigma; 0: none) and
    ``cycle_slip_probability``: the simulated carrier phase, whose changes
    between epochs the filters use, and its silent cycle slips per
    satellite and epoch (:func:`~memsnav.experiments.navigation`).
    Raises ValueError naming the argument.
    """
    lengths = [float(v) for v in outage_lengths]
    if not lengths or any(not (math.isfinite(v) and v > 0) for v in lengths):
        raise ValueError(f"outage_lengths: needs positive lengths in s, got {outage_lengths!r}")
    if len(set(lengths)) != len(lengths):
        raise ValueError(f"outage_lengths: lengths must be distinct, got {outage_lengths!r}")
    counts = [int(n) for n in visible_satellites]
    sources = _imu_sources(grades)
    names = [name for name, _ in sources]
    imus: dict[str, Any] = dict(sources)
    if calibrated:
        for name in names:
            imus[name + CALIBRATED_SUFFIX] = f"calibrated:{name}"
    if duration is None:
        duration = outage_start + max(lengths) + 10.0
    done_before = 0
    total = runs * len(lengths)

    def counted(done: int, _: int) -> object:
        return None if progress is None else progress(done_before + done, total)

    results: dict[float, dict[int, NavigationResult]] = {}
    interrupted = False
    completed = runs
    for length in lengths:
        study = partial_outage(
            imus=imus,
            runs=runs,
            duration=duration,
            seed=seed,
            outage_start=outage_start,
            outage_length=length,
            satellites=counts,
            loose=False,
            calibration_duration=calibration_duration,
            smooth=smooth,
            client=client,
            chunk_runs=chunk_runs,
            threads=threads,
            progress=counted,
            n_satellites=n_satellites,
            systems=systems,
            inter_system_bias=inter_system_bias,
            carrier_phase_std=carrier_phase_std,
            cycle_slip_probability=cycle_slip_probability,
        )
        results[length] = {
            study.n_visible[label]: result for label, result in study.scenarios.items()
        }
        done_before += runs
        completed = min(completed, study.completed_runs)
        if study.interrupted:
            interrupted = True
            break
    return OutageStudyResult(
        results=results,
        grades=list(imus),
        completed_runs=completed,
        interrupted=interrupted,
        config={
            "grades": list(imus),
            "outage_lengths": list(results),
            "visible_satellites": counts,
            "runs": runs,
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
