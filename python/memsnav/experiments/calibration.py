"""Calibration Monte Carlo: paper §5.1, figures 3-10 (method §3 and §6).

Each parameter set is an IMU drawn from a preset ("paper-mems": the paper's
magnitudes); each run simulates fresh land-vehicle motion, the sensor
outputs, and GNSS-like references (truth plus white noise: 0.03 m/s² for
the specific force, from Doppler/RTK velocity differenced over 1 s, and
0.1 °/s for the angular rate, from differenced GNSS attitude), then
calibrates with plain least squares and with the errors-in-variables
estimator. The Cramér-Rao bound is that of exact references: the floor
that only the sensor noise sets.
"""

from __future__ import annotations

import math
from collections.abc import Callable
from dataclasses import dataclass
from typing import Any

import numpy as np
import numpy.typing as npt

from memsnav import _memsnav
from memsnav.experiments._plotting import new_figure

ACCELEROMETER_GROUPS = {
    "bias": slice(0, 3),
    "scale_factor": slice(3, 6),
    "misalignment": slice(6, 12),
    "nonlinearity": slice(12, 15),
}
GYROSCOPE_GROUPS = {
    "bias": slice(0, 3),
    "scale_factor": slice(3, 6),
    "misalignment": slice(6, 12),
    "g_sensitivity": slice(12, 21),
}
# The paper's figure numbers and titles, in group order.
_FIGURES = {
    ("accelerometer", "bias"): "Fig. 3: MSE of the accelerometer biases [(m/s²)²]",
    ("accelerometer", "scale_factor"): "Fig. 4: MSE of the accelerometer scale factors",
    ("accelerometer", "misalignment"): "Fig. 5: MSE of the accelerometer misalignments",
    ("accelerometer", "nonlinearity"): "Fig. 6: MSE of the accelerometer nonlinearity [(m/s²)⁻²]",
    ("gyroscope", "bias"): "Fig. 7: MSE of the gyro biases [(rad/s)²]",
    ("gyroscope", "scale_factor"): "Fig. 8: MSE of the gyro scale factors",
    ("gyroscope", "misalignment"): "Fig. 9: MSE of the gyro misalignments",
    ("gyroscope", "g_sensitivity"): "Fig. 10: MSE of the gyro g-sensitivity [((rad/s)/(m/s²))²]",
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


@dataclass(frozen=True)
class CalibrationResult:
    """Result of :func:`calibration`.

    ``accelerometer`` and ``gyroscope`` hold per-set arrays (MSE of plain LS
    and of the errors-in-variables estimator, their mean errors, the mean
    variance each calibration reported, and the mean Cramér-Rao bound).
    ``method`` is the estimator the summary reports first.
    """

    accelerometer: SensorStatistics
    gyroscope: SensorStatistics
    method: str
    config: dict[str, Any]
    completed_runs: int = 0
    interrupted: bool = False

    def _groups(self, stat: str) -> dict[str, dict[str, float]]:
        out: dict[str, dict[str, float]] = {}
        for sensor, groups in (
            ("accelerometer", ACCELEROMETER_GROUPS),
            ("gyroscope", GYROSCOPE_GROUPS),
        ):
            values = getattr(getattr(self, sensor), stat)
            # Sets none of whose runs completed (an interrupted experiment)
            # hold NaN: average over the sets that ran.
            ran = values[np.isfinite(values).all(axis=1)]
            out[sensor] = {
                g: float(ran[:, s].mean()) if len(ran) else math.nan for g, s in groups.items()
            }
        return out

    def summary(self) -> dict[str, Any]:
        """MSE per parameter group, averaged over the group's components and
        the parameter sets (SI units): ``{"accelerometer": {"bias",
        "scale_factor", "misalignment", "nonlinearity"}, "gyroscope": {"bias",
        "scale_factor", "misalignment", "g_sensitivity"}}`` for ``method``,
        plus the same for ``"ls"``, ``"eiv"`` and the Cramér-Rao bound
        (``"crb"``), and the configuration."""
        main = self._groups(f"mse_{self.method}")
        return {
            **main,
            "method": self.method,
            "ls": self._groups("mse_ls"),
            "eiv": self._groups("mse_eiv"),
            "crb": self._groups("crb"),
            "config": dict(self.config),
        }

    def plot(self) -> list[Any]:
        """Figures 3-10: per parameter set, the MSE of the group's parameters
        per output axis (errors-in-variables estimator), the group's MSE with
        plain LS, the Cramér-Rao bound and the mean square of the true
        parameters (an MSE above it is worse than no estimate)."""
        figures = []
        for sensor, groups in (
            ("accelerometer", ACCELEROMETER_GROUPS),
            ("gyroscope", GYROSCOPE_GROUPS),
        ):
            stats: SensorStatistics = getattr(self, sensor)
            sets = np.arange(1, stats.mse_ls.shape[0] + 1)
            for group, cols in groups.items():
                fig, ax = new_figure(_FIGURES[(sensor, group)])
                names = stats.parameter_names[cols]
                # Output axis of each parameter: the first letter after the
                # group name (bias_u -> u, misalignment_pq -> p).
                axes = [name[len(group) + 1] for name in names]
                for axis in dict.fromkeys(axes):
                    columns = [cols.start + i for i, a in enumerate(axes) if a == axis]
                    ax.plot(
                        sets,
                        stats.mse_eiv[:, columns].mean(axis=1),
                        "o-",
                        ms=3,
                        label=f"MSE, EIV, axis {axis}",
                    )
                ax.plot(
                    sets,
                    stats.mse_ls[:, cols].mean(axis=1),
                    "-",
                    color="0.6",
                    lw=1,
                    label="MSE, plain LS (all axes)",
                )
                ax.plot(sets, stats.crb[:, cols].mean(axis=1), "k--", label="Cramér-Rao bound")
                ax.plot(
                    sets,
                    (stats.truth[:, cols] ** 2).mean(axis=1),
                    ":",
                    color="grey",
                    label="parameter² (scale)",
                )
                ax.set_xlabel("parameter set")
                ax.legend(fontsize="x-small", ncol=2)
                figures.append(fig)
        return figures


def _stats(d: dict[str, Any]) -> SensorStatistics:
    return SensorStatistics(**d)


def calibration(
    *,
    parameter_sets: int = 50,
    runs: int = 20,
    duration: float = 300.0,
    preset: str = "paper-mems",
    method: str = "eiv",
    reference_specific_force_std: float = 0.03,
    reference_angular_rate_std: float = math.radians(0.1),
    motion: str = "land-vehicle",
    seed: int = 0,
    threads: int | None = None,
    progress: Callable[[int, int], None] | None = None,
) -> CalibrationResult:
    """Runs the calibration Monte Carlo (paper: 50 sets x 1000 runs).

    ``duration``: calibration segment, s. Reference noise per 100 Hz sample:
    ``reference_specific_force_std`` m/s², ``reference_angular_rate_std``
    rad/s. ``motion``: "land-vehicle" (body-frame vehicle motion with roll and
    pitch dynamics) or "trajectory" (``Trajectory.random``, whose roll and
    pitch follow the manoeuvres only: p/q scale factors and the vertical
    terms are then barely observable). ``method`` ("eiv" or "ls") selects
    the estimator the summary reports first; both are always run.
    ``progress(done, total)`` is called with the number of completed runs.
    Ctrl-C stops the set: the result then covers the completed runs and has
    ``interrupted = True``. Same ``seed`` -> same numbers, whatever
    ``threads``.
    """
    if method not in ("ls", "eiv"):
        raise ValueError(f"method: expected 'ls' or 'eiv', got {method!r}")
    config: dict[str, Any] = {
        "parameter_sets": parameter_sets,
        "runs": runs,
        "duration": duration,
        "preset": preset,
        "reference_specific_force_std": reference_specific_force_std,
        "reference_angular_rate_std": reference_angular_rate_std,
        "motion": motion,
        "seed": seed,
    }
    raw = _memsnav.calibration_experiment(**config, threads=threads, progress=progress)
    return CalibrationResult(
        accelerometer=_stats(raw["accelerometer"]),
        gyroscope=_stats(raw["gyroscope"]),
        method=method,
        config=config,
        completed_runs=int(raw["completed_runs"]),
        interrupted=bool(raw["interrupted"]),
    )
