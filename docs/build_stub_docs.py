"""Writes the docstrings of python/memsnav/_memsnav.pyi from the runtime
docstrings of the installed native module: ``python docs/build_stub_docs.py``
(``--check`` lists the names whose stub docstring differs, and fails).

The runtime docstrings are the Rust doc comments of ``crates/memsnav-py``
(what ``help()`` shows); the stub keeps its hand-written signatures and
takes their docstrings, so the two cannot drift apart
(``tests/test_docstrings.py`` runs the check). A public class or function
of the stub without a docstring gets one; dunder methods keep none (their
runtime docstrings are Python's own). Lines longer than the stub's line
length are wrapped at spaces, keeping their indentation: the text compared
is the same whatever the wrapping."""

from __future__ import annotations

import ast
import inspect
import subprocess
import sys
import textwrap
from collections.abc import Iterator
from pathlib import Path

import memsnav._memsnav as native

ROOT = Path(__file__).resolve().parents[1]
STUB = ROOT / "python" / "memsnav" / "_memsnav.pyi"
LINE_LENGTH = 100


def runtime_doc(name: str) -> str | None:
    """The runtime docstring of ``name`` (``Class.member``), without the
    text signature PyO3 puts first, cleaned as ``inspect.cleandoc``; None
    when the native module has no such name or it has no docstring."""
    obj: object = native
    for part in name.split("."):
        if not hasattr(obj, part):
            return None
        obj = getattr(obj, part)
    doc = getattr(obj, "__doc__", None)
    if not doc:
        return None
    if "\n--\n\n" in doc:  # PyO3's "name(signature)\n--\n\n" header
        doc = doc.split("\n--\n\n", 1)[1]
    return inspect.cleandoc(doc)


def _documented(
    tree: ast.Module,
) -> Iterator[tuple[str, ast.ClassDef | ast.FunctionDef | ast.AsyncFunctionDef]]:
    """Every class and function of the stub with its dotted name."""

    def walk(body: list[ast.stmt], prefix: str) -> Iterator[tuple[str, ast.AST]]:
        for node in body:
            if isinstance(node, ast.ClassDef | ast.FunctionDef | ast.AsyncFunctionDef):
                yield prefix + node.name, node
                if isinstance(node, ast.ClassDef):
                    yield from walk(node.body, f"{prefix}{node.name}.")

    yield from walk(tree.body, "")  # type: ignore[misc]


def _same(a: str, b: str) -> bool:
    return a.split() == b.split()


def differences() -> list[str]:
    """The names whose stub docstring is not the runtime one."""
    tree = ast.parse(STUB.read_text())
    out = []
    for name, node in _documented(tree):
        if node.name.startswith("__"):
            continue
        doc = runtime_doc(name)
        if doc is not None and not _same(ast.get_docstring(node) or "", doc):
            out.append(name)
    return out


def _wrapped(text: str, indent: str) -> list[str]:
    """``text`` as docstring lines under ``indent``, long lines wrapped."""
    lines = []
    for line in text.replace("\\", "\\\\").split("\n"):
        if len(indent) + len(line) <= LINE_LENGTH or not line.strip():
            lines.append(line)
            continue
        lead = line[: len(line) - len(line.lstrip())]
        lines += textwrap.wrap(
            line,
            width=LINE_LENGTH - len(indent),
            subsequent_indent=lead,
            break_long_words=False,
            break_on_hyphens=False,
        )
    return lines


def _docstring_lines(text: str, indent: str) -> list[str]:
    # A quote next to the delimiters would end or extend them.
    text = (" " if text.startswith('"') else "") + text + (" " if text.endswith('"') else "")
    lines = _wrapped(text, indent)
    if len(lines) == 1 and len(indent) + len(lines[0]) + 6 <= LINE_LENGTH:
        return [f'{indent}"""{lines[0]}"""']
    body = [f"{indent}{line}" if line else "" for line in lines]
    body[0] = f'{indent}"""{lines[0]}'
    return [*body, f'{indent}"""']


def write() -> list[str]:
    """Rewrites the stub's docstrings; returns the names changed."""
    source = STUB.read_text().split("\n")
    tree = ast.parse("\n".join(source))
    edits: list[tuple[int, int, list[str]]] = []
    changed = []
    for name, node in _documented(tree):
        doc = runtime_doc(name)
        if node.name.startswith("__") or doc is None:
            continue
        first = node.body[0]
        has_doc = (
            isinstance(first, ast.Expr)
            and isinstance(first.value, ast.Constant)
            and isinstance(first.value.value, str)
        )
        if has_doc and _same(ast.get_docstring(node) or "", doc):
            continue
        changed.append(name)
        indent = " " * (node.col_offset + 4)
        if has_doc:
            assert first.end_lineno is not None
            edits.append((first.lineno - 1, first.end_lineno, _docstring_lines(doc, indent)))
        elif node.lineno == first.lineno:  # "class X(Base): ..." on one line
            header = source[node.lineno - 1].rsplit(": ...", 1)[0] + ":"
            edits.append((node.lineno - 1, node.lineno, [header, *_docstring_lines(doc, indent)]))
        else:
            edits.append((first.lineno - 1, first.lineno - 1, _docstring_lines(doc, indent)))
    for start, end, lines in sorted(edits, reverse=True):
        source[start:end] = lines
    STUB.write_text("\n".join(source))
    # The blank lines around a class that gained a body are ruff's to set.
    subprocess.run([sys.executable, "-m", "ruff", "format", "--quiet", str(STUB)], check=True)
    return changed


def main(argv: list[str]) -> int:
    if argv == ["--check"]:
        stale = differences()
        for name in stale:
            print(f"stub docstring differs: {name}")
        return 1 if stale else 0
    if argv:
        print("usage: python docs/build_stub_docs.py [--check]", file=sys.stderr)
        return 2
    for name in write():
        print(f"wrote {name}")
    return 0


if __name__ == "__main__":
    sys.exit(main(sys.argv[1:]))
