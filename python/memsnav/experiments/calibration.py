"""Calibration Monte Carlo: paper §5.1, figures 3-10 (method §3 and §6).

Each parameter set is an IMU drawn from a preset ("paper-mems": the paper's
magnitudes); each run simulates fresh land-vehicle motion, the sensor
outputs, and GNSS-like references (truth plus white noise: 0.03 m/s² for
the specific force, from Doppler/RTK velocity differenced over 1 s, and
0.1 °/s for the angular rate, from differenced GNSS attitude), then
calibrates with plain least squares and with the errors-in-variables
estimator. The Cramér-Rao bound is that of the problem solved: noisy
references, the errors-in-variables model (``memsnav_core::calibration``
docs), at each run's true inputs — per parameter and per output axis.

Axes: the accelerometer's u, v, w and the gyroscope's p, q, r are the body
axes x, y, z (forward, right, down); a parameter's output axis is the first
letter after its group (``misalignment_uw``: axis u). Which parameter sits
at which index is the core's ``CalibrationLayout``.
"""

from __future__ import annotations

import math
from collections.abc import Callable
from dataclasses import dataclass
from typing import Any

import numpy as np
import numpy.typing as npt

from memsnav import _memsnav
from memsnav._distributed import run_set
from memsnav.experiments._plotting import legend_below

LAYOUTS = {sensor: _memsnav.CalibrationLayout(sensor) for sensor in ("accelerometer", "gyroscope")}
"""The parameter vector of each sensor's calibration (the core's layout)."""
ACCELEROMETER_GROUPS = {
    g: LAYOUTS["accelerometer"].group_slice(g) for g in LAYOUTS["accelerometer"].groups
}
GYROSCOPE_GROUPS = {g: LAYOUTS["gyroscope"].group_slice(g) for g in LAYOUTS["gyroscope"].groups}
AXES = {sensor: tuple(layout.axes) for sensor, layout in LAYOUTS.items()}
"""Output axes of each triad: the body axes x, y, z (forward, right, down)."""

# The unit of each group's MSE (SI).
MSE_UNITS = {
    ("accelerometer", "bias"): "(m/s²)²",
    ("accelerometer", "scale_factor"): "1",
    ("accelerometer", "misalignment"): "1",
    ("accelerometer", "nonlinearity"): "(s²/m)²",
    ("gyroscope", "bias"): "(rad/s)²",
    ("gyroscope", "scale_factor"): "1",
    ("gyroscope", "misalignment"): "1",
    ("gyroscope", "g_sensitivity"): "(rad/s per m/s²)²",
}
# The paper's figure numbers and titles, in group order.
_FIGURES = {
    ("accelerometer", "bias"): "Fig. 3: MSE of the accelerometer biases",
    ("accelerometer", "scale_factor"): "Fig. 4: MSE of the accelerometer scale factors",
    ("accelerometer", "misalignment"): "Fig. 5: MSE of the accelerometer misalignments",
    ("accelerometer", "nonlinearity"): "Fig. 6: MSE of the accelerometer nonlinearity",
    ("gyroscope", "bias"): "Fig. 7: MSE of the gyro biases",
    ("gyroscope", "scale_factor"): "Fig. 8: MSE of the gyro scale factors",
    ("gyroscope", "misalignment"): "Fig. 9: MSE of the gyro misalignments",
    ("gyroscope", "g_sensitivity"): "Fig. 10: MSE of the gyro g-sensitivity",
}


@dataclass(frozen=True)
class SensorStatistics:
    """Per-set statistics of one sensor; arrays of shape (sets, parameters), SI."""

    parameter_names: list[str]
    truth: npt.NDArray[np.float64]
    mse_ls: npt.NDArray[np.float64]
    mse_eiv: npt.NDArray[np.float64]
    mean_error_ls: npt.NDArray[np.float64]
    mean_error_eiv: npt.NDArray[np.float64]
    reported_variance_ls: npt.NDArray[np.float64]
    reported_variance_eiv: npt.NDArray[np.float64]
    crb: npt.NDArray[np.float64]

    def ran(self) -> npt.NDArray[np.bool_]:
        """Sets with at least one completed run (an interrupted experiment
        leaves the others NaN)."""
        return np.asarray(np.isfinite(self.mse_eiv).all(axis=1))


def _mean_and_se(per_set: npt.NDArray[np.float64]) -> tuple[float, float]:
    """Mean over sets and its standard error (NaN with fewer than 2 sets)."""
    if len(per_set) == 0:
        return math.nan, math.nan
    se = float(per_set.std(ddof=1) / math.sqrt(len(per_set))) if len(per_set) > 1 else math.nan
    return float(per_set.mean()), se


def _figures(stats: SensorStatistics, columns: list[int]) -> dict[str, float]:
    """MSE (both estimators, with standard errors over sets), bound,
    efficiencies and normalised MSE of a set of parameters, averaged over
    them and over the sets that ran."""
    ran = stats.ran()
    out: dict[str, float] = {}
    for key in ("mse_eiv", "mse_ls"):
        mean, se = _mean_and_se(getattr(stats, key)[ran][:, columns].mean(axis=1))
        out[key] = mean
        out[f"{key}_se"] = se
    out["crb"] = float(stats.crb[ran][:, columns].mean()) if ran.any() else math.nan
    scale = float((stats.truth[ran][:, columns] ** 2).mean()) if ran.any() else math.nan
    out["parameter_mean_square"] = scale
    for estimator in ("eiv", "ls"):
        out[f"efficiency_{estimator}"] = out[f"mse_{estimator}"] / out["crb"]
        # The share of the MSE that is the estimator's bias (mean error)².
        bias2 = getattr(stats, f"mean_error_{estimator}")[ran][:, columns] ** 2
        out[f"bias_share_{estimator}"] = (
            float(bias2.mean()) / out[f"mse_{estimator}"] if ran.any() else math.nan
        )
        out[f"normalized_mse_{estimator}"] = (
            out[f"mse_{estimator}"] / scale if scale > 0 else math.nan
        )
    return out


@dataclass(frozen=True)
class CalibrationResult:
    """Result of :func:`calibration`.

    ``accelerometer`` and ``gyroscope`` hold per-set arrays (MSE of plain LS
    and of the errors-in-variables estimator, their mean errors, the mean
    variance each calibration reported, and the mean Cramér-Rao bound).
    ``method`` is the estimator the summary reports first; ``config`` the
    settings that ran (every default filled in).
    """

    accelerometer: SensorStatistics
    gyroscope: SensorStatistics
    method: str
    config: dict[str, Any]
    completed_runs: int = 0
    interrupted: bool = False

    def __repr__(self) -> str:
        return (
            f"CalibrationResult({self.method}, {self.completed_runs} runs, "
            f"{len(self.accelerometer.parameter_names)} accelerometer and "
            f"{len(self.gyroscope.parameter_names)} gyro parameters"
            + (", interrupted" if self.interrupted else "")
            + ")"
        )

    def group_summary(self, sensor: str, group: str) -> dict[str, Any]:
        """One parameter group: its MSE unit, the figures of
        :func:`_figures` over the whole group, ``per_axis`` (u, v, w or p,
        q, r) and ``per_parameter``."""
        stats: SensorStatistics = getattr(self, sensor)
        layout = LAYOUTS[sensor]
        indices = layout.indices(group=group)
        return {
            "unit": MSE_UNITS[(sensor, group)],
            **_figures(stats, indices),
            "per_axis": {
                axis: _figures(stats, layout.indices(group=group, axis=axis))
                for axis in layout.axes
            },
            "per_parameter": {stats.parameter_names[i]: _figures(stats, [i]) for i in indices},
        }

    def summary(self) -> dict[str, Any]:
        """Per sensor and parameter group (``bias``, ``scale_factor``,
        ``misalignment``, ``nonlinearity`` / ``g_sensitivity``): the MSE
        unit and, over the group, per output axis and per parameter, the
        MSE of each estimator (``mse_eiv``, ``mse_ls``, SI, mean over the
        sets, with its standard error over sets ``*_se``), the Cramér-Rao
        bound ``crb``, the efficiencies ``efficiency_eiv`` / ``_ls``
        (MSE / bound: 1 attains it), ``bias_share_eiv`` / ``_ls`` (the
        share of the MSE that is the squared mean error), the normalised MSE (MSE / mean square
        of the true values: 1 is no better than knowing nothing) and
        ``parameter_mean_square``. Also ``estimator``, ``completed_runs``,
        ``interrupted`` and ``config``."""
        return {
            "estimator": self.method,
            **{
                sensor: {g: self.group_summary(sensor, g) for g in layout.groups}
                for sensor, layout in LAYOUTS.items()
            },
            "completed_runs": self.completed_runs,
            "interrupted": self.interrupted,
            "config": dict(self.config),
        }

    def plot(self) -> list[Any]:
        """Figures 3-10, one panel per output axis: per parameter set, the
        axis' MSE with the errors-in-variables estimator (markers) and plain
        LS (line), its Cramér-Rao bound (dashed) and the mean square of the
        true parameters (dotted: an MSE above it is worse than no
        estimate). Log scale, SI units."""
        import matplotlib.pyplot as plt

        figures = []
        for sensor, layout in LAYOUTS.items():
            stats: SensorStatistics = getattr(self, sensor)
            sets = np.arange(1, stats.mse_ls.shape[0] + 1)
            for group in layout.groups:
                fig, panels = plt.subplots(1, 3, figsize=(10.5, 3.6), sharex=True)
                fig.suptitle(_FIGURES[(sensor, group)])
                unit = MSE_UNITS[(sensor, group)]
                for ax, axis in zip(panels, layout.axes, strict=True):
                    columns = layout.indices(group=group, axis=axis)
                    ax.plot(
                        sets, stats.mse_eiv[:, columns].mean(axis=1), "o", ms=3, label="MSE, EIV"
                    )
                    ax.plot(
                        sets,
                        stats.mse_ls[:, columns].mean(axis=1),
                        "-",
                        color="tab:orange",
                        lw=1,
                        label="MSE, plain LS",
                    )
                    ax.plot(
                        sets,
                        stats.crb[:, columns].mean(axis=1),
                        "k--",
                        lw=1,
                        label="Cramér-Rao bound (noisy references)",
                    )
                    ax.plot(
                        sets,
                        (stats.truth[:, columns] ** 2).mean(axis=1),
                        ":",
                        color="grey",
                        label="parameter² (no estimate)",
                    )
                    ax.set_yscale("log")
                    ax.grid(True, which="both", alpha=0.3)
                    ax.set_title(f"axis {axis}")
                    ax.set_xlabel("parameter set")
                panels[0].set_ylabel(f"MSE [{unit}]")
                legend_below(fig, panels[0])
                figures.append(fig)
        return figures


def land_vehicle_motion(
    duration: float = 300.0, rate: float = 100.0, seed: int = 0
) -> tuple[npt.NDArray[np.float64], npt.NDArray[np.float64]]:
    """The motion the calibration experiment calibrates on: ``duration`` s at
    ``rate`` Hz of a land vehicle's body-frame true specific force (N, 3)
    m/s² and angular rate (N, 3) rad/s (speed changes, turns, road
    roughness, roll and pitch dynamics; Earth rotation neglected). Unlike
    ``Trajectory.random``, whose roll and pitch follow the manoeuvres only,
    it excites the roll and pitch rates, so the gyro scale factors and the
    misalignments onto p and q are determined."""
    return _memsnav.land_vehicle_motion(duration, rate, seed)


def _stats(d: dict[str, Any]) -> SensorStatistics:
    return SensorStatistics(**d)


def calibration(
    *,
    parameter_sets: int | None = None,
    runs: int | None = None,
    duration: float | None = None,
    preset: str | None = None,
    method: str = "eiv",
    reference_specific_force_std: float | None = None,
    reference_angular_rate_std: float | None = None,
    motion: str | None = None,
    seed: int | None = None,
    threads: int | None = None,
    progress: Callable[[int, int], None] | None = None,
    client: Any = None,
    chunk_runs: int | None = None,
) -> CalibrationResult:
    """Runs the calibration Monte Carlo (paper: 50 sets x 1000 runs).

    ``None`` takes the core's default (``memsnav_core`` writes each default
    once; ``result.config`` shows the values that ran): ``parameter_sets``
    50, ``runs`` 20 per set, ``duration`` 300 s of motion per run,
    ``preset`` "paper-mems", reference noise per 100 Hz sample
    ``reference_specific_force_std`` 0.03 m/s² and
    ``reference_angular_rate_std`` 0.1 °/s (in rad/s), ``motion``
    "land-vehicle", ``seed`` 0. ``motion``: "land-vehicle" (body-frame
    vehicle motion with roll and pitch dynamics) or "trajectory"
    (``Trajectory.random``, whose roll and pitch follow the manoeuvres
    only: p/q scale factors and the vertical terms are then barely
    observable). ``method`` ("eiv" or "ls") selects the estimator the
    summary reports first; both are always run. ``progress(done, total)``
    is called with the number of completed runs. Ctrl-C stops the set: the
    result then covers the completed runs and has ``interrupted = True``.
    Same ``seed`` -> same numbers, whatever ``threads``.
    ``client``: a ``dask.distributed.Client`` to run the set on its
    cluster in chunks of ``chunk_runs`` runs (``docs/how-to/run-on-dask.md``):
    the same numbers bit for bit; ``threads`` must then be None.
    """
    if method not in ("ls", "eiv"):
        raise ValueError(f"method: expected 'ls' or 'eiv', got {method!r}")
    kwargs: dict[str, Any] = {
        "parameter_sets": parameter_sets,
        "runs": runs,
        "duration": duration,
        "preset": preset,
        "reference_specific_force_std": reference_specific_force_std,
        "reference_angular_rate_std": reference_angular_rate_std,
        "motion": motion,
        "seed": seed,
    }
    # The set's size, defaults filled in by the core (a fold of no chunk).
    total = 0
    if client is not None:
        config = _memsnav.calibration_experiment(**kwargs, chunks=[])["config"]
        total = int(config["parameter_sets"]) * int(config["runs"])
    raw = run_set(
        "calibration_experiment",
        kwargs,
        total,
        client=client,
        threads=threads,
        progress=progress,
        chunk_runs=chunk_runs,
    )
    return CalibrationResult(
        accelerometer=_stats(raw["accelerometer"]),
        gyroscope=_stats(raw["gyroscope"]),
        method=method,
        config=dict(raw["config"]),
        completed_runs=int(raw["completed_runs"]),
        interrupted=bool(raw["interrupted"]),
    )
