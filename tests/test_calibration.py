"""Calibration (method §3) against analytic truths: exact recovery on
noise-free data, Monte Carlo spread against the reported sigma and the
Cramér-Rao bound, the first-order shortcut's bias, the errors-in-variables
correction, diagnostics and bad input."""

import math

import numpy as np
import pytest

import memsnav as mn

G0 = 9.80665
OFF = [(0, 1), (0, 2), (1, 0), (1, 2), (2, 0), (2, 1)]


def misalignment(rng, std):
    m = rng.normal(scale=std, size=(3, 3))
    np.fill_diagonal(m, 0.0)
    return m


def accel_model(rng, noise_std=0.0):
    # Ten times the paper's magnitudes (method §2), so every term is visible.
    return mn.AccelerometerModel(
        rng.normal(scale=0.1 * G0, size=3),
        rng.normal(scale=1e-2, size=3),
        misalignment(rng, 0.1),
        rng.normal(scale=1e-3 / G0, size=3),
        noise_std=noise_std,
    )


def gyro_model(rng, noise_std=0.0):
    return mn.GyroscopeModel(
        rng.normal(scale=math.radians(0.1), size=3),
        rng.normal(scale=1e-2, size=3),
        misalignment(rng, 0.1),
        rng.normal(scale=math.radians(1e-2) / G0, size=(3, 3)),
        noise_std=noise_std,
    )


def params(model):
    """Parameter vector in the documented covariance order."""
    last = model.nonlinearity if hasattr(model, "nonlinearity") else model.g_sensitivity.ravel()
    mis = [model.misalignment[i, j] for i, j in OFF]
    return np.concatenate([model.bias, model.scale_factor, mis, last])


def with_noise(model, noise_std):
    cls = type(model)
    last = model.nonlinearity if hasattr(model, "nonlinearity") else model.g_sensitivity
    return cls(model.bias, model.scale_factor, model.misalignment, last, noise_std=noise_std)


def motion(rng, n):
    return rng.normal(scale=6.0, size=(n, 3)), rng.normal(scale=0.5, size=(n, 3))


def test_noise_free_recovery_of_every_parameter():
    rng = np.random.default_rng(1)
    acc, gyr = accel_model(rng), gyro_model(rng)
    f, w = motion(rng, 500)
    cal = mn.calibrate_accelerometer(acc.measure(f, seed=0), f)
    assert isinstance(cal.model, mn.AccelerometerModel)
    truth = params(acc)
    typical = np.r_[np.full(12, 1e-2), np.full(3, 1e-5)]
    np.testing.assert_array_less(
        np.abs(params(cal.model) - truth), 1e-9 * np.maximum(abs(truth), typical)
    )
    cal = mn.calibrate_gyroscope(gyr.measure(w, f, seed=0), w, f)
    assert isinstance(cal.model, mn.GyroscopeModel)
    truth = params(gyr)
    np.testing.assert_array_less(
        np.abs(params(cal.model) - truth), 1e-9 * np.maximum(abs(truth), 1e-5)
    )
    assert cal.parameter_names[12] == "g_sensitivity_pu"


def test_spread_matches_sigma_and_the_cramer_rao_bound():
    rng = np.random.default_rng(2)
    sa, sg = 0.05, 2e-3
    acc, gyr = accel_model(rng, sa), gyro_model(rng, sg)
    f, w = motion(rng, 300)
    runs = 200
    ea, va, ca, eg, vg, cg = [], [], [], [], [], []
    for seed in range(runs):
        cal = mn.calibrate_accelerometer(acc.measure(f, seed=seed), f, noise_std=sa)
        ea.append(params(cal.model) - params(acc))
        va.append(params(cal.std) ** 2)
        ca.append(np.diag(cal.crb))
        if seed == 0:  # crb_std is the bound's diagonal in the model's layout
            np.testing.assert_allclose(params(cal.crb_std) ** 2, ca[-1], rtol=1e-12)
        cal = mn.calibrate_gyroscope(gyr.measure(w, f, seed=seed), w, f, noise_std=sg)
        eg.append(params(cal.model) - params(gyr))
        vg.append(params(cal.std) ** 2)
        cg.append(np.diag(cal.crb))
        if seed == 0:
            np.testing.assert_allclose(params(cal.crb_std) ** 2, cg[-1], rtol=1e-12)
    for e, v, c in ((ea, va, ca), (eg, vg, cg)):
        mse = np.mean(np.square(e), axis=0)
        # 200 runs: the MSE has a relative std of 10 %; ±35 % is 3.5 sigma.
        np.testing.assert_allclose(mse / np.mean(v, axis=0), 1.0, atol=0.35)
        # Exact references, Gaussian noise, linear model: LS is efficient.
        np.testing.assert_allclose(mse / np.mean(c, axis=0), 1.0, atol=0.35)


def test_first_order_shortcut_bias_exceeds_the_statistical_error():
    rng = np.random.default_rng(3)
    acc = accel_model(rng, 0.03)
    f, _ = motion(rng, 20_000)
    cal = mn.calibrate_accelerometer(acc.measure(f, seed=1), f)
    m = cal.model
    a = np.eye(3) - np.diag(m.scale_factor) - m.misalignment
    shortcut_bias = a @ m.bias  # b ~ -c0 with c0 = -A b
    exact = np.abs(m.bias - acc.bias)
    shortcut = np.abs(shortcut_bias - acc.bias)
    assert np.all(exact < 4 * cal.std.bias)
    assert np.all(shortcut > 10 * cal.std.bias)


def test_errors_in_variables_removes_the_attenuation_bias():
    rng = np.random.default_rng(4)
    gyr = gyro_model(rng, 1e-3)
    f, w = motion(rng, 20_000)
    sw, sf = 0.15, 1.5
    s = gyr.measure(w, f, seed=2)
    w_ref = w + rng.normal(scale=sw, size=w.shape)
    f_ref = f + rng.normal(scale=sf, size=f.shape)
    ls = mn.calibrate_gyroscope(s, w_ref, f_ref)
    eiv = mn.calibrate_gyroscope(
        s, w_ref, f_ref, method="eiv", reference_noise_std=sw, reference_specific_force_noise_std=sf
    )
    expected = sw**2 / (0.25 + sw**2)  # attenuation of 1 - D
    np.testing.assert_allclose(ls.model.scale_factor - gyr.scale_factor, expected, rtol=0.1)
    err = np.abs(eiv.model.scale_factor - gyr.scale_factor)
    assert np.all(err < 4 * eiv.std.scale_factor)
    assert np.all(err < 0.05 * expected)


def test_an_axis_that_never_moves_names_axis_and_parameter():
    rng = np.random.default_rng(5)
    f, w = motion(rng, 200)
    w[:, 1] = 0.0
    s = gyro_model(rng).measure(w, f, seed=0)
    with pytest.raises(mn.UnobservableError, match=r"q axis: scale_factor"):
        mn.calibrate_gyroscope(s, w, f)


def test_poorly_determined_parameters_warn():
    rng = np.random.default_rng(6)
    f = rng.normal(scale=3.0, size=(2000, 3))
    f[:, 2] = -9.8 + rng.normal(scale=0.01, size=2000)  # hardly any vertical motion
    acc = mn.AccelerometerModel([0.1, 0.2, 0.3], [1e-3, 0, 0], np.zeros((3, 3)), [0, 0, 1e-4])
    with pytest.warns(UserWarning) as record:
        cal = mn.calibrate_accelerometer(acc.measure(f, seed=1), f)
    assert cal.condition_number[2] > 1e6 > cal.condition_number[0]
    # The w row, and the misalignments that multiply the same still input.
    messages = [str(w.message) for w in record]
    assert any(m.startswith("w axis: scale_factor is poorly determined") for m in messages)
    assert any("misalignment_uw" in m for m in messages)
    assert messages == cal.warnings


@pytest.mark.parametrize(
    ("kwargs", "argument"),
    [
        ({"reference_specific_force": np.zeros((9, 3))}, "reference_specific_force"),
        ({"measured": np.full((10, 3), np.nan)}, "measured"),
        ({"measured": np.zeros((5, 3)), "reference_specific_force": np.ones((5, 3))}, "measured"),
        ({"noise_std": 0.0}, "noise_std"),
        ({"reference_noise_std": -1.0}, "reference_noise_std"),
        ({"method": "eiv"}, "reference_noise_std"),
        ({"method": "tls"}, "method"),
        ({"measured": np.zeros((10, 2))}, "measured"),
    ],
)
def test_bad_input_names_the_argument(kwargs, argument):
    rng = np.random.default_rng(7)
    args = {
        "measured": rng.normal(size=(10, 3)),
        "reference_specific_force": rng.normal(size=(10, 3)),
    }
    args.update(kwargs)
    measured = args.pop("measured")
    reference = args.pop("reference_specific_force")
    with pytest.raises(ValueError, match=f"^{argument}"):
        mn.calibrate_accelerometer(measured, reference, **args)


@pytest.mark.slow
def test_experiment_summary_and_reproducibility():
    kw = {"parameter_sets": 2, "runs": 2, "duration": 60.0, "seed": 3}
    one = mn.experiments.calibration(**kw, threads=1)
    two = mn.experiments.calibration(**kw, threads=2)
    np.testing.assert_array_equal(one.accelerometer.mse_ls, two.accelerometer.mse_ls)
    s = one.summary()
    assert set(s["accelerometer"]) == {"bias", "scale_factor", "misalignment", "nonlinearity"}
    assert set(s["gyroscope"]) == {"bias", "scale_factor", "misalignment", "g_sensitivity"}
    # Misalignments are determined far better than their size (paper fig. 5, 9).
    for sensor in (one.accelerometer, one.gyroscope):
        assert np.mean(sensor.mse_eiv[:, 6:12]) < 0.1 * np.mean(sensor.truth[:, 6:12] ** 2)
    import matplotlib

    matplotlib.use("Agg")
    assert len(one.plot()) == 8


def test_experiment_on_random_trajectories_and_bad_motion():
    r = mn.experiments.calibration(parameter_sets=1, runs=1, duration=60.0, motion="trajectory")
    assert np.all(np.isfinite(r.accelerometer.mse_eiv))
    with pytest.raises(ValueError, match=r"^motion"):
        mn.experiments.calibration(parameter_sets=1, runs=1, motion="boat")
