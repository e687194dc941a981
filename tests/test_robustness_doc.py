"""docs/reference/robustness.md's figures are the code's: the fuzzing table is what
docs/fuzz_runs.py writes from its record (no fuzzing run here) and covers
the readers and entries the suites fuzz today; the budgets, mutations,
limits and warning thresholds it quotes are the constants of the code; the
error messages it quotes are what the calls say."""

import json
import math
import re
import runpy
import sys
from pathlib import Path

import numpy as np
import pytest
import test_api_fuzz
import test_readers_fuzz
from doc_pages import NAVIGATE_GUIDE, doc_text

import memsnav as mn

ROOT = Path(__file__).resolve().parent.parent
PAGE = ROOT / "docs" / "reference" / "robustness.md"
RUST_FUZZ = ROOT / "crates" / "memsnav-core" / "tests" / "readers_fuzz.rs"
CORE = ROOT / "crates" / "memsnav-core" / "src"


def _script() -> dict:
    # Its sibling scripts are on the path: pytest's pythonpath.
    return runpy.run_path(str(ROOT / "docs" / "fuzz_runs.py"))


SCRIPT = _script()


def _page() -> str:
    return " ".join(PAGE.read_text().split())


def _quoted(pattern: str) -> tuple[str, ...]:
    found = re.search(pattern, _page())
    assert found, f"docs/reference/robustness.md no longer quotes {pattern!r}"
    return found.groups()


SUPERSCRIPT = str.maketrans("⁰¹²³⁴⁵⁶⁷⁸⁹⁻", "0123456789-")


def _doc_number(text: str) -> float:
    """A figure as the page writes it: "1024", "10⁶", "−10⁵", "10⁻⁹"."""
    text = text.replace("−", "-").strip()
    power = re.fullmatch(r"(-?)10([⁰¹²³⁴⁵⁶⁷⁸⁹⁻]+)", text)
    if power:
        return float(f"{power.group(1)}1e{power.group(2).translate(SUPERSCRIPT)}")
    return float(text)


def _const(path: Path, name: str) -> object:
    """A Rust constant's value (a literal or an expression of literals)."""
    found = re.search(rf"const {name}: [^=]+ = ([^;]+);", path.read_text())
    assert found, f"{path.name} no longer defines {name}"
    return eval(found.group(1).replace("_", ""), {"__builtins__": {}})


def _rust_readers() -> list[str]:
    return sorted(re.findall(r"^fuzz_reader!\(\s*(\w+)_mutated,", RUST_FUZZ.read_text(), re.M))


def test_the_fuzz_table_is_what_the_script_writes_from_its_record():
    text = PAGE.read_text()
    begin, end = SCRIPT["BEGIN"], SCRIPT["END"]
    block = text[text.index(begin) : text.index(end) + len(end)]
    record = json.loads((ROOT / "docs" / "fuzz_runs.json").read_text())
    assert block == SCRIPT["render"](record), (
        "docs/reference/robustness.md's fuzzing table is not what docs/fuzz_runs.py writes from "
        "docs/fuzz_runs.json: run python docs/fuzz_runs.py --write"
    )
    fuzzed = {run["suite"]: run["fuzzed"] for run in record["runs"]}
    assert fuzzed == {
        "rust_readers": _rust_readers(),
        "python_readers": sorted(test_readers_fuzz.READERS),
        "numeric_api": sorted(test_api_fuzz.ENTRIES),
    }, "a reader or entry was added or removed: rerun python docs/fuzz_runs.py --write"


def test_the_budgets_are_the_suites_defaults():
    rust, rust_readers, python, python_readers, api, entries = _quoted(
        r"(\d+) inputs per reader and kind in Rust \((\d+) readers × 2 kinds\), (\d+) "
        r"derandomised examples per reader and kind in Python \((\d+) readers × 2 kinds\) and "
        r"(\d+) per entry of the numeric API \((\d+) entries\)"
    )
    defaults = SCRIPT["default_budgets"]()
    assert int(rust) == defaults["rust_readers"]
    assert int(python) == defaults["python_readers"]
    assert int(api) == defaults["numeric_api"]
    assert int(rust_readers) == len(_rust_readers())
    assert int(python_readers) == len(test_readers_fuzz.READERS)
    assert int(entries) == len(test_api_fuzz.ENTRIES)


def test_the_mutations_quoted_are_the_suites():
    rust = RUST_FUZZ.read_text()
    nasty = re.search(r"NASTY_NUMBERS: \[&str; \d+\] = \[(.*?)\];", rust, re.S).group(1)
    nasty_values = re.findall(r'"([^"]+)"', nasty)
    (listed,) = _quoted(r"a number replaced by (.*?), bytes inserted")
    for value in re.findall(r"`([^`]+)`", listed):
        assert value in nasty_values, value
    assert "a 20-digit integer" in listed and any(
        v.isdigit() and len(v) == 20 for v in nasty_values
    )
    assert "2³²" in listed and str(2**32) in nasty_values
    assert "a subnormal" in listed and any(
        0 < float(v) < sys.float_info.min for v in nasty_values if "e-" in v
    )
    assert _quoted(r"Each input applies (one) to (four) mutations") == ("one", "four")
    assert "proptest::collection::vec(mutation(), 1..5)" in rust
    assert _quoted(r"followed by (\d+) to (\d+) random bytes") == ("0", "599")
    assert "proptest::collection::vec(any::<u8>(), 0..600)" in rust
    (hang,) = _quoted(r"a panic, no answer within (\d+) s")
    assert f"const HANG: Duration = Duration::from_secs({hang});" in rust
    # The numeric API: the extremes and the hang.
    (extremes,) = _quoted(r"whole array\) by (.*?) or any float")
    assert extremes == (
        "±0, ±1, ±1e-300, the smallest subnormal, ±10⁶, ±10³⁰⁰, the largest float, NaN, ±inf"
    )
    named = [0.0, -0.0, 1.0, -1.0, 1e-300, -1e-300, 5e-324, 1e6, -1e6, 1e300, -1e300]
    named += [sys.float_info.max, math.inf, -math.inf]
    drawn = [float(x) for x in test_api_fuzz.EXTREMES]
    assert sorted(x for x in drawn if not math.isnan(x)) == sorted(named)
    assert sum(math.isnan(x) for x in drawn) == 1
    (api_hang,) = _quoted(r"The call must return within (\d+) s")
    assert float(api_hang) == test_api_fuzz.HANG_S


def test_the_python_readers_fuzzed_are_the_ones_listed():
    (listed,) = _quoted(r"through the Python faces \((.*?)\), written to a file")
    names = set(re.findall(r"`(?:mn\.)?([\w.]+)`", listed))
    public = {
        reader.__qualname__
        for _, _, reader in test_readers_fuzz.READERS.values()
        if not reader.__name__.startswith("_")
    }
    assert public <= names, public - names


def test_the_api_entries_fuzzed_are_the_ones_listed():
    """Each entry of tests/test_api_fuzz.py under the words the page uses."""
    words = {
        "strapdown": "`strapdown`",
        "simulate_gnss": "`simulate_gnss`",
        "solve_fix": "`solve_fix`",
        "accelerometer": "`AccelerometerModel`",
        "gyroscope": "`GyroscopeModel`",
        "imu_spec": "an `ImuModel` with every `spec` key given",
        "tight": "both filters' constructors and `run`",
        "loose": "both filters' constructors and `run`",
        "running_filter": "a `RunningFilter` loop",
    }
    assert set(words) == set(test_api_fuzz.ENTRIES)
    page = _page()
    assert all(w in page for w in words.values()), [w for w in words.values() if w not in page]


LIMITS = CORE / "limits.rs"
DOMAIN = CORE / "geodesy" / "domain.rs"


def _limit_row(first_cell: str) -> str:
    rows = [r for r in PAGE.read_text().splitlines() if r.startswith(f"| {first_cell}")]
    assert len(rows) == 1, f"the limits table has no single row {first_cell!r}"
    return rows[0].split(" | ")[1]


@pytest.mark.parametrize(
    ("row", "pattern", "constants"),
    [
        ("`runs`, `parameter_sets`", r"≤ (\S+) each", [(LIMITS, "MAX_RUNS")]),
        ("runs × parameter sets", r"≤ (\S+)", [(LIMITS, "MAX_TOTAL_RUNS")]),
        ("`threads`", r"≤ (\S+)", [(LIMITS, "MAX_THREADS")]),
        ("`simulate_gnss(n_satellites=)`", r"≤ (\S+)", [(LIMITS, "MAX_SATELLITES")]),
        (
            "duration of a simulated",
            r"≤ (\S+) s, ≤ (\S+) samples",
            [(LIMITS, "MAX_DURATION_S"), (LIMITS, "MAX_SAMPLES")],
        ),
        ("sensor magnitudes", r"\\\|x\\\| ≤ (\S+) \(SI", [(LIMITS, "MAX_SENSOR_MAGNITUDE")]),
        ("sensor `sample_rate`", r"≤ (\S+) Hz", [(LIMITS, "MAX_SAMPLE_RATE_HZ")]),
        ("speeds:", r"≤ (\S+) m/s", [(DOMAIN, "MAX_SPEED_M_S")]),
        (
            "geodetic input `lla`",
            r"height in \[(\S+), (\S+)\] m",
            [(DOMAIN, "MIN_HEIGHT_M"), (DOMAIN, "MAX_HEIGHT_M")],
        ),
        ("IMU `time`", r"median period ≤ (\S+) s", [(LIMITS, "MAX_IMU_PERIOD_S")]),
    ],
)
def test_the_limits_are_the_codes_constants(row, pattern, constants):
    found = re.search(pattern, _limit_row(row))
    assert found, (row, pattern)
    quoted = [_doc_number(v) for v in found.groups()]
    assert quoted == [float(_const(path, name)) for path, name in constants]


def test_the_imu_time_rule_is_the_codes():
    cell = _limit_row("IMU `time`")
    assert "no interval shorter than a hundredth of it" in cell
    assert "no gap longer than max(1 s, 100 × median period)" in cell
    code = (CORE / "validate.rs").read_text()
    assert "if shortest.1 < 0.01 * median {" in code
    assert "let limit = (100.0 * median).max(1.0);" in code


def test_the_warning_thresholds_are_the_codes():
    diagnostics = CORE / "coupling" / "diagnostics.rs"
    integrity = CORE / "coupling" / "integrity.rs"
    low, high = _quoted(r"median magnitude is between ([\d.]+) and ([\d.]+) warns")
    assert (float(low), float(high)) == _const(diagnostics, "G_UNITS_RANGE")
    rad_s, deg_s, share = _quoted(r"angular rates above ([\d.]+) rad/s \((\d+) deg/s\) in (\d+) %")
    assert float(rad_s) == _const(diagnostics, "RATE_LIMIT_RAD_S")
    assert int(deg_s) == round(math.degrees(float(rad_s)))
    assert float(share) / 100 == _const(diagnostics, "RATE_SHARE")
    share, least, span = _quoted(
        r"When (\d+) % or more of the GNSS batches .*? at least (\d+), spread over (\d+) s"
    )
    assert float(share) / 100 == _const(integrity, "DIVERGENCE_REJECTED_SHARE")
    assert int(least) == _const(integrity, "DIVERGENCE_MIN_REJECTED")
    assert float(span) == _const(integrity, "DIVERGENCE_MIN_SPAN_S")
    (power,) = _quoted(r"chi-square quantile of 1 − (10⁻[⁰¹²³⁴⁵⁶⁷⁸⁹]+)")
    assert 1.0 - _doc_number(power) == _const(integrity, "OUTLIER_PROBABILITY")


def _imu_and_gnss_times_apart():
    track = mn.Trajectory.random(duration=60.0, rate=100.0, seed=1)
    imu = mn.ImuModel.preset("paper-mems", seed=2)
    f, w = imu.measure(track.specific_force, track.angular_rate, seed=3)
    g = mn.simulate_gnss(
        track.time, track.position_ecef, track.velocity_ecef, mn.Constellation.walker(), seed=4
    )
    mn.TightlyCoupledFilter(imu).run(track.time + 1.4e9, f, w, g)


def _flat_imu():
    t = np.arange(0.0, 10.0, 0.01)
    f = np.tile([0.0, 0.0, -9.81], (len(t), 1))
    return t, f, np.zeros_like(f)


def _nan_at_row_100():
    xyz = np.tile([6.4e6, 0.0, 0.0], (200, 1))
    xyz[100, 2] = np.nan
    mn.ecef_to_geodetic(xyz)


def _simulate_gnss(**kwargs):
    track = mn.Trajectory.random(duration=5.0, rate=10.0, seed=1)
    mn.simulate_gnss(
        track.time, track.position_ecef, track.velocity_ecef, mn.Constellation.walker(), **kwargs
    )


@pytest.mark.parametrize(
    ("quoted", "call"),
    [
        (
            "runs: 2147483648 is more than the limit of 1000000 runs per set",
            lambda: mn.experiments.navigation(runs=2**31),
        ),
        ("xyz: row 100, column 2 is NaN", _nan_at_row_100),
        (
            "pseudorange_std: must be a real number, got 'x' (str)",
            lambda: _simulate_gnss(pseudorange_std="x"),
        ),
        (
            "seed: must be None or an integer in [0, 2**64), got -1",
            lambda: _simulate_gnss(seed=-1),
        ),
        (
            "accel_noise_density: 1e200 is too large",
            lambda: mn.TightlyCoupledFilter(
                mn.ImuModel.preset("consumer"), accel_noise_density=1e200
            ),
        ),
        (
            "initial_position_std: 1e200 is out of range",
            lambda: mn.TightlyCoupledFilter(
                mn.ImuModel.preset("consumer"), initial_position_std=1e200
            ),
        ),
        (
            "gnss.time: has no epochs (length 0)",
            lambda: mn.TightlyCoupledFilter(mn.ImuModel.preset("consumer")).run(
                *_flat_imu(), {"time": np.zeros(0), "sat_id": np.zeros(0)}
            ),
        ),
        (
            "gnss: no epoch falls inside the IMU span [1400000000.000, 1400000060.000] s: the "
            "epochs span [0.000, 60.000] s",
            _imu_and_gnss_times_apart,
        ),
    ],
)
def test_the_quoted_error_messages_are_what_the_calls_say(quoted, call):
    assert quoted in _page(), f"docs/reference/robustness.md no longer quotes {quoted!r}"
    with pytest.raises((ValueError, TypeError, mn.MemsnavError)) as caught:
        call()
    assert quoted in " ".join(str(caught.value).split())


def test_the_imu_csv_ranges_real_data_lists_are_the_readers():
    """robustness.md points to the navigate guide (Readers) for each reader's
    ranges; the IMU CSV reader's there are the constants of
    crates/memsnav-core/src/logs/imu_csv.rs."""
    page = " ".join(doc_text(*NAVIGATE_GUIDE).split())
    found = re.search(
        r"\|f\| ≤ (\d+) g, \|ω\| ≤ (\d+) rad/s, .*?\|t\| ≤ (10\S+) s\).*?a median \|f\| outside "
        r"([\d.]+)-([\d.]+) g .*?(\d+) % of the rates above (\d+) °/s .*?a median sample "
        r"interval outside (\d+) µs-([\d.]+) s .*?jumps in time longer than (\d+) s and (\d+) "
        r"intervals",
        page,
    )
    assert found, "the navigate guide no longer lists the IMU CSV reader's ranges"
    g, w, t, f_low, f_high, share, deg_s, dt_low, dt_high, gap_s, gap_n = found.groups()
    source = (CORE / "logs" / "imu_csv.rs").read_text()
    assert f"MAX_SPECIFIC_FORCE_M_S2: f64 = {int(g):_}.0 * STANDARD_GRAVITY_M_S2;" in source
    assert float(w) == _const(CORE / "logs" / "imu_csv.rs", "MAX_ANGULAR_RATE_RAD_S")
    assert _doc_number(t) == _const(CORE / "logs" / "imu_csv.rs", "MAX_TIME_S")
    force = re.search(r"PLAUSIBLE_MEDIAN_FORCE_G: [^=]+ = ([\d.]+)..=([\d.]+);", source)
    assert (float(force.group(1)), float(force.group(2))) == (float(f_low), float(f_high))
    p99 = _const(CORE / "logs" / "imu_csv.rs", "PLAUSIBLE_RATE_P99_RAD_S")
    assert share == "1" and "1 % of the angular rates exceed" in source  # the 99th percentile
    assert int(deg_s) == round(math.degrees(p99))
    interval = re.search(r"PLAUSIBLE_INTERVAL_S: [^=]+ = ([\d.e-]+)..=([\d.]+);", source)
    assert (float(interval.group(1)), float(interval.group(2))) == (
        float(dt_low) / 1e6,
        float(dt_high),
    )
    assert float(gap_n) == _const(CORE / "logs" / "imu_csv.rs", "GAP_INTERVALS")
    assert gap_s == "1" and "(and than 1 s)" in source
