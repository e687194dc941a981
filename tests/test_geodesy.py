"""Geodesy against independent values: published coordinates, an independent
closed-form inversion (Heikkinen 1982), round trips and the free-air gradient."""

import math

import numpy as np
import pytest
from figures import figures

import memsnav as mn

# WGS84 (TR8350.2) written out here, independently of the Rust constants.
A = 6378137.0
F = 1 / 298.257223563
E2 = F * (2 - F)
B = A * (1 - F)


def heikkinen(xyz: np.ndarray) -> np.ndarray:
    """Closed-form ECEF -> geodetic (Heikkinen 1982, as in Zhu 1994)."""
    x, y, z = xyz
    ep2 = (A**2 - B**2) / B**2
    p = math.hypot(x, y)
    f_ = 54 * B**2 * z**2
    g = p**2 + (1 - E2) * z**2 - E2 * (A**2 - B**2)
    c = E2**2 * f_ * p**2 / g**3
    s = (1 + c + math.sqrt(c**2 + 2 * c)) ** (1 / 3)
    k = s + 1 + 1 / s
    pp = f_ / (3 * k**2 * g**2)
    q = math.sqrt(1 + 2 * E2**2 * pp)
    r0 = -(pp * E2 * p) / (1 + q) + math.sqrt(
        A**2 / 2 * (1 + 1 / q) - pp * (1 - E2) * z**2 / (q * (1 + q)) - pp * p**2 / 2
    )
    u = math.sqrt((p - E2 * r0) ** 2 + z**2)
    v = math.sqrt((p - E2 * r0) ** 2 + (1 - E2) * z**2)
    z0 = B**2 * z / (A * v)
    return np.array([math.atan((z + ep2 * z0) / p), math.atan2(y, x), u * (1 - B**2 / (A * v))])


def test_published_station_coordinates():
    # IGS station WTZR (Wettzell), ITRF ECEF and its geodetic coordinates as
    # published in the IGS site log: 49°08'39.1" N, 12°52'44.1" E, 666.0 m.
    wtzr = np.array([4075580.3, 931853.9, 4801568.2])
    lla = mn.ecef_to_geodetic(wtzr)
    assert math.degrees(lla[0]) == pytest.approx(49 + 8 / 60 + 39.1 / 3600, abs=0.1 / 3600)
    assert math.degrees(lla[1]) == pytest.approx(12 + 52 / 60 + 44.1 / 3600, abs=0.1 / 3600)
    assert lla[2] == pytest.approx(666.0, abs=0.5)


def test_matches_independent_closed_form():
    rng = np.random.default_rng(1)
    lat = rng.uniform(-1.5, 1.5, 200)
    lon = rng.uniform(-math.pi, math.pi, 200)
    h = rng.uniform(-1000.0, 30e6, 200)
    lla = np.stack([lat, lon, h], axis=-1)
    xyz = mn.geodetic_to_ecef(lla)
    ours = mn.ecef_to_geodetic(xyz)
    for row, expected in zip(ours, (heikkinen(r) for r in xyz), strict=True):
        assert row[0] == pytest.approx(expected[0], abs=1e-11)  # 0.06 mm on the ground
        assert row[2] == pytest.approx(expected[2], abs=1e-4)
    np.testing.assert_allclose(ours[:, 0], lat, atol=1e-12)
    np.testing.assert_allclose(ours[:, 2], h, atol=1e-6)


def test_round_trip_at_the_poles_under_a_millimetre():
    for lat in (math.pi / 2, -math.pi / 2, math.pi / 2 - 1e-10):
        for h in (0.0, 8848.0, -400.0):
            xyz = mn.geodetic_to_ecef([lat, 0.7, h])
            back = mn.geodetic_to_ecef(mn.ecef_to_geodetic(xyz))
            assert np.linalg.norm(back - xyz) < 1e-6
    pole = mn.ecef_to_geodetic([0.0, 0.0, B])
    assert pole[0] == pytest.approx(math.pi / 2, abs=1e-15)
    assert pole[2] == pytest.approx(0.0, abs=1e-9)


def test_vectorised_over_leading_dimensions():
    lla = np.zeros((4, 5, 3))
    lla[..., 0] = np.linspace(-1, 1, 5)
    xyz = mn.geodetic_to_ecef(lla)
    assert xyz.shape == (4, 5, 3)
    assert mn.gravity_ecef(xyz).shape == (4, 5, 3)
    np.testing.assert_allclose(mn.ecef_to_geodetic(xyz), lla, atol=1e-9)


def test_gravity_magnitude_and_direction():
    # At the equator on the ellipsoid normal gravity is 9.7803253 m/s²
    # (Somigliana); the J2 model used by the INS agrees to 5e-5 m/s².
    g = mn.gravity_ecef(mn.geodetic_to_ecef([0.0, 0.0, 0.0]))
    assert np.linalg.norm(g) == pytest.approx(9.7803253359, abs=5e-5)
    assert g[0] < 0 and abs(g[1]) < 1e-12 and abs(g[2]) < 1e-9
    # Free-air gradient ≈ -3.086e-6 s^-2.
    g1 = mn.gravity_ecef(mn.geodetic_to_ecef([0.0, 0.0, 1000.0]))
    assert (np.linalg.norm(g1) - np.linalg.norm(g)) / 1000 == pytest.approx(-3.086e-6, rel=0.01)


@pytest.mark.parametrize(
    ("value", "message"),
    [
        (np.zeros((4, 2)), r"lla: expected shape \(\.\.\., 3\)"),
        ([0.0, float("nan"), 0.0], "lla: element 1 is NaN"),
        ("abc", "lla: must be an array of real numbers"),
    ],
)
def test_bad_input_names_the_argument(value, message):
    with pytest.raises(ValueError, match=message):
        mn.geodetic_to_ecef(value)


def test_the_j2_model_departs_from_somigliana_as_recorded():
    """docs/explanation/concepts.md shows how far gravity_ecef departs from
    WGS84 normal gravity (Somigliana) from docs/data/somigliana_departure.json:
    on the ellipsoid, against Somigliana's closed form with the WGS84
    constants (NIMA TR8350.2 eq. 4-1, table 3.4), largest at a pole, and
    within the digits shown (two significant figures at the poles, one at
    the equator)."""
    recorded = figures("somigliana_departure")
    lat = np.radians(np.linspace(-90.0, 90.0, 181))
    lla = np.stack([lat, np.zeros_like(lat), np.zeros_like(lat)], axis=1)
    g = np.linalg.norm(mn.gravity_ecef(mn.geodetic_to_ecef(lla)), axis=1)
    s2 = np.sin(lat) ** 2
    normal = 9.7803253359 * (1 + 0.00193185265241 * s2) / np.sqrt(1 - 0.00669437999013 * s2)
    departure = np.abs(g - normal)
    assert departure.max() == pytest.approx(recorded["largest_m_s2"], abs=0.05e-4)
    assert departure.argmax() in (0, len(lat) - 1)
    assert departure[90] == pytest.approx(recorded["equator_m_s2"], abs=0.5e-5)
    assert departure.max() < 2e-4
