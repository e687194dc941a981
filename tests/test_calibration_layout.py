"""The calibration parameter layout (``memsnav_core::calibration::layout``)
and the drive calibration's numerics in the core (AR(1) covariance
inflation, calibrations drawn from their covariance): against the
calibrations' own names and models, the rules the Python code used to
re-derive the layout with, a direct numpy implementation of the inflation,
and the statistics of many draws."""

import math

import numpy as np
import pytest

import memsnav as mn
from memsnav import _memsnav
from memsnav.calibration.drive import parameter_index
from memsnav.experiments.calibration import ACCELEROMETER_GROUPS, AXES, GYROSCOPE_GROUPS

LAYOUTS = {s: _memsnav.CalibrationLayout(s) for s in ("accelerometer", "gyroscope")}


@pytest.fixture(scope="module")
def calibrations():
    """An accelerometer and a gyroscope calibration of noise-free data
    (every parameter distinct and estimated)."""
    rng = np.random.default_rng(3)
    mis = rng.normal(scale=0.01, size=(3, 3))
    np.fill_diagonal(mis, 0.0)
    acc = mn.AccelerometerModel(
        rng.normal(scale=0.1, size=3), rng.normal(scale=1e-2, size=3), mis, [1e-4, 2e-4, 3e-4]
    )
    gyr = mn.GyroscopeModel(
        rng.normal(scale=1e-3, size=3),
        rng.normal(scale=1e-2, size=3),
        mis.T,
        rng.normal(scale=1e-4, size=(3, 3)),
    )
    f, w = rng.normal(scale=6.0, size=(400, 3)), rng.normal(scale=0.5, size=(400, 3))
    return (
        mn.calibrate_accelerometer(acc.measure(f, seed=0), f, sample_rate=50.0),
        mn.calibrate_gyroscope(gyr.measure(w, f, seed=0), w, f, sample_rate=50.0),
    )


def _by_name(name: str) -> tuple[str, tuple[int, ...]]:
    """The rule the drive calibration parsed names with before the layout:
    the group is what precedes the last underscore, each letter after it
    an axis (u, v, w and p, q, r both 0, 1, 2)."""
    group, letters = name.rsplit("_", 1)
    return group, tuple("uvwpqr".index(c) % 3 for c in letters)


def test_layout_is_the_calibrations_parameter_vector(calibrations):
    for layout, cal in zip(LAYOUTS.values(), calibrations, strict=True):
        assert layout.names == cal.parameter_names
        assert len(layout) == len(cal.parameter_names) == cal.covariance.shape[0]
        values = layout.values(cal.model)
        for i, name in enumerate(layout.names):
            group, index = layout.parameter(i)
            assert (group, index) == _by_name(name) == parameter_index(name)
            assert layout.index(name) == i
            assert values[i] == np.asarray(getattr(cal.model, group))[index]
        # The way back: the same model, noise-free, at the given rate.
        back = layout.model(values, sample_rate=cal.model.sample_rate)
        assert type(back) is type(cal.model)
        assert back.sample_rate == 50.0
        for group in layout.groups:
            np.testing.assert_array_equal(getattr(back, group), getattr(cal.model, group))


def test_groups_slices_and_axes():
    for sensor, layout in LAYOUTS.items():
        assert layout.sensor == sensor
        assert layout.axes == list(AXES[sensor])
        covered = []
        for group in layout.groups:
            s = layout.group_slice(group)
            indices = list(range(len(layout)))[s]
            assert indices == layout.indices(group=group)
            assert all(n.startswith(group + "_") for n in layout.names[s])
            covered += indices
            # Each group split by output axis: the first letter after the group.
            by_axis = [layout.indices(group=group, axis=a) for a in layout.axes]
            assert sorted(i for part in by_axis for i in part) == indices
            for axis, part in zip(layout.axes, by_axis, strict=True):
                assert all(layout.names[i][len(group) + 1] == axis for i in part)
        assert covered == list(range(len(layout)))
    accel, gyro = LAYOUTS["accelerometer"], LAYOUTS["gyroscope"]
    assert ACCELEROMETER_GROUPS == {g: accel.group_slice(g) for g in accel.groups}
    assert GYROSCOPE_GROUPS == {g: gyro.group_slice(g) for g in gyro.groups}
    assert list(GYROSCOPE_GROUPS) == ["bias", "scale_factor", "misalignment", "g_sensitivity"]
    assert gyro.parameter(17) == ("g_sensitivity", (1, 2))
    assert accel.parameter(7) == ("misalignment", (0, 2))


def test_bad_arguments_name_themselves(calibrations):
    with pytest.raises(ValueError, match="sensor"):
        _memsnav.CalibrationLayout("magnetometer")
    accel = LAYOUTS["accelerometer"]
    with pytest.raises(ValueError, match="name"):
        accel.index("bias_p")
    with pytest.raises(ValueError, match="name"):
        parameter_index("bias_x")
    with pytest.raises(ValueError, match="group"):
        accel.group_slice("g_sensitivity")
    with pytest.raises(ValueError, match="axis"):
        accel.indices(axis="p")
    with pytest.raises(ValueError, match="index"):
        accel.parameter(15)
    with pytest.raises(ValueError, match="model"):
        accel.values(calibrations[1].model)
    with pytest.raises(ValueError, match="values"):
        accel.model(np.zeros(21))
    singular = np.zeros(15)
    singular[3] = 1.0  # D_uu = 1: I - D - M singular
    with pytest.raises(ValueError):
        accel.model(singular)


# --- the drive calibration's covariance inflation -----------------------------


def _ar1_factor(residual):
    """(1 + ρ)/(1 − ρ) of the lag-one autocorrelation ρ (capped at 0.9), at
    least 1 (Wilks eq. 5.12): the drive calibration's rule, written out."""
    r = residual - residual.mean()
    if r @ r == 0.0:
        return 1.0
    rho = min((r[1:] @ r[:-1]) / (r @ r), 0.9)
    return max(1.0, (1.0 + rho) / (1.0 - rho))


def _inflated(names, covariance, factors, held, bias_cov, scale_cov):
    """Each entry scaled by √(f_a f_b) of its parameters' output axes (the
    first letter after the group), plus the inherited covariance on the
    bias and scale-factor blocks of the parameters not held."""
    axes = np.array([_by_name(n)[1][0] for n in names])
    out = covariance * np.sqrt(np.outer(factors[axes], factors[axes]))
    for group, inherited in (("bias", bias_cov), ("scale_factor", scale_cov)):
        index = [i for i, n in enumerate(names) if _by_name(n)[0] == group and n not in held]
        keep = [axes[i] for i in index]
        out[np.ix_(index, index)] += inherited[np.ix_(keep, keep)]
    return out


@pytest.mark.parametrize("sensor", ["accelerometer", "gyroscope"])
def test_inflation_matches_its_formula(sensor):
    rng = np.random.default_rng(7)
    layout = LAYOUTS[sensor]
    p = len(layout)
    a = rng.normal(size=(p, p))
    covariance = a @ a.T
    held = [layout.names[4], layout.names[p - 1]]
    for name in held:
        i = layout.index(name)
        covariance[i, :] = covariance[:, i] = 0.0
    # Residuals: an AR(1) series (ρ ≈ 0.6), white noise, a trend (ρ capped).
    e = rng.normal(size=(300, 3))
    residual = e.copy()
    for k in range(1, 300):
        residual[k, 0] = 0.6 * residual[k - 1, 0] + e[k, 0]
    residual[:, 2] = np.linspace(0.0, 1.0, 300) + 0.01 * e[:, 2]
    b, s = rng.normal(size=(3, 3)), rng.normal(size=(3, 3))
    bias_cov, scale_cov = b @ b.T, s @ s.T
    out, factors = _memsnav.inflate_calibration_covariance(
        sensor,
        covariance,
        residual,
        held=held,
        bias_covariance=bias_cov,
        scale_factor_covariance=scale_cov,
    )
    expected_factors = np.array([_ar1_factor(residual[:, j]) for j in range(3)])
    np.testing.assert_allclose(factors, expected_factors, rtol=1e-12)
    assert 3.0 < factors[0] < 5.0 and factors[2] == pytest.approx(19.0, rel=1e-3)
    expected = _inflated(layout.names, covariance, factors, held, bias_cov, scale_cov)
    np.testing.assert_allclose(out, expected, rtol=1e-12, atol=1e-15)
    for name in held:
        assert not out[layout.index(name)].any()
    with pytest.raises(ValueError, match="held"):
        _memsnav.inflate_calibration_covariance(
            sensor,
            covariance,
            residual,
            held=["bias_x"],
            bias_covariance=bias_cov,
            scale_factor_covariance=scale_cov,
        )
    with pytest.raises(ValueError, match="covariance"):
        _memsnav.inflate_calibration_covariance(
            sensor,
            covariance[1:, 1:],
            residual,
            held=[],
            bias_covariance=bias_cov,
            scale_factor_covariance=scale_cov,
        )


# --- calibrations drawn from their covariance ---------------------------------


def _covariances():
    """Covariances with strong correlations, variances orders of magnitude
    apart, and held (zero-variance) parameters."""
    rng = np.random.default_rng(11)
    out = []
    for p, held in ((15, [5, 12, 13, 14]), (21, [14, 17, 20])):
        a = rng.normal(size=(p, p + 5))
        r = a @ a.T
        d = np.sqrt(np.diag(r))
        scale = 10.0 ** rng.uniform(-6, -1, size=p)
        c = (r / np.outer(d, d)) * np.outer(scale, scale)
        c[held, :] = c[:, held] = 0.0
        out.append((rng.normal(scale=1e-2, size=p), c, held))
    return out


def test_draws_have_the_given_mean_and_covariance():
    (ma, ca, ha), (mg, cg, hg) = _covariances()
    n = 20_000
    a, g = _memsnav.draw_imu_calibrations(ma, ca, mg, cg, draws=n, seed=3)
    assert a.shape == (n, 15) and g.shape == (n, 21)
    for x, mean, c, held in ((a, ma, ca, ha), (g, mg, cg, hg)):
        # A held parameter stays at its estimate exactly.
        assert np.all(x[:, held] == mean[held])
        sd = np.sqrt(np.diag(c))
        # Mean: standard error σ/√n; covariance about the given mean:
        # standard error √((Σ_ii Σ_jj + Σ_ij²)/n); 5 standard errors.
        assert np.all(np.abs((x - mean).mean(axis=0)) <= 5.0 * sd / math.sqrt(n))
        d = x - mean
        s = d.T @ d / n
        se = np.sqrt((np.outer(sd**2, sd**2) + c**2) / n)
        assert np.all(np.abs(s - c) <= 5.0 * se)
    # The accelerometer and gyroscope draws are independent of each other.
    free_a = np.setdiff1d(np.arange(15), ha)
    free_g = np.setdiff1d(np.arange(21), hg)
    cross = np.corrcoef(a[:, free_a].T, g[:, free_g].T)[: len(free_a), len(free_a) :]
    assert np.abs(cross).max() < 5.0 / math.sqrt(n)


def test_draw_i_depends_only_on_seed_and_i():
    (ma, ca, ha), (mg, cg, _) = _covariances()
    few = _memsnav.draw_imu_calibrations(ma, ca, mg, cg, draws=3, seed=5)
    many = _memsnav.draw_imu_calibrations(ma, ca, mg, cg, draws=40, seed=5)
    for x, y in zip(few, many, strict=True):
        np.testing.assert_array_equal(x, y[:3])
    free = np.setdiff1d(np.arange(15), ha)
    other = _memsnav.draw_imu_calibrations(ma, ca, mg, cg, draws=3, seed=6)
    assert not np.any(other[0][:, free] == few[0][:, free])
    assert not np.any(few[0][0, free] == few[0][1, free])


def test_draws_refuse_bad_covariances():
    (ma, ca, _), (mg, cg, _) = _covariances()
    indefinite = ca.copy()
    indefinite[0, 1] = indefinite[1, 0] = 2.0 * math.sqrt(ca[0, 0] * ca[1, 1])
    with pytest.raises(ValueError, match="accelerometer_covariance: not positive semi"):
        _memsnav.draw_imu_calibrations(ma, indefinite, mg, cg, draws=1, seed=0)
    with pytest.raises(ValueError, match="gyroscope_covariance"):
        _memsnav.draw_imu_calibrations(ma, ca, mg, cg[:20, :20], draws=1, seed=0)
    with pytest.raises(ValueError, match="gyroscope_mean"):
        _memsnav.draw_imu_calibrations(ma, ca, mg[:20], cg, draws=1, seed=0)
