"""The 600 s tightly coupled run through memsnav's Python API, beside the
textbook version a Python user would otherwise write: FilterPy's
``ExtendedKalmanFilter`` with the same 17-state error model and NumPy for the
strapdown mechanization (same second-order ECEF step, same measurement
model, same tuning, closed loop).

    python benches/python/bench_tight.py results.json [--filterpy-seconds 60]

The FilterPy loop costs ~0.2 ms per IMU epoch, so by default it processes
only the first 60 s (6 000 epochs, 60 GNSS updates) and its time is
extrapolated per IMU epoch to the 60 000 epochs of the full run (updates
are ~1 % of the work in either implementation); the output says so. Both
solutions are checked against the truth (position RMS) so the comparison
is between two working filters. FilterPy is a benchmark-only dependency
(``pip install memsnav[bench]``).
"""

from __future__ import annotations

import argparse
import json
import platform
import time
from pathlib import Path
from typing import Any

import numpy as np
from filterpy.kalman import ExtendedKalmanFilter

import memsnav as mn

OMEGA_IE = 7.292115e-5  # rad/s, WGS 84
MU = 3.986004418e14  # m³/s², WGS 84
J2 = 1.082627e-3
R_EQ = 6378137.0  # m
E2 = 6.69437999014e-3
C_LIGHT = 299792458.0  # m/s
DURATION_S = 600.0
RATE_HZ = 100.0
N_SATELLITES = 6
SEED = 2008


def skew(v: np.ndarray) -> np.ndarray:
    return np.array([[0.0, -v[2], v[1]], [v[2], 0.0, -v[0]], [-v[1], v[0], 0.0]])


OMEGA = skew(np.array([0.0, 0.0, OMEGA_IE]))


def gravity(r: np.ndarray) -> np.ndarray:
    """J2 gravitation plus centrifugal acceleration, ECEF (Groves eq. 2.142-2.143)."""
    rn = np.linalg.norm(r)
    z2 = 5.0 * (r[2] / rn) ** 2
    k = 1.5 * J2 * (R_EQ / rn) ** 2
    gamma = -MU / rn**3 * (r + k * np.array([(1 - z2) * r[0], (1 - z2) * r[1], (3 - z2) * r[2]]))
    return gamma + OMEGA_IE**2 * np.array([r[0], r[1], 0.0])


def rotation(theta: np.ndarray) -> np.ndarray:
    """Rodrigues: the DCM of rotation vector theta."""
    a = np.linalg.norm(theta)
    k = skew(theta)
    if a < 1e-8:
        return np.eye(3) + k + 0.5 * k @ k
    return np.eye(3) + np.sin(a) / a * k + (1 - np.cos(a)) / a**2 * k @ k


def strapdown(r, v, c, f0, w0, f1, w1, dt):
    """memsnav's second-order ECEF step (ins::step): coning-corrected attitude,
    trapezoidal specific force, Heun for gravity and Coriolis."""
    theta = 0.5 * dt * (w0 + w1) + dt * dt / 12.0 * np.cross(w0, w1)
    s, co = np.sin(OMEGA_IE * dt), np.cos(OMEGA_IE * dt)
    earth = np.array([[co, s, 0.0], [-s, co, 0.0], [0.0, 0.0, 1.0]])
    c1 = earth @ c @ rotation(theta)
    c1 = c1 - 0.5 * c1 @ (c1.T @ c1 - np.eye(3))
    dv = 0.5 * dt * (c @ f0 + c1 @ f1)
    g0 = gravity(r)
    cor0 = 2.0 * OMEGA @ v
    v_pred = v + dv + dt * (g0 - cor0)
    r_pred = r + 0.5 * dt * (v + v_pred)
    v1 = v + dv + 0.5 * dt * (g0 + gravity(r_pred) - cor0 - 2.0 * OMEGA @ v_pred)
    return r + 0.5 * dt * (v + v1), v1, c1


def gravity_gradient(r: np.ndarray) -> np.ndarray:
    rn = np.linalg.norm(r)
    u = r / rn
    return -MU / rn**3 * (np.eye(3) - 3.0 * np.outer(u, u)) + np.diag(
        [OMEGA_IE**2, OMEGA_IE**2, 0.0]
    )


def transition(c, f_b, r, dt, tau_a, tau_g) -> np.ndarray:
    """Φ = I + F Δt of the 17-state model (memsnav filter::system_matrix)."""
    f = np.zeros((17, 17))
    f[0:3, 0:3] = -OMEGA
    f[0:3, 12:15] = -c
    f[3:6, 0:3] = -skew(c @ f_b)
    f[3:6, 3:6] = -2.0 * OMEGA
    f[3:6, 6:9] = gravity_gradient(r)
    f[3:6, 9:12] = -c
    f[6:9, 3:6] = np.eye(3)
    f[15, 16] = 1.0
    phi = np.eye(17) + f * dt
    phi[9:12, 9:12] = np.eye(3) * (np.exp(-dt / tau_a) if np.isfinite(tau_a) else 1.0)
    phi[12:15, 12:15] = np.eye(3) * (np.exp(-dt / tau_g) if np.isfinite(tau_g) else 1.0)
    return phi


def process_noise(t: dict[str, Any], dt: float) -> np.ndarray:
    def bias_q(psd: float, tau: float) -> float:
        return 0.5 * psd * tau * (1 - np.exp(-2 * dt / tau)) if np.isfinite(tau) else psd * dt

    q = np.zeros((17, 17))
    q[0:3, 0:3] = np.eye(3) * t["gyro_white_psd"] * dt
    q[3:6, 3:6] = np.eye(3) * t["accel_white_psd"] * dt
    q[9:12, 9:12] = np.eye(3) * bias_q(t["accel_bias_psd"], t["accel_bias_correlation_time"])
    q[12:15, 12:15] = np.eye(3) * bias_q(t["gyro_bias_psd"], t["gyro_bias_correlation_time"])
    sp, sf = t["clock_phase_psd"], t["clock_frequency_psd"]
    q[15:17, 15:17] = [[sp * dt + sf * dt**3 / 3, sf * dt**2 / 2], [sf * dt**2 / 2, sf * dt]]
    return q


def predicted_range(sat_r, sat_v, r, v):
    """Range and rate with the Sagnac correction (Groves eq. 8.41-8.46)."""
    tau = np.linalg.norm(sat_r - r) / C_LIGHT
    a = OMEGA_IE * tau
    rot = np.array([[np.cos(a), np.sin(a), 0.0], [-np.sin(a), np.cos(a), 0.0], [0.0, 0.0, 1.0]])
    rs = rot @ sat_r
    vs = rot @ (sat_v + OMEGA @ sat_r) - OMEGA @ rs
    d = rs - r
    rho = np.linalg.norm(d)
    u = d / rho
    return rho, u @ (vs - v), u


def c_n_e(lat: float, lon: float) -> np.ndarray:
    sl, cl, so, co = np.sin(lat), np.cos(lat), np.sin(lon), np.cos(lon)
    return np.array([[-sl * co, -so, -cl * co], [-sl * so, co, -cl * so], [cl, 0.0, -sl]])


def filterpy_run(scenario, start, tuning, epochs_to_run: int):
    """The textbook closed-loop EKF over the first `epochs_to_run` IMU epochs."""
    traj, acc, gyr, gnss = scenario
    t = traj.time
    r, v, c, clk, drift = start
    ba, bg = np.zeros(3), np.zeros(3)
    ekf = ExtendedKalmanFilter(dim_x=17, dim_z=2 * N_SATELLITES)
    ekf.x = np.zeros(17)
    lat, lon, _ = mn.ecef_to_geodetic(r)
    cne = c_n_e(lat, lon)
    tilt, heading = tuning["initial_tilt_std"], tuning["initial_heading_std"]
    p = np.zeros((17, 17))
    p[0:3, 0:3] = cne @ np.diag([tilt**2, tilt**2, heading**2]) @ cne.T
    p[3:6, 3:6] = np.eye(3) * tuning["initial_velocity_std"] ** 2
    p[6:9, 6:9] = np.eye(3) * tuning["initial_position_std"] ** 2
    p[9:12, 9:12] = np.eye(3) * tuning["initial_accel_bias_std"] ** 2
    p[12:15, 12:15] = np.eye(3) * tuning["initial_gyro_bias_std"] ** 2
    p[15, 15] = tuning["initial_clock_offset_std"] ** 2
    p[16, 16] = tuning["initial_clock_drift_std"] ** 2
    ekf.P = p
    tau_a, tau_g = tuning["accel_bias_correlation_time"], tuning["gyro_bias_correlation_time"]
    epoch_at = {round((te - t[0]) * RATE_HZ): i for i, te in enumerate(gnss.time)}
    positions = [r.copy()]
    for k in range(1, epochs_to_run):
        dt = t[k] - t[k - 1]
        f0, f1 = acc[k - 1] - ba, acc[k] - ba
        w0, w1 = gyr[k - 1] - bg, gyr[k] - bg
        r, v, c = strapdown(r, v, c, f0, w0, f1, w1, dt)
        clk += drift * dt
        ekf.F = transition(c, f1, r, dt, tau_a, tau_g)
        ekf.Q = process_noise(tuning, dt)
        ekf.predict()
        if k in epoch_at:
            i = epoch_at[k]
            ok = gnss.sat_id[i] >= 0
            sat_r = gnss.satellite_position_ecef[i][ok]
            sat_v = gnss.satellite_velocity_ecef[i][ok]
            m = len(sat_r)
            h = np.zeros((2 * m, 17))
            z = np.zeros(2 * m)
            for j in range(m):
                rho, rate, u = predicted_range(sat_r[j], sat_v[j], r, v)
                h[j, 6:9], h[j, 15] = -u, 1.0
                h[m + j, 3:6], h[m + j, 16] = -u, 1.0
                z[j] = rho + clk - gnss.pseudorange[i][ok][j]
                z[m + j] = rate + drift - gnss.pseudorange_rate[i][ok][j]
            rr = np.diag(
                np.concatenate([gnss.pseudorange_std[i][ok], gnss.pseudorange_rate_std[i][ok]]) ** 2
            )
            ekf.update(z, lambda x, h=h: h, lambda x, h=h: h @ x, R=rr)
            # Closed loop: errors are estimate − truth.
            x = ekf.x
            c = rotation(-x[0:3]) @ c
            v, r = v - x[3:6], r - x[6:9]
            ba, bg = ba - x[9:12], bg - x[12:15]
            clk, drift = clk - x[15], drift - x[16]
            ekf.x = np.zeros(17)
        positions.append(r.copy())
    return np.array(positions)


def scenario():
    traj = mn.Trajectory.random(DURATION_S, RATE_HZ, seed=SEED)
    imu = mn.ImuModel.preset("paper-mems", seed=SEED)
    acc, gyr = imu.measure(traj.specific_force, traj.angular_rate, seed=SEED)
    gnss = mn.simulate_gnss(
        traj.time,
        traj.position_ecef,
        traj.velocity_ecef,
        mn.Constellation.walker(),
        n_satellites=N_SATELLITES,
        seed=SEED,
    )
    return imu, (traj, acc, gyr, gnss)


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("output", type=Path, help="where to write the JSON results")
    parser.add_argument("--filterpy-seconds", type=float, default=60.0)
    parser.add_argument("--repeats", type=int, default=5, help="memsnav runs (best is kept)")
    args = parser.parse_args()
    imu, sc = scenario()
    traj, acc, gyr, gnss = sc
    n = len(traj.time)
    filt = mn.TightlyCoupledFilter(imu)
    times = []
    for _ in range(args.repeats):
        t0 = time.perf_counter()
        sol = filt.run(traj.time, acc, gyr, gnss, initial_attitude=traj.attitude[0])
        times.append(time.perf_counter() - t0)
    memsnav_s = min(times)

    m = round(args.filterpy_seconds * RATE_HZ) + 1
    start = (
        sol.position_ecef[0].copy(),
        sol.velocity_ecef[0].copy(),
        sol.attitude[0].copy(),
        float(sol.clock_offset[0]),
        float(sol.clock_drift[0]),
    )
    t0 = time.perf_counter()
    fp_positions = filterpy_run(sc, start, filt.tuning, m)
    filterpy_s = time.perf_counter() - t0
    filterpy_per_epoch = filterpy_s / m
    filterpy_full_s = filterpy_per_epoch * n

    def rms(p: np.ndarray) -> float:
        return float(np.sqrt(np.mean(np.sum((p - traj.position_ecef[: len(p)]) ** 2, axis=1))))

    result = {
        "workload": f"{DURATION_S:.0f} s, {RATE_HZ:.0f} Hz IMU ({n} epochs), 1 Hz GNSS, "
        f"{N_SATELLITES} satellites, pseudorange + rate, 17 states",
        "memsnav_seconds": memsnav_s,
        "memsnav_epochs_per_second": n / memsnav_s,
        "filterpy_epochs_timed": m,
        "filterpy_seconds_timed": filterpy_s,
        "filterpy_seconds_per_epoch": filterpy_per_epoch,
        "filterpy_seconds_extrapolated": filterpy_full_s,
        "filterpy_epochs_per_second": 1.0 / filterpy_per_epoch,
        "speedup": filterpy_full_s / memsnav_s,
        "memsnav_position_rms_m_first_span": rms(sol.position_ecef[:m]),
        "filterpy_position_rms_m_first_span": rms(fp_positions),
        "machine": f"{platform.processor() or platform.machine()}, {platform.python_version()}",
    }
    print(f"workload: {result['workload']}")
    rate = n / memsnav_s
    print(f"memsnav TightlyCoupledFilter.run: {memsnav_s * 1e3:.1f} ms ({rate:,.0f} epochs/s)")
    print(
        f"FilterPy EKF + NumPy: {filterpy_s:.2f} s for the first {m} epochs "
        f"({args.filterpy_seconds:g} s), {filterpy_per_epoch * 1e6:.0f} us/epoch, "
        f"extrapolated per IMU epoch to {n} epochs: {filterpy_full_s:.1f} s"
    )
    print(f"ratio (FilterPy / memsnav): {result['speedup']:.0f}x")
    print(
        f"position RMS over the first {args.filterpy_seconds:g} s: memsnav "
        f"{result['memsnav_position_rms_m_first_span']:.2f} m, FilterPy "
        f"{result['filterpy_position_rms_m_first_span']:.2f} m"
    )
    args.output.parent.mkdir(parents=True, exist_ok=True)
    args.output.write_text(json.dumps(result, indent=2) + "\n")


if __name__ == "__main__":
    main()
