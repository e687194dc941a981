"""Partial outages: a window keeping 0-3 satellites, tight
coupling against loose; the same draws in every scenario of a run."""

import matplotlib
import numpy as np
import pytest

import memsnav as mn

matplotlib.use("Agg")


@pytest.fixture(scope="module")
def study():
    return mn.experiments.partial_outage(
        imus=("ins", "mems"),
        runs=2,
        duration=100.0,
        outage_start=30.0,
        outage_length=60.0,
        calibration_duration=60.0,
        threads=2,
    )


def test_scenarios_config_and_summary(study):
    assert list(study.scenarios) == [
        "tight, 0 satellites",
        "tight, 1 satellite",
        "tight, 2 satellites",
        "tight, 3 satellites",
        "loose",
    ]
    assert study.config["outage_start"] == 30.0 and study.config["satellites"] == [0, 1, 2, 3]
    assert study.completed_runs == 2 and not study.interrupted
    s = study.summary()
    three = s["scenarios"]["tight, 3 satellites"]["imus"]["mems"]
    none = s["scenarios"]["tight, 0 satellites"]["imus"]["mems"]
    loose = s["scenarios"]["loose"]["imus"]["mems"]
    key = "mean_max_position_error_during_outage_m"
    # 3 satellites hold the raw MEMS far below free inertial drift; loose
    # coupling has no fix below 4 satellites and drifts like it.
    assert three[key] < 0.3 * none[key]
    assert loose[key] > 0.5 * none[key]
    for e in (three, none, loose):
        horizontal = e["mean_max_horizontal_error_during_outage_m"]
        vertical = e["mean_max_vertical_error_during_outage_m"]
        # Run by run each part is at most the norm, so their means are too.
        assert max(horizontal, vertical) <= e[key] + 1e-9
    fig = study.plot()
    assert len(fig.axes) == 2 and "[m]" in fig.axes[0].get_ylabel()


def test_scenarios_share_their_draws(study):
    # Before the window every tight scenario saw the same measurements.
    before = study.scenarios["tight, 0 satellites"].time < 30.0
    for label in ("tight, 1 satellite", "tight, 3 satellites"):
        np.testing.assert_array_equal(
            study.scenarios[label].mean["mems"][before],
            study.scenarios["tight, 0 satellites"].mean["mems"][before],
        )


def test_navigation_outage_keeping_satellites_and_bad_windows():
    kw = dict(runs=1, duration=60.0, imus=("ins",), threads=1)
    total = mn.experiments.navigation(outage=(20.0, 30.0), **kw)
    three = mn.experiments.navigation(outage=(20.0, 30.0, 3), **kw)
    assert three.config["outage"] == (20.0, 30.0, 3)
    # Pseudoranges and rates of 3 satellites inside the window.
    accepted = three.runs_summary["ins"]["accepted"] + three.runs_summary["ins"]["rejected"]
    assert accepted[0] == 2 * (6 * 31 + 3 * 30)
    assert (
        three.summary()["ins"]["max_position_error_during_outage_m"]
        < total.summary()["ins"]["max_position_error_during_outage_m"]
    )
    with pytest.raises(ValueError, match="outage"):
        mn.experiments.navigation(outage=(20.0, 30.0, 4), **kw)
    with pytest.raises(ValueError, match="outage"):
        mn.experiments.navigation(outage=(20.0, 30.0, 1.5), **kw)
    with pytest.raises(ValueError, match="satellites"):
        mn.experiments.partial_outage(satellites=(0, 5), runs=1)
