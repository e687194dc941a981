"""``navigate``: real IMU and GNSS logs through the core's log engine
(``memsnav.navigate_log``), scored against a truth (an RTK solution, another
system's INS) moved to the antenna and into the GNSS's datum.

This module only orchestrates: it reads the files the configuration names
(IMU CSV and its time tag, an RTKLIB solution or RINEX observations and
navigation data, the truth), hands the arrays and the engine's settings to
the core in one call, and writes what comes back (CSV, RTKLIB ``.pos``,
``summary.json``, the HTML report). Every number (time mapping of the
samples, mounting, alignment, the filter and its aids, the outages, the
local frames, the scoring) is computed in the core.
"""

from __future__ import annotations

import contextlib
import html
import json
import os
import time as _time
import warnings
from collections.abc import Iterator, Sequence
from dataclasses import dataclass
from pathlib import Path
from typing import Any

import numpy as np
import numpy.typing as npt

import memsnav._memsnav as _mn
from memsnav._files import check_replaceable, fresh_output_folder
from memsnav.realdata import fix_readers, readers, satellites
from memsnav.realdata.config import RunConfig, load_config
from memsnav.realdata.result import LogNavigationResult


def read_imu(cfg: RunConfig) -> tuple[np.ndarray, np.ndarray, np.ndarray, dict[str, Any]]:
    """IMU sample times on GPS time (before the configured offset), specific
    force and angular rate in the sensor's FRD axes (SI), and notes about
    the time mapping and the sampling (``imu_timing``: median interval,
    jitter, gaps)."""
    c = cfg["imu"]
    path = cfg.data_file("imu", "file")
    try:
        log = readers.read_imu_csv(
            path,
            c["columns"],
            accel_unit=c["accel_unit"],
            gyro_unit=c["gyro_unit"],
            time_unit=c["time_unit"],
            axes=c["axes"],
            skip_first_line=c["skip_first_line"],
            header_lines=c["header_lines"],
        )
    except readers.ParseError:
        raise  # names the data file
    except ValueError as e:
        # The layout and the units are checked by the reader, which names
        # its argument: the key of the same name.
        raise ValueError(f"{cfg.path}: imu.{e}") from None
    notes: dict[str, Any] = {"imu_timing": log.timing}
    if c["time_reference"] == "tag":
        tag = readers.read_time_tag(cfg.data_file("imu", "time_tag"))
        t, spread = readers.gps_time_from_tag(log, tag)
        notes["tag_arrival_spread_s"] = spread
    elif c["time_reference"] == "column_unix_gpst":
        t = log.time - readers.UNIX_TO_GPS_S
    else:
        t = log.time
    f, w = log.specific_force, log.angular_rate
    if c["calibration"]:
        f, w = apply_calibration(cfg, f, w)
    return t, f, w, notes


def apply_calibration(
    cfg: RunConfig, specific_force: np.ndarray, angular_rate: np.ndarray
) -> tuple[np.ndarray, np.ndarray]:
    """The readings corrected by the calibration file ``[imu] calibration``
    (docs/how-to/calibrate-an-imu.md). Only a calibration of SI readings applies (nominal
    scale 1, offset 0: a drive calibration, or a static one made from SI
    readings): the reader has already converted the log's units."""
    from memsnav.calibration.file import load_calibration

    path = cfg.config_path("imu", "calibration")
    assert path is not None  # read_imu calls this only when it is given
    if not path.exists():
        raise ValueError(
            f"{cfg.path}: imu.calibration: no such file {path} (relative to the "
            "configuration's folder)"
        )
    cal = load_calibration(path)
    if not cal.identity_nominal:
        raise ValueError(
            f"{cfg.path}: imu.calibration: {path} calibrates raw readings (nominal "
            f"accelerometer scale {cal.nominal['accel_scale'].tolist()}, offset "
            f"{cal.nominal['accel_offset'].tolist()}); "
            "navigate reads the IMU in SI units (imu.accel_unit, imu.gyro_unit): calibrate "
            "from SI readings (nominal scale 1, offset 0) to apply it here"
        )
    return cal.correct(specific_force, angular_rate)


#: RTKLIB's solution qualities (Q), by value.
_QUALITY_NAMES = ("none", "fix", "float", "SBAS", "DGPS", "single", "PPP", "dead reckoning")


def read_solution(cfg: RunConfig, table: str) -> tuple[readers.PosSolution, np.ndarray, np.ndarray]:
    """The solution ``[table] pos`` (RTKLIB ``.pos``, fixes CSV or NMEA:
    ``[table] format``, by default from the file name), which of its epochs
    have a quality in ``[table] quality`` (None having one is an error
    naming the key, the file and the qualities its epochs have), and its
    latitude, longitude (rad) and ellipsoidal height (m): heights above mean
    sea level (``[table] height = "msl"``) plus the geoid separation."""
    path = cfg.data_file(table, "pos")
    c = cfg[table]
    try:
        solution = fix_readers.read_fixes(
            path, c["format"], columns=c["columns"], time_reference=c["time_reference"]
        )
    except readers.ParseError:
        raise  # names the data file
    except ValueError as e:
        # The column mapping and the time reference are checked by the
        # reader, which names its argument: the key of the same name.
        raise ValueError(f"{cfg.path}: {table}.{e}") from None
    wanted = c["quality"]
    if wanted is None:
        # The file's own epochs, whatever their quality, each weighted by
        # the σ the file gives it: a receiver's standalone fixes (Q = 5)
        # are what many users have, and dropping them silently left runs
        # without GNSS.
        qualities, counts = np.unique(np.asarray(solution.quality), return_counts=True)
        used = ", ".join(
            f"Q = {q} ({_QUALITY_NAMES[int(q)]}) {n}"
            for q, n in zip(qualities.tolist(), counts.tolist(), strict=True)
        )
        warnings.warn(
            f"{cfg.path}: {table}.quality not given: using every epoch of {path} ({used}), "
            "each weighted by the file's own σ",
            stacklevel=3,
        )
        wanted = qualities.tolist()
    keep = np.isin(solution.quality, wanted)
    if not keep.any():
        present = sorted(set(np.asarray(solution.quality).tolist()))
        raise ValueError(
            f"{cfg.path}: {table}.quality: no epoch of {path} has a quality in {wanted}; "
            f"its {len(keep)} epochs have the qualities {present}"
        )
    lla = np.array(solution.lla, dtype=float)
    if cfg[table]["height"] == "msl":
        lla[:, 2] += cfg[table]["geoid_separation_m"]
    return solution, keep, lla


@dataclass(frozen=True)
class Truth:
    """The truth's epochs of the chosen quality as the configuration names
    it: ``name`` (``[truth] name``, else the file's name), ``path``, GPS
    ``time`` (s), ``geodetic`` (N, 3) at its own point (ellipsoidal),
    ``attitude`` (N, 3, 3) C_b^n or None, and ``lever_arm_m`` (``[truth]
    lever_arm_m``: the scored point from the truth's, its body axes)."""

    name: str
    path: Path
    time: np.ndarray
    geodetic: np.ndarray
    attitude: np.ndarray | None
    lever_arm_m: list[float]

    def position_ecef(self, offset_ned_m: npt.ArrayLike | None = None) -> np.ndarray:
        """ECEF at the scored point, with the datum offset ``offset_ned_m``
        (N, E, D, m) added (``memsnav.truth_at_point``)."""
        return np.asarray(
            _mn.truth_at_point(
                self.geodetic,
                self.attitude,
                lever_arm=self.lever_arm_m,
                offset_ned=offset_ned_m,
            )
        )


def read_truth(cfg: RunConfig) -> Truth | None:
    """The truth of the configuration (None when it names none); a lever
    arm for a truth without attitude is an error naming the key."""
    if cfg.data_path("truth", "pos") is None:
        return None
    solution, keep, lla = read_solution(cfg, "truth")
    path = cfg.data_file("truth", "pos")
    attitude = solution.attitude
    lever_arm = cfg["truth"]["lever_arm_m"]
    if any(lever_arm) and attitude is None:
        raise ValueError(
            f"{cfg.path}: truth.lever_arm_m: {path} gives no attitude (a fixes CSV's qw, qx, "
            "qy, qz or roll_deg, pitch_deg, yaw_deg columns): a lever arm in the truth's body "
            "axes needs it"
        )
    return Truth(
        name=cfg["truth"]["name"] or path.name,
        path=path,
        time=np.asarray(solution.gps_time)[keep],
        geodetic=lla[keep],
        attitude=None if attitude is None else np.asarray(attitude)[keep],
        lever_arm_m=lever_arm,
    )


def truth_before_the_run(cfg: RunConfig, truth: Truth) -> tuple[np.ndarray, np.ndarray]:
    """The truth's times and ECEF positions as scored, for a comparison made
    without a navigate run (a calibration session's): at the antenna, moved
    by a given datum offset. ``"from_gnss"`` needs a run's GNSS epochs: an
    error naming the key."""
    setting = cfg["truth"]["offset_ned_m"]
    if setting == "from_gnss":
        raise ValueError(
            f'{cfg.path}: truth.offset_ned_m = "from_gnss" is measured in a navigate run, '
            "from its GNSS epochs; a comparison without one needs it given ([n, e, d] m, the "
            "datum offset a navigate run of this configuration reports)"
        )
    return truth.time, truth.position_ecef(setting)


def gnss_input(cfg: RunConfig) -> Any:
    """The GNSS side of the run: fixes (loose) or pseudoranges (tight)."""
    return loose_input(cfg) if cfg["gnss"]["mode"] == "loose" else tight_input(cfg)


def _optional(values: dict[str, Any], *keys: str) -> dict[str, Any]:
    """The keys of ``values`` that were given (not None)."""
    return {k: values[k] for k in keys if values[k] is not None}


def loose_input(cfg: RunConfig) -> Any:
    """The GNSS solution's epochs of the chosen quality as antenna fixes
    (``PositionFixes``) with the file's covariances (full where it gives
    them): at ``rate_hz``, with seeded white noise added when asked for."""
    g = cfg["gnss"]
    sol, keep, lla = read_solution(cfg, "gnss")
    covariance = np.asarray(sol.covariance_ned)[keep]
    if np.isnan(np.asarray(sol.std_ned)[keep]).all():
        # A file without σ: exact positions (memsnav simulate's
        # trajectory.csv), which can play a receiver with noise added.
        if g["position_noise_m"] is None:
            raise ValueError(
                f"{cfg.path}: gnss.pos: {cfg.data_path('gnss', 'pos')} gives no position σ "
                "(std_n_m, std_e_m, std_d_m or cov_nn_m2, ...): loose coupling weights each fix "
                "by it; give the columns, or gnss.position_noise_m to add noise to exact "
                "positions (their σ is then that noise)"
            )
        covariance = np.zeros_like(covariance)
    given = _optional(g, "rate_hz", "velocity_noise_m_s", "use_velocity", "position_noise_m")
    kwargs: dict[str, Any] = {
        "rate_hz": given.get("rate_hz"),
        "added_velocity_noise": given.get("velocity_noise_m_s"),
        "use_velocity": given.get("use_velocity"),
        "added_position_noise_ned": given.get("position_noise_m"),
    }
    fixes = _mn.fixes_from_solution(
        sol.gps_time[keep],
        lla[keep],
        covariance_ned=covariance,
        velocity_ned=sol.velocity_ned[keep],
        velocity_covariance_ned=sol.velocity_covariance_ned[keep],
        seed=g["seed"],
        **kwargs,
    )
    if len(fixes) == 0:
        # Only rate_hz can leave none (the qualities matched some epochs).
        raise ValueError(
            f"{cfg.path}: gnss.rate_hz: no epoch of {cfg.data_path('gnss', 'pos')} lies on the "
            f"{g['rate_hz']:g} Hz grid (GPS time a multiple of 1/rate_hz, within 0.02 s)"
        )
    return fixes


def tight_input(cfg: RunConfig) -> Any:
    """Pseudoranges and Dopplers of the configured systems (``[gnss]
    systems``): from a u-blox log (``ubx``: its observations and the
    ephemerides decoded from it), from RINEX files (``obs`` + ``nav``), or
    from a long table (``table``). The Klobuchar coefficients are the
    configuration's, else the navigation file's, else the log's (GPS CNAV
    type 30), else RTKLIB's defaults."""
    g = cfg["gnss"]
    if g["table"]:
        return table_input(cfg)
    alpha, beta = g["klobuchar_alpha"], g["klobuchar_beta"]
    klobuchar: tuple[Sequence[float], Sequence[float]] | None = (alpha, beta) if alpha else None
    if g["ubx"]:
        log = _mn.read_ubx(cfg.data_file("gnss", "ubx"))
        observations, ephemerides = log.observations, log.broadcast_ephemerides
        klobuchar = klobuchar or log.klobuchar
    else:
        observations = _mn.read_rinex_obs(cfg.data_file("gnss", "obs"))
        ephemerides = _mn.read_broadcast_nav(cfg.data_file("gnss", "nav"))
    if klobuchar is None and g["nav"]:
        klobuchar = _mn.read_klobuchar(cfg.data_file("gnss", "nav"))
    try:
        return observations.measurements(
            ephemerides,
            systems=g["systems"],
            elevation_mask_deg=g["elevation_mask_deg"],
            min_cn0_db_hz=g["min_cn0_db_hz"],
            ionosphere=g["ionosphere"],
            klobuchar=klobuchar,
            troposphere=g["troposphere"],
            # The filters' noise was tuned with the signal-strength model.
            weighting="signal-strength",
            pseudorange_std=g["pseudorange_std_m"],
            pseudorange_rate_std=g["pseudorange_rate_std_m_s"],
            satellites=g["satellites"] or None,
            dual_frequency=g["dual_frequency"],
        )
    except ValueError as e:
        # What the core checks beyond the configuration's ranges (the
        # Klobuchar coefficients' ICD ranges), named by its argument.
        raise ValueError(f"{cfg.path}: gnss: {e}") from None


def table_input(cfg: RunConfig) -> Any:
    """Pseudoranges (and rates) from a long table, one row per epoch and
    satellite (``GnssMeasurements.from_table``: the ``gnss.csv`` of ``memsnav
    simulate``), σ columns left out taking ``pseudorange_std_m`` and
    ``pseudorange_rate_std_m_s``. A navigate run's IMU is on GPS time, so the
    epochs are at the table's ``gps_time_s`` when it has one (``time_s`` is
    then a time axis of its own, as in a simulation's table), else at its
    ``time_s``, taken as GPS time."""
    g = cfg["gnss"]
    path = cfg.data_file("gnss", "table")
    try:
        table = _mn.GnssMeasurements.from_table(
            path,
            pseudorange_std=g["pseudorange_std_m"],
            pseudorange_rate_std=g["pseudorange_rate_std_m_s"],
        )
    except ValueError as e:
        raise ValueError(f"{cfg.path}: gnss.table: {e}") from None
    fields = (
        "sat_id",
        "satellite_position_ecef",
        "satellite_velocity_ecef",
        "pseudorange",
        "pseudorange_std",
        "pseudorange_rate",
        "pseudorange_rate_std",
    )
    return _mn.GnssMeasurements(
        time=table.gps_time,
        start_gps_time=float(table.gps_time[0]),
        **{name: getattr(table, name) for name in fields},
    )


def _counts(run: Any) -> dict[str, dict[str, int]]:
    """Scalar measurements per kind and status."""
    m = run.solution.measurements
    kinds, statuses = np.asarray(m["kind"]), np.asarray(m["status"])
    out: dict[str, dict[str, int]] = {}
    for kind in dict.fromkeys(kinds.tolist()):
        sel = kinds == kind
        out[str(kind)] = {
            str(s): int(np.sum(statuses[sel] == s)) for s in dict.fromkeys(statuses[sel].tolist())
        }
    return out


def _finite(value: Any) -> Any:
    """``value`` with every non-finite float replaced by None (strict JSON)."""
    if isinstance(value, dict):
        return {k: _finite(v) for k, v in value.items()}
    if isinstance(value, list | tuple):
        return [_finite(v) for v in value]
    if isinstance(value, float) and not np.isfinite(value):
        return None
    return value


def _statistics(score: dict[str, Any], outages: Any, anchor: float) -> dict[str, Any]:
    """The statistics of a ``LogRun.score`` for ``summary.json``, each
    outage's start in s after ``anchor`` (the earliest start the log allows,
    as configured)."""
    stats: dict[str, Any] = {
        "all": score["all"],
        "aided": score["aided"],
        "in_outages": score["in_outages"],
    }
    for i, (window, st) in enumerate(zip(outages, score["outages"], strict=True)):
        stats[f"outage_{i + 1}"] = {
            "start_s": float(window[0] - anchor),
            "length_s": float(window[1] - window[0]),
            **st,
        }
    stats["by_outage_length_s"] = {
        f"{length:g}": st for length, st in score["by_outage_length"].items()
    }
    return stats


# Sensor error states in the summary: (state-name prefix, summary key,
# factor from the state's SI unit to the key's unit).
_SENSOR_STATES = (
    ("accel_bias", "accel_bias_m_s2", 1.0),
    ("gyro_bias", "gyro_bias_deg_s", float(np.degrees(1.0))),
    ("accel_scale_factor", "accel_scale_factor_ppm", 1e6),
    ("gyro_scale_factor", "gyro_scale_factor_ppm", 1e6),
)


# Installation states in the summary: (summary key, state names, factor
# from the state's SI unit to the key's unit); the columns of
# ``FilterSolution.installation`` are in the order of the names.
_INSTALLATION_STATES = (
    ("lever_arm_m", ("lever_arm_x", "lever_arm_y", "lever_arm_z"), 1.0),
    ("time_offset_s", ("time_offset",), 1.0),
    ("velocity_latency_s", ("velocity_latency",), 1.0),
    ("mounting_pitch_yaw_deg", ("mounting_pitch", "mounting_yaw"), float(np.degrees(1.0))),
)


def _installation_estimates(solution: _mn.FilterSolution, sample: int) -> dict[str, Any] | None:
    """The installation states at one sample with their one-sigma (None
    without the states): the lever arm in body axes, the IMU time offset
    (added to the IMU time stamps, on top of ``[imu] time_offset_s``), the
    velocity latency and the mounting boresight's pitch and yaw (its roll
    is not observable and not a state)."""
    values = solution.installation
    if values is None:
        return None
    names = solution.state_names
    variances = np.asarray(solution.covariance_diagonal)[sample]
    row = np.asarray(values)[sample]
    first = names.index("lever_arm_x")
    estimates: dict[str, Any] = {"gps_time_s": float(np.asarray(solution.time)[sample])}
    for key, state_names, factor in _INSTALLATION_STATES:
        columns = [names.index(n) for n in state_names]
        value = factor * row[[c - first for c in columns]]
        std = factor * np.sqrt(variances[columns])
        single = len(columns) == 1
        estimates[key] = {
            "value": float(value[0]) if single else value.tolist(),
            "std": float(std[0]) if single else std.tolist(),
        }
    return estimates


def _sensor_estimates(solution: _mn.FilterSolution, sample: int) -> dict[str, Any]:
    """The sensor error states at one sample with their one-sigma from the
    filter's covariance, in the summary's units (scale factors only when the
    filter has them). The filter's model is f̃ = (1 + s) f + b per axis."""
    names = solution.state_names
    variances = np.asarray(solution.covariance_diagonal)[sample]
    estimates: dict[str, Any] = {"gps_time_s": float(np.asarray(solution.time)[sample])}
    for prefix, key, factor in _SENSOR_STATES:
        values = getattr(solution, prefix)
        if values is None:
            continue
        columns = [names.index(f"{prefix}_{axis}") for axis in "xyz"]
        estimates[key] = {
            "value": (factor * np.asarray(values)[sample]).tolist(),
            "std": (factor * np.sqrt(variances[columns])).tolist(),
        }
    return estimates


def navigate(
    config: str | Path | RunConfig,
    *,
    data_root: str | Path | None = None,
    output: str | Path | None = None,
    duration_s: float | None = None,
) -> LogNavigationResult:
    """Runs a configuration end to end and writes its outputs.

    ``config``: a TOML path or a loaded :class:`RunConfig`; ``data_root``
    overrides where relative data paths point; ``output`` the output folder
    (default the config's ``output``, relative to the configuration's
    folder); ``duration_s`` stops the run that many seconds after the start
    (a quick look or a test).

    A run that fails once its output folder is accepted (an input that
    cannot be read, a start that cannot be found, a filter that stops or
    diverges, a gyro unit the GNSS course contradicts, a file that cannot
    be written) still replaces the folder's contents: ``summary.json`` with
    a ``failure`` entry (``stage``, ``what``, when: ``gps_time_s`` and
    ``time_s`` after the start, ``message``, ``hints``: the warnings that
    may explain it) and whatever was computed before it, the solution files
    of a run that stopped (up to where it stopped) and ``report.html``
    opening with the failure. Then it raises the error, with the result as
    its ``result`` attribute: the error as it happened (``ValueError`` for
    an input, ``OSError``...), ``ValueError`` naming ``imu.gyro_unit`` for a
    gyro unit the course contradicts, :class:`memsnav.DivergenceError` for a
    run that stopped early or diverged (docs/how-to/when-a-run-fails.md, "When a run
    fails"). An interrupt (Ctrl-C) leaves the folder as it was.
    """
    started = _time.perf_counter()
    cfg = config if isinstance(config, RunConfig) else load_config(config, data_root)
    if duration_s is not None and not (np.isfinite(duration_s) and duration_s > 0):
        raise ValueError(f"duration: must be a positive number of seconds, got {duration_s}")
    out = Path(output) if output is not None else cfg.config_path("", "output")
    assert out is not None  # "output" has a default
    # Refused before the run, not after it (and checked again when replaced).
    check_replaceable(out, "navigate")
    result = LogNavigationResult(
        cfg,
        None,
        None,
        None,
        summary={"name": cfg[""]["name"], "mode": cfg["gnss"]["mode"], "input_warnings": []},
    )
    failures = _Failures(result.summary)
    _run(result, duration_s, failures)
    result.summary["processing_s"] = _time.perf_counter() - started
    _write_outputs(result, out, failures)
    failure = result.failure
    if failure is not None:
        raised = failures.first_error or _failure_error(cfg, failure)
        raised.add_note(f"memsnav navigate: the failed run's summary and report are in {out}")
        setattr(raised, "result", result)  # noqa: B010  (no attribute on the exception types)
        raise raised
    return result


def _run(result: LogNavigationResult, duration_s: float | None, failures: _Failures) -> None:
    """The run of ``result.config`` into ``result``: the inputs, the engine,
    the summary, the scores. An exception ends it, recorded in
    ``failures``; so are the failures that are not exceptions (a run
    stopped or diverged, a gyro unit the GNSS course contradicts)."""
    cfg, summary = result.config, result.summary
    mode = cfg["gnss"]["mode"]
    try:
        with _recording_warnings(summary["input_warnings"]):
            t, f_s, w_s, notes = read_imu(cfg)
            gnss = gnss_input(cfg)
            truth = read_truth(cfg)  # before the run: a truth that matches nothing fails at once
    except Exception as e:
        failures.add("inputs", "reading the inputs", e)
        return
    run_started = _time.perf_counter()
    try:
        with warnings.catch_warnings():
            # Said once, by the failure entry and the command's error.
            warnings.filterwarnings("ignore", message="the run stopped at", category=UserWarning)
            run = _mn.navigate_log(t, f_s, w_s, gnss, settings=cfg.engine, duration_s=duration_s)
    except ValueError as e:
        # What the logs hold against each other (times, a start), found by
        # the core: the configuration that paired them is the one to name.
        error = ValueError(f"{cfg.path}: {e}")
        failures.add("run", "starting the run", error)
        return
    except Exception as e:
        failures.add("run", "the run", e)
        return
    run_s = _time.perf_counter() - run_started
    result.run = run
    try:
        _summarise(result, notes, gnss)
    except Exception as e:
        failures.add("summary", "summarising the run", e)
        return
    summary["filter_run_s"] = run_s
    _check_run(result, failures)
    if truth is not None:
        try:
            summary["truth_is_gnss_input"] = _same_file(truth.path, cfg.data_path("gnss", "pos"))
            scored = _truth_in_gnss_datum(cfg, run, truth, summary)
            _score(result, (truth.time, scored), precision=cfg["truth"]["score"] == "precision")
            if mode == "tight":
                after = np.asarray(run.gnss["time"]) >= summary["start_gps_time_s"]
                valid = np.all(np.isfinite(np.asarray(run.gnss["position_ecef"])), axis=1)
                summary["spp_epochs_without_fix"] = int(np.sum(after & ~valid))
        except Exception as e:
            failures.add("scoring", "scoring against the truth", e)


def _summarise(result: LogNavigationResult, notes: dict[str, Any], gnss: Any) -> None:
    """The run's numbers into ``result.summary``: the start, the counts,
    the integrity, the resets, the estimates (times after the start)."""
    cfg, run, summary = result.config, result.run, result.summary
    mode = summary["mode"]
    start = run.start
    t0 = start.time
    # The outage windows count from the earliest start the log allows, not
    # from the start the alignment found (a late start does not move them).
    anchor = start.earliest_time
    solution = run.solution
    batches = solution.batches
    resets = solution.resets
    summary.update(
        {
            "start": {
                "kind": start.kind,
                "gps_time_s": t0,
                "heading_from_first_motion": start.kind == "static",
                "after_first_imu_sample_s": t0 - start.first_imu_time,
                "after_first_gnss_epoch_s": t0 - start.first_gnss_time,
                "earliest_gps_time_s": anchor,
                "late_reason": start.late_reason,
            },
            "start_gps_time_s": float(t0),
            "duration_s": float(run.time[-1] - run.time[0]),
            "imu_samples": len(run),
            "imu_calibration": str(cfg.config_path("imu", "calibration") or "") or None,
            "gnss_epochs_used": int(np.sum(run.gnss["used"])),
            "measurements": _counts(run),
            "batches_failed": int(np.sum(~np.asarray(batches["accepted"]))),
            "diverged": bool(solution.diverged),
            "integrity": _integrity(solution.integrity, t0),
            "warnings": list(solution.warnings),
            "gyro_scale": None if run.gyro_scale is None else run.gyro_scale.to_dict(),
            "resets": [
                {
                    "time_s": float(tr - t0),
                    "kind": str(k),
                    "change": float(c),
                    "unit": str(u),
                    "failed_epochs": int(n),
                }
                for tr, k, c, u, n in zip(
                    resets["time"],
                    resets["kind"],
                    resets["change"],
                    resets["unit"],
                    resets["failed_epochs"],
                    strict=True,
                )
            ],
            "standstills_s": [[float(a - t0), float(b - t0)] for a, b in run.standstills],
            "outages_s": [[float(a - anchor), float(b - a)] for a, b in run.outages],
            "sensor_estimates": _sensor_estimates(solution, -1),
            "adaptation": run.adaptation,
            **notes,
        }
    )
    if run.smoothed is not None:
        summary["sensor_estimates_smoothed"] = _sensor_estimates(run.smoothed.solution, 0)
    installation = _installation_estimates(solution, -1)
    if installation is not None:
        summary["installation_estimates"] = installation
    if solution.inter_system_bias is not None:
        galileo, beidou, glonass = solution.inter_system_bias[-1]
        summary["inter_system_bias_m"] = {
            "galileo": float(galileo),
            "beidou": float(beidou),
            "glonass": float(glonass),
        }
    if run.carrier_phase is not None:
        # How many carrier changes the run used, and why not (its warning is
        # among the solution's).
        summary["carrier_phase"] = run.carrier_phase.to_dict()
    if mode == "tight":
        rows = satellites.satellite_rows(solution.measurements, gnss)
        summary["satellites"] = rows
        summary["satellite_systems"] = satellites.system_totals(rows)
    if run.range_biases and mode == "tight":
        summary["range_biases_m"] = {
            _mn.satellite_name(int(k)): v for k, v in run.range_biases.items()
        }
    elif run.range_biases:
        # Loose coupling's slots hold the fixes' position error per ECEF axis.
        summary["fix_error_ecef_m"] = [run.range_biases[axis] for axis in range(3)]


def _check_run(result: LogNavigationResult, failures: _Failures) -> None:
    """The failures a finished engine call can hold without raising, into
    the summary in the order they matter: the run stopped before the end of
    the log, the gyro's turns contradict its unit, the solution diverged."""
    run, summary = result.run, result.summary
    t0 = summary["start_gps_time_s"]
    if run.failure is not None:
        failures.add(
            "run",
            "the run stopped before the end of the log; the solution ends there",
            run.failure.message,
            gps_time_s=run.failure.time,
        )
    gyro = run.gyro_scale
    if gyro is not None and gyro.warning is not None:
        failures.add("units", "the gyro's turns contradict its unit", gyro.warning)
    alerts = summary["integrity"]["alerts"]
    if summary["integrity"]["diverged"] and alerts:
        failures.add(
            "integrity",
            "the solution diverged (integrity alert): it is not trustworthy",
            alerts[0]["message"],
            gps_time_s=alerts[0]["time_s"] + t0,
        )


@dataclass
class _Failures:
    """A run's failures, into its summary: the first as ``failure``
    (``stage``, ``what``, ``gps_time_s`` and ``time_s`` after the start when
    known, ``message``, ``hints``: the inputs' warnings and the run's, which
    may explain it), any later one under its ``also``; and the first one's
    exception when it was one (the one :func:`navigate` raises)."""

    summary: dict[str, Any]
    first_error: Exception | None = None

    def add(
        self,
        stage: str,
        what: str,
        error: Exception | str,
        *,
        gps_time_s: float | None = None,
    ) -> None:
        message = error if isinstance(error, str) else _message(error)
        t0 = self.summary.get("start_gps_time_s")
        entry: dict[str, Any] = {
            "stage": stage,
            "what": what,
            "gps_time_s": gps_time_s,
            "time_s": None if gps_time_s is None or t0 is None else gps_time_s - t0,
            "message": message,
        }
        failure = self.summary.get("failure")
        if failure is not None:
            failure.setdefault("also", []).append(entry)
            return
        warned = [*self.summary.get("input_warnings", []), *self.summary.get("warnings", [])]
        self.summary["failure"] = {**entry, "hints": [w for w in warned if w != message]}
        if isinstance(error, Exception):
            self.first_error = error


def _message(error: BaseException) -> str:
    """An exception as one line: its message (its type when it has none)."""
    return " ".join(str(error).split()) or type(error).__name__


def _failure_error(cfg: RunConfig, failure: dict[str, Any]) -> Exception:
    """The exception of a failure that was not one (module docstring of
    :func:`navigate`)."""
    if failure["stage"] == "units":
        return ValueError(f"{cfg.path}: imu.{failure['message']}")
    return _mn.DivergenceError(f"{cfg.path}: {failure['what']}: {failure['message']}")


@contextlib.contextmanager
def _recording_warnings(into: list[str]) -> Iterator[None]:
    """Records the text of every warning raised inside into ``into`` (for
    the summary) and raises each again after, as it was (for the terminal),
    also when the block fails."""
    seen: list[warnings.WarningMessage] = []
    try:
        with warnings.catch_warnings(record=True) as caught:
            warnings.simplefilter("always")
            try:
                yield
            finally:
                seen = list(caught or [])
    finally:
        for w in seen:
            into.append(str(w.message))
            warnings.warn_explicit(w.message, w.category, w.filename, w.lineno)


def _in_run(run: Any, time: np.ndarray) -> np.ndarray:
    """Which of ``time`` lie inside the run's span (its start to its end)."""
    t = np.asarray(run.time)
    inside: np.ndarray = (time >= t[0]) & (time <= t[-1])
    return inside


def _truth_in_gnss_datum(
    cfg: RunConfig, run: Any, truth: Truth, summary: dict[str, Any]
) -> np.ndarray:
    """The truth's ECEF positions as scored: at the antenna (its lever arm)
    and moved by the datum offset ``[truth] offset_ned_m`` (the GNSS's datum
    less the truth's): given, or ``"from_gnss"``, the mean of (GNSS − truth)
    over the GNSS epochs inside the run's span (those in the scheduled
    outages too: the offset belongs to the two references, not to the
    schedule), the truth interpolated at each epoch. Records the truth
    and the offset in ``summary["truth"]``."""
    at_point = truth.position_ecef()
    setting = cfg["truth"]["offset_ned_m"]
    described: dict[str, Any] = {
        "name": truth.name,
        "file": str(truth.path),
        "epochs": len(truth.time),
        "attitude": truth.attitude is not None,
        "lever_arm_m": list(truth.lever_arm_m),
    }
    if setting == "from_gnss":
        inside = _in_run(run, truth.time)
        estimate = run.score_gnss(
            truth.time[inside], at_point[inside], interpolate=True, remove_mean_offset=True
        )
        count = estimate["stats"]["epochs"]
        if count == 0:
            raise ValueError(
                f'{cfg.path}: truth.offset_ned_m = "from_gnss": no GNSS epoch of the run lies '
                f"between two epochs of {truth.path} at most 1 s apart; give the offset "
                "([n, e, d] m) instead"
            )
        offset = np.asarray(estimate["offset_removed_ned"], dtype=float)
        described["datum_offset"] = {
            "source": "from_gnss",
            "ned_m": offset.tolist(),
            "gnss_epochs": int(count),
        }
    elif setting is None:
        offset = np.zeros(3)
        described["datum_offset"] = {"source": "none", "ned_m": offset.tolist()}
    else:
        offset = np.asarray(setting, dtype=float)
        described["datum_offset"] = {"source": "given", "ned_m": offset.tolist()}
    summary["truth"] = described
    return at_point if setting is None else truth.position_ecef(offset)


def _same_file(a: Path | None, b: Path | None) -> bool:
    """Whether two configured paths name one file: a truth that is the
    filter's own GNSS input scores how closely the filter follows it."""
    return a is not None and b is not None and a.resolve() == b.resolve()


def _score(
    result: LogNavigationResult, truth: tuple[np.ndarray, np.ndarray], *, precision: bool
) -> None:
    """The errors against the truth: of the forward solution, the smoothed
    one, and the GNSS epochs' own positions (loose coupling: its fixes;
    tight: the single-point fixes), into ``result`` and its summary. Always
    by accuracy (``errors_vs_truth``...); with ``precision`` also less each
    solution's own mean offset (``..._precision``, with the offset
    removed): a truth known to sit a constant unknown offset away
    (docs/explanation/time-and-truth.md, "Truth"; a known datum offset is the truth's own,
    ``_truth_in_gnss_datum``)."""
    run, summary = result.run, result.summary
    anchor = summary["start"]["earliest_gps_time_s"]
    tt, r_truth = truth
    scored: dict[str, tuple[dict[str, Any], dict[str, Any] | None]] = {}
    for name, solution in (("", run), ("_smoothed", run.smoothed)):
        if solution is None:
            continue
        raw = solution.score(tt, r_truth)
        summary[f"errors_vs_truth{name}"] = _statistics(raw, run.outages, anchor)
        scored[name] = (raw, None)
        if precision:
            precise = solution.score(tt, r_truth, remove_mean_offset=True)
            summary[f"errors_vs_truth{name}_precision"] = {
                "offset_removed_ned_m": precise["offset_removed_ned"].tolist(),
                **_statistics(precise, run.outages, anchor),
            }
            scored[name] = (raw, precise)
    result.truth = {**scored[""][0], "position_ecef": r_truth, "all_time": tt}
    result.truth_smoothed = scored["_smoothed"][0] if "_smoothed" in scored else None
    result.precision = {
        (name[1:] or "forward"): precise for name, (_, precise) in scored.items() if precise
    } or None
    if summary["mode"] == "loose":
        # The fixes the filter was given, against the same truth (inside
        # the run's span, the truth interpolated at each): what the filter
        # adds to them.
        inside = _in_run(run, tt)
        fixes = run.score_gnss(tt[inside], r_truth[inside], interpolate=True)
        summary["gnss_errors_vs_truth"] = fixes["stats"]
        if precision:
            precise = run.score_gnss(
                tt[inside], r_truth[inside], interpolate=True, remove_mean_offset=True
            )
            summary["gnss_errors_vs_truth_precision"] = {
                "offset_removed_ned_m": precise["offset_removed_ned"].tolist(),
                **precise["stats"],
            }
    if summary["mode"] == "tight":
        result.spp = run.score_gnss(tt, r_truth)
        summary["spp_errors_vs_truth"] = result.spp["stats"]
        if precision:
            precise = run.score_gnss(tt, r_truth, remove_mean_offset=True)
            summary["spp_errors_vs_truth_precision"] = {
                "offset_removed_ned_m": precise["offset_removed_ned"].tolist(),
                **precise["stats"],
            }
            result.precision = {**(result.precision or {}), "spp": precise}


def _integrity(integrity: _mn.Integrity, t0: float) -> dict[str, Any]:
    """The solution's integrity (``FilterSolution.integrity``) under its own
    field names, its times (``time_s``, ``max_at_s``) in seconds after the
    start like every time in ``summary.json``."""
    return {
        **integrity.to_dict(),
        "alerts": [{**a.to_dict(), "time_s": float(a.time_s - t0)} for a in integrity.alerts],
        "consistency": [
            {**c.to_dict(), "max_at_s": float(c.max_at_s - t0)} for c in integrity.consistency
        ],
    }


def _write_outputs(result: LogNavigationResult, out: Path, failures: _Failures) -> None:
    """The run's files into a fresh ``out`` (replacing an earlier run's):
    the solution files of what was computed, the report, then the summary,
    so that it records a file that could not be written. A writer or the
    report failing is a failure of the run, not of the writing: the other
    files are still written (the report, then, as a page naming the
    failure)."""
    name = result.config[""]["name"]  # a plain file name (the configuration checks it)
    summary = result.summary
    files = {}
    with fresh_output_folder(out, "navigate") as tmp:
        run = result.run
        views = (("", run), ("smoothed_", None if run is None else run.smoothed))
        for prefix, view in views:
            stem = f"{name}_smoothed" if prefix else name
            if view is None:
                continue
            for extension in ("csv", "pos"):
                try:
                    view.write(tmp / f"{stem}.{extension}")
                except Exception as e:
                    failures.add("outputs", f"writing {stem}.{extension}", e)
                else:
                    files[f"{prefix}{extension}"] = f"{stem}.{extension}"
        if result.config["report"]["html"]:
            # Deferred: the report needs matplotlib, which ``import memsnav``
            # does not load.
            try:
                from memsnav.realdata.report import write_report

                write_report(result, tmp)
            except Exception as e:
                failures.add("report", "drawing the report", e)
                _write_failure_page(result, tmp)
            files["report"] = "report.html"
        result.summary = _finite(summary)
        (tmp / "summary.json").write_text(json.dumps(result.summary, indent=2, allow_nan=False))
        files["summary"] = "summary.json"
        for p in tmp.rglob("*"):
            os.chmod(p, 0o755 if p.is_dir() else 0o644)
    order = ("csv", "pos", "smoothed_csv", "smoothed_pos", "summary", "report")
    result.files = {k: str(out / files[k]) for k in order if k in files}


def _write_failure_page(result: LogNavigationResult, out: Path) -> None:
    """``report.html`` when the report itself could not be drawn: the
    failures and the answer, plain HTML (no figure, nothing that could fail
    the same way)."""
    from memsnav.realdata.answer import answer_lines

    s = result.summary
    try:
        lines = answer_lines(s)
    except Exception:
        lines = [f"{s['name']}: {s['mode']} coupling"]
    failure = s["failure"]
    entries = [failure, *failure.get("also", [])]
    body = "".join(
        f"<p><b>{html.escape(e['what'])}</b> ({html.escape(e['stage'])}): "
        f"{html.escape(e['message'])}</p>"
        for e in entries
    )
    items = "".join(f"<li>{html.escape(line.strip())}</li>" for line in lines)
    title = html.escape(f"memsnav navigate: {s['name']}")
    (out / "report.html").write_text(
        f"<!DOCTYPE html><html><head><meta charset='utf-8'><title>{title}</title></head>"
        f"<body><h1>{title}</h1><h2>The run failed</h2>{body}<h2>The answer</h2>"
        f"<ul>{items}</ul><p>summary.json holds every number.</p></body></html>\n",
        encoding="utf-8",
    )
