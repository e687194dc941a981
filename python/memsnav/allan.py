"""Allan deviation of inertial sensor samples (IEEE Std 952-1997, annex C;
El-Sheimy et al. 2008): noise densities and bias instability from a static
record. The numerics are the core's (``memsnav_core::allan``)."""

from __future__ import annotations

import numpy as np
from numpy.typing import ArrayLike

from memsnav import _memsnav


def allan_deviation(
    samples: ArrayLike, rate_hz: float, taus: ArrayLike | None = None
) -> tuple[np.ndarray, np.ndarray]:
    """Overlapping Allan deviation of ``samples`` ``(N,)`` or ``(N, k)``
    taken at ``rate_hz`` (Riley, *Handbook of Frequency Stability
    Analysis*, NIST SP 1065, eq. 11).

    ``taus``: averaging times, s, each rounded to whole samples and between
    one sample and half the record (default: 40 log-spaced cluster sizes
    from one sample to a ninth of the record). Returns ``(taus, adev)``,
    ``adev`` of shape ``(len(taus),)`` or ``(len(taus), k)`` in the
    samples' unit. For white noise of density q (unit·√s), adev(τ) = q/√τ,
    so the white noise density is adev read at τ = 1 s on the -1/2 slope;
    a random walk of rate K (unit/√s) gives K·√(τ/3).
    """
    return _memsnav.allan_deviation(samples, rate_hz, taus)
