"""Regenerates the excerpts in this folder from the full logs
(``python make_excerpts.py DATA_ROOT``; DATA_ROOT holds real-imu-gnss/).

- ``walk_head.*``: the first lines/records/epochs of the walk_0827 files,
  byte for byte (reader tests), ``walk.nav`` the whole navigation file;
  ``walk.rnx`` the RINEX 4.00 navigation file ``memsnav convert`` writes of
  ``walk_head.ubx`` (4 GPS LNAV, 7 GPS CNAV, 7 Galileo, 8 BeiDou records).
- ``walk_40s.*``: the first 40 s of the walk (9 s at rest, then walking),
  byte for byte: IMU lines, their tag records, the RINEX observations and
  the RTK solution over the same span (tight coupling from a static start).
- ``drive_60s.csv``: lines 3379-9878 of drive_0708's IMU log, byte for
  byte: 65 s from 5 s before the first motion; ``drive_60s.pos``: the RTK
  solution over the same span (±1 s).
- ``walk_head.ubx``: frames of the walk's raw u-blox log, byte for byte
  (framing, sync bytes and checksums kept): the RXM-RAWX and NAV-PVT
  frames of its first 5 s and every GPS L1 C/A, L2C and L5, Galileo E1-B
  and BeiDou B3I D1 RXM-SFRBX frame of the log (the words of its 4 GPS
  LNAV, 7 GPS CNAV, 7 Galileo I/NAV and 8 BeiDou D1 ephemerides), in log
  order; the interleaved NMEA text and the other messages are left out.
- ``*.csv.tag``: the original tag's header (start time and ticks stay
  relative to the opening of the whole log) and the records of the
  excerpt's bytes, their file positions made relative to the excerpt's
  first byte, the last cut at the excerpt's end. Positions count the CR LF
  line ends the logger wrote (the CSV files are stored with LF), so a tag
  ends at the excerpt's size plus its number of newlines, like the full
  logs' tags.
"""

import struct
import sys
from pathlib import Path

import numpy as np

import memsnav as mn
from memsnav.realdata import readers

root = Path(sys.argv[1]) / "real-imu-gnss"
here = Path(__file__).parent


def excerpt_tag(tag: bytes, log: bytes, first_line: int, excerpt: bytes) -> bytes:
    """The records of ``excerpt`` (starting at 1-based ``first_line`` of
    ``log``), positions relative to its first byte and counted with CR LF."""
    start = sum(len(s) + 2 for s in log.split(b"\n")[: first_line - 1])
    end = start + len(excerpt) + excerpt.count(b"\n")
    out = bytearray(tag[:76])
    for tick, offset in struct.iter_unpack("<II", tag[76 : 76 + (len(tag) - 76) // 8 * 8]):
        if offset > start:
            out += struct.pack("<II", tick, min(offset, end) - start)
        if offset >= end:
            break
    return bytes(out)


walk = root / "walk_0827"
walk_log = (walk / "imu_1730.csv").read_bytes()
walk_head = b"\n".join(walk_log.split(b"\n")[:40]) + b"\n0.01"
(here / "walk_head.csv").write_bytes(walk_head)
(here / "walk_head.csv.tag").write_bytes(
    excerpt_tag((walk / "imu_1730.csv.tag").read_bytes(), walk_log, 1, walk_head)
)
obs = (walk / "gnss_1730.obs").read_text().splitlines(keepends=True)
end = [i for i, s in enumerate(obs) if s.startswith(">")][4]
(here / "walk_head.obs").write_text("".join(obs[:end]))
(here / "walk.nav").write_bytes((walk / "gnss_1730.nav").read_bytes())
# What memsnav convert writes of walk_head.ubx as RINEX 4.00 navigation.
mn.read_ubx(here / "walk_head.ubx").write_rinex_nav(here / "walk.rnx")
pos = (walk / "gnss_1730_sf.pos").read_text().splitlines(keepends=True)
(here / "walk_head.pos").write_text("".join(pos[:30]))

drive = root / "drive_0708"
first, last = 3379, 9878
drive_log = (drive / "imu_1934.csv").read_bytes()
chunk = b"\n".join(drive_log.split(b"\n")[first - 1 : last]) + b"\n"
(here / "drive_60s.csv").write_bytes(chunk)
(here / "drive_60s.csv.tag").write_bytes(
    excerpt_tag((drive / "imu_1934.csv.tag").read_bytes(), drive_log, first, chunk)
)
log = readers.read_imu_csv(drive / "imu_1934.csv", skip_first_line=True)
gps, _ = readers.gps_time_from_tag(log, readers.read_time_tag(drive / "imu_1934.csv.tag"))
span = gps[np.isin(log.line, [first, last])]
sol = readers.read_pos(drive / "gnss_1934_sf.pos")
keep = (sol.gps_time >= span[0] - 1.0) & (sol.gps_time <= span[1] + 1.0)
pos = (drive / "gnss_1934_sf.pos").read_text().splitlines(keepends=True)
head = [s for s in pos if s.startswith("%")]
body = [s for s in pos if not s.startswith("%")]
(here / "drive_60s.pos").write_text(
    "".join(head + [b for b, k in zip(body, keep, strict=True) if k])
)

# ``walk_40s.*``: the first 40 s of the walk (9 s at rest, then walking),
# byte for byte: the IMU lines and their time-tag records, the RINEX
# observations and the RTK solution over the same span (tight coupling from
# a static start).
imu_log = readers.read_imu_csv(walk / "imu_1730.csv", skip_first_line=True)
walk_gps, _ = readers.gps_time_from_tag(imu_log, readers.read_time_tag(walk / "imu_1730.csv.tag"))
end_line = int(imu_log.line[np.searchsorted(walk_gps, walk_gps[0] + 40.0)])
walk_csv = b"\n".join(walk_log.split(b"\n")[:end_line]) + b"\n"
(here / "walk_40s.csv").write_bytes(walk_csv)
(here / "walk_40s.csv.tag").write_bytes(
    excerpt_tag((walk / "imu_1730.csv.tag").read_bytes(), walk_log, 1, walk_csv)
)


def rinex_epoch_gps_seconds(line: str) -> float:
    """GPS seconds of a RINEX 3 epoch line ``> yyyy mm dd hh mm ss.sssssss ...``."""
    y, mo, d, hh, mm, ss = (float(v) for v in line[1:].split()[:6])
    day = np.datetime64(f"{int(y):04d}-{int(mo):02d}-{int(d):02d}") - np.datetime64("1980-01-06")
    return day.astype(int) * 86400.0 + hh * 3600.0 + mm * 60.0 + ss


t_end = walk_gps[0] + 40.0
late = [i for i, s in enumerate(obs) if s.startswith(">") and rinex_epoch_gps_seconds(s) > t_end]
(here / "walk_40s.obs").write_text("".join(obs[: late[0]]))
walk_pos = (walk / "gnss_1730_sf.pos").read_text().splitlines(keepends=True)
walk_sol = readers.read_pos(walk / "gnss_1730_sf.pos")
n_head = sum(1 for s in walk_pos if s.startswith("%"))
n_body = int(np.searchsorted(walk_sol.gps_time, t_end, side="right"))
(here / "walk_40s.pos").write_text("".join(walk_pos[: n_head + n_body]))


def ubx_frames(log: bytes) -> list[tuple[int, int, bytes]]:
    """(class, id, whole frame) of every UBX frame with a good checksum."""
    frames, i = [], 0
    while (i := log.find(b"\xb5\x62", i)) >= 0 and i + 8 <= len(log):
        length = int.from_bytes(log[i + 4 : i + 6], "little")
        frame = log[i : i + 8 + length]
        a = b = 0
        for x in frame[2:-2]:
            a = (a + x) & 0xFF
            b = (b + a) & 0xFF
        if len(frame) == 8 + length and frame[-2:] == bytes([a, b]):
            frames.append((frame[2], frame[3], frame))
            i += len(frame)
        else:
            i += 1
    return frames


ubx = ubx_frames((walk / "gnss_1730.ubx").read_bytes())
rawx = [k for k, (c, m, _) in enumerate(ubx) if (c, m) == (0x02, 0x15)]
head_end = rawx[20]  # 20 epochs at 4 Hz
keep = [
    f
    for k, (c, m, f) in enumerate(ubx)
    if (k < head_end and (c, m) in ((0x02, 0x15), (0x01, 0x07)))
    or (
        (c, m) == (0x02, 0x13)
        and (f[6], f[8]) in ((0, 0), (0, 3), (0, 4), (0, 6), (0, 7), (2, 1), (3, 4))
    )
]
(here / "walk_head.ubx").write_bytes(b"".join(keep))
