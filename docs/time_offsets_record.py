"""The time offsets of the two full logs, as docs/explanation/time-and-truth.md
("Finding the time offsets from the data") shows them: ``record`` runs
``mn.estimate_time_offset`` on each log and signal (IMU on the corrected
tag clock, the authors' mounting) and ``mn.estimate_velocity_latency`` on
each RTK solution; ``table`` writes the page's table from the record.

``python docs/doc_runs.py full_log_time_offsets`` writes the record;
``tests/test_timing.py`` compares ``record`` today with it."""

from __future__ import annotations

import warnings
from pathlib import Path
from typing import Any

import numpy as np

import memsnav as mn

#: Per log: its label in the table, its files' stem, the authors' mounting
#: (degrees) and the estimator's options.
LOGS: dict[str, dict[str, Any]] = {
    "drive_0708": {
        "label": "drive_0708",
        "imu": "drive_0708/imu_1934",
        "mounting_deg": [[180.0, 0.0, 180.0], [0.0, -6.79, 5.35]],
        "options": {},
    },
    "walk_0827": {
        "label": "walk_0827 (≥ 0.5 m/s)",
        "imu": "walk_0827/imu_1730",
        "mounting_deg": [[180.0, 0.0, -90.0]],
        "options": {"min_speed_m_s": 0.5},
    },
}
SIGNALS = {"along_track": "along-track", "yaw_rate": "yaw rate"}
#: The drive's IMU offset the data's authors give, s.
AUTHORS_DRIVE_OFFSET_S = -0.125
#: The RTK solutions' interval, s (4 Hz).
RTK_INTERVAL_S = 0.25
TABLE = ("<!-- full-log-time-offsets:begin -->", "<!-- full-log-time-offsets:end -->")


def _rtk(root: Path, log: dict[str, Any]) -> Any:
    return mn.read_pos(root / (log["imu"].replace("imu_", "gnss_") + "_sf.pos"))


def backward_difference_rms_m_s(rtk: Any) -> float:
    """The horizontal RMS of the reported velocity less the backward
    difference of the positions, over consecutive epochs one interval
    apart (m/s): each ECEF step resolved on north and east at the later
    epoch."""
    time, lla = np.asarray(rtk.gps_time), np.asarray(rtk.lla)
    step = np.diff(mn.geodetic_to_ecef(lla), axis=0) / np.diff(time)[:, None]
    lat, lon = lla[1:, 0], lla[1:, 1]
    north = np.column_stack([-np.sin(lat) * np.cos(lon), -np.sin(lat) * np.sin(lon), np.cos(lat)])
    east = np.column_stack([-np.sin(lon), np.cos(lon), np.zeros_like(lon)])
    difference = np.asarray(rtk.velocity_ned)[1:, :2] - np.column_stack(
        [np.sum(step * north, axis=1), np.sum(step * east, axis=1)]
    )
    keep = (np.abs(np.diff(time) - RTK_INTERVAL_S) < 1e-3) & np.all(np.isfinite(difference), axis=1)
    return float(np.sqrt(np.mean(np.sum(difference[keep] ** 2, axis=1))))


def record(data_root: Path) -> dict[str, Any]:
    """Per log: each signal's offset to add (s), its std (s), the peak
    correlation and the four stretches' offsets (s); the RTK velocity
    latency (s), its std (s) and the RMS velocity difference (m/s), and
    the reported velocity's horizontal RMS difference from the positions'
    backward difference (m/s)."""
    root = data_root / "real-imu-gnss"
    out: dict[str, Any] = {}
    for name, log in LOGS.items():
        with warnings.catch_warnings():
            warnings.simplefilter("ignore")  # the logs' cut first and last lines
            imu = mn.read_imu_csv(root / f"{log['imu']}.csv", skip_first_line=True)
        clock = mn.fit_tag_clock(imu, mn.read_time_tag(root / f"{log['imu']}.csv.tag"))
        c_b_s = mn.mounting_matrix(log["mounting_deg"])
        rtk = _rtk(root, log)
        out[name] = {}
        for signal in SIGNALS:
            e = mn.estimate_time_offset(
                clock.gps_time,
                imu.specific_force @ c_b_s.T,
                imu.angular_rate @ c_b_s.T,
                rtk,
                signal=signal,
                **log["options"],
            )
            out[name][signal] = {
                "offset_s": e.offset_s,
                "std_s": e.std_s,
                "correlation": e.correlation,
                "stretches_s": [float(v) for v in e.block_offsets_s],
                "stretch_spread_s": float(np.ptp(e.block_offsets_s)),
            }
        latency = mn.estimate_velocity_latency(rtk)
        out[name]["velocity_latency"] = {
            "latency_s": latency.latency_s,
            "std_s": latency.std_s,
            "rms_m_s": latency.rms_m_s,
            "backward_difference_rms_m_s": backward_difference_rms_m_s(rtk),
            # Beyond the backward difference's own latency, half the interval.
            "beyond_half_interval_ms": 1e3 * (latency.latency_s - RTK_INTERVAL_S / 2),
        }
        along, yaw = out[name]["along_track"], out[name]["yaw_rate"]
        out[name]["yaw_minus_along_track_ms"] = 1e3 * (yaw["offset_s"] - along["offset_s"])
    drive = out["drive_0708"]["along_track"]
    out["drive_0708"]["along_track_standard_errors_from_authors"] = (
        abs(drive["offset_s"] - AUTHORS_DRIVE_OFFSET_S) / drive["std_s"]
    )
    return out


def _signed(value: float) -> str:
    return f"{value:+.3f}".replace("-", "−")


def table(recorded: dict[str, Any]) -> str:
    """The offsets table; the drive's along-track offset, the one to use,
    in bold."""
    rows = [
        "| log | signal | offset to add | std | correlation | stretches |",
        "|---|---|---|---|---|---|",
    ]
    for name, log in LOGS.items():
        for signal, label in SIGNALS.items():
            e = recorded["figures"][name][signal]
            offset = f"{_signed(e['offset_s'])} s"
            if (name, signal) == ("drive_0708", "along_track"):
                offset = f"**{offset}**"
            stretches = ", ".join(_signed(v) for v in e["stretches_s"])
            rows.append(
                f"| {log['label']} | {label} | {offset} | {e['std_s']:.3f} s | "
                f"{e['correlation']:.2f} | {stretches} |"
            )
    return "\n".join([TABLE[0], *rows, TABLE[1]])
