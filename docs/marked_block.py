"""The one way the docs scripts put what they generate into a page: the
block from its begin marker to its end marker (HTML comments such as
``<!-- timings:begin -->``) replaced by the new text, which carries the
markers itself; and the command line of the scripts whose block is
rendered from a record. The scripts import it as a sibling (``python docs/x.py``
puts ``docs/`` on the path; pytest's ``pythonpath`` does for the tests)."""

from __future__ import annotations

import argparse
from collections.abc import Callable
from pathlib import Path
from typing import Any

from figures import ROOT, load_record, write_pages, write_record


def replace_block(page: Path, begin: str, end: str, text: str) -> None:
    """Writes ``page`` with its ``begin`` … ``end`` block replaced by ``text``
    (ValueError when either marker is missing)."""
    old = page.read_text()
    start, stop = old.index(begin), old.index(end) + len(end)
    page.write_text(old[:start] + text + old[stop:])


def record_block_script(
    parser: argparse.ArgumentParser,
    name: str,
    page: Path,
    markers: tuple[str, str],
    measure: Callable[[argparse.Namespace], dict[str, Any]],
    render: Callable[[dict[str, Any]], str],
) -> None:
    """The command line of a script whose block is rendered from its record
    ``docs/data/<name>.json``: without options it measures and prints the
    block; ``--write`` keeps the figures in the record, then puts the block
    into ``page`` between ``markers`` and re-renders the pages' figures;
    ``--from-record`` does the second part alone. ``parser`` may carry the
    script's own options, which ``measure`` receives."""
    parser.add_argument(
        "--write",
        action="store_true",
        help=f"write docs/data/{name}.json and update {page.relative_to(ROOT)}",
    )
    parser.add_argument(
        "--from-record", action="store_true", help="re-render the page from the last record"
    )
    args = parser.parse_args()
    if not args.from_record:
        figures = measure(args)
        if not args.write:
            print(render({"figures": figures}))
            return
        write_record(name, figures, render=False)
    replace_block(page, *markers, render(load_record(name)))
    write_pages()
