"""What every report's test checks of its figures: none has a linear y-axis
stretched by a bound (a curve drawn with ``gid="bound"``: a ±3σ envelope, a
requirement) to more than ten times the size of its data, which flattens
the data to a line. A figure that draws both on a scale that shows both
(log, symlog) passes. :func:`capture_figures` collects each figure a
report adds, with what it hides, before the report closes it."""

from __future__ import annotations

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
