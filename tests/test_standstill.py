"""Standstills seen by the sensors in a GNSS outage: a car that
stops while its solution coasts on. The IMU shows the quiet of a car at rest;
the solution's speed, drifted metres per second away from zero, must not veto
it when the filter's own velocity σ cannot tell that speed from zero."""

from __future__ import annotations

import doc_runs
import numpy as np
from figures import figures

import memsnav as mn


def test_a_stop_in_an_outage_is_seen_by_the_sensors_and_bounds_the_error():
    trajectory, runs, (stop_start, stop_end), figures_now = doc_runs.stop_and_go_runs()
    t = trajectory.time
    # The default sees the stop: a standstill inside it (within the
    # detector's 1 s window of its ends), none while moving.
    stills = [(a, b) for a, b in runs[3.0].standstills if a > t[0] + 40.0]
    assert len(stills) == 1
    assert stop_start <= stills[0][0] < stop_start + 1.5
    assert stop_end - 1.0 < stills[0][1] <= stop_end + 1.5
    # Its zero-velocity updates pass their batch test and hold the coast:
    # metres at the end of the outage, where the solution-speed veto alone
    # (0 sigmas: the previous rule) lets the stopped car drive on for
    # hundreds of metres.
    m = runs[3.0].solution.measurements
    zupt = (np.asarray(m["kind"]) == "zero_velocity") & (np.asarray(m["time"]) > stop_start)
    assert np.mean(np.asarray(m["status"])[zupt] == "accepted") > 0.95
    assert not any(a > t[0] + 40.0 for a, _ in runs[0.0].standstills)
    error_with, error_without = figures_now["error_with_stop_m"], figures_now["error_without_m"]
    assert error_with < 20.0 < 100.0 < error_without, figures_now
    # The configuration reference shows this run's record.
    recorded = figures("stop_and_go")
    for key, value in figures_now.items():
        assert abs(value - recorded[key]) <= 1e-9 * max(1.0, abs(value)), (key, value)


def test_braking_smoothly_to_a_stop_is_not_taken_for_one():
    """A car that rolls to a stop in a GNSS outage (12 m/s to 0 in 20 s), its
    IMU as quiet below 3 m/s as at rest: for its last two seconds its speed
    is under the detector's 1 m/s and the variance test cannot tell it from
    rest. Its mean specific force can, against the tilt and bias
    uncertainty of an industrial-grade IMU's filter 25 s into the outage
    (at 0.5 m/s the car still decelerates at 0.4 m/s²; a consumer-grade
    filter's tilt uncertainty there is several times larger, and the test
    with it): no zero-velocity update is applied while the car moves faster
    than 0.2 m/s, and the stop itself is held (its ZUPTs accepted)."""
    trajectory = mn.Trajectory.from_segments(
        [
            ("stop", 30.0),
            ("accelerate", 10.0, 12.0),
            ("cruise", 30.0),
            ("accelerate", 20.0, 0.0),
            ("stop", 20.0),
            ("accelerate", 10.0, 12.0),
            ("cruise", 20.0),
        ]
    )
    t = trajectory.time
    rng = np.random.default_rng(11)
    speed = np.linalg.norm(trajectory.velocity_ecef, axis=1)
    # An industrial-grade IMU: 0.3 m/s² and 0.3 °/s of vibration when
    # rolling faster than 3 m/s, 0.1 and 0.1 slower and at rest.
    rolling = speed > 3.0
    accel_std = np.where(rolling, 0.3, 0.1)[:, None]
    gyro_std = np.radians(np.where(rolling, 0.3, 0.1))[:, None]
    f = trajectory.specific_force + accel_std * rng.normal(size=(len(t), 3)) + [0.01, -0.02, 0.01]
    w = trajectory.angular_rate + gyro_std * rng.normal(size=(len(t), 3)) + np.radians(0.03)
    k = np.arange(0, len(t), 100)
    fixes = mn.fixes_from_solution(
        t[k],
        trajectory.position_geodetic()[k],
        np.full((len(k), 3), 0.5),
        velocity_ned=trajectory.velocity_ned()[k],
        velocity_std_ned=np.full((len(k), 3), 0.05),
        added_position_noise_ned=[0.5, 0.5, 0.5],
        added_velocity_noise=0.05,
        seed=11,
    )
    braking_starts = 30.0 + 10.0 + 30.0
    settings = {
        # From 10 s before the braking to 5 s into the stop (the first
        # fix, the start, is at the trajectory's first sample).
        "outages": {"windows_s": [[braking_starts - 10.0, 35.0]]},
        "aids": {"nhc": True},
        # The vibration as the filter's white noise (per √s at 100 Hz).
        "filter": {
            "imu_preset": "industrial",
            "accel_noise_density": 0.03,
            "gyro_noise_density_deg": 0.03,
        },
    }
    run = mn.navigate_log(t, f, w, fixes, settings=settings)
    m = run.solution.measurements
    kind, status = np.asarray(m["kind"]), np.asarray(m["status"])
    when = np.asarray(m["time"])
    applied = (kind == "zero_velocity") & (status == "accepted")
    true_speed = np.interp(when, t, speed)
    moving_zupts = applied & (true_speed > 0.2) & (when > t[0] + braking_starts)
    assert not moving_zupts.any(), when[moving_zupts]
    stop = (when > t[0] + braking_starts + 21.0) & (when < t[0] + braking_starts + 40.0)
    stop &= kind == "zero_velocity"
    assert np.mean(status[stop] == "accepted") > 0.9
