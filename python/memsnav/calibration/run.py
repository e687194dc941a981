"""What a calibration run of a recorded session produced: filled by
:func:`memsnav.calibration.session.run_calibration`, drawn by the report
(``calibration/report.py``)."""

from __future__ import annotations

from dataclasses import dataclass, field
from pathlib import Path
from typing import Any

import numpy as np

from memsnav._memsnav import StaticCalibration
from memsnav.calibration.config import CalibrationConfig
from memsnav.calibration.drive import DriveCalibration
from memsnav.calibration.file import ImuCalibration


@dataclass
class CalibrationRun:
    """What a ``calibrate`` run produced: the fit, the file's content, the
    files written (``calibration``, ``report``) and the summary."""

    config: CalibrationConfig
    calibration: StaticCalibration | DriveCalibration
    imu_calibration: ImuCalibration
    time: np.ndarray
    accel: np.ndarray
    gyro: np.ndarray
    files: dict[str, Path] = field(default_factory=dict)
    summary: dict[str, Any] = field(default_factory=dict)
