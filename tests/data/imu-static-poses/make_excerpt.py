"""Writes xsens_excerpt.csv.gz: the first 262 s of the Xsens multi-position
session of ../shared/data/imu-static-poses (the 50 s rest and 19 poses), as
integer counts: t_ms, accel x y z, gyro x y z (the raw logs hold integers).

Run: python tests/data/imu-static-poses/make_excerpt.py DATA_ROOT (the
folder that holds imu-static-poses/, e.g. ../shared/data).
"""

import gzip
import sys
from pathlib import Path

import numpy as np

SOURCE = Path(sys.argv[1]) / "imu-static-poses"
OUT = Path(__file__).resolve().parent / "xsens_excerpt.csv.gz"

accel = np.loadtxt(SOURCE / "xsens_acc.mat")
gyro = np.loadtxt(SOURCE / "xsens_gyro.mat")
assert np.array_equal(accel[:, 0], gyro[:, 0])
keep = accel[:, 0] < 262.0
rows = np.column_stack([np.round(accel[keep, 0] * 1e6), accel[keep, 1:], gyro[keep, 1:]])
assert np.array_equal(rows[:, 1:], np.round(rows[:, 1:]))
with gzip.open(OUT, "wt") as f:
    f.write("# t_us,ax,ay,az,gx,gy,gz (raw counts)\n")
    np.savetxt(f, rows.astype(np.int64), fmt="%d", delimiter=",")
print(OUT, keep.sum(), "rows")
