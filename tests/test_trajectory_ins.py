"""Trajectories and the strapdown INS from Python: closure on every kind of
trajectory and on a motion written here in closed form, the increment form,
limits, reproducibility and bad input."""

import math
import time
from pathlib import Path

import numpy as np
import pytest
from shared_data import shared_data

import memsnav as mn

OMEGA_IE = 7.292115e-5  # rad/s, WGS84


def profile(name: str) -> Path:
    return shared_data(f"trajectories/{name}")


def run(tr: mn.Trajectory, **kwargs: str) -> mn.NavSolution:
    return mn.strapdown(
        tr.time,
        tr.specific_force,
        tr.angular_rate,
        tr.position_ecef[0],
        tr.velocity_ecef[0],
        tr.attitude[0],
        **kwargs,
    )


def max_position_error(nav: mn.NavSolution, position: np.ndarray) -> float:
    return float(np.linalg.norm(nav.position_ecef - position, axis=1).max())


def test_random_trajectory_closes_and_reports_speed():
    t0 = time.perf_counter()
    tr = mn.Trajectory.random(duration=600.0, rate=100.0, seed=0)
    generated = time.perf_counter() - t0
    t0 = time.perf_counter()
    nav = run(tr)
    elapsed = time.perf_counter() - t0
    error = max_position_error(nav, tr.position_ecef)
    print(
        f"random 600 s: generated in {generated:.3f} s, strapdown {len(tr) / elapsed:.3g} "
        f"epochs/s, closure {error:.2e} m"
    )
    assert len(tr) == len(nav) == 60001
    assert tr.time[-1] == pytest.approx(600.0)
    assert error < 0.1
    # The two-sample step the filters chain closes too, to second order.
    assert max_position_error(run(tr, scheme="trapezoid"), tr.position_ecef) < 0.3
    # Attitude returned as proper rotations.
    c = nav.attitude[-1]
    np.testing.assert_allclose(c.T @ c, np.eye(3), atol=1e-12)
    np.testing.assert_allclose(c, tr.attitude[-1], atol=1e-6)


def rodrigues(v: np.ndarray) -> np.ndarray:
    """Rotation matrix of a rotation vector, written out here."""
    angle = np.linalg.norm(v)
    k = np.array([[0, -v[2], v[1]], [v[2], 0, -v[0]], [-v[1], v[0], 0]]) / angle
    return np.eye(3) + math.sin(angle) * k + (1 - math.cos(angle)) * k @ k


def test_closes_on_a_closed_form_tumbling_flight():
    # Independent motion: a straight line at constant ECEF velocity while
    # the body tumbles at 0.3 rad/s about a fixed body axis. Then
    # C(t) = C0 exp(t [w x]), ω_ib^b = w + Cᵀ ω_ie and
    # f = Cᵀ (2 ω_ie x v - g(r)) (no acceleration relative to the Earth).
    rate = 100.0
    t = np.arange(0, 600 * rate + 1) / rate
    r0 = mn.geodetic_to_ecef([0.5, -2.0, 1000.0])
    v = np.array([12.0, -15.0, 4.0])
    r = r0 + t[:, None] * v
    w = 0.3 * np.array([1.0, 2.0, 3.0]) / math.sqrt(14)
    c0 = rodrigues(np.array([0.2, -0.4, 1.0]))
    c = np.array([c0 @ rodrigues(w * ti) if ti > 0 else c0 for ti in t])
    we = np.array([0.0, 0.0, OMEGA_IE])
    f_e = 2 * np.cross(we, v) - mn.gravity_ecef(r)
    f = np.einsum("nji,nj->ni", c, f_e)
    omega = w + np.einsum("nji,j->ni", c, we)
    nav = mn.strapdown(t, f, omega, r[0], v, c[0])
    error = max_position_error(nav, r)
    print(f"closed-form tumbling flight 600 s: closure {error:.2e} m")
    assert error < 0.1


def test_scripted_trajectory_closes_and_does_what_it_says():
    segments = [
        ("cruise", 10.0),
        ("accelerate", 20.0, 20.0),
        ("turn", 16.0, math.pi / 2),
        ("climb", 40.0, 0.05),
        ("turn", 30.0, -math.pi),
        ("cruise", 400.0),
        ("turn", 24.0, math.pi / 4),
        ("accelerate", 20.0, 5.0),
        ("stop", 10.0),
        ("cruise", 30.0),
    ]
    tr = mn.Trajectory.from_segments(segments, origin=(0.8, 0.1, 200.0), heading=0.0, rate=100.0)
    assert len(tr) == 60001
    error = max_position_error(run(tr), tr.position_ecef)
    print(f"scripted 600 s: closure {error:.2e} m")
    assert error < 0.1
    yaw = tr.euler_ned()[:, 2]
    assert yaw[100 * 30] == pytest.approx(0.0, abs=1e-9)
    assert yaw[100 * 47] == pytest.approx(math.pi / 2, abs=1e-6)
    v = np.linalg.norm(tr.velocity_ned(), axis=1)
    assert v[100 * 5] == 0.0
    assert v[100 * 40] == pytest.approx(20.0, abs=1e-9)
    assert v[-1] < 1e-12
    lla = tr.position_geodetic()
    np.testing.assert_allclose(lla[0], [0.8, 0.1, 200.0], atol=1e-9)
    # Climb: 20 m/s at a path angle ramped 0 → 0.05 → 0 (mean ¾ of the peak).
    gain = lla[100 * 86, 2] - lla[100 * 46, 2]
    assert gain == pytest.approx(20 * 40 * 0.75 * 0.05, rel=0.01)


@pytest.mark.parametrize("name", ["Profile_2.csv", "Profile_3.csv"])
def test_profile_closes(name):
    tr = mn.Trajectory.from_profile(profile(name), rate=100.0)
    error = max_position_error(run(tr), tr.position_ecef)
    print(f"{name} ({tr.time[-1]:.0f} s): closure {error:.2e} m")
    assert error < 0.1
    # The smoothed truth stays on the file's path.
    data = np.loadtxt(profile(name), delimiter=",")
    lla = np.column_stack([np.radians(data[:, 1]), np.radians(data[:, 2]), data[:, 3]])
    offset = np.linalg.norm(mn.geodetic_to_ecef(lla) - tr.position_ecef, axis=1).max()
    assert offset < 1.0


def test_increments_form_matches_samples():
    tr = mn.Trajectory.random(duration=60.0, seed=4)
    dv, da = mn.imu_increments(tr.time, tr.specific_force, tr.angular_rate)
    assert dv.shape == da.shape == (len(tr) - 1, 3)
    # The increments are integrals of the rates: ∫ω ≈ trapezoid to O(dt³).
    trapezoid = 0.5 * (tr.angular_rate[1:] + tr.angular_rate[:-1]) * 0.01
    np.testing.assert_allclose(da, trapezoid, atol=1e-7)
    nav = mn.strapdown_increments(
        tr.time, dv, da, tr.position_ecef[0], tr.velocity_ecef[0], tr.attitude[0]
    )
    assert max_position_error(nav, tr.position_ecef) < 1e-3


def test_random_limits_and_smoothness():
    tr = mn.Trajectory.random(duration=300.0, seed=9, stationary_start=10.0)
    speed = np.linalg.norm(tr.velocity_ecef, axis=1)
    assert speed.max() <= 30.0 + 1e-9
    assert np.all(speed[:1000] < 1e-12)
    a = np.gradient(tr.velocity_ecef, tr.time, axis=0)
    a_body = np.einsum("nji,nj->ni", tr.attitude, a)
    assert np.abs(a_body[:, 1]).max() <= 3.0 * 1.01
    assert np.abs(a_body[:, 0]).max() <= 2.0 * 1.03
    # No jumps in the IMU truth: second differences are O(dt²).
    assert np.abs(np.diff(tr.specific_force, 2, axis=0)).max() < 2e-3
    assert np.abs(np.diff(tr.angular_rate, 2, axis=0)).max() < 1e-3


def test_seeded_reproducibility():
    a = mn.Trajectory.random(duration=20.0, seed=5)
    b = mn.Trajectory.random(duration=20.0, seed=5)
    c = mn.Trajectory.random(duration=20.0, seed=6)
    np.testing.assert_array_equal(a.specific_force, b.specific_force)
    assert not np.array_equal(a.position_ecef, c.position_ecef)


def valid_inputs() -> dict:
    tr = mn.Trajectory.random(duration=1.0, seed=0)
    return {
        "time": tr.time,
        "specific_force": tr.specific_force,
        "angular_rate": tr.angular_rate,
        "position_ecef": tr.position_ecef[0],
        "velocity_ecef": tr.velocity_ecef[0],
        "attitude": tr.attitude[0],
    }


def nan_at(a: np.ndarray) -> np.ndarray:
    a = a.copy()
    a[3, 1] = np.nan
    return a


@pytest.mark.parametrize(
    ("argument", "change", "message"),
    [
        ("time", lambda t: np.r_[t[:5], t[4], t[6:]], "time: times must be strictly increasing"),
        ("time", lambda t: t[:-1], "specific_force: has 101 rows but time has 100"),
        ("specific_force", nan_at, "specific_force: row 3, column 1 is NaN"),
        ("angular_rate", nan_at, "angular_rate: row 3, column 1 is NaN"),
        ("angular_rate", lambda w: w[:, :2], r"angular_rate: expected shape \(N, 3\)"),
        ("position_ecef", lambda r: r[:2], r"position_ecef: expected shape \(3,\)"),
        ("attitude", lambda c: 2 * c, "attitude: is not a rotation matrix"),
        ("attitude", lambda c: c @ np.diag([1.0, 1.0, -1.0]), "attitude: is not a rotation"),
    ],
)
def test_strapdown_bad_input_names_the_argument(argument, change, message):
    inputs = valid_inputs()
    inputs[argument] = change(inputs[argument])
    with pytest.raises(ValueError, match=message):
        mn.strapdown(**inputs)


def test_other_bad_inputs_name_the_argument():
    inputs = valid_inputs()
    with pytest.raises(ValueError, match="scheme"):
        mn.strapdown(**inputs, scheme="euler")
    dv, da = mn.imu_increments(inputs["time"], inputs["specific_force"], inputs["angular_rate"])
    rest = (inputs["position_ecef"], inputs["velocity_ecef"], inputs["attitude"])
    with pytest.raises(ValueError, match="delta_velocity: has 101 rows"):
        mn.strapdown_increments(inputs["time"], dv[:-1].tolist() + [[0, 0, 0]] * 2, da, *rest)
    with pytest.raises(ValueError, match="delta_angle: row 3, column 1 is NaN"):
        mn.strapdown_increments(inputs["time"], dv, nan_at(da), *rest)
    for kwargs, name in [
        ({"duration": 0.0}, "duration"),
        ({"duration": -3.0}, "duration"),
        ({"rate": 0.0}, "rate"),
        ({"rate": -100.0}, "rate"),
        ({"origin": (2.0, 0.0, 0.0)}, "origin"),
        ({"origin": (0.1, 0.2)}, "origin"),
        ({"max_speed": float("nan")}, "max_speed"),
        ({"stationary_start": -1.0}, "stationary_start"),
    ]:
        with pytest.raises(ValueError, match=f"^{name}:"):
            mn.Trajectory.random(**kwargs)
    for segments, message in [
        ([], "segments: needs at least one"),
        ([("cruise", 10.0), ("fly", 3.0)], r"segments\[1\]: unknown kind \"fly\""),
        ([("turn", 10.0)], r"segments\[0\]: \"turn\" takes"),
        ([("cruise", -1.0)], r"segments\[0\]\.duration_s"),
        ([("accelerate", 5.0, -2.0)], r"segments\[0\]\.target_speed_m_s"),
        ([3.0], r"segments\[0\]: expected a tuple"),
    ]:
        with pytest.raises(ValueError, match=message):
            mn.Trajectory.from_segments(segments)
    with pytest.raises(ValueError, match=r"^rate:"):
        mn.Trajectory.from_segments([("cruise", 1.0)], rate=0.0)


GOOD = "0,51,0,10,0,1,0,0,0,0\n0.01,51,0.0000001,10,0,1,0,0,0,0\n0.02,51,0.0000002,10,0,1,0,0,0,0\n"


@pytest.mark.parametrize(
    ("text", "line", "reason"),
    [
        (GOOD + "0.03,51,0.0000003,10,0,1", 4, "expected 10"),
        (GOOD + "0.03,51,x,10,0,1,0,0,0,0\n", 4, "column 3"),
        ("0,51,0,10,0,1,0,0,0,0\n0,51,0,10,0,1,0,0,0,0\n", 2, "does not follow"),
        (GOOD, 3, "at least 4 rows"),
        # An east velocity of 1e308 gave 1 176 of 1 200 specific
        # forces non-finite; each column now has its range.
        (GOOD + "0.03,51,0.0000003,10,0,1e308,0,0,0,0\n", 4, r"column 6 \(v_E, m/s\): 1e308"),
        (GOOD + "0.03,51,0.0000003,10,7e4,7e4,7e4,0,0,0\n", 4, "a speed of 121243"),
        (GOOD + "0.03,91,0.0000003,10,0,1,0,0,0,0\n", 4, r"column 2 \(latitude"),
        (GOOD + "0.03,51,0.0000003,10,0,1,0,0,1e300,0\n", 4, r"column 9 \(pitch"),
    ],
)
def test_bad_profile_names_file_and_line(tmp_path, text, line, reason):
    path = tmp_path / "profile.csv"
    path.write_text(text)
    with pytest.raises(mn.ParseError, match=f"profile.csv:{line}: .*{reason}"):
        mn.Trajectory.from_profile(path)


def test_missing_profile_is_an_os_error(tmp_path):
    with pytest.raises(OSError, match=r"missing\.csv"):
        mn.Trajectory.from_profile(tmp_path / "missing.csv")
