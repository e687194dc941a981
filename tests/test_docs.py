"""The documentation stays true: every Python example in the README and
docs/ runs, docs/reference/api.md is what docs/build_api.py generates from the
docstrings of the installed package, and docs/how-to/run-on-dask.md's scaling
table is what docs/distributed_scaling.py writes from its record."""

import ast
import inspect
import json
import re
import runpy
import warnings
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
    """The configuration keys and their JSON schema (from the core's key
    table and the reading schema) and the CLI reference are what
    docs/build_reference.py writes."""
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


#: Where a page may name a file of the repository: the root, and the core
#: crate (whose own tests/ and src/ pages name the way cargo does).
SOURCE_ROOTS = (ROOT, ROOT / "crates" / "memsnav-core")
SOURCE_PATH = re.compile(
    r"`((?:tests|docs|benches|examples|python/memsnav|crates/[\w-]+/(?:src|tests))"
    r"/[\w/.-]+\.(?:py|rs|md|json|toml|pyi))`"
)


def test_the_files_the_pages_name_exist():
    """A file of the repository a hand-written page names in code
    (`tests/test_x.py`) exists: a renamed test or script leaves no page
    pointing at nothing. Decision records and the changelog keep history."""
    missing = []
    for page in [ROOT / "CONTRIBUTING.md", *PAGES]:
        if "decisions" in page.parts:
            continue
        for name in SOURCE_PATH.findall(page.read_text()):
            if "NNNN" not in name and not any((r / name).exists() for r in SOURCE_ROOTS):
                missing.append(f"{page.relative_to(ROOT)}: {name}")
    assert not missing, missing


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


# An inline code span of a hand-written page that parses as a Python
# expression with a call in it is checked: run, when its names are ones
# the check provides (below) and it needs no file; otherwise each call in
# it must name one of memsnav's functions, classes or methods and bind to
# its signature (`...` stands for arguments left out). A span that is not
# memsnav's Python (Rust, a formula) is followed by NOT_PYTHON. The
# generated reference pages show the live signatures themselves.
NOT_PYTHON = "<!-- not python -->"
GENERATED_PAGES = {"reference/api.md", "reference/configuration-keys.md", "reference/cli.md"}


def _inline_calls(page: Path) -> list[tuple[int, str, ast.Expression]]:
    """(line, span, parsed) of the page's unmarked inline calls."""
    text = re.sub(r"```.*?```", lambda m: "\n" * m[0].count("\n"), page.read_text(), flags=re.S)
    calls = []
    for match in re.finditer(r"(?<!`)`([^`\n]+)`(?!`)", text):
        if text[match.end() :].lstrip(" ").startswith(NOT_PYTHON):
            continue
        try:
            tree = ast.parse(match[1].strip(), mode="eval")
        except SyntaxError:
            continue  # not Python: a path, a unit, a command line
        if any(isinstance(node, ast.Call) for node in ast.walk(tree)):
            calls.append((text.count("\n", 0, match.start()) + 1, match[1], tree))
    return calls


def _namespace() -> dict:
    """The names an inline call may use and be run with."""
    import numpy as np

    import memsnav as mn

    imu = mn.ImuModel.preset("paper-mems", seed=0)
    f = np.tile([0.0, 0.0, -9.81], (100, 1))
    public = {name: getattr(mn, name) for name in dir(mn) if not name.startswith("_")}
    return (
        public
        | {"mn": mn, "memsnav": mn, "np": np, "imu": imu}
        | {
            "f": f,
            "w": np.zeros((100, 3)),
            "seed": 7,
            "name": "imu",
        }
    )


#: Calls bound to their signature, never run: they take minutes.
COSTLY = {"experiments", "navigate", "reproduce"}


def _memsnav_modules() -> list:
    """memsnav's modules, the ones the package imports and its converters."""
    import sys

    import memsnav.realdata.convert  # noqa: F401  (`convert_ubx`)

    return [m for name, m in sorted(sys.modules.items()) if name.split(".")[0] == "memsnav"]


def _memsnav_classes() -> list[type]:
    found = {}
    for module in _memsnav_modules():
        for value in vars(module).values():
            if isinstance(value, type) and value.__module__.startswith("memsnav"):
                found[value.__qualname__, value.__module__] = value
    return list(found.values())


def _callees(func: ast.expr, namespace: dict, classes: list[type]) -> list:
    """What a call's function may be: itself when it evaluates, else
    memsnav's function or the classes' methods of that name."""

    try:
        return [eval(compile(ast.Expression(func), "<doc>", "eval"), dict(namespace))]
    except Exception:
        pass
    name = func.attr if isinstance(func, ast.Attribute) else getattr(func, "id", None)
    if not name:
        return []
    found = [vars(m)[name] for m in _memsnav_modules() if callable(vars(m).get(name))]
    return found + [getattr(c, name) for c in classes if name in vars(c)]


def _binds(callee, call: ast.Call) -> bool:
    try:
        signature = inspect.signature(callee)
    except (TypeError, ValueError):
        return callable(callee)  # no signature to bind: that it exists is the check
    elided = [a for a in call.args if isinstance(a, ast.Constant) and a.value is Ellipsis]
    positional = [None] * (len(call.args) - len(elided))
    if next(iter(signature.parameters), None) == "self":
        positional.insert(0, None)
    keywords = {k.arg: None for k in call.keywords if k.arg}
    bind = signature.bind_partial if elided else signature.bind
    try:
        bind(*positional, **keywords)
    except TypeError:
        return False
    return True


def _check_call(span: str, tree: ast.Expression, namespace: dict, classes: list[type]) -> str:
    """ "" when the span runs or binds; else why not."""
    names = {n.id for n in ast.walk(tree) if isinstance(n, ast.Name)}
    elided = any(isinstance(n, ast.Constant) and n.value is Ellipsis for n in ast.walk(tree))
    costly = names | {n.attr for n in ast.walk(tree) if isinstance(n, ast.Attribute)}
    if names <= namespace.keys() and not elided and not costly & COSTLY:
        try:
            eval(compile(tree, "<doc>", "eval"), dict(namespace))
            return ""
        except OSError:
            pass  # a file the check does not have: bind it instead
        except Exception as e:
            return f"raises {e!r}"
    for call in (n for n in ast.walk(tree) if isinstance(n, ast.Call)):
        callees = _callees(call.func, namespace, classes)
        if not callees:
            return f"{ast.unparse(call.func)} is none of memsnav's"
        if not any(_binds(c, call) for c in callees):
            return f"{ast.unparse(call)} does not bind to {ast.unparse(call.func)}'s signature"
    return ""


def test_every_inline_call_runs_or_binds_or_is_marked(tmp_path, monkeypatch):
    monkeypatch.chdir(tmp_path)
    namespace, classes = _namespace(), _memsnav_classes()
    failed = []
    for page in PAGES:
        if page.relative_to(ROOT).as_posix().removeprefix("docs/") in GENERATED_PAGES:
            continue
        for line, span, tree in _inline_calls(page):
            with warnings.catch_warnings():
                warnings.simplefilter("ignore")
                why = _check_call(span, tree, namespace, classes)
            if why:
                failed.append(f"{page.relative_to(ROOT)}:{line}: `{span}` {why}")
    assert not failed, "\n".join(failed)
