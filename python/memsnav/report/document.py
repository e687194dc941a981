"""A report: sections of prose, tables and figures, written as one HTML page
with every figure embedded, plus each figure as PNG and SVG and its curves as
CSV."""

from __future__ import annotations

import base64
import csv
import html
import io
import re
from collections.abc import Sequence
from dataclasses import dataclass, field
from pathlib import Path

import matplotlib.pyplot as plt
import numpy as np
from matplotlib.figure import Figure

from memsnav._files import write_bytes, write_text
from memsnav.report.numbers import number

_STYLE = """
body { font-family: system-ui, sans-serif; max-width: 60rem; margin: 2rem auto;
       padding: 0 1rem; line-height: 1.5; color: #1d1d1f; }
h1 { font-size: 1.8rem; } h2 { border-bottom: 1px solid #ddd; margin-top: 2.5rem; }
figure { margin: 1.5rem 0; } figure img { max-width: 100%; }
figcaption { font-size: 0.9rem; color: #555; }
.table { overflow-x: auto; margin: 1rem 0; }
table { border-collapse: collapse; font-size: 0.9rem; }
td.num { white-space: nowrap; }
th, td { border: 1px solid #ccc; padding: 0.3rem 0.6rem; text-align: left; }
th { background: #f4f4f4; } .ok { color: #1a7f37; } .no { color: #b42318; }
.partly { color: #9a6700; } .none { color: #57606a; }
code { background: #f4f4f4; padding: 0 0.2rem; }
"""


def figure_to_csv(fig: Figure) -> str:
    """The curves of every axes of ``fig`` in long format:
    ``axes,curve,label,x,y`` (one row per point)."""
    out = io.StringIO()
    writer = csv.writer(out)
    writer.writerow(["axes", "curve", "label", "x", "y"])
    for a, ax in enumerate(fig.axes):
        title = ax.get_title() or f"axes {a}"
        for c, line in enumerate(ax.get_lines()):
            label = line.get_label()
            xs = np.asarray(line.get_xdata(), dtype=float)
            ys = np.asarray(line.get_ydata(), dtype=float)
            for x, y in zip(xs, ys, strict=True):
                writer.writerow([title, c, label, repr(float(x)), repr(float(y))])
        for c, coll in enumerate(ax.collections):
            # Filled bands (mean ± std): their outline vertices.
            for path in getattr(coll, "get_paths", list)():
                for x, y in path.vertices:
                    writer.writerow(
                        [title, f"band{c}", coll.get_label(), repr(float(x)), repr(float(y))]
                    )
    return out.getvalue()


@dataclass
class _Figure:
    name: str
    caption: str
    png: bytes
    svg: bytes
    # The curves behind it; None for a drawing without data (fig. 13).
    csv: str | None


@dataclass
class Report:
    """Build with :meth:`section`, :meth:`paragraph`, :meth:`table` and
    :meth:`figure`, then :meth:`write` into a directory."""

    title: str
    _body: list[str] = field(default_factory=list)
    _figures: list[_Figure] = field(default_factory=list)

    def section(self, title: str) -> None:
        self._body.append(f"<h2>{html.escape(title)}</h2>")

    def paragraph(self, text: str) -> None:
        self._body.append(f"<p>{html.escape(text)}</p>")

    def html(self, fragment: str) -> None:
        """Trusted HTML written by memsnav itself (lists, code)."""
        self._body.append(fragment)

    def table(self, header: Sequence[str], rows: Sequence[Sequence[object]]) -> None:
        """A table in a container that scrolls sideways: a table wider than
        the text column scrolls within it rather than running past the page
        (tests/report_checks.py checks every report for both). A number
        never breaks across lines ("6.42e-" over "05")."""
        head = "".join(f"<th>{html.escape(h)}</th>" for h in header)
        body = "".join("<tr>" + "".join(_cell(v) for v in row) + "</tr>" for row in rows)
        self._body.append(
            f'<div class="table"><table><thead><tr>{head}</tr></thead><tbody>{body}'
            "</tbody></table></div>"
        )

    def figure(self, name: str, fig: Figure, caption: str) -> None:
        """Adds ``fig`` (saved as ``name``.png/.svg/.csv) with a caption."""
        png, svg = io.BytesIO(), io.BytesIO()
        fig.savefig(png, format="png", dpi=110, bbox_inches="tight")
        fig.savefig(svg, format="svg", bbox_inches="tight")
        has_curves = any(ax.get_lines() or ax.collections for ax in fig.axes)
        entry = _Figure(
            name,
            caption,
            png.getvalue(),
            svg.getvalue(),
            figure_to_csv(fig) if has_curves else None,
        )
        # Release pyplot's reference: a report holds dozens of figures.
        plt.close(fig)
        self._figures.append(entry)
        data = base64.b64encode(entry.png).decode("ascii")
        self._body.append(
            f'<figure id="{html.escape(name)}"><img alt="{html.escape(caption)}" '
            f'src="data:image/png;base64,{data}"><figcaption>{html.escape(caption)}'
            f"</figcaption></figure>"
        )

    @property
    def figure_names(self) -> list[str]:
        return [f.name for f in self._figures]

    def render(self) -> str:
        return (
            "<!DOCTYPE html>\n<html lang='en'><head><meta charset='utf-8'>"
            f"<title>{html.escape(self.title)}</title><style>{_STYLE}</style></head><body>"
            f"<h1>{html.escape(self.title)}</h1>" + "\n".join(self._body) + "</body></html>\n"
        )

    def write(self, directory: Path, name: str = "report.html") -> Path:
        """Writes the figures (PNG, SVG, and CSV when they plot data) into
        ``figures/`` (made when there are any) and then the page, each
        atomically."""
        figures = directory / "figures"
        if self._figures:
            figures.mkdir(parents=True, exist_ok=True)
        for f in self._figures:
            write_bytes(figures / f"{f.name}.png", f.png)
            write_bytes(figures / f"{f.name}.svg", f.svg)
            if f.csv is not None:
                write_text(figures / f"{f.name}.csv", f.csv)
        path = directory / name
        write_text(path, self.render())
        return path


class Verdict(str):
    """A claim's verdict in a table cell, coloured by what it says."""


_VERDICT_CLASSES = {"holds": "ok", "partly": "partly", "does not hold": "no"}


_NUMERIC = re.compile(r"[-+−±()\[\]\d.,eE%∞/ ]*\d[-+−±()\[\]\d.,eE%∞/ ]*")
"""A cell that holds only numbers: "(5.9 ± 0.1)e-05", "1.86 / 11.94", "[2.5, ∞)"."""


def _cell(value: object) -> str:
    """The ``<td>`` of ``value``: a verdict coloured, a bool as yes / no, a
    float as :func:`memsnav.report.numbers.number` writes it, numbers kept
    on one line."""
    if isinstance(value, Verdict):
        css = _VERDICT_CLASSES.get(str(value), "none")
        return f'<td><span class="{css}">{html.escape(str(value))}</span></td>'
    if isinstance(value, bool):
        return f'<td><span class="{"ok" if value else "no"}">{"yes" if value else "no"}</span></td>'
    text = number(value) if isinstance(value, float) else str(value)
    numeric = isinstance(value, int | float) or _NUMERIC.fullmatch(text) is not None
    return (
        f'<td class="num">{html.escape(text)}</td>' if numeric else f"<td>{html.escape(text)}</td>"
    )
