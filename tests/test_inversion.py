"""Inversion (method §4) against an independent straightforward EKF written
here in numpy, plus the experiment's numbers and bad input."""

import math

import numpy as np
import pytest

import memsnav as mn

G0 = 9.80665


def reference_ekf(measured, h_and_jac, x0, p0, q, r):
    """A textbook EKF for a random-walk state: predict P += Q, then the
    standard gain and Joseph update, linearised at the prediction."""
    x, p = x0.copy(), p0.copy()
    out, var = [x.copy()], [np.diag(p).copy()]
    for k in range(1, len(measured)):
        p = p + q
        h, jac = h_and_jac(x, k)
        s = jac @ p @ jac.T + r
        gain = p @ jac.T @ np.linalg.inv(s)
        x = x + gain @ (measured[k] - h)
        ikh = np.eye(3) - gain @ jac
        p = ikh @ p @ ikh.T + gain @ r @ gain.T
        out.append(x.copy())
        var.append(np.diag(p).copy())
    return np.array(out), np.array(var)


def smooth_motion(n, rng):
    t = np.arange(n) / 100.0
    f = np.stack([np.sin(0.7 * t), 0.5 * np.cos(1.3 * t), -G0 + 0.2 * np.sin(3 * t)], axis=1)
    w = np.stack([0.1 * np.sin(0.5 * t), 0.05 * np.cos(t), 0.3 * np.sin(0.2 * t)], axis=1)
    return f, w


def test_accelerometer_filter_matches_an_independent_ekf():
    rng = np.random.default_rng(1)
    mis = np.array([[0, 0.01, -0.02], [0.005, 0, 0.01], [-0.01, 0.02, 0]])
    acc = mn.AccelerometerModel([0.1, -0.2, 0.05], [1e-3, -2e-3, 5e-4], mis, [1e-3, -2e-3, 1e-3])
    f, _ = smooth_motion(500, rng)
    s = acc.measure(f, seed=1) + rng.normal(scale=0.03, size=f.shape)
    a = np.eye(3) - np.diag(acc.scale_factor) - acc.misalignment
    b, nl = acc.bias, acc.nonlinearity
    q, r = 0.05, 0.03

    def h_and_jac(x, _k):
        return a @ (x - b - nl * x * x), a @ np.diag(1 - 2 * nl * x)

    # Exact first-sample inversion: per axis N y² - y + x = 0, root near x.
    x = np.linalg.solve(a, s[0]) + b
    x0 = 2 * x / (1 + np.sqrt(1 - 4 * nl * x))
    jac0 = h_and_jac(x0, 0)[1]
    p0 = np.linalg.inv(jac0) @ (r**2 * np.eye(3)) @ np.linalg.inv(jac0).T
    expected, var = reference_ekf(s, h_and_jac, x0, p0, q**2 * np.eye(3), r**2 * np.eye(3))
    est, ours_var = mn.invert_accelerometer(s, acc, q, r, return_variance=True)
    np.testing.assert_allclose(est, expected, rtol=0, atol=1e-10)
    np.testing.assert_allclose(ours_var, var, rtol=1e-8)
    # And it does its job: errors near the noise floor.
    assert np.mean((est - f) ** 2) < r**2


def test_gyroscope_filter_matches_an_independent_ekf():
    rng = np.random.default_rng(2)
    mis = np.array([[0, 0.01, 0], [0, 0, -0.01], [0.02, 0, 0]])
    k = 1e-4 * np.arange(9.0).reshape(3, 3)
    gyr = mn.GyroscopeModel([1e-3, 2e-3, -1e-3], [1e-3, 0, -1e-3], mis, k)
    f, w = smooth_motion(400, rng)
    s = gyr.measure(w, f, seed=1) + rng.normal(scale=5e-4, size=w.shape)
    f_hat = f + rng.normal(scale=0.01, size=f.shape)
    a = np.eye(3) - np.diag(gyr.scale_factor) - gyr.misalignment
    q, r = np.array([1e-3, 2e-3, 3e-3]), 5e-4

    def h_and_jac(x, i):
        return a @ (x - gyr.bias - k @ f_hat[i]), a

    x0 = np.linalg.solve(a, s[0]) + gyr.bias + k @ f_hat[0]
    p0 = np.linalg.inv(a) @ (r**2 * np.eye(3)) @ np.linalg.inv(a).T
    expected, _ = reference_ekf(s, h_and_jac, x0, p0, np.diag(q**2), r**2 * np.eye(3))
    est = mn.invert_gyroscope(s, f_hat, gyr, q, r)
    np.testing.assert_allclose(est, expected, rtol=0, atol=1e-12)


@pytest.mark.parametrize(
    ("call", "argument"),
    [
        (lambda m, g, s: mn.invert_accelerometer(s, m, 0.0, 0.1), "process_std"),
        (lambda m, g, s: mn.invert_accelerometer(s, m, 0.1, [0.1, -1, 0.1]), "measurement_std"),
        (lambda m, g, s: mn.invert_accelerometer(s * np.nan, m, 0.1, 0.1), "measured"),
        (lambda m, g, s: mn.invert_gyroscope(s, s[:3], g, 0.1, 0.1), "specific_force"),
        (lambda m, g, s: mn.invert_gyroscope(s, s, g, 0.1, [0.1, 0.1]), "measurement_std"),
    ],
)
def test_bad_input_names_the_argument(call, argument):
    z = np.zeros(3)
    m = mn.AccelerometerModel(z, z, np.zeros((3, 3)), z)
    g = mn.GyroscopeModel(z, z, np.zeros((3, 3)), np.zeros((3, 3)))
    with pytest.raises(ValueError, match=f"^{argument}"):
        call(m, g, np.ones((5, 3)))


def test_inversion_experiment_lands_near_the_paper():
    one = mn.experiments.inversion(runs=4, duration=30.0, calibration_duration=120.0, threads=1)
    two = mn.experiments.inversion(runs=4, duration=30.0, calibration_duration=120.0, threads=2)
    np.testing.assert_array_equal(one.accel_mse, two.accel_mse)
    s = one.summary()
    # Paper fig. 11-12: ≈ 1e-5 g² and ≈ 1e-3 (°/s)²; paper-mems white noise is
    # 3e-3 g and 0.03 °/s per sample, i.e. 9e-6 g² and 9e-4 (°/s)².
    assert 3e-6 < s["accel_mse_g2"] < 2e-5
    assert 3e-4 < s["gyro_mse_dps2"] < 2e-3
    assert s["raw_accel_mse_g2"] > 3 * s["accel_mse_g2"]
    assert one.gyro_mse.shape == (4, 3)
    assert math.isfinite(s["gyro_mse_rad2_s2"])
    assert s["accel_mse_se_g2"] > 0 and s["completed_runs"] == 4
    # The defaults of the core ran, and the config says which.
    assert one.config["runs"] == 4 and one.config["method"] == "eiv"
    assert one.config["accel_process_std"] == 0.1
    import matplotlib

    matplotlib.use("Agg")
    assert len(one.plot()) == 2
