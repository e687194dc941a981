"""Argument types and options that several commands share."""

from __future__ import annotations

import argparse
import math
from collections.abc import Callable
from typing import TypeVar

T = TypeVar("T", int, float)


def _checked(
    parse: Callable[[str], T], kind: str, ok: Callable[[T], bool], rule: str
) -> Callable[[str], T]:
    """An argparse type: ``parse`` the text (else "expected <kind>"), then
    require ``ok`` of the value (else "must be <rule>")."""

    def convert(text: str) -> T:
        try:
            value = parse(text)
        except ValueError:
            raise argparse.ArgumentTypeError(f"expected {kind}, got {text!r}") from None
        if not ok(value):
            raise argparse.ArgumentTypeError(f"must be {rule}, got {text}")
        return value

    return convert


positive_int = _checked(int, "a positive integer", lambda v: v > 0, "positive")
non_negative_int = _checked(int, "an integer", lambda v: v >= 0, "zero or more")
positive_float = _checked(float, "a number", lambda v: 0 < v < math.inf, "positive and finite")
non_negative_float = _checked(
    float, "a number", lambda v: 0 <= v < math.inf, "zero or more and finite"
)
probability = _checked(float, "a number", lambda v: 0 <= v <= 1, "within [0, 1]")


def threads_argument(command: argparse.ArgumentParser) -> None:
    command.add_argument(
        "--threads", type=positive_int, metavar="T", help="worker threads (default: all cores)"
    )


def scheduler_argument(command: argparse.ArgumentParser) -> None:
    command.add_argument(
        "--scheduler",
        metavar="ADDRESS",
        default=None,
        help="run the Monte Carlo runs on the Dask cluster of this scheduler "
        "(e.g. tcp://10.0.0.5:8786; needs pip install 'memsnav[dask]'); the numbers "
        "do not change (docs/how-to/run-on-dask.md)",
    )


def configured_run(command: argparse.ArgumentParser, config_help: str) -> None:
    """The arguments of a command driven by a TOML configuration."""
    command.add_argument("--config", required=True, help=config_help)
    command.add_argument(
        "--data-root",
        default=None,
        help=(
            "folder relative data paths point into (default: "
            "$MEMSNAV_DATA_ROOT, else ../shared/data next to the repository)"
        ),
    )
    command.add_argument(
        "--output", default=None, help="output folder (default: the configuration's 'output')"
    )
