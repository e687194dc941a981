"""Writes simulator_reference.npz: the simulator's output on seeded inputs,
produced by memsnav at commit d3cd6a2 (the simulator before its
speed-up), for tests/test_simulator_reference.py.

    python tests/data/simulator-reference/make_reference.py

Stored: the reference workload's 600 s random trajectory (seed 2008, every
97th sample: the position is integrated, so every stored sample depends on
every step before it), its paper-mems IMU readings and 6-satellite GNSS
(every 7th epoch); a 20 s random trajectory with a stationary start and a
scripted one at every 5th sample; the 60 s Groves profile Profile_1.csv at
100 Hz, every 13th sample (only when the data root holds it: ``$MEMSNAV_DATA_ROOT``, else
``shared/data`` beside the checkout).
"""

from __future__ import annotations

from pathlib import Path

import numpy as np

import memsnav as mn
from memsnav.realdata.config import resolve_data_root

SEED = 2008
STRIDE = 97
GNSS_STRIDE = 7
TRAJECTORY_FIELDS = (
    "time",
    "position_ecef",
    "velocity_ecef",
    "attitude",
    "specific_force",
    "angular_rate",
)
GNSS_FIELDS = (
    "time",
    "sat_id",
    "satellite_position_ecef",
    "satellite_velocity_ecef",
    "pseudorange",
    "pseudorange_rate",
    "pseudorange_std",
    "pseudorange_rate_std",
)
SEGMENTS = [
    ("accelerate", 5.0, 15.0),
    ("turn", 6.0, 1.2),
    ("climb", 4.0, 0.03),
    ("cruise", 2.0),
    ("turn", 3.0, -0.8),
    ("stop", 4.0),
]


def profile_path() -> Path | None:
    """Profile_1.csv under the project's data root, if it is there."""
    path = resolve_data_root(Path(__file__)) / "trajectories" / "Profile_1.csv"
    return path if path.is_file() else None


def trajectory_arrays(prefix: str, traj: mn.Trajectory, stride: int) -> dict[str, np.ndarray]:
    return {f"{prefix}.{f}": np.asarray(getattr(traj, f))[::stride] for f in TRAJECTORY_FIELDS}


def simulator_arrays() -> dict[str, np.ndarray]:
    """What the simulator produces on the seeded inputs, subsampled."""
    out: dict[str, np.ndarray] = {}
    traj = mn.Trajectory.random(600.0, 100.0, seed=SEED)
    out |= trajectory_arrays("random600", traj, STRIDE)
    imu = mn.ImuModel.preset("paper-mems", seed=SEED)
    acc, gyr = imu.measure(traj.specific_force, traj.angular_rate, seed=SEED)
    out["imu.specific_force"] = acc[::STRIDE]
    out["imu.angular_rate"] = gyr[::STRIDE]
    gnss = mn.simulate_gnss(
        traj.time,
        traj.position_ecef,
        traj.velocity_ecef,
        mn.Constellation.walker(),
        n_satellites=6,
        seed=SEED,
    )
    for f in GNSS_FIELDS:
        out[f"gnss.{f}"] = np.asarray(getattr(gnss, f))[::GNSS_STRIDE]
    short = mn.Trajectory.random(20.0, 100.0, seed=SEED + 1, stationary_start=3.0)
    out |= trajectory_arrays("random20", short, 5)
    out |= trajectory_arrays("segments", mn.Trajectory.from_segments(SEGMENTS), 5)
    path = profile_path()
    if path is not None:
        out |= trajectory_arrays("profile1", mn.Trajectory.from_profile(path), 13)
    return out


if __name__ == "__main__":
    arrays = simulator_arrays()
    assert any(k.startswith("profile1.") for k in arrays), "no Profile_1.csv under the data root"
    np.savez_compressed(Path(__file__).parent / "simulator_reference.npz", **arrays)
