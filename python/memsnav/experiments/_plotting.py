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
