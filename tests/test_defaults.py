"""One definition of every default: ``memsnav.defaults()`` reads
the core's ``Default``s and constants; every layer that takes one of those
arguments (the binding's signature, the stub, the Python wrappers) says
``None`` for it, and ``None`` behaves exactly as the listed value given
explicitly. Changing a default is one edit in the core; a layer that
writes its own literal fails here."""

from __future__ import annotations

import ast
import inspect
from pathlib import Path
from typing import Any

import numpy as np
import pytest

import memsnav as mn
from memsnav import _memsnav
from memsnav.experiments.navigation import navigation

STUB = Path(_memsnav.__file__).with_name("_memsnav.pyi")
DEFAULTS = mn.defaults()
# Python functions that wrap a binding entry and repeat its arguments.
WRAPPERS = {"navigation_experiment": [navigation]}


def _binding_object(api: str) -> Any:
    obj: Any = _memsnav
    for part in api.split("."):
        obj = getattr(obj, part)
    return obj


def _stub_function(api: str) -> ast.FunctionDef:
    """The stub's definition of ``api`` (a class means its ``__new__``)."""
    body: list[ast.stmt] = ast.parse(STUB.read_text()).body
    *outer, name = api.split(".")
    for part in outer:
        body = next(n for n in body if isinstance(n, ast.ClassDef) and n.name == part).body
    node = next(n for n in body if getattr(n, "name", None) == name)
    if isinstance(node, ast.ClassDef):
        node = next(n for n in node.body if isinstance(n, ast.FunctionDef) and n.name == "__new__")
    assert isinstance(node, ast.FunctionDef), api
    return node


def _stub_defaults(fn: ast.FunctionDef) -> dict[str, ast.expr]:
    a = fn.args
    positional = a.posonlyargs + a.args
    pairs = list(zip(positional[len(positional) - len(a.defaults) :], a.defaults, strict=True))
    pairs += [(arg, d) for arg, d in zip(a.kwonlyargs, a.kw_defaults, strict=True) if d]
    return {arg.arg: d for arg, d in pairs}


def _cases() -> list[tuple[str, str]]:
    return [(api, arg) for api, values in DEFAULTS.items() for arg in values]


def test_defaults_cover_the_apis_that_had_literals():
    assert {
        "TightlyCoupledFilter",
        "LooselyCoupledFilter",
        "RinexObservations.gps_l1",
        "navigation_experiment",
        "Constellation.walker",
        "AccelerometerModel",
        "ImuModel.preset",
    } <= set(DEFAULTS)
    for api, values in DEFAULTS.items():
        assert values, api
        for arg, value in values.items():
            assert value is not None, (api, arg)


@pytest.mark.parametrize(("api", "arg"), _cases(), ids=[f"{a}.{b}" for a, b in _cases()])
def test_every_layer_says_none(api, arg):
    obj = _binding_object(api)
    signature = inspect.signature(obj)
    assert signature.parameters[arg].default is None, f"binding {api}({arg}=...)"
    stub = _stub_defaults(_stub_function(api))
    assert arg in stub and isinstance(stub[arg], ast.Constant) and stub[arg].value is None, (
        f"stub {api}({arg}=...) is {ast.unparse(stub[arg]) if arg in stub else 'required'}"
    )
    for wrapper in WRAPPERS.get(api, []):
        default = inspect.signature(wrapper).parameters[arg].default
        assert default is None, f"{wrapper.__module__}.{wrapper.__qualname__}({arg}={default!r})"


def test_the_filters_take_the_listed_defaults(drive_300s):
    imu = drive_300s[2]
    for name in ("TightlyCoupledFilter", "LooselyCoupledFilter"):
        cls = getattr(mn, name)
        listed = DEFAULTS[name]
        implicit, explicit = cls(imu).tuning, cls(imu, **listed).tuning
        assert implicit == explicit
        for arg, value in listed.items():
            if arg in implicit:
                assert implicit[arg] == value, (name, arg)
        overridden = cls(imu, initial_position_std=2.0, gate_probability=0.99).tuning
        assert overridden["initial_position_std"] == 2.0
        assert overridden["gate_probability"] == 0.99


def test_the_observables_take_the_listed_defaults(tmp_path):
    excerpt = Path(__file__).parent / "data" / "real-imu-gnss"
    obs = mn.read_rinex_obs(excerpt / "walk_head.obs")
    sky = mn.Constellation.from_rinex_nav(excerpt / "walk.nav")
    # pseudorange_std is the signal-strength weighting's (the default
    # weighting refuses it): both models, each with its listed values.
    listed = DEFAULTS["RinexObservations.gps_l1"]
    assert listed["weighting"] == "rtklib"
    rtklib = {k: v for k, v in listed.items() if k != "pseudorange_std"}
    np.testing.assert_array_equal(
        obs.gps_l1(sky).pseudorange_std, obs.gps_l1(sky, **rtklib).pseudorange_std
    )
    implicit = obs.gps_l1(sky, weighting="signal-strength")
    explicit = obs.gps_l1(sky, **{**listed, "weighting": "signal-strength"})
    assert len(implicit) == len(explicit) > 0
    fields = ("pseudorange", "pseudorange_std", "pseudorange_rate_std", "sat_id", "carrier_phase")
    for field in fields:
        np.testing.assert_array_equal(getattr(implicit, field), getattr(explicit, field))
    strength = obs.gps_l1(sky, weighting="signal-strength")
    loose = obs.gps_l1(sky, weighting="signal-strength", pseudorange_std=6.0)
    np.testing.assert_allclose(loose.pseudorange_std, 2.0 * strength.pseudorange_std)


def test_the_walker_and_the_rates_take_the_listed_defaults():
    walker = DEFAULTS["Constellation.walker"]
    a, b = mn.Constellation.walker(), mn.Constellation.walker(**walker)
    assert a.prns == b.prns and len(a.prns) == walker["n_satellites"]
    np.testing.assert_array_equal(a.position_velocity(100.0)[0], b.position_velocity(100.0)[0])
    z3, z33 = np.zeros(3), np.zeros((3, 3))
    for made, api in [
        (mn.AccelerometerModel(z3, z3, z33, z3), "AccelerometerModel"),
        (mn.GyroscopeModel(z3, z3, z33, z33), "GyroscopeModel"),
        (mn.ImuModel.preset("consumer", seed=1), "ImuModel.preset"),
    ]:
        assert made.sample_rate == DEFAULTS[api]["sample_rate"], api
    segments = mn.Trajectory.from_segments([("cruise", 1.0)])
    assert np.diff(segments.time)[0] == pytest.approx(
        1.0 / DEFAULTS["Trajectory.from_segments"]["rate"]
    )


def test_the_statistics_and_scores_take_the_listed_defaults(drive_300s):
    """The quantile interval, the sequential look error, a calibration
    layout's model, and a log run's fix scores and calibration references:
    None is the listed value given explicitly."""
    runs = np.linspace(1.0, 3.0, 40) ** 2
    listed = DEFAULTS["quantile_interval"]
    implicit = mn.quantile_interval(runs, 0.9).to_dict()
    assert implicit == mn.quantile_interval(runs, 0.9, **listed).to_dict()
    assert implicit != mn.quantile_interval(runs, 0.9, confidence=0.5).to_dict()
    listed = DEFAULTS["sequential_look_error"]
    looks = [20, 40, 80]
    assert mn.sequential_look_error(looks, 0.9) == mn.sequential_look_error(looks, 0.9, **listed)
    layout = mn.CalibrationLayout("gyroscope")
    values = np.zeros(len(layout))
    listed = DEFAULTS["CalibrationLayout.model"]
    assert layout.model(values).sample_rate == listed["sample_rate"]
    traj, gnss, _, f, w = drive_300s
    run = mn.navigate_log(traj.time, f, w, gnss, settings={"filter": {"imu_preset": "consumer"}})
    implicit = run.score_gnss(traj.time, traj.position_ecef)
    explicit = run.score_gnss(traj.time, traj.position_ecef, **DEFAULTS["LogRun.score_gnss"])
    np.testing.assert_array_equal(implicit["error_ned"], explicit["error_ned"])
    implicit = run.calibration_references(traj.time, f, w)
    explicit = run.calibration_references(
        traj.time, f, w, **DEFAULTS["LogRun.calibration_references"]
    )
    np.testing.assert_array_equal(implicit["time"], explicit["time"])
    assert implicit["window_s"] == DEFAULTS["LogRun.calibration_references"]["window_s"]


def test_the_navigation_study_records_the_listed_defaults():
    listed = DEFAULTS["navigation_experiment"]
    result = navigation(runs=1, duration=20.0, imus=("ins",))
    for arg, value in listed.items():
        if arg in ("runs", "duration"):
            continue
        recorded = result.config[arg]
        assert recorded == (tuple(value) if isinstance(value, tuple) else value), arg


def test_seed_none_is_the_default_seed_everywhere():
    """``seed=None`` has one meaning: seed 0 (docs/explanation/concepts.md, "Seeds")."""
    tr = mn.Trajectory.random(duration=5.0)
    np.testing.assert_array_equal(tr.position_ecef, mn.Trajectory.random(5.0, seed=0).position_ecef)
    sky = mn.Constellation.walker()
    pair = [
        mn.simulate_gnss(tr.time, tr.position_ecef, tr.velocity_ecef, sky, seed=seed)
        for seed in (None, 0)
    ]
    np.testing.assert_array_equal(pair[0].pseudorange, pair[1].pseudorange)
    imu = mn.ImuModel.preset("consumer")
    assert imu == mn.ImuModel.preset("consumer", seed=0)
    assert imu != mn.ImuModel.preset("consumer", seed=1)
    a = imu.measure(tr.specific_force, tr.angular_rate)
    b = imu.measure(tr.specific_force, tr.angular_rate, seed=0)
    np.testing.assert_array_equal(a[0], b[0])
    np.testing.assert_array_equal(a[1], b[1])
