"""Regenerates the excerpts in this folder from the full logs
(``python make_excerpts.py DATA_ROOT``; DATA_ROOT holds real-imu-gnss/).

- ``walk_head.*``: the first lines/records/epochs of the walk_0827 files,
  byte for byte (reader tests), ``walk.nav`` the whole navigation file.
- ``drive_60s.csv``: 65 s of raw drive_0708 IMU lines around the first
  motion, byte for byte; ``drive_60s.csv.tag``: the original tag header
  and one record (tick, offset 0) that gives the excerpt's first line the
  GPS time the full log's tag assigns it (RTKLIB tags are relative to the
  start of the whole file, so a cut file needs its own);
  ``drive_60s.pos``: the RTK solution over the same span.
"""

import struct
import sys
from pathlib import Path

import numpy as np

from memsnav.realdata import readers

root = Path(sys.argv[1]) / "real-imu-gnss"
here = Path(__file__).parent
walk = root / "walk_0827"
(here / "walk_head.csv").write_bytes(
    b"\n".join((walk / "imu_1730.csv").read_bytes().split(b"\n")[:40]) + b"\n0.01"
)
(here / "walk_head.csv.tag").write_bytes((walk / "imu_1730.csv.tag").read_bytes()[: 76 + 8 * 20])
obs = (walk / "gnss_1730.obs").read_text().splitlines(keepends=True)
end = [i for i, s in enumerate(obs) if s.startswith(">")][4]
(here / "walk_head.obs").write_text("".join(obs[:end]))
(here / "walk.nav").write_bytes((walk / "gnss_1730.nav").read_bytes())
pos = (walk / "gnss_1730_sf.pos").read_text().splitlines(keepends=True)
(here / "walk_head.pos").write_text("".join(pos[:30]))

drive = root / "drive_0708"
log = readers.read_imu_csv(drive / "imu_1934.csv", skip_first_line=True)
tag = readers.read_time_tag(drive / "imu_1934.csv.tag")
gps, _ = readers.gps_time_from_tag(log, tag)
sol = readers.read_pos(drive / "gnss_1934_sf.pos")
t_move = sol.gps_time[np.argmax(np.hypot(sol.velocity_ned[:, 0], sol.velocity_ned[:, 1]) > 3.0)]
sel = np.nonzero((gps >= t_move - 5.0) & (gps <= t_move + 60.0))[0]
lines = (drive / "imu_1934.csv").read_bytes().split(b"\n")
chunk = b"\n".join(lines[log.line[sel[0]] - 1 : log.line[sel[-1]]]) + b"\n"
(here / "drive_60s.csv").write_bytes(chunk)
raw = (drive / "imu_1934.csv.tag").read_bytes()
# First line's newline is at its length; it arrives at the mapped time.
tick = round((gps[sel[0]] - tag.start_gps_time) * 1000.0)
(here / "drive_60s.csv.tag").write_bytes(raw[:76] + struct.pack("<II", tick, 0))
keep = (sol.gps_time >= gps[sel[0]] - 1.0) & (sol.gps_time <= gps[sel[-1]] + 1.0)
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
walk_tag = readers.read_time_tag(walk / "imu_1730.csv.tag")
walk_gps, _ = readers.gps_time_from_tag(imu_log, walk_tag)
end_line = int(imu_log.line[np.searchsorted(walk_gps, walk_gps[0] + 40.0)])
walk_lines = (walk / "imu_1730.csv").read_bytes().split(b"\n")
walk_csv = b"\n".join(walk_lines[:end_line]) + b"\n"
(here / "walk_40s.csv").write_bytes(walk_csv)
walk_raw = (walk / "imu_1730.csv.tag").read_bytes()
records = np.frombuffer(walk_raw[76:], dtype="<u4").reshape(-1, 2)
n_records = int(np.searchsorted(records[:, 1], len(walk_csv), side="right"))
(here / "walk_40s.csv.tag").write_bytes(walk_raw[: 76 + 8 * n_records])


def rinex_epoch_gps_seconds(line: str) -> float:
    """GPS seconds of a RINEX 3 epoch line ``> yyyy mm dd hh mm ss.sssssss ...``."""
    y, mo, d, hh, mm, ss = line[1:].split()[:6]
    return readers._gps_seconds(f"{y}/{mo}/{d}", f"{hh}:{mm}:{ss}")


t_end = walk_gps[0] + 40.0
late = [i for i, s in enumerate(obs) if s.startswith(">") and rinex_epoch_gps_seconds(s) > t_end]
(here / "walk_40s.obs").write_text("".join(obs[: late[0]]))
walk_pos = (walk / "gnss_1730_sf.pos").read_text().splitlines(keepends=True)
walk_sol = readers.read_pos(walk / "gnss_1730_sf.pos")
n_head = sum(1 for s in walk_pos if s.startswith("%"))
n_body = int(np.searchsorted(walk_sol.gps_time, t_end, side="right"))
(here / "walk_40s.pos").write_text("".join(walk_pos[: n_head + n_body]))
