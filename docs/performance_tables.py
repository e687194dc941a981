"""The current figures of docs/results/performance.md, measured anew:
``python docs/performance_tables.py [--from-existing] [--write]``.

Runs the criterion suites (``cargo bench -p memsnav-benches --bench
filter``, ``experiments``, ``readers``) and the Python benchmark
(``benches/python/bench_tight.py``, its JSON into
``target/bench_tight.json``), then prints the page's block: the machine
(processor, CPUs, date, load average before and after), criterion's mean of
every benchmark with its 95 % interval and throughput, the Python
benchmark's figures, and each target beside the figure it is about.
``--from-existing`` runs nothing: it reads criterion's last results
(``target/criterion/**/new/``) and the last ``target/bench_tight.json``.
``--write`` keeps the measurements in ``docs/performance.json`` and puts
the block between docs/results/performance.md's ``performance`` markers; the block
is ``render`` of that record (tests/test_performance_doc.py checks it). The
step API's rate the README quotes is a figure of ``docs/data/step_api_rate.json``
(``step_api_rate`` of the same measurements), written with it.
"""

from __future__ import annotations

import argparse
import datetime
import json
import os
import platform
import subprocess
import sys
from importlib import metadata
from pathlib import Path
from typing import Any

from figures import write_record
from marked_block import replace_block

ROOT = Path(__file__).resolve().parents[1]
PAGE = ROOT / "docs" / "results" / "performance.md"
RECORD = ROOT / "docs" / "performance.json"
CRITERION = ROOT / "target" / "criterion"
PYTHON_RESULTS = ROOT / "target" / "bench_tight.json"
#: The machine and load of the last run of this script (for --from-existing).
RUN = ROOT / "target" / "performance_run.json"
BEGIN, END = "<!-- performance:begin -->", "<!-- performance:end -->"
SUITES = ("filter", "experiments", "readers")
#: What criterion's element throughput counts, by benchmark group.
ELEMENTS = {
    "epoch": "steps",
    "gnss_update": "updates",
    "tight_600s_6sat": "IMU epochs",
    "calibration_60000_samples": "samples",
    "inversion": "samples",
    "calibration_experiment_300s": "runs",
    "navigation_experiment_600s_3imus": "runs",
    "navigation_experiment_600s_mems": "runs",
    "simulator_600s": "samples",
}


def suite_of(group: str) -> str | None:
    """The criterion suite whose source names benchmark group ``group``
    (None: a result left by a benchmark that no longer exists)."""
    for suite in SUITES:
        if f'"{group}"' in (ROOT / "benches" / f"{suite}.rs").read_text():
            return suite
    return None


def criterion_results(directory: Path = CRITERION) -> list[dict[str, Any]]:
    """criterion's last estimate of every benchmark of the suites: id,
    mean and its 95 % interval (s), throughput per iteration."""
    found = []
    for described in directory.glob("**/new/benchmark.json"):
        bench = json.loads(described.read_text())
        suite = suite_of(bench["group_id"])
        if suite is None:
            continue
        mean = json.loads((described.parent / "estimates.json").read_text())["mean"]
        interval = mean["confidence_interval"]
        found.append(
            {
                "suite": suite,
                "id": bench["full_id"],
                "group": bench["group_id"],
                "mean_s": mean["point_estimate"] * 1e-9,
                "low_s": interval["lower_bound"] * 1e-9,
                "high_s": interval["upper_bound"] * 1e-9,
                "throughput": bench["throughput"],
            }
        )
    return sorted(found, key=lambda b: (SUITES.index(b["suite"]), b["id"]))


def cpu_model() -> str:
    """``lscpu``'s model name, family, model and BogoMIPS (the name alone
    does not tell two hosts of a cloud apart); else the platform's name."""
    try:
        out = subprocess.run(["lscpu"], capture_output=True, text=True, check=True).stdout
    except (OSError, subprocess.CalledProcessError):
        return platform.processor() or platform.machine()
    fields = dict(line.split(":", 1) for line in out.splitlines() if ":" in line)
    field = {k.strip(): v.strip() for k, v in fields.items()}.get
    return (
        f"{field('Model name', platform.machine())} (family {field('CPU family', '?')}, "
        f"model {field('Model', '?')}, BogoMIPS {field('BogoMIPS', '?')})"
    )


def version(package: str) -> str:
    try:
        return metadata.version(package)
    except metadata.PackageNotFoundError:
        return "not installed"


def machine_now() -> dict[str, Any]:
    """The machine, the software and the load average as the run starts."""
    rustc = subprocess.run(["rustc", "--version"], capture_output=True, text=True, check=False)
    return {
        "date": datetime.datetime.now(datetime.UTC).strftime("%Y-%m-%d %H:%M UTC"),
        "cpu": cpu_model(),
        "cpus": os.cpu_count(),
        "load_start": os.getloadavg()[0],
        "python": platform.python_version(),
        "numpy": version("numpy"),
        "filterpy": version("filterpy"),
        "sidereon": version("sidereon"),
        "rustc": rustc.stdout.split(" (")[0] or "unknown",
    }


def run_benchmarks() -> None:
    """The suites and the Python benchmark, one after the other; the machine
    and the load before and after go into ``RUN``."""
    machine = machine_now()
    for suite in SUITES:
        command = ["cargo", "bench", "-p", "memsnav-benches", "--bench", suite]
        subprocess.run(command, cwd=ROOT, check=True)
    bench = ROOT / "benches" / "python" / "bench_tight.py"
    subprocess.run([sys.executable, str(bench), str(PYTHON_RESULTS)], cwd=ROOT, check=True)
    machine["load_end"] = os.getloadavg()[0]
    RUN.write_text(json.dumps(machine, indent=2) + "\n")


def measurements() -> dict[str, Any]:
    """The record the block is made from: the last run's machine, criterion's
    estimates and the Python benchmark's JSON."""
    if RUN.exists():
        machine = json.loads(RUN.read_text())
    else:  # results from cargo bench run by hand: dated by their files, load not recorded
        newest = max(f.stat().st_mtime for f in [PYTHON_RESULTS, *CRITERION.glob("**/new/*")])
        when = datetime.datetime.fromtimestamp(newest, datetime.UTC)
        machine = machine_now() | {
            "date": when.strftime("%Y-%m-%d %H:%M UTC"),
            "load_start": None,
            "load_end": None,
        }
    return {
        "machine": machine,
        "criterion": criterion_results(),
        "python": json.loads(PYTHON_RESULTS.read_text()),
    }


def duration(seconds: float) -> str:
    """``seconds`` in the unit that puts it in [1, 1000), three figures."""
    unit, scale = next(
        (u, s) for u, s in (("s", 1.0), ("ms", 1e-3), ("µs", 1e-6), ("ns", 0.0)) if seconds >= s
    )
    return f"{figures(seconds / (scale or 1e-9))} {unit}"


def figures(value: float) -> str:
    """Three significant figures, as a plain number (1.50, 10.0, 143, 1234)."""
    shown = f"{value:#.3g}"
    return f"{value:.0f}" if "e" in shown else shown.rstrip(".")


def times(ratio: float) -> str:
    return f"{figures(ratio)}×"


def extrapolated(flag: bool) -> str:
    return " (extrapolated)" if flag else ""


def rate(per_second: float) -> str:
    for unit, scale in ((" G", 1e9), (" M", 1e6), (" k", 1e3)):
        if per_second >= scale:
            return f"{figures(per_second / scale)}{unit}"
    return figures(per_second)


def throughput(bench: dict[str, Any]) -> str:
    kind, count = next(iter((bench["throughput"] or {"": 0}).items()))
    if kind == "Bytes":
        return f"{figures(count / bench['mean_s'] / 2**20)} MiB/s"
    if kind == "Elements":
        return f"{rate(count / bench['mean_s'])} {ELEMENTS.get(bench['group'], 'elements')}/s"
    return ""


def machine_line(m: dict[str, Any]) -> str:
    if m["load_start"] is None:
        load = "load average not recorded"
    else:
        load = f"load average {m['load_start']:.1f} at the start, {m['load_end']:.1f} at the end"
        if max(m["load_start"], m["load_end"]) > m["cpus"]:
            load += " (other jobs shared the machine: the times are longer than on a quiet one)"
    return (
        f"Measured by `python docs/performance_tables.py` on {m['date']}: {m['cpu']}, "
        f"{m['cpus']} CPUs, {load}. Release build for the portable x86-64 target; "
        f"{m['rustc']}, Python {m['python']}, NumPy {m['numpy']}, FilterPy {m['filterpy']}, "
        f"sidereon {m['sidereon']}."
    )


def verdict(value: float, target: float, at_least: bool, unit: str) -> str:
    """``value`` against ``target`` (at least or at most), e.g. "≥ 100×: met"."""
    met = value >= target if at_least else value <= target
    shown = rate(target) if target >= 1e3 else f"{target:g}"
    return f"{'≥' if at_least else '≤'} {shown}{unit}: {'met' if met else '**not met**'}"


def python_rows(p: dict[str, Any]) -> list[tuple[str, ...]]:
    """(what, figure, target) of the Python benchmark."""
    rows = [
        ("simulator (trajectory, IMU, GNSS) through Python", duration(p["simulator_seconds"]), ""),
        (
            "`TightlyCoupledFilter.run`",
            f"{duration(p['memsnav_seconds'])} ({rate(p['memsnav_epochs_per_second'])} "
            "IMU epochs/s)",
            "",
        ),
    ]
    rows += [
        (
            "FilterPy `ExtendedKalmanFilter` + NumPy loop",
            f"{duration(p['filterpy_seconds_full_run'])}{extrapolated(p['filterpy_extrapolated'])} "
            f"({duration(p['filterpy_seconds_per_epoch'])} per IMU epoch)",
            "",
        ),
        (
            "memsnav's call faster than that loop",
            times(p["speedup"]),
            verdict(p["speedup"], 100.0, True, "×"),
        ),
    ]
    sd = p["sidereon"]
    if "skipped" not in sd:
        rows += [
            (
                f"sidereon {sd['version']} `InertialFilter` loop",
                f"{duration(sd['seconds_full_run'])}{extrapolated(sd['extrapolated'])}"
                f" ({duration(sd['seconds_per_epoch'])} per IMU epoch)",
                "",
            ),
            ("memsnav's call faster than sidereon's loop", times(sd["speedup"]), ""),
        ]
    mc = p["monte_carlo_run_seconds_1_thread"]
    rf = p["running_filter"]
    rows += [
        (
            "one whole navigation Monte Carlo run (trajectory, IMU, GNSS, filter), 1 thread",
            f"{duration(mc)} ({figures(p['monte_carlo_runs_per_second_1_thread'])} runs/s)",
            "",
        ),
        (
            "that run faster than the FilterPy loop alone",
            times(p["whole_run_speedup"]),
            verdict(p["whole_run_speedup"], 50.0, True, "×"),
        ),
        (
            "2 threads ÷ 1",
            times(p["monte_carlo_2_thread_scaling"]),
            verdict(p["monte_carlo_2_thread_scaling"], 1.8, True, "×"),
        ),
        *(
            (
                f"`smooth=True` adds, {states.replace('_', ' ')}",
                f"{times(s['smoother_adds_times_forward'])} the forward run",
                verdict(s["smoother_adds_times_forward"], 2.0, False, "×"),
            )
            for states, s in p["smoother"].items()
        ),
        (
            "`RunningFilter` loop from Python, per IMU sample",
            f"{duration(rf['seconds_per_epoch'])} ({rate(rf['epochs_per_second'])} samples/s)",
            verdict(rf["epochs_per_second"], 2e5, True, " samples/s"),
        ),
        (
            "its calls: `predict` / `update_gnss` / `position_ecef` read",
            f"{duration(rf['predict_seconds_per_call'])} / "
            f"{duration(rf['update_gnss_seconds_per_call'])} / "
            f"{duration(rf['position_read_seconds_per_call'])}",
            "",
        ),
        (
            "the loop's positions identical to `run`'s",
            "yes" if rf["identical_to_run"] else "**no**",
            "",
        ),
        (
            "position RMS against the truth, memsnav / FilterPy",
            f"{p['memsnav_position_rms_m_first_span']:.2f} / "
            f"{p['filterpy_position_rms_m_first_span']:.2f} m",
            "within 1.5× of each other (the same job done): "
            + ("met" if p["same_accuracy"] else "**not met**"),
        ),
    ]
    if "skipped" not in sd:
        # sidereon's ImuSpec takes no noise that follows the inputs, so it
        # lacks memsnav's noise for the unmodelled sensor errors
        # (bench_tight.py): a different filter, shown without a target.
        rows.append(
            (
                "sidereon's position RMS (no noise for the unmodelled sensor errors)",
                f"{sd['position_rms_m']:.2f} m",
                "",
            )
        )
    return rows


def rust_rows(rust: dict[str, dict[str, Any]]) -> list[tuple[str, ...]]:
    """(what, figure, target) of the Rust targets criterion measured."""
    rows = []
    if "tight_600s_6sat/records_only" in rust:
        b = rust["tight_600s_6sat/records_only"]
        per_second = b["throughput"]["Elements"] / b["mean_s"]
        rows.append(
            (
                "the 600 s tight run in Rust, records only",
                f"{rate(per_second)} IMU epochs/s",
                verdict(per_second, 1e6, True, " IMU epochs/s"),
            )
        )
    if {"tight_600s_6sat/solution", "tight_600s_6sat/solution_and_smoothed"} <= rust.keys():
        forward = rust["tight_600s_6sat/solution"]["mean_s"]
        adds = (rust["tight_600s_6sat/solution_and_smoothed"]["mean_s"] - forward) / forward
        rows.append(
            (
                "the smoother adds, Rust",
                f"{times(adds)} the forward run",
                verdict(adds, 2.0, False, "×"),
            )
        )
    return rows


def render(record: dict[str, Any]) -> str:
    """The page's block, from a record of ``measurements()``."""
    rust = {b["id"]: b for b in record["criterion"]}
    p = record["python"]
    lines = [
        BEGIN,
        "",
        machine_line(record["machine"]),
        "",
        f"Python benchmark: {p['workload']}; the filter call is the best of "
        f"{p['memsnav_best_of']}, "
        f"the Monte Carlo run the best of {p['monte_carlo_sets_best_of']} sets of "
        f"{p['monte_carlo_runs_per_set']['1']} runs (1 thread) and "
        f"{p['monte_carlo_runs_per_set']['2']} (2 threads).",
        "",
        "| what | figure | target |",
        "|---|---|---|",
        *(f"| {' | '.join(row)} |" for row in rust_rows(rust) + python_rows(p)),
        "",
        "criterion (`cargo bench -p memsnav-benches --bench filter`, `experiments`, `readers`): "
        "the mean per iteration and its 95 % confidence interval.",
        "",
        "| benchmark | mean | 95 % interval | throughput |",
        "|---|---|---|---|",
        *(
            f"| `{b['id']}` | {duration(b['mean_s'])} | {duration(b['low_s'])} - "
            f"{duration(b['high_s'])} | {throughput(b)} |"
            for b in record["criterion"]
        ),
        "",
        END,
    ]
    return "\n".join(lines)


def step_api_rate(record: dict[str, Any]) -> dict[str, float]:
    """The figures of docs/data/step_api_rate.json: the `RunningFilter`
    loop's rate from Python, thousands of IMU samples per second."""
    return {
        "running_filter_k_samples_per_s": record["python"]["running_filter"]["epochs_per_second"]
        / 1e3
    }


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument(
        "--from-existing",
        action="store_true",
        help="run no benchmark: read the last criterion and bench_tight.py results",
    )
    parser.add_argument(
        "--write", action="store_true", help="update docs/results/performance.md and its record"
    )
    args = parser.parse_args()
    if not args.from_existing:
        run_benchmarks()
    record = measurements()
    text = render(record)
    print(text)
    if args.write:
        RECORD.write_text(json.dumps(record, indent=1, ensure_ascii=False) + "\n")
        replace_block(PAGE, BEGIN, END, text)
        write_record("step_api_rate", step_api_rate(record))


if __name__ == "__main__":
    main()
