"""The ``calibrate`` configuration (TOML, read with :mod:`tomllib`).

Checked like the ``navigate`` configuration (:mod:`memsnav.realdata.config`):
every table and key is known, an unknown one (a typo) is an error naming the
file and the key, a wrong type or value names the key and what was expected,
and a relative path of a recording read resolves as in ``navigate``: beside
the configuration when the file is there, else under the data root
(``--data-root``, else ``$MEMSNAV_DATA_ROOT``, else ``../shared/data`` next
to the repository), an error naming both when neither holds it; every
other one (``output``, ``[drive] navigate``) against the configuration's
folder. The detector's defaults are the core's.

``[session] kind`` says what kind of calibration session the data are:
``"static-poses"`` (a multi-position session of raw readings: tables
``[imu]`` and ``[static]``) or ``"drive"`` (the paper's GNSS-reference
calibration on a drive: table ``[drive]``, which names the drive's
``navigate`` configuration); docs/how-to/calibrate-an-imu.md. A table of the other
kind is an error.
"""

from __future__ import annotations

from dataclasses import dataclass, field
from pathlib import Path
from typing import Any

from memsnav import _memsnav
from memsnav._config import (
    ABSENT,
    REQUIRED,
    Check,
    data_path,
    flag,
    integer,
    list_of,
    load_toml,
    missing_data_file,
    number,
    pathname,
    read_table,
    resolve_path,
    scalar_or_list,
    split_tables,
    text,
)
from memsnav.calibration.drive import DEFAULT_WINDOW_S
from memsnav.calibration.file import SESSIONS
from memsnav.realdata.config import resolve_data_root

_DEFAULTS = _memsnav.static_calibration_defaults()
# A nominal scale or offset: one for the three axes, or one per axis.
_PER_AXIS = scalar_or_list(number(), list_of(number(), lengths=(3,)))
_ESTIMATE = text("determinable", "all")

#: Each key: (kind, default; REQUIRED when it must be given). See
#: :mod:`memsnav._config`.
SCHEMA: dict[str, dict[str, tuple[Check, Any]]] = {
    "": {"name": (text(), REQUIRED), "output": (pathname(), "out")},
    "session": {"kind": (text(*SESSIONS), REQUIRED)},
    "imu": {
        "accel_file": (pathname(), REQUIRED),
        "gyro_file": (pathname(), REQUIRED),
        "time_unit": (text("s", "ms"), "s"),
        "accel_scale": (_PER_AXIS, _DEFAULTS["scale"]),
        "accel_offset": (_PER_AXIS, _DEFAULTS["offset"]),
        "gyro_scale": (_PER_AXIS, _DEFAULTS["scale"]),
        "gyro_offset": (_PER_AXIS, _DEFAULTS["offset"]),
    },
    "static": {
        "gravity_m_s2": (number(above=0.0), REQUIRED),
        "window_s": (number(above=0.0), _DEFAULTS["window"]),
        "threshold_factor": (number(above=0.0), _DEFAULTS["threshold_factor"]),
        "initial_rest_s": (number(above=0.0), _DEFAULTS["initial_rest"]),
        "min_pose_s": (number(above=0.0), _DEFAULTS["min_pose"]),
        "estimate": (_ESTIMATE, "determinable"),
        # 0 (none) or at least 2: checked below.
        "holdout_every": (integer(0), 0),
        # Absent: none; else poses ending at or after this time (s, the
        # files' time axis) are held out.
        "holdout_from_s": (number(), ABSENT),
    },
    "drive": {
        "navigate": (pathname(), REQUIRED),
        "window_s": (number(above=0.0), DEFAULT_WINDOW_S),
        # 0: the whole drive.
        "until_s": (number(minimum=0.0), 0.0),
        "estimate": (_ESTIMATE, "determinable"),
        "scale_factor_states": (flag(), True),
        "compare": (flag(), True),
        "draws": (integer(0), 10),
        "seed": (integer(0), 0),
    },
    "report": {"html": (flag(), True)},
}
#: The tables each session kind reads (the others must be absent).
KIND_TABLES = {"static-poses": ("imu", "static"), "drive": ("drive",)}


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
        """The recording named by ``section.key``: beside this configuration
        when it is there, else under the data root; a ``ValueError`` naming
        the key and both places when neither holds it."""
        value = self.values[section][key]
        missing = missing_data_file(f"{section}.{key}", value, self.path.parent, self.data_root)
        if missing is not None:
            raise ValueError(f"{self.path}: {missing}")
        return data_path(value, self.path.parent, self.data_root)

    def config_path(self, section: str, key: str) -> Path:
        """The file or folder named by ``section.key`` (``output``, ``[drive]
        navigate``), resolved against this configuration's folder."""
        return resolve_path(self.values[section][key], self.path.parent)


def load_calibration_config(
    path: str | Path, data_root: str | Path | None = None
) -> CalibrationConfig:
    """Reads and checks a ``calibrate`` configuration (module docstring)."""
    path = Path(path)
    cfg = CalibrationConfig(path=path, data_root=resolve_data_root(path, data_root))
    tables = split_tables(path, load_toml(path), [k for k in SCHEMA if k])
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
        cfg.values[section] = read_table(path, section, tables.get(section, {}), schema)
    if session != "drive" and cfg["static"]["holdout_every"] == 1:
        raise ValueError(f"{path}: static.holdout_every: must be 0 (none) or at least 2, got 1")
    return cfg
