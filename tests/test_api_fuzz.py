"""Hypothesis over the public numeric arguments of ``strapdown``,
``simulate_gnss``, ``solve_fix``, the sensor models, an IMU's spec (through
the filter tuned from it), both filters and the step API (``RunningFilter``,
every predict and update). Each
example takes a valid call and replaces one argument (a scalar, one element
of an array, or the whole array) by an extreme: 0, ±1e-300, the smallest
subnormal, ±1e6, ±1e300, the largest float, NaN, ±inf, or any float.

Every call must, within the hang limit, either return results that are all
finite (a NaN or inf out of finite input is silent garbage), or raise a
``ValueError``, ``TypeError`` or ``memsnav.MemsnavError`` whose message
names an argument. A non-finite value is never accepted silently, except a
NaN pseudorange or rate, which marks a satellite without a measurement.

CI runs a fixed, derandomised budget; ``MEMSNAV_FUZZ_EXAMPLES=N`` raises it
and draws new inputs each run (docs/reference/robustness.md).
"""

from __future__ import annotations

import math
import os
import threading
import warnings
from collections.abc import Callable
from dataclasses import dataclass
from functools import cache
from typing import Any

import numpy as np
import pytest
from hypothesis import HealthCheck, given, settings
from hypothesis import strategies as st

import memsnav as mn

LONG = "MEMSNAV_FUZZ_EXAMPLES" in os.environ
FUZZ = settings(
    max_examples=int(os.environ.get("MEMSNAV_FUZZ_EXAMPLES", "60")),
    derandomize=not LONG,
    database=None,
    deadline=None,
    suppress_health_check=[HealthCheck.too_slow],
)
# A call still running after this long is a hang (a correct one on these
# short inputs takes milliseconds).
HANG_S = 60.0

EXTREMES = [0.0, -0.0, 1.0, -1.0, 1e-300, -1e-300, 5e-324, 1e6, -1e6, 1e300, -1e300]
EXTREMES += [np.finfo(float).max, math.nan, math.inf, -math.inf]
VALUES = st.one_of(st.sampled_from(EXTREMES), st.floats())
# In the per-satellite GNSS arrays a non-finite value marks a slot without
# a (usable) measurement, as the layout documents (NaN padding where fewer
# satellites are tracked; a rate whose std is NaN is absent): the filter
# skips it and records it as invalid in its measurement records.
MISSING_MARKERS = {"pseudorange", "pseudorange_rate", "pseudorange_std", "pseudorange_rate_std"}
MISSING_MARKERS |= {"satellite_position_ecef", "satellite_velocity_ecef"}


@cache
def track():
    """A 10 s drive at 100 Hz with its Walker-constellation GNSS and fixes."""
    t = mn.Trajectory.random(duration=10.0, seed=11)
    gnss = mn.simulate_gnss(t.time, t.position_ecef, t.velocity_ecef, mn.Constellation.walker())
    fixes = mn.solve_fix(gnss)
    return t, gnss, fixes


def gnss_arrays() -> dict[str, np.ndarray]:
    _, gnss, _ = track()
    names = ("time", "sat_id", "pseudorange", "pseudorange_rate", "pseudorange_std")
    names += ("pseudorange_rate_std", "satellite_position_ecef", "satellite_velocity_ecef")
    return {name: np.array(getattr(gnss, name)) for name in names}


def fix_arrays() -> dict[str, np.ndarray]:
    _, _, fixes = track()
    return {
        "time": np.array(fixes.time),
        "position_ecef": np.array(fixes.position_ecef),
        "position_covariance": np.array(fixes.position_clock_covariance)[:, :3, :3],
    }


def imu() -> mn.ImuModel:
    return mn.ImuModel.preset("consumer", seed=1)


@dataclass
class Entry:
    """One public entry: its valid arguments (numeric ones by name, GNSS
    dicts as ``gnss.<key>``), the call, and the arrays of its result."""

    arguments: Callable[[], dict[str, Any]]
    call: Callable[[dict[str, Any]], Any]
    outputs: Callable[[Any], list[np.ndarray]]


def nav_outputs(sol) -> list[np.ndarray]:
    return [sol.position_ecef, sol.velocity_ecef, sol.attitude]


def filter_outputs(sol) -> list[np.ndarray]:
    return [*nav_outputs(sol), sol.position_std_ned, sol.velocity_std_ned, sol.covariance_diagonal]


def strapdown_arguments() -> dict[str, Any]:
    t, _, _ = track()
    return {
        "time": t.time,
        "specific_force": t.specific_force,
        "angular_rate": t.angular_rate,
        "position_ecef": t.position_ecef[0],
        "velocity_ecef": t.velocity_ecef[0],
        "attitude": t.attitude[0],
    }


def simulate_arguments() -> dict[str, Any]:
    t, _, _ = track()
    return {
        "time": t.time,
        "position_ecef": t.position_ecef,
        "velocity_ecef": t.velocity_ecef,
        "rate": 1.0,
        "elevation_mask_deg": 10.0,
        "pseudorange_std": 3.0,
        "pseudorange_rate_std": 0.1,
        "residual_std": 1.0,
        "residual_correlation_time": 300.0,
        "clock_h0": 2e-19,
        "clock_h_minus2": 2e-20,
        "clock_initial_offset_std": 100.0,
        "clock_initial_drift_std": 1.0,
        "start_gps_time": 1e5,
    }


def simulate_outputs(g) -> list[np.ndarray]:
    tracked = np.array(g.sat_id) >= 0
    return [
        np.array(g.time),
        np.array(g.pseudorange)[tracked],
        np.array(g.pseudorange_rate)[tracked],
        np.array(g.satellite_position_ecef)[tracked],
    ]


def fix_outputs(fixes) -> list[np.ndarray]:
    valid = np.array(fixes.valid, dtype=bool)
    return [
        np.array(fixes.position_ecef)[valid],
        np.array(fixes.velocity_ecef)[valid],
        np.array(fixes.position_clock_covariance)[valid],
    ]


SENSOR_NOISE = {
    "noise_density": 1e-3,
    "sample_rate": 100.0,
    "bias_instability": 1e-3,
    "bias_correlation_time": 100.0,
    "bias_random_walk": 1e-4,
    "quantization": 1e-4,
}


def accelerometer_arguments() -> dict[str, Any]:
    t, _, _ = track()
    return {
        "bias": np.full(3, 0.05),
        "scale_factor": np.full(3, 1e-3),
        "misalignment": np.array([[0, 1e-3, 0], [0, 0, 1e-3], [1e-3, 0, 0]]),
        "nonlinearity": np.full(3, 1e-4),
        **SENSOR_NOISE,
        "specific_force": t.specific_force[:200],
    }


def accelerometer_call(a: dict[str, Any]):
    inputs = {k: v for k, v in a.items() if k != "specific_force"}
    return mn.AccelerometerModel(**inputs).measure(a["specific_force"], seed=1)


def gyroscope_arguments() -> dict[str, Any]:
    t, _, _ = track()
    return {
        "bias": np.full(3, 1e-3),
        "scale_factor": np.full(3, 1e-3),
        "misalignment": np.array([[0, 1e-3, 0], [0, 0, 1e-3], [1e-3, 0, 0]]),
        "g_sensitivity": np.full((3, 3), 1e-4),
        **SENSOR_NOISE,
        "angular_rate": t.angular_rate[:200],
        "specific_force": t.specific_force[:200],
    }


def gyroscope_call(a: dict[str, Any]):
    inputs = {k: v for k, v in a.items() if k not in ("angular_rate", "specific_force")}
    return mn.GyroscopeModel(**inputs).measure(a["angular_rate"], a["specific_force"], seed=1)


TUNING = {
    "accel_noise_density": 2e-3,
    "gyro_noise_density": 2e-4,
    "accel_bias_psd": 1e-8,
    "gyro_bias_psd": 1e-12,
    "gate_probability": 0.999,
    "initial_position_std": 5.0,
    "initial_velocity_std": 0.5,
    "initial_tilt_std": 0.02,
    "initial_heading_std": 0.2,
    "initial_accel_bias_std": 0.1,
    "initial_gyro_bias_std": 0.01,
    "initial_clock_offset_std": 100.0,
    "initial_clock_drift_std": 10.0,
    "manoeuvre_correlation_time": 5.0,
    "pseudorange_correlation_time": 5.0,
}


def filter_arguments(aiding: Callable[[], dict[str, np.ndarray]]) -> Callable[[], dict[str, Any]]:
    def arguments() -> dict[str, Any]:
        t, _, _ = track()
        return {
            **TUNING,
            "time": t.time,
            "specific_force": t.specific_force,
            "angular_rate": t.angular_rate,
            "initial_attitude": t.attitude[0],
            **{f"gnss.{k}": v for k, v in aiding().items()},
        }

    return arguments


def filter_call(filter_class) -> Callable[[dict[str, Any]], Any]:
    def call(a: dict[str, Any]):
        tuning = {k: a[k] for k in TUNING}
        gnss = {k.removeprefix("gnss."): v for k, v in a.items() if k.startswith("gnss.")}
        run = filter_class(imu(), **tuning).run
        return run(
            a["time"],
            a["specific_force"],
            a["angular_rate"],
            gnss,
            initial_attitude=a["initial_attitude"],
        )

    return call


def spec_arguments() -> dict[str, Any]:
    return {"sample_rate": 100.0, **{f"spec.{k}": v for k, v in imu().spec.items()}}


def spec_call(a: dict[str, Any]):
    """An IMU from explicit models with every spec key given, its readings,
    and the tight filter tuned from the spec."""
    t, gnss, _ = track()
    spec = {k.removeprefix("spec."): v for k, v in a.items() if k.startswith("spec.")}
    model = mn.ImuModel(imu().accelerometer, imu().gyroscope, a["sample_rate"], spec=spec)
    f, w = model.measure(t.specific_force, t.angular_rate, seed=2)
    sol = mn.TightlyCoupledFilter(model).run(t.time, f, w, gnss, initial_attitude=t.attitude[0])
    return f, w, sol


def running_arguments() -> dict[str, Any]:
    """The step API over the first 2 s of the drive: every IMU sample,
    every GNSS epoch, and at 10 Hz an odometer speed, a height, a heading,
    the NHC, a ZUPT and a ZARU (their values need not be true: a wrong
    one is gated, not fatal)."""
    t, _, _ = track()
    n = 201
    return {
        "time": t.time[:n],
        "specific_force": t.specific_force[:n],
        "angular_rate": t.angular_rate[:n],
        "position_ecef": t.position_ecef[0],
        "velocity_ecef": t.velocity_ecef[0],
        "attitude": t.attitude[0],
        "delta_v": t.specific_force[1] * 0.01,
        "delta_theta": t.angular_rate[1] * 0.01,
        "speed": 10.0,
        "speed_std": 0.1,
        "lever_arm": np.array([1.0, 0.0, -0.5]),
        "height": 150.0,
        "height_std": 1.0,
        "yaw": 0.3,
        "yaw_std": 0.05,
        "nhc_std": 0.2,
        "zupt_std": 0.5,
        "mean_angular_rate": np.zeros(3),
        "zaru_std": 0.01,
    }


def running_call(a: dict[str, Any]):
    _, gnss, _ = track()
    start = {k: a[k] for k in ("position_ecef", "velocity_ecef", "attitude")}
    time = a["time"]
    running = mn.TightlyCoupledFilter(imu()).start(
        time[0], a["specific_force"][0], a["angular_rate"][0], start
    )
    epoch_time, j = np.asarray(gnss.time), 0
    for k in range(len(time)):
        if k > 0:
            running.predict(time[k], a["specific_force"][k], a["angular_rate"][k])
        while epoch_time[j] <= time[k] + 1e-4:
            running.update_gnss(gnss, j)
            j += 1
        if k % 10 == 0:
            running.update_speed(a["speed"], a["speed_std"], a["lever_arm"])
            running.update_height(a["height"], a["height_std"])
            running.update_heading(a["yaw"], a["yaw_std"])
            running.update_non_holonomic(a["nhc_std"], a["lever_arm"])
            running.update_zupt(a["zupt_std"])
            running.update_zaru(a["mean_angular_rate"], a["zaru_std"])
    running.predict_increments(time[-1] + 0.01, a["delta_v"], a["delta_theta"])
    return running


ENTRIES = {
    "running_filter": Entry(
        running_arguments,
        running_call,
        lambda r: [r.position_ecef, r.velocity_ecef, r.attitude, r.covariance],
    ),
    "strapdown": Entry(strapdown_arguments, lambda a: mn.strapdown(*a.values()), nav_outputs),
    "simulate_gnss": Entry(
        simulate_arguments,
        lambda a: mn.simulate_gnss(
            a["time"],
            a["position_ecef"],
            a["velocity_ecef"],
            mn.Constellation.walker(),
            **{k: v for k, v in a.items() if k not in ("time", "position_ecef", "velocity_ecef")},
        ),
        simulate_outputs,
    ),
    "solve_fix": Entry(
        lambda: {"prior": np.array([6.4e6, 1e5, 1e5])},
        lambda a: mn.solve_fix(track()[1], prior=a["prior"]),
        fix_outputs,
    ),
    "accelerometer": Entry(accelerometer_arguments, accelerometer_call, lambda r: [r]),
    "gyroscope": Entry(gyroscope_arguments, gyroscope_call, lambda r: [r]),
    "imu_spec": Entry(spec_arguments, spec_call, lambda r: [r[0], r[1], *filter_outputs(r[2])]),
    "tight": Entry(
        filter_arguments(gnss_arrays), filter_call(mn.TightlyCoupledFilter), filter_outputs
    ),
    "loose": Entry(
        filter_arguments(fix_arrays), filter_call(mn.LooselyCoupledFilter), filter_outputs
    ),
}


@dataclass(frozen=True)
class Mutation:
    """One argument replaced: a scalar, the element at flat `index` of an
    array, or (index None) the whole array, by `value`."""

    name: str
    index: int | None
    value: float

    def apply(self, entry: Entry) -> dict[str, Any]:
        arguments = {
            k: np.array(v, dtype=float) if isinstance(v, np.ndarray) else v
            for k, v in entry.arguments().items()
        }
        current = arguments[self.name]
        if not isinstance(current, np.ndarray):
            arguments[self.name] = self.value
        elif self.index is None:
            current[...] = self.value
        else:
            current.reshape(-1)[self.index % current.size] = self.value
        return arguments


@st.composite
def mutations(draw, entry: Entry) -> Mutation:
    name = draw(st.sampled_from(sorted(entry.arguments())))
    index = draw(st.one_of(st.none(), st.integers(0, 10**6)))
    return Mutation(name, index, draw(VALUES))


def finite_input(arguments: dict[str, Any], name: str) -> bool:
    return bool(np.isfinite(arguments[name]).all())


def call_with_hang_limit(call: Callable[[], Any]) -> tuple[Any, BaseException | None]:
    """The call on a daemon thread (the binding releases the GIL): its
    result or exception; fails the test if it has not returned in HANG_S."""
    outcome: dict[str, Any] = {}

    def target():
        try:
            with warnings.catch_warnings():
                warnings.simplefilter("ignore")
                outcome["result"] = call()
        except BaseException as e:  # judged by the caller
            outcome["error"] = e

    worker = threading.Thread(target=target, daemon=True)
    worker.start()
    worker.join(HANG_S)
    assert not worker.is_alive(), f"still running after {HANG_S} s: a hang"
    return outcome.get("result"), outcome.get("error")


@pytest.mark.parametrize("entry_name", sorted(ENTRIES))
def test_the_valid_calls_succeed(entry_name):
    """The calls the examples mutate run as given (else every example would
    only test an error path)."""
    entry = ENTRIES[entry_name]
    with warnings.catch_warnings():
        warnings.simplefilter("error")
        result = entry.call(entry.arguments())
    assert all(np.isfinite(array).all() for array in entry.outputs(result))


@pytest.mark.parametrize("entry_name", sorted(ENTRIES))
def test_extreme_arguments_give_finite_results_or_a_named_error(entry_name):
    entry = ENTRIES[entry_name]

    @FUZZ
    @given(mutations(entry))
    def check(mutation: Mutation):
        arguments, name = mutation.apply(entry), mutation.name
        result, error = call_with_hang_limit(lambda: entry.call(arguments))
        if error is not None:
            assert isinstance(error, ValueError | TypeError | mn.MemsnavError), repr(error)
            message = str(error)
            # The message starts by naming what is wrong: an argument, a
            # key (`gnss.time`, `initial.position_ecef`) or a field.
            assert ":" in message.split(" ")[0] or ": " in message, message
            return
        short = name.removeprefix("gnss.")
        assert finite_input(arguments, name) or short in MISSING_MARKERS, (
            f"{name} = non-finite was accepted"
        )
        for array in entry.outputs(result):
            assert np.isfinite(array).all(), f"{name}: non-finite output from finite input"

    check()
