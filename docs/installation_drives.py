"""Simulated drives with the installation as filter states (the antenna
lever arm, the IMU time offset, the fixes' velocity latency and the
mounting boresight), as docs/reference/configuration.md shows them:
``record`` gives the σ the states end with and what assuming the
installation zero costs, over :data:`CASES`. ``python docs/doc_runs.py
installation_states`` writes the record; ``tests/test_installation.py``
runs the same drives (:func:`installed_drive`, cached) for its own checks
and compares ``record`` with it."""

from __future__ import annotations

import functools
from pathlib import Path
from typing import Any

import numpy as np
from scipy.spatial.transform import Rotation

import memsnav as mn

NAMES = [
    "lever_arm_x",
    "lever_arm_y",
    "lever_arm_z",
    "time_offset",
    "velocity_latency",
    "mounting_pitch",
    "mounting_yaw",
]


@functools.lru_cache(maxsize=16)
def installed_drive(
    seed: int,
    lever_v: tuple[float, ...],
    time_offset: float,
    latency: float,
    mounting: tuple[float, ...],
    states: bool = True,
) -> tuple[Any, np.ndarray, dict[str, Any]]:
    """A 900 s drive from rest (heading unknown at the start) with an
    industrial-grade IMU mounted `mounting` (rad, vehicle-to-sensor
    rotation vector) off the vehicle axes, its time stamps `time_offset`
    s early (true time = stamp + offset), an antenna at `lever_v` (vehicle
    axes, m) and 1 Hz fixes (0.3 m, 0.05 m/s white noise) whose velocity is
    the antenna's `latency` s before their time. Returns the run, the
    truth in the filter's state order (lever arm in sensor axes) and the
    errors of the solution at the antenna (the run's lever arm: configured,
    or estimated) against the true antenna. Cached: the tests and the
    record run the same drives once."""
    trajectory = mn.Trajectory.random(900.0, seed=seed, stationary_start=20.0)
    t = trajectory.time
    rng = np.random.default_rng(seed)
    sensor_from_vehicle = Rotation.from_rotvec(mounting).as_matrix()
    f = (
        trajectory.specific_force @ sensor_from_vehicle.T
        + 0.01 * rng.normal(size=(len(t), 3))
        + 0.02 * rng.normal(size=3)
    )
    w = (
        trajectory.angular_rate @ sensor_from_vehicle.T
        + np.radians(0.02) * rng.normal(size=(len(t), 3))
        + np.radians(0.05) * rng.normal(size=3)
    )
    c = trajectory.attitude
    lever = np.asarray(lever_v)
    antenna = trajectory.position_ecef + np.einsum("nij,j->ni", c, lever)
    antenna_velocity = trajectory.velocity_ecef + np.einsum(
        "nij,nj->ni", c, np.cross(trajectory.angular_rate, lever)
    )
    k = np.arange(2000, len(t), 100)
    lag = round(latency * 100)
    geodetic = mn.ecef_to_geodetic(antenna[k])
    # A velocity into NED axes: the NED offset of the point one velocity
    # away (the rotation is linear).
    velocity_ned = np.array(
        [
            mn.ecef_to_ned(a + v, a)
            for a, v in zip(antenna[k], antenna_velocity[k - lag], strict=True)
        ]
    )
    fixes = mn.fixes_from_solution(
        t[k],
        geodetic,
        np.full((len(k), 3), 0.3),
        velocity_ned=velocity_ned,
        velocity_std_ned=np.full((len(k), 3), 0.05),
        added_position_noise_ned=[0.3, 0.3, 0.3],
        added_velocity_noise=0.05,
        seed=seed,
    )
    settings = {
        # A vibration-free simulated IMU: no standstill detection.
        "aids": {"zupt": False, "zaru": False, "nhc": True},
        # The study the navigate guide quotes: the consumer preset, the
        # fixes as white noise (what the log would teach is left out).
        "filter": {"installation_states": states, "imu_preset": "consumer"},
        "gnss": {"fix_error_states": False},
        "outages": {"windows_s": [[400.0, 30.0]]},
    }
    run = mn.navigate_log(t - time_offset, f, w, fixes, settings=settings)
    truth = np.concatenate(
        [sensor_from_vehicle @ lever, [time_offset, latency], np.asarray(mounting)[1:]]
    )
    score = run.score(t[k], antenna[k])
    return run, truth, score


# Long and short lever arms, time offsets of either sign, 0.2 s latency,
# mountings a few degrees off (the installation states' ranges).
CASES = [
    (seed, lever, offset, tuple(float(x) for x in np.radians(mounting_deg)))
    for seed, lever, offset, mounting_deg in (
        (1, (-2.0, 0.3, -1.2), 0.04, (1.0, 2.0, -3.0)),
        (2, (-2.0, 0.3, -1.2), 0.04, (1.0, 2.0, -3.0)),
        (3, (-0.6, 0.3, -0.4), -0.05, (-1.0, -2.5, 2.0)),
        (4, (-0.6, 0.3, -0.4), -0.05, (-1.0, -2.5, 2.0)),
    )
]


LATENCY_S = 0.2
"""The fixes' velocity latency of every case, s."""


def case_drive(
    case: tuple[Any, ...], states: bool = True
) -> tuple[Any, np.ndarray, dict[str, Any]]:
    """:func:`installed_drive` of one of :data:`CASES`."""
    seed, lever, offset, mounting = case
    return installed_drive(seed, lever, offset, LATENCY_S, mounting, states)


def final_sigma(run: Any) -> np.ndarray:
    """The σ of the installation states at the end of ``run``, in
    :data:`NAMES` order (m, s, rad)."""
    solution = run.solution
    columns = [solution.state_names.index(n) for n in NAMES]
    return np.sqrt(np.asarray(solution.covariance_diagonal)[-1][columns])


def _span(values: list[float]) -> dict[str, float]:
    return {"least": float(min(values)), "most": float(max(values))}


def record(data_root: Path | None = None) -> dict[str, Any]:
    """The final σ of each group of states over :data:`CASES` (least and
    most: horizontal lever arm m, vertical m, time offset ms, latency ms,
    boresight °), and the same drives with the installation assumed zero:
    the share of aided errors outside 3σ (%), the mean 30 s outage RMS
    (m) without and with the states."""
    sigmas = [final_sigma(case_drive(case)[0]) for case in CASES]
    assumed = [case_drive(case, states=False)[2] for case in CASES]
    estimated = [case_drive(case)[2] for case in CASES]
    return {
        "sigma": {
            "horizontal_lever_arm_m": _span([v for s in sigmas for v in s[:2]]),
            "vertical_lever_arm_m": _span([s[2] for s in sigmas]),
            "time_offset_ms": _span([1e3 * s[3] for s in sigmas]),
            "latency_ms": _span([1e3 * s[4] for s in sigmas]),
            "boresight_deg": _span([float(np.degrees(v)) for s in sigmas for v in s[5:]]),
        },
        "assumed_outside_3sigma_pct": _span(
            [100.0 * (1.0 - s["aided"]["within_3sigma_share"]) for s in assumed]
        ),
        "assumed_outage_rms_m": float(
            np.mean([s["in_outages"]["rms_horizontal_m"] for s in assumed])
        ),
        "estimated_outage_rms_m": float(
            np.mean([s["in_outages"]["rms_horizontal_m"] for s in estimated])
        ),
    }
