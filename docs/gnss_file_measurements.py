"""The runs behind the figures of the pages on GNSS and IMU files:
docs/how-to/convert-ublox.md, docs/reference/readers.md,
docs/how-to/your-own-files.md, docs/how-to/own-logs.md,
docs/how-to/your-own-imu-log.md that no other record holds: each returns a
record's figures (docs/doc_runs.py writes them to docs/data/<name>.json)."""

from __future__ import annotations

import warnings
from collections.abc import Callable
from pathlib import Path
from typing import Any

import numpy as np

import memsnav as mn
from memsnav.realdata import readers

TAGGED_LOGS = {"drive_0708": "drive_0708/imu_1934.csv", "walk_0827": "walk_0827/imu_1730.csv"}
"""The shared logs whose IMU lines RTKLIB time-tagged, by name."""


def tag_clocks(data_root: Path) -> dict[str, Any]:
    """docs/reference/readers.md's IMU clocks: for each tagged log, the
    fitted clock (``fit_tag_clock``, CR LF counted) as its rate against
    the logger's tick (ppm) and the largest arrival lag above the fitted
    line (s) over the whole log, its first 50 s and after its first second;
    and the apparent rate of the same fit with the tags read as the
    file's LF bytes (%, the miscount's drift)."""
    clocks: dict[str, Any] = {}
    for name, imu in TAGGED_LOGS.items():
        path = data_root / "real-imu-gnss" / imu
        with warnings.catch_warnings():
            warnings.simplefilter("ignore")  # the walk's last line is cut short
            log = readers.read_imu_csv(path, skip_first_line=True)
        tag = readers.read_time_tag(f"{path}.tag")
        clock = mn.fit_tag_clock(log, tag)
        line_end = log.line_end_offset + log.line
        lag = tag.arrival_gps_time(line_end) - clock.gps_time
        since = clock.gps_time - clock.gps_time[0]
        with warnings.catch_warnings():
            warnings.simplefilter("ignore")  # the misread's rate warning is the point
            misread = mn.fit_tag_clock(log, tag, line_ends="as_in_file")
        clocks[name] = {
            "rate_ppm": clock.rate_ppm,
            "lag_spread_s": clock.arrival_lag_spread_s,
            "lag_spread_first_50s_s": float(np.max(lag[since < 50.0])),
            "lag_spread_after_1s_s": float(np.max(lag[since > 1.0])),
            "misread_rate_percent": -1e-4 * misread.rate_ppm,
        }
    return clocks


RUNS: dict[str, Callable[[Path], dict[str, Any]]] = {"tag_clocks": tag_clocks}
"""Each record's name and the run that measures it."""
