"""docs/results/performance.md's figures: its timings are the block that
docs/performance_tables.py writes (checked here against the measurements
it keeps in docs/performance.json, without running a benchmark: speed is
measured by the benchmarks, never by a test), and its other figures (the
reference workload, the floating-point count) are checked against the
benchmark sources and their own arithmetic. The 58 non-zeros of Φ the
count is built on are counted from the code by
crates/memsnav-core/tests/quoted_figures.rs."""

import json
import re
import runpy
from pathlib import Path

ROOT = Path(__file__).resolve().parent.parent
PAGE = ROOT / "docs" / "results" / "performance.md"
SCRIPT = runpy.run_path(str(ROOT / "docs" / "performance_tables.py"))


def _page() -> str:
    return " ".join(PAGE.read_text().split())


def _number(text: str) -> float:
    """A figure as the page writes it: "60 001", "≈ 3 960"."""
    return float(text.replace("≈", "").replace(" ", ""))


def test_the_block_is_what_the_script_writes_from_its_record():
    text = PAGE.read_text()
    begin, end = SCRIPT["BEGIN"], SCRIPT["END"]
    assert text.count(begin) == 1 and text.count(end) == 1
    block = text[text.index(begin) : text.index(end) + len(end)]
    record = json.loads((ROOT / "docs" / "performance.json").read_text())
    assert block == SCRIPT["render"](record), (
        "docs/results/performance.md's figures are not what docs/performance_tables.py writes from "
        "docs/performance.json: run python docs/performance_tables.py --write "
        "(--from-existing to reuse the last results)"
    )


def _bench_groups() -> set[str]:
    """The criterion groups the suites define (a literal group name, or one
    passed to the navigation suite's helper)."""
    groups = set()
    for suite in SCRIPT["SUITES"]:
        source = (ROOT / "benches" / f"{suite}.rs").read_text()
        groups |= set(re.findall(r'benchmark_group\("([^"]+)"\)', source))
        groups |= set(re.findall(r'navigation_group\(\s*c,\s*"([^"]+)"', source))
    return groups


def test_the_record_has_every_benchmark_group_of_the_suites_and_no_other():
    """The rows the script writes are one per benchmark of the suites: a
    group added to or removed from benches/*.rs needs a new run."""
    record = json.loads((ROOT / "docs" / "performance.json").read_text())
    recorded = {b["group"] for b in record["criterion"]}
    assert recorded == _bench_groups(), recorded ^ _bench_groups()
    assert all(SCRIPT["suite_of"](group) for group in recorded)


def _constant(source: str, name: str) -> float:
    found = re.search(rf"^{name} = ([\d.]+)$", source, re.M)
    assert found, name
    return float(found.group(1))


def test_the_reference_workload_is_the_benchmarks():
    """ "600 s random land-vehicle trajectory (Toulouse) at 100 Hz = 60 001
    IMU epochs, the paper's MEMS IMU (`paper-mems`), 1 Hz GNSS with 6
    satellites (... 12 scalar updates per epoch, 600 epochs), 17-state"."""
    page = _page()
    found = re.search(
        r"([\d.]+) s random land-vehicle trajectory \(Toulouse\) at ([\d.]+) Hz = ([\d ]+) IMU "
        r"epochs, the paper's MEMS IMU \(`([\w-]+)`\), ([\d.]+) Hz GNSS with (\d+) satellites "
        r"\(pseudorange \+ pseudorange rate: (\d+) scalar updates per epoch, ([\d ]+) epochs\), "
        r"(\d+)-state",
        page,
    )
    assert found, "docs/results/performance.md no longer describes the reference workload"
    duration, rate, epochs, preset, gnss_hz, sats, updates, gnss_epochs, states = found.groups()
    python = (ROOT / "benches" / "python" / "bench_tight.py").read_text()
    assert float(duration) == _constant(python, "DURATION_S")
    assert float(rate) == _constant(python, "RATE_HZ")
    assert int(sats) == _constant(python, "N_SATELLITES")
    assert f'ImuModel.preset("{preset}"' in python
    assert _number(epochs) == float(duration) * float(rate) + 1  # both ends sampled
    assert int(updates) == 2 * int(sats)  # a pseudorange and a rate per satellite
    assert _number(gnss_epochs) == float(duration) * float(gnss_hz)
    rust = (ROOT / "benches" / "lib.rs").read_text()
    assert f'ImuModel::preset("{preset}"' in rust
    assert (
        f"TightScenario::new({float(duration):.1f}, {sats})"
        in (ROOT / "benches" / "filter.rs").read_text()
    )
    assert (
        f"{states} states"
        in json.loads((ROOT / "docs" / "performance.json").read_text())["python"]["workload"]
    )
    (seed,) = re.search(r"`memsnav_benches::SEED` = (\d+)", page).groups()
    assert f"pub const SEED: u64 = {seed};" in rust
    assert _constant(python, "SEED") == int(seed)


def test_the_floating_point_count_adds_up():
    """The table of flops per IMU epoch: its products, sums and the amortised
    updates are the arithmetic of its own entries (each "≈" within 1 %)."""
    page = _page()
    terms, rows = (
        int(v) for v in re.search(r"M Φᵀ: (\d+) column terms × (\d+) rows × 2", page).groups()
    )
    (one_product,) = re.search(r"× 2 \| ([\d ]+) \|", page).groups()
    assert _number(one_product) == terms * rows * 2
    (covariance,) = re.search(r"two products \+ Q \| \| (≈ [\d ]+) \|", page).groups()
    # Q adds its diagonal to the two products.
    assert abs(_number(covariance) - (2 * _number(one_product) + rows)) <= 0.01 * 3960
    update, per_epoch, per_second, amortised, rate = re.search(
        r"symmetrisation (≈ [\d ]+) flops; (\d+) per GNSS epoch \+ range predictions "
        r"(≈ [\d ]+) per second \| \| (≈ [\d ]+) \(amortised over (\d+) IMU epochs\)",
        page,
    ).groups()
    assert int(per_epoch) * _number(update) <= _number(per_second)
    assert _number(amortised) == _number(per_second) / int(rate)
    parts = [
        _number(v)
        for v in re.search(
            r"\| mechanization .*? \| (≈ [\d ]+) \| [\d ]+ \| \| Φ blocks .*? \| (≈ [\d ]+) \|",
            page,
        ).groups()
    ]
    (total,) = re.search(r"\*\*total\*\* \| \| \*\*(≈ [\d ]+)\*\*", page).groups()
    whole = sum(parts) + _number(covariance) + _number(amortised)
    assert abs(_number(total) - whole) <= 0.01 * whole
    symmetric, symmetric_total = re.search(
        r"covariance could drop to (≈ [\d ]+) flops \(design note\), (≈ [\d ]+) in total", page
    ).groups()
    lower = _number(total) - _number(covariance) + _number(symmetric)
    assert abs(_number(symmetric_total) - lower) <= 0.02 * lower


def test_the_readme_quotes_the_step_api_rate_of_the_block():
    """The README's "about 330 k IMU steps/s from a Python loop" is the
    `RunningFilter` row of the block (a timing: within a factor of 2 of
    what the script last measured, the README naming the page)."""
    readme = " ".join((ROOT / "README.md").read_text().split())
    quoted = re.search(r"about (\d+) k IMU steps/s from a Python loop \(on the", readme)
    assert quoted, "the README no longer quotes the step API's rate"
    measured = re.search(
        r"\| `RunningFilter` loop from Python, per IMU sample \| [\d.]+ µs \((\d+) k samples/s\)",
        _page(),
    )
    assert measured, "docs/results/performance.md's block has no RunningFilter row"
    ratio = float(quoted.group(1)) / float(measured.group(1))
    assert 0.5 <= ratio <= 2.0, (quoted.group(1), measured.group(1))
