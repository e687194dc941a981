"""A one-line text progress bar for the command line (stderr)."""

from __future__ import annotations

import sys
import time
from typing import TextIO


class ProgressBar:
    """Callable as ``progress(done, total)``, the form the experiments accept."""

    def __init__(self, label: str, stream: TextIO | None = None, width: int = 30) -> None:
        self.label = label
        self.stream = stream if stream is not None else sys.stderr
        self.width = width
        self.start = time.perf_counter()

    def __call__(self, done: int, total: int) -> None:
        # Redrawing in place only makes sense on a terminal; a log gets the
        # final line only.
        if done < total and not self.stream.isatty():
            return
        fraction = done / total if total else 1.0
        filled = round(self.width * fraction)
        elapsed = time.perf_counter() - self.start
        eta = elapsed / fraction - elapsed if fraction > 0 else float("nan")
        bar = "#" * filled + "-" * (self.width - filled)
        self.stream.write(
            f"\r{self.label:<22} [{bar}] {done}/{total} {elapsed:6.1f} s (eta {eta:5.0f} s)"
        )
        if done >= total:
            self.stream.write("\n")
        self.stream.flush()
