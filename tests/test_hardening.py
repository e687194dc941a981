"""Inputs that once killed, hung or panicked the interpreter, or
were accepted as silent garbage, now fail up front with an error naming the
argument (docs/reference/robustness.md lists the limits)."""

import os
import subprocess
import sys
import warnings
from pathlib import Path

import doc_runs
import numpy as np
import pytest
from figures import figures
from test_navigate import DATA, DRIVE, WALK
from test_navigate import _config as navigate_config

import memsnav as mn
from memsnav import _memsnav


def short_track():
    t = mn.Trajectory.random(duration=20.0, rate=10.0, seed=0)
    return t.time, t.position_ecef, t.velocity_ecef


# --- no panic reaches Python ---------------------------------------------------


def test_a_rust_panic_is_a_memsnav_error_with_its_message():
    # The hook panics inside a binding entry, as a memsnav bug would: the
    # #[catch_panics] wrapper turns it into an Exception (pyo3's own
    # PanicException is a BaseException that `except Exception` misses).
    with pytest.raises(mn.MemsnavError, match=r"internal error.*boom at row 3"):
        _memsnav._panic_for_test("boom at row 3")
    assert issubclass(mn.MemsnavError, Exception)


def binding_entries_without_catch_panics(source: str) -> list[int]:
    """Lines (1-based) of `#[pyfunction]` / `#[pymethods]` whose attribute
    block (the attributes and doc comments just above) lacks `#[catch_panics]`."""
    lines = source.splitlines()
    missing = []
    for i, line in enumerate(lines):
        if line.strip() not in ("#[pyfunction]", "#[pymethods]"):
            continue
        j, attributes = i - 1, []
        while j >= 0 and lines[j].strip().startswith(("#[", "///")):
            attributes.append(lines[j].strip())
            j -= 1
        if not any(a.endswith("catch_panics]") for a in attributes):
            missing.append(i + 1)
    return missing


def test_every_binding_entry_catches_panics():
    # The scan, checked on a sample first so that it can fail.
    assert binding_entries_without_catch_panics("/// doc\n#[pyfunction]\nfn f() {}") == [2]
    assert binding_entries_without_catch_panics("#[catch_panics]\n#[pymethods]\nimpl X {}") == []
    sources = sorted((Path(__file__).parents[1] / "crates" / "memsnav-py" / "src").glob("*.rs"))
    assert len(sources) > 10
    entries = sum(s.read_text().count("#[pyfunction]") for s in sources)
    assert entries > 30
    missing = {
        s.name: lines
        for s in sources
        if (lines := binding_entries_without_catch_panics(s.read_text()))
    }
    assert missing == {}


# --- sizes and hangs -------------------------------------------------------------


def test_simulate_gnss_sizes_are_bounded_before_allocating():
    time, position, velocity = short_track()
    sky = mn.Constellation.walker()
    with pytest.raises(
        ValueError, match="n_satellites: 1099511627776 is more than the limit of 256"
    ):
        mn.simulate_gnss(time, position, velocity, sky, n_satellites=2**40)
    # A 1e12 Hz rate on a 10 Hz track: one epoch per track sample at most.
    m = mn.simulate_gnss(time, position, velocity, sky, rate=1e12)
    assert m.pseudorange.shape[0] == len(time)


@pytest.mark.parametrize("span_s", [1e12, 1e20])
def test_simulate_gnss_over_a_huge_span_is_two_epochs(span_s):
    # 1e12 s aborted on allocation, 1e20 s hung (one loop turn per
    # empty 1 s target); the epochs are bounded by the track's samples.
    sky = mn.Constellation.walker()
    position = np.tile(mn.geodetic_to_ecef([0.5, 0.1, 0.0]), (2, 1))
    m = mn.simulate_gnss([0.0, span_s], position, np.zeros((2, 3)), sky)
    np.testing.assert_array_equal(m.time, [0.0, span_s])


@pytest.mark.parametrize(
    ("call", "message"),
    [
        (lambda: mn.experiments.inversion(runs=2**31), "runs: 2147483648 is more than the limit"),
        (lambda: mn.experiments.inversion(runs=2**63), "runs: 9223372036854775808 is more"),
        (lambda: mn.experiments.navigation(runs=2**31), "runs: 2147483648 is more than"),
        (
            lambda: mn.experiments.calibration(parameter_sets=2**31),
            "parameter_sets: 2147483648 is more than",
        ),
        (lambda: mn.experiments.calibration(runs=2**31), "runs: 2147483648 is more than"),
        (
            lambda: mn.experiments.calibration(parameter_sets=10**5, runs=1000),
            r"parameter_sets × runs: 100000000 is more than the limit of 10000000",
        ),
        (
            lambda: mn.experiments.calibration(parameter_sets=2, runs=2, threads=2**31),
            "threads: 2147483648 is more than the limit of 1024",
        ),
        (lambda: mn.experiments.inversion(runs=2, threads=2**31), "threads: 2147483648"),
    ],
)
def test_monte_carlo_sizes_are_refused_with_the_figure(call, message):
    with pytest.raises(ValueError, match=message):
        call()


def reference_poses(scale: float) -> np.ndarray:
    six = np.vstack([np.eye(3), -np.eye(3)]) * scale
    return np.tile(six, (4, 1))


@pytest.mark.parametrize("scale", [1e300, 1e7])
def test_calibration_with_huge_inputs_is_refused_not_hung(scale):
    # 1e300 overflowed the least-squares factors and the SVD never ended.
    f = reference_poses(9.8)
    with pytest.raises(ValueError, match=r"measured: row 0 holds .*beyond the limit of ±1e6"):
        mn.calibrate_accelerometer(f * scale, f)
    with pytest.raises(ValueError, match="reference_specific_force: row 0"):
        mn.calibrate_accelerometer(f, f * scale)
    w = reference_poses(1.0)
    with pytest.raises(ValueError, match="reference_angular_rate: row 0"):
        mn.calibrate_gyroscope(w, w * scale, np.tile([0.0, 0.0, 9.8], (len(w), 1)))


def test_calibration_experiment_reference_noise_is_bounded():
    with pytest.raises(ValueError, match="reference_specific_force_std: 1e300 is beyond"):
        mn.experiments.calibration(
            parameter_sets=1, runs=1, duration=10.0, reference_specific_force_std=1e300
        )


# --- geodesy domain ----------------------------------------------------------------


@pytest.mark.parametrize(
    ("function", "value", "message"),
    [
        (mn.ecef_to_geodetic, [0.0, 0.0, 0.0], "xyz: row 0: 0 m from the Earth's centre"),
        (mn.ecef_to_geodetic, [1e-3, 0.0, 0.0], "xyz: row 0: 0.001 m from"),
        (mn.gravity_ecef, [0.0, 0.0, 0.0], "position_ecef: row 0: 0 m from"),
        (mn.geodetic_to_ecef, [np.radians(100.0), 0.0, 0.0], "lla: row 0: latitude 100"),
        (mn.geodetic_to_ecef, [0.0, 0.0, -1e7], r"lla: row 0: height -10000000 m is outside"),
        (mn.geodetic_to_ecef, [0.0, 0.0, 1e12], "lla: row 0: height 1000000000000 m"),
    ],
)
def test_geodesy_outside_its_domain_names_the_argument(function, value, message):
    with pytest.raises(ValueError, match=message):
        function(value)


def test_geodesy_domain_edges_are_accepted():
    # The poles, 100 km down and 1e9 m up are inside; so is a GPS orbit.
    lla = np.array([[np.pi / 2, 0.0, -1e5], [-np.pi / 2, 1.0, 1e9], [0.3, 2.0, 2.02e7]])
    xyz = mn.geodetic_to_ecef(lla)
    np.testing.assert_allclose(mn.ecef_to_geodetic(xyz)[:, 2], lla[:, 2], rtol=1e-9, atol=1e-6)


def test_nan_is_reported_at_row_and_column():
    xyz = np.tile([6.4e6, 0.0, 0.0], (200, 1))
    xyz[100, 2] = np.nan
    with pytest.raises(ValueError, match="xyz: row 100, column 2 is NaN"):
        mn.ecef_to_geodetic(xyz)


# --- scalar arguments ---------------------------------------------------------------


@pytest.mark.parametrize(
    ("kwargs", "error", "message"),
    [
        (
            {"pseudorange_std": "x"},
            TypeError,
            r"pseudorange_std: must be a real number, got 'x' \(str\)",
        ),
        ({"seed": -1}, ValueError, r"seed: must be None or an integer in \[0, 2\*\*64\), got -1"),
        ({"n_satellites": 2.5}, ValueError, r"n_satellites: must be an integer ≥ 0, got 2.5"),
        ({"rate": [1.0]}, TypeError, r"rate: must be a real number, got \[1.0\] \(list\)"),
    ],
)
def test_scalar_arguments_are_named(kwargs, error, message):
    time, position, velocity = short_track()
    with pytest.raises(error, match=message):
        mn.simulate_gnss(time, position, velocity, mn.Constellation.walker(), **kwargs)


@pytest.mark.parametrize(
    ("kwargs", "message"),
    [
        ({"n_satellites": -3}, "n_satellites: must be an integer ≥ 0, got -3"),
        ({"planes": "a"}, "planes: must be an integer ≥ 0, got 'a'"),
        ({"inclination_deg": "north"}, "inclination_deg: must be a real number, got .north."),
    ],
)
def test_constructor_scalars_are_named(kwargs, message):
    with pytest.raises((TypeError, ValueError), match=message):
        mn.Constellation.walker(**kwargs)


@pytest.mark.parametrize("filter_class", [mn.LooselyCoupledFilter, mn.TightlyCoupledFilter])
@pytest.mark.parametrize(
    ("kwargs", "message"),
    [
        ({"accel_noise_density": 1e200}, r"accel_noise_density: 1e200 is too large"),
        ({"gyro_noise_density": 1e160}, r"gyro_noise_density: 1e160 is too large"),
        ({"initial_position_std": 1e200}, r"initial_position_std: 1e200 is out of range"),
        ({"initial_tilt_std": 1e-170}, r"initial_tilt_std: 1e-170 is out of range"),
        ({"initial_heading_std": -1.0}, r"initial_heading_std: must be finite and positive"),
    ],
)
def test_filter_constructor_errors_name_the_python_argument(filter_class, kwargs, message):
    # These said "accel_white_psd", "initial_attitude_std" or, at
    # run time, "initial_covariance": names the user never typed.
    with pytest.raises(ValueError, match=message) as caught:
        filter_class(mn.ImuModel.preset("consumer"), **kwargs)
    assert not any(
        internal in str(caught.value)
        for internal in ("white_psd", "initial_attitude_std", "initial_covariance")
    )


def test_an_initial_covariance_that_is_not_one_names_the_stds():
    t = np.arange(0.0, 5.0, 0.01)
    f = np.tile([0.0, 0.0, -9.81], (len(t), 1))
    position = np.array([4e6, 3e6, 3e6]) / np.linalg.norm([4e6, 3e6, 3e6]) * 6.371e6
    fixes = {
        "time": np.arange(0.0, 5.0, 1.0),
        "position_ecef": np.tile(position, (5, 1)),
        "position_covariance": np.tile(np.eye(3), (5, 1, 1)),
    }
    kf = mn.LooselyCoupledFilter(
        mn.ImuModel.preset("consumer"), initial_tilt_std=1e-10, initial_heading_std=1e5
    )
    with pytest.raises(ValueError, match="initial_tilt_std, initial_heading_std: 1e-10 and") as e:
        kf.run(t, f, np.zeros_like(f), fixes, initial_attitude=np.eye(3))
    assert "initial_covariance" not in str(e.value)


def flat_imu(duration=10.0, rate=100.0):
    t = np.arange(0.0, duration, 1.0 / rate)
    f = np.tile([0.0, 0.0, -9.81], (len(t), 1))
    return t, f, np.zeros_like(f)


EMPTY_PSEUDORANGES = {"time": np.zeros(0), "sat_id": np.zeros(0)}
EMPTY_FIXES = {"time": np.zeros(0), "position_ecef": np.zeros(0), "position_covariance": []}


@pytest.mark.parametrize(
    ("call", "argument"),
    [
        (
            lambda: mn.TightlyCoupledFilter(mn.ImuModel.preset("consumer")).run(
                *flat_imu(), EMPTY_PSEUDORANGES
            ),
            "gnss.time",
        ),
        (
            lambda: mn.LooselyCoupledFilter(mn.ImuModel.preset("consumer")).run(
                *flat_imu(), EMPTY_FIXES
            ),
            "fixes.time",
        ),
        (lambda: mn.navigate_log(*flat_imu(), EMPTY_PSEUDORANGES), "gnss.time"),
        (lambda: mn.navigate_log(*flat_imu(), EMPTY_FIXES), "fixes.time"),
        (lambda: mn.fixes_from_solution(np.zeros(0), np.zeros(0), np.zeros(0)), "time"),
    ],
)
def test_empty_gnss_time_says_no_epochs(call, argument):
    # An empty time array used to fail on the shape of sat_id.
    with pytest.raises(ValueError, match=rf"^{argument}: has no epochs") as caught:
        call()
    assert "shape" not in str(caught.value)


SPANS = (
    r"no epoch falls inside the IMU span \[1400000000\.000, 1400000060\.000\] s: the epochs "
    r"span \[0\.000, 60\.000\] s"
)


@pytest.mark.parametrize(
    ("run", "gnss"),
    [
        (lambda imu: mn.TightlyCoupledFilter(imu).run, lambda g: g),
        (lambda imu: mn.LooselyCoupledFilter(imu).run, mn.solve_fix),
    ],
)
@pytest.mark.parametrize("attitude", [None, np.eye(3)])
def test_imu_and_gnss_on_different_time_scales_name_both_spans(run, gnss, attitude):
    """IMU time in GPS seconds, GNSS time from the start: the error says no
    GNSS epoch falls inside the IMU span, naming both (a start without an
    attitude used to blame initial_attitude)."""
    track = mn.Trajectory.random(duration=60.0, rate=100.0, seed=1)
    imu = mn.ImuModel.preset("paper-mems", seed=2)
    f, w = imu.measure(track.specific_force, track.angular_rate, seed=3)
    g = mn.simulate_gnss(
        track.time, track.position_ecef, track.velocity_ecef, mn.Constellation.walker(), seed=4
    )
    with pytest.raises(ValueError, match=rf"^(gnss|fixes): {SPANS}"):
        run(imu)(track.time + 1.4e9, f, w, gnss(g), initial_attitude=attitude)


def test_navigate_with_imu_and_gnss_times_apart_names_the_file_and_both_spans(tmp_path):
    # The excerpt's IMU column is milliseconds from power-on; read as GPS
    # time it lies 45 years before the RTK epochs.
    config = navigate_config(
        tmp_path, extra="", **{"time_offset_s": 'time_reference = "column_gps"\ntime_offset_s'}
    )
    with pytest.raises(
        ValueError,
        match=r"run.toml: gnss: no epoch falls inside the IMU span \[295\.466, 360\.457\] s: "
        r"the epochs span \[1436038494\.999, 1436038561\.749\] s",
    ):
        mn.navigate(config, data_root=DATA)


def first_epochs_with(change):
    track = mn.Trajectory.random(duration=20.0, rate=10.0, seed=0)
    g = mn.simulate_gnss(
        track.time, track.position_ecef, track.velocity_ecef, mn.Constellation.walker(), seed=1
    )
    names = ("time", "sat_id", "satellite_position_ecef", "satellite_velocity_ecef")
    arrays = {k: np.array(getattr(g, k))[:3] for k in (*names, "pseudorange", "pseudorange_std")}
    change(arrays)
    t = track.time[:50]
    f = np.tile([0.0, 0.0, -9.8], (len(t), 1))
    run = mn.TightlyCoupledFilter(mn.ImuModel.preset("consumer")).run
    return lambda: run(t, f, np.zeros_like(f), arrays, initial_attitude=np.eye(3))


@pytest.mark.parametrize("offset", [5e7, 7e7, -2e7])
def test_a_first_epoch_pseudorange_outlier_is_not_singular_geometry(offset):
    # A 1e9 m error on one pseudorange of the first epoch was
    # reported as "the satellite geometry at t = 0 s is singular". A
    # pseudorange beyond 1e8 m is no receiver's and is refused up front
    # (the test below); outliers within the range are the filter's to find.
    corrupted = []

    def corrupt(a):
        a["pseudorange"][0, 2] += offset
        corrupted.append(int(a["sat_id"][0, 2]))

    run = first_epochs_with(corrupt)
    with pytest.raises(mn.MemsnavError) as caught:
        run()
    message = str(caught.value)
    assert "singular" not in message
    assert not isinstance(caught.value, mn.UnobservableError)
    assert f"the pseudorange of satellite {corrupted[0]} is an outlier" in message


@pytest.mark.parametrize("offset", [1e8, 1e9, 1e12])
def test_a_pseudorange_no_receiver_reports_is_refused_naming_the_slot(offset):
    def corrupt(a):
        a["pseudorange"][0, 2] += offset

    with pytest.raises(ValueError, match=r"gnss: \[0, 2\] .*pseudorange = .* is out of range"):
        first_epochs_with(corrupt)()


def test_a_truly_singular_geometry_is_still_reported_as_such():
    def stack(a):
        # Every satellite at the same place: no geometry at all.
        a["satellite_position_ecef"][0] = a["satellite_position_ecef"][0, 0]

    with pytest.raises(mn.UnobservableError, match="geometry at t = 0 s is singular"):
        first_epochs_with(stack)()


# --- warnings: units and divergence --------------------------------------------------


@pytest.fixture(scope="module")
def drive():
    return doc_runs.hardening_drive()


loose_run = doc_runs.loose_run


def test_clean_simulated_runs_give_no_warning(drive):
    traj, gnss, imu, f, w, _ = drive
    with warnings.catch_warnings():
        warnings.simplefilter("error")
        loose = loose_run(drive)
        tight = mn.TightlyCoupledFilter(imu).run(
            traj.time, f, w, gnss, initial_attitude=traj.attitude[0], smooth=True
        )
    for sol in (loose, tight, tight.smoothed):
        assert sol.warnings == [] and not sol.diverged


def test_specific_force_in_g_warns_naming_the_argument(drive):
    _, _, _, f, _, _ = drive
    with warnings.catch_warnings(record=True) as caught:
        warnings.simplefilter("always")
        sol = loose_run(drive, f=f / 9.80665)
    messages = [str(c.message) for c in caught]
    assert all(issubclass(c.category, UserWarning) for c in caught)
    assert messages[0].startswith("specific_force: the median magnitude is 1.0")
    assert "g given as m/s²" in messages[0]
    assert sol.warnings == messages


def test_gyro_in_deg_per_s_warns_naming_the_argument(drive):
    # A car's turns in deg/s read as rad/s (3.5 km error, silently).
    _, _, _, _, w, _ = drive
    with pytest.warns(UserWarning) as caught:
        sol = loose_run(drive, w=np.degrees(w))
    messages = [str(c.message) for c in caught]
    assert any(m.startswith("angular_rate:") and "deg/s given as rad/s" in m for m in messages)
    assert sol.warnings == messages


@pytest.mark.parametrize("which", ["after_the_first", "first"])
def test_wildly_wrong_fixes_warn_of_divergence_or_recover(drive, which):
    traj, *_, arrays = drive
    bad = doc_runs.fixes_off(arrays, which)
    with warnings.catch_warnings(record=True) as caught:
        warnings.simplefilter("always")
        sol = loose_run(drive, fixes=bad)
    error = np.linalg.norm(sol.position_ecef - traj.position_ecef, axis=1)[-1]
    if which == "first":
        # Never a silent 1e9 m finish. Either the filter
        # recovers (resets to the later fixes) or it says it diverged.
        assert error < 100.0 and len(sol.resets["time"]) >= 1
        # docs/reference/robustness.md shows this run's record.
        assert abs(error - figures("robustness_runs")["first_fix_off_error_m"]) <= 1e-9, error
        assert list(sol.resets["kind"]) == ["position_to_fix"] and not caught
    else:
        # Every fix but the first is 1e9 m off the truth: the filter follows
        # them by resets but its innovations stay far outside their covariance.
        assert sol.diverged
        assert any("diverged from its GNSS aiding" in str(c.message) for c in caught)
        assert any("diverged" in m for m in sol.warnings)


def test_the_failed_shares_are_the_record(drive):
    """docs/reference/robustness.md shows the failed shares of GNSS batches
    (a clean loose and tight run, fixes 10⁹ m off after the first, a gyro
    in deg/s) from the record: a consistent filter fails about
    1 − gate_probability, the broken inputs half or more."""
    shares = doc_runs.failed_shares(drive)
    assert shares["clean_loose_pct"] < 2.0 and shares["clean_tight_pct"] < 2.0, shares
    assert shares["fixes_off_pct"] > 25.0 and shares["gyro_deg_s_pct"] > 25.0, shares
    recorded = figures("robustness_runs")["failed_shares"]
    for key, value in shares.items():
        assert abs(value - recorded[key]) <= 1e-9, (key, value)


def test_a_sat_id_of_minus_inf_is_refused_not_taken_as_padding(drive):
    """A finite negative sat_id marks an empty slot; −inf is not one (the
    numeric-API fuzzing at 500 examples found it taken as padding)."""
    traj, gnss, imu, f, w, _ = drive
    names = ("time", "sat_id", "pseudorange", "pseudorange_rate", "pseudorange_std")
    names += ("pseudorange_rate_std", "satellite_position_ecef", "satellite_velocity_ecef")
    g = {name: np.array(getattr(gnss, name), dtype=float) for name in names}
    g["sat_id"][0, 0] = -np.inf
    with pytest.raises(ValueError, match=r"gnss: \[0, 0\] .*sat_id = -inf is not a satellite"):
        mn.TightlyCoupledFilter(imu).run(traj.time, f, w, g, initial_attitude=traj.attitude[0])


# --- arguments that hung ---------------------------------------------------


def test_a_fix_prior_far_beyond_any_receiver_is_refused_not_iterated():
    """A prior of 1e200 m overflowed the line of sight and the SVD of the
    geometry never returned; 1e100 already answered."""
    tr = mn.Trajectory.random(duration=5.0, seed=1)
    g = mn.simulate_gnss(tr.time, tr.position_ecef, tr.velocity_ecef, mn.Constellation.walker())
    for far in (1e200, 1e10):
        with pytest.raises(ValueError, match=r"^prior: has a component of 1\.0e\+?\d+ m"):
            mn.solve_fix(g, prior=np.full(3, far))
    # A prior anywhere a receiver can be still converges.
    fix = mn.solve_fix(g, prior=[1e7, 0.0, 0.0])
    np.testing.assert_allclose(fix.position_ecef[0], tr.position_ecef[0], atol=50.0)


def test_a_gnss_rate_finer_than_the_time_stamps_answers_at_once():
    """1e18 Hz on a 1 s track: the epoch search advanced one target per
    pass. A period below the sample spacing makes every sample an epoch."""
    tr = mn.Trajectory.random(duration=1.0, seed=1)
    sky = mn.Constellation.walker()
    for rate in (1e18, 1e12):
        g = mn.simulate_gnss(tr.time, tr.position_ecef, tr.velocity_ecef, sky, rate=rate)
        np.testing.assert_array_equal(g.time, tr.time)


def test_strapdown_checks_its_start_as_every_position_is_checked():
    """Zeros gave 18 000 of 18 003 values NaN, [1, 2, 3] 4.8e22 m: the start
    now passes the one ECEF position check the filters use too."""
    tr = mn.Trajectory.random(duration=2.0, seed=1)
    for start in ([0.0, 0.0, 0.0], [1.0, 2.0, 3.0], [2e9, 0.0, 0.0]):
        with pytest.raises(ValueError, match=r"^position_ecef: row 0: .* from the Earth's centre"):
            mn.strapdown(
                tr.time,
                tr.specific_force,
                tr.angular_rate,
                start,
                tr.velocity_ecef[0],
                tr.attitude[0],
            )


def test_simulate_gnss_refuses_a_receiver_off_the_earth():
    """A receiver at the Earth's centre gave every pseudorange NaN."""
    tr = mn.Trajectory.random(duration=2.0, seed=1)
    sky = mn.Constellation.walker()
    with pytest.raises(ValueError, match=r"^position_ecef: row 0: 0 m from the Earth's centre"):
        mn.simulate_gnss(tr.time, np.zeros_like(tr.position_ecef), tr.velocity_ecef, sky)


def test_a_draw_set_too_large_to_hold_is_refused_not_allocated():
    """draws=10**12 aborted the interpreter on allocation."""
    from memsnav import _memsnav

    a, g = np.eye(15) * 1e-6, np.eye(21) * 1e-8
    with pytest.raises(ValueError, match=r"^draws: would need the gyroscope draws: 2\.100e\+?13"):
        _memsnav.draw_imu_calibrations(np.zeros(15), a, np.zeros(21), g, draws=10**12, seed=1)
    small = _memsnav.draw_imu_calibrations(np.zeros(15), a, np.zeros(21), g, draws=2, seed=1)
    assert small[0].shape == (2, 15) and small[1].shape == (2, 21)


# --- IMU time gaps --------------------------------------------------------------------


def test_strapdown_refuses_an_imu_gap_far_beyond_the_period():
    t = mn.Trajectory.random(duration=20.0, rate=10.0, seed=0)
    time = t.time.copy()
    time[50:] += 1e6  # integrated through, the INS reached 1e17 m
    with pytest.raises(ValueError, match=r"time: a gap of 1000000\.1 s between samples 49 and 50"):
        mn.strapdown(
            time,
            t.specific_force,
            t.angular_rate,
            t.position_ecef[0],
            t.velocity_ecef[0],
            t.attitude[0],
        )


# --- the command line -------------------------------------------------------------------


def run_cli(*args: str) -> subprocess.CompletedProcess[str]:
    return subprocess.run(
        [sys.executable, "-m", "memsnav", *args], capture_output=True, text=True, check=False
    )


def test_cli_errors_are_one_line_and_debug_shows_the_traceback(tmp_path):
    config = tmp_path / "bad.toml"
    config.write_bytes(b'name = "\xff\xfe"\n')
    done = run_cli("navigate", "--config", str(config))
    assert done.returncode == 1
    assert done.stderr.count("\n") == 1, done.stderr
    assert done.stderr.startswith(f"memsnav: error: {config}: not UTF-8 text")
    debug = run_cli("--debug", "navigate", "--config", str(config))
    assert debug.returncode == 1 and "Traceback" in debug.stderr


@pytest.mark.parametrize("duration", ["nan", "-5", "0", "inf"])
def test_cli_navigate_duration_must_be_positive_and_finite(tmp_path, duration):
    done = run_cli("navigate", "--config", str(tmp_path / "x.toml"), "--duration", duration)
    assert done.returncode == 2
    assert "argument --duration: must be positive and finite" in done.stderr
    assert "Traceback" not in done.stderr


# --- one check of every IMU series and start --------------------------------


def imu_gap_track():
    t = mn.Trajectory.random(duration=20.0, rate=10.0, seed=0)
    time = t.time.copy()
    time[50:] += 1e6
    return t, time


@pytest.mark.parametrize("kind", ["tight", "loose"])
def test_the_filters_refuse_the_imu_gap_strapdown_refuses(kind):
    """Both filters integrated across a 10⁶ s gap and ended 4.7e15 m off with
    diverged = False: they now run the one IMU series check strapdown runs."""
    t, time = imu_gap_track()
    imu = mn.ImuModel.preset("consumer", seed=1)
    gnss = mn.simulate_gnss(t.time, t.position_ecef, t.velocity_ecef, mn.Constellation.walker())
    if kind == "tight":
        run = mn.TightlyCoupledFilter(imu).run
        aiding = gnss
    else:
        run = mn.LooselyCoupledFilter(imu).run
        fixes = mn.solve_fix(gnss)
        aiding = {
            "time": np.array(fixes.time),
            "position_ecef": np.array(fixes.position_ecef),
            "position_covariance": np.array(fixes.position_clock_covariance)[:, :3, :3],
        }
    with pytest.raises(ValueError, match=r"^time: a gap of 1000000\.1 s between samples 49 and 50"):
        run(time, t.specific_force, t.angular_rate, aiding, initial_attitude=t.attitude[0])


def strapdown_with(**changes):
    t = mn.Trajectory.random(duration=2.0, seed=1)
    args = {
        "time": t.time,
        "specific_force": t.specific_force,
        "angular_rate": t.angular_rate,
        "position_ecef": t.position_ecef[0],
        "velocity_ecef": t.velocity_ecef[0],
        "attitude": t.attitude[0],
    }
    args.update({k: v(args[k]) for k, v in changes.items()})
    return mn.strapdown(*args.values())


@pytest.mark.parametrize(
    ("changes", "message"),
    [
        # 1e300 m/s² or rad/s: all NaN before; beyond any sensor's range.
        ({"specific_force": lambda f: f * 0 + 1e300}, r"^specific_force: row 0 holds 1e300, "),
        ({"angular_rate": lambda w: w * 0 + 1e300}, r"^angular_rate: row 0 holds 1e300, "),
        # A stamp 1e-300 s after the first (hypothesis): NaN from then on.
        (
            {"time": lambda t: np.concatenate([[t[0], t[0] + 1e-300], t[2:]])},
            r"^time: samples 0 and 1 .* are 1e-300 s apart, less than a hundredth",
        ),
        # A span of 1e300 s: every period far beyond an IMU's.
        ({"time": lambda t: t * 1e298}, r"^time: the median sample period is .* longer than 1 s"),
        ({"velocity_ecef": lambda v: v * 0 + 1e300}, r"^velocity_ecef: row 0: a speed of"),
    ],
)
def test_strapdown_refuses_series_no_sensor_gives(changes, message):
    with pytest.raises(ValueError, match=message):
        strapdown_with(**changes)


def test_strapdown_at_the_limits_is_finite():
    """At the edges of what is accepted the INS stays a number."""
    sol = strapdown_with(
        specific_force=lambda f: f * 0 + 1e6,
        angular_rate=lambda w: w * 0 - 1e6,
        velocity_ecef=lambda v: v / np.linalg.norm(v) * 1e5,
    )
    assert np.isfinite(sol.position_ecef).all() and np.isfinite(sol.attitude).all()


# --- sensor models on finite extremes ----------------------------------------

Z3, Z33 = np.zeros(3), np.zeros((3, 3))


@pytest.mark.parametrize(
    ("build", "message"),
    [
        # N f² with f = 1e160 overflowed to [-inf, nan, nan].
        (
            lambda: mn.AccelerometerModel(Z3, Z3, Z33, [1e-4, 0, 0]).measure([[1e160, 0, 0]]),
            r"^specific_force: row 0 holds 1e160, beyond the limit of ±1e6",
        ),
        (
            lambda: mn.AccelerometerModel(Z3, Z3, Z33, Z3, bias_instability=1e300),
            r"^bias_instability: 1e300 is beyond the limit of 1e6",
        ),
        # 1e300 Hz gave a per-sample noise std of 1e147.
        (
            lambda: mn.AccelerometerModel(Z3, Z3, Z33, Z3, noise_density=1e-3, sample_rate=1e300),
            r"^sample_rate: 1e300 is beyond the limit of 1e6",
        ),
        (
            lambda: mn.GyroscopeModel([1e300, 0, 0], Z3, Z33, Z33),
            r"^bias: row 0 holds 1e300, beyond the limit of ±1e6",
        ),
        (
            lambda: mn.GyroscopeModel(Z3, Z3, Z33, np.full((3, 3), 1e300)),
            r"^g_sensitivity: holds 1e300, beyond the limit of ±1e6",
        ),
    ],
)
def test_sensor_models_refuse_values_beyond_any_sensor(build, message):
    with pytest.raises(ValueError, match=message):
        build()


def test_sensor_models_at_their_limits_give_finite_readings():
    """Everything at the largest accepted magnitude, the tiniest LSB and a
    correlation time near zero (its PSD 2σ²/τ overflowed): finite readings."""
    big = np.full(3, 1e6)
    misalignment = np.full((3, 3), 1e6) - np.diag(np.full(3, 1e6))
    noise = {
        "bias_instability": 1e6,
        "bias_correlation_time": 1e-300,
        "bias_random_walk": 1e6,
        "noise_density": 1e6,
        "sample_rate": 1e6,
    }
    for lsb in (1e-300, 5e-324, 1e6):
        acc = mn.AccelerometerModel(big, big, misalignment, big, quantization=lsb, **noise)
        k = np.full((3, 3), 1e6)
        gyr = mn.GyroscopeModel(big, big, misalignment, k, quantization=lsb, **noise)
        inputs = np.full((50, 3), -1e6)
        assert np.isfinite(acc.measure(inputs, seed=1)).all()
        assert np.isfinite(gyr.measure(inputs, inputs, seed=1)).all()


def test_a_tiny_lsb_keeps_the_reading_it_cannot_resolve():
    acc = mn.AccelerometerModel(Z3, Z3, Z33, Z3, quantization=1e-300)
    np.testing.assert_array_equal(acc.measure([[9.81, -1.0, 0.5]]), [[9.81, -1.0, 0.5]])
    coarse = mn.AccelerometerModel(Z3, Z3, Z33, Z3, quantization=0.5)
    np.testing.assert_array_equal(coarse.measure([[9.81, -1.2, 0.2]]), [[10.0, -1.0, 0.0]])


# --- an outlier applied with the gate off ------------------------------------


@pytest.mark.parametrize("kind", ["tight", "loose"])
def test_an_outlier_applied_with_the_gate_off_is_reported(drive, kind):
    """gate_probability = 1 lets an outlier through (a fix 10⁹ m off; a
    pseudorange 5·10⁷ m too long: a longer one is no receiver's and is
    refused up front), which used to go without a warning."""
    traj, _, imu, f, w, _ = drive
    sol, aiding, caught = doc_runs.outlier_run(drive, kind)
    applied = "GNSS batches were applied although their NIS was beyond"
    assert any(applied in str(c.message) for c in caught)
    # How far the outlier leaves the run: docs/reference/robustness.md shows the record.
    error_km = np.linalg.norm(sol.position_ecef[-1] - traj.position_ecef[-1]) / 1e3
    assert abs(error_km - figures("robustness_runs")[f"outlier_{kind}_end_km"]) <= 1e-9
    assert sol.diverged
    assert [a.kind for a in sol.integrity.alerts].count("applied_outliers") == 1
    # The same run with the gate on rejects the outlier and says nothing.
    gated = (mn.TightlyCoupledFilter if kind == "tight" else mn.LooselyCoupledFilter)(imu)
    with warnings.catch_warnings():
        warnings.simplefilter("error")
        clean = gated.run(traj.time, f, w, aiding, initial_attitude=traj.attitude[0])
    assert not clean.diverged


EXAMPLES = Path(__file__).parents[1] / "examples"


def walk_arguments(tmp_path: Path) -> list[str]:
    """``navigate`` of the first second of the walk excerpt."""
    config = navigate_config(tmp_path, WALK)
    return ["navigate", "--config", str(config), "--data-root", str(DATA), "--duration", "1"]


def test_cli_refuses_an_output_that_is_a_users_file_and_moves_nothing(tmp_path):
    """``--output FILE`` used to exit 0 having moved the file to a hidden
    ``.FILE.<random>.old``; a non-empty folder memsnav did not write is
    refused by every command, and nothing in either is touched."""
    users = tmp_path / "users"
    users.mkdir()
    mine = users / "mine.txt"
    mine.write_text("precious")
    folder = users / "folder"
    folder.mkdir()
    (folder / "notes.txt").write_text("mine too")
    commands = {
        "navigate": [*walk_arguments(tmp_path), "--output"],
        "simulate": ["simulate", "--duration", "2", "--out"],
        "study": ["study", "--config", str(EXAMPLES / "study_land_vehicle.toml"), "--output"],
        "reproduce": ["reproduce", "--runs", "1", "--out"],
        "calibrate": ["calibrate", "--config", str(EXAMPLES / "xsens_static.toml"), "--output"],
    }
    # All at once: each is refused before any work. The folder case is the
    # same check (_files.output_folder) for all: three commands suffice.
    cases = [
        (command, target)
        for command in commands
        for target in (mine, folder)
        if target == mine or command in ("navigate", "simulate", "calibrate")
    ]
    done = run_cli_at_once(*[[*commands[command], str(target)] for command, target in cases])
    for (command, target), (status, stderr) in zip(cases, done, strict=True):
        reason = (
            "is a file, not a folder; memsnav does not replace, move or delete a file it was "
            "not asked to write"
            if target == mine
            else "is not empty and memsnav did not write it (no .memsnav-output in it); give a "
            "new or empty folder"
        )
        wanted = f"memsnav: error: output folder {str(target)!r}: {reason}\n"
        assert (status, stderr) == (1, wanted), command
    assert sorted(p.name for p in users.iterdir()) == ["folder", "mine.txt"]
    assert mine.read_text() == "precious" and os.listdir(folder) == ["notes.txt"]


def test_cli_navigate_replaces_only_what_an_earlier_navigate_wrote(tmp_path):
    out = tmp_path / "out"
    navigate = walk_arguments(tmp_path)
    assert run_cli(*navigate, "--output", str(out)).returncode == 0
    assert run_cli(*navigate, "--output", str(out)).returncode == 0  # its own: replaced
    (out / "notes.txt").write_text("added by the user")
    done = run_cli(*navigate, "--output", str(out))
    assert done.returncode == 1
    assert done.stderr.splitlines()[-1] == (
        f"memsnav: error: output folder {str(out)!r}: holds 'notes.txt' that memsnav navigate "
        "did not write; navigate replaces its output folder whole: move them away or give "
        "another folder"
    )
    assert (out / "notes.txt").read_text() == "added by the user"
    # A folder another command wrote into is memsnav's, but not navigate's to replace.
    simulated = tmp_path / "simulated"
    assert run_cli("simulate", "--duration", "2", "--out", str(simulated)).returncode == 0
    done = run_cli(*navigate, "--output", str(simulated))
    assert done.returncode == 1 and "holds 'gnss.csv' and 4 more entries" in done.stderr
    assert not [p.name for p in tmp_path.iterdir() if p.name.startswith(".")]


def run_cli_at_once(*command_lines: list[str]) -> list[tuple[int, str]]:
    """Each command line as ``python -m memsnav`` at the same time: (exit
    status, stderr) of each, in order."""
    processes = [
        subprocess.Popen(
            [sys.executable, "-m", "memsnav", *line],
            stdout=subprocess.PIPE,
            stderr=subprocess.PIPE,
            text=True,
        )
        for line in command_lines
    ]
    stderrs = [p.communicate()[1] for p in processes]
    return [(p.returncode, stderr) for p, stderr in zip(processes, stderrs, strict=True)]


# (template, replacements, the message after "memsnav: error: <config>: ").
CONFIG_ERRORS = [
    # A truth that matches no epoch was scored as {epochs: 0} with exit 0.
    (
        DRIVE,
        {"quality = [1]": "quality = [7]"},
        "truth.quality: no epoch of {data}/real-imu-gnss/drive_60s.pos has a quality in [7]; "
        "its 268 epochs have the qualities [1, 2]",
    ),
    (
        DRIVE,
        {"quality = [1]": 'quality = ["a"]'},
        "truth.quality: entry 0: must be an integer in [0, 7], got 'a'",
    ),
    (DRIVE, {"quality = [1]": 'quality = "a"'}, "truth.quality: must be a list, got 'a'"),
    # Was: no epoch of <memsnav._memsnav.PosSolution object at 0x...> has a quality ...
    (
        DRIVE,
        {"quality = [1, 2]": "quality = [5]"},
        "gnss.quality: no epoch of {data}/real-imu-gnss/drive_60s.pos has a quality in [5]; "
        "its 268 epochs have the qualities [1, 2]",
    ),
    # Was accepted and changed the result.
    (
        WALK,
        {
            "min_cn0_db_hz = 20.0": "min_cn0_db_hz = 20.0\nklobuchar_alpha = [nan, 0, 0, 0]\n"
            "klobuchar_beta = [0, 0, 0, 0]"
        },
        "gnss.klobuchar_alpha: entry 0: must be a finite number, got nan",
    ),
    (
        WALK,
        {"min_cn0_db_hz = 20.0": "min_cn0_db_hz = 20.0\nklobuchar_alpha = [0, 0, 0, 0]"},
        "gnss.klobuchar_alpha and gnss.klobuchar_beta: give four numbers each, or neither",
    ),
    # Was: 'int' object is not an instance of 'str' (and 'bool').
    (
        DRIVE,
        {"[imu]": "[imu]\ncolumns = [1, 2, 3, 4, 5, 6, 7]"},
        "imu.columns: entry 0: must be a string, got 1",
    ),
    (
        DRIVE,
        {"[imu]": "[imu]\ncolumns = [true]"},
        "imu.columns: entry 0: must be a string, got True",
    ),
    (
        DRIVE,
        {"[imu]": "[imu]\ncalibration = 5"},
        "imu.calibration: must be a path (a string), got 5",
    ),
    # Was: invalid literal for int() with base 10: 'a' (and 1.5 silently taken for 1).
    (
        WALK,
        {"min_cn0_db_hz = 20.0": 'min_cn0_db_hz = 20.0\nsatellites = ["a"]'},
        'gnss.satellites: entry 0: must be a satellite name like "G10", "E24", "C11", "R05", '
        "got 'a'",
    ),
    (
        WALK,
        {"min_cn0_db_hz = 20.0": "min_cn0_db_hz = 20.0\nsatellites = [1.5]"},
        'gnss.satellites: entry 0: must be a satellite name like "G10", "E24", "C11", "R05", '
        "got 1.5",
    ),
    # Was: embedded null byte (the output), or a "no such file" with an invisible NUL.
    (
        DRIVE,
        {'output = "': 'output = "\\u0000'},
        "output: must be a path, got '\\x00{out}': it contains a NUL character",
    ),
    (
        DRIVE,
        {'drive_60s.csv"': 'drive_60s.csv\\u0000"'},
        "imu.file: must be a path, got 'real-imu-gnss/drive_60s.csv\\x00': it contains a NUL "
        "character",
    ),
    # Was: fixes: has no epochs (length 0); give at least one GNSS epoch.
    (
        DRIVE,
        {'mode = "loose"': 'mode = "loose"\nrate_hz = 1e-3'},
        "gnss.rate_hz: no epoch of {data}/real-imu-gnss/drive_60s.pos lies on the 0.001 Hz grid "
        "(GPS time a multiple of 1/rate_hz, within 0.02 s)",
    ),
    # The engine's keys (checked by the core): were accepted.
    (
        DRIVE,
        {"mounting_rpy_deg = [[180.0, 0.0, 180.0], [0.0, -6.79, 5.35]]": "mounting_rpy_deg = []"},
        "imu.mounting_rpy_deg: expected at least one [roll, pitch, yaw] triple, got []",
    ),
    (
        DRIVE,
        {"[truth]": "[alignment]\nheading_deg = 1e300\n[truth]"},
        "alignment.heading_deg: must be an angle within ±360°, got 1e300",
    ),
    # The reader's arguments are the keys of the same name.
    (
        DRIVE,
        {'accel_unit = "g"': 'accel_unit = "G"'},
        "imu.accel_unit: unknown unit 'G'; expected one of "
        "['g', 'm/s^2', 'm/s2', 'm/s', 'g*s', 'g.s']",
    ),
    (
        WALK,
        {"elevation_mask_deg = 5.0": "elevation_mask_deg = 1e300"},
        "gnss.elevation_mask_deg: must be a finite number in [0, 90], got 1e+300",
    ),
]


def test_cli_config_errors_name_the_file_and_the_key(tmp_path):
    """Each error names the configuration and the key: an error found
    while the configuration is read is the command's one line; one found
    while the inputs are read (the output folder already accepted) is the
    failed run's, which names its report."""
    command_lines, expected = [], []
    for i, (template, replace, message) in enumerate(CONFIG_ERRORS):
        case = tmp_path / f"case{i}"
        case.mkdir()
        config = navigate_config(case, template, **replace)
        command_lines.append(["navigate", "--config", str(config), "--data-root", str(DATA)])
        message = message.format(data=DATA, out=case / "out")
        report = case / "out" / "report.html"
        expected.append(
            (
                f"memsnav: error: {config}: {message}\n",
                f"memsnav: error: FAILED (inputs): reading the inputs: {config}: {message} "
                f"(what the run computed and what may explain it: {report})\n",
            )
        )
    for (status, stderr), wanted in zip(run_cli_at_once(*command_lines), expected, strict=True):
        assert status == 1
        assert stderr in wanted


def test_cli_spans_that_hung_or_aborted_are_refused_naming_the_key(tmp_path):
    """``simulate --duration 1e300 --rate 1e-298`` (100 samples) never
    finished, the position integration stepping every 0.01 s; a study's
    ``calibration_duration = 1e10`` aborted the interpreter on allocation."""
    study = tmp_path / "study.toml"
    study.write_text(
        '[study]\ngrades = ["consumer"]\noutage_lengths = [10]\nvisible_satellites = [0]\n'
        "runs = 1\ncalibrated = true\ncalibration_duration = 1e10\n"
    )
    done = run_cli_at_once(
        ["simulate", "--duration", "1e300", "--rate", "1e-298", "--out", str(tmp_path / "s")],
        ["study", "--config", str(study), "--output", str(tmp_path / "o"), "--quiet"],
    )
    assert done == [
        (1, "memsnav: error: duration: 1e300 s is longer than the limit of 1e6 s\n"),
        (
            1,
            f"memsnav: error: {study}: study: calibration_duration: 1e10 s is longer than the "
            "limit of 1e6 s\n",
        ),
    ]


def test_a_gnss_step_too_long_for_the_clock_names_time():
    """Was ``clock: process noise is not positive definite``. The command
    line no longer reaches it (a simulated span is at most 10⁶ s)."""
    t = mn.Trajectory.random(duration=2.0, seed=1)
    with pytest.raises(ValueError, match=r"^time: GNSS epochs at 0e0 s and 1e300 s: clock: the "
                       r"process noise over a step of 1e300 s overflows"):  # fmt: skip
        mn.simulate_gnss(
            np.array([0.0, 1e300]),
            t.position_ecef[[0, -1]],
            t.velocity_ecef[[0, -1]],
            mn.Constellation.walker(),
        )


# --- values no receiver reports ----------------------------------------------


def test_a_gnsslogger_satellite_that_does_not_exist_is_skipped_and_counted(tmp_path):
    """Svid 255 of ConstellationType 1 (GPS) was read as satellite G255."""
    lines = (DATA / "android-gnsslogger" / "pixel6_excerpt.txt").read_text().splitlines()
    header = next(line for line in lines if line.startswith("# Raw,")).split(",")
    svid, constellation = header.index("Svid"), header.index("ConstellationType")
    k, fields = next(
        (k, line.split(","))
        for k, line in enumerate(lines)
        if line.startswith("Raw,") and line.split(",")[constellation] == "1"
    )
    fields[svid] = "255"
    lines[k] = ",".join(fields)
    path = tmp_path / "g255.txt"
    path.write_text("\n".join(lines) + "\n")
    log = mn.read_gnsslogger(path)
    assert "G255" not in log.observations.satellites
    assert log.skipped["Svid outside its constellation's satellite numbers (system G)"] == 1
    before = mn.read_gnsslogger(DATA / "android-gnsslogger" / "pixel6_excerpt.txt")
    assert set(log.observations.satellites) <= set(before.observations.satellites)


def test_a_gnss_table_with_values_no_receiver_reports_is_refused():
    """gps_time_s = 1e308, a pseudorange of 1e300 m, a rate of 1e300 m/s were
    accepted; each is refused naming the row and the column."""
    row = {
        "time_s": [0.0],
        "gps_time_s": [1.4e9],
        "sat_id": [5],
        **{
            f"sat_position_ecef_{a}_m": [v]
            for a, v in zip("xyz", [-2.2e6, -2.6e7, -3.4e6], strict=True)
        },
        **{
            f"sat_velocity_ecef_{a}_m_s": [v]
            for a, v in zip("xyz", [325.5, -419.7, 3129.0], strict=True)
        },
        "pseudorange_m": [2.3e7],
        "pseudorange_rate_m_s": [-120.5],
    }
    assert len(mn.GnssMeasurements.from_table(row).time) == 1
    for column, value, message in [
        ("gps_time_s", 1e308, r"row 0: gps_time_s = 1e308 s is out of range \(0e0 to 3.78648e9"),
        ("pseudorange_m", 1e300, r"row 0: pseudorange = 1e300 m is out of range \(0e0 to 1e8 m\)"),
        ("pseudorange_rate_m_s", 1e300, r"row 0: pseudorange_rate = 1e300 m/s is out of range"),
    ]:
        with pytest.raises(ValueError, match=message):
            mn.GnssMeasurements.from_table(row | {column: [value]})
