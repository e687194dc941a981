"""The runs behind the figures docs/reference/configuration.md,
docs/how-to/tune-for-your-imu.md, docs/how-to/own-logs.md and
docs/how-to/when-a-run-fails.md quote: each a function of the data root
returning its figures (full precision, in the units the pages show),
registered in docs/doc_runs.py ``RUNS``, so that ``python
docs/doc_runs.py NAME`` writes ``docs/data/NAME.json`` and re-renders the
pages. ``tests/test_doc_runs.py`` (and, for the gyro-scale table,
``tests/test_failed_runs.py``) run them again and compare them with their
records within the digits the pages show. Each takes seconds; the
foreign drive's four runs about twenty."""

from __future__ import annotations

import contextlib
import copy
import io
import os
import re
import tempfile
import warnings
from pathlib import Path
from typing import Any

import numpy as np

import memsnav as mn
from memsnav.realdata import readers
from memsnav.realdata.config import RunConfig
from memsnav.realdata.pipeline import read_imu

ROOT = Path(__file__).resolve().parents[1]

DEG = float(np.degrees(1.0))
"""Degrees per radian: the factor of both gyro unit mistakes."""


def _example(name: str, data_root: Path) -> RunConfig:
    """examples/<name>.toml against ``data_root``, without its HTML report."""
    config = mn.load_config(ROOT / "examples" / f"{name}.toml", data_root)
    config.values["report"]["html"] = False
    return config


def _navigate(config: RunConfig) -> Any:
    """``mn.navigate`` into a temporary folder; a run the integrity check
    fails is scored all the same (its written result)."""
    with warnings.catch_warnings(), tempfile.TemporaryDirectory() as out:
        warnings.simplefilter("ignore")  # the logs' cut lines; a failing tuning's alerts
        try:
            return mn.navigate(config, output=out)
        except mn.DivergenceError as failed:
            return failed.result  # type: ignore[attr-defined]


def _span(values: list[float]) -> dict[str, float]:
    return {"least": float(min(values)), "most": float(max(values))}


# --- the standstill detector's statistics on the example logs -----------------

#: Each example log's RTK solution (its truth), whose velocity tells rest
#: from motion.
TRUTH_POS = {
    "drive_0708": "real-imu-gnss/drive_0708/gnss_1934_sf.pos",
    "walk_0827": "real-imu-gnss/walk_0827/gnss_1730_sf.pos",
}

#: A window is at rest when the RTK ground speed stays below the
#: detector's `standstill.gnss_speed_m_s` default, m/s, and moving when it
#: stays above this, m/s, from half a second before the window to half a
#: second after it (RTKLIB's velocities lag their epochs by 0.13-0.15 s).
REST_SPEED_M_S, MOVING_SPEED_M_S, SPEED_MARGIN_S = 0.2, 0.5, 0.5


def detector_windows(config: RunConfig, pos: Path) -> dict[str, np.ndarray]:
    """The log of ``config`` cut into consecutive 1 s windows (the
    detector's `window_s` default): per window the norm of the per-axis
    stds (n − 1) of specific force (m/s²) and angular rate (°/s), as
    ``navigate/standstill.rs`` takes them (the norm is √trace of the
    covariance: the same in any axes), and the least and largest RTK
    ground speed around it (m/s)."""
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")  # the logs' cut first and last lines
        t, f, w, _ = read_imu(config)
    n = round(1.0 / float(np.median(np.diff(t))))
    k = len(t) // n

    def spread(x: np.ndarray) -> np.ndarray:
        return np.linalg.norm(x[: k * n].reshape(k, n, 3).std(axis=1, ddof=1), axis=1)

    solution = mn.read_pos(pos)
    epochs = np.asarray(solution.gps_time)
    speed = np.hypot(*np.asarray(solution.velocity_ned)[:, :2].T)
    least, most = [], []
    for start, end in zip(t[: k * n : n], t[n - 1 : k * n : n], strict=True):
        near = speed[(epochs >= start - SPEED_MARGIN_S) & (epochs <= end + SPEED_MARGIN_S)]
        near = near[np.isfinite(near)]
        least.append(near.min() if len(near) else np.nan)
        most.append(near.max() if len(near) else np.nan)
    return {
        "accel_m_s2": spread(f),
        "gyro_deg_s": DEG * spread(w),
        "least_speed_m_s": np.asarray(least),
        "largest_speed_m_s": np.asarray(most),
    }


def standstill_spread(data_root: Path) -> dict[str, Any]:
    """drive_0708 and walk_0827 in the standstill detector's 1 s windows:
    for the windows at rest and those moving (:data:`REST_SPEED_M_S`,
    :data:`MOVING_SPEED_M_S`), the 5 % and 95 % points of the specific
    force's spread (m/s²) and the angular rate's (°/s), and how many
    windows."""
    figures: dict[str, Any] = {}
    for name, pos in TRUTH_POS.items():
        windows = detector_windows(_example(name, data_root), data_root / pos)
        with np.errstate(invalid="ignore"):  # windows without a velocity are neither
            states = {
                "rest": windows["largest_speed_m_s"] < REST_SPEED_M_S,
                "moving": windows["least_speed_m_s"] > MOVING_SPEED_M_S,
            }
        figures[name] = {
            state: {
                "windows": int(np.sum(chosen)),
                **{
                    key: {
                        "p5": float(np.percentile(windows[key][chosen], 5)),
                        "p95": float(np.percentile(windows[key][chosen], 95)),
                    }
                    for key in ("accel_m_s2", "gyro_deg_s")
                },
            }
            for state, chosen in states.items()
        }
    return figures


# --- drive_0708's rest at the start -------------------------------------------


def drive_rest_start(data_root: Path) -> dict[str, Any]:
    """drive_0708 as configured: how long it rests from its first IMU
    sample (to the first RTK epoch moving faster than the detector's
    0.2 m/s), how far its first fix precedes its first IMU sample and how
    far after that fix the run starts (s); its z-gyro bias estimate at the
    end of the rest and the estimate's σ (°/s) there with ZARU and
    without (and without at the end of the log); the outages (numbered
    from 1) in which the car stopped, those spent at a standstill (not
    scored) left out."""
    config = _example("drive_0708", data_root)
    runs = {}
    for zaru in (True, False):
        chosen = copy.deepcopy(config)
        chosen.engine.setdefault("aids", {})["zaru"] = zaru
        runs[zaru] = _navigate(chosen)
    summary = runs[True].summary
    start = summary["start"]
    first_imu = start["gps_time_s"] - start["after_first_imu_sample_s"]
    solution = mn.read_pos(data_root / TRUTH_POS["drive_0708"])
    epochs = np.asarray(solution.gps_time)
    speed = np.hypot(*np.asarray(solution.velocity_ned)[:, :2].T)
    moving = epochs[(epochs > start["gps_time_s"]) & (speed > REST_SPEED_M_S)]
    rest_end = float(moving[0])

    def z_bias(run: Any, when: float) -> tuple[float, float]:
        filter_solution = run.run.solution
        time = np.asarray(filter_solution.time)
        k = min(int(np.searchsorted(time, when)), len(time) - 1)
        column = filter_solution.state_names.index("gyro_bias_z")
        sigma = np.sqrt(np.asarray(filter_solution.covariance_diagonal)[k, column])
        return DEG * float(np.asarray(filter_solution.gyro_bias)[k, 2]), DEG * float(sigma)

    bias, sigma = z_bias(runs[True], rest_end)
    outages = summary["errors_vs_truth"]
    scored = [outages.get(f"outage_{n}") for n in range(1, len(summary["outages_s"]) + 1)]
    stood = [
        number
        for number, outage in enumerate(scored, start=1)
        if outage is not None and outage["standstill_s"] > 0.0 and not outage["at_standstill"]
    ]
    return {
        "rest_s": rest_end - first_imu,
        "first_fix_before_imu_s": start["after_first_gnss_epoch_s"]
        - start["after_first_imu_sample_s"],
        "start_after_first_fix_s": start["after_first_gnss_epoch_s"],
        "z_gyro_bias_deg_s": bias,
        "z_gyro_bias_sigma_deg_s": {
            "zaru": sigma,
            "no_zaru": z_bias(runs[False], rest_end)[1],
            "no_zaru_log_end": z_bias(runs[False], np.inf)[1],
        },
        "outages_with_a_stop": stood,
    }


# --- the tactical preset on drive_0708 without fading -------------------------


def tactical_without_fading(data_root: Path) -> dict[str, Any]:
    """drive_0708 with the tactical preset (too tight for its consumer
    IMU) and `reset_fading_factor = 1` (no fading): its position and
    velocity resets and its forward RMS horizontal error in the 15 s
    outages, m."""
    config = _example("drive_0708", data_root)
    config.engine.setdefault("filter", {}).update(imu_preset="tactical", reset_fading_factor=1.0)
    summary = _navigate(config).summary
    kinds = [r["kind"] for r in summary["resets"]]
    return {
        "position_velocity_resets": kinds.count("position_to_fix") + kinds.count("velocity_to_fix"),
        "outage_rms_m": summary["errors_vs_truth"]["in_outages"]["rms_horizontal_m"],
    }


# --- the foreign drive's vertical errors with a tight constraint --------------


def vertical_outside_percent(score: dict[str, Any]) -> float:
    """The share of the vertical errors outside the solution's 3σ, %, from
    a score's shares of all N/E/D components and of N/E inside
    (``navigate/score.rs`` counts each component of each epoch)."""
    inside = 3.0 * score["within_3sigma_share"] - 2.0 * score["within_3sigma_share_horizontal"]
    return max(0.0, 100.0 * (1.0 - inside))


def foreign_drive_nhc(data_root: Path) -> dict[str, Any]:
    """examples/foreign_drive.toml with outages of 30 s and of 60 s every
    180 s (docs/foreign_drive_study.py's schedules), the engine's defaults
    but the non-holonomic constraint's std at 0.1 m/s, and as the log
    chooses it (`"auto"`): the share of the forward aided vertical errors
    outside 3σ (%), by outage length, and the std the log chose, m/s."""
    import foreign_drive_study

    base = _example("foreign_drive", data_root)
    figures: dict[str, Any] = {"nhc_0_1": {}, "auto": {}}
    learnt = []
    for length_s in foreign_drive_study.OUTAGE_LENGTHS_S:
        for key, std in (("nhc_0_1", 0.1), ("auto", "auto")):
            config = foreign_drive_study.configured(base, "defaults", length_s)
            config.engine.setdefault("aids", {})["nhc_std_m_s"] = std
            summary = _navigate(config).summary
            aided = summary["errors_vs_truth"]["aided"]
            figures[key][f"{length_s:g}"] = vertical_outside_percent(aided)
            if key == "auto":
                learnt.append(summary["adaptation"]["nhc_std_m_s"])
    assert len(set(learnt)) == 1, learnt
    return figures | {"learnt_nhc_std_m_s": learnt[0]}


# --- a simulated IMU's misalignment under the constraint ----------------------

EARTH_RADIUS_M = 6378137.0


def misaligned_drive_runs() -> dict[bool, dict[str, Any]]:
    """tests/test_adaptation.py's drive with correlated fixes (seed 6,
    900 s from 20 s at rest; an industrial IMU drawn from its preset, whose
    misalignment tilts its axes off the car's; 1 Hz fixes whose errors are
    0.8 m of Gauss-Markov error over 40 s plus 0.1 m white, reported with
    their total σ), run with the non-holonomic constraint, fix-error
    states learnt, and the installation states off and on: each run's
    aided score against the truth, by whether the states were on."""
    seed, tau_s, slow_m = 6, 40.0, 0.8
    trajectory = mn.Trajectory.random(900.0, seed=seed, stationary_start=20.0)
    imu = mn.ImuModel.preset("industrial", seed=seed, sample_rate=100.0)
    f, w = imu.measure(trajectory.specific_force, trajectory.angular_rate, seed=seed)
    k = np.arange(0, len(trajectory.time), 100)
    rng = np.random.default_rng(seed)
    phi = np.exp(-1.0 / tau_s)
    slow = np.zeros((len(k), 3))
    slow[0] = slow_m * rng.normal(size=3)
    for i in range(1, len(k)):
        slow[i] = phi * slow[i - 1] + slow_m * np.sqrt(1 - phi**2) * rng.normal(size=3)
    errors = slow + 0.1 * rng.normal(size=(len(k), 3))
    lla = trajectory.position_geodetic()[k].copy()
    lla[:, 0] += errors[:, 0] / EARTH_RADIUS_M
    lla[:, 1] += errors[:, 1] / (EARTH_RADIUS_M * np.cos(lla[:, 0]))
    lla[:, 2] -= errors[:, 2]
    fixes = mn.fixes_from_solution(
        trajectory.time[k],
        lla,
        np.full((len(k), 3), np.hypot(slow_m, 0.1)),
        velocity_ned=trajectory.velocity_ned()[k],
        velocity_std_ned=np.full((len(k), 3), 0.05),
        added_velocity_noise=0.05,
        seed=seed,
    )
    scores = {}
    for states in (False, True):
        settings = {
            "aids": {"zupt": False, "zaru": False, "nhc": True},
            "filter": {"imu_preset": "industrial", "installation_states": states},
        }
        run = mn.navigate_log(trajectory.time, f, w, fixes, settings=settings)
        scores[states] = run.score(trajectory.time[k], trajectory.position_ecef[k])["aided"]
    return scores


def misaligned_vertical(data_root: Path) -> dict[str, Any]:
    """The share of the aided vertical errors outside 3σ (%) on
    :func:`misaligned_drive_runs`' drive without and with the
    installation states."""
    scores = misaligned_drive_runs()
    return {
        "without_states_percent": vertical_outside_percent(scores[False]),
        "with_states_percent": vertical_outside_percent(scores[True]),
    }


# --- walk_0827's receiver clock and its code errors ----------------------------


def walk_clock_span(data_root: Path) -> dict[str, Any]:
    """walk_0827's UBX log: the change of its receiver clock drift from
    the first to the last 10 s of its single-point fixes (m/s,
    docs/walk_multi_gnss.py's ramp) and the span of its RXM-RAWX epochs
    (s)."""
    import walk_multi_gnss

    log = mn.read_ubx(data_root / walk_multi_gnss.UBX)
    ramp = walk_multi_gnss.clock_ramp(log)
    epochs = np.asarray(log.observations.time)
    return {
        "drift_change_m_s": abs(ramp["last_m_s"] - ramp["first_m_s"]),
        "log_s": float(epochs[-1] - epochs[0]),
    }


def walk_white_code(data_root: Path) -> dict[str, Any]:
    """walk_0827 as configured (Doppler on) with its pseudorange errors
    taken as white (`range_bias_states = false`) and with the range-bias
    states: the shares of the aided errors inside 3σ, all components and
    horizontal, %."""
    figures = {}
    for key, states in (("white", False), ("range_bias_states", True)):
        config = _example("walk_0827", data_root)
        config.engine.setdefault("gnss", {})["range_bias_states"] = states
        aided = _navigate(config).summary["errors_vs_truth"]["aided"]
        figures[key] = {
            "inside_percent": 100.0 * aided["within_3sigma_share"],
            "inside_horizontal_percent": 100.0 * aided["within_3sigma_share_horizontal"],
        }
    return figures


# --- the Allan fit on simulated and real records --------------------------------

#: The simulated terms: white noise density (unit·√s), Gauss-Markov σ
#: and τ (s), random walk (unit/√s), as tests/test_allan.py draws them.
ALLAN_TERMS = {
    "white_density": 1e-3,
    "bias_instability": 5e-4,
    "bias_correlation_time": 100.0,
    "bias_random_walk": 2e-5,
}

#: The seeds of the Allan fit's spread.
ALLAN_SEEDS = range(1, 21)


def allan_record(seed: int, rate_hz: float, seconds: float) -> np.ndarray:
    """Three axes of white noise, a stationary first-order Gauss-Markov
    process and a random walk of :data:`ALLAN_TERMS`, simulated with numpy
    and scipy apart from the core's sensor models (tests/test_allan.py's
    record)."""
    from scipy.signal import lfilter

    rng = np.random.default_rng(seed)
    n, dt = int(seconds * rate_hz), 1.0 / rate_hz
    sigma, tau = ALLAN_TERMS["bias_instability"], ALLAN_TERMS["bias_correlation_time"]
    phi = np.exp(-dt / tau)
    drive = sigma * np.sqrt(1.0 - phi**2) * rng.normal(size=(n, 3))
    start = sigma * rng.normal(size=3)
    markov = np.column_stack(
        [lfilter([1.0], [1.0, -phi], drive[:, k], zi=[phi * start[k]])[0] for k in range(3)]
    )
    white = ALLAN_TERMS["white_density"] * np.sqrt(rate_hz) * rng.normal(size=(n, 3))
    walk = np.cumsum(ALLAN_TERMS["bias_random_walk"] * np.sqrt(dt) * rng.normal(size=(n, 3)), 0)
    return np.asarray(white + markov + walk)


def xsens_rest() -> np.ndarray:
    """The 50 s rest of the Xsens session (tests/data/imu-static-poses,
    BSD, raw counts): accelerometer and gyro, (N, 6)."""
    import gzip

    path = ROOT / "tests" / "data" / "imu-static-poses" / "xsens_excerpt.csv.gz"
    with gzip.open(path, "rt") as f:
        x = np.loadtxt(f, delimiter=",", comments="#")
    return np.asarray(x[x[:, 0] < 50e6, 1:])


def allan_fit_spread(data_root: Path) -> dict[str, Any]:
    """``mn.allan_fit`` on :func:`allan_record` (10 h at 10 Hz) over
    :data:`ALLAN_SEEDS`: each term's relative error, its spread (standard
    deviation over the seeds, n − 1) and mean, %; and on the Xsens gyro's
    50 s rest, its white noise against the IEEE 952 reading (the Allan
    deviation at 1 s, RMS over the axes), % difference."""
    errors = []
    for seed in ALLAN_SEEDS:
        fit = mn.allan_fit(allan_record(seed, 10.0, 36_000.0), 10.0)
        errors.append([100.0 * (getattr(fit, k) / v - 1.0) for k, v in ALLAN_TERMS.items()])
    table = np.asarray(errors)
    gyro = xsens_rest()[:, 3:]
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")  # the terms a 50 s record cannot determine
        white = mn.allan_fit(gyro, 100.0).white_density
    _, adev = mn.allan_deviation(gyro, 100.0, taus=[1.0])
    reading = float(np.sqrt(np.mean(adev[0] ** 2)))
    return {
        "seeds": len(ALLAN_SEEDS),
        "spread_percent": dict(zip(ALLAN_TERMS, table.std(axis=0, ddof=1).tolist(), strict=True)),
        "mean_error_percent": dict(zip(ALLAN_TERMS, table.mean(axis=0).tolist(), strict=True)),
        "xsens_white_vs_reading_percent": 100.0 * (white / reading - 1.0),
    }


# --- the gyro's unit against the GNSS course, on every shared log --------------

#: The rates as given, divided by 180/π (radians read as degrees) and
#: multiplied by it (the reverse), with the unit the warning then names.
GYRO_FACTORS = {
    "as_given": (1.0, None),
    "divided": (1.0 / DEG, '"rad/s"'),
    "multiplied": (DEG, '"deg/s"'),
}


def _pos_fixes(path: Path) -> Any:
    solution = mn.read_pos(path)
    return mn.fixes_from_solution(
        solution.gps_time,
        solution.lla,
        solution.std_ned,
        velocity_ned=solution.velocity_ned,
        velocity_std_ned=solution.velocity_std_ned,
    )


def shared_logs(data_root: Path) -> dict[str, tuple[Any, ...]]:
    """Every IMU log of the shared data with a GNSS velocity to compare
    with: by name, (IMU time on GNSS time, specific force, angular rate,
    fixes). The Xsens poses have no GNSS and no motion to compare."""
    base = data_root / "real-imu-gnss"
    logs: dict[str, tuple[Any, ...]] = {}
    for name, imu, pos in (
        ("drive_0708", "drive_0708/imu_1934.csv", "drive_0708/gnss_1934_sf.pos"),
        ("walk_0827", "walk_0827/imu_1730.csv", "walk_0827/gnss_1730_sf.pos"),
    ):
        with warnings.catch_warnings():
            warnings.simplefilter("ignore")  # the walk's last line is cut short
            log = readers.read_imu_csv(base / imu, skip_first_line=True)
            t, _ = readers.gps_time_from_tag(log, readers.read_time_tag(f"{base / imu}.tag"))
        logs[name] = (t, log.specific_force, log.angular_rate, _pos_fixes(base / pos))
    sf = readers.read_imu_csv(
        base / "walk_0827" / "imu_1730_sf.csv",
        ["t", "ax", "ay", "az", "gx", "gy", "gz", "mx", "my", "mz", "z"],
        gyro_unit="rad/s",
        time_unit="s",
    )
    logs["walk_0827_sf"] = (
        sf.time - readers.UNIX_TO_GPS_S,
        sf.specific_force,
        sf.angular_rate,
        _pos_fixes(base / "walk_0827" / "gnss_1730_sf.pos"),
    )
    foreign = data_root / "foreign-drive"
    vn = readers.read_imu_csv(
        foreign / "vn100_imu.csv",
        {
            "t": "time_s",
            "ax": "dv_x_m_s",
            "ay": "dv_y_m_s",
            "az": "dv_z_m_s",
            "gx": "dtheta_x_rad",
            "gy": "dtheta_y_rad",
            "gz": "dtheta_z_rad",
        },
        accel_unit="m/s",
        gyro_unit="rad",
        time_unit="s",
    )
    # The F9T fixes' own layout, read here as plain numbers (their columns
    # are not the fixes CSV's names): time on the IMU's clock, the NED
    # position and velocity covariances.
    f9t = np.genfromtxt(foreign / "f9t_fixes.csv", delimiter=",", names=True)
    lla = np.column_stack([np.radians(f9t["lat_deg"]), np.radians(f9t["lon_deg"]), f9t["height_m"]])

    def covariance(names: list[str]) -> np.ndarray:
        nn, ne, nd, ee, ed, dd = (f9t[name] for name in names)
        return np.moveaxis(np.array([[nn, ne, nd], [ne, ee, ed], [nd, ed, dd]]), -1, 0)

    position = ["cov_nn_m2", "cov_ne_m2", "cov_nd_m2", "cov_ee_m2", "cov_ed_m2", "cov_dd_m2"]
    velocity = ["cov_vnvn", "cov_vnve", "cov_vnvd", "cov_veve", "cov_vevd", "cov_vdvd"]
    fixes = mn.fixes_from_solution(
        f9t["time_s"],
        lla,
        covariance_ned=covariance(position),
        velocity_ned=np.column_stack([f9t["vn_m_s"], f9t["ve_m_s"], f9t["vd_m_s"]]),
        velocity_covariance_ned=covariance(velocity),
    )
    logs["foreign_drive"] = (vn.time, vn.specific_force, vn.angular_rate, fixes)
    return logs


def gyro_scale_checks(data_root: Path) -> dict[str, dict[str, dict[str, Any]]]:
    """The gyro-scale check (``navigate::gyro_scale``) of every log of
    :func:`shared_logs` with its rates as given, divided and multiplied by
    180/π (:data:`GYRO_FACTORS`; a 2 s run each): by log and factor, the
    run's ``gyro_scale`` (None when the start failed), the warnings naming
    ``gyro_unit``, and the error of a start the rates spoiled (else None)."""
    checks: dict[str, dict[str, dict[str, Any]]] = {}
    for name, (t, f, w, fixes) in shared_logs(data_root).items():
        checks[name] = {}
        for key, (factor, _) in GYRO_FACTORS.items():
            check: dict[str, Any] = {"gyro_scale": None, "warnings": [], "error": None}
            with warnings.catch_warnings(record=True) as caught:
                warnings.simplefilter("always")
                try:
                    run = mn.navigate_log(t, f, w * factor, fixes, duration_s=2.0)
                    gyro_scale = run.gyro_scale
                    check["gyro_scale"] = None if gyro_scale is None else gyro_scale.to_dict()
                except (ValueError, mn.MemsnavError) as e:
                    check["error"] = str(e)
            check["warnings"] = [str(c.message) for c in caught if "gyro_unit" in str(c.message)]
            checks[name][key] = check
    return checks


def gyro_scale_figures(checks: dict[str, dict[str, dict[str, Any]]]) -> dict[str, Any]:
    """The ratio of each check of :func:`gyro_scale_checks` (None when
    the start failed) and the pairs of course changes behind it, by log
    and factor."""
    return {
        name: {
            key: {
                "ratio": None if c["gyro_scale"] is None else c["gyro_scale"]["ratio"],
                "pairs": None if c["gyro_scale"] is None else c["gyro_scale"]["pairs"],
            }
            for key, c in by_factor.items()
        }
        for name, by_factor in checks.items()
    }


def gyro_scale_logs(data_root: Path) -> dict[str, Any]:
    """:func:`gyro_scale_figures` of every shared log."""
    return gyro_scale_figures(gyro_scale_checks(data_root))


#: The gyro-scale table's markers in docs/how-to/when-a-run-fails.md.
GYRO_SCALE_TABLE = ("<!-- gyro-scale-logs:begin -->", "<!-- gyro-scale-logs:end -->")

#: Its rows: the label (``{pairs}`` the pairs of course changes) and the
#: logs a row shows.
GYRO_SCALE_ROWS = (
    ("drive_0708 (RTK velocities, {pairs} pairs)", ("drive_0708",)),
    ("walk_0827, raw and `imu_1730_sf.csv` ({pairs} pairs)", ("walk_0827", "walk_0827_sf")),
    ("foreign-drive VN-100, F9T velocities ({pairs} pairs)", ("foreign_drive",)),
)


def _range(values: list[Any], spec: str) -> str:
    """Values as shown with ``spec``: one, or the least and the largest."""
    if any(v is None for v in values):
        return "no start"
    shown = sorted({format(v, spec) for v in values}, key=float)
    return "-".join([shown[0], shown[-1]] if len(shown) > 1 else shown)


def gyro_scale_table(record: dict[str, Any]) -> str:
    """docs/how-to/when-a-run-fails.md's table from its record, between
    its markers: the ratio of each factor (two figures, the divided
    rates' three, the multiplied rates' to the unit)."""
    logs = record["figures"]
    rows = []
    for label, names in GYRO_SCALE_ROWS:
        pairs = sorted({logs[n]["as_given"]["pairs"] for n in names})
        count = " and ".join(f"{p:,}".replace(",", " ") for p in pairs)
        cells = [
            _range([logs[n][key]["ratio"] for n in names], spec)
            for key, spec in (("as_given", ".2f"), ("divided", ".3f"), ("multiplied", ".0f"))
        ]
        rows.append(f"| {label.format(pairs=count)} | " + " | ".join(cells) + " |")
    header = (
        "| log | gyro as given | rates ÷ 57.3 (rad read as deg) | rates × 57.3 |\n|---|---|---|---|"
    )
    return "\n".join([GYRO_SCALE_TABLE[0], header, *rows, GYRO_SCALE_TABLE[1]])


def wrong_gyro_example(data_root: Path) -> dict[str, Any]:
    """docs/how-to/when-a-run-fails.md's Python block (drive_0708's gyro
    declared as rad/s): the failure's stage and the gyro-scale ratio it
    prints."""
    text = (ROOT / "docs" / "how-to" / "when-a-run-fails.md").read_text()
    text = text[text.index("## From Python") :]
    block = re.search(r"```python\n(.*?)```", text, re.S)
    assert block is not None, "no Python block in when-a-run-fails.md"
    out = io.StringIO()
    saved = os.environ.get("MEMSNAV_DATA_ROOT")
    os.environ["MEMSNAV_DATA_ROOT"] = str(data_root)
    try:
        with contextlib.redirect_stdout(out), tempfile.TemporaryDirectory() as tmp:
            with contextlib.chdir(tmp):
                exec(compile(block.group(1), "when-a-run-fails.md", "exec"), {})
    finally:
        if saved is None:
            del os.environ["MEMSNAV_DATA_ROOT"]
        else:
            os.environ["MEMSNAV_DATA_ROOT"] = saved
    stage, ratio = out.getvalue().splitlines()[0].split()
    return {"stage": stage, "ratio": float(ratio)}


# --- the Xsens static session: docs/how-to/calibrate-an-imu.md -----------------

#: The gyro scale per count the Xsens data's README suggests, rad/s per
#: count, and the length of the session's initial rest, s (the data
#: source's description).
XSENS_README_GYRO_SCALE, XSENS_REST_S = 2.1e-4, 50.0

#: The Earth's rotation rate, rad/s (WGS84).
EARTH_RATE_RAD_S = 7.292115e-5


def xsens_guide(data_root: Path) -> dict[str, Any]:
    """docs/how-to/calibrate-an-imu.md's figures of the Xsens session that
    the other xsens_* runs of docs/doc_runs.py do not give, every 4th pose
    held out unless named: the poses, the held-out turns of each split,
    the halves' middle (s) and the poses the first half fits besides the
    rest; the turns' RMS miss (°) before calibration with
    the data source's nominal values, and with the README's gyro scale and
    the bias of the initial rest; the gyro's largest misalignment, %; how
    far the fitted gyro scale is above the data source's (mean over the
    axes, %); the largest difference of the corrected rates when the
    calibration starts from the README's scale instead, rad/s; the fitted
    accelerometer scale per count (least, most), m/s²; the nonlinearity
    N's largest σ at g (σ_N g², mm/s²) and, with N estimated, what it
    gains in the fit and the accelerometer biases' σ (mm/s²) and the
    biases' and scale factors' σ over those without it (least, most);
    the gyro's g-sensitivity (rows p, q, r) and its mean σ,
    (rad/s)/(m/s²); the largest move of a gyro axis's pose mean (README
    scale) from the initial rest's, mrad/s and in Earth rates."""
    import doc_runs  # imported here: doc_runs imports this module

    cal, accel, gyro = doc_runs._xsens_calibration(data_root, "determinable", holdout_every=4)
    every_4th = mn.static_summary(cal)
    t = accel[:, 0]
    middle = float((t[0] + t[-1]) / 2)
    halves = doc_runs._xsens_calibration(data_root, "determinable", holdout_from=middle)[0]
    held_halves = np.asarray(halves.pose_held_out)
    with_n = doc_runs._xsens_calibration(data_root, "all", holdout_every=4)[0]
    with_n_summary = mn.static_summary(with_n)

    def calibrated_from(**nominal: Any) -> Any:
        with warnings.catch_warnings():
            warnings.simplefilter("ignore")  # the data source's gyro scale is 31 % off
            return mn.calibrate_static(
                t,
                accel[:, 1:],
                gyro[:, 1:],
                gravity=doc_runs.XSENS_GRAVITY,
                holdout_every=4,
                **{**doc_runs.XSENS_NOMINAL, **nominal},
            )

    rest = gyro[t < t[0] + XSENS_REST_S, 1:].mean(axis=0)
    rest_bias = mn.static_summary(
        calibrated_from(gyro_scale=XSENS_README_GYRO_SCALE, gyro_offset=rest)
    )
    _, w = cal.correct(accel[:, 1:], gyro[:, 1:])
    _, w_readme = calibrated_from(gyro_scale=XSENS_README_GYRO_SCALE).correct(
        accel[:, 1:], gyro[:, 1:]
    )
    gyro_scale = np.asarray(cal.nominal["gyro_scale"]) / (
        1 - np.asarray(cal.gyroscope.scale_factor)
    )
    accel_scale = np.asarray(cal.nominal["accel_scale"]) / (
        1 - np.asarray(cal.accelerometer.scale_factor)
    )
    n_sigma = float(np.max(with_n.accelerometer_std.nonlinearity))
    bias_sigma = np.asarray(cal.accelerometer_std.bias)
    bias_sigma_n = np.asarray(with_n.accelerometer_std.bias)
    scale_ratio = np.asarray(with_n.accelerometer_std.scale_factor) / np.asarray(
        cal.accelerometer_std.scale_factor
    )
    rates = XSENS_README_GYRO_SCALE * (gyro[:, 1:] - doc_runs.XSENS_NOMINAL["gyro_offset"])
    means = np.array([rates[a:b].mean(axis=0) for a, b in cal.poses])
    move = float(np.abs(means - means[0]).max())
    return {
        "poses": len(cal.poses),
        "turns_held_out": {
            "every_4th": every_4th["turns_held_out"],
            "halves": mn.static_summary(halves)["turns_held_out"],
        },
        "middle_s": middle,
        "halves_fit_poses_after_rest": int((~held_halves).sum()) - 1,
        "source_nominal_turn_deg": {
            "fit": every_4th["turn_rms_before_fit_deg"],
            "held_out": every_4th["turn_rms_before_held_out_deg"],
        },
        "rest_bias_turn_deg": {
            "fit": rest_bias["turn_rms_before_fit_deg"],
            "held_out": rest_bias["turn_rms_before_held_out_deg"],
        },
        "gyro_misalignment_most_percent": 100.0
        * float(np.abs(np.asarray(cal.gyroscope.misalignment)).max()),
        "source_gyro_scale_low_percent": 100.0
        * float(np.mean(gyro_scale / doc_runs.XSENS_NOMINAL["gyro_scale"] - 1)),
        "readme_start_rates_rad_s": float(np.abs(w - w_readme).max()),
        "accel_scale_per_count": {
            "least": float(accel_scale.min()),
            "most": float(accel_scale.max()),
        },
        "n_sigma_at_g_mm_s2": 1e3 * n_sigma * doc_runs.XSENS_GRAVITY**2,
        "n_fit_gain_mm_s2": 1e3
        * (
            every_4th["magnitude_rms_after_fit_m_s2"]
            - with_n_summary["magnitude_rms_after_fit_m_s2"]
        ),
        "bias_sigma_with_n_mm_s2": _span((1e3 * bias_sigma_n).tolist()),
        "bias_sigma_ratio_with_n": _span((bias_sigma_n / bias_sigma).tolist()),
        "scale_sigma_ratio_with_n": _span(scale_ratio.tolist()),
        "g_sensitivity": np.asarray(cal.gyroscope.g_sensitivity).tolist(),
        "g_sensitivity_sigma_mean": float(np.mean(cal.gyroscope_std.g_sensitivity)),
        "rest_mean_move_mrad_s": 1e3 * move,
        "rest_mean_move_earth_rates": move / EARTH_RATE_RAD_S,
    }
