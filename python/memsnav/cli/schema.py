"""``memsnav schema``: the JSON schema of a ``navigate`` configuration
(:func:`memsnav.realdata.config.json_schema`), for an editor that completes
and checks the TOML as it is typed."""

from __future__ import annotations

import argparse
import json
from pathlib import Path
from typing import Any

NAME = "schema"
HELP = "print the JSON schema of a navigate configuration (editor completion)"
DESCRIPTION = (
    "Print (or write with --output) the JSON schema (draft 2020-12) of a navigate "
    "configuration: every table and key, each key's kind of value, bounds, default and "
    "description, and no other key. A TOML language server (Taplo, Even Better TOML) "
    "uses it when the file starts with '#:schema ./navigate.schema.json'. Checks that "
    "need several keys (a bias instability needs its correlation time, an outage "
    "window inside the run) happen when the configuration is loaded."
)


def add_arguments(command: argparse.ArgumentParser) -> None:
    command.add_argument(
        "--output",
        type=Path,
        default=None,
        help="write the schema to this file instead of printing it",
    )


def run(args: argparse.Namespace, client: Any) -> int:
    from memsnav.realdata.config import json_schema

    text = json.dumps(json_schema(), indent=2, sort_keys=True) + "\n"
    if args.output is None:
        print(text, end="")
    else:
        args.output.write_text(text)
        print(f"schema: {args.output}")
    return 0
