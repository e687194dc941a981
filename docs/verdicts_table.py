"""The verdicts table of docs/results/paper-comparison.md, rerunnable by anyone:
``python docs/verdicts_table.py [--summary results/summary.json] [--write]``.

Judges the paper's claims (``memsnav.report.claims``) on the
``summary.json`` of a ``memsnav reproduce`` run: the one given, else a
quick run with seed 0 made here (a few minutes). Prints each claim's
title, the paper's statement, memsnav's figure and the verdict, then each
criterion as the report prints it and the errors-in-variables
calibration's efficiency range; ``--write`` keeps them in the record
docs/data/verdicts.json and puts them into
docs/results/paper-comparison.md between its ``verdicts`` markers
(``--from-record`` re-renders the page from the record without a run).
"""

from __future__ import annotations

import argparse
import json
import math
import tempfile
from pathlib import Path
from typing import Any

from marked_block import record_block_script

from memsnav.report.claims import CLAIMS, evaluate_claims
from memsnav.reproduce import reproduce

ROOT = Path(__file__).resolve().parents[1]
BEGIN, END = "<!-- verdicts:begin -->", "<!-- verdicts:end -->"


def _summary(path: Path | None) -> dict[str, Any]:
    if path is not None:
        return json.loads(path.read_text())
    with tempfile.TemporaryDirectory() as out:
        return reproduce(out, seed=0, progress=False).summary


def _efficiency(summary: dict[str, Any]) -> dict[str, float]:
    """The errors-in-variables calibration's MSE over the Cramér-Rao bound,
    least and most over every parameter group and axis."""
    values = [
        axis["efficiency_eiv"]
        for sensor in ("accelerometer", "gyroscope")
        for group in summary["calibration"][sensor].values()
        for axis in group["per_axis"].values()
        if axis["efficiency_eiv"] is not None and math.isfinite(axis["efficiency_eiv"])
    ]
    return {"least": min(values), "most": max(values)}


def record_figures(summary: dict[str, Any]) -> dict[str, Any]:
    """What the block shows, from a reproduce run's summary: the run's
    sizes and seed, each claim as judged, the calibration's efficiency."""
    return {
        "sizes": summary.get("sizes", "the paper's" if summary["full"] else "quick"),
        "seed": summary["seed"],
        "claims": [
            {k: c[k] for k in ("title", "paper", "figures", "memsnav", "verdict")}
            for c in evaluate_claims(summary)
        ],
        "efficiency_eiv": _efficiency(summary),
    }


def render(record: dict[str, Any]) -> str:
    """The block the page shows, from the record."""
    f = record["figures"]
    efficiency = f["efficiency_eiv"]
    lines = [
        BEGIN,
        "",
        f"`memsnav reproduce` with {f['sizes']} Monte Carlo sizes, seed {f['seed']}:",
        "",
        "| claim | the paper | memsnav (± one standard error) | verdict |",
        "|---|---|---|---|",
        *(
            f"| {c['title']} | {c['paper']} ({c['figures']}) | {c['memsnav']} | {c['verdict']} |"
            for c in f["claims"]
        ),
        "",
        "The criteria, as the report prints them (thresholds are named constants in "
        "`memsnav/report/claims.py`):",
        "",
        *(f"- {claim.title}: {claim.criterion}." for claim in CLAIMS),
        "",
        "The errors-in-variables calibration's MSE is "
        f"{efficiency['least']:.2f} to {efficiency['most']:.2f} times the Cramér-Rao bound "
        "over every parameter group and axis.",
        "",
        END,
    ]
    return "\n".join(lines)


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--summary", type=Path, help="summary.json of a reproduce run")
    page = ROOT / "docs" / "results" / "paper-comparison.md"
    record_block_script(
        parser,
        "verdicts",
        page,
        (BEGIN, END),
        lambda args: record_figures(_summary(args.summary)),
        render,
    )


if __name__ == "__main__":
    main()
