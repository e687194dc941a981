"""The foreign-drive study of docs/results/foreign-drive.md, rerunnable by anyone:
``python docs/foreign_drive_study.py [--data-root DIR] [--write]``.

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

Prints the tables as Markdown; ``--write`` puts them into
docs/results/foreign-drive.md between its ``study`` markers.
"""

from __future__ import annotations

import argparse
import copy
import datetime
import platform
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


def _cell(stats: dict[str, Any]) -> str:
    return (
        f"{stats['rms_horizontal_m']:.2f} / {stats['max_horizontal_m']:.1f} | "
        f"{stats['within_3sigma_share_horizontal']:.2f}"
    )


def _learnt(adaptation: dict[str, Any] | None) -> str:
    """What the run learnt, in a table cell."""
    if not adaptation:
        return "nothing"
    words = [f"IMU {adaptation['imu_preset']}"] if adaptation["imu_candidates"] else []
    if adaptation["nhc_std_m_s"] is not None:
        words.append(f"NHC {adaptation['nhc_std_m_s']:g} m/s")
    if adaptation["fix_error_std_m"] is not None:
        words.append(
            f"fix-error states {adaptation['fix_error_std_m']:.2f} m, "
            f"τ {adaptation['fix_error_correlation_time_s']:.0f} s"
        )
    return "; ".join(words) or "nothing"


def study(data_root: str | None) -> str:
    """The study's tables as Markdown."""
    base = mn.load_config(ROOT / "examples" / "foreign_drive.toml", data_root)
    header = (
        "| configuration | forward aided: RMS / max [m] | N/E in 3σ | forward outages: RMS / max "
        "[m] | N/E in 3σ | smoothed aided: RMS / max [m] | N/E in 3σ | smoothed outages: RMS / "
        "max [m] | N/E in 3σ | resets | diverged | learnt | run [s] |"
    )
    blocks = []
    for length in OUTAGE_LENGTHS_S:
        rows = [header, "|---" * 13 + "|"]
        line = None
        for name in CONFIGURATIONS:
            result, seconds = run(configured(base, name, length))
            s = result.summary
            forward, smoothed = s["errors_vs_truth"], s["errors_vs_truth_smoothed"]
            key = f"{length:g}"
            rows.append(
                f"| {name} | {_cell(forward['aided'])} | "
                f"{_cell(forward['by_outage_length_s'][key])} | {_cell(smoothed['aided'])} | "
                f"{_cell(smoothed['by_outage_length_s'][key])} | {len(s['resets'])} | "
                f"{'yes' if s['integrity']['diverged'] else 'no'} | "
                f"{_learnt(s.get('adaptation'))} | {seconds:.1f} |"
            )
            if line is None:
                line = straight_line(result, length)
                outages = forward["by_outage_length_s"][key]["epochs"]
                fixes = s["gnss_errors_vs_truth"]
        assert line is not None
        blocks.append(
            f"**{length:g} s outages** ({outages} outage epochs at the reference's 10 Hz; the "
            f"fixes alone: {fixes['rms_horizontal_m']:.2f} m horizontal RMS; the straight line "
            f"between the fixes that bound each outage: {line[0]:.1f} / {line[1]:.1f} m RMS / "
            "max)\n\n" + "\n".join(rows)
        )
    stamp = (
        f"Generated by `python docs/foreign_drive_study.py --write` on "
        f"{datetime.date.today().isoformat()} ({platform.machine()}, "
        f"{platform.python_implementation()} {platform.python_version()}, memsnav "
        f"{mn.__version__})."
    )
    return "\n\n".join([stamp, *blocks])


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--data-root", default=None, help="the shared data folder")
    parser.add_argument(
        "--write", action="store_true", help="write into docs/results/foreign-drive.md"
    )
    args = parser.parse_args()
    text = study(args.data_root)
    print(text)
    if args.write:
        replace_block(PAGE, BEGIN, END, f"{BEGIN}\n{text}\n{END}")


if __name__ == "__main__":
    main()
