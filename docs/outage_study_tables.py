"""The land-vehicle study of docs/results/outage-study.md, rerunnable by anyone:
``python docs/outage_study_tables.py [--write]``.

Runs ``examples/study_land_vehicle.toml`` as ``memsnav study`` does (into a
temporary folder) and prints, in Markdown: its size and run time, the
answer (the terminal's lines: per grade the longest outage within the
requirement, decided at 95 % confidence, with the 95th percentile there,
the bounds its decision rests on and the cell's runs) and the tables of
the report (median / p95 of the horizontal error at the outage end, the
smoothed solution's p95 of its largest error in brackets, the cell's runs
and decision), built by the same functions as the report.
``--write`` puts them into docs/results/outage-study.md between its ``study``
markers and writes, from the same run, the record its sentences show
(``docs/data/outage_study.json``: :func:`cell_figures`).
"""

from __future__ import annotations

import argparse
import os
import tempfile
import time
from pathlib import Path
from typing import Any

import numpy as np
from figures import write_record
from marked_block import replace_block

import memsnav as mn
from memsnav.report.numbers import number
from memsnav.reproduce import worker_threads
from memsnav.study import Requirement, answer_lines, run_study, table_cells

ROOT = Path(__file__).resolve().parents[1]
CONFIG = ROOT / "examples" / "study_land_vehicle.toml"
BEGIN, END = "<!-- study:begin -->", "<!-- study:end -->"


def _look_error_sentence(looks: list[int], requirement: Requirement) -> str:
    """Each look's error, exact, against Bonferroni's and what Bonferroni's
    would err overall, in words."""
    p, allowed = requirement.percentile / 100.0, 1.0 - requirement.confidence
    exact = mn.sequential_look_error(looks, p, requirement.confidence)
    union = allowed / len(looks)
    worst = max(mn.sequential_error(looks, p, union))
    return (
        f"Each look's bounds err with probability {exact * 100:.2f} % (exact over the "
        f"{len(looks)} looks); Bonferroni's {union * 100:.2f} % would keep a decision wrong "
        f"at most {worst * 100:.1f} % of the time where {allowed * 100:g} % is allowed."
    )


def cell_figures(result: Any, requirement: Requirement) -> dict[str, Any]:
    """Per grade, satellites kept and outage length (``grade.n.length``):
    the cell's runs, decision and interval (m), the percentile of the
    requirement's metric over all its runs and over its first look's runs
    (what a fixed study of that size would have said), m."""
    first_look = result.config["looks"][0]
    out: dict[str, Any] = {}
    for (grade, length, n), cell in result.cells.items():
        values = result.per_run(grade, length, n, requirement.metric)
        out.setdefault(grade, {}).setdefault(str(n), {})[f"{length:g}"] = {
            "runs": cell.runs,
            "decision": cell.decision,
            "interval_m": list(cell.interval_m) if cell.interval_m else None,
            "percentile_m": float(np.percentile(values, requirement.percentile)),
            "first_look_percentile_m": float(
                np.percentile(values[:first_look], requirement.percentile)
            ),
        }
    return out


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--write", action="store_true", help="update docs/results/outage-study.md")
    args = parser.parse_args()
    load, threads = os.getloadavg()[0], worker_threads(None)
    with tempfile.TemporaryDirectory() as out:
        cpu = time.process_time()
        study = run_study(CONFIG, output=out, progress=False)
        cpu = time.process_time() - cpu
    result, summary = study.result, study.summary
    c = result.config
    runs = [cell.runs for cell in result.cells.values()]
    requirement = Requirement.of(summary["requirement"])
    parts = [
        BEGIN,
        "",
        f"{len(result.grades)} presets × ({', '.join(number(v) for v in result.outage_lengths)} "
        f"s) × ({', '.join(str(n) for n in result.visible_satellites)} satellites kept), "
        f"{min(runs)}-{max(runs)} runs per cell ({sum(runs)} cell runs, looks "
        f"{', '.join(str(n) for n in c['looks'])}; runs drawn for {c['duration']:.0f} s), "
        f"forward {'and smoothed (first look)' if c['smooth'] else 'only'}: "
        f"{summary['elapsed_s']:.0f} s of wall "
        f"time ({cpu:.0f} s of CPU) on {threads} threads, load average {load:.1f} at the "
        "start" + (" (other jobs shared the machine)." if load > threads else "."),
        "",
        _look_error_sentence(c["looks"], requirement),
        "",
        "What `memsnav study` prints (the answer, for the forward filter):",
        "",
        "```text",
        *answer_lines(summary),
        "```",
    ]
    for n in result.visible_satellites:
        cells = table_cells(result, n, requirement)
        parts += [
            "",
            f"**{n} satellite{'' if n == 1 else 's'} kept**: median / p{requirement.percentile:g} "
            "of the horizontal error at the outage end, m (smoothed: p"
            f"{requirement.percentile:g} of its largest error in the outage); the cell's runs "
            "and decision",
            "",
            "| grade | " + " | ".join(f"{number(v)} s" for v in result.outage_lengths) + " |",
            "|---|" + "---|" * len(result.outage_lengths),
            *(f"| {grade} | " + " | ".join(row) + " |" for grade, row in cells.items()),
        ]
    text = "\n".join([*parts, "", END])
    print(text)
    if args.write:
        page = ROOT / "docs" / "results" / "outage-study.md"
        # The record first: it names the commit, which the page's new block
        # would mark as changed.
        write_record("outage_study", {"cells": cell_figures(result, requirement)})
        replace_block(page, BEGIN, END, text)


if __name__ == "__main__":
    main()
