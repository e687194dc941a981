"""``memsnav navigate``: real IMU/GNSS logs through a coupled filter
(:func:`memsnav.navigate`)."""

from __future__ import annotations

import argparse
import sys
from typing import Any

from memsnav.cli.arguments import configured_run, positive_float

NAME = "navigate"
HELP = "run real IMU/GNSS logs through a coupled filter (see docs/tutorials/navigate-a-log.md)"
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
    """Runs the configuration and prints its answer and files. A run that
    failed once its output folder was accepted prints what it computed,
    then the failure and where its report is as the error (exit status 1);
    any other error is the command's usual one line."""
    from memsnav.realdata.answer import answer_lines, failure_line
    from memsnav.realdata.pipeline import navigate

    try:
        result = navigate(
            args.config, data_root=args.data_root, output=args.output, duration_s=args.duration
        )
    except Exception as e:
        written = getattr(e, "result", None)
        if written is None:
            raise
        result = written
    print("\n".join(answer_lines(result.summary)))
    for kind, path in result.files.items():
        print(f"{kind}: {path}")
    if result.failure is None:
        return 0
    where = result.files.get("report", result.files["summary"])
    print(
        f"memsnav: error: {failure_line(result.failure)} (what the run computed and what may "
        f"explain it: {where})",
        file=sys.stderr,
    )
    return 1
