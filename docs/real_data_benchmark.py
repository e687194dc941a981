"""The real-data benchmark of docs/real-data.md, rerunnable by anyone:
``python docs/real_data_benchmark.py [--data-root DIR] [--write]``.

- drive_0708 (``examples/drive_0708.toml``: loose coupling on the 4 Hz RTK
  solution): GNSS outages of 15, 30 and 60 s on the schedule of the
  published filter that comes with the log (the first 40 s after the start,
  then an outage of L seconds every 3L seconds, none ending later than the
  log), forward filter; horizontal RMS and max error in the outages, the
  share of N/E/D errors inside the filter's 3σ, the error while aided, the
  time the run takes.
- walk_0827 (``examples/walk_0827.toml``: tight coupling with Doppler on
  four satellites): errors against RTK, and the single-point solution's.

Prints the tables as Markdown; ``--write`` puts them into docs/real-data.md
between its ``benchmark`` markers.
"""

from __future__ import annotations

import argparse
import copy
import tempfile
import time
import warnings
from pathlib import Path
from typing import Any

import memsnav as mn
from memsnav.realdata.config import RunConfig

ROOT = Path(__file__).resolve().parents[1]
BEGIN, END = "<!-- benchmark:begin -->", "<!-- benchmark:end -->"


def _run(cfg: RunConfig) -> tuple[dict[str, Any], float]:
    cfg.values["report"]["html"] = False
    with tempfile.TemporaryDirectory() as out, warnings.catch_warnings():
        warnings.simplefilter("ignore")  # the logs' last lines are cut short
        started = time.perf_counter()
        result = mn.navigate(cfg, output=out)
        return result.summary, time.perf_counter() - started


def drive_table(data_root: str | None) -> str:
    base = mn.load_config(ROOT / "examples" / "drive_0708.toml", data_root)
    rows = [
        "| outage length | outages | epochs | RMS horiz. [m] | max horiz. [m] | share in 3σ "
        "| aided RMS horiz. [m] | run [s] |",
        "|---|---|---|---|---|---|---|---|",
    ]
    for length in (15.0, 30.0, 60.0):
        cfg = copy.deepcopy(base)
        cfg.engine["outages"] = {"first_s": 40.0, "length_s": length, "every_s": 3.0 * length}
        s, seconds = _run(cfg)
        e = s["errors_vs_truth"]
        o, a = e["by_outage_length_s"][f"{length:g}"], e["aided"]
        rows.append(
            f"| {length:g} s | {len(s['outages_s'])} | {o['epochs']} | "
            f"{o['rms_horizontal_m']:.2f} | {o['max_horizontal_m']:.2f} | "
            f"{o['within_3sigma_share']:.3f} | {a['rms_horizontal_m']:.3f} | {seconds:.1f} |"
        )
    return "\n".join(rows)


def walk_table(data_root: str | None) -> str:
    cfg = mn.load_config(ROOT / "examples" / "walk_0827.toml", data_root)
    s, seconds = _run(cfg)
    a, spp = s["errors_vs_truth"]["aided"], s["spp_errors_vs_truth"]
    return "\n".join(
        [
            "| solution | epochs | RMS horiz. [m] | RMS vert. [m] | max horiz. [m] "
            "| share in 3σ | run [s] |",
            "|---|---|---|---|---|---|---|",
            f"| memsnav, tight with Doppler | {a['epochs']} | {a['rms_horizontal_m']:.2f} | "
            f"{a['rms_vertical_m']:.2f} | {a['max_horizontal_m']:.2f} | "
            f"{a['within_3sigma_share']:.3f} | {seconds:.1f} |",
            f"| single-point solution | {spp['epochs']} | {spp['rms_horizontal_m']:.2f} | "
            f"{spp['rms_vertical_m']:.2f} | {spp['max_horizontal_m']:.2f} | – | – |",
        ]
    )


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--data-root", default=None, help="folder holding real-imu-gnss/")
    parser.add_argument("--write", action="store_true", help="update docs/real-data.md")
    args = parser.parse_args()
    text = (
        f"{BEGIN}\n\n**drive_0708**, loose, 4 Hz RTK, forward filter:\n\n"
        f"{drive_table(args.data_root)}\n\n**walk_0827**, tight, four satellites:\n\n"
        f"{walk_table(args.data_root)}\n\n{END}"
    )
    print(text)
    if args.write:
        page = ROOT / "docs" / "real-data.md"
        old = page.read_text()
        start, stop = old.index(BEGIN), old.index(END) + len(END)
        page.write_text(old[:start] + text + old[stop:])


if __name__ == "__main__":
    main()
