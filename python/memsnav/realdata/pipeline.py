"""``navigate``: real IMU and GNSS logs through a coupled filter, scored
against an RTK truth (issue 8).

Steps: read the IMU (time to GPS time by the RTKLIB tag, mounting into
body axes FRD), read the GNSS (an RTKLIB solution with optional added noise
for loose coupling, or RINEX observations + navigation for tight
coupling), align (level from the mean specific force, heading from the GNSS
course at the first epoch above a speed, or a given heading at rest), drop
the GNSS in the scheduled outage windows, run the filter, write the
solution (CSV and RTKLIB ``.pos``), errors against the truth with the
filter's 3sigma bounds, ``summary.json`` and an HTML report.
"""

from __future__ import annotations

import json
import time as _time
from dataclasses import dataclass, field
from pathlib import Path
from typing import Any

import numpy as np

import memsnav._memsnav as _mn
from memsnav.realdata import readers
from memsnav.realdata.config import RunConfig, load_config


def c_n_e(lat: np.ndarray, lon: np.ndarray) -> np.ndarray:
    """NED-to-ECEF rotations, ``(N, 3, 3)`` (Groves eq. 2.150, transposed)."""
    sl, cl, so, co = np.sin(lat), np.cos(lat), np.sin(lon), np.cos(lon)
    return np.stack(
        [
            np.stack([-sl * co, -so, -cl * co], -1),
            np.stack([-sl * so, co, -cl * so], -1),
            np.stack([cl, np.zeros_like(lat), -sl], -1),
        ],
        -2,
    )


def euler_to_dcm(roll: float, pitch: float, yaw: float) -> np.ndarray:
    """C_b^n from roll, pitch, yaw, rad (Groves eq. 2.22 transposed)."""
    cr, sr, cp, sp, cy, sy = (
        np.cos(roll),
        np.sin(roll),
        np.cos(pitch),
        np.sin(pitch),
        np.cos(yaw),
        np.sin(yaw),
    )
    return np.array(
        [
            [cp * cy, -cr * sy + sr * sp * cy, sr * sy + cr * sp * cy],
            [cp * sy, cr * cy + sr * sp * sy, -sr * cy + cr * sp * sy],
            [-sp, sr * cp, cr * cp],
        ]
    )


def dcm_to_euler(c: np.ndarray) -> np.ndarray:
    """Roll, pitch, yaw (rad) of C_b^n matrices ``(N, 3, 3)`` → ``(N, 3)``."""
    return np.column_stack(
        [
            np.arctan2(c[:, 2, 1], c[:, 2, 2]),
            -np.arcsin(np.clip(c[:, 2, 0], -1.0, 1.0)),
            np.arctan2(c[:, 1, 0], c[:, 0, 0]),
        ]
    )


def mounting_matrix(rpy_deg: list[list[float]]) -> np.ndarray:
    """C_b^s: body ← sensor rotation from a sequence of roll/pitch/yaw
    triples applied in order, f_b = C(last) ··· C(first) f_s, each C the
    DCM of ``euler_to_dcm`` (so a triple is the sensor's attitude relative
    to the frame that follows)."""
    c = np.eye(3)
    for triple in rpy_deg:
        if len(triple) != 3:
            raise ValueError(
                f"imu.mounting_rpy_deg: each rotation needs roll, pitch, yaw; got {triple}"
            )
        c = euler_to_dcm(*np.radians(triple)) @ c
    return c


@dataclass
class NavigationResult:
    """Everything a run produced; ``summary`` is the plain dict written to
    ``summary.json``."""

    config: RunConfig
    time: np.ndarray
    lla: np.ndarray
    velocity_ned: np.ndarray
    euler: np.ndarray
    position_std_ned: np.ndarray
    velocity_std_ned: np.ndarray
    outages: list[tuple[float, float]]
    gnss_lla: np.ndarray
    truth: dict[str, np.ndarray] | None
    spp: dict[str, np.ndarray] | None
    summary: dict[str, Any] = field(default_factory=dict)
    files: dict[str, str] = field(default_factory=dict)


def _vec3(cfg: RunConfig, section: str, key: str) -> np.ndarray:
    v = cfg[section][key]
    if len(v) != 3 or not all(isinstance(x, (int, float)) for x in v):
        raise ValueError(f"{cfg.path}: {section}.{key} must be three numbers, got {v!r}")
    return np.asarray(v, dtype=float)


def _require(cfg: RunConfig, section: str, key: str) -> Path:
    p = cfg.data_path(section, key)
    if p is None:
        raise ValueError(f"{cfg.path}: {section}.{key} is required for this run")
    if not p.exists():
        raise ValueError(
            f"{cfg.path}: {section}.{key}: no such file {p} (data root {cfg.data_root})"
        )
    return p


def read_imu(cfg: RunConfig) -> tuple[np.ndarray, np.ndarray, np.ndarray, dict[str, float]]:
    """GPS time (s), specific force and angular rate in body axes (FRD) at
    the IMU, and notes about the time mapping."""
    c = cfg["imu"]
    path = _require(cfg, "imu", "file")
    log = readers.read_imu_csv(
        path,
        c["columns"],
        accel_unit=c["accel_unit"],
        gyro_unit=c["gyro_unit"],
        time_unit=c["time_unit"],
        skip_first_line=c["skip_first_line"],
        header_lines=c["header_lines"],
    )
    notes: dict[str, float] = {}
    if c["time_reference"] == "tag":
        tag = readers.read_time_tag(_require(cfg, "imu", "time_tag"))
        t, spread = readers.gps_time_from_tag(log, tag)
        notes["tag_arrival_spread_s"] = spread
    elif c["time_reference"] == "column_unix_gpst":
        t = log.time - readers.UNIX_TO_GPS_S
    else:
        t = log.time
    t = t + c["time_offset_s"]
    c_b_s = mounting_matrix(c["mounting_rpy_deg"])
    return t, log.specific_force @ c_b_s.T, log.angular_rate @ c_b_s.T, notes


@dataclass
class GnssInput:
    time: np.ndarray
    position_ecef: np.ndarray  # at the antenna
    velocity_ecef: np.ndarray
    position_cov: np.ndarray | None = None
    velocity_cov: np.ndarray | None = None
    measurements: Any = None
    spp_valid: np.ndarray | None = None


def _pos_to_ecef(sol: readers.PosSolution) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    r = np.asarray(_mn.geodetic_to_ecef(sol.lla))
    cne = c_n_e(sol.lla[:, 0], sol.lla[:, 1])
    v = np.einsum("nij,nj->ni", cne, sol.velocity_ned)
    return r, v, cne


def loose_input(cfg: RunConfig) -> GnssInput:
    """RTKLIB fixes at ``rate_hz`` with white noise of the given NED stds
    added (seeded), their covariance = RTK std² + added noise²."""
    g = cfg["gnss"]
    sol = readers.read_pos(_require(cfg, "gnss", "pos"))
    keep = np.isin(sol.quality, g["quality"])
    if g["rate_hz"] <= 0:
        raise ValueError(f"{cfg.path}: gnss.rate_hz must be positive, got {g['rate_hz']}")
    step = 1.0 / g["rate_hz"]
    phase = np.abs(sol.gps_time / step - np.round(sol.gps_time / step)) * step
    keep &= phase < 0.02  # epochs on the requested grid (tolerance for RTKLIB's ms rounding)
    t = sol.gps_time[keep]
    r, v, cne = _pos_to_ecef(sol)
    r, v, cne = r[keep], v[keep], cne[keep]
    noise = _vec3(cfg, "gnss", "position_noise_m")
    rng = np.random.default_rng(g["seed"])
    var_ned = sol.std_ned[keep] ** 2 + noise**2
    r = r + np.einsum("nij,nj->ni", cne, rng.standard_normal((len(t), 3)) * noise)
    pcov = np.einsum("nij,nj,nkj->nik", cne, var_ned, cne)
    vn = g["velocity_noise_m_s"]
    vvar = np.nan_to_num(sol.velocity_std_ned[keep], nan=0.1) ** 2 + vn**2
    v = v + np.einsum("nij,nj->ni", cne, rng.standard_normal((len(t), 3)) * vn)
    vcov = np.einsum("nij,nj,nkj->nik", cne, vvar, cne)
    return GnssInput(t, r, v, pcov, vcov)


def tight_input(cfg: RunConfig) -> GnssInput:
    """GPS L1 pseudoranges and Dopplers from RINEX, and their single-point
    solution (SPP) for alignment and comparison."""
    g = cfg["gnss"]
    sky = _mn.Constellation.from_rinex_nav(_require(cfg, "gnss", "nav"))
    obs = _mn.read_rinex_obs(_require(cfg, "gnss", "obs"))
    alpha, beta = g["klobuchar_alpha"], g["klobuchar_beta"]
    if bool(alpha) != bool(beta) or (alpha and (len(alpha) != 4 or len(beta) != 4)):
        raise ValueError(
            f"{cfg.path}: gnss.klobuchar_alpha and "
            "klobuchar_beta: give four numbers each, or neither"
        )
    klobuchar = (
        (tuple(alpha), tuple(beta)) if alpha else _mn.read_klobuchar(_require(cfg, "gnss", "nav"))
    )
    meas = obs.gps_l1(
        sky,
        elevation_mask_deg=g["elevation_mask_deg"],
        min_cn0_db_hz=g["min_cn0_db_hz"],
        ionosphere=g["ionosphere"],
        klobuchar=klobuchar,
        troposphere=g["troposphere"],
        pseudorange_std=g["pseudorange_std_m"],
        pseudorange_rate_std=g["pseudorange_rate_std_m_s"],
        satellites=[int(s) for s in g["satellites"]] or None,
    )
    fixes = _mn.solve_fix(meas)
    return GnssInput(
        np.asarray(fixes.time),
        np.asarray(fixes.position_ecef),
        np.asarray(fixes.velocity_ecef),
        measurements=meas,
        spp_valid=np.asarray(fixes.valid),
    )


def _align(
    cfg: RunConfig, t: np.ndarray, f_b: np.ndarray, gnss: GnssInput
) -> tuple[int, float, np.ndarray, np.ndarray, np.ndarray]:
    """Start index into the GNSS epochs, start time, and the initial
    position (antenna), velocity and C_b^e."""
    a = cfg["alignment"]
    valid = np.all(np.isfinite(gnss.position_ecef), axis=1)
    valid &= (gnss.time >= t[0] + a["level_window_s"]) & (gnss.time <= t[-1])
    lla = np.asarray(_mn.ecef_to_geodetic(np.nan_to_num(gnss.position_ecef, nan=6.4e6)))
    cne = c_n_e(lla[:, 0], lla[:, 1])
    v_ned = np.einsum("nji,nj->ni", cne, gnss.velocity_ecef)
    speed = np.hypot(v_ned[:, 0], v_ned[:, 1])
    if a["method"] == "gnss_velocity":
        cand = np.nonzero(valid & (speed >= a["min_speed_m_s"]))[0]
        if cand.size == 0:
            raise ValueError(
                f"{cfg.path}: alignment: no GNSS epoch reaches "
                f"alignment.min_speed_m_s = {a['min_speed_m_s']} m/s"
            )
        k = int(cand[0])
        yaw = np.arctan2(v_ned[k, 1], v_ned[k, 0])
    else:
        if not np.isfinite(a["heading_deg"]):
            raise ValueError(f"{cfg.path}: alignment.method = 'static' needs alignment.heading_deg")
        k = int(np.nonzero(valid)[0][0])
        yaw = np.radians(a["heading_deg"])
    t0 = gnss.time[k]
    window = (t > t0 - a["level_window_s"]) & (t <= t0)
    f = f_b[window].mean(axis=0)
    # Levelling (Groves eq. 5.101): f_b = -C_n^b g^n.
    roll, pitch = np.arctan2(-f[1], -f[2]), np.arctan2(f[0], np.hypot(f[1], f[2]))
    c_b_e = cne[k] @ euler_to_dcm(roll, pitch, yaw)
    v0 = gnss.velocity_ecef[k] if a["method"] == "gnss_velocity" else np.zeros(3)
    return k, t0, gnss.position_ecef[k], v0, c_b_e


def _outage_mask(times: np.ndarray, windows: list[tuple[float, float]]) -> np.ndarray:
    out = np.zeros(times.shape, dtype=bool)
    for s, d in windows:
        out |= (times >= s) & (times < s + d)
    return out


def _filter(cfg: RunConfig) -> _mn.TightlyCoupledFilter | _mn.LooselyCoupledFilter:
    """The coupled filter of ``cfg["gnss"]["mode"]`` tuned by ``[filter]``:
    the configured noise densities, bias spreads and initial uncertainties
    are the filter's own; the IMU model is ideal but for its spec, which
    carries the Gauss-Markov bias processes (instability, correlation time)."""
    fil = cfg["filter"]
    attitude_std = np.radians(_vec3(cfg, "filter", "initial_attitude_std_deg"))
    if attitude_std[0] != attitude_std[1]:
        raise ValueError(
            f"{cfg.path}: filter.initial_attitude_std_deg: the filter takes one tilt "
            f"std for north and east; got {fil['initial_attitude_std_deg']}"
        )
    tau = fil["bias_correlation_time_s"]
    spec = {}
    for prefix, instability in (
        ("accel", fil["accel_bias_instability"]),
        ("gyro", np.radians(fil["gyro_bias_instability_deg_s"])),
    ):
        # Without a finite correlation time an instability drives nothing: a constant bias.
        if instability > 0 and np.isfinite(tau):
            spec[f"{prefix}_bias_instability"] = instability
            spec[f"{prefix}_bias_correlation_time"] = tau
    zero, zero33 = np.zeros(3), np.zeros((3, 3))
    imu = _mn.ImuModel(
        _mn.AccelerometerModel(zero, zero, zero33, zero),
        _mn.GyroscopeModel(zero, zero, zero33, zero33),
        spec=spec,
    )
    tuning: dict[str, Any] = {
        "accel_noise_density": fil["accel_noise_density"],
        "gyro_noise_density": np.radians(fil["gyro_noise_density_deg"]),
        "initial_accel_bias_std": fil["accel_bias_std"],
        "initial_gyro_bias_std": np.radians(fil["gyro_bias_std_deg_s"]),
        "initial_position_std": fil["initial_position_std_m"],
        "initial_velocity_std": fil["initial_velocity_std_m_s"],
        "initial_tilt_std": attitude_std[0],
        "initial_heading_std": attitude_std[2],
        "gate_probability": fil["gate_probability"],
    }
    if cfg["gnss"]["mode"] == "loose":
        return _mn.LooselyCoupledFilter(imu, **tuning)
    return _mn.TightlyCoupledFilter(
        imu, use_pseudorange_rate=cfg["gnss"]["use_pseudorange_rate"], **tuning
    )


def _epochs(meas: Any, keep: np.ndarray) -> dict[str, np.ndarray]:
    """The epochs of ``meas`` (a ``GnssMeasurements``) where ``keep``, as the
    padded arrays ``TightlyCoupledFilter.run`` reads."""
    names = (
        "time",
        "sat_id",
        "satellite_position_ecef",
        "satellite_velocity_ecef",
        "pseudorange",
        "pseudorange_std",
        "pseudorange_rate",
        "pseudorange_rate_std",
    )
    return {n: np.asarray(getattr(meas, n))[keep] for n in names}


def _error_stats(e_ned: np.ndarray, std_ned: np.ndarray) -> dict[str, float]:
    if len(e_ned) == 0:
        return {"epochs": 0}
    h = np.hypot(e_ned[:, 0], e_ned[:, 1])
    return {
        "epochs": len(e_ned),
        "rms_horizontal_m": float(np.sqrt(np.mean(h**2))),
        "rms_vertical_m": float(np.sqrt(np.mean(e_ned[:, 2] ** 2))),
        "max_horizontal_m": float(h.max()),
        "within_3sigma_share": float(np.mean(np.abs(e_ned) <= 3.0 * std_ned)),
    }


def navigate(
    config: str | Path | RunConfig,
    *,
    data_root: str | Path | None = None,
    output: str | Path | None = None,
    duration_s: float | None = None,
) -> NavigationResult:
    """Runs a configuration end to end and writes its outputs.

    ``config``: a TOML path or a loaded :class:`RunConfig`; ``data_root``
    overrides where relative data paths point; ``output`` the output folder
    (default the config's ``output``); ``duration_s`` cuts the run to that
    many seconds after alignment (a quick look or a test).
    """
    started = _time.perf_counter()
    cfg = config if isinstance(config, RunConfig) else load_config(config, data_root)
    g = cfg["gnss"]
    t, f_b, w_b, notes = read_imu(cfg)
    gnss = loose_input(cfg) if g["mode"] == "loose" else tight_input(cfg)
    lever_imu = _vec3(cfg, "imu", "lever_arm_m")
    lever = _vec3(cfg, "gnss", "antenna_lever_arm_m") - lever_imu  # IMU → antenna, body axes
    if g["mode"] == "tight" and np.any(lever != 0):
        raise ValueError(
            f"{cfg.path}: tight coupling here needs the antenna at "
            "the IMU (gnss.antenna_lever_arm_m = imu.lever_arm_m)"
        )
    _, t0, r0, v0, c0 = _align(cfg, t, f_b, gnss)
    t_end = t[-1] if duration_s is None else min(t[-1], t0 + duration_s)
    # From the last IMU sample at or before the alignment epoch, so every GNSS epoch lies inside.
    imu_sel = (t >= t[max(int(np.searchsorted(t, t0, side="right")) - 1, 0)]) & (t <= t_end)
    t_end = t[imu_sel][-1]
    windows = []
    for w in cfg["outages"]["windows_s"]:
        if len(w) != 2 or not all(isinstance(x, (int, float)) for x in w) or w[1] <= 0:
            raise ValueError(
                f"{cfg.path}: outages.windows_s: each window is [start_s, length_s > 0], got {w!r}"
            )
        windows.append((t0 + float(w[0]), float(w[1])))
    ti, fi, wi = t[imu_sel], f_b[imu_sel], w_b[imu_sel]
    # The filter's point is the IMU: antenna fixes move by -C_b^e l (lever arm).
    initial = {"position_ecef": r0 - c0 @ lever, "velocity_ecef": v0, "attitude": c0}
    kf = _filter(cfg)
    run_started = _time.perf_counter()
    if g["mode"] == "loose":
        sel = (gnss.time >= t0) & (gnss.time <= t_end) & ~_outage_mask(gnss.time, windows)
        # Antenna → IMU with the level heading of the GNSS course (the filter
        # has no lever-arm state; for the car's 5 cm the attitude error is negligible).
        lla = np.asarray(_mn.ecef_to_geodetic(gnss.position_ecef[sel]))
        cne = c_n_e(lla[:, 0], lla[:, 1])
        v_ned = np.einsum("nji,nj->ni", cne, gnss.velocity_ecef[sel])
        yaw = np.arctan2(v_ned[:, 1], v_ned[:, 0])
        l_ned = np.column_stack(
            [
                np.cos(yaw) * lever[0] - np.sin(yaw) * lever[1],
                np.sin(yaw) * lever[0] + np.cos(yaw) * lever[1],
            ]
        )
        l_ned = np.column_stack([l_ned, np.full(len(yaw), lever[2])])
        assert gnss.position_cov is not None and gnss.velocity_cov is not None  # loose input
        fixes = {
            "time": gnss.time[sel],
            "position_ecef": gnss.position_ecef[sel] - np.einsum("nij,nj->ni", cne, l_ned),
            "position_covariance": gnss.position_cov[sel],
        }
        if g["use_velocity"]:
            fixes["velocity_ecef"] = gnss.velocity_ecef[sel]
            fixes["velocity_covariance"] = gnss.velocity_cov[sel]
        sol = kf.run(ti, fi, wi, fixes, initial_state=initial)
        gnss_used = gnss.position_ecef[sel]
    else:
        meas = gnss.measurements
        mt = np.asarray(meas.time)
        keep = (mt >= t0) & (mt <= t_end) & ~_outage_mask(mt, windows)
        # The clock starts from the first epoch's residuals (no clock in ``initial``).
        sol = kf.run(ti, fi, wi, _epochs(meas, keep), initial_state=initial)
        ok = keep & gnss.spp_valid
        gnss_used = gnss.position_ecef[ok]
    run_s = _time.perf_counter() - run_started
    c_b_e = np.asarray(sol.attitude)
    r_ant = np.asarray(sol.position_ecef) + c_b_e @ lever
    lla = np.asarray(_mn.ecef_to_geodetic(r_ant))
    cne = c_n_e(lla[:, 0], lla[:, 1])
    v_ned = np.einsum("nji,nj->ni", cne, np.asarray(sol.velocity_ecef))
    euler = dcm_to_euler(np.einsum("nji,njk->nik", cne, c_b_e))
    pos_std = np.asarray(sol.position_std_ned)
    vel_std = np.asarray(sol.velocity_std_ned)
    time_out = np.asarray(sol.time)

    result = NavigationResult(
        cfg,
        time_out,
        lla,
        v_ned,
        euler,
        pos_std,
        vel_std,
        [(s - t0, d) for s, d in windows],
        np.asarray(_mn.ecef_to_geodetic(gnss_used)) if len(gnss_used) else np.zeros((0, 3)),
        None,
        None,
    )
    rec = sol.measurements
    status = np.asarray(rec["status"])
    summary: dict[str, Any] = {
        "name": cfg[""]["name"],
        "mode": g["mode"],
        "start_gps_time_s": float(t0),
        "duration_s": float(time_out[-1] - time_out[0]),
        "imu_samples": len(time_out),
        "gnss_epochs_used": len(np.unique(np.asarray(rec["time"]))),
        "measurements_accepted": int(np.sum(status == "accepted")),
        "measurements_gated": int(np.sum(status == "gate")),
        "outages_s": [[s - t0, d] for s, d in windows],
        **notes,
    }
    truth_path = cfg.data_path("truth", "pos")
    if truth_path is not None:
        truth = readers.read_pos(_require(cfg, "truth", "pos"))
        tsel = np.isin(truth.quality, cfg["truth"]["quality"]) & (truth.gps_time >= time_out[0])
        tsel &= truth.gps_time <= time_out[-1]
        tt = truth.gps_time[tsel]
        r_truth = np.asarray(_mn.geodetic_to_ecef(truth.lla[tsel]))
        r_est = np.column_stack([np.interp(tt, time_out, r_ant[:, j]) for j in range(3)])
        std_est = np.column_stack([np.interp(tt, time_out, pos_std[:, j]) for j in range(3)])
        cn = c_n_e(truth.lla[tsel, 0], truth.lla[tsel, 1])
        e_ned = np.einsum("nji,nj->ni", cn, r_est - r_truth)
        in_out = _outage_mask(tt, windows)
        result.truth = {
            "time": tt - t0,
            "lla": truth.lla[tsel],
            "error_ned": e_ned,
            "std_ned": std_est,
        }
        stats = {
            "all": _error_stats(e_ned, std_est),
            "aided": _error_stats(e_ned[~in_out], std_est[~in_out]),
        }
        for i, (s, d) in enumerate(windows):
            m = (tt >= s) & (tt < s + d)
            stats[f"outage_{i + 1}"] = {
                "start_s": s - t0,
                "length_s": d,
                **_error_stats(e_ned[m], std_est[m]),
            }
        summary["errors_vs_truth"] = stats
        if g["mode"] == "tight":
            ft = gnss.time[gnss.spp_valid]
            fr = gnss.position_ecef[gnss.spp_valid]
            # Pair each fix with the truth epoch within 20 ms (receiver epochs
            # and RTKLIB's output times differ by its millisecond rounding).
            j = np.clip(np.searchsorted(tt, ft), 1, max(len(tt) - 1, 1))
            j = np.where(
                np.abs(tt[j - 1] - ft) < np.abs(tt[np.minimum(j, len(tt) - 1)] - ft), j - 1, j
            )
            j = np.minimum(j, len(tt) - 1)
            a = np.abs(tt[j] - ft) < 0.02
            b = j[a]
            e_spp = np.einsum("nji,nj->ni", cn[b], fr[a] - r_truth[b])
            result.spp = {"time": ft[a] - t0, "error_ned": e_spp}
            spp_stats = _error_stats(e_spp, np.full_like(e_spp, np.inf))
            spp_stats.pop("within_3sigma_share", None)
            summary["spp_errors_vs_truth"] = spp_stats
            assert gnss.spp_valid is not None  # set with the tight input
            summary["spp_epochs_without_fix"] = int(np.sum(~gnss.spp_valid & (gnss.time >= t0)))
    summary["filter_run_s"] = run_s
    summary["processing_s"] = _time.perf_counter() - started
    result.summary = summary
    _write_outputs(result, Path(output) if output is not None else Path(cfg[""]["output"]))
    return result


def _write_outputs(result: NavigationResult, out: Path) -> None:
    out.mkdir(parents=True, exist_ok=True)
    name = result.config[""]["name"]
    t0 = result.summary["start_gps_time_s"]
    csv = out / f"{name}.csv"
    cols = np.column_stack(
        [
            result.time,
            np.degrees(result.lla[:, :2]),
            result.lla[:, 2],
            result.velocity_ned,
            np.degrees(result.euler),
            result.position_std_ned,
            result.velocity_std_ned,
        ]
    )
    np.savetxt(
        csv,
        cols,
        delimiter=",",
        fmt=["%.4f", "%.9f", "%.9f", "%.4f"] + ["%.5f"] * 12,
        header="gps_time_s,lat_deg,lon_deg,height_m,vn_m_s,ve_m_s,vd_m_s,roll_deg,pitch_deg,yaw_deg,"
        "sdn_m,sde_m,sdd_m,sdvn_m_s,sdve_m_s,sdvd_m_s",
        comments="",
    )
    # The .pos at 10 Hz at most (RTKLIB files are per GNSS epoch; 100 Hz is unwieldy).
    keep = np.concatenate([[True], np.diff(np.floor((result.time - t0) * 10.0)) > 0])
    pos = out / f"{name}.pos"
    readers.write_pos(
        pos,
        result.time[keep],
        result.lla[keep],
        result.position_std_ned[keep],
        result.velocity_ned[keep],
        result.velocity_std_ned[keep],
    )
    summary = out / "summary.json"
    summary.write_text(json.dumps(result.summary, indent=2))
    result.files = {"csv": str(csv), "pos": str(pos), "summary": str(summary)}
    if result.config["report"]["html"]:
        from memsnav.realdata.report import write_report

        result.files["report"] = str(write_report(result, out))
