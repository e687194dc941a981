"""The drive calibration of ``examples/drive_0708_calibration.toml`` as
docs/how-to/calibrate-an-imu.md ("Results on drive_0708") and the README
show it: ``record`` runs ``memsnav calibrate`` on it and returns
``figures_of`` its calibration file; ``parameters_table`` and
``outages_table`` write the page's two tables from the record.

``python docs/doc_runs.py drive_calibration`` writes the record (about a
minute); ``tests/test_drive_calibration.py`` computes ``figures_of`` its own
run of the same command and compares it with the record."""

from __future__ import annotations

import contextlib
import io
import json
import tempfile
from pathlib import Path
from typing import Any

import numpy as np

from memsnav.cli import main

ROOT = Path(__file__).resolve().parents[1]
CONFIG = ROOT / "examples" / "drive_0708_calibration.toml"

#: The parameters table's rows: label, sensor, term, factor to the unit shown.
PARAMETER_ROWS = (
    ("accelerometer bias, m/s²", "accelerometer", "bias", 1.0),
    ("accelerometer scale factor", "accelerometer", "scale_factor", 1.0),
    ("gyro bias, °/s", "gyroscope", "bias", float(np.degrees(1.0))),
    ("gyro scale factor", "gyroscope", "scale_factor", 1.0),
)
#: The outages table's rows: the outages, their key in the calibration file.
OUTAGE_ROWS = (
    ("after the calibration span ({n}, never seen by the fit)", "after_fit"),
    ("inside the span ({n})", "in_fit"),
    ("the first one", "first"),
)
PARAMETERS = (
    "<!-- drive-calibration-parameters:begin -->",
    "<!-- drive-calibration-parameters:end -->",
)
OUTAGES = ("<!-- drive-calibration-outages:begin -->", "<!-- drive-calibration-outages:end -->")


def calibrate(data_root: Path, output: Path, config: Path = CONFIG) -> dict[str, Any]:
    """Runs ``memsnav calibrate`` on ``config`` (the example) into
    ``output`` (its terminal output swallowed) and returns the calibration
    file."""
    argv = ["calibrate", "--config", str(config), "--data-root", str(data_root)]
    with contextlib.redirect_stdout(io.StringIO()):
        code = main([*argv, "--output", str(output)])
    if code != 0:
        raise RuntimeError(f"memsnav calibrate failed with exit code {code}")
    content: dict[str, Any] = json.loads((output / "calibration.json").read_text())
    return content


def _outage(run: dict[str, Any]) -> dict[str, float]:
    return {"rms_m": run["rms_horizontal_m"], "max_m": run["max_horizontal_m"]}


def figures_of(calibration: dict[str, Any]) -> dict[str, Any]:
    """The figures the pages show of a drive calibration file."""
    fit = calibration["fit"]
    nav = fit["navigation"]
    outages = {
        key: {
            f"{imu}_{view}": _outage(nav[imu][view][key])
            for view in ("forward", "smoothed")
            for imu in ("raw", "calibrated")
        }
        | {"count": nav["raw"]["forward"][key]["outages"]}
        for _, key in OUTAGE_ROWS
    }
    forward = [d["forward"]["after_fit"]["rms_horizontal_m"] for d in nav["draws"]]
    smoothed = [d["smoothed"]["after_fit"]["rms_horizontal_m"] for d in nav["draws"]]
    raw_after = outages["after_fit"]["raw_forward"]["rms_m"]
    calibrated_after = outages["after_fit"]["calibrated_forward"]["rms_m"]
    parameters = {
        f"{sensor}_{term}": {
            "value": [factor * v for v in calibration[sensor][term]],
            "sigma": [factor * s for s in calibration[f"{sensor}_std"][term]],
        }
        for _, sensor, term, factor in PARAMETER_ROWS
    }
    return {
        "windows": {
            "count": fit["windows"],
            "window_s": fit["window_s"],
            "until_s": fit["until_s"],
            "before_heading": fit["skipped_before_heading"],
            "around_resets": fit["skipped_for_resets"],
        },
        "parameters": parameters,
        "accel_x_scale_pct": 100 * calibration["accelerometer"]["scale_factor"][0],
        "accel_x_scale_sigma_pct": 100 * calibration["accelerometer_std"]["scale_factor"][0],
        "accel_condition_number": max(fit["condition_number"]["accelerometer"]),
        "outages": outages,
        "after_fit_change_pct": 100 * (calibrated_after / raw_after - 1),
        "draws": {
            "count": len(forward),
            "forward_least_m": min(forward),
            "forward_most_m": max(forward),
            "forward_median_m": float(np.median(forward)),
            "forward_above_raw": sum(v > raw_after for v in forward),
            "smoothed_least_m": min(smoothed),
            "smoothed_most_m": max(smoothed),
        },
    }


def record(data_root: Path) -> dict[str, Any]:
    """The example calibrated anew, as :func:`figures_of` shows it."""
    with tempfile.TemporaryDirectory() as tmp:
        return figures_of(calibrate(data_root, Path(tmp)))


#: The reference windows the window study compares, s.
WINDOWS_S = (0.5, 1.0, 2.0, 4.0)


def window_study(data_root: Path) -> dict[str, Any]:
    """The example calibrated with each of :data:`WINDOWS_S` (no draws):
    the forward horizontal RMS in the outages after the calibration span,
    calibrated per window and raw, m."""
    text = _replaced(
        CONFIG.read_text(),
        ('navigate = "drive_0708.toml"', f'navigate = "{CONFIG.parent / "drive_0708.toml"}"'),
        ("draws = 10", "draws = 0"),
    )
    calibrated, raw = [], None
    with tempfile.TemporaryDirectory() as tmp:
        for window_s in WINDOWS_S:
            config = Path(tmp) / f"window_{window_s:g}.toml"
            config.write_text(_replaced(text, ("window_s = 2.0", f"window_s = {window_s}")))
            content = calibrate(data_root, Path(tmp) / f"out_{window_s:g}", config)
            after = content["fit"]["navigation"]
            calibrated.append(after["calibrated"]["forward"]["after_fit"]["rms_horizontal_m"])
            raw = after["raw"]["forward"]["after_fit"]["rms_horizontal_m"]
    return {"window_s": list(WINDOWS_S), "calibrated_rms_m": calibrated, "raw_rms_m": raw}


def _replaced(text: str, *changes: tuple[str, str]) -> str:
    """``text`` with each (old, new) replaced; an old the example no longer
    holds is an error, not a study of the unchanged example."""
    for old, new in changes:
        if old not in text:
            raise ValueError(f"{CONFIG.name} no longer holds {old!r}")
        text = text.replace(old, new)
    return text


def _minus(text: str) -> str:
    return text.replace("-", "−")


def parameters_table(recorded: dict[str, Any]) -> str:
    """The fitted biases and scale factors with their σ, "held" where the
    fit holds the term (σ 0), in the sensor's axes."""
    rows = ["| | x | y | z |", "|---|---|---|---|"]
    for label, sensor, term, _ in PARAMETER_ROWS:
        fitted = recorded["figures"]["parameters"][f"{sensor}_{term}"]
        cells = [
            "held" if sigma == 0.0 else _minus(f"{value:.3f} ± {sigma:.3f}")
            for value, sigma in zip(fitted["value"], fitted["sigma"], strict=True)
        ]
        rows.append(f"| {label} | " + " | ".join(cells) + " |")
    return "\n".join([PARAMETERS[0], *rows, PARAMETERS[1]])


def outages_table(recorded: dict[str, Any]) -> str:
    """Horizontal RMS / max of the outages, m, raw and calibrated, forward
    and smoothed."""
    figures = recorded["figures"]
    rows = [
        "| outages | raw forward | calibrated forward | raw smoothed | calibrated smoothed |",
        "|---|---|---|---|---|",
    ]
    for label, key in OUTAGE_ROWS:
        runs = figures["outages"][key]
        shown = label.format(n=runs["count"])
        cells = [
            f"{runs[f'{imu}_{view}']['rms_m']:.2f} / {runs[f'{imu}_{view}']['max_m']:.2f}"
            for view in ("forward", "smoothed")
            for imu in ("raw", "calibrated")
        ]
        rows.append(f"| {shown} | " + " | ".join(cells) + " |")
    return "\n".join([OUTAGES[0], *rows, OUTAGES[1]])
