"""GNSS from Python: constellations against SP3 and an independent Walker
formula, the simulator against geometry written here, the least-squares fix,
reproducibility, outages and every bad input."""

import math
from pathlib import Path

import numpy as np
import pytest
from shared_data import shared_data

import memsnav as mn

OMEGA_E = 7.292115e-5
C = 299792458.0
# 2015-10-07 10:00 GPST: GPS week 1865 (starts 2015-10-04) + 3 days 10 h.
START_2015 = 1865 * 604800.0 + 3 * 86400.0 + 10 * 3600.0


def brdc_2015() -> Path:
    return shared_data("gnss-products/2015-280/brdc2800.15n")


def brdc_2021() -> Path:
    return shared_data("gnss-products/2021-118/brdc1180.21n")


def sp3_2021() -> Path:
    return shared_data("gnss-products/2021-118/COD0MGXFIN_20211180000_01D_05M_ORB.SP3")


def nav_rinex3() -> Path:
    return shared_data("real-imu-gnss/walk_0827/gnss_1730.nav")


def track(duration=60.0, rate=10.0):
    """Straight east-bound motion at 20 m/s from Toulouse, written here."""
    lat, lon = math.radians(43.6), math.radians(1.44)
    origin = mn.geodetic_to_ecef([lat, lon, 150.0])
    east = np.array([-math.sin(lon), math.cos(lon), 0.0])
    t = np.arange(int(duration * rate) + 1) / rate
    v = np.tile(20.0 * east, (t.size, 1))
    return t, origin + t[:, None] * 20.0 * east, v


def test_broadcast_orbits_match_sp3():
    sky = mn.Constellation.from_rinex_nav(brdc_2021())
    sp3 = mn.read_sp3(sp3_2021())
    assert sp3.position_ecef.shape == (sp3.time.size, len(sp3.satellites), 3)
    errors = []
    for k in range(0, sp3.time.size, 6):
        pos, vel = sky.position_velocity(sp3.time[k])
        assert pos.shape == vel.shape == (len(sky.prns), 3)
        for i, prn in enumerate(sky.prns):
            if prn in sp3.satellites and np.isfinite(pos[i, 0]):
                precise = sp3.position_ecef[k, sp3.satellites.index(prn)]
                if np.isfinite(precise[0]):
                    errors.append(np.linalg.norm(pos[i] - precise))
    rms = math.sqrt(np.mean(np.square(errors)))
    assert len(errors) > 150
    assert rms < 3.0, rms
    # Clock corrections are microseconds to a millisecond, finite where orbits are.
    clk = sky.clock_correction(sp3.time[0])
    assert np.all(np.abs(clk[np.isfinite(clk)]) < 1e-3)


def test_prns_and_mixed_rinex3():
    assert mn.Constellation.from_rinex_nav(brdc_2015()).prns[:3] == ["G01", "G02", "G03"]
    sky = mn.Constellation.from_rinex_nav(nav_rinex3())
    assert sky.prns == ["G10", "G23", "G27", "G32"]
    pos, _ = sky.position_velocity(0.0)
    assert np.isnan(pos).all()


def test_walker_against_the_circular_orbit_formula():
    sky = mn.Constellation.walker(n_satellites=24, planes=6, inclination_deg=55.0)
    assert len(sky) == 24
    t = 1234.0
    pos, vel = sky.position_velocity(t)
    a = 26_560_000.0
    n = math.sqrt(3.986004418e14 / a**3)
    # Satellite 0: plane 0 (node at 0), slot 0, argument of latitude n t.
    u, inc, theta = n * t, math.radians(55.0), OMEGA_E * t
    r_inertial = a * np.array(
        [math.cos(u), math.sin(u) * math.cos(inc), math.sin(u) * math.sin(inc)]
    )
    rot = np.array(
        [[math.cos(theta), math.sin(theta), 0], [-math.sin(theta), math.cos(theta), 0], [0, 0, 1]]
    )
    np.testing.assert_allclose(pos[0], rot @ r_inertial, atol=1e-5)
    np.testing.assert_allclose(np.linalg.norm(pos, axis=1), a, rtol=1e-12)
    inertial_v = vel + np.cross([0, 0, OMEGA_E], pos)
    np.testing.assert_allclose(np.linalg.norm(inertial_v, axis=1), a * n, rtol=1e-12)


def test_nominal_galileo_and_beidou_walkers_have_their_published_orbits():
    sky = mn.Constellation.nominal(["G", "E", "C"])
    assert len(sky) == 72 and sky.systems == ["G", "E", "C"]
    assert sky.prns[:1] + sky.prns[24:25] + sky.prns[48:49] == ["G01", "E01", "C01"]
    assert mn.Constellation.nominal(["G"]).position_velocity(5.0)[0].tolist() == (
        mn.Constellation.walker().position_velocity(5.0)[0].tolist()
    )
    pos, vel = sky.position_velocity(777.0)
    inertial_v = vel + np.cross([0, 0, OMEGA_E], pos)
    period_min = 2 * math.pi * np.linalg.norm(pos, axis=1) / np.linalg.norm(inertial_v, axis=1)
    period_min /= 60.0
    # Published: GPS 11 h 58 min, Galileo 14 h 4 min, BeiDou MEO 12 h 53 min.
    for block, published in ((slice(0, 24), 718.0), (slice(24, 48), 844.0), (slice(48, 72), 773.0)):
        np.testing.assert_allclose(period_min[block], published, atol=1.0)
    for bad in (["G", "G"], ["X"], ["GE"], []):
        with pytest.raises(ValueError, match="systems"):
            mn.Constellation.nominal(bad)
    # GLONASS: 24/3/1 at 25 510 km, 11 h 15 min 49 s, slots R01-R24 (301-324).
    glonass = mn.Constellation.nominal(["R"])
    assert len(glonass) == 24 and glonass.prns[0] == "R01"
    pos, vel = glonass.position_velocity(777.0)
    inertial_v = vel + np.cross([0, 0, OMEGA_E], pos)
    period_min = 2 * math.pi * np.linalg.norm(pos, axis=1) / np.linalg.norm(inertial_v, axis=1)
    np.testing.assert_allclose(period_min / 60.0, 675.8, atol=1.0)


def test_inter_system_biases_are_in_the_other_systems_pseudoranges():
    t, p, v = track(20.0)
    sky = mn.Constellation.nominal(["G", "E", "C"])
    quiet = {"pseudorange_std": 0.0, "pseudorange_rate_std": 0.0, "seed": 2, "n_satellites": 40}
    plain = mn.simulate_gnss(t, p, v, sky, **quiet)
    biased = mn.simulate_gnss(t, p, v, sky, inter_system_bias=(3.0, -25.0), **quiet)
    np.testing.assert_array_equal(biased.inter_system_bias, [3.0, -25.0, 0.0])
    np.testing.assert_array_equal(plain.sat_id, biased.sat_id)
    ids = biased.sat_id
    difference = biased.pseudorange - plain.pseudorange
    expected = np.where(ids > 200, -25.0, np.where(ids > 100, 3.0, 0.0))
    np.testing.assert_allclose(difference[ids >= 0], expected[ids >= 0], atol=1e-6)
    assert {1, 101, 201} <= {int(i) // 100 * 100 + 1 for i in ids[ids >= 0]}
    with pytest.raises(ValueError, match="inter_system_bias"):
        mn.simulate_gnss(t, p, v, sky, inter_system_bias=(math.nan, 0.0))


def test_pseudorange_minus_range_is_clock_plus_noise():
    t, p, v = track(300.0)
    sky = mn.Constellation.from_rinex_nav(brdc_2015())
    meas = mn.simulate_gnss(t, p, v, sky, seed=3, start_gps_time=START_2015)
    assert len(meas) == 301
    assert meas.pseudorange.shape == (301, 6)
    assert meas.satellite_position_ecef.shape == (301, 6, 3)
    k = np.round(meas.time * 10).astype(int)
    sat = meas.satellite_position_ecef
    rx = p[k][:, None, :]
    # Independent geometry: rotate the transmission-time position by ω τ.
    tau = np.linalg.norm(sat - rx, axis=2) / C
    for _ in range(3):
        ang = OMEGA_E * tau
        x = np.cos(ang) * sat[..., 0] + np.sin(ang) * sat[..., 1]
        y = -np.sin(ang) * sat[..., 0] + np.cos(ang) * sat[..., 1]
        rng = np.linalg.norm(np.stack([x, y, sat[..., 2]], axis=-1) - rx, axis=2)
        tau = rng / C
    residual = meas.pseudorange - rng - meas.clock_offset[:, None]
    n = residual.size
    assert abs(residual.mean()) < 4 * 3.0 / math.sqrt(n)
    assert abs(residual.std() / 3.0 - 1) < 0.05
    assert np.all(meas.pseudorange_std == 3.0)


def test_fix_recovers_the_track():
    t, p, v = track(30.0)
    sky = mn.Constellation.walker()
    quiet = mn.simulate_gnss(t, p, v, sky, pseudorange_std=0.0, pseudorange_rate_std=0.0, seed=1)
    fix = mn.solve_fix(quiet)
    k = np.round(quiet.time * 10).astype(int)
    assert fix.valid.all()
    np.testing.assert_allclose(fix.position_ecef, p[k], atol=1e-3)
    np.testing.assert_allclose(fix.velocity_ecef, v[k], atol=1e-4)
    np.testing.assert_allclose(fix.clock_offset, quiet.clock_offset, atol=1e-3)
    np.testing.assert_allclose(fix.clock_drift, quiet.clock_drift, atol=1e-4)
    assert np.all(fix.gdop >= fix.pdop)
    noisy = mn.solve_fix(mn.simulate_gnss(t, p, v, sky, seed=2))
    err = noisy.position_ecef - p[k]
    predicted = np.sqrt(np.trace(noisy.position_clock_covariance[:, :3, :3], axis1=1, axis2=2))
    ratio = np.sqrt(np.mean(np.sum(err**2, axis=1))) / np.mean(predicted)
    assert 0.6 < ratio < 1.5, ratio


def test_seeded_reproducibility_and_outages():
    t, p, v = track(60.0)
    sky = mn.Constellation.walker()
    kw = dict(residual_std=1.0, outages=[(10.0, 5.0), (20.0, 10.0, 4)])
    a = mn.simulate_gnss(t, p, v, sky, seed=7, **kw)
    b = mn.simulate_gnss(t, p, v, sky, seed=7, **kw)
    c = mn.simulate_gnss(t, p, v, sky, seed=8, **kw)
    np.testing.assert_array_equal(a.pseudorange, b.pseudorange)
    assert not np.array_equal(a.pseudorange, c.pseudorange, equal_nan=True)
    total = (a.time >= 10.0) & (a.time < 15.0)
    partial = (a.time >= 20.0) & (a.time < 30.0)
    assert np.all(a.n_satellites[total] == 0)
    assert np.all(a.n_satellites[partial] == 4)
    assert np.all(a.n_satellites[~total & ~partial] == 6)
    assert np.all(a.sat_id[total] == -1)
    assert np.isnan(a.pseudorange[partial][:, 4:]).all()
    fix = mn.solve_fix(a)
    assert not fix.valid[total].any() and fix.valid[partial].all()
    assert np.isnan(fix.position_ecef[total]).all()
    with pytest.raises(ValueError, match="at least 4 satellites"):
        mn.solve_fix(a, strict=True)


def test_bad_inputs(tmp_path):
    lines = brdc_2015().read_text().splitlines()
    cut = tmp_path / "cut.15n"
    cut.write_text("\n".join(lines[:19]))
    with pytest.raises(mn.ParseError, match=r"cut\.15n:20: truncated record for G02"):
        mn.Constellation.from_rinex_nav(cut)
    junk = tmp_path / "junk.txt"
    junk.write_text("not a rinex file\n")
    with pytest.raises(mn.ParseError, match=r"junk\.txt:1:"):
        mn.Constellation.from_rinex_nav(junk)
    with pytest.raises(OSError):
        mn.Constellation.from_rinex_nav(tmp_path / "missing.15n")
    with pytest.raises(mn.ParseError, match=r"junk\.txt:1:"):
        mn.read_sp3(junk)
    with pytest.raises(ValueError, match="n_satellites"):
        mn.Constellation.walker(n_satellites=25)
    with pytest.raises(ValueError, match="inclination"):
        mn.Constellation.walker(inclination_deg=200.0)
    sky = mn.Constellation.walker()
    with pytest.raises(ValueError, match="gps_time"):
        sky.position_velocity(float("nan"))
    t, p, v = track(5.0)
    with pytest.raises(ValueError, match=r"^time:"):
        mn.simulate_gnss(t[::-1], p, v, sky)
    bad = p.copy()
    bad[3, 1] = np.nan
    with pytest.raises(ValueError, match=r"^position_ecef:"):
        mn.simulate_gnss(t, bad, v, sky)
    with pytest.raises(ValueError, match=r"^velocity_ecef:"):
        mn.simulate_gnss(t, p, v[:, :2], sky)
    with pytest.raises(ValueError, match=r"^velocity_ecef:"):
        mn.simulate_gnss(t, p, v[1:], sky)
    with pytest.raises(ValueError, match=r"^rate:"):
        mn.simulate_gnss(t, p, v, sky, rate=0.0)
    with pytest.raises(ValueError, match=r"^elevation_mask"):
        mn.simulate_gnss(t, p, v, sky, elevation_mask_deg=95.0)
    with pytest.raises(ValueError, match=r"^pseudorange_std:"):
        mn.simulate_gnss(t, p, v, sky, pseudorange_std=-1.0)
    with pytest.raises(ValueError, match=r"^outages:"):
        mn.simulate_gnss(t, p, v, sky, outages=[(1.0,)])
    with pytest.raises(ValueError, match=r"^outages:"):
        mn.simulate_gnss(t, p, v, sky, outages=[(1.0, -2.0)])
    with pytest.raises(ValueError, match=r"^start_gps_time:"):
        mn.simulate_gnss(t, p, v, mn.Constellation.from_rinex_nav(brdc_2015()), start_gps_time=0.0)
    meas = mn.simulate_gnss(t, p, v, sky)
    with pytest.raises(ValueError, match=r"^prior:"):
        mn.solve_fix(meas, prior=[1.0, 2.0])


L1_WAVELENGTH = C / 1575.42e6  # IS-GPS-200 §3.3.1.1: f_L1 = 1575.42 MHz.


def test_simulated_carrier_phase_and_its_slips():
    """Carrier minus noise-free code is a whole number of L1 cycles that
    changes only at the listed slips, by the listed cycles; the pseudoranges
    are the numbers of a simulation without carrier phase."""
    t, p, v = track(120.0)
    sky = mn.Constellation.walker()
    quiet = {"pseudorange_std": 0.0, "pseudorange_rate_std": 0.0, "seed": 4}
    plain = mn.simulate_gnss(t, p, v, sky, **quiet)
    meas = mn.simulate_gnss(
        t, p, v, sky, carrier_phase_std=0.001, cycle_slip_probability=0.05, **quiet
    )
    np.testing.assert_array_equal(meas.pseudorange, plain.pseudorange)
    np.testing.assert_array_equal(meas.pseudorange_rate, plain.pseudorange_rate)
    tracked = meas.sat_id >= 0
    assert np.isfinite(meas.carrier_phase[tracked]).all()
    assert np.isnan(meas.carrier_phase[~tracked]).all() and np.isnan(plain.carrier_phase).all()
    assert (meas.carrier_phase_std[tracked] == 0.001).all()
    assert meas.loss_of_lock[0][tracked[0]].all() and not meas.loss_of_lock[1:].any()
    assert meas.loss_of_lock.dtype == bool
    cycles = (meas.carrier_phase - meas.pseudorange) / L1_WAVELENGTH
    assert np.abs(cycles[tracked] - np.round(cycles[tracked])).max() < 0.05
    found = []
    for k in range(1, len(meas)):
        for j, sat in enumerate(meas.sat_id[k]):
            (before,) = np.flatnonzero(meas.sat_id[k - 1] == sat)
            jump = round(cycles[k, j] - cycles[k - 1, before])
            if jump:
                found.append((meas.time[k], int(sat), jump))
    slips = meas.cycle_slips
    listed = list(
        zip(slips["time"], slips["sat_id"].tolist(), slips["cycles"].tolist(), strict=True)
    )
    assert sorted(found) == sorted(listed) and 15 <= len(listed) <= 60
    assert {len(a) for a in plain.cycle_slips.values()} == {0}


def test_carrier_phase_arrays_round_trip():
    t, p, v = track(20.0)
    sky = mn.Constellation.walker()
    meas = mn.simulate_gnss(t, p, v, sky, carrier_phase_std=0.003, seed=1)
    arrays = {
        name: getattr(meas, name)
        for name in (
            "time", "sat_id", "satellite_position_ecef", "satellite_velocity_ecef",
            "pseudorange", "pseudorange_std", "pseudorange_rate", "pseudorange_rate_std",
            "carrier_phase", "carrier_phase_std", "loss_of_lock",
        )
    }  # fmt: skip
    # A satellite without carrier at one epoch: NaN range (its σ ignored).
    arrays["carrier_phase"] = arrays["carrier_phase"].copy()
    arrays["carrier_phase"][5, 2] = math.nan
    back = mn.GnssMeasurements(**arrays)
    np.testing.assert_array_equal(back.carrier_phase, arrays["carrier_phase"])
    np.testing.assert_array_equal(back.loss_of_lock, meas.loss_of_lock)
    assert math.isnan(back.carrier_phase_std[5, 2])
    # solve_fix takes the dict with its carrier entries.
    assert mn.solve_fix(arrays).valid.all()
    # The long table: one row per tracked slot.
    rows = meas.sat_id >= 0
    k, _ = np.nonzero(rows)
    table = {
        "time_s": meas.time[k],
        "sat_id": meas.sat_id[rows],
        **{
            f"sat_{kind}_ecef_{a}_m{unit}": getattr(meas, f"satellite_{kind}_ecef")[rows][:, i]
            for kind, unit in (("position", ""), ("velocity", "_s"))
            for i, a in enumerate("xyz")
        },
        "pseudorange_m": meas.pseudorange[rows],
        "carrier_phase_m": meas.carrier_phase[rows],
        "carrier_phase_std_m": meas.carrier_phase_std[rows],
        "loss_of_lock": meas.loss_of_lock[rows].astype(float),
    }
    from_table = mn.GnssMeasurements.from_table(table)
    np.testing.assert_array_equal(from_table.carrier_phase, meas.carrier_phase)
    np.testing.assert_array_equal(from_table.loss_of_lock, meas.loss_of_lock)


def test_bad_carrier_phase_inputs_are_named():
    t, p, v = track(5.0)
    sky = mn.Constellation.walker()
    for kwargs, message in [
        ({"carrier_phase_std": -0.003}, "carrier_phase_std: must be finite and non-negative"),
        ({"carrier_phase_std": math.nan}, "carrier_phase_std"),
        ({"cycle_slip_probability": 1.5}, r"cycle_slip_probability: must be within \[0, 1\]"),
    ]:
        with pytest.raises(ValueError, match=message):
            mn.simulate_gnss(t, p, v, sky, **kwargs)
    meas = mn.simulate_gnss(t, p, v, sky, carrier_phase_std=0.003, seed=1)
    base = {
        name: getattr(meas, name)
        for name in (
            "time", "sat_id", "satellite_position_ecef", "satellite_velocity_ecef",
            "pseudorange", "pseudorange_std",
        )
    }  # fmt: skip
    carrier, std = meas.carrier_phase.copy(), meas.carrier_phase_std.copy()
    with pytest.raises(ValueError, match="give both, or neither"):
        mn.GnssMeasurements(**base, carrier_phase=carrier)
    with pytest.raises(ValueError, match="give both, or neither"):
        mn.solve_fix({**base, "carrier_phase_std": std})
    bad = carrier.copy()
    bad[1, 3] = math.inf
    with pytest.raises(ValueError, match=r"gnss: \[1, 3\] \(time 1(\.0)? s\): carrier_phase = inf"):
        mn.GnssMeasurements(**base, carrier_phase=bad, carrier_phase_std=std)
    bad = std.copy()
    bad[2, 0] = 0.0
    with pytest.raises(ValueError, match=r"gnss: \[2, 0\].*carrier_phase_std = 0 m"):
        mn.GnssMeasurements(**base, carrier_phase=carrier, carrier_phase_std=bad)
    flags = np.zeros(carrier.shape)
    flags[0, 0] = 2.0
    with pytest.raises(ValueError, match=r"gnss: \[0, 0\].*loss_of_lock = 2"):
        mn.GnssMeasurements(
            **base, carrier_phase=carrier, carrier_phase_std=std, loss_of_lock=flags
        )
    with pytest.raises(ValueError, match="carrier_phse"):
        mn.solve_fix({**base, "carrier_phse": carrier})


def test_rinex_carrier_phase_follows_its_option():
    """The L1C phase of the walk excerpt (written by the receiver) becomes
    carrier ranges near the pseudoranges' scale, with a σ that scales with
    ``carrier_phase_std``; 0 drops them."""
    excerpt = Path(__file__).parent / "data" / "real-imu-gnss"
    obs = mn.read_rinex_obs(excerpt / "walk_head.obs")
    sky = mn.Constellation.from_rinex_nav(excerpt / "walk.nav")
    default = obs.gps_l1(sky)
    tracked = default.sat_id >= 0
    assert np.isfinite(default.carrier_phase[tracked]).all()
    assert np.isnan(obs.gps_l1(sky, carrier_phase_std=0.0).carrier_phase).all()
    doubled = obs.gps_l1(
        sky, carrier_phase_std=2 * mn.defaults()["RinexObservations.gps_l1"]["carrier_phase_std"]
    )
    np.testing.assert_allclose(
        doubled.carrier_phase_std[tracked], 2 * default.carrier_phase_std[tracked]
    )
    ephemerides = mn.read_broadcast_nav(excerpt / "walk.nav")
    several = obs.measurements(ephemerides, systems=["G"], carrier_phase_std=0.0)
    assert len(several) and np.isnan(several.carrier_phase).all()
    with pytest.raises(ValueError, match="carrier_phase_std"):
        obs.gps_l1(sky, carrier_phase_std=-1.0)
