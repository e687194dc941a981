"""The ``calibrate`` configuration (TOML, read with :mod:`tomllib`).

Checked like the ``navigate`` configuration (:mod:`memsnav.realdata.config`):
every table and key is known, an unknown one (a typo) is an error naming the
file and the key, a wrong type or value names the key and what was expected,
and relative data paths resolve against the data root (``--data-root``,
else ``$MEMSNAV_DATA_ROOT``, else ``../shared/data`` next to the
repository). The detector's defaults are the core's.

``[session] kind`` says what kind of calibration session the data are:
``"static-poses"`` (a multi-position session of raw readings: tables
``[imu]`` and ``[static]``) or ``"drive"`` (the paper's GNSS-reference
calibration on a drive: table ``[drive]``, which names the drive's
``navigate`` configuration); docs/calibration.md. A table of the other
kind is an error.
"""

from __future__ import annotations

import tomllib
from dataclasses import dataclass, field
from pathlib import Path
from typing import Any

from memsnav import _memsnav
from memsnav.calibration.drive import DEFAULT_WINDOW_S
from memsnav.calibration.file import SESSIONS
from memsnav.realdata.config import resolve_data_root

_DEFAULTS = _memsnav.static_calibration_defaults()
REQUIRED = object()
_NUM = (int, float)
_NUM_OR_LIST = (int, float, list)

# Each key: (type or tuple of types, default; REQUIRED when it must be given).
SCHEMA: dict[str, dict[str, tuple[Any, Any]]] = {
    "": {"name": (str, REQUIRED), "output": (str, "out")},
    "session": {"kind": (str, REQUIRED)},
    "imu": {
        "accel_file": (str, REQUIRED),
        "gyro_file": (str, REQUIRED),
        "time_unit": (str, "s"),
        "accel_scale": (_NUM_OR_LIST, _DEFAULTS["scale"]),
        "accel_offset": (_NUM_OR_LIST, _DEFAULTS["offset"]),
        "gyro_scale": (_NUM_OR_LIST, _DEFAULTS["scale"]),
        "gyro_offset": (_NUM_OR_LIST, _DEFAULTS["offset"]),
    },
    "static": {
        "gravity_m_s2": (_NUM, REQUIRED),
        "window_s": (_NUM, _DEFAULTS["window"]),
        "threshold_factor": (_NUM, _DEFAULTS["threshold_factor"]),
        "initial_rest_s": (_NUM, _DEFAULTS["initial_rest"]),
        "min_pose_s": (_NUM, _DEFAULTS["min_pose"]),
        "estimate": (str, "determinable"),
        "holdout_every": (int, 0),
    },
    "drive": {
        "navigate": (str, REQUIRED),
        "window_s": (_NUM, DEFAULT_WINDOW_S),
        "until_s": (_NUM, 0.0),
        "estimate": (str, "determinable"),
        "scale_factor_states": (bool, True),
        "compare": (bool, True),
        "draws": (int, 10),
        "seed": (int, 0),
    },
    "report": {"html": (bool, True)},
}
#: The tables each session kind reads (the others must be absent).
KIND_TABLES = {"static-poses": ("imu", "static"), "drive": ("drive",)}
CHOICES = {
    ("session", "kind"): SESSIONS,
    ("imu", "time_unit"): ("s", "ms"),
    ("static", "estimate"): ("determinable", "all"),
    ("drive", "estimate"): ("determinable", "all"),
}


@dataclass
class CalibrationConfig:
    """A checked configuration: ``section[key]`` values with defaults filled
    in, and where it came from."""

    path: Path
    data_root: Path
    values: dict[str, dict[str, Any]] = field(default_factory=dict)

    def __getitem__(self, section: str) -> dict[str, Any]:
        return self.values[section]

    def data_path(self, section: str, key: str) -> Path:
        """The file named by ``section.key``, resolved against the data root."""
        p = Path(self.values[section][key]).expanduser()
        return p if p.is_absolute() else self.data_root / p

    def config_path(self, section: str, key: str) -> Path:
        """The configuration file named by ``section.key``, resolved against
        this configuration's folder."""
        p = Path(self.values[section][key]).expanduser()
        return p if p.is_absolute() else self.path.parent / p


def _check(file: Path, name: str, value: Any, kind: Any) -> Any:
    if isinstance(value, bool) and kind is not bool:
        ok = False
    else:
        ok = isinstance(value, kind)
    if ok and isinstance(value, list):
        ok = len(value) == 3 and all(
            isinstance(v, int | float) and not isinstance(v, bool) for v in value
        )
    if not ok:
        expected = {
            _NUM: "a number",
            _NUM_OR_LIST: "a number or a list of 3 numbers",
        }.get(kind, getattr(kind, "__name__", str(kind)))
        raise ValueError(f"{file}: {name} must be {expected}, got {value!r}")
    if kind is _NUM:
        return float(value)
    if kind is _NUM_OR_LIST:
        return [float(v) for v in value] if isinstance(value, list) else float(value)
    return value


def load_calibration_config(
    path: str | Path, data_root: str | Path | None = None
) -> CalibrationConfig:
    """Reads and checks a ``calibrate`` configuration (module docstring)."""
    path = Path(path)
    try:
        raw = tomllib.loads(path.read_text())
    except tomllib.TOMLDecodeError as e:
        raise ValueError(f"{path}: not valid TOML: {e}") from None
    except OSError as e:
        raise ValueError(f"config: cannot read {path}: {e.strerror}") from None
    cfg = CalibrationConfig(path=path, data_root=resolve_data_root(path, data_root))
    tables = {k: v for k, v in raw.items() if isinstance(v, dict)}
    top = {k: v for k, v in raw.items() if not isinstance(v, dict)}
    for name in tables:
        if name not in SCHEMA or name == "":
            raise ValueError(
                f"{path}: unknown table [{name}]; expected one of {sorted(k for k in SCHEMA if k)}"
            )
    session = tables.get("session", {}).get("kind")
    for other, names in KIND_TABLES.items():
        for name in names:
            if name in tables and session in KIND_TABLES and session != other:
                raise ValueError(
                    f"{path}: table [{name}] is for session kind {other!r}, "
                    f"not {session!r}; remove it"
                )
    for section, schema in SCHEMA.items():
        if (
            session in KIND_TABLES
            and section not in KIND_TABLES[session]
            and any(section in names for names in KIND_TABLES.values())
        ):
            continue
        given = top if section == "" else tables.get(section, {})
        unknown = sorted(set(given) - set(schema))
        if unknown:
            where = f"[{section}]" if section else "the top level"
            raise ValueError(
                f"{path}: unknown key(s) {unknown} in {where}; expected some of {sorted(schema)}"
            )
        out: dict[str, Any] = {}
        for key, (kind, default) in schema.items():
            name = f"{section}.{key}" if section else key
            if key in given:
                out[key] = _check(path, name, given[key], kind)
            elif default is REQUIRED:
                raise ValueError(f"{path}: missing required key {name}")
            else:
                out[key] = default
            choices = CHOICES.get((section, key))
            if choices and out[key] not in choices:
                raise ValueError(f"{path}: {name} must be one of {list(choices)}, got {out[key]!r}")
        cfg.values[section] = out
    if session == "drive":
        drive = cfg["drive"]
        if drive["draws"] < 0:
            raise ValueError(f"{path}: drive.draws must be 0 or more, got {drive['draws']}")
        if drive["window_s"] <= 0 or drive["until_s"] < 0:
            raise ValueError(
                f"{path}: drive.window_s must be positive and drive.until_s at least 0 "
                f"(0: the whole drive), got {drive['window_s']} and {drive['until_s']}"
            )
        return cfg
    if cfg["static"]["holdout_every"] == 1 or cfg["static"]["holdout_every"] < 0:
        raise ValueError(
            f"{path}: static.holdout_every must be 0 (none) or at least 2, "
            f"got {cfg['static']['holdout_every']}"
        )
    return cfg
