"""A user's own drive through ``memsnav navigate``, written by hand the way a
user writes one: 1 Hz fixes as NMEA GGA + RMC without GST, an IMU CSV, 30 s
at rest at the start, two scheduled outages. The run must start in the
standstill (RMC's speed and course are the horizontal velocity they are; a
start from the IMU's own stillness when the GNSS has no velocity), score both
outages, and say where and why when it starts late; outage windows count in
the log's own time, and one outside the run is refused by name. The drive
is simulated here (``memsnav.Trajectory.from_segments``, car vibration on
the IMU) and every sentence's checksum is computed here."""

from __future__ import annotations

import datetime as dt
import functools
import json
from dataclasses import dataclass
from pathlib import Path

import numpy as np
import pytest

import memsnav as mn
from memsnav.realdata.answer import answer_lines

GPS_EPOCH = dt.datetime(1980, 1, 6)
LEAP_S = 18  # GPS − UTC since 2017-01-01 (IERS Bulletin C)
START_UTC = dt.datetime(2024, 3, 15, 12, 0, 0)
START_GPS_S = (START_UTC - GPS_EPOCH).total_seconds() + LEAP_S
STANDSTILL_S = 30.0
IMU_RATE_HZ = 50.0
TRUTH_RATE_HZ = 10.0
HDOP = 0.9
WINDOWS_S = [[200.0, 30.0], [450.0, 30.0]]
KNOTS_PER_M_S = 3600.0 / 1852.0


@dataclass(frozen=True)
class Drive:
    """The simulated drive: times from 0 (s), the IMU's readings (body
    axes, SI), the true geodetic position and NED velocity, and the 1 Hz
    fixes' noisy positions and speeds."""

    time: np.ndarray
    specific_force: np.ndarray
    angular_rate: np.ndarray
    geodetic: np.ndarray
    velocity_ned: np.ndarray
    fix: np.ndarray  # indices of the 1 Hz epochs
    fix_offset_ned: np.ndarray  # position noise, m
    fix_velocity_ne: np.ndarray  # RMC's north and east velocity, m/s


@functools.cache
def _drive(seed: int = 5) -> Drive:
    """590 s of a car: 30 s at rest, town and a fast stretch (28 m/s), a
    stop at the end; turn-on biases and vibration on the IMU (drive_0708's
    window stds, the navigate guide); fixes with 1 m (1.5 m vertical) of
    white noise, RMC velocity with 0.05 m/s per axis."""
    trajectory = mn.Trajectory.from_segments(
        [
            ("stop", STANDSTILL_S),
            ("accelerate", 10.0, 14.0),
            ("cruise", 60.0),
            ("turn", 10.0, 1.5),
            ("cruise", 60.0),
            ("accelerate", 10.0, 8.0),
            ("turn", 10.0, -1.5),
            ("cruise", 60.0),
            ("accelerate", 15.0, 28.0),
            ("cruise", 60.0),
            ("accelerate", 15.0, 14.0),
            ("turn", 10.0, 1.0),
            ("cruise", 100.0),
            ("turn", 10.0, -1.0),
            ("cruise", 80.0),
            ("accelerate", 10.0, 0.0),
            ("stop", 40.0),
        ],
        origin=[np.radians(48.1), np.radians(11.5), 520.0],
        rate=IMU_RATE_HZ,
    )
    t = trajectory.time - trajectory.time[0]
    rng = np.random.default_rng(seed)
    velocity = trajectory.velocity_ned()
    moving = np.linalg.norm(velocity, axis=1) > 0.05
    accel_std = np.where(moving, 0.5, 0.12)[:, None]
    gyro_std = np.radians(np.where(moving, 2.0, 0.5))[:, None]
    f = trajectory.specific_force + accel_std * rng.normal(size=(len(t), 3)) + [0.15, -0.1, 0.1]
    w = (
        trajectory.angular_rate
        + gyro_std * rng.normal(size=(len(t), 3))
        + np.radians([0.3, -0.2, 0.4])
    )
    fix = np.flatnonzero(np.abs(t - np.round(t)) < 1e-6)
    offset = rng.normal(size=(len(fix), 3)) * [1.0, 1.0, 1.5]
    v_ne = velocity[fix, :2] + 0.05 * rng.normal(size=(len(fix), 2))
    v_ne[~moving[fix]] = 0.0
    return Drive(t, f, w, trajectory.position_geodetic(), velocity, fix, offset, v_ne)


def _sentence(body: str) -> str:
    return f"${body}*{functools.reduce(lambda a, c: a ^ ord(c), body, 0):02X}"


def _angle(rad: float, digits: int, hemispheres: str) -> str:
    degrees = np.degrees(rad)
    sign = hemispheres[0] if degrees >= 0 else hemispheres[1]
    whole = int(abs(degrees))
    return f"{whole:0{digits}d}{(abs(degrees) - whole) * 60:09.6f},{sign}"


def _nmea(drive: Drive, *, speed: bool, from_s: float) -> str:
    """GGA (HDOP 0.9, geoid separation 47 m) and RMC at each fix from
    ``from_s``; RMC's speed in knots and course in degrees (at rest 0.00 and
    no course, as receivers give them), or both empty (``speed=False``)."""
    lines = []
    for k, i in enumerate(drive.fix):
        if drive.time[i] < from_s:
            continue
        lat, lon, h = drive.geodetic[i]
        dn, de, dd = drive.fix_offset_ned[k]
        lat += dn / 6378137.0
        lon += de / (6378137.0 * np.cos(lat))
        utc = START_UTC + dt.timedelta(seconds=float(drive.time[i]))
        hms = utc.strftime("%H%M%S.00")
        where = f"{_angle(lat, 2, 'NS')},{_angle(lon, 3, 'EW')}"
        gga = f"GPGGA,{hms},{where},1,09,{HDOP},{h - dd - 47.0:.2f},M,47.00,M,,"
        vn, ve = drive.fix_velocity_ne[k]
        if not speed:
            over_ground = ","
        elif vn == 0.0 and ve == 0.0:
            over_ground = "0.00,"
        else:
            knots = np.hypot(vn, ve) * KNOTS_PER_M_S
            over_ground = f"{knots:.2f},{np.degrees(np.arctan2(ve, vn)) % 360.0:.2f}"
        rmc = f"GPRMC,{hms},A,{where},{over_ground},{utc.strftime('%d%m%y')},,,A"
        lines += [_sentence(gga), _sentence(rmc)]
    return "\n".join(lines) + "\n"


def _write_log(folder: Path, *, speed: bool = True, from_s: float = 0.0, outages: str) -> Path:
    """The drive from ``from_s`` as files (imu.csv on GPS time, drive.nmea,
    truth.csv at 10 Hz) and a run configuration with ``outages`` (the
    ``[outages]`` table's lines); the configuration's path."""
    d = _drive()
    folder.mkdir(parents=True, exist_ok=True)
    keep = d.time >= from_s
    gps = START_GPS_S + d.time
    imu = np.column_stack([gps, d.specific_force, d.angular_rate])[keep]
    np.savetxt(folder / "imu.csv", imu, delimiter=",", fmt="%.6f", header="t,ax,ay,az,gx,gy,gz")
    (folder / "drive.nmea").write_text(_nmea(d, speed=speed, from_s=from_s))
    step = round(IMU_RATE_HZ / TRUTH_RATE_HZ)
    lat, lon, h = np.degrees(d.geodetic[:, 0]), np.degrees(d.geodetic[:, 1]), d.geodetic[:, 2]
    rows = [
        f"{gps[i]:.3f},{lat[i]:.10f},{lon[i]:.10f},{h[i]:.4f},0.01,0.01,0.01,1"
        for i in np.flatnonzero(keep)[::step]
    ]
    header = "gps_time_s,lat_deg,lon_deg,height_m,std_n_m,std_e_m,std_d_m,quality"
    (folder / "truth.csv").write_text("\n".join([header, *rows]) + "\n")
    config = folder / "run.toml"
    config.write_text(
        f"""
name = "own_drive"
output = "{folder / "out"}"
[imu]
file = "{folder / "imu.csv"}"
columns = ["t", "ax", "ay", "az", "gx", "gy", "gz"]
header_lines = 1
accel_unit = "m/s^2"
gyro_unit = "rad/s"
time_unit = "s"
time_reference = "column_gps"
[gnss]
mode = "loose"
pos = "{folder / "drive.nmea"}"
quality = [5]
[aids]
nhc = true
[truth]
pos = "{folder / "truth.csv"}"
quality = [1]
[report]
html = false
[outages]
{outages}
"""
    )
    return config


def _navigate(config: Path) -> dict:
    with pytest.warns(UserWarning, match="epoch.s. without GST"):
        mn.navigate(config)
    return json.loads((config.parent / "out" / "summary.json").read_text())


def test_an_nmea_drive_starts_in_its_standstill_and_scores_both_outages(tmp_path):
    windows = f"windows_s = {WINDOWS_S}"
    config = _write_log(tmp_path / "speed", outages=windows)
    with pytest.warns(UserWarning, match="without GST"):
        fixes = mn.read_nmea(tmp_path / "speed" / "drive.nmea")
    # RMC's speed and course: north and east, no vertical; zero at rest,
    # each with its σ (HDOP 0.9 × 0.1 m/s / √2 at least).
    d = _drive()
    rest = d.time[d.fix] < STANDSTILL_S
    assert np.all(np.isnan(fixes.velocity_ned[:, 2])) and np.all(fixes.velocity_ned[rest, :2] == 0)
    np.testing.assert_allclose(fixes.velocity_ned[:, :2], d.fix_velocity_ne, atol=0.01)
    assert np.all(fixes.velocity_std_ned[:, :2] >= HDOP * 0.1 / np.sqrt(2))
    assert np.all(np.isnan(fixes.velocity_std_ned[:, 2]))

    s = _navigate(config)
    start = s["start"]
    assert start["kind"] == "static" and start["late_reason"] is None
    # The first epoch with a second of IMU before it, inside the 30 s at rest.
    assert start["after_first_gnss_epoch_s"] == pytest.approx(1.0)
    assert start["after_first_gnss_epoch_s"] < STANDSTILL_S
    assert s["outages_s"] == WINDOWS_S
    errors = s["errors_vs_truth"]
    for k, (_, length) in enumerate(WINDOWS_S, start=1):
        # Every truth epoch in the window: its length at the truth's rate.
        assert abs(errors[f"outage_{k}"]["epochs"] - length * TRUTH_RATE_HZ) <= 1
        assert not errors[f"outage_{k}"]["at_standstill"]
    assert errors["by_outage_length_s"]["30"]["epochs"] == sum(
        errors[f"outage_{k}"]["epochs"] for k in (1, 2)
    )
    # The answer names the truth, then scores both outages.
    answer = answer_lines(s)
    assert answer[1] == "  truth: truth.csv"
    assert answer[2].startswith("  the 2 outages of 30 s: horizontal RMS")
    # The velocity reached the filter horizontally: two measurements (north,
    # east) at every epoch it used.
    velocity = s["measurements"]["velocity"]
    assert sum(velocity.values()) == 2 * s["gnss_epochs_used"]
    # The standstill at the start is found, the zero-velocity updates hold it.
    first_still = s["standstills_s"][0]
    assert first_still[0] < 2.0 and STANDSTILL_S - 2.0 < first_still[1] <= STANDSTILL_S

    # Without RMC's speed only position differences give a velocity (σ
    # 4.5 m/s: metre-class fixes a second apart), too noisy to show a
    # standstill: the IMU's stillness decides, and the run starts at rest.
    config = _write_log(tmp_path / "no_speed", speed=False, outages=windows)
    s = _navigate(config)
    assert s["start"]["kind"] == "static" and s["start"]["late_reason"] is None
    assert s["start"]["after_first_gnss_epoch_s"] == pytest.approx(1.0)
    assert "velocity" not in s["measurements"]
    errors = s["errors_vs_truth"]
    assert errors["outage_1"]["epochs"] > 0 and errors["outage_2"]["epochs"] > 0


def test_a_late_start_says_where_and_why_and_outages_keep_the_log_time(tmp_path):
    """The log cut to begin while driving at 14 m/s, RMC without speed: no
    rest and no course good enough (position differences, course σ above
    10° below 25 m/s) until the fast stretch. The run warns, summary.json
    says where and why, and the periodic windows are those of the log's own
    time that fit in the run; a window outside it is an error naming it."""
    every = "first_s = 10.0\nlength_s = 10.0\nevery_s = 50.0"
    config = _write_log(tmp_path / "late", speed=False, from_s=45.0, outages=every)
    with pytest.warns(UserWarning, match=r"the run starts [\d.]+ s after the log's first GNSS"):
        s = _navigate(config)
    start = s["start"]
    assert start["kind"] == "moving" and start["after_first_gnss_epoch_s"] > 100.0
    reason = start["late_reason"]
    assert "none was at rest" in reason and "a velocity only from position differences" in reason
    assert reason in s["warnings"]
    # The windows count from the first epoch with a second of IMU before it
    # (45 s + 1 s into the drive), not from the start.
    imu_time = np.loadtxt(tmp_path / "late" / "imu.csv", delimiter=",", skiprows=1)[:, 0]
    anchor = start["earliest_gps_time_s"]
    assert anchor == pytest.approx(imu_time[0] + 1.0)
    run_from, run_to = start["gps_time_s"] - anchor, imu_time[-1] - anchor
    expected = [
        [10.0 + 50.0 * k, 10.0]
        for k in range(20)
        if 10.0 + 50.0 * k >= run_from and 20.0 + 50.0 * k <= run_to
    ]
    assert s["outages_s"] == expected and len(expected) >= 4
    for window in ("[[100.0, 30.0]]", "[[300.0, 30.0], [500.0, 60.0]]"):
        refused = _write_log(tmp_path / "refused", speed=False, from_s=45.0, outages="")
        refused.write_text(refused.read_text() + f"windows_s = {window}\n")
        with pytest.raises(ValueError) as e, pytest.warns(UserWarning):
            mn.navigate(refused)
        message = str(e.value)
        name = "window 1 [100.0, 30.0]" if "100.0" in window else "window 2 [500.0, 60.0]"
        assert f"outages.windows_s: {name}" in message, message
        assert f"is not inside the run, which spans {run_from:.3f} to" in message, message


def test_the_answer_names_every_outage_and_how_many_were_scored():
    """Each outage length's line says how many of its windows it scores;
    a window no truth epoch falls in is named, not scored silently."""

    def stats(epochs: int, start: float, **more: object) -> dict[str, object]:
        return {
            "epochs": epochs,
            "rms_horizontal_m": 2.0 if epochs else float("nan"),
            "rms_vertical_m": 1.0 if epochs else float("nan"),
            "max_horizontal_m": 4.0 if epochs else float("nan"),
            "start_s": start,
            "length_s": 30.0,
            **more,
        }

    aided = stats(1000, 0.0)
    summary = {
        "name": "own",
        "mode": "loose",
        "duration_s": 590.0,
        "outages_s": [[200.0, 30.0], [450.0, 30.0]],
        "errors_vs_truth": {
            "aided": aided,
            "outage_1": stats(300, 200.0),
            "outage_2": stats(0, 450.0),
            "by_outage_length_s": {"30": stats(300, 0.0)},
        },
    }
    lines = answer_lines(summary)
    assert lines[1].startswith("  the 1 outage of 30 s scored (of 2): horizontal RMS 2 m")
    assert "  outage 2 (450 s): no truth epoch in it, not scored" in lines
    summary["errors_vs_truth"]["outage_1"] = stats(0, 200.0)
    summary["errors_vs_truth"]["by_outage_length_s"]["30"] = stats(0, 0.0)
    lines = answer_lines(summary)
    assert lines[1] == "  the 0 outages of 30 s scored (of 2): no errors to show"
    assert sum("no truth epoch in it, not scored" in line for line in lines) == 2


def test_a_log_that_begins_creeping_starts_at_its_first_course_without_a_warning(tmp_path):
    """The drive excerpt begins creeping below 1 m/s: no epoch at rest, an
    in-motion start at the first course, 1.5 s (6 epochs at 4 Hz) after the
    earliest start, which is not late (docs/how-to/own-logs.md tells the
    rule)."""
    from test_navigate import DATA, _config

    summary = mn.navigate(_config(tmp_path), data_root=DATA, duration_s=5.0).summary
    start = summary["start"]
    assert start["kind"] == "moving" and start["late_reason"] is None
    assert start["gps_time_s"] - start["earliest_gps_time_s"] == pytest.approx(1.5, abs=1e-3)
