"""The verdicts table of docs/results/paper-comparison.md, rerunnable by anyone:
``python docs/verdicts_table.py [--summary results/summary.json] [--write]``.

Judges the paper's claims (``memsnav.report.claims``) on the
``summary.json`` of a ``memsnav reproduce`` run: the one given, else a
quick run with seed 0 made here (a few minutes). Prints each claim's
title, the paper's statement, memsnav's figure and the verdict, then each
criterion as the report prints it and the errors-in-variables
calibration's efficiency range; ``--write`` puts them into
docs/results/paper-comparison.md between its ``verdicts`` markers.
"""

from __future__ import annotations

import argparse
import json
import math
import tempfile
from pathlib import Path
from typing import Any

from marked_block import replace_block

from memsnav.report.claims import CLAIMS, evaluate_claims
from memsnav.reproduce import reproduce

ROOT = Path(__file__).resolve().parents[1]
BEGIN, END = "<!-- verdicts:begin -->", "<!-- verdicts:end -->"


def _summary(path: Path | None) -> dict[str, Any]:
    if path is not None:
        return json.loads(path.read_text())
    with tempfile.TemporaryDirectory() as out:
        return reproduce(out, seed=0, progress=False).summary


def _efficiency(summary: dict[str, Any]) -> str:
    values = [
        axis["efficiency_eiv"]
        for sensor in ("accelerometer", "gyroscope")
        for group in summary["calibration"][sensor].values()
        for axis in group["per_axis"].values()
        if axis["efficiency_eiv"] is not None and math.isfinite(axis["efficiency_eiv"])
    ]
    return f"{min(values):.2f} to {max(values):.2f}"


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--summary", type=Path, help="summary.json of a reproduce run")
    parser.add_argument(
        "--write", action="store_true", help="update docs/results/paper-comparison.md"
    )
    args = parser.parse_args()
    summary = _summary(args.summary)
    claims = evaluate_claims(summary)
    sizes = summary.get("sizes", "the paper's" if summary["full"] else "quick")
    lines = [
        BEGIN,
        "",
        f"`memsnav reproduce` with {sizes} Monte Carlo sizes, seed {summary['seed']}:",
        "",
        "| claim | the paper | memsnav (± one standard error) | verdict |",
        "|---|---|---|---|",
        *(
            f"| {c['title']} | {c['paper']} ({c['figures']}) | {c['memsnav']} | {c['verdict']} |"
            for c in claims
        ),
        "",
        "The criteria, as the report prints them (thresholds are named constants in "
        "`memsnav/report/claims.py`):",
        "",
        *(f"- {claim.title}: {claim.criterion}." for claim in CLAIMS),
        "",
        "The errors-in-variables calibration's MSE is "
        f"{_efficiency(summary)} times the Cramér-Rao bound over every parameter group and "
        "axis.",
        "",
        END,
    ]
    text = "\n".join(lines)
    print(text)
    if args.write:
        page = ROOT / "docs" / "results" / "paper-comparison.md"
        replace_block(page, BEGIN, END, text)


if __name__ == "__main__":
    main()
