"""Results print as what they are, in a line: the class, its sizes and its
state, never a wall of arrays."""

from pathlib import Path

import memsnav as mn


def _check(result, name, *words):
    text = repr(result)
    assert text.startswith(f"{name}(") and "\n" not in text and len(text) < 200, text
    for word in words:
        assert word in text, (word, text)


def test_experiment_results_print_in_a_line():
    nav = mn.experiments.navigation(runs=2, duration=20.0, threads=1)
    _check(nav, "NavigationResult", "ins, mems, calibrated_mems", "2 runs", "20 s")
    partial = mn.experiments.partial_outage(
        imus=("tactical",),
        runs=1,
        duration=40.0,
        outage_start=20.0,
        outage_length=10.0,
        satellites=(0,),
        loose=False,
    )
    _check(partial, "PartialOutageResult", "tight, 0 satellites", "1 runs")
    study = mn.experiments.outage_study(
        grades=("tactical",),
        outage_lengths=(5.0,),
        visible_satellites=(0,),
        runs=2,
        outage_start=20.0,
        max_error_m=100.0,
    )
    _check(study, "OutageStudyResult", "1 grades", "2-2 runs per cell", "undecided")
    _check(study.cell("tactical", 5.0, 0), "StudyCell", "'tactical', 5 s", "2 runs")
    calibration = mn.experiments.calibration(parameter_sets=1, runs=2, duration=10.0)
    _check(calibration, "CalibrationResult", "eiv", "2 runs", "accelerometer")
    inversion = mn.experiments.inversion(runs=1, duration=5.0)
    _check(inversion, "InversionResult", "1 runs", "100 Hz")


def test_filters_fixes_and_logs_print_in_a_line():
    imu = mn.ImuModel.preset("tactical")
    _check(mn.TightlyCoupledFilter(imu), "TightlyCoupledFilter", "100 Hz", "17 error states")
    every = mn.TightlyCoupledFilter(
        imu, settings={"gnss": {"range_bias_states": "every_satellite"}}
    )
    _check(every, "TightlyCoupledFilter", "57 error states", "range biases")
    _check(
        mn.LooselyCoupledFilter(imu, scale_factor_states=True),
        "LooselyCoupledFilter",
        "23 error states",
        "scale factors",
    )
    fixes = mn.fixes_from_solution(
        time=[0.0, 1.0, 2.0],
        geodetic=[[0.76, 0.03, 100.0]] * 3,
        std_ned=[[1.0, 1.0, 2.0]] * 3,
    )
    _check(fixes, "PositionFixes", "3 fixes", "0.000-2.000 s", "0 with velocity")
    log = mn.read_gnsslogger(
        Path(__file__).parent / "data" / "android-gnsslogger" / "pixel6_excerpt.txt"
    )
    _check(log, "GnssLoggerLog", "epochs", "warnings")


def test_gnss_files_measurements_and_fixes_print_in_a_line():
    from test_single_point import PUBLIC, _skydel_gr

    _check(
        mn.read_rinex_obs(PUBLIC / "skydel_20230080000_GR_C1C.rnx"),
        "RinexObservations",
        "epochs",
        "GR",
    )
    measurements = _skydel_gr()
    _check(measurements, "GnssMeasurements", "49 epochs", "satellites")
    _check(
        mn.solve_fix(measurements),
        "FixSeries",
        "49 fixes of 49 epochs",
        "0 with satellites excluded",
    )
    sp3 = sorted(PUBLIC.glob("*.SP3"))[0]
    _check(mn.read_sp3(sp3), "Sp3", "satellites", "epochs")


def _public_classes():
    """Every public class of memsnav and its native module (exceptions
    aside), each once: the classes of test_docstrings' walk."""
    import inspect

    from test_docstrings import _documented_names

    for _, obj in _documented_names():
        if inspect.isclass(obj) and not issubclass(obj, BaseException):
            yield obj


def test_no_public_class_prints_as_an_address_or_a_wall_of_fields():
    """Every public class has a repr of its own: not object's address, not
    a dataclass's generated one (every field, arrays in full)."""
    import inspect

    generic = []
    for cls in _public_classes():
        if cls.__repr__ is object.__repr__:
            generic.append(f"{cls.__qualname__}: object's")
            continue
        if "__dataclass_fields__" in vars(cls):
            try:
                inspect.getsource(cls.__repr__)
            except (OSError, TypeError):
                generic.append(f"{cls.__qualname__}: the dataclass's")
    assert not generic, generic


def test_calibration_files_timing_estimates_and_log_runs_print_in_a_line(tmp_path):
    import warnings

    from shared_data import shared_data

    data = shared_data("real-imu-gnss").parent
    root = data / "real-imu-gnss"
    rtk = mn.read_pos(root / "drive_0708" / "gnss_1934_sf.pos")
    _check(mn.estimate_velocity_latency(rtk), "VelocityLatencyEstimate", "0.13", "intervals")
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")  # the log's cut last line
        imu = mn.read_imu_csv(root / "drive_0708" / "imu_1934.csv", skip_first_line=True)
    clock = mn.fit_tag_clock(imu, mn.read_time_tag(root / "drive_0708" / "imu_1934.csv.tag"))
    c_b_s = mn.mounting_matrix([[180.0, 0.0, 180.0], [0.0, -6.79, 5.35]])
    offset = mn.estimate_time_offset(
        clock.gps_time, imu.specific_force @ c_b_s.T, imu.angular_rate @ c_b_s.T, rtk
    )
    _check(offset, "TimeOffsetEstimate", "-0.27", "4 stretches")
    run = mn.navigate(
        Path(__file__).parent.parent / "examples" / "drive_0708.toml",
        data_root=data,
        output=tmp_path / "nav",
        duration_s=30.0,
    )
    _check(run, "LogNavigationResult", "'drive_0708'", "epochs", "scored against the truth")
    _check(mn.load_calibration(_calibration_file(tmp_path)), "ImuCalibration", "parameters")


def _calibration_file(tmp_path):
    """A calibration file of the Xsens static session (a few seconds)."""
    from shared_data import shared_data

    from memsnav.cli import main

    config = Path(__file__).parent.parent / "examples" / "xsens_static.toml"
    data = shared_data("imu-static-poses").parent
    out = tmp_path / "cal"
    assert (
        main(["calibrate", "--config", str(config), "--data-root", str(data), "--output", str(out)])
        == 0
    )
    return out / "calibration.json"


def test_fixed_shape_results_are_typed_records(drive_300s):
    """A log run's start, failure and gyro check and a quantile interval
    are records: each field an attribute (the start's state goes straight
    into a filter class), `to_dict()` the same fields for JSON, a one-line
    repr; they are frozen."""
    import numpy as np
    import pytest

    traj, gnss, _, f, w = drive_300s
    run = mn.navigate_log(traj.time, f, w, gnss, settings={"filter": {"imu_preset": "consumer"}})
    start = run.start
    assert isinstance(start, mn.RunStart) and isinstance(start.initial_state, mn.InitialState)
    _check(start, "RunStart", start.kind, "sample")
    fields = start.to_dict()
    assert set(fields) >= {"kind", "time", "first_sample", "initial_state", "heading_std"}
    assert fields["first_sample"] == start.first_sample
    np.testing.assert_array_equal(
        start.initial_state.position_ecef, start.initial_state.to_dict()["position_ecef"]
    )
    with pytest.raises(AttributeError):
        start.time = 0.0
    assert run.failure is None and isinstance(run.gyro_scale, mn.GyroScaleCheck)
    _check(run.gyro_scale, "GyroScaleCheck", "pairs")
    interval = mn.quantile_interval(np.arange(1.0, 101.0), 0.5)
    _check(interval, "QuantileInterval", "coverage")
    assert interval.lower < 50.5 < interval.upper and interval.coverage >= 0.95
