"""The walk_0827 figures docs/how-to/multi-gnss.md quotes from its u-blox
log and its three-system run (examples/walk_0827_multi_gnss.toml): each a
function of the log or of the run, which tests/test_multi_gnss.py calls on
its own log and run to compare with the record ``walk_multi_gnss`` that
``python docs/doc_runs.py walk_multi_gnss`` writes."""

from __future__ import annotations

import warnings
from pathlib import Path
from typing import Any

import numpy as np

import memsnav as mn
from memsnav.realdata.answer import answer_lines

ROOT = Path(__file__).resolve().parents[1]
UBX = "real-imu-gnss/walk_0827/gnss_1730.ubx"

#: examples/walk_0827_multi_gnss.toml's measurement settings (σ sets the
#: smoothing), GPS only: the satellites whose delays the page compares.
DELAY_SETTINGS = {
    "elevation_mask_deg": 5.0,
    "min_cn0_db_hz": 20.0,
    "pseudorange_std": 0.5,
    "weighting": "signal-strength",
    "systems": ["G"],
}

#: The GPS satellites at one elevation whose delays disagree.
DELAY_SATELLITES = (24, 27, 18)


def geometry_free_delays(log) -> dict[str, Any]:
    """Each satellite's delay measured from L2C (the corrected pseudorange
    without any ionosphere correction less the one with the measured
    delay) averaged over the log, m, and the satellites' mean elevations."""
    eph, obs = log.broadcast_ephemerides, log.observations
    measured = obs.measurements(eph, dual_frequency=True, **DELAY_SETTINGS)
    left_in = obs.measurements(eph, ionosphere=False, **DELAY_SETTINGS)
    ids = np.asarray(measured.sat_id)
    delay = np.asarray(left_in.pseudorange) - np.asarray(measured.pseudorange)
    elevation = np.degrees(np.asarray(measured.elevation_rad))
    means = [float(np.mean(elevation[ids == prn])) for prn in DELAY_SATELLITES]
    return {
        "delay_m": [float(np.mean(delay[ids == prn])) for prn in DELAY_SATELLITES],
        "elevation_deg": {"least": min(means), "most": max(means)},
    }


def clock_ramp(log) -> dict[str, float]:
    """The single-point fixes' receiver clock drift over the first and
    the last 10 s (m/s) and its slope over the log (m/s²)."""
    gnss = log.observations.measurements(log.broadcast_ephemerides, systems=["G", "E", "C"])
    fixes = mn.solve_fix(gnss)
    time, drift = np.asarray(fixes.time), np.asarray(fixes.clock_drift)
    ok = np.isfinite(drift)
    time, drift = time[ok] - time[ok][0], drift[ok]
    return {
        "first_m_s": float(np.mean(drift[time < 10])),
        "last_m_s": float(np.mean(drift[time > time[-1] - 10])),
        "slope_m_s2": float(np.polyfit(time, drift, 1)[0]),
    }


def wind_up(run) -> dict[str, float]:
    """The tilt of the body's vertical axis per 0.25 s epoch (median and
    95th percentile, °) and the differential wind-up it bounds, λ·tilt/360°
    at the 95th percentile, mm."""
    solution = run.run.solution
    time, c_b_e = np.asarray(solution.time), np.asarray(solution.attitude)
    at = np.searchsorted(time, np.arange(time[0], time[-1], 0.25))
    z_axis = c_b_e[at][:, :, 2]
    tilt_deg = np.degrees(np.arccos(np.clip(np.sum(z_axis[1:] * z_axis[:-1], axis=1), -1, 1)))
    wavelength_m = 299_792_458.0 / 1575.42e6
    p95 = float(np.percentile(tilt_deg, 95))
    return {
        "median_tilt_deg": float(np.median(tilt_deg)),
        "p95_tilt_deg": p95,
        "bound_mm": 1000 * wavelength_m * p95 / 360,
    }


def satellites(summary: dict[str, Any]) -> dict[str, Any]:
    """The weakest and strongest satellites by mean C/N0 (dB-Hz; the
    weakest's mean elevation and epochs) and the most epochs any has."""
    rows = summary["satellites"]
    low = min(rows, key=lambda r: r["mean_cn0_db_hz"])
    high = max(rows, key=lambda r: r["mean_cn0_db_hz"])
    return {
        "weakest": {
            "satellite": low["satellite"],
            "mean_cn0_db_hz": low["mean_cn0_db_hz"],
            "mean_elevation_deg": low["mean_elevation_deg"],
            "epochs": low["epochs"],
        },
        "strongest": {"satellite": high["satellite"], "mean_cn0_db_hz": high["mean_cn0_db_hz"]},
        "most_epochs": max(r["epochs"] for r in rows),
    }


def slips(summary: dict[str, Any]) -> dict[str, Any]:
    """The carrier changes the slip tests refused, by system (GPS's also
    its least and most on a satellite)."""
    per_system = {
        t: [r["slips"] for r in summary["satellites"] if r["system"] == t]
        for t in ("GPS", "Galileo", "BeiDou")
    }
    gps = per_system["GPS"]
    return {
        "gps": sum(gps),
        "gps_least": min(gps),
        "gps_most": max(gps),
        "galileo": sum(per_system["Galileo"]),
        "beidou": sum(per_system["BeiDou"]),
    }


def navigate(
    data_root: Path,
    output: Path,
    overrides: dict | None = None,
    engine: dict[str, dict] | None = None,
    example: str = "walk_0827_multi_gnss.toml",
):
    """``memsnav navigate`` of ``examples/<example>`` on the shared data, no
    HTML; ``overrides`` update its ``[gnss]`` table (``carrier_phase``, an
    engine key, included), ``engine`` the engine's tables by name
    (``{"filter": {...}}``)."""
    config = mn.load_config(ROOT / "examples" / example, data_root)
    config.values["report"]["html"] = False
    overrides = dict(overrides or {})
    if overrides.pop("carrier_phase", False):
        config.engine.setdefault("gnss", {})["carrier_phase"] = True
    for table, values in (engine or {}).items():
        config.engine.setdefault(table, {}).update(values)
    config.values["gnss"].update(overrides)
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")  # the log's last line is cut short
        return mn.navigate(config, output=output)


#: The four GPS satellites the walk's RINEX files carry.
GPS_4 = ["G10", "G23", "G27", "G32"]
GPS_4_G08 = {"systems": ["G"], "satellites": [*GPS_4, "G08"]}
GPS_7 = {"systems": ["G"]}
ALL_3 = {"systems": ["G", "E", "C"]}
ALL_3_CARRIER = {**ALL_3, "carrier_phase": True}

#: The C/N0 mask docs/how-to/multi-gnss.md tries, and the example's, dB-Hz.
CN0_MASKS = (28.0, 20.0)
#: The range-bias models it tries: std (m), correlation time (s).
RANGE_BIAS_MODELS = ((6.0, 1800.0), (10.0, 1800.0), (3.0, 60.0))
#: The error the page says the G08 run is back under, m.
BACK_UNDER_M = 9.0
#: The carrier-phase std floors it compares, cm.
CARRIER_FLOORS_CM = (0.5, 1.0, 2.0, 4.0, 8.0)


def _precision(summary: dict[str, Any]) -> float:
    return summary["errors_vs_truth_precision"]["aided"]["rms_horizontal_m"]


def g08_start(run) -> dict[str, Any]:
    """GPS 4 + G08: G08's entry (s after the start), its first 2 s of
    pseudorange innovations and their stds (m), and the horizontal error
    against the truth it causes (before, at its peak within 20 s, the time
    of the peak and the time it is back under BACK_UNDER_M after the
    entry)."""
    m = run.run.solution.measurements
    kind, ids, time = (np.asarray(m[k]) for k in ("kind", "id", "time"))
    g08 = (kind == "pseudorange") & (ids == 8)
    first = time[g08][0]
    early = g08 & (time < first + 2.0)
    innovation, std = np.asarray(m["innovation"])[early], np.asarray(m["innovation_std"])[early]
    forward = run.precision["forward"]
    t = np.asarray(forward["time"])
    error = np.linalg.norm(
        np.asarray(forward["error_ned"]) + np.asarray(forward["offset_removed_ned"]), axis=1
    )
    k = int(np.argmax(np.where(t < first + 20.0, error, 0.0)))
    recovered = t[(t > t[k]) & (error < BACK_UNDER_M)][0]
    return {
        "entry_s": float(first - time.min()),
        "early_pseudoranges": int(early.sum()),
        "early_innovation_m": {"least": float(innovation.min()), "most": float(innovation.max())},
        "early_innovation_std_m": {"least": float(std.min()), "most": float(std.max())},
        "error_before_m": float(error[t < first].max()),
        "error_peak_m": float(error[k]),
        "peak_after_s": float(t[k] - first),
        "back_after_s": float(recovered - first),
    }


def g08_record(data_root: Path) -> dict[str, Any]:
    """The G08 run, the C/N0 mask's runs and the range-bias models' runs."""
    import tempfile

    mask, default = CN0_MASKS
    with tempfile.TemporaryDirectory() as out:
        figures = {"g08": g08_start(navigate(data_root, Path(out) / "g08", GPS_4_G08))}

        def precision(overrides, engine=None) -> float:
            return _precision(navigate(data_root, Path(out) / "run", overrides, engine).summary)

        figures["cn0_mask_precision_m"] = {
            "gps_7_masked": precision({**GPS_7, "min_cn0_db_hz": mask}),
            "gps_4_g08_masked": precision({**GPS_4_G08, "min_cn0_db_hz": mask}),
            "all_3_default": precision({**ALL_3, "min_cn0_db_hz": default}),
            "all_3_masked": precision({**ALL_3, "min_cn0_db_hz": mask}),
        }
        figures["range_bias_model_precision_m"] = [
            precision(
                GPS_7,
                {"gnss": {"range_bias_std_m": s, "range_bias_correlation_time_s": tau}},
            )
            for s, tau in RANGE_BIAS_MODELS
        ]
    return figures


def carrier_floors(data_root: Path) -> dict[str, Any]:
    """All three systems with carrier phase at each floor of
    CARRIER_FLOORS_CM: horizontal precision (m) and the carrier changes
    whose batches failed their test."""
    import tempfile

    precision, gated = [], []
    with tempfile.TemporaryDirectory() as out:
        for floor_cm in CARRIER_FLOORS_CM:
            engine = {"filter": {"carrier_phase_std_floor_m": floor_cm / 100.0}}
            summary = navigate(data_root, Path(out) / "floor", ALL_3_CARRIER, engine).summary
            precision.append(_precision(summary))
            gated.append(summary["measurements"]["carrier_phase"].get("gate", 0))
    return {"floors_cm": list(CARRIER_FLOORS_CM), "precision_m": precision, "gated": gated}


#: The configurations of docs/how-to/multi-gnss.md's walk tables, in their
#: order: a key, the row's label, the ``[gnss]`` overrides
#: (``carrier_phase``, an engine key, included).
CONFIGURATIONS: dict[str, tuple[str, dict[str, Any]]] = {
    "gps_4": ("GPS, 4 satellites (LNAV)", {"systems": ["G"], "satellites": GPS_4}),
    "gps_7": ("GPS, all 7 (LNAV + CNAV)", GPS_7),
    **{
        f"gps_4_{extra.lower()}": (
            f"GPS 4 + {extra}",
            {"systems": ["G"], "satellites": [*GPS_4, extra]},
        )
        for extra in ("G08", "G18", "G24")
    },
    "galileo": ("Galileo alone", {"systems": ["E"]}),
    "beidou": ("BeiDou alone", {"systems": ["C"]}),
    "gps_galileo": ("GPS + Galileo", {"systems": ["G", "E"]}),
    "gps_galileo_beidou": ("GPS + Galileo + BeiDou", ALL_3),
    "gps_galileo_carrier": (
        "GPS + Galileo + carrier phase",
        {"systems": ["G", "E"], "carrier_phase": True},
    ),
    "gps_galileo_beidou_carrier": ("GPS + Galileo + BeiDou + carrier phase", ALL_3_CARRIER),
    # The ionosphere measured from a second signal, and left in.
    **{
        f"{key}_{suffix}": (f"GPS + Galileo{extra}, {ionosphere}", {"systems": systems, **setting})
        for suffix, ionosphere, setting in (
            ("dual", "ionosphere from L2C / E5a", {"dual_frequency": True}),
            ("no_iono", "no ionosphere correction", {"ionosphere": False}),
        )
        for key, extra, systems in (
            ("gps_galileo", "", ["G", "E"]),
            ("gps_galileo_beidou", " + BeiDou", ["G", "E", "C"]),
        )
    },
}

#: The code correlation times (s) of the second walk table; 0 is the first's.
CODE_CORRELATION_TIMES_S = (5.0, 10.0, 20.0)


def configuration_row(summary: dict[str, Any]) -> dict[str, Any]:
    """One row of the walk's configuration table: satellites used,
    horizontal and vertical precision, vertical accuracy (against MSL −
    21.387 m), the mean height below the truth and single-point
    precision, m."""
    precise, accurate = summary["errors_vs_truth_precision"], summary["errors_vs_truth"]
    return {
        "satellites": len(summary["satellites"]),
        "precision_horizontal_m": precise["aided"]["rms_horizontal_m"],
        "precision_vertical_m": precise["aided"]["rms_vertical_m"],
        "accuracy_vertical_m": accurate["aided"]["rms_vertical_m"],
        "height_below_truth_m": precise["offset_removed_ned_m"][2],
        "single_point_precision_horizontal_m": summary["spp_errors_vs_truth_precision"][
            "rms_horizontal_m"
        ],
    }


def configurations_record(data_root: Path) -> dict[str, Any]:
    """The record of the configuration table: each configuration's row."""
    import tempfile

    rows = {}
    with tempfile.TemporaryDirectory() as out:
        for key, (_, overrides) in CONFIGURATIONS.items():
            rows[key] = configuration_row(navigate(data_root, Path(out) / key, overrides).summary)
    return rows


def correlation_precision(data_root: Path, key: str, tau_s: float) -> list[float]:
    """Configuration ``key`` with ``pseudorange_correlation_time_s = tau_s``:
    its horizontal and vertical precision, m."""
    import tempfile

    with tempfile.TemporaryDirectory() as out:
        summary = navigate(
            data_root,
            Path(out) / "walk",
            CONFIGURATIONS[key][1],
            {"filter": {"pseudorange_correlation_time_s": tau_s}},
        ).summary
    precise = summary["errors_vs_truth_precision"]["aided"]
    return [precise["rms_horizontal_m"], precise["rms_vertical_m"]]


#: The configurations with more satellites than the 12 shared range-bias slots.
EVERY_SATELLITE_CONFIGURATIONS = ("gps_galileo", "gps_galileo_beidou")


def every_satellite_record(data_root: Path) -> dict[str, Any]:
    """The configurations of :data:`EVERY_SATELLITE_CONFIGURATIONS` with the
    12 shared range-bias slots (the default) and with a slot for every
    satellite (``gnss.range_bias_states = "every_satellite"``): each one's
    satellites and horizontal and vertical precision, m."""
    import tempfile

    rows: dict[str, Any] = {}
    with tempfile.TemporaryDirectory() as out:
        for key in EVERY_SATELLITE_CONFIGURATIONS:
            rows[key] = {}
            for name, slots in (("shared", True), ("every_satellite", "every_satellite")):
                summary = navigate(
                    data_root,
                    Path(out) / f"{key}_{name}",
                    CONFIGURATIONS[key][1],
                    {"gnss": {"range_bias_states": slots}},
                ).summary
                precise = summary["errors_vs_truth_precision"]["aided"]
                rows[key][name] = {
                    "satellites": len(summary["satellites"]),
                    "horizontal_m": precise["rms_horizontal_m"],
                    "vertical_m": precise["rms_vertical_m"],
                }
    return rows


def correlation_record(data_root: Path) -> dict[str, Any]:
    """The record of the code-correlation table: each configuration's
    precision by correlation time (τ = 0 is the configuration table's
    record; about 45 walk runs, a few minutes)."""
    return {
        "correlation_times_s": list(CODE_CORRELATION_TIMES_S),
        "precision_m": {
            key: [correlation_precision(data_root, key, tau) for tau in CODE_CORRELATION_TIMES_S]
            for key in CONFIGURATIONS
        },
    }


#: The tables' markers.
CONFIGURATION_TABLE = ("<!-- multi-gnss-walk:begin -->", "<!-- multi-gnss-walk:end -->")
CORRELATION_TABLE = ("<!-- code-correlation-walk:begin -->", "<!-- code-correlation-walk:end -->")


def configuration_table(record: dict[str, Any]) -> str:
    """The configuration table from its record, between its markers."""
    header = (
        "| configuration | satellites | precision horiz. [m] | precision vert. [m] "
        "| accuracy vert. [m] | mean height below truth [m] "
        "| single-point precision horiz. [m] |\n|---|---|---|---|---|---|---|"
    )
    rows = []
    for key, row in record["figures"].items():
        cells = [f"{v:.2f}" for k, v in row.items() if k != "satellites"]
        rows.append(f"| {CONFIGURATIONS[key][0]} | {row['satellites']} | {' | '.join(cells)} |")
    return "\n".join([CONFIGURATION_TABLE[0], header, *rows, CONFIGURATION_TABLE[1]])


def correlation_table(record: dict[str, Any]) -> str:
    """The code-correlation table from its record and the configuration
    table's (τ = 0), between its markers."""
    from figures import figures

    white = figures("walk_configurations")
    taus = record["figures"]["correlation_times_s"]
    header = "| configuration | τ = 0 s | " + " | ".join(f"τ = {t:g} s" for t in taus) + " |"
    rows = []
    for key, cells in record["figures"]["precision_m"].items():
        w = white[key]
        shown = [f"{w['precision_horizontal_m']:.2f} / {w['precision_vertical_m']:.2f}"]
        shown += [f"{h:.2f} / {v:.2f}" for h, v in cells]
        rows.append(f"| {CONFIGURATIONS[key][0]} | {' | '.join(shown)} |")
    rule = "|---" * (len(taus) + 2) + "|"
    return "\n".join([CORRELATION_TABLE[0], header, rule, *rows, CORRELATION_TABLE[1]])


#: The shortest unbroken L1 arc (epochs) whose code correlation time counts.
MIN_ARC_EPOCHS = 350


def code_correlation_times(log) -> dict[str, Any]:
    """The L1 code-minus-carrier of each satellite tracked without a break
    for at least MIN_ARC_EPOCHS epochs (its longest arc, less a quadratic
    over it: the ambiguity and the ionosphere's code-carrier divergence):
    the first lag at which its autocorrelation falls below 1/e, s; the
    shortest and longest with their satellites."""
    obs = log.observations
    time = np.asarray(obs.time)
    interval = float(np.median(np.diff(time)))
    wavelength = 299792458.0 / 1575.42e6
    code_minus_carrier = obs.observation("C1C") - wavelength * obs.observation("L1C")
    lags = {}
    for j, name in enumerate(obs.satellites):
        usable = np.flatnonzero(np.isfinite(code_minus_carrier[:, j]))
        if len(usable) == 0:
            continue
        arc = max(np.split(usable, np.flatnonzero(np.diff(usable) > 1) + 1), key=len)
        if len(arc) < MIN_ARC_EPOCHS:
            continue
        t = time[arc] - time[arc][0]
        x = code_minus_carrier[arc, j]
        x = x - np.polyval(np.polyfit(t, x, 2), t)
        x -= x.mean()
        correlation = np.correlate(x, x, "full")[len(x) - 1 :] / (x @ x)
        lags[str(name)] = float(np.flatnonzero(correlation < np.exp(-1.0))[0] * interval)
    shortest, longest = min(lags, key=lags.get), max(lags, key=lags.get)
    return {
        "min_arc_epochs": MIN_ARC_EPOCHS,
        "satellites": len(lags),
        "shortest": {"satellite": shortest, "time_s": lags[shortest]},
        "longest": {"satellite": longest, "time_s": lags[longest]},
    }


def code_correlation_record(data_root: Path) -> dict[str, Any]:
    """The record of the code's correlation times on the walk's log, and
    the pseudorange std inflation √((1 + ρ)/(1 − ρ)), ρ = e^(−Δt/τ), for
    τ = 10 s at the log's 4 Hz."""
    rho = np.exp(-0.25 / 10.0)
    return {
        **code_correlation_times(mn.read_ubx(data_root / UBX)),
        "inflation_tau_10s_at_4hz": float(np.sqrt((1 + rho) / (1 - rho))),
    }


def record(data_root: Path) -> dict[str, Any]:
    """The record: the log's, the run's, the carrier-phase run's figures."""
    import tempfile

    log = mn.read_ubx(data_root / UBX)
    with tempfile.TemporaryDirectory() as out:
        run = navigate(data_root, Path(out) / "walk")
        carrier = navigate(data_root, Path(out) / "carrier", {"carrier_phase": True}).summary
    return {
        "geometry_free": geometry_free_delays(log),
        "clock": clock_ramp(log),
        "wind_up": wind_up(run),
        "inter_system_bias_m": run.summary["inter_system_bias_m"],
        "satellites": satellites(run.summary),
        "carrier_slips": slips(carrier),
        "satellites_line": answer_lines(run.summary)[1],
    }


#: The markers of the terminal's satellites line in docs/how-to/multi-gnss.md.
SATELLITES_LINE = ("<!-- walk-satellites-line:begin -->", "<!-- walk-satellites-line:end -->")


def satellites_line_block(record: dict[str, Any]) -> str:
    """The terminal's satellites line on the walk, as a text block between
    its markers."""
    line = record["figures"]["satellites_line"]
    return "\n".join([SATELLITES_LINE[0], "```text", line, "```", SATELLITES_LINE[1]])
