"""The runs behind the figures of the results pages and the guides to the
filter's runs: docs/results/*.md, docs/how-to/run-on-dask.md,
docs/how-to/step-api.md, docs/explanation/smoother.md,
docs/explanation/few-satellites.md, docs/reference/robustness.md that no
other record holds: each returns a record's figures (docs/doc_runs.py
writes them to docs/data/<name>.json)."""

from __future__ import annotations

from collections.abc import Callable
from pathlib import Path
from typing import Any

RUNS: dict[str, Callable[[Path], dict[str, Any]]] = {}
"""Each record's name and the run that measures it."""
