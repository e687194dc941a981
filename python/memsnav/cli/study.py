"""``memsnav study``: the outage study of a TOML configuration
(:func:`memsnav.study.run_study`)."""

from __future__ import annotations

import argparse
from typing import Any

from memsnav.cli.arguments import scheduler_argument, threads_argument

NAME = "study"
HELP = "which IMU grade is good enough through which GNSS outages (Monte Carlo sweep)"
DESCRIPTION = (
    "Run the outage study of a TOML configuration (IMU grades x outage lengths x "
    "satellites kept; see examples/study_land_vehicle.toml) and write report.html, "
    "summary.json and the figures into the output folder."
)


def add_arguments(command: argparse.ArgumentParser) -> None:
    command.add_argument(
        "--config",
        required=True,
        help="study configuration (TOML), e.g. examples/study_land_vehicle.toml",
    )
    command.add_argument(
        "--output", default=None, help="output folder (default: the configuration's 'output')"
    )
    threads_argument(command)
    command.add_argument("--quiet", action="store_true", help="no progress bar")
    scheduler_argument(command)


def run(args: argparse.Namespace, client: Any) -> int:
    from memsnav.study import answer_lines, run_study

    study = run_study(
        args.config,
        output=args.output,
        threads=args.threads,
        progress=not args.quiet,
        client=client,
    )
    print("\n".join(answer_lines(study.summary)))
    for kind, written in study.files.items():
        print(f"{kind}: {written}")
    return 130 if study.interrupted else 0
