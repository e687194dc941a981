"""What a navigate run learns from its log (``navigate/adapt.rs``): the IMU
grade its GNSS innovations support, and how slowly its fixes' errors change.
Each check runs on a simulated drive whose IMU grade and fix errors are
known, so the learnt values are compared with the ones the data were drawn
from."""

from __future__ import annotations

import numpy as np
import pytest

import memsnav as mn
from memsnav import _memsnav

EARTH_RADIUS_M = 6378137.0
# A vibration-free simulated IMU: no standstill detection; a car: NHC.
AIDS = {"zupt": False, "zaru": False, "nhc": True}


def _drive(seed: int, duration_s: float = 600.0):
    return mn.Trajectory.random(duration_s, seed=seed, stationary_start=20.0)


def _fixes(trajectory, k, errors_ned, std_m, seed):
    """1 Hz fixes at the epochs ``k`` with the given N/E/D errors, reported
    with the one-sigma ``std_m``, velocities with 0.05 m/s noise."""
    lla = trajectory.position_geodetic()[k].copy()
    lla[:, 0] += errors_ned[:, 0] / EARTH_RADIUS_M
    lla[:, 1] += errors_ned[:, 1] / (EARTH_RADIUS_M * np.cos(lla[:, 0]))
    lla[:, 2] -= errors_ned[:, 2]
    return mn.fixes_from_solution(
        trajectory.time[k],
        lla,
        np.full((len(k), 3), std_m),
        velocity_ned=trajectory.velocity_ned()[k],
        velocity_std_ned=np.full((len(k), 3), 0.05),
        added_velocity_noise=0.05,
        seed=seed,
    )


def _gauss_markov(rng, n, std_m, tau_s, dt_s=1.0):
    phi = np.exp(-dt_s / tau_s)
    x = np.zeros((n, 3))
    x[0] = std_m * rng.normal(size=3)
    for i in range(1, n):
        x[i] = phi * x[i - 1] + std_m * np.sqrt(1 - phi**2) * rng.normal(size=3)
    return x


@pytest.mark.parametrize(("grade", "seed"), [("industrial", 4), ("consumer", 5)])
def test_the_imu_grade_is_the_one_the_readings_come_from(grade, seed):
    """Readings drawn from a preset's error model (biases, scale factors,
    misalignments, noise); 1 Hz fixes with 0.5 m white errors. The run that
    names no preset chooses the grade the readings come from."""
    trajectory = _drive(seed)
    imu = mn.ImuModel.preset(grade, seed=seed, sample_rate=100.0)
    f, w = imu.measure(trajectory.specific_force, trajectory.angular_rate, seed=seed)
    k = np.arange(0, len(trajectory.time), 100)
    rng = np.random.default_rng(seed)
    fixes = _fixes(trajectory, k, 0.5 * rng.normal(size=(len(k), 3)), 0.5, seed)
    run = mn.navigate_log(trajectory.time, f, w, fixes, settings={"aids": AIDS})
    adaptation = run.adaptation
    assert adaptation["imu_preset"] == grade, adaptation["imu_candidates"]
    scores = {c["preset"]: c["log_likelihood"] for c in adaptation["imu_candidates"]}
    assert list(scores) == ["consumer", "industrial", "tactical"]
    # The tactical model is far too tight for either MEMS grade.
    assert scores["tactical"] < scores[grade] - 50.0, scores
    # A named preset is used as it is: no first pass per grade.
    named = mn.navigate_log(
        trajectory.time,
        f,
        w,
        fixes,
        settings={"aids": AIDS, "filter": {"imu_preset": grade}},
    )
    assert named.adaptation["imu_preset"] is None
    assert named.adaptation["imu_candidates"] == []


def test_the_fixes_correlation_time_is_learnt_and_the_bounds_hold():
    """Fixes whose errors are a Gauss-Markov process (0.8 m, τ = 40 s) plus
    0.1 m white noise, reported with their total σ. Learnt: a correlation
    time of the order of τ (the method reads it conservatively: from τ to
    its 120 s bound) and a variance ratio of at least 1 (an upper bound:
    the dead reckoning's share of the innovations counts as the fixes'),
    modelled as fix-error states of the fixes' σ times √ratio; the aided
    errors then lie inside the forward filter's 3σ, where the white-noise
    filter (``fix_error_states = false``) leaves a third outside."""
    tau_s, slow_m = 40.0, 0.8
    trajectory = _drive(6, 900.0)
    imu = mn.ImuModel.preset("industrial", seed=6, sample_rate=100.0)
    f, w = imu.measure(trajectory.specific_force, trajectory.angular_rate, seed=6)
    k = np.arange(0, len(trajectory.time), 100)
    rng = np.random.default_rng(6)
    errors = _gauss_markov(rng, len(k), slow_m, tau_s) + 0.1 * rng.normal(size=(len(k), 3))
    fixes = _fixes(trajectory, k, errors, np.hypot(slow_m, 0.1), 6)
    # The installation states, as for any car with the non-holonomic
    # constraint: the simulated IMU's misalignment tilts its axes off the
    # car's, and a pitch nobody estimates bends the height away from fixes
    # the states no longer hold it to.
    settings = {
        "aids": AIDS,
        "filter": {"imu_preset": "industrial", "installation_states": True},
    }
    learnt = mn.navigate_log(trajectory.time, f, w, fixes, settings=settings)
    white = mn.navigate_log(
        trajectory.time,
        f,
        w,
        fixes,
        settings={**settings, "gnss": {"fix_error_states": False}},
    )
    correlation = learnt.adaptation["fix_correlation"]
    assert 0.8 * tau_s <= correlation["correlation_time_s"] <= 120.0, correlation
    # Two or three components read (one may be the dead reckoning's).
    assert sum(c is not None for c in correlation["component_s"]) >= 2, correlation
    assert 1.0 <= correlation["variance_ratio"] <= 2.0, correlation
    states = learnt.adaptation
    assert states["fix_error_correlation_time_s"] == correlation["correlation_time_s"]
    # Every fix reports the same σ per axis: the typical σ is that σ.
    expected_std_m = np.hypot(slow_m, 0.1) * np.sqrt(correlation["variance_ratio"])
    assert states["fix_error_std_m"] == pytest.approx(expected_std_m, rel=1e-9)
    assert white.adaptation["fix_correlation"] is None
    assert white.adaptation["fix_error_std_m"] is None
    truth_t, truth_r = trajectory.time[k], trajectory.position_ecef[k]
    inside = {
        name: run.score(truth_t, truth_r)["aided"]["within_3sigma_share"]
        for name, run in (("learnt", learnt), ("white", white))
    }
    assert inside["learnt"] >= 0.9 > 0.8 > inside["white"], inside


def test_fixes_more_precise_than_the_dead_reckoning_stay_white():
    """RTK-like fixes (2 cm white at 4 Hz) on a consumer IMU: between fixes
    the dead reckoning errs more than the fixes, so their correlation cannot
    be read off the innovations, and the fixes are taken as white."""
    trajectory = _drive(7, 300.0)
    imu = mn.ImuModel.preset("consumer", seed=7, sample_rate=100.0)
    f, w = imu.measure(trajectory.specific_force, trajectory.angular_rate, seed=7)
    k = np.arange(0, len(trajectory.time), 25)
    rng = np.random.default_rng(7)
    fixes = _fixes(trajectory, k, 0.02 * rng.normal(size=(len(k), 3)), 0.02, 7)
    run = mn.navigate_log(trajectory.time, f, w, fixes, settings={"aids": AIDS})
    correlation = run.adaptation["fix_correlation"]
    assert correlation["component_s"] == [None, None, None], correlation
    assert min(correlation["innovation_to_fix_variance"]) > 2.0
    assert correlation["correlation_time_s"] == 0.0
    assert run.adaptation["fix_error_std_m"] is None
    assert run.adaptation["fix_error_correlation_time_s"] is None


def test_adaptation_settings_are_checked():
    for key, value in (
        ("fix_correlation_time_s", -1.0),
        ("fix_correlation_time_s", "auto"),
        ("fix_correlation_time_s", True),
        ("fix_error_states", "sometimes"),
        ("fix_error_states", 1.0),
    ):
        with pytest.raises(ValueError, match=rf"gnss\.{key}"):
            _memsnav.check_navigate_settings({"gnss": {key: value}})
    with pytest.raises(ValueError, match=r"filter\.imu_preset"):
        _memsnav.check_navigate_settings({"filter": {"imu_preset": "automatic"}})
    for states in ("auto", True, False):
        _memsnav.check_navigate_settings(
            {"gnss": {"fix_error_states": states}, "filter": {"imu_preset": "auto"}}
        )
