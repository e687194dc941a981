"""``memsnav navigate``: real IMU/GNSS logs through a coupled filter
(:func:`memsnav.navigate`)."""

from __future__ import annotations

import argparse
from typing import Any

from memsnav.cli.arguments import configured_run, positive_float

NAME = "navigate"
HELP = "run real IMU/GNSS logs through a coupled filter (see docs/real-data.md)"
DESCRIPTION = (
    "Read the logs of a TOML run configuration, align, run the loosely or tightly "
    "coupled filter, write the solution (CSV, RTKLIB .pos), summary.json and report.html."
)


def add_arguments(command: argparse.ArgumentParser) -> None:
    configured_run(command, "run configuration (TOML), e.g. examples/drive_0708.toml")
    command.add_argument(
        "--duration",
        type=positive_float,
        default=None,
        help="stop this many seconds after alignment",
    )


def run(args: argparse.Namespace, client: Any) -> int:
    from memsnav.realdata.pipeline import navigate

    result = navigate(
        args.config, data_root=args.data_root, output=args.output, duration_s=args.duration
    )
    for kind, path in result.files.items():
        print(f"{kind}: {path}")
    stats = result.summary.get("errors_vs_truth", {}).get("aided")
    if stats and stats.get("epochs"):
        print(
            f"aided: RMS horizontal {stats['rms_horizontal_m']:.2f} "
            f"m, vertical {stats['rms_vertical_m']:.2f} m, "
            f"{100 * stats['within_3sigma_share']:.1f} % within 3 sigma"
        )
    precise = result.summary.get("errors_vs_truth_precision", {})
    if precise.get("aided", {}).get("epochs"):
        north, east, down = precise["offset_removed_ned_m"]
        spp = result.summary.get("spp_errors_vs_truth_precision", {})
        print(
            f"aided, less the mean offset (N {north:.2f}, E {east:.2f}, D {down:.2f} m; "
            f"[truth] score = precision): RMS horizontal "
            f"{precise['aided']['rms_horizontal_m']:.2f} m, vertical "
            f"{precise['aided']['rms_vertical_m']:.2f} m"
            + (
                f"; single-point fixes {spp['rms_horizontal_m']:.2f} m horizontal"
                if spp.get("epochs")
                else ""
            )
        )
    return 0
