"""Real-data readers, on excerpts of the
BSD-3 real-imu-gnss logs kept in tests/data/real-imu-gnss (LICENSE there)."""

from __future__ import annotations

import struct
import warnings
from pathlib import Path

import numpy as np
import pytest

import memsnav as mn

DATA = Path(__file__).parent / "data"
EX = DATA / "real-imu-gnss"
G = 9.80665
C = 299_792_458.0
GPS_WEEK_2381_THURSDAY = 2381 * 604_800.0 + 4 * 86_400.0


# --- IMU CSV -------------------------------------------------------------


def test_imu_csv_fields_units_and_cut_lines():
    with pytest.warns(UserWarning, match=r"walk_head.csv:41: last line cut short \(no end of line"):
        log = mn.read_imu_csv(EX / "walk_head.csv", skip_first_line=True)
    assert len(log.time) == 39  # 40 lines (the first skipped) and the cut "0.01" dropped
    # Second line of the file: -0.017,-0.007,1.011,0.038,-0.160,0.160,3326345
    np.testing.assert_allclose(log.specific_force[0], np.array([-0.017, -0.007, 1.011]) * G)
    np.testing.assert_allclose(log.angular_rate[0], np.radians([0.038, -0.160, 0.160]))
    assert log.time[0] == pytest.approx(3326.345)
    assert log.line[0] == 2
    # Line 4: -0.018,-0.006,1.012,0.099,-0.153,0.183,3326357
    np.testing.assert_allclose(log.specific_force[2], np.array([-0.018, -0.006, 1.012]) * G)
    assert log.time[2] == pytest.approx(3326.357)


def test_imu_csv_other_layout_and_units(tmp_path):
    p = tmp_path / "imu.csv"
    p.write_text("t,gx,gy,gz,ax,ay,az,temp\n0.00,0.1,0.2,0.3,1,2,9,25\n0.01,0.1,0.2,0.3,1,2,9,25\n")
    log = mn.read_imu_csv(
        p,
        ["t", "gx", "gy", "gz", "ax", "ay", "az", "temp"],
        accel_unit="m/s^2",
        gyro_unit="rad/s",
        time_unit="s",
        header_lines=1,
    )
    np.testing.assert_allclose(log.specific_force, [[1, 2, 9]] * 2)
    np.testing.assert_allclose(log.angular_rate, [[0.1, 0.2, 0.3]] * 2)
    np.testing.assert_allclose(log.time, [0.0, 0.01])


def test_imu_csv_bad_files_name_file_and_line(tmp_path):
    p = tmp_path / "bad.csv"
    p.write_text("1,2,3,4,5,6,0\n1,2,3,4,5,10\n1,2,3,4,5,6,20\n")
    with pytest.raises(
        mn.ParseError, match=r"bad.csv:2: expected 7 comma-separated fields .* got 6"
    ):
        mn.read_imu_csv(p)
    p.write_text("1,2,3,4,5,6,0\n1,2,x,4,5,6,10\n1,2,3,4,5,6,20\n")
    with pytest.raises(mn.ParseError, match=r"bad.csv:2: column 3 \(az\): expected a finite"):
        mn.read_imu_csv(p)
    p.write_text("1,2,3,4,5,6,10\n1,2,3,4,5,6,10\n1,2,3,4,5,6,20\n")
    with pytest.raises(mn.ParseError, match=r"bad.csv:2: time 10 repeats the previous line"):
        mn.read_imu_csv(p)
    with pytest.raises(ValueError, match=r"accel_unit: unknown unit 'gee'"):
        mn.read_imu_csv(p, accel_unit="gee")
    with pytest.raises(ValueError, match=r"gyro_unit"):
        mn.read_imu_csv(p, gyro_unit="dps")
    with pytest.raises(ValueError, match=r"columns: the layout lacks \[\"t\"\]"):
        mn.read_imu_csv(p, ["ax", "ay", "az", "gx", "gy", "gz", "time"])


def test_imu_csv_magnitudes_that_do_not_fit_the_units_warn(tmp_path):
    # A gyro in °/s declared as rad/s ran to kilometres silently;
    # 1e308 g became inf.
    p = tmp_path / "imu.csv"
    p.write_text("".join(f"0,0,1,0,0,{30 if k > 50 else 0},{10 * k}\n" for k in range(100)))
    with pytest.warns(UserWarning, match=r'imu.csv: gyro_unit: .* is gyro_unit "deg/s"\?'):
        mn.read_imu_csv(p, gyro_unit="rad/s")
    p.write_text("".join(f"0,0,9.81,0,0,0,{10 * k}\n" for k in range(10)))
    with pytest.warns(UserWarning, match=r'accel_unit: .* is accel_unit "m/s\^2"\?'):
        mn.read_imu_csv(p)
    p.write_text("0,0,1,0,0,0,0\n0,0,1e308,0,0,0,10\n0,0,1,0,0,0,20\n")
    with pytest.raises(mn.ParseError, match=r"imu.csv:2: column 3 \(az\): 1e308 g is out of range"):
        mn.read_imu_csv(p)
    with pytest.raises(ValueError, match=r"header_lines: must be >= 0, got -5"):
        mn.read_imu_csv(p, header_lines=-5)


# --- RTKLIB time tags and .pos --------------------------------------------


def test_time_tag_header_and_records():
    raw = (EX / "walk_head.csv.tag").read_bytes()
    tag = mn.read_time_tag(EX / "walk_head.csv.tag")
    seconds, _ = struct.unpack_from("<Id", raw, 64)  # written by RTKLIB's strfile
    assert seconds == 1756402240  # 2025-08-28 17:30:40 GPST as a 1970-based count
    assert tag.start_gps_time == pytest.approx(1756402240 - 315964800 + 0.961, abs=1e-9)
    assert tag.start_tick_ms == struct.unpack_from("<I", raw, 60)[0]
    assert len(tag.tick_ms) == (len(raw) - 76) // 8 == 16
    assert (tag.tick_ms[0], tag.file_offset[0]) == (113, 835)
    assert (tag.tick_ms[2], tag.file_offset[2]) == (128, 943)
    # RTKLIB records the file position after each write: bytes 0-834 came
    # with the first write (tick 113 ms), byte 900 with the third (128 ms).
    t = tag.arrival_gps_time(np.array([0, 834, 900, 10**6, -1]))
    assert t[0] == t[1] == pytest.approx(tag.start_gps_time + 0.113)
    assert t[2] == pytest.approx(tag.start_gps_time + 0.128)
    assert np.isnan(t[3]) and np.isnan(t[4])


def test_time_tags_count_the_crlf_line_ends_of_the_excerpts():
    # The logger wrote CR LF; the files keep LF: a tag's last position is
    # the file size plus its number of newlines.
    for name, skip in [("walk_head.csv", True), ("drive_60s.csv", False)]:
        raw = (EX / name).read_bytes()
        tag = mn.read_time_tag(EX / f"{name}.tag")
        assert tag.file_offset[-1] == len(raw) + raw.count(b"\n")
        with warnings.catch_warnings():
            warnings.simplefilter("ignore")  # walk_head's cut last line
            log = mn.read_imu_csv(EX / name, skip_first_line=skip)
        clock = mn.fit_tag_clock(log, tag)
        assert clock.line_ends == "crlf_counted"
        assert clock.tagged_samples == len(log)
        # Every sample arrives after it was taken, at the minimum latency
        # on the fitted line.
        end = log.line_end_offset + 1 + log.line
        lag = tag.arrival_gps_time(end - 1) - clock.gps_time
        assert lag.min() == pytest.approx(0.0, abs=1e-6)
        assert clock.arrival_lag_spread_s == pytest.approx(lag.max(), abs=1e-6)
    # drive_60s: within 40 ms, the IMU clock within 100 ppm of the logger's.
    assert clock.arrival_lag_spread_s < 0.04 and abs(clock.rate_ppm) < 100.0
    gps, spread = mn.realdata.readers.gps_time_from_tag(log, tag)
    np.testing.assert_array_equal(gps, clock.gps_time)
    assert spread == clock.arrival_lag_spread_s
    # Counted as LF alone the lines seem to arrive later and later (the
    # "12.2 s drift" of the full drive): the rate says the tag is misread.
    with pytest.warns(UserWarning, match=r"ppm off the logger's clock"):
        wrong = mn.fit_tag_clock(log, tag, line_ends="as_in_file")
    assert wrong.rate_ppm < -10_000.0
    with pytest.raises(ValueError, match=r"line_ends: unknown convention 'lf'"):
        mn.fit_tag_clock(log, tag, line_ends="lf")


def test_time_tag_and_log_that_do_not_belong_together():
    log = mn.read_imu_csv(EX / "drive_60s.csv")
    tag = mn.read_time_tag(EX / "walk_head.csv.tag")
    with pytest.raises(ValueError, match=r"tag: the time tag's last file position \(1916\) fits"):
        mn.fit_tag_clock(log, tag)


def test_time_tag_bad_file(tmp_path):
    p = tmp_path / "x.tag"
    p.write_bytes(b"NOT A TAG" + bytes(80))
    with pytest.raises(mn.ParseError, match=r"x.tag: byte 0: expected the header 'TIMETAG RTKLIB"):
        mn.read_time_tag(p)


def test_pos_fields():
    sol = mn.read_pos(EX / "walk_head.pos")
    # 2025/08/28 17:30:39.749 40.0966916 -105.1471665 1601.4350000 1 25
    # 0.0098995 0.0098995 0.0100000
    # ... vn 0.001 ve -0.002 vu 0.027, sdv 0.0494975 x3
    assert sol.gps_time[0] == pytest.approx(GPS_WEEK_2381_THURSDAY + 17 * 3600 + 30 * 60 + 39.749)
    np.testing.assert_allclose(
        sol.lla[0], [np.radians(40.0966916), np.radians(-105.1471665), 1601.435]
    )
    assert sol.quality[0] == 1 and sol.n_satellites[0] == 25
    np.testing.assert_allclose(sol.std_ned[0], [0.0098995, 0.0098995, 0.01])
    np.testing.assert_allclose(sol.velocity_ned[0], [0.001, -0.002, -0.027])
    np.testing.assert_allclose(sol.velocity_std_ned[0], [0.0494975] * 3)


def test_pos_bad_and_cut_lines(tmp_path):
    text = (EX / "walk_head.pos").read_text()
    p = tmp_path / "cut.pos"
    p.write_text(text[:-40])
    with pytest.warns(UserWarning, match=r"cut.pos:\d+: last line cut short \(no end of line"):
        sol = mn.read_pos(p)
    assert len(sol.gps_time) == len(mn.read_pos(EX / "walk_head.pos").gps_time) - 1
    lines = text.splitlines()
    k = next(i for i, s in enumerate(lines) if not s.startswith("%"))
    lines[k + 1] = lines[k + 1].replace("1601.", "16x1.")
    p.write_text("\n".join(lines) + "\n")
    with pytest.raises(
        mn.ParseError, match=rf"cut.pos:{k + 2}: field 5 \(height\(m\)\): expected a finite number"
    ):
        mn.read_pos(p)


# --- RINEX -----------------------------------------------------------------


def test_rinex_obs_fields():
    obs = mn.read_rinex_obs(EX / "walk_head.obs")
    assert len(obs) == 4 and obs.warnings == []
    assert obs.observation_types["G"] == ["C1C", "L1C", "D1C", "S1C", "C2L", "L2L", "D2L", "S2L"]
    assert obs.observation_types["E"] == ["C1C", "L1C", "D1C", "S1C"]
    np.testing.assert_allclose(
        obs.approx_position_ecef, [-1276965.2487, -4717231.7278, 4087230.1460]
    )
    t = obs.time
    assert t[0] == pytest.approx(GPS_WEEK_2381_THURSDAY + 17 * 3600 + 30 * 60 + 39.748, abs=1e-6)
    assert t[1] - t[0] == pytest.approx(0.25, abs=1e-6)
    j = obs.satellites.index("G10")
    assert obs.observation("C1C")[0, j] == 20576396.770
    assert obs.observation("D1C")[0, j] == 1064.326
    assert obs.observation("S1C")[0, j] == 51.0
    assert obs.observation("C2L")[0, j] == 20576399.569
    assert obs.observation("C1C")[1, j] == 20576346.113
    g8 = obs.satellites.index("G08")
    assert np.isnan(obs.observation("C1C")[0, g8]) and obs.observation("C2L")[0, g8] == 22846861.832
    assert obs.observation("D1C")[0, obs.satellites.index("E29")] == 2175.723
    assert np.isnan(obs.observation("C2L")[0, obs.satellites.index("E29")])  # not a Galileo type


def test_rinex_obs_truncated_and_bad(tmp_path):
    text = (EX / "walk_head.obs").read_text()
    p = tmp_path / "cut.obs"
    p.write_text(text[:-30])
    obs = mn.read_rinex_obs(p)
    assert len(obs) == 3 and "cut short" in obs.warnings[0] and "cut.obs:" in obs.warnings[0]
    assert obs.time[-1] == pytest.approx(mn.read_rinex_obs(EX / "walk_head.obs").time[2])
    lines = text.splitlines()
    k = next(i for i, s in enumerate(lines) if s.startswith("G10"))
    lines[k] = lines[k][:8] + "x" + lines[k][9:]
    p.write_text("\n".join(lines) + "\n")
    with pytest.raises(mn.ParseError, match=rf"cut.obs:{k + 1}: expected a number for G10 C1C"):
        mn.read_rinex_obs(p)


def test_gps_l1_measurements_against_independent_corrections():
    sky = mn.Constellation.from_rinex_nav(EX / "walk.nav")
    obs = mn.read_rinex_obs(EX / "walk_head.obs")
    assert mn.read_klobuchar(EX / "walk.nav") is None  # this header has no ION ALPHA/BETA
    raw = mn.read_rinex_obs(EX / "walk_head.obs")
    m = obs.gps_l1(
        sky, ionosphere=False, troposphere=False, elevation_mask_deg=0.0, min_cn0_db_hz=0.0
    )
    ids = np.asarray(m.sat_id)[0]
    assert sorted(ids[ids >= 0]) == [10, 23, 27, 32]
    t = obs.time[0]
    for col, prn in enumerate(ids[ids >= 0]):
        p = raw.observation("C1C")[0, raw.satellites.index(f"G{prn:02d}")]
        d = raw.observation("D1C")[0, raw.satellites.index(f"G{prn:02d}")]
        i = sky.prns.index(f"G{prn:02d}")
        dt_sv = sky.clock_correction(t - p / C)[i]
        # P + c Δt_sv (IS-GPS-200 20.3.3.3.3.1), and -λ D for the rate.
        assert np.asarray(m.pseudorange)[0, col] == pytest.approx(p + C * dt_sv, abs=1e-3)
        rate = np.asarray(m.pseudorange_rate)[0, col]
        assert rate == pytest.approx(-d * C / 1575.42e6, abs=0.01)
    # With the atmosphere the ranges shrink by a few metres (zenith ~2 m troposphere at 1.6 km);
    # the troposphere needs a mask of 5° or more.
    with pytest.raises(ValueError, match=r"elevation_mask: 0\.00° is below 5°"):
        obs.gps_l1(sky, elevation_mask_deg=0.0, min_cn0_db_hz=0.0)
    m2 = obs.gps_l1(sky, elevation_mask_deg=5.0, min_cn0_db_hz=0.0)
    delay = np.asarray(m.pseudorange)[0] - np.asarray(m2.pseudorange)[0]
    assert np.all((delay[ids >= 0] > 2.0) & (delay[ids >= 0] < 40.0))
    # Pseudorange-only fix with 4 satellites: tens of metres from the RTK truth at most.
    fix = mn.solve_fix(m2)
    truth = mn.read_pos(EX / "walk_head.pos")
    r_truth = mn.geodetic_to_ecef(truth.lla[0])
    assert np.linalg.norm(np.asarray(fix.position_ecef)[0] - r_truth) < 40.0


# --- Allan deviation -------------------------------------------------------


def test_allan_deviation_of_white_noise():
    rate, sigma = 100.0, 0.02
    x = np.random.default_rng(5).normal(0.0, sigma, (60_000, 2))
    taus, adev = mn.allan_deviation(x, rate, taus=[0.1, 1.0, 5.0])
    density = sigma / np.sqrt(rate)  # white noise: adev(tau) = q / sqrt(tau)
    np.testing.assert_allclose(
        adev, np.repeat(density / np.sqrt(taus)[:, None], 2, axis=1), rtol=0.15
    )
    with pytest.raises(ValueError, match="taus"):
        mn.allan_deviation(x, rate, taus=[1000.0])
