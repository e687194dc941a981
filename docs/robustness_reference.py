"""The constants and error messages docs/reference/robustness.md and
docs/reference/readers.md show, read from where they are defined:

- ``constants``: the argument limits, the warning thresholds, the IMU CSV
  reader's ranges and the fuzzing suites' mutations, budgets and hang
  limits, each read from the Rust or Python source that defines it (one
  place holds each figure);
- ``messages``: what the calls the page quotes say, run here.

``python docs/doc_runs.py robustness_constants robustness_messages`` writes
their records; ``tests/test_robustness_doc.py`` compares them with the
source and the calls today."""

from __future__ import annotations

import math
import re
import sys
from collections.abc import Callable
from pathlib import Path
from typing import Any

import numpy as np
from fuzz_runs import default_budgets

import memsnav as mn

ROOT = Path(__file__).resolve().parents[1]
CORE = ROOT / "crates" / "memsnav-core" / "src"
RUST_FUZZ = ROOT / "crates" / "memsnav-core" / "tests" / "readers_fuzz.rs"
LIMITS = CORE / "limits.rs"
DOMAIN = CORE / "geodesy" / "domain.rs"
DIAGNOSTICS = CORE / "coupling" / "diagnostics.rs"
INTEGRITY = CORE / "coupling" / "integrity.rs"
IMU_CSV = CORE / "logs" / "imu_csv.rs"
VALIDATE = CORE / "validate.rs"


def _fuzz_suites() -> tuple[Any, Any]:
    """The Python fuzzing suites (tests/test_readers_fuzz.py,
    tests/test_api_fuzz.py), imported for their constants."""
    tests = str(ROOT / "tests")
    if tests not in sys.path:
        sys.path.insert(0, tests)
    import test_api_fuzz
    import test_readers_fuzz

    return test_readers_fuzz, test_api_fuzz


def _search(path: Path, pattern: str) -> tuple[str, ...]:
    found = re.search(pattern, path.read_text(), re.S)
    if found is None:
        raise LookupError(f"{path.relative_to(ROOT)} no longer matches {pattern!r}")
    return found.groups()


def rust_const(path: Path, name: str) -> Any:
    """A Rust constant's value: a literal, a tuple or a range of literals."""
    (expression,) = _search(path, rf"const {name}: [^=]+ = ([^;]+);")
    expression = expression.replace("_", "")
    if "..=" in expression:
        low, high = expression.split("..=")
        return [float(low), float(high)]
    value = eval(expression, {"__builtins__": {}})
    return list(value) if isinstance(value, tuple) else value


def rust_readers() -> list[str]:
    """The readers tests/readers_fuzz.rs fuzzes, sorted."""
    return sorted(re.findall(r"^fuzz_reader!\(\s*(\w+)_mutated,", RUST_FUZZ.read_text(), re.M))


def _code_list(values: list[str]) -> str:
    return ", ".join(f"`{v}`" for v in values)


def constants(data_root: Path | None = None) -> dict[str, Any]:
    """The constants the pages show, from their sources."""
    readers_fuzz, api_fuzz = _fuzz_suites()
    (nasty,) = _search(RUST_FUZZ, r"NASTY_NUMBERS: \[&str; \d+\] = \[(.*?)\];")
    first, last = (int(v) for v in _search(RUST_FUZZ, r"vec\(mutation\(\), (\d+)\.\.(\d+)\)"))
    bytes_end = int(_search(RUST_FUZZ, r"vec\(any::<u8>\(\), 0\.\.(\d+)\)")[0])
    (hang_s,) = _search(RUST_FUZZ, r"const HANG: Duration = Duration::from_secs\((\d+)\);")
    python_readers = sorted(
        {
            reader.__qualname__
            for _, _, reader in readers_fuzz.READERS.values()
            if not reader.__name__.startswith("_")
        }
    )
    (force_g,) = _search(IMU_CSV, r"MAX_SPECIFIC_FORCE_M_S2: f64 = ([\d_.]+) \* STANDARD_GRAVITY")
    (share,) = _search(VALIDATE, r"if shortest\.1 < ([\d.]+) \* median \{")
    periods, floor_s = _search(VALIDATE, r"let limit = \(([\d.]+) \* median\)\.max\(([\d.]+)\);")
    rate_p99 = rust_const(IMU_CSV, "PLAUSIBLE_RATE_P99_RAD_S")
    rate_limit = rust_const(DIAGNOSTICS, "RATE_LIMIT_RAD_S")
    interval_s = rust_const(IMU_CSV, "PLAUSIBLE_INTERVAL_S")
    return {
        "limits": {
            name.lower(): rust_const(LIMITS, name)
            for name in (
                "MAX_RUNS",
                "MAX_TOTAL_RUNS",
                "MAX_THREADS",
                "MAX_SATELLITES",
                "MAX_DURATION_S",
                "MAX_SAMPLES",
                "MAX_SENSOR_MAGNITUDE",
                "MAX_SAMPLE_RATE_HZ",
                "MAX_IMU_PERIOD_S",
            )
        }
        | {
            name.lower(): rust_const(DOMAIN, name)
            for name in ("MAX_SPEED_M_S", "MIN_HEIGHT_M", "MAX_HEIGHT_M")
        },
        "imu_time": {
            "shortest_share_of_median": float(share),
            "gap_median_periods": float(periods),
            "gap_floor_s": float(floor_s),
        },
        "warnings": {
            "g_units_range": rust_const(DIAGNOSTICS, "G_UNITS_RANGE"),
            "rate_limit_rad_s": rate_limit,
            "rate_limit_deg_s": math.degrees(rate_limit),
            "rate_share_pct": 100 * rust_const(DIAGNOSTICS, "RATE_SHARE"),
            "divergence_share_pct": 100 * rust_const(INTEGRITY, "DIVERGENCE_REJECTED_SHARE"),
            "divergence_min_rejected": rust_const(INTEGRITY, "DIVERGENCE_MIN_REJECTED"),
            "divergence_min_span_s": rust_const(INTEGRITY, "DIVERGENCE_MIN_SPAN_S"),
            # 1 − the quantile's probability, exactly as the source writes it
            # (1.0 − 1e-9 in floating point is not 1 − 10⁻⁹ to the last bit).
            "outlier_tail": float(
                _search(INTEGRITY, r"OUTLIER_PROBABILITY: f64 = 1\.0 - ([\de.-]+);")[0]
            ),
        },
        "imu_csv": {
            "max_force_g": float(force_g.replace("_", "")),
            "max_rate_rad_s": rust_const(IMU_CSV, "MAX_ANGULAR_RATE_RAD_S"),
            "max_time_s": rust_const(IMU_CSV, "MAX_TIME_S"),
            "median_force_g": rust_const(IMU_CSV, "PLAUSIBLE_MEDIAN_FORCE_G"),
            "rate_p99_deg_s": math.degrees(rate_p99),
            "interval_us": 1e6 * interval_s[0],
            "interval_s": interval_s[1],
            "gap_intervals": rust_const(IMU_CSV, "GAP_INTERVALS"),
        },
        "fuzz": {
            "budgets": default_budgets(),
            "rust_readers": len(rust_readers()),
            "python_readers": len(readers_fuzz.READERS),
            "api_entries": len(api_fuzz.ENTRIES),
            "mutations_per_input": [first, last - 1],
            "random_bytes": [0, bytes_end - 1],
            "nasty_numbers": _code_list(re.findall(r'"([^"]+)"', nasty)),
            "rust_hang_s": int(hang_s),
            "python_reader_faces": _code_list(python_readers),
            "api_extremes": _code_list([repr(float(x)) for x in api_fuzz.EXTREMES]),
            "api_hang_s": api_fuzz.HANG_S,
        },
    }


def _simulate_gnss(**kwargs: Any) -> None:
    track = mn.Trajectory.random(duration=5.0, rate=10.0, seed=1)
    mn.simulate_gnss(
        track.time, track.position_ecef, track.velocity_ecef, mn.Constellation.walker(), **kwargs
    )


def _nan_at_row_100() -> None:
    xyz = np.tile([6.4e6, 0.0, 0.0], (200, 1))
    xyz[100, 2] = np.nan
    mn.ecef_to_geodetic(xyz)


def _flat_imu() -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    t = np.arange(0.0, 10.0, 0.01)
    f = np.tile([0.0, 0.0, -9.81], (len(t), 1))
    return t, f, np.zeros_like(f)


def _imu_and_gnss_times_apart() -> None:
    track = mn.Trajectory.random(duration=60.0, rate=100.0, seed=1)
    imu = mn.ImuModel.preset("paper-mems", seed=2)
    f, w = imu.measure(track.specific_force, track.angular_rate, seed=3)
    g = mn.simulate_gnss(
        track.time, track.position_ecef, track.velocity_ecef, mn.Constellation.walker(), seed=4
    )
    mn.TightlyCoupledFilter(imu).run(track.time + 1.4e9, f, w, g)


CALLS: dict[str, Callable[[], Any]] = {
    "too_many_runs": lambda: mn.experiments.navigation(runs=2**31),
    "nan_row": _nan_at_row_100,
    "text_for_a_number": lambda: _simulate_gnss(pseudorange_std="x"),
    "negative_seed": lambda: _simulate_gnss(seed=-1),
    "huge_noise_density": lambda: mn.TightlyCoupledFilter(
        mn.ImuModel.preset("consumer"), accel_noise_density=1e200
    ),
    "huge_initial_std": lambda: mn.TightlyCoupledFilter(
        mn.ImuModel.preset("consumer"), initial_position_std=1e200
    ),
    "no_gnss_epochs": lambda: mn.TightlyCoupledFilter(mn.ImuModel.preset("consumer")).run(
        *_flat_imu(), {"time": np.zeros(0), "sat_id": np.zeros(0)}
    ),
    "gnss_outside_imu_span": _imu_and_gnss_times_apart,
}
"""The calls whose errors the page quotes, by the record's key."""


def message(call: Callable[[], Any]) -> str:
    """The error ``call`` raises, as one line."""
    try:
        call()
    except (ValueError, TypeError, mn.MemsnavError) as error:
        return " ".join(str(error).split())
    raise AssertionError("the call raised no error")


def messages(data_root: Path | None = None) -> dict[str, str]:
    """What each of :data:`CALLS` says."""
    return {name: message(call) for name, call in CALLS.items()}
