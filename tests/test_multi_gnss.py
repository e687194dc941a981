"""Several systems in the tight filter: GPS, Galileo and BeiDou
measurements from the walk's own u-blox log, the inter-system-bias states
(simulated truth recovered; a filter without them refuses other systems),
what ``measurements`` refuses, and the walk's figures per configuration
as the navigate guide quotes them.

Real data: walk_0827 (licence in the shared data's real-imu-gnss/LICENSE),
found through the data-root resolver.
"""

from __future__ import annotations

import re
from pathlib import Path
from typing import Any

import numpy as np
import pytest
import walk_multi_gnss
from figures import figures
from record_agreement import agree
from shared_data import shared_data

import memsnav as mn
from memsnav.realdata.answer import answer_lines

ROOT = Path(__file__).resolve().parents[1]
UBX = walk_multi_gnss.UBX
RECORD = figures("walk_multi_gnss")
"""The walk's figures docs/how-to/multi-gnss.md shows (docs/walk_multi_gnss.py)."""


@pytest.fixture(scope="module")
def walk_log():
    return mn.read_ubx(shared_data(UBX))


def _numbers(gnss) -> set[int]:
    ids = np.asarray(gnss.sat_id)
    return {int(v) for v in ids[np.isfinite(ids)].ravel() if v > 0}


def test_the_walk_log_gives_three_systems(walk_log):
    """Every healthy satellite with an ephemeris and a signal the model
    takes: 7 GPS (4 LNAV + 3 CNAV), 6 Galileo (E14 unhealthy left out), 7
    BeiDou on B3I (C50 unhealthy left out; C36, C45, C49 have no D1
    ephemeris in the log)."""
    eph = walk_log.broadcast_ephemerides
    gnss = walk_log.observations.measurements(eph, elevation_mask_deg=5.0, min_cn0_db_hz=20.0)
    assert _numbers(gnss) == {
        *(8, 10, 18, 23, 24, 27, 32),
        *(100 + p for p in (7, 8, 13, 26, 29, 33)),
        *(200 + p for p in (11, 21, 22, 34, 42, 43, 44)),
    }
    gps = walk_log.observations.measurements(eph, systems=["G"], satellites=["G10", "G23"])
    assert _numbers(gps) == {10, 23}


def test_the_log_measurements_fit_one_position_per_system(walk_log):
    """The least-squares fix of every epoch with one clock and two
    inter-system biases fits all 20 satellites: its position sits within
    the broadcast solutions' 8-10 m of the receiver's own RTK (NAV-PVT;
    the data README's offset), and the biases are steady over the log
    (each system's group delays and time offsets applied right would
    leave only the receiver's; a wrong one moves with the geometry)."""
    gnss = walk_log.observations.measurements(
        walk_log.broadcast_ephemerides,
        elevation_mask_deg=5.0,
        min_cn0_db_hz=30.0,
        klobuchar=walk_log.klobuchar,
    )
    pvt = mn.geodetic_to_ecef(walk_log.fixes.lla)
    fixes = mn.solve_fix(gnss)
    matched = np.searchsorted(walk_log.fixes.gps_time, gnss.gps_time).clip(0, len(pvt) - 1)
    offsets = np.linalg.norm(fixes.position_ecef - pvt[matched], axis=1)
    # Galileo and BeiDou; GLONASS (the third column) is not in the log.
    biases = fixes.inter_system_bias[:, :2]
    assert np.all(np.isfinite(biases)) and np.all(np.isnan(fixes.inter_system_bias[:, 2]))
    assert np.median(offsets) < 12.0, np.median(offsets)
    assert np.all(np.std(biases, axis=0) < 1.5), np.std(biases, axis=0)


def test_the_geometry_free_delays_are_the_records(walk_log):
    """docs/how-to/multi-gnss.md: G24, G27 and G18 at one elevation
    average delays metres apart, measured from L2C and averaged over the
    log (shown to 0.1 m, the elevations to the degree)."""
    fresh = walk_multi_gnss.geometry_free_delays(walk_log)
    recorded = RECORD["geometry_free"]
    np.testing.assert_allclose(fresh["delay_m"], recorded["delay_m"], atol=0.05)
    for end in ("least", "most"):
        assert abs(fresh["elevation_deg"][end] - recorded["elevation_deg"][end]) <= 0.5
    # Metres apart where the 1/f² law puts them decimetres apart.
    assert max(fresh["delay_m"]) - min(fresh["delay_m"]) > 3.0
    settings = walk_multi_gnss.DELAY_SETTINGS
    measured = walk_log.observations.measurements(
        walk_log.broadcast_ephemerides, dual_frequency=True, **settings
    )
    assert {name for row in measured.signal for name in row if name} == {"L1 C/A + L2C (L)"}


def test_measurements_refuse_what_they_cannot_use(walk_log):
    eph, obs = walk_log.broadcast_ephemerides, walk_log.observations
    with pytest.raises(ValueError, match="systems"):
        obs.measurements(eph, systems=["J"])
    with pytest.raises(ValueError, match="systems"):
        obs.measurements(eph, systems=[])
    with pytest.raises(ValueError, match="satellites"):
        obs.measurements(eph, satellites=["X01"])
    with pytest.raises(ValueError, match="satellites"):
        obs.measurements(eph, satellites=["G1O"])


def test_inter_system_biases_are_estimated_and_needed(drive_300s):
    """A tight run on G + E + C with biases +3 and −25 m estimates them
    within 3σ; a running filter started without the states refuses a
    Galileo epoch, naming it, and one started with them takes it."""
    traj, _, imu, f, w = drive_300s
    n = 6001
    sky = mn.Constellation.nominal(["G", "E", "C"])
    gnss = mn.simulate_gnss(
        traj.time[:n],
        traj.position_ecef[:n],
        traj.velocity_ecef[:n],
        sky,
        n_satellites=20,
        inter_system_bias=(3.0, -25.0),
        seed=8,
    )
    start = _true_start(traj)
    flt = mn.TightlyCoupledFilter(imu)
    sol = flt.run(traj.time[:n], f[:n], w[:n], gnss, initial_state=start)
    names = list(sol.state_names)
    assert names[-3:] == [
        "inter_system_bias_galileo",
        "inter_system_bias_beidou",
        "inter_system_bias_glonass",
    ]
    estimate = sol.inter_system_bias[-1, :2]
    sigma = np.sqrt(np.asarray(sol.covariance_diagonal)[-1, -3:-1])
    assert np.all(np.abs(estimate - np.array([3.0, -25.0])) < 3.0 * sigma), (estimate, sigma)
    assert np.all(sigma < 1.0)
    galileo = next(k for k in range(len(gnss.time)) if np.any(np.asarray(gnss.sat_id)[k] > 100))
    running = flt.start(traj.time[0], f[0], w[0], start)
    _predict_to(running, traj, f, w, gnss.time[galileo])
    with pytest.raises(ValueError, match="inter-system-bias"):
        running.update_gnss(gnss, galileo)
    running = flt.start(traj.time[0], f[0], w[0], start, inter_system_biases=True)
    _predict_to(running, traj, f, w, gnss.time[galileo])
    running.update_gnss(gnss, galileo)
    assert len(running.state.inter_system_bias) == 3


def test_the_glonass_inter_system_bias_is_estimated(drive_300s):
    """A tight run on simulated GPS + GLONASS (``systems`` "G", "R"; a
    GLONASS bias of +12 m as the third ``inter_system_bias``) estimates it
    within 3σ, σ below 0.5 m, and stays within metres of the truth."""
    traj, _, imu, f, w = drive_300s
    n = 6001
    sky = mn.Constellation.nominal(["G", "R"])
    gnss = mn.simulate_gnss(
        traj.time[:n],
        traj.position_ecef[:n],
        traj.velocity_ecef[:n],
        sky,
        n_satellites=16,
        inter_system_bias=(0.0, 0.0, 12.0),
        seed=9,
    )
    np.testing.assert_array_equal(gnss.inter_system_bias, [0.0, 0.0, 12.0])
    ids = np.asarray(gnss.sat_id)
    assert np.any(ids > 300)
    sol = mn.TightlyCoupledFilter(imu).run(
        traj.time[:n], f[:n], w[:n], gnss, initial_state=_true_start(traj)
    )
    estimate = sol.inter_system_bias[-1, 2]
    sigma = np.sqrt(np.asarray(sol.covariance_diagonal)[-1, -1])
    assert abs(estimate - 12.0) < 3.0 * sigma, (estimate, sigma)
    assert sigma < 0.5
    error = np.linalg.norm(sol.position_ecef - traj.position_ecef[:n], axis=1)
    assert np.max(error[100:]) < 5.0, np.max(error)


def _true_start(traj) -> dict[str, Any]:
    """The filters' initial state: the trajectory's first sample."""
    return {
        "position_ecef": traj.position_ecef[0],
        "velocity_ecef": traj.velocity_ecef[0],
        "attitude": traj.attitude[0],
    }


def _predict_to(running, traj, f, w, time):
    k = int(np.searchsorted(traj.time, running.time, side="right"))
    while running.time < time - 1e-9:
        running.predict(traj.time[k], f[k], w[k])
        k += 1


#: The walk tables' configurations by row label (docs/walk_multi_gnss.py).
CONFIGURATIONS = dict(walk_multi_gnss.CONFIGURATIONS.values())
#: Their keys in the records, by row label.
KEYS = {label: key for key, (label, _) in walk_multi_gnss.CONFIGURATIONS.items()}


def _navigate(
    example: str,
    output: Path,
    overrides: dict | None = None,
    engine: dict[str, dict] | None = None,
) -> Any:
    """``memsnav navigate`` of ``examples/<example>`` on the shared data
    (docs/walk_multi_gnss.py's ``navigate``)."""
    data = shared_data("real-imu-gnss/walk_0827").parent.parent
    return walk_multi_gnss.navigate(data, output, overrides, engine, example)


def test_the_walk_figures_per_configuration_are_the_runs(tmp_path):
    """docs/how-to/multi-gnss.md's configuration table is
    docs/data/walk_configurations.json: each configuration of
    examples/walk_0827_multi_gnss.toml run today agrees with it within
    half the 0.01 m shown (satellite counts exactly)."""
    table = figures("walk_configurations")
    assert table.keys() == walk_multi_gnss.CONFIGURATIONS.keys()
    for name, overrides in CONFIGURATIONS.items():
        s = _navigate("walk_0827_multi_gnss.toml", tmp_path / "walk", overrides).summary
        fresh, row = walk_multi_gnss.configuration_row(s), table[KEYS[name]]
        assert fresh["satellites"] == row["satellites"], name
        measured = [v for k, v in fresh.items() if k != "satellites"]
        expected = [v for k, v in row.items() if k != "satellites"]
        np.testing.assert_allclose(measured, expected, rtol=0, atol=0.005, err_msg=name)
        # Slots are named by satellite (12 of them: with 20 satellites the
        # ones that found none are used with their bias variance as noise).
        systems = {key[0] for key in s["range_biases_m"]}
        assert systems <= set(overrides["systems"]), (name, s["range_biases_m"])
        assert all(re.fullmatch(r"[GEC]\d\d", key) for key in s["range_biases_m"])
        assert ("inter_system_bias_m" in s) == (overrides["systems"] != ["G"])
        carrier = s["measurements"].get("carrier_phase", {})
        if "carrier phase" in name:
            # Most changes are used; the rest are slips (flags, Doppler)
            # or excluded by the residual test, never a whole epoch gated.
            assert carrier["accepted"] > 0.9 * sum(carrier.values()), carrier
            assert set(carrier) <= {"accepted", "slip", "excluded"}, carrier
            # The satellite table's slip column holds the carrier's slips.
            slips = sum(r["slips"] for r in s["satellites"])
            assert slips == carrier.get("slip", 0) > 0, (slips, carrier)
            if len(overrides["systems"]) == 3:
                assert walk_multi_gnss.slips(s) == RECORD["carrier_slips"]
        else:
            assert not carrier, (name, carrier)
        if name == "GPS + Galileo + BeiDou":
            isb, recorded = s["inter_system_bias_m"], RECORD["inter_system_bias_m"]
            assert all(abs(isb[k] - recorded[k]) <= 0.006 for k in ("galileo", "beidou")), isb


@pytest.mark.slow
def test_the_carrier_floors_are_the_record():
    """docs/how-to/multi-gnss.md: all three systems with carrier phase at
    floors of 0.5-8 cm (five runs): the horizontal precision (shown to the
    cm) and the changes gated (exactly); none gated from 2 cm on."""
    fresh = walk_multi_gnss.carrier_floors(shared_data("real-imu-gnss").parent)
    recorded = figures("walk_carrier_floors")
    assert fresh["floors_cm"] == recorded["floors_cm"]
    assert fresh["gated"] == recorded["gated"]
    np.testing.assert_allclose(fresh["precision_m"], recorded["precision_m"], atol=0.006)
    assert fresh["gated"][2:] == [0, 0, 0] and fresh["gated"][0] > 0


@pytest.mark.slow
def test_the_g08_start_is_the_record():
    """docs/how-to/multi-gnss.md, "GPS alone on all seven is worse than on
    four": G08's entry, its first 2 s of innovations and their stds, the
    error against the truth it causes (one run), what a 28 dB-Hz C/N0
    mask does (four) and wider or faster range-bias models (three), within
    the digits shown."""
    fresh = walk_multi_gnss.g08_record(shared_data("real-imu-gnss").parent)
    recorded = figures("walk_g08")
    g08, kept = fresh["g08"], recorded["g08"]
    assert g08["early_pseudoranges"] == kept["early_pseudoranges"]
    assert abs(g08["entry_s"] - kept["entry_s"]) <= 0.005
    for key in ("early_innovation_m", "early_innovation_std_m"):
        for end in ("least", "most"):
            assert abs(g08[key][end] - kept[key][end]) <= 0.05, (key, end)
    for key in ("error_before_m", "error_peak_m", "peak_after_s", "back_after_s"):
        assert abs(g08[key] - kept[key]) <= 0.5, (key, g08[key], kept[key])
    for key, value in recorded["cn0_mask_precision_m"].items():
        assert abs(fresh["cn0_mask_precision_m"][key] - value) <= 0.005, key
    np.testing.assert_allclose(
        fresh["range_bias_model_precision_m"], recorded["range_bias_model_precision_m"], atol=0.005
    )
    # The pull: G08's innovations sit beyond the others' metres, and the
    # mask that would drop it costs the three systems.
    assert g08["early_innovation_m"]["least"] > 10.0
    mask = fresh["cn0_mask_precision_m"]
    assert mask["all_3_masked"] > mask["all_3_default"]


def test_the_phase_wind_up_bound_is_the_record(walk_run):
    """docs/how-to/multi-gnss.md bounds the walk's differential phase
    wind-up by the tilt of the body's vertical axis per 0.25 s epoch
    (λ·tilt/360°), each shown to 0.1: well under the 2 cm floor."""
    fresh = walk_multi_gnss.wind_up(walk_run)
    for key, value in RECORD["wind_up"].items():
        assert abs(fresh[key] - value) <= 0.05, (key, fresh[key], value)
    assert fresh["bound_mm"] < 20.0


def test_the_receiver_clock_ramp_is_the_record(walk_log):
    """docs/how-to/multi-gnss.md explains why the carrier changes eliminate
    the clock by the walk's receiver clock drifting over the log (the
    single-point fixes' Doppler drift; shown to 1 m/s and 0.01 m/s²): a
    warming oscillator's steady ramp."""
    fresh = walk_multi_gnss.clock_ramp(walk_log)
    recorded = RECORD["clock"]
    assert abs(fresh["first_m_s"] - recorded["first_m_s"]) <= 0.5
    assert abs(fresh["last_m_s"] - recorded["last_m_s"]) <= 0.5
    assert abs(fresh["slope_m_s2"] - recorded["slope_m_s2"]) <= 0.005
    assert fresh["slope_m_s2"] < 0 and fresh["last_m_s"] < fresh["first_m_s"]
    # crates/memsnav-core/tests/gnss.rs sizes the change of 20 m/s over
    # 133.75 s against the clock models: the record's.
    assert round(fresh["first_m_s"] - fresh["last_m_s"]) == 20


@pytest.fixture(scope="module")
def walk_run(tmp_path_factory):
    """The walk on three systems from its u-blox log (examples/walk_0827_multi_gnss.toml)."""
    return _navigate("walk_0827_multi_gnss.toml", tmp_path_factory.mktemp("walk") / "out")


def test_the_inter_system_biases_are_the_records(walk_run):
    """docs/how-to/multi-gnss.md: the final inter-system biases of the
    example's run, shown to the cm."""
    biases, recorded = walk_run.summary["inter_system_bias_m"], RECORD["inter_system_bias_m"]
    assert all(abs(biases[k] - recorded[k]) <= 0.005 for k in ("galileo", "beidou")), biases


#: The S observation of the signal each system's walk measurements use
#: (RINEX 3.05 §5.1: GPS L1 C/A, Galileo E1 C, BeiDou B3I).
_STRENGTH = {"G": "S1C", "E": "S1C", "C": "S6I"}


def test_the_walk_summary_lists_its_satellites(walk_run, walk_log):
    """summary.json's satellite table: the 20 satellites of the three
    systems; its counts add up to the filter's records, kind by kind; each
    mean C/N0 is the log's own S observation of the signal averaged over
    the epochs whose records hold the satellite; the terminal line says it."""
    s = walk_run.summary
    rows = s["satellites"]
    names = [r["satellite"] for r in rows]
    assert names == [
        *(f"G{p:02d}" for p in (8, 10, 18, 23, 24, 27, 32)),
        *(f"E{p:02d}" for p in (7, 8, 13, 26, 29, 33)),
        *(f"C{p:02d}" for p in (11, 21, 22, 34, 42, 43, 44)),
    ]
    systems = s["satellite_systems"]
    assert {k: v["satellites"] for k, v in systems.items()} == {
        "GPS": 7,
        "Galileo": 6,
        "BeiDou": 7,
    }
    for kind in ("pseudorange", "pseudorange_rate"):
        for status, count in s["measurements"][kind].items():
            assert sum(r["measurements"][kind].get(status, 0) for r in rows) == count
    total = sum(sum(s["measurements"][k].values()) for k in ("pseudorange", "pseudorange_rate"))
    columns = ("used", "excluded", "rejected", "slips")
    assert sum(r[c] for r in rows for c in columns) == total
    assert sum(t["measurements"] for t in systems.values()) == total

    records = walk_run.run.solution.measurements
    ids, times = np.asarray(records["id"]), np.asarray(records["time"])
    pseudorange = np.asarray(records["kind"]) == "pseudorange"
    obs = walk_log.observations
    columns_of = {name: j for j, name in enumerate(obs.satellites)}
    for row in rows:
        name = row["satellite"]
        number = {"G": 0, "E": 100, "C": 200}[name[0]] + int(name[1:])
        epochs = np.isin(obs.time, times[pseudorange & (ids == number)])
        strength = obs.observation(_STRENGTH[name[0]])[epochs, columns_of[name]]
        assert row["epochs"] == np.sum(epochs)
        assert 20.0 <= row["mean_cn0_db_hz"] <= 55.0, row
        assert row["mean_cn0_db_hz"] == pytest.approx(np.mean(strength), abs=1e-9), name
        assert 5.0 <= row["mean_elevation_deg"] <= 90.0, row
    line = answer_lines(s)[1]
    assert "satellites used: GPS 7, Galileo 6, BeiDou 7 (20)" in line
    assert line == RECORD["satellites_line"], (
        "docs/data/walk_multi_gnss.json's satellites line is not today's: "
        "rerun python docs/doc_runs.py walk_multi_gnss"
    )
    # docs/how-to/multi-gnss.md's weakest and strongest satellites (C/N0
    # shown to 0.1 dB-Hz, the elevation to the degree).
    fresh, recorded = walk_multi_gnss.satellites(s), RECORD["satellites"]
    assert fresh["most_epochs"] == recorded["most_epochs"]
    for end in ("weakest", "strongest"):
        assert fresh[end]["satellite"] == recorded[end]["satellite"]
        assert abs(fresh[end]["mean_cn0_db_hz"] - recorded[end]["mean_cn0_db_hz"]) <= 0.05
    assert fresh["weakest"]["epochs"] == recorded["weakest"]["epochs"]
    elevation = fresh["weakest"]["mean_elevation_deg"]
    assert abs(elevation - recorded["weakest"]["mean_elevation_deg"]) <= 0.5


def test_a_gps_rinex_run_lists_one_system(tmp_path):
    """The walk from its GPS RINEX files (examples/walk_0827.toml): one
    system in the satellite table."""
    s = _navigate("walk_0827.toml", tmp_path / "walk").summary
    assert list(s["satellite_systems"]) == ["GPS"]
    assert {r["system"] for r in s["satellites"]} == {"GPS"}
    assert {r["signal"] for r in s["satellites"]} == {"L1 C/A"}


def test_a_slot_for_every_satellite_is_the_record():
    """docs/how-to/multi-gnss.md compares the 12 shared range-bias slots
    with a slot for every satellite on the walk from
    docs/data/walk_every_satellite.json: today's runs agree with it within
    half the 0.01 m shown (satellite counts exactly), and the shared
    configurations are the configuration table's rows."""
    data = shared_data("real-imu-gnss/walk_0827").parent.parent
    fresh = walk_multi_gnss.every_satellite_record(data)
    # Counts differ by whole satellites: 0.005 holds them exactly too.
    assert not agree(fresh, figures("walk_every_satellite"), 0.005)
    table = figures("walk_configurations")
    for key, runs in fresh.items():
        # More satellites than the shared slots: the comparison means something.
        assert runs["shared"]["satellites"] > 12
        assert runs["shared"]["horizontal_m"] == pytest.approx(
            table[key]["precision_horizontal_m"], abs=1e-9
        )


#: The code-correlation table's cells recomputed by the test (one walk run
#: each, ~2 s): the configurations the prose after the table discusses.
CORRELATION_CHECKED = ("gps_4", "gps_7", "gps_galileo_beidou")


@pytest.mark.slow
def test_the_code_correlation_table_is_the_record():
    """docs/how-to/multi-gnss.md's code-correlation table is
    docs/data/walk_correlation_table.json (τ = 0 the configuration
    table's record; python docs/doc_runs.py walk_correlation_table writes
    it in a few minutes); here a few configurations at τ = 10 s are run
    again and agree with it within half the 0.01 m shown."""
    recorded = figures("walk_correlation_table")
    assert recorded["precision_m"].keys() == walk_multi_gnss.CONFIGURATIONS.keys()
    taus = recorded["correlation_times_s"]
    assert taus == list(walk_multi_gnss.CODE_CORRELATION_TIMES_S)
    data = shared_data("real-imu-gnss/walk_0827").parent.parent
    for key in CORRELATION_CHECKED:
        fresh = walk_multi_gnss.correlation_precision(data, key, 10.0)
        expected = recorded["precision_m"][key][taus.index(10.0)]
        np.testing.assert_allclose(fresh, expected, rtol=0, atol=0.005, err_msg=key)


def test_the_code_correlation_times_are_the_record(walk_log):
    """docs/how-to/multi-gnss.md shows the L1 code-minus-carrier's shortest
    and longest correlation times over the satellites tracked without a
    break for at least MIN_ARC_EPOCHS epochs from
    docs/data/walk_code_correlation.json: today's log gives the same
    satellites and times within half the 0.1 s shown, and the record's
    std inflation is √((1 + ρ)/(1 − ρ)) for τ = 10 s at 4 Hz."""
    fresh = walk_multi_gnss.code_correlation_times(walk_log)
    recorded = figures("walk_code_correlation")
    assert fresh["min_arc_epochs"] == recorded["min_arc_epochs"]
    assert fresh["satellites"] == recorded["satellites"] >= 2
    for end in ("shortest", "longest"):
        assert fresh[end]["satellite"] == recorded[end]["satellite"], (end, fresh, recorded)
        assert abs(fresh[end]["time_s"] - recorded[end]["time_s"]) <= 0.05, (end, fresh)
    interval = float(np.median(np.diff(np.asarray(walk_log.observations.time))))
    rho = np.exp(-interval / 10.0)
    inflation = recorded["inflation_tau_10s_at_4hz"]
    assert inflation == pytest.approx(np.sqrt((1 + rho) / (1 - rho)), rel=1e-12)


def test_the_code_correlation_time_reaches_the_python_filter(drive_300s):
    """TightlyCoupledFilter(pseudorange_correlation_time=τ) is listed by
    the tuning and the defaults, and it takes each epoch's pseudoranges as
    worth less (rust tests/correlated_code.rs has the consistency check):
    on code errors correlated over 10 s at 4 Hz, its position σ is wider
    and covers the errors that the white filter's does not."""
    traj, _, imu, f, w = drive_300s
    assert mn.defaults()["TightlyCoupledFilter"]["pseudorange_correlation_time"] == 0.0
    assert mn.TightlyCoupledFilter(imu).tuning["pseudorange_correlation_time"] == 0.0
    gnss = mn.simulate_gnss(
        traj.time,
        traj.position_ecef,
        traj.velocity_ecef,
        mn.Constellation.walker(),
        rate=4.0,
        n_satellites=8,
        pseudorange_std=2.0,
        residual_std=2.0,
        residual_correlation_time=10.0,
        seed=9,
    )
    start = _true_start(traj)
    ratios = {}
    for tau in (0.0, 10.0):
        flt = mn.TightlyCoupledFilter(imu, pseudorange_correlation_time=tau)
        assert flt.tuning["pseudorange_correlation_time"] == tau
        sol = flt.run(traj.time, f, w, gnss, initial_state=start)
        later = traj.time >= 60.0
        error = np.linalg.norm(sol.position_ecef[later] - traj.position_ecef[later], axis=1)
        sigma = np.sqrt((np.asarray(sol.position_std_ned)[later] ** 2).sum(axis=1))
        ratios[tau] = float(np.sqrt(np.mean(error**2)) / np.sqrt(np.mean(sigma**2)))
    # White: errors well beyond σ; with τ: about σ or inside.
    assert ratios[0.0] > 2.0 * ratios[10.0], ratios
    assert ratios[10.0] < 1.5, ratios
