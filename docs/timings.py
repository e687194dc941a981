"""The run times the README quotes, measured anew:
``python docs/timings.py [--tests] [--write]``.

Times ``memsnav reproduce`` with its quick and (unless ``--no-full``) its
full (the paper's) Monte Carlo sizes, each in a temporary folder, on every core this process
may use: wall time and CPU time (the children's user + system), with the
machine and its load average when measured (other jobs on the machine
lengthen the wall time). ``--tests`` also times both test tiers
(``pytest -m "not slow"`` and all) and counts their tests. Prints the
README's block; ``--write`` puts it between the README's ``timings``
markers.
"""

from __future__ import annotations

import argparse
import datetime
import os
import platform
import re
import resource
import subprocess
import sys
import tempfile
import time
from pathlib import Path

from marked_block import replace_block

from memsnav.reproduce import FULL, QUICK, Sizes, worker_threads

ROOT = Path(__file__).resolve().parents[1]
BEGIN, END = "<!-- timings:begin -->", "<!-- timings:end -->"


def timed(command: list[str]) -> tuple[float, float, str]:
    """Wall and CPU seconds of ``command`` (a child process), and its output."""
    before = resource.getrusage(resource.RUSAGE_CHILDREN)
    started = time.perf_counter()
    done = subprocess.run(command, capture_output=True, text=True, check=False, cwd=ROOT)
    wall = time.perf_counter() - started
    after = resource.getrusage(resource.RUSAGE_CHILDREN)
    if done.returncode != 0:
        sys.exit(f"{' '.join(command)} failed:\n{done.stdout[-2000:]}\n{done.stderr[-2000:]}")
    cpu = (after.ru_utime - before.ru_utime) + (after.ru_stime - before.ru_stime)
    return wall, cpu, done.stdout


def sizes(s: Sizes) -> str:
    return (
        f"calibration {s.calibration_sets} sets × {s.calibration_runs} runs, inversion "
        f"{s.inversion_runs}, navigation {s.navigation_runs} runs × 2 scenarios, partial "
        f"outages {s.partial_outage_runs} runs"
    )


def reproduce_rows(full: bool = True) -> list[str]:
    rows = []
    runs = [("`memsnav reproduce` (quick)", [], QUICK)]
    if full:
        runs.append(("`memsnav reproduce --full` (the paper's)", ["--full"], FULL))
    for label, flags, s in runs:
        with tempfile.TemporaryDirectory() as out:
            command = [sys.executable, "-m", "memsnav", "reproduce", "--quiet", "--out", out]
            wall, cpu, _ = timed(command + flags)
        rows.append(f"| {label} | {sizes(s)} | {wall:.0f} s | {cpu:.0f} s |")
    return rows


def test_rows() -> list[str]:
    rows = []
    for label, marker in (('fast tier, `-m "not slow"`', ["-m", "not slow"]), ("all", [])):
        wall, cpu, out = timed([sys.executable, "-m", "pytest", "tests", "-q", *marker])
        passed = re.search(r"(\d+) passed", out)
        count = passed.group(1) if passed else "?"
        rows.append(f"| Python tests, {label} | {count} tests | {wall:.0f} s | {cpu:.0f} s |")
    return rows


def cpu_model() -> str:
    """The processor's name (Linux: /proc/cpuinfo), else the platform's."""
    try:
        for line in Path("/proc/cpuinfo").read_text().splitlines():
            if line.startswith("model name"):
                return line.split(":", 1)[1].strip()
    except OSError:
        pass
    return platform.processor() or platform.machine()


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--tests", action="store_true", help="also time the test tiers")
    parser.add_argument(
        "--no-full", action="store_true", help="time the quick run only, not --full"
    )
    parser.add_argument("--write", action="store_true", help="update README.md")
    args = parser.parse_args()
    load = os.getloadavg()[0]
    threads = worker_threads(None)
    rows = reproduce_rows(full=not args.no_full) + (test_rows() if args.tests else [])
    machine = cpu_model()
    text = "\n".join(
        [
            BEGIN,
            "",
            "| run | sizes | wall time | CPU time |",
            "|---|---|---|---|",
            *rows,
            "",
            f"Measured by `python docs/timings.py` on {datetime.date.today():%Y-%m-%d}: "
            f"{machine}, {threads} threads, release build, load average {load:.1f} at the "
            "start"
            + (
                " (other jobs shared the machine: the wall times are longer than on a quiet "
                "one, and the CPU times too when the worker threads wait for a core)."
                if load > threads
                else "."
            ),
            "",
            END,
        ]
    )
    print(text)
    if args.write:
        page = ROOT / "README.md"
        replace_block(page, BEGIN, END, text)


if __name__ == "__main__":
    main()
