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

Prints the tables as Markdown; ``--write`` keeps the figures in the record
docs/data/against_rtk.json (with the figures the page's sentences draw
from the tables: ranges, the published filter's errors over memsnav's) and
puts the tables into docs/results/against-rtk.md between its
``benchmark`` markers, its sentences' figures through placeholders;
``--from-record`` re-renders them from the record without a run.
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
from marked_block import record_block_script

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


def _stats(stats: dict[str, Any]) -> dict[str, float]:
    """RMS and largest horizontal error, m, and the share inside 3σ."""
    return {
        "rms_m": stats["rms_horizontal_m"],
        "max_m": stats["max_horizontal_m"],
        "share": stats["within_3sigma_share"],
    }


def _cells(stats: dict[str, float]) -> str:
    return f"{stats['rms_m']:.2f} | {stats['max_m']:.2f} | {stats['share']:.3f}"


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


def drive_figures(data_root: str | None) -> dict[str, Any]:
    """The outage runs by length, the run without outages, and the 15 s
    outages one by one (each with the standstill in it, s: ZUPT holds the
    coast there)."""
    base = mn.load_config(ROOT / "examples" / "drive_0708.toml", data_root)
    figures: dict[str, Any] = {"lengths": {}}
    for length, (s, seconds) in peer_window_runs(base).items():
        count = PEER_WINDOWS[length][0]
        f, sm = s["errors_vs_truth"], s["errors_vs_truth_smoothed"]
        figures["lengths"][f"{length:g}"] = {
            "outages": count,
            "epochs": f["in_outages"]["epochs"],
            "forward": _stats(f["in_outages"]),
            "smoothed": _stats(sm["in_outages"]),
            "aided_rms_m": f["aided"]["rms_horizontal_m"],
            "run_s": seconds,
        }
        if length == 15.0:
            figures["outages_15s"] = [
                {
                    "start_s": f[f"outage_{k}"]["start_s"],
                    "forward": _stats(f[f"outage_{k}"]),
                    "smoothed": _stats(sm[f"outage_{k}"]),
                    "standstill_s": f[f"outage_{k}"]["standstill_s"],
                }
                for k in range(1, count + 1)
            ]
    cfg = _with_smoother(base)
    cfg.engine.pop("outages", None)
    s, seconds = _run(cfg)
    a = s["errors_vs_truth"]["aided"]
    figures["none"] = {
        "epochs": a["epochs"],
        "forward": _stats(a),
        "smoothed": _stats(s["errors_vs_truth_smoothed"]["aided"]),
        "aided_rms_m": a["rms_horizontal_m"],
        "run_s": seconds,
    }
    return figures


def drive_table(drive: dict[str, Any]) -> str:
    rows = [
        "| outage length | outages | epochs | forward: RMS horiz. [m] | max [m] | share in 3σ "
        "| smoothed: RMS horiz. [m] | max [m] | share in 3σ | aided RMS [m] | run [s] |",
        "|---|---|---|---|---|---|---|---|---|---|---|",
    ]
    for length, r in drive["lengths"].items():
        rows.append(
            f"| {length} s | {r['outages']} | {r['epochs']} | {_cells(r['forward'])} | "
            f"{_cells(r['smoothed'])} | {r['aided_rms_m']:.3f} | {r['run_s']:.1f} |"
        )
    r = drive["none"]
    rows.append(
        f"| none | 0 | {r['epochs']} (aided) | {_cells(r['forward'])} | "
        f"{_cells(r['smoothed'])} | {r['aided_rms_m']:.3f} | {r['run_s']:.1f} |"
    )
    return "\n".join(rows)


def each_outage_table(drive: dict[str, Any]) -> str:
    """One row per 15 s outage: forward and smoothed errors, the smoothed
    solution's share of errors in its 3σ, the standstill in it."""
    rows = [
        "| outage | start [s] | forward: RMS / max [m] | smoothed: RMS / max [m] | smoothed "
        "share in 3σ | standstill in it [s] |",
        "|---|---|---|---|---|---|",
    ]
    for k, o in enumerate(drive["outages_15s"], 1):
        f, sm = o["forward"], o["smoothed"]
        rows.append(
            f"| {k} | {o['start_s']:.1f} | {f['rms_m']:.2f} / {f['max_m']:.2f} | "
            f"{sm['rms_m']:.2f} / {sm['max_m']:.2f} | {sm['share']:.3f} | "
            f"{o['standstill_s']:.1f} |"
        )
    return "\n".join(rows)


def walk_figures(data_root: str | None) -> dict[str, Any]:
    """The walk on its four satellites: forward, smoothed and single-point,
    against the truth's fixed epochs with its heights made ellipsoidal, by
    accuracy and by precision (each less its own mean offset: the truth's
    ~8 m, the data README)."""
    cfg = mn.load_config(ROOT / "examples" / "walk_0827.toml", data_root)
    cfg.engine["filter"] = {**cfg.engine.get("filter", {}), "smoother": True}
    s, seconds = _run(cfg)

    def solution(raw: dict[str, Any], precise: dict[str, Any], share, run) -> dict[str, Any]:
        return {
            "epochs": raw["epochs"],
            "accuracy_rms_horizontal_m": raw["rms_horizontal_m"],
            "accuracy_rms_vertical_m": raw["rms_vertical_m"],
            "precision_rms_horizontal_m": precise["rms_horizontal_m"],
            "precision_rms_vertical_m": precise["rms_vertical_m"],
            "precision_max_horizontal_m": precise["max_horizontal_m"],
            "offset_removed_ned_m": list(precise["offset_removed_ned_m"]),
            "share": share,
            "run_s": run,
        }

    f, fp = s["errors_vs_truth"]["aided"], s["errors_vs_truth_precision"]
    sm, smp = s["errors_vs_truth_smoothed"]["aided"], s["errors_vs_truth_smoothed_precision"]
    return {
        "forward": solution(f, {**fp["aided"], **fp}, fp["aided"]["within_3sigma_share"], seconds),
        "smoothed": solution(
            sm, {**smp["aided"], **smp}, smp["aided"]["within_3sigma_share"], None
        ),
        "single_point": solution(
            s["spp_errors_vs_truth"], s["spp_errors_vs_truth_precision"], None, None
        ),
    }


def walk_table(walk: dict[str, Any]) -> str:
    def row(name: str, r: dict[str, Any], run: str) -> str:
        share = "–" if r["share"] is None else f"{r['share']:.3f}"
        offset = ", ".join(f"{v:.1f}" for v in r["offset_removed_ned_m"])
        return (
            f"| {name} | {r['epochs']} | {r['accuracy_rms_horizontal_m']:.2f} | "
            f"{r['accuracy_rms_vertical_m']:.2f} | {r['precision_rms_horizontal_m']:.2f} | "
            f"{r['precision_rms_vertical_m']:.2f} | {r['precision_max_horizontal_m']:.2f} | "
            f"{offset} | {share} | {run} |"
        )

    return "\n".join(
        [
            "| solution | epochs | accuracy: RMS horiz. [m] | RMS vert. [m] | precision: "
            "RMS horiz. [m] | RMS vert. [m] | max horiz. [m] | offset removed (N, E, D) [m] "
            "| share in 3σ | run [s] |",
            "|---|---|---|---|---|---|---|---|---|---|",
            row("memsnav, forward", walk["forward"], f"{walk['forward']['run_s']:.1f}"),
            row("memsnav, smoothed", walk["smoothed"], "(same run)"),
            row("single-point solution", walk["single_point"], "–"),
        ]
    )


#: The windows in which the walk keeps fewer satellites, s after the
#: earliest start the log allows (where the walk starts): two of 30 s, with
#: the full four before, between and after them.
WALK_WINDOWS_S = [[20.0, 30.0], [70.0, 30.0]]


def withheld_figures(data_root: str | None) -> dict[str, Any]:
    """walk_0827 keeping 4, 3, 2 or 1 of its satellites in
    :data:`WALK_WINDOWS_S` (the highest of each epoch), scored by precision
    as the example configuration says (fixed truth epochs, heights made
    ellipsoidal, each run's errors less their mean over the epochs outside
    the windows: the truth's ~8 m offset)."""
    figures = {}
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
        figures[str(kept)] = {
            "epochs": int(inside_windows.sum()),
            "rms_horizontal_m": float(np.sqrt(np.mean(horizontal**2))),
            "max_horizontal_m": float(horizontal.max()),
            "rms_vertical_m": float(np.sqrt(np.mean(d[inside_windows, 2] ** 2))),
            "share_in_windows": float(within[inside_windows].mean()),
            "share_whole_run": float(within.mean()),
            "offset_removed_ned_m": [float(v) for v in offset],
            "flagged": bool(result.summary["diverged"]),
        }
    return figures


def withheld_table(withheld: dict[str, Any]) -> str:
    rows = [
        "| satellites in the windows | epochs in the windows | horizontal precision in "
        "the windows: RMS / max [m] | vertical RMS there [m] | share of N/E/D errors in "
        "3σ, windows / whole run | offset removed (N, E, D) [m] | flagged |",
        "|---|---|---|---|---|---|---|",
    ]
    for kept, r in withheld.items():
        offset = ", ".join(f"{v:.1f}" for v in r["offset_removed_ned_m"])
        rows.append(
            f"| {kept} | {r['epochs']} | {r['rms_horizontal_m']:.2f} / "
            f"{r['max_horizontal_m']:.2f} | {r['rms_vertical_m']:.2f} | "
            f"{r['share_in_windows']:.3f} / {r['share_whole_run']:.3f} | {offset} | "
            f"{'yes' if r['flagged'] else 'no'} |"
        )
    return "\n".join(rows)


#: The published filter's errors in the same windows (rtklibexplorer/
#: GNSS_IMU, run 2026-11-23 outside this repository): forward and
#: `vel_match` RMS / max, m.
PEER = {
    "15": {"forward": (3.09, 12.81), "vel_match": (0.296, 0.684)},
    "30": {"forward": (20.57, 76.35), "vel_match": (2.10, 4.83)},
    "60": {"forward": (115.5, 392.0), "vel_match": (14.08, 39.73)},
}
#: The same run's internal position covariance: the least and most share
#: of its aided and of its outage N/E errors inside 3σ over the three
#: lengths, %, and its CPU time for the 548 s log, s.
PEER_BOUNDS_PERCENT = {"aided": (61.0, 78.0), "outages": (41.0, 88.0)}
PEER_CPU_S = 48.0


def derived(figures: dict[str, Any]) -> dict[str, Any]:
    """The figures the page's sentences draw from the tables: ranges over
    the outages, the peer's errors over memsnav's."""
    drive, walk = figures["drive"], figures["walk"]
    lengths = drive["lengths"]
    outages = drive["outages_15s"]
    shares = [r["forward"]["share"] for r in (*lengths.values(), drive["none"])]
    still = [(k, o["standstill_s"]) for k, o in enumerate(outages, 1) if o["standstill_s"]]
    worst = max(range(len(outages)), key=lambda k: outages[k]["forward"]["max_m"])
    accuracy = [
        walk[s]["accuracy_rms_horizontal_m"] for s in ("forward", "smoothed", "single_point")
    ]
    return {
        "peer": {
            "errors_m": PEER,
            "bounds_percent": PEER_BOUNDS_PERCENT,
            "cpu_s": PEER_CPU_S,
        },
        "peer_over_forward": [PEER[k]["forward"][0] / lengths[k]["forward"]["rms_m"] for k in PEER],
        "peer_over_smoothed": [
            PEER[k]["vel_match"][0] / lengths[k]["smoothed"]["rms_m"] for k in PEER
        ],
        "forward_share_percent": {"least": 100 * min(shares), "most": 100 * max(shares)},
        "outage_share_percent": {
            "least": 100 * min(r["forward"]["share"] for r in lengths.values()),
            "most": 100 * max(r["forward"]["share"] for r in lengths.values()),
        },
        "outages_15s": {
            "forward_rms_m": {
                "least": min(o["forward"]["rms_m"] for o in outages),
                "most": max(o["forward"]["rms_m"] for o in outages),
            },
            "worst": worst + 1,
            "worst_max_m": outages[worst]["forward"]["max_m"],
            "smoothed_rms_most_m": max(o["smoothed"]["rms_m"] for o in outages),
            "smoothed_max_most_m": max(o["smoothed"]["max_m"] for o in outages),
            "smoothed_share_least_percent": 100 * min(o["smoothed"]["share"] for o in outages),
            "standstills": len(still),
            "standstill_outage": still[0][0] if still else 0,
            "standstill_s": still[0][1] if still else 0.0,
        },
        "walk_accuracy_m": {"least": min(accuracy), "most": max(accuracy)},
        "drive_run_s": {
            "least": min(r["run_s"] for r in (*lengths.values(), drive["none"])),
            "most": max(r["run_s"] for r in (*lengths.values(), drive["none"])),
        },
        "walk_down_offsets_m": [
            walk[s]["offset_removed_ned_m"][2] for s in ("smoothed", "forward")
        ],
        "walk_forward_share_percent": 100 * walk["forward"]["share"],
    }


def render(record: dict[str, Any]) -> str:
    """The block the page shows, from the record."""
    figures = record["figures"]
    return (
        f"{BEGIN}\n\n**drive_0708**, loose, 4 Hz RTK, the published filter's outage "
        f"windows:\n\n{drive_table(figures['drive'])}\n\nThe 15 s outages one by one:\n\n"
        f"{each_outage_table(figures['drive'])}\n\n"
        f"**walk_0827**, tight with "
        f"Doppler, four satellites, fixed truth epochs, by accuracy and by precision:\n\n"
        f"{walk_table(figures['walk'])}\n\n**walk_0827** "
        f"with satellites withheld in two 30 s windows ({WALK_WINDOWS_S[0][0]:g}-"
        f"{sum(WALK_WINDOWS_S[0]):g} s and {WALK_WINDOWS_S[1][0]:g}-{sum(WALK_WINDOWS_S[1]):g} "
        f"s after the start), scored by precision:\n\n"
        f"{withheld_table(figures['withheld'])}\n\n{END}"
    )


def measure(args: argparse.Namespace) -> dict[str, Any]:
    """Every table's figures and the figures the sentences draw from them."""
    figures = {
        "drive": drive_figures(args.data_root),
        "walk": walk_figures(args.data_root),
        "withheld": withheld_figures(args.data_root),
    }
    figures["derived"] = derived(figures)
    return figures


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--data-root", default=None, help="folder holding real-imu-gnss/")
    page = ROOT / "docs" / "results" / "against-rtk.md"
    record_block_script(parser, "against_rtk", page, (BEGIN, END), measure, render)


if __name__ == "__main__":
    main()
