"""The one reader of memsnav's TOML configurations (``navigate``,
``calibrate``, ``study``): the file read as TOML, every table and key
known, every value of its kind and in its range. Each error names the file
and the key (``table.key``; a top-level key bare), so a typo or a value out
of range never reaches the code that uses it.

A schema maps each table (``""``: the top level) to its keys, each key to
``(check, default)``: ``check`` is one of the kinds below, ``default`` the
value when the key is left out, :data:`REQUIRED` when it must be given, or
:data:`ABSENT` to leave it out of the values.
"""

from __future__ import annotations

import math
import tomllib
import warnings
from collections.abc import Callable, Collection, Mapping
from pathlib import Path
from typing import Any

from memsnav._memsnav import closest_name as _closest_name

#: Environment variable naming the data root.
DATA_ROOT_ENV = "MEMSNAV_DATA_ROOT"


def resolve_path(value: str, base: Path) -> Path:
    """A path written in a configuration: ``~`` expanded, absolute as given,
    else relative to ``base`` (the data root for the recordings a
    configuration reads when they are not beside it, :func:`data_path`; the
    configuration's own folder for everything else: docs/tutorials/first-session.md,
    "Paths in a configuration")."""
    p = Path(value).expanduser()
    return p if p.is_absolute() else base / p


def data_path_candidates(value: str, folder: Path, data_root: Path) -> list[Path]:
    """Where a recording named in a configuration may be, in the order they
    are tried: an absolute path as given; a relative one beside the
    configuration (in its ``folder``), then under the data root."""
    if Path(value).expanduser().is_absolute():
        return [Path(value).expanduser()]
    return [resolve_path(value, folder), resolve_path(value, data_root)]


def data_path(value: str, folder: Path, data_root: Path) -> Path:
    """A recording named in a configuration in ``folder``: the first of
    :func:`data_path_candidates` that is a file, else the last one (the one
    under the data root, which :func:`missing_data_file` reports with the
    others)."""
    candidates = data_path_candidates(value, folder, data_root)
    return next((p for p in candidates if p.is_file()), candidates[-1])


def missing_data_file(key: str, value: str, folder: Path, data_root: Path) -> str | None:
    """None when the recording ``key`` = ``value`` exists; else an error
    message naming the key and every place tried."""
    candidates = data_path_candidates(value, folder, data_root)
    if any(p.is_file() for p in candidates):
        return None
    if len(candidates) == 1:
        return f"{key}: no such file {candidates[0]}"
    beside, under_root = candidates
    return (
        f"{key}: no such file {value!r}: tried {beside} (beside the configuration) and "
        f"{under_root} (under the data root, set by --data-root or ${DATA_ROOT_ENV})"
    )


REQUIRED = object()
"""The default of a key that must be given."""
ABSENT = object()
"""The default of a key that is left out of the values when not given."""


class _Wrong(Exception):
    """A value that is not what its key holds: what it must be."""


class Check:
    """A kind of value: called with a value, returns it as the code uses it
    (a TOML integer given for a number as a float) or raises
    :class:`_Wrong`; :attr:`schema` is the JSON schema of the values it
    takes (what an editor completes and checks as the file is typed)."""

    def __init__(self, check: Callable[[Any], Any], schema: dict[str, Any]) -> None:
        self._check = check
        self.schema = schema

    def __call__(self, value: Any) -> Any:
        return self._check(value)


Schema = Mapping[str, Mapping[str, tuple[Check, Any]]]


def _is_number(value: Any) -> bool:
    # TOML booleans are not numbers.
    return isinstance(value, int | float) and not isinstance(value, bool)


def text(*choices: str) -> Check:
    """A string; one of ``choices`` when given."""

    def check(value: Any) -> str:
        if not isinstance(value, str):
            raise _Wrong(f"must be a string, got {value!r}")
        if choices and value not in choices:
            raise _Wrong(f"must be one of {list(choices)}, got {value!r}")
        return value

    return Check(check, {"type": "string", **({"enum": list(choices)} if choices else {})})


def pathname() -> Check:
    """A file or folder name ("" where the key is optional: none)."""

    def check(value: Any) -> str:
        if not isinstance(value, str):
            raise _Wrong(f"must be a path (a string), got {value!r}")
        if "\0" in value:
            raise _Wrong(f"must be a path, got {value!r}: it contains a NUL character")
        return value

    return Check(check, {"type": "string"})


def file_name() -> Check:
    """A plain file name: no folder part, not "", "." or ".."."""

    def check(value: Any) -> str:
        if not (
            isinstance(value, str)
            and "\0" not in value
            and value not in ("", ".", "..")
            and value == Path(value).name
        ):
            raise _Wrong(f"must be a plain file name, got {value!r}")
        return value

    return Check(check, {"type": "string", "minLength": 1, "pattern": r"^[^/\\\\]+$"})


def flag() -> Check:
    """true or false."""

    def check(value: Any) -> bool:
        if not isinstance(value, bool):
            raise _Wrong(f"must be true or false, got {value!r}")
        return value

    return Check(check, {"type": "boolean"})


def _range(minimum: float | None, maximum: float | None, above: float | None) -> str:
    if minimum is not None and maximum is not None:
        return f" in [{minimum:g}, {maximum:g}]"
    if above is not None:
        return f" > {above:g}"
    if minimum is not None:
        return f" >= {minimum:g}"
    return ""


def _bounds(
    schema: dict[str, Any], minimum: float | None, maximum: float | None, above: float | None
) -> dict[str, Any]:
    """``schema`` with the JSON schema's bounds of a number."""
    bounds = {"minimum": minimum, "maximum": maximum, "exclusiveMinimum": above}
    return {**schema, **{k: v for k, v in bounds.items() if v is not None}}


def integer(minimum: int | None = None, maximum: int | None = None) -> Check:
    """A TOML integer in [``minimum``, ``maximum``]."""

    def check(value: Any) -> int:
        if not (isinstance(value, int) and not isinstance(value, bool)) or not (
            (minimum is None or value >= minimum) and (maximum is None or value <= maximum)
        ):
            raise _Wrong(f"must be an integer{_range(minimum, maximum, None)}, got {value!r}")
        return value

    return Check(check, _bounds({"type": "integer"}, minimum, maximum, None))


def number(
    minimum: float | None = None, maximum: float | None = None, *, above: float | None = None
) -> Check:
    """A finite number (a TOML integer or float, as a float) in
    [``minimum``, ``maximum``], and greater than ``above``."""

    def check(value: Any) -> float:
        if not (
            _is_number(value)
            and math.isfinite(value)
            and (minimum is None or value >= minimum)
            and (maximum is None or value <= maximum)
            and (above is None or value > above)
        ):
            expected = _range(minimum, maximum, above)
            raise _Wrong(f"must be a finite number{expected}, got {value!r}")
        return float(value)

    return Check(check, _bounds({"type": "number"}, minimum, maximum, above))


def satellite() -> Check:
    """A satellite by its RINEX name (``"G10"``, ``"E24"``, ``"C11"``,
    ``"R05"``). A bare number is ambiguous once several systems are read; a
    GPS PRN (1-63) is still read as ``"Gnn"``, with a DeprecationWarning
    that names the fix, and will be refused in a later release."""

    def check(value: Any) -> str:
        if isinstance(value, int) and not isinstance(value, bool) and 1 <= value <= 63:
            name = f"G{value:02d}"
            warnings.warn(
                f"satellites: the bare number {value} is read as {name!r} (GPS); name the "
                f'system ("G10", "E24", "C11", "R05"): bare numbers are ambiguous once '
                "several systems are read and will be refused",
                DeprecationWarning,
                stacklevel=2,
            )
            return name
        if (
            isinstance(value, str)
            and len(value) == 3
            and value[0] in "GECR"
            and value[1:].isdigit()
            and 1 <= int(value[1:]) <= 63
        ):
            return value
        raise _Wrong(f'must be a satellite name like "G10", "E24", "C11", "R05", got {value!r}')

    return Check(check, {"type": "string", "pattern": "^[GECR](0[1-9]|[1-5][0-9]|6[0-3])$"})


def list_of(item: Check, *, lengths: Collection[int] = (), min_length: int = 0) -> Check:
    """A list whose entries each pass ``item``, of one of ``lengths`` entries
    (any when empty) and at least ``min_length``."""

    def check(value: Any) -> list[Any]:
        if not isinstance(value, list):
            raise _Wrong(f"must be a list, got {value!r}")
        if (lengths and len(value) not in lengths) or len(value) < min_length:
            count = " or ".join(str(n) for n in sorted(lengths)) if lengths else f"{min_length}+"
            raise _Wrong(f"must be a list of {count} entries, got {len(value)}: {value!r}")
        checked = []
        for i, entry in enumerate(value):
            try:
                checked.append(item(entry))
            except _Wrong as e:
                raise _Wrong(f"entry {i}: {e}") from None
        return checked

    return Check(
        check,
        {
            "type": "array",
            "items": item.schema,
            **({"minItems": min(lengths), "maxItems": max(lengths)} if lengths else {}),
            **({"minItems": min_length} if min_length and not lengths else {}),
        },
    )


def imu_columns() -> Check:
    """Where each IMU quantity is: a list naming every column in order, or a
    table from each of ``ax ay az gx gy gz t`` to a header name or a 1-based
    column number (the reader checks the names and numbers)."""

    def check(value: Any) -> list[str] | dict[str, str | int]:
        if isinstance(value, list):
            names: list[str] = list_of(text(), min_length=1)(value)
            return names
        if isinstance(value, dict):
            for k, v in value.items():
                if not (isinstance(v, str) or (isinstance(v, int) and not isinstance(v, bool))):
                    raise _Wrong(
                        f"{k}: must be a header name (a string) or a 1-based column number, "
                        f"got {v!r}"
                    )
            return dict(value)
        raise _Wrong(f"must be a list of column names or a table of columns, got {value!r}")

    return Check(
        check,
        {
            "anyOf": [
                {"type": "array", "items": {"type": "string"}, "minItems": 1},
                {"type": "object", "additionalProperties": {"type": ["string", "integer"]}},
            ]
        },
    )


def header_names() -> Check:
    """A table from names to a file's header names (strings); the reader
    checks the names."""

    def check(value: Any) -> dict[str, str]:
        if not isinstance(value, dict):
            raise _Wrong(f"must be a table of header names, got {value!r}")
        for k, v in value.items():
            if not isinstance(v, str):
                raise _Wrong(f"{k}: must be a header name (a string), got {v!r}")
        return dict(value)

    return Check(check, {"type": "object", "additionalProperties": {"type": "string"}})


def axes() -> Check:
    """An axis convention by name (the reader knows them) or a 3×3 rotation
    given as three rows of three numbers."""
    rows = list_of(list_of(number(), lengths=(3,)), lengths=(3,))

    def check(value: Any) -> str | list[list[float]]:
        checked: str | list[list[float]] = text()(value) if isinstance(value, str) else rows(value)
        return checked

    return Check(check, {"anyOf": [{"type": "string"}, rows.schema]})


def list_or_choice(listed: Check, *choices: str) -> Check:
    """A list ``listed`` passes, or one of the words ``choices``."""

    def check(value: Any) -> Any:
        if isinstance(value, str):
            if value not in choices:
                raise _Wrong(f"must be a list or one of {list(choices)}, got {value!r}")
            return value
        return listed(value)

    return Check(check, {"anyOf": [listed.schema, {"enum": list(choices)}]})


def scalar_or_list(scalar: Check, listed: Check) -> Check:
    """A value ``scalar`` passes, or a list ``listed`` passes."""

    def check(value: Any) -> Any:
        return listed(value) if isinstance(value, list) else scalar(value)

    return Check(check, {"anyOf": [scalar.schema, listed.schema]})


def key_name(table: str, key: str) -> str:
    """``table.key`` (a top-level key bare), as every message names it."""
    return f"{table}.{key}" if table else key


def checked(file: Path, table: str, key: str, value: Any, check: Check) -> Any:
    """``value`` of ``table.key`` through ``check``; a ``ValueError`` naming
    the file and the key when it does not pass."""
    try:
        return check(value)
    except _Wrong as e:
        raise ValueError(f"{file}: {key_name(table, key)}: {e}") from None


def load_toml(file: Path) -> dict[str, Any]:
    """The file's TOML; an error names the file."""
    try:
        return tomllib.loads(file.read_text(encoding="utf-8"))
    except tomllib.TOMLDecodeError as e:
        raise ValueError(f"{file}: not valid TOML: {e}") from None
    except OSError as e:
        raise ValueError(f"config: cannot read {file}: {e.strerror}") from None
    except UnicodeDecodeError as e:
        raise ValueError(f"{file}: not UTF-8 text (byte {e.start}); TOML must be UTF-8") from None


def split_tables(file: Path, raw: dict[str, Any], known: Collection[str]) -> dict[str, Any]:
    """The top-level keys (table ``""``) and each table of ``raw``; an
    unknown table is an error naming it."""
    tables: dict[str, Any] = {"": {k: v for k, v in raw.items() if not isinstance(v, dict)}}
    for name, value in raw.items():
        if isinstance(value, dict):
            if name not in known:
                raise ValueError(f"{file}: unknown table [{name}]; expected one of {sorted(known)}")
            tables[name] = value
    return tables


def read_table(
    file: Path,
    table: str,
    given: Mapping[str, Any],
    keys: Mapping[str, tuple[Check, Any]],
    *,
    others: Collection[str] = (),
) -> dict[str, Any]:
    """The values of one table: each key of ``keys`` checked, defaults filled
    in. ``others``: keys read elsewhere (passed over here); any other key is
    an error naming it."""
    unknown = sorted(set(given) - set(keys) - set(others))
    if unknown:
        where = f"[{table}]" if table else "the top level"
        expected = sorted(set(keys) | set(others))
        meant = {k: _closest_name(k, expected) for k in unknown}
        hint = "; ".join(f"{k!r}: did you mean {m!r}?" for k, m in meant.items() if m)
        raise ValueError(
            f"{file}: unknown key(s) {unknown} in {where}"
            + (f" ({hint})" if hint else "")
            + f"; expected some of {expected}"
        )
    values: dict[str, Any] = {}
    for key, (check, default) in keys.items():
        if key in given:
            values[key] = checked(file, table, key, given[key], check)
        elif default is REQUIRED:
            raise ValueError(f"{file}: missing required key {key_name(table, key)}")
        elif default is not ABSENT:
            values[key] = default
    return values
