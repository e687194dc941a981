"""The ``memsnav`` command. :func:`main` parses the command line and runs
one command; each command is a module of this package that declares its
options and what it prints, and calls the library function that does the
work (``memsnav.reproduce``, ``memsnav.study``, ``memsnav.simulate``,
``memsnav.navigate``, ``memsnav.calibration.session``,
``memsnav.realdata.convert``, ``memsnav.realdata.config``)."""

from __future__ import annotations

import argparse
import sys
import warnings

import memsnav
from memsnav.cli import calibrate, convert, navigate, reproduce, schema, simulate, study

COMMANDS = {
    command.NAME: command
    for command in (
        reproduce,
        study,
        simulate,
        navigate,
        calibrate,
        convert,
        schema,
    )
}
"""The commands by name, in the order ``memsnav --help`` lists them."""


def build_parser() -> argparse.ArgumentParser:
    parser = argparse.ArgumentParser(
        prog="memsnav",
        description=(
            "MEMS inertial sensors aided by GNSS: the study of de Boer et al. (ION GNSS 2008)."
        ),
    )
    parser.add_argument("--version", action="version", version=f"memsnav {memsnav.__version__}")
    parser.add_argument(
        "--debug",
        action="store_true",
        help="show the full traceback of an error (default: one line)",
    )
    commands = parser.add_subparsers(dest="command", metavar="COMMAND")
    for name, command in COMMANDS.items():
        command.add_arguments(
            commands.add_parser(name, help=command.HELP, description=command.DESCRIPTION)
        )
    return parser


def main(argv: list[str] | None = None) -> int:
    """Runs a command; any error is one line ``memsnav: error: ...`` on
    stderr and exit status 1 (the traceback with ``--debug``), an interrupt
    exit status 130."""
    parser = build_parser()
    args = parser.parse_args(argv)
    if args.command is None:
        parser.print_help(sys.stderr)
        return 2
    format_warning = warnings.formatwarning
    if not args.debug:
        warnings.formatwarning = _one_line_warning
    client = None
    try:
        if getattr(args, "scheduler", None) is not None:
            from memsnav._distributed import connect

            client = connect(args.scheduler)
        code: int = COMMANDS[args.command].run(args, client)
        return code
    except KeyboardInterrupt:
        print("memsnav: interrupted", file=sys.stderr)
        return 130
    except Exception as e:
        if args.debug:
            raise
        message = " ".join(str(e).split()) or type(e).__name__
        print(f"memsnav: error: {message}", file=sys.stderr)
        return 1
    finally:
        warnings.formatwarning = format_warning
        if client is not None:
            client.close()


def _one_line_warning(
    message: Warning | str,
    category: type[Warning],
    filename: str,
    lineno: int,
    line: str | None = None,
) -> str:
    """A warning as ``memsnav: warning: ...`` (no source line)."""
    return f"memsnav: warning: {message}\n"
