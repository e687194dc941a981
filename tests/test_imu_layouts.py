"""A log from another IMU and receiver, in its own layout, runs from a
configuration with no conversion script: a
simulated drive written as memsnav's native files (IMU rates in FRD, an
RTKLIB ``.pos``, the simulation's pseudoranges) and as another system's
(IMU increments in FLU axes, degrees and g·s, columns in its own order
named by its header, jittered stamps and a gap; the fixes CSV with
covariance; NMEA; the long raw table ``memsnav simulate`` writes), each
run through ``memsnav.navigate``, gives the native solution.

The increments are the native rates times each interval, the native
samples sit at the middles of the intervals (where the reader puts the
mean rates of increments): the same log twice, so the solutions agree to
the rounding of the conversions: 1e-9 m (a few ulps of a 4 600 km ECEF
coordinate) with the fixes CSV and the long table, 1e-8 m with NMEA,
whose degrees-and-minutes take another float path."""

from __future__ import annotations

import math
from pathlib import Path

import numpy as np
import pytest
from test_fix_readers import _nmea_epoch

import memsnav as mn
from memsnav.realdata.readers import write_pos

# GPS time of the start: 2025-08-28 (week 2381, Thursday) 17:30:00.
T0 = 2381 * 604_800.0 + 4 * 86_400.0 + 63_000.0
DURATION_S = 60.0
STANDARD_GRAVITY = 9.80665

COMMON = """
name = "{name}"
output = "{out}"
[imu]
file = "{imu}"
time_reference = "column_gps"
time_unit = "s"
{imu_layout}
[gnss]
{gnss}
quality = [1]
[report]
html = false
"""
NATIVE_IMU = """
accel_unit = "m/s^2"
gyro_unit = "rad/s"
columns = ["t", "ax", "ay", "az", "gx", "gy", "gz"]
header_lines = 1
"""
FOREIGN_IMU = """
accel_unit = "g*s"
gyro_unit = "deg"
axes = "FLU"
header_lines = 2
[imu.columns]
t = "gps_time_s"
ax = "dvel_fwd"
ay = "dvel_left"
az = "dvel_up"
gx = "dang_fwd"
gy = "dang_left"
gz = "dang_up"
"""


@pytest.fixture(scope="module")
def logs(tmp_path_factory) -> dict[str, object]:
    """The drive's files in both layouts."""
    folder = tmp_path_factory.mktemp("layouts")
    trajectory = mn.Trajectory.random(DURATION_S, seed=7, stationary_start=10.0)
    tau = trajectory.time
    rng = np.random.default_rng(8)
    # The other IMU's stamps: the ends of its intervals, half a sample after
    # the trajectory's grid, jittered by ±2 ms, rows 3001-3003 lost (the
    # IMU integrated across: one row covers the gap).
    stamps = T0 + tau - 0.005 + rng.uniform(-0.002, 0.002, len(tau))
    stamps = np.append(stamps, stamps[-1] + 0.01)
    stamps = np.delete(stamps, [3001, 3002, 3003])
    dt = np.diff(stamps)
    middle = stamps[:-1] + 0.5 * dt  # the reader's sample times, same float ops
    f = np.column_stack(
        [np.interp(middle - T0, tau, trajectory.specific_force[:, i]) for i in range(3)]
    )
    w = np.column_stack(
        [np.interp(middle - T0, tau, trajectory.angular_rate[:, i]) for i in range(3)]
    )
    native_imu = folder / "imu_native.csv"
    np.savetxt(
        native_imu,
        np.column_stack([middle, f, w]),
        delimiter=",",
        header="t,ax,ay,az,gx,gy,gz",
        comments="",
        fmt="%.17g",
    )
    flu = np.array([1.0, -1.0, -1.0])
    dv_gs = np.vstack([np.zeros(3), f * dt[:, None] * flu / STANDARD_GRAVITY])
    da_deg = np.vstack([np.zeros(3), np.degrees(w * dt[:, None]) * flu])
    foreign_imu = folder / "imu_increments.csv"
    rows = np.column_stack([stamps, da_deg[:, 2], dv_gs[:, 0], da_deg[:, 0], dv_gs[:, 2]])
    rows = np.column_stack([rows, da_deg[:, 1], dv_gs[:, 1], np.full(len(stamps), 21.5)])
    np.savetxt(
        foreign_imu,
        rows,
        delimiter=",",
        header=(
            "# exported by another logger\n"
            "# columns: its own order; increments since the previous row\n"
            "gps_time_s,dang_up,dvel_fwd,dang_fwd,dvel_up,dang_left,dvel_left,temp_c"
        ),
        comments="",
        fmt="%.17g",
    )
    # Fixes at 1 Hz from the truth, positions on 1e-7 degree (what NMEA's
    # 6-decimal minutes hold exactly), 0.5 m / 0.1 m/s.
    k = np.arange(100, len(tau) - 100, 100)
    lla = trajectory.position_geodetic()[k]
    lla[:, :2] = np.radians(np.round(np.degrees(lla[:, :2]), 7))
    pos = folder / "fixes.pos"
    write_pos(
        pos,
        T0 + tau[k],
        lla,
        np.full((len(k), 3), 0.5),
        trajectory.velocity_ned()[k],
        np.full((len(k), 3), 0.1),
        quality=1,
    )
    gnss = mn.simulate_gnss(
        T0 + tau,
        trajectory.position_ecef,
        trajectory.velocity_ecef,
        mn.Constellation.walker(),
        seed=9,
        start_gps_time=T0 + tau[0],
    )
    return {
        "folder": folder,
        "native_imu": native_imu,
        "foreign_imu": foreign_imu,
        "pos": pos,
        "gnss": gnss,
        "middle": middle,
        "f": f,
        "w": w,
    }


def _navigate(logs: dict, name: str, imu: str, gnss: str) -> mn.LogRun:
    folder = logs["folder"]
    assert isinstance(folder, Path)
    native = imu == "native"
    cfg = folder / f"{name}.toml"
    cfg.write_text(
        COMMON.format(
            name=name,
            out=folder / name,
            imu=logs["native_imu" if native else "foreign_imu"],
            imu_layout=NATIVE_IMU if native else FOREIGN_IMU,
            gnss=gnss,
        )
    )
    return mn.navigate(cfg).run


def _largest_difference(a: mn.LogRun, b: mn.LogRun) -> float:
    assert len(a) == len(b)
    np.testing.assert_array_equal(a.time, b.time)
    return float(
        max(
            np.max(np.abs(np.asarray(a.position_ecef) - b.position_ecef)),
            np.max(np.abs(np.asarray(a.velocity_ned) - b.velocity_ned)),
        )
    )


def test_increments_in_flu_are_the_native_rates(logs):
    """The reader turns the other IMU's increments into the native samples:
    times bitwise, rates and forces to a few ulps."""
    log = mn.read_imu_csv(
        logs["foreign_imu"],
        {"t": "gps_time_s", "ax": "dvel_fwd", "ay": "dvel_left", "az": "dvel_up"}
        | {"gx": "dang_fwd", "gy": "dang_left", "gz": "dang_up"},
        accel_unit="g*s",
        gyro_unit="deg",
        time_unit="s",
        axes="FLU",
        header_lines=2,
    )
    np.testing.assert_array_equal(log.time, logs["middle"])
    np.testing.assert_allclose(log.specific_force, logs["f"], rtol=1e-14, atol=1e-14)
    np.testing.assert_allclose(log.angular_rate, logs["w"], rtol=1e-14, atol=1e-16)
    timing = log.timing
    # The lost rows: one gap of 4 intervals, closed by the row that follows
    # row 3000 (two comment lines and the header before row 0 on line 4).
    assert timing["gap_count"] == 1
    assert timing["largest_gap_line"] == 4 + 3001
    assert 0.036 < timing["largest_gap_s"] < 0.044
    assert 0.9e-3 < timing["interval_std_s"] < 1.8e-3  # ±2 ms uniform: 1.6 ms


def test_foreign_log_runs_from_a_configuration_to_the_native_solution(logs):
    """Loose coupling from the fixes CSV with covariance (the .pos's own
    digits and values), the foreign IMU, against the .pos and the native
    IMU; and the run's summary reports the gap."""
    pos = logs["pos"]
    native = mn.read_pos(pos)
    rows = [
        line.split()
        for line in Path(pos).read_text().splitlines()
        if line.strip() and not line.startswith("%")
    ]
    header = (
        "gps_week,gps_tow_s,lat_deg,lon_deg,height_m,cov_nn_m2,cov_ne_m2,cov_nd_m2,cov_ee_m2,"
        "cov_ed_m2,cov_dd_m2,vn_m_s,ve_m_s,vd_m_s,std_vn_m_s,std_ve_m_s,std_vd_m_s,quality"
    )
    lines = [header]
    for k, f in enumerate(rows):
        t = float(native.gps_time[k])
        week = int(t // 604800)
        sn, se, su = (float(x) for x in f[7:10])
        cov = [sn * sn, 0.0, 0.0, se * se, 0.0, su * su]
        v, sv = native.velocity_ned[k], native.velocity_std_ned[k]
        lines.append(
            ",".join(
                [str(week), repr(t - week * 604800), f[2], f[3], f[4]]
                + [repr(c) for c in cov]
                + [repr(float(x)) for x in (*v, *sv)]
                + [str(int(float(f[5])))]
            )
        )
    csv = logs["folder"] / "fixes.csv"
    csv.write_text("\n".join(lines) + "\n")
    want = _navigate(logs, "native_loose", "native", f'mode = "loose"\npos = "{pos}"')
    got = _navigate(logs, "foreign_loose", "foreign", f'mode = "loose"\npos = "{csv}"')
    assert _largest_difference(got, want) <= 1e-9
    summary = (logs["folder"] / "foreign_loose" / "summary.json").read_text()
    assert '"gap_count": 1' in summary


def test_foreign_nmea_runs_to_the_native_solution(logs):
    """NMEA GGA + RMC + GST of the same fixes (geoid separation 0: the
    heights pass unchanged; the 1e-7 degree positions exact in 6-decimal
    minutes): to 1e-8 m, ten ulps of a 4 600 km ECEF coordinate, for the
    degrees-plus-minutes/60 of NMEA's latitudes and longitudes round
    differently from the .pos's degrees (1 ulp of the angle is 0.7 nm);
    both without velocity (NMEA has no vertical velocity)."""
    from decimal import Decimal

    pos = logs["pos"]
    rows = [
        line.split()
        for line in Path(pos).read_text().splitlines()
        if line.strip() and not line.startswith("%")
    ]
    nmea = logs["folder"] / "fixes.nmea"
    nmea.write_text("\n".join(s for f in rows for s in _nmea_epoch(f, Decimal(0))) + "\n")
    no_velocity = "use_velocity = false"
    want = _navigate(logs, "native_nmea", "native", f'mode = "loose"\npos = "{pos}"\n{no_velocity}')
    got = _navigate(
        logs, "foreign_nmea", "foreign", f'mode = "loose"\npos = "{nmea}"\n{no_velocity}'
    )
    assert _largest_difference(got, want) <= 1e-8


def test_foreign_raw_table_runs_to_the_native_solution(logs):
    """Tight coupling from the long table (one row per epoch and satellite,
    the columns ``memsnav simulate`` writes, with σ) and the foreign IMU,
    against the simulation's measurements handed to the engine with the
    native IMU log."""
    gnss = logs["gnss"]
    epoch, slot = np.nonzero(gnss.sat_id >= 0)
    columns = {
        "time_s": gnss.time[epoch],
        "gps_time_s": gnss.gps_time[epoch],
        "sat_id": gnss.sat_id[epoch, slot],
        **{
            f"sat_position_ecef_{a}_m": gnss.satellite_position_ecef[epoch, slot, i]
            for i, a in enumerate("xyz")
        },
        **{
            f"sat_velocity_ecef_{a}_m_s": gnss.satellite_velocity_ecef[epoch, slot, i]
            for i, a in enumerate("xyz")
        },
        "pseudorange_m": gnss.pseudorange[epoch, slot],
        "pseudorange_rate_m_s": gnss.pseudorange_rate[epoch, slot],
        "pseudorange_std_m": gnss.pseudorange_std[epoch, slot],
        "pseudorange_rate_std_m_s": gnss.pseudorange_rate_std[epoch, slot],
    }
    table = logs["folder"] / "gnss.csv"
    np.savetxt(
        table,
        np.column_stack(list(columns.values())),
        delimiter=",",
        header=",".join(columns),
        comments="",
        fmt="%.17g",
    )
    got = _navigate(logs, "foreign_tight", "foreign", f'mode = "tight"\ntable = "{table}"')
    imu = np.loadtxt(logs["native_imu"], delimiter=",", skiprows=1)
    want = mn.navigate_log(imu[:, 0], imu[:, 1:4], imu[:, 4:7], gnss)
    assert _largest_difference(got, want) <= 1e-9
    assert not math.isnan(float(np.asarray(got.position_ecef)[-1, 0]))


@pytest.mark.parametrize(
    ("layout", "message"),
    [
        # An unknown key of [imu]: named, with the key meant (the core's
        # known_keys rule).
        (FOREIGN_IMU.replace("axes =", "axis ="), r"unknown key\(s\) \['axis'\] in \[imu\] "),
        (FOREIGN_IMU.replace("axes =", "axis ="), r"'axis': did you mean 'axes'\?"),
        # An unknown quantity in [imu.columns].
        (FOREIGN_IMU.replace("gz =", "gzz ="), r'unknown key "gzz" \(did you mean "gz"\?\)'),
        # A header name the file lacks: the file and its header line.
        (
            FOREIGN_IMU.replace('"dang_up"', '"dang_upp"'),
            r'imu_increments.csv:3: columns.gz: the header has no column "dang_upp" '
            r'\(did you mean "dang_up"\?\)',
        ),
        (FOREIGN_IMU.replace('"FLU"', '"FUL"'), r'imu.axes: unknown axis convention "FUL"'),
        (
            FOREIGN_IMU.replace('"FLU"', "[[1, 0, 0], [0, 1, 0], [0, 0, 2]]"),
            r"imu.axes: is not a rotation matrix",
        ),
        (FOREIGN_IMU.replace('"deg"', '"deg/s"'), r"imu.accel_unit, gyro_unit: the accelerometer"),
        (FOREIGN_IMU.replace("gx = ", "gx = 3 #"), r"imu.columns: give every quantity by header"),
    ],
)
def test_imu_layout_errors_name_the_key(logs, layout, message):
    folder = logs["folder"]
    cfg = folder / "bad.toml"
    cfg.write_text(
        COMMON.format(
            name="bad",
            out=folder / "bad",
            imu=logs["foreign_imu"],
            imu_layout=layout,
            gnss=f'mode = "loose"\npos = "{logs["pos"]}"',
        )
    )
    with pytest.raises(ValueError, match=message):
        mn.navigate(cfg)


def test_increments_by_column_number_and_rotation_matrix(logs, tmp_path):
    """The same increments read by 1-based column numbers with the FLU
    axes given as a matrix: the same samples."""
    by_name = mn.read_imu_csv(
        logs["foreign_imu"],
        {"t": "gps_time_s", "ax": "dvel_fwd", "ay": "dvel_left", "az": "dvel_up"}
        | {"gx": "dang_fwd", "gy": "dang_left", "gz": "dang_up"},
        accel_unit="g*s",
        gyro_unit="deg",
        time_unit="s",
        axes="FLU",
        header_lines=2,
    )
    by_number = mn.read_imu_csv(
        logs["foreign_imu"],
        {"t": 1, "gz": 2, "ax": 3, "gx": 4, "az": 5, "gy": 6, "ay": 7},
        accel_unit="g*s",
        gyro_unit="deg",
        time_unit="s",
        axes=np.diag([1.0, -1.0, -1.0]),
        header_lines=3,
    )
    np.testing.assert_array_equal(by_number.time, by_name.time)
    np.testing.assert_array_equal(by_number.angular_rate, by_name.angular_rate)
    np.testing.assert_array_equal(by_number.specific_force, by_name.specific_force)
    with pytest.raises(ValueError, match=r'columns: "gz" = 0: columns are numbered from 1'):
        mn.read_imu_csv(
            logs["foreign_imu"],
            {"t": 1, "gz": 0, "ax": 3, "gx": 4, "az": 5, "gy": 6, "ay": 7},
            accel_unit="g*s",
            gyro_unit="deg",
            time_unit="s",
        )
