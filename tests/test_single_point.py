"""Single-point positioning against RTKLIB and under faults: the default
pseudorange weighting (RTKLIB's error model) gives horizontal and vertical
RMS within 5 % of RTKLIB 2.4.3's single mode on a GPS + GLONASS file, and
the residual test of ``solve_fix`` leaves out a satellite given a large
error while a fault-free epoch keeps every satellite (at the stated
false-alarm rate, checked on simulated noise of known σ).

The RTKLIB solution ``skydel_20230080000_GR_rtklib_single.pos`` was made by
``rnx2rtkp -k rtklib_single_noatm.conf -sys G,R -o <pos>
skydel_20230080000_GR_C1C.rnx skydel_20230080000_GR_nav.rnx`` (RTKLIB
2.4.3 b34, Debian's package; single mode, L1, 10° mask, no ionosphere or
troposphere: the simulation has none); the files are in
``tests/data/rinex-public`` with their README and licence."""

from __future__ import annotations

import warnings
from pathlib import Path

import numpy as np
import pytest
import single_point_rtklib

import memsnav as mn

PUBLIC = Path(__file__).parent / "data" / "rinex-public"
#: The Skydel simulation's receiver (its README), ECEF m.
SKYDEL_TRUTH = np.array([-481819.31349724, 5507219.95375401, 3170373.73538364])


def _enu(errors_ecef: np.ndarray, reference_ecef: np.ndarray) -> np.ndarray:
    lat, lon, _ = mn.ecef_to_geodetic(reference_ecef)
    sl, cl, so, co = np.sin(lat), np.cos(lat), np.sin(lon), np.cos(lon)
    rotation = np.array([[-so, co, 0.0], [-sl * co, -sl * so, cl], [cl * co, cl * so, sl]])
    return errors_ecef @ rotation.T


def _rms_h_v(position_ecef: np.ndarray, truth_ecef: np.ndarray) -> tuple[float, float]:
    enu = _enu(position_ecef - truth_ecef, truth_ecef)
    return (
        float(np.sqrt(np.mean(enu[:, 0] ** 2 + enu[:, 1] ** 2))),
        float(np.sqrt(np.mean(enu[:, 2] ** 2))),
    )


def _skydel_gr(**options: object) -> mn.GnssMeasurements:
    obs = mn.read_rinex_obs(PUBLIC / "skydel_20230080000_GR_C1C.rnx")
    eph = mn.read_broadcast_nav(PUBLIC / "skydel_20230080000_GR_nav.rnx")
    return obs.measurements(
        eph,
        SKYDEL_TRUTH,
        systems=["G", "R"],
        ionosphere=False,
        troposphere=False,
        **options,  # type: ignore[arg-type]
    )


def _rtklib_positions(path: Path) -> np.ndarray:
    rows = [line.split() for line in path.read_text().splitlines() if not line.startswith("%")]
    return np.array([[float(r[2]), float(r[3]), float(r[4])] for r in rows])


def test_gps_glonass_rms_is_within_five_percent_of_rtklib_single_mode():
    gnss = _skydel_gr()
    ids = np.asarray(gnss.sat_id)
    assert np.any(ids > 300), "GLONASS in the fix"
    fixes = mn.solve_fix(gnss)
    assert np.all(fixes.valid), "availability: every epoch RTKLIB solves"
    ours = _rms_h_v(fixes.position_ecef, SKYDEL_TRUTH)
    rtklib = _rtklib_positions(PUBLIC / "skydel_20230080000_GR_rtklib_single.pos")
    assert len(rtklib) == len(fixes.time)
    theirs = _rms_h_v(rtklib, SKYDEL_TRUTH)
    print(
        f"H/V RMS, m: memsnav {ours[0]:.3f}/{ours[1]:.3f}, RTKLIB {theirs[0]:.3f}/{theirs[1]:.3f}"
    )
    assert ours[0] <= 1.05 * theirs[0], (ours, theirs)
    assert ours[1] <= 1.05 * theirs[1], (ours, theirs)


def test_the_signal_strength_weighting_is_worse_in_height_on_the_same_file():
    """The model the default replaced: the vertical is what it cost."""
    rtklib = mn.solve_fix(_skydel_gr())
    strength = mn.solve_fix(_skydel_gr(weighting="signal-strength"))
    v_rtklib = _rms_h_v(rtklib.position_ecef, SKYDEL_TRUTH)[1]
    v_strength = _rms_h_v(strength.position_ecef, SKYDEL_TRUTH)[1]
    assert v_strength > 1.15 * v_rtklib, (v_strength, v_rtklib)


def test_weighting_and_pseudorange_std_are_checked():
    with pytest.raises(ValueError, match='weighting: "elevation" is not a weighting model'):
        _skydel_gr(weighting="elevation")
    with pytest.raises(ValueError, match='pseudorange_std: sets the "signal-strength"'):
        _skydel_gr(pseudorange_std=2.0)
    loose = _skydel_gr(weighting="signal-strength", pseudorange_std=6.0)
    tight = _skydel_gr(weighting="signal-strength", pseudorange_std=3.0)
    np.testing.assert_allclose(loose.pseudorange_std, 2.0 * tight.pseudorange_std)


def test_glonass_weights_are_one_and_a_half_times_gps_in_the_receiver_term():
    """At equal elevation the RTKLIB model's σ² differ by the system factor's
    receiver term and GLONASS's 5 m ephemeris error against GPS's 2.4 m."""
    gnss = _skydel_gr()
    ids, std = np.asarray(gnss.sat_id), np.asarray(gnss.pseudorange_std)
    el = np.asarray(gnss.elevation_rad)
    var = std**2
    # No ionosphere or troposphere corrections: RTKLIB's 5 m and 3 m.
    rest = 0.09 + 25.0 + 9.0
    gps, glo = (ids >= 0) & (ids < 100), ids > 300
    receiver = 0.09 + 0.09 / np.sin(el)
    np.testing.assert_allclose(var[gps], receiver[gps] + 2.4**2 + rest, rtol=1e-9)
    np.testing.assert_allclose(var[glo], 2.25 * receiver[glo] + 5.0**2 + rest, rtol=1e-9)


def _clean_epoch() -> dict[str, np.ndarray]:
    """The first epoch of the Skydel file as padded arrays, one row."""
    gnss = _skydel_gr()
    keys = (
        "sat_id",
        "satellite_position_ecef",
        "satellite_velocity_ecef",
        "pseudorange",
        "pseudorange_std",
    )
    epoch = {k: np.asarray(getattr(gnss, k))[:1].copy() for k in keys}
    epoch["time"] = np.asarray(gnss.time)[:1].copy()
    return epoch


def test_a_large_error_on_one_satellite_is_excluded_and_the_fix_recovers():
    clean_epoch = _clean_epoch()
    clean = mn.solve_fix(clean_epoch)
    assert clean.excluded == [[]]
    assert clean.residual_chi_square[0] <= clean.residual_threshold[0]
    ids = clean_epoch["sat_id"][0]
    for slot in np.flatnonzero(ids >= 0):
        faulty = {k: v.copy() for k, v in clean_epoch.items()}
        faulty["pseudorange"][0, slot] += 100.0
        untested = mn.solve_fix(faulty, false_alarm_probability=None)
        tested = mn.solve_fix(faulty)
        name = ("G" if ids[slot] < 100 else "R") + f"{int(ids[slot]) % 100:02d}"
        assert tested.excluded == [[name]], (name, tested.excluded)
        moved = np.linalg.norm(untested.position_ecef[0] - clean.position_ecef[0])
        recovered = np.linalg.norm(tested.position_ecef[0] - clean.position_ecef[0])
        assert recovered < 0.3 * moved or recovered < 1.0, (name, moved, recovered)
        assert tested.residual_chi_square[0] <= tested.residual_threshold[0]


def test_fault_free_epochs_fail_the_test_at_the_false_alarm_rate():
    """Simulated pseudoranges whose noise has exactly the σ given: the share
    of epochs with an exclusion is the false-alarm probability (binomial
    band of 4 σ)."""
    traj = mn.Trajectory.random(duration=600.0, rate=10.0, seed=3)
    gnss = mn.simulate_gnss(
        traj.time,
        traj.position_ecef,
        traj.velocity_ecef,
        mn.Constellation.walker(),
        rate=2.0,
        n_satellites=9,
        pseudorange_std=3.0,
        seed=5,
    )
    p_fa = 0.05
    fixes = mn.solve_fix(gnss, false_alarm_probability=p_fa)
    n = int(np.sum(fixes.valid))
    alarms = sum(1 for e in fixes.excluded if e)
    band = 4.0 * np.sqrt(n * p_fa * (1.0 - p_fa))
    print(f"{alarms} of {n} fault-free epochs excluded a satellite (expected {n * p_fa:.0f})")
    assert abs(alarms - n * p_fa) < band, (alarms, n)
    default = mn.solve_fix(gnss)
    assert sum(1 for e in default.excluded if e) <= 0.001 * n + 4.0 * np.sqrt(0.001 * n) + 1


def test_the_false_alarm_probability_is_checked():
    with pytest.raises(ValueError, match="false_alarm_probability"):
        mn.solve_fix(_clean_epoch(), false_alarm_probability=1.5)


def test_real_cors_epochs_keep_every_satellite():
    """SLAC's five epochs (RINEX 2.11, GPS): nothing to exclude."""
    from shared_data import shared_data

    obs = mn.read_rinex_obs(PUBLIC / "slac1180_excerpt.21o")
    eph = mn.read_broadcast_nav(shared_data("gnss-products/2021-118/brdc1180.21n"))
    with warnings.catch_warnings():
        warnings.simplefilter("error")
        fixes = mn.solve_fix(obs.measurements(eph, systems=["G"]))
    assert all(e == [] for e in fixes.excluded)
    assert np.all(fixes.residual_chi_square <= fixes.residual_threshold)


def test_the_recorded_comparison_is_this_code_and_the_page_quotes_it():
    """docs/single_point_rtklib.json (written by docs/single_point_rtklib.py)
    holds what the code gives on the Skydel excerpt, and docs/how-to/convert-ublox.md's
    table is rendered from it."""
    import json

    root = Path(__file__).parent.parent
    recorded = json.loads((root / "docs" / "single_point_rtklib.json").read_text())
    skydel = recorded["skydel_gps_glonass"]
    for weighting in ("rtklib", "signal-strength"):
        fixes = mn.solve_fix(_skydel_gr(weighting=weighting))
        h, v = _rms_h_v(fixes.position_ecef, SKYDEL_TRUTH)
        assert skydel[f"memsnav_{weighting}"]["horizontal_rms_m"] == round(h, 3)
        assert skydel[f"memsnav_{weighting}"]["vertical_rms_m"] == round(v, 3)
    text = single_point_rtklib.PAGE.read_text()
    begin, end = single_point_rtklib.BEGIN, single_point_rtklib.END
    block = text[text.index(begin) : text.index(end) + len(end)]
    assert block == single_point_rtklib.render_table(recorded), (
        "the how-to's table is not what docs/single_point_rtklib.py renders from its record"
    )
