"""The ``memsnav`` command."""

from __future__ import annotations

import argparse
import sys

import memsnav


def _positive_int(text: str) -> int:
    try:
        value = int(text)
    except ValueError:
        raise argparse.ArgumentTypeError(f"expected a positive integer, got {text!r}") from None
    if value <= 0:
        raise argparse.ArgumentTypeError(f"must be positive, got {value}")
    return value


def _non_negative_int(text: str) -> int:
    try:
        value = int(text)
    except ValueError:
        raise argparse.ArgumentTypeError(f"expected an integer, got {text!r}") from None
    if value < 0:
        raise argparse.ArgumentTypeError(f"must be zero or more, got {value}")
    return value


def build_parser() -> argparse.ArgumentParser:
    parser = argparse.ArgumentParser(
        prog="memsnav",
        description=(
            "MEMS inertial sensors aided by GNSS: the study of de Boer et al. (ION GNSS 2008)."
        ),
    )
    parser.add_argument("--version", action="version", version=f"memsnav {memsnav.__version__}")
    commands = parser.add_subparsers(dest="command", metavar="COMMAND")

    reproduce = commands.add_parser(
        "reproduce",
        help="reproduce the paper's experiments (figures 3-18) and write the report",
        description=(
            "Run the calibration, inversion and navigation experiments (nominal and with a "
            "30 s outage) and write report.html, summary.json, the figures (PNG, SVG) and "
            "their curves (CSV) into DIR."
        ),
    )
    reproduce.add_argument(
        "--out", default="results", metavar="DIR", help="output directory (default: results)"
    )
    reproduce.add_argument(
        "--full",
        action="store_true",
        help="the paper's Monte Carlo sizes (1000 x 50 calibration, 300 inversion, "
        "200 navigation runs) instead of the quick defaults",
    )
    reproduce.add_argument(
        "--runs",
        type=_positive_int,
        metavar="N",
        help="Monte Carlo runs of every experiment (calibration: runs per parameter set)",
    )
    reproduce.add_argument(
        "--seed", type=_non_negative_int, default=0, metavar="S", help="base seed (default: 0)"
    )
    reproduce.add_argument(
        "--threads", type=_positive_int, metavar="T", help="worker threads (default: all cores)"
    )
    reproduce.add_argument("--quiet", action="store_true", help="no progress bars")
    return parser


def main(argv: list[str] | None = None) -> int:
    parser = build_parser()
    args = parser.parse_args(argv)
    if args.command is None:
        parser.print_help(sys.stderr)
        return 2
    try:
        if args.command == "reproduce":
            from memsnav.reproduce import reproduce

            result = reproduce(
                out=args.out,
                full=args.full,
                runs=args.runs,
                seed=args.seed,
                threads=args.threads,
                progress=not args.quiet,
            )
            print(f"memsnav: report written to {result.report}", file=sys.stderr)
            return 130 if result.interrupted else 0
    except KeyboardInterrupt:
        print("memsnav: interrupted", file=sys.stderr)
        return 130
    except (OSError, ValueError, memsnav.MemsnavError) as e:
        print(f"memsnav: error: {e}", file=sys.stderr)
        return 1
    return 0
