"""Finding time offsets in real logs from the data themselves.

``estimate_time_offset``: the offset to add to IMU times that aligns the
IMU with GNSS positions, by cross-correlating the body forward specific
force with the rate of change of the GNSS speed (or the body yaw rate with
the course rate), both as means under the same triangle (Knapp & Carter,
IEEE Trans. ASSP 24(4), 1976, for the correlation method).

``estimate_velocity_latency``: how late a GNSS solution's velocity is
behind its own positions.

The numerics are in the Rust core (``memsnav_core::timing``); see
``docs/explanation/time-and-truth.md`` for the method and the numbers on the example logs.
"""

from __future__ import annotations

from collections.abc import Sequence
from dataclasses import dataclass
from typing import Protocol

import numpy as np

from memsnav import _memsnav

__all__ = [
    "GnssPositions",
    "GnssVelocities",
    "TimeOffsetEstimate",
    "VelocityLatencyEstimate",
    "estimate_time_offset",
    "estimate_velocity_latency",
]


class GnssPositions(Protocol):
    """GNSS positions: a ``PosSolution`` (``read_pos``) or any object with
    ``gps_time`` (N,) s and ``lla`` (N, 3) [lat rad, lon rad, h m] (and
    ``quality`` (N,), RTKLIB's Q, to select epochs by)."""

    @property
    def gps_time(self) -> np.ndarray: ...

    @property
    def lla(self) -> np.ndarray: ...


class GnssVelocities(GnssPositions, Protocol):
    """``GnssPositions`` with ``velocity_ned`` (N, 3) m/s."""

    @property
    def velocity_ned(self) -> np.ndarray: ...


@dataclass(frozen=True)
class TimeOffsetEstimate:
    """The IMU time offset found in a log.

    ``offset_s``: add it to the IMU times (the peak of the correlation,
    refined between grid steps); ``std_s``: its standard error from the
    spread of ``block_offsets_s``, the offsets found in ``len(block_offsets_s)``
    consecutive stretches of the log; ``correlation``: the peak correlation;
    ``curvature``: −d²(correlation)/d(offset)² at the peak, 1/s² (a sharp peak
    is a well-determined offset); ``lag_s`` and ``correlation_curve``: the
    searched offsets and their correlation; ``epochs``: GNSS epochs used.
    """

    offset_s: float
    std_s: float
    correlation: float
    curvature: float
    block_offsets_s: np.ndarray
    lag_s: np.ndarray
    correlation_curve: np.ndarray
    epochs: int

    def __repr__(self) -> str:
        return (
            f"TimeOffsetEstimate(offset {self.offset_s:+.3f} s ± {self.std_s:.3f}, "
            f"correlation {self.correlation:.2f}, {len(self.block_offsets_s)} stretches, "
            f"{self.epochs} epochs)"
        )


@dataclass(frozen=True)
class VelocityLatencyEstimate:
    """How late a GNSS velocity is behind the positions of the same solution.

    ``latency_s``: positive when the velocity is late; ``std_s``: standard
    error from ``block_latencies_s`` (consecutive stretches of the log);
    ``rms_m_s``: RMS velocity difference at the latency; ``curvature``:
    d²(mean square)/d(latency)² there, m²/s⁴; ``lag_s`` and ``rms_curve_m_s``:
    the searched latencies and their RMS; ``epochs``: intervals used.
    """

    latency_s: float
    std_s: float
    rms_m_s: float
    curvature: float
    block_latencies_s: np.ndarray
    lag_s: np.ndarray
    rms_curve_m_s: np.ndarray
    epochs: int

    def __repr__(self) -> str:
        return (
            f"VelocityLatencyEstimate(latency {self.latency_s:.3f} s ± {self.std_s:.3f}, "
            f"RMS difference {self.rms_m_s:.3f} m/s, {self.epochs} intervals)"
        )


def _epochs(gnss: GnssPositions, quality: Sequence[int] | None) -> np.ndarray:
    """Indices of the epochs whose Q is in ``quality`` (all for None or
    when ``gnss`` has no ``quality``)."""
    q = getattr(gnss, "quality", None)
    if quality is None or q is None:
        return np.arange(len(gnss.gps_time))
    return np.flatnonzero(np.isin(q, list(quality)))


def estimate_time_offset(
    imu_time: np.ndarray,
    specific_force: np.ndarray,
    angular_rate: np.ndarray,
    gnss: GnssPositions,
    *,
    signal: str = "along_track",
    quality: Sequence[int] | None = (1, 2),
    max_offset_s: float = 1.0,
    step_s: float = 0.005,
    min_speed_m_s: float = 2.0,
    blocks: int = 4,
) -> TimeOffsetEstimate:
    """The offset to add to ``imu_time`` that best aligns the IMU with the
    GNSS positions of ``gnss`` (a ``PosSolution`` from ``read_pos``, or any
    object with ``gps_time`` and ``lla`` arrays, see ``GnssPositions``).

    ``imu_time``: the IMU on GPS time as mapped so far (for example by
    ``fit_tag_clock``), s, ``(N,)``; ``specific_force`` m/s² and
    ``angular_rate`` rad/s in body axes forward-right-down (the mounting
    applied), ``(N, 3)``. ``signal``: ``"along_track"`` compares the forward
    specific force with the rate of change of the GNSS speed (insensitive
    to how the vehicle turns; the default), ``"yaw_rate"`` the body yaw rate
    with the course rate (biased where the course lags the heading: side-slip,
    a walker turning the device before the path). Only GNSS epochs with Q in
    ``quality`` (None: all) moving faster than ``min_speed_m_s`` on both
    sides count. Offsets from −``max_offset_s`` to ``max_offset_s`` every
    ``step_s`` are tried; a best offset at the edge is an error (widen the
    window). The search is repeated on ``blocks`` consecutive stretches for
    ``std_s``.
    """
    keep = _epochs(gnss, quality)
    e = _memsnav.estimate_time_offset(
        imu_time,
        specific_force,
        angular_rate,
        np.asarray(gnss.gps_time)[keep],
        np.asarray(gnss.lla)[keep],
        signal,
        max_offset_s,
        step_s,
        min_speed_m_s,
        blocks,
    )
    return TimeOffsetEstimate(
        offset_s=e.lag_s,
        std_s=e.std_s,
        correlation=e.score,
        curvature=e.curvature,
        block_offsets_s=e.block_lag_s,
        lag_s=e.curve_lag_s,
        correlation_curve=e.curve_score,
        epochs=e.samples,
    )


def estimate_velocity_latency(
    gnss: GnssVelocities,
    *,
    quality: Sequence[int] | None = (1, 2),
    max_latency_s: float = 0.5,
    step_s: float = 0.005,
    blocks: int = 4,
) -> VelocityLatencyEstimate:
    """How late the velocity of ``gnss`` (a ``PosSolution`` with velocity
    columns, or any object with ``gps_time``, ``lla`` and ``velocity_ned``
    arrays) is behind its own positions, s.

    The velocity's mean over each interval [t_j + L, t_{j+1} + L] is compared
    with the mean velocity of the positions over [t_j, t_{j+1}]; the
    latency L minimises the RMS difference (a velocity that is the backward
    difference of the positions has L = h/2). Only epochs with Q in
    ``quality`` (None: all) count; gaps are left out. Latencies from
    −``max_latency_s`` to ``max_latency_s`` every ``step_s`` are tried; the
    search is repeated on ``blocks`` consecutive stretches for ``std_s``.
    """
    keep = _epochs(gnss, quality)
    e = _memsnav.estimate_velocity_latency(
        np.asarray(gnss.gps_time)[keep],
        np.asarray(gnss.lla)[keep],
        np.asarray(gnss.velocity_ned)[keep],
        max_latency_s,
        step_s,
        blocks,
    )
    return VelocityLatencyEstimate(
        latency_s=e.lag_s,
        std_s=e.std_s,
        rms_m_s=e.score,
        curvature=e.curvature,
        block_latencies_s=e.block_lag_s,
        lag_s=e.curve_lag_s,
        rms_curve_m_s=e.curve_score,
        epochs=e.samples,
    )
