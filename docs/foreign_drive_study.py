"""The foreign-drive study of docs/results/foreign-drive.md, rerunnable by anyone:
``python docs/doc_runs.py foreign_drive_study`` (about a minute) writes its
record, ``docs/data/foreign_drive_study.json``, and the page's tables
(:func:`tables`); the page's sentences show the record through
placeholders.

``examples/foreign_drive.toml`` (a VN-100 IMU, u-blox F9T standalone
fixes at 1 Hz, an INS-D reference; loose coupling with NHC, the
installation states and the smoother) run with GNSS outages of 30 s and of
60 s every 180 s from 180 s, in three filter configurations:

- ``defaults``: the file as it is, the engine's defaults: the IMU grade and
  the fixes' error correlation learnt from the log;
- ``datasheet``: the same with the VN-100's data-sheet figures in
  ``[imu_spec]`` (``DATASHEET``);
- ``fixed consumer, white fixes``: ``imu_preset = "consumer"``,
  ``nhc_std_m_s = 0.1`` and ``fix_error_states = false``, nothing learnt.

For each, forward and smoothed: the aided errors and the errors in the
outages of the run's length (those not spent at a standstill), horizontal
RMS and max, and the share of the N and E errors inside the solution's own
3σ; the straight line between the fixes that bound each outage, scored on
the same epochs; the resets, whether the run diverged, what it learnt and
the time it took.

``tests/test_foreign_drive.py`` reruns two of the configurations and
compares them with the record.
"""

from __future__ import annotations

import copy
import tempfile
import time
import warnings
from pathlib import Path
from typing import Any

import numpy as np

import memsnav as mn
from memsnav.realdata.config import RunConfig

ROOT = Path(__file__).resolve().parents[1]
PAGE = ROOT / "docs" / "results" / "foreign-drive.md"
BEGIN, END = "<!-- study:begin -->", "<!-- study:end -->"
OUTAGE_LENGTHS_S = (30.0, 60.0)

#: The VN-100's data sheet (VectorNav VN-100 product brief: accelerometer
#: noise density 140 µg/√Hz and in-run bias stability 40 µg; gyro noise
#: density 0.0035 °/s/√Hz and in-run bias stability 10 °/h). The data
#: sheet gives no correlation time: 100 s puts the Gauss-Markov process's
#: Allan maximum at 189 s (docs/reference/configuration.md, "[imu_spec]"), where a
#: MEMS Allan curve typically flattens. The terms it leaves out come from
#: the grade the log supports (imu_preset "auto").
DATASHEET = {
    "accel_noise_density_ug_sqrt_hz": 140.0,
    "accel_bias_instability_ug": 40.0,
    "accel_bias_correlation_time_s": 100.0,
    "gyro_noise_density_deg_s_sqrt_hz": 0.0035,
    "gyro_bias_instability_deg_h": 10.0,
    "gyro_bias_correlation_time_s": 100.0,
}

#: The configurations, as what each adds to the example's engine tables.
CONFIGURATIONS: dict[str, dict[str, dict[str, Any]]] = {
    "defaults": {},
    "datasheet": {"imu_spec": DATASHEET},
    "fixed consumer, white fixes": {
        "filter": {"imu_preset": "consumer"},
        "aids": {"nhc_std_m_s": 0.1},
        "gnss": {"fix_error_states": False},
    },
}


def configured(base: RunConfig, name: str, length_s: float) -> RunConfig:
    """``base`` with configuration ``name`` and outages of ``length_s``."""
    cfg = copy.deepcopy(base)
    for table, keys in CONFIGURATIONS[name].items():
        cfg.engine[table] = {**cfg.engine.get(table, {}), **keys}
    cfg.engine["outages"] = {"first_s": 180.0, "length_s": length_s, "every_s": 180.0}
    cfg.values["report"]["html"] = False
    return cfg


def straight_line(result: Any, length_s: float) -> tuple[float, float]:
    """Horizontal RMS and max of the straight line between the last fix
    before each outage of ``length_s`` (not at a standstill) and the first
    one after it, at the truth's epochs inside the outage (the truth as the
    run scores it: at the antenna, in the fixes' datum)."""
    run, score = result.run, result.truth
    used = np.asarray(run.gnss["used"], dtype=bool)
    fix_t = np.asarray(run.gnss["time"])[used]
    fix_r = np.asarray(run.gnss["position_ecef"])[used]
    truth_t, truth_r = np.asarray(score["all_time"]), np.asarray(score["position_ecef"])
    origin = truth_r[0]
    errors = []
    for (start, end), window in zip(run.outages, score["outages"], strict=True):
        if abs((end - start) - length_s) > 1e-6 or window["at_standstill"]:
            continue
        before, after = np.searchsorted(fix_t, start) - 1, np.searchsorted(fix_t, end)
        if before < 0 or after >= len(fix_t):
            continue
        inside = (truth_t >= start) & (truth_t < end)
        weight = (truth_t[inside] - fix_t[before]) / (fix_t[after] - fix_t[before])
        line = fix_r[before] + weight[:, None] * (fix_r[after] - fix_r[before])
        # Both in the local axes at the drive's start (a few km: the axes
        # turn by a few hundredths of a degree over it).
        errors.append(mn.ecef_to_ned(line, origin) - mn.ecef_to_ned(truth_r[inside], origin))
    horizontal = np.hypot(*np.vstack(errors)[:, :2].T)
    return float(np.sqrt(np.mean(horizontal**2))), float(horizontal.max())


def run(cfg: RunConfig) -> tuple[Any, float]:
    """The run of ``cfg`` and its wall time, s."""
    with tempfile.TemporaryDirectory() as out, warnings.catch_warnings():
        warnings.simplefilter("ignore")
        started = time.perf_counter()
        result = mn.navigate(cfg, output=out)
        return result, time.perf_counter() - started


def slug(name: str) -> str:
    """A configuration's key in the record (a placeholder's path has no
    spaces): "fixed consumer, white fixes" is ``fixed_consumer``."""
    return name.split(",")[0].replace(" ", "_")


def _stats(stats: dict[str, Any]) -> dict[str, float]:
    return {
        "rms_m": stats["rms_horizontal_m"],
        "max_m": stats["max_horizontal_m"],
        "in_3sigma": stats["within_3sigma_share_horizontal"],
    }


def _learnt(adaptation: dict[str, Any] | None) -> dict[str, Any]:
    """What the run learnt: the grade (when it chose one), the constraint's
    std and the fix-error states' std and correlation time (None where it
    learnt nothing)."""
    a = adaptation or {}
    return {
        "imu_preset": a.get("imu_preset") if a.get("imu_candidates") else None,
        "nhc_std_m_s": a.get("nhc_std_m_s"),
        "fix_error_std_m": a.get("fix_error_std_m"),
        "fix_error_correlation_time_s": a.get("fix_error_correlation_time_s"),
    }


def _installation(estimates: dict[str, Any]) -> dict[str, Any]:
    """The installation states' final estimates and σ: lever arm (m, sensor
    axes), mounting pitch and yaw (°), IMU time offset and velocity latency (s)."""
    return {
        "lever_arm_m": estimates["lever_arm_m"]["value"],
        "lever_arm_std_m": estimates["lever_arm_m"]["std"],
        "mounting_std_deg": estimates["mounting_pitch_yaw_deg"]["std"],
        "time_offset_s": estimates["time_offset_s"]["value"],
        "time_offset_std_s": estimates["time_offset_s"]["std"],
        "velocity_latency_s": estimates["velocity_latency_s"]["value"],
        "velocity_latency_std_s": estimates["velocity_latency_s"]["std"],
    }


def configuration_figures(result: Any, length_s: float, seconds: float) -> dict[str, Any]:
    """One configuration's row of the study: forward and smoothed, aided
    and in the outages of ``length_s``; resets, divergence, the windowed
    NIS's largest window over its band's edge (position and velocity
    fixes), what it learnt, its installation estimates and its wall time."""
    s = result.summary
    forward, smoothed = s["errors_vs_truth"], s["errors_vs_truth_smoothed"]
    key = f"{length_s:g}"
    return {
        "forward_aided": _stats(forward["aided"]),
        "forward_outages": _stats(forward["by_outage_length_s"][key]),
        "smoothed_aided": _stats(smoothed["aided"]),
        "smoothed_outages": _stats(smoothed["by_outage_length_s"][key]),
        "resets": len(s["resets"]),
        "diverged": bool(s["integrity"]["diverged"]),
        "nis_band_ratio_most": {
            c["kind"]: c["max_band_ratio"] for c in s["integrity"]["consistency"]
        },
        "learnt": _learnt(s.get("adaptation")),
        "installation": _installation(s["installation_estimates"]),
        "run_s": seconds,
    }


def record(data_root: Path | None) -> dict[str, Any]:
    """Every configuration at each outage length (:func:`configuration_figures`),
    with the outage epochs, the fixes' own RMS and the straight line's
    RMS / max per length."""
    base = mn.load_config(ROOT / "examples" / "foreign_drive.toml", data_root)
    out: dict[str, Any] = {}
    for length in OUTAGE_LENGTHS_S:
        rows = {}
        for name in CONFIGURATIONS:
            result, seconds = run(configured(base, name, length))
            rows[slug(name)] = {"name": name} | configuration_figures(result, length, seconds)
            if name == "defaults":
                line_rms, line_max = straight_line(result, length)
                forward = result.summary["errors_vs_truth"]
                outages = forward["by_outage_length_s"][f"{length:g}"]["epochs"]
                fixes_rms = result.summary["gnss_errors_vs_truth"]["rms_horizontal_m"]
        out[f"{length:g}"] = {
            "outage_epochs": outages,
            "fixes_rms_m": fixes_rms,
            "line_rms_m": line_rms,
            "line_max_m": line_max,
            "configurations": rows,
        }
    return out


def _cell(stats: dict[str, float]) -> str:
    return f"{stats['rms_m']:.2f} / {stats['max_m']:.1f} | {stats['in_3sigma']:.2f}"


def _learnt_cell(learnt: dict[str, Any]) -> str:
    """What the run learnt, in a table cell."""
    words = [f"IMU {learnt['imu_preset']}"] if learnt["imu_preset"] else []
    if learnt["nhc_std_m_s"] is not None:
        words.append(f"NHC {learnt['nhc_std_m_s']:g} m/s")
    if learnt["fix_error_std_m"] is not None:
        words.append(
            f"fix-error states {learnt['fix_error_std_m']:.2f} m, "
            f"τ {learnt['fix_error_correlation_time_s']:.0f} s"
        )
    return "; ".join(words) or "nothing"


def tables(recorded: dict[str, Any]) -> str:
    """The page's block: the tables of the record, between the markers."""
    header = (
        "| configuration | forward aided: RMS / max [m] | N/E in 3σ | forward outages: RMS / max "
        "[m] | N/E in 3σ | smoothed aided: RMS / max [m] | N/E in 3σ | smoothed outages: RMS / "
        "max [m] | N/E in 3σ | resets | diverged | learnt | run [s] |"
    )
    blocks = []
    for length, study in recorded["figures"].items():
        rows = [header, "|---" * 13 + "|"]
        for c in study["configurations"].values():
            rows.append(
                f"| {c['name']} | {_cell(c['forward_aided'])} | {_cell(c['forward_outages'])} | "
                f"{_cell(c['smoothed_aided'])} | {_cell(c['smoothed_outages'])} | "
                f"{c['resets']} | {'yes' if c['diverged'] else 'no'} | "
                f"{_learnt_cell(c['learnt'])} | {c['run_s']:.1f} |"
            )
        blocks.append(
            f"**{length} s outages** ({study['outage_epochs']} outage epochs at the reference's "
            f"10 Hz; the fixes alone: {study['fixes_rms_m']:.2f} m horizontal RMS; the straight "
            f"line between the fixes that bound each outage: {study['line_rms_m']:.1f} / "
            f"{study['line_max_m']:.1f} m RMS / max)\n\n" + "\n".join(rows)
        )
    return "\n".join([BEGIN, "\n\n".join(blocks), END])
