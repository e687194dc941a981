"""The foreign drive's datum and fixes (docs/how-to/your-own-files.md):
examples/foreign_drive.toml on the whole drive (~20 s), and the fixes
against the INS-D computed from the CSVs with numpy alone (at the
antenna, and left at the INS-D's point). ``python docs/doc_runs.py
foreign_drive`` writes the record; tests/test_your_own_files.py checks
the engine against the independent computation and both against the
record. ``files_record`` measures what the files show a user of the same
sensors (docs/results/foreign-drive.md), from the CSVs alone."""

from __future__ import annotations

import tempfile
from pathlib import Path
from typing import Any

import numpy as np

import memsnav as mn
from memsnav.realdata.readers import UNIX_TO_GPS_S

ROOT = Path(__file__).resolve().parents[1]
EXAMPLE = ROOT / "examples" / "foreign_drive.toml"
#: The antenna's lever arm along the INS-D's forward axis, m.
LEVER_ARM_M = -2.2

A_M, E2 = 6_378_137.0, 6.69437999014e-3


def _ecef(lat_deg: np.ndarray, lon_deg: np.ndarray, h_m: np.ndarray) -> np.ndarray:
    lat, lon = np.radians(lat_deg), np.radians(lon_deg)
    n = A_M / np.sqrt(1.0 - E2 * np.sin(lat) ** 2)
    return np.column_stack(
        [
            (n + h_m) * np.cos(lat) * np.cos(lon),
            (n + h_m) * np.cos(lat) * np.sin(lon),
            (n * (1.0 - E2) + h_m) * np.sin(lat),
        ]
    )


def _ned_axes(lat_deg: np.ndarray, lon_deg: np.ndarray) -> np.ndarray:
    """(N, 3, 3): the columns north, east, down in ECEF."""
    lat, lon = np.radians(lat_deg), np.radians(lon_deg)
    north = np.column_stack([-np.sin(lat) * np.cos(lon), -np.sin(lat) * np.sin(lon), np.cos(lat)])
    east = np.column_stack([-np.sin(lon), np.cos(lon), np.zeros_like(lon)])
    down = np.column_stack([-np.cos(lat) * np.cos(lon), -np.cos(lat) * np.sin(lon), -np.sin(lat)])
    return np.stack([north, east, down], axis=2)


def _quaternion_matrix(w, x, y, z) -> np.ndarray:
    """(N, 3, 3) rotation matrices of unit quaternions, scalar first (the
    Hamilton product's v' = q v q*, written out)."""
    return np.stack(
        [
            np.column_stack([1 - 2 * (y * y + z * z), 2 * (x * y + w * z), 2 * (x * z - w * y)]),
            np.column_stack([2 * (x * y - w * z), 1 - 2 * (x * x + z * z), 2 * (y * z + w * x)]),
            np.column_stack([2 * (x * z + w * y), 2 * (y * z - w * x), 1 - 2 * (x * x + y * y)]),
        ],
        axis=2,
    )


def _csv(path: Path) -> dict[str, np.ndarray]:
    table = np.genfromtxt(path, delimiter=",", names=True)
    return {name: table[name] for name in table.dtype.names}


def independent(
    folder: Path, span: tuple[float, float], lever_arm_m: float
) -> dict[str, np.ndarray]:
    """The fixes against the INS-D moved by ``lever_arm_m`` along its
    forward axis, from the CSVs in ``folder`` with numpy alone: the truth
    interpolated at each fix inside ``span`` (Unix-like GPS s), the NED
    errors, their mean (the datum offset) and the errors less it."""
    fixes, ref = _csv(folder / "f9t_fixes.csv"), _csv(folder / "insd_reference.csv")
    inside = (ref["time_s"] >= span[0]) & (ref["time_s"] <= span[1])
    ref = {k: v[inside] for k, v in ref.items()}
    c_b_n = _quaternion_matrix(ref["qw"], ref["qx"], ref["qy"], ref["qz"])
    axes = _ned_axes(ref["lat_deg"], ref["lon_deg"])
    forward_ned = c_b_n[:, :, 0] * lever_arm_m
    truth = _ecef(ref["lat_deg"], ref["lon_deg"], ref["height_m"]) + np.einsum(
        "kij,kj->ki", axes, forward_ned
    )
    t = fixes["time_s"]
    keep = (t >= ref["time_s"][0]) & (t <= ref["time_s"][-1])
    t = t[keep]
    at_fix = np.column_stack([np.interp(t, ref["time_s"], truth[:, i]) for i in range(3)])
    fix_ecef = _ecef(fixes["lat_deg"], fixes["lon_deg"], fixes["height_m"])[keep]
    nearest = np.clip(np.searchsorted(ref["time_s"], t), 0, len(ref["time_s"]) - 1)
    errors = np.einsum("kji,kj->ki", axes[nearest], fix_ecef - at_fix)
    offset = errors.mean(axis=0)
    return {"errors": errors, "offset": offset, "less_offset": errors - offset}


def rms(errors: np.ndarray) -> tuple[float, float]:
    return (
        float(np.sqrt(np.mean(errors[:, 0] ** 2 + errors[:, 1] ** 2))),
        float(np.sqrt(np.mean(errors[:, 2] ** 2))),
    )


def figures_of(summary: dict[str, Any], folder: Path) -> dict[str, Any]:
    """The page's figures from a run's summary: the estimated datum offset
    (N, E, D, m), the fixes it averages, the fixes' RMS against the moved
    truth (horizontal, vertical, m), and the horizontal RMS against the
    truth left at the INS-D's point (independent computation)."""
    start = summary["start_gps_time_s"] + UNIX_TO_GPS_S
    span = (start, start + summary["duration_s"])
    datum = summary["truth"]["datum_offset"]
    fixes = summary["gnss_errors_vs_truth"]
    unmoved, _ = rms(independent(folder, span, 0.0)["less_offset"])
    return {
        "datum_offset_ned_m": list(datum["ned_m"]),
        "fixes": datum["gnss_epochs"],
        "fixes_rms_horizontal_m": fixes["rms_horizontal_m"],
        "fixes_rms_vertical_m": fixes["rms_vertical_m"],
        "unmoved_rms_horizontal_m": unmoved,
    }


def record(data_root: Path) -> dict[str, Any]:
    with tempfile.TemporaryDirectory() as out:
        summary = mn.navigate(EXAMPLE, data_root=data_root, output=Path(out) / "out").summary
    return figures_of(summary, data_root / "foreign-drive")


#: The INS-D's speed below which the car stands still, m/s; the shortest
#: standstill measured, s; the time left out at each end of one while the
#: car settles, s.
STANDSTILL_SPEED_M_S = 0.02
STANDSTILL_SHORTEST_S = 5.0
STANDSTILL_SETTLE_S = 1.0


def standstills(ref: dict[str, np.ndarray]) -> list[tuple[float, float]]:
    """The (start, end) times of the INS-D's standstills, settling left out."""
    speed = np.linalg.norm(np.column_stack([ref["vn_m_s"], ref["ve_m_s"], ref["vd_m_s"]]), axis=1)
    still = speed < STANDSTILL_SPEED_M_S
    runs = np.split(np.arange(len(still)), np.flatnonzero(np.diff(still.astype(int))) + 1)
    spans = [(ref["time_s"][r[0]], ref["time_s"][r[-1]]) for r in runs if still[r[0]]]
    return [
        (start + STANDSTILL_SETTLE_S, end - STANDSTILL_SETTLE_S)
        for start, end in spans
        if end - start >= STANDSTILL_SHORTEST_S
    ]


def _antenna_regression(
    errors: np.ndarray, forward_ned: np.ndarray, velocity_ned: np.ndarray | None
) -> np.ndarray:
    """Least squares of fix − INS-D point (N, E, D per fix) on a constant
    datum offset and a lever arm along the INS-D's forward axis, and with
    ``velocity_ned`` a fix latency too (fix = truth(t − latency)):
    [datum N, E, D m, lever arm m, (latency s)]. No stds: the fixes'
    errors are correlated over a minute or more, so the residuals' scatter
    would overstate what the fit knows."""
    columns = [np.tile(np.eye(3), (len(errors), 1)), forward_ned.reshape(-1, 1)]
    if velocity_ned is not None:
        columns.append(-velocity_ned.reshape(-1, 1))
    estimate, *_ = np.linalg.lstsq(np.hstack(columns), errors.reshape(-1), rcond=None)
    return estimate


def files_record(data_root: Path) -> dict[str, Any]:
    """What the foreign drive's files show, from the CSVs with numpy alone:
    the antenna's distance behind the INS-D's point from a regression of
    fix − INS-D point on the INS-D's forward axis (m; alone, and with a
    fix latency as a second unknown, s); at the standstills the VN-100's
    mean angular rate per axis (°/s, Earth rate included: at most
    0.004 °/s) and its specific force's scatter about its mean (m/s², the
    three axes' root sum square), and the F9T's east σ (median) against
    its east error (RMS, antenna at the example's 2.2 m, datum offset
    removed); the F9T's mean vertical velocity less the INS-D's (mm/s)."""
    folder = data_root / "foreign-drive"
    ref, fixes = _csv(folder / "insd_reference.csv"), _csv(folder / "f9t_fixes.csv")
    imu = _csv(folder / "vn100_imu.csv")
    span = (ref["time_s"][0], ref["time_s"][-1])
    time = fixes["time_s"]
    keep = (time >= span[0]) & (time <= span[1])
    time = time[keep]
    nearest = np.clip(np.searchsorted(ref["time_s"], time), 0, len(ref["time_s"]) - 1)
    forward_ned = _quaternion_matrix(ref["qw"], ref["qx"], ref["qy"], ref["qz"])[nearest][:, :, 0]
    velocity_ned = np.column_stack(
        [np.interp(time, ref["time_s"], ref[k]) for k in ("vn_m_s", "ve_m_s", "vd_m_s")]
    )
    at_point = independent(folder, span, 0.0)["errors"]
    alone = _antenna_regression(at_point, forward_ned, None)
    joint = _antenna_regression(at_point, forward_ned, velocity_ned)

    rests = standstills(ref)
    imu_time = imu["time_s"]
    rates, scatters = [], []
    for start, end in rests:
        inside = np.flatnonzero((imu_time > start) & (imu_time < end))
        interval = (imu_time[inside] - imu_time[inside - 1])[:, None]
        rate = np.column_stack([imu[f"dtheta_{a}_rad"][inside] for a in "xyz"]) / interval
        force = np.column_stack([imu[f"dv_{a}_m_s"][inside] for a in "xyz"]) / interval
        rates.append(np.degrees(rate.mean(axis=0)))
        scatters.append(float(np.sqrt(np.sum(force.var(axis=0)))))
    rates_deg_s = np.array(rates)

    at_antenna = independent(folder, span, LEVER_ARM_M)["less_offset"]
    at_rest = np.zeros(len(time), dtype=bool)
    for start, end in rests:
        at_rest |= (time > start) & (time < end)
    vertical_velocity_mm_s = 1e3 * np.mean(fixes["vd_m_s"][keep] - velocity_ned[:, 2])
    return {
        "antenna_behind_m": -float(alone[3]),
        "with_latency": {"antenna_behind_m": -float(joint[3]), "fix_latency_s": float(joint[4])},
        "standstills": len(rests),
        "gyro_rest_deg_s": {
            "mean": rates_deg_s.mean(axis=0).tolist(),
            "spread": float(np.max(np.ptp(rates_deg_s, axis=0))),
        },
        "vibration_m_s2": {"least": min(scatters), "most": max(scatters)},
        "rest_east_sigma_m": float(np.median(np.sqrt(fixes["cov_ee_m2"][keep][at_rest]))),
        "rest_east_error_rms_m": float(np.sqrt(np.mean(at_antenna[at_rest, 1] ** 2))),
        "moving_east_error_rms_m": float(np.sqrt(np.mean(at_antenna[~at_rest, 1] ** 2))),
        "vertical_velocity_bias_mm_s": float(vertical_velocity_mm_s),
    }
