"""The scaling measurement of docs/how-to/run-on-dask.md: one navigation Monte Carlo
set run on local rayon threads and on process LocalClusters of 1 and 2
workers (1 thread each), with wall time and the runs per second, and the
check that every way gives the same numbers bit for bit.

    python docs/distributed_scaling.py [--runs 24] [--duration 300] [--write]

``--write`` keeps the measurements in ``docs/distributed_scaling.json`` and
puts the table between docs/how-to/run-on-dask.md's ``scaling`` markers; the table
is ``render`` of that record (tests/test_docs.py checks it).
"""

from __future__ import annotations

import argparse
import datetime
import json
import os
import sys
import time
from pathlib import Path
from typing import Any

import numpy as np
from marked_block import replace_block

import memsnav as mn

ROOT = Path(__file__).resolve().parents[1]
PAGE = ROOT / "docs" / "how-to" / "run-on-dask.md"
RECORD = ROOT / "docs" / "distributed_scaling.json"
BEGIN, END = "<!-- scaling:begin -->", "<!-- scaling:end -->"


def measure(runs: int, duration: float) -> list[dict[str, Any]]:
    from distributed import Client, LocalCluster

    config = {
        "runs": runs,
        "duration": duration,
        "outage": (150.0, 30.0),
        "seed": 7,
        "keep_runs": True,
    }
    rows: list[dict[str, Any]] = []
    reference = None

    def record(how: str, run: Any) -> None:
        nonlocal reference
        start = time.perf_counter()
        result = run()
        wall = time.perf_counter() - start
        curves = result.position_error["mems"]
        if reference is None:
            reference = curves
        same = bool(np.array_equal(reference.view(np.uint64), curves.view(np.uint64)))
        rows.append({"how": how, "wall_s": wall, "identical": same})
        print(f"{how:<42} {wall:7.1f} s  {runs / wall:5.2f} runs/s  identical: {same}")

    for threads in (1, 2):
        record(
            f"local, {threads} rayon thread{'s' if threads > 1 else ''}",
            lambda t=threads: mn.experiments.navigation(**config, threads=t),
        )
    for workers in (1, 2):
        with (
            LocalCluster(
                n_workers=workers, threads_per_worker=1, processes=True, dashboard_address=None
            ) as cluster,
            Client(cluster) as client,
        ):
            record(
                f"Dask, {workers} worker process{'es' if workers > 1 else ''} (1 thread each)",
                lambda c=client: mn.experiments.navigation(**config, client=c),
            )
    return rows


def render(record: dict[str, Any]) -> str:
    m, rows, runs = record["machine"], record["rows"], record["runs"]
    wall = {row["how"]: row["wall_s"] for row in rows}
    load = f"load average {m['load_start']:.1f} at the start, {m['load_end']:.1f} at the end"
    if max(m["load_start"], m["load_end"]) > m["cpus"]:
        load += " (other jobs held the cores: a saturated machine does not scale)"
    two_workers = (
        wall["Dask, 1 worker process (1 thread each)"]
        / wall["Dask, 2 worker processes (1 thread each)"]
    )
    dask_cost = wall["Dask, 2 worker processes (1 thread each)"] / wall["local, 2 rayon threads"]
    return "\n".join(
        [
            BEGIN,
            "",
            f"Measured by `python docs/distributed_scaling.py --runs {runs} --duration "
            f"{record['duration']:g}` on {m['date']}: {m['cpu']}, {m['cpus']} CPUs, {load}. "
            f"One navigation set: {runs} runs of {record['duration']:g} s, the paper's three "
            "IMUs, a 30 s outage.",
            "",
            "| how | wall time | runs/s | the same numbers bit for bit |",
            "|---|---|---|---|",
            *(
                f"| {row['how']} | {row['wall_s']:.1f} s | {runs / row['wall_s']:.1f} | "
                f"{'yes' if row['identical'] else '**no**'} |"
                for row in rows
            ),
            "",
            f"Two worker processes ran {two_workers:.2f}× as fast as one; Dask with 2 worker "
            f"processes took {abs(100 * (dask_cost - 1)):.0f} % "
            f"{'more' if dask_cost >= 1 else 'less'} time than 2 local threads "
            "(worker start excluded).",
            "",
            END,
        ]
    )


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--runs", type=int, default=24)
    parser.add_argument("--duration", type=float, default=300.0)
    parser.add_argument("--write", action="store_true", help="update docs/how-to/run-on-dask.md")
    args = parser.parse_args()
    sys.path.insert(0, str(ROOT / "docs"))
    from performance_tables import cpu_model

    machine = {
        "date": datetime.datetime.now(datetime.UTC).strftime("%Y-%m-%d %H:%M UTC"),
        "cpu": cpu_model(),
        "cpus": os.cpu_count(),
        "load_start": os.getloadavg()[0],
    }
    rows = measure(args.runs, args.duration)
    machine["load_end"] = os.getloadavg()[0]
    record = {"runs": args.runs, "duration": args.duration, "machine": machine, "rows": rows}
    text = render(record)
    print(text)
    if args.write:
        RECORD.write_text(json.dumps(record, indent=1, ensure_ascii=False) + "\n")
        replace_block(PAGE, BEGIN, END, text)


if __name__ == "__main__":
    main()
