"""Calibrating a real IMU: the multi-position (static-pose) session, the
calibration file, the ``memsnav calibrate`` command and its report."""

from memsnav.calibration.file import (
    ImuCalibration,
    load_calibration,
    save_calibration,
)
from memsnav.calibration.static import calibrate_static, static_summary

__all__ = [
    "ImuCalibration",
    "calibrate_static",
    "load_calibration",
    "save_calibration",
    "static_summary",
]
