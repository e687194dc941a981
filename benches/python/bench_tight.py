"""The 600 s tightly coupled run through memsnav's Python API, beside the
careful version a Python user would otherwise write: FilterPy's
``ExtendedKalmanFilter`` with the same 17-state error model and NumPy for the
strapdown mechanization (same second-order ECEF step, same measurement
model, same tuning, closed loop; Φ rebuilt in place each epoch, the
constant blocks of Φ and Q computed once, scalar work on floats). The same
tuning includes memsnav's noise for the sensor errors the 17 states lack
(scale factors, misalignments: ``unmodelled_psd``), shaped by each step's
inputs and added to Q's attitude and velocity blocks; without it the peer
is a different filter, overconfident in turns (6.66 m position RMS on this
run against memsnav's 1.32 m; with it, within a few per cent). And whole Monte
Carlo runs of the navigation experiment on 1 and 2 threads; what
``smooth=True`` adds to the filter call (17 and 23 states); and memsnav's
step API (``RunningFilter``) driven from a Python loop as the peers are,
with its cost per call (predict, update_gnss, reading the position).

    python benches/python/bench_tight.py results.json [--filterpy-seconds 600]
        [--peer-seconds 600] [--mc-runs 8] [--mc-repeats 3]

FilterPy runs the whole 600 s by default (~50-90 µs per IMU epoch, a few
seconds); with ``--filterpy-seconds`` shorter its time is extrapolated per
IMU epoch to the full run (updates are ~1 % of the work in either
implementation) and the output says so. Both solutions are checked against
the truth (position RMS over the common span) so the comparison is between
two working filters. FilterPy is a benchmark-only dependency
(``pip install memsnav[bench]``).

Second peer: sidereon (PyPI ``sidereon==3.0.4``, MIT, a Rust + PyO3 GNSS
engine), its ``InertialFilter`` with ``update_tight``: a closed-loop
error-state EKF, 15 INS error states (position, velocity, attitude,
accelerometer and gyro biases, all ECEF) plus its two receiver-clock states,
17 in all. It runs on the same IMU samples (``ImuSample.rate``: specific
force m/s² and angular rate rad/s, body axes, tagged by time in s), the same
pseudoranges and pseudorange rates with their σ (``TightGnssObservation``
with a ``TightRangeRateObservation``, satellite clock drift 0), from the same
initial position, velocity and C_b^e as FilterPy (memsnav's solution at
epoch 0) with the same initial covariance (reordered to sidereon's state
order) and the same noise densities. sidereon has no whole-run call: it is
driven as its API asks, one ``propagate`` per IMU sample and one
``update_tight`` per GNSS epoch from Python, the position read back each
epoch. ``--peer-seconds`` shortens its span (extrapolated per epoch as for
FilterPy). If sidereon is not installed the comparison is skipped with a
note. What differs from the memsnav / FilterPy job, and why:

- Satellites: ``update_tight`` takes an ephemeris source, not positions per
  measurement, and solves the light time and the Sagnac rotation itself. It
  gets the same Walker orbits that made ``gnss.satellite_position_ecef``,
  sampled every 10 s over the run ± 2 min (``PreciseEphemerisSamples``,
  satellite clock 0: memsnav's pseudoranges are satellite-clock corrected).
  The bench checks that sidereon's transmission-time positions from this
  source match ``gnss.satellite_position_ecef`` (printed, sub-millimetre);
  satellite velocities come from sidereon's interpolant, not from
  ``gnss.satellite_velocity_ecef``.
- Time axis: sidereon counts seconds since J2000; the IMU, GNSS and
  ephemeris times are all given on the trajectory's time axis (the
  simulated Walker constellation has no calendar date), so only differences
  matter, as in the other two.
- Receiver clock: sidereon starts its clock bias and drift at zero (no API
  sets them). Their initial variances are memsnav's σ² plus the square of
  memsnav's epoch-0 estimate, so the first update, which resolves the clock,
  starts from a prior as wide as its error. Clock process noise: the same
  phase and frequency PSDs (m²/s, m²/s³) in the same discrete form.
- Propagation: sidereon's own ECEF mechanization from rate samples, each
  held over its interval (rectangular), against the trapezoidal, coning-
  corrected step of memsnav and FilterPy (trapezoidal increments through
  ``ImuSample.increment`` changed the 60 s RMS by 0.2 mm). Its Φ is
  I + FΔt + ½(FΔt)² (memsnav and FilterPy: I + FΔt), its Q adds the
  Δt³/3 and Δt²/2 position terms of the accelerometer white noise, and it
  re-projects the covariance to positive semi-definite each step.
- Biases: memsnav's tuning makes them random constants (PSD 0, correlation
  time ∞); ``ImuSpec`` with instability 0 and τ = ∞ gives the same (no
  bias process noise).
- No innovation gate (as FilterPy; memsnav gates at 0.999).
- No noise for the unmodelled sensor errors: ``ImuSpec`` takes white
  noises and bias processes, not a noise that follows the inputs, so
  sidereon is the filter FilterPy was without ``unmodelled_psd``
  (overconfident in turns; its position RMS is not expected to match).
"""

from __future__ import annotations

import argparse
import json
import math
import platform
import time
from pathlib import Path
from typing import Any

import numpy as np
from filterpy.kalman import ExtendedKalmanFilter

import memsnav as mn

try:
    import sidereon as sd
except ImportError:  # the optional second peer (memsnav[bench])
    sd = None

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
EYE3 = np.eye(3)
CENTRIFUGAL_GRADIENT = np.diag([OMEGA_IE**2, OMEGA_IE**2, 0.0])


def gravity(x: float, y: float, z: float) -> np.ndarray:
    """J2 gravitation plus centrifugal acceleration, ECEF (Groves eq. 2.142-2.143)."""
    r2 = x * x + y * y + z * z
    rn = math.sqrt(r2)
    z2 = 5.0 * z * z / r2
    k = 1.5 * J2 * R_EQ * R_EQ / r2
    m = -MU / (r2 * rn)
    h = m * (1.0 + k * (1.0 - z2))
    w2 = OMEGA_IE * OMEGA_IE
    return np.array([(h + w2) * x, (h + w2) * y, m * (1.0 + k * (3.0 - z2)) * z])


def rotation(tx: float, ty: float, tz: float) -> np.ndarray:
    """Rodrigues: the DCM of rotation vector theta."""
    a2 = tx * tx + ty * ty + tz * tz
    if a2 < 1e-16:
        s, c = 1.0, 0.5
    else:
        a = math.sqrt(a2)
        s, c = math.sin(a) / a, (1.0 - math.cos(a)) / a2
    return np.array(
        [
            [1.0 - c * (ty * ty + tz * tz), c * tx * ty - s * tz, c * tx * tz + s * ty],
            [c * tx * ty + s * tz, 1.0 - c * (tx * tx + tz * tz), c * ty * tz - s * tx],
            [c * tx * tz - s * ty, c * ty * tz + s * tx, 1.0 - c * (tx * tx + ty * ty)],
        ]
    )


def earth_rotation(dt: float) -> np.ndarray:
    s, co = math.sin(OMEGA_IE * dt), math.cos(OMEGA_IE * dt)
    return np.array([[co, s, 0.0], [-s, co, 0.0], [0.0, 0.0, 1.0]])


def strapdown(r, v, c, f0, w0, f1, w1, dt, earth):
    """memsnav's second-order ECEF step (ins::step): coning-corrected attitude,
    trapezoidal specific force, Heun for gravity and Coriolis. Vectors are
    NumPy arrays; scalar work is done on floats (math), NumPy only where a
    matrix product pays."""
    h, q = 0.5 * dt, dt * dt / 12.0
    a0, a1, a2 = w0.tolist()
    b0, b1, b2 = w1.tolist()
    c1 = (
        earth
        @ c
        @ rotation(
            h * (a0 + b0) + q * (a1 * b2 - a2 * b1),
            h * (a1 + b1) + q * (a2 * b0 - a0 * b2),
            h * (a2 + b2) + q * (a0 * b1 - a1 * b0),
        )
    )
    c1 = 1.5 * c1 - 0.5 * c1 @ (c1.T @ c1)
    dv = h * (c @ f0 + c1 @ f1)
    x, y, z = r.tolist()
    vx, vy, vz = v.tolist()
    g0 = gravity(x, y, z)
    w2 = 2.0 * OMEGA_IE
    cor0 = np.array([-w2 * vy, w2 * vx, 0.0])
    v_pred = v + dv + dt * (g0 - cor0)
    px, py, pz = v_pred.tolist()
    g1 = gravity(x + h * (vx + px), y + h * (vy + py), z + h * (vz + pz))
    v1 = v + dv + h * (g0 + g1 - cor0 - np.array([-w2 * py, w2 * px, 0.0]))
    return r + h * (v + v1), v1, c1


def gravity_gradient(r: np.ndarray) -> np.ndarray:
    rn = math.sqrt(r @ r)
    u = r / rn
    return -MU / rn**3 * (EYE3 - 3.0 * np.outer(u, u)) + CENTRIFUGAL_GRADIENT


class Transition:
    """Φ = I + F Δt of the 17-state model (memsnav filter::system_matrix),
    kept in one array: the constant blocks are set once, the four blocks
    that change with the state are overwritten each epoch."""

    def __init__(self, dt: float, tau_a: float, tau_g: float) -> None:
        f = np.zeros((17, 17))
        f[0:3, 0:3] = -OMEGA
        f[3:6, 3:6] = -2.0 * OMEGA
        f[6:9, 3:6] = EYE3
        f[15, 16] = 1.0
        self.phi = np.eye(17) + f * dt
        self.phi[9:12, 9:12] = EYE3 * (math.exp(-dt / tau_a) if math.isfinite(tau_a) else 1.0)
        self.phi[12:15, 12:15] = EYE3 * (math.exp(-dt / tau_g) if math.isfinite(tau_g) else 1.0)

    def update(self, c: np.ndarray, f_b: np.ndarray, r: np.ndarray, dt: float) -> np.ndarray:
        phi = self.phi
        cf = (c @ f_b) * dt
        phi[3:6, 0:3] = [[0.0, cf[2], -cf[1]], [-cf[2], 0.0, cf[0]], [cf[1], -cf[0], 0.0]]
        phi[3:6, 6:9] = gravity_gradient(r) * dt
        phi[3:6, 9:12] = phi[0:3, 12:15] = -dt * c
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


def unmodelled_psd(t: dict[str, Any], f_ref, f, w) -> tuple[np.ndarray, np.ndarray]:
    """memsnav's noise for the sensor errors the 17 states lack
    (filter/input_noise.rs): the scale factors, misalignments, nonlinearity
    and g-sensitivity of the tuning's ``unmodelled_*`` σ, as the white-noise
    PSD 2σ²τ (τ the manoeuvres' correlation time) of the error they make at
    this step's corrected inputs ``f``, ``w`` less the specific force at
    rest ``f_ref`` the biases absorb; per body axis, (accelerometer, gyro)."""
    u = f - f_ref
    u2, w2 = u * u, w * w
    white = 2.0 * t["manoeuvre_correlation_time"]
    nonlinear = 2.0 * f_ref * u + u2
    accel = white * (
        t["unmodelled_accel_scale_factor_std"] ** 2 * u2
        + t["unmodelled_accel_misalignment_std"] ** 2 * (u2.sum() - u2)
        + t["unmodelled_accel_nonlinearity_std"] ** 2 * nonlinear * nonlinear
    )
    gyro = white * (
        t["unmodelled_gyro_scale_factor_std"] ** 2 * w2
        + t["unmodelled_gyro_misalignment_std"] ** 2 * (w2.sum() - w2)
        + t["unmodelled_gyro_g_sensitivity_std"] ** 2 * u2.sum()
    )
    return accel, gyro


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
    """The careful closed-loop EKF over the first `epochs_to_run` IMU epochs:
    FilterPy's ``ExtendedKalmanFilter`` (``predict`` every IMU epoch with Φ
    rebuilt in place, one batch ``update`` of every pseudorange and rate per
    GNSS epoch, then the errors fed back), NumPy strapdown with scalar work
    in floats, Q and the constant blocks of Φ computed once (nominal Δt),
    no work per epoch beyond the filter's."""
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
    dt_nominal = 1.0 / RATE_HZ
    q_white = process_noise(tuning, dt_nominal)
    ekf.Q = q_white.copy()
    # The specific force at rest in the initial attitude (memsnav's f_ref).
    f_ref = -c.T @ gravity(*r.tolist())
    phi = Transition(dt_nominal, tau_a, tau_g)
    earth = earth_rotation(dt_nominal)
    epoch_at = {round((te - t[0]) * RATE_HZ): i for i, te in enumerate(gnss.time)}
    positions = np.empty((epochs_to_run, 3))
    positions[0] = r
    f_prev, w_prev = acc[0] - ba, gyr[0] - bg
    for k in range(1, epochs_to_run):
        dt = dt_nominal
        f1, w1 = acc[k] - ba, gyr[k] - bg
        r, v, c = strapdown(r, v, c, f_prev, w_prev, f1, w1, dt, earth)
        f_prev, w_prev = f1, w1
        clk += drift * dt
        ekf.F = phi.update(c, f1, r, dt)
        # Ĉ diag(q) Ĉᵀ Δt of the unmodelled errors on the attitude and
        # velocity blocks, as memsnav's propagation adds it.
        q_accel, q_gyro = unmodelled_psd(tuning, f_ref, f1, w1)
        ekf.Q[0:3, 0:3] = q_white[0:3, 0:3] + (c * q_gyro) @ c.T * dt
        ekf.Q[3:6, 3:6] = q_white[3:6, 3:6] + (c * q_accel) @ c.T * dt
        ekf.predict()
        i = epoch_at.get(k)
        if i is not None:
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
            c = rotation(-x[0], -x[1], -x[2]) @ c
            v, r = v - x[3:6], r - x[6:9]
            ba, bg = ba - x[9:12], bg - x[12:15]
            clk, drift = clk - x[15], drift - x[16]
            f_prev, w_prev = f1 + x[9:12], w1 + x[12:15]
            ekf.x = np.zeros(17)
        positions[k] = r
    return positions


EPHEMERIS_STEP_S = 10.0
EPHEMERIS_MARGIN_S = 120.0


def sidereon_ephemeris(gnss, t: np.ndarray):
    """The Walker orbits that made ``gnss`` as a sidereon ephemeris source:
    every satellite every ``EPHEMERIS_STEP_S`` over the run ± the margin,
    on the trajectory's time axis, satellite clock 0."""
    walker = mn.Constellation.walker()
    gps_offset = float(gnss.gps_time[0] - gnss.time[0])
    samples = []
    for ts in np.arange(t[0] - EPHEMERIS_MARGIN_S, t[-1] + EPHEMERIS_MARGIN_S, EPHEMERIS_STEP_S):
        position, _ = walker.position_velocity(gps_offset + ts)
        samples += [
            sd.PreciseEphemerisSample(name, float(ts), position[j], 0.0)
            for j, name in enumerate(walker.prns)
        ]
    return sd.PreciseEphemerisSamples.from_samples(samples)


def sidereon_satellite_check(scenario) -> float:
    """Largest distance, m, between the transmission-time satellite positions
    sidereon computes from its source (light time solved from the true
    receiver position, Sagnac rotation off so the frames agree) and
    ``gnss.satellite_position_ecef``, over every epoch and satellite."""
    traj, _, _, gnss = scenario
    t = traj.time
    source = sidereon_ephemeris(gnss, t)
    worst = 0.0
    for i, te in enumerate(gnss.time):
        k = round((te - t[0]) * RATE_HZ)
        ok = gnss.sat_id[i] >= 0
        requests = [
            sd.RangePredictionRequest(f"G{s:02d}", traj.position_ecef[k], float(t[k]))
            for s in gnss.sat_id[i][ok]
        ]
        out = sd.predict_ranges(source, requests, light_time=True, sagnac=False)
        for o, p in zip(out, gnss.satellite_position_ecef[i][ok], strict=True):
            worst = max(worst, float(np.linalg.norm(np.asarray(o.sat_pos_ecef_m) - p)))
    return worst


def sidereon_run(scenario, start, tuning, epochs_to_run: int):
    """sidereon's closed-loop tight EKF over the first `epochs_to_run` IMU
    epochs, driven as its API asks (module docstring: what differs): one
    ``propagate`` per IMU sample, one ``update_tight`` with every
    pseudorange and rate per GNSS epoch, the position read back each epoch.
    Building the ephemeris source is part of the run."""
    traj, acc, gyr, gnss = scenario
    t = traj.time
    r, v, c, clk, drift = start
    source = sidereon_ephemeris(gnss, t)

    def bias_instability(psd: float, tau: float) -> float:
        # Gauss-Markov σ: PSD τ / 2; memsnav's default PSD 0 (random constant).
        return math.sqrt(psd * tau / 2.0) if psd > 0.0 else 0.0

    tau_a, tau_g = tuning["accel_bias_correlation_time"], tuning["gyro_bias_correlation_time"]
    if (tuning["accel_bias_psd"] > 0.0 and not math.isfinite(tau_a)) or (
        tuning["gyro_bias_psd"] > 0.0 and not math.isfinite(tau_g)
    ):
        raise ValueError("sidereon's ImuSpec has no random-walk bias with a PSD")
    spec = sd.ImuSpec(
        math.sqrt(tuning["accel_white_psd"]),
        math.sqrt(tuning["gyro_white_psd"]),
        bias_instability(tuning["accel_bias_psd"], tau_a),
        bias_instability(tuning["gyro_bias_psd"], tau_g),
        tau_a,
        tau_g,
    )
    tight = sd.TightCouplingConfig(
        light_time=True,
        sagnac=True,
        initial_clock_bias_variance_m2=tuning["initial_clock_offset_std"] ** 2 + clk**2,
        initial_clock_drift_variance_m2_s2=tuning["initial_clock_drift_std"] ** 2 + drift**2,
        clock_bias_random_walk_m2_s=tuning["clock_phase_psd"],
        clock_drift_random_walk_m2_s3=tuning["clock_frequency_psd"],
    )
    # sidereon's error-state order: position, velocity, attitude, biases.
    lat, lon, _ = mn.ecef_to_geodetic(r)
    cne = c_n_e(lat, lon)
    tilt, heading = tuning["initial_tilt_std"], tuning["initial_heading_std"]
    p = np.zeros((15, 15))
    p[0:3, 0:3] = np.eye(3) * tuning["initial_position_std"] ** 2
    p[3:6, 3:6] = np.eye(3) * tuning["initial_velocity_std"] ** 2
    p[6:9, 6:9] = cne @ np.diag([tilt**2, tilt**2, heading**2]) @ cne.T
    p[9:12, 9:12] = np.eye(3) * tuning["initial_accel_bias_std"] ** 2
    p[12:15, 12:15] = np.eye(3) * tuning["initial_gyro_bias_std"] ** 2
    state = sd.InsFilterState.from_covariance(
        sd.NavState(float(t[0]), r, v, c), sd.ErrorStateLayout.FIFTEEN, p
    )
    f = sd.InertialFilter.with_config(state, sd.InertialFilterConfig(spec, tight=tight))

    epoch_at = {round((te - t[0]) * RATE_HZ): i for i, te in enumerate(gnss.time)}
    times, f_list, w_list = t.tolist(), acc.tolist(), gyr.tolist()
    positions = np.empty((epochs_to_run, 3))
    positions[0] = r
    for k in range(1, epochs_to_run):
        nav = f.propagate(sd.ImuSample.rate(times[k], f_list[k], w_list[k]))
        i = epoch_at.get(k)
        if i is not None:
            ok = gnss.sat_id[i] >= 0
            observations = [
                sd.TightGnssObservation(
                    f"G{s:02d}",
                    rho,
                    rho_std,
                    range_rate=sd.TightRangeRateObservation(rate, rate_std, 0.0),
                )
                for s, rho, rho_std, rate, rate_std in zip(
                    gnss.sat_id[i][ok].tolist(),
                    gnss.pseudorange[i][ok].tolist(),
                    gnss.pseudorange_std[i][ok].tolist(),
                    gnss.pseudorange_rate[i][ok].tolist(),
                    gnss.pseudorange_rate_std[i][ok].tolist(),
                    strict=True,
                )
            ]
            f.update_tight(source, sd.TightGnssEpoch(times[k], observations))
            nav = f.state
        positions[k] = nav.nominal.position_ecef_m
    return positions


def running_filter_run(scenario, filt, initial_state: dict[str, Any]):
    """memsnav's own step API driven from Python the way sidereon is: one
    ``predict`` per IMU sample, one ``update_gnss`` per GNSS epoch, the
    position read back each epoch. Returns the positions and the seconds
    spent in predict, update_gnss and the read-back."""
    traj, acc, gyr, gnss = scenario
    t = traj.time
    epoch_at = {round((te - t[0]) * RATE_HZ): i for i, te in enumerate(gnss.time)}
    times = t.tolist()
    positions = np.empty((len(t), 3))
    spent = {"predict": 0.0, "update_gnss": 0.0, "position_ecef": 0.0}
    clock = time.perf_counter
    running = filt.start(times[0], acc[0], gyr[0], initial_state)
    if epoch_at.get(0) is not None:
        running.update_gnss(gnss, epoch_at[0])
    positions[0] = running.position_ecef
    for k in range(1, len(times)):
        t0 = clock()
        running.predict(times[k], acc[k], gyr[k])
        t1 = clock()
        i = epoch_at.get(k)
        if i is not None:
            running.update_gnss(gnss, i)
        t2 = clock()
        positions[k] = running.position_ecef
        t3 = clock()
        spent["predict"] += t1 - t0
        spent["update_gnss"] += t2 - t1
        spent["position_ecef"] += t3 - t2
    return positions, spent


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


def start_of(sol: Any) -> tuple[np.ndarray, np.ndarray, np.ndarray, float, float]:
    """The peers' start: memsnav's solution at epoch 0 (position, velocity,
    attitude, clock offset and drift)."""
    return (
        sol.position_ecef[0].copy(),
        sol.velocity_ecef[0].copy(),
        sol.attitude[0].copy(),
        float(sol.clock_offset[0]),
        float(sol.clock_drift[0]),
    )


def best_of(repeats: int, run: Any) -> tuple[float, Any]:
    """Best wall time of `repeats` calls, and the last result."""
    times, out = [], None
    for _ in range(repeats):
        t0 = time.perf_counter()
        out = run()
        times.append(time.perf_counter() - t0)
    return min(times), out


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("output", type=Path, help="where to write the JSON results")
    parser.add_argument(
        "--filterpy-seconds",
        type=float,
        default=DURATION_S,
        help="seconds of the run FilterPy processes (less: extrapolated per epoch)",
    )
    parser.add_argument(
        "--peer-seconds",
        type=float,
        default=DURATION_S,
        help="seconds of the run sidereon processes (less: extrapolated per epoch)",
    )
    parser.add_argument("--repeats", type=int, default=5, help="memsnav runs (best is kept)")
    parser.add_argument(
        "--mc-runs", type=int, default=8, help="navigation Monte Carlo runs per thread count"
    )
    parser.add_argument(
        "--mc-repeats", type=int, default=3, help="Monte Carlo sets per thread count (best is kept)"
    )
    args = parser.parse_args()
    sim_s, (imu, sc) = best_of(args.repeats, scenario)
    traj, acc, gyr, gnss = sc
    n = len(traj.time)
    filt = mn.TightlyCoupledFilter(imu)
    memsnav_s, sol = best_of(
        args.repeats,
        lambda: filt.run(traj.time, acc, gyr, gnss, initial_attitude=traj.attitude[0]),
    )

    # What the fixed-interval smoother adds to the forward run,
    # for the 17-state filter and the 23-state one with scale factors.
    smoother = {}
    for states, scale_factor_states in ((17, False), (23, True)):
        f = mn.TightlyCoupledFilter(imu, scale_factor_states=scale_factor_states)
        runs = {
            smooth: best_of(
                args.repeats,
                lambda f=f, smooth=smooth: f.run(
                    traj.time, acc, gyr, gnss, initial_attitude=traj.attitude[0], smooth=smooth
                ),
            )[0]
            for smooth in (False, True)
        }
        smoother[states] = (runs[False], runs[True])

    m = min(n, round(args.filterpy_seconds * RATE_HZ) + 1)
    start = start_of(sol)
    t0 = time.perf_counter()
    fp_positions = filterpy_run(sc, start, filt.tuning, m)
    filterpy_s = time.perf_counter() - t0
    filterpy_per_epoch = filterpy_s / m
    filterpy_full_s = filterpy_per_epoch * n

    # memsnav's step API from a Python loop, from the same start as the
    # peers (its clock too): bit for bit the batch run from that state.
    initial_state = dict(
        zip(("position_ecef", "velocity_ecef", "attitude"), start[:3], strict=True)
    )
    initial_state.update(clock_offset=start[3], clock_drift=start[4])
    same_start = filt.run(traj.time, acc, gyr, gnss, initial_state=initial_state)
    t0 = time.perf_counter()
    step_positions, step_spent = running_filter_run(sc, filt, initial_state)
    step_s = time.perf_counter() - t0
    step_identical = bool(np.array_equal(step_positions, same_start.position_ecef))

    # The second peer, sidereon, on the same data from the same start.
    peer = None
    if sd is not None:
        m_sd = min(n, round(args.peer_seconds * RATE_HZ) + 1)
        t0 = time.perf_counter()
        sd_positions = sidereon_run(sc, start, filt.tuning, m_sd)
        sd_s = time.perf_counter() - t0
        peer = (m_sd, sd_s, sd_positions, sidereon_satellite_check(sc))

    # Whole Monte Carlo runs (trajectory, IMU, GNSS, filter) of the paper's
    # navigation experiment with one IMU, on 1 and on 2 threads; the best of
    # `--mc-repeats` sets, as the filter call is the best of `--repeats`
    # (one set of 8 runs lasts ~0.3 s: one busy moment of a shared machine
    # shows in a single set).
    mc = {}
    for threads in (1, 2):
        runs = args.mc_runs * threads
        wall, _ = best_of(
            args.mc_repeats,
            lambda threads=threads, runs=runs: mn.experiments.navigation(
                runs=runs, duration=DURATION_S, seed=SEED, imus=["mems"], threads=threads
            ),
        )
        mc[threads] = (runs, wall)
    run_1 = mc[1][1] / mc[1][0]
    run_2 = mc[2][1] / mc[2][0]

    def rms(p: np.ndarray) -> float:
        return float(np.sqrt(np.mean(np.sum((p - traj.position_ecef[: len(p)]) ** 2, axis=1))))

    result = {
        "workload": f"{DURATION_S:.0f} s, {RATE_HZ:.0f} Hz IMU ({n} epochs), 1 Hz GNSS, "
        f"{N_SATELLITES} satellites, pseudorange + rate, 17 states",
        "simulator_seconds": sim_s,
        "memsnav_seconds": memsnav_s,
        "memsnav_best_of": args.repeats,
        "memsnav_epochs_per_second": n / memsnav_s,
        "memsnav_runs_per_second": 1.0 / memsnav_s,
        "filterpy_epochs_timed": m,
        "filterpy_seconds_timed": filterpy_s,
        "filterpy_seconds_per_epoch": filterpy_per_epoch,
        "filterpy_seconds_full_run": filterpy_full_s,
        "filterpy_extrapolated": m < n,
        "filterpy_epochs_per_second": 1.0 / filterpy_per_epoch,
        "filterpy_runs_per_second": 1.0 / filterpy_full_s,
        "speedup": filterpy_full_s / memsnav_s,
        "smoother": {
            f"{states}_states": {
                "forward_seconds": forward,
                "forward_and_smoothed_seconds": both,
                "smoother_adds_times_forward": (both - forward) / forward,
            }
            for states, (forward, both) in smoother.items()
        },
        "monte_carlo_runs_per_set": {"1": mc[1][0], "2": mc[2][0]},
        "monte_carlo_sets_best_of": args.mc_repeats,
        "monte_carlo_run_seconds_1_thread": run_1,
        "monte_carlo_runs_per_second_1_thread": 1.0 / run_1,
        "monte_carlo_runs_per_second_2_threads": 1.0 / run_2,
        "monte_carlo_2_thread_scaling": run_1 / run_2,
        "whole_run_speedup": filterpy_full_s / run_1,
        "running_filter": {
            "seconds": step_s,
            "seconds_per_epoch": step_s / n,
            "epochs_per_second": n / step_s,
            "predict_seconds_per_call": step_spent["predict"] / (n - 1),
            "update_gnss_seconds_per_call": step_spent["update_gnss"] / len(gnss.time),
            "position_read_seconds_per_call": step_spent["position_ecef"] / n,
            "predict_calls_per_second": (n - 1) / step_spent["predict"],
            "speedup_over_filterpy_loop": filterpy_per_epoch * n / step_s,
            "identical_to_run": step_identical,
        },
        "memsnav_position_rms_m_first_span": rms(sol.position_ecef[:m]),
        "filterpy_position_rms_m_first_span": rms(fp_positions),
        "machine": f"{platform.processor() or platform.machine()}, {platform.python_version()}",
    }
    print(f"workload: {result['workload']}")
    print(f"simulator (trajectory, IMU, GNSS): {sim_s * 1e3:.1f} ms")
    print(
        f"memsnav TightlyCoupledFilter.run: {memsnav_s * 1e3:.1f} ms "
        f"({n / memsnav_s:,.0f} epochs/s, {1.0 / memsnav_s:.1f} runs/s)"
    )
    extrapolated = f", extrapolated per IMU epoch to {n} epochs" if m < n else ""
    print(
        f"FilterPy EKF + NumPy: {filterpy_s:.2f} s for {m} epochs "
        f"({(m - 1) / RATE_HZ:g} s), {filterpy_per_epoch * 1e6:.0f} us/epoch "
        f"({1.0 / filterpy_per_epoch:,.0f} epochs/s, {1.0 / filterpy_full_s:.3f} runs/s)"
        f"{extrapolated}: {filterpy_full_s:.2f} s per run"
    )
    print(f"filter ratio (FilterPy / memsnav): {result['speedup']:.0f}x")
    rf = result["running_filter"]
    print(
        f"memsnav RunningFilter (Python loop): {step_s:.2f} s, "
        f"{rf['seconds_per_epoch'] * 1e6:.1f} us/epoch ({rf['epochs_per_second']:,.0f} epochs/s); "
        f"per call: predict {rf['predict_seconds_per_call'] * 1e6:.2f} us "
        f"({rf['predict_calls_per_second']:,.0f}/s), update_gnss "
        f"{rf['update_gnss_seconds_per_call'] * 1e6:.1f} us, position read "
        f"{rf['position_read_seconds_per_call'] * 1e6:.2f} us; "
        f"{rf['speedup_over_filterpy_loop']:.1f}x the FilterPy loop; "
        f"identical to run: {step_identical}"
    )
    if not step_identical:
        print("WARNING: the RunningFilter loop differs from run() from the same state")
    for states, (forward, both) in smoother.items():
        print(
            f"{states} states: forward {forward * 1e3:.1f} ms, with smooth=True "
            f"{both * 1e3:.1f} ms: the smoother adds {(both - forward) / forward:.2f}x "
            "the forward run"
        )
    print(
        f"navigation Monte Carlo, 1 IMU: {1.0 / run_1:.2f} runs/s on 1 thread "
        f"({run_1 * 1e3:.0f} ms per run), {1.0 / run_2:.2f} runs/s on 2 "
        f"(scaling {run_1 / run_2:.2f}x); whole run vs the FilterPy filter alone: "
        f"{result['whole_run_speedup']:.0f}x"
    )
    print(
        f"position RMS over {(m - 1) / RATE_HZ:g} s: memsnav "
        f"{result['memsnav_position_rms_m_first_span']:.2f} m, FilterPy "
        f"{result['filterpy_position_rms_m_first_span']:.2f} m"
    )
    # Two working filters on the same data: within half again of each other.
    fp_rms = result["filterpy_position_rms_m_first_span"]
    ratio = fp_rms / result["memsnav_position_rms_m_first_span"]
    result["same_accuracy"] = bool(1 / 1.5 <= ratio <= 1.5)
    if not result["same_accuracy"]:
        print(f"WARNING: the position RMS differ by {ratio:.2f}x: not the same job")
    if peer is None:
        result["sidereon"] = {"skipped": "sidereon is not installed (pip install memsnav[bench])"}
        print("sidereon: not installed, second peer skipped (pip install memsnav[bench])")
    else:
        m_sd, sd_s, sd_positions, sat_diff = peer
        sd_per_epoch = sd_s / m_sd
        sd_full_s = sd_per_epoch * n
        sd_rms, ms_rms = rms(sd_positions), rms(sol.position_ecef[:m_sd])
        result["sidereon"] = {
            "version": sd.__version__,
            "epochs_timed": m_sd,
            "seconds_timed": sd_s,
            "seconds_per_epoch": sd_per_epoch,
            "seconds_full_run": sd_full_s,
            "extrapolated": m_sd < n,
            "epochs_per_second": 1.0 / sd_per_epoch,
            "runs_per_second": 1.0 / sd_full_s,
            "speedup": sd_full_s / memsnav_s,
            "position_rms_m": sd_rms,
            "memsnav_position_rms_m_same_span": ms_rms,
            "satellite_position_max_diff_m": sat_diff,
        }
        extrapolated = f", extrapolated per IMU epoch to {n} epochs" if m_sd < n else ""
        print(
            f"sidereon {sd.__version__} InertialFilter (Python loop): {sd_s:.2f} s for {m_sd} "
            f"epochs ({(m_sd - 1) / RATE_HZ:g} s), {sd_per_epoch * 1e6:.0f} us/epoch "
            f"({1.0 / sd_per_epoch:,.0f} epochs/s, {1.0 / sd_full_s:.3f} runs/s)"
            f"{extrapolated}: {sd_full_s:.2f} s per run"
        )
        print(f"filter ratio (sidereon / memsnav): {result['sidereon']['speedup']:.0f}x")
        result["sidereon"]["running_filter_speedup"] = sd_per_epoch * n / step_s
        print(
            "Python loops, sidereon / memsnav RunningFilter: "
            f"{result['sidereon']['running_filter_speedup']:.1f}x"
        )
        print(
            f"position RMS over {(m_sd - 1) / RATE_HZ:g} s: memsnav {ms_rms:.2f} m, "
            f"sidereon {sd_rms:.2f} m; sidereon's satellites vs memsnav's: "
            f"{sat_diff * 1e3:.2f} mm at most"
        )
    args.output.parent.mkdir(parents=True, exist_ok=True)
    args.output.write_text(json.dumps(result, indent=2) + "\n")


if __name__ == "__main__":
    main()
