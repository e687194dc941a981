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
    from memsnav.realdata.answer import answer_lines
    from memsnav.realdata.pipeline import navigate

    result = navigate(
        args.config, data_root=args.data_root, output=args.output, duration_s=args.duration
    )
    print("\n".join(answer_lines(result.summary)))
    for kind, path in result.files.items():
        print(f"{kind}: {path}")
    return 0
