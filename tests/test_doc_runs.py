"""The short runs behind the figures the pages quote (docs/doc_runs.py),
run again: each agrees with its record, docs/data/<name>.json, within
half the last digit the pages show (counts exactly). The pages show the
records (tests/test_doc_figures.py); here the library today is held to
them."""

import doc_runs
import pytest
from figures import figures, load_record
from run_record import check_run


def test_the_first_session_prints_its_record():
    """The INS fed the truth stays within millimetres over 120 s; the raw
    MEMS drifts by kilometres (shown to 0.1 km)."""
    fresh = check_run("first_session", {"ins_largest_error_m": 5e-4, "drift_km": 0.05})
    assert fresh["ins_largest_error_m"] < 0.01


def test_the_step_api_example_prints_its_record():
    """docs/how-to/step-api.md's example run again: its outage errors (shown
    to 0.1 m; the wheel speed cuts the error) and the vertical velocity its
    constraint's 0.2 m/s must cover (shown to 0.01 m/s)."""
    fresh = check_run(
        "step_api_example",
        {
            "outage_end_error_m": 0.05,
            "outage_end_error_odometry_m": 0.05,
            "largest_vertical_body_velocity_m_s": 0.005,
        },
    )
    assert fresh["outage_end_error_odometry_m"] < 0.5 * fresh["outage_end_error_m"]
    assert fresh["largest_vertical_body_velocity_m_s"] < 0.2


def test_the_study_defaults_are_the_record():
    """The outage study's default outage start and duration margin, exact."""
    check_run("study_defaults", 0.0)


@pytest.mark.slow
def test_the_drive_calibration_windows_are_the_record():
    """The example calibrated with 0.5, 1, 2 and 4 s windows (about half a
    minute): each window's outage RMS within half the page's last digit."""
    fresh = check_run(
        "drive_calibration_windows",
        {"window_s": 0.0, "calibrated_rms_m": 5e-3, "raw_rms_m": 5e-3},
        needs_data=True,
    )
    assert fresh["window_s"] == [0.5, 1.0, 2.0, 4.0]


def test_the_own_arrays_example_is_as_poorly_conditioned_as_recorded():
    """The w axis's condition number, shown to one significant figure."""
    fresh = check_run("own_arrays_conditioning", {"w_axis_condition_number": float("inf")})
    recorded = figures("own_arrays_conditioning")["w_axis_condition_number"]
    assert f"{fresh['w_axis_condition_number']:.0e}" == f"{recorded:.0e}"


def test_the_inputs_correlation_times_are_the_records():
    """Shown to the second: τ = 10 s is chosen from them."""
    fresh = check_run("input_correlation_times", 0.5)
    assert fresh["yaw_rate_s"]["least"] < 10.0 < fresh["horizontal_force_s"]["most"]


def test_the_tactical_runs_on_three_satellites_are_the_records():
    """Final errors and vertical σ shown to 0.1 km, the share inside 3σ
    to the percent (~3 s)."""
    fresh = check_run(
        "tactical_three_satellites",
        {"final_error_km": 0.05, "final_vertical_sigma_km": 0.05, "least_inside_percent": 0.5},
    )
    assert fresh["least_inside_percent"] == 100.0  # every error inside 3σ


def test_the_drive_at_other_time_offsets_and_latencies_is_the_record():
    """drive_0708 without outages at four IMU offsets (NIS shown to
    0.001) and three velocity latencies (aided error to the cm, resets
    exactly): seven runs, ~5 s."""
    fresh = check_run(
        "drive_time_offsets",
        {
            "imu_offsets_s": 0.0,
            "position_nis_per_dof": 5e-4,
            "velocity_latencies_s": 0.0,
            "aided_rms_cm": 0.5,
            "position_resets": 0,
        },
        needs_data=True,
    )
    # The latency RTKLIB's velocities have cures the resets.
    assert fresh["position_resets"][1:] == [1, 1] < fresh["position_resets"][:1]


def test_the_example_logs_consistency_is_the_record():
    """The largest NIS-to-band ratio of each example log, shown to 0.1
    (~2 s); both inside the band."""
    fresh = check_run("example_consistency", 0.05, needs_data=True)
    assert max(fresh["largest_band_ratio"].values()) < 1.0


@pytest.mark.slow
def test_the_walk_by_precision_is_the_record():
    """walk_0827 by precision: the truth's offset shown to the metre, the
    RMS to the cm; the filter beats the single-point solution."""
    fresh = check_run(
        "walk_precision",
        {
            "truth_offset_m": 0.5,
            "forward_rms_horizontal_m": 0.005,
            "single_point_rms_horizontal_m": 0.005,
        },
        needs_data=True,
    )
    assert fresh["forward_rms_horizontal_m"] < fresh["single_point_rms_horizontal_m"]


@pytest.mark.slow
def test_the_two_satellite_runs_are_the_record():
    """The few-satellite study's eight 900 s runs on 2 satellites (~7 s):
    counts and the latest alert exactly, NIS to 0.1, tilts to the degree,
    their σ to 0.1°."""
    fresh = check_run(
        "two_satellite_runs",
        {
            "runs": 0,
            "inside_until_alert": 0,
            "latest_first_alert_s": 0.0,
            "nis_per_dof_60s": 0.05,
            "exception_tilt_deg": 0.5,
            "exception_tilt_sigma_deg": 0.05,
        },
    )
    # The innovations do not see the open directions: NIS stays near 1.
    assert 0.5 < fresh["nis_per_dof_60s"]["least"] <= fresh["nis_per_dof_60s"]["most"] < 1.5


@pytest.mark.slow
def test_the_partial_outages_are_the_record():
    """The partial-outage experiment's quick run (30 runs, seed 0; ~16 s):
    the table's errors to three figures, NEES to 0.01, the shares to the
    percent; no run flagged, every extra satellite helps."""
    fresh = check_run(
        "partial_outages",
        {
            "scenarios": {"largest_m": 0.05, "nees_per_dof": 0.005, "diverged_share": 0.0},
            "three_satellites_kept_percent": 0.5,
            "two_satellites_kept_percent": 0.5,
            "nees_per_dof": 0.05,
        },
    )
    table = fresh["scenarios"]
    assert all(c["diverged_share"] == 0.0 for row in table.values() for c in row.values())
    for imu in doc_runs.PAPER_IMUS:
        largest = [table[f"tight, {n} satellites"][imu]["largest_m"] for n in (0, 2, 3)]
        assert largest == sorted(largest, reverse=True), (imu, largest)


@pytest.mark.slow
def test_the_quick_calibration_is_the_record():
    """The calibration experiment's quick run (~30 s): efficiencies to the
    unit, shares to the percent, misalignment errors to 0.01; plain least
    squares' MSE is mostly its bias."""
    fresh = check_run(
        "quick_calibration",
        {
            "gyro_pq_efficiency_ls": 0.5,
            "accel_u_efficiency_ls": 0.5,
            "bias_share_percent": 0.5,
            "gyro_misalignment_nrmse": 0.005,
            "accel_misalignment_nrmse": 0.005,
        },
    )
    assert fresh["bias_share_percent"]["least"] > 50.0


@pytest.mark.slow
def test_the_drive_with_other_settings_is_the_record():
    """drive_0708 through the published filter's outage windows with other
    settings (~15 s): every error to the cm, the latency to the ms, the
    lever arm to the cm."""
    fresh = check_run(
        "drive_other_settings",
        {
            "example": 0.005,
            "offset_m0_125": 0.005,
            "offset_m0_27": 0.005,
            "fix_error_states": 0.005,
            "installation_states": {
                "forward_rms_m": 0.005,
                "smoothed_rms_m": 0.005,
                "smoothed_max_m": 0.005,
                "velocity_latency_s": 5e-4,
                "lever_arm_cm": 0,
                "time_offset_s": 0.005,
                "smoothed_rms_change_m": 0.005,
            },
            "aided_rms_m": 0.005,
        },
        needs_data=True,
    )
    # The states let the solution leave its input.
    aided = fresh["aided_rms_m"]
    assert aided["installation_states"] > aided["example"]


def test_the_standstill_detectors_statistics_are_the_record():
    """drive_0708 and walk_0827 in the detector's 1 s windows (~1 s):
    window counts exactly, the specific force's spread to 0.01 m/s², the
    angular rate's to 0.1 °/s; each log's rest quieter than its motion."""
    fresh = check_run(
        "standstill_spread",
        {"windows": 0, "accel_m_s2": 0.005, "gyro_deg_s": 0.05},
        needs_data=True,
    )
    for log in fresh.values():
        assert log["rest"]["accel_m_s2"]["p5"] < log["moving"]["accel_m_s2"]["p5"]
        assert log["rest"]["gyro_deg_s"]["p5"] < log["moving"]["gyro_deg_s"]["p5"]


def test_drive_0708s_rest_at_the_start_is_the_record():
    """drive_0708 with and without ZARU (~4 s): its rest and its first
    fix to 0.1 s, the z-gyro bias to 0.01 °/s and its σ as shown; one
    outage with a stop; ZARU knows the bias at rest better than the drive
    without it does by the end of the log."""
    fresh = check_run(
        "drive_rest_start",
        {
            "rest_s": 0.05,
            "first_fix_before_imu_s": 0.05,
            "start_after_first_fix_s": 0.05,
            "z_gyro_bias_deg_s": 0.005,
            "z_gyro_bias_sigma_deg_s": {"zaru": 5e-4, "no_zaru": 0.005, "no_zaru_log_end": 5e-4},
            "outages_with_a_stop": 0,
        },
        needs_data=True,
    )
    assert len(fresh["outages_with_a_stop"]) == 1
    sigma = fresh["z_gyro_bias_sigma_deg_s"]
    assert sigma["zaru"] < sigma["no_zaru_log_end"] < sigma["no_zaru"]


def test_the_tactical_preset_without_fading_is_the_record():
    """drive_0708 with the tactical preset and no fading (~2 s): resets
    exactly, the outage RMS to the metre; more resets and a worse coast
    than with fading (tactical_preset_fading)."""
    fresh = check_run(
        "tactical_without_fading",
        {"position_velocity_resets": 0, "outage_rms_m": 0.5},
        needs_data=True,
    )
    faded = figures("tactical_preset_fading")
    assert fresh["position_velocity_resets"] > faded["position_velocity_resets"]
    assert fresh["outage_rms_m"] > faded["tactical_outage_rms_m"]


@pytest.mark.slow
def test_the_foreign_drive_with_a_tight_constraint_is_the_record():
    """The foreign drive with the constraint's std at 0.1 m/s and as the
    log chooses it, 30 and 60 s outages (~20 s): the shares outside 3σ to
    the percent, the learnt std exactly; what the log chooses leaves none
    outside."""
    fresh = check_run(
        "foreign_drive_nhc",
        {"nhc_0_1": 0.5, "auto": 0.5, "learnt_nhc_std_m_s": 0.0},
        needs_data=True,
    )
    assert all(v == 0.0 for v in fresh["auto"].values())
    assert min(fresh["nhc_0_1"].values()) > 5.0


def test_a_misalignment_under_the_constraint_is_the_record():
    """tests/test_adaptation.py's drive with correlated fixes, installation
    states off and on (~4 s): the vertical share outside 3σ to the
    percent; none with the states."""
    fresh = check_run("misaligned_vertical", 0.5)
    assert fresh["with_states_percent"] == 0.0 < fresh["without_states_percent"]


def test_the_walks_clock_drift_and_span_are_the_record():
    """walk_0827's UBX log: the drift change to the m/s, its span to
    0.01 s."""
    check_run("walk_clock_span", {"drift_change_m_s": 0.5, "log_s": 0.005}, needs_data=True)


def test_the_walk_with_white_code_errors_is_the_record():
    """walk_0827 with its code errors as white noise and as range-bias
    states (~1 s): the shares inside 3σ to the percent (horizontal to
    0.1 %); the white-noise model's bounds hold for a minority only."""
    fresh = check_run(
        "walk_white_code",
        {"inside_percent": 0.5, "inside_horizontal_percent": 0.05},
        needs_data=True,
    )
    assert fresh["white"]["inside_percent"] < 50.0 < fresh["range_bias_states"]["inside_percent"]


def test_the_allan_fits_spread_is_the_record():
    """The Allan fit over 20 simulated records and on the Xsens rest
    (~4 s): spreads and mean errors as shown (N's to 0.01 %, the others'
    to 0.1 %); the Xsens white noise within 5 % of the IEEE reading."""
    tolerance = {"white_density": 0.005, "*": 0.05}
    fresh = check_run(
        "allan_fit_spread",
        {
            "seeds": 0,
            "spread_percent": tolerance,
            "mean_error_percent": tolerance,
            "xsens_white_vs_reading_percent": 0.05,
        },
    )
    assert abs(fresh["xsens_white_vs_reading_percent"]) < 5.0


def test_the_wrong_gyro_example_prints_its_record():
    """docs/how-to/when-a-run-fails.md's example (~2 s): the stage, the
    ratio to 0.1; a gyro about 57 times off."""
    fresh = check_run("wrong_gyro_example", {"stage": 0, "ratio": 0.05}, needs_data=True)
    assert fresh["stage"] == "units" and 50.0 < fresh["ratio"] < 65.0


def test_the_xsens_guides_own_figures_are_the_record():
    """docs/how-to/calibrate-an-imu.md's Xsens figures the other xsens_*
    records do not hold (eight calibrations, ~5 s): counts exactly, the
    others within half the last digit the page shows. The turns miss by
    more than the required 1.2° until the misalignments, g-sensitivity and
    scales are estimated, and the README's gyro scale as the start changes
    the corrected rates by rounding only."""
    fresh = check_run(
        "xsens_guide",
        {
            "poses": 0,
            "turns_held_out": 0,
            "middle_s": 0.005,
            "halves_fit_poses_after_rest": 0,
            "source_gyro_scale_low_percent": 0.5,
            "readme_start_rates_rad_s": 1e-9,  # rounding noise; the page states the bound
            "accel_scale_per_count": 5e-7,  # shown as 2.412e-3
            "n_sigma_at_g_mm_s2": 0.5,
            "n_fit_gain_mm_s2": 0.005,
            "g_sensitivity": 5e-7,
            "g_sensitivity_sigma_mean": 5e-6,
            "rest_mean_move_earth_rates": 0.5,
            "*": 0.05,
        },
        needs_data=True,
    )
    assert fresh["source_nominal_turn_deg"]["held_out"] > fresh["rest_bias_turn_deg"]["held_out"]
    assert fresh["rest_bias_turn_deg"]["held_out"] > 1.2
    assert fresh["readme_start_rates_rad_s"] < 1e-9


def test_the_readme_describes_the_drive_example_by_its_schedule():
    """The README's outage schedule is examples/drive_0708.toml's."""
    check_run("drive_example_schedule", 0.0)


def test_the_tables_are_their_records():
    """Each table a run fills (doc_runs.TABLES) is what its record renders
    to: python docs/doc_runs.py NAME rewrites it."""
    for name, tables in doc_runs.TABLES.items():
        for page, (begin, end), table in tables:
            text = (doc_runs.ROOT / "docs" / page).read_text()
            block = text[text.index(begin) : text.index(end) + len(end)]
            assert block == table(load_record(name)), f"rerun python docs/doc_runs.py {name}"
