"""The tight filter with one, two or three satellites
(docs/explanation/few-satellites.md): keeping satellites never makes an outage worse,
the covariance covers the errors through a total outage and over whole
runs, and a long run on few satellites either stays inside its 3σ or is
flagged, with a warning that says why. Each of these failed with the
filter model before the one that added the range-bias states (157/446/273/21 m;
24 %, 13 % inside 3σ and no flag; outage NEES/dof 0.1)."""

from __future__ import annotations

import itertools
import warnings

import numpy as np
import pytest
from scipy.stats import chi2

import memsnav as mn


def _ned(position_ecef: np.ndarray) -> np.ndarray:
    lat, lon, _ = mn.ecef_to_geodetic(position_ecef)
    sl, cl, so, co = np.sin(lat), np.cos(lat), np.sin(lon), np.cos(lon)
    return np.array([[-sl * co, -sl * so, cl], [-so, co, 0.0], [-cl * co, -cl * so, -sl]])


def test_keeping_satellites_never_makes_an_outage_worse():
    """Paired Monte Carlo (the draws are shared, the outage removes
    satellites after them): the paper's MEMS through a 60 s window keeping
    0-3 of its 6 satellites. The mean of each run's largest error does not
    grow with the satellites kept (5 % slack) and three satellites hold it
    below a quarter of the total outage's."""
    means = []
    for kept in range(4):
        r = mn.experiments.navigation(
            outage=(150.0, 60.0, kept), runs=12, duration=300.0, seed=3, imus=("mems",)
        )
        means.append(float(np.mean(r.runs_summary["mems"]["max_in_outage"])))
        assert not r.runs_summary["mems"]["diverged"].any(), kept
    for fewer, more in itertools.pairwise(means):
        assert more <= 1.05 * fewer, means
    assert means[3] < 0.25 * means[0], means


@pytest.mark.parametrize("imu", ["mems", "consumer", "ins"])
def test_the_covariance_covers_the_errors_through_an_outage_and_over_whole_runs(imu):
    """Monte Carlo position NEES/dof: at the end of a 60 s total outage in
    [0.25, 4] (a covariance ten times the errors gave 0.1), and at every
    second of the run inside the 99.9 % chi-square band of the mean of 16
    runs' NEES."""
    runs = 16
    r = mn.experiments.navigation(
        outage=(150.0, 60.0), runs=runs, duration=300.0, seed=11, imus=(imu,)
    )
    at_end = r.summary()[imu]["position_nees_per_dof_at_outage_end"]
    assert 0.25 <= at_end <= 4.0, at_end
    low, high = chi2.ppf([0.0005, 0.9995], 3 * runs) / (3 * runs)
    per_epoch = r.position_nees_mean[imu] / 3.0
    assert np.all((per_epoch >= low) & (per_epoch <= high)), (per_epoch.min(), per_epoch.max())


def _few_satellite_run(kept: int, seed: int):
    """900 s of a consumer IMU on the `kept` highest of its 6 satellites
    from the first epoch on, from the exact initial state (the study's
    finding 2, which kept the first `kept` columns)."""
    truth = mn.Trajectory.random(duration=900.0, seed=seed)
    imu = mn.ImuModel.preset("consumer", seed=seed)
    accel, gyro = imu.measure(truth.specific_force, truth.angular_rate, seed=seed)
    gnss = mn.simulate_gnss(
        truth.time,
        truth.position_ecef,
        truth.velocity_ecef,
        mn.Constellation.walker(),
        outages=[(0.5, truth.time[-1], kept)],
        seed=seed,
    )
    start = {
        "position_ecef": truth.position_ecef[0],
        "velocity_ecef": truth.velocity_ecef[0],
        "attitude": truth.attitude[0],
    }
    with warnings.catch_warnings(record=True) as caught:
        warnings.simplefilter("always")
        sol = mn.TightlyCoupledFilter(imu).run(truth.time, accel, gyro, gnss, initial_state=start)
    error = (sol.position_ecef - truth.position_ecef) @ _ned(truth.position_ecef[0]).T
    inside = float(np.mean(np.abs(error) <= 3.0 * sol.position_std_ned))
    return sol, inside, [str(w.message) for w in caught]


@pytest.mark.parametrize("seed", [1, 2])
def test_long_runs_on_few_satellites_are_honest_or_flagged(seed):
    """Three satellites: the errors stay inside 3σ (however far the clock
    and the unobserved direction let them grow) and nothing is flagged. Two
    or one: inside 3σ at 90 % of the N/E/D errors, or the run is flagged
    diverged with a warning that says why."""
    sol, inside, _ = _few_satellite_run(3, seed)
    assert inside >= 0.9, inside
    assert not sol.diverged, sol.integrity.alerts
    for kept in (2, 1):
        sol, inside, caught = _few_satellite_run(kept, seed)
        if inside >= 0.9:
            continue
        assert sol.diverged, (kept, inside)
        alerts = sol.integrity.alerts
        assert alerts and all(a.message in caught for a in alerts), (kept, alerts)
        assert alerts[0].kind in {"beyond_linear_model", "inconsistent_innovations"}


@pytest.mark.parametrize(
    ("kwargs", "name"),
    [
        ({"clock_h0": float("nan")}, "clock_h0"),
        ({"clock_h0": 1e300}, "clock_h0"),
        ({"clock_h_minus2": -1.0}, "clock_h_minus2"),
        ({"manoeuvre_correlation_time": 0.0}, "manoeuvre_correlation_time"),
        ({"manoeuvre_correlation_time": float("inf")}, "manoeuvre_correlation_time"),
        ({"pseudorange_correlation_time": -1.0}, "pseudorange_correlation_time"),
        ({"pseudorange_correlation_time": float("nan")}, "pseudorange_correlation_time"),
        ({"pseudorange_correlation_time": float("inf")}, "pseudorange_correlation_time"),
    ],
)
def test_the_clock_and_manoeuvre_arguments_are_checked(kwargs, name):
    """The filters' clock model, manoeuvre correlation time and
    code correlation time refuse values that are not numbers or give none,
    naming the argument; the simulator refuses the same clock."""
    imu = mn.ImuModel.preset("consumer", seed=1)
    for cls in (mn.TightlyCoupledFilter, mn.LooselyCoupledFilter):
        with pytest.raises(ValueError, match=name):
            cls(imu, **kwargs)
    if name.startswith("clock"):
        truth = mn.Trajectory.random(duration=5.0, seed=1)
        with pytest.raises(ValueError, match=name):
            mn.simulate_gnss(
                truth.time,
                truth.position_ecef,
                truth.velocity_ecef,
                mn.Constellation.walker(),
                **kwargs,
            )
