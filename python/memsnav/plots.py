"""Figures of a navigation solution (matplotlib, imported when a function is
called): the track in local east/north metres, and the position errors
against a truth with the filter's ±kσ bounds. The ``navigate`` report draws
its track and error figures with these."""

from __future__ import annotations

from collections.abc import Sequence
from typing import Any

import numpy as np
import numpy.typing as npt

import memsnav._memsnav as _mn


def _axes(ax: Any, rows: int, figsize: tuple[float, float]) -> Any:
    """``ax`` when given, else new axes (``rows`` stacked, sharing x)."""
    if ax is not None:
        return ax
    import matplotlib.pyplot as plt

    _, new = plt.subplots(rows, 1, figsize=figsize, sharex=rows > 1)
    return new


def plot_track(
    track: Any,
    *,
    time: npt.ArrayLike | None = None,
    origin_ecef: npt.ArrayLike | None = None,
    rate_hz: float | None = None,
    outages: Sequence[tuple[float, float]] | npt.ArrayLike = (),
    ax: Any = None,
    fmt: str = "-",
    **style: Any,
) -> Any:
    """Draws a track as north against east metres from ``origin_ecef`` (default
    its first point) and returns the axes.

    ``track``: an ECEF position series (N, 3), m, with its ``time`` (N,) s
    when thinning or marking outages; or anything with ``position_ecef``
    and ``time`` (a ``FilterSolution`` at the IMU, a ``LogRun`` at the
    antenna). ``rate_hz``: thin to that rate first (the first sample of each
    interval, as the solution writers do; None: every point).
    ``outages``: (start, end) times whose stretches are drawn over in red.
    ``fmt`` and ``style`` go to ``Axes.plot`` (``label``, ``color``, ``lw``...).
    ``ax``: axes to draw into (default a new figure).
    """
    if hasattr(track, "position_ecef"):
        time = track.time if time is None else time
        track = track.position_ecef
    position = np.asarray(track, dtype=float)
    t = None if time is None else np.asarray(time, dtype=float)
    origin = position[0] if origin_ecef is None else np.asarray(origin_ecef, dtype=float)
    windows = np.asarray(outages, dtype=float).reshape(-1, 2)
    if t is None and (rate_hz is not None or len(windows)):
        raise ValueError("time: needed with rate_hz or outages")
    if rate_hz is not None and t is not None:
        keep = np.asarray(_mn.decimate(t, rate_hz))
        position, t = position[keep], t[keep]
    ax = _axes(ax, 1, (7, 6))
    ned = np.asarray(_mn.ecef_to_ned(position, origin))
    ax.plot(ned[:, 1], ned[:, 0], fmt, **style)
    for i, (start, end) in enumerate(windows):
        assert t is not None
        m = (t >= start) & (t < end)
        ax.plot(
            ned[m, 1], ned[m, 0], "-", lw=2, color="tab:red", label="outages" if i == 0 else None
        )
    ax.set_xlabel("east [m]")
    ax.set_ylabel("north [m]")
    ax.set_aspect("equal", adjustable="datalim")
    ax.grid(alpha=0.3)
    return ax


#: The error figure's lowest value, m (log scale): an RTK truth's own noise
#: is about a centimetre, and an error's zero crossings would otherwise
#: stretch the axis down to nothing.
ERROR_FLOOR_M = 0.01


def plot_errors(
    time: npt.ArrayLike,
    error_ned: npt.ArrayLike,
    std_ned: npt.ArrayLike | None = None,
    *,
    sigmas: float = 3.0,
    t0: float = 0.0,
    label: str = "solution - truth",
    outages: Sequence[tuple[float, float]] | npt.ArrayLike = (),
    standstills: Sequence[tuple[float, float]] | npt.ArrayLike = (),
    axes: Any = None,
    floor_m: float = ERROR_FLOOR_M,
) -> Any:
    """Draws the size of the north, east and down position errors against
    time since ``t0`` on three stacked axes, log scale, with the
    ``sigmas``·σ bound of ``std_ned`` (dashed red, ``gid="bound"``; none when
    None), and returns the axes (add more series with
    :func:`plot_error_series`). A log scale because bounds ten times the
    errors (an outage's 3σ of tens of metres against errors of a metre)
    flatten the errors to a line on a linear one; values below ``floor_m``
    are drawn at it. ``time`` (T,) s, ``error_ned`` and ``std_ned`` (T, 3)
    m: e.g. ``LogRun.score(truth_time, truth_ecef)``'s ``time``,
    ``error_ned`` and ``std_ned``. ``outages`` are shaded red,
    ``standstills`` green ((start, end) times, s). ``axes``: three axes to
    draw into (default a new figure).
    """
    axes = _axes(axes, 3, (9, 7.5))
    plot_error_series(axes, time, error_ned, t0=t0, floor_m=floor_m, lw=0.8, label=f"|{label}|")
    t = np.asarray(time, dtype=float) - t0
    for j, name in enumerate(("north", "east", "down")):
        a = axes[j]
        if std_ned is not None:
            bound = sigmas * np.asarray(std_ned, dtype=float)[:, j]
            # gid "bound": a bound, not data (the report tests read it).
            a.semilogy(t, bound, "r--", lw=0.8, label=rf"${sigmas:g}\sigma$", gid="bound")
        for start, end in np.asarray(outages, dtype=float).reshape(-1, 2):
            a.axvspan(start - t0, end - t0, color="tab:red", alpha=0.1)
        for start, end in np.asarray(standstills, dtype=float).reshape(-1, 2):
            a.axvspan(start - t0, end - t0, color="tab:green", alpha=0.08)
        a.set_ylim(bottom=floor_m)
        a.set_ylabel(f"{name} [m]")
        a.grid(alpha=0.3, which="both")
    axes[-1].set_xlabel("time since the start [s]" if t0 else "time [s]")
    return axes


def plot_error_series(
    axes: Any,
    time: npt.ArrayLike,
    error_ned: npt.ArrayLike,
    *,
    t0: float = 0.0,
    floor_m: float = ERROR_FLOOR_M,
    fmt: str = "-",
    **style: Any,
) -> None:
    """Adds the size of another solution's N, E, D errors to the three axes
    of :func:`plot_errors` (log scale, below ``floor_m`` drawn at it);
    ``fmt`` and ``style`` go to ``Axes.semilogy``."""
    t = np.asarray(time, dtype=float) - t0
    error = np.abs(np.asarray(error_ned, dtype=float))
    for j in range(3):
        axes[j].semilogy(t, np.maximum(error[:, j], floor_m), fmt, **style)
