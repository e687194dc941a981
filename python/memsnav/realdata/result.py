"""What :func:`memsnav.navigate` returns for a run of real logs: shared by
the run (``realdata/pipeline.py``) that fills it and the report
(``realdata/report.py``) that draws it."""

from __future__ import annotations

from dataclasses import dataclass, field
from typing import Any

from memsnav.realdata.config import RunConfig


@dataclass
class LogNavigationResult:
    """Everything a run of real logs produced: the engine's ``run`` (a
    ``LogRun``; its ``smoothed`` when ``[filter] smoother = true``), the
    scores against the truth (``truth``, ``truth_smoothed``) and of the
    single-point solution (``spp``), the same less each one's mean offset
    when the truth is scored by precision (``precision``: ``forward``,
    ``smoothed``, ``spp``), and ``summary``, the plain dict written to
    ``summary.json``. A run that failed (``failure``) has what was computed
    before the failure: ``run`` None when it failed before the engine ran."""

    config: RunConfig
    run: Any
    truth: dict[str, Any] | None
    spp: dict[str, Any] | None
    summary: dict[str, Any] = field(default_factory=dict)
    files: dict[str, str] = field(default_factory=dict)
    truth_smoothed: dict[str, Any] | None = None
    precision: dict[str, dict[str, Any]] | None = None

    def __repr__(self) -> str:
        if self.failure is not None:
            state = f"failed at {self.failure.get('stage')}"
        else:
            state = f"{len(self.run)} epochs" if self.run is not None else "not run"
        scored = ", scored against the truth" if self.truth is not None else ""
        name = self.config[""]["name"]
        return f"LogNavigationResult({name!r}: {state}{scored}, {len(self.files)} files)"

    @property
    def failure(self) -> dict[str, Any] | None:
        """The summary's ``failure`` entry (``stage``, ``what``,
        ``gps_time_s``, ``time_s``, ``message``, ``hints``; later failures
        under ``also``), or None for a run that did not fail."""
        return self.summary.get("failure")
