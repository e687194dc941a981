"""Allan deviation (``memsnav_core::allan``) against a direct numpy
implementation of the overlapping estimator and against the slopes of
white noise (q/√τ) and of a random walk (K√(τ/3), IEEE Std 952 table C.1)
on long seeded series."""

import warnings
from pathlib import Path

import numpy as np
import pytest
from figures import figures

import memsnav as mn


def _overlapping_adev(y: np.ndarray, rate: float, m: int) -> float:
    """Riley (NIST SP 1065) eq. 11 from the definition: the averages of
    the clusters of m samples starting at every sample, and half the mean
    squared difference of each with the one m samples later."""
    c = np.concatenate([[0.0], np.cumsum(y)])
    averages = (c[m:] - c[:-m]) / m
    d = averages[m:] - averages[:-m]
    return float(np.sqrt(np.mean(d**2) / 2.0))


def test_matches_a_direct_implementation():
    rng = np.random.default_rng(1)
    rate = 20.0
    y = np.column_stack(
        [
            rng.normal(size=3000) + 0.5,
            np.cumsum(rng.normal(size=3000)) * 0.01 + np.linspace(0, 1, 3000),
        ]
    )
    taus, adev = mn.allan_deviation(y, rate, taus=[0.05, 0.35, 2.0, 40.0, 74.95])
    np.testing.assert_allclose(taus, [0.05, 0.35, 2.0, 40.0, 74.95])
    assert adev.shape == (5, 2)
    for i, tau in enumerate(taus):
        m = round(tau * rate)
        for k in range(2):
            assert adev[i, k] == pytest.approx(_overlapping_adev(y[:, k], rate, m), rel=1e-9)
    # One column alone gives the same numbers, shape (len(taus),).
    taus1, adev1 = mn.allan_deviation(y[:, 1], rate, taus=taus)
    np.testing.assert_array_equal(taus1, taus)
    assert adev1.shape == (5,)
    np.testing.assert_allclose(adev1, adev[:, 1], rtol=1e-12)


def test_white_noise_and_random_walk_slopes():
    rate, sigma, n = 100.0, 0.02, 400_000
    rng = np.random.default_rng(5)
    white = rng.normal(0.0, sigma, n)
    walk = np.cumsum(rng.normal(0.0, sigma, n))
    taus, adev = mn.allan_deviation(np.column_stack([white, walk]), rate, taus=[0.1, 1.0, 10.0])
    q = sigma / np.sqrt(rate)  # white noise density, unit·√s
    k = sigma * np.sqrt(rate)  # random-walk rate, unit/√s
    # Relative error of the estimate: about 1/√(2N/m) for white noise, a
    # few times more for the random walk (fewer effective degrees of freedom).
    rel = 4.0 / np.sqrt(2.0 * n / (taus * rate))
    np.testing.assert_array_less(np.abs(adev[:, 0] / (q / np.sqrt(taus)) - 1.0), rel)
    np.testing.assert_array_less(
        np.abs(adev[:, 1] / (k * np.sqrt(taus / 3.0)) - 1.0), np.maximum(rel, 0.1)
    )


def test_default_taus_span_one_sample_to_a_ninth_of_the_record():
    n, rate = 9000, 10.0
    taus, adev = mn.allan_deviation(np.random.default_rng(2).normal(size=n), rate)
    assert taus[0] == pytest.approx(1.0 / rate)
    assert taus[-1] == pytest.approx(n / 9 / rate)
    assert np.all(np.diff(taus) > 0) and len(taus) <= 40
    assert np.allclose(taus * rate, np.round(taus * rate))
    assert adev.shape == taus.shape


def test_bad_input_names_the_argument():
    x = np.random.default_rng(0).normal(size=(600, 2))
    with pytest.raises(ValueError, match="taus"):
        mn.allan_deviation(x, 100.0, taus=[1000.0])
    with pytest.raises(ValueError, match="taus"):
        mn.allan_deviation(x, 100.0, taus=[0.001])
    with pytest.raises(ValueError, match="rate_hz"):
        mn.allan_deviation(x, 0.0)
    bad = x.copy()
    bad[3, 1] = np.nan
    with pytest.raises(ValueError, match="samples"):
        mn.allan_deviation(bad, 100.0)
    with pytest.raises(ValueError, match="samples"):
        mn.allan_deviation(x[:2], 100.0)
    with pytest.raises(ValueError, match="samples"):
        mn.allan_deviation(np.zeros((10, 2, 2)), 100.0)


# --- the noise terms fitted to the Allan variance (memsnav_core::allan_fit) ---


def _record(
    seed: int, rate: float, seconds: float, white: float, gm: tuple[float, float], walk: float
):
    """Three axes of white noise of density ``white`` (unit·√s), a
    stationary first-order Gauss-Markov process (σ, τ) and a random walk of
    rate ``walk`` (unit/√s), simulated here with numpy and scipy, apart
    from the core's own sensor models."""
    from scipy.signal import lfilter

    rng = np.random.default_rng(seed)
    n, dt = int(seconds * rate), 1.0 / rate
    sigma, tau = gm
    phi = np.exp(-dt / tau)
    drive = sigma * np.sqrt(1.0 - phi**2) * rng.normal(size=(n, 3))
    start = sigma * rng.normal(size=3)
    markov = np.column_stack(
        [lfilter([1.0], [1.0, -phi], drive[:, k], zi=[phi * start[k]])[0] for k in range(3)]
    )
    return (
        white * np.sqrt(rate) * rng.normal(size=(n, 3))
        + markov
        + np.cumsum(walk * np.sqrt(dt) * rng.normal(size=(n, 3)), axis=0)
    )


def test_fit_recovers_the_terms_of_an_independent_simulation():
    """10 h at 10 Hz of known white noise, Gauss-Markov bias and random
    walk: each term within three times the spread of its estimate over
    seeds (the core's test measured N 0.24 %, σ 4.0 %, τ 9.8 %, K 11 %)."""
    x = _record(7, 10.0, 36_000.0, 1e-3, (5e-4, 100.0), 2e-5)
    fit = mn.allan_fit(x, 10.0)
    assert fit.white_density == pytest.approx(1e-3, rel=0.0072)
    assert fit.bias_instability == pytest.approx(5e-4, rel=0.12)
    assert fit.bias_correlation_time == pytest.approx(100.0, rel=0.3)
    assert fit.bias_random_walk == pytest.approx(2e-5, rel=0.33)
    assert 1.0 <= fit.min_tau < 1.3 and fit.record_s == pytest.approx(36_000.0)
    # The fitted curve follows the estimate (within its error at each τ).
    taus = fit.taus
    used = taus >= fit.min_tau
    rel = 4.0 / np.sqrt(2.0 * (36_000.0 / taus[used] - 1.0))
    np.testing.assert_array_less(np.abs(fit.model_adev[used] / fit.adev[used] - 1.0), rel)


def _xsens_rest() -> np.ndarray:
    """The 50 s rest of the Xsens session (tests/data/imu-static-poses,
    BSD, raw counts): accelerometer and gyro, (N, 6)."""
    import gzip

    path = Path(__file__).parent / "data" / "imu-static-poses" / "xsens_excerpt.csv.gz"
    with gzip.open(path, "rt") as f:
        x = np.loadtxt(f, delimiter=",", comments="#")
    return x[x[:, 0] < 50e6, 1:]


def test_fit_of_a_real_rest_reads_the_white_noise_and_leaves_the_rest_out():
    """The Xsens gyro at rest, 50 s (counts): its white noise is the IEEE
    952 reading of the −1/2 slope, adev(τ)·√τ at τ ≈ 1 s, within 5 %; the
    bias instability and the random walk are left out, each warning why."""
    gyro = _xsens_rest()[:, 3:]
    with pytest.warns(UserWarning) as caught:
        fit = mn.allan_fit(gyro, 100.0)
    messages = [str(w.message) for w in caught]
    assert len(messages) == 2
    assert messages[0].startswith(
        "bias instability not determined: the record (50.0 s) gives the Allan deviation "
        "up to τ = 5.550 s"
    )
    assert messages[1].startswith("random walk not determined")
    assert fit.bias_instability is None and fit.bias_random_walk is None
    _, adev = mn.allan_deviation(gyro, 100.0, taus=[1.0])
    reading = float(np.sqrt(np.mean(adev[0] ** 2)))
    assert fit.white_density == pytest.approx(reading, rel=0.05)


def test_fit_refuses_a_record_too_short_and_checks_its_arguments():
    gyro = _xsens_rest()[:2000, 3:]
    with pytest.raises(ValueError, match=r"samples: the record \(20.0 s\) gives the Allan"):
        mn.allan_fit(gyro, 100.0)
    with pytest.raises(ValueError, match=r"min_tau: must be finite and positive"):
        mn.allan_fit(gyro, 100.0, min_tau=-1.0)
    with pytest.raises(ValueError, match=r"angular_rate: "):
        mn.imu_spec_from_allan(np.zeros((10, 3)), np.zeros((9, 3)), 100.0)


@pytest.fixture(scope="module")
def drive_0708_start():
    """drive_0708's configuration, its IMU's first 34 s (at rest) and the
    spec their Allan fit gives, with the warnings it raised."""
    from shared_data import shared_data

    from memsnav.realdata.pipeline import read_imu

    data = shared_data("real-imu-gnss/drive_0708/imu_1934.csv").parents[2]
    cfg = mn.load_config(Path(__file__).parents[1] / "examples" / "drive_0708.toml", data)
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")  # the log's cut first and last lines
        _, f, w, _ = read_imu(cfg)
    with warnings.catch_warnings(record=True) as caught:
        warnings.simplefilter("always")
        spec = mn.imu_spec_from_allan(f[:3400], w[:3400], 100.0)
    return cfg, f[:3400], w[:3400], spec, caught


def test_imu_spec_from_the_static_start_of_drive_0708(drive_0708_start):
    """drive_0708 starts with 34 s at rest, engine running: the white noise
    of both triads is determined (engine vibration makes it 3-4 times the
    BMI088-class data sheet's), nothing else, and the entries are
    `[imu_spec]` keys that reach the tuning."""
    _, f, w, spec, caught = drive_0708_start
    assert sorted(spec) == ["accel_noise_density_ug_sqrt_hz", "gyro_arw_deg_sqrt_h"]
    assert len(caught) == 4 and all("the record (34.0 s)" in str(c.message) for c in caught)
    assert all(issubclass(c.category, UserWarning) for c in caught)
    assert 400.0 < spec["accel_noise_density_ug_sqrt_hz"] < 900.0
    assert 1.0 < spec["gyro_arw_deg_sqrt_h"] < 3.0
    # Each entry is the fit in the key's unit: µg/√Hz = 1e-6 g0 (m/s²)·√s,
    # °/√h = 60 °/√s.
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        accel = mn.allan_fit(f, 100.0).white_density
        gyro = mn.allan_fit(w, 100.0).white_density
    assert spec["accel_noise_density_ug_sqrt_hz"] == pytest.approx(accel / 9.80665e-6, rel=1e-12)
    assert spec["gyro_arw_deg_sqrt_h"] == pytest.approx(np.degrees(gyro) * 60.0, rel=1e-12)


def test_the_static_start_spec_is_the_record(drive_0708_start):
    """docs/how-to/tune-for-your-imu.md shows the static start's white
    noise, the consumer preset's and their ratios from
    docs/data/static_start_spec.json (docs/doc_runs.py); today's fit and
    preset agree with it within half the last digit shown (1 µg/√Hz,
    0.01 °/√h, 0.1 for the ratios)."""
    spec, record = drive_0708_start[3], figures("static_start_spec")
    consumer = mn.ImuModel.preset("consumer").spec
    preset = {
        "accel_noise_density_ug_sqrt_hz": consumer["accel_noise_density"] / 9.80665e-6,
        "gyro_arw_deg_sqrt_h": np.degrees(consumer["gyro_noise_density"]) * 60.0,
    }
    steps = {"accel_noise_density_ug_sqrt_hz": 0.5, "gyro_arw_deg_sqrt_h": 0.005}
    for key, step in steps.items():
        assert abs(spec[key] - record["spec"][key]) <= step, (key, spec[key], record["spec"])
        assert abs(preset[key] - record["preset"][key]) <= step, (key, preset[key])
        assert abs(spec[key] / preset[key] - record["ratio"][key]) <= 0.05, key


@pytest.mark.slow
def test_the_drive_with_the_static_start_spec_is_the_record():
    """The table of drive_0708 through the published filter's outage
    windows with the Allan spec over the consumer preset (~15 s): today's
    run agrees with docs/data/static_start_spec.json to the digits the
    table shows (the preset's columns are the benchmark's record)."""
    import doc_runs
    from shared_data import shared_data

    data = shared_data("real-imu-gnss/drive_0708/imu_1934.csv").parents[2]
    fresh, record = doc_runs.static_start_spec(data), figures("static_start_spec")
    steps = {"forward_rms_m": 0.005, "forward_max_m": 0.005, "share": 0.0005}
    steps["smoothed_rms_m"] = 0.005
    assert fresh["windows"].keys() == record["windows"].keys()
    for length, recorded in record["windows"].items():
        for key, step in steps.items():
            value = fresh["windows"][length][key]
            assert abs(value - recorded[key]) <= step + 1e-9, (length, key, value, recorded[key])
