"""GNSS fixes from other receivers: the fixes CSV and NMEA
readers give the same ``PosSolution`` as ``read_pos``, and a drive run from
either reaches the native RTKLIB solution. The drive excerpt is
tests/data/real-imu-gnss (BSD-3, LICENSE there); the phone's NMEA is the
shared ``android-gnsslogger`` data (MIT, LICENSE-gnss_lib_py there).
Checksums and expected values are computed here, independently of the
readers."""

from __future__ import annotations

import datetime as dt
import functools
import math
from decimal import Decimal
from pathlib import Path

import numpy as np
import pytest
from shared_data import shared_data

import memsnav as mn

DATA = Path(__file__).parent / "data"
EX = DATA / "real-imu-gnss"
GPS_EPOCH = dt.datetime(1980, 1, 6)
LEAP_S = 18  # GPS − UTC since 2017-01-01 (IERS Bulletin C)

DRIVE = """
name = "drive"
output = "{out}"
[imu]
file = "real-imu-gnss/drive_60s.csv"
accel_unit = "g"
gyro_unit = "deg/s"
time_unit = "ms"
time_tag = "real-imu-gnss/drive_60s.csv.tag"
time_offset_s = -0.22
mounting_rpy_deg = [[180.0, 0.0, 180.0], [0.0, -6.79, 5.35]]
lever_arm_m = [0.0, 0.0, -0.65]
[gnss]
mode = "loose"
pos = "{gnss}"
quality = [1, 2]
antenna_lever_arm_m = [0.0, -0.05, -0.65]
velocity_latency_s = 0.132
{gnss_extra}
[truth]
pos = "{truth}"
quality = [1]
[report]
html = false
"""


def _run(tmp_path: Path, name: str, gnss: str, truth: str, gnss_extra: str = "") -> mn.LogRun:
    cfg = tmp_path / f"{name}.toml"
    cfg.write_text(DRIVE.format(out=tmp_path / name, gnss=gnss, truth=truth, gnss_extra=gnss_extra))
    return mn.navigate(cfg, data_root=DATA).run


def _pos_rows() -> list[list[str]]:
    """The fields of the drive excerpt's .pos lines, as text."""
    lines = (EX / "drive_60s.pos").read_text().splitlines()
    return [line.split() for line in lines if line.strip() and not line.startswith("%")]


def _checksum(body: str) -> str:
    return f"{functools.reduce(lambda a, c: a ^ ord(c), body, 0):02X}"


def _sentence(body: str) -> str:
    return f"${body}*{_checksum(body)}"


def test_fixes_csv_with_covariance_reaches_the_native_solution(tmp_path):
    """A fixes CSV of the drive (GPS week and time of week, the .pos's own
    latitude/longitude/height digits, the full covariance with its
    diagonal the .pos's σ², velocity with σ, quality) as [gnss] and [truth]
    gives the native .pos run's solution to 1e-9 m."""
    native = mn.read_pos(EX / "drive_60s.pos")
    header = (
        "gps_week,gps_tow_s,lat_deg,lon_deg,height_m,cov_nn_m2,cov_ne_m2,cov_nd_m2,cov_ee_m2,"
        "cov_ed_m2,cov_dd_m2,vn_m_s,ve_m_s,vd_m_s,std_vn_m_s,std_ve_m_s,std_vd_m_s,quality,"
        "n_satellites"
    )
    lines = ["# drive_60s.pos as a fixes CSV", header]
    for k, f in enumerate(_pos_rows()):
        t = float(native.gps_time[k])
        week = int(t // 604800)
        sn, se, su = (float(x) for x in f[7:10])
        v = native.velocity_ned[k]
        sv = native.velocity_std_ned[k]
        cov = [sn * sn, 0.0, 0.0, se * se, 0.0, su * su]
        lines.append(
            ",".join(
                [str(week), repr(t - week * 604800), f[2], f[3], f[4]]
                + [repr(c) for c in cov]
                + [repr(float(x)) for x in (*v, *sv)]
                + [str(int(float(f[5]))), str(int(float(f[6])))]
            )
        )
    csv = tmp_path / "drive_fixes.csv"
    csv.write_text("\n".join(lines) + "\n")
    back = mn.read_fixes_csv(csv)
    assert back.has_full_covariance
    np.testing.assert_array_equal(back.lla, native.lla)
    np.testing.assert_allclose(back.gps_time, native.gps_time, rtol=0, atol=1e-6)
    np.testing.assert_array_equal(back.quality, native.quality)
    np.testing.assert_array_equal(back.covariance_ned, native.covariance_ned)
    pos = "real-imu-gnss/drive_60s.pos"
    want = _run(tmp_path, "native", pos, pos)
    got = _run(tmp_path, "csv", str(csv), str(csv))
    assert len(got) == len(want)
    assert np.max(np.abs(np.asarray(got.position_ecef) - want.position_ecef)) <= 1e-9
    assert np.max(np.abs(np.asarray(got.velocity_ned) - want.velocity_ned)) <= 1e-9


def _nmea_epoch(f: list[str], geoid_m: Decimal) -> list[str]:
    """GGA, RMC and GST of one .pos line: UTC = GPST − 18 s; the .pos's
    7-decimal degrees as 6-decimal minutes (exact); MSL height = h − N;
    the .pos's own σ digits in GST; RTKLIB Q 1/2 as GGA 4/5."""
    gpst = dt.datetime.strptime(f"{f[0]} {f[1]}", "%Y/%m/%d %H:%M:%S.%f")
    utc = gpst - dt.timedelta(seconds=LEAP_S)
    hms = utc.strftime("%H%M%S.") + f"{utc.microsecond // 1000:03d}"

    def angle(text: str, digits: int, hemispheres: str) -> str:
        d = Decimal(text)
        sign = hemispheres[0] if d >= 0 else hemispheres[1]
        d = abs(d)
        whole = int(d)
        minutes = (d - whole) * 60
        return f"{whole:0{digits}d}{minutes:09.6f},{sign}"

    msl = Decimal(f[4]) - geoid_m
    quality = {1: 4, 2: 5}[int(float(f[5]))]
    gga = (
        f"GNGGA,{hms},{angle(f[2], 2, 'NS')},{angle(f[3], 3, 'EW')},{quality},"
        f"{int(float(f[6])):02d},0.8,{msl},M,{geoid_m},M,,"
    )
    rmc = (
        f"GNRMC,{hms},A,{angle(f[2], 2, 'NS')},{angle(f[3], 3, 'EW')},,,"
        f"{utc.strftime('%d%m%y')},,,D"
    )
    gst = f"GNGST,{hms},0.5,,,,{f[7]},{f[8]},{f[9]}"
    return [_sentence(s) for s in (gga, rmc, gst)]


def test_nmea_reaches_the_native_solution(tmp_path):
    """NMEA GGA + RMC + GST of the drive: the positions parse to the .pos's
    own values (the 7-decimal degrees are exact in 6-decimal minutes; the
    height goes through MSL + geoid separation), so the run matches the
    native .pos run to the float rounding of those two sums: 1e-8 m, ten
    ulps of a 4 000 km ECEF coordinate (2.8e-9 m measured); both without
    velocity (NMEA has no vertical velocity)."""
    geoid = Decimal("-21.387")
    lines = [s for f in _pos_rows() for s in _nmea_epoch(f, geoid)]
    nmea = tmp_path / "drive.nmea"
    nmea.write_text("\n".join(lines) + "\n")
    native = mn.read_pos(EX / "drive_60s.pos")
    back = mn.read_nmea(nmea)
    np.testing.assert_allclose(back.gps_time, native.gps_time, rtol=0, atol=1e-6)
    np.testing.assert_allclose(back.lla[:, :2], native.lla[:, :2], rtol=0, atol=1e-15)
    np.testing.assert_allclose(back.lla[:, 2], native.lla[:, 2], rtol=0, atol=1e-9)
    np.testing.assert_array_equal(back.std_ned, native.std_ned)
    np.testing.assert_array_equal(back.quality, native.quality)
    assert np.all(np.isnan(back.velocity_ned))  # no speed in these RMCs
    pos = "real-imu-gnss/drive_60s.pos"
    no_velocity = "use_velocity = false"
    want = _run(tmp_path, "native", pos, pos, no_velocity)
    got = _run(tmp_path, "nmea", str(nmea), pos, no_velocity)
    assert len(got) == len(want)
    assert np.max(np.abs(np.asarray(got.position_ecef) - want.position_ecef)) <= 1e-8


def test_format_key_overrides_the_extension(tmp_path):
    """[gnss] format names the reader whatever the file's name; a format
    that is not one of the four is an error naming the key."""
    lines = [s for f in _pos_rows()[:8] for s in _nmea_epoch(f, Decimal(0))]
    odd = tmp_path / "fixes.txt"
    odd.write_text("\n".join(lines) + "\n")
    assert mn.realdata.fix_readers.fix_format(odd) == "rtklib"
    cfg = tmp_path / "f.toml"
    text = DRIVE.format(out=tmp_path / "o", gnss=odd, truth=odd, gnss_extra='format = "nmea"')
    cfg.write_text(text.replace("[truth]\n", '[truth]\nformat = "nmea"\n'))
    loaded = mn.load_config(cfg, DATA)
    assert loaded["gnss"]["format"] == "nmea"
    from memsnav.realdata.pipeline import read_solution

    solution, keep, _ = read_solution(loaded, "gnss")
    assert len(solution) == 8 and keep.all()
    cfg.write_text(text.replace('format = "nmea"', 'format = "sbf"'))
    with pytest.raises(
        ValueError, match=r"gnss.format: must be one of \['rtklib', 'csv', 'nmea', 'ubx'\]"
    ):
        mn.load_config(cfg, DATA)


def test_full_covariance_reaches_the_fixes(tmp_path):
    """A CSV covariance with north-east and vertical correlation reaches
    the ECEF fix whole: C_e^n P_e C_n^e gives it back."""
    csv = tmp_path / "c.csv"
    csv.write_text(
        "gps_time_s,x_ecef_m,y_ecef_m,z_ecef_m,cov_nn_m2,cov_ne_m2,cov_nd_m2,cov_ee_m2,"
        "cov_ed_m2,cov_dd_m2\n"
        "1400000000,-1288160.0,-4720790.0,4079600.0,4,1.5,-0.5,9,0.3,16\n"
    )
    sol = mn.read_fixes_csv(csv)
    fixes = mn.fixes_from_solution(sol.gps_time, sol.lla, covariance_ned=sol.covariance_ned)
    lat, lon = sol.lla[0, :2]
    sl, cl, so, co = math.sin(lat), math.cos(lat), math.sin(lon), math.cos(lon)
    c_e_n = np.array([[-sl * co, -sl * so, cl], [-so, co, 0.0], [-cl * co, -cl * so, -sl]])
    p_ned = c_e_n @ np.asarray(fixes.position_covariance)[0] @ c_e_n.T
    want = np.array([[4, 1.5, -0.5], [1.5, 9, 0.3], [-0.5, 0.3, 16]])
    np.testing.assert_allclose(p_ned, want, rtol=0, atol=1e-12)
    np.testing.assert_allclose(np.asarray(fixes.position_ecef)[0], [-1288160, -4720790, 4079600])
    with pytest.raises(ValueError, match="std_ned, covariance_ned: give exactly one"):
        mn.fixes_from_solution(
            sol.gps_time, sol.lla, sol.std_ned, covariance_ned=sol.covariance_ned
        )


def test_phone_nmea_gnsslogger_records():
    """The Pixel's GnssLogger NMEA (``NMEA,<sentence>,<unix ms>``): 48
    epochs of GPGGA + GPRMC; the first one parsed by hand here; every
    epoch's GPS time within a second before the phone's own arrival stamp
    (unix ms − 315 964 800 s + 18 leap seconds): the leap seconds and the
    date are right. No GST: σ from HDOP 0.4 × 5 m UERE, with a warning."""
    path = shared_data("android-gnsslogger/pixel6.nmea")
    with pytest.warns(UserWarning, match="48 epoch.s. without GST"):
        sol = mn.read_nmea(path)
    assert len(sol) == 48
    first = dt.datetime(2023, 11, 7, 23, 42, 57) + dt.timedelta(seconds=LEAP_S)
    assert sol.gps_time[0] == (first - GPS_EPOCH).total_seconds()
    assert sol.lla[0, 0] == pytest.approx(math.radians(37 + 25.590397 / 60), abs=1e-15)
    assert sol.lla[0, 1] == pytest.approx(-math.radians(122 + 10.422534 / 60), abs=1e-15)
    assert sol.lla[0, 2] == pytest.approx(51.9 - 28.4, abs=1e-12)
    assert (sol.quality == 5).all() and sol.n_satellites[0] == 24
    np.testing.assert_allclose(sol.std_ned[0], [0.4 * 5 / math.sqrt(2)] * 2 + [1.5 * 0.4 * 5])
    stamps = []
    for line in path.read_text().splitlines():
        fields = line.split(",")
        if fields[1].endswith("GGA"):
            stamps.append(int(fields[-1]) / 1000 - 315964800 + LEAP_S)
    lag = np.asarray(stamps) - sol.gps_time
    assert np.all((lag >= 0) & (lag < 1)), lag
    # The last RMC: 0.2 knots on 20.9° true, no vertical velocity.
    speed = 0.2 * 1852 / 3600
    np.testing.assert_allclose(
        sol.velocity_ned[-1, :2],
        [speed * math.cos(math.radians(20.9)), speed * math.sin(math.radians(20.9))],
        rtol=0,
        atol=1e-15,
    )
    assert np.isnan(sol.velocity_ned[-1, 2])


def test_hand_written_sentences_and_their_errors(tmp_path):
    """Sentences written here with checksums computed here: a GN talker,
    VTG joining its epoch, a GST error ellipse; a wrong checksum and an
    out-of-range field are errors naming line and field."""
    gga = _sentence("GNGGA,120000.00,5130.000000,N,00007.500000,W,2,12,1.0,45.0,M,47.0,M,1.0,0123")
    rmc = _sentence("GNRMC,120000.00,A,5130.000000,N,00007.500000,W,,,150320,,,D")
    vtg = _sentence("GNVTG,90.0,T,,M,1.0,N,3.6,K,D")
    gst = _sentence("GNGST,120000.00,1.0,2.0,1.0,45.0,1.5,1.5,3.0")
    path = tmp_path / "a.nmea"
    path.write_text("\n".join([gga, rmc, vtg, gst]) + "\n")
    sol = mn.read_nmea(path)
    t = dt.datetime(2020, 3, 15, 12, 0, 0) + dt.timedelta(seconds=LEAP_S)
    assert sol.gps_time[0] == (t - GPS_EPOCH).total_seconds()
    assert sol.quality[0] == 4  # DGPS
    assert sol.lla[0, 2] == pytest.approx(92.0, abs=1e-12)
    np.testing.assert_allclose(sol.velocity_ned[0, :2], [0.0, 1.0], atol=1e-15)
    # Ellipse 2 × 1 m along 45°: ρ = (4 − 1)/2 / √(2.5 · 2.5) = 0.6.
    c = sol.covariance_ned[0]
    np.testing.assert_allclose(c, [[2.25, 0.6 * 2.25, 0], [0.6 * 2.25, 2.25, 0], [0, 0, 9]])
    bad = gga[:-2] + ("00" if gga[-2:] != "00" else "01")
    path.write_text("\n".join([rmc, bad, gst]) + "\n")
    with pytest.raises(mn.realdata.readers.ParseError, match=r"a.nmea:2: checksum"):
        mn.read_nmea(path)
    lat = _sentence("GNGGA,120000.00,9130.000000,N,00007.500000,W,2,12,1.0,45.0,M,47.0,M,,")
    path.write_text("\n".join([rmc, lat, gst]) + "\n")
    with pytest.raises(ValueError, match=r"a.nmea:2: GGA field 2 \(latitude\): 9130.000000 is out"):
        mn.read_nmea(path)
