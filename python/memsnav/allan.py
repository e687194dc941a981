"""Allan deviation of inertial sensor samples (IEEE Std 952-1997, annex C;
El-Sheimy et al. 2008): noise densities and bias instability from a static
record."""

from __future__ import annotations

import numpy as np
from numpy.typing import ArrayLike


def allan_deviation(
    samples: ArrayLike, rate_hz: float, taus: ArrayLike | None = None
) -> tuple[np.ndarray, np.ndarray]:
    """Overlapping Allan deviation of ``samples`` ``(N,)`` or ``(N, k)``
    taken at ``rate_hz``.

    ``taus``: averaging times, s (default: about 10 per decade from one
    sample to a ninth of the record). Returns ``(taus, adev)``, ``adev`` of
    shape ``(len(taus),)`` or ``(len(taus), k)`` in the samples' unit.
    For white noise of density q (unit·√s), adev(τ) = q/√τ, so the white
    noise density is adev read at τ = 1 s on the -1/2 slope.
    """
    x = np.asarray(samples, dtype=float)
    if x.ndim not in (1, 2) or x.shape[0] < 3 or not np.all(np.isfinite(x)):
        raise ValueError("samples: expected a finite (N,) or (N, k) array with N >= 3")
    if not (np.isfinite(rate_hz) and rate_hz > 0):
        raise ValueError(f"rate_hz: must be positive, got {rate_hz}")
    n = x.shape[0]
    if taus is None:
        m = np.unique(np.round(np.logspace(0, np.log10(max(n // 9, 1)), 40)).astype(int))
    else:
        tau_in = np.asarray(taus, dtype=float)
        m = np.round(tau_in * rate_hz).astype(int)
        if np.any(m < 1) or np.any(2 * m >= n):
            raise ValueError(
                "taus: each must lie between 1/rate_hz and "
                f"half the record ({n / rate_hz / 2:.1f} s)"
            )
    theta = np.concatenate([np.zeros((1, *x.shape[1:])), np.cumsum(x, axis=0)]) / rate_hz
    adev = []
    for mi in m:
        tau = mi / rate_hz
        d = theta[2 * mi :] - 2.0 * theta[mi:-mi] + theta[: -2 * mi]
        adev.append(np.sqrt(np.sum(d**2, axis=0) / (2.0 * tau**2 * (n - 2 * mi))))
    return m / rate_hz, np.asarray(adev)
