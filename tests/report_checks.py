"""What every report's test checks of its figures and its page.

Figures: none has a linear y-axis stretched by a bound (a curve drawn with
``gid="bound"``: a ±3σ envelope, a requirement) to more than ten times the
size of its data, which flattens the data to a line. A figure that draws
both on a scale that shows both (log, symlog) passes.
:func:`capture_figures` collects each figure a report adds, with what it
hides, before the report closes it.

Page: :func:`page_problems` finds the tables that could run past the
page's text column (not inside a container that scrolls sideways, or more
than :data:`MAX_COLUMNS` columns) and the numbers a line break could split.
It reads the HTML, so it needs no browser; docs/screenshots.py shows the
page as Chromium draws it.
"""

from __future__ import annotations

import re
from html.parser import HTMLParser

import numpy as np
from matplotlib.figure import Figure

from memsnav.report.document import Report

FACTOR = 10.0
"""A y-range more than this many times its data's size is set by a bound."""


def _y_values(artists) -> np.ndarray:
    values = []
    for artist in artists:
        if hasattr(artist, "get_ydata"):
            values.append(np.asarray(artist.get_ydata(), dtype=float).ravel())
        else:  # a filled band: its outline
            values += [np.asarray(path.vertices[:, 1], dtype=float) for path in artist.get_paths()]
    values = np.concatenate(values) if values else np.zeros(0)
    return values[np.isfinite(values)]


def hidden_by_bounds(fig: Figure, factor: float = FACTOR) -> list[str]:
    """The axes of ``fig`` whose linear y-range, set by a bound, exceeds
    ``factor`` times the size of their data (the 95th percentile of its
    absolute values: a spike does not make flat data readable)."""
    problems = []
    for k, ax in enumerate(fig.axes):
        if ax.get_yscale() != "linear":
            continue
        artists = [*ax.get_lines(), *ax.collections]
        bounds = [a for a in artists if a.get_gid() == "bound"]
        data = _y_values([a for a in artists if a.get_gid() != "bound"])
        if not bounds or data.size == 0:
            continue
        low, high = ax.get_ylim()
        size = float(np.percentile(np.abs(data), 95.0))
        bound = float(np.abs(_y_values(bounds)).max(initial=0.0))
        if bound > np.abs(data).max() and high - low > factor * size:
            problems.append(
                f"axes {k} ({ax.get_title() or ax.get_ylabel()}): y-range {high - low:.3g} set by "
                f"a bound up to {bound:.3g}, data of size {size:.3g}"
            )
    return problems


def capture_figures(monkeypatch) -> dict[str, list[str]]:
    """Every figure the reports built while patched, by name, with what
    :func:`hidden_by_bounds` finds in it (filled as the reports are built)."""
    found: dict[str, list[str]] = {}
    add = Report.figure

    def figure(self: Report, name: str, fig: Figure, caption: str) -> None:
        found[name] = hidden_by_bounds(fig)
        add(self, name, fig, caption)

    monkeypatch.setattr(Report, "figure", figure)
    return found


MAX_COLUMNS = 10
"""More columns than this do not fit the 60 rem text column at 0.9 rem,
scrolling or not: such a table is to be split (the study's six wide
tables were)."""


class _Page(HTMLParser):
    def __init__(self) -> None:
        super().__init__()
        self.open: list[tuple[str, dict[str, str | None]]] = []
        self.tables: list[dict] = []
        self.cell: dict | None = None

    def handle_starttag(self, tag, attrs):
        attributes = dict(attrs)
        if tag == "table":
            scrolls = any(
                t == "div" and "table" in (a.get("class") or "").split() for t, a in self.open
            )
            self.tables.append({"scrolls": scrolls, "columns": 0, "row": 0, "split": []})
        elif tag == "tr" and self.tables:
            self.tables[-1]["row"] = 0
        elif tag in ("td", "th") and self.tables:
            self.tables[-1]["row"] += 1
            self.tables[-1]["columns"] = max(self.tables[-1]["columns"], self.tables[-1]["row"])
            self.cell = {"text": "", "nowrap": "num" in (attributes.get("class") or "").split()}
        if tag not in ("br", "img", "meta", "hr", "input"):
            self.open.append((tag, attributes))

    def handle_data(self, data):
        if self.cell is not None:
            self.cell["text"] += data

    def handle_endtag(self, tag):
        if tag in ("td", "th") and self.cell is not None:
            text = self.cell["text"].strip()
            # An exponent's sign or the spaces around "±" are where a browser
            # breaks a number ("6.42e-" over "05").
            numeric = re.fullmatch(r"[-+−±()\[\]\d.,eE%/ ]*\d[-+−±()\[\]\d.,eE%/ ]*", text)
            breaks = re.search(r"\d[eE][-+]\d|±", text)
            if numeric and breaks and not self.cell["nowrap"]:
                self.tables[-1]["split"].append(text)
            self.cell = None
        while self.open:
            if self.open.pop()[0] == tag:
                break


def page_problems(page: str) -> list[str]:
    """The tables of the HTML ``page`` that could run past its text column
    or split a number over two lines, each named by its place and header."""
    parser = _Page()
    parser.feed(page)
    problems = []
    for k, table in enumerate(parser.tables):
        if not table["scrolls"]:
            problems.append(f"table {k}: not in a container that scrolls sideways")
        if table["columns"] > MAX_COLUMNS:
            problems.append(f"table {k}: {table['columns']} columns (at most {MAX_COLUMNS} fit)")
        if table["split"]:
            problems.append(f"table {k}: numbers a line may split: {table['split'][:3]}")
    return problems
