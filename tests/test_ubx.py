"""u-blox UBX logs: ``memsnav.read_ubx`` and ``memsnav convert``.

The converted RINEX files are read by independent readers (georinex for
RINEX 3, nmbu.rinex for the RINEX 4 navigation file)
and must hold the values the log decodes to; the GPS ephemerides decoded
from the log's navigation words give the orbits and clocks of the RINEX
navigation file another converter made from the same log; the log's
NAV-PVT is the walk's RTK truth file field for field; the least-squares
fix on the log's GPS L1 C/A pseudoranges with its own ephemerides sits
where the data README says broadcast-ephemeris solutions sit."""

from __future__ import annotations

import struct
import warnings
from pathlib import Path

import numpy as np
import pytest
from figures import figures
from shared_data import shared_data

import memsnav as mn
from memsnav.cli import main
from memsnav.realdata.convert import convert_ubx

EXCERPT = Path(__file__).parent / "data" / "real-imu-gnss" / "walk_head.ubx"
WALK = "real-imu-gnss/walk_0827/"

#: georinex's names of the RINEX GPS navigation fields, with ours.
GEORINEX_NAV = {
    "SVclockBias": "af0",
    "SVclockDrift": "af1",
    "SVclockDriftRate": "af2",
    "IODE": "iode",
    "Crs": "crs",
    "DeltaN": "delta_n",
    "M0": "m0",
    "Cuc": "cuc",
    "Eccentricity": "eccentricity",
    "Cus": "cus",
    "sqrtA": "sqrt_a",
    "Cic": "cic",
    "Omega0": "omega0",
    "Cis": "cis",
    "Io": "i0",
    "Crc": "crc",
    "omega": "omega",
    "OmegaDot": "omega_dot",
    "IDOT": "idot",
    "CodesL2": "l2_codes",
    "GPSWeek": "week",
    "L2Pflag": "l2p_data_flag",
    "SVacc": "ura_m",
    "health": "health",
    "TGD": "tgd",
    "IODC": "iodc",
    "FitIntvl": "fit_interval_h",
}


def _georinex(path: Path):
    georinex = pytest.importorskip("georinex")
    with warnings.catch_warnings():
        # georinex's xarray merges warn of xarray's coming defaults.
        warnings.simplefilter("ignore", FutureWarning)
        return georinex.load(path)


def _ned(delta_ecef: np.ndarray, lla: np.ndarray) -> np.ndarray:
    """ECEF differences as north, east, down at geodetic ``lla`` (rad)."""
    lat, lon = lla[0], lla[1]
    c_e_n = np.array(
        [
            [-np.sin(lat) * np.cos(lon), -np.sin(lat) * np.sin(lon), np.cos(lat)],
            [-np.sin(lon), np.cos(lon), 0.0],
            [-np.cos(lat) * np.cos(lon), -np.cos(lat) * np.sin(lon), -np.sin(lat)],
        ]
    )
    return delta_ecef @ c_e_n.T


def test_convert_writes_rinex_that_georinex_reads_back(tmp_path, capsys):
    # georinex reads RINEX 2 and 3 navigation files, not RINEX 4's.
    out = str(tmp_path / "out")
    assert main(["convert", str(EXCERPT), "--output", out, "--rinex-version", "3.04"]) == 0
    printed = capsys.readouterr().out
    assert (
        "20 epochs" in printed
        and "4 GPS LNAV, 7 Galileo, 8 BeiDou and 0 GLONASS ephemerides" in printed
    )
    assert "7 GPS CNAV ephemerides decoded, not written to the RINEX 3.04 .nav" in printed
    log = mn.read_ubx(EXCERPT)
    obs_path, nav_path = tmp_path / "out" / "walk_head.obs", tmp_path / "out" / "walk_head.nav"

    nav = _georinex(nav_path)
    assert sorted(s for s in nav.sv.values if s[0] == "G") == ["G10", "G23", "G27", "G32"]
    for e in log.ephemerides:
        record = nav.sel(sv=e["sat"]).dropna("time", how="all")
        assert record.time.size == 1
        for theirs, ours in GEORINEX_NAV.items():
            value = float(record[theirs].values[0])
            assert value == pytest.approx(e[ours], rel=1e-12, abs=1e-300), theirs
        # t_oe and the transmission time in seconds of the t_oe week.
        assert float(record["Toe"].values[0]) == e["toe"] - e["week"] * 604800.0
        toc = (record.time.values[0] - np.datetime64("1980-01-06")) / np.timedelta64(1, "s")
        assert toc == e["toc"]

    obs = _georinex(obs_path)
    observations = log.observations
    times = (obs.time.values - np.datetime64("1980-01-06")) / np.timedelta64(1, "s")
    np.testing.assert_allclose(times, observations.time, rtol=0, atol=2e-6)
    assert sorted(obs.sv.values) == observations.satellites
    checked = 0
    for system, codes in observations.observation_types.items():
        columns = [k for k, s in enumerate(observations.satellites) if s[0] == system]
        names = [observations.satellites[k] for k in columns]
        for code in codes:
            ours = observations.observation(code)[:, columns]
            theirs = obs[code].sel(sv=names).values
            np.testing.assert_array_equal(np.isnan(theirs), np.isnan(ours), err_msg=code)
            # F14.3: half a millimetre, a thousandth of a cycle or Hz.
            np.testing.assert_allclose(theirs, ours, rtol=0, atol=5.0001e-4, err_msg=code)
            checked += int(np.isfinite(ours).sum())
    # And the observations are the receiver's values: GPS L1 C/A pseudoranges
    # marked valid, in RAWX's own record.
    rawx = log.rawx
    gps_l1 = (np.array(rawx["code"]) == "1C") & (rawx["gnss_id"] == 0)
    gps_l1 &= rawx["pseudorange_valid"]
    for k in np.flatnonzero(gps_l1)[:50]:
        sat = rawx["sat"][k]
        at = rawx["epoch_gps_time"][rawx["epoch"][k]]
        value = obs["C1C"].sel(sv=sat).values[np.argmin(np.abs(times - at))]
        assert value == pytest.approx(rawx["pseudorange"][k], abs=5.0001e-4)
    assert checked > 5000


def test_ubx_ephemerides_give_the_orbits_of_the_broadcast_file():
    log = mn.read_ubx(shared_data(WALK + "gnss_1730.ubx"))
    broadcast = mn.Constellation.from_rinex_nav(shared_data(WALK + "gnss_1730.nav"))
    ours = log.constellation
    assert ours.prns == broadcast.prns == ["G10", "G23", "G27", "G32"]
    start = log.observations.time[0]
    for t in (start, start + 133.0, start + 7200.0):
        p_ours, v_ours = ours.position_velocity(t)
        p_file, v_file = broadcast.position_velocity(t)
        # The file prints 12 digits: 0.1 mm of orbit, 1e-15 s of clock.
        np.testing.assert_allclose(p_ours, p_file, rtol=0, atol=1e-3)
        np.testing.assert_allclose(v_ours, v_file, rtol=0, atol=1e-6)
        np.testing.assert_allclose(
            ours.clock_correction(t), broadcast.clock_correction(t), rtol=0, atol=1e-14
        )
    assert all(e["health"] == 0 and e["ura_m"] == 2.4 for e in log.ephemerides)


def test_nav_pvt_is_the_walk_truth_file():
    log = mn.read_ubx(shared_data(WALK + "gnss_1730.ubx"))
    truth = mn.read_pos(shared_data(WALK + "gnss_1730_sf.pos"))
    fixes = mn.read_fixes(shared_data(WALK + "gnss_1730.ubx"))
    np.testing.assert_allclose(fixes.gps_time, truth.gps_time, rtol=0, atol=1e-3)
    np.testing.assert_allclose(fixes.lla[:, :2], truth.lla[:, :2], rtol=0, atol=1e-10)
    # The truth's heights are NAV-PVT's heights above mean sea level.
    np.testing.assert_allclose(log.nav_pvt["height_msl"], truth.lla[:, 2], rtol=0, atol=1e-3)
    np.testing.assert_allclose(log.fixes.lla[:, 2] - truth.lla[:, 2], -21.387, atol=0.01)
    np.testing.assert_array_equal(fixes.quality, truth.quality)
    np.testing.assert_allclose(fixes.std_ned, truth.std_ned, rtol=0, atol=1e-4)


def test_solve_fix_on_the_log_gps_l1_sits_where_broadcast_solutions_sit():
    log = mn.read_ubx(shared_data(WALK + "gnss_1730.ubx"))
    measurements = log.observations.gps_l1(log.constellation)
    fixes = mn.solve_fix(measurements)
    pvt = log.nav_pvt
    nearest = np.searchsorted(pvt["gps_time"], measurements.gps_time - 0.1)
    # RAWX epochs on the receiver clock (bias ~ -1.5 ms) against NAV-PVT's.
    assert np.abs(pvt["gps_time"][nearest] - measurements.gps_time).max() < 0.005
    valid = fixes.valid
    assert valid.sum() > 500
    delta = fixes.position_ecef - mn.geodetic_to_ecef(pvt["lla"][nearest])
    ned = _ned(delta[valid], pvt["lla"][0])
    offset = ned.mean(axis=0)
    # The data README: every broadcast solution sits 6.3-7.8 m east and
    # 2.5-5.2 m north of this truth, with a scatter of about 1 m.
    assert 2.5 <= offset[0] <= 5.2 and 6.3 <= offset[1] <= 7.8, offset
    precision = np.sqrt(np.mean(np.sum((ned[:, :2] - offset[:2]) ** 2, axis=1)))
    assert 0.5 < precision < 1.3, precision
    # docs/how-to/convert-ublox.md shows the record of docs/doc_runs.py's
    # walk_ubx_fix: this independent rotation gives it to its digits.
    recorded = figures("walk_ubx_fix")
    assert int(valid.sum()) == recorded["fixes"]
    assert (
        abs(offset[0] - recorded["north_m"]) < 0.05 and abs(offset[1] - recorded["east_m"]) < 0.05
    )
    assert abs(precision - recorded["horizontal_scatter_m"]) < 0.005
    # The receiver clock is not steered: about -1.5 ms, drifting ~ -60 m/s.
    assert -2e-3 < fixes.clock_offset[valid][0] / 299792458.0 < -1e-3


def test_bad_input_is_a_clear_error(tmp_path):
    text = tmp_path / "notes.ubx"
    text.write_text("not a u-blox log\n")
    with pytest.raises(mn.ParseError, match=r"notes\.ubx.*no UBX frame"):
        mn.read_ubx(text)
    with pytest.raises(OSError, match=r"missing\.ubx"):
        mn.read_ubx(tmp_path / "missing.ubx")
    # A cut and a flipped byte: what survives is read, the rest counted.
    data = bytearray(EXCERPT.read_bytes())
    data[5000] ^= 0xFF
    cut = tmp_path / "cut.ubx"
    cut.write_bytes(bytes(data[:-100]))
    log = mn.read_ubx(cut)
    assert log.skipped["frames with a bad checksum"] >= 1
    assert any("cut short" in w for w in log.warnings)
    assert len(log.rawx["epoch_gps_time"]) >= 18


#: georinex's names of the RINEX Galileo navigation fields, with ours.
GEORINEX_GALILEO = {
    "SVclockBias": "af0",
    "SVclockDrift": "af1",
    "SVclockDriftRate": "af2",
    "IODnav": "iod_nav",
    "Crs": "crs",
    "DeltaN": "delta_n",
    "M0": "m0",
    "Cuc": "cuc",
    "Eccentricity": "eccentricity",
    "Cus": "cus",
    "sqrtA": "sqrt_a",
    "Cic": "cic",
    "Omega0": "omega0",
    "Cis": "cis",
    "Io": "i0",
    "Crc": "crc",
    "omega": "omega",
    "OmegaDot": "omega_dot",
    "IDOT": "idot",
    "SISA": "sisa_m",
    "BGDe5a": "bgd_e1_e5a",
    "BGDe5b": "bgd_e1_e5b",
}


def test_galileo_ephemerides_in_the_converted_navigation_file(tmp_path):
    log = mn.read_ubx(shared_data(WALK + "gnss_1730.ubx"))
    galileo = log.galileo_ephemerides
    # The data README: I/NAV for 7 Galileo satellites, E14 flagged unhealthy.
    assert sorted(e["sat"] for e in galileo) == ["E07", "E08", "E13", "E14", "E26", "E29", "E33"]
    assert [e["sat"] for e in galileo if not e["healthy"]] == ["E14"]
    path = tmp_path / "walk.nav"
    log.write_rinex_nav(path, rinex_version="3.04")
    nav = _georinex(path)
    for e in galileo:
        record = nav.sel(sv=e["sat"]).dropna("time", how="all")
        assert record.time.size == 1
        for theirs, ours in GEORINEX_GALILEO.items():
            value = float(record[theirs].values[0])
            assert value == pytest.approx(e[ours], rel=1e-12, abs=1e-300), theirs
        health = int(record["health"].values[0])
        assert (health >> 1) & 3 == e["e1b_health"] and (health >> 7) & 3 == e["e5b_health"]
        assert float(record["GALWeek"].values[0]) == e["gst_week"] + 1024
    # And the GPS records beside them are unchanged.
    assert sorted(s for s in nav.sv.values if s[0] == "G") == ["G10", "G23", "G27", "G32"]


#: georinex's names of the RINEX BeiDou navigation fields, with ours.
GEORINEX_BEIDOU = {
    **{
        k: v
        for k, v in GEORINEX_GALILEO.items()
        if v not in ("iod_nav", "sisa_m", "bgd_e1_e5a", "bgd_e1_e5b")
    },
    "AODE": "aode",
    "AODC": "aodc",
    "SatH1": "sat_h1",
    "TGD1": "tgd1",
    "TGD2": "tgd2",
    "BDTWeek": "bdt_week",
}


def test_beidou_ephemerides_equal_the_rinex_of_another_converter(tmp_path):
    # The walk's .nav was written by another converter from the same log;
    # georinex reads it, independently of memsnav's RINEX reader.
    log = mn.read_ubx(shared_data(WALK + "gnss_1730.ubx"))
    beidou = log.beidou_ephemerides
    # The data README: D1 for 8 BeiDou satellites, C50 unhealthy.
    assert sorted(e["sat"] for e in beidou) == [
        "C11",
        "C21",
        "C22",
        "C34",
        "C42",
        "C43",
        "C44",
        "C50",
    ]
    assert [e["sat"] for e in beidou if not e["healthy"]] == ["C50"]
    nav = _georinex(shared_data(WALK + "gnss_1730.nav"))
    bdt_week_zero = 1356 * 604_800 + 14  # GPS s of BDT week 0 (BDT = GPS − 14 s)
    for e in beidou:
        record = nav.sel(sv=e["sat"]).dropna("time", how="all")
        assert record.time.size == 1
        for theirs, ours in GEORINEX_BEIDOU.items():
            value = float(record[theirs].values[0])
            assert value == pytest.approx(e[ours], rel=1e-11, abs=1e-300), (e["sat"], theirs)
        # The other converter writes URAI 0 as 2.0 m, inside its bin (0-2.4 m).
        assert float(record["SVacc"].values[0]) <= e["ura_m"] and e["urai"] == 0
        # t_oe in seconds of the BDT week; the record's epoch (t_oc) is BDT.
        assert (e["toe"] - bdt_week_zero) % 604_800 == float(record["Toe"].values[0])
        epoch_gps = (record.time.values[0] - np.datetime64("1980-01-06")) / np.timedelta64(1, "s")
        assert e["toc"] == epoch_gps + 14
    # memsnav's own navigation file, read by georinex, carries the same.
    path = tmp_path / "walk.nav"
    log.write_rinex_nav(path, rinex_version="3.04")
    ours = _georinex(path)
    for e in beidou:
        record = ours.sel(sv=e["sat"]).dropna("time", how="all")
        for theirs, name in {**GEORINEX_BEIDOU, "SVacc": "ura_m"}.items():
            value = float(record[theirs].values[0])
            assert value == pytest.approx(e[name], rel=1e-12, abs=1e-300), (e["sat"], theirs)


def test_gps_cnav_ephemerides_and_klobuchar(tmp_path):
    log = mn.read_ubx(EXCERPT)
    cnav = {e["sat"]: e for e in log.gps_cnav_ephemerides}
    lnav = {e["sat"]: e for e in log.ephemerides}
    # The data README: CNAV (L2C) for 7 GPS satellites, LNAV for 4 of them.
    assert sorted(cnav) == ["G08", "G10", "G18", "G23", "G24", "G27", "G32"]
    assert set(lnav) <= set(cnav)
    for sat, c in cnav.items():
        assert (c["l1_health"], c["l2_health"], c["week"]) == (0, 0, 2381)
        assert c["toc"] == c["toe"]
        assert c["tgd"] is not None and c["isc_l1ca"] is not None
        if sat in lnav:
            # Another upload of the same orbit (t_oe 30 min apart): the same
            # T_GD, and elements that agree to what half an hour moves them.
            other = lnav[sat]
            assert c["tgd"] == pytest.approx(other["tgd"], abs=2.0**-32)
            assert c["sqrt_a"] == pytest.approx(other["sqrt_a"], abs=0.01)
            assert c["eccentricity"] == pytest.approx(other["eccentricity"], abs=1e-5)
            assert c["i0"] == pytest.approx(other["i0"], abs=1e-5)
    alpha, beta = log.klobuchar
    assert len(alpha) == len(beta) == 4 and 0 < alpha[0] < 1e-7 and beta[0] > 7e4
    # RINEX 3.04 has no CNAV record: the navigation file keeps LNAV's 4.
    log.write_rinex_nav(tmp_path / "walk.nav", rinex_version="3.04")
    text = (tmp_path / "walk.nav").read_text()
    assert sorted({line[:3] for line in text.splitlines() if line.startswith("G")}) == sorted(lnav)
    # RINEX 4.00, the default, has: all 7 satellites, G08, G18 and G24 by CNAV alone.
    log.write_rinex_nav(tmp_path / "walk.rnx")
    text = (tmp_path / "walk.rnx").read_text()
    assert sorted({line[:3] for line in text.splitlines() if line.startswith("G")}) == sorted(cnav)
    assert text.count(" CNAV\n") == 7 and text.count(" LNAV\n") == 4


#: nmbu.rinex's names of the RINEX 4 GPS CNAV record fields, with ours.
NMBU_CNAV = {
    "A_DOT": "a_dot",
    "Crs": "crs",
    "Delta_n": "delta_n",
    "M0": "m0",
    "Cuc": "cuc",
    "e": "eccentricity",
    "Cus": "cus",
    "sqrt_A": "sqrt_a",
    "Cic": "cic",
    "OMEGA0": "omega0",
    "Cis": "cis",
    "i0": "i0",
    "Crc": "crc",
    "omega": "omega",
    "OMEGA_DOT": "omega_dot",
    "IDOT": "idot",
    "Delta_n_dot": "delta_n_dot",
    "URAI_NED0": "ura_ned0_index",
    "URAI_NED1": "ura_ned1_index",
    "URAI_ED": "ura_ed_index",
    "TGD": "tgd",
    "URAI_NED2": "ura_ned2_index",
    "ISC_L1CA": "isc_l1ca",
    "ISC_L2C": "isc_l2c",
    "ISC_L5I5": "isc_l5i5",
    "ISC_L5Q5": "isc_l5q5",
}


def _gps_seconds(timestamp: str) -> float:
    """An ISO calendar time (GPS time scale) as GPS s since 1980-01-06."""
    return float((np.datetime64(timestamp) - np.datetime64("1980-01-06")) / np.timedelta64(1, "s"))


def test_convert_writes_rinex4_navigation_an_independent_reader_reads(tmp_path, capsys):
    """RINEX 4.00 is convert's default: the CNAV records reach the file and
    nmbu.rinex (an independent RINEX 3/4 reader) gives back every value the
    log decoded, as memsnav's own reader does."""
    nmbu = pytest.importorskip("nmbu.rinex.reader")
    assert main(["convert", str(EXCERPT), "--output", str(tmp_path)]) == 0
    assert "7 GPS CNAV ephemerides written to the RINEX 4.00 .nav" in capsys.readouterr().out
    path = tmp_path / "walk_head.nav"
    log = mn.read_ubx(EXCERPT)
    rinex = nmbu.read_rinex_file(str(path))
    assert rinex.header.version == 4.0
    satellites = rinex.data.satellites
    cnav = log.gps_cnav_ephemerides
    gps = sorted(s for s in satellites if s[0] == "G")
    # 7 GPS satellites, 3 (G08, G18, G24) by CNAV alone.
    assert gps == ["G08", "G10", "G18", "G23", "G24", "G27", "G32"]
    assert sorted(e["sat"] for e in cnav) == gps
    for e in cnav:
        # nmbu keys records by epoch; LNAV and CNAV of one satellite differ in t_oc.
        records = satellites[e["sat"]]
        record = next(r for t, r in records.items() if _gps_seconds(t) == e["toc"])
        assert hasattr(record, "t_op"), e["sat"]  # a CNAV record, not LNAV
        for theirs, ours in NMBU_CNAV.items():
            value = float(getattr(record, theirs))
            assert value == pytest.approx(e[ours], rel=1e-12, abs=1e-300), (e["sat"], theirs)
        assert float(record.clock_bias) == pytest.approx(e["af0"], rel=1e-12)
        # Health: L1, L2, L5 bits as one number, L1 first.
        health = e["l1_health"] << 2 | e["l2_health"] << 1 | e["l5_health"]
        assert int(record.SV_health) == health
        # t_op in seconds of week WN_op; t_tm in seconds of its week.
        assert record.wn_op * 604_800 + record.t_op == e["top"]
        assert record.t_tm == e["transmission_time"] % 604_800
    for e in log.ephemerides:
        records = satellites[e["sat"]]
        record = next(r for t, r in records.items() if _gps_seconds(t) == e["toc"])
        assert float(record.IODE) == e["iode"]
        assert float(record.TGD) == pytest.approx(e["tgd"], rel=1e-12)
        assert float(record.sqrt_A) == pytest.approx(e["sqrt_a"], rel=1e-12)
    for e in log.beidou_ephemerides:
        (record,) = satellites[e["sat"]].values()
        assert float(record.AODE) == e["aode"]
        assert float(record.TGD1) == pytest.approx(e["tgd1"], rel=1e-12)
        assert float(record.sqrt_A) == pytest.approx(e["sqrt_a"], rel=1e-12)
    for e in log.galileo_ephemerides:
        (record,) = satellites[e["sat"]].values()
        assert float(record.IODnav) == e["iod_nav"]
        assert float(record.GAL_Week_no) == e["gst_week"] + 1024
        assert float(record.sqrt_A) == pytest.approx(e["sqrt_a"], rel=1e-12)
    # memsnav's reader reads RINEX 4 too: the same CNAV ephemerides (the
    # integrity and L2C phasing flags have no place in the record).
    back = mn.read_broadcast_nav(path)
    assert back.skipped == {}
    assert sorted(back.satellites) == sorted(s for s in satellites)
    dropped = ("integrity_status_flag", "l2c_phasing")
    for b, e in zip(back.gps_cnav_ephemerides, cnav, strict=True):
        for key, value in e.items():
            if key in dropped or value is None or isinstance(value, str):
                assert key in dropped or b[key] == value, key
            else:
                assert b[key] == pytest.approx(value, rel=1e-12, abs=1e-300, nan_ok=True), key


def test_a_rinex_version_convert_does_not_write_is_refused(tmp_path):
    log = mn.read_ubx(EXCERPT)
    with pytest.raises(ValueError, match=r"rinex_version.*3\.05"):
        log.write_rinex_nav(tmp_path / "x.nav", rinex_version="3.05")
    assert not (tmp_path / "x.nav").exists()


def _frame(cls: int, msg_id: int, payload: bytes) -> bytes:
    """A UBX frame with its Fletcher checksum (interface description §3.4)."""
    body = bytes([cls, msg_id]) + struct.pack("<H", len(payload)) + payload
    a = b = 0
    for x in body:
        a = (a + x) & 0xFF
        b = (b + a) & 0xFF
    return b"\xb5\x62" + body + bytes([a, b])


def _nav_pvt(itow_ms: int, height_mm: int = 1_580_048, vel_e_mm_s: int = 250) -> bytes:
    """A 3D-fix NAV-PVT on 2025-08-28 (GPS week 2381)."""
    p = bytearray(92)
    struct.pack_into("<IHBBBBBB", p, 0, itow_ms, 2025, 8, 28, 17, 30, 0, 0x07)
    p[20], p[21], p[23] = 3, 0x01, 12
    struct.pack_into("<iiii", p, 24, -1_052_500_000, 400_000_000, height_mm, height_mm + 21_000)
    struct.pack_into("<IIiii", p, 40, 14, 20, 100, vel_e_mm_s, -50)
    struct.pack_into("<I", p, 68, 30)
    return _frame(0x01, 0x07, bytes(p))


def _rawx(tow_s: float, week: int, signals: list[tuple[float, float, float]]) -> bytes:
    """An RXM-RAWX of GPS L1 C/A signals (PRN 3, 4, ...) with the given
    (prMes m, cpMes cycles, doMes Hz), pseudorange and phase flagged valid."""
    p = struct.pack("<dHbBBBBB", tow_s, week, 18, len(signals), 1, 1, 0, 0)
    for k, (pr, cp, do) in enumerate(signals):
        p += struct.pack("<ddfBBBBHBBBBBB", pr, cp, do, 0, 3 + k, 0, 0, 5000, 44, 5, 2, 5, 0x07, 0)
    return _frame(0x02, 0x15, p)


def test_nav_pvt_values_no_receiver_reports_are_skipped_and_counted(tmp_path):
    """NAV-PVT with velE = −2³¹ mm/s (−2 147 km/s) or a height of −1 043 km
    is skipped with a count and a warning naming the field; the good
    solution around them is kept."""
    itow = (4 * 86_400 + 17 * 3_600 + 30 * 60 + 18) * 1000
    path = tmp_path / "pvt.ubx"
    path.write_bytes(
        _nav_pvt(itow)
        + _nav_pvt(itow + 1000, vel_e_mm_s=-(2**31))
        + _nav_pvt(itow + 2000, height_mm=-1_043_477_000)
    )
    log = mn.read_ubx(path)
    assert log.skipped["NAV-PVT with a value no receiver reports"] == 2
    assert len(log.fixes.gps_time) == 1
    assert np.abs(log.fixes.velocity_ned).max() < 1.0
    assert log.fixes.lla[0, 2] == 1580.048
    assert any("NAV-PVT velE = -2.147483648e6 m/s is out of range" in w for w in log.warnings)
    assert any("NAV-PVT height = -1.043477e6 m is out of range" in w for w in log.warnings)


def test_rawx_weeks_after_2099_and_infinite_values_are_skipped(tmp_path):
    """An RXM-RAWX of week 9999 (2171) is skipped, not an epoch; ±inf
    pseudorange, phase and Doppler flagged valid leave their signal out."""
    good = (2.1e7, 1.1e8, -1234.5)
    path = tmp_path / "rawx.ubx"
    path.write_bytes(
        _rawx(408_618.0, 2381, [good])
        + _rawx(408_619.0, 9999, [good])
        + _rawx(
            408_620.0,
            2381,
            [good, (np.inf, 1.1e8, -1.0), (2.1e7, -np.inf, -1.0), (2.1e7, 1.1e8, np.inf)],
        )
    )
    log = mn.read_ubx(path)
    assert log.skipped["RXM-RAWX malformed"] == 1
    assert any("week 9999 is outside 1024-6260" in w for w in log.warnings)
    assert log.skipped["RXM-RAWX signals with a value no receiver reports"] == 3
    times = np.asarray(log.rawx["epoch_gps_time"])
    np.testing.assert_array_equal(times, 2381 * 604_800.0 + np.array([408_618.0, 408_620.0]))
    for name in ("pseudorange", "carrier_phase", "doppler"):
        assert np.isfinite(log.rawx[name]).all(), name
    assert len(log.rawx["pseudorange"]) == 2


def test_convert_of_a_log_without_observations_says_so(tmp_path, capsys):
    """A log of NAV-PVT only has no observations: ``convert`` is an error
    saying so and writes no file its readers would refuse."""
    path = tmp_path / "pvt_only.ubx"
    path.write_bytes(_nav_pvt(408_618_000) + _nav_pvt(408_619_000))
    out = tmp_path / "rinex"
    with pytest.raises(ValueError, match=r"no observations to write.*RXM-RAWX"):
        convert_ubx(path, out)
    assert not (out / "pvt_only.obs").exists()
    assert main(["convert", str(path), "--output", str(out)]) != 0
    assert "no observations" in capsys.readouterr().err


def test_convert_reads_its_files_back(tmp_path):
    """What ``convert`` writes, memsnav's readers read back whole."""
    files = convert_ubx(EXCERPT, tmp_path)[1]
    log = mn.read_ubx(EXCERPT)
    obs = mn.read_rinex_obs(files["observations"])
    assert len(obs.time) == len(log.rawx["epoch_gps_time"])
    nav = mn.read_broadcast_nav(files["navigation"])
    # RINEX 4.00: LNAV and CNAV records of GPS, each one ephemeris.
    written = len(log.ephemerides) + len(log.gps_cnav_ephemerides)
    written += len(log.galileo_ephemerides) + len(log.beidou_ephemerides)
    assert written == 4 + 7 + 7 + 8 and len(nav) == written and nav.skipped == {}
    assert len(nav.gps_cnav_ephemerides) == 7


#: LNAV parity equations (IS-GPS-200 table 20-XIV): whether each parity
#: bit starts from D30* (else D29*) and which source data bits d1-d24 it sums.
_LNAV_PARITY = [
    (False, [1, 2, 3, 5, 6, 10, 11, 12, 13, 14, 17, 18, 20, 23]),
    (True, [2, 3, 4, 6, 7, 11, 12, 13, 14, 15, 18, 19, 21, 24]),
    (False, [1, 3, 4, 5, 7, 8, 12, 13, 14, 15, 16, 19, 20, 22]),
    (True, [2, 4, 5, 6, 8, 9, 13, 14, 15, 16, 17, 20, 21, 23]),
    (True, [1, 3, 5, 6, 7, 9, 10, 14, 15, 16, 17, 18, 21, 22, 24]),
    (False, [3, 5, 6, 8, 9, 10, 11, 13, 15, 19, 22, 23, 24]),
]


def _lnav_word(word: int, data: int) -> int:
    """``word`` (u-blox layout: D29*, D30* in bits 31-30) carrying the 24
    source data bits ``data`` instead, its parity recomputed."""
    d29, d30 = word >> 31 & 1, word >> 30 & 1
    parity = 0
    for from_d30, bits in _LNAV_PARITY:
        p = d30 if from_d30 else d29
        for i in bits:
            p ^= data >> (24 - i) & 1
        parity = parity << 1 | p
    sent = data ^ 0xFFFFFF if d30 else data
    return d29 << 31 | d30 << 30 | sent << 6 | parity


def _lnav_data(word: int) -> int:
    return (word >> 6 & 0xFFFFFF) ^ (0xFFFFFF if word >> 30 & 1 else 0)


def test_an_lnav_orbit_inside_the_earth_is_skipped_and_counted(tmp_path):
    """Every GPS subframe 2 of the log carrying √A = 33.6 √m (an orbit
    inside the Earth) behind a valid parity and checksum: the LNAV
    ephemerides are skipped and counted, the others kept, and ``convert``
    writes what memsnav reads back."""
    log = bytearray(EXCERPT.read_bytes())
    raw = round(33.6 * 2**19)
    at, changed = 0, 0
    while at + 8 <= len(log):
        length = int.from_bytes(log[at + 4 : at + 6], "little")
        p = at + 6
        words = [int.from_bytes(log[p + 8 + 4 * k : p + 12 + 4 * k], "little") for k in range(10)]
        if log[at + 2 : at + 4] == b"\x02\x13" and length == 48 and log[p] == 0 and log[p + 2] == 0:
            if _lnav_data(words[1]) >> 2 & 7 == 2:  # subframe id 2 (HOW bits 20-22)
                w8 = _lnav_data(words[7]) & ~0xFF | raw >> 24
                new = [_lnav_word(words[7], w8), _lnav_word(words[8], raw & 0xFFFFFF)]
                for k, w in zip((7, 8), new, strict=True):
                    log[p + 8 + 4 * k : p + 12 + 4 * k] = w.to_bytes(4, "little")
                body = log[at + 2 : at + 6 + length]
                a = b = 0
                for x in body:
                    a, b = (a + x) & 0xFF, (b + ((a + x) & 0xFF)) & 0xFF
                log[at + 6 + length : at + 8 + length] = bytes([a, b])
                changed += 1
        at += 8 + length
    path = tmp_path / "inside.ubx"
    path.write_bytes(bytes(log))
    before = mn.read_ubx(EXCERPT)
    read = mn.read_ubx(path)
    assert changed > 0 and "frames with a bad checksum" not in read.skipped
    assert "GPS LNAV subframes with a parity failure" not in read.skipped
    assert read.skipped["GPS LNAV ephemerides out of range"] == len(before.ephemerides) == 4
    assert len(read.ephemerides) == 0
    assert any("sqrt(A) = 3.36" in w and "is out of range" in w for w in read.warnings)
    assert len(read.galileo_ephemerides) == len(before.galileo_ephemerides)
    files = convert_ubx(path, tmp_path / "rinex")[1]
    nav = mn.read_broadcast_nav(files["navigation"])
    # The CNAV records of the same satellites still reach the file.
    assert len(nav) == len(read.gps_cnav_ephemerides) + len(read.galileo_ephemerides) + len(
        read.beidou_ephemerides
    )
