"""In-run sensor error states: on simulated drives with known
biases and scale factors, the tight filter's 23-state estimates end within
their own one-sigma of the truth, as a chi-square test over seeds says, and
the observable ones (gyro z scale factor through the turns) are learnt.

The truth is written in the filter's convention, f̃ = (1 + s) f + b per
axis, by fitting a straight line to the noise-free sensor output against
the exact input: independent of how the filter or the sensor model are
parameterised (the sensor model of method §2 has S = (I − D)(Γ − b))."""

from __future__ import annotations

import numpy as np
import pytest
from scipy import stats

import memsnav as mn

ZERO3, ZERO33 = np.zeros(3), np.zeros((3, 3))
ACCEL_BIAS, ACCEL_SCALE = np.array([0.05, -0.04, 0.06]), np.array([3e-3, -2e-3, 4e-3])
GYRO_BIAS, GYRO_SCALE = np.array([1e-3, -8e-4, 6e-4]), np.array([5e-3, -4e-3, 6e-3])
SENSOR_STATES = ("accel_bias", "accel_scale_factor", "gyro_bias", "gyro_scale_factor")


def _imu(noisy: bool) -> mn.ImuModel:
    accel = mn.AccelerometerModel(
        ACCEL_BIAS, ACCEL_SCALE, ZERO33, ZERO3, noise_density=2e-3 if noisy else None
    )
    gyro = mn.GyroscopeModel(
        GYRO_BIAS, GYRO_SCALE, ZERO33, ZERO33, noise_density=2e-4 if noisy else None
    )
    return mn.ImuModel(accel, gyro)


def _truth_in_filter_convention(truth: mn.Trajectory) -> dict[str, np.ndarray]:
    accel, gyro = _imu(noisy=False).measure(truth.specific_force, truth.angular_rate, seed=0)
    out = {}
    for name, measured, exact in (
        ("accel", accel, truth.specific_force),
        ("gyro", gyro, truth.angular_rate),
    ):
        line = np.array([np.polyfit(exact[:, i], measured[:, i], 1) for i in range(3)])
        out[f"{name}_scale_factor"] = line[:, 0] - 1.0
        out[f"{name}_bias"] = line[:, 1]
    return out


@pytest.fixture(scope="module")
def normalised_errors():
    """(z = (estimate − truth)/σ at the end, σ_end/σ_start) per seed and state."""
    runs = []
    for seed in range(3):
        truth = mn.Trajectory.random(duration=600.0, seed=20 + seed)
        gnss = mn.simulate_gnss(
            truth.time,
            truth.position_ecef,
            truth.velocity_ecef,
            mn.Constellation.walker(),
            seed=40 + seed,
        )
        imu = _imu(noisy=True)
        accel, gyro = imu.measure(truth.specific_force, truth.angular_rate, seed=60 + seed)
        solution = mn.TightlyCoupledFilter(imu, scale_factor_states=True).run(
            truth.time, accel, gyro, gnss, initial_attitude=truth.attitude[0]
        )
        exact = _truth_in_filter_convention(truth)
        variance = np.asarray(solution.covariance_diagonal)
        run = {}
        for state in SENSOR_STATES:
            columns = [solution.state_names.index(f"{state}_{a}") for a in "xyz"]
            sigma_end = np.sqrt(variance[-1, columns])
            error = np.asarray(getattr(solution, state))[-1] - exact[state]
            run[state] = (error / sigma_end, sigma_end / np.sqrt(variance[0, columns]))
        runs.append(run)
    return runs


def test_sensor_states_end_within_their_sigma(normalised_errors):
    z = np.concatenate([run[s][0] for run in normalised_errors for s in SENSOR_STATES])
    # Σz² over 36 components is chi-square with 36 degrees of freedom if
    # the filter's σ are honest (components are correlated within a run, so
    # the band is wide: 0.5 % tails).
    low, high = stats.chi2.ppf([0.005, 0.995], z.size)
    assert low < np.sum(z**2) < high, np.round(z, 2)
    assert np.all(np.abs(z) < 3.5)


def test_observable_sensor_states_are_learnt(normalised_errors):
    for run in normalised_errors:
        # Heading changes make the gyro z scale factor observable; the
        # horizontal gyro biases through the attitude the fixes determine.
        assert run["gyro_scale_factor"][1][2] < 0.5
        assert np.all(run["gyro_bias"][1][:2] < 0.05)
        # Accelerating along the track: the x accelerometer scale factor.
        assert run["accel_scale_factor"][1][0] < 0.7
