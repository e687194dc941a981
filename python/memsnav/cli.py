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
    parser.add_subparsers(dest="command", metavar="COMMAND")
    return parser


def main(argv: list[str] | None = None) -> int:
    parser = build_parser()
    args = parser.parse_args(argv)
    if args.command is None:
        parser.print_help(sys.stderr)
        return 2
    return 0
