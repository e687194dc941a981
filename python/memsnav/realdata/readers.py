"""Readers of real sensor logs: IMU CSV with a declared layout and units,
RTKLIB time-tag files, RTKLIB ``.pos`` solutions.

Every error names the file, the 1-based line and what was expected
(``memsnav.ParseError``); a line cut short at the start or the end of a log
(a recording started or stopped mid-line) is skipped with a warning.
"""

from __future__ import annotations

import struct
import warnings
from collections.abc import Sequence
from dataclasses import dataclass, field
from pathlib import Path

import numpy as np

from memsnav._memsnav import ParseError

#: Seconds from the Unix epoch to the GPS epoch 1980-01-06 (RTKLIB keeps GPST
#: in a ``time_t``-like count from 1970, without leap seconds).
UNIX_TO_GPS_S = 315_964_800.0
STANDARD_GRAVITY = 9.80665
ACCEL_UNITS = {"g": STANDARD_GRAVITY, "m/s^2": 1.0, "m/s2": 1.0}
GYRO_UNITS = {"deg/s": np.pi / 180.0, "rad/s": 1.0}
TIME_UNITS = {"ms": 1e-3, "s": 1.0}
#: Columns an IMU layout must name; other names are read and ignored, "_" skips.
IMU_COLUMNS = ("ax", "ay", "az", "gx", "gy", "gz", "t")


def _parse_error(file: Path | str, line: int, reason: str) -> ParseError:
    return ParseError(f"{file}:{line}: {reason}")


def _unit(table: dict[str, float], value: str, what: str, file: Path | str) -> float:
    if value not in table:
        raise ValueError(
            f"{what}: unknown unit {value!r} for {file}; expected one of {sorted(table)}"
        )
    return table[value]


@dataclass(frozen=True)
class ImuLog:
    """IMU samples in SI units and sensor axes.

    ``time``: the log's own clock, s (``(N,)``); ``specific_force``: m/s²
    ``(N, 3)``; ``angular_rate``: rad/s ``(N, 3)``; ``line``: the 1-based
    line of each sample; ``line_end_offset``: byte offset of each line's
    newline (to match RTKLIB time tags); ``warnings``: lines skipped.
    """

    time: np.ndarray
    specific_force: np.ndarray
    angular_rate: np.ndarray
    line: np.ndarray
    line_end_offset: np.ndarray
    warnings: list[str] = field(default_factory=list)


def read_imu_csv(
    path: str | Path,
    columns: Sequence[str] = IMU_COLUMNS,
    *,
    accel_unit: str = "g",
    gyro_unit: str = "deg/s",
    time_unit: str = "ms",
    skip_first_line: bool = False,
    header_lines: int = 0,
) -> ImuLog:
    """Reads an IMU CSV log.

    ``columns``: the name of every comma-separated column in order; it must
    contain ``ax ay az`` (accelerometer), ``gx gy gz`` (gyro) and ``t``
    (time); any other name is read and ignored. Units: ``accel_unit`` "g"
    or "m/s^2"; ``gyro_unit`` "deg/s" or "rad/s"; ``time_unit`` "ms" or "s".
    ``skip_first_line``: drop the first data line unread (a log that started
    mid-line may still parse). The last line, when it does not parse, is
    skipped with a warning; any other bad line raises ``ParseError`` naming
    the file and line.
    """
    path = Path(path)
    columns = list(columns)
    missing = [c for c in IMU_COLUMNS if c not in columns]
    if missing:
        raise ValueError(
            f"columns: the layout for {path} lacks {missing}; it needs {list(IMU_COLUMNS)}"
        )
    if len(set(columns)) != len(columns):
        raise ValueError(f"columns: duplicate names in {columns}")
    sa = _unit(ACCEL_UNITS, accel_unit, "accel_unit", path)
    sg = _unit(GYRO_UNITS, gyro_unit, "gyro_unit", path)
    st = _unit(TIME_UNITS, time_unit, "time_unit", path)
    idx = [columns.index(c) for c in IMU_COLUMNS]
    raw = path.read_bytes()
    lines = raw.split(b"\n")
    # Byte offset of each line's terminating newline (or end of file).
    ends = np.cumsum([len(s) + 1 for s in lines]) - 1
    rows: list[list[float]] = []
    line_no: list[int] = []
    line_end: list[int] = []
    notes: list[str] = []
    last = max(i for i, s in enumerate(lines) if s.strip()) if raw.strip() else -1
    start = header_lines + (1 if skip_first_line else 0)
    if skip_first_line and last >= header_lines:
        notes.append(f"{path}:{header_lines + 1}: first data line skipped (skip_first_line)")
    for i in range(start, last + 1):
        text = lines[i].strip()
        if not text:
            continue
        fields = text.split(b",")
        reason = None
        if len(fields) != len(columns):
            reason = (
                f"expected {len(columns)} comma-separated fields ({', '.join(columns)}), "
                f"got {len(fields)}"
            )
        else:
            try:
                values = [float(fields[j]) for j in idx]
            except ValueError:
                got = text.decode(errors="replace")
                reason = f"expected numbers in columns {list(IMU_COLUMNS)}, got {got!r}"
            else:
                if not np.all(np.isfinite(values)):
                    reason = "expected finite numbers"
        if reason is not None:
            if i == last:
                notes.append(f"{path}:{i + 1}: last line cut short ({reason}); skipped")
                continue
            raise _parse_error(path, i + 1, reason)
        rows.append(values)
        line_no.append(i + 1)
        line_end.append(int(ends[i]))
    for note in notes[1 if skip_first_line else 0 :]:
        warnings.warn(note, stacklevel=2)
    if len(rows) < 2:
        raise _parse_error(path, max(last, 0) + 1, "expected at least two IMU samples")
    a = np.asarray(rows)
    time = a[:, 6] * st
    bad = np.nonzero(np.diff(time) <= 0)[0]
    if bad.size:
        k = bad[0] + 1
        raise _parse_error(
            path, line_no[k], f"time {a[k, 6]} does not increase (previous {a[k - 1, 6]})"
        )
    return ImuLog(
        time=time,
        specific_force=a[:, 0:3] * sa,
        angular_rate=a[:, 3:6] * sg,
        line=np.asarray(line_no),
        line_end_offset=np.asarray(line_end),
        warnings=notes,
    )


@dataclass(frozen=True)
class TimeTag:
    """An RTKLIB time-tag file: the GPS time of the stream's start and, per
    write, the tick (ms since start) and the file offset of its first byte."""

    start_gps_time: float
    tick_ms: np.ndarray
    file_offset: np.ndarray

    def arrival_gps_time(self, byte_offset: np.ndarray) -> np.ndarray:
        """GPS time (s since 1980-01-06) at which each byte was written; NaN
        before the first tagged write."""
        i = np.searchsorted(self.file_offset, byte_offset, side="right") - 1
        out = self.start_gps_time + self.tick_ms[np.clip(i, 0, None)] * 1e-3
        return np.where(i >= 0, out, np.nan)


def read_time_tag(path: str | Path) -> TimeTag:
    """Reads an RTKLIB ``.tag`` file: a 64-byte header (``"TIMETAG RTKLIB
    ..."``, with the start tick in its last 4 bytes), the start time as a
    uint32 GPST count from 1970 and a double fraction of a second, then
    (uint32 tick ms, uint32 file offset) records, little-endian."""
    path = Path(path)
    b = path.read_bytes()
    if not b.startswith(b"TIMETAG RTKLIB"):
        raise _parse_error(
            path, 1, "expected the header 'TIMETAG RTKLIB ...': not an RTKLIB time-tag file"
        )
    if len(b) < 76:
        raise _parse_error(
            path, 1, f"expected at least 76 bytes (header and start time), got {len(b)}"
        )
    seconds, fraction = struct.unpack_from("<Id", b, 64)
    n = (len(b) - 76) // 8
    if (len(b) - 76) % 8:
        warnings.warn(f"{path}: last time-tag record cut short; skipped", stacklevel=2)
    rec = np.frombuffer(b, dtype="<u4", count=2 * n, offset=76).reshape(n, 2).astype(np.int64)
    if n and np.any(np.diff(rec[:, 1]) < 0):
        k = int(np.nonzero(np.diff(rec[:, 1]) < 0)[0][0]) + 1
        raise _parse_error(path, k + 1, f"record {k + 1}: file offsets must not decrease")
    return TimeTag(seconds - UNIX_TO_GPS_S + fraction, rec[:, 0].astype(float), rec[:, 1])


def gps_time_from_tag(imu: ImuLog, tag: TimeTag) -> tuple[np.ndarray, float]:
    """GPS time of every IMU sample: the IMU's own clock shifted so that the
    first tagged line gets its tagged arrival time (RTKLIB practice).

    The IMU clock keeps the rate (the yaw rate of ``drive_0708`` matches the
    RTK course rate at one constant offset over the whole log, see
    ``docs/real-data.md``) while later arrival tags drift by seconds with the
    logger's buffering, so a line fitted to all tags would stretch the time
    axis. Returns the times and the spread (max - min) of arrival - mapped
    time over the log, s, a measure of that buffering.
    """
    arrival = tag.arrival_gps_time(imu.line_end_offset)
    ok = np.nonzero(np.isfinite(arrival))[0]
    if ok.size == 0:
        raise ValueError("time tag: no IMU line falls inside the tagged part of the log")
    offset = arrival[ok[0]] - imu.time[ok[0]]
    gps = imu.time + offset
    lag = arrival[ok] - gps[ok]
    return gps, float(lag.max() - lag.min())


@dataclass(frozen=True)
class PosSolution:
    """An RTKLIB ``.pos`` solution in geodetic form.

    ``gps_time`` s since 1980-01-06; ``lla`` (N, 3) [lat rad, lon rad, h m
    ellipsoidal]; ``quality`` Q (1 fix, 2 float, 5 single, ...);
    ``n_satellites``; ``std_ned`` (N, 3) m; ``velocity_ned`` (N, 3) m/s
    (NaN when the file has none) and ``velocity_std_ned``.
    """

    gps_time: np.ndarray
    lla: np.ndarray
    quality: np.ndarray
    n_satellites: np.ndarray
    std_ned: np.ndarray
    velocity_ned: np.ndarray
    velocity_std_ned: np.ndarray
    warnings: list[str] = field(default_factory=list)


def _gps_seconds(date: str, clock: str) -> float:
    y, mo, d = (int(v) for v in date.split("/"))
    hh, mm, ss = clock.split(":")
    days = (np.datetime64(f"{y:04d}-{mo:02d}-{d:02d}") - np.datetime64("1980-01-06")).astype(int)
    return float(days) * 86400.0 + int(hh) * 3600.0 + int(mm) * 60.0 + float(ss)


def read_pos(path: str | Path) -> PosSolution:
    """Reads an RTKLIB ``.pos`` file written with GPST date/time and
    latitude/longitude/height (``%  GPST  latitude(deg) ...`` header),
    with or without the velocity columns."""
    path = Path(path)
    lines = path.read_text(errors="replace").splitlines()
    header = next(
        (i for i, s in enumerate(lines) if s.startswith("%") and "latitude(deg)" in s), None
    )
    if header is None:
        raise _parse_error(
            path, 1, "expected a '%  GPST  latitude(deg) longitude(deg) height(m) Q ns ...' header"
        )
    names = lines[header].lstrip("%").split()
    if names[0] != "GPST":
        raise _parse_error(path, header + 1, f"expected times in GPST, got {names[0]!r}")
    has_velocity = "vn(m/s)" in names
    n_fields = 24 if has_velocity else 15
    rows: list[list[float]] = []
    notes: list[str] = []
    data = [
        i
        for i in range(header + 1, len(lines))
        if lines[i].strip() and not lines[i].startswith("%")
    ]
    for i in data:
        f = lines[i].split()
        reason = None
        if len(f) != n_fields:
            extra = ", velocity and its stds" if has_velocity else ""
            reason = (
                f"expected {n_fields} fields (date, time, lat, lon, height, Q, ns, stds, age, "
                f"ratio{extra}), got {len(f)}"
            )
        else:
            try:
                rows.append([_gps_seconds(f[0], f[1])] + [float(v) for v in f[2:]])
            except ValueError:
                reason = f"expected 'yyyy/mm/dd hh:mm:ss.sss' and numbers, got {lines[i]!r}"
        if reason is not None:
            if i == data[-1]:
                notes.append(f"{path}:{i + 1}: last line cut short ({reason}); skipped")
                continue
            raise _parse_error(path, i + 1, reason)
    for note in notes:
        warnings.warn(note, stacklevel=2)
    if not rows:
        raise _parse_error(path, len(lines), "expected at least one solution line")
    a = np.asarray(rows)
    nan3 = np.full((len(a), 3), np.nan)
    return PosSolution(
        gps_time=a[:, 0],
        lla=np.column_stack([np.radians(a[:, 1]), np.radians(a[:, 2]), a[:, 3]]),
        quality=a[:, 4].astype(int),
        n_satellites=a[:, 5].astype(int),
        std_ned=a[:, 6:9],
        velocity_ned=a[:, 14:17] * np.array([1.0, 1.0, -1.0]) if has_velocity else nan3,
        velocity_std_ned=a[:, 17:20] if has_velocity else nan3,
        warnings=notes,
    )


def write_pos(
    path: str | Path,
    gps_time: np.ndarray,
    lla: np.ndarray,
    std_ned: np.ndarray,
    velocity_ned: np.ndarray,
    velocity_std_ned: np.ndarray,
    *,
    quality: int = 5,
    n_satellites: np.ndarray | None = None,
    program: str = "memsnav",
) -> None:
    """Writes an RTKLIB-compatible ``.pos`` (GPST, lat/lon/height, the
    velocity columns of RTKLIB 2.4.3 demo5); ``quality`` is RTKLIB's Q."""
    ns = np.zeros(len(gps_time), dtype=int) if n_satellites is None else n_satellites
    head = (
        f"% program   : {program}\n"
        "%  GPST                  latitude(deg) longitude(deg) "
        " height(m)   Q  ns   sdn(m)   sde(m)   sdu(m)  "
        "sdne(m)  sdeu(m)  sdun(m) age(s)  ratio    vn(m/s)   "
        " ve(m/s)    vu(m/s)      sdvn     sdve     sdvu    "
        "sdvne    sdveu    sdvun\n"
    )
    week_start = np.datetime64("1980-01-06T00:00:00", "ms")
    out = [head]
    for k in range(len(gps_time)):
        stamp = week_start + np.timedelta64(round(gps_time[k] * 1000.0), "ms")
        s = str(stamp).replace("-", "/").replace("T", " ")
        lat, lon = np.degrees(lla[k, :2])
        sn, se, sd = std_ned[k]
        vn, ve, vd = velocity_ned[k]
        svn, sve, svd = velocity_std_ned[k]
        out.append(
            f"{s} {lat:14.9f} {lon:14.9f} {lla[k, 2]:10.4f} {quality:3d} {ns[k]:3d} "
            f"{sn:8.4f} {se:8.4f} {sd:8.4f} {0.0:8.4f} {0.0:8.4f} {0.0:8.4f} {0.0:6.2f} {0.0:6.1f} "
            f"{vn:10.5f} {ve:10.5f} {-vd:10.5f} {svn:9.5f} {sve:9.5f} "
            f"{svd:9.5f} {0.0:9.5f} {0.0:9.5f} {0.0:9.5f}\n"
        )
    Path(path).write_text("".join(out))
