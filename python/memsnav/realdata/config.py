"""The ``navigate`` run configuration (TOML, read with :mod:`tomllib`).

A configuration has two kinds of keys. The ones that say where the data
are and how to read them (files, column layouts, units, the GNSS input)
are listed in :data:`SCHEMA` with their defaults. The ones that tune the
navigation engine (mounting, lever arms, filter, alignment, standstill
detection, aids, outages) belong to the core engine: their names, units
and defaults live there (``memsnav.navigate_settings()`` lists them) and a
key left out keeps the engine's default. Either way, an unknown table or
key (a typo) is an error naming the file and the key, and so is a value of
the wrong kind or out of range (the reading keys by the one configuration
reader, :mod:`memsnav._config`; the engine's keys by the core), all when the
file is loaded.

A relative path of a recording read (``[imu] file`` and ``time_tag``,
``[gnss] pos``, ``table``, ``obs``, ``nav`` and ``ubx``, ``[truth] pos``)
resolves against the configuration's own folder when a file exists there
(a configuration saved beside its data), else against the data root:
``--data-root``, else ``$MEMSNAV_DATA_ROOT``, else ``../shared/data``
relative to the repository that holds the configuration (the parent of its
``examples/`` folder, or the nearest ``shared/data`` above it; for a
configuration elsewhere, the same from its own folder). When neither
exists, the error names the key and both places tried. Every other
relative path (``output``, ``[imu] calibration``) resolves against the
configuration's own folder.
"""

from __future__ import annotations

import json
import os
from dataclasses import dataclass, field
from pathlib import Path
from typing import Any

import memsnav._memsnav as _mn
from memsnav._config import (
    DATA_ROOT_ENV,
    REQUIRED,
    Check,
    axes,
    data_path,
    file_name,
    flag,
    header_names,
    imu_columns,
    integer,
    list_of,
    list_or_choice,
    load_toml,
    missing_data_file,
    number,
    pathname,
    read_table,
    resolve_path,
    satellite,
    split_tables,
    text,
)
from memsnav.realdata.fix_readers import FIX_FORMATS

# The observables' defaults are the core's (``memsnav.defaults()``).
_OBSERVABLES: dict[str, float] = _mn.defaults()["RinexObservations.gps_l1"]
#: RTKLIB's solution qualities (Q): 0 none, 1 fix, 2 float, 3 SBAS, 4 DGPS,
#: 5 single, 6 PPP, 7 dead reckoning (the range ``read_pos`` accepts).
_QUALITIES = list_of(integer(0, 7), min_length=1)
#: The format of a fixes file (``[gnss] pos``, ``[truth] pos``): RTKLIB
#: ``.pos``, the fixes CSV or NMEA; not given: from the file name
#: (``fix_readers.fix_format``: ``.csv``, ``.nmea``, else RTKLIB). A fixes
#: CSV with the user's own header: ``columns``, a table from memsnav's column
#: names to the file's (the reader checks both and names them), and
#: ``time_reference``, what its time column counts (None: GPS time since
#: 1980, the reader's default; docs/how-to/your-own-files.md).
_FIX_FORMAT: dict[str, tuple[Check, Any]] = {
    "format": (text(*FIX_FORMATS), None),
    "columns": (header_names(), None),
    "time_reference": (text("column_gps", "column_unix_gpst"), None),
}
#: The height datum of an RTKLIB solution's heights (``[gnss]`` fixes,
#: ``[truth]``): ellipsoidal (WGS 84), or above mean sea level with the
#: geoid separation N at the site (h = H + N, m). Geoid undulations lie
#: within −107 m and +86 m over the Earth (EGM2008).
_HEIGHT_DATUM: dict[str, tuple[Check, Any]] = {
    "height": (text("ellipsoidal", "msl"), "ellipsoidal"),
    "geoid_separation_m": (number(-120.0, 100.0), None),
}

#: The reading keys: (kind, default; REQUIRED when it must be given; None:
#: not given, the reader's own default applies). See :mod:`memsnav._config`.
SCHEMA: dict[str, dict[str, tuple[Check, Any]]] = {
    "": {"name": (file_name(), REQUIRED), "output": (pathname(), "out")},
    "imu": {
        "file": (pathname(), REQUIRED),
        # A list naming every column, or a table of each quantity's header
        # name or 1-based number (docs/how-to/your-own-imu-log.md, "Your own IMU log").
        "columns": (imu_columns(), ["ax", "ay", "az", "gx", "gy", "gz", "t"]),
        # The units' and the axis conventions' names are the reader's (its
        # error names them): rates or increments, FRD/FLU/RFU/... or a matrix.
        "axes": (axes(), "FRD"),
        "accel_unit": (text(), REQUIRED),
        "gyro_unit": (text(), REQUIRED),
        "time_unit": (text(), REQUIRED),
        "time_reference": (text("tag", "column_gps", "column_unix_gpst"), "tag"),
        "time_tag": (pathname(), ""),
        "skip_first_line": (flag(), False),
        "header_lines": (integer(0), 0),
        "calibration": (pathname(), ""),
    },
    "gnss": {
        "mode": (text("loose", "tight"), REQUIRED),
        "pos": (pathname(), ""),
        **_FIX_FORMAT,
        # None: every quality the file holds (a warning names them).
        "quality": (_QUALITIES, None),
        "rate_hz": (number(above=0.0), None),
        "position_noise_m": (list_of(number(minimum=0.0), lengths=(3,)), None),
        "velocity_noise_m_s": (number(minimum=0.0), None),
        "use_velocity": (flag(), None),
        "seed": (integer(0), 0),
        # Tight coupling from a long table instead of RINEX (one row per
        # epoch and satellite: GnssMeasurements.from_table).
        "table": (pathname(), ""),
        "obs": (pathname(), ""),
        "nav": (pathname(), ""),
        # A u-blox UBX log instead of obs + nav: its RXM-RAWX observations
        # and the ephemerides decoded from its RXM-SFRBX.
        "ubx": (pathname(), ""),
        # RINEX letters of the systems combined (G GPS, E Galileo, C BeiDou,
        # R GLONASS).
        "systems": (list_of(text("G", "E", "C", "R"), min_length=1), ["G"]),
        # Satellites kept: GPS PRNs (1-63) or RINEX names ("G10", "E07", "C21").
        "satellites": (list_of(satellite()), []),
        "elevation_mask_deg": (number(0.0, 90.0), _OBSERVABLES["elevation_mask_deg"]),
        # C/N0 of any GNSS signal received on the ground is below 100 dB-Hz.
        "min_cn0_db_hz": (number(0.0, 100.0), _OBSERVABLES["min_cn0_db_hz"]),
        "pseudorange_std_m": (number(above=0.0), _OBSERVABLES["pseudorange_std"]),
        "pseudorange_rate_std_m_s": (number(minimum=0.0), _OBSERVABLES["pseudorange_rate_std"]),
        "ionosphere": (flag(), True),
        # Each satellite's ionosphere from a second signal's pseudorange
        # where the log has one (GPS L5/L2C, Galileo E5a/E5b, BeiDou
        # another D1 band); the Klobuchar model for the rest.
        "dual_frequency": (flag(), False),
        "troposphere": (flag(), True),
        # Four each, or neither (the navigation file's); the ICD's ranges
        # are the core's check.
        "klobuchar_alpha": (list_of(number(), lengths=(0, 4)), []),
        "klobuchar_beta": (list_of(number(), lengths=(0, 4)), []),
        **_HEIGHT_DATUM,
    },
    "truth": {
        "pos": (pathname(), ""),
        # What the report and the terminal call it (None: its file name).
        "name": (text(), None),
        **_FIX_FORMAT,
        "quality": (_QUALITIES, [1, 2]),
        **_HEIGHT_DATUM,
        # The scored point (the GNSS antenna) from the truth's own point, in
        # the truth's body axes (forward, right, down), m: needs its attitude.
        "lever_arm_m": (list_of(number(), lengths=(3,)), [0.0, 0.0, 0.0]),
        # The GNSS's datum less the truth's, N, E, D, m: given, or the mean
        # of (GNSS − truth) over the run's GNSS epochs; None: none.
        "offset_ned_m": (list_or_choice(list_of(number(), lengths=(3,)), "from_gnss"), None),
        "score": (text("accuracy", "precision"), "accuracy"),
    },
    "report": {"html": (flag(), True)},
}
#: The engine's tables and keys, from the core.
ENGINE: dict[str, dict[str, str]] = _mn.navigate_settings()


def json_schema() -> dict[str, Any]:
    """The JSON schema (draft 2020-12) of a ``navigate`` configuration:
    every table and key, the reading keys' kinds and defaults
    (:data:`SCHEMA`) and the engine's kinds, bounds and descriptions
    (``memsnav.navigate_settings_schema()``), no other table or key, and
    the keys that must be given. An editor with a TOML language server
    completes and checks a configuration against it
    (``#:schema ./navigate.schema.json`` as the file's first line, or
    ``memsnav schema --output``). What a schema cannot say (a key that
    needs another, a window inside the run) is checked when the file is
    loaded."""
    engine = json.loads(_mn.navigate_settings_schema())
    tables: dict[str, Any] = {}
    required_tables = []
    for table in sorted({k for k in SCHEMA if k} | set(engine)):
        properties: dict[str, Any] = {}
        required = []
        for key, (check, default) in SCHEMA.get(table, {}).items():
            properties[key] = dict(check.schema)
            if default is REQUIRED:
                required.append(key)
            elif default is not None and default != "":
                properties[key]["default"] = default
        properties.update(engine.get(table, {}).get("properties", {}))
        tables[table] = {
            "type": "object",
            "properties": properties,
            "additionalProperties": False,
            **({"required": required} if required else {}),
        }
        if required:
            required_tables.append(table)
    top: dict[str, Any] = {}
    top_required = []
    for key, (check, default) in SCHEMA[""].items():
        top[key] = dict(check.schema)
        if default is REQUIRED:
            top_required.append(key)
        elif default is not None:
            top[key]["default"] = default
    return {
        "$schema": "https://json-schema.org/draft/2020-12/schema",
        "title": "memsnav navigate configuration",
        "type": "object",
        "properties": {**top, **tables},
        "additionalProperties": False,
        "required": top_required + required_tables,
    }


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
        """The recording named by ``section.key``: beside this configuration
        when it is there, else under the data root (None when not given;
        module docstring)."""
        v = self.values[section][key]
        return data_path(v, self.path.parent, self.data_root) if v else None

    def data_file(self, section: str, key: str) -> Path:
        """:meth:`data_path` of a recording the run needs: a ``ValueError``
        naming the file and the key when it is not given, or when no file
        is at any place tried (each named)."""
        v = self.values[section][key]
        name = f"{section}.{key}" if section else key
        if not v:
            raise ValueError(f"{self.path}: {name} is required for this run")
        missing = missing_data_file(name, v, self.path.parent, self.data_root)
        if missing is not None:
            raise ValueError(f"{self.path}: {missing}")
        return data_path(v, self.path.parent, self.data_root)

    def config_path(self, section: str, key: str) -> Path | None:
        """The file or folder named by ``section.key`` (``output``, ``[imu]
        calibration``), resolved against this configuration's folder (None
        when not given)."""
        v = self.values[section][key]
        return resolve_path(v, self.path.parent) if v else None


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


def load_config(path: str | Path, data_root: str | Path | None = None) -> RunConfig:
    """Reads and checks a run configuration (see the module docstring).

    ``path``: the TOML configuration; ``data_root``: the folder its data
    files resolve against [:func:`resolve_data_root`: ``$MEMSNAV_DATA_ROOT``,
    else the nearest ``shared/data`` above the configuration].
    """
    path = Path(path)
    cfg = RunConfig(path=path, data_root=resolve_data_root(path, data_root))
    tables = split_tables(path, load_toml(path), {k for k in SCHEMA if k} | set(ENGINE))
    for table in ["", *sorted({k for k in SCHEMA if k} | set(ENGINE))]:
        given = tables.get(table, {})
        engine_keys = ENGINE.get(table, {})
        cfg.values[table] = read_table(
            path, table, given, SCHEMA.get(table, {}), others=engine_keys
        )
        engine = {k: v for k, v in given.items() if k in engine_keys}
        if engine:
            cfg.engine[table] = engine
    for table in ("gnss", "truth"):
        datum = cfg.values[table]
        if (datum["height"] == "msl") != (datum["geoid_separation_m"] is not None):
            raise ValueError(
                f"{path}: {table}.geoid_separation_m: give it exactly when {table}.height = "
                f'"msl" (the geoid separation N at the site, ellipsoidal h = H + N, m); '
                f"got height = {datum['height']!r}"
            )
    gnss = cfg.values["gnss"]
    # The keys that say how to read a fixes file, given where none is read:
    # an error, not a silent omission.
    unread = [
        (f"gnss.{key}", 'loose coupling\'s fixes (gnss.pos); gnss.mode is "tight"')
        for key in ("columns", "time_reference")
        if gnss["mode"] == "tight" and key in tables.get("gnss", {})
    ] + [
        (f"truth.{key}", "a truth file (truth.pos), which is not given")
        for key in ("name", "columns", "time_reference", "lever_arm_m", "offset_ned_m")
        if not cfg.values["truth"]["pos"] and key in tables.get("truth", {})
    ]
    if unread:
        key, reads = unread[0]
        raise ValueError(f"{path}: {key}: it applies to {reads}")
    if len(gnss["klobuchar_alpha"]) != len(gnss["klobuchar_beta"]):
        raise ValueError(
            f"{path}: gnss.klobuchar_alpha and gnss.klobuchar_beta: give four numbers each, "
            "or neither"
        )
    try:
        _mn.check_navigate_settings(cfg.engine)
    except ValueError as e:
        raise ValueError(f"{path}: {e}") from None
    return cfg
