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


def navigate(data_root: Path, output: Path, carrier_phase: bool = False):
    """examples/walk_0827_multi_gnss.toml on the shared data, no HTML."""
    config = mn.load_config(ROOT / "examples" / "walk_0827_multi_gnss.toml", data_root)
    config.values["report"]["html"] = False
    if carrier_phase:
        config.engine.setdefault("gnss", {})["carrier_phase"] = True
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")  # the log's last line is cut short
        return mn.navigate(config, output=output)


def record(data_root: Path) -> dict[str, Any]:
    """The record: the log's, the run's, the carrier-phase run's figures."""
    import tempfile

    log = mn.read_ubx(data_root / UBX)
    with tempfile.TemporaryDirectory() as out:
        run = navigate(data_root, Path(out) / "walk")
        carrier = navigate(data_root, Path(out) / "carrier", carrier_phase=True).summary
    return {
        "geometry_free": geometry_free_delays(log),
        "clock": clock_ramp(log),
        "wind_up": wind_up(run),
        "inter_system_bias_m": run.summary["inter_system_bias_m"],
        "satellites": satellites(run.summary),
        "carrier_slips": slips(carrier),
    }
