"""GNSS files from other tools through the Python faces: RINEX 2.11
observations (a CORS station) with their RINEX 2 navigation file, event
records counted, GLONASS broadcast orbits against precise ones, GLONASS in
single-point fixes on a simulator's files, satellite states at given times
for every system, and the clear refusals (ephemerides that cover nothing,
a mask too low for the troposphere), and GLONASS in the tight filter. The
public excerpts and their licences are in ``tests/data/rinex-public``."""

from __future__ import annotations

import warnings
from pathlib import Path

import numpy as np
import pytest
from figures import figures
from shared_data import shared_data

import memsnav as mn

PUBLIC = Path(__file__).parent / "data" / "rinex-public"
EX = Path(__file__).parent / "data" / "real-imu-gnss"
#: The Skydel simulation's receiver (its README), ECEF m.
SKYDEL_TRUTH = np.array([-481819.31349724, 5507219.95375401, 3170373.73538364])


def test_a_cors_rinex_2_11_file_and_its_navigation_file_give_fixes():
    """SLAC (teqc, RINEX 2.11) with the IGS RINEX 2 GPS navigation file of
    the day: every epoch gives a GPS fix within metres of the station's
    header position."""
    obs = mn.read_rinex_obs(PUBLIC / "slac1180_excerpt.21o")
    assert obs.skipped == {} and len(obs) == 5
    assert {"C1C", "C1W", "C2W", "L1C", "L2W", "S1C"} <= set(obs.observation_types["G"])
    eph = mn.read_broadcast_nav(shared_data("gnss-products/2021-118/brdc1180.21n"))
    gnss = obs.measurements(eph, systems=["G"])
    fixes = mn.solve_fix(gnss)
    errors = np.linalg.norm(fixes.position_ecef - obs.approx_position_ecef, axis=1)
    assert np.all(errors < 10.0), errors
    # docs/how-to/convert-ublox.md shows the record (docs/doc_runs.py).
    recorded = figures("slac_rinex2_fixes")
    assert len(errors) == recorded["epochs"]
    assert abs(errors.min() - recorded["least_m"]) < 0.05
    assert abs(errors.max() - recorded["most_m"]) < 0.05


def test_the_navigation_files_klobuchar_is_the_default(tmp_path):
    obs = mn.read_rinex_obs(PUBLIC / "slac1180_excerpt.21o")
    nav = shared_data("gnss-products/2021-118/brdc1180.21n")
    eph = mn.read_broadcast_nav(nav)
    assert eph.klobuchar is not None and eph.klobuchar == mn.read_klobuchar(nav)
    default = obs.measurements(eph, systems=["G"])
    header = obs.measurements(eph, systems=["G"], klobuchar=eph.klobuchar)
    np.testing.assert_array_equal(default.pseudorange, header.pseudorange)
    # Without ION ALPHA/BETA in the header: RTKLIB's coefficients, metres apart.
    bare = tmp_path / "bare.21n"
    lines = nav.read_text().splitlines(True)
    bare.write_text("".join(x for x in lines if "ION ALPHA" not in x and "ION BETA" not in x))
    assert mn.read_broadcast_nav(bare).klobuchar is None
    rtklib = obs.measurements(mn.read_broadcast_nav(bare), systems=["G"])
    assert np.nanmax(np.abs(rtklib.pseudorange - default.pseudorange)) > 0.1


def test_event_records_are_counted():
    obs = mn.read_rinex_obs(PUBLIC / "14601736.18o")
    assert obs.skipped == {
        "event records with flag 2 (start moving antenna)": 2,
        "event records with flag 3 (new site occupation)": 1,
    }
    assert len(obs) == 3


def test_glonass_slot_frequencies_of_an_observation_header(tmp_path):
    """The phone's RINEX 3.03 header lists 6 GLONASS slots with their FDMA
    channels: read, they are the channels the IGS broadcast file gives the
    same slots (channels stay with their slots), and a count that disagrees
    with the list is refused naming the line."""
    obs = mn.read_rinex_obs(shared_data("android-gnsslogger/pixel6.23o"))
    channels = obs.glonass_channels
    assert channels == {"R01": 1, "R02": -4, "R03": 5, "R12": -1, "R13": -2, "R21": 4}
    broadcast = mn.read_broadcast_nav(PUBLIC / "brdc1360_excerpt.20g").glonass_channels
    common = set(channels) & set(broadcast)
    assert len(common) >= 4 and all(channels[s] == broadcast[s] for s in common)
    text = (shared_data("android-gnsslogger/pixel6.23o")).read_text().splitlines(True)
    line = next(i for i, t in enumerate(text) if "GLONASS SLOT / FRQ #" in t)
    text[line] = " 7" + text[line][2:]
    path = tmp_path / "seven.23o"
    path.write_text("".join(text[: line + 40]))
    with pytest.raises(
        mn.ParseError,
        match=r"seven\.23o:13: GLONASS SLOT / FRQ # declares 7 satellites and lists 6",
    ):
        mn.read_rinex_obs(path)


def test_glonass_broadcast_states_agree_with_precise_orbits():
    eph = mn.read_broadcast_nav(PUBLIC / "brdc1360_excerpt.20g")
    assert len(eph) == 100 and eph.glonass_channels["R01"] == 1
    sp3 = mn.read_sp3(PUBLIC / "COD0MGXFIN_20201360000_R_excerpt.SP3")
    # One satellite of the 23 has no healthy record in the excerpt: 17 epochs.
    with pytest.warns(UserWarning, match="17 of 391 satellite states"):
        position, _, clock = eph.satellite_states(sp3.time, sp3.satellites)
    assert position.shape == (len(sp3.time), len(sp3.satellites), 3)
    assert np.sum(np.isnan(clock)) == 17
    error = np.linalg.norm(position - sp3.position_ecef, axis=2)
    rms = np.sqrt(np.nanmean(error**2))
    assert rms < 4.5 and np.nanmax(error) < 12.0, (rms, np.nanmax(error))
    assert np.all(np.abs(clock[np.isfinite(clock)]) < 2e-3)
    # One time: (S, 3), (S, 3), (S,).
    p, v, c = eph.satellite_states(float(sp3.time[0]), ["R01", "R02"])
    assert p.shape == (2, 3) and v.shape == (2, 3) and c.shape == (2,)
    np.testing.assert_allclose(p, position[0, :2])
    assert 3000.0 < np.linalg.norm(v[0]) < 4500.0


def test_satellite_states_of_gps_agree_with_precise_orbits():
    eph = mn.read_broadcast_nav(shared_data("gnss-products/2021-118/brdc1180.21n"))
    sp3 = mn.read_sp3(shared_data("gnss-products/2021-118/COD0MGXFIN_20211180000_01D_05M_ORB.SP3"))
    gps = [k for k, name in enumerate(sp3.satellites) if name.startswith("G")]
    names = [sp3.satellites[k] for k in gps if sp3.satellites[k] in eph.satellites]
    columns = [sp3.satellites.index(n) for n in names]
    position, _, _ = eph.satellite_states(sp3.time[12:36], names)
    error = np.linalg.norm(position - sp3.position_ecef[12:36, columns], axis=2)
    assert np.sqrt(np.nanmean(error**2)) < 3.0


def test_satellite_states_of_galileo_and_beidou_and_an_uncovered_time():
    log = mn.read_ubx(EX / "walk_head.ubx")
    eph = log.broadcast_ephemerides
    # E14 and C50 are flagged unhealthy: no state from them.
    names = [n for n in eph.healthy_satellites if n[0] in "EC"]
    assert any(n[0] == "E" for n in names) and any(n[0] == "C" for n in names)
    t = float(log.observations.time[0])
    position, _, clock = eph.satellite_states(t, names)
    radius = np.linalg.norm(position, axis=1)
    assert np.all((radius > 2.5e7) & (radius < 4.3e7)), radius
    assert np.all(np.abs(clock) < 1e-2)
    with pytest.warns(UserWarning, match=f"{len(names)} of {len(names)} satellite states"):
        far, _, _ = eph.satellite_states(t + 86_400.0, names)
    assert np.all(np.isnan(far))
    with pytest.raises(ValueError, match="satellites"):
        eph.satellite_states(t, ["X01"])
    with pytest.raises(ValueError, match="gps_time"):
        eph.satellite_states(np.array([t, np.nan]), names)


def _skydel(systems: list[str], nav: Path = PUBLIC / "skydel_20230080000_excerpt_RN.rnx"):
    obs = mn.read_rinex_obs(PUBLIC / "skydel_20230080000_excerpt_MO.rnx")
    eph = mn.read_broadcast_nav(nav)
    return obs.measurements(
        eph,
        SKYDEL_TRUTH,
        systems=systems,
        ionosphere=False,
        troposphere=False,
        elevation_mask_deg=0.0,
    )


def test_glonass_alone_gives_fixes_on_the_simulator():
    gnss = _skydel(["R"])
    ids = np.asarray(gnss.sat_id)
    assert np.all((ids[ids >= 0] > 300) & (ids[ids >= 0] < 325))
    fixes = mn.solve_fix(gnss)
    errors = np.linalg.norm(fixes.position_ecef - SKYDEL_TRUTH, axis=1)
    # RTKLIB on the same files: 2.48, 1.92, 0.98, 0.26, 0.34 m.
    assert np.all(errors < 3.5), errors
    satellites = _skydel(["R"])
    assert len(satellites.time) == 5


def test_ephemerides_that_cover_nothing_or_part_are_named(tmp_path):
    # GLONASS records of another year: nothing covered.
    with pytest.raises(ValueError, match="none covers any satellite of the 5 epochs"):
        _skydel(["R"], PUBLIC / "brdc1360_excerpt.20g")
    # Only the 09:45 records: the 10:20 epoch is 35 min from t_b, beyond 30.
    lines = (PUBLIC / "skydel_20230080000_excerpt_RN.rnx").read_text().splitlines(True)
    header = lines[: next(k for k, x in enumerate(lines) if "END OF HEADER" in x) + 1]
    early = [
        line
        for k in range(len(header), len(lines), 4)
        if lines[k][14:20] == " 09 45"
        for line in lines[k : k + 4]
    ]
    path = tmp_path / "early.rnx"
    path.write_text("".join(header + early))
    with pytest.warns(UserWarning, match="1 of 5 epochs have no satellite with an ephemeris"):
        gnss = _skydel(["R"], path)
    assert len(mn.solve_fix(gnss).time) == 5


def test_a_mask_too_low_for_the_troposphere_is_refused():
    obs = mn.read_rinex_obs(PUBLIC / "skydel_20230080000_excerpt_MO.rnx")
    eph = mn.read_broadcast_nav(PUBLIC / "skydel_20230080000_excerpt_RN.rnx")
    with pytest.raises(ValueError, match=r"elevation_mask: 2\.00° is below 5°"):
        obs.measurements(eph, SKYDEL_TRUTH, systems=["R"], elevation_mask_deg=2.0)
    with warnings.catch_warnings():
        warnings.simplefilter("error")
        obs.measurements(eph, SKYDEL_TRUTH, systems=["R"], elevation_mask_deg=5.0)


def test_the_tight_filter_takes_glonass():
    """The simulator's GPS + GLONASS files through the step API at rest on
    the truth: every epoch's pseudoranges pass, with a GLONASS bias state."""
    gnss = _skydel(["G", "R"])
    z3, z33 = np.zeros(3), np.zeros((3, 3))
    imu = mn.ImuModel(mn.AccelerometerModel(z3, z3, z33, z3), mn.GyroscopeModel(z3, z3, z33, z33))
    up = SKYDEL_TRUTH / np.linalg.norm(SKYDEL_TRUTH)
    start = {"position_ecef": SKYDEL_TRUTH, "velocity_ecef": z3, "attitude": np.eye(3)}
    running = mn.TightlyCoupledFilter(imu).start(
        float(gnss.time[0]), 9.81 * up, z3, start, inter_system_biases=True
    )
    assert running.update_gnss(gnss, 0)
    assert len(running.state.inter_system_bias) == 3


def test_a_reference_position_per_epoch():
    obs = mn.read_rinex_obs(PUBLIC / "skydel_20230080000_excerpt_MO.rnx")
    eph = mn.read_broadcast_nav(PUBLIC / "skydel_20230080000_excerpt_RN.rnx")
    settings = {"systems": ["R"], "ionosphere": False, "elevation_mask_deg": 10.0}
    one = obs.measurements(eph, SKYDEL_TRUTH, **settings)
    track = np.tile(SKYDEL_TRUTH, (len(obs), 1))
    each = obs.measurements(eph, track, **settings)
    np.testing.assert_array_equal(each.pseudorange, one.pseudorange)
    # Another position at the third epoch moves only that epoch's corrections.
    track[2] += [0.0, 0.0, 5000.0]
    moved = obs.measurements(eph, track, **settings)
    changed = np.nanmax(np.abs(moved.pseudorange - one.pseudorange), axis=1)
    assert changed[2] > 0.01 and np.all(changed[[0, 1, 3, 4]] == 0.0), changed
    with pytest.raises(ValueError, match="4 positions for 5 observation epochs"):
        obs.measurements(eph, track[:4], **settings)


def test_precise_states_between_epochs_agree_with_broadcast_ones():
    sp3 = mn.read_sp3(shared_data("gnss-products/2021-118/COD0MGXFIN_20211180000_01D_05M_ORB.SP3"))
    eph = mn.read_broadcast_nav(shared_data("gnss-products/2021-118/brdc1180.21n"))
    names = [n for n in sp3.satellites if n in eph.healthy_satellites]
    at_epoch, _, _ = sp3.satellite_states(float(sp3.time[20]), names)
    columns = [sp3.satellites.index(n) for n in names]
    np.testing.assert_allclose(at_epoch, sp3.position_ecef[20, columns], atol=1e-6)
    # Half-way between epochs, over two hours.
    times = sp3.time[12:36] + 150.0
    precise, velocity, _ = sp3.satellite_states(times, names)
    broadcast, broadcast_velocity, _ = eph.satellite_states(times, names)
    error = np.linalg.norm(precise - broadcast, axis=2)
    assert np.sqrt(np.nanmean(error**2)) < 3.0, np.sqrt(np.nanmean(error**2))
    assert np.nanmax(np.linalg.norm(velocity - broadcast_velocity, axis=2)) < 0.05
    with pytest.warns(UserWarning, match="no precise orbit around their time"):
        outside, _, _ = sp3.satellite_states(float(sp3.time[-1]) + 60.0, names[:1])
    assert np.all(np.isnan(outside))
    with pytest.raises(ValueError, match="not in the file"):
        sp3.satellite_states(float(sp3.time[0]), ["G99"])
