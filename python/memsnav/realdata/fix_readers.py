"""Readers of GNSS fixes in the formats other than RTKLIB ``.pos``: the
fixes CSV, NMEA 0183 and the NAV-PVT solutions of a u-blox UBX log. Each
gives the same ``PosSolution`` as ``read_pos`` (GPS time,
latitude/longitude/ellipsoidal height, RTKLIB's quality code, satellites,
NED σ and, when the file has it, the full NED covariance; NED velocity and
its σ), so that loose coupling
(``fixes_from_solution``, ``[gnss] pos``) and the truth (``[truth] pos``)
take any of them. The parsing is in the Rust core (``memsnav_core::logs``);
the formats are described in docs/how-to/your-own-imu-log.md, "GNSS fixes from other
receivers", and a user's own CSV layout in docs/how-to/your-own-files.md.
"""

from __future__ import annotations

from collections.abc import Mapping
from pathlib import Path

from memsnav import _memsnav
from memsnav._memsnav import PosSolution
from memsnav.realdata.readers import _warn, read_pos

__all__ = [
    "FIX_FORMATS",
    "fix_format",
    "read_fixes",
    "read_fixes_csv",
    "read_nmea",
    "read_ubx_fixes",
]

#: The fix formats and the file name endings that choose each by default.
FIX_FORMATS: dict[str, tuple[str, ...]] = {
    "rtklib": (".pos",),
    "csv": (".csv",),
    "nmea": (".nmea", ".nma", ".gga"),
    "ubx": (".ubx",),
}


def fix_format(path: str | Path, format: str | None = None) -> str:
    """The format of a fixes file: ``format`` when given (one of
    :data:`FIX_FORMATS`), else from the file name's ending (``.csv`` the
    fixes CSV, ``.nmea``/``.nma``/``.gga`` NMEA, ``.ubx`` a u-blox log's
    NAV-PVT, anything else RTKLIB
    ``.pos``)."""
    if format is not None:
        if format not in FIX_FORMATS:
            raise ValueError(f"format: must be one of {list(FIX_FORMATS)}, got {format!r}")
        return format
    suffix = Path(path).suffix.lower()
    for name, endings in FIX_FORMATS.items():
        if suffix in endings:
            return name
    return "rtklib"


def read_fixes_csv(
    path: str | Path,
    columns: Mapping[str, str] | None = None,
    *,
    time_reference: str | None = None,
) -> PosSolution:
    """Reads GNSS fixes (or a truth) from a CSV whose header names its
    columns, in any order: time as ``gps_time_s`` (GPS s since 1980-01-06)
    or ``gps_week`` and ``gps_tow_s``; position as ``lat_deg, lon_deg,
    height_m`` (ellipsoidal) or ``x_ecef_m, y_ecef_m, z_ecef_m``; optionally
    its uncertainty as ``std_n_m, std_e_m, std_d_m`` or the six entries
    ``cov_nn_m2, cov_ne_m2, cov_nd_m2, cov_ee_m2, cov_ed_m2, cov_dd_m2``
    (loose coupling needs it; without it ``std_ned`` is NaN), ``vn_m_s,
    ve_m_s, vd_m_s`` with ``std_vn_m_s, ...`` or ``cov_vnvn_m2_s2, ...``,
    the attitude (body to NED) as the scalar-first quaternion ``qw, qx, qy,
    qz`` or ``roll_deg, pitch_deg, yaw_deg`` (``attitude``: C_b^n),
    ``quality`` (RTKLIB's Q, default 5) and ``n_satellites``. ``#`` lines
    are comments.

    ``columns``: a user's own header, as a dict from memsnav's column names
    to the file's header names (``{"gps_time_s": "time_s"}``); header
    columns that carry memsnav's names are then read as themselves unless
    mapped over, and every other column is ignored. Without it an unknown
    column is an error naming it. ``time_reference``: what the time column
    counts, ``"column_gps"`` (None: GPS s since 1980-01-06) or
    ``"column_unix_gpst"`` (GPS s counted from 1970 without leap seconds).

    Every field is range-checked (covariances positive semi-definite,
    quaternions of unit norm) and times must increase; errors name the file,
    line and field (``ParseError``), or the key of ``columns``. The last
    line is skipped with a warning when cut short.

    ``path``: the file to read (str or path-like).
    """
    solution = _memsnav.read_fixes_csv(
        Path(path), None if columns is None else dict(columns), time_reference
    )
    _warn(solution.warnings)
    return solution


def read_nmea(path: str | Path) -> PosSolution:
    """Reads GNSS fixes from an NMEA 0183 log: GGA (position, quality,
    satellites, HDOP, height above mean sea level + geoid separation), RMC
    (date, speed, course), GST (σ and error ellipse → NED covariance), VTG
    (course, speed); talkers GP, GN, GL, GA, GB, BD, GQ; plain sentences or
    Android GnssLogger ``NMEA,<sentence>,<unix ms>`` records. Checksums are
    verified; sentences with one UTC time form an epoch; UTC → GPS time with
    the leap seconds. Epochs without GST get σ from HDOP (a warning says
    so). The speed and course are the north and east velocity (zero at a
    speed of zero), σ = max(HDOP · 0.1 m/s / √2, 0.05 m/s) per axis with
    the rounding of the sentence's digits; NMEA has no vertical velocity, so
    ``velocity_ned[:, 2]`` and its σ are NaN and loose coupling takes the
    velocity as horizontal only (docs/how-to/own-logs.md). Other sentence types are
    ignored with a warning.

    ``path``: the file to read (str or path-like).
    """
    solution = _memsnav.read_nmea(Path(path))
    _warn(solution.warnings)
    return solution


def read_ubx_fixes(path: str | Path) -> PosSolution:
    """Reads the receiver's own solutions (UBX-NAV-PVT) of a u-blox UBX log
    as fixes: those with ``gnssFixOK`` and a 2D, 3D or GNSS + dead-reckoning
    fix; quality 1 carrier fixed, 2 float, 4 differential, 5 single point;
    σ north and east hAcc/√2, down vAcc, velocity σ sAcc per axis; the GPS
    week from the UTC date and the leap seconds (:func:`memsnav.read_ubx`
    gives the rest of the log)."""
    solution = _memsnav.read_ubx(Path(path)).fixes
    _warn(solution.warnings)
    return solution


def read_fixes(
    path: str | Path,
    format: str | None = None,
    *,
    columns: Mapping[str, str] | None = None,
    time_reference: str | None = None,
) -> PosSolution:
    """Reads a fixes file in ``format`` (:func:`fix_format`: by default
    from the file name): ``read_pos``, :func:`read_fixes_csv` (with its
    ``columns`` and ``time_reference``, which only a fixes CSV takes),
    :func:`read_nmea` or :func:`read_ubx_fixes`.

    ``path``: the file to read (str or path-like).
    """
    chosen = fix_format(path, format)
    if chosen == "csv":
        return read_fixes_csv(path, columns, time_reference=time_reference)
    for argument, value in (("columns", columns), ("time_reference", time_reference)):
        if value is not None:
            raise ValueError(
                f"{argument}: only a fixes CSV (format 'csv') takes it; {path} is read as "
                f"{chosen!r}"
            )
    reader = {"rtklib": read_pos, "nmea": read_nmea, "ubx": read_ubx_fixes}
    return reader[chosen](path)
