"""The HTML report of a ``calibrate`` run: the session with its poses, the
gravity-magnitude and gravity-direction errors of every pose and turn
before and after, and the parameters with σ and the Cramér-Rao bound."""

from __future__ import annotations

import html
from pathlib import Path

import numpy as np

from memsnav._memsnav import StaticCalibration
from memsnav.calibration.drive import DriveCalibration, parameter_index
from memsnav.calibration.run import CalibrationRun
from memsnav.report.document import Report
from memsnav.report.numbers import number

# Misalignments the gravity magnitude cannot see: they define the body frame.
_FRAME = {
    "accelerometer misalignment_uv",
    "accelerometer misalignment_uw",
    "accelerometer misalignment_vw",
}


def _rms_text(value: float | None, scale: float, unit: str) -> str:
    return "—" if value is None else f"{number(value * scale)} {unit}"


def write_report(run: CalibrationRun, out: Path) -> Path:
    """Writes ``report.html`` (figures embedded) and ``figures/`` into ``out``."""
    import matplotlib

    matplotlib.use("Agg")
    if isinstance(run.calibration, DriveCalibration):
        return _drive_report(run, run.calibration, out)
    return _static_report(run, run.calibration, out)


def _static_report(run: CalibrationRun, cal: StaticCalibration, out: Path) -> Path:
    import matplotlib.pyplot as plt

    cfg, s = run.config, run.summary
    poses = np.asarray(cal.poses)
    pose_out = np.asarray(cal.pose_held_out, dtype=bool)
    turn_out = np.asarray(cal.turn_held_out, dtype=bool)
    t = run.time - run.time[0]
    doc = Report(f"memsnav calibrate: {cfg['']['name']}")
    doc.paragraph(
        f"Static-pose (multi-position) calibration, {s['poses']} poses "
        f"({s['poses_held_out']} held out of the fit) and {s['turns']} turns between them, "
        f"{len(t)} samples over {t[-1]:.1f} s; local gravity {cal.gravity} m/s². "
        f"Processing {s['processing_s']:.2f} s. Configuration: {cfg.path}. "
        "Method: docs/explanation/calibration.md (Tedaldi et al., ICRA 2014, in the models of "
        "method §2)."
    )

    doc.section("Figures of merit")
    rows: list[list[object]] = []
    for label, key, scale, unit in (
        ("‖f‖ − g over the poses, RMS", "magnitude", 1e3, "mm/s²"),
        ("gravity direction after a turn, RMS", "turn", 1.0, "°"),
    ):
        suffix = "m_s2" if key == "magnitude" else "deg"
        for subset in ("fit", "held_out"):
            rows.append(
                [
                    f"{label} ({'in the fit' if subset == 'fit' else 'held out'})",
                    _rms_text(s[f"{key}_rms_before_{subset}_{suffix}"], scale, unit),
                    _rms_text(s[f"{key}_rms_after_{subset}_{suffix}"], scale, unit),
                ]
            )
    doc.table(["", "nominal readings", "calibrated"], rows)
    doc.paragraph(
        "Nominal readings: scale × (raw − offset) with the configuration's nominal values, "
        f"no bias or offset estimated. Held-out poses ({_holdout_text(cfg['static'])}) and the "
        "turns into and out of them never enter the fit."
    )
    _model_selection(doc, cal, s["model"])

    # 1. The session.
    nominal_accel = np.asarray(cal.nominal["accel_scale"]) * (
        run.accel - np.asarray(cal.nominal["accel_offset"])
    )
    magnitude = np.linalg.norm(nominal_accel, axis=1)
    step = max(1, len(t) // 5000)
    fig, axes = plt.subplots(2, 1, figsize=(10, 6), sharex=True)
    axes[0].plot(t[::step], magnitude[::step], lw=0.6, color="k", label="‖nominal specific force‖")
    for k, (a, b) in enumerate(poses):
        colour = "tab:orange" if pose_out[k] else "tab:green"
        axes[0].axvspan(t[a], t[b - 1], color=colour, alpha=0.25, lw=0)
    axes[0].axhline(cal.gravity, color="tab:blue", lw=0.8, ls="--", label="local gravity")
    axes[0].set_ylabel("m/s²")
    axes[0].set_title("session: poses in the fit (green) and held out (orange)")
    axes[0].legend(loc="upper right")
    ratio = np.asarray(cal.variance_magnitude) / np.asarray(cal.detector_threshold)
    for j, name in enumerate(("accelerometer", "gyroscope")):
        axes[1].semilogy(t[::step], ratio[::step, j], lw=0.6, label=name)
    axes[1].axhline(1.0, color="k", lw=0.8, ls="--", label="threshold")
    axes[1].set_ylabel("variance / threshold")
    axes[1].set_xlabel("time since start [s]")
    axes[1].set_title("static-interval detector: static where both are below 1")
    axes[1].legend(loc="upper right")
    doc.section("The session")
    doc.figure(
        "session",
        fig,
        "Top: magnitude of the nominal accelerometer readings with the detected poses. Bottom: "
        "the detector's variance magnitudes over a sliding window, divided by their thresholds.",
    )

    # 2. Poses and turns, before and after.
    index = np.arange(len(poses))
    fig, axes = plt.subplots(2, 2, figsize=(11, 6.5))
    for col, when in enumerate(("before", "after")):
        a = axes[0, col]
        v = np.asarray(getattr(cal, f"magnitude_error_{when}")) * 1e3
        a.plot(index[~pose_out], v[~pose_out], "o", color="tab:green", label="in the fit")
        a.plot(index[pose_out], v[pose_out], "s", color="tab:orange", label="held out")
        a.axhline(0.0, color="k", lw=0.6)
        a.set_title(f"‖f‖ − g per pose, {'nominal' if when == 'before' else 'calibrated'}")
        a.set_xlabel("pose")
        a.set_ylabel("mm/s²")
        a.legend()
    turns = np.asarray(cal.turn_from)
    for col, when in enumerate(("before", "after")):
        a = axes[1, col]
        v = np.degrees(np.asarray(getattr(cal, f"turn_error_{when}")))
        a.semilogy(turns[~turn_out], v[~turn_out], "o", color="tab:green", label="in the fit")
        a.semilogy(turns[turn_out], v[turn_out], "s", color="tab:orange", label="held out")
        a.set_title(
            f"gravity direction after each turn, {'nominal' if when == 'before' else 'calibrated'}"
        )
        a.set_xlabel("turn (from pose)")
        a.set_ylabel("degrees")
        a.legend()
    fig.tight_layout()
    doc.section("Residuals before and after")
    doc.figure(
        "residuals",
        fig,
        "Top: the specific-force magnitude of every pose minus local gravity. Bottom: the angle "
        "between the gravity direction carried through each turn by the gyroscope and the one "
        "the accelerometer measures in the next pose.",
    )
    plt.close("all")

    # 3. Parameters.
    doc.section("Parameters")
    names = list(cal.parameter_names)
    value = np.asarray(cal.parameters)
    sigma = np.sqrt(np.clip(np.diag(cal.covariance), 0.0, None))
    bound = np.sqrt(np.clip(np.diag(cal.crb), 0.0, None))
    held = dict(cal.held)
    parameter_rows: list[list[object]] = []
    for k, name in enumerate(names):
        if name in _FRAME:
            status = "0 by the frame convention (body x = u, y in the u-v plane)"
        elif name in held:
            status = f"held: {held[name]}"
        else:
            status = "estimated"
        parameter_rows.append(
            [
                name,
                number(value[k], 6),
                f"{sigma[k]:.3g}" if sigma[k] > 0 else "—",
                f"{bound[k]:.3g}" if bound[k] > 0 else "—",
                f"{sigma[k] / bound[k]:.2f}" if bound[k] > 0 else "—",
                status,
            ]
        )
    doc.table(["parameter (SI)", "value", "σ", "CRB σ", "σ / CRB", "status"], parameter_rows)
    white = np.sqrt(np.asarray(cal.white_noise_variance))
    doc.paragraph(
        "Models of the nominal readings (method §2): S = (I − D − M)(Γ − b − N Γ²) and "
        "S = (I − D − M)(Ω − b − K Γ). σ from the residuals of each stage, propagated through "
        "the later stages; CRB σ: the Cramér-Rao bound for white noise of the level measured "
        f"at the initial rest (accelerometer {white[0].mean():.3g} m/s², gyroscope "
        f"{white[1].mean():.3g} rad/s per sample). σ well above the bound means errors that "
        "are not white: hand tremor, settling, bias drift, the Earth's rate at rest."
    )
    _warnings(
        doc, cal.warnings, "None: every parameter is determined well below its physical size."
    )
    return doc.write(out)


def _holdout_text(static: dict[str, object]) -> str:
    rules = []
    if static["holdout_every"]:
        rules.append(f"every {static['holdout_every']}-th")
    if "holdout_from_s" in static:
        rules.append(f"every one ending at or after {static['holdout_from_s']:g} s")
    return " and ".join(rules) or "none"


def _model_selection(doc: Report, cal: StaticCalibration, chosen: dict[str, list[str]]) -> None:
    """The candidates of each stage's choice of second-order terms (AICc)."""
    if not cal.model_selection:
        return
    doc.section("Model selection")
    doc.paragraph(
        "Chosen: "
        + "; ".join(f"{stage}: {', '.join(terms) or 'none'}" for stage, terms in chosen.items())
        + ". Each stage fits every combination of its second-order terms that the poses "
        "determine and keeps the one of smallest AICc = n ln(RSS/n) + 2K + 2K(K + 1)/(n − K − 1) "
        "(K: parameters plus the residual variance; Hurvich and Tsai 1989), an estimate of the "
        "error on poses the fit has not seen (docs/how-to/calibrate-an-imu.md)."
    )
    for selection in cal.model_selection:
        best = selection["candidates"][selection["chosen"]]["aicc"]
        rows: list[list[object]] = []
        for k, c in enumerate(selection["candidates"]):
            if k == selection["chosen"]:
                status = "chosen"
            elif c["aicc"] is None:
                status = f"refused: {c['refused']}"
            else:
                status = f"ΔAICc {c['aicc'] - best:+.1f}"
            rows.append(
                [
                    ", ".join(c["terms"]) or "none",
                    c["parameters"],
                    c["observations"],
                    f"{c['residual_rms']:.3g}",
                    "—" if c["aicc"] is None else f"{c['aicc']:.1f}",
                    status,
                ]
            )
        doc.paragraph(f"{selection['stage']}:")
        doc.table(["terms", "parameters", "residuals", "RMS residual (SI)", "AICc", "status"], rows)


_SUBSETS = (
    ("after_fit", "outages after the calibration span (never seen by the fit)"),
    ("in_fit", "outages inside the calibration span"),
    ("first", "the first outage (the first minutes)"),
    ("all", "every outage"),
)


def _drive_report(run: CalibrationRun, cal: DriveCalibration, out: Path) -> Path:
    import matplotlib.pyplot as plt

    cfg, s = run.config, run.summary
    doc = Report(f"memsnav calibrate: {cfg['']['name']}")
    span = "the whole drive" if cal.until_s is None else f"the first {cal.until_s:g} s"
    doc.paragraph(
        f"GNSS-reference calibration on a drive (method §3): {s['windows']} windows of "
        f"{number(cal.window_s)} s from {span} after the start ({s['skipped_for_resets']} left "
        f"out for filter resets, {s.get('skipped_before_heading', 0)} before the heading was "
        f"known), references from the smoothed navigation of "
        f"{html.escape(str(run.imu_calibration.source.get('navigate_config')))}. Processing "
        f'{s["processing_s"]:.2f} s. Method: docs/how-to/calibrate-an-imu.md, "A drive".'
    )

    comparison = s.get("navigation")
    doc.section("Navigation with and without the calibration")
    if comparison is None:
        doc.paragraph("Not computed ([drive] compare = false, or no truth in the configuration).")
    else:
        rows: list[list[object]] = []
        for view in ("forward", "smoothed"):
            for key, words in _SUBSETS:
                raw, calibrated = comparison["raw"][view][key], comparison["calibrated"][view][key]
                if not raw.get("outages"):
                    continue
                rows.append(
                    [
                        f"{view}: {words}",
                        raw["outages"],
                        f"{raw['rms_horizontal_m']:.2f} / {raw['max_horizontal_m']:.2f}",
                        f"{calibrated['rms_horizontal_m']:.2f} / "
                        f"{calibrated['max_horizontal_m']:.2f}",
                    ]
                )
        doc.table(
            ["horizontal error in GNSS outages", "outages", "raw: RMS / max m", "calibrated"],
            rows,
        )
        draws = comparison.get("draws") or []
        if draws:
            spread = []
            for view in ("forward", "smoothed"):
                rms = [d[view]["after_fit"].get("rms_horizontal_m") for d in draws]
                finite = np.array([r for r in rms if r is not None])
                if finite.size:
                    spread.append(
                        f"{view} {finite.min():.2f}-{finite.max():.2f} m "
                        f"(median {np.median(finite):.2f})"
                    )
            doc.paragraph(
                f"The calibration's uncertainty in navigation terms: the drive navigated with "
                f"{len(draws)} calibrations drawn from its covariance gives, over the outages "
                "after the calibration span, a horizontal RMS of " + "; ".join(spread) + "."
            )
        doc.paragraph(
            "The drive navigated twice with the outages of its navigate configuration: with the "
            "raw readings and with the readings corrected by this calibration (exact inverse of "
            "the models). Only the outages after the calibration span test it honestly: inside "
            "the span the references saw the GNSS the outage removes."
        )

    before, after = cal.residual_before, cal.residual_after
    t = np.asarray(cal.references["time"]) - float(np.asarray(cal.references["time"])[0])
    fig, axes = plt.subplots(2, 3, figsize=(12, 6), sharex=True)
    for j in range(6):
        a = axes[j // 3, j % 3]
        scale, unit = (1.0, "m/s²") if j < 3 else (float(np.degrees(1.0)), "°/s")
        a.plot(t, scale * before[:, j], lw=0.7, color="tab:red", label="raw − reference")
        a.plot(t, scale * after[:, j], lw=0.7, color="tab:green", label="calibrated − reference")
        a.axhline(0.0, color="k", lw=0.5)
        a.set_title(("accelerometer " + "uvw"[j]) if j < 3 else ("gyroscope " + "pqr"[j - 3]))
        a.set_ylabel(unit)
        if j >= 3:
            a.set_xlabel("time since the first window [s]")
    axes[0, 0].legend(loc="upper right")
    fig.tight_layout()
    doc.section("Residuals before and after")
    doc.figure(
        "residuals",
        fig,
        "Window means of the IMU's output minus the GNSS-derived reference, sensor axes: the raw "
        "readings (red) and those predicted by the calibrated model (green).",
    )
    plt.close("all")

    doc.section("Parameters")
    rows = []
    for sensor, fit, cov in (
        ("accelerometer", cal.accelerometer, cal.accelerometer_covariance),
        ("gyroscope", cal.gyroscope, cal.gyroscope_covariance),
    ):
        held = dict(fit.held)
        names = list(fit.parameter_names)
        least_squares = np.sqrt(np.clip(np.diag(np.asarray(fit.covariance)), 0.0, None))
        sigma = np.sqrt(np.clip(np.diag(cov), 0.0, None))
        for k, name in enumerate(names):
            rows.append(
                [
                    f"{sensor} {name}",
                    _value(fit, name),
                    f"{least_squares[k]:.3g}" if least_squares[k] > 0 else "—",
                    f"{sigma[k]:.3g}" if sigma[k] > 0 else "—",
                    f"held: {held[name]}" if name in held else "estimated",
                ]
            )
    doc.table(["parameter (SI)", "value", "LS σ", "σ (reported)", "status"], rows)
    doc.paragraph(
        "LS σ: the least-squares covariance from the residual variance, as if the windows were "
        "independent. σ (reported, and in the calibration file): per output axis scaled by the "
        "AR(1) factor of the residuals (inflation "
        + ", ".join(f"{x:.2f}" for x in cal.inflation)
        + "), plus the smoothed solution's own uncertainty of the biases and scale factors that "
        "the references inherit. No Cramér-Rao bound here: the references' errors are not "
        "white noise of a known level."
    )
    _warnings(doc, cal.warnings, "None.")
    return doc.write(out)


def _warnings(doc: Report, warnings: list[str], none: str) -> None:
    """The report's warnings section (``none`` when there are none)."""
    doc.section("Warnings")
    if warnings:
        doc.html("<ul>" + "".join(f"<li>{html.escape(w)}</li>" for w in warnings) + "</ul>")
    else:
        doc.paragraph(none)


def _value(fit: object, name: str) -> str:
    """A parameter's value by its name."""
    kind, index = parameter_index(name)
    return number(np.asarray(getattr(fit.model, kind))[index], 6)  # type: ignore[attr-defined]
