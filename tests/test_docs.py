"""The documentation stays true: every Python example in the README and
docs/ runs, docs/reference/api.md is what docs/build_api.py generates from the
docstrings of the installed package, and docs/how-to/run-on-dask.md's scaling
table is what docs/distributed_scaling.py writes from its record."""

import json
import re
import runpy
from pathlib import Path

import pytest
from shared_data import data_root

ROOT = Path(__file__).resolve().parent.parent
PAGES = [ROOT / "README.md", *sorted((ROOT / "docs").rglob("*.md"))]
# The examples read the shared data as a user in the checkout would; they run
# in a temporary directory, so the data root is given the documented way.
SHARED_DATA = data_root()


def _python_blocks(page: Path) -> str:
    return "\n".join(re.findall(r"```python\n(.*?)```", page.read_text(), flags=re.S))


@pytest.mark.parametrize(
    "page", [p for p in PAGES if _python_blocks(p)], ids=lambda p: str(p.relative_to(ROOT))
)
def test_examples_run(page, tmp_path, monkeypatch, capsys):
    monkeypatch.chdir(tmp_path)
    monkeypatch.setenv("MEMSNAV_DATA_ROOT", str(SHARED_DATA))
    # All blocks of a page form one session, as a reader would type them.
    exec(compile(_python_blocks(page), str(page), "exec"), {"__name__": "__docs__"})
    assert capsys.readouterr().out  # the examples print what they show


def test_api_reference_is_current():
    build = runpy.run_path(str(ROOT / "docs" / "build_api.py"))
    assert (ROOT / "docs" / "reference" / "api.md").read_text() == build["render"](), (
        "docs/reference/api.md is stale: run python docs/build_api.py"
    )


def test_distributed_scaling_table_is_its_scripts():
    """No run here (speed is measured by the script, never by a test): the
    table is ``render`` of the measurements the script kept."""
    script = runpy.run_path(str(ROOT / "docs" / "distributed_scaling.py"))
    text = (ROOT / "docs" / "how-to" / "run-on-dask.md").read_text()
    begin, end = script["BEGIN"], script["END"]
    block = text[text.index(begin) : text.index(end) + len(end)]
    record = json.loads((ROOT / "docs" / "distributed_scaling.json").read_text())
    assert block == script["render"](record), (
        "docs/how-to/run-on-dask.md's scaling table is stale: run python "
        "docs/distributed_scaling.py --write"
    )


def test_reference_pages_are_current():
    """The configuration keys (from the core's key table and the reading
    schema) and the CLI reference are what docs/build_reference.py writes."""
    build = runpy.run_path(str(ROOT / "docs" / "build_reference.py"))
    for name, render in build["PAGES"].items():
        page = ROOT / "docs" / "reference" / name
        assert page.read_text() == render(), (
            f"docs/reference/{name} is stale: run python docs/build_reference.py"
        )


def test_no_hand_written_page_is_over_600_lines():
    generated = {"reference/api.md", "reference/configuration-keys.md", "reference/cli.md"}
    long = {
        str(p.relative_to(ROOT / "docs")): n
        for p in (ROOT / "docs").rglob("*.md")
        if str(p.relative_to(ROOT / "docs")) not in generated
        and (n := len(p.read_text().splitlines())) > 600
    }
    assert not long, long


def test_relative_links_resolve():
    """Every relative Markdown link of README.md and docs/ names a file
    that exists (outside code blocks)."""
    broken = []
    for page in PAGES:
        text = re.sub(r"```.*?```", "", page.read_text(), flags=re.S)
        for target in re.findall(r"\]\(([^)\s]+)\)", text):
            file = target.partition("#")[0]
            if file and not re.match(r"^[a-z]+:", target) and not (page.parent / file).exists():
                broken.append(f"{page.relative_to(ROOT)}: {target}")
    assert not broken, broken


# A fenced block is Python that runs (test_examples_run), Python marked as
# not runnable ("python no-run": a cluster, files outside the data root),
# or not Python at all.
FENCES = {"python", "python no-run", "sh", "bash", "text", "toml", "json"}


def test_every_code_block_runs_or_is_marked():
    unmarked = []
    for page in PAGES:
        inside = False
        for number, line in enumerate(page.read_text().splitlines(), 1):
            if line.startswith("```"):
                if not inside and line[3:].strip() not in FENCES:
                    unmarked.append(f"{page.relative_to(ROOT)}:{number}: {line}")
                inside = not inside
    assert not unmarked, unmarked
