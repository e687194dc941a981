"""The outage study's wall time as a ratio to the FilterPy loop timed in
the same run, so that two studies measured at different times, or on
differently loaded machines, compare: ``memsnav study`` on a configuration
(the shipped example by default), then the careful FilterPy + NumPy filter
of ``bench_tight.py`` over part of its 600 s run, extrapolated per IMU
epoch to the whole run.

    python benches/python/bench_study.py results.json [--config FILE]
        [--filterpy-seconds 120] [--record]

``--record`` also writes the figures as the record
``docs/data/study_cost.json`` the outage-study page quotes (the shipped
example only).

The ratio is the study's wall time divided by the time FilterPy takes for
one 600 s run. It reads the study in "FilterPy runs' worth" of work; a
faster or slower machine, or one shared with other jobs, moves both
numbers alike as long as the study and the loop see the same conditions.
FilterPy is a benchmark-only dependency (``pip install memsnav[bench]``).
"""

from __future__ import annotations

import argparse
import json
import os
import platform
import resource
import sys
import tempfile
import time
from pathlib import Path

from memsnav.study import run_study

sys.path.insert(0, str(Path(__file__).resolve().parent))
import bench_tight

import memsnav as mn

ROOT = Path(__file__).resolve().parents[2]


def cpu_s() -> float:
    """CPU time of this process and its threads, s."""
    usage = resource.getrusage(resource.RUSAGE_SELF)
    return usage.ru_utime + usage.ru_stime


def filterpy_seconds_per_run(seconds: float) -> float:
    """FilterPy's time for one whole run, s, from `seconds` of it."""
    imu, sc = bench_tight.scenario()
    traj, acc, gyr, gnss = sc
    filt = mn.TightlyCoupledFilter(imu)
    sol = filt.run(traj.time, acc, gyr, gnss, initial_attitude=traj.attitude[0])
    start = bench_tight.start_of(sol)
    m = min(len(traj.time), round(seconds * bench_tight.RATE_HZ) + 1)
    t0 = time.perf_counter()
    bench_tight.filterpy_run(sc, start, filt.tuning, m)
    return (time.perf_counter() - t0) / m * len(traj.time)


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("output", type=Path, help="where to write the JSON results")
    parser.add_argument(
        "--config",
        type=Path,
        default=ROOT / "examples" / "study_land_vehicle.toml",
        help="the study configuration (default: the shipped example)",
    )
    parser.add_argument(
        "--record",
        action="store_true",
        help="also write docs/data/study_cost.json (the shipped example only)",
    )
    parser.add_argument(
        "--filterpy-seconds",
        type=float,
        default=120.0,
        help="seconds of the 600 s run FilterPy processes (extrapolated per epoch)",
    )
    args = parser.parse_args()
    load = os.getloadavg()[0]
    with tempfile.TemporaryDirectory() as out:
        t0, c0 = time.perf_counter(), cpu_s()
        study = run_study(args.config, output=out, progress=False)
        wall, cpu = time.perf_counter() - t0, cpu_s() - c0
    filterpy_s = filterpy_seconds_per_run(args.filterpy_seconds)
    cells = getattr(study.result, "cells", None)  # None: a memsnav without per-cell runs
    cell_runs = None if cells is None else sum(cell.runs for cell in cells.values())
    results = {
        "date": time.strftime("%Y-%m-%d"),
        "machine": platform.processor() or platform.machine(),
        "cores": os.cpu_count(),
        "load_average_at_start": load,
        "memsnav": mn.__version__,
        "config": str(args.config),
        "cell_runs": cell_runs,
        "study_wall_s": wall,
        "study_cpu_s": cpu,
        "filterpy_600s_run_s": filterpy_s,
        "study_in_filterpy_runs": wall / filterpy_s,
    }
    args.output.write_text(json.dumps(results, indent=2) + "\n")
    if args.record:
        if args.config.resolve() != (ROOT / "examples" / "study_land_vehicle.toml").resolve():
            raise SystemExit("--record: the page quotes the shipped example only")
        sys.path.insert(0, str(ROOT / "docs"))
        from figures import write_record

        write_record("study_cost", {k: v for k, v in results.items() if k != "config"})
    print(
        f"study: {cell_runs} cell runs, {wall:.1f} s wall, {cpu:.1f} s CPU; "
        f"FilterPy: {filterpy_s:.2f} s per 600 s run; "
        f"the study takes {wall / filterpy_s:.2f} FilterPy runs (load {load:.1f} at the start)"
    )


if __name__ == "__main__":
    main()
