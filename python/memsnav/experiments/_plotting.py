"""Shared matplotlib helpers for the experiment figures."""

from __future__ import annotations

from typing import Any

G0 = 9.80665
"""Standard gravity, m/s² (method §1), for plots in g."""


def new_figure(title: str) -> tuple[Any, Any]:
    """A figure with one log-scale axis, titled like the paper's figures."""
    import matplotlib.pyplot as plt

    fig, ax = plt.subplots(figsize=(6.4, 4.0))
    ax.set_title(title)
    ax.set_yscale("log")
    ax.grid(True, which="both", alpha=0.3)
    return fig, ax


def legend_below(fig: Any, ax: Any, ncol: int = 4) -> None:
    """The legend of ``ax``'s curves under the figure, never over the data."""
    handles, labels = ax.get_legend_handles_labels()
    fig.legend(
        handles,
        labels,
        loc="lower center",
        ncol=min(ncol, len(labels)),
        fontsize="small",
        frameon=False,
    )
    fig.tight_layout(rect=(0.0, 0.1, 1.0, 1.0))
