"""Array arguments are read by value, whatever their memory layout: a
C-contiguous float64 array is copied as one slice, every other layout
(Fortran order, strided views, other dtypes, lists) element by element in
C order. The results must not depend on which path was taken."""

from __future__ import annotations

import numpy as np
import pytest

import memsnav as mn


def _layouts(a: np.ndarray) -> dict[str, object]:
    """The same values as a Fortran array, a strided view, a negative-stride
    view of a reversed copy and a nested list."""
    wide = np.zeros((a.shape[0], 2 * a.shape[1]))
    wide[:, ::2] = a
    return {
        "fortran": np.asfortranarray(a),
        "strided": wide[:, ::2],
        "negative strides": a[::-1].copy()[::-1],
        "list": a.tolist(),
    }


def test_geodetic_conversion_reads_every_layout_alike() -> None:
    rng = np.random.default_rng(7)
    xyz = np.array([6378137.0, 0.0, 0.0]) + rng.normal(0.0, 2e4, size=(50, 3))
    expected = mn.ecef_to_geodetic(np.ascontiguousarray(xyz))
    for name, arg in _layouts(xyz).items():
        assert np.array_equal(mn.ecef_to_geodetic(arg), expected), name


def test_strapdown_reads_every_layout_alike() -> None:
    n = 200
    time = np.arange(n) * 0.01
    rng = np.random.default_rng(3)
    f = np.array([0.1, -0.2, -9.8]) + rng.normal(0.0, 0.05, size=(n, 3))
    w = rng.normal(0.0, 0.01, size=(n, 3))
    r0 = mn.geodetic_to_ecef([0.7, 0.2, 100.0])
    c0 = np.eye(3)
    expected = mn.strapdown(time, f, w, r0, np.zeros(3), c0).position_ecef
    f_layouts, w_layouts = _layouts(f), _layouts(w)
    for name in f_layouts:
        got = mn.strapdown(time, f_layouts[name], w_layouts[name], r0, np.zeros(3), c0)
        assert np.array_equal(got.position_ecef, expected), name


@pytest.mark.parametrize("bad", [np.nan, np.inf])
def test_non_finite_values_are_named_in_every_layout(bad: float) -> None:
    xyz = np.tile([6378137.0, 0.0, 0.0], (4, 1))
    xyz[2, 1] = bad
    for arg in _layouts(xyz).values():
        with pytest.raises(ValueError, match="row 2, column 1"):
            mn.ecef_to_geodetic(arg)
