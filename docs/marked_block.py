"""The one way the docs scripts put what they generate into a page: the
block from its begin marker to its end marker (HTML comments such as
``<!-- timings:begin -->``) replaced by the new text, which carries the
markers itself. The scripts import it as a sibling (``python docs/x.py``
puts ``docs/`` on the path; pytest's ``pythonpath`` does for the tests)."""

from __future__ import annotations

from pathlib import Path


def replace_block(page: Path, begin: str, end: str, text: str) -> None:
    """Writes ``page`` with its ``begin`` … ``end`` block replaced by ``text``
    (ValueError when either marker is missing)."""
    old = page.read_text()
    start, stop = old.index(begin), old.index(end) + len(end)
    page.write_text(old[:start] + text + old[stop:])
