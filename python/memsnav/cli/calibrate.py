"""``memsnav calibrate``: an IMU calibrated from a recorded session
(:func:`memsnav.calibration.session.run_calibration`)."""

from __future__ import annotations

import argparse
import sys
from typing import Any

from memsnav.cli.arguments import configured_run

NAME = "calibrate"
HELP = "calibrate an IMU from a recorded session (see docs/how-to/calibrate-an-imu.md)"
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
    print("\n".join(answer_lines(calibration.summary, calibration.config["session"]["kind"])))
    for kind, path in calibration.files.items():
        print(f"{kind}: {path}")
    found = calibration.calibration.warnings
    if found:
        print(
            f"{len(found)} warning{'s' if len(found) > 1 else ''} (the calibration is written; "
            "its report lists them):",
            file=sys.stderr,
        )
    for warning in found:
        print(f"warning: {warning}", file=sys.stderr)
    return 0


_DRIVE_SUBSETS = (
    ("after_fit", "outages after the calibration span (never seen by the fit)"),
    ("first", "the first outage"),
)


def answer_lines(s: dict[str, Any], kind: str) -> list[str]:
    """What the calibration did, first: a drive's outage errors raw and
    calibrated (the outages after the calibration span, and the first one,
    which a calibration from the first minutes may not help), a static
    session's figures of merit in the fit and held out."""
    lines = []
    if kind == "drive":
        navigation = s.get("navigation") or {}
        for view in ("forward", "smoothed"):
            for key, words in _DRIVE_SUBSETS:
                raw = navigation.get("raw", {}).get(view, {}).get(key, {})
                cal = navigation.get("calibrated", {}).get(view, {}).get(key, {})
                if raw.get("outages") and cal.get("outages"):
                    lines.append(
                        f"{view}, {words}: horizontal RMS {raw['rms_horizontal_m']:.2f} -> "
                        f"{cal['rms_horizontal_m']:.2f} m, max {raw['max_horizontal_m']:.2f} -> "
                        f"{cal['max_horizontal_m']:.2f} m (raw -> calibrated)"
                    )
            rms = [
                d[view]["after_fit"].get("rms_horizontal_m") for d in navigation.get("draws", [])
            ]
            finite = [r for r in rms if r is not None]
            if finite:
                lines.append(
                    f"{view}, {len(finite)} calibrations drawn from its covariance: RMS "
                    f"{min(finite):.2f}-{max(finite):.2f} m after the calibration span"
                )
    for subset in ("fit", "held_out"):
        magnitude = s.get(f"magnitude_rms_after_{subset}_m_s2")
        if magnitude is None:
            continue
        lines.append(
            f"{subset.replace('_', ' ')}: |f| - g RMS {1e3 * magnitude:.2f} mm/s^2 "
            f"(nominal {1e3 * s[f'magnitude_rms_before_{subset}_m_s2']:.0f}), gravity "
            f"direction after a turn RMS {s[f'turn_rms_after_{subset}_deg']:.3f} deg "
            f"(nominal {s[f'turn_rms_before_{subset}_deg']:.1f})"
        )
    return lines
