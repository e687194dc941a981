"""The real-data benchmark of docs/tutorials/navigate-a-log.md, rerunnable by anyone:
``python docs/real_data_benchmark.py [--data-root DIR] [--write]``.

- drive_0708 (``examples/drive_0708.toml``: loose coupling on the 4 Hz RTK
  solution, the smoother on): GNSS outages of 15, 30 and 60 s on exactly the
  windows of the published filter that comes with the log
  (rtklibexplorer/GNSS_IMU: an outage of L seconds every 3L seconds from
  GPS time 1436038498.499 until 30 s before the end; the last 30 s window
  is cut to 29 s), forward and smoothed: horizontal RMS and max error over
  the outage epochs, the share of N/E/D errors inside each solution's 3σ,
  the forward error while aided, the time the run takes.
- walk_0827 (``examples/walk_0827.toml``: tight coupling with Doppler on
  four satellites, the smoother on): forward and smoothed errors against
  the RTK truth's fixed epochs, heights made ellipsoidal (the truth's are
  above mean sea level), and the single-point solution's; by accuracy and
  by precision (each less its own mean offset: the truth sits ~8 m off).
  Then the same with 3, 2 or 1 satellites kept in two 30 s windows.

Prints the tables as Markdown; ``--write`` puts them into docs/tutorials/navigate-a-log.md
between its ``benchmark`` markers.
"""

from __future__ import annotations

import argparse
import copy
import tempfile
import time
import warnings
from pathlib import Path
from typing import Any

import numpy as np
from marked_block import replace_block

import memsnav as mn
from memsnav.realdata.config import RunConfig

ROOT = Path(__file__).resolve().parents[1]
BEGIN, END = "<!-- benchmark:begin -->", "<!-- benchmark:end -->"
#: The published filter's first withheld epoch on drive_0708, GPS time, s.
PEER_FIRST_OUTAGE_GPS_S = 1436038498.499
#: Its windows per outage length: count, and the last one's length.
PEER_WINDOWS = {15.0: (11, 15.0), 30.0: (6, 29.0), 60.0: (3, 60.0)}


def _navigate(cfg: RunConfig, duration_s: float | None = None) -> tuple[Any, float]:
    cfg.values["report"]["html"] = False
    with tempfile.TemporaryDirectory() as out, warnings.catch_warnings():
        warnings.simplefilter("ignore")  # the logs' last lines are cut short
        started = time.perf_counter()
        result = mn.navigate(cfg, output=out, duration_s=duration_s)
        return result, time.perf_counter() - started


def _run(cfg: RunConfig, duration_s: float | None = None) -> tuple[dict[str, Any], float]:
    result, seconds = _navigate(cfg, duration_s)
    return result.summary, seconds


def _cells(stats: dict[str, Any]) -> str:
    return (
        f"{stats['rms_horizontal_m']:.2f} | {stats['max_horizontal_m']:.2f} | "
        f"{stats['within_3sigma_share']:.3f}"
    )


def _with_smoother(cfg: RunConfig) -> RunConfig:
    """A copy of ``cfg`` that also runs the smoother."""
    cfg = copy.deepcopy(cfg)
    cfg.engine["filter"] = {**cfg.engine.get("filter", {}), "smoother": True}
    return cfg


def peer_window_runs(base: RunConfig) -> dict[float, tuple[dict[str, Any], float]]:
    """``base`` (a drive_0708 configuration) run with the smoother through
    the published filter's outage windows of each length: its summary and
    run time by length."""
    base = _with_smoother(base)
    # Windows count from the earliest start the log allows.
    anchor = _run(copy.deepcopy(base), duration_s=1.0)[0]["start"]["earliest_gps_time_s"]
    first = PEER_FIRST_OUTAGE_GPS_S - anchor
    runs = {}
    for length, (count, last) in PEER_WINDOWS.items():
        cfg = copy.deepcopy(base)
        windows = [[first + 3.0 * length * k, length] for k in range(count)]
        windows[-1][1] = last
        cfg.engine["outages"] = {"windows_s": windows}
        runs[length] = _run(cfg)
    return runs


def drive_table(data_root: str | None) -> tuple[str, str]:
    """The outage table, and the 15 s outages one by one."""
    base = mn.load_config(ROOT / "examples" / "drive_0708.toml", data_root)
    rows = [
        "| outage length | outages | epochs | forward: RMS horiz. [m] | max [m] | share in 3σ "
        "| smoothed: RMS horiz. [m] | max [m] | share in 3σ | aided RMS [m] | run [s] |",
        "|---|---|---|---|---|---|---|---|---|---|---|",
    ]
    for length, (s, seconds) in peer_window_runs(base).items():
        count = PEER_WINDOWS[length][0]
        f, sm = s["errors_vs_truth"], s["errors_vs_truth_smoothed"]
        if length == 15.0:
            each = _each_outage(s, count)
        rows.append(
            f"| {length:g} s | {count} | {f['in_outages']['epochs']} | "
            f"{_cells(f['in_outages'])} | {_cells(sm['in_outages'])} | "
            f"{f['aided']['rms_horizontal_m']:.3f} | {seconds:.1f} |"
        )
    cfg = _with_smoother(base)
    cfg.engine.pop("outages", None)
    s, seconds = _run(cfg)
    a = s["errors_vs_truth"]["aided"]
    rows.append(
        f"| none | 0 | {a['epochs']} (aided) | {_cells(a)} | "
        f"{_cells(s['errors_vs_truth_smoothed']['aided'])} | {a['rms_horizontal_m']:.3f} | "
        f"{seconds:.1f} |"
    )
    return "\n".join(rows), each


def _each_outage(s: dict[str, Any], count: int) -> str:
    """One row per outage: forward and smoothed errors, the smoothed
    solution's share of errors in its 3σ, and whether the car stood still
    in it (a standstill detected in the window: ZUPT holds the coast)."""
    rows = [
        "| outage | start [s] | forward: RMS / max [m] | smoothed: RMS / max [m] | smoothed "
        "share in 3σ | standstill in it [s] |",
        "|---|---|---|---|---|---|",
    ]
    for k in range(1, count + 1):
        f, sm = s["errors_vs_truth"][f"outage_{k}"], s["errors_vs_truth_smoothed"][f"outage_{k}"]
        start, still = f["start_s"], f["standstill_s"]
        rows.append(
            f"| {k} | {start:.1f} | {f['rms_horizontal_m']:.2f} / {f['max_horizontal_m']:.2f} | "
            f"{sm['rms_horizontal_m']:.2f} / {sm['max_horizontal_m']:.2f} | "
            f"{sm['within_3sigma_share']:.3f} | {still:.1f} |"
        )
    return "\n".join(rows)


def walk_table(data_root: str | None) -> str:
    """The walk on its four satellites: forward, smoothed and single-point,
    against the truth's fixed epochs with its heights made ellipsoidal, by
    accuracy and by precision (each less its own mean offset: the truth's
    ~8 m, the data README)."""
    cfg = mn.load_config(ROOT / "examples" / "walk_0827.toml", data_root)
    cfg.engine["filter"] = {**cfg.engine.get("filter", {}), "smoother": True}
    s, seconds = _run(cfg)

    def row(name: str, raw: dict[str, Any], precise: dict[str, Any], share: str, run: str) -> str:
        return (
            f"| {name} | {raw['epochs']} | {raw['rms_horizontal_m']:.2f} | "
            f"{raw['rms_vertical_m']:.2f} | {precise['rms_horizontal_m']:.2f} | "
            f"{precise['rms_vertical_m']:.2f} | {precise['max_horizontal_m']:.2f} | "
            f"{_offset(precise)} | {share} | {run} |"
        )

    f, fp = s["errors_vs_truth"]["aided"], s["errors_vs_truth_precision"]
    sm, smp = s["errors_vs_truth_smoothed"]["aided"], s["errors_vs_truth_smoothed_precision"]
    spp = s["spp_errors_vs_truth"]
    return "\n".join(
        [
            "| solution | epochs | accuracy: RMS horiz. [m] | RMS vert. [m] | precision: "
            "RMS horiz. [m] | RMS vert. [m] | max horiz. [m] | offset removed (N, E, D) [m] "
            "| share in 3σ | run [s] |",
            "|---|---|---|---|---|---|---|---|---|---|",
            row(
                "memsnav, forward",
                f,
                {**fp["aided"], **fp},
                f"{fp['aided']['within_3sigma_share']:.3f}",
                f"{seconds:.1f}",
            ),
            row(
                "memsnav, smoothed",
                sm,
                {**smp["aided"], **smp},
                f"{smp['aided']['within_3sigma_share']:.3f}",
                "(same run)",
            ),
            row("single-point solution", spp, s["spp_errors_vs_truth_precision"], "–", "–"),
        ]
    )


def _offset(precise: dict[str, Any]) -> str:
    return ", ".join(f"{v:.1f}" for v in precise["offset_removed_ned_m"])


#: The windows in which the walk keeps fewer satellites, s after the
#: earliest start the log allows (where the walk starts): two of 30 s, with
#: the full four before, between and after them.
WALK_WINDOWS_S = [[20.0, 30.0], [70.0, 30.0]]


def walk_withheld_table(data_root: str | None) -> str:
    """walk_0827 keeping 4, 3, 2 or 1 of its satellites in
    :data:`WALK_WINDOWS_S` (the highest of each epoch), scored by precision
    as the example configuration says (fixed truth epochs, heights made
    ellipsoidal, each run's errors less their mean over the epochs outside
    the windows: the truth's ~8 m offset)."""
    rows = [
        "| satellites in the windows | epochs in the windows | horizontal precision in "
        "the windows: RMS / max [m] | vertical RMS there [m] | share of N/E/D errors in "
        "3σ, windows / whole run | offset removed (N, E, D) [m] | flagged |",
        "|---|---|---|---|---|---|---|",
    ]
    for kept in (4, 3, 2, 1):
        cfg = mn.load_config(ROOT / "examples" / "walk_0827.toml", data_root)
        if kept < 4:
            cfg.engine["outages"] = {"windows_s": WALK_WINDOWS_S, "keep_satellites": kept}
        result, _ = _navigate(cfg)
        truth = result.truth
        t = np.asarray(truth["time"]) - result.summary["start"]["earliest_gps_time_s"]
        error, std = np.asarray(truth["error_ned"]), np.asarray(truth["std_ned"])
        inside_windows = np.zeros(len(t), dtype=bool)
        for start, length in WALK_WINDOWS_S:
            inside_windows |= (t >= start) & (t < start + length)
        # The same offset as the engine's precision score (the mean over
        # the epochs outside the windows), here also with all four kept.
        offset = error[~inside_windows].mean(axis=0)
        d = error - offset
        horizontal = np.hypot(d[:, 0], d[:, 1])[inside_windows]
        within = np.abs(d) <= 3.0 * std
        rows.append(
            f"| {kept} | {int(inside_windows.sum())} | "
            f"{np.sqrt(np.mean(horizontal**2)):.2f} / {horizontal.max():.2f} | "
            f"{np.sqrt(np.mean(d[inside_windows, 2] ** 2)):.2f} | "
            f"{within[inside_windows].mean():.3f} / {within.mean():.3f} | "
            f"{offset[0]:.1f}, {offset[1]:.1f}, {offset[2]:.1f} | "
            f"{'yes' if result.summary['diverged'] else 'no'} |"
        )
    return "\n".join(rows)


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--data-root", default=None, help="folder holding real-imu-gnss/")
    parser.add_argument("--write", action="store_true", help="update docs/results/against-rtk.md")
    args = parser.parse_args()
    drive, each = drive_table(args.data_root)
    text = (
        f"{BEGIN}\n\n**drive_0708**, loose, 4 Hz RTK, the published filter's outage "
        f"windows:\n\n{drive}\n\nThe 15 s outages one by one:\n\n{each}\n\n"
        f"**walk_0827**, tight with "
        f"Doppler, four satellites, fixed truth epochs, by accuracy and by precision:\n\n"
        f"{walk_table(args.data_root)}\n\n**walk_0827** "
        f"with satellites withheld in two 30 s windows ({WALK_WINDOWS_S[0][0]:g}-"
        f"{sum(WALK_WINDOWS_S[0]):g} s and {WALK_WINDOWS_S[1][0]:g}-{sum(WALK_WINDOWS_S[1]):g} "
        f"s after the start), scored by precision:\n\n"
        f"{walk_withheld_table(args.data_root)}\n\n{END}"
    )
    print(text)
    if args.write:
        page = ROOT / "docs" / "results" / "against-rtk.md"
        replace_block(page, BEGIN, END, text)


if __name__ == "__main__":
    main()
