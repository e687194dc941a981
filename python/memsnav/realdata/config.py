"""The ``navigate`` run configuration (TOML, read with :mod:`tomllib`).

A configuration has two kinds of keys. The ones that say where the data
are and how to read them (files, column layouts, units, the GNSS input)
are listed in :data:`SCHEMA` with their defaults. The ones that tune the
navigation engine (mounting, lever arms, filter, alignment, standstill
detection, aids, outages) belong to the core engine: their names, units
and defaults live there (``memsnav.navigate_settings()`` lists them) and a
key left out keeps the engine's default. Either way, an unknown table or
key (a typo) is an error naming the file and the key, and so is a value of
the wrong kind; the engine's keys are checked when the file is loaded.

Relative data paths resolve against the data root: ``--data-root``, else
``$MEMSNAV_DATA_ROOT``, else ``../shared/data`` relative to the repository
that holds the configuration (the parent of its ``examples/`` folder, or the
nearest ``shared/data`` above it; for a configuration elsewhere, the same
from its own folder).
"""

from __future__ import annotations

import os
import tomllib
from dataclasses import dataclass, field
from pathlib import Path
from typing import Any

import memsnav._memsnav as _mn

#: Environment variable naming the data root.
DATA_ROOT_ENV = "MEMSNAV_DATA_ROOT"

# The reading keys: (type or tuple of types, default; REQUIRED when it must be
# given; None: not given, the reader's own default applies).
REQUIRED = object()
_NUM = (int, float)
# The observables' defaults are the core's (``memsnav.defaults()``).
_OBSERVABLES: dict[str, float] = _mn.defaults()["RinexObservations.gps_l1"]
SCHEMA: dict[str, dict[str, tuple[Any, Any]]] = {
    "": {"name": (str, REQUIRED), "output": (str, "out")},
    "imu": {
        "file": (str, REQUIRED),
        "columns": (list, ["ax", "ay", "az", "gx", "gy", "gz", "t"]),
        "accel_unit": (str, REQUIRED),
        "gyro_unit": (str, REQUIRED),
        "time_unit": (str, REQUIRED),
        "time_reference": (str, "tag"),
        "time_tag": (str, ""),
        "skip_first_line": (bool, False),
        "header_lines": (int, 0),
        "calibration": (str, ""),
    },
    "gnss": {
        "mode": (str, REQUIRED),
        "pos": (str, ""),
        "quality": (list, [1, 2]),
        "rate_hz": (_NUM, None),
        "position_noise_m": (list, None),
        "velocity_noise_m_s": (_NUM, None),
        "use_velocity": (bool, None),
        "seed": (int, 0),
        "obs": (str, ""),
        "nav": (str, ""),
        "satellites": (list, []),
        "elevation_mask_deg": (_NUM, _OBSERVABLES["elevation_mask_deg"]),
        "min_cn0_db_hz": (_NUM, _OBSERVABLES["min_cn0_db_hz"]),
        "pseudorange_std_m": (_NUM, _OBSERVABLES["pseudorange_std"]),
        "pseudorange_rate_std_m_s": (_NUM, _OBSERVABLES["pseudorange_rate_std"]),
        "ionosphere": (bool, True),
        "troposphere": (bool, True),
        "klobuchar_alpha": (list, []),
        "klobuchar_beta": (list, []),
    },
    "truth": {"pos": (str, ""), "quality": (list, [1, 2])},
    "report": {"html": (bool, True)},
}
CHOICES = {
    ("imu", "time_reference"): ("tag", "column_gps", "column_unix_gpst"),
    ("gnss", "mode"): ("loose", "tight"),
}
#: The engine's tables and keys, from the core.
ENGINE: dict[str, dict[str, str]] = _mn.navigate_settings()


@dataclass
class RunConfig:
    """A checked configuration: ``section[key]`` values of the reading keys
    with defaults filled in, the engine's keys as given (``engine``), data
    paths resolved, and where it came from."""

    path: Path
    data_root: Path
    values: dict[str, dict[str, Any]] = field(default_factory=dict)
    engine: dict[str, dict[str, Any]] = field(default_factory=dict)

    def __getitem__(self, section: str) -> dict[str, Any]:
        return self.values[section]

    def data_path(self, section: str, key: str) -> Path | None:
        """The file named by ``section.key``, resolved against the data root
        (None when not given)."""
        v = self.values[section][key]
        if not v:
            return None
        p = Path(v).expanduser()
        return p if p.is_absolute() else self.data_root / p


def resolve_data_root(near: str | Path | None = None, explicit: str | Path | None = None) -> Path:
    """Where relative data paths resolve: ``explicit`` (``--data-root``),
    else ``$MEMSNAV_DATA_ROOT``, else the ``shared/data`` folder beside the
    repository holding ``near`` (a configuration file or a folder; the
    current directory when omitted): the nearest ``shared/data`` above it,
    so a git worktree nested deeper finds it too. A configuration inside an
    ``examples/`` folder counts from the repository, not from the folder."""
    chosen = explicit or os.environ.get(DATA_ROOT_ENV)
    if chosen:
        return Path(chosen).expanduser().resolve()
    start = Path.cwd() if near is None else Path(near).resolve()
    folder = start if start.is_dir() else start.parent
    repo = folder.parent if folder.name == "examples" else folder
    for parent in (repo, *repo.parents):
        candidate = parent / "shared" / "data"
        if candidate.is_dir():
            return candidate
    return (repo / ".." / "shared" / "data").resolve()


def _check(file: Path, where: str, key: str, value: Any, kind: Any) -> Any:
    name = f"{where}.{key}" if where else key
    if (kind is _NUM and isinstance(value, bool)) or not isinstance(value, kind):
        expected = "a number" if kind is _NUM else kind.__name__
        raise ValueError(f"{file}: {name} must be {expected}, got {value!r}")
    return float(value) if kind is _NUM else value


def load_config(path: str | Path, data_root: str | Path | None = None) -> RunConfig:
    """Reads and checks a run configuration (see the module docstring)."""
    path = Path(path)
    try:
        raw = tomllib.loads(path.read_text())
    except tomllib.TOMLDecodeError as e:
        raise ValueError(f"{path}: not valid TOML: {e}") from None
    except OSError as e:
        raise ValueError(f"config: cannot read {path}: {e.strerror}") from None
    except UnicodeDecodeError as e:
        raise ValueError(f"{path}: not UTF-8 text (byte {e.start}); TOML must be UTF-8") from None
    cfg = RunConfig(path=path, data_root=resolve_data_root(path, data_root))
    top = {k: v for k, v in raw.items() if not isinstance(v, dict)}
    tables = {k: v for k, v in raw.items() if isinstance(v, dict)}
    known_tables = sorted({k for k in SCHEMA if k} | set(ENGINE))
    for name in tables:
        if name not in known_tables:
            raise ValueError(f"{path}: unknown table [{name}]; expected one of {known_tables}")
    for section in ["", *known_tables]:
        schema = SCHEMA.get(section, {})
        engine_keys = ENGINE.get(section, {})
        given = top if section == "" else tables.get(section, {})
        unknown = sorted(set(given) - set(schema) - set(engine_keys))
        if unknown:
            where = f"[{section}]" if section else "the top level"
            expected = sorted(set(schema) | set(engine_keys))
            raise ValueError(
                f"{path}: unknown key(s) {unknown} in {where}; expected some of {expected}"
            )
        out: dict[str, Any] = {}
        for key, (kind, default) in schema.items():
            if key in given:
                out[key] = _check(path, section, key, given[key], kind)
            elif default is REQUIRED:
                raise ValueError(
                    f"{path}: missing required key {section + '.' if section else ''}{key}"
                )
            else:
                out[key] = default
            choices = CHOICES.get((section, key))
            if choices and out[key] not in choices:
                raise ValueError(
                    f"{path}: {section}.{key} must be one of {list(choices)}, got {out[key]!r}"
                )
        cfg.values[section] = out
        engine = {k: v for k, v in given.items() if k in engine_keys}
        if engine:
            cfg.engine[section] = engine
    try:
        _mn.check_navigate_settings(cfg.engine)
    except ValueError as e:
        raise ValueError(f"{path}: {e}") from None
    return cfg
