"""The documentation stays true: every Python example in the README and
docs/ runs, docs/api.md is what docs/build_api.py generates from the
docstrings of the installed package, and docs/distributed.md's scaling
table is what docs/distributed_scaling.py writes from its record."""

import json
import re
import runpy
from pathlib import Path

import pytest
from shared_data import data_root

ROOT = Path(__file__).resolve().parent.parent
PAGES = [ROOT / "README.md", *sorted((ROOT / "docs").glob("*.md"))]
# The examples read the shared data as a user in the checkout would; they run
# in a temporary directory, so the data root is given the documented way.
SHARED_DATA = data_root()


def _python_blocks(page: Path) -> str:
    return "\n".join(re.findall(r"```python\n(.*?)```", page.read_text(), flags=re.S))


@pytest.mark.parametrize("page", [p for p in PAGES if _python_blocks(p)], ids=lambda p: p.name)
def test_examples_run(page, tmp_path, monkeypatch, capsys):
    monkeypatch.chdir(tmp_path)
    monkeypatch.setenv("MEMSNAV_DATA_ROOT", str(SHARED_DATA))
    # All blocks of a page form one session, as a reader would type them.
    exec(compile(_python_blocks(page), str(page), "exec"), {"__name__": "__docs__"})
    assert capsys.readouterr().out  # the examples print what they show


def test_api_reference_is_current():
    build = runpy.run_path(str(ROOT / "docs" / "build_api.py"))
    assert (ROOT / "docs" / "api.md").read_text() == build["render"](), (
        "docs/api.md is stale: run python docs/build_api.py"
    )


def test_distributed_scaling_table_is_its_scripts():
    """No run here (speed is measured by the script, never by a test): the
    table is ``render`` of the measurements the script kept."""
    script = runpy.run_path(str(ROOT / "docs" / "distributed_scaling.py"))
    text = (ROOT / "docs" / "distributed.md").read_text()
    begin, end = script["BEGIN"], script["END"]
    block = text[text.index(begin) : text.index(end) + len(end)]
    record = json.loads((ROOT / "docs" / "distributed_scaling.json").read_text())
    assert block == script["render"](record), (
        "docs/distributed.md's scaling table is stale: run python docs/distributed_scaling.py "
        "--write"
    )
