"""``memsnav reproduce``: the paper's study (:func:`memsnav.reproduce.reproduce`)."""

from __future__ import annotations

import argparse
import sys
from typing import Any

from memsnav.cli.arguments import (
    non_negative_int,
    positive_int,
    scheduler_argument,
    threads_argument,
)

NAME = "reproduce"
HELP = "reproduce the paper's experiments (figures 3-18) and write the report"
DESCRIPTION = (
    "Run the calibration, inversion and navigation experiments (nominal, with a "
    "30 s outage, and with partial outages of 0-3 satellites) and write report.html, "
    "summary.json (every number, each experiment's completed runs, and each paper "
    "claim's verdict), the figures (PNG, SVG) and their curves (CSV) into DIR."
)


def add_arguments(command: argparse.ArgumentParser) -> None:
    command.add_argument(
        "--out", default="results", metavar="DIR", help="output directory (default: results)"
    )
    command.add_argument(
        "--full",
        action="store_true",
        help="the paper's Monte Carlo sizes (1000 x 50 calibration, 300 inversion, "
        "200 navigation runs; 100 partial-outage runs) instead of the quick defaults",
    )
    command.add_argument(
        "--runs",
        type=positive_int,
        metavar="N",
        help="Monte Carlo runs of every experiment (calibration: runs per parameter set)",
    )
    command.add_argument(
        "--seed", type=non_negative_int, default=0, metavar="S", help="base seed (default: 0)"
    )
    threads_argument(command)
    command.add_argument("--quiet", action="store_true", help="no progress bars")
    scheduler_argument(command)


def run(args: argparse.Namespace, client: Any) -> int:
    from memsnav.reproduce import reproduce

    study = reproduce(
        out=args.out,
        full=args.full,
        runs=args.runs,
        seed=args.seed,
        threads=args.threads,
        progress=not args.quiet,
        client=client,
    )
    print("\n".join(answer_lines(study.summary)))
    incomplete = {
        name: state
        for name, state in study.summary["experiments"].items()
        if state["state"] != "completed"
    }
    for name, state in incomplete.items():
        print(
            f"memsnav: {name}: {state['completed_runs']}/{state['planned_runs']} runs, "
            f"{state['state']}",
            file=sys.stderr,
        )
    print(f"report: {study.report} (each claim's criterion, figures and data)")
    return 130 if study.interrupted else 0


def answer_lines(summary: dict[str, Any]) -> list[str]:
    """The answer in a few lines: each claim's verdict and title, the
    verdicts aligned in a column."""
    claims = summary["claims"]
    width = max(len(c["verdict"]) for c in claims)
    label = summary["sizes"]
    sizes = label if "runs" in label else f"{label} Monte Carlo sizes"
    return [f"The paper's claims, judged ({sizes}, seed {summary['seed']}):"] + [
        f"  {c['verdict']:<{width}}  {c['title']}" for c in claims
    ]
