"""Inversion Monte Carlo: paper §5.2, figures 11-12 (method §4 and §6).

Each run draws an IMU from the preset, calibrates it on its own segment
with GNSS-like references, then inverts the outputs of a fresh 120 s
land-vehicle trajectory with the two random-walk EKFs, and measures the
mean square error of the estimated specific force and angular rate.
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
from memsnav.experiments._plotting import G0, legend_below, new_figure

DEG = math.pi / 180.0


@dataclass(frozen=True)
class InversionResult:
    """Result of :func:`inversion`; arrays in SI units.

    ``accel_mse`` / ``gyro_mse`` (runs, 3): per run and axis (u, v, w and
    p, q, r: the body axes x, y, z), the mean over the trajectory of the
    squared error of Γ̂ ((m/s²)²) and Ω̂ ((rad/s)²); ``raw_*``: the same for
    the uncorrected outputs; ``*_squared_error_vs_time`` (samples, 3): mean
    over runs per sample; ``config``: the settings that ran.
    """

    accel_mse: npt.NDArray[np.float64]
    gyro_mse: npt.NDArray[np.float64]
    raw_accel_mse: npt.NDArray[np.float64]
    raw_gyro_mse: npt.NDArray[np.float64]
    accel_squared_error_vs_time: npt.NDArray[np.float64]
    gyro_squared_error_vs_time: npt.NDArray[np.float64]
    sample_rate: float
    config: dict[str, Any]
    completed_runs: int = 0
    interrupted: bool = False

    def __repr__(self) -> str:
        return (
            f"InversionResult({self.completed_runs} runs at {self.sample_rate:g} Hz"
            + (", interrupted" if self.interrupted else "")
            + ")"
        )

    def summary(self) -> dict[str, Any]:
        """MSE averaged over axes and runs: ``accel_mse_g2`` (g²) and
        ``gyro_mse_dps2`` ((°/s)²), the paper's ≈1e-5 g² and ≈1e-3 (°/s)²,
        with their standard errors over runs (``*_se_*``); the same for the
        raw outputs; SI values (``accel_mse_m2_s4``, ``gyro_mse_rad2_s2``);
        ``completed_runs``, ``interrupted``, ``config``."""
        runs = self.accel_mse.shape[0]

        def mean_se(per_run_axis: npt.NDArray[np.float64], scale: float) -> tuple[float, float]:
            per_run = per_run_axis.mean(axis=1) / scale
            if runs == 0:
                return math.nan, math.nan
            se = float(per_run.std(ddof=1) / math.sqrt(runs)) if runs > 1 else math.nan
            return float(per_run.mean()), se

        accel, accel_se = mean_se(self.accel_mse, G0**2)
        gyro, gyro_se = mean_se(self.gyro_mse, DEG**2)
        return {
            "accel_mse_g2": accel,
            "accel_mse_se_g2": accel_se,
            "gyro_mse_dps2": gyro,
            "gyro_mse_se_dps2": gyro_se,
            "raw_accel_mse_g2": mean_se(self.raw_accel_mse, G0**2)[0],
            "raw_gyro_mse_dps2": mean_se(self.raw_gyro_mse, DEG**2)[0],
            "accel_mse_m2_s4": mean_se(self.accel_mse, 1.0)[0],
            "gyro_mse_rad2_s2": mean_se(self.gyro_mse, 1.0)[0],
            "completed_runs": self.completed_runs,
            "interrupted": self.interrupted,
            "config": dict(self.config),
        }

    def plot(self) -> list[Any]:
        """Figures 11-12: MSE of Γ̂ (g²) and of Ω̂ ((°/s)²) per run and axis
        (u, v, w and p, q, r: the body axes, as in figures 3-10)."""
        figures = []
        for title, mse, unit, axes in (
            ("Fig. 11: MSE of Γ", self.accel_mse / G0**2, "g²", "uvw"),
            ("Fig. 12: MSE of Ω", self.gyro_mse / DEG**2, "(°/s)²", "pqr"),
        ):
            fig, ax = new_figure(title)
            runs = np.arange(1, mse.shape[0] + 1)
            for i, axis in enumerate(axes):
                ax.plot(runs, mse[:, i], ".", label=f"axis {axis}")
            ax.axhline(mse.mean(), color="k", ls="--", label=f"mean {mse.mean():.2e} {unit}")
            ax.set_xlabel("Monte Carlo run")
            ax.set_ylabel(f"MSE [{unit}]")
            legend_below(fig, ax)
            figures.append(fig)
        return figures


def inversion(
    *,
    runs: int | None = None,
    duration: float | None = None,
    calibration_duration: float | None = None,
    preset: str | None = None,
    method: str | None = None,
    reference_specific_force_std: float | None = None,
    reference_angular_rate_std: float | None = None,
    accel_process_std: float | None = None,
    gyro_process_std: float | None = None,
    seed: int | None = None,
    threads: int | None = None,
    progress: Callable[[int, int], None] | None = None,
    client: Any = None,
    chunk_runs: int | None = None,
) -> InversionResult:
    """Runs the inversion Monte Carlo (paper: 300 runs x 120 s).

    ``None`` takes the core's default (``result.config`` shows the values
    that ran): ``runs`` 50, ``duration`` 120 s inverted per run,
    ``calibration_duration`` 300 s, ``preset`` "paper-mems", ``method``
    "eiv" (calibration estimator, or "ls"), reference noise 0.03 m/s² and
    0.1 °/s per sample, ``accel_process_std`` 0.1 m/s² and
    ``gyro_process_std`` 1 °/s (in rad/s): random-walk increment per sample
    of the two filters, set high so the filters follow the motion (method
    §4); the measurement noise is the preset's white noise per sample;
    ``seed`` 0. Same ``seed`` -> same numbers, whatever ``threads``.
    ``progress(done, total)`` is called as runs complete; Ctrl-C stops the
    set and the result covers the completed runs (``interrupted = True``).
    ``client``: a ``dask.distributed.Client`` to run the set on its
    cluster in chunks of ``chunk_runs`` runs (``docs/how-to/run-on-dask.md``):
    the same numbers bit for bit; ``threads`` must then be None.
    """
    kwargs: dict[str, Any] = {
        "runs": runs,
        "duration": duration,
        "calibration_duration": calibration_duration,
        "preset": preset,
        "method": method,
        "reference_specific_force_std": reference_specific_force_std,
        "reference_angular_rate_std": reference_angular_rate_std,
        "accel_process_std": accel_process_std,
        "gyro_process_std": gyro_process_std,
        "seed": seed,
    }
    total = 0
    if client is not None:
        # The set's size, defaults filled in by the core (a fold of no chunk).
        total = int(_memsnav.inversion_experiment(**kwargs, chunks=[])["config"]["runs"])
    raw = run_set(
        "inversion_experiment",
        kwargs,
        total,
        client=client,
        threads=threads,
        progress=progress,
        chunk_runs=chunk_runs,
    )
    return InversionResult(
        accel_mse=raw["accel_mse"],
        gyro_mse=raw["gyro_mse"],
        raw_accel_mse=raw["raw_accel_mse"],
        raw_gyro_mse=raw["raw_gyro_mse"],
        accel_squared_error_vs_time=raw["accel_squared_error_vs_time"],
        gyro_squared_error_vs_time=raw["gyro_squared_error_vs_time"],
        sample_rate=float(raw["sample_rate"]),
        config=dict(raw["config"]),
        completed_runs=int(raw["completed_runs"]),
        interrupted=bool(raw["interrupted"]),
    )
