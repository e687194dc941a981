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
from memsnav.experiments._plotting import G0, new_figure

DEG = math.pi / 180.0


@dataclass(frozen=True)
class InversionResult:
    """Result of :func:`inversion`; arrays in SI units.

    ``accel_mse`` / ``gyro_mse`` (runs, 3): per run and axis, the mean over
    the trajectory of the squared error of Γ̂ ((m/s²)²) and Ω̂ ((rad/s)²);
    ``raw_*``: the same for the uncorrected outputs;
    ``*_squared_error_vs_time`` (samples, 3): mean over runs per sample.
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

    def summary(self) -> dict[str, Any]:
        """MSE per component averaged over axes and runs: ``accel_mse_g2``
        (g²) and ``gyro_mse_dps2`` ((°/s)²), the paper's ≈1e-5 g² and
        ≈1e-3 (°/s)²; the same for the raw outputs; SI values; config."""
        return {
            "accel_mse_g2": float(self.accel_mse.mean() / G0**2),
            "gyro_mse_dps2": float(self.gyro_mse.mean() / DEG**2),
            "raw_accel_mse_g2": float(self.raw_accel_mse.mean() / G0**2),
            "raw_gyro_mse_dps2": float(self.raw_gyro_mse.mean() / DEG**2),
            "accel_mse": float(self.accel_mse.mean()),
            "gyro_mse": float(self.gyro_mse.mean()),
            "runs": int(self.accel_mse.shape[0]),
            "config": dict(self.config),
        }

    def plot(self) -> list[Any]:
        """Figures 11-12: MSE of Γ̂ (g²) and of Ω̂ ((°/s)²) per run and axis."""
        figures = []
        for title, mse, unit in (
            ("Fig. 11: MSE of Γ [g²]", self.accel_mse / G0**2, "g²"),
            ("Fig. 12: MSE of Ω [(°/s)²]", self.gyro_mse / DEG**2, "(°/s)²"),
        ):
            fig, ax = new_figure(title)
            runs = np.arange(1, mse.shape[0] + 1)
            for i, axis in enumerate("xyz"):
                ax.plot(runs, mse[:, i], ".", label=f"{axis} axis")
            ax.axhline(mse.mean(), color="k", ls="--", label=f"mean {mse.mean():.2e} {unit}")
            ax.set_xlabel("Monte Carlo run")
            ax.set_ylabel(f"MSE [{unit}]")
            ax.legend(fontsize="small")
            figures.append(fig)
        return figures


def inversion(
    *,
    runs: int = 50,
    duration: float = 120.0,
    calibration_duration: float = 300.0,
    preset: str = "paper-mems",
    method: str = "eiv",
    reference_specific_force_std: float = 0.03,
    reference_angular_rate_std: float = math.radians(0.1),
    accel_process_std: float = 0.1,
    gyro_process_std: float = math.radians(1.0),
    seed: int = 0,
    threads: int | None = None,
    progress: Callable[[int, int], None] | None = None,
) -> InversionResult:
    """Runs the inversion Monte Carlo (paper: 300 runs x 120 s).

    ``accel_process_std`` (m/s²) and ``gyro_process_std`` (rad/s): random-walk
    increment per sample of the two filters, set high so the filters
    follow the motion (method §4); the measurement noise is the preset's
    white noise per sample. ``method``: calibration estimator, "eiv" or
    "ls". Same ``seed`` -> same numbers, whatever ``threads``.
    ``progress(done, total)`` is called as runs complete; Ctrl-C stops the
    set and the result covers the completed runs (``interrupted = True``).
    """
    config: dict[str, Any] = {
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
    raw = _memsnav.inversion_experiment(**config, threads=threads, progress=progress)
    return InversionResult(
        accel_mse=raw["accel_mse"],
        gyro_mse=raw["gyro_mse"],
        raw_accel_mse=raw["raw_accel_mse"],
        raw_gyro_mse=raw["raw_gyro_mse"],
        accel_squared_error_vs_time=raw["accel_squared_error_vs_time"],
        gyro_squared_error_vs_time=raw["gyro_squared_error_vs_time"],
        sample_rate=float(raw["sample_rate"]),
        config=config,
        completed_runs=int(raw["completed_runs"]),
        interrupted=bool(raw["interrupted"]),
    )
