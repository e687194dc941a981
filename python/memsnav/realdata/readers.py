"""Readers of real sensor logs: IMU CSV with a declared layout and units,
RTKLIB time-tag files, RTKLIB ``.pos`` solutions (and a ``.pos`` writer).

The parsing is in the Rust core (``memsnav_core::logs``); these are its
Python faces with their defaults. Every field is range-checked; an error
names the file, the 1-based line (the byte for a ``.tag``), the column and
the field (``memsnav.ParseError``). A line cut short at the end of a log (a
recording stopped mid-line) is skipped with a warning, and so are contents
that do not fit the declared units (a warning, with the likely unit).
"""

from __future__ import annotations

import operator
import warnings
from collections.abc import Iterable, Mapping, Sequence
from pathlib import Path

import numpy as np
import numpy.typing as npt

from memsnav import _memsnav
from memsnav._memsnav import ImuLog, ParseError, PosSolution, TagClock, TimeTag

__all__ = [
    "IMU_COLUMNS",
    "UNIX_TO_GPS_S",
    "ImuLog",
    "ParseError",
    "PosSolution",
    "TagClock",
    "TimeTag",
    "fit_tag_clock",
    "gps_time_from_tag",
    "read_imu_csv",
    "read_pos",
    "read_time_tag",
    "write_pos",
]

#: Seconds from the Unix epoch to the GPS epoch 1980-01-06 (RTKLIB keeps GPST
#: in a ``time_t``-like count from 1970, without leap seconds): the core's.
UNIX_TO_GPS_S: float = _memsnav.UNIX_TO_GPS_S
#: Columns an IMU layout must name; other names are read and ignored.
IMU_COLUMNS = ("ax", "ay", "az", "gx", "gy", "gz", "t")


def _warn(messages: Iterable[str]) -> None:
    for message in messages:
        warnings.warn(message, stacklevel=3)


def _count(value: object, argument: str) -> int:
    """A non-negative integer argument, or a ValueError naming it."""
    try:
        n = operator.index(value)  # type: ignore[arg-type]
    except TypeError:
        raise ValueError(f"{argument}: must be an integer, got {value!r}") from None
    if n < 0:
        raise ValueError(f"{argument}: must be >= 0, got {n}")
    return n


def read_imu_csv(
    path: str | Path,
    columns: Sequence[str] | Mapping[str, str | int] = IMU_COLUMNS,
    *,
    accel_unit: str = "g",
    gyro_unit: str = "deg/s",
    time_unit: str = "ms",
    axes: str | npt.ArrayLike = "FRD",
    skip_first_line: bool = False,
    header_lines: int = 0,
) -> ImuLog:
    """Reads an IMU CSV log (parsed in Rust with the ``csv`` crate) into
    samples in SI units and FRD sensor axes (docs/how-to/your-own-imu-log.md, "Your own
    IMU log").

    ``columns``, where each quantity ``ax ay az`` (accelerometer), ``gx gy
    gz`` (gyro) and ``t`` (time) is: a list naming every comma-separated
    column in order (other names are read and ignored; a line must have
    exactly that many fields); or a dict from each quantity to its name in
    the file's header line (the first line after ``header_lines``; other
    columns ignored) or to its 1-based column number. An unknown quantity
    names the one meant.

    Units: ``accel_unit`` "g" or "m/s^2" (specific force), "m/s" or "g*s"
    (velocity increment per row); ``gyro_unit`` "deg/s" or "rad/s"
    (rate), "deg" or "rad" (angle increment per row); ``time_unit`` "ms"
    or "s". Increments (both columns' units say so) cover the interval
    since the previous row; each becomes its mean rate at the interval's
    middle, the first row only opening the first interval.

    ``axes``: the log's axis convention, rotated into FRD (x forward, y
    right, z down): "FRD" (or "NED"), "FLU" (ROS), "RFU" (or "ENU"), or a
    3×3 rotation ``C`` with ``v_FRD = C v_log``.

    ``header_lines`` lines are skipped, then (columns by header name) the
    header line, then the first data line when ``skip_first_line`` (a log
    that started mid-line). Each value is range-checked (|f| ≤ 1000 g, |ω|
    ≤ 100 rad/s, for increments as mean rates) and times must increase: a
    repeated or backward time raises ``ParseError`` naming the file and
    line. The last line is skipped with a warning when it has no end of
    line or does not parse; any other bad line raises ``ParseError``
    naming the file, line and column. Warnings also say when the
    magnitudes do not fit the units (median |f| far from 1 g, rates above
    573 °/s, sample intervals outside 10 µs-0.5 s) and where the time jumps
    by more than 1 s.

    Returns an ``ImuLog``: ``time`` (the log's clock, s: each sample's
    time), ``specific_force`` (m/s²) and ``angular_rate`` (rad/s) in FRD
    sensor axes, ``line_time`` (the stamp of each sample's line),
    ``timing`` (median interval, jitter, gaps: intervals over 1.5 median
    intervals, their count and the largest), ``line`` (1-based),
    ``line_end_offset`` (byte offset of each line's newline),
    ``file_bytes``, ``newline_count`` and ``warnings``.

    ``path``: the file to read (str or path-like).
    """
    log = _memsnav.read_imu_csv(
        Path(path),
        dict(columns) if isinstance(columns, Mapping) else list(columns),
        accel_unit,
        gyro_unit,
        time_unit,
        bool(skip_first_line),
        _count(header_lines, "header_lines"),
        axes,
    )
    _warn(log.warnings)
    return log


def read_time_tag(path: str | Path) -> TimeTag:
    """Reads an RTKLIB ``.tag`` file: a 64-byte header (``"TIMETAG RTKLIB
    ..."``, with the logger's start tick in its last 4 bytes), the GPST of
    the log's opening (uint32 seconds from 1970 and a double fraction), then
    one (uint32 tick ms, uint32 file position) record per write,
    little-endian. RTKLIB takes the position after the write: byte ``b`` of
    the log arrived with the first record whose position exceeds ``b``.

    The start must lie after 1980-01-06 with a fraction in [0, 1); ticks and
    positions must not decrease (``ParseError`` naming the byte). A record
    cut short at the end is dropped with a warning.

    ``path``: the file to read (str or path-like).
    """
    tag = _memsnav.read_time_tag(Path(path))
    _warn(tag.warnings)
    return tag


def fit_tag_clock(imu: ImuLog, tag: TimeTag, *, line_ends: str | None = None) -> TagClock:
    """Maps the IMU clock of ``imu`` to GPS time with the time tag of its log.

    Each line's arrival (the write that completed it) is its sampling time
    plus a latency that is never negative; the map is the line below every
    (IMU time, arrival − IMU time) point that lies highest at the mean time
    (an edge of their lower convex hull; Moon, Skelly & Towsley, IEEE
    INFOCOM 1999), so it takes the buffering at its minimum and the IMU
    clock's rate against the logger's. ``line_ends``: how the tag's file
    positions count line ends, ``"as_in_file"`` or ``"crlf_counted"`` (a log
    written with CR LF and stored with LF); None detects it from the file
    size (the tag's last position equals the size, or the size plus the
    number of newlines) and refuses a tag that fits neither.

    Returns a ``TagClock``: ``gps_time`` of every sample, ``offset_s``,
    ``rate_ppm``, ``arrival_lag_spread_s`` (largest lag above the line),
    ``line_ends``, ``tagged_samples`` and ``warnings``.

    ``imu``: the ``ImuLog`` of ``read_imu_csv``; ``tag``: its log's
    ``TimeTag`` (``read_time_tag``).
    """
    clock = _memsnav.fit_tag_clock(imu, tag, line_ends)
    _warn(clock.warnings)
    return clock


def gps_time_from_tag(
    imu: ImuLog, tag: TimeTag, *, line_ends: str | None = None
) -> tuple[np.ndarray, float]:
    """GPS time of every IMU sample from the log's time tag
    (``fit_tag_clock``), and the spread of the arrival lag above the fitted
    line, s (the logger's buffering: 0.04 s on ``drive_0708``)."""
    clock = fit_tag_clock(imu, tag, line_ends=line_ends)
    return clock.gps_time, clock.arrival_lag_spread_s


def read_pos(path: str | Path) -> PosSolution:
    """Reads an RTKLIB ``.pos`` file written with GPST date/time and
    latitude/longitude/height (``%  GPST  latitude(deg) ...`` header), with
    or without the velocity columns of RTKLIB demo5.

    Each field is range-checked (a real date, latitude ±90°, longitude
    ±180°, height −10 km to 10 000 km, Q 0-7, stds ≥ 0, speeds ≤ 10 km/s) and
    epochs must increase; errors name the file, line and field. The last
    line is skipped with a warning when cut short.

    Returns a ``PosSolution``: ``gps_time`` s since 1980-01-06, ``lla``
    (N, 3) [lat rad, lon rad, h m ellipsoidal], ``quality`` (RTKLIB's Q),
    ``n_satellites``, ``std_ned`` (N, 3) m, ``velocity_ned`` (N, 3) m/s and
    ``velocity_std_ned`` (NaN when the file has no velocity), ``warnings``.

    ``path``: the file to read (str or path-like).
    """
    solution = _memsnav.read_pos(Path(path))
    _warn(solution.warnings)
    return solution


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
    velocity columns of RTKLIB 2.4.3 demo5) that ``read_pos`` and RTKLIB's
    ``rtkplot`` read; times rounded to the millisecond. ``quality`` is
    RTKLIB's Q; ``n_satellites`` defaults to zeros. Every value must be
    finite and within ``read_pos``'s ranges (``ValueError`` naming the
    argument and row)."""
    n = len(np.atleast_1d(gps_time))
    ns = np.zeros(n) if n_satellites is None else n_satellites
    _memsnav.write_pos(
        Path(path),
        gps_time,
        lla,
        std_ned,
        velocity_ned,
        velocity_std_ned,
        quality,
        ns,
        program,
    )
