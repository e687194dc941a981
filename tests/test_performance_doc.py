"""docs/results/performance.md's figures: its timings are the block that
docs/performance_tables.py writes (checked here against the measurements
it keeps in docs/performance.json, without running a benchmark: speed is
measured by the benchmarks, never by a test), and its reference workload
and floating-point count are the blocks docs/flop_count.py writes from
the benchmark sources and the non-zeros of Φ that
crates/memsnav-core/tests/phi_structure.rs counts from the code
(docs/data/phi_structure.json)."""

import json
import re
import runpy
from pathlib import Path

from figures import figures

ROOT = Path(__file__).resolve().parent.parent
PAGE = ROOT / "docs" / "results" / "performance.md"
SCRIPT = runpy.run_path(str(ROOT / "docs" / "performance_tables.py"))
FLOPS = runpy.run_path(str(ROOT / "docs" / "flop_count.py"))


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


def _block(begin: str, end: str) -> str:
    text = PAGE.read_text()
    assert text.count(begin) == 1 and text.count(end) == 1, begin
    return text[text.index(begin) : text.index(end) + len(end)]


def test_the_reference_workload_is_the_benchmarks():
    """The workload paragraph is what docs/flop_count.py writes from the
    Python benchmark's constants, and the Rust suites run the same one."""
    assert _block(*FLOPS["WORKLOAD"]) == FLOPS["render_workload"](), (
        "docs/results/performance.md's workload is stale: run python docs/flop_count.py --write"
    )
    w = FLOPS["workload"]()
    python = (ROOT / "benches" / "python" / "bench_tight.py").read_text()
    assert 'ImuModel.preset("paper-mems"' in python
    rust = (ROOT / "benches" / "lib.rs").read_text()
    assert 'ImuModel::preset("paper-mems"' in rust
    assert f"pub const SEED: u64 = {w['seed']};" in rust
    assert (
        f"TightScenario::new({w['duration_s']:.1f}, {w['satellites']})"
        in (ROOT / "benches" / "filter.rs").read_text()
    )
    assert (
        f"{w['states']} states"
        in json.loads((ROOT / "docs" / "performance.json").read_text())["python"]["workload"]
    )


def test_the_floating_point_count_adds_up():
    """The table of flops per IMU epoch is what docs/flop_count.py writes
    (on the non-zeros of Φ that crates/memsnav-core/tests/phi_structure.rs
    counts), and its parts add up to the totals it shows (each "≈" within
    1 %)."""
    assert _block(*FLOPS["FLOPS"]) == FLOPS["render_flops"](), (
        "docs/results/performance.md's flop count is stale: run python docs/flop_count.py --write"
    )
    f, w = FLOPS["flops"](), FLOPS["workload"]()
    assert f["covariance"] == 2 * f["one_product"] + w["states"]
    assert w["updates_per_epoch"] * FLOPS["JOSEPH_UPDATE_FLOPS"] <= f["per_second"]
    parts = FLOPS["MECHANIZATION_FLOPS"] + FLOPS["PHI_BLOCK_FLOPS"] + f["covariance"]
    assert abs(f["total"] - parts - f["per_second"] / w["rate_hz"]) <= 0.01 * f["total"]
    assert f["symmetric_total"] < f["total"]


def test_the_readme_s_step_api_rate_is_the_block_s():
    """The README shows the step API's rate from docs/data/step_api_rate.json
    (tests/test_doc_figures.py checks the rendering); that record is the
    `RunningFilter` rate of the measurements the block is rendered from."""
    record = json.loads((ROOT / "docs" / "performance.json").read_text())
    assert figures("step_api_rate") == SCRIPT["step_api_rate"](record), (
        "docs/data/step_api_rate.json is not docs/performance.json's rate: "
        "run python docs/performance_tables.py --from-existing --write"
    )
