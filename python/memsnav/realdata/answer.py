"""The answer of a ``navigate`` run in a few lines, for the terminal and
the top of its report: the truth it is scored against as the user named
it, the errors through the scheduled GNSS outages (what a drive with
outages is run for) with their schedule, then the errors while aided with
what they can mean. A truth that is the filter's own GNSS
input scores only how closely the filter follows that input, and the
lines say so where the number is; an outage spent at a standstill tests
the zero-velocity updates, not the coast, and is named and left out of
its length's figures (the core's score)."""

from __future__ import annotations

import itertools
from typing import Any

from memsnav.report.numbers import number, percent

TIME_DIGITS = 5
"""Significant digits of a time in seconds from the start (530.5 s, not 530)."""


def schedule(outages_s: list[list[float]]) -> str:
    """The outage windows ((start, length) s after the earliest start the
    log allows) in words:
    "12 GNSS outages of 15 s every 45 s from 35.5 s" for a periodic
    schedule, else each window."""
    if not outages_s:
        return "no GNSS outage scheduled"
    starts = [start for start, _ in outages_s]
    lengths = {round(length, 6) for _, length in outages_s}
    steps = {round(b - a, 6) for a, b in itertools.pairwise(starts)}
    count = len(outages_s)
    plural = "s" if count > 1 else ""
    if len(lengths) == 1 and len(steps) <= 1:
        every = f" every {number(steps.pop(), TIME_DIGITS)} s" if steps else ""
        return (
            f"{count} GNSS outage{plural} of {number(outages_s[0][1], TIME_DIGITS)} s{every} "
            f"from {number(starts[0], TIME_DIGITS)} s"
        )
    windows = ", ".join(
        f"{number(a, TIME_DIGITS)}-{number(a + length, TIME_DIGITS)} s" for a, length in outages_s
    )
    return f"{count} GNSS outages: {windows}"


def _errors(stats: dict[str, Any]) -> str:
    """Horizontal RMS and max, vertical RMS, and how the filter's σ's
    describe them: the share within 3σ and the NEES per degree of freedom
    (a share of 1 with a NEES of 0.01 is bounds ten times the errors), the
    horizontal errors' share apart (loose vertical bounds would flatter the
    horizontal ones)."""
    text = (
        f"horizontal RMS {number(stats['rms_horizontal_m'])} m, max "
        f"{number(stats['max_horizontal_m'])} m, vertical RMS {number(stats['rms_vertical_m'])} m"
    )
    if "within_3sigma_share" in stats:
        text += (
            f"; {percent(stats['within_3sigma_share'], 1)} within 3σ "
            f"(N/E {percent(stats['within_3sigma_share_horizontal'], 1)}), NEES/dof "
            f"{number(stats['nees_per_dof'], 2)}"
        )
    return text


def outage_label(key: str, stats: dict[str, Any]) -> str:
    """``outage_7`` as "outage 7 (305.5 s)"."""
    return f"outage {key.removeprefix('outage_')} ({number(stats['start_s'], TIME_DIGITS)} s)"


def standstill_outages(scores: dict[str, Any]) -> list[str]:
    """The outages spent mostly at a standstill, with how long, in words."""
    return [
        f"{outage_label(key, st)}: at a standstill {number(st['standstill_s'], 2)} s of its "
        f"{number(st['length_s'], TIME_DIGITS)} s"
        for key, st in scores.items()
        if key.startswith("outage_") and st.get("at_standstill")
    ]


def _outages(count: int) -> str:
    return f"{count} outage{'s' if count != 1 else ''}"


def by_length_label(length: str, scores: dict[str, Any]) -> str:
    """ "the 11 outages of 15 s in motion (of 12)" for the statistics of
    one outage length: how many of its windows they score, which leave out
    the outages at a standstill and those without a truth epoch."""
    windows = [
        st
        for key, st in scores.items()
        if key.startswith("outage_") and f"{st['length_s']:g}" == length
    ]
    moving = [st for st in windows if not st.get("at_standstill")]
    scored = sum(st["epochs"] > 0 for st in moving)
    if scored == len(windows):
        return f"the {_outages(scored)} of {length} s"
    if scored == len(moving):
        return f"the {_outages(scored)} of {length} s in motion (of {len(windows)})"
    return f"the {_outages(scored)} of {length} s scored (of {len(windows)})"


def unscored_outages(scores: dict[str, Any]) -> list[str]:
    """The outages in motion that no truth epoch falls in (the truth has a
    gap there, or none of its epochs has the quality asked for), in words:
    named, not scored silently."""
    return [
        f"{outage_label(key, st)}: no truth epoch in it, not scored"
        for key, st in scores.items()
        if key.startswith("outage_") and not st.get("at_standstill") and st["epochs"] == 0
    ]


def satellites_line(systems: dict[str, dict[str, Any]]) -> str:
    """The satellites each system had in use and the share of its
    measurements excluded (rejected and cycle slips when there are any),
    from the summary's ``satellite_systems``."""
    used = ", ".join(f"{name} {t['satellites']}" for name, t in systems.items())
    total = sum(t["satellites"] for t in systems.values())
    text = f"satellites used: {used} ({total}); measurements excluded: " + ", ".join(
        f"{name} {percent(t['excluded_share'], 2)}" for name, t in systems.items()
    )
    if any(t["rejected"] for t in systems.values()):
        text += "; rejected: " + ", ".join(
            f"{name} {percent(t['rejected_share'], 2)}" for name, t in systems.items()
        )
    slips = sum(t["slips"] for t in systems.values())
    return text + (f"; {slips} cycle slips" if slips else "")


def _metres(values: list[float]) -> str:
    """[−2.2, 0, 0] as "(−2.2, 0, 0) m"."""
    return "(" + ", ".join(number(v) for v in values) + ") m"


def truth_line(summary: dict[str, Any]) -> str | None:
    """What the run is scored against, as the configuration names it
    (``[truth] name``, else its file), and how it was moved: to the antenna
    by its lever arm, into the GNSS's datum by a constant offset (given, or
    the mean of GNSS − truth over the run's GNSS epochs). None without a
    truth."""
    truth = summary.get("truth")
    if truth is None:
        return None
    moves = []
    if any(truth["lever_arm_m"]):
        moves.append(
            f"moved to the antenna by {_metres(truth['lever_arm_m'])} in its body axes "
            "(forward, right, down)"
        )
    offset = truth["datum_offset"]
    if offset["source"] != "none":
        north, east, down = offset["ned_m"]
        how = (
            f"the mean of GNSS − truth over {offset['gnss_epochs']} GNSS epochs"
            if offset["source"] == "from_gnss"
            else "as given"
        )
        moves.append(
            f"into the GNSS's datum by N {number(north)}, E {number(east)}, D {number(down)} m "
            f"({how})"
        )
    return f"  truth: {truth['name']}" + (f", {'; '.join(moves)}" if moves else "")


def failure_line(failure: dict[str, Any]) -> str:
    """A failure entry of the summary in one line: what failed, where in
    the run (the stage; the time after the start when it has one), why."""
    when = (
        f", {number(failure['time_s'], TIME_DIGITS)} s after the start"
        if failure.get("time_s") is not None
        else ""
    )
    return f"FAILED ({failure['stage']}{when}): {failure['what']}: {failure['message']}"


def answer_lines(summary: dict[str, Any]) -> list[str]:
    """What the run found, first: a failure, the schedule, the satellites
    in use (tight coupling), the outage errors per length, the outages at a
    standstill, the aided errors with their context. Without a truth only
    the schedule, the satellites and the run; a run that failed before the
    engine ran, only the failure."""
    failure = summary.get("failure")
    if "duration_s" not in summary:
        assert failure is not None  # a summary without a run is a failed one's
        return [f"{summary['name']}: {summary['mode']} coupling; " + failure_line(failure)]
    lines = [
        f"{summary['name']}: {summary['mode']} coupling, {summary['duration_s']:.0f} s; "
        + schedule(summary["outages_s"])
    ]
    if failure is not None:
        lines.append("  " + failure_line(failure))
    if summary.get("satellite_systems"):
        lines.append("  " + satellites_line(summary["satellite_systems"]))
    if summary.get("integrity", {}).get("diverged"):
        lines.append("  INTEGRITY ALERT: the solution is not trustworthy (report: Integrity)")
    raw = summary.get("errors_vs_truth")
    if raw is None:
        return [*lines, "  no truth configured: no errors to show"]
    truth = truth_line(summary)
    if truth:
        lines.append(truth)
    precise = summary.get("errors_vs_truth_precision")
    # The configured score: by precision the outage errors are the drift
    # from the solution's own offset, which is what a precision truth knows.
    scores = precise or raw
    scored = " (by precision)" if precise else ""
    for view, errors in (("", scores), ("smoothed, ", summary.get("errors_vs_truth_smoothed"))):
        if errors is None:
            continue
        for length, st in errors["by_outage_length_s"].items():
            label = by_length_label(length, errors)
            if st["epochs"]:
                lines.append(f"  {view}{label}{scored}: {_errors(st)}")
            else:
                lines.append(f"  {view}{label}: no errors to show")
    for text in standstill_outages(scores):
        lines.append(f"  {text}: left out (the zero-velocity updates hold it still)")
    for text in unscored_outages(scores):
        lines.append(f"  {text}")
    aided = raw["aided"]
    if aided["epochs"]:
        lines.append(f"  aided: {_errors(aided)}")
    fixes = summary.get("gnss_errors_vs_truth", {})
    if fixes.get("epochs") and not summary.get("truth_is_gnss_input"):
        lines.append(
            f"  the GNSS fixes alone (the filter's input, {fixes['epochs']} epochs): horizontal "
            f"RMS {number(fixes['rms_horizontal_m'])} m, max {number(fixes['max_horizontal_m'])} "
            f"m, vertical RMS {number(fixes['rms_vertical_m'])} m"
        )
    if precise and precise["aided"]["epochs"]:
        north, east, down = precise["offset_removed_ned_m"]
        spp = summary.get("spp_errors_vs_truth_precision", {})
        lines.append(
            f"  aided, less its mean offset (N {number(north)}, E {number(east)}, D "
            f'{number(down)} m; [truth] score = "precision"): horizontal RMS '
            f"{number(precise['aided']['rms_horizontal_m'])} m, vertical "
            f"{number(precise['aided']['rms_vertical_m'])} m"
            + (
                f"; single-point fixes {number(spp['rms_horizontal_m'])} m horizontal"
                if spp.get("epochs")
                else ""
            )
        )
    if summary.get("truth_is_gnss_input"):
        lines.append(
            "  the truth is the filter's own GNSS input (truth.pos is gnss.pos): the aided "
            "error shows how closely the filter follows it, not its accuracy; the outages "
            "are the test"
        )
    return lines
