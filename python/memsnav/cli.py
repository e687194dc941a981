"""The ``memsnav`` command."""

from __future__ import annotations

import argparse
import sys

import memsnav


def build_parser() -> argparse.ArgumentParser:
    parser = argparse.ArgumentParser(
        prog="memsnav",
        description=(
            "MEMS inertial sensors aided by GNSS: the study of de Boer et al. (ION GNSS 2008)."
        ),
    )
    parser.add_argument("--version", action="version", version=f"memsnav {memsnav.__version__}")
    commands = parser.add_subparsers(dest="command", metavar="COMMAND")
    nav = commands.add_parser(
        "navigate",
        help="run real IMU/GNSS logs through a coupled filter (see docs/real-data.md)",
        description="Read the logs of a TOML run configuration, align, run the loosely or tightly "
        "coupled filter, write the solution (CSV, RTKLIB .pos), summary.json and report.html.",
    )
    nav.add_argument(
        "--config", required=True, help="run configuration (TOML), e.g. examples/drive_0708.toml"
    )
    nav.add_argument(
        "--data-root",
        default=None,
        help=(
            "folder relative data paths point into (default: "
            "$MEMSNAV_DATA_ROOT, else ../shared/data next to the repository)"
        ),
    )
    nav.add_argument(
        "--output", default=None, help="output folder (default: the configuration's 'output')"
    )
    nav.add_argument(
        "--duration", type=float, default=None, help="stop this many seconds after alignment"
    )
    return parser


def main(argv: list[str] | None = None) -> int:
    parser = build_parser()
    args = parser.parse_args(argv)
    if args.command is None:
        parser.print_help(sys.stderr)
        return 2
    if args.command == "navigate":
        from memsnav.realdata.pipeline import navigate

        try:
            result = navigate(
                args.config, data_root=args.data_root, output=args.output, duration_s=args.duration
            )
        except (ValueError, memsnav.MemsnavError) as e:
            print(f"memsnav navigate: {e}", file=sys.stderr)
            return 1
        for kind, path in result.files.items():
            print(f"{kind}: {path}")
        stats = result.summary.get("errors_vs_truth", {}).get("aided")
        if stats and stats.get("epochs"):
            print(
                f"aided: RMS horizontal {stats['rms_horizontal_m']:.2f} "
                f"m, vertical {stats['rms_vertical_m']:.2f} m, "
                f"{100 * stats['within_3sigma_share']:.1f} % within 3 sigma"
            )
    return 0
