"""``memsnav calibrate``: an IMU calibrated from a recorded session
(:func:`memsnav.calibration.session.run_calibration`)."""

from __future__ import annotations

import argparse
import sys
from typing import Any

from memsnav.cli.arguments import configured_run

NAME = "calibrate"
HELP = "calibrate an IMU from a recorded session (see docs/calibration.md)"
DESCRIPTION = (
    "Read a calibration session described by a TOML configuration (a "
    "multi-position static-pose session, or a drive calibrated against its GNSS), fit the "
    "accelerometer and gyroscope models and write calibration.json (the calibration file) "
    "and report.html."
)


def add_arguments(command: argparse.ArgumentParser) -> None:
    configured_run(
        command,
        "configuration (TOML), e.g. examples/xsens_static.toml or "
        "examples/drive_0708_calibration.toml",
    )


def run(args: argparse.Namespace, client: Any) -> int:
    from memsnav.calibration.session import run_calibration

    calibration = run_calibration(args.config, data_root=args.data_root, output=args.output)
    for kind, path in calibration.files.items():
        print(f"{kind}: {path}")
    s = calibration.summary
    if calibration.config["session"]["kind"] == "drive":
        for view in ("forward", "smoothed"):
            for label in ("raw", "calibrated"):
                st = s.get("navigation", {}).get(label, {}).get(view, {}).get("after_fit", {})
                if st.get("outages"):
                    print(
                        f"{view}, {label}: outages after the calibration span: horizontal RMS "
                        f"{st['rms_horizontal_m']:.2f} m, max {st['max_horizontal_m']:.2f} m"
                    )
            draws = s.get("navigation", {}).get("draws") or []
            rms = [d[view]["after_fit"].get("rms_horizontal_m") for d in draws]
            finite = [r for r in rms if r is not None]
            if finite:
                print(
                    f"{view}, {len(finite)} calibrations drawn from its covariance: RMS "
                    f"{min(finite):.2f}-{max(finite):.2f} m"
                )
    for subset in ("fit", "held_out"):
        if f"magnitude_rms_after_{subset}_m_s2" not in s:
            continue
        magnitude = s[f"magnitude_rms_after_{subset}_m_s2"]
        turn = s[f"turn_rms_after_{subset}_deg"]
        if magnitude is not None:
            print(
                f"{subset.replace('_', ' ')}: |f| - g RMS {1e3 * magnitude:.2f} mm/s^2 "
                f"(nominal {1e3 * s[f'magnitude_rms_before_{subset}_m_s2']:.0f}), gravity "
                f"direction after a turn RMS {turn:.3f} deg "
                f"(nominal {s[f'turn_rms_before_{subset}_deg']:.1f})"
            )
    for warning in calibration.calibration.warnings:
        print(f"warning: {warning}", file=sys.stderr)
    return 0
