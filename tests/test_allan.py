"""Allan deviation (``memsnav_core::allan``) against a direct numpy
implementation of the overlapping estimator and against the slopes of
white noise (q/√τ) and of a random walk (K√(τ/3), IEEE Std 952 table C.1)
on long seeded series."""

import numpy as np
import pytest

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
