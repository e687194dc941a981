"""The short runs behind figures the pages quote in their sentences, each
writing its record ``docs/data/<name>.json`` (docs/figures.py):
``python docs/doc_runs.py [--data-root DIR] [NAME ...]`` runs the named
ones (all without a name), writes their records and re-renders the pages.

Each run is a function returning its figures, full precision, in the
units the pages show; ``tests/test_doc_runs.py`` (and, for the walk's,
the foreign drive's, the static start's and the Xsens session's,
``tests/test_multi_gnss.py``, ``tests/test_your_own_files.py``,
``tests/test_allan.py`` and ``tests/test_static_calibration.py``) call
the same functions, or compute the same figures, and compare them today
with the records, within the digits the pages show. Most take seconds;
the calibration quick run and the drive with other settings take about
half a minute each, the walk's code-correlation table (45 walk runs)
about a minute, all of them together a few minutes (more on a shared
machine). A record in ``TABLES`` also fills a block of its page."""

from __future__ import annotations

import argparse
import contextlib
import copy
import io
import re
import tempfile
import warnings
from collections.abc import Callable
from pathlib import Path
from typing import Any

import drive_calibration_record
import foreign_drive_datum
import foreign_drive_study
import gnss_file_measurements
import installation_drives
import multi_gnss_measurements
import numpy as np
import page_measurements
import results_measurements
import robustness_reference
import time_offsets_record
import walk_multi_gnss
from figures import load_record, write_record
from marked_block import replace_block

import memsnav as mn
from memsnav.realdata.config import RunConfig, resolve_data_root
from memsnav.reproduce import QUICK

ROOT = Path(__file__).resolve().parents[1]


def _python_block(page: str, heading: str | None = None) -> str:
    """The first Python block of ``docs/<page>`` (after ``heading``)."""
    text = (ROOT / "docs" / page).read_text()
    if heading:
        text = text[text.index(heading) :]
    return re.search(r"```python\n(.*?)```", text, re.S).group(1)


def first_session(data_root: Path) -> dict[str, Any]:
    """The first session's Python block (docs/tutorials/first-session.md):
    what it prints, the INS fed the truth's largest error and the raw
    MEMS's drift after 120 s."""
    out = io.StringIO()
    with contextlib.redirect_stdout(out), tempfile.TemporaryDirectory() as tmp:
        with contextlib.chdir(tmp):
            block = _python_block("tutorials/first-session.md", "## A first session in Python")
            exec(compile(block, "first-session.md", "exec"), {})
    truth_error_m, drift_m = (float(v) for v in out.getvalue().split())
    return {"ins_largest_error_m": truth_error_m, "drift_km": drift_m / 1e3}


def step_api_example(data_root: Path) -> dict[str, Any]:
    """docs/how-to/step-api.md's example: the position error at the end of
    its 30 s outage without and with the wheel speed and non-holonomic
    constraint (m), and the largest vertical velocity in body axes of its
    trajectory (m/s), which sizes the constraint's std."""
    out = io.StringIO()
    namespace: dict[str, Any] = {"__name__": "__docs__"}
    with contextlib.redirect_stdout(out), tempfile.TemporaryDirectory() as tmp:
        with contextlib.chdir(tmp):
            exec(compile(_python_block("how-to/step-api.md"), "step-api.md", "exec"), namespace)
    printed = dict(re.findall(r"odometry (\w+): end of the outage ([\d.]+) m", out.getvalue()))
    truth = namespace["truth"]
    body = np.einsum("nji,nj->ni", truth.attitude, truth.velocity_ecef)
    return {
        "outage_end_error_m": float(printed["False"]),
        "outage_end_error_odometry_m": float(printed["True"]),
        "largest_vertical_body_velocity_m_s": float(np.abs(body[:, 2]).max()),
    }


def own_arrays_conditioning(data_root: Path) -> dict[str, Any]:
    """The condition number of the w axis of the accelerometer calibration
    in docs/how-to/your-own-arrays.md's first example."""
    namespace: dict[str, Any] = {}
    with warnings.catch_warnings(), contextlib.redirect_stdout(io.StringIO()):
        warnings.simplefilter("ignore")  # the warnings the page describes
        exec(compile(_python_block("how-to/your-own-arrays.md"), "howto.md", "exec"), namespace)
    return {"w_axis_condition_number": float(namespace["acc_cal"].condition_number[2])}


def _one_over_e_time_s(x: np.ndarray, rate_hz: float) -> float:
    """The first lag at which the sample autocorrelation of ``x`` (mean
    removed; FFT of the zero-padded series) falls below 1/e, s."""
    x = x - x.mean()
    spectrum = np.fft.rfft(x, 2 * len(x))
    acf = np.fft.irfft(spectrum * np.conj(spectrum))[: len(x)]
    return float(np.argmax(acf / acf[0] < 1.0 / np.e) / rate_hz)


def input_correlation_times(data_root: Path) -> dict[str, Any]:
    """On six 600 s random trajectories (seeds 0-5, 100 Hz), the time the
    yaw rate's and the horizontal specific force's autocorrelation take to
    fall to 1/e (decision 0008 chooses τ = 10 s from them)."""
    yaw, force = [], []
    for seed in range(6):
        truth = mn.Trajectory.random(duration=600.0, rate=100.0, seed=seed)
        yaw.append(_one_over_e_time_s(truth.angular_rate[:, 2], 100.0))
        force += [_one_over_e_time_s(truth.specific_force[:, k], 100.0) for k in (0, 1)]
    return {
        "yaw_rate_s": {"least": min(yaw), "most": max(yaw)},
        "horizontal_force_s": {"least": min(force), "most": max(force)},
    }


def tactical_three_satellites(data_root: Path) -> dict[str, Any]:
    """A tactical IMU 900 s on the 3 highest of 6 satellites from the exact
    start, seeds 1-8: final error and vertical σ, km; the share of errors
    inside 3σ."""
    import few_satellites_study

    runs = [few_satellites_study._long_run(3, seed, grade="tactical") for seed in range(1, 9)]
    final_km = [r["final_m"] / 1e3 for r in runs]
    sigma_km = [r["final_vertical_sigma_m"] / 1e3 for r in runs]
    return {
        "final_error_km": {"least": min(final_km), "most": max(final_km)},
        "final_vertical_sigma_km": {"least": min(sigma_km), "most": max(sigma_km)},
        "least_inside_percent": 100.0 * min(r["inside"] for r in runs),
    }


def _example(name: str, data_root: Path) -> RunConfig:
    config = mn.load_config(ROOT / "examples" / f"{name}.toml", data_root)
    config.values["report"]["html"] = False
    return config


def _navigate(config) -> Any:
    with warnings.catch_warnings(), tempfile.TemporaryDirectory() as out:
        warnings.simplefilter("ignore")  # the logs' cut lines
        return mn.navigate(config, output=out)


#: The IMU time offsets docs/explanation/time-and-truth.md compares, s.
IMU_OFFSETS_S = (-0.27, -0.22, -0.20, -0.125)

#: The velocity latencies it compares, s.
VELOCITY_LATENCIES_S = (0.0, 0.125, 0.132)


def drive_time_offsets(data_root: Path) -> dict[str, Any]:
    """drive_0708 without outages: the mean NIS per degree of freedom of
    its position fixes at four IMU offsets, and its aided error (cm) and
    position resets at three velocity latencies (one navigate each)."""
    base = _example("drive_0708", data_root)
    base.engine.pop("outages")
    nis = []
    for offset_s in IMU_OFFSETS_S:
        config = copy.deepcopy(base)
        config.engine["imu"]["time_offset_s"] = offset_s
        batches = _navigate(config).run.solution.batches
        position = np.asarray(batches["kind"]) == "position"
        per_dof = np.asarray(batches["nis"])[position] / np.asarray(batches["dof"])[position]
        nis.append(float(np.mean(per_dof)))
    aided_cm, resets = [], []
    for latency_s in VELOCITY_LATENCIES_S:
        config = copy.deepcopy(base)
        config.engine["gnss"]["velocity_latency_s"] = latency_s
        summary = _navigate(config).summary
        aided_cm.append(100.0 * summary["errors_vs_truth"]["aided"]["rms_horizontal_m"])
        resets.append([r["kind"] for r in summary["resets"]].count("position_to_fix"))
    return {
        "imu_offsets_s": list(IMU_OFFSETS_S),
        "position_nis_per_dof": nis,
        "velocity_latencies_s": list(VELOCITY_LATENCIES_S),
        "aided_rms_cm": aided_cm,
        "position_resets": resets,
    }


def example_consistency(data_root: Path) -> dict[str, Any]:
    """Each example log run as configured: the largest ratio of its
    time-averaged NIS to the band's edge, over every GNSS kind."""
    figures = {}
    for name in ("drive_0708", "walk_0827"):
        summary = _navigate(_example(name, data_root)).summary
        figures[name] = max(c["max_band_ratio"] for c in summary["integrity"]["consistency"])
    return {"largest_band_ratio": figures}


def walk_precision(data_root: Path) -> dict[str, Any]:
    """walk_0827 as configured, scored by precision (each solution less its
    own mean offset from the truth): the offset removed (horizontal, m),
    the filter's and the single-point solution's horizontal RMS, m."""
    summary = _navigate(_example("walk_0827", data_root)).summary
    precise = summary["errors_vs_truth_precision"]
    north, east, _ = precise["offset_removed_ned_m"]
    return {
        "truth_offset_m": float(np.hypot(north, east)),
        "forward_rms_horizontal_m": precise["aided"]["rms_horizontal_m"],
        "single_point_rms_horizontal_m": summary["spp_errors_vs_truth_precision"][
            "rms_horizontal_m"
        ],
    }


def two_satellite_runs(data_root: Path) -> dict[str, Any]:
    """The few-satellite study's eight 900 s consumer-IMU runs on 2
    satellites (seeds 1-8): how many stay inside 3σ until the first alert
    (the share rounding to 1.00, as the study's table prints it), the
    latest first alert, the NIS per dof over 60 s windows, and the
    latest-alerting run's tilt 20 s in with its σ, degrees."""
    import few_satellites_study

    runs = [few_satellites_study._long_run(2, seed) for seed in range(1, 9)]
    nis = [v for r in runs for v in r["nis_per_dof_60s"]]
    exception = max(runs, key=lambda r: r["first_alert_s"])
    return {
        "runs": len(runs),
        "inside_until_alert": sum(round(r["inside_before_alert"], 2) == 1.0 for r in runs),
        "latest_first_alert_s": max(r["first_alert_s"] for r in runs),
        "nis_per_dof_60s": {"least": min(nis), "most": max(nis)},
        "exception_tilt_deg": [abs(v) for v in exception["tilt_at_20s_deg"]],
        "exception_tilt_sigma_deg": list(exception["tilt_std_at_20s_deg"]),
    }


#: The IMUs of the paper comparison, in its tables' order.
PAPER_IMUS = ("ins", "mems", "calibrated_mems")


def study_defaults(data_root: Path) -> dict[str, Any]:
    """The outage study's default outage start (s) and the margin its runs
    last past the longest outage (s), from a one-run study's configuration."""
    lengths = [10.0, 30.0]
    study = mn.experiments.outage_study(
        grades=["consumer"], outage_lengths=lengths, visible_satellites=[0], runs=1, threads=1
    )
    start = study.config["outage_start"]
    return {"outage_start_s": start, "duration_margin_s": study.config["duration"] - start - 30.0}


def slac_rinex2_fixes(data_root: Path) -> dict[str, Any]:
    """GPS fixes of the SLAC CORS RINEX 2.11 excerpt (tests/data/rinex-public)
    with the IGS RINEX 2 navigation file of the day: the least and largest
    distance from the station's header position, m."""
    public = ROOT / "tests" / "data" / "rinex-public"
    obs = mn.read_rinex_obs(public / "slac1180_excerpt.21o")
    eph = mn.read_broadcast_nav(data_root / "gnss-products" / "2021-118" / "brdc1180.21n")
    fixes = mn.solve_fix(obs.measurements(eph, systems=["G"]))
    errors = np.linalg.norm(fixes.position_ecef - obs.approx_position_ecef, axis=1)
    return {"least_m": float(errors.min()), "most_m": float(errors.max()), "epochs": len(errors)}


def walk_ubx_fix(data_root: Path) -> dict[str, Any]:
    """The least-squares fixes on the walk's UBX log (its own GPS L1 C/A
    pseudoranges and LNAV ephemerides) against its NAV-PVT positions: the
    mean north and east offset and the horizontal scatter about it, m."""
    log = mn.read_ubx(data_root / "real-imu-gnss" / "walk_0827" / "gnss_1730.ubx")
    measurements = log.observations.gps_l1(log.constellation)
    fixes = mn.solve_fix(measurements)
    pvt = log.nav_pvt
    nearest = np.searchsorted(pvt["gps_time"], measurements.gps_time - 0.1)
    truth = mn.geodetic_to_ecef(pvt["lla"][nearest])
    valid = np.flatnonzero(fixes.valid)
    ned = np.array([mn.ecef_to_ned(fixes.position_ecef[k], truth[k]) for k in valid])
    offset = ned.mean(axis=0)
    scatter = np.sqrt(np.mean(np.sum((ned[:, :2] - offset[:2]) ** 2, axis=1)))
    return {
        "north_m": float(offset[0]),
        "east_m": float(offset[1]),
        "horizontal_scatter_m": float(scatter),
        "fixes": len(valid),
    }


def partial_outages(data_root: Path) -> dict[str, Any]:
    """The partial-outage experiment's quick run (30 runs, seed 0): per
    scenario and IMU the mean largest error in the window (m), the position
    NEES/dof at its end, the share of runs flagged; the shares of the
    no-satellite error kept with 3 and 2 satellites, %."""
    scenarios = mn.experiments.partial_outage(runs=30, seed=0).summary()["scenarios"]
    table = {
        scenario: {
            imu: {
                "largest_m": s["imus"][imu]["mean_max_position_error_during_outage_m"],
                "nees_per_dof": s["imus"][imu]["position_nees_per_dof_at_outage_end"],
                "diverged_share": s["imus"][imu]["diverged_share"],
            }
            for imu in PAPER_IMUS
        }
        for scenario, s in scenarios.items()
    }

    def kept(imu: str, n: int) -> float:
        return (
            100.0
            * table[f"tight, {n} satellites"][imu]["largest_m"]
            / table["tight, 0 satellites"][imu]["largest_m"]
        )

    nees = [cell["nees_per_dof"] for row in table.values() for cell in row.values()]
    two = [kept(imu, 2) for imu in PAPER_IMUS]
    return {
        "scenarios": table,
        "three_satellites_kept_percent": {imu: kept(imu, 3) for imu in PAPER_IMUS},
        "two_satellites_kept_percent": {"least": min(two), "most": max(two)},
        "nees_per_dof": {"least": min(nees), "most": max(nees)},
    }


def partial_outages_table(record: dict[str, Any]) -> str:
    """docs/results/paper-comparison.md's partial-outage table from its
    record, between its markers."""
    rows = [
        f"| {scenario} | "
        + " | ".join(
            f"{_three_figures(c['largest_m'])} ({c['nees_per_dof']:.2f})" for c in imus.values()
        )
        + " |"
        for scenario, imus in record["figures"]["scenarios"].items()
    ]
    header = "| scenario | ins | mems | calibrated_mems |\n|---|---|---|---|"
    return "\n".join([PARTIAL_OUTAGES[0], header, *rows, PARTIAL_OUTAGES[1]])


def _three_figures(value: float) -> str:
    """Three significant figures, no exponent: 105, 26.1, 8.9 (two below 10)."""
    return f"{value:.0f}" if value >= 100 else f"{value:.1f}"


#: The partial-outage table's markers.
PARTIAL_OUTAGES = ("<!-- partial-outages:begin -->", "<!-- partial-outages:end -->")


def quick_calibration(data_root: Path) -> dict[str, Any]:
    """The calibration experiment's quick run (``memsnav reproduce``: 50
    sets × 100 runs, seed 0): plain least squares' efficiency on the gyro p
    and q and the accelerometer u scale factors and the share of its MSE
    that is squared mean error (%); the misalignments' normalised RMS error
    (errors-in-variables)."""
    sizes = QUICK
    s = mn.experiments.calibration(
        parameter_sets=sizes.calibration_sets, runs=sizes.calibration_runs, seed=0
    ).summary()
    gyro_sf = s["gyroscope"]["scale_factor"]["per_axis"]
    accel_sf = s["accelerometer"]["scale_factor"]["per_axis"]
    shares = [100.0 * gyro_sf[a]["bias_share_ls"] for a in ("p", "q")]
    shares.append(100.0 * accel_sf["u"]["bias_share_ls"])
    return {
        "gyro_pq_efficiency_ls": [gyro_sf[a]["efficiency_ls"] for a in ("p", "q")],
        "accel_u_efficiency_ls": accel_sf["u"]["efficiency_ls"],
        "bias_share_percent": {"least": min(shares), "most": max(shares)},
        "gyro_misalignment_nrmse": s["gyroscope"]["misalignment"]["normalized_mse_eiv"] ** 0.5,
        "accel_misalignment_nrmse": s["accelerometer"]["misalignment"]["normalized_mse_eiv"] ** 0.5,
    }


def _outage_errors(config: RunConfig) -> dict[str, list[float]]:
    """drive_0708 through the published filter's 15 / 30 / 60 s outage
    windows (docs/real_data_benchmark.py): forward RMS, smoothed RMS and
    maximum, m, by length; the installation estimates when estimated."""
    import real_data_benchmark

    runs = real_data_benchmark.peer_window_runs(config)
    errors: dict[str, list] = {"forward_rms_m": [], "smoothed_rms_m": [], "smoothed_max_m": []}
    for summary, _ in runs.values():
        errors["forward_rms_m"].append(summary["errors_vs_truth"]["in_outages"]["rms_horizontal_m"])
        smoothed = summary["errors_vs_truth_smoothed"]["in_outages"]
        errors["smoothed_rms_m"].append(smoothed["rms_horizontal_m"])
        errors["smoothed_max_m"].append(smoothed["max_horizontal_m"])
        if "installation_estimates" in summary:
            estimates = summary["installation_estimates"]
            errors.setdefault("lever_arm_cm", []).append(
                [100.0 * abs(v) for v in estimates["lever_arm_m"]["value"]]
            )
            errors.setdefault("velocity_latency_s", []).append(
                estimates["velocity_latency_s"]["value"]
            )
            errors.setdefault("time_offset_s", []).append(estimates["time_offset_s"]["value"])
    return errors


def drive_other_settings(data_root: Path) -> dict[str, Any]:
    """drive_0708 through the published filter's outage windows with the
    example's settings and others (~15 s): the IMU offset at −0.125 s and
    −0.27 s instead of −0.22 s; `fix_error_states`; `installation_states`,
    its estimates, and its aided error without outages against the
    example's."""
    base = _example("drive_0708", data_root)
    figures: dict[str, Any] = {"example": _outage_errors(base)}
    for name, offset_s in (("offset_-0.125", -0.125), ("offset_-0.27", -0.27)):
        config = copy.deepcopy(base)
        config.engine["imu"]["time_offset_s"] = offset_s
        figures[name.replace("-0.", "m0_")] = _outage_errors(config)["forward_rms_m"]
    config = copy.deepcopy(base)
    config.engine["gnss"]["fix_error_states"] = True
    figures["fix_error_states"] = _outage_errors(config)
    config = copy.deepcopy(base)
    config.engine.setdefault("filter", {})["installation_states"] = True
    states = _outage_errors(config)
    change = np.abs(np.subtract(states["smoothed_rms_m"], figures["example"]["smoothed_rms_m"]))
    lever = [round(v) for run in states.pop("lever_arm_cm") for v in run]
    offsets = states.pop("time_offset_s")
    figures["installation_states"] = states | {
        "lever_arm_cm": {"least": min(lever), "most": max(lever)},
        "time_offset_s": {"least": min(offsets), "most": max(offsets)},
        "smoothed_rms_change_m": float(change.max()),
    }
    aided = []
    for states_on in (False, True):
        config = copy.deepcopy(base)
        config.engine.pop("outages")
        config.engine.setdefault("filter", {}).update(smoother=True, installation_states=states_on)
        aided.append(_navigate(config).summary["errors_vs_truth"]["aided"]["rms_horizontal_m"])
    figures["aided_rms_m"] = {"example": aided[0], "installation_states": aided[1]}
    return figures


def drive_example_schedule(data_root: Path) -> dict[str, Any]:
    """The outage schedule examples/drive_0708.toml sets, s (the README
    describes the example by it)."""
    import tomllib

    outages = tomllib.loads((ROOT / "examples" / "drive_0708.toml").read_text())["outages"]
    return {"length_s": outages["length_s"], "every_s": outages["every_s"]}


def static_start_spec(data_root: Path) -> dict[str, Any]:
    """drive_0708's first 34 s (at rest, engine running) through
    ``imu_spec_from_allan``: the white noise it determines (µg/√Hz, °/√h),
    the consumer preset's, and drive_0708 over the consumer preset with
    those two entries through the published filter's outage windows
    (forward RMS and largest error, m, share inside 3σ, smoothed RMS, m,
    by outage length in s)."""
    import real_data_benchmark

    from memsnav.realdata.pipeline import read_imu

    config = _example("drive_0708", data_root)
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")  # the log's cut lines; the terms left out
        _, f, w, _ = read_imu(config)
        spec = mn.imu_spec_from_allan(f[:3400], w[:3400], 100.0)
    consumer = mn.ImuModel.preset("consumer").spec
    preset = {
        "accel_noise_density_ug_sqrt_hz": consumer["accel_noise_density"] / 9.80665e-6,
        "gyro_arw_deg_sqrt_h": float(np.degrees(consumer["gyro_noise_density"]) * 60.0),
    }
    allan = copy.deepcopy(config)
    allan.engine["imu_spec"] = dict(spec)
    allan.engine.setdefault("filter", {})["imu_preset"] = "consumer"
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        runs = real_data_benchmark.peer_window_runs(allan)
    windows = {}
    for length, (summary, _) in runs.items():
        forward = summary["errors_vs_truth"]["in_outages"]
        smoothed = summary["errors_vs_truth_smoothed"]["in_outages"]
        windows[f"{length:g}"] = {
            "forward_rms_m": forward["rms_horizontal_m"],
            "forward_max_m": forward["max_horizontal_m"],
            "share": forward["within_3sigma_share"],
            "smoothed_rms_m": smoothed["rms_horizontal_m"],
        }
    return {
        "spec": {k: float(v) for k, v in spec.items()},
        "preset": preset,
        "ratio": {k: float(spec[k]) / preset[k] for k in preset},
        "windows": windows,
    }


def static_start_spec_table(record: dict[str, Any]) -> str:
    """docs/how-to/tune-for-your-imu.md's table: the preset's columns from
    docs/data/against_rtk.json (the benchmark), the Allan spec's from
    ``record``, between the markers."""
    bench = load_record("against_rtk")["figures"]["drive"]["lengths"]
    rows = []
    for length, allan in record["figures"]["windows"].items():
        b = bench[length]
        rows.append(
            f"| {length} s | {b['forward']['rms_m']:.2f} / {b['forward']['max_m']:.2f}, "
            f"{b['forward']['share']:.3f} | {allan['forward_rms_m']:.2f} / "
            f"{allan['forward_max_m']:.2f}, {allan['share']:.3f} | "
            f"{b['smoothed']['rms_m']:.2f} / {allan['smoothed_rms_m']:.2f} |"
        )
    header = (
        "| outage length | preset: forward RMS / max [m], share in 3σ "
        "| Allan spec: forward RMS / max [m], share in 3σ "
        "| smoothed RMS, preset / Allan [m] |\n|---|---|---|---|"
    )
    return "\n".join([STATIC_START_SPEC[0], header, *rows, STATIC_START_SPEC[1]])


#: The static-start spec table's markers.
STATIC_START_SPEC = ("<!-- static-start-spec:begin -->", "<!-- static-start-spec:end -->")


def xsens_session(data_root: Path) -> dict[str, Any]:
    """examples/xsens_static.toml run as shipped (every 4th pose held out):
    the figures of merit before and after, in the fit and held out
    (‖f‖ − g RMS in mm/s², the gravity direction after a turn in °); the
    estimated parameters' σ over their white-noise Cramér-Rao bound, least
    and most, per sensor; the accelerometer biases' σ, mm/s²."""
    from memsnav.calibration.session import run_calibration

    with warnings.catch_warnings(), tempfile.TemporaryDirectory() as out:
        warnings.simplefilter("ignore")
        cal = run_calibration(
            ROOT / "examples" / "xsens_static.toml", data_root=data_root, output=Path(out)
        ).calibration
    fit = mn.static_summary(cal)
    merit = {
        f"{key}_{stage}_{subset}": fit[f"{key}_rms_{stage}_{subset}_{unit}"] * scale
        for key, unit, scale in (("magnitude", "m_s2", 1e3), ("turn", "deg", 1.0))
        for stage in ("before", "after")
        for subset in ("fit", "held_out")
    }
    sigma = np.sqrt(np.diag(np.asarray(cal.covariance)))
    bound = np.sqrt(np.diag(np.asarray(cal.crb)))
    estimated = sigma > 0
    ratio = sigma[estimated] / bound[estimated]
    n_accel = int(estimated[:15].sum())
    bias_mm_s2 = 1e3 * np.asarray(cal.accelerometer_std.bias)
    return {
        "merit": merit,
        "sigma_over_bound": {
            sensor: {"least": float(r.min()), "most": float(r.max())}
            for sensor, r in (("accelerometer", ratio[:n_accel]), ("gyroscope", ratio[n_accel:]))
        },
        "accel_bias_sigma_mm_s2": {
            "least": float(bias_mm_s2.min()),
            "most": float(bias_mm_s2.max()),
        },
    }


#: The Xsens session's gravity (given with the data, m/s²) and the nominal
#: scales and offsets docs/how-to/calibrate-an-imu.md starts from.
XSENS_GRAVITY = 9.81744
XSENS_NOMINAL = {
    "accel_scale": XSENS_GRAVITY / 3724.0,
    "accel_offset": 32768.0,
    "gyro_scale": 1 / 6258,
    "gyro_offset": 32768.0,
}


def xsens_parameters(data_root: Path) -> dict[str, Any]:
    """The Xsens session calibrated from the data source's nominal values
    (every 4th pose held out, the terms the data determine): each sensor's
    bias, scale factor and misalignment with their σ, SI, and the fitted
    gyro scales, rad/s per count."""
    data = data_root / "imu-static-poses"
    accel = np.loadtxt(data / "xsens_acc.mat")
    gyro = np.loadtxt(data / "xsens_gyro.mat")
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")  # the gyro's nominal scale is 31 % off
        cal = mn.calibrate_static(
            accel[:, 0],
            accel[:, 1:],
            gyro[:, 1:],
            gravity=XSENS_GRAVITY,
            estimate="determinable",
            holdout_every=4,
            **XSENS_NOMINAL,
        )
    figures: dict[str, Any] = {}
    for sensor, model, std in (
        ("accelerometer", cal.accelerometer, cal.accelerometer_std),
        ("gyroscope", cal.gyroscope, cal.gyroscope_std),
    ):
        figures[sensor] = {
            f"{term}{suffix}": np.asarray(getattr(of, term)).tolist()
            for term in ("bias", "scale_factor", "misalignment")
            for suffix, of in (("", model), ("_sigma", std))
        }
    scale = np.asarray(cal.nominal["gyro_scale"]) / (1 - np.asarray(cal.gyroscope.scale_factor))
    figures["fitted_gyro_scale"] = scale.tolist()
    return figures


def plain_model(x: np.ndarray, counts: np.ndarray) -> np.ndarray:
    """imu_tk's a = T K (counts - b) (Tedaldi et al. 2014 eq. 10-12): T
    unit upper triangular (three non-orthogonality angles), K diagonal
    scales per count, b offsets; the plain 9-parameter fit's model."""
    t = np.array([[1.0, -x[6], x[7]], [0.0, 1.0, -x[8]], [0.0, 0.0, 1.0]])
    return (counts - x[:3]) @ (t @ np.diag(x[3:6])).T


def plain_fit(counts: np.ndarray) -> np.ndarray:
    """The 9 parameters minimising sum (|a_k| - g)^2 over pose means in
    counts (scipy, independent of memsnav)."""
    from scipy.optimize import least_squares

    start = np.r_[np.full(3, 32768.0), np.full(3, XSENS_GRAVITY / 3724.0), np.zeros(3)]
    scale = np.r_[np.full(3, 100.0), np.full(3, 1e-5), np.full(3, 1e-2)]
    result = least_squares(
        lambda x: np.linalg.norm(plain_model(x, counts), axis=1) - XSENS_GRAVITY,
        start,
        x_scale=scale,
        xtol=1e-15,
        ftol=1e-15,
        gtol=1e-15,
    )
    if not result.success:
        raise RuntimeError(f"the plain fit did not converge: {result.message}")
    return result.x


def xsens_splits(data_root: Path) -> dict[str, Any]:
    """docs/how-to/calibrate-an-imu.md's table of the two splits (every 4th
    pose held out; the first half fitted, the second held out): memsnav
    with every term estimated ("before"), with the terms the data
    determine ("now") and the plain 9-parameter fit on the same pose means:
    ‖f‖ − g RMS in the fit, held out and (halves) over the held-out poses
    that start after the middle, mm/s²; memsnav's gravity direction after
    the held-out turns, °; the counts of poses and turns."""
    data = data_root / "imu-static-poses"
    accel = np.loadtxt(data / "xsens_acc.mat")
    gyro = np.loadtxt(data / "xsens_gyro.mat")
    t = accel[:, 0]
    figures: dict[str, Any] = {}
    for split, holdout in (
        ("every_4th", {"holdout_every": 4}),
        ("halves", {"holdout_from": (t[0] + t[-1]) / 2}),
    ):
        row: dict[str, Any] = {}
        for label, estimate in (("before", "all"), ("now", "determinable")):
            with warnings.catch_warnings():
                warnings.simplefilter("ignore")  # the gyro's nominal scale is 31 % off
                cal = mn.calibrate_static(
                    t,
                    accel[:, 1:],
                    gyro[:, 1:],
                    gravity=XSENS_GRAVITY,
                    estimate=estimate,
                    **XSENS_NOMINAL,
                    **holdout,
                )
            summary = mn.static_summary(cal)
            held = np.asarray(cal.pose_held_out)
            after = np.asarray(cal.magnitude_error_after)
            late = t[np.asarray(cal.poses)[:, 0]] > (t[0] + t[-1]) / 2
            row[label] = {
                "fit_mm_s2": 1e3 * summary["magnitude_rms_after_fit_m_s2"],
                "held_out_mm_s2": 1e3 * summary["magnitude_rms_after_held_out_m_s2"],
                "after_middle_mm_s2": 1e3 * float(np.sqrt(np.mean(after[held & late] ** 2))),
                "turns_deg": summary["turn_rms_after_held_out_deg"],
            }
        means = np.array([accel[a:b, 1:].mean(axis=0) for a, b in cal.poses])
        errors = np.linalg.norm(plain_model(plain_fit(means[~held]), means), axis=1)
        errors -= XSENS_GRAVITY
        row["plain"] = {
            "fit_mm_s2": 1e3 * float(np.sqrt(np.mean(errors[~held] ** 2))),
            "held_out_mm_s2": 1e3 * float(np.sqrt(np.mean(errors[held] ** 2))),
            "after_middle_mm_s2": 1e3 * float(np.sqrt(np.mean(errors[held & late] ** 2))),
        }
        row["poses"] = {
            "fit": int((~held).sum()),
            "held_out": int(held.sum()),
            "after_middle": int((held & late).sum()),
        }
        figures[split] = row
    return figures


def _xsens_calibration(data_root: Path, estimate: str, **holdout: float) -> Any:
    """The Xsens session calibrated from the data source's nominal values."""
    data = data_root / "imu-static-poses"
    accel = np.loadtxt(data / "xsens_acc.mat")
    gyro = np.loadtxt(data / "xsens_gyro.mat")
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")  # the gyro's nominal scale is 31 % off
        cal = mn.calibrate_static(
            accel[:, 0],
            accel[:, 1:],
            gyro[:, 1:],
            gravity=XSENS_GRAVITY,
            estimate=estimate,
            **XSENS_NOMINAL,
            **holdout,
        )
    return cal, accel, gyro


def xsens_nonlinearity(data_root: Path) -> dict[str, Any]:
    """docs/how-to/calibrate-an-imu.md, "Why memsnav lost on unseen poses":
    the plain fit on all 38 poses (mm/s²); the accelerometer nonlinearity
    N's largest σ with every term estimated (per m/s²) on each split and
    how many times below 1e-3 its smallest (every 4th pose) and largest
    (halves) are; the first
    half's in-fit RMS without N and with it; the held-out pose where N
    extrapolates worst on the halves (its index, its specific force's
    direction after the calibration, its miss with N and without, mm/s²);
    what N costs held out on each split (RMS with N less without, mm/s²)."""
    _, accel, gyro = _xsens_calibration(data_root, "determinable")
    t = accel[:, 0]

    def rms(errors: np.ndarray) -> float:
        return float(np.sqrt(np.mean(np.square(errors))))

    figures: dict[str, Any] = {"n_sigma_most": {}, "times_below_1e3": {}, "n_cost_mm_s2": {}}
    for split, holdout in (
        ("every_4th", {"holdout_every": 4}),
        ("halves", {"holdout_from": (t[0] + t[-1]) / 2}),
    ):
        now = _xsens_calibration(data_root, "determinable", **holdout)[0]
        before = _xsens_calibration(data_root, "all", **holdout)[0]
        held = np.asarray(now.pose_held_out)
        after_now = np.asarray(now.magnitude_error_after)
        after_before = np.asarray(before.magnitude_error_after)
        sigma = np.asarray(before.accelerometer_std.nonlinearity)
        figures["n_sigma_most"][split] = float(sigma.max())
        if split == "halves":
            figures["times_below_1e3"]["least"] = float(1e-3 / sigma.max())
        figures["n_cost_mm_s2"][split] = 1e3 * (rms(after_before[held]) - rms(after_now[held]))
        if split == "halves":
            figures["first_half_fit_mm_s2"] = {
                "without_n": 1e3 * rms(after_now[~held]),
                "with_n": 1e3 * rms(after_before[~held]),
            }
            k = int(np.argmax(np.where(held, np.abs(after_before) - np.abs(after_now), -np.inf)))
            f, _ = now.correct(accel[:, 1:], gyro[:, 1:])
            a, b = now.poses[k]
            mean = f[a:b].mean(axis=0)
            figures["worst_pose"] = {
                "index": k,
                "direction": (mean / np.linalg.norm(mean)).tolist(),
                "missed_with_n_mm_s2": 1e3 * abs(float(after_before[k])),
                "missed_without_n_mm_s2": 1e3 * abs(float(after_now[k])),
            }
    every_4th = _xsens_calibration(data_root, "all", holdout_every=4)[0]
    figures["times_below_1e3"]["most"] = float(
        1e-3 / np.asarray(every_4th.accelerometer_std.nonlinearity).min()
    )
    cal = _xsens_calibration(data_root, "determinable")[0]
    means = np.array([accel[a:b, 1:].mean(axis=0) for a, b in cal.poses])
    errors = np.linalg.norm(plain_model(plain_fit(means), means), axis=1) - XSENS_GRAVITY
    figures["all_poses_plain_mm_s2"] = 1e3 * rms(errors)
    return figures


def nonlinear_errors(theta: np.ndarray, nominal: np.ndarray, axes: list[int]) -> np.ndarray:
    """‖Γ_k‖ − g in memsnav's parametrisation (docs/explanation/calibration.md,
    "The model and the fit"), written out: x = L s + b with L lower
    triangular, then Γ_i = 2x_i / (1 + √(1 − 4 N_i x_i)) on the nonlinear
    ``axes``; theta = [b (3), L's diagonal − 1 (3), L_vu, L_wu, L_wv, N on
    axes]."""
    lower = np.array(
        [
            [1 + theta[3], 0.0, 0.0],
            [theta[6], 1 + theta[4], 0.0],
            [theta[7], theta[8], 1 + theta[5]],
        ]
    )
    x = nominal @ lower.T + theta[:3]
    for n, axis in zip(theta[9:], axes, strict=True):
        x[:, axis] = 2 * x[:, axis] / (1 + np.sqrt(1 - 4 * n * x[:, axis]))
    return np.linalg.norm(x, axis=1) - XSENS_GRAVITY


def nonlinear_fit(nominal: np.ndarray, axes: list[int]) -> np.ndarray:
    """theta minimising Σ(‖Γ_k‖ − g)² (scipy, independent of memsnav)."""
    from scipy.optimize import least_squares

    scale = np.r_[np.full(3, 1e-2), np.full(6, 1e-3), np.full(len(axes), 1e-5)]
    result = least_squares(
        lambda theta: nonlinear_errors(theta, nominal, axes),
        np.zeros(9 + len(axes)),
        x_scale=scale,
        xtol=1e-15,
        ftol=1e-15,
        gtol=1e-15,
    )
    if not result.success:
        raise RuntimeError(f"the nonlinear fit did not converge: {result.message}")
    return result.x


def _candidates(cal: Any, stage: str) -> tuple[list[dict], int]:
    (selection,) = [m for m in cal.model_selection if m["stage"] == stage]
    return selection["candidates"], selection["chosen"]


def xsens_criteria(data_root: Path) -> dict[str, Any]:
    """docs/how-to/calibrate-an-imu.md's information criteria on the Xsens
    log (every 4th pose held out, the halves, all 38 poses): AICc's margin
    for the linear model against the best candidate with an entry of N, by
    pose set; the least margin by which it keeps all of K; plain AIC's gap
    from the linear model to N_v and BIC's margin for the linear model
    (least, most over the pose sets); leave-one-out RMS over the first
    half's poses with N_v and without and N_v's RMS on the second half
    (scipy fits in memsnav's parametrisation), mm/s²."""
    _, accel, _ = _xsens_calibration(data_root, "determinable")
    t = accel[:, 0]
    sets = {
        "every_4th": {"holdout_every": 4},
        "halves": {"holdout_from": (t[0] + t[-1]) / 2},
        "all": {},
    }
    cals = {name: _xsens_calibration(data_root, "determinable", **h)[0] for name, h in sets.items()}
    n_margin, k_margins, aic_gaps, bic_margins = {}, [], [], []
    for name, cal in cals.items():
        candidates, _ = _candidates(cal, "accelerometer nonlinearity")
        with_n = min(c["aicc"] for c in candidates[1:] if c["aicc"] is not None)
        n_margin[name] = with_n - candidates[0]["aicc"]
        gyro, chosen = _candidates(cal, "gyroscope g-sensitivity")
        k_margins.append(
            min(c["aicc"] for i, c in enumerate(gyro) if i != chosen and c["aicc"] is not None)
            - gyro[chosen]["aicc"]
        )
        criteria = []
        for c in candidates:
            n, k = c["observations"], c["parameters"] + 1
            fit = n * np.log(c["residual_rms"] ** 2)
            criteria.append((c["terms"], fit + 2 * k, fit + k * np.log(n)))
        aic_v = next(a for terms, a, _ in criteria if terms == ["nonlinearity_v"])
        aic_gaps.append(aic_v - criteria[0][1])
        bic_margins.append(min(b for _, _, b in criteria[1:]) - criteria[0][2])
    halves = cals["halves"]
    held = np.asarray(halves.pose_held_out)
    means = np.array([accel[a:b, 1:].mean(axis=0) for a, b in halves.poses])
    nominal = XSENS_NOMINAL["accel_scale"] * (means - XSENS_NOMINAL["accel_offset"])
    in_fit = nominal[~held]

    def rms(errors: np.ndarray) -> float:
        return float(np.sqrt(np.mean(np.square(errors))))

    loo = {}
    for terms in ((), ("nonlinearity_v",)):
        axes = ["uvw".index(term[-1]) for term in terms]
        left_out = [
            nonlinear_errors(nonlinear_fit(np.delete(in_fit, k, 0), axes), in_fit[[k]], axes)
            for k in range(len(in_fit))
        ]
        loo["nonlinearity_v" if terms else "linear"] = 1e3 * rms(np.concatenate(left_out))
    theta = nonlinear_fit(in_fit, [1])
    return {
        "aicc_n_margin": n_margin,
        "aicc_k_margin_least": float(min(k_margins)),
        "aic_nv_gap": {"least": float(min(aic_gaps)), "most": float(max(aic_gaps))},
        "bic_margin": {"least": float(min(bic_margins)), "most": float(max(bic_margins))},
        "loo_mm_s2": loo,
        "first_half_poses": len(in_fit),
        "nv_second_half_mm_s2": 1e3 * rms(nonlinear_errors(theta, nominal[held], [1])),
    }


def plain_jacobian(x: np.ndarray, counts: np.ndarray) -> np.ndarray:
    """∂(‖a_k‖ − g)/∂x of the plain model by central differences (steps
    1e-6 of each parameter's size: the model is smooth and the columns span
    1e-5 to 3e4 in size)."""
    size = np.r_[np.full(3, 100.0), np.full(3, 1e-5), np.full(3, 1e-2)]
    columns = []
    for i, step in enumerate(1e-6 * size):
        up, down = x.copy(), x.copy()
        up[i] += step
        down[i] -= step
        difference = np.linalg.norm(plain_model(up, counts), axis=1) - np.linalg.norm(
            plain_model(down, counts), axis=1
        )
        columns.append(difference / (2 * step))
    return np.column_stack(columns)


#: The second half's pose N extrapolates worst (xsens_nonlinearity's
#: worst_pose), numbered from the rest (pose 0).
XSENS_WORST_POSE = 26
#: The detector factors docs/how-to/calibrate-an-imu.md and
#: docs/explanation/calibration.md try, first and last.
XSENS_DETECTOR_FACTORS = (4, 10)
#: The later splits it tries: the first poses fitted, fewest and most.
XSENS_LATER_SPLITS = (19, 23)


def xsens_second_half(data_root: Path) -> dict[str, Any]:
    """docs/how-to/calibrate-an-imu.md, "What is left": the plain fit's
    held-out RMS when the split moves later (first and last of
    XSENS_LATER_SPLITS); the z-up poses' scatter about the all-pose plain
    fit and the standard deviation of the rest's 1 s means (their
    magnitude error under that fit); σ̂ = √(RSS/(n − 9)) of the first-half
    and all-pose plain fits; the first-half fit's predicted RMS on the
    second half's poses by its covariance σ̂² (JᵀJ)⁻¹, and at
    XSENS_WORST_POSE (its std, the part from the parameters, its miss in
    σ); memsnav's held-out RMS on the halves for the detector factors of
    XSENS_DETECTOR_FACTORS (least, most). All mm/s² but the miss."""
    accel = np.loadtxt(data_root / "imu-static-poses" / "xsens_acc.mat")
    t, counts = accel[:, 0], accel[:, 1:]
    middle = (t[0] + t[-1]) / 2
    now = _xsens_calibration(data_root, "determinable", holdout_from=middle)[0]
    held = np.asarray(now.pose_held_out)
    means = np.array([counts[a:b].mean(axis=0) for a, b in now.poses])

    def rms(errors: np.ndarray) -> float:
        return float(np.sqrt(np.mean(np.square(errors))))

    def errors_of(x: np.ndarray, c: np.ndarray) -> np.ndarray:
        return np.linalg.norm(plain_model(x, c), axis=1) - XSENS_GRAVITY

    fewest, most = XSENS_LATER_SPLITS
    later = [1e3 * rms(errors_of(plain_fit(means[:m]), means[m:])) for m in (fewest, most)]
    x_all = plain_fit(means)
    all_errors = errors_of(x_all, means)
    z_up = plain_model(x_all, means)[:, 2] / XSENS_GRAVITY > 0.9
    a, b = now.poses[0]
    rate = round(1.0 / np.median(np.diff(t)))
    seconds = counts[a : a + (b - a) // rate * rate].reshape(-1, rate, 3).mean(axis=1)
    x = plain_fit(means[~held])
    errors = errors_of(x, means)
    n = int(np.sum(~held))
    residual_std = float(np.sqrt(np.sum(errors[~held] ** 2) / (n - 9)))
    jacobian = plain_jacobian(x, means[~held])
    covariance = residual_std**2 * np.linalg.inv(jacobian.T @ jacobian)
    ahead = plain_jacobian(x, means)
    from_parameters = np.einsum("ij,jk,ik->i", ahead, covariance, ahead)
    sd = np.sqrt(residual_std**2 + from_parameters)
    k = XSENS_WORST_POSE
    first, last = XSENS_DETECTOR_FACTORS
    detector = []
    for factor in range(first, last + 1):
        cal = _xsens_calibration(
            data_root, "determinable", holdout_from=middle, threshold_factor=factor
        )[0]
        detector.append(1e3 * mn.static_summary(cal)["magnitude_rms_after_held_out_m_s2"])
    return {
        "later_split_mm_s2": {"fewest_poses": later[0], "most_poses": later[1]},
        "later_split_poses": {"fewest": fewest, "most": most},
        "z_up_poses": int(z_up.sum()),
        "z_up_scatter_mm_s2": {
            "least": 1e3 * float(all_errors[z_up].min()),
            "most": 1e3 * float(all_errors[z_up].max()),
        },
        "rest_s": round((b - a) / rate),
        "rest_spread_mm_s2": 1e3 * float(np.std(errors_of(x_all, seconds), ddof=1)),
        "residual_std_mm_s2": {
            "first_half": 1e3 * residual_std,
            "all_poses": 1e3 * float(np.sqrt(np.sum(all_errors**2) / (len(means) - 9))),
        },
        "predicted_mm_s2": 1e3 * rms(sd[held]),
        "worst_pose": {
            "index": k,
            "predicted_mm_s2": 1e3 * float(sd[k]),
            "from_parameters_mm_s2": 1e3 * float(np.sqrt(from_parameters[k])),
            "missed_sigmas": float(abs(errors[k]) / sd[k]),
        },
        "detector_factors": {"first": first, "last": last},
        "detector_held_out_mm_s2": {"least": min(detector), "most": max(detector)},
    }


#: The detector factor docs/explanation/calibration.md shows too low, and
#: memsnav's default it compares factors with.
XSENS_LOW_FACTOR, XSENS_DEFAULT_FACTOR = 3, 6.0


def xsens_detector(data_root: Path) -> dict[str, Any]:
    """docs/explanation/calibration.md, "The detector", every 4th pose held
    out: what XSENS_LOW_FACTOR does (poses found, in-fit and held-out
    ‖f‖ − g RMS, the held-out one with every term estimated, mm/s²), and the
    largest departure of the factors of XSENS_DETECTOR_FACTORS from the
    default's figures (in-fit and held-out magnitude, mm/s²; held-out
    turns, °)."""

    def summary(factor: float, estimate: str = "determinable") -> dict[str, Any]:
        cal = _xsens_calibration(data_root, estimate, holdout_every=4, threshold_factor=factor)[0]
        return {"poses": len(cal.poses), **mn.static_summary(cal)}

    low = summary(XSENS_LOW_FACTOR)
    estimated = summary(XSENS_LOW_FACTOR, "all")
    default = summary(XSENS_DEFAULT_FACTOR)
    first, last = XSENS_DETECTOR_FACTORS
    magnitude, turn = 0.0, 0.0
    for factor in range(first, last + 1):
        s = summary(factor)
        for key in ("magnitude_rms_after_fit_m_s2", "magnitude_rms_after_held_out_m_s2"):
            magnitude = max(magnitude, 1e3 * abs(s[key] - default[key]))
        key = "turn_rms_after_held_out_deg"
        turn = max(turn, abs(s[key] - default[key]))
    return {
        "low_factor": XSENS_LOW_FACTOR,
        "low_poses": low["poses"],
        "low_fit_mm_s2": 1e3 * low["magnitude_rms_after_fit_m_s2"],
        "low_held_out_mm_s2": 1e3 * low["magnitude_rms_after_held_out_m_s2"],
        "low_held_out_all_terms_mm_s2": 1e3 * estimated["magnitude_rms_after_held_out_m_s2"],
        "largest_departure": {"magnitude_mm_s2": magnitude, "turn_deg": turn},
    }


def somigliana_departure(data_root: Path) -> dict[str, Any]:
    """How far ``gravity_ecef`` (J2) departs from WGS84 normal gravity
    (Somigliana's closed form, NIMA TR8350.2 eq. 4-1, table 3.4) on the
    ellipsoid, m/s²: the largest departure (at a pole) and the one at the
    equator."""
    lat = np.radians(np.linspace(-90.0, 90.0, 181))
    lla = np.stack([lat, np.zeros_like(lat), np.zeros_like(lat)], axis=1)
    g = np.linalg.norm(mn.gravity_ecef(mn.geodetic_to_ecef(lla)), axis=1)
    s2 = np.sin(lat) ** 2
    normal = 9.7803253359 * (1 + 0.00193185265241 * s2) / np.sqrt(1 - 0.00669437999013 * s2)
    departure = np.abs(g - normal)
    return {"largest_m_s2": float(departure.max()), "equator_m_s2": float(departure[90])}


def fading_run(seed: int, fading_factor: float) -> tuple[dict[str, Any], list[str], list[Any]]:
    """A tactical tuning on a simulated consumer IMU (0.15 m/s² and 0.5 °/s
    biases) over 400 s with two 30 s outages, with `fading_factor` as
    `reset_fading_factor` (1: no fading): the score against the truth at
    the fixes, the kinds of its resets, and the warnings it gave."""
    trajectory = mn.Trajectory.random(400.0, seed=seed, stationary_start=20.0)
    t = trajectory.time
    rng = np.random.default_rng(seed)
    f = (
        trajectory.specific_force
        + 0.02 * rng.normal(size=(len(t), 3))
        + 0.15 * rng.choice([-1.0, 1.0], 3)
    )
    w = (
        trajectory.angular_rate
        + np.radians(0.05) * rng.normal(size=(len(t), 3))
        + np.radians(0.5) * rng.choice([-1.0, 1.0], 3)
    )
    k = np.arange(0, len(t), 25)
    fixes = mn.fixes_from_solution(
        t[k],
        trajectory.position_geodetic()[k],
        np.full((len(k), 3), 0.05),
        velocity_ned=trajectory.velocity_ned()[k],
        velocity_std_ned=np.full((len(k), 3), 0.05),
        added_position_noise_ned=[0.05] * 3,
        added_velocity_noise=0.05,
        seed=seed,
    )
    settings = {
        # A vibration-free simulated IMU: no standstill detection.
        "aids": {"zupt": False, "zaru": False, "nhc": True},
        "filter": {"imu_preset": "tactical", "reset_fading_factor": fading_factor},
        "outages": {"windows_s": [[150.0, 30.0], [300.0, 30.0]]},
    }
    with warnings.catch_warnings(record=True) as caught:
        warnings.simplefilter("always")
        run = mn.navigate_log(t, f, w, fixes, settings=settings)
    kinds = [str(kind) for kind in run.solution.resets["kind"]]
    return run.score(t[k], trajectory.position_ecef[k]), kinds, caught


def simulated_fading_figures(
    stuck: dict[str, Any], stuck_resets: list[str], faded: dict[str, Any]
) -> dict[str, Any]:
    """The figures the configuration reference quotes of one seed's pair
    of :func:`fading_run` runs (without fading, with it)."""
    return {
        "stuck_resets": len(stuck_resets),
        "stuck_outage_rms_km": stuck["in_outages"]["rms_horizontal_m"] / 1e3,
        "faded_aided_rms_m": faded["aided"]["rms_horizontal_m"],
        "faded_outage_rms_m": faded["in_outages"]["rms_horizontal_m"],
        "faded_outage_max_m": faded["in_outages"]["max_horizontal_m"],
    }


def simulated_fading(data_root: Path) -> dict[str, Any]:
    """:func:`fading_run` without and with fading (factor 10) for seeds 1
    and 2: each seed's figures, and their range as the page shows it."""
    seeds = {}
    for seed in (1, 2):
        faded, _, _ = fading_run(seed, 10.0)
        stuck, stuck_resets, _ = fading_run(seed, 1.0)
        seeds[str(seed)] = simulated_fading_figures(stuck, stuck_resets, faded)
    out: dict[str, Any] = {"seeds": seeds}
    for key in ("stuck_resets", "stuck_outage_rms_km", "faded_outage_rms_m"):
        out[f"{key}_low"] = min(s[key] for s in seeds.values())
        out[f"{key}_high"] = max(s[key] for s in seeds.values())
    for key in ("faded_aided_rms_m", "faded_outage_max_m"):
        out[f"{key}_high"] = max(s[key] for s in seeds.values())
    return out


#: Earth's equatorial radius, m: turns the simulated fixes' metre errors
#: into latitude and longitude.
EARTH_RADIUS_M = 6378137.0


def drive_with_slow_fix_errors(seed: int, tau_s: float = 60.0, slow_m: float = 1.0):
    """A 600 s drive, a MEMS-grade IMU, 1 Hz fixes whose N/E/D errors are a
    Gauss-Markov process (``slow_m``, ``tau_s``) plus 0.3 m white noise,
    reported with their total σ (as a receiver reports its fixes)."""
    trajectory = mn.Trajectory.random(600.0, seed=seed, stationary_start=20.0)
    t = trajectory.time
    rng = np.random.default_rng(seed)
    f = trajectory.specific_force + 0.02 * rng.normal(size=(len(t), 3)) + 0.05 * rng.normal(size=3)
    w = (
        trajectory.angular_rate
        + np.radians(0.1) * rng.normal(size=(len(t), 3))
        + np.radians(0.2) * rng.normal(size=3)
    )
    k = np.arange(0, len(t), 100)
    phi = np.exp(-1.0 / tau_s)
    error = np.zeros((len(k), 3))
    error[0] = slow_m * rng.normal(size=3)
    for i in range(1, len(k)):
        error[i] = phi * error[i - 1] + slow_m * np.sqrt(1 - phi**2) * rng.normal(size=3)
    error += 0.3 * rng.normal(size=(len(k), 3))
    lla = trajectory.position_geodetic()[k].copy()
    # North, east, down metres to latitude, longitude, height (the sphere's
    # radius: a 0.3 % scale error of a metre-level error).
    lla[:, 0] += error[:, 0] / EARTH_RADIUS_M
    lla[:, 1] += error[:, 1] / (EARTH_RADIUS_M * np.cos(lla[:, 0]))
    lla[:, 2] -= error[:, 2]
    fixes = mn.fixes_from_solution(
        t[k],
        lla,
        np.full((len(k), 3), np.hypot(slow_m, 0.3)),
        velocity_ned=trajectory.velocity_ned()[k],
        velocity_std_ned=np.full((len(k), 3), 0.1),
        added_velocity_noise=0.1,
        seed=seed,
    )
    return trajectory, f, w, fixes, k


def fix_error_runs(seed: int) -> tuple[dict[bool, Any], dict[bool, Any], dict[bool, float]]:
    """:func:`drive_with_slow_fix_errors` navigated without and with
    ``[gnss] fix_error_states`` (keys False, True): per run the aided
    share within 3σ with the outage's scores, the run, and the aided
    horizontal RMS, m."""
    trajectory, f, w, fixes, k = drive_with_slow_fix_errors(seed)
    share, run, rms = {}, {}, {}
    for states in (False, True):
        settings = {
            # A vibration-free simulated IMU: no standstill detection.
            "aids": {"zupt": False, "zaru": False, "nhc": True},
            # Without the states, the fixes as white noise (not the
            # correlation learnt from the log: tests/test_adaptation.py).
            "gnss": {"fix_error_states": states},
            "outages": {"windows_s": [[200.0, 30.0]]},
        }
        run[states] = mn.navigate_log(trajectory.time, f, w, fixes, settings=settings)
        score = run[states].score(trajectory.time[k], trajectory.position_ecef[k])
        share[states] = (score["aided"]["within_3sigma_share"], score["in_outages"])
        rms[states] = score["aided"]["rms_horizontal_m"]
    return share, run, rms


def fix_error_figures(share: dict[bool, Any], rms: dict[bool, float]) -> dict[str, float]:
    """The figures the configuration reference quotes of one seed's
    :func:`fix_error_runs`."""
    return {
        "white_share": share[False][0],
        "states_share": share[True][0],
        "white_rms_m": rms[False],
        "states_rms_m": rms[True],
    }


def fix_error_states(data_root: Path) -> dict[str, Any]:
    """:func:`fix_error_runs` for seeds 1 and 2: each seed's figures and
    their ranges."""
    seeds = {}
    for seed in (1, 2):
        share, _, rms = fix_error_runs(seed)
        seeds[str(seed)] = fix_error_figures(share, rms)
    out: dict[str, Any] = {"seeds": seeds}
    for key in seeds["1"]:
        out[f"{key}_low"] = min(s[key] for s in seeds.values())
        out[f"{key}_high"] = max(s[key] for s in seeds.values())
    return out


#: The arrays of simulated GNSS measurements a filter takes by name.
GNSS_ARRAY_KEYS = (
    "time",
    "sat_id",
    "satellite_position_ecef",
    "satellite_velocity_ecef",
    "pseudorange",
    "pseudorange_std",
    "pseudorange_rate",
    "pseudorange_rate_std",
)


def simulated_drive_300s() -> tuple[Any, Any, Any, np.ndarray, np.ndarray]:
    """A 300 s random drive, its simulated GNSS (Walker constellation), an
    IMU with random biases and white noise only (the 17 error states model
    it exactly) and its readings: (trajectory, gnss, imu, f, w). The tests'
    `drive_300s` fixture."""
    traj = mn.Trajectory.random(duration=300.0, seed=3)
    sky = mn.Constellation.walker()
    gnss = mn.simulate_gnss(traj.time, traj.position_ecef, traj.velocity_ecef, sky, seed=4)
    rng = np.random.default_rng(5)
    z3, z33 = np.zeros(3), np.zeros((3, 3))
    acc = mn.AccelerometerModel(rng.normal(0, 0.03, 3), z3, z33, z3, noise_density=2e-3)
    gyr = mn.GyroscopeModel(rng.normal(0, 2e-4, 3), z3, z33, z33, noise_density=2e-4)
    imu = mn.ImuModel(acc, gyr)
    f, w = imu.measure(traj.specific_force, traj.angular_rate, seed=6)
    return traj, gnss, imu, f, w


def pseudorange_rates_value(data_root: Path) -> dict[str, Any]:
    """On :func:`simulated_drive_300s`, the tight filter's position RMS, m,
    with the pseudorange rates and without them (what leaving the rates out
    costs)."""
    traj, g, imu, f, w = simulated_drive_300s()
    arrays = {k: getattr(g, k) for k in GNSS_ARRAY_KEYS}

    def rms(gnss: dict[str, Any]) -> float:
        sol = mn.TightlyCoupledFilter(imu).run(
            traj.time, f, w, gnss, initial_attitude=traj.attitude[0]
        )
        return float(np.sqrt(np.mean(np.sum((sol.position_ecef - traj.position_ecef) ** 2, 1))))

    without = {k: v for k, v in arrays.items() if not k.startswith("pseudorange_rate")}
    return {"with_rates_rms_m": rms(arrays), "without_rates_rms_m": rms(without)}


# Vibration of a car's IMU, one-sigma per 100 Hz sample (drive_0708's
# window stds, the navigate guide: at rest with the engine running 0.1-0.28
# m/s² and up to 2.8 °/s, driving 0.5-1.5 m/s² and 2.5-12 °/s).
VIBRATION_MOVING = (0.5, 2.0)  # m/s², °/s
VIBRATION_AT_REST = (0.12, 0.5)


def stop_and_go_drive(seed: int = 3):
    """A drive that stops for 25 s in the middle of a 70 s GNSS outage:
    30 s at rest, off to 12 m/s, a turn, down to a stop at 118 s, away again.
    A MEMS IMU with turn-on biases and vibration; 1 Hz fixes, 1 m noise."""
    trajectory = mn.Trajectory.from_segments(
        [
            ("stop", 30.0),
            ("accelerate", 10.0, 12.0),
            ("cruise", 40.0),
            ("turn", 10.0, 1.2),
            ("cruise", 20.0),
            ("accelerate", 8.0, 0.0),
            ("stop", 25.0),
            ("accelerate", 10.0, 12.0),
            ("cruise", 40.0),
        ]
    )
    t = trajectory.time
    rng = np.random.default_rng(seed)
    moving = np.linalg.norm(trajectory.velocity_ecef, axis=1) > 0.05
    accel_std = np.where(moving, VIBRATION_MOVING[0], VIBRATION_AT_REST[0])[:, None]
    gyro_std = np.radians(np.where(moving, VIBRATION_MOVING[1], VIBRATION_AT_REST[1]))[:, None]
    f = trajectory.specific_force + accel_std * rng.normal(size=(len(t), 3)) + [0.15, -0.1, 0.1]
    w = (
        trajectory.angular_rate
        + gyro_std * rng.normal(size=(len(t), 3))
        + np.radians([0.3, -0.2, 0.4])
    )
    k = np.arange(0, len(t), 100)
    fixes = mn.fixes_from_solution(
        t[k],
        trajectory.position_geodetic()[k],
        np.full((len(k), 3), 1.0),
        velocity_ned=trajectory.velocity_ned()[k],
        velocity_std_ned=np.full((len(k), 3), 0.1),
        added_position_noise_ned=[1.0, 1.0, 1.0],
        added_velocity_noise=0.1,
        seed=seed,
    )
    stop = t[~moving & (t > 60.0)]
    return trajectory, f, w, fixes, (stop[0], stop[-1])


def stop_and_go_runs() -> tuple[Any, dict[float, Any], tuple[float, float], dict[str, float]]:
    """:func:`stop_and_go_drive` through a 70 s outage around its stop,
    with the standstill rule's solution-speed σ at 3 (the default) and at
    0 (the speed alone vetoes): the trajectory, the runs by σ, the stop's
    start and end, s, and the figures the configuration reference quotes
    (the error at the outage's end with each rule, m; the speed the
    solution had coasted to by the stop, m/s)."""
    trajectory, f, w, fixes, (stop_start, stop_end) = stop_and_go_drive()
    t = trajectory.time
    outage = (stop_start - 45.0, 70.0)  # 45 s of coasting, the stop, 0.4 s of moving off
    runs = {}
    for sigmas in (3.0, 0.0):
        settings = {
            "outages": {"windows_s": [[outage[0] - t[0], outage[1]]]},
            "aids": {"nhc": True},
            "standstill": {"solution_speed_sigmas": sigmas},
        }
        runs[sigmas] = mn.navigate_log(t, f, w, fixes, settings=settings)
    end = outage[0] + outage[1]
    errors = {}
    for sigmas, run in runs.items():
        at = np.searchsorted(t, np.asarray(run.time))
        error = np.linalg.norm(np.asarray(run.position_ecef) - trajectory.position_ecef[at], axis=1)
        errors[sigmas] = error[np.searchsorted(np.asarray(run.time), end) - 1]
    at_stop = np.searchsorted(np.asarray(runs[0.0].time), stop_start)
    coasted = float(np.linalg.norm(np.asarray(runs[0.0].velocity_ned)[at_stop]))
    found = {
        "error_with_stop_m": float(errors[3.0]),
        "error_without_m": float(errors[0.0]),
        "coasted_speed_m_s": coasted,
    }
    return trajectory, runs, (stop_start, stop_end), found


def stop_and_go(data_root: Path) -> dict[str, Any]:
    """The figures of :func:`stop_and_go_runs`."""
    return stop_and_go_runs()[3]


CARRIER_STUDY = dict(
    imus=("tactical", "consumer"),
    outage_length=30.0,
    satellites=(0, 3),
    loose=False,
    runs=16,
    outage_start=60.0,
    duration=100.0,
    seed=0,
    threads=2,
)
"""The carrier-phase comparison of docs/results/outage-study.md: a tactical and a
consumer IMU, 30 s outages keeping 0 or 3 satellites after 60 s of aided
navigation (the outage study's cells, with the partial-outage set's
curves: the forward figures are the same runs)."""


def _carrier_set(**carrier: Any) -> dict[Any, Any]:
    result = mn.experiments.partial_outage(**CARRIER_STUDY, **carrier)
    return {"config": result.config} | {
        result.n_visible[label]: nav for label, nav in result.scenarios.items()
    }


def carrier_study_sets() -> dict[str, dict[Any, Any]]:
    """The comparison's three sets: code only, carrier phase (3 mm), and
    carrier phase with silent slips (0.01 per satellite and epoch)."""
    return {
        "code": _carrier_set(),
        "carrier": _carrier_set(carrier_phase_std=0.003),
        "slips": _carrier_set(carrier_phase_std=0.003, cycle_slip_probability=0.01),
    }


def carrier_end(study: dict[Any, Any], grade: str, n: int) -> np.ndarray:
    """The per-run horizontal errors at the end of the outage, m."""
    return np.asarray(study[n].runs_summary[grade]["horizontal_at_outage_end"])


def carrier_aided(study: dict[Any, Any], grade: str = "tactical") -> tuple[float, np.ndarray]:
    """Mean over the runs and over 30-60 s (aided, converged) of the
    position error, m, and of the NEES per degree of freedom."""
    result = study[0]
    t = np.asarray(result.time)
    aided = (t >= 30.0) & (t < 60.0)
    error = float(np.asarray(result.mean[grade])[aided].mean())
    nees = np.asarray(result.nees_mean[grade])[aided] / 9.0
    return error, nees


def carrier_phase_figures(sets: dict[str, dict[Any, Any]]) -> dict[str, dict[str, float]]:
    """Per grade, what the outage-study page quotes of
    :func:`carrier_study_sets`: the aided position error (m) and the
    median horizontal error at the outage's end with 0 and 3 satellites
    kept (m), code only and with carrier phase."""
    code, carrier = sets["code"], sets["carrier"]
    out = {}
    for grade in CARRIER_STUDY["imus"]:
        out[grade] = {
            "code_aided_m": carrier_aided(code, grade)[0],
            "carrier_aided_m": carrier_aided(carrier, grade)[0],
        }
        for n in (0, 3):
            for name, s in (("code", code), ("carrier", carrier)):
                out[grade][f"{name}_end_{n}_m"] = float(np.median(carrier_end(s, grade, n)))
    return out


def carrier_phase_comparison(data_root: Path) -> dict[str, Any]:
    """:func:`carrier_phase_figures` of :func:`carrier_study_sets`."""
    return carrier_phase_figures(carrier_study_sets())


def excerpt_time_offset(data_root: Path) -> dict[str, Any]:
    """The IMU time offset (s, with its standard error and correlation)
    that the 65 s drive excerpt the tests ship (tests/data) gives, from its
    along-track signal against its RTK positions, as
    docs/explanation/time-and-truth.md's example estimates a whole log's."""
    excerpt = ROOT / "tests" / "data" / "real-imu-gnss"
    imu = mn.read_imu_csv(excerpt / "drive_60s.csv")
    clock = mn.fit_tag_clock(imu, mn.read_time_tag(excerpt / "drive_60s.csv.tag"))
    c_b_s = mn.mounting_matrix([[180.0, 0.0, 180.0], [0.0, -6.79, 5.35]])
    rtk = mn.read_pos(excerpt / "drive_60s.pos")
    e = mn.estimate_time_offset(
        clock.gps_time, imu.specific_force @ c_b_s.T, imu.angular_rate @ c_b_s.T, rtk
    )
    return {"offset_s": e.offset_s, "std_s": e.std_s, "correlation": e.correlation}


#: An epoch within this of an IMU sample is applied after it, s (as `run`).
STEP_TOLERANCE_S = 1e-4


def initial_state(traj: Any, k: int = 0) -> dict[str, Any]:
    """The truth at sample k as a filter's `initial_state`."""
    return {
        "position_ecef": traj.position_ecef[k],
        "velocity_ecef": traj.velocity_ecef[k],
        "attitude": traj.attitude[k],
    }


def trajectory_yaw(traj: Any) -> np.ndarray:
    """The true yaw from north (NED) at every sample: C_b^n = C_e^n C_b^e."""
    geo = mn.ecef_to_geodetic(traj.position_ecef)
    lat, lon = geo[:, 0], geo[:, 1]
    sl, cl, so, co = np.sin(lat), np.cos(lat), np.sin(lon), np.cos(lon)
    c_e_n = np.stack(
        [
            np.stack([-sl * co, -sl * so, cl], axis=-1),
            np.stack([-so, co, np.zeros_like(lat)], axis=-1),
            np.stack([-cl * co, -cl * so, -sl], axis=-1),
        ],
        axis=1,
    )
    c_b_n = c_e_n @ traj.attitude
    return np.arctan2(c_b_n[:, 1, 0], c_b_n[:, 0, 0])


def aided_outage_runs() -> tuple[dict[bool, Any], dict[bool, list[bool]], dict[bool, set[str]]]:
    """:func:`simulated_drive_300s` through the step API with a 60 s GNSS
    outage (120-180 s), coasting (False) and bridged by a wheel speed, a
    height and a heading at 10 Hz (True): per run the position errors in
    the outage (m) with their ratios to the filter's σ per axis, whether
    each aid was accepted, and the kinds of measurement recorded."""
    traj, gnss, imu, f, w = simulated_drive_300s()
    t = traj.time
    rng = np.random.default_rng(9)
    outage = (t >= 120.0) & (t < 180.0)
    speed = np.einsum("nji,nj->ni", traj.attitude, traj.velocity_ecef)[:, 0]
    height = mn.ecef_to_geodetic(traj.position_ecef)[:, 2]
    yaw = trajectory_yaw(traj)
    flt = mn.TightlyCoupledFilter(imu)
    gt = np.asarray(gnss.time)
    results, accepted_by, kinds = {}, {}, {}
    for aided in (False, True):
        running = flt.start(t[0], f[0], w[0], initial_state(traj))
        j, errors, z, accepted = 0, [], [], []
        for k in range(len(t)):
            if t[k] > 180.0:
                break
            if k > 0:
                running.predict(t[k], f[k], w[k])
            while j < len(gt) and gt[j] <= t[k] + STEP_TOLERANCE_S:
                if not (120.0 <= gt[j] < 180.0):
                    running.update_gnss(gnss, j)
                j += 1
            if aided and outage[k] and k % 10 == 0:
                accepted.append(running.update_speed(speed[k] + rng.normal(0, 0.05), 0.05))
                accepted.append(running.update_height(height[k] + rng.normal(0, 0.5), 0.5))
                heading = yaw[k] + rng.normal(0, np.radians(0.5))
                accepted.append(running.update_heading(heading, np.radians(0.5)))
            if outage[k]:
                e = running.position_ecef - traj.position_ecef[k]
                p = running.covariance[6:9, 6:9]
                errors.append(np.linalg.norm(e))
                z.append(np.abs(e) / np.sqrt(np.diag(p)))
        results[aided] = (np.array(errors), np.array(z))
        accepted_by[aided] = accepted
        kinds[aided] = set(running.take_records()["measurements"]["kind"])
    return results, accepted_by, kinds


def aided_outage(data_root: Path) -> dict[str, Any]:
    """The errors at the end of :func:`aided_outage_runs`' outage, m."""
    results, _, _ = aided_outage_runs()
    return {"coast_end_m": float(results[False][0][-1]), "aided_end_m": float(results[True][0][-1])}


def increments_gain(data_root: Path | None) -> dict[str, Any]:
    """600 s of unaided step-API propagation from error-free data on a car
    trajectory, at 100 and 20 Hz: how far it ends from the truth, m, by
    increments (`predict_increments`) and by instantaneous samples
    (`predict`)."""
    imu = mn.ImuModel.preset("tactical", seed=1)
    ends = {}
    for rate in (100.0, 20.0):
        traj = mn.Trajectory.random(duration=600.0, rate=rate, seed=3)
        t = traj.time
        dv, dtheta = mn.imu_increments(t, traj.specific_force, traj.angular_rate)
        flt = mn.TightlyCoupledFilter(imu)
        by_increments = flt.start(
            t[0], traj.specific_force[0], traj.angular_rate[0], initial_state(traj)
        )
        by_samples = flt.start(
            t[0], traj.specific_force[0], traj.angular_rate[0], initial_state(traj)
        )
        for k in range(1, len(t)):
            by_increments.predict_increments(t[k], dv[k - 1], dtheta[k - 1])
            by_samples.predict(t[k], traj.specific_force[k], traj.angular_rate[k])
        ends[rate] = [
            float(np.linalg.norm(r.position_ecef - traj.position_ecef[-1]))
            for r in (by_increments, by_samples)
        ]
    return {
        f"{rate:g}": {"increments_m": ends[rate][0], "samples_m": ends[rate][1]} for rate in ends
    }


def smoothed_reset_run() -> tuple[Any, Any]:
    """A loosely coupled run with smoothing whose start is 2.8 m/s off
    while claiming 0.02 m/s, 60 s without fixes, then a position reset at
    the first fix: (truth, solution)."""
    truth = mn.Trajectory.random(duration=180.0, seed=3)
    imu = mn.ImuModel.preset("tactical", seed=2)
    accel, gyro = imu.measure(truth.specific_force, truth.angular_rate, seed=3)
    k = np.arange(6000, len(truth.time), 100)
    rng = np.random.default_rng(1)
    fixes = {
        "time": truth.time[k],
        "position_ecef": truth.position_ecef[k] + rng.normal(0, 0.3, (len(k), 3)),
        "position_covariance": np.repeat((np.eye(3) * 0.09)[None], len(k), axis=0),
    }
    start = {
        "position_ecef": truth.position_ecef[0],
        "velocity_ecef": truth.velocity_ecef[0] + np.array([2.0, -2.0, 0.0]),
        "attitude": truth.attitude[0],
    }
    flt = mn.LooselyCoupledFilter(imu, initial_velocity_std=0.02, initial_position_std=0.5)
    sol = flt.run(truth.time, accel, gyro, fixes, initial_state=start, smooth=True)
    return truth, sol


def rms(e: np.ndarray) -> float:
    """Root mean square of ``e``."""
    return float(np.sqrt(np.mean(e**2)))


def smoothed_reset_figures(sol: Any, truth: Any) -> dict[str, float]:
    """What docs/explanation/smoother.md quotes of :func:`smoothed_reset_run`:
    the reset (m), the forward and smoothed RMS in the 60 s without fixes
    and the smoothed RMS after the reset (m)."""
    forward = np.linalg.norm(sol.position_ecef - truth.position_ecef, axis=1)
    smoothed = np.linalg.norm(sol.smoothed.position_ecef - truth.position_ecef, axis=1)
    outage = truth.time < 60.0
    return {
        "reset_m": float(sol.resets["change"][0]),
        "forward_outage_rms_m": rms(forward[outage]),
        "smoothed_outage_rms_m": rms(smoothed[outage]),
        "smoothed_after_rms_m": rms(smoothed[~outage]),
    }


def smoothed_reset(data_root: Path) -> dict[str, Any]:
    """The figures of :func:`smoothed_reset_run`."""
    return smoothed_reset_figures(*reversed(smoothed_reset_run()))


def drive_smoothed_sigma(data_root: Path) -> dict[str, Any]:
    """drive_0708 as its example configures it (15 s outages) with the
    smoother: the ratio of the forward horizontal variance to the smoothed
    one at each outage's end (median and largest), the smallest smoothed
    position σ (m), the largest over N, E, D of the 99.9th percentile of
    the smoothed position σ's relative second difference, and the smoothed
    errors' share within 3σ in the outages."""
    with tempfile.TemporaryDirectory() as out_dir, warnings.catch_warnings():
        warnings.simplefilter("ignore")  # the log's cut lines
        out = Path(out_dir)
        cfg = out / "drive_0708.toml"
        example = (ROOT / "examples" / "drive_0708.toml").read_text()
        cfg.write_text(example + "\n[filter]\nsmoother = true\n\n[report]\nhtml = false\n")
        summary = mn.navigate(cfg, data_root=data_root, output=out / "out").summary
        forward = np.genfromtxt(out / "out" / "drive_0708.csv", delimiter=",", names=True)
        smoothed = np.genfromtxt(out / "out" / "drive_0708_smoothed.csv", delimiter=",", names=True)
    time_s = forward["gps_time_s"] - summary["start_gps_time_s"]
    ratios = []
    for start, length in summary["outages_s"]:
        inside = (time_s >= start) & (time_s < start + length)
        end = np.argmax(np.where(inside, forward["sdn_m"], 0.0))
        ratios += [(forward[c][end] / smoothed[c][end]) ** 2 for c in ("sdn_m", "sde_m")]
    columns = ("sdn_m", "sde_m", "sdd_m")
    roughness = [
        np.percentile(np.abs(np.diff(smoothed[c], 2)) / smoothed[c][1:-1], 99.9) for c in columns
    ]
    return {
        "variance_ratio_median": float(np.median(ratios)),
        "variance_ratio_max": float(np.max(ratios)),
        "smallest_sigma_m": float(min(smoothed[c].min() for c in columns)),
        "roughness_p999": float(max(roughness)),
        "share_15": summary["errors_vs_truth_smoothed"]["in_outages"]["within_3sigma_share"],
    }


def hardening_drive() -> tuple[Any, ...]:
    """:func:`simulated_drive_300s` with its least-squares fixes as the
    loose filter's input: (trajectory, gnss, imu, f, w, fixes)."""
    traj, gnss, imu, f, w = simulated_drive_300s()
    fixes = mn.solve_fix(gnss)
    arrays = {
        "time": np.array(fixes.time),
        "position_ecef": np.array(fixes.position_ecef),
        "position_covariance": np.array(fixes.position_clock_covariance)[:, :3, :3],
    }
    return traj, gnss, imu, f, w, arrays


def loose_run(drive: tuple[Any, ...], f: Any = None, w: Any = None, fixes: Any = None) -> Any:
    """The loose filter over :func:`hardening_drive`, with its readings or
    fixes replaced where given."""
    traj, _, imu, f0, w0, arrays = drive
    return mn.LooselyCoupledFilter(imu).run(
        traj.time,
        f0 if f is None else f,
        w0 if w is None else w,
        arrays if fixes is None else fixes,
        initial_attitude=traj.attitude[0],
    )


def fixes_off(arrays: dict[str, Any], which: str) -> dict[str, Any]:
    """The fixes with the first ("first") or every later one
    ("after_the_first") moved 10⁹ m."""
    bad = {k: v.copy() for k, v in arrays.items()}
    if which == "first":
        bad["position_ecef"][0] += [1e9, 0.0, 0.0]
    else:
        bad["position_ecef"][1:] += [1e9, 0.0, 0.0]
    return bad


def failed_shares(drive: tuple[Any, ...]) -> dict[str, float]:
    """The share of GNSS batches failing their gate, %, on
    :func:`hardening_drive`: a clean loose and tight run, fixes 10⁹ m off
    after the first, a gyro read in deg/s."""
    traj, gnss, imu, f, w, arrays = drive
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")  # the broken inputs warn of divergence
        runs = {
            "clean_loose_pct": loose_run(drive),
            "clean_tight_pct": mn.TightlyCoupledFilter(imu).run(
                traj.time, f, w, gnss, initial_attitude=traj.attitude[0]
            ),
            "fixes_off_pct": loose_run(drive, fixes=fixes_off(arrays, "after_the_first")),
            "gyro_deg_s_pct": loose_run(drive, w=np.degrees(w)),
        }
    return {k: 100.0 * (1.0 - float(np.mean(r.batches["accepted"]))) for k, r in runs.items()}


def outlier_run(drive: tuple[Any, ...], kind: str) -> tuple[Any, dict[str, Any], list[Any]]:
    """One outlier let through with the gate off (gate_probability 1) at
    epoch 100 of :func:`hardening_drive`: a pseudorange 5·10⁷ m too long
    (`kind` "tight") or a fix 10⁹ m off ("loose"). The solution, the
    aiding and the warnings."""
    traj, gnss, imu, f, w, arrays = drive
    if kind == "tight":
        g = {name: np.array(getattr(gnss, name)) for name in GNSS_ARRAY_KEYS}
        g["pseudorange"][100, 0] += 5e7
        run, aiding = mn.TightlyCoupledFilter(imu, gate_probability=1.0).run, g
    else:
        aiding = {k: v.copy() for k, v in arrays.items()}
        aiding["position_ecef"][100] += [1e9, 0.0, 0.0]
        run = mn.LooselyCoupledFilter(imu, gate_probability=1.0).run
    with warnings.catch_warnings(record=True) as caught:
        warnings.simplefilter("always")
        sol = run(traj.time, f, w, aiding, initial_attitude=traj.attitude[0])
    return sol, aiding, list(caught)


def robustness_runs(data_root: Path) -> dict[str, Any]:
    """What docs/reference/robustness.md quotes of :func:`hardening_drive`:
    the loose filter's final error (m) from a first fix 10⁹ m off, the
    failed shares (:func:`failed_shares`), and how far one outlier let
    through leaves each filter at the end (km)."""
    drive = hardening_drive()
    traj = drive[0]
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        first = loose_run(drive, fixes=fixes_off(drive[5], "first"))
    out: dict[str, Any] = {
        "first_fix_off_error_m": float(
            np.linalg.norm(first.position_ecef[-1] - traj.position_ecef[-1])
        ),
        "failed_shares": failed_shares(drive),
    }
    for kind in ("tight", "loose"):
        sol, _, _ = outlier_run(drive, kind)
        error = np.linalg.norm(sol.position_ecef[-1] - traj.position_ecef[-1])
        out[f"outlier_{kind}_end_km"] = float(error / 1e3)
    return out


def tactical_preset_fading(data_root: Path) -> dict[str, Any]:
    """drive_0708 as its example configures it, with the tactical preset
    (far too optimistic for its consumer IMU) and with the consumer one:
    the tactical run's fading resets and position and velocity resets,
    each run's horizontal RMS in the 15 s outages (m), and the consumer
    run's resets (kinds, in order)."""
    summaries = {}
    for preset in ("tactical", "consumer"):
        config = _example("drive_0708", data_root)
        config.engine.setdefault("filter", {})["imu_preset"] = preset
        with tempfile.TemporaryDirectory() as out, warnings.catch_warnings():
            warnings.simplefilter("ignore")  # the log's cut lines; the tactical tuning's alerts
            try:
                summaries[preset] = mn.navigate(config, output=out).summary
            except mn.DivergenceError as failed:
                # Too optimistic a tuning fails the integrity check; the
                # run is scored all the same.
                summaries[preset] = failed.result.summary  # type: ignore[attr-defined]
    kinds = [r["kind"] for r in summaries["tactical"]["resets"]]
    return {
        "tactical_failure_stage": (summaries["tactical"].get("failure") or {}).get("stage"),
        "fades": kinds.count("fading"),
        "position_velocity_resets": kinds.count("position_to_fix") + kinds.count("velocity_to_fix"),
        "tactical_outage_rms_m": summaries["tactical"]["errors_vs_truth"]["in_outages"][
            "rms_horizontal_m"
        ],
        "consumer_outage_rms_m": summaries["consumer"]["errors_vs_truth"]["in_outages"][
            "rms_horizontal_m"
        ],
        "consumer_resets": [r["kind"] for r in summaries["consumer"]["resets"]],
    }


RUNS: dict[str, Callable[[Path], dict[str, Any]]] = {
    "first_session": first_session,
    "own_arrays_conditioning": own_arrays_conditioning,
    "step_api_example": step_api_example,
    "input_correlation_times": input_correlation_times,
    "tactical_three_satellites": tactical_three_satellites,
    "drive_time_offsets": drive_time_offsets,
    "example_consistency": example_consistency,
    "walk_precision": walk_precision,
    "two_satellite_runs": two_satellite_runs,
    "partial_outages": partial_outages,
    "study_defaults": study_defaults,
    "walk_ubx_fix": walk_ubx_fix,
    "slac_rinex2_fixes": slac_rinex2_fixes,
    "quick_calibration": quick_calibration,
    "drive_other_settings": drive_other_settings,
    "walk_multi_gnss": walk_multi_gnss.record,
    "walk_g08": walk_multi_gnss.g08_record,
    "walk_carrier_floors": walk_multi_gnss.carrier_floors,
    "walk_code_correlation": walk_multi_gnss.code_correlation_record,
    "walk_configurations": walk_multi_gnss.configurations_record,
    "walk_every_satellite": walk_multi_gnss.every_satellite_record,
    "walk_correlation_table": walk_multi_gnss.correlation_record,
    "drive_example_schedule": drive_example_schedule,
    "foreign_drive": foreign_drive_datum.record,
    "foreign_drive_files": foreign_drive_datum.files_record,
    "foreign_drive_study": foreign_drive_study.record,
    "static_start_spec": static_start_spec,
    "xsens_session": xsens_session,
    "xsens_parameters": xsens_parameters,
    "xsens_splits": xsens_splits,
    "xsens_nonlinearity": xsens_nonlinearity,
    "xsens_criteria": xsens_criteria,
    "xsens_second_half": xsens_second_half,
    "xsens_detector": xsens_detector,
    "somigliana_departure": somigliana_departure,
    "tactical_preset_fading": tactical_preset_fading,
    "simulated_fading": simulated_fading,
    "fix_error_states": fix_error_states,
    "pseudorange_rates_value": pseudorange_rates_value,
    "stop_and_go": stop_and_go,
    "carrier_phase_comparison": carrier_phase_comparison,
    "excerpt_time_offset": excerpt_time_offset,
    "aided_outage": aided_outage,
    "increments_gain": increments_gain,
    "smoothed_reset": smoothed_reset,
    "drive_smoothed_sigma": drive_smoothed_sigma,
    "robustness_runs": robustness_runs,
    "drive_calibration": drive_calibration_record.record,
    "drive_calibration_windows": drive_calibration_record.window_study,
    "installation_states": installation_drives.record,
    "full_log_time_offsets": time_offsets_record.record,
    "robustness_constants": robustness_reference.constants,
    "robustness_messages": robustness_reference.messages,
    "standstill_spread": page_measurements.standstill_spread,
    "drive_rest_start": page_measurements.drive_rest_start,
    "tactical_without_fading": page_measurements.tactical_without_fading,
    "foreign_drive_nhc": page_measurements.foreign_drive_nhc,
    "misaligned_vertical": page_measurements.misaligned_vertical,
    "walk_clock_span": page_measurements.walk_clock_span,
    "walk_white_code": page_measurements.walk_white_code,
    "allan_fit_spread": page_measurements.allan_fit_spread,
    "gyro_scale_logs": page_measurements.gyro_scale_logs,
    "wrong_gyro_example": page_measurements.wrong_gyro_example,
    "xsens_guide": page_measurements.xsens_guide,
    **multi_gnss_measurements.RUNS,
    **gnss_file_measurements.RUNS,
    **results_measurements.RUNS,
}
"""Each record's name and the run that measures it."""

Table = tuple[str, tuple[str, str], Callable[[dict[str, Any]], str]]
"""A block of a page a record fills: the page, its markers, the renderer."""

TABLES: dict[str, tuple[Table, ...]] = {
    "partial_outages": (("results/paper-comparison.md", PARTIAL_OUTAGES, partial_outages_table),),
    "walk_multi_gnss": (
        (
            "how-to/multi-gnss.md",
            walk_multi_gnss.SATELLITES_LINE,
            walk_multi_gnss.satellites_line_block,
        ),
    ),
    "walk_configurations": (
        (
            "how-to/multi-gnss.md",
            walk_multi_gnss.CONFIGURATION_TABLE,
            walk_multi_gnss.configuration_table,
        ),
    ),
    "walk_correlation_table": (
        (
            "how-to/multi-gnss.md",
            walk_multi_gnss.CORRELATION_TABLE,
            walk_multi_gnss.correlation_table,
        ),
    ),
    "static_start_spec": (
        ("how-to/tune-for-your-imu.md", STATIC_START_SPEC, static_start_spec_table),
    ),
    "full_log_time_offsets": (
        ("explanation/time-and-truth.md", time_offsets_record.TABLE, time_offsets_record.table),
    ),
    "foreign_drive_study": (
        (
            "results/foreign-drive.md",
            (foreign_drive_study.BEGIN, foreign_drive_study.END),
            foreign_drive_study.tables,
        ),
    ),
    "drive_calibration": (
        (
            "how-to/calibrate-an-imu.md",
            drive_calibration_record.PARAMETERS,
            drive_calibration_record.parameters_table,
        ),
        (
            "how-to/calibrate-an-imu.md",
            drive_calibration_record.OUTAGES,
            drive_calibration_record.outages_table,
        ),
    ),
    "gyro_scale_logs": (
        (
            "how-to/when-a-run-fails.md",
            page_measurements.GYRO_SCALE_TABLE,
            page_measurements.gyro_scale_table,
        ),
    ),
}
"""The records that also fill a table: the page, its markers, the table."""


def write_table(name: str) -> None:
    """Writes ``name``'s tables into their pages from its record."""
    for page, (begin, end), table in TABLES[name]:
        replace_block(ROOT / "docs" / page, begin, end, table(load_record(name)))


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("names", nargs="*", help=f"the runs, of {', '.join(RUNS)} (default all)")
    parser.add_argument("--data-root", help="the shared data (default: the project's resolver)")
    args = parser.parse_args()
    data_root = resolve_data_root(Path(__file__), args.data_root)
    unknown = set(args.names) - RUNS.keys()
    if unknown:
        parser.error(f"no run named {', '.join(sorted(unknown))}")
    for name in args.names or RUNS:
        path = write_record(name, RUNS[name](data_root))
        if name in TABLES:
            write_table(name)
        print(f"wrote {path.relative_to(ROOT)}")


if __name__ == "__main__":
    main()
