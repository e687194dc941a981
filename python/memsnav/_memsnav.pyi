"""Type stubs of the native module (checked by ``mypy.stubtest``)."""

import os
from collections.abc import Sequence
from typing import final

import numpy as np
import numpy.typing as npt

__version__: str

class MemsnavError(Exception): ...
class UnobservableError(MemsnavError): ...
class DivergenceError(MemsnavError): ...
class ParseError(ValueError): ...

def geodetic_to_ecef(lla: npt.ArrayLike) -> npt.NDArray[np.float64]:
    """Geodetic [latitude rad, longitude rad, height m] -> ECEF position, m."""

def ecef_to_geodetic(xyz: npt.ArrayLike) -> npt.NDArray[np.float64]:
    """ECEF position, m -> geodetic [latitude rad, longitude rad, height m]."""

def gravity_ecef(position_ecef: npt.ArrayLike) -> npt.NDArray[np.float64]:
    """Gravity (J2 gravitation plus centrifugal) in ECEF, m/s²."""

# --- trajectory (issue 4) ---

@final
class Trajectory:
    """Truth of a vehicle's motion at the IMU rate: position, velocity and
    attitude in ECEF, and the exact specific force and angular rate in body
    axes (Earth rotation and the gravity model of ``gravity_ecef`` included).
    """

    @staticmethod
    def random(
        duration: float = 600.0,
        rate: float = 100.0,
        seed: int = 0,
        origin: npt.ArrayLike | None = None,
        *,
        heading: float | None = None,
        max_speed: float = 30.0,
        max_longitudinal_acceleration: float = 2.0,
        max_lateral_acceleration: float = 3.0,
        max_yaw_rate: float = 0.4,
        max_slope: float = 0.05,
        stationary_start: float = 0.0,
    ) -> Trajectory:
        """Random land-vehicle motion: cruises, speed changes (sometimes to a
        stop), turns, road slope, body lean and squat; C² smooth.

        duration s, rate Hz, origin [lat rad, lon rad, h m] (default
        Toulouse 43.6° N 1.44° E 150 m), heading rad from north (None:
        random), speeds m/s, accelerations m/s², yaw rate rad/s, slope rad,
        stationary_start: seconds at rest before moving off (0: start moving).
        """

    @staticmethod
    def from_segments(
        segments: Sequence[tuple[str, float] | tuple[str, float, float]],
        origin: npt.ArrayLike | None = None,
        heading: float = 0.0,
        rate: float = 100.0,
    ) -> Trajectory:
        """Scripted motion from rest: ``("accelerate", duration_s,
        target_speed_m_s)``, ``("cruise", duration_s)``, ``("turn",
        duration_s, heading_change_rad)`` (positive right),
        ``("climb", duration_s, path_angle_rad)`` (ramps up and back to
        level), ``("stop", duration_s)``. heading rad, rate Hz."""

    @staticmethod
    def from_profile(path: str | os.PathLike[str], rate: float = 100.0) -> Trajectory:
        """A profile CSV of Groves' book software (t, lat, lon deg, h m,
        v_NED m/s, roll, pitch, yaw deg), smoothed by splines through knots
        0.5 s apart and sampled at ``rate`` Hz. ParseError names file and line."""

    @property
    def time(self) -> npt.NDArray[np.float64]:
        """Sample times, s, (N,)."""
    @property
    def position_ecef(self) -> npt.NDArray[np.float64]:
        """ECEF position, m, (N, 3)."""
    @property
    def velocity_ecef(self) -> npt.NDArray[np.float64]:
        """ECEF velocity, m/s, (N, 3)."""
    @property
    def attitude(self) -> npt.NDArray[np.float64]:
        """Body-to-ECEF rotation matrices, (N, 3, 3)."""
    @property
    def specific_force(self) -> npt.NDArray[np.float64]:
        """True specific force f_ib^b, m/s², (N, 3)."""
    @property
    def angular_rate(self) -> npt.NDArray[np.float64]:
        """True angular rate ω_ib^b, rad/s, (N, 3)."""
    def position_geodetic(self) -> npt.NDArray[np.float64]:
        """[latitude rad, longitude rad, height m], (N, 3)."""
    def velocity_ned(self) -> npt.NDArray[np.float64]:
        """NED velocity, m/s, (N, 3)."""
    def euler_ned(self) -> npt.NDArray[np.float64]:
        """[roll, pitch, yaw] of the body relative to local NED, rad, (N, 3)."""
    def __len__(self) -> int: ...

# --- ins (issue 4) ---

@final
class NavSolution:
    """An INS solution: the state at every input time."""

    @property
    def time(self) -> npt.NDArray[np.float64]:
        """Times, s, (N,)."""
    @property
    def position_ecef(self) -> npt.NDArray[np.float64]:
        """ECEF position, m, (N, 3)."""
    @property
    def velocity_ecef(self) -> npt.NDArray[np.float64]:
        """ECEF velocity, m/s, (N, 3)."""
    @property
    def attitude(self) -> npt.NDArray[np.float64]:
        """Body-to-ECEF rotation matrices, (N, 3, 3)."""
    def __len__(self) -> int: ...

def strapdown(
    time: npt.ArrayLike,
    specific_force: npt.ArrayLike,
    angular_rate: npt.ArrayLike,
    position_ecef: npt.ArrayLike,
    velocity_ecef: npt.ArrayLike,
    attitude: npt.ArrayLike,
    *,
    scheme: str = "cubic",
) -> NavSolution:
    """Strapdown INS in ECEF (Earth rate, Coriolis, J2 gravity) from
    instantaneous samples: time s (N,), specific_force m/s² and angular_rate
    rad/s (N, 3) in body axes, initial position m, velocity m/s (3,) and
    body-to-ECEF attitude (3, 3). scheme "cubic" (default): cubic
    interpolation of the samples with coning/sculling, fourth order;
    "trapezoid": the two-sample second-order step the filters chain."""

def strapdown_increments(
    time: npt.ArrayLike,
    delta_velocity: npt.ArrayLike,
    delta_angle: npt.ArrayLike,
    position_ecef: npt.ArrayLike,
    velocity_ecef: npt.ArrayLike,
    attitude: npt.ArrayLike,
) -> NavSolution:
    """Strapdown INS from increments with coning and sculling corrections:
    time s (N + 1,), delta_velocity m/s and delta_angle rad (N, 3), row k
    integrated over [time[k], time[k + 1]]; initial state as ``strapdown``."""

def imu_increments(
    time: npt.ArrayLike, specific_force: npt.ArrayLike, angular_rate: npt.ArrayLike
) -> tuple[npt.NDArray[np.float64], npt.NDArray[np.float64]]:
    """(delta_velocity m/s, delta_angle rad), each (N - 1, 3): the integrals
    of the cubic through the samples over each interval (fourth order)."""
