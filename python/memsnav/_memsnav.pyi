"""Type stubs of the native module (checked by ``mypy.stubtest``)."""

from collections.abc import Callable
from typing import Any, final

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

# --- calibration (method §3), inversion (method §4), experiments (paper §5.1-5.2) ---

@final
class Calibration:
    """A calibrated sensor model with its uncertainties (method §3)."""

    @property
    def model(self) -> AccelerometerModel | GyroscopeModel:
        """The estimated model (same class as the calibrated sensor)."""

    @property
    def std(self) -> AccelerometerModel | GyroscopeModel:
        """One-sigma uncertainties in the model's attributes (SI)."""

    @property
    def covariance(self) -> npt.NDArray[np.float64]:
        """Covariance of the parameter vector, ordered as ``parameter_names``."""

    @property
    def crb(self) -> npt.NDArray[np.float64] | None:
        """Cramér-Rao bound of the parameter vector (exact references), if
        ``noise_std`` was given."""

    @property
    def crb_std(self) -> AccelerometerModel | GyroscopeModel | None:
        """Square root of the bound's diagonal, in the model's attributes."""

    @property
    def parameter_names(self) -> list[str]:
        """Names of the parameters in covariance order (``bias_u``, ...)."""

    @property
    def residual_std(self) -> npt.NDArray[np.float64]:
        """Residual standard deviation per output axis (3,), SI."""

    @property
    def condition_number(self) -> npt.NDArray[np.float64]:
        """Condition number of the column-equilibrated regressors per axis (3,)."""

    @property
    def warnings(self) -> list[str]:
        """Parameters that are only poorly determined (also raised as UserWarning)."""

def calibrate_accelerometer(
    measured: npt.ArrayLike,
    reference_specific_force: npt.ArrayLike,
    *,
    method: str = "ls",
    reference_noise_std: float | None = None,
    noise_std: float | None = None,
    sample_rate: float = 100.0,
) -> Calibration:
    """Accelerometer calibration from outputs and reference specific forces,
    both (N, 3) m/s². ``method``: "ls" or "eiv" (needs ``reference_noise_std``,
    m/s² per sample). ``noise_std`` (m/s² per sample) enables ``.crb``.
    Raises UnobservableError naming the axis and parameter."""

def calibrate_gyroscope(
    measured: npt.ArrayLike,
    reference_angular_rate: npt.ArrayLike,
    reference_specific_force: npt.ArrayLike,
    *,
    method: str = "ls",
    reference_noise_std: float | None = None,
    reference_specific_force_noise_std: float | None = None,
    noise_std: float | None = None,
    sample_rate: float = 100.0,
) -> Calibration:
    """Gyroscope calibration from outputs (N, 3) rad/s, reference angular
    rates (N, 3) rad/s and specific forces (N, 3) m/s². ``method``: "ls" or
    "eiv" (needs ``reference_noise_std``, rad/s per sample)."""

def invert_accelerometer(
    measured: npt.ArrayLike,
    model: AccelerometerModel,
    process_std: npt.ArrayLike,
    measurement_std: npt.ArrayLike,
    *,
    return_variance: bool = False,
) -> Any:
    """Specific force (N, 3) m/s² from accelerometer outputs by the random-walk
    EKF (method §4); noise stds per sample, scalar or (3,). With
    ``return_variance=True``: ``(estimate, variance)``."""

def invert_gyroscope(
    measured: npt.ArrayLike,
    specific_force: npt.ArrayLike,
    model: GyroscopeModel,
    process_std: npt.ArrayLike,
    measurement_std: npt.ArrayLike,
    *,
    return_variance: bool = False,
) -> Any:
    """Angular rate (N, 3) rad/s from gyro outputs and the estimated specific
    force (N, 3) m/s² by the EKF of method §4; noise stds in rad/s per sample."""

def calibration_experiment(
    *,
    parameter_sets: int = 50,
    runs: int = 20,
    duration: float = 300.0,
    preset: str = "paper-mems",
    reference_specific_force_std: float = 0.03,
    reference_angular_rate_std: float = 0.0017453292519943296,
    seed: int = 0,
    threads: int | None = None,
    progress: Callable[[int], None] | None = None,
) -> dict[str, Any]:
    """Calibration Monte Carlo (paper figs 3-10); per-set arrays, SI."""

def inversion_experiment(
    *,
    runs: int = 50,
    duration: float = 120.0,
    calibration_duration: float = 300.0,
    preset: str = "paper-mems",
    method: str = "eiv",
    reference_specific_force_std: float = 0.03,
    reference_angular_rate_std: float = 0.0017453292519943296,
    accel_process_std: float = 0.1,
    gyro_process_std: float = 0.017453292519943295,
    seed: int = 0,
    threads: int | None = None,
    progress: Callable[[int], None] | None = None,
) -> dict[str, Any]:
    """Inversion Monte Carlo (paper figs 11-12); per-run MSE arrays, SI."""
