"""A recorded calibration session (static poses or a drive) calibrated as
its TOML configuration describes: read, fit, write the calibration file and
its report (what ``memsnav calibrate --config cal.toml`` runs)."""

from __future__ import annotations

import time as _time
import warnings
from dataclasses import replace
from pathlib import Path

import numpy as np

from memsnav._files import output_folder
from memsnav.calibration.config import CalibrationConfig, load_calibration_config
from memsnav.calibration.drive import calibrate_drive, compare_navigation
from memsnav.calibration.file import ImuCalibration
from memsnav.calibration.run import CalibrationRun
from memsnav.calibration.static import calibrate_static, static_summary


def read_triad_table(path: Path, time_unit: str) -> tuple[np.ndarray, np.ndarray]:
    """A whitespace- or comma-separated text table of ``t x y z`` rows (as
    the Xsens logs of ``imu-static-poses``): time (s) and readings (N, 3).
    Errors name the file."""
    try:
        table = np.loadtxt(path, ndmin=2, delimiter=None)
    except OSError as e:
        raise ValueError(f"{path}: cannot read: {e.strerror or e}") from None
    except ValueError as e:
        raise ValueError(f"{path}: not a table of numbers: {e}") from None
    if table.shape[1] != 4 or table.shape[0] < 2:
        raise ValueError(
            f"{path}: expected rows of 4 columns (t, x, y, z), got shape {table.shape}"
        )
    if not np.isfinite(table).all():
        row = int(np.argwhere(~np.isfinite(table))[0, 0]) + 1
        raise ValueError(f"{path}:{row}: not a finite number")
    scale = 1e-3 if time_unit == "ms" else 1.0
    return table[:, 0] * scale, table[:, 1:]


def run_calibration(
    config: str | Path,
    *,
    data_root: str | Path | None = None,
    output: str | Path | None = None,
) -> CalibrationRun:
    """Runs the calibration a configuration describes (module docstring) and
    writes ``calibration.json`` and, unless ``[report] html = false``,
    ``report.html`` with its figures into the output folder."""
    cfg = load_calibration_config(config, data_root)
    out = output_folder(output if output is not None else cfg.config_path("", "output"))
    run = _drive(cfg) if cfg["session"]["kind"] == "drive" else _static(cfg)
    run.files["calibration"] = run.imu_calibration.save(out / "calibration.json")
    if cfg["report"]["html"]:
        from memsnav.calibration.report import write_report

        run.files["report"] = write_report(run, out)
    return run


def _static(cfg: CalibrationConfig) -> CalibrationRun:
    """A multi-position session (``[imu]``, ``[static]``)."""
    imu, static = cfg["imu"], cfg["static"]
    accel_path, gyro_path = cfg.data_path("imu", "accel_file"), cfg.data_path("imu", "gyro_file")
    t_accel, accel = read_triad_table(accel_path, imu["time_unit"])
    t_gyro, gyro = read_triad_table(gyro_path, imu["time_unit"])
    if len(t_accel) != len(t_gyro) or np.abs(t_accel - t_gyro).max() > 1e-6:
        raise ValueError(
            f"{gyro_path}: its time stamps differ from {accel_path}'s "
            f"({len(t_gyro)} and {len(t_accel)} rows): the two triads must be sampled together"
        )
    started = _time.perf_counter()
    with warnings.catch_warnings(record=True):
        # The warnings are in the file and the report; the CLI prints them.
        warnings.simplefilter("always")
        cal = calibrate_static(
            t_accel,
            accel,
            gyro,
            gravity=static["gravity_m_s2"],
            accel_scale=imu["accel_scale"],
            accel_offset=imu["accel_offset"],
            gyro_scale=imu["gyro_scale"],
            gyro_offset=imu["gyro_offset"],
            window=static["window_s"],
            threshold_factor=static["threshold_factor"],
            initial_rest=static["initial_rest_s"],
            min_pose=static["min_pose_s"],
            estimate=static["estimate"],
            holdout_every=static["holdout_every"] or None,
            holdout_from=static.get("holdout_from_s"),
        )
    elapsed = _time.perf_counter() - started
    source = {
        "config": str(cfg.path),
        "name": cfg[""]["name"],
        "accel_file": str(accel_path),
        "gyro_file": str(gyro_path),
        "samples": len(t_accel),
        "duration_s": float(t_accel[-1] - t_accel[0]),
        "settings": cfg["static"],
    }
    imu_cal = ImuCalibration.from_static(cal, source)
    run = CalibrationRun(cfg, cal, imu_cal, t_accel, accel, gyro)
    run.summary = {**static_summary(cal), "processing_s": elapsed}
    return run


def _drive(cfg: CalibrationConfig) -> CalibrationRun:
    """The paper's calibration on a drive (``[drive]``): the references from
    the smoothed navigation of the drive's ``navigate`` configuration, the
    fit, and (``compare``) the drive navigated with and without it."""
    from memsnav.realdata import pipeline
    from memsnav.realdata.config import load_config

    drive = cfg["drive"]
    nav = load_config(cfg.config_path("drive", "navigate"), cfg.data_root)
    if nav["imu"]["calibration"]:
        raise ValueError(
            f"{cfg.path}: drive.navigate: {nav.path} applies a calibration already "
            "([imu] calibration); a drive is calibrated from its raw readings"
        )
    t, f, w, _ = pipeline.read_imu(nav)
    gnss = pipeline.gnss_input(nav)
    until = drive["until_s"] or None
    started = _time.perf_counter()
    with warnings.catch_warnings(record=True):
        # The warnings are in the file and the report; the CLI prints them.
        warnings.simplefilter("always")
        cal = calibrate_drive(
            t,
            f,
            w,
            gnss,
            settings=nav.engine,
            window_s=drive["window_s"],
            until_s=until,
            estimate=drive["estimate"],
            scale_factor_states=drive["scale_factor_states"],
        )
    elapsed = _time.perf_counter() - started
    truth = pipeline.read_truth(nav)
    comparison = None
    if drive["compare"] and truth is not None:
        truth_time, truth_position_ecef = pipeline.truth_before_the_run(nav, truth)
        comparison = compare_navigation(
            t,
            f,
            w,
            gnss,
            cal,
            settings=nav.engine,
            truth_time=truth_time,
            truth_position_ecef=truth_position_ecef,
            draws=drive["draws"],
            seed=drive["seed"],
        )
    source = {
        "config": str(cfg.path),
        "name": cfg[""]["name"],
        "navigate_config": str(nav.path),
        "imu_file": str(nav.data_path("imu", "file")),
        "samples": len(t),
        "duration_s": float(t[-1] - t[0]),
        "settings": drive,
    }
    rate = float(1.0 / np.median(np.diff(t)))
    imu_cal = ImuCalibration.from_drive(cal, rate, source)
    if comparison is not None:
        imu_cal = replace(imu_cal, fit={**imu_cal.fit, "navigation": comparison})
    run = CalibrationRun(cfg, cal, imu_cal, t, f, w)
    run.summary = {
        **imu_cal.fit,
        "accelerometer_bias_m_s2": np.asarray(cal.accelerometer.model.bias).tolist(),
        "gyroscope_bias_deg_s": np.degrees(np.asarray(cal.gyroscope.model.bias)).tolist(),
        "processing_s": elapsed,
    }
    return run
