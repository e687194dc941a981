"""Sensor models against a direct numpy evaluation of method §2, the noise
processes against their theoretical statistics, the presets against their
published magnitudes, and every bad input the models refuse."""

import itertools
import math
import pickle

import numpy as np
import pytest

import memsnav as mn

G0 = 9.80665
DEG = math.pi / 180


def random_params(rng: np.random.Generator):
    m = rng.normal(0, 1e-2, (3, 3))
    np.fill_diagonal(m, 0.0)
    return rng.normal(0, 0.1, 3), rng.normal(0, 1e-3, 3), m


def accel_eq2(f, bias, d, m, n, nu=0.0):
    """Method §2, accelerometer: S = (I - D - M)(Γ - b - N(Γ⊙Γ) - nu), per row."""
    a = np.eye(3) - np.diag(d) - m
    return (f - bias - n * f * f - nu) @ a.T


def gyro_eq3(w, f, bias, d, m, k):
    """Method §2, gyroscope: S = (I - D - M)(Ω - b - K Γ)."""
    a = np.eye(3) - np.diag(d) - m
    return (w - bias - f @ k.T) @ a.T


def ideal_accel(**noise):
    return mn.AccelerometerModel(np.zeros(3), np.zeros(3), np.zeros((3, 3)), np.zeros(3), **noise)


# --- forward model -----------------------------------------------------------


def test_accelerometer_matches_eq2():
    rng = np.random.default_rng(0)
    bias, d, m = random_params(rng)
    n = rng.normal(0, 1e-3, 3)
    f = rng.normal(0, 20.0, (500, 3))
    acc = mn.AccelerometerModel(bias, d, m, n)
    np.testing.assert_allclose(acc.measure(f, seed=1), accel_eq2(f, bias, d, m, n), atol=1e-12)
    np.testing.assert_array_equal(acc.bias, bias)
    np.testing.assert_array_equal(acc.misalignment, m)
    np.testing.assert_array_equal(acc.nonlinearity, n)
    np.testing.assert_array_equal(acc.scale_factor, d)


def test_gyroscope_matches_eq3():
    rng = np.random.default_rng(1)
    bias, d, m = random_params(rng)
    k = rng.normal(0, 1e-3, (3, 3))
    w = rng.normal(0, 1.0, (500, 3))
    f = rng.normal(0, 10.0, (500, 3))
    gyr = mn.GyroscopeModel(bias, d, m, k)
    np.testing.assert_allclose(gyr.measure(w, f, seed=1), gyro_eq3(w, f, bias, d, m, k), atol=1e-14)
    np.testing.assert_array_equal(gyr.g_sensitivity, k)


def test_imu_measure_is_both_sensors():
    rng = np.random.default_rng(2)
    bias, d, m = random_params(rng)
    n = rng.normal(0, 1e-3, 3)
    k = rng.normal(0, 1e-3, (3, 3))
    imu = mn.ImuModel(mn.AccelerometerModel(bias, d, m, n), mn.GyroscopeModel(bias, d, m, k))
    f = rng.normal(0, 10.0, (50, 3))
    w = rng.normal(0, 1.0, (50, 3))
    accel, gyro = imu.measure(f, w, seed=3)
    np.testing.assert_allclose(accel, accel_eq2(f, bias, d, m, n), atol=1e-12)
    np.testing.assert_allclose(gyro, gyro_eq3(w, f, bias, d, m, k), atol=1e-14)


# --- noise statistics --------------------------------------------------------


def test_white_noise_std_is_input_referred():
    sigma = 0.05
    # D_x = 0.5 halves the x noise: the white noise sits inside (I - D - M)(...), as in the paper.
    acc = mn.AccelerometerModel(np.zeros(3), [0.5, 0.0, 0.0], np.zeros((3, 3)), np.zeros(3), sigma)
    out = acc.measure(np.zeros((60_000, 3)), seed=4)
    std = out.std(axis=0)
    tol = 4 / math.sqrt(2 * 60_000)
    assert std[0] / (0.5 * sigma) == pytest.approx(1, abs=tol)
    assert std[1] / sigma == pytest.approx(1, abs=tol)
    assert std[2] / sigma == pytest.approx(1, abs=tol)
    assert abs(np.corrcoef(out[1:, 1], out[:-1, 1])[0, 1]) < 0.02  # white


def test_density_and_per_sample_std():
    acc = ideal_accel(noise_density=0.01, sample_rate=400.0)
    assert acc.noise_std == pytest.approx(0.01 * math.sqrt(400.0))
    out = acc.measure(np.zeros((40_000, 3)), seed=5)
    assert out.std() == pytest.approx(0.2, rel=0.02)
    by_std = ideal_accel(noise_std=0.2, sample_rate=400.0)
    assert by_std.noise_density == pytest.approx(0.01)


def test_gauss_markov_stationary_variance_and_autocorrelation():
    sigma, tau, rate = 0.3, 0.2, 100.0
    acc = ideal_accel(bias_instability=sigma, bias_correlation_time=tau, sample_rate=rate)
    x = -acc.measure(np.zeros((200_000, 3)), seed=6)  # output = -β
    assert x.var() / sigma**2 == pytest.approx(1, abs=0.08)
    for k in (5, 20, 40):
        rho = np.mean(x[k:] * x[:-k]) / np.mean(x * x)
        assert rho == pytest.approx(math.exp(-k / rate / tau), abs=0.04), k
    # Started from the stationary distribution: the first sample already has variance σ².
    first = np.array([acc.measure(np.zeros((1, 3)), seed=s)[0] for s in range(1500)])
    assert first.var() / sigma**2 == pytest.approx(1, abs=4 * math.sqrt(2 / first.size))


def test_random_walk_variance_grows_linearly():
    q, rate = 0.05, 100.0
    gyr = mn.GyroscopeModel(
        np.zeros(3), np.zeros(3), np.zeros((3, 3)), np.zeros((3, 3)), bias_random_walk=q
    )
    z = np.zeros((401, 3))
    runs = np.array([gyr.measure(z, z, seed=s) for s in range(1000)])
    np.testing.assert_array_equal(runs[:, 0], 0.0)
    tol = 4 * math.sqrt(2 / 3000)
    for k in (100, 200, 400):
        assert runs[:, k].var() / (q**2 * k / rate) == pytest.approx(1, abs=tol), k


def test_quantisation_error_is_bounded_and_uniform():
    lsb = 0.01
    acc = ideal_accel(quantization=lsb)
    f = np.random.default_rng(7).uniform(-5, 5, (30_000, 3))
    out = acc.measure(f, seed=0)
    np.testing.assert_allclose(out / lsb, np.round(out / lsb), atol=1e-9)
    err = out - f
    assert np.abs(err).max() <= lsb / 2 + 1e-12
    assert abs(err.mean()) < 1e-4
    assert err.var() == pytest.approx(lsb**2 / 12, rel=0.03)
    hist, _ = np.histogram(err, bins=10, range=(-lsb / 2, lsb / 2))
    assert hist.min() > 0.9 * hist.mean()


def test_seeds():
    imu = mn.ImuModel.preset("consumer", seed=1)
    f = np.tile([0.0, 0.0, -G0], (100, 1))
    w = np.zeros((100, 3))
    a1, g1 = imu.measure(f, w, seed=8)
    a2, g2 = imu.measure(f, w, seed=8)
    a3, _ = imu.measure(f, w, seed=9)
    np.testing.assert_array_equal(a1, a2)
    np.testing.assert_array_equal(g1, g2)
    assert not np.array_equal(a1, a3)
    # seed=None is the default seed 0, not fresh entropy (docs/explanation/concepts.md).
    np.testing.assert_array_equal(imu.measure(f, w)[0], imu.measure(f, w, seed=0)[0])
    assert mn.ImuModel.preset("consumer", seed=1) == imu
    assert mn.ImuModel.preset("consumer", seed=2) != imu


# --- presets and specs -------------------------------------------------------

PAPER_SPEC = {
    "accel_bias_std": 1e-2 * G0,
    "accel_scale_factor_std": 1e-5,
    "accel_misalignment_std": 1e-2,
    "accel_nonlinearity_std": 1e-5 / G0,
    "accel_noise_density": 3e-3 * G0 / 10,
    "gyro_bias_std": 1e-2 * DEG,
    "gyro_scale_factor_std": 1e-4,
    "gyro_misalignment_std": 1e-2,
    "gyro_g_sensitivity_std": 1e-3 * DEG / G0,
    "gyro_noise_density": 0.03 * DEG / 10,
}


def test_paper_mems_has_the_paper_magnitudes():
    imu = mn.ImuModel.preset("paper-mems", seed=0)
    for key, value in PAPER_SPEC.items():
        assert imu.spec[key] == pytest.approx(value, rel=1e-12), key
    assert imu.accelerometer.noise_std == pytest.approx(0.0294, abs=1e-4)
    assert imu.gyroscope.noise_std == pytest.approx(0.03 * DEG)


def sample_std(models, attribute):
    values = np.array([getattr(m, attribute) for m in models])
    if values.ndim == 3:  # misalignment: the six off-diagonal terms only
        values = values[:, ~np.eye(3, dtype=bool)]
    return values.std(), values.size


@pytest.mark.parametrize("name", mn.ImuModel.presets())
def test_presets_draw_their_spec(name):
    imus = [mn.ImuModel.preset(name, seed=s) for s in range(300)]
    spec = imus[0].spec
    for sensor, prefix, terms in (
        ("accelerometer", "accel", ("bias", "scale_factor", "misalignment", "nonlinearity")),
        ("gyroscope", "gyro", ("bias", "scale_factor", "misalignment", "g_sensitivity")),
    ):
        models = [getattr(i, sensor) for i in imus]
        for term in terms:
            std, n = sample_std(models, term)
            expected = spec[f"{prefix}_{term}_std"]
            if expected == 0:
                assert std == 0
            else:
                assert std / expected == pytest.approx(1, abs=4 / math.sqrt(2 * n)), term
        assert models[0].noise_density == pytest.approx(spec[f"{prefix}_noise_density"])
        assert models[0].bias_instability == spec[f"{prefix}_bias_instability"]
        assert models[0].quantization == spec[f"{prefix}_quantization"]
        assert all(np.all(np.diag(m.misalignment) == 0) for m in models)


def test_grades_are_ordered():
    grades = ("consumer", "industrial", "tactical", "navigation")
    specs = [mn.ImuModel.preset(n, seed=0).spec for n in grades]
    for worse, better in itertools.pairwise(specs):
        assert better["gyro_bias_std"] < worse["gyro_bias_std"]
        assert better["accel_bias_std"] < worse["accel_bias_std"]
    # HG1700 product sheet: 1 °/h, 0.125 °/√h; HG9900: 0.0035 °/h.
    tactical = mn.ImuModel.preset("tactical", seed=0).spec
    assert tactical["gyro_bias_std"] == pytest.approx(DEG / 3600)
    assert tactical["gyro_noise_density"] == pytest.approx(0.125 * DEG / 60)
    assert specs[3]["gyro_bias_std"] == pytest.approx(0.0035 * DEG / 3600)


def test_hand_built_imu_spec_and_rates():
    acc = mn.AccelerometerModel([0.3, -0.4, 0.0], np.zeros(3), np.zeros((3, 3)), np.zeros(3), 0.02)
    gyr = mn.GyroscopeModel(np.zeros(3), np.zeros(3), np.zeros((3, 3)), np.zeros((3, 3)))
    imu = mn.ImuModel(acc, gyr)
    assert imu.sample_rate == 100.0
    assert imu.spec["accel_bias_std"] == pytest.approx(math.sqrt(0.25 / 3))
    assert imu.spec["accel_noise_density"] == pytest.approx(0.002)
    # A faster IMU keeps the noise density: 0.02 at 100 Hz is 0.04 per sample at 400 Hz.
    fast = mn.ImuModel(acc, gyr, sample_rate=400.0)
    assert fast.accelerometer.noise_std == pytest.approx(0.04)
    custom = mn.ImuModel(acc, gyr, spec={"gyro_bias_std": 1e-4})
    assert custom.spec["gyro_bias_std"] == 1e-4
    assert custom.spec["accel_bias_std"] == imu.spec["accel_bias_std"]


def test_pickle_and_repr():
    imu = mn.ImuModel.preset("industrial", seed=3)
    assert pickle.loads(pickle.dumps(imu)) == imu
    for sensor in (imu.accelerometer, imu.gyroscope):
        assert pickle.loads(pickle.dumps(sensor)) == sensor
        assert repr(sensor).startswith(type(sensor).__name__ + "(bias=[")
    assert "sample_rate=100.0" in repr(imu)
    assert set(mn.ImuModel.presets()) == {
        "paper-mems",
        "consumer",
        "industrial",
        "tactical",
        "navigation",
    }


# --- bad input ---------------------------------------------------------------

Z3 = np.zeros(3)
Z33 = np.zeros((3, 3))


def diagonal_misalignment():
    m = np.zeros((3, 3))
    m[1, 1] = 0.01
    return m


@pytest.mark.parametrize(
    ("build", "message"),
    [
        (lambda: mn.AccelerometerModel(np.zeros(2), Z3, Z33, Z3), r"bias: expected shape \(3,\)"),
        (lambda: mn.AccelerometerModel(Z3, [0, np.nan, 0], Z33, Z3), "scale_factor: element 1"),
        (lambda: mn.AccelerometerModel(Z3, Z3, np.zeros((3, 2)), Z3), "misalignment: expected"),
        (lambda: mn.AccelerometerModel(Z3, Z3, diagonal_misalignment(), Z3), "misalignment: diag"),
        (lambda: mn.AccelerometerModel(Z3, Z3, Z33, [0, 0, np.inf]), "nonlinearity: element 2"),
        (lambda: mn.AccelerometerModel(Z3, Z3, Z33, Z3, -0.1), "noise_std: must be finite and"),
        (lambda: mn.AccelerometerModel(Z3, Z3, Z33, Z3, noise_density=-1.0), "noise_density:"),
        (lambda: mn.AccelerometerModel(Z3, Z3, Z33, Z3, 0.1, noise_density=0.1), "noise_density:"),
        (lambda: mn.AccelerometerModel(Z3, Z3, Z33, Z3, sample_rate=0.0), "sample_rate:"),
        (
            lambda: mn.AccelerometerModel(Z3, Z3, Z33, Z3, bias_instability=0.1),
            "bias_correlation_time: must be finite and positive",
        ),
        (
            lambda: mn.GyroscopeModel(Z3, Z3, Z33, Z33, bias_correlation_time=-1.0),
            "bias_correlation_time: must be finite and non-negative",
        ),
        (lambda: mn.GyroscopeModel(Z3, Z3, Z33, Z33, bias_instability=-1.0), "bias_instability:"),
        (lambda: mn.GyroscopeModel(Z3, Z3, Z33, Z33, bias_random_walk=-1.0), "bias_random_walk:"),
        (lambda: mn.GyroscopeModel(Z3, Z3, Z33, Z33, quantization=np.nan), "quantization:"),
        (lambda: mn.GyroscopeModel(Z3, Z3, Z33, np.full((3, 3), np.nan)), "g_sensitivity:"),
        (lambda: mn.GyroscopeModel(Z3, Z3, diagonal_misalignment(), Z33), "misalignment: diag"),
        (lambda: mn.ImuModel.preset("mems"), "name: unknown preset 'mems'; expected one of"),
        (lambda: mn.ImuModel.preset("consumer", seed=-1), "seed: must be None or an integer"),
        (lambda: mn.ImuModel.preset("consumer", sample_rate=-5.0), "sample_rate:"),
        (
            lambda: mn.ImuModel(ideal_accel(), mn.GyroscopeModel(Z3, Z3, Z33, Z33, sample_rate=50)),
            "sample_rate: the accelerometer runs at 100",
        ),
        (
            lambda: mn.ImuModel(ideal_accel(), mn.GyroscopeModel(Z3, Z3, Z33, Z33), spec={"x": 1}),
            "spec: unknown key 'x'",
        ),
        (
            lambda: mn.ImuModel(
                ideal_accel(), mn.GyroscopeModel(Z3, Z3, Z33, Z33), spec={"gyro_bias_std": -1}
            ),
            r"spec\['gyro_bias_std'\]: must be finite and non-negative",
        ),
    ],
)
def test_bad_construction_names_the_argument(build, message):
    with pytest.raises(ValueError, match=message):
        build()


@pytest.mark.parametrize(
    ("call", "message"),
    [
        (lambda a, g, i: a.measure(np.zeros((5, 2))), r"specific_force: expected shape \(N, 3\)"),
        (lambda a, g, i: a.measure(np.zeros(3)), r"specific_force: expected shape \(N, 3\)"),
        (lambda a, g, i: a.measure([[0, np.nan, 0]]), "specific_force: row 0, column 1 is NaN"),
        (lambda a, g, i: a.measure("x"), "specific_force: must be an array of real numbers"),
        (lambda a, g, i: g.measure(np.zeros((5, 3)), np.zeros((4, 3))), "specific_force: has 4"),
        (lambda a, g, i: g.measure([[np.inf, 0, 0]], [[0, 0, 0]]), "angular_rate: row 0, column 0"),
        (lambda a, g, i: i.measure(np.zeros((5, 3)), np.zeros((6, 3))), "angular_rate: has 6"),
        (lambda a, g, i: a.measure(np.zeros((5, 3)), seed=1.5), "seed: must be None"),
    ],
)
def test_bad_measure_input_names_the_argument(call, message):
    imu = mn.ImuModel.preset("paper-mems", seed=0)
    with pytest.raises(ValueError, match=message):
        call(imu.accelerometer, imu.gyroscope, imu)
