"""The report page (memsnav.report.document): its tables stay within the
text column and its numbers on one line, checked on the HTML
(report_checks.page_problems, which every report's test applies) and, when
Chromium is installed, on the page as the browser draws it at 1400 px
(docs/screenshots.py); without Chromium that test skips."""

import shutil
import subprocess
from pathlib import Path

import numpy as np
import pytest
from PIL import Image
from report_checks import MAX_COLUMNS, page_problems

from memsnav.report.document import Report

WIDE_ROW = [
    "accelerometer scale factor",
    "(5.9 ± 0.1)e-05",
    6.42e-05,
    "1.86 / 11.94",
    -1.70507e-04,
    "[2.5, ∞)",
    1334.2,
    0.967,
    "0.222 rad (12.7°)",
]


def _report(columns: int = len(WIDE_ROW)) -> Report:
    report = Report("a wide table")
    header = [f"a long column header {k}" for k in range(columns)]
    report.table(header, [(WIDE_ROW * 2)[:columns]] * 3)
    return report


def test_tables_scroll_and_numbers_stay_on_one_line():
    page = _report().render()
    assert not page_problems(page)
    assert '<div class="table"><table>' in page and ".table { overflow-x: auto;" in page
    # Floats as numbers.number writes them; numbers (and only they) unbroken.
    assert '<td class="num">6.42e-05</td>' in page and '<td class="num">1334</td>' in page
    assert '<td class="num">(5.9 ± 0.1)e-05</td>' in page
    assert '<td class="num">[2.5, ∞)</td>' in page
    assert "<td>0.222 rad (12.7°)</td>" in page and "<td>accelerometer scale factor</td>" in page


def test_the_page_check_finds_what_overflows():
    """The check can fail: a bare table, too many columns, a number a line
    may split."""
    page = _report().render()
    bare = page.replace('<div class="table">', "<div>")
    assert page_problems(bare) == ["table 0: not in a container that scrolls sideways"]
    wide = _report(MAX_COLUMNS + 1).render()
    assert page_problems(wide) == [f"table 0: {MAX_COLUMNS + 1} columns (at most 10 fit)"]
    split = page.replace('<td class="num">6.42e-05', "<td>6.42e-05")
    assert page_problems(split) == [f"table 0: numbers a line may split: {['6.42e-05'] * 3}"]


def _ink_right_edge(page: str, tmp_path: Path, name: str) -> int:
    """The rightmost non-white column of ``page`` drawn at 1400 px (as
    docs/screenshots.py draws it, in a window only as tall as this page)."""
    html, png = tmp_path / f"{name}.html", tmp_path / f"{name}.png"
    html.write_text(page)
    subprocess.run(
        [
            "chromium",
            "--headless",
            "--no-sandbox",
            "--hide-scrollbars",
            "--window-size=1400,600",
            f"--screenshot={png}",
            html.as_uri(),
        ],
        check=True,
        capture_output=True,
    )
    image = np.asarray(Image.open(png).convert("L"))
    return int(np.flatnonzero((image < 250).any(axis=0)).max())


@pytest.mark.slow
@pytest.mark.skipif(shutil.which("chromium") is None, reason="needs chromium (apt-get install)")
def test_chromium_draws_tables_within_the_text_column(tmp_path):
    """At 1400 px the text column (60 rem + 1 rem padding each side)
    ends at (1400 + 60·16) / 2 = 1180 px. The widest table the check
    lets through, of the numbers the reports print, fits it; a table too
    wide for it scrolls inside it, and runs past it outside its container."""
    column_right = (1400 + 60 * 16) // 2
    fits = _report(MAX_COLUMNS).render().replace("a long column header", "h")
    assert _ink_right_edge(fits, tmp_path, "fits") <= column_right
    report = Report("too wide")
    report.table(
        [f"h {k}" for k in range(MAX_COLUMNS)],
        [["(5.9 ± 0.1)e-05 / (6.0 ± 0.1)e-05"] * MAX_COLUMNS],
    )
    page = report.render()
    assert _ink_right_edge(page, tmp_path, "scrolls") <= column_right
    bare = page.replace('<div class="table">', "<div>")
    assert _ink_right_edge(bare, tmp_path, "bare") > column_right + 100
