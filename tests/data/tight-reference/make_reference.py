"""Writes tight_reference.npz: the tightly coupled filter's output on a short
seeded scenario, for tests/test_tight_reference.py. First written at commit
162d5d4 (before the AVX2/FMA propagation kernels); rewritten for
the few-satellite filter model, which changes the output on purpose (the rate row's
position term, the input-shaped noise of the unmodelled sensor errors, the
random-walk bias, the simulator's clock model).

    python tests/data/tight-reference/make_reference.py

Scenario: 60 s random land trajectory at 100 Hz, the paper's MEMS IMU,
6 satellites at 1 Hz (pseudorange + rate), seed 2017; forward and smoothed
solutions, every 25th IMU epoch stored (the filter's whole history feeds
every stored epoch, so the subsample still checks every step).
"""

from __future__ import annotations

from pathlib import Path

import numpy as np

import memsnav as mn

SEED = 2017
DURATION_S = 60.0
RATE_HZ = 100.0
STRIDE = 25
FIELDS = (
    "position_ecef",
    "velocity_ecef",
    "attitude",
    "accel_bias",
    "gyro_bias",
    "clock_offset",
    "clock_drift",
    "covariance_diagonal",
)


def scenario() -> tuple[mn.ImuModel, tuple]:
    """The seeded inputs of the reference run (also used by the test)."""
    traj = mn.Trajectory.random(DURATION_S, RATE_HZ, seed=SEED)
    imu = mn.ImuModel.preset("paper-mems", seed=SEED)
    acc, gyr = imu.measure(traj.specific_force, traj.angular_rate, seed=SEED)
    gnss = mn.simulate_gnss(
        traj.time,
        traj.position_ecef,
        traj.velocity_ecef,
        mn.Constellation.walker(),
        n_satellites=6,
        seed=SEED,
    )
    return imu, (traj.time, acc, gyr, gnss, traj.attitude[0])


def solution_arrays() -> dict[str, np.ndarray]:
    """Forward and smoothed fields of the reference run, subsampled."""
    imu, (time, acc, gyr, gnss, attitude0) = scenario()
    sol = mn.TightlyCoupledFilter(imu).run(
        time, acc, gyr, gnss, initial_attitude=attitude0, smooth=True
    )
    smoothed = sol.smoothed
    assert smoothed is not None
    out = {}
    for name in FIELDS:
        out[f"forward_{name}"] = np.asarray(getattr(sol, name))[::STRIDE]
        out[f"smoothed_{name}"] = np.asarray(getattr(smoothed, name))[::STRIDE]
    return out


if __name__ == "__main__":
    path = Path(__file__).with_name("tight_reference.npz")
    np.savez_compressed(path, **solution_arrays())
    print(f"wrote {path} ({path.stat().st_size} bytes)")
