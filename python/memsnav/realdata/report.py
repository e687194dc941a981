"""The HTML report of a ``navigate`` run: the answer first (the outage
errors with their schedule, the aided errors with their context), the
track in local east/north metres, the errors against the truth with the
filter's 3σ bounds on a scale that shows both, the statistics while aided
and in each outage, and every reset the filter made."""

from __future__ import annotations

import html
from pathlib import Path
from typing import Any

import numpy as np

from memsnav.plots import ERROR_FLOOR_M, plot_error_series, plot_errors, plot_track
from memsnav.realdata.answer import (
    TIME_DIGITS,
    answer_lines,
    by_length_label,
    failure_line,
    outage_label,
    truth_line,
)
from memsnav.realdata.result import LogNavigationResult
from memsnav.realdata.satellites import SATELLITE_KINDS
from memsnav.report.document import Report
from memsnav.report.numbers import number, percent


def write_report(result: LogNavigationResult, out: Path) -> Path:
    """Writes ``report.html`` (figures embedded) and ``figures/`` (PNG, SVG,
    CSV of the curves) into ``out`` with the shared report helper."""
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    name = result.config[""]["name"]
    s = result.summary
    run = result.run
    doc = Report(f"memsnav navigate: {name}")
    if s.get("failure"):
        _failure_section(doc, s, run is not None)
    if run is None:
        return doc.write(out)
    t0 = s["start_gps_time_s"]
    origin = np.asarray(run.position_ecef)[0]
    doc.section("The answer")
    first, *rest = answer_lines(s)
    doc.paragraph(first)
    doc.html("<ul>" + "".join(f"<li>{html.escape(line.strip())}</li>" for line in rest) + "</ul>")
    doc.section("The run")
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
            "twice in a row: an alert; docs/explanation/few-satellites.md)."
        )
    if s.get("satellites"):
        _satellites_section(doc, s)
    fig, ax = plt.subplots(figsize=(7, 6))
    if result.truth is not None:
        plot_track(
            result.truth["position_ecef"],
            origin_ecef=origin,
            ax=ax,
            fmt="k-",
            lw=2.5,
            alpha=0.35,
            label=f"truth ({s['truth']['name']})",
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
    doc.figure(
        "track",
        fig,
        "East/north metres from the start"
        + ("; red: scheduled GNSS outages." if len(run.outages) else "."),
    )
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
        if smoothed is not None:
            plot_error_series(
                axes,
                smoothed["time"],
                smoothed["error_ned"],
                t0=t0,
                lw=0.8,
                color="tab:green",
                label="|smoothed - truth|",
            )
        if spp is not None:
            plot_error_series(
                axes,
                spp["time"],
                spp["error_ned"],
                t0=t0,
                fmt=".",
                ms=2,
                color="tab:gray",
                label="|SPP - truth|",
            )
        axes[0].legend(loc="upper right", fontsize=8, ncol=2)
        doc.section("Errors against the truth")
        shading = [
            text
            for text, present in (
                ("shaded red: scheduled GNSS outages", len(run.outages)),
                ("green: standstills (zero-velocity and zero-rate updates)", len(run.standstills)),
            )
            if present
        ]
        doc.figure(
            "errors",
            fig,
            "Size of the position error at the antenna (the smoothed solution's too when asked "
            f"for) against the truth: {_truth_words(s)}; "
            + (
                "each less its own mean offset while aided (the truth is scored by "
                "precision: [truth] score); "
                if precision
                else ""
            )
            + f"with the forward filter's 3σ bound, log scale (below {ERROR_FLOOR_M * 100:g} "
            "cm drawn at 1 cm)"
            + ("; " + "; ".join(shading) if shading else "")
            + "."
            + (
                " The truth is the filter's own GNSS input: while aided the error is how "
                "closely the filter follows it."
                if s.get("truth_is_gnss_input")
                else ""
            ),
        )
        plt.close(fig)
        rows: list[list[object]] = []
        for suffix, view in (("", ""), ("_smoothed", " (smoothed)")):
            errors = s.get(f"errors_vs_truth{suffix}")
            if errors is None:
                continue
            rows += _statistics_rows(errors, view)
        if s.get("spp_errors_vs_truth", {}).get("epochs"):
            rows.append(_row("single-point fixes (pseudoranges only)", s["spp_errors_vs_truth"]))
        if s.get("gnss_errors_vs_truth", {}).get("epochs") and not s.get("truth_is_gnss_input"):
            rows.append(_row("GNSS fixes alone (the filter's input)", s["gnss_errors_vs_truth"]))
        for suffix, view in (("", ""), ("_smoothed", " smoothed")):
            st = s.get(f"errors_vs_truth{suffix}_precision")
            if st:
                rows += [
                    _row(f"{words}{view}, less its mean offset", st[key])
                    for key, words in (("aided", "aided"), ("in_outages", "in the outages"))
                    if st[key]["epochs"]
                ]
        for key, words in (
            ("spp_errors_vs_truth_precision", "single-point fixes"),
            ("gnss_errors_vs_truth_precision", "GNSS fixes alone"),
        ):
            if s.get(key, {}).get("epochs"):
                rows.append(_row(f"{words}, less their mean offset", s[key]))
        doc.section("Statistics")
        doc.table(
            [
                "segment",
                "epochs",
                "RMS horiz. [m]",
                "RMS vert. [m]",
                "max horiz. [m]",
                "within 3σ",
                "N/E within 3σ",
                "NEES/dof",
            ],
            rows,
        )
        doc.paragraph(
            "Within 3σ: the share of the N, E, D errors inside the filter's own 3σ (N/E: of the "
            "horizontal ones alone); NEES/dof: "
            "the mean of (error / σ)² over the epochs and the N, E, D axes, 1 when the σ's "
            "describe the errors, 0.01 when they are ten times the errors: a share of 1 "
            "with a small NEES is a filter far more cautious than it needs to be."
            + (
                " The truth is the filter's own GNSS input: the aided rows show how closely "
                "the filter follows it, not its accuracy."
                if s.get("truth_is_gnss_input")
                else ""
            )
        )
    doc.section("Resets")
    if s["resets"]:
        doc.table(
            ["time [s]", "kind", "change", "failed epochs before"],
            [
                [
                    number(r["time_s"], TIME_DIGITS),
                    r["kind"].replace("_", " "),
                    _change(r),
                    r["failed_epochs"],
                ]
                for r in s["resets"]
            ],
        )
    else:
        doc.paragraph("The filter made no reset.")
    return doc.write(out)


def _truth_words(s: dict[str, Any]) -> str:
    """The truth's name and how it was moved, for a caption: "insd.csv,
    moved to the antenna by (−2.2, 0, 0) m in its body axes ...", as the
    answer's truth line says it."""
    line = truth_line(s)
    assert line is not None  # a scored run has a truth
    return line.strip().removeprefix("truth: ")


def _failure_section(doc: Report, s: dict[str, Any], ran: bool) -> None:
    """What failed, where, why, what may explain it, and what the rest of
    the report holds."""
    failure = s["failure"]
    doc.section("The run failed")
    doc.paragraph(failure_line(failure))
    for other in failure.get("also", []):
        doc.paragraph("Also " + failure_line(other))
    if failure["hints"]:
        doc.paragraph("What the inputs and the run warned about, which may explain it:")
        doc.html(
            "<ul>" + "".join(f"<li>{html.escape(hint)}</li>" for hint in failure["hints"]) + "</ul>"
        )
    if not ran:
        doc.paragraph(
            "Nothing was computed: the failure came before the engine ran. summary.json holds "
            "the failure and the inputs' warnings."
        )
    elif failure["stage"] == "run":
        doc.paragraph(
            "The rest of this report and the solution files hold the run up to where it "
            "stopped (summary.json: every number of it)."
        )
    elif failure["stage"] in ("units", "integrity"):
        doc.paragraph(
            "The rest of this report, the solution files and summary.json hold the whole run, "
            "which is not trustworthy."
        )
    else:
        doc.paragraph("The rest of this report holds the whole run, less what the failure stopped.")


def _satellites_section(doc: Report, s: dict[str, Any]) -> None:
    """Per system, then per satellite: how many measurements the filter
    used, excluded, rejected and found slipped, with C/N0 and elevation."""
    doc.section("Satellites")
    doc.table(
        [
            "system",
            "satellites used",
            "measurements",
            "used",
            "excluded",
            "rejected",
            "cycle slips",
        ],
        [
            [
                name,
                t["satellites"],
                t["measurements"],
                t["used"],
                f"{t['excluded']} ({percent(t['excluded_share'], 2)})",
                f"{t['rejected']} ({percent(t['rejected_share'], 2)})",
                t["slips"],
            ]
            for name, t in s["satellite_systems"].items()
        ],
    )
    doc.table(
        [
            "satellite",
            "system",
            "signal",
            "epochs",
            "mean C/N0 [dB-Hz]",
            "mean elevation [°]",
            "used",
            "excluded",
            "rejected",
            "cycle slips",
        ],
        [
            [
                r["satellite"],
                r["system"],
                r["signal"] or "—",
                r["epochs"],
                number(r["mean_cn0_db_hz"]),
                number(r["mean_elevation_deg"], 2),
                r["used"],
                r["excluded"],
                r["rejected"],
                r["slips"],
            ]
            for r in s["satellites"]
        ],
    )
    kinds = ", ".join(kind.replace("_", " ") + "s" for kind in SATELLITE_KINDS)
    doc.paragraph(
        f"Counts are scalar measurements ({kinds}) as the filter recorded them: used; "
        "excluded (left out of their epoch's batch by fault exclusion, the rest applied); "
        "rejected (their batch failed the chi-square gate or reset the filter, or an invalid "
        "value); cycle slips "
        "(a carrier-phase change the slip tests refused). Epochs: those with a measurement "
        "of the satellite in the filter; C/N0 (of the signal the pseudorange was taken "
        "from) and elevation (at the receiver's approximate position) are means over them."
    )


def _change(reset: dict[str, Any]) -> str:
    """How much a reset moved the state, with its unit (a heading also in
    degrees)."""
    value, unit = reset["change"], reset["unit"]
    if unit == "rad":
        return f"{number(value)} rad ({number(np.degrees(value))}°)"
    return f"{number(value)} {unit}" if unit else f"× {number(value)}"


def _statistics_rows(errors: dict[str, Any], view: str) -> list[list[object]]:
    """Every epoch, aided, in the outages, each outage (those at a
    standstill marked) and each outage length (over the outages in
    motion)."""
    rows = [
        _row(f"{words}{view}", errors[key])
        for key, words in (
            ("all", "every epoch"),
            ("aided", "aided"),
            ("in_outages", "in the outages"),
        )
        if errors[key]["epochs"]
    ]
    for key, st in errors.items():
        if key.startswith("outage_") and st["epochs"]:
            still = (
                f", at a standstill {number(st['standstill_s'], 2)} s: left out of its length"
                if st.get("at_standstill")
                else ""
            )
            rows.append(_row(f"{outage_label(key, st)}{view}{still}", st))
    for length, st in errors["by_outage_length_s"].items():
        if st["epochs"]:
            rows.append(_row(f"{by_length_label(length, errors)}{view}", st))
    return rows


def _row(label: str, st: dict[str, Any]) -> list[object]:
    return [
        label,
        st["epochs"],
        number(st["rms_horizontal_m"]),
        number(st["rms_vertical_m"]),
        number(st["max_horizontal_m"]),
        percent(st.get("within_3sigma_share"), 1),
        percent(st.get("within_3sigma_share_horizontal"), 1),
        number(st.get("nees_per_dof"), 2),
    ]
