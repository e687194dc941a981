"""The HTML report of a ``navigate`` run: the track in local east/north
metres, the errors against the truth with the filter's 3sigma bounds, the
statistics while aided and in each outage, and every reset the filter made."""

from __future__ import annotations

from pathlib import Path

import numpy as np

from memsnav.plots import plot_errors, plot_track
from memsnav.realdata.result import LogNavigationResult
from memsnav.report.document import Report


def write_report(result: LogNavigationResult, out: Path) -> Path:
    """Writes ``report.html`` (figures embedded) and ``figures/`` (PNG, SVG,
    CSV of the curves) into ``out`` with the shared report helper."""
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    name = result.config[""]["name"]
    s = result.summary
    run = result.run
    t0 = s["start_gps_time_s"]
    origin = np.asarray(run.position_ecef)[0]
    doc = Report(f"memsnav navigate: {name}")
    counts = s["measurements"]
    excluded = sum(c.get("excluded", 0) for c in counts.values())
    gated = sum(c.get("gate", 0) for c in counts.values())
    doc.paragraph(
        f"{s['mode']} coupling, {s['start']['kind']} start, {s['duration_s']:.1f} s, "
        f"{s['imu_samples']} IMU samples, {s['gnss_epochs_used']} GNSS epochs used; "
        f"{gated} scalar measurements in failed batches, {excluded} excluded, "
        f"{len(s['resets'])} resets; processing {s['processing_s']:.1f} s (engine "
        f"{s['filter_run_s']:.2f} s). Configuration: {result.config.path}."
    )
    integrity = s["integrity"]
    if integrity["diverged"]:
        doc.paragraph(
            "INTEGRITY: THE SOLUTION IS NOT TRUSTWORTHY. "
            + " ".join(a["message"] for a in integrity["alerts"])
        )
    else:
        ratios = ", ".join(
            f"{c['kind']} {c['max_band_ratio']:.2f}" for c in integrity["consistency"]
        )
        doc.paragraph(
            "Integrity: no alert. Largest summed NIS of a 30 s window over the upper edge of "
            f"its chi-square band (0.9999), per GNSS kind: {ratios or 'no GNSS batch'} (above "
            "1: the innovations exceed their predicted spread, a tuning mismatch; above 4 "
            "twice in a row: an alert; docs/few-satellites.md)."
        )
    fig, ax = plt.subplots(figsize=(7, 6))
    if result.truth is not None:
        plot_track(
            result.truth["position_ecef"],
            origin_ecef=origin,
            ax=ax,
            fmt="k-",
            lw=2.5,
            alpha=0.35,
            label="truth (RTK)",
        )
    gnss = run.gnss
    used = np.asarray(gnss["used"]) & np.all(np.isfinite(gnss["position_ecef"]), axis=1)
    if used.any():
        plot_track(
            np.asarray(gnss["position_ecef"])[used],
            origin_ecef=origin,
            ax=ax,
            fmt=".",
            ms=2,
            color="tab:orange",
            label="GNSS input",
        )
    # The solution drawn at 10 Hz: the track figure's SVG and CSV stay small.
    plot_track(
        run,
        origin_ecef=origin,
        rate_hz=10.0,
        outages=run.outages,
        ax=ax,
        lw=1,
        color="tab:blue",
        label="memsnav",
    )
    ax.legend()
    doc.section("Track")
    doc.figure("track", fig, "East/north metres from the start; red: scheduled GNSS outages.")
    plt.close(fig)

    if result.truth is not None:
        # A truth scored by precision: each solution's errors less its own
        # mean offset (the raw ones are dominated by the truth's offset).
        precision = result.precision or {}
        tr = precision.get("forward", result.truth)
        smoothed = precision.get("smoothed", result.truth_smoothed)
        spp = precision.get("spp", result.spp)
        axes = plot_errors(
            tr["time"],
            tr["error_ned"],
            tr["std_ned"],
            t0=t0,
            label="memsnav (forward) - truth",
            outages=run.outages,
            standstills=run.standstills,
        )
        fig = axes[0].figure
        for j in range(3):
            if smoothed is not None:
                axes[j].plot(
                    np.asarray(smoothed["time"]) - t0,
                    smoothed["error_ned"][:, j],
                    lw=0.8,
                    color="tab:green",
                    label="smoothed - truth",
                )
            if spp is not None:
                axes[j].plot(
                    np.asarray(spp["time"]) - t0,
                    spp["error_ned"][:, j],
                    ".",
                    ms=2,
                    color="tab:gray",
                    label="SPP - truth",
                )
        axes[0].legend(loc="upper right", fontsize=8)
        doc.section("Errors against the truth")
        doc.figure(
            "errors",
            fig,
            "Position error of the solution at the antenna against the RTK solution (the "
            "smoothed one too when asked for)"
            + (
                ", each less its own mean offset while aided (the truth is scored by "
                "precision: [truth] score)"
                if precision
                else ""
            )
            + ", with the forward filter's 3-sigma bounds; shaded red: scheduled GNSS "
            "outages; green: standstills (zero-velocity and zero-rate updates).",
        )
        plt.close(fig)
        rows: list[list[object]] = []
        errors = s["errors_vs_truth"]
        for key, st in errors.items():
            if key == "by_outage_length_s" or st.get("epochs", 0) == 0:
                continue
            rows.append(_row(key, st))
        for length, st in errors["by_outage_length_s"].items():
            if st.get("epochs", 0):
                rows.append(_row(f"all {length} s outages", st))
        for key, st in s.get("errors_vs_truth_smoothed", {}).items():
            if key == "by_outage_length_s" or st.get("epochs", 0) == 0:
                continue
            rows.append(_row(f"{key} (smoothed)", st))
        for length, st in (
            s.get("errors_vs_truth_smoothed", {}).get("by_outage_length_s", {}).items()
        ):
            if st.get("epochs", 0):
                rows.append(_row(f"all {length} s outages (smoothed)", st))
        if "spp_errors_vs_truth" in s and s["spp_errors_vs_truth"].get("epochs"):
            rows.append(_row("SPP (pseudorange only)", s["spp_errors_vs_truth"]))
        for solution in ("", "_smoothed"):
            st = s.get(f"errors_vs_truth{solution}_precision")
            if st:
                label = solution.replace("_", " ") + " (less its mean offset)"
                rows += [
                    _row(f"{key}{label}", st[key])
                    for key in ("aided", "in_outages")
                    if st[key]["epochs"]
                ]
        if s.get("spp_errors_vs_truth_precision", {}).get("epochs"):
            rows.append(_row("SPP (less its mean offset)", s["spp_errors_vs_truth_precision"]))
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
    doc.section("Resets")
    if s["resets"]:
        doc.table(
            ["time [s]", "kind", "change", "failed epochs before"],
            [[r["time_s"], r["kind"], r["change"], r["failed_epochs"]] for r in s["resets"]],
        )
    else:
        doc.paragraph("The filter made no reset.")
    return doc.write(out)


def _row(label: str, st: dict[str, float]) -> list[object]:
    return [
        label,
        st["epochs"],
        st["rms_horizontal_m"],
        st["rms_vertical_m"],
        st["max_horizontal_m"],
        st.get("within_3sigma_share", "-"),
    ]
