"""The figures a docs page quotes, read from the page so that a test
compares them with what it computed (every quoted figure is
generated or checked); the Python side of crates/memsnav-core/tests/quoted."""

import re
from pathlib import Path

ROOT = Path(__file__).resolve().parent.parent


def quoted_figures(page: str, pattern: str) -> tuple[float, ...]:
    """The groups of `pattern` in `page` (a path from the repository root),
    whitespace runs made single spaces, as numbers; fails naming the page
    when it no longer quotes them."""
    text = " ".join((ROOT / page).read_text().split())
    found = re.search(pattern, text)
    assert found, f"{page} no longer quotes {pattern!r}"
    return tuple(float(v) for v in found.groups())


def rounds_to(quoted: float, value: float) -> bool:
    """``quoted`` is ``value`` rounded to the digits it is quoted with (as
    far as the float tells them: "8" and "0.50" read as 8 and 0.5)."""
    step = 1.0 if quoted.is_integer() else 10.0 ** -len(repr(quoted).partition(".")[2])
    return abs(quoted - value) <= 0.5 * step + 1e-9
