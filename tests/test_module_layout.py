"""No import circle among the project's modules, computed from the sources
(nothing listed by hand): a circle is a strongly connected component of
more than one module in the graph of "module A uses module B".

Python (``python/memsnav``): every ``import`` and ``from ... import`` of
every module, absolute or relative, wherever it stands: inside a function
or under ``if TYPE_CHECKING`` it is still a dependency a reader meets, and
a circle that only a deferred import keeps from failing at import time is
still a circle. ``from package import name`` depends on the submodule
``package.name`` when there is one, else on the package's ``__init__``.
Importing ``a.b.c`` also runs ``a`` and ``a.b``, but that is containment,
not use: it is no edge.

Rust (``crates/memsnav-core/src``, ``crates/memsnav-py/src``): ``foo.rs`` or
``foo/mod.rs`` is the module ``foo``. A module uses another when its code
(its unit tests included, which live in it) names an item of the other
through a ``use`` or a ``crate::``, ``super::`` or ``self::`` path. A path
is followed through the ``use`` declarations of the modules it passes
(``gnss/mod.rs``'s ``pub use ephemeris::GpsEphemeris`` makes
``super::GpsEphemeris`` a use of ``gnss::ephemeris``), so a re-export is
no dependency of its own. The edge is drawn between siblings: a use of
``filter::update`` from ``coupling::engine`` is an edge ``coupling ->
filter`` among the crate's top-level modules, one from ``filter::smoother``
the edge ``smoother -> update`` inside ``filter``. A module and the modules
inside it (``gnss`` and ``gnss::ephemeris``) are one another's container
and content, not neighbours: no edge, as no ``mod`` declaration is one.
"""

from __future__ import annotations

import ast
import re
from collections.abc import Iterator
from dataclasses import dataclass
from pathlib import Path

ROOT = Path(__file__).resolve().parent.parent
PACKAGE = ROOT / "python" / "memsnav"
CRATES = (ROOT / "crates" / "memsnav-core" / "src", ROOT / "crates" / "memsnav-py" / "src")

Module = tuple[str, ...]
Graph = dict[Module, dict[Module, list[str]]]
"""module -> module it uses -> where (``file:line``), the evidence."""


def circles(graph: Graph) -> list[list[Module]]:
    """The strongly connected components of more than one module (Tarjan),
    each sorted, sorted by their first module."""
    index: dict[Module, int] = {}
    low: dict[Module, int] = {}
    stack: list[Module] = []
    on_stack: set[Module] = set()
    found: list[list[Module]] = []

    def visit(v: Module) -> None:
        index[v] = low[v] = len(index)
        stack.append(v)
        on_stack.add(v)
        for w in graph.get(v, {}):
            if w not in index:
                visit(w)
                low[v] = min(low[v], low[w])
            elif w in on_stack:
                low[v] = min(low[v], index[w])
        if low[v] == index[v]:
            component = []
            while True:
                w = stack.pop()
                on_stack.discard(w)
                component.append(w)
                if w == v:
                    break
            if len(component) > 1:
                found.append(sorted(component))

    for v in sorted(graph):
        if v not in index:
            visit(v)
    return sorted(found)


def describe(graph: Graph, component: list[Module], separator: str) -> str:
    """A circle and the uses that close it, one line per edge inside it."""
    members = set(component)
    lines = [" <-> ".join(separator.join(m) or "(crate root)" for m in component)]
    for a in component:
        for b in sorted(set(graph.get(a, {})) & members):
            where = graph[a][b]
            more = f" (+{len(where) - 1} more)" if len(where) > 1 else ""
            lines.append(f"    {separator.join(a)} -> {separator.join(b)}: {where[0]}{more}")
    return "\n".join(lines)


def _where(path: Path, line: int) -> str:
    return f"{path.relative_to(ROOT) if path.is_relative_to(ROOT) else path.name}:{line}"


def _add(graph: Graph, a: Module, b: Module, where: str) -> None:
    graph.setdefault(a, {})
    graph.setdefault(b, {})
    if a != b:
        graph[a].setdefault(b, []).append(where)


# --- Python -----------------------------------------------------------------


def python_modules(package: Path) -> dict[Module, Path]:
    """Every module of the package by its dotted name (``__init__.py`` is
    the package itself), the native module (``_memsnav.abi3.so``, or its
    stub when it is not built) included: it imports none of ours."""
    modules: dict[Module, Path] = {}
    for path in sorted(package.rglob("*")):
        if path.suffix not in (".py", ".pyi", ".so", ".pyd"):
            continue
        parts = (*path.parent.relative_to(package.parent).parts, path.name.split(".")[0])
        if parts[-1] == "__init__":
            parts = parts[:-1]
        if path.suffix == ".py" or parts not in modules:
            modules[parts] = path
    return modules


def python_graph(package: Path) -> Graph:
    modules = python_modules(package)
    graph: Graph = {m: {} for m in modules}
    for module, path in modules.items():
        if path.suffix != ".py":
            continue
        is_package = path.name == "__init__.py"
        for node in ast.walk(ast.parse(path.read_text(encoding="utf-8"), str(path))):
            where = _where(path, getattr(node, "lineno", 0))
            if isinstance(node, ast.Import):
                for alias in node.names:
                    _add_python(graph, modules, module, tuple(alias.name.split(".")), where)
            elif isinstance(node, ast.ImportFrom):
                if node.level:
                    # Relative: from the module's package (a package's
                    # __init__ is its own package), up level - 1.
                    base = module if is_package else module[:-1]
                    base = base[: len(base) - (node.level - 1)]
                else:
                    base = ()
                target = base + tuple(node.module.split(".") if node.module else ())
                for alias in node.names:
                    sub = (*target, alias.name)
                    named = sub if sub in modules else target
                    _add_python(graph, modules, module, named, where)
    return graph


def _add_python(
    graph: Graph, modules: dict[Module, Path], module: Module, target: Module, where: str
) -> None:
    if target in modules:
        _add(graph, module, target, where)


def test_python_modules_import_no_circle():
    graph = python_graph(PACKAGE)
    assert len(graph) > 30, "the package's modules were not found"
    assert ("memsnav", "allan") in graph[("memsnav",)]
    found = circles(graph)
    assert not found, "import circles among the Python modules:\n" + "\n".join(
        describe(graph, c, ".") for c in found
    )


def test_python_analysis_sees_every_kind_of_import(tmp_path):
    package = tmp_path / "pkg"
    (package / "sub").mkdir(parents=True)
    (package / "__init__.py").write_text("from pkg import a\n")
    (package / "a.py").write_text("def f():\n    from .sub import b\n")
    (package / "sub" / "__init__.py").write_text("")
    (package / "sub" / "b.py").write_text(
        "from typing import TYPE_CHECKING\nif TYPE_CHECKING:\n    from ..c import C\n"
    )
    (package / "c.py").write_text("import pkg.a\nfrom pkg.sub.b import x\n")
    graph = python_graph(package)
    assert set(graph[("pkg", "a")]) == {("pkg", "sub", "b")}
    assert set(graph[("pkg", "sub", "b")]) == {("pkg", "c")}
    assert set(graph[("pkg", "c")]) == {("pkg", "a"), ("pkg", "sub", "b")}
    # The package's own import of a runs a; its submodules importing it
    # (here, none) would close a circle; containment alone does not.
    assert set(graph[("pkg",)]) == {("pkg", "a")}
    assert circles(graph) == [[("pkg", "a"), ("pkg", "c"), ("pkg", "sub", "b")]]


# --- Rust -------------------------------------------------------------------


_LITERAL_OR_COMMENT = re.compile(
    r"""
      //[^\n]*                                # line and doc comments
    | /\*.*?\*/                               # block comments (the code nests none)
    | (?<!\w)b?r(\#*)".*?"\1                  # raw strings, r#"..."#
    | b?"(?:\\.|[^"\\])*"                       # strings
    | '(?:\\(?:x[0-9a-fA-F]{2}|u\{[0-9a-fA-F]+\}|.)|[^\\'])'   # characters, not lifetimes
    """,
    re.S | re.X,
)


def strip_rust(source: str) -> str:
    """The code without comments, string and character literals (each
    replaced by a space, newlines kept so that line numbers hold): a path in
    a doc comment or a message is no use of a module."""
    return _LITERAL_OR_COMMENT.sub(lambda m: "\n" * m.group(0).count("\n") or " ", source)


def _use_paths(tree: str) -> Iterator[tuple[list[str], str]]:
    """The paths of a ``use`` tree (``a::{b, c::{d as e}, self}``) with the
    name each binds (``*`` for a glob)."""
    tree = re.sub(r"\s+", " ", tree).strip()
    brace = tree.find("{")
    if brace < 0:
        m = re.fullmatch(r"(.*?)(?: as ([A-Za-z_]\w*))?", tree)
        assert m is not None
        segments = [s.strip() for s in m.group(1).split("::") if s.strip()]
        if segments and segments[-1] == "self":
            segments = segments[:-1]
        if segments:
            yield segments, m.group(2) or segments[-1]
        return
    prefix = [s.strip() for s in tree[:brace].split("::") if s.strip()]
    inner = tree[brace + 1 : tree.rindex("}")]
    depth, start = 0, 0
    for k, ch in enumerate(inner + ","):
        if ch == "{":
            depth += 1
        elif ch == "}":
            depth -= 1
        elif ch == "," and depth == 0:
            if inner[start:k].strip():
                for segments, alias in _use_paths(inner[start:k]):
                    yield prefix + segments, alias
            start = k + 1


@dataclass
class RustModule:
    path: Path
    children: set[str]
    uses: dict[str, list[str]]
    """Name bound by a ``use`` of the module -> the path it stands for (as
    written, relative to the module); globs under ``*`` + a counter."""
    items: set[str]
    """Names the module defines itself."""
    references: list[tuple[Module, list[str], int]]
    """(inline module inside the file, path as written, line)."""


_ITEM = re.compile(
    r"\b(?:fn|struct|enum|trait|type|union|macro_rules!|static(?:\s+mut)?"
    r"|const(?!\s+(?:fn|unsafe|async|extern)\b))\s+([A-Za-z_]\w*)"
)
_USE = re.compile(r"\b(?:pub(?:\([^)]*\))?\s+)?use\s+([^;]+);")
_PATH = re.compile(r"(?<![\w$:])((?:crate|super|self)(?:\s*::\s*[A-Za-z_]\w*)+)")
_INLINE_MOD = re.compile(r"\bmod\s+([A-Za-z_]\w*)\s*\{")
_FILE_MOD = re.compile(r"\bmod\s+([A-Za-z_]\w*)\s*;")


def _inline(spans: list[tuple[int, int, str]], offset: int) -> Module:
    """The inline modules (``mod tests { ... }``) around ``offset``."""
    return tuple(name for a, b, name in spans if a <= offset < b)


def rust_modules(src: Path) -> dict[Module, RustModule]:
    """The crate's modules by path (``()`` the crate root), with the inline
    modules of each file (``mod tests { ... }``) folded into the file's: a
    file is one module of the layout."""
    modules: dict[Module, RustModule] = {}
    for path in sorted(src.rglob("*.rs")):
        parts = path.relative_to(src).with_suffix("").parts
        if parts[-1] == "mod" or parts == ("lib",) or parts == ("main",):
            parts = parts[:-1]
        code = strip_rust(path.read_text(encoding="utf-8"))
        module = RustModule(path, set(_FILE_MOD.findall(code)), {}, set(), [])
        # Inline modules: where each opens and closes, to resolve super::
        # from inside them.
        closing: dict[int, int] = {}
        opened: list[int] = []
        for brace in re.finditer(r"[{}]", code):
            if brace.group() == "{":
                opened.append(brace.start())
            elif opened:
                closing[opened.pop()] = brace.start()
        spans = [
            (m.start(), closing.get(m.end() - 1, len(code)), m.group(1))
            for m in _INLINE_MOD.finditer(code)
        ]

        glob = 0
        for m in _USE.finditer(code):
            line = code.count("\n", 0, m.start()) + 1
            for segments, alias in _use_paths(m.group(1)):
                if segments[0] in ("crate", "super", "self") or segments[0] in module.children:
                    module.references.append((_inline(spans, m.start()), segments, line))
                if not _inline(spans, m.start()):
                    key = alias
                    if alias == "*":
                        glob += 1
                        key = f"*{glob}"
                    module.uses[key] = segments[:-1] if alias == "*" else segments
        code_without_uses = _USE.sub(lambda m: "\n" * m.group(0).count("\n"), code)
        for m in _PATH.finditer(code_without_uses):
            segments = re.sub(r"\s+", "", m.group(1)).split("::")
            line = code_without_uses.count("\n", 0, m.start()) + 1
            module.references.append((_inline(spans, m.start()), segments, line))
        module.items = set(_ITEM.findall(code)) - module.children
        modules[parts] = module
    return modules


def _resolve(
    modules: dict[Module, RustModule],
    start: Module,
    segments: list[str],
    seen: frozenset[tuple[Module, str]] = frozenset(),
) -> Module | None:
    """The module that defines what ``segments`` names, seen from the module
    ``start`` (a path into the crate, file modules then inline ones), or None
    when it leaves the crate."""
    where = list(start)
    rest = list(segments)
    if rest[0] == "crate":
        where, rest = [], rest[1:]
    while rest and rest[0] in ("super", "self"):
        if rest.pop(0) == "super":
            if not where:
                return None
            where.pop()
    # Inline modules inside a file are part of the file's module.
    while tuple(where) not in modules:
        if not where:
            return None
        where.pop()
    at: Module = tuple(where)
    while rest:
        name = rest[0]
        module = modules[at]
        if (*at, name) in modules:
            at, rest = (*at, name), rest[1:]
            continue
        if name in module.items:
            return at
        if name in module.uses and (at, name) not in seen:
            target = module.uses[name]
            if target[0] not in ("crate", "super", "self") and target[0] not in module.children:
                return None  # another crate (nalgebra, memsnav_core, std)
            return _resolve(modules, at, target + rest[1:], seen | {(at, name)})
        for key, target in module.uses.items():
            if (
                key.startswith("*")
                and (at, key) not in seen
                and (target[0] in ("crate", "super", "self") or target[0] in module.children)
            ):
                found = _resolve(modules, at, [*target, *rest], seen | {(at, key)})
                if found is not None and found != at:
                    inner = modules[found]
                    if name in inner.items or name in inner.uses:
                        return found
        return at
    return at


def rust_graph(src: Path) -> Graph:
    modules = rust_modules(src)
    graph: Graph = {m: {} for m in modules if m}
    for at, module in modules.items():
        for inline, segments, line in module.references:
            target = _resolve(modules, (*at, *inline), segments)
            if target is None:
                continue
            k = 0
            while k < min(len(at), len(target)) and at[k] == target[k]:
                k += 1
            if k == len(at) or k == len(target):
                continue  # container and content
            where = f"{_where(module.path, line)} ({'::'.join(segments)})"
            _add(graph, at[: k + 1], target[: k + 1], where)
    return graph


def rust_circles() -> list[str]:
    found = []
    for src in CRATES:
        graph = rust_graph(src)
        crate = src.parent.name
        found += [f"{crate}: {describe(graph, c, '::')}" for c in circles(graph)]
    return found


def test_rust_modules_use_no_circle():
    for src in CRATES:
        assert len(rust_modules(src)) > 10, f"the modules of {src} were not found"
    found = rust_circles()
    assert not found, "circles among the Rust modules:\n" + "\n".join(found)


def test_rust_analysis_follows_paths_and_reexports(tmp_path):
    src = tmp_path / "src"
    (src / "gnss").mkdir(parents=True)
    (src / "lib.rs").write_text("pub mod gnss;\npub mod filter;\npub use gnss::Epoch;\n")
    (src / "gnss" / "mod.rs").write_text(
        "mod a;\nmod b;\npub use a::A;\npub use b::*;\n/// [`crate::filter::F`]\n"
        "pub struct Epoch;\n"
    )
    (src / "gnss" / "a.rs").write_text(
        'use super::{B, Epoch};\nconst S: &str = "crate::filter::F";\npub struct A;\n'
        "#[cfg(test)]\nmod tests {\n    use super::*;\n}\n"
    )
    (src / "gnss" / "b.rs").write_text("pub struct B(super::super::filter::F);\n")
    (src / "filter.rs").write_text(
        "pub struct F;\nfn f() -> crate::Epoch { todo!() }\n"
        "#[cfg(test)]\nmod tests {\n    fn g(_: super::super::gnss::A) {}\n}\n"
    )
    graph = rust_graph(src)
    # a uses b through the parent's glob re-export and the parent's own
    # Epoch (container: no edge); b uses filter (lifted to gnss -> filter);
    # filter uses gnss through the crate root's re-export and in its tests.
    assert set(graph[("gnss", "a")]) == {("gnss", "b")}
    assert set(graph[("gnss", "b")]) == set()
    assert set(graph[("gnss",)]) == {("filter",)}
    assert set(graph[("filter",)]) == {("gnss",)}
    assert circles(graph) == [[("filter",), ("gnss",)]]
