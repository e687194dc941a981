"""The figures the docs show come from records (docs/figures.py): every
record says when, on which commit and on what machine it was measured;
every placeholder names a recorded figure and shows what its record
renders to; every record is shown somewhere. The figures themselves are
checked by the tests that measure them."""

import datetime
import json
import re

import figures
import pytest

RECORDS = sorted(figures.DATA.glob("*.json"))


@pytest.mark.parametrize("path", RECORDS, ids=lambda p: p.stem)
def test_every_record_says_when_where_and_from_which_commit(path):
    record = json.loads(path.read_text())
    assert sorted(record) == ["commit", "figures", "generated", "machine"], list(record)
    datetime.date.fromisoformat(record["generated"])
    assert re.fullmatch(r"[0-9a-f]{7,40}\+?", record["commit"]), record["commit"]
    assert re.fullmatch(r"\w+, \d+ CPUs, \w+", record["machine"]), record["machine"]
    assert record["figures"], path


def _placeholders() -> list[tuple[str, str]]:
    return [
        (str(page.relative_to(figures.ROOT)), match["path"])
        for page in figures.pages()
        for match in figures.PLACEHOLDER.finditer(page.read_text())
    ]


def test_every_placeholder_names_a_recorded_figure():
    missing = []
    for page, path in _placeholders():
        try:
            figures.figure(path)
        except (KeyError, FileNotFoundError) as e:
            missing.append(f"{page}: {e}")
    assert not missing, missing


def test_the_pages_show_what_their_records_render_to():
    stale = [str(p.relative_to(figures.ROOT)) for p in figures.stale_pages()]
    assert not stale, f"stale figures in {stale}: run python docs/figures.py --write"


def test_every_dated_marker_names_a_record_and_every_results_page_is_dated():
    """A results page says when, where and at which commit its figures
    were measured: through a dated marker (rendered from its record) or
    the line its generating script writes."""
    pages = figures.pages()
    names = [m["name"] for page in pages for m in figures.DATED.finditer(page.read_text())]
    assert names
    missing = [name for name in names if not (figures.DATA / f"{name}.json").exists()]
    assert not missing, missing
    undated = [
        page.name
        for page in (figures.DOCS / "results").glob("*.md")
        if not figures.DATED.search(text := page.read_text())
        and not re.search(r"Measured by `[^`]+` on \d{4}-\d{2}-\d{2}", text)
    ]
    assert not undated, undated


def test_every_record_is_shown():
    """Each record fills a placeholder or a docs script's block."""
    shown = {path.split(".")[0] for _, path in _placeholders()} | {
        m["name"] for page in figures.pages() for m in figures.DATED.finditer(page.read_text())
    }
    scripts = "".join(p.read_text() for p in figures.DOCS.glob("*.py"))
    unshown = {p.stem for p in RECORDS if p.stem not in shown and f'"{p.stem}' not in scripts}
    assert not unshown, unshown


def test_a_placeholder_renders_its_figure_with_its_format():
    """The rendering itself, on a record of the repository: the format
    spec, the minus sign, the duration specs."""
    assert figures.shown(-0.125, ".2f") == "−0.12"
    assert figures.shown(50_681.0, "hms") == "14 h 4 min 41 s"
    assert figures.shown(43_080.0 + 20, "hm") == "11 h 58 min"
    powers = [figures.shown(v, "p10") for v in (1e6, -1e5, 1e-9, 100)]
    assert powers == ["10⁶", "−10⁵", "10⁻⁹", "10²"]
    with pytest.raises(ValueError, match="1024 is not a power of ten"):
        figures.shown(1024, "p10")
    dated = json.loads(RECORDS[0].read_text())
    when = f"{dated['generated']} ({dated['machine']}, commit {dated['commit']})"
    marker = f"<!-- dated {RECORDS[0].stem} -->"
    assert figures.render(f"on {marker}?<!-- /dated -->.") == f"on {marker}{when}<!-- /dated -->."
    (path,) = RECORDS[:1]
    name = path.stem
    key, value = next(iter(json.loads(path.read_text())["figures"].items()))
    if isinstance(value, int | float):
        text = f"a <!-- fig {name}.{key} .3f -->old<!-- /fig --> b"
        expected = f"a <!-- fig {name}.{key} .3f -->{figures.shown(value, '.3f')}<!-- /fig --> b"
        assert figures.render(text) == expected
