"""The figures the docs quote, from the records the scripts write.

A script that measures what a page quotes writes a record,
``docs/data/<name>.json``::

    {"generated": "2026-12-02", "commit": "b5a9f39", "machine": "x86_64, 2 CPUs, Linux",
     "figures": {"drift_km": 45.3, "in_view": {"gps": [6.7, 6, 8]}}}

and a page shows a figure only through a placeholder that names it and
the format it is shown with (a Python format spec; negative numbers get a
true minus sign)::

    drifts by about <!-- fig first_session.drift_km .1f -->45.3<!-- /fig --> km

The text between the markers is what ``render`` writes there from the
record; ``python docs/figures.py --write`` re-renders every page (the
scripts do it after writing their record), ``--check`` lists the stale
ones. A figure's path is the record's name, then keys and list indices
separated by dots (``concepts.in_view.gps.0``). Tables stay whole blocks
(marked_block.py); this module is for the figures in sentences, and for
the date a page's results carry: ``<!-- dated name -->…<!-- /dated -->``
shows when, on what machine and at which commit the record ``name`` was
measured.

The scripts import it as a sibling (``python docs/x.py`` puts ``docs/`` on
the path; pytest's ``pythonpath`` does for the tests)."""

from __future__ import annotations

import datetime
import json
import math
import os
import platform
import re
import subprocess
import sys
from pathlib import Path
from typing import Any

DOCS = Path(__file__).resolve().parent
ROOT = DOCS.parent
DATA = DOCS / "data"

PLACEHOLDER = re.compile(
    r"<!-- fig (?P<path>[\w-]+(?:\.[\w-]+)+)(?: (?P<spec>\S+))? -->(?P<shown>.*?)<!-- /fig -->",
    re.S,
)
"""A figure in a page: its path, its format spec, what is shown."""

DATED = re.compile(r"<!-- dated (?P<name>[\w-]+) -->(?P<shown>.*?)<!-- /dated -->", re.S)
"""A record's provenance in a page: the record's name, what is shown."""


def pages() -> list[Path]:
    """The pages that may quote figures: the README and docs/."""
    return [ROOT / "README.md", *sorted(DOCS.rglob("*.md"))]


def _commit() -> str:
    """The short hash of HEAD, with ``+`` when the work tree has changes
    (the figures then come from code no commit holds). The records
    themselves do not count: a script writing several sees its own."""
    run = {"cwd": ROOT, "capture_output": True, "text": True, "check": True}
    commit = subprocess.run(["git", "rev-parse", "--short", "HEAD"], **run).stdout.strip()
    status = ["git", "status", "--porcelain", "--untracked-files=no", "--", ".", ":!docs/data"]
    dirty = subprocess.run(status, **run)
    return commit + ("+" if dirty.stdout.strip() else "")


def machine() -> str:
    """The machine a record was measured on, as far as it matters to a
    figure (architecture, cores, system), never its name."""
    return f"{platform.machine()}, {os.cpu_count()} CPUs, {platform.system()}"


def write_record(name: str, figures: dict[str, Any], *, render: bool = True) -> Path:
    """Writes ``docs/data/<name>.json`` with today's UTC date, the commit
    and the machine, then (``render``) re-renders the pages from it."""
    record = {
        "generated": datetime.datetime.now(datetime.UTC).date().isoformat(),
        "commit": _commit(),
        "machine": machine(),
        "figures": figures,
    }
    DATA.mkdir(exist_ok=True)
    path = DATA / f"{name}.json"
    path.write_text(json.dumps(record, indent=2, ensure_ascii=False) + "\n")
    if render:
        write_pages()
    return path


def load_record(name: str) -> dict[str, Any]:
    """The record ``docs/data/<name>.json`` (FileNotFoundError naming the
    script to run when it is missing)."""
    return json.loads((DATA / f"{name}.json").read_text())


def figures(name: str) -> dict[str, Any]:
    """The figures of the record ``name``."""
    return load_record(name)["figures"]


def figure(path: str) -> Any:
    """The figure at ``path`` (``record.key.0``): KeyError naming the path
    when the record does not hold it."""
    name, *keys = path.split(".")
    value: Any = figures(name)
    for key in keys:
        try:
            value = value[int(key)] if isinstance(value, list) else value[key]
        except (KeyError, IndexError, ValueError) as e:
            raise KeyError(f"docs/data/{name}.json holds no figure {path}") from e
    return value


def _duration(seconds: float, spec: str) -> str:
    """``seconds`` as hours and minutes (``hm``, to the minute) or hours,
    minutes and seconds (``hms``, to the second): "14 h 4 min 41 s"."""
    step = 60 if spec == "hm" else 1
    whole = round(seconds / step) * step
    parts = [(whole // 3600, "h"), (whole % 3600 // 60, "min"), (whole % 60, "s")]
    return " ".join(f"{n:.0f} {unit}" for n, unit in parts[: 2 if spec == "hm" else 3])


SUPERSCRIPT = str.maketrans("0123456789-", "⁰¹²³⁴⁵⁶⁷⁸⁹⁻")


def _power_of_ten(value: float) -> str:
    """``value``, a power of ten, as ``10⁶``, ``−10⁵`` or ``10⁻⁹``."""
    exponent = round(math.log10(abs(value)))
    if value == 0 or abs(value) != float(f"1e{exponent}"):
        raise ValueError(f"{value} is not a power of ten (format p10)")
    return ("−" if value < 0 else "") + "10" + str(exponent).translate(SUPERSCRIPT)


def shown(value: Any, spec: str | None) -> str:
    """``value`` as a page shows it: formatted with ``spec`` (a Python
    format spec; ``hm`` / ``hms`` for a duration in seconds; ``p10`` for
    a power of ten), a minus sign for a negative number."""
    if spec in ("hm", "hms"):
        return _duration(value, spec)
    if spec == "p10":
        return _power_of_ten(value)
    text = format(value, spec or "")
    if spec and spec.endswith("e"):  # 2e+04 → 2e4, 1.5e-03 → 1.5e-3
        text = re.sub(r"e([+-])0*(\d)", lambda m: f"e{m[1].strip('+')}{m[2]}", text)
    return text.replace("-", "−") if isinstance(value, int | float) else text


def render(text: str, *, keep_missing: bool = False) -> str:
    """``text`` with every placeholder showing its figure and every dated
    marker its record's date, machine and commit; one whose record or
    figure is missing raises, or (``keep_missing``) stays as it is."""

    def one(match: re.Match[str]) -> str:
        try:
            value = shown(figure(match["path"]), match["spec"])
        except (KeyError, FileNotFoundError):
            if keep_missing:
                return match[0]
            raise
        spec = f" {match['spec']}" if match["spec"] else ""
        return f"<!-- fig {match['path']}{spec} -->{value}<!-- /fig -->"

    def dated(match: re.Match[str]) -> str:
        try:
            record = load_record(match["name"])
        except FileNotFoundError:
            if keep_missing:
                return match[0]
            raise
        when = f"{record['generated']} ({record['machine']}, commit {record['commit']})"
        return f"<!-- dated {match['name']} -->{when}<!-- /dated -->"

    return DATED.sub(dated, PLACEHOLDER.sub(one, text))


def stale_pages() -> list[Path]:
    """The pages whose figures are not what their records render to."""
    return [p for p in pages() if render(text := p.read_text()) != text]


def write_pages() -> list[Path]:
    """Re-renders the pages from the records there are (a placeholder
    whose record is still to be written stays); returns those changed."""
    changed = []
    for page in pages():
        text = page.read_text()
        if (new := render(text, keep_missing=True)) != text:
            page.write_text(new)
            changed.append(page)
    return changed


def main(argv: list[str]) -> int:
    if argv == ["--write"]:
        for page in write_pages():
            print(f"wrote {page.relative_to(ROOT)}")
        return 0
    if argv == ["--check"]:
        stale = stale_pages()
        for page in stale:
            print(f"stale: {page.relative_to(ROOT)}")
        return 1 if stale else 0
    print("usage: python docs/figures.py --write | --check", file=sys.stderr)
    return 2


if __name__ == "__main__":
    sys.exit(main(sys.argv[1:]))
