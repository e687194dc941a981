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
    _check(mn.TightlyCoupledFilter(imu), "TightlyCoupledFilter", "100 Hz", "17 navigation")
    _check(
        mn.LooselyCoupledFilter(imu, scale_factor_states=True),
        "LooselyCoupledFilter",
        "23 navigation",
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
