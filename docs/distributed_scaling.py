"""The scaling measurement of docs/distributed.md: one navigation Monte Carlo
set run on local rayon threads and on process LocalClusters of 1 and 2
workers (1 thread each), with wall time and the runs per second, and the
check that every way gives the same numbers bit for bit.

    python docs/distributed_scaling.py [--runs 24] [--duration 300]
"""

from __future__ import annotations

import argparse
import time

import numpy as np

import memsnav as mn


def main() -> None:
    parser = argparse.ArgumentParser()
    parser.add_argument("--runs", type=int, default=24)
    parser.add_argument("--duration", type=float, default=300.0)
    args = parser.parse_args()
    from distributed import Client, LocalCluster

    config = {
        "runs": args.runs,
        "duration": args.duration,
        "outage": (150.0, 30.0),
        "seed": 7,
        "keep_runs": True,
    }
    rows = []
    reference = None

    def record(label: str, run: object) -> None:
        nonlocal reference
        start = time.perf_counter()
        result = run()  # type: ignore[operator]
        wall = time.perf_counter() - start
        curves = result.position_error["mems"]
        if reference is None:
            reference = curves
        same = np.array_equal(reference.view(np.uint64), curves.view(np.uint64))
        rows.append((label, wall, args.runs / wall, same))
        print(f"{label:<34} {wall:7.1f} s  {args.runs / wall:5.2f} runs/s  identical: {same}")

    for threads in (1, 2):
        record(
            f"local, {threads} rayon thread(s)",
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
                f"Dask, {workers} worker process(es)",
                lambda c=client: mn.experiments.navigation(**config, client=c),
            )


if __name__ == "__main__":
    main()
