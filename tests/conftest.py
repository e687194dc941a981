"""Shared fixtures."""

import importlib.util
from pathlib import Path

import numpy as np
import pytest

import memsnav as mn


@pytest.fixture(scope="session")
def drive_300s():
    """A 300 s random drive, its simulated GNSS (Walker constellation), an
    IMU with random biases and white noise only (the 17 error states model
    it exactly) and its readings: (trajectory, gnss, imu, f, w)."""
    traj = mn.Trajectory.random(duration=300.0, seed=3)
    sky = mn.Constellation.walker()
    gnss = mn.simulate_gnss(traj.time, traj.position_ecef, traj.velocity_ecef, sky, seed=4)
    rng = np.random.default_rng(5)
    z3, z33 = np.zeros(3), np.zeros((3, 3))
    acc = mn.AccelerometerModel(rng.normal(0, 0.03, 3), z3, z33, z3, noise_density=2e-3)
    gyr = mn.GyroscopeModel(rng.normal(0, 2e-4, 3), z3, z33, z33, noise_density=2e-4)
    imu = mn.ImuModel(acc, gyr)
    f, w = imu.measure(traj.specific_force, traj.angular_rate, seed=6)
    return traj, gnss, imu, f, w


@pytest.fixture(scope="session")
def reference_script():
    """Loads a stored reference's writer, ``tests/data/<folder>/make_reference.py``
    (the tests compare against its arrays): ``reference_script(folder)``."""

    def load(folder: str):
        path = Path(__file__).parent / "data" / folder / "make_reference.py"
        spec = importlib.util.spec_from_file_location(f"make_{folder}", path)
        assert spec is not None and spec.loader is not None
        module = importlib.util.module_from_spec(spec)
        spec.loader.exec_module(module)
        return module

    return load
