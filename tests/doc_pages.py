"""The documentation pages tests read, by their path under docs/.

The guide to ``memsnav navigate`` and the calibration guide are several
pages (a tutorial, how-to guides, reference, explanation, results); a test
that checks what the guide says about a run reads the pages named here."""

from pathlib import Path

DOCS = Path(__file__).resolve().parent.parent / "docs"

NAVIGATE_GUIDE = (
    "tutorials/navigate-a-log.md",
    "reference/configuration.md",
    "how-to/tune-for-your-imu.md",
    "reference/readers.md",
    "explanation/time-and-truth.md",
    "results/against-rtk.md",
    "how-to/your-own-imu-log.md",
    "how-to/convert-ublox.md",
    "how-to/multi-gnss.md",
)
"""The pages about navigating a real log."""

CALIBRATION_GUIDE = ("how-to/calibrate-an-imu.md", "explanation/calibration.md")
"""The pages about calibrating a real IMU."""


def doc_text(*pages: str) -> str:
    """The text of ``pages`` (paths under docs/), one after the other."""
    return "\n\n".join((DOCS / page).read_text() for page in pages)
