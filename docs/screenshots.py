"""Screenshots of memsnav's HTML reports as a reader sees them, to check
that no table overflows the page and every figure reads:
``python docs/screenshots.py REPORT.html [...] [--out DIR] [--width 1400]``.

Each report is drawn by headless Chromium (on Debian:
``sudo apt-get update && sudo apt-get install -y chromium``; ``--chromium``
names another binary, e.g. ``google-chrome``) in a window ``--width``
pixels wide and tall enough for the whole page, then cut at the end of
the page and into PNG pages of at most ``--page-height`` pixels
(``<report>-0.png``, ``<report>-1.png``, ...) that an image viewer shows at
full size. The window is wider than the page's text column (60 rem): a
table or figure wider than that column runs past its right edge, which the
screenshot shows.
"""

from __future__ import annotations

import argparse
import shutil
import subprocess
import tempfile
from pathlib import Path

import numpy as np
from PIL import Image

#: A window this tall holds the longest report (memsnav reproduce).
WINDOW_HEIGHT = 30000


def shoot(report: Path, out: Path, chromium: str, width: int, page_height: int) -> list[Path]:
    """The report's screenshot pages, written into ``out``."""
    with tempfile.TemporaryDirectory() as tmp:
        full = Path(tmp) / "full.png"
        subprocess.run(
            [
                chromium,
                "--headless",
                # As root (a container) Chromium needs it; it only reads a local file.
                "--no-sandbox",
                "--hide-scrollbars",
                f"--window-size={width},{WINDOW_HEIGHT}",
                f"--screenshot={full}",
                report.resolve().as_uri(),
            ],
            check=True,
            capture_output=True,
        )
        image = Image.open(full).convert("RGB")
    # The page ends where the last non-white row is.
    ink = np.flatnonzero((np.asarray(image) < 250).any(axis=(1, 2)))
    height = min(image.height, int(ink.max()) + 20) if ink.size else image.height
    stem = report.parent.name if report.stem == "report" else report.stem
    pages = []
    for k, top in enumerate(range(0, height, page_height)):
        path = out / f"{stem}-{k}.png"
        image.crop((0, top, width, min(height, top + page_height))).save(path)
        pages.append(path)
    return pages


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("reports", nargs="+", type=Path, help="report.html files")
    parser.add_argument("--out", type=Path, default=Path("screenshots"), help="output folder")
    parser.add_argument("--width", type=int, default=1400, help="window width, px")
    parser.add_argument("--page-height", type=int, default=2400, help="height of a page, px")
    parser.add_argument("--chromium", default="chromium", help="the Chromium binary")
    args = parser.parse_args()
    if shutil.which(args.chromium) is None:
        parser.error(
            f"{args.chromium}: not found (sudo apt-get update && sudo apt-get install -y "
            "chromium, or --chromium)"
        )
    args.out.mkdir(parents=True, exist_ok=True)
    for report in args.reports:
        for page in shoot(report, args.out, args.chromium, args.width, args.page_height):
            print(page)


if __name__ == "__main__":
    main()
