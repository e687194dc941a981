"""The HTML report of a ``navigate`` run: the track on a map-like
east/north plot, the errors against the truth with the filter's 3sigma bounds,
and the statistics while aided and in each outage."""

from __future__ import annotations

from pathlib import Path
from typing import TYPE_CHECKING

import numpy as np

from memsnav.report.document import Report

if TYPE_CHECKING:
    from memsnav.realdata.pipeline import NavigationResult

_EARTH_RADIUS_M = 6_378_137.0


def _east_north(lla: np.ndarray, origin: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """Local east/north metres about ``origin`` (equirectangular: exact to
    well under a centimetre over a few km)."""
    east = (lla[:, 1] - origin[1]) * np.cos(origin[0]) * (_EARTH_RADIUS_M + origin[2])
    north = (lla[:, 0] - origin[0]) * (_EARTH_RADIUS_M + origin[2])
    return east, north


def write_report(result: NavigationResult, out: Path) -> Path:
    """Writes ``report.html`` (figures embedded) and ``figures/`` (PNG, SVG,
    CSV of the curves) into ``out`` with the shared report helper."""
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    name = result.config[""]["name"]
    s = result.summary
    origin = result.lla[0]
    t = result.time - s["start_gps_time_s"]
    doc = Report(f"memsnav navigate: {name}")
    doc.paragraph(
        f"{s['mode']} coupling, {s['duration_s']:.1f} s, {s['imu_samples']} IMU samples, "
        f"{s['gnss_epochs_used']} GNSS epochs used ({s['measurements_gated']} scalar "
        f"measurements gated); processing {s['processing_s']:.1f} s (filter "
        f"{s['filter_run_s']:.2f} s). Configuration: {result.config.path}."
    )
    # The solution drawn at 10 Hz: the track figure's SVG and CSV stay small.
    step = max(1, round(0.1 / max(np.median(np.diff(t)), 1e-6)))
    fig, ax = plt.subplots(figsize=(7, 6))
    if result.truth is not None:
        e, n = _east_north(result.truth["lla"], origin)
        ax.plot(e, n, "k-", lw=2.5, alpha=0.35, label="truth (RTK)")
    if len(result.gnss_lla):
        e, n = _east_north(result.gnss_lla, origin)
        ax.plot(e, n, ".", ms=2, color="tab:orange", label="GNSS input")
    e, n = _east_north(result.lla[::step], origin)
    ax.plot(e, n, "-", lw=1, color="tab:blue", label="memsnav")
    for i, (st, d) in enumerate(result.outages):
        m = (t[::step] >= st) & (t[::step] < st + d)
        ax.plot(e[m], n[m], "-", lw=2, color="tab:red", label="outages" if i == 0 else None)
    ax.set_xlabel("east [m]")
    ax.set_ylabel("north [m]")
    ax.set_aspect("equal", adjustable="datalim")
    ax.legend()
    ax.grid(alpha=0.3)
    doc.section("Track")
    doc.figure("track", fig, "East/north metres from the start; red: scheduled GNSS outages.")
    plt.close(fig)

    if result.truth is not None:
        tr = result.truth
        fig, axes = plt.subplots(3, 1, figsize=(9, 7), sharex=True)
        for j, label in enumerate(("north", "east", "down")):
            a = axes[j]
            a.plot(tr["time"], tr["error_ned"][:, j], lw=0.8, label="memsnav - truth")
            a.plot(tr["time"], 3 * tr["std_ned"][:, j], "r--", lw=0.8, label=r"$\pm 3\sigma$")
            a.plot(tr["time"], -3 * tr["std_ned"][:, j], "r--", lw=0.8)
            if result.spp is not None:
                a.plot(
                    result.spp["time"],
                    result.spp["error_ned"][:, j],
                    ".",
                    ms=2,
                    color="tab:gray",
                    label="SPP - truth",
                )
            for st, d in result.outages:
                a.axvspan(st, st + d, color="tab:red", alpha=0.1)
            a.set_ylabel(f"{label} [m]")
            a.grid(alpha=0.3)
        axes[0].legend(loc="upper right", fontsize=8)
        axes[-1].set_xlabel("time since alignment [s]")
        doc.section("Errors against the truth")
        doc.figure(
            "errors",
            fig,
            "Position error of the solution at the antenna against the RTK solution, with "
            "the filter's 3-sigma bounds; shaded: scheduled GNSS outages.",
        )
        plt.close(fig)
        rows: list[list[object]] = []
        for key, st in s["errors_vs_truth"].items():
            if st.get("epochs", 0) == 0:
                continue
            rows.append(
                [
                    key,
                    st["epochs"],
                    st["rms_horizontal_m"],
                    st["rms_vertical_m"],
                    st["max_horizontal_m"],
                    st["within_3sigma_share"],
                ]
            )
        if "spp_errors_vs_truth" in s:
            st = s["spp_errors_vs_truth"]
            rows.append(
                [
                    "SPP (pseudorange only)",
                    st["epochs"],
                    st["rms_horizontal_m"],
                    st["rms_vertical_m"],
                    st["max_horizontal_m"],
                    "-",
                ]
            )
        doc.section("Statistics")
        doc.table(
            [
                "segment",
                "epochs",
                "RMS horiz. [m]",
                "RMS vert. [m]",
                "max horiz. [m]",
                "share within 3 sigma",
            ],
            rows,
        )
    return doc.write(out)
