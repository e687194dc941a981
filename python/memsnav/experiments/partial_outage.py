"""The partial-outage study: the urban canyon that the paper's conclusion
names as the critical case for MEMS/GNSS, which its experiments leave out.

Through one window (default 60 s at 100 s of 180 s runs) the receiver keeps
0, 1, 2 or 3 of its 6 satellites — the highest ones: a canyon's view, and
the worst horizontal geometry of the set. Every IMU crosses the window with
the tightly coupled filter for each count, and with the loosely coupled
filter, which has no position fix below 4 satellites and is therefore blind
through the window whatever the count. All scenarios of a run share its
trajectory, GNSS draws, initial errors and IMU readings (a paired
comparison); they differ only by the satellites the window removes.

With 1-3 satellites and a free receiver clock the position is not
determined epoch by epoch: 3 pseudoranges leave one direction of
(position, clock) open, which the filter can only bound through the
dynamics of the INS and of the clock model. What k satellites determine,
and why the filter's covariance covers its errors whatever k is, is in
docs/explanation/few-satellites.md; every satellite kept lowers the error.
"""

from __future__ import annotations

from collections.abc import Callable, Mapping, Sequence
from dataclasses import dataclass
from typing import Any

import numpy as np

from memsnav import _memsnav
from memsnav._distributed import run_set
from memsnav.experiments.navigation import (
    PAPER_IMUS,
    NavigationResult,
    _imu_sources,
    imu_label,
    real_number,
    result_from_raw,
)


def scenario_label(coupling: str, n_visible: int) -> str:
    """``"tight, 2 satellites"``; ``"loose"`` (blind below 4 satellites)."""
    if coupling == "loose":
        return "loose"
    return f"tight, {n_visible} satellite{'' if n_visible == 1 else 's'}"


@dataclass(frozen=True)
class PartialOutageResult:
    """Result of :func:`partial_outage`: per scenario label (see
    :func:`scenario_label`, in run order: tight with each count, then
    loose) a :class:`~memsnav.experiments.NavigationResult` of every IMU,
    whose ``config["outage"]`` is the scenario's ``(start, length,
    n_visible)``; ``config`` the settings that ran."""

    scenarios: dict[str, NavigationResult]
    coupling: dict[str, str]
    n_visible: dict[str, int]
    completed_runs: int
    interrupted: bool
    config: dict[str, Any]

    def __repr__(self) -> str:
        return (
            f"PartialOutageResult({', '.join(self.scenarios)}; {self.completed_runs} runs"
            + (", interrupted" if self.interrupted else "")
            + ")"
        )

    @property
    def imus(self) -> list[str]:
        """IMU names, in the set's order."""
        return next(iter(self.scenarios.values())).imus

    def summary(self) -> dict[str, Any]:
        """Per scenario label: ``coupling``, ``n_visible`` and per IMU the
        navigation summary's outage figures (``max_position_error_during_
        outage_m``, ``mean_max_position_error_during_outage_m`` and its
        horizontal and vertical parts,
        ``position_error_at_outage_end_m``, ``rms_position_error_m``), the
        Monte Carlo ``position_nees_per_dof_at_outage_end`` (1 when the
        filter's covariance matches its errors) and ``diverged_share`` (runs
        whose solution raised an integrity alert), with their
        ``standard_error``; plus ``completed_runs``, ``interrupted`` and
        ``config``."""
        keys = (
            "max_position_error_during_outage_m",
            "mean_max_position_error_during_outage_m",
            "mean_max_horizontal_error_during_outage_m",
            "mean_max_vertical_error_during_outage_m",
            "position_error_at_outage_end_m",
            "rms_position_error_m",
            "position_nees_per_dof_at_outage_end",
            "diverged_share",
        )
        scenarios = {}
        for label, result in self.scenarios.items():
            per_imu = {}
            for imu, s in result.summary().items():
                per_imu[imu] = {k: s[k] for k in keys} | {
                    "standard_error": {k: s["standard_error"][k] for k in keys}
                }
            scenarios[label] = {
                "coupling": self.coupling[label],
                "n_visible": self.n_visible[label],
                "imus": per_imu,
            }
        return {
            "scenarios": scenarios,
            "completed_runs": self.completed_runs,
            "interrupted": self.interrupted,
            "config": dict(self.config),
        }

    def plot(self) -> Any:
        """One panel per IMU: the mean position error through the window
        (from 10 s before to 20 s after) for each scenario, log scale."""
        import matplotlib.pyplot as plt

        start = float(self.config["outage_start"])
        length = float(self.config["outage_length"])
        imus = self.imus
        # Narrow panels: the page shows the figure about 9 inches wide.
        fig, panels = plt.subplots(
            1, len(imus), figsize=(3.4 * len(imus), 4.0), sharey=True, squeeze=False
        )
        styles = ["-", "--", "-.", ":", "-"]
        for ax, imu in zip(panels[0], imus, strict=True):
            for k, (label, result) in enumerate(self.scenarios.items()):
                t = result.time
                sel = (t >= start - 10.0) & (t <= start + length + 20.0)
                # Loose coupling is blind below 4 satellites, so its curve
                # follows "tight, 0 satellites" through the window: a wide
                # grey band behind the others keeps that one visible.
                loose = self.coupling[label] == "loose"
                ax.plot(
                    t[sel],
                    result.mean[imu][sel],
                    "-" if loose else styles[k % len(styles)],
                    color="0.7" if loose else f"C{k}",
                    lw=5.0 if loose else 1.6,
                    zorder=1 if loose else 2,
                    label=label,
                )
            ax.axvspan(start, start + length, color="grey", alpha=0.15)
            ax.set_yscale("log")
            ax.set_title(imu_label(imu))
            ax.set_xlabel("time [s]")
            ax.grid(True, which="both", alpha=0.3)
        panels[0][0].set_ylabel("position error norm, mean over runs [m]")
        fig.suptitle(
            f"Partial outage: {length:.0f} s from {start:.0f} s keeping 0-3 satellites "
            f"({self.completed_runs} runs)"
        )
        handles, labels = panels[0][0].get_legend_handles_labels()
        fig.legend(
            handles, labels, loc="lower center", ncol=len(labels), fontsize="small", frameon=False
        )
        fig.tight_layout(rect=(0.0, 0.08, 1.0, 1.0))
        return fig


def run_partial_outage(
    kwargs: dict[str, Any],
    *,
    client: Any = None,
    threads: int | None = None,
    progress: Callable[[int, int], object] | None = None,
    chunk_runs: int | None = None,
) -> Any:
    """The binding's raw dict for the study ``kwargs`` describe (the
    keywords of ``_memsnav.partial_outage_experiment``), here or on
    ``client``'s cluster."""
    total = 0
    if client is not None:
        # The set's size, defaults filled in by the core (a fold of no chunk).
        total = int(_memsnav.partial_outage_experiment(**kwargs, chunks=[])["config"]["runs"])
    return run_set(
        "partial_outage_experiment",
        kwargs,
        total,
        client=client,
        threads=threads,
        progress=progress,
        chunk_runs=chunk_runs,
    )


def partial_outage(
    *,
    imus: Sequence[str] | Mapping[str, Any] = PAPER_IMUS,
    runs: int | None = None,
    duration: float | None = None,
    seed: int | None = None,
    outage_start: float | None = None,
    outage_length: float | None = None,
    satellites: Sequence[int] | None = None,
    loose: bool | None = None,
    calibration_duration: float | None = None,
    smooth: bool | None = None,
    keep_runs: bool | None = None,
    threads: int | None = None,
    progress: Callable[[int, int], object] | None = None,
    client: Any = None,
    chunk_runs: int | None = None,
    n_satellites: int | None = None,
    systems: Sequence[str] | None = None,
    inter_system_bias: Sequence[float] | None = None,
    carrier_phase_std: float | None = None,
    cycle_slip_probability: float | None = None,
) -> PartialOutageResult:
    """Runs the partial-outage study (module docs) in Rust, GIL released.

    ``None`` takes the core's default (``result.config`` shows the values
    that ran): ``runs`` 20, ``duration`` 180 s, ``seed`` 0,
    ``outage_start`` 100 s, ``outage_length`` 60 s, ``satellites`` (0, 1,
    2, 3) kept in the window (one tightly coupled scenario each),
    ``loose`` True (add the loosely coupled scenario), ``calibration_duration``
    300 s, ``keep_runs`` False; every other setting is the navigation
    experiment's default (6 satellites, 3 m and 0.1 m/s, 1°/1°/5° initial
    attitude error). ``imus`` as in :func:`~memsnav.experiments.navigation`.
    Ctrl-C stops the set and returns the completed runs
    (``interrupted=True``). ``smooth``: also score every filter's
    fixed-interval smoothed solution (each scenario's ``.smoothed``).
    Raises ValueError naming the argument.
    ``client``: a ``dask.distributed.Client`` to run the set on its
    cluster in chunks of ``chunk_runs`` runs (``docs/how-to/run-on-dask.md``):
    the same numbers bit for bit; ``threads`` must then be None.
    ``n_satellites``: tracked outside the window (default 6), of every
    system in ``systems`` (RINEX letters, default ("G",); "E" Galileo,
    "C" BeiDou and "R" GLONASS add their nominal constellations and three
    inter-system-bias states to every filter, the pseudoranges carrying
    ``inter_system_bias`` (Galileo, BeiDou[, GLONASS] against GPS, m;
    default 0)).
    ``carrier_phase_std`` (m; default 0: none) and ``cycle_slip_probability``
    (default 0): the simulated carrier phase and its silent slips, used by
    the tightly coupled filters, as in :func:`~memsnav.experiments.navigation`.
    """
    raw = run_partial_outage(
        {
            "imus": _imu_sources(imus),
            "runs": runs,
            "duration": duration,
            "seed": seed,
            "outage_start": outage_start,
            "outage_length": outage_length,
            "satellites": None if satellites is None else [int(n) for n in satellites],
            "loose": loose,
            "calibration_duration": calibration_duration,
            "smooth": smooth,
            "keep_runs": keep_runs,
            "n_satellites": n_satellites,
            "systems": None if systems is None else list(systems),
            "inter_system_bias": None
            if inter_system_bias is None
            else tuple(float(b) for b in inter_system_bias),
            "carrier_phase_std": None
            if carrier_phase_std is None
            else real_number(carrier_phase_std, "carrier_phase_std"),
            "cycle_slip_probability": None
            if cycle_slip_probability is None
            else real_number(cycle_slip_probability, "cycle_slip_probability"),
        },
        client=client,
        threads=threads,
        progress=progress,
        chunk_runs=chunk_runs,
    )
    config = dict(raw["config"])
    results: dict[str, NavigationResult] = {}
    coupling: dict[str, str] = {}
    n_visible: dict[str, int] = {}
    for s in raw["scenarios"]:
        label = scenario_label(s["coupling"], int(s["n_visible"]))
        scenario_raw = {
            "time": np.asarray(raw["time"]),
            "imus": s["imus"],
            "completed_runs": raw["completed_runs"],
            "interrupted": raw["interrupted"],
        }
        results[label] = result_from_raw(
            scenario_raw,
            {
                "outage": (config["outage_start"], config["outage_length"], int(s["n_visible"])),
                "coupling": s["coupling"],
                "runs": config["runs"],
                "duration": config["duration"],
                "seed": config["seed"],
                "imus": [e["name"] for e in s["imus"]],
                "early_window": config["early_window"],
            },
        )
        coupling[label] = s["coupling"]
        n_visible[label] = int(s["n_visible"])
    return PartialOutageResult(
        scenarios=results,
        coupling=coupling,
        n_visible=n_visible,
        completed_runs=int(raw["completed_runs"]),
        interrupted=bool(raw["interrupted"]),
        config=config,
    )
