"""The navigation experiment's study options (docs/results/paper-comparison.md):
pseudorange rates on/off, GNSS noise, initial attitude uncertainty, scale-
factor states, absorption of unmodelled errors, preset specs with overrides."""

from __future__ import annotations

import numpy as np
import pytest

import memsnav as mn

G0 = 9.80665


def test_pseudorange_only_halves_the_measurements_and_still_converges():
    kw = dict(runs=2, duration=40.0, seed=3, imus=("ins",), threads=1)
    both = mn.experiments.navigation(**kw)
    ranges = mn.experiments.navigation(pseudorange_rate=False, **kw)
    # 6 satellites x 41 epochs, one range each (and one rate each with rates).
    epochs_sats = 6 * 41
    acc_both = both.runs_summary["ins"]["accepted"]
    acc_ranges = ranges.runs_summary["ins"]["accepted"]
    assert np.all(acc_ranges <= epochs_sats) and np.all(acc_ranges >= epochs_sats - 10)
    assert np.all(acc_both >= 2 * epochs_sats - 20)
    # Converged to the GNSS level (3 m ranges, PDOP ~2) and consistent.
    assert np.all(ranges.position_error["ins"][:, 20:] < 10.0)
    assert 0.2 < ranges.summary()["ins"]["mean_nees_per_dof"] < 2.0
    assert ranges.config["pseudorange_rate"] is False


def test_initial_tilt_error_drives_the_outage_drift_as_half_g_psi_t2():
    """A total outage right after the first fix: the uncorrected initial
    tilt ψ makes the INS drift by ≈ ½ g ψ t² per horizontal axis."""
    t = 20.0
    kw = dict(runs=4, duration=22.0, seed=5, imus=("ins",), outage=(1.0, t), threads=1)
    small = mn.experiments.navigation(initial_attitude_std_deg=(0.01, 0.01, 0.01), **kw)
    big = mn.experiments.navigation(initial_attitude_std_deg=(2.0, 2.0, 2.0), **kw)
    end = int(t)  # last epoch inside the outage [1, 21)
    expected = 0.5 * G0 * np.radians(2.0) * (t - 1.0) ** 2 * np.sqrt(2.0)
    e_big = np.sqrt(np.mean(big.position_error["ins"][:, end] ** 2))
    e_small = np.sqrt(np.mean(small.position_error["ins"][:, end] ** 2))
    assert 0.3 * expected < e_big < 3.0 * expected
    assert e_small < 0.2 * e_big


def test_spec_overrides_and_gnss_noise():
    """Removing the raw MEMS misalignments removes most of its outage drift
    (the error budget of docs/results/paper-comparison.md; 71 % over 12 runs, 61 %
    over these 4), and larger pseudorange noise gives a larger aided
    error."""
    kw = dict(runs=4, duration=155.0, seed=0, outage=(120.0, 30.0), threads=1)
    no_mis = {"gyro_misalignment_std": 0.0, "accel_misalignment_std": 0.0}
    r = mn.experiments.navigation(imus={"mems": "mems", "no_mis": ("mems", no_mis)}, **kw)
    s = r.summary()
    mems = s["mems"]["max_position_error_during_outage_m"]
    assert s["no_mis"]["max_position_error_during_outage_m"] < 0.5 * mems
    quiet = mn.experiments.navigation(runs=2, duration=40.0, imus=("ins",), threads=1)
    noisy = mn.experiments.navigation(
        runs=2, duration=40.0, imus=("ins",), threads=1, pseudorange_std=12.0
    )
    assert noisy.summary()["ins"]["rms_position_error_m"] > (
        1.5 * quiet.summary()["ins"]["rms_position_error_m"]
    )


def test_scale_factor_states_and_absorption_change_the_filter():
    kw = dict(runs=2, duration=60.0, seed=2, imus=("mems",), threads=1)
    base = mn.experiments.navigation(**kw)
    sf = mn.experiments.navigation(scale_factor_states=True, **kw)
    raw = mn.experiments.navigation(absorb_unmodelled=False, **kw)
    assert not np.array_equal(base.position_error["mems"], sf.position_error["mems"])
    # Without absorbing its 1 % misalignments the raw MEMS filter is
    # overconfident: its NEES is far above the absorbing filter's.
    assert (
        raw.summary()["mems"]["mean_nees_per_dof"]
        > 3.0 * base.summary()["mems"]["mean_nees_per_dof"]
    )
    assert sf.config["scale_factor_states"] and not raw.config["absorb_unmodelled"]


def test_study_options_bad_input():
    kw = dict(runs=1, duration=10.0, imus=("ins",))
    with pytest.raises(ValueError, match="initial_attitude_std"):
        mn.experiments.navigation(initial_attitude_std_deg=(1.0, 1.0), **kw)
    with pytest.raises(ValueError, match="initial_attitude_std"):
        mn.experiments.navigation(initial_attitude_std_deg=(1.0, -1.0, 5.0), **kw)
    with pytest.raises(ValueError, match="pseudorange_std"):
        mn.experiments.navigation(pseudorange_std=0.0, **kw)
    with pytest.raises(ValueError, match="pseudorange_rate_std"):
        mn.experiments.navigation(pseudorange_rate_std=float("nan"), **kw)
    with pytest.raises(ValueError, match=r"imus.*unknown key"):
        mn.experiments.navigation(imus={"x": ("mems", {"no_such_key": 0.0})}, runs=1, duration=10.0)
    with pytest.raises(ValueError, match="imus"):
        mn.experiments.navigation(imus={"x": ("no-grade", {})}, runs=1, duration=10.0)


def test_galileo_and_beidou_with_inter_system_biases():
    """G + E + C with biases of +3 m and -25 m on the Galileo and BeiDou
    pseudoranges: the filters estimate them (three more states) and track
    every satellite in view (about 20 against GPS's 6), staying consistent."""
    kw = dict(runs=2, duration=40.0, seed=3, imus=("ins",), threads=1)
    gps = mn.experiments.navigation(**kw)
    three = mn.experiments.navigation(
        systems=("G", "E", "C"), inter_system_bias=(3.0, -25.0), n_satellites=40, **kw
    )
    accepted_gps = gps.runs_summary["ins"]["accepted"]
    accepted_three = three.runs_summary["ins"]["accepted"]
    assert np.all(accepted_three > 3 * accepted_gps)
    assert np.all(three.position_error["ins"][:, 20:] < 5.0)
    assert 0.2 < three.summary()["ins"]["mean_nees_per_dof"] < 2.0
    with pytest.raises(ValueError, match="systems"):
        mn.experiments.navigation(systems=("G", "X"), **kw)
