"""Time-correlated fix errors in loose coupling: a receiver's
standalone fixes err slowly, and a filter that takes their errors for white
noise averages them and reports bounds below the fixes' own. With
``[gnss] fix_error_states`` the fixes' position error is a first-order
Gauss-Markov state per ECEF axis and the aided bounds hold."""

from __future__ import annotations

import re

import numpy as np
import pytest
from doc_pages import NAVIGATE_GUIDE, doc_text

import memsnav as mn

EARTH_RADIUS_M = 6378137.0


def _drive_with_slow_fix_errors(seed: int, tau_s: float = 60.0, slow_m: float = 1.0):
    """A 600 s drive, a MEMS-grade IMU, 1 Hz fixes whose N/E/D errors are a
    Gauss-Markov process (``slow_m``, ``tau_s``) plus 0.3 m white noise,
    reported with their total σ (as a receiver reports its fixes)."""
    trajectory = mn.Trajectory.random(600.0, seed=seed, stationary_start=20.0)
    t = trajectory.time
    rng = np.random.default_rng(seed)
    f = trajectory.specific_force + 0.02 * rng.normal(size=(len(t), 3)) + 0.05 * rng.normal(size=3)
    w = (
        trajectory.angular_rate
        + np.radians(0.1) * rng.normal(size=(len(t), 3))
        + np.radians(0.2) * rng.normal(size=3)
    )
    k = np.arange(0, len(t), 100)
    phi = np.exp(-1.0 / tau_s)
    error = np.zeros((len(k), 3))
    error[0] = slow_m * rng.normal(size=3)
    for i in range(1, len(k)):
        error[i] = phi * error[i - 1] + slow_m * np.sqrt(1 - phi**2) * rng.normal(size=3)
    error += 0.3 * rng.normal(size=(len(k), 3))
    lla = trajectory.position_geodetic()[k].copy()
    # North, east, down metres to latitude, longitude, height (the sphere's
    # radius: a 0.3 % scale error of a metre-level error).
    lla[:, 0] += error[:, 0] / EARTH_RADIUS_M
    lla[:, 1] += error[:, 1] / (EARTH_RADIUS_M * np.cos(lla[:, 0]))
    lla[:, 2] -= error[:, 2]
    fixes = mn.fixes_from_solution(
        t[k],
        lla,
        np.full((len(k), 3), np.hypot(slow_m, 0.3)),
        velocity_ned=trajectory.velocity_ned()[k],
        velocity_std_ned=np.full((len(k), 3), 0.1),
        added_velocity_noise=0.1,
        seed=seed,
    )
    return trajectory, f, w, fixes, k


@pytest.mark.parametrize("seed", [1, 2])
def test_fix_error_states_keep_the_aided_bounds(seed):
    trajectory, f, w, fixes, k = _drive_with_slow_fix_errors(seed)
    share, run, rms = {}, {}, {}
    for states in (False, True):
        settings = {
            # A vibration-free simulated IMU: no standstill detection.
            "aids": {"zupt": False, "zaru": False, "nhc": True},
            # Without the states, the fixes as white noise (not the
            # correlation learnt from the log: tests/test_adaptation.py).
            "gnss": {"fix_error_states": states},
            "outages": {"windows_s": [[200.0, 30.0]]},
        }
        run[states] = mn.navigate_log(trajectory.time, f, w, fixes, settings=settings)
        score = run[states].score(trajectory.time[k], trajectory.position_ecef[k])
        share[states] = (score["aided"]["within_3sigma_share"], score["in_outages"])
        rms[states] = score["aided"]["rms_horizontal_m"]
    # White noise: bounds below the fixes' own error (about 2/3 inside 3σ);
    # the Gauss-Markov states: at least 0.9, in the outage too.
    assert share[False][0] < 0.8, share
    assert share[True][0] >= 0.9, share
    assert share[True][1]["within_3sigma_share"] >= 0.9, share
    # the navigate guide quotes both seeds' shares and RMS as ranges.
    page = " ".join(doc_text(*NAVIGATE_GUIDE).split())
    quoted = re.search(
        r"the aided share of errors inside 3σ is ([\d.]+) without the states and ([\d.]+)-([\d.]+) "
        r"with them, the aided horizontal RMS ([\d.]+)-([\d.]+) m without and ([\d.]+)-([\d.]+) m",
        page,
    )
    assert quoted, "the navigate guide no longer quotes the fix-error states' effect"
    white, low, high, rms_low, rms_high, states_low, states_high = map(float, quoted.groups())
    assert round(share[False][0], 2) == white, share
    assert low <= round(share[True][0], 2) <= high, share
    assert rms_low <= round(rms[False], 1) <= rms_high, rms
    assert states_low <= round(rms[True], 1) <= states_high, rms
    # Three of the twelve slots, one per ECEF axis, with metre-level estimates.
    errors = run[True].range_biases
    assert sorted(errors) == [0, 1, 2]
    assert all(abs(v) < 4.0 for v in errors.values())
    assert not run[False].range_biases
