"""The fuzzing runs docs/reference/robustness.md quotes, measured anew:
``python docs/fuzz_runs.py [--rust-cases N] [--python-examples N]
[--api-examples N] [--write]``.

Runs the three fuzzing suites with the budgets given (by default the
suites' own, which CI runs: ``default_budgets``) through their environment variables
(``MEMSNAV_FUZZ_CASES`` for the Rust readers, ``MEMSNAV_FUZZ_EXAMPLES`` for
the Python readers and the numeric API), each timed (wall and CPU), and
prints the page's table: per suite the budget, what was fuzzed (the
readers or entries that passed, read from the run's own report), the
inputs and the times, with the machine and its load. A failing suite
stops the script: a failure is fixed (and its input kept in
``tests/data/regressions/``), not documented. ``--write`` keeps the record
in ``docs/fuzz_runs.json`` and puts the table between docs/reference/robustness.md's
``fuzz`` markers; the table is ``render`` of that record
(tests/test_robustness_doc.py checks it).
"""

from __future__ import annotations

import argparse
import datetime
import json
import os
import re
import sys
from pathlib import Path
from typing import Any

from marked_block import replace_block
from performance_tables import cpu_model
from timings import timed

ROOT = Path(__file__).resolve().parents[1]
PAGE = ROOT / "docs" / "reference" / "robustness.md"
RECORD = ROOT / "docs" / "fuzz_runs.json"
BEGIN, END = "<!-- fuzz:begin -->", "<!-- fuzz:end -->"

#: suite: (what it is, environment variable, the command, the pattern of a
#: passed per-reader test in its verbose report: its group is the reader,
#: kinds: tests per reader and budget unit).
SUITES: dict[str, dict[str, Any]] = {
    "rust_readers": {
        "what": "Rust readers (`crates/memsnav-core/tests/readers_fuzz.rs`, proptest)",
        "variable": "MEMSNAV_FUZZ_CASES",
        "command": ["cargo", "test", "-p", "memsnav-core", "--release", "--test", "readers_fuzz"],
        "passed": r"^test (\w+)_(?:mutated|garbage) \.\.\. ok$",
        "kinds": "mutated + garbage",
    },
    "python_readers": {
        "what": "Python readers (`tests/test_readers_fuzz.py`, hypothesis)",
        "variable": "MEMSNAV_FUZZ_EXAMPLES",
        "command": [sys.executable, "-m", "pytest", "tests/test_readers_fuzz.py", "-v"],
        "passed": r"::test_(?:mutated_files_give_a_result_or_an_error_naming_the_file|"
        r"garbage_after_a_valid_beginning)\[(\w+)\] PASSED",
        "kinds": "mutated + garbage",
    },
    "numeric_api": {
        "what": "numeric API (`tests/test_api_fuzz.py`, hypothesis)",
        "variable": "MEMSNAV_FUZZ_EXAMPLES",
        "command": [sys.executable, "-m", "pytest", "tests/test_api_fuzz.py", "-v"],
        "passed": r"::test_extreme_arguments_give_finite_results_or_a_named_error\[(\w+)\] PASSED",
        "kinds": "mutated arguments",
    },
}


def default_budgets() -> dict[str, int]:
    """Each suite's budget when its variable is not set, read from its
    source (one place holds each figure)."""
    rust = (ROOT / "crates" / "memsnav-core" / "tests" / "readers_fuzz.rs").read_text()
    found = {
        "rust_readers": re.search(r'"MEMSNAV_FUZZ_CASES"\)[^;]*?unwrap_or\((\d+)\)', rust, re.S)
    }
    for suite, test in (("python_readers", "test_readers_fuzz"), ("numeric_api", "test_api_fuzz")):
        source = (ROOT / "tests" / f"{test}.py").read_text()
        found[suite] = re.search(r'os\.environ\.get\("MEMSNAV_FUZZ_EXAMPLES", "(\d+)"\)', source)
    missing = [suite for suite, match in found.items() if match is None]
    if missing:
        sys.exit(f"no default budget found in the source of {missing}")
    return {suite: int(match.group(1)) for suite, match in found.items() if match}


def run(suite: str, budget: int) -> dict[str, Any]:
    s = SUITES[suite]
    if suite == "rust_readers":  # built first: the time is the fuzzing's
        timed([*s["command"], "--no-run"])
    os.environ[s["variable"]] = str(budget)
    try:
        wall, cpu, out = timed(s["command"])
    finally:
        del os.environ[s["variable"]]
    passed = re.findall(s["passed"], out, flags=re.M)
    tests = int(re.findall(r"(\d+) passed", out)[-1])
    return {
        "suite": suite,
        "budget": budget,
        "fuzzed": sorted(set(passed)),
        "per_fuzzed": len(passed) // max(1, len(set(passed))),
        "tests_passed": tests,
        "wall_s": wall,
        "cpu_s": cpu,
    }


def minutes(seconds: float) -> str:
    return f"{seconds:.0f} s" if seconds < 120 else f"{seconds / 60:.0f} min"


def render(record: dict[str, Any]) -> str:
    m = record["machine"]
    load = f"load average {m['load_start']:.1f} at the start, {m['load_end']:.1f} at the end"
    if max(m["load_start"], m["load_end"]) > m["cpus"]:
        load += " (other jobs shared the machine: the wall times are longer than on a quiet one)"
    rows = []
    for r in record["runs"]:
        s = SUITES[r["suite"]]
        inputs = r["budget"] * r["per_fuzzed"] * len(r["fuzzed"])
        per = "per entry" if r["suite"] == "numeric_api" else "per reader and kind"
        fuzzed = ", ".join(f"`{n}`" for n in r["fuzzed"])
        rows.append(
            f"| {s['what']} | `{s['variable']}={r['budget']}` {per} | "
            f"{len(r['fuzzed'])}: {fuzzed} | {f'{inputs:,}'.replace(',', ' ')} ({s['kinds']}) | "
            f"{r['tests_passed']} tests passed | {minutes(r['wall_s'])} | {minutes(r['cpu_s'])} |"
        )
    return "\n".join(
        [
            BEGIN,
            "",
            f"Measured by `python docs/fuzz_runs.py {record['arguments']}` on {m['date']}: "
            f"{m['cpu']}, {m['cpus']} CPUs, {load}; release build. A suite passes when no "
            "input gives what its section above forbids (a panic, a hang, an error that does "
            "not name the file or the argument, an out-of-range or non-finite result).",
            "",
            "| suite | budget | fuzzed | inputs | result | wall time | CPU time |",
            "|---|---|---|---|---|---|---|",
            *rows,
            "",
            END,
        ]
    )


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    defaults = default_budgets()
    parser.add_argument(
        "--rust-cases",
        type=int,
        default=defaults["rust_readers"],
        help="Rust inputs per reader and kind",
    )
    parser.add_argument(
        "--python-examples",
        type=int,
        default=defaults["python_readers"],
        help="Python examples per reader and kind",
    )
    parser.add_argument(
        "--api-examples", type=int, default=defaults["numeric_api"], help="examples per API entry"
    )
    parser.add_argument("--write", action="store_true", help="update docs/reference/robustness.md")
    parser.add_argument(
        "--from-record",
        action="store_true",
        help="run nothing: the table from docs/fuzz_runs.json (after a change of its layout)",
    )
    args = parser.parse_args()
    if args.from_record:
        record = json.loads(RECORD.read_text())
        write(render(record), record if args.write else None)
        return
    machine = {
        "date": datetime.datetime.now(datetime.UTC).strftime("%Y-%m-%d %H:%M UTC"),
        "cpu": cpu_model(),
        "cpus": os.cpu_count(),
        "load_start": os.getloadavg()[0],
    }
    runs = [
        run("rust_readers", args.rust_cases),
        run("python_readers", args.python_examples),
        run("numeric_api", args.api_examples),
    ]
    machine["load_end"] = os.getloadavg()[0]
    record = {
        "arguments": f"--rust-cases {args.rust_cases} --python-examples "
        f"{args.python_examples} --api-examples {args.api_examples}",
        "machine": machine,
        "runs": runs,
    }
    write(render(record), record if args.write else None)


def write(text: str, record: dict[str, Any] | None) -> None:
    """Prints the table; with a record, keeps it and puts the table in the page."""
    print(text)
    if record is not None:
        RECORD.write_text(json.dumps(record, indent=1, ensure_ascii=False) + "\n")
        replace_block(PAGE, BEGIN, END, text)


if __name__ == "__main__":
    main()
