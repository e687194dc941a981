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

# --- sensors (method §2) -------------------------------------------------------

@final
class AccelerometerModel:
    """Accelerometer triad, method §2 (paper eq. 2), SI units.

    ``S = Q((I - D - M) (Γ - (b + β + r) - N (Γ ⊙ Γ) - nu))``

    ``bias`` (3,) m/s²; ``scale_factor`` (3,) D; ``misalignment`` (3, 3) M with
    a zero diagonal (``M[i, j]`` couples input axis j into output axis i);
    ``nonlinearity`` (3,) N, 1/(m/s²).

    Noise (all optional, zero = off, m/s² based): ``noise_std`` white
    input-referred noise nu, std per sample; or ``noise_density`` the same per
    √Hz (velocity random walk, m/s²/√Hz), std per sample = density ·
    √sample_rate (give one, not both); ``sample_rate`` Hz;
    ``bias_instability`` steady-state std (m/s²) of a first-order Gauss-Markov
    bias β with correlation time ``bias_correlation_time`` s, started from its
    stationary distribution; ``bias_random_walk`` r's growth, m/s²/√s,
    starting at zero; ``quantization`` output LSB, m/s². β and r add to
    ``bias``; quantisation rounds the output to a multiple of the LSB.
    """

    def __new__(
        cls,
        bias: npt.ArrayLike,
        scale_factor: npt.ArrayLike,
        misalignment: npt.ArrayLike,
        nonlinearity: npt.ArrayLike,
        noise_std: float = 0.0,
        *,
        noise_density: float | None = None,
        sample_rate: float = 100.0,
        bias_instability: float = 0.0,
        bias_correlation_time: float = 0.0,
        bias_random_walk: float = 0.0,
        quantization: float = 0.0,
    ) -> AccelerometerModel: ...
    def measure(
        self, specific_force: npt.ArrayLike, seed: int | None = None
    ) -> npt.NDArray[np.float64]:
        """Readings (N, 3) m/s² for true specific forces (N, 3) m/s² at ``sample_rate``."""

    @property
    def bias(self) -> npt.NDArray[np.float64]:
        """b, (3,) m/s²."""

    @property
    def scale_factor(self) -> npt.NDArray[np.float64]:
        """D, (3,) dimensionless."""

    @property
    def misalignment(self) -> npt.NDArray[np.float64]:
        """M, (3, 3) dimensionless, zero diagonal."""

    @property
    def nonlinearity(self) -> npt.NDArray[np.float64]:
        """N, (3,) 1/(m/s²)."""

    @property
    def noise_std(self) -> float:
        """White noise std per sample at ``sample_rate``, m/s²."""

    @property
    def noise_density(self) -> float:
        """White noise density, m/s²/√Hz (= noise_std / √sample_rate)."""

    @property
    def sample_rate(self) -> float:
        """Sample rate, Hz."""

    @property
    def bias_instability(self) -> float:
        """Gauss-Markov bias steady-state std, m/s²."""

    @property
    def bias_correlation_time(self) -> float:
        """Gauss-Markov bias correlation time, s."""

    @property
    def bias_random_walk(self) -> float:
        """Random-walk bias growth, m/s²/√s."""

    @property
    def quantization(self) -> float:
        """Output LSB, m/s² (0: none)."""

    def __getnewargs_ex__(self) -> tuple[tuple[object, ...], dict[str, object]]: ...
    def __eq__(self, value: object, /) -> bool: ...

@final
class GyroscopeModel:
    """Gyroscope triad, method §2 (paper eq. 3), SI units.

    ``S = Q((I - D - M) (Ω - (b + β + r) - K Γ - nu))``

    ``bias`` (3,) rad/s; ``scale_factor`` (3,) D; ``misalignment`` (3, 3) M
    with a zero diagonal; ``g_sensitivity`` (3, 3) K, (rad/s)/(m/s²), row i =
    gyro axis i's sensitivity to the three specific-force components.

    Noise keywords as :class:`AccelerometerModel`, in rad/s: ``noise_density``
    is the angle random walk (rad/s/√Hz), ``bias_random_walk`` the rate random
    walk (rad/s/√s).
    """

    def __new__(
        cls,
        bias: npt.ArrayLike,
        scale_factor: npt.ArrayLike,
        misalignment: npt.ArrayLike,
        g_sensitivity: npt.ArrayLike,
        noise_std: float = 0.0,
        *,
        noise_density: float | None = None,
        sample_rate: float = 100.0,
        bias_instability: float = 0.0,
        bias_correlation_time: float = 0.0,
        bias_random_walk: float = 0.0,
        quantization: float = 0.0,
    ) -> GyroscopeModel: ...
    def measure(
        self,
        angular_rate: npt.ArrayLike,
        specific_force: npt.ArrayLike,
        seed: int | None = None,
    ) -> npt.NDArray[np.float64]:
        """Readings (N, 3) rad/s for true rates (N, 3) rad/s and specific forces (N, 3) m/s²."""

    @property
    def bias(self) -> npt.NDArray[np.float64]:
        """b, (3,) rad/s."""

    @property
    def scale_factor(self) -> npt.NDArray[np.float64]:
        """D, (3,) dimensionless."""

    @property
    def misalignment(self) -> npt.NDArray[np.float64]:
        """M, (3, 3) dimensionless, zero diagonal."""

    @property
    def g_sensitivity(self) -> npt.NDArray[np.float64]:
        """K, (3, 3) (rad/s)/(m/s²)."""

    @property
    def noise_std(self) -> float:
        """White noise std per sample at ``sample_rate``, rad/s."""

    @property
    def noise_density(self) -> float:
        """White noise density (angle random walk), rad/s/√Hz."""

    @property
    def sample_rate(self) -> float:
        """Sample rate, Hz."""

    @property
    def bias_instability(self) -> float:
        """Gauss-Markov bias steady-state std, rad/s."""

    @property
    def bias_correlation_time(self) -> float:
        """Gauss-Markov bias correlation time, s."""

    @property
    def bias_random_walk(self) -> float:
        """Random-walk bias growth (rate random walk), rad/s/√s."""

    @property
    def quantization(self) -> float:
        """Output LSB, rad/s (0: none)."""

    def __getnewargs_ex__(self) -> tuple[tuple[object, ...], dict[str, object]]: ...
    def __eq__(self, value: object, /) -> bool: ...

@final
class ImuModel:
    """An accelerometer and a gyroscope triad sampled together, plus the spec
    (one-sigma magnitudes) their errors come from.

    ``sample_rate=None`` takes the sensors' common rate (an error if they
    differ); another rate keeps each sensor's noise *density* (noise given per
    sample is converted at the sensor's own rate). ``spec`` overrides keys of
    the derived spec, whose defaults are the RMS of the models' own values
    (noise: the models' own). ``.spec`` is a dict of floats, SI units, keys
    ``accel_`` / ``gyro_`` + ``bias_std``, ``scale_factor_std``,
    ``misalignment_std``, ``nonlinearity_std`` (accel, 1/(m/s²)) or
    ``g_sensitivity_std`` (gyro, (rad/s)/(m/s²)), ``noise_density`` (per √Hz),
    ``bias_instability``, ``bias_correlation_time`` (s), ``bias_random_walk``
    (per √s), ``quantization``. The coupled filters tune Q and the initial
    bias covariance from it.
    """

    def __new__(
        cls,
        acc: AccelerometerModel,
        gyr: GyroscopeModel,
        sample_rate: float | None = None,
        *,
        spec: dict[str, float] | None = None,
    ) -> ImuModel: ...
    @staticmethod
    def preset(name: str, seed: int | None = None, sample_rate: float = 100.0) -> ImuModel:
        """A named grade ("paper-mems", "consumer", "industrial", "tactical",
        "navigation"), every error term drawn zero-mean Gaussian from its spec."""

    @staticmethod
    def presets() -> list[str]:
        """The names :meth:`preset` accepts."""

    def measure(
        self,
        specific_force: npt.ArrayLike,
        angular_rate: npt.ArrayLike,
        seed: int | None = None,
    ) -> tuple[npt.NDArray[np.float64], npt.NDArray[np.float64]]:
        """Readings ``(accel m/s², gyro rad/s)``, each (N, 3), for true specific
        forces (N, 3) m/s² and angular rates (N, 3) rad/s."""

    @property
    def accelerometer(self) -> AccelerometerModel:
        """The accelerometer triad (at the IMU's rate)."""

    @property
    def gyroscope(self) -> GyroscopeModel:
        """The gyroscope triad (at the IMU's rate)."""

    @property
    def sample_rate(self) -> float:
        """Sample rate of both triads, Hz."""

    @property
    def spec(self) -> dict[str, float]:
        """One-sigma magnitudes of every error term and the noise parameters, SI."""

    def __getnewargs_ex__(self) -> tuple[tuple[object, ...], dict[str, object]]: ...
    def __eq__(self, value: object, /) -> bool: ...

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
