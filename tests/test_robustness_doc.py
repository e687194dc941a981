"""docs/reference/robustness.md's figures are the code's: the fuzzing table is what
docs/fuzz_runs.py writes from its record (no fuzzing run here) and covers
the readers and entries the suites fuzz today; the records its budgets,
mutations, limits, warning thresholds and the IMU CSV reader's ranges
come from hold the constants of the code today, and the record of its
error messages holds what the calls say today (docs/robustness_reference.py).
The pages show the records through placeholders (tests/test_doc_figures.py)."""

import json
import runpy
from pathlib import Path

import pytest
import robustness_reference
import test_api_fuzz
import test_readers_fuzz
from figures import figures

ROOT = Path(__file__).resolve().parent.parent
PAGE = ROOT / "docs" / "reference" / "robustness.md"


def _script() -> dict:
    # Its sibling scripts are on the path: pytest's pythonpath.
    return runpy.run_path(str(ROOT / "docs" / "fuzz_runs.py"))


SCRIPT = _script()


def _fuzzed() -> dict[str, list[str]]:
    """What the last fuzzing run fuzzed, per suite (docs/fuzz_runs.json)."""
    record = json.loads((ROOT / "docs" / "fuzz_runs.json").read_text())
    return {run["suite"]: run["fuzzed"] for run in record["runs"]}


def test_the_fuzz_table_is_what_the_script_writes_from_its_record():
    text = PAGE.read_text()
    begin, end = SCRIPT["BEGIN"], SCRIPT["END"]
    block = text[text.index(begin) : text.index(end) + len(end)]
    record = json.loads((ROOT / "docs" / "fuzz_runs.json").read_text())
    assert block == SCRIPT["render"](record), (
        "docs/reference/robustness.md's fuzzing table is not what docs/fuzz_runs.py writes from "
        "docs/fuzz_runs.json: run python docs/fuzz_runs.py --write"
    )
    assert _fuzzed() == {
        "rust_readers": robustness_reference.rust_readers(),
        "python_readers": sorted(test_readers_fuzz.READERS),
        "numeric_api": sorted(test_api_fuzz.ENTRIES),
    }, "a reader or entry was added or removed: rerun python docs/fuzz_runs.py --write"


def test_the_constants_record_is_the_codes():
    """Every budget, mutation, limit, threshold and range the pages show,
    read anew from the Rust and Python sources that define it."""
    assert robustness_reference.constants() == figures("robustness_constants"), (
        "a constant the robustness pages show has changed: "
        "python docs/doc_runs.py robustness_constants"
    )


def test_the_constants_are_read_from_the_definitions():
    """The reader of the sources against values written here independently:
    a pattern that matched the wrong definition would not give these."""
    limits = robustness_reference.constants()["limits"]
    assert limits["max_threads"] == 1024 and limits["max_speed_m_s"] == 1e5
    interval = robustness_reference.rust_const(robustness_reference.IMU_CSV, "PLAUSIBLE_INTERVAL_S")
    assert interval == [1e-5, 0.5]
    fuzz = robustness_reference.constants()["fuzz"]
    fuzzed = _fuzzed()
    assert fuzz["rust_readers"] == len(fuzzed["rust_readers"])
    assert fuzz["python_readers"] == len(fuzzed["python_readers"])
    assert fuzz["api_entries"] == len(fuzzed["numeric_api"])


def test_the_messages_record_is_what_the_calls_say():
    assert robustness_reference.messages() == figures("robustness_messages"), (
        "an error message the robustness page quotes has changed: "
        "python docs/doc_runs.py robustness_messages"
    )


@pytest.mark.parametrize("name", sorted(robustness_reference.CALLS))
def test_each_quoted_call_fails_with_a_message_naming_its_argument(name):
    """The record's messages name what is wrong, before the first colon."""
    argument = robustness_reference.message(robustness_reference.CALLS[name]).split(":")[0]
    assert argument in {
        "runs",
        "xyz",
        "pseudorange_std",
        "seed",
        "accel_noise_density",
        "initial_position_std",
        "gnss.time",
        "gnss",
    }
