"""The runs behind the figures of the pages on GNSS and IMU files:
docs/how-to/convert-ublox.md, docs/reference/readers.md,
docs/how-to/your-own-files.md, docs/how-to/own-logs.md,
docs/how-to/your-own-imu-log.md that no other record holds: each returns a
record's figures (docs/doc_runs.py writes them to docs/data/<name>.json)."""

from __future__ import annotations

from collections.abc import Callable
from pathlib import Path
from typing import Any

RUNS: dict[str, Callable[[Path], dict[str, Any]]] = {}
"""Each record's name and the run that measures it."""
