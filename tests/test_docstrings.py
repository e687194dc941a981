"""Every public name of memsnav documents itself at runtime: ``help()`` and
docs/reference/api.md (``docs/build_api.py``) read ``__doc__``, so a class, attribute,
method or function without one is a hole in both. The names are found by
walking the package, not listed by hand, so a new getter without a doc
comment fails here."""

import inspect
import types
from collections.abc import Iterator

import build_stub_docs
import pytest

import memsnav
import memsnav._memsnav as native

# Descriptors the binding (PyO3) and Python classes expose as attributes.
_ATTRIBUTES = (property, types.GetSetDescriptorType, types.MemberDescriptorType)


def _public(module: types.ModuleType) -> Iterator[tuple[str, object]]:
    """The names a module exports (its ``__all__``), private ones left out."""
    for name in module.__all__:
        if not name.startswith("_"):
            yield f"{module.__name__}.{name}", getattr(module, name)


def _documented_names() -> Iterator[tuple[str, object]]:
    """Every public class, class member and function reachable from
    ``memsnav`` and ``memsnav._memsnav``, each once, with its dotted name."""
    seen: set[int] = set()
    modules = [memsnav, native]
    while modules:
        for name, obj in _public(modules.pop(0)):
            if id(obj) in seen:
                continue
            seen.add(id(obj))
            if isinstance(obj, types.ModuleType):
                modules.append(obj)
            elif inspect.isclass(obj):
                yield name, obj
                for member_name, member in vars(obj).items():
                    if member_name.startswith("_"):
                        continue
                    if isinstance(member, (staticmethod, classmethod)):
                        member = member.__func__
                    if isinstance(member, _ATTRIBUTES) or callable(member):
                        yield f"{name}.{member_name}", member
            elif callable(obj):
                yield name, obj


def test_walk_reaches_the_binding_and_the_python_package():
    names = dict(_documented_names())
    # A getter and a field of the binding, a static method, a class only the
    # native module exports, a native function, a submodule's function and a
    # Python class's property: the walk is not vacuous.
    for name in (
        "memsnav.AccelerometerModel.noise_density",
        "memsnav.Calibration.model",
        "memsnav.ImuModel.preset",
        "memsnav._memsnav.LagEstimate",
        "memsnav.simulate_gnss",
        "memsnav.experiments.navigation",
        "memsnav.experiments.OutageStudyResult.outage_lengths",
    ):
        assert name in names


def test_every_public_name_has_a_docstring():
    undocumented = sorted(
        name
        for name, obj in _documented_names()
        if not (getattr(obj, "__doc__", None) or "").strip()
    )
    assert not undocumented, f"{len(undocumented)} without a docstring: {', '.join(undocumented)}"


def test_native_classes_live_in_the_native_module():
    """pickle, pydoc and ``repr`` find a class through ``__module__`` and
    ``__qualname__``; the binding's classes all live in ``memsnav._memsnav``
    (where the stub declares them; not every class is re-exported by
    ``memsnav``). The exceptions are ``memsnav.<Name>``, re-exported there."""
    for name, obj in _public(native):
        if inspect.isclass(obj):
            home = "memsnav" if issubclass(obj, BaseException) else native.__name__
            assert obj.__module__ == home, name
            assert getattr(memsnav if home == "memsnav" else native, obj.__qualname__) is obj, name


def test_the_stub_says_what_help_says():
    """python/memsnav/_memsnav.pyi's docstrings are the runtime ones (the
    binding's Rust doc comments): docs/build_stub_docs.py writes them, and a
    doc comment changed without rerunning it fails here."""
    stale = build_stub_docs.differences()
    assert not stale, f"rerun python docs/build_stub_docs.py: {stale}"


@pytest.mark.parametrize(
    "entry",
    [
        memsnav.simulate_gnss,
        memsnav.strapdown,
        memsnav.Trajectory.random,
        memsnav.solve_fix,
        memsnav.TightlyCoupledFilter,
        memsnav.LooselyCoupledFilter,
        memsnav.TightlyCoupledFilter.run,
        memsnav.LooselyCoupledFilter.run,
        memsnav.TightlyCoupledFilter.start,
        memsnav.ImuModel.preset,
        memsnav.ImuModel.measure,
        memsnav.AccelerometerModel.measure,
        memsnav.GyroscopeModel.measure,
        memsnav.Constellation.walker,
        memsnav.Trajectory.from_segments,
        memsnav.Trajectory.from_profile,
        memsnav.strapdown_increments,
        memsnav.ecef_to_geodetic,
        memsnav.geodetic_to_ecef,
        memsnav.gravity_ecef,
        memsnav.mounting_matrix,
        memsnav.read_imu_csv,
        memsnav.read_time_tag,
        memsnav.fit_tag_clock,
        memsnav.read_pos,
        memsnav.read_fixes,
        memsnav.read_fixes_csv,
        memsnav.read_nmea,
        memsnav.read_rinex_obs,
        memsnav.read_broadcast_nav,
        memsnav.read_sp3,
        memsnav.read_ubx,
        memsnav.read_gnsslogger,
        memsnav.read_klobuchar,
        memsnav.load_calibration,
        memsnav.load_config,
    ],
    ids=lambda f: f.__qualname__,
)
def test_help_names_every_argument(entry):
    """The entries users start from say what each argument is in help():
    every parameter of the signature is named in the docstring."""
    doc = entry.__doc__ or ""
    unnamed = [
        name
        for name in inspect.signature(entry).parameters
        if name not in ("self", "cls") and f"`{name}`" not in doc and f"``{name}``" not in doc
    ]
    assert not unnamed, f"help({entry.__qualname__}) does not name {unnamed}"
