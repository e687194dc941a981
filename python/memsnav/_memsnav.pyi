"""Type stubs of the native module (checked by ``mypy.stubtest``)."""

import os
from collections.abc import Callable, Mapping, Sequence
from typing import Any, final

import numpy as np
import numpy.typing as npt

__version__: str

class MemsnavError(Exception):
    """Base class of memsnav's estimation failures."""

class UnobservableError(MemsnavError):
    """The data cannot determine a parameter (rank-deficient or badly conditioned problem)."""

class DivergenceError(MemsnavError):
    """A filter diverged: its covariance stopped being positive definite or its state became
    non-finite.
    """

class ParseError(ValueError):
    """A data file could not be read; the message names the file and the line."""

def geodetic_to_ecef(lla: npt.ArrayLike) -> npt.NDArray[np.float64]:
    """ECEF position, m, of `lla`: geodetic [latitude rad, longitude rad,
    height m] (3,) or (N, 3), WGS84.
    """

def ecef_to_geodetic(xyz: npt.ArrayLike) -> npt.NDArray[np.float64]:
    """Geodetic [latitude rad, longitude rad, height m] of `xyz`: ECEF
    positions, m, (3,) or (N, 3), WGS84.
    """

def ecef_to_ned(
    position_ecef: npt.ArrayLike, origin_ecef: npt.ArrayLike
) -> npt.NDArray[np.float64]:
    """`position_ecef` (..., 3) minus `origin_ecef` (3,) in the local
    north, east, down axes at the origin, m.
    """

def gravity_ecef(position_ecef: npt.ArrayLike) -> npt.NDArray[np.float64]:
    """Gravity (J2 gravitation plus centrifugal) in ECEF, m/s², at
    `position_ecef` (3,) or (N, 3), m.
    """

# --- sensors (method §2) -------------------------------------------------------

@final
class AccelerometerModel:
    """Accelerometer triad, method §2 (paper eq. 2), SI units:
    S = Q((I − D − M)(Γ − (b + β + ρ) − N (Γ ⊙ Γ) − ν)).

    `bias` (3,) m/s²; `scale_factor` (3,) D; `misalignment` (3, 3) M with a
    zero diagonal (M[i, j] couples input axis j into output axis i);
    `nonlinearity` (3,) N, 1/(m/s²).

    Noise keywords (all optional, zero = off, units of the sensor's output):
    `noise_std` white input-referred noise ν, std per sample; or
    `noise_density` the same as a density per √Hz (velocity / angle random
    walk), std per sample = density · √sample_rate (give one, not both);
    `sample_rate` Hz; `bias_instability` steady-state std of a first-order
    Gauss-Markov bias with correlation time `bias_correlation_time` s,
    started stationary; `bias_random_walk` bias growth per √s, starting at
    zero; `quantization` output LSB (readings rounded to a multiple of it).
    The Gauss-Markov and random-walk biases add to `bias`; quantisation acts
    on the output.
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
        sample_rate: float | None = None,
        bias_instability: float = 0.0,
        bias_correlation_time: float = 0.0,
        bias_random_walk: float = 0.0,
        quantization: float = 0.0,
    ) -> AccelerometerModel: ...
    def measure(
        self, specific_force: npt.ArrayLike, seed: int | None = None
    ) -> npt.NDArray[np.float64]:
        """Readings for true specific forces, sampled at `sample_rate`.

        - `specific_force` (N, 3) m/s²: the true input in body axes.
        - `seed`: the noise's random stream, an integer in [0, 2**64) [0].
        """

    @property
    def bias(self) -> npt.NDArray[np.float64]:
        """Bias b, (3,) m/s², per sensor axis."""

    @property
    def scale_factor(self) -> npt.NDArray[np.float64]:
        """Scale-factor errors D, (3,) dimensionless, per sensor axis."""

    @property
    def misalignment(self) -> npt.NDArray[np.float64]:
        """Misalignment M, (3, 3) dimensionless with a zero diagonal:
        `M[i, j]` couples input axis j into output axis i.
        """

    @property
    def nonlinearity(self) -> npt.NDArray[np.float64]:
        """Nonlinearity N, (3,) 1/(m/s²), per sensor axis."""

    @property
    def noise_std(self) -> float:
        """White noise std per sample at `sample_rate`, m/s²."""

    @property
    def noise_density(self) -> float:
        """White noise density (velocity random walk), m/s²/√Hz (= noise_std / √sample_rate)."""

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
    """Gyroscope triad, method §2 (paper eq. 3), SI units:
    S = Q((I − D − M)(Ω − (b + β + ρ) − K Γ − ν)).

    `bias` (3,) rad/s; `scale_factor` (3,) D; `misalignment` (3, 3) M with a
    zero diagonal; `g_sensitivity` (3, 3) K, (rad/s)/(m/s²), row i = gyro
    axis i's sensitivity to the three specific-force components.

    Noise keywords (all optional, zero = off, units of the sensor's output):
    `noise_std` white input-referred noise ν, std per sample; or
    `noise_density` the same as a density per √Hz (velocity / angle random
    walk), std per sample = density · √sample_rate (give one, not both);
    `sample_rate` Hz; `bias_instability` steady-state std of a first-order
    Gauss-Markov bias with correlation time `bias_correlation_time` s,
    started stationary; `bias_random_walk` bias growth per √s, starting at
    zero; `quantization` output LSB (readings rounded to a multiple of it).
    The Gauss-Markov and random-walk biases add to `bias`; quantisation acts
    on the output.
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
        sample_rate: float | None = None,
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
        """Readings for true angular rates, sampled at `sample_rate`.

        - `angular_rate` (N, 3) rad/s: the true input in body axes.
        - `specific_force` (N, 3) m/s²: the true specific force (for the
          g-sensitivity).
        - `seed`: the noise's random stream, an integer in [0, 2**64) [0].
        """

    @property
    def bias(self) -> npt.NDArray[np.float64]:
        """Bias b, (3,) rad/s, per sensor axis."""

    @property
    def scale_factor(self) -> npt.NDArray[np.float64]:
        """Scale-factor errors D, (3,) dimensionless, per sensor axis."""

    @property
    def misalignment(self) -> npt.NDArray[np.float64]:
        """Misalignment M, (3, 3) dimensionless with a zero diagonal:
        `M[i, j]` couples input axis j into output axis i.
        """

    @property
    def g_sensitivity(self) -> npt.NDArray[np.float64]:
        """g-sensitivity K, (3, 3) (rad/s)/(m/s²): row i is gyro axis i's
        sensitivity to the three specific-force components.
        """

    @property
    def noise_std(self) -> float:
        """White noise std per sample at `sample_rate`, rad/s."""

    @property
    def noise_density(self) -> float:
        """White noise density (angle random walk), rad/s/√Hz (= noise_std / √sample_rate)."""

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
    """An accelerometer and a gyroscope triad sampled together, with the spec
    (one-sigma magnitudes) their errors come from.

    `ImuModel(acc, gyr, sample_rate=None, *, spec=None)`: `sample_rate` None
    takes the sensors' common rate; a different rate keeps each sensor's
    noise density (per-sample noise is converted at the sensor's own rate).
    `spec` is a dict overriding some keys of the derived spec, whose default
    magnitudes are the RMS of the models' own values. `ImuModel.preset(name,
    seed=None, sample_rate=None)` draws a grade from its spec (at 100 Hz
    unless given); names in
    `ImuModel.presets()`. `.spec` is a dict of one-sigma magnitudes, SI:
    accel_/gyro_ + bias_std, scale_factor_std, misalignment_std,
    nonlinearity_std (accel, 1/(m/s²)) or g_sensitivity_std (gyro,
    (rad/s)/(m/s²)), noise_density (per √Hz), bias_instability,
    bias_correlation_time (s), bias_random_walk (per √s), quantization.
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
    def preset(name: str, seed: int | None = None, sample_rate: float | None = None) -> ImuModel:
        """A named grade, every error term drawn zero-mean Gaussian from its spec.

        - `name`: "paper-mems", "consumer", "industrial", "tactical" or
          "navigation" (`presets()`).
        - `seed`: the draw's random stream, an integer in [0, 2**64) [0].
        - `sample_rate`: Hz [100].
        """

    @staticmethod
    def presets() -> list[str]:
        """The preset names `preset` accepts."""

    def measure(
        self,
        specific_force: npt.ArrayLike,
        angular_rate: npt.ArrayLike,
        seed: int | None = None,
    ) -> tuple[npt.NDArray[np.float64], npt.NDArray[np.float64]]:
        """Readings ``(accel m/s², gyro rad/s)``, each (N, 3), sampled at the
        model's `sample_rate`.

        - `specific_force` (N, 3) m/s² and `angular_rate` (N, 3) rad/s: the
          true inputs in body axes.
        - `seed`: the noise's random stream, an integer in [0, 2**64) [0].
        """

    @property
    def accelerometer(self) -> AccelerometerModel:
        """The accelerometer triad, at the IMU's sample rate."""

    @property
    def gyroscope(self) -> GyroscopeModel:
        """The gyroscope triad, at the IMU's sample rate."""

    @property
    def sample_rate(self) -> float:
        """Sample rate of both triads, Hz."""

    @property
    def spec(self) -> dict[str, float]:
        """One-sigma magnitudes of every error term and the noise parameters,
        SI: a dict keyed `accel_…` / `gyro_…` (listed in the class doc).
        """

    def __getnewargs_ex__(self) -> tuple[tuple[object, ...], dict[str, object]]: ...
    def __eq__(self, value: object, /) -> bool: ...

# --- calibration (method §3), inversion (method §4), experiments (paper §5.1-5.2) ---

@final
class Calibration:
    """A calibrated sensor model with its uncertainties (method §3).

    `model`: the estimated `AccelerometerModel` / `GyroscopeModel`.
    `std`: an object of the same class whose parameter attributes hold the
    one-sigma uncertainties (SI). `covariance`: covariance of the parameter
    vector ordered as `parameter_names`. `residual_std` (3,): residual
    standard deviation per output axis. `condition_number` (3,): of the
    column-equilibrated regressors per axis. `crb`: Cramér-Rao bound of the
    parameter vector (None unless `noise_std` was given) for references with
    the noise the calibration was given (`reference_noise_std`: the
    errors-in-variables bound; exact references without); `crb_std`: its
    square-root diagonal as a model-shaped object.
    `warnings`: parameters that are only poorly determined. `held`:
    [(parameter, reason)] not estimated under `estimate="determinable"`.
    """

    @property
    def model(self) -> AccelerometerModel | GyroscopeModel:
        """The estimated model: an `AccelerometerModel` or `GyroscopeModel`, like
        the calibrated sensor.
        """

    @property
    def std(self) -> AccelerometerModel | GyroscopeModel:
        """One-sigma uncertainties (SI) in the attributes of an object of the
        model's class.
        """

    @property
    def covariance(self) -> npt.NDArray[np.float64]:
        """Covariance of the parameter vector, ordered as `parameter_names`, SI."""

    @property
    def crb(self) -> npt.NDArray[np.float64] | None:
        """Cramér-Rao bound of the parameter vector (ordered as `parameter_names`),
        None unless `noise_std` was given: for references with the noise given as
        `reference_noise_std` (the errors-in-variables bound), exact references without.
        """

    @property
    def crb_std(self) -> AccelerometerModel | GyroscopeModel | None:
        """Square root of the Cramér-Rao bound's diagonal in the model's
        attributes (SI); None unless `noise_std` was given.
        """

    @property
    def parameter_names(self) -> list[str]:
        """Names of the parameters in covariance order (`bias_u`, …)."""

    @property
    def residual_std(self) -> npt.NDArray[np.float64]:
        """Residual standard deviation per output axis, (3,) m/s² or rad/s."""

    @property
    def condition_number(self) -> npt.NDArray[np.float64]:
        """Condition number of the column-equilibrated regressors per output axis, (3,)."""

    @property
    def warnings(self) -> list[str]:
        """Parameters that are only poorly determined (each also raised as a
        `UserWarning`).
        """

    @property
    def held(self) -> list[tuple[str, str]]:
        """[(parameter, reason)] of the parameters not estimated under
        `estimate="determinable"` (held at zero, with zero variance).
        """

def calibrate_accelerometer(
    measured: npt.ArrayLike,
    reference_specific_force: npt.ArrayLike,
    *,
    method: str = "ls",
    reference_noise_std: float | None = None,
    noise_std: float | None = None,
    sample_rate: float | None = None,
    estimate: str = "all",
) -> Calibration:
    """Calibrates an accelerometer triad (method §3): `measured` (N, 3) outputs
    and `reference_specific_force` (N, 3) reference inputs, m/s², body axes.
    `method`: "ls" (plain least squares) or "eiv" (errors-in-variables
    correction for noisy references; needs `reference_noise_std`, m/s² per
    sample). `noise_std`: the sensor's white noise per sample (m/s²); when
    given, `.crb` holds the Cramér-Rao bound. `sample_rate` (Hz) is stored
    in the returned model. `estimate`: "all" (every parameter; data that
    cannot determine one raise `UnobservableError`) or "determinable" (only
    what the data determine; the rest held at zero and listed in `.held`;
    the rule is in docs/how-to/calibrate-an-imu.md).
    """

def calibrate_gyroscope(
    measured: npt.ArrayLike,
    reference_angular_rate: npt.ArrayLike,
    reference_specific_force: npt.ArrayLike,
    *,
    method: str = "ls",
    reference_noise_std: float | None = None,
    reference_specific_force_noise_std: float | None = None,
    noise_std: float | None = None,
    sample_rate: float | None = None,
    estimate: str = "all",
) -> Calibration:
    """Calibrates a gyroscope triad (method §3): `measured` (N, 3) outputs
    (rad/s), `reference_angular_rate` (N, 3) rad/s and
    `reference_specific_force` (N, 3) m/s², body axes. `method`: "ls" or
    "eiv" (needs `reference_noise_std`, rad/s per sample; the optional
    `reference_specific_force_noise_std`, m/s², corrects the g-sensitivity
    columns too). `noise_std`: the gyro white noise per sample (rad/s), for
    the Cramér-Rao bound. `estimate`: "all" or "determinable" (static data:
    bias and g-sensitivity only), as for `calibrate_accelerometer`.
    """

@final
class StaticCalibration:
    """The result of `calibrate_static` (see `memsnav.calibrate_static`)."""

    @property
    def accelerometer(self) -> AccelerometerModel:
        """The accelerometer model of the nominal readings (SI), method §2."""

    @property
    def gyroscope(self) -> GyroscopeModel:
        """The gyroscope model of the nominal readings (SI), method §2."""

    @property
    def accelerometer_std(self) -> AccelerometerModel:
        """One-sigma values in the accelerometer's attributes (SI; 0 where not estimated)."""

    @property
    def gyroscope_std(self) -> GyroscopeModel:
        """One-sigma values in the gyroscope's attributes (SI; 0 where not estimated)."""

    @property
    def covariance(self) -> npt.NDArray[np.float64]:
        """Covariance (36, 36) of `parameter_names`."""

    @property
    def crb(self) -> npt.NDArray[np.float64]:
        """Cramér-Rao bound (36, 36) for white noise of the initial rest's level."""

    @property
    def white_noise_variance(self) -> npt.NDArray[np.float64]:
        """White-noise variance per sample at the initial rest, (2, 3):
        accelerometer (m/s²)², gyroscope (rad/s)², nominal readings.
        """

    @property
    def parameters(self) -> npt.NDArray[np.float64]:
        """The 36 parameters in the order of `parameter_names` (SI)."""

    @property
    def parameter_names(self) -> list[str]:
        """ "accelerometer bias_u", …, "gyroscope g_sensitivity_rw"."""

    @property
    def nominal(self) -> dict[str, npt.NDArray[np.float64]]:
        """accel_scale, accel_offset, gyro_scale, gyro_offset, each (3,)."""

    @property
    def gravity(self) -> float:
        """Local gravity magnitude used, m/s²."""

    @property
    def sample_rate(self) -> float:
        """Mean sample rate of the session, Hz."""

    @property
    def poses(self) -> npt.NDArray[np.int64]:
        """(P, 2) start and end (exclusive) sample indices of the poses."""

    @property
    def pose_held_out(self) -> list[bool]:
        """(P,) True for poses left out of the fits."""

    @property
    def magnitude_error_before(self) -> npt.NDArray[np.float64]:
        """(P,) ‖f‖ − g of each pose with the nominal readings, m/s²."""

    @property
    def magnitude_error_after(self) -> npt.NDArray[np.float64]:
        """(P,) ‖f‖ − g of each pose after the calibration, m/s²."""

    @property
    def turn_from(self) -> npt.NDArray[np.int64]:
        """(T,) the first pose of each turn (turn k goes from pose k to k + 1)."""

    @property
    def turn_held_out(self) -> list[bool]:
        """(T,) True for turns into or out of a held-out pose."""

    @property
    def turn_error_before(self) -> npt.NDArray[np.float64]:
        """(T,) gravity-direction error of each turn with the nominal readings, rad."""

    @property
    def turn_error_after(self) -> npt.NDArray[np.float64]:
        """(T,) gravity-direction error of each turn after the calibration, rad."""

    @property
    def held(self) -> list[tuple[str, str]]:
        """[(parameter, reason)] of the parameters not estimated."""

    @property
    def model_selection(self) -> list[dict[str, Any]]:
        """The models of the second-order terms each stage considered (the
        accelerometer's nonlinearity, the gyroscope's g-sensitivity; empty
        under estimate="all"): [{"stage", "chosen" (index), "candidates":
        [{"terms", "parameters", "observations", "residual_rms", "aicc"
        (None when refused), "refused"}]}]."""

    @property
    def warnings(self) -> list[str]:
        """Poor conditioning, a sigma above the physical size, too few poses, a
        nominal scale far off (each also emitted as a `UserWarning`).
        """

    @property
    def variance_magnitude(self) -> npt.NDArray[np.float64]:
        """The detector's accelerometer and gyroscope variance magnitudes per
        sample, (N, 2) (+inf within half a window of the ends).
        """

    @property
    def detector_threshold(self) -> tuple[float, float]:
        """The detector's two thresholds (accelerometer, gyroscope)."""

    @property
    def accelerometer_residual_std(self) -> float:
        """Residual std of the gravity-magnitude fit, m/s²."""

    @property
    def rest_residual_std(self) -> npt.NDArray[np.float64]:
        """(3,) residual std of the gyroscope rest fit per axis, rad/s."""

    @property
    def turn_residual_std(self) -> float:
        """Residual std of the turn fit per direction component, rad."""

    @property
    def condition_number(self) -> npt.NDArray[np.float64]:
        """Condition numbers of the magnitude, rest and turn problems (3,)."""

    def correct(
        self, accel: npt.ArrayLike, gyro: npt.ArrayLike
    ) -> tuple[npt.NDArray[np.float64], npt.NDArray[np.float64]]:
        """SI specific force and angular rate (each (N, 3)) of raw readings."""

def calibrate_static(
    time: npt.ArrayLike,
    accel: npt.ArrayLike,
    gyro: npt.ArrayLike,
    *,
    gravity: float,
    accel_scale: npt.ArrayLike,
    accel_offset: npt.ArrayLike,
    gyro_scale: npt.ArrayLike,
    gyro_offset: npt.ArrayLike,
    window: float,
    threshold_factor: float,
    initial_rest: float,
    min_pose: float,
    estimate: str,
    holdout_every: int | None,
    holdout_from: float | None,
) -> StaticCalibration:
    """Every argument is required here; `memsnav.calibrate_static` documents
    them and holds the defaults (from the core).
    """

def correct_imu(
    accel: npt.ArrayLike,
    gyro: npt.ArrayLike,
    accelerometer: AccelerometerModel,
    gyroscope: GyroscopeModel,
    *,
    accel_scale: npt.ArrayLike,
    accel_offset: npt.ArrayLike,
    gyro_scale: npt.ArrayLike,
    gyro_offset: npt.ArrayLike,
) -> tuple[npt.NDArray[np.float64], npt.NDArray[np.float64]]:
    """SI specific force and angular rate (each (N, 3)) of raw readings
    through nominal scales and offsets and the models' exact inverses.
    """

def static_calibration_defaults() -> dict[str, float]:
    """The core's defaults of the detector and of the nominal readings (scale
    1, offset 0: readings already in SI), for the Python signature.
    """

def calibrated_imu(
    accelerometer: Calibration,
    gyroscope: Calibration,
    *,
    accel_noise_std: float,
    gyro_noise_std: float,
) -> ImuModel:
    """The IMU to tune a coupled filter with when it runs on outputs corrected
    by these calibrations (`invert_accelerometer`, `invert_gyroscope`): the
    calibrated models with the sensors' white noise per sample
    (`accel_noise_std` m/s², `gyro_noise_std` rad/s), and a spec holding
    what the calibrations leave uncertain at a land vehicle's operating
    point (level, g on the vertical axis), from their full covariances:
    terms the motion could not separate count by the combination that
    reaches the output, not by their own large stds
    (`memsnav_core::experiments::calibrate_invert::calibrated_spec`).
    """

@final
class CalibrationLayout:
    """The parameter vector of an accelerometer (15) or gyroscope (21)
    calibration: the order of `Calibration.parameter_names`, `.covariance`
    and `.crb`. Groups in order: `bias` (3), `scale_factor` (3),
    `misalignment` (6, off-diagonal uv, uw, vu, vw, wu, wv) and
    `nonlinearity` (3) or `g_sensitivity` (9, row-major). A parameter's
    output axis is the first letter after its group (u, v, w or p, q, r:
    the body axes x, y, z); a matrix entry's second letter is its column.
    """

    def __new__(cls, sensor: str) -> CalibrationLayout: ...
    @property
    def sensor(self) -> str:
        """ "accelerometer" or "gyroscope"."""

    @property
    def names(self) -> list[str]:
        """The parameter names in index order (`bias_u`, ..., `misalignment_uv`, ...)."""

    @property
    def groups(self) -> list[str]:
        """The groups (model attributes) in index order."""

    @property
    def axes(self) -> list[str]:
        """The triad's output axes: ["u", "v", "w"] or ["p", "q", "r"]."""

    def __len__(self) -> int: ...
    def index(self, name: str) -> int:
        """The index of parameter `name`."""

    def group_slice(self, group: str) -> slice:
        """The indices of `group`, as a slice of the parameter vector."""

    def parameter(self, index: int) -> tuple[str, tuple[int, ...]]:
        """The model attribute and the index in it of parameter `index`:
        ("bias", (0,)), ("misalignment", (0, 2)), ("g_sensitivity", (1, 2)).
        """

    def indices(self, *, group: str | None = None, axis: str | None = None) -> list[int]:
        """The indices, in order, of the parameters of `group` (all groups when
        None) whose output axis is `axis` (a letter of `axes`; all when None).
        """

    def values(self, model: AccelerometerModel | GyroscopeModel) -> npt.NDArray[np.float64]:
        """The parameter vector of `model` (an `AccelerometerModel` or
        `GyroscopeModel` of this layout's sensor).
        """

    def model(
        self, values: npt.ArrayLike, *, sample_rate: float | None = None
    ) -> AccelerometerModel | GyroscopeModel:
        """The noise-free model of this layout's sensor whose parameters are
        `values` (the inverse of `values`), stored with `sample_rate` (Hz)
        [100].
        """

def inflate_calibration_covariance(
    sensor: str,
    covariance: npt.ArrayLike,
    residual: npt.ArrayLike,
    *,
    held: Sequence[str],
    bias_covariance: npt.ArrayLike,
    scale_factor_covariance: npt.ArrayLike,
) -> tuple[npt.NDArray[np.float64], npt.NDArray[np.float64]]:
    """The covariance of a `sensor`'s ("accelerometer" or "gyroscope")
    calibration from correlated references: each output axis' block of
    `covariance` scaled by the AR(1) variance factor (1 + ρ)/(1 − ρ) of that
    axis' column of `residual` (W, 3), ρ its lag-one autocorrelation capped
    at 0.9, the factor at least 1 (Wilks, eq. 5.12), plus the reference
    solution's `bias_covariance` and `scale_factor_covariance` (3, 3) on the
    bias and scale-factor blocks, except for the parameters named in `held`.
    Returns `(covariance, factors)`, factors (3,) per output axis.
    """

def draw_imu_calibrations(
    accelerometer_mean: npt.ArrayLike,
    accelerometer_covariance: npt.ArrayLike,
    gyroscope_mean: npt.ArrayLike,
    gyroscope_covariance: npt.ArrayLike,
    *,
    draws: int,
    seed: int,
) -> tuple[npt.NDArray[np.float64], npt.NDArray[np.float64]]:
    """`draws` calibrations drawn from the Gaussians N(mean, covariance) of an
    accelerometer (15 parameters) and a gyroscope (21) calibration, in
    `CalibrationLayout` order: draw i takes the accelerometer's parameters,
    then the gyroscope's, from its own random stream (seed, i), so it is the
    same whatever `draws` is. A singular covariance (held parameters) is
    fine; one that is not positive semi-definite is refused. Returns
    `(accelerometer, gyroscope)` arrays of shape (draws, 15) and (draws, 21).
    """

@final
class QuantileInterval:
    """An equal-tailed interval for a quantile of the distribution some
    runs were drawn from (`quantile_interval`).
    """

    @property
    def lower(self) -> float:
        """The largest run below the quantile at the confidence (-inf when
        no run bounds that side).
        """

    @property
    def upper(self) -> float:
        """The smallest run above it (inf when no run bounds that side: a
        95th percentile of 20 runs has none).
        """

    @property
    def coverage(self) -> float:
        """The interval's exact coverage, at least the confidence asked for."""

    @property
    def runs_for_upper(self) -> int:
        """The fewest runs that give an upper bound."""

    def to_dict(self) -> dict[str, Any]:
        """The fields as a dict, by attribute name (records inside stay
        records; arrays stay arrays).
        """

def quantile_interval(
    values: npt.ArrayLike, p: float, confidence: float | None = None
) -> QuantileInterval:
    """The equal-tailed `confidence` [0.95] interval for the `p`-quantile of the
    distribution the runs `values` (N,) were drawn from, from their order
    statistics (distribution-free; independent runs, continuous errors):
    a `QuantileInterval` (`lower`, `upper`, `coverage`, `runs_for_upper`).
    """

def sequential_error(looks: Sequence[int], p: float, look_error: float) -> tuple[float, float]:
    """The probability that a cell decided in looks after `looks` runs
    (cumulative, increasing) wrongly decides at some look, when its
    `p`-quantile sits at the requirement and each look's one-sided bounds
    err with probability `look_error`: `(meets, fails)`. Exact (the
    binomial count of runs at or below the requirement, carried from look
    to look; a decision stops the cell).
    """

def sequential_look_error(looks: Sequence[int], p: float, confidence: float | None = None) -> float:
    """The largest per-look one-sided error at which a cell decided in
    `looks` errs, on either side, with probability at most
    `1 - confidence` (`confidence` [0.95]; exact, see `sequential_error`): never below
    Bonferroni's `(1 - confidence) / len(looks)`.
    """

def allan_deviation(
    samples: npt.ArrayLike, rate_hz: float, taus: npt.ArrayLike | None = None
) -> tuple[npt.NDArray[np.float64], npt.NDArray[np.float64]]:
    """Overlapping Allan deviation (IEEE Std 952-1997 annex C; Riley, NIST SP
    1065, eq. 11) of `samples` (N,) or (N, k) taken at `rate_hz`, at the
    averaging times `taus` (s; each rounded to whole samples, between one
    sample and half the record) or, when None, at 40 log-spaced cluster
    sizes from one sample to a ninth of the record. Returns `(taus, adev)`,
    adev of shape (len(taus),) or (len(taus), k) in the samples' unit.
    """

@final
class AllanFit:
    """The noise terms of a static record fitted to its Allan variance
    (`allan_fit`), in the samples' unit; a term the record does not
    determine is None.
    """

    @property
    def white_density(self) -> float | None:
        """White noise N, unit·√s (= unit/√Hz)."""

    @property
    def bias_instability(self) -> float | None:
        """First-order Gauss-Markov bias instability: its std, unit."""

    @property
    def bias_correlation_time(self) -> float | None:
        """Its correlation time, s."""

    @property
    def bias_random_walk(self) -> float | None:
        """Bias random walk K, unit/√s."""

    @property
    def taus(self) -> npt.NDArray[np.float64]:
        """The averaging times fitted, s, (T,)."""

    @property
    def adev(self) -> npt.NDArray[np.float64]:
        """The Allan deviation pooled over the columns, (T,)."""

    @property
    def model_adev(self) -> npt.NDArray[np.float64]:
        """The fitted model's deviation, (T,)."""

    @property
    def min_tau(self) -> float:
        """The shortest averaging time fitted, s."""

    @property
    def record_s(self) -> float:
        """The record's length, s."""

    def to_dict(self) -> dict[str, Any]:
        """The fields as a dict, by attribute name (records inside stay
        records; arrays stay arrays).
        """

def allan_fit(samples: npt.ArrayLike, rate_hz: float, *, min_tau: float | None = None) -> AllanFit:
    """The noise terms of a static record fitted to its Allan variance
    (`memsnav_core::allan_fit`; IEEE Std 952-1997 annex C): white noise N
    (unit·√s = unit/√Hz), a first-order Gauss-Markov bias instability
    (std, unit, and correlation time, s) and a bias random walk K
    (unit/√s), by weighted least squares over the averaging times from
    `min_tau` (s; None: 1 s) on the Allan variance pooled over the columns
    of `samples` (N,) or (N, k) taken at `rate_hz`. A term the record does
    not determine (not half of the curve over a factor 3 of τ) is None and
    raises a `UserWarning` saying why; a record too short for a factor 3 of
    τ from `min_tau` is a `ValueError`. Returns an `AllanFit`:
    `white_density`, `bias_instability`, `bias_correlation_time`,
    `bias_random_walk` (float or None), `taus` (T,), `adev` (T,) pooled,
    `model_adev` (T,) the fitted curve, `min_tau` (the shortest fitted τ),
    `record_s`.
    """

def imu_spec_from_allan(
    specific_force: npt.ArrayLike,
    angular_rate: npt.ArrayLike,
    rate_hz: float,
    *,
    min_tau: float | None = None,
) -> dict[str, float]:
    """The `[imu_spec]` entries (data-sheet keys, their units) of the noise
    terms a static IMU record determines: `allan_fit` of the specific force
    (N, 3) m/s² and of the angular rate (N, 3) rad/s taken at `rate_hz`,
    from `min_tau` (None: 1 s). A Gauss-Markov bias comes as
    `*_bias_markov_std_*` and `*_bias_correlation_time_s`; a term left out
    is absent and raises a `UserWarning` naming its triad and why. Put the
    entries in a configuration's `[imu_spec]` table (or
    `navigate_log(settings={"imu_spec": ...})`): the terms they do not give
    keep the preset's.
    """

def imu_spec_from_datasheet(
    datasheet: dict[str, float], *, base: str | None = None
) -> dict[str, float]:
    """An IMU spec from a data sheet, in the units data sheets use
    (`memsnav_core::sensors::datasheet`; the `[imu_spec]` table of a
    `navigate` configuration, whose keys `navigate_settings()["imu_spec"]`
    lists): `datasheet` maps keys such as `gyro_arw_deg_sqrt_h`,
    `gyro_bias_instability_deg_h` (the Allan floor F; the Gauss-Markov std
    is F / 0.6174) with `gyro_bias_correlation_time_s`,
    `accel_turn_on_bias_mg`, `accel_scale_factor_ppm` to values. The terms
    it leaves out are the preset `base`'s (None: "consumer", the engine's
    default). Returns the spec as `ImuModel.spec` holds it (SI keys), for
    `ImuModel(..., spec=...)` and the navigation experiment's
    `(preset, overrides)`. A bad key or value is a `ValueError` naming
    `imu_spec.key`.
    """

def derive_seed(seed: int, purpose: str) -> int:
    """The seed of the independent draw named `purpose` made from user seed
    `seed`: the first output of its own stream of `seed` (see
    `docs/explanation/concepts.md`, "Seeds"). Use it when one seed must feed several
    functions that each take a seed, instead of `seed + 1`, `seed + 2`, ...
    """

def invert_accelerometer(
    measured: npt.ArrayLike,
    model: AccelerometerModel,
    process_std: npt.ArrayLike,
    measurement_std: npt.ArrayLike,
    *,
    return_variance: bool = False,
) -> Any:
    """Estimates the true specific force (N, 3), m/s², from accelerometer
    outputs `measured` (N, 3) with the random-walk EKF of method §4 and the
    calibrated `model`. `process_std`: std of the random-walk increment per
    sample, `measurement_std`: std of the output noise per sample (m/s²,
    scalar or (3,)). With `return_variance=True` returns `(estimate,
    variance)`, the second the per-sample covariance diagonal.
    """

def invert_gyroscope(
    measured: npt.ArrayLike,
    specific_force: npt.ArrayLike,
    model: GyroscopeModel,
    process_std: npt.ArrayLike,
    measurement_std: npt.ArrayLike,
    *,
    return_variance: bool = False,
) -> Any:
    """Estimates the true angular rate (N, 3), rad/s, from gyroscope outputs
    `measured` (N, 3) and the estimated specific force `specific_force`
    (N, 3, m/s², from `invert_accelerometer`) with the EKF of method §4.
    Noise arguments in rad/s per sample, scalar or (3,).
    """

def land_vehicle_motion(
    duration: float, rate: float, seed: int
) -> tuple[npt.NDArray[np.float64], npt.NDArray[np.float64]]:
    """The body-frame land-vehicle motion of the calibration experiment
    (`memsnav_core::experiments::motion::land_vehicle`: speed changes,
    turns, road roughness, roll and pitch dynamics): `duration` s at `rate`
    Hz from `seed`, as (specific force (N, 3) m/s², angular rate (N, 3) rad/s).
    """

def calibration_experiment(
    *,
    parameter_sets: int | None = None,
    runs: int | None = None,
    duration: float | None = None,
    preset: str | None = None,
    reference_specific_force_std: float | None = None,
    reference_angular_rate_std: float | None = None,
    motion: str | None = None,
    seed: int | None = None,
    threads: int | None = None,
    progress: Callable[[int, int], None] | None = None,
    run_range: tuple[int, int] | None = None,
    chunks: Sequence[bytes] | None = None,
) -> Any:
    """Calibration Monte Carlo (paper figs 3-10); per-set arrays, SI, and the
    ``config`` that ran. ``None``: the core's default (documented in
    ``memsnav.experiments.calibration``). ``run_range=(start, end)``:
    compute only those runs and return them encoded (bytes, a Dask task);
    ``chunks``: fold such encoded runs instead of running (the same numbers
    bit for bit; ``memsnav._distributed``)."""

def inversion_experiment(
    *,
    runs: int | None = None,
    duration: float | None = None,
    calibration_duration: float | None = None,
    preset: str | None = None,
    method: str | None = None,
    reference_specific_force_std: float | None = None,
    reference_angular_rate_std: float | None = None,
    accel_process_std: float | None = None,
    gyro_process_std: float | None = None,
    seed: int | None = None,
    threads: int | None = None,
    progress: Callable[[int, int], None] | None = None,
    run_range: tuple[int, int] | None = None,
    chunks: Sequence[bytes] | None = None,
) -> Any:
    """Inversion Monte Carlo (paper figs 11-12); per-run MSE arrays, SI, and
    the ``config`` that ran. ``None``: the core's default (documented in
    ``memsnav.experiments.inversion``). ``run_range`` / ``chunks`` as in
    ``calibration_experiment``."""

def partial_outage_experiment(
    imus: Sequence[tuple[str, str | ImuModel | tuple[str, dict[str, float]]]],
    *,
    runs: int | None = None,
    duration: float | None = None,
    seed: int | None = None,
    outage_start: float | None = None,
    outage_length: float | None = None,
    satellites: Sequence[int] | None = None,
    loose: bool | None = None,
    calibration_duration: float | None = None,
    smooth: bool | None = None,
    keep_runs: bool | None = None,
    threads: int | None = None,
    progress: Callable[[int, int], object] | None = None,
    run_range: tuple[int, int] | None = None,
    chunks: Sequence[bytes] | None = None,
    n_satellites: int | None = None,
    systems: Sequence[str] | None = None,
    inter_system_bias: tuple[float, float] | Sequence[float] | None = None,
    carrier_phase_std: float | None = None,
    cycle_slip_probability: float | None = None,
) -> Any:
    """Partial-outage study (0-3 satellites through a window, tight against
    loose coupling): ``time``, ``scenarios`` (``coupling``, ``n_visible``,
    ``imus`` as in ``navigation_experiment``), ``completed_runs``,
    ``interrupted``, ``config``. ``None``: the core's default (documented in
    ``memsnav.experiments.partial_outage``). ``run_range`` / ``chunks`` as
    in ``calibration_experiment``."""

def outage_study_runs(
    imus: Sequence[tuple[str, str | ImuModel | tuple[str, dict[str, float]]]],
    *,
    cells: Sequence[tuple[int, int, int]],
    run_range: tuple[int, int],
    outage_lengths: Sequence[float],
    visible_satellites: Sequence[int],
    outage_start: float | None = None,
    duration: float | None = None,
    tail: float | None = None,
    seed: int | None = None,
    calibration_duration: float | None = None,
    smooth: bool | None = None,
    threads: int | None = None,
    progress: Callable[[int, int], object] | None = None,
    n_satellites: int | None = None,
    systems: Sequence[str] | None = None,
    inter_system_bias: tuple[float, float] | Sequence[float] | None = None,
    carrier_phase_std: float | None = None,
    cycle_slip_probability: float | None = None,
) -> dict[str, Any]:
    """The outage study's runs `run_range` for `cells`, triples of indices
    (IMU, outage length, satellites count) into `imus`, `outage_lengths`
    and `visible_satellites` (`memsnav_core::experiments::outage_study_runs`;
    `memsnav.experiments.outage_study` chooses the cells and the looks).
    Every cell's run ends `tail` s after its window (default 10 s with
    `smooth`, else 0); `duration` defaults to the start, the longest
    window and the tail. Returns per solution (`forward`, and `smoothed`
    with `smooth`) arrays (runs, cells): `horizontal_end`,
    `horizontal_max`, `error_3d_end`, `error_3d_max` (m), `diverged`,
    `rejected`, `accepted`; `completed_runs` and `interrupted`.
    """

# --- GNSS (constellations, SP3, measurement simulation, least-squares fix) ---

@final
class Constellation:
    """GPS satellites from broadcast ephemerides, or synthetic Walker
    constellations (GPS, or several systems: :meth:`nominal`).

    Times are GPS seconds since 1980-01-06 00:00:00 GPST; positions ECEF m,
    velocities m/s.
    """

    @staticmethod
    def from_rinex_nav(path: str | os.PathLike[str]) -> Constellation:
        """GPS ephemerides of a RINEX 2 or 3 navigation file (other systems skipped).

        Raises ParseError naming the file and the 1-based line for unreadable
        or truncated records.
        """

    @staticmethod
    def walker(
        n_satellites: int | None = None,
        planes: int | None = None,
        inclination_deg: float | None = None,
        semi_major_axis_m: float | None = None,
        phasing: int | None = None,
        raan0_deg: float | None = None,
    ) -> Constellation:
        """A Walker delta constellation i: t/p/f of circular orbits.

        None takes the core's default (`defaults()`), the GPS-like pattern:

        - `n_satellites` t [24], `planes` p [6] and `phasing` f [1].
        - `inclination_deg` i, degrees [55].
        - `semi_major_axis_m`: the orbits' radius, m [26 560 km].
        - `raan0_deg`: the first plane's right ascension, degrees [0].
        """

    @staticmethod
    def nominal(systems: Sequence[str]) -> Constellation:
        """The nominal Walker constellations of ``systems`` (RINEX letters, in
        this order): "G" GPS 24/6/1 at a = 26 560 km, 55°; "E" Galileo 24/3/1
        at 29 599.8 km, 56° (period 14 h 4 min); "C" BeiDou MEO 24/3/1 at
        27 906.1 km, 55° (12 h 53 min; no GEO or IGSO satellites); "R"
        GLONASS 24/3/1 at 25 510 km, 64.8° (11 h 16 min; slots on the current
        FDMA channel plan). Satellites are numbered G 1-24, E 101-124,
        C 201-224, R 301-324 (``sat_id``) and named G01, E01, C01, R01, ...
        (``prns``). ``nominal(["G"])`` is
        ``walker()``.

        Raises ValueError for an unknown letter or a system named twice.
        """

    @property
    def prns(self) -> list[str]:
        """Satellite names, e.g. ["G01", "G02", ...] (Walker slots are named
        like their system's PRNs: G01..GNN, E01.., C01..)."""

    @property
    def systems(self) -> list[str]:
        """The satellite systems, as RINEX letters in the constellation's order."""

    def __len__(self) -> int: ...
    def position_velocity(
        self, gps_time: float
    ) -> tuple[npt.NDArray[np.float64], npt.NDArray[np.float64]]:
        """ECEF positions (m) and velocities (m/s), each ``(n_sat, 3)``, at
        ``gps_time`` (s since 1980-01-06 GPST); NaN rows without a valid ephemeris.
        """

    def clock_correction(self, gps_time: float) -> npt.NDArray[np.float64]:
        """Satellite clock corrections Δt_sv (s, L1 C/A: relativistic term and
        −T_GD included) at ``gps_time``; NaN without a valid ephemeris.
        """

@final
class Sp3:
    """Precise orbits from an SP3 file (centre of mass), in SI units."""

    @property
    def time(self) -> npt.NDArray[np.float64]:
        """Epochs, GPS s since 1980-01-06, ``(n_epochs,)``."""

    @property
    def satellites(self) -> list[str]:
        """Satellite names as in the file ("G01", "E05", ...)."""

    @property
    def position_ecef(self) -> npt.NDArray[np.float64]:
        """Centre-of-mass positions, ECEF m, ``(n_epochs, n_sat, 3)``; NaN if missing."""

    @property
    def clock(self) -> npt.NDArray[np.float64]:
        """Satellite clocks, s, ``(n_epochs, n_sat)``; NaN if missing."""

    def satellite_states(
        self, gps_time: float | npt.ArrayLike, satellites: Sequence[str] | None = None
    ) -> tuple[npt.NDArray[np.float64], npt.NDArray[np.float64], npt.NDArray[np.float64]]:
        """Positions, velocities (ECEF, m, m/s) and clocks (s) at GPS times
        ``gps_time`` (a number or ``(T,)``) of ``satellites`` (names, default
        ``satellites``): 10-point Lagrange interpolation of the positions
        and its derivative, the clock linear between epochs. Shapes as
        ``BroadcastEphemerides.satellite_states``; NaN outside the file's
        epochs or where a position is missing, counted in a ``UserWarning``.
        """

def read_sp3(path: str | os.PathLike[str]) -> Sp3:
    """Reads an SP3-c/d precise orbit file (GPS time; km and µs converted to m and s).

    `path`: the file to read (str or path-like).
    """

@final
class GnssMeasurements:
    """Simulated measurements; per-epoch arrays padded to n_max = n_satellites
    (NaN for values, -1 for sat_id, where fewer satellites are tracked)."""

    def __new__(
        cls,
        time: npt.ArrayLike,
        sat_id: npt.ArrayLike,
        satellite_position_ecef: npt.ArrayLike,
        satellite_velocity_ecef: npt.ArrayLike,
        pseudorange: npt.ArrayLike,
        pseudorange_std: npt.ArrayLike,
        pseudorange_rate: npt.ArrayLike | None = None,
        pseudorange_rate_std: npt.ArrayLike | None = None,
        *,
        start_gps_time: float | None = None,
        carrier_phase: npt.ArrayLike | None = None,
        carrier_phase_std: npt.ArrayLike | None = None,
        loss_of_lock: npt.ArrayLike | None = None,
    ) -> GnssMeasurements:
        """Measurements from padded arrays: time (T,) s, sat_id (T, n)
        (negative: an empty slot), satellite_position_ecef and
        satellite_velocity_ecef (T, n, 3) at transmission, pseudorange (T, n)
        m (satellite clock corrected), pseudorange_std (T, n) m, optional
        pseudorange_rate with pseudorange_rate_std (T, n) m/s, optional
        carrier_phase with carrier_phase_std (T, n) m (the carrier range λ·φ,
        corrected as the pseudorange with the ionosphere's sign reversed) and
        loss_of_lock (T, n) bool; start_gps_time: the GPS time of time[0]
        (None: time is GPS time). NaN is refused in every non-empty slot
        except a rate or a carrier phase (NaN: none there); ValueError names
        the slot."""

    @staticmethod
    def from_table(
        table: str | os.PathLike[str] | Mapping[str, npt.ArrayLike] | Any,
        *,
        pseudorange_std: float | None = None,
        pseudorange_rate_std: float | None = None,
    ) -> GnssMeasurements:
        """Measurements from a long table, one row per epoch and satellite (the
        layout ``memsnav simulate`` writes as ``gnss.csv``): the path of a
        CSV file, a pandas or polars DataFrame, or a dict of columns. Columns:
        ``time_s``, ``sat_id``, ``sat_position_ecef_{x,y,z}_m``,
        ``sat_velocity_ecef_{x,y,z}_m_s``, ``pseudorange_m``; optional
        ``gps_time_s``, ``pseudorange_rate_m_s`` (empty or NaN: no rate),
        ``pseudorange_std_m``, ``pseudorange_rate_std_m_s`` (left out: the
        σ given here, None: ``defaults()["gnss"]``). Any other column is a
        ValueError naming it and the closest known name; a row with NaN
        outside a rate is refused, naming the row (CSV: the line).
        """

    @property
    def time(self) -> npt.NDArray[np.float64]:
        """Epoch times on the trajectory's time axis, s, ``(T,)``."""

    @property
    def gps_time(self) -> npt.NDArray[np.float64]:
        """Epoch times in GPS s since 1980-01-06, ``(T,)``."""

    @property
    def n_satellites(self) -> npt.NDArray[np.int64]:
        """Number of satellites tracked at each epoch, ``(T,)``."""

    @property
    def sat_id(self) -> npt.NDArray[np.int64]:
        """Satellite ids (PRN numbers), ``(T, n_max)``, −1 where padded."""

    @property
    def satellite_position_ecef(self) -> npt.NDArray[np.float64]:
        """Satellite positions at transmission time (ECEF of that time), m, ``(T, n_max, 3)``,
        NaN-padded.
        """

    @property
    def satellite_velocity_ecef(self) -> npt.NDArray[np.float64]:
        """Satellite velocities at transmission time, m/s, ``(T, n_max, 3)``, NaN-padded."""

    @property
    def pseudorange(self) -> npt.NDArray[np.float64]:
        """Pseudoranges (satellite clock corrected), m, (T, n_max)."""

    @property
    def pseudorange_rate(self) -> npt.NDArray[np.float64]:
        """Pseudorange rates, m/s, ``(T, n_max)``, NaN-padded."""

    @property
    def pseudorange_std(self) -> npt.NDArray[np.float64]:
        """Pseudorange noise one-sigma, m, ``(T, n_max)``, NaN-padded."""

    @property
    def pseudorange_rate_std(self) -> npt.NDArray[np.float64]:
        """Pseudorange-rate noise one-sigma, m/s, ``(T, n_max)``, NaN-padded."""

    @property
    def signal(self) -> list[list[str]] | None:
        """The signal each measurement was taken from ("L1 C/A", "E1 C",
        "B3I"; "L1 C/A + L5 Q" when a second signal measured its
        ionosphere), ``T`` lists of ``n_max`` names, "" where padded; None
        for measurements not built from observations.
        """

    @property
    def cn0_db_hz(self) -> npt.NDArray[np.float64] | None:
        """C/N0 of each measurement's signal (its S observation), dB-Hz,
        ``(T, n_max)``, NaN-padded and NaN where the file has none; None for
        measurements not built from observations.
        """

    @property
    def elevation_rad(self) -> npt.NDArray[np.float64] | None:
        """Each satellite's elevation at the reference position, rad,
        ``(T, n_max)``, NaN-padded; None for measurements not built from
        observations.
        """

    @property
    def carrier_phase(self) -> npt.NDArray[np.float64]:
        """Carrier ranges λ·φ, m, ``(T, n_max)``; NaN where padded or without
        a carrier phase. Each holds an unknown constant per lock arc.
        """

    @property
    def carrier_phase_std(self) -> npt.NDArray[np.float64]:
        """Carrier-range noise one-sigma, m, ``(T, n_max)``; NaN where padded
        or without a carrier phase.
        """

    @property
    def loss_of_lock(self) -> npt.NDArray[np.bool_]:
        """The receiver reports lock lost since the previous epoch (a new
        carrier arc), ``(T, n_max)``; False where padded or without a
        carrier phase.
        """

    @property
    def cycle_slips(self) -> dict[str, npt.NDArray[Any]]:
        """The cycle slips the simulator put in the carrier phases (unflagged:
        ``loss_of_lock`` stays False): a dict of ``time`` (s), ``sat_id`` and
        ``cycles`` (L1 cycles added from that epoch on) arrays, in epoch
        order; empty for measurements not simulated here.
        """

    @property
    def clock_offset(self) -> npt.NDArray[np.float64]:
        """True receiver clock offset, m, ``(T,)``."""

    @property
    def clock_drift(self) -> npt.NDArray[np.float64]:
        """True receiver clock drift, m/s, ``(T,)``."""

    @property
    def inter_system_bias(self) -> npt.NDArray[np.float64]:
        """True inter-system biases (Galileo, BeiDou, GLONASS minus GPS) in
        the pseudoranges, m, ``(3,)``; NaN for measurements not simulated here.
        """

    def __len__(self) -> int: ...

def simulate_gnss(
    time: npt.ArrayLike,
    position_ecef: npt.ArrayLike,
    velocity_ecef: npt.ArrayLike,
    constellation: Constellation,
    rate: float | None = None,
    n_satellites: int | None = None,
    elevation_mask_deg: float | None = None,
    pseudorange_std: float | None = None,
    pseudorange_rate_std: float | None = None,
    residual_std: float | None = None,
    residual_correlation_time: float | None = None,
    clock_h0: float | None = None,
    clock_h_minus2: float | None = None,
    clock_initial_offset_std: float | None = None,
    clock_initial_drift_std: float | None = None,
    outages: Sequence[tuple[float, float] | tuple[float, float, int]] | None = None,
    seed: int | None = None,
    start_gps_time: float | None = None,
    inter_system_bias: tuple[float, float] | Sequence[float] | None = None,
    carrier_phase_std: float | None = None,
    cycle_slip_probability: float | None = None,
) -> GnssMeasurements:
    """Pseudoranges (m) and rates (m/s) along a trajectory (method §5).

    Arguments; ``None`` takes the core's default
    (``memsnav_core::gnss::SimulationConfig``), given in brackets:

    - ``time`` (N,) s, ``position_ecef`` (N, 3) m, ``velocity_ecef`` (N, 3)
      m/s: the receiver's trajectory, time increasing.
    - ``constellation``: the satellites (``Constellation.walker``,
      ``nominal`` or ``from_rinex_nav``).
    - ``rate``: epochs per second, Hz [1]; the epochs fall on the
      trajectory samples nearest to t0 + k/rate.
    - ``n_satellites``: satellites tracked [6].
    - ``elevation_mask_deg``: elevation mask, degrees [10].
    - ``pseudorange_std``, m [3], and ``pseudorange_rate_std``, m/s [0.1]:
      white noise.
    - ``residual_std``, m [none], and ``residual_correlation_time``, s
      [300]: a Gauss-Markov residual per satellite (atmosphere, orbit).
    - ``clock_h0`` [2e-19] and ``clock_h_minus2`` [2e-20]: the receiver
      clock's Allan coefficients (a TCXO; two-state model);
      ``clock_initial_offset_std``, m [30], and ``clock_initial_drift_std``,
      m/s [1]: its initial one-sigmas.
    - ``outages``: (start s, length s) total, or (start, length,
      n_satellites) partial, keeping the highest of the tracked satellites
      (an urban canyon's view), on the trajectory's time axis [none]. They
      are applied after every random draw, so the kept satellites' noise
      does not depend on them.
    - ``seed``: the random stream, an integer in [0, 2**64) [0: the same
      draws every call; pass different seeds for independent draws].
    - ``start_gps_time``: GPS time of time[0], s [the earliest t_oe of a
      broadcast file; 0 for a Walker constellation].
    - ``inter_system_bias``: Galileo, BeiDou[, GLONASS] minus GPS, m
      [none], added to that system's pseudoranges.
    - ``carrier_phase_std``, m [0: no carrier phase]: adds carrier ranges:
      the pseudorange's range, clock and bias, minus the residual (the
      ionosphere advances the phase), plus a whole number of GPS L1 cycles
      drawn per lock arc, plus white noise; ``loss_of_lock`` is set where a
      satellite was not in the previous epoch. The carrier draws from a
      stream of its own: the pseudoranges and rates are the same with or
      without it.
    - ``cycle_slip_probability``, per satellite and epoch [0]: silent slips
      (±1 and ±2 cycles common, up to ±1000; ``loss_of_lock`` stays False),
      listed in ``cycle_slips``.

    At the first epoch the ``n_satellites`` with the best GDOP above the
    mask are chosen (greedy elimination), of every system the constellation
    holds, and kept while visible; a setting satellite is replaced by the
    one giving the best GDOP (with several systems the GDOP has one
    inter-system-bias unknown per system other than GPS, so a system's lone
    satellite adds nothing). Pseudorange = exact light-time range with
    Earth rotation + receiver clock + the system's inter-system bias + the
    residual + white noise.
    """

@final
class FixSeries:
    """Least-squares fixes per epoch; NaN rows where ``valid`` is False."""

    @property
    def time(self) -> npt.NDArray[np.float64]:
        """Epoch times, s, ``(T,)``."""

    @property
    def valid(self) -> npt.NDArray[np.bool_]:
        """True where the epoch had at least 4 satellites and a fix, ``(T,)``."""

    @property
    def position_ecef(self) -> npt.NDArray[np.float64]:
        """ECEF position, m, ``(T, 3)`` (NaN rows where not valid)."""

    @property
    def velocity_ecef(self) -> npt.NDArray[np.float64]:
        """ECEF velocity, m/s, ``(T, 3)``."""

    @property
    def clock_offset(self) -> npt.NDArray[np.float64]:
        """Receiver clock offset, m, ``(T,)``."""

    @property
    def inter_system_bias(self) -> npt.NDArray[np.float64]:
        """Inter-system biases of Galileo, BeiDou and GLONASS relative to the
        epoch's reference system (GPS when present), m, ``(T, 3)``; NaN for
        a system not in the epoch.
        """
    @property
    def clock_drift(self) -> npt.NDArray[np.float64]:
        """Receiver clock drift, m/s, ``(T,)``."""

    @property
    def position_clock_covariance(self) -> npt.NDArray[np.float64]:
        """Covariance of (x, y, z, clock offset), m², ``(T, 4, 4)``."""

    @property
    def velocity_drift_covariance(self) -> npt.NDArray[np.float64]:
        """Covariance of (vx, vy, vz, clock drift), (m/s)², ``(T, 4, 4)``."""

    @property
    def gdop(self) -> npt.NDArray[np.float64]:
        """Geometric dilution of precision, (T,)."""

    @property
    def pdop(self) -> npt.NDArray[np.float64]:
        """Position dilution of precision, (T,)."""

    @property
    def hdop(self) -> npt.NDArray[np.float64]:
        """Horizontal dilution of precision, (T,)."""

    @property
    def vdop(self) -> npt.NDArray[np.float64]:
        """Vertical dilution of precision, (T,)."""

    @property
    def tdop(self) -> npt.NDArray[np.float64]:
        """Time dilution of precision, (T,)."""

    @property
    def excluded(self) -> list[list[str]]:
        """Satellites the residual test left out of each epoch's fix (RINEX
        names, in the order they were left out); empty where every satellite
        fits or the epoch has no fix."""

    @property
    def residual_chi_square(self) -> npt.NDArray[np.float64]:
        """Post-fit test statistic Σ (v/σ)² of the satellites used, ``(T,)``;
        NaN without redundancy, with unit weights or without a fix.
        """

    @property
    def residual_threshold(self) -> npt.NDArray[np.float64]:
        """The residual test's threshold χ²(1 − false_alarm_probability,
        satellites − unknowns), ``(T,)``; NaN where the test did not run.
        """

def solve_fix(
    measurements: GnssMeasurements | Mapping[str, npt.ArrayLike],
    prior: npt.ArrayLike | None = None,
    strict: bool = False,
    *,
    false_alarm_probability: float | None = 0.001,
) -> FixSeries:
    """Gauss-Newton position/velocity/clock fix of every epoch (Sagnac-corrected
    predicted ranges).

    - ``measurements``: a ``GnssMeasurements``, or its padded arrays as a
      dict (the constructor's keys, no others).
    - ``prior``: (3,) ECEF start of the first epoch's iterations, m [the
      Earth's centre]; later epochs start from the previous fix.
    - ``strict`` [False]: an epoch with fewer than 4 satellites is a
      ValueError instead of a NaN row.
    - ``false_alarm_probability`` [0.001]: the residual test's, per epoch;
      None turns the test off.

    Residual test (RAIM fault detection and exclusion): the weighted post-fit
    residuals' sum of squares is held to the chi-square quantile
    1 - ``false_alarm_probability`` (default 0.001 per epoch, RTKLIB's) of
    satellites - unknowns degrees of freedom; while it fails and a test after
    the exclusion remains possible, the satellite with the largest normalized
    residual is left out and the fix made again. The satellites left out are
    in ``excluded``; the final statistic and threshold in
    ``residual_chi_square`` and ``residual_threshold`` (a statistic still above
    its threshold: no exclusion could make the epoch fit).
    ``false_alarm_probability=None`` turns the test off.
    """

# --- trajectory ---

@final
class Trajectory:
    """Truth of a vehicle's motion at the IMU rate: position, velocity and
    attitude in ECEF, and the exact specific force and angular rate in body
    axes (Earth rotation and the gravity model of ``gravity_ecef`` included).
    """

    @staticmethod
    def random(
        duration: float | None = None,
        rate: float | None = None,
        seed: int | None = None,
        origin: npt.ArrayLike | None = None,
        *,
        heading: float | None = None,
        max_speed: float | None = None,
        max_longitudinal_acceleration: float | None = None,
        max_lateral_acceleration: float | None = None,
        max_yaw_rate: float | None = None,
        max_slope: float | None = None,
        stationary_start: float | None = None,
    ) -> Trajectory:
        """Random land-vehicle motion: cruises, speed changes (sometimes to a
        stop), turns, road slope, body lean and squat; C² smooth.

        Arguments; ``None`` takes the core's default
        (``RandomTrajectoryConfig``), given in brackets:

        - ``duration``, s [600]; ``rate``, Hz [100].
        - ``seed``: the random stream, an integer in [0, 2**64) [0: the same
          trajectory every call].
        - ``origin``: [latitude rad, longitude rad, height m] of the start
          [Toulouse, 43.6° N 1.44° E 150 m].
        - ``heading``: the initial heading, rad from north [random].
        - ``max_speed``, m/s [30]; ``max_longitudinal_acceleration``, m/s²
          [2]; ``max_lateral_acceleration``, m/s² [3]; ``max_yaw_rate``, rad/s
          [0.4]; ``max_slope``, rad [0.05].
        - ``stationary_start``: seconds at rest before moving off [0].
        """

    @staticmethod
    def from_segments(
        segments: Sequence[tuple[str, float] | tuple[str, float, float]],
        origin: npt.ArrayLike | None = None,
        heading: float = 0.0,
        rate: float | None = None,
    ) -> Trajectory:
        """Scripted motion from rest.

        - `segments`: a list of manoeuvres, each a tuple:
          ``("accelerate", duration_s, target_speed_m_s)``,
          ``("cruise", duration_s)``, ``("turn", duration_s,
          heading_change_rad)`` (positive right), ``("climb", duration_s,
          path_angle_rad)`` (ramps up and back to level),
          ``("stop", duration_s)``.
        - `origin`: [latitude rad, longitude rad, height m] of the start
          [Toulouse, as `Trajectory.random`].
        - `heading`: the initial heading, rad from north [0].
        - `rate`: Hz [100].
        """

    @staticmethod
    def from_profile(path: str | os.PathLike[str], rate: float | None = None) -> Trajectory:
        """A profile of Groves' book software, smoothed by splines through
        knots 0.5 s apart.

        - `path`: the CSV file (t, lat, lon deg, h m, v_NED m/s, roll, pitch,
          yaw deg); a ParseError names its file and line.
        - `rate`: the samples' rate, Hz [100].
        """

    @property
    def time(self) -> npt.NDArray[np.float64]:
        """Sample times, s, shape (N,)."""
    @property
    def position_ecef(self) -> npt.NDArray[np.float64]:
        """ECEF position, m, shape (N, 3)."""
    @property
    def velocity_ecef(self) -> npt.NDArray[np.float64]:
        """ECEF velocity, m/s, shape (N, 3)."""
    @property
    def attitude(self) -> npt.NDArray[np.float64]:
        """Body-to-ECEF rotation matrices, shape (N, 3, 3)."""
    @property
    def specific_force(self) -> npt.NDArray[np.float64]:
        """True specific force f_ib^b, m/s², shape (N, 3)."""
    @property
    def angular_rate(self) -> npt.NDArray[np.float64]:
        """True angular rate ω_ib^b, rad/s, shape (N, 3)."""
    def position_geodetic(self) -> npt.NDArray[np.float64]:
        """[latitude rad, longitude rad, height m] of each sample, shape (N, 3)."""
    def velocity_ned(self) -> npt.NDArray[np.float64]:
        """NED velocity at each sample, m/s, shape (N, 3)."""
    def euler_ned(self) -> npt.NDArray[np.float64]:
        """[roll, pitch, yaw] of the body relative to local NED, rad, shape (N, 3)."""
    def __len__(self) -> int: ...

# --- ins ---

@final
class NavSolution:
    """An INS solution: the state at every input time."""

    @property
    def time(self) -> npt.NDArray[np.float64]:
        """Times, s, shape (N,)."""
    @property
    def position_ecef(self) -> npt.NDArray[np.float64]:
        """ECEF position, m, shape (N, 3)."""
    @property
    def velocity_ecef(self) -> npt.NDArray[np.float64]:
        """ECEF velocity, m/s, shape (N, 3)."""
    @property
    def attitude(self) -> npt.NDArray[np.float64]:
        """Body-to-ECEF rotation matrices, shape (N, 3, 3)."""
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
    instantaneous samples (Groves ch. 5).

    - ``time`` (N,) s, increasing.
    - ``specific_force`` (N, 3) m/s² and ``angular_rate`` (N, 3) rad/s: the
      IMU's samples in body axes (x forward, y right, z down).
    - ``position_ecef`` (3,) m, ``velocity_ecef`` (3,) m/s and ``attitude``
      (3, 3) C_b^e (body to ECEF): the state at ``time[0]``.
    - ``scheme`` ["cubic"]: "cubic" interpolates the samples with coning
      and sculling, fourth order; "trapezoid" is the two-sample
      second-order step the filters chain.

    Returns a ``NavSolution`` (position, velocity and attitude per sample).
    """

def strapdown_increments(
    time: npt.ArrayLike,
    delta_velocity: npt.ArrayLike,
    delta_angle: npt.ArrayLike,
    position_ecef: npt.ArrayLike,
    velocity_ecef: npt.ArrayLike,
    attitude: npt.ArrayLike,
) -> NavSolution:
    """Strapdown INS from increments with coning and sculling corrections.

    - `time` (N + 1,) s, increasing.
    - `delta_velocity` (N, 3) m/s and `delta_angle` (N, 3) rad: row k
      integrated over [time[k], time[k + 1]], in body axes.
    - `position_ecef` (3,) m, `velocity_ecef` (3,) m/s and `attitude`
      (3, 3) C_b^e: the state at `time[0]`, as for `strapdown`.
    """

def imu_increments(
    time: npt.ArrayLike, specific_force: npt.ArrayLike, angular_rate: npt.ArrayLike
) -> tuple[npt.NDArray[np.float64], npt.NDArray[np.float64]]:
    """(delta_velocity m/s, delta_angle rad), each (N - 1, 3): the integrals
    of the cubic through the samples over each interval (fourth order)."""

# --- coupled GNSS/INS filters (method §5) and the navigation experiment (paper §5.3) ---

@final
class IntegrityAlert:
    """An integrity alert: the solution cannot be trusted from `time_s` on."""

    @property
    def kind(self) -> str:
        """ "gated_batches", "inconsistent_innovations", "beyond_linear_model"
        or "applied_outliers".
        """

    @property
    def time_s(self) -> float:
        """When, GNSS time, s."""

    @property
    def message(self) -> str:
        """What happened, in words."""

    def to_dict(self) -> dict[str, Any]:
        """The fields as a dict, by attribute name (records inside stay
        records; arrays stay arrays).
        """

@final
class Consistency:
    """The consistency of one kind of GNSS measurement over 30 s windows."""

    @property
    def kind(self) -> str:
        """The measurement kind ("pseudorange", ...)."""

    @property
    def windows(self) -> int:
        """Windows of 30 s."""

    @property
    def windows_above_band(self) -> int:
        """Windows whose summed NIS exceeded the 0.9999 chi-square quantile."""

    @property
    def max_band_ratio(self) -> float:
        """The largest summed NIS over that quantile."""

    @property
    def max_at_s(self) -> float:
        """Its window's start, s."""

    def to_dict(self) -> dict[str, Any]:
        """The fields as a dict, by attribute name (records inside stay
        records; arrays stay arrays).
        """

@final
class Integrity:
    """Whether a solution can be trusted (`FilterSolution.integrity`)."""

    @property
    def diverged(self) -> bool:
        """Whether any alert was raised."""

    @property
    def alerts(self) -> list[IntegrityAlert]:
        """The alerts, in time order."""

    @property
    def consistency(self) -> list[Consistency]:
        """Per GNSS kind, the windows' consistency."""

    def to_dict(self) -> dict[str, Any]:
        """The fields as a dict, by attribute name (records inside stay
        records; arrays stay arrays).
        """

@final
class FilterSolution:
    """The whole solution of a coupled filter, at every IMU sample (SI units).

    Measurement records (``measurements``, ``rejected``) are dicts of arrays:
    ``time`` (s), ``id`` (satellite id; fix component 0-2 for the loose
    filter; axis for the aids), ``kind`` ("pseudorange" m, "pseudorange_rate"
    m/s, "carrier_phase" m: a carrier change between consecutive epochs with
    the epoch's weighted mean removed, "position" / "velocity" whitened,
    unit variance, "zero_velocity", "zero_rate", "non_holonomic"),
    ``innovation`` (measurement minus the prediction before the epoch's
    updates), ``innovation_std``, ``nis`` (nu²/s), ``status`` ("accepted";
    "gate": its batch failed the chi-square test; "excluded": left out of
    its batch by fault exclusion; "invalid": NaN/inf value or non-positive
    std; "reset": its batch failed and the filter was reset from it;
    "slip": a carrier change holding a cycle slip, flagged by the receiver
    or found against the Doppler, not used; "too-few": a clean carrier
    change whose epoch had fewer than the 5 a batch needs, not used).
    """

    @property
    def time(self) -> npt.NDArray[np.float64]:
        """IMU sample times, s, (N,)."""

    @property
    def position_ecef(self) -> npt.NDArray[np.float64]:
        """Position, ECEF m, (N, 3)."""

    @property
    def velocity_ecef(self) -> npt.NDArray[np.float64]:
        """Velocity, ECEF m/s, (N, 3)."""

    @property
    def attitude(self) -> npt.NDArray[np.float64]:
        """Attitude C_b^e (body to ECEF), (N, 3, 3)."""

    @property
    def accel_bias(self) -> npt.NDArray[np.float64]:
        """Accelerometer bias estimate, m/s², (N, 3), additive: reading = truth +
        bias (an ``AccelerometerModel.bias`` enters as S = Γ - b, so the
        estimate converges to minus it)."""

    @property
    def gyro_bias(self) -> npt.NDArray[np.float64]:
        """Gyro bias estimate, rad/s, (N, 3), additive like ``accel_bias``."""

    @property
    def accel_scale_factor(self) -> npt.NDArray[np.float64] | None:
        """Accelerometer scale-factor estimate, (N, 3); None without scale-factor states."""

    @property
    def gyro_scale_factor(self) -> npt.NDArray[np.float64] | None:
        """Gyro scale-factor estimate, (N, 3); None without scale-factor states."""

    @property
    def installation(self) -> npt.NDArray[np.float64] | None:
        """Installation estimates, (N, 7): antenna lever arm x, y, z (body
        axes, m), IMU time offset (s), velocity latency (s), mounting
        boresight pitch, yaw (rad); None without the installation states."""

    @property
    def clock_offset(self) -> npt.NDArray[np.float64]:
        """Receiver clock offset, m, (N,)."""

    @property
    def clock_drift(self) -> npt.NDArray[np.float64]:
        """Receiver clock drift, m/s, (N,)."""

    @property
    def inter_system_bias(self) -> npt.NDArray[np.float64] | None:
        """Inter-system bias estimates (Galileo, BeiDou, GLONASS pseudoranges
        minus GPS's), m, (N, 3); None without the inter-system-bias states.
        """
    @property
    def covariance_diagonal(self) -> npt.NDArray[np.float64]:
        """Diagonal of the error covariance, (N, n_states), order ``state_names``
        (rad², (m/s)², m², (m/s²)², (rad/s)², m², (m/s)², dimensionless²)."""

    @property
    def position_covariance_ecef(self) -> npt.NDArray[np.float64]:
        """Position-error covariance (ECEF axes), m², (N, 3, 3)."""

    @property
    def velocity_covariance_ecef(self) -> npt.NDArray[np.float64]:
        """Velocity-error covariance (ECEF axes), m²/s², (N, 3, 3)."""

    @property
    def attitude_covariance_ecef(self) -> npt.NDArray[np.float64]:
        """Attitude-error covariance (ECEF axes), rad², (N, 3, 3)."""

    @property
    def position_std_ned(self) -> npt.NDArray[np.float64]:
        """One-sigma position uncertainty along north, east, down, m, (N, 3): the
        position block rotated into the local NED axes of each sample."""

    @property
    def velocity_std_ned(self) -> npt.NDArray[np.float64]:
        """One-sigma velocity uncertainty along north, east, down, m/s, (N, 3)."""

    @property
    def attitude_std_ned(self) -> npt.NDArray[np.float64]:
        """One-sigma attitude uncertainty about north, east, down, rad, (N, 3)."""

    @property
    def state_names(self) -> list[str]:
        """Error-state names: attitude_x..z (ECEF, rad), velocity_x..z, position_x..z,
        accel_bias_x..z, gyro_bias_x..z, clock_offset, clock_drift
        [, accel_scale_factor_x..z, gyro_scale_factor_x..z]
        [, lever_arm_x..z, time_offset, velocity_latency, mounting_pitch, mounting_yaw]
        [, inter_system_bias_galileo, _beidou, _glonass] [, range_bias_0, ...].
        """

    @property
    def measurements(self) -> dict[str, npt.NDArray[Any] | list[str]]:
        """Every scalar measurement: dict of arrays `time`, `id`, `kind`,
        `innovation`, `innovation_std`, `nis`, `status`.
        """

    @property
    def rejected(self) -> dict[str, npt.NDArray[Any] | list[str]]:
        """The rejected measurements only (status "gate" or "invalid")."""

    @property
    def smoothed(self) -> FilterSolution | None:
        """The fixed-interval smoothed solution (``run(..., smooth=True)``),
        else None."""

    @property
    def batches(self) -> dict[str, npt.NDArray[Any] | list[str]]:
        """Every batch test (an epoch's measurements of one kind): dict of arrays
        ``time``, ``kind``, ``nis`` (the batch's nu' S^-1 nu), ``dof``,
        ``threshold`` (its chi-square quantile), ``excluded`` (measurements left
        out by fault exclusion), ``accepted``, ``nonlinearity`` (pseudoranges:
        the largest expected curvature term over the position uncertainty in
        units of the measurement std, NaN for other kinds; above 0.1 the
        first-order model no longer holds, see ``integrity``)."""

    @property
    def resets(self) -> dict[str, npt.NDArray[Any] | list[str]]:
        """Every reset the filter made: dict of arrays ``time``, ``kind``
        ("position_to_fix", "velocity_to_fix", "velocity_to_zero" (a standstill
        whose ZUPTs kept failing), "clock_jump", "clock_drift_jump",
        "inflation", "fading", "heading"), ``change`` (m, m/s, rad, or the
        inflation or fading factor), ``unit`` (of each change: "m", "m/s",
        "rad", "" for a factor), ``failed_epochs`` (consecutive failed epochs
        before it)."""

    @property
    def warnings(self) -> list[str]:
        """What the run found implausible, one sentence each (also raised as
        `UserWarning`s by `run`): IMU magnitudes that do not fit m/s² and
        rad/s, a filter diverged from its GNSS aiding. Empty when all is well.
        """

    @property
    def diverged(self) -> bool:
        """Whether the run raised an integrity alert: its solution and
        covariance are not trustworthy (GNSS batches mostly gated,
        innovations far outside their chi-square band, or a position too
        uncertain for the linearised model, or outliers applied with the
        gate off; see `integrity` and `warnings`).
        """

    @property
    def integrity(self) -> Integrity:
        """Whether the solution can be trusted (docs/explanation/few-satellites.md):
        an `Integrity` with ``diverged``, ``alerts`` (`IntegrityAlert`: ``kind``
        "gated_batches", "inconsistent_innovations", "beyond_linear_model" or
        "applied_outliers", ``time_s`` GNSS time s, ``message``, in time order)
        and ``consistency`` (`Consistency` per GNSS kind: ``windows`` of 30 s,
        ``windows_above_band`` whose summed NIS exceeded the 0.9999 chi-square
        quantile, ``max_band_ratio`` the largest summed NIS over that quantile,
        ``max_at_s`` its window's start, s). A ratio above 4 in two windows in
        a row is an alert; 1-4 is a tuning mismatch, reported here only.
        ``summary.json`` of ``navigate`` has the same keys (its times in
        seconds after the start).
        """

    def write(
        self,
        path: str | os.PathLike[str],
        format: str | None = None,
        *,
        rate_hz: float | None = None,
        name: str | None = None,
        overwrite: bool = False,
    ) -> None:
        """Writes the solution at the IMU (its geodetic position, NED velocity, roll/pitch/yaw
        and NED one-sigmas) to `path` in `format`: "csv" (`columns()`,
        every sample), "pos" (RTKLIB, GPST; `read_pos` reads it), "kml" (KML
        2.2: the track as a LineString, start and end placemarks), "gpx" (GPX
        1.1: trk/trkseg/trkpt, times in UTC) or "geojson" (RFC 7946: a
        LineString Feature of [lon, lat, h] with the times as properties);
        None: from the extension (.csv, .pos, .kml, .gpx, .geojson or .json).
        Heights are ellipsoidal (WGS 84); UTC is GPS time less the leap
        seconds (18 s since 2017). `rate_hz`: the rows' rate (the first sample
        of each interval); None: every sample for "csv", 10 Hz for the others
        (a rate at or above the sample rate keeps every sample). `name` titles
        a map track (default the file's stem). The file is written whole or
        not at all; its folder must exist (`OSError` naming it). An existing
        file is replaced only when memsnav wrote it (a solution file of any of
        these formats) or with `overwrite=True`, a folder never (`ValueError`);
        an unknown format is a `ValueError` naming `format` and the accepted
        names.
        """

    def columns(self, rate_hz: float | None = None) -> dict[str, npt.NDArray[np.float64]]:
        """The solution at the IMU (its geodetic position, NED velocity, roll/pitch/yaw
        and NED one-sigmas) as columns named with their units, (N,) each:
        `gps_time_s`, `lat_deg`, `lon_deg`, `height_m` (ellipsoidal), `vn_m_s`,
        `ve_m_s`, `vd_m_s`, `roll_deg`, `pitch_deg`, `yaw_deg`, `sdn_m`, `sde_m`,
        `sdd_m`, `sdvn_m_s`, `sdve_m_s`, `sdvd_m_s` (one-sigma, local
        north/east/down); `rate_hz` thins as in `write` (None: every sample).
        """

    def to_pandas(self, rate_hz: float | None = None) -> Any:
        """`columns(rate_hz)` as a pandas `DataFrame`; `ImportError` saying what
        to install when pandas is not installed.
        """

    def to_polars(self, rate_hz: float | None = None) -> Any:
        """`columns(rate_hz)` as a polars `DataFrame`; `ImportError` saying what
        to install when polars is not installed.
        """

    def __len__(self) -> int: ...

@final
class TightlyCoupledFilter:
    """Closed-loop error-state EKF in ECEF on pseudoranges and pseudorange rates
    (method §5; Groves §14.3.3): 17 states (attitude, velocity, position, accel
    and gyro biases, clock offset and drift), 23 with `scale_factor_states`.
    An epoch's pseudoranges are one batch and its rates another (sequential
    Joseph updates, Sagnac and light time in the prediction), tested together
    by the chi-square test of the batch NIS: a faulty satellite is excluded, a
    receiver clock jump moved into the clock, and when the pseudoranges keep
    failing (3 epochs) the filter resets to the epoch's least-squares fix (or
    opens its covariance with fewer than 4 satellites); every reset is in
    `FilterSolution.resets`. Fewer than four satellites still help (the
    rate row keeps the line of sight's turn with position, so ranges and
    rates leave the same directions unobserved); with none the INS coasts.
    `FilterSolution.integrity` says when the result cannot be trusted
    (docs/explanation/few-satellites.md). Measurement stds are floored (0.5 m, 0.02 m/s).

    Raises ValueError naming the argument for a bad value.

    Tuning from `imu.spec` at `imu.sample_rate` (`FilterTuning::from_imu_spec`):
    white-noise PSDs = noise density² (or per-sample std² / rate); bias
    processes from bias instability (2 sigma²/tau) and random walk, the
    instability taken as a random walk when the bias has a turn-on part
    (nothing makes a turn-on bias fade); initial bias std =
    sqrt(bias_std² + instability²), floored at 1e-6 m/s² and 1e-9 rad/s;
    errors the states lack (scale factor unless estimated, misalignment,
    nonlinearity, g-sensitivity): their part driven by the specific force at
    rest widens the initial bias std, their part driven by the motion is
    process noise shaped by the sensed specific force and rate at every step,
    2 sigma² tau with the manoeuvres' correlation time tau = 10 s
    (`filter::input_noise`). Receiver clock: the simulator's TCXO
    (`clock_h0` 2e-19, `clock_h_minus2` 2e-20, the same names and model
    as `simulate_gnss`: S_cφ = c² h0 / 2, S_cf = 2π² c² h−2). Every default
    below can be overridden; an argument left None takes the core's
    default, listed by `memsnav.defaults()` under the class name
    (`tuning` shows the values in effect):

    - `imu`: the `ImuModel` whose spec and sample rate tune the filter.
    - `settings` [None]: a `navigate` configuration's tables as a dict
      (`{"filter": {...}, "gnss": {...}, "imu": {...}, "imu_spec": {...},
      "standstill": {...}, "aids": {...}}`, the keys `navigate_settings()`
      lists, with their units and defaults): the filter is navigate's for
      those keys, defaults included (range-bias states on for pseudoranges;
      `gnss.range_bias_states = "every_satellite"` gives each of up to 40
      satellites one), tuned from `imu.spec`, and `run` applies navigate's
      aids as a navigate run does: zero-velocity and zero-rate updates at the
      standstills it detects (on unless `aids.zupt`/`aids.zaru` are false)
      and, with `aids.nhc`, the non-holonomic constraint (give
      `aids.nhc_std_m_s`). Tables and keys that prepare a navigate run
      (`[alignment]`, `[outages]`, `filter.imu_preset`, `filter.smoother`,
      `imu.time_offset_s`, `imu.mounting_rpy_deg`, any `"auto"`) raise
      ValueError naming them, and `start` raises while an aid is on. Not with
      the keywords below.
    - `scale_factor_states` [False]: six more states, the accelerometer and
      gyro scale factors (23 in all).
    - `accel_noise_density` (m/s²/√Hz), `gyro_noise_density` (rad/s/√Hz):
      replace the sensor's white PSDs by density² (the input-shaped noise of
      the unmodelled errors stays).
    - `accel_bias_psd` ((m/s²)²/s), `gyro_bias_psd` ((rad/s)²/s): bias
      driving-noise PSDs.
    - `gate_probability`: chi-square(1) gate, 0.999 (|nu| > 3.29 sigma rejected
      and reported); 1.0 disables it.
    - initial one-sigmas: `initial_position_std` 5 m and
      `initial_velocity_std` 0.5 m/s per ECEF axis (a code fix),
      `initial_tilt_std` 1° and `initial_heading_std` 5° (in rad),
      `initial_accel_bias_std` / `initial_gyro_bias_std` (None: from the
      spec as above), `initial_clock_offset_std` 50 m,
      `initial_clock_drift_std` 10 m/s; scale factors (23 states): the
      spec's scale_factor_std (floored at 1e-6).
    - `use_pseudorange_rate`: use rates when the epoch carries them.
    - `use_carrier_phase`: use each satellite's carrier-phase change
      between consecutive epochs (time-differenced carrier phase, as a
      velocity measurement; cycle slips found from the receiver's flags,
      the Doppler and the residual test) when the epochs carry it.
    - `clock_h0`, `clock_h_minus2`: the receiver oscillator's Allan
      coefficients (None: the TCXO above).
    - `manoeuvre_correlation_time`: tau of the input-shaped noise, s (None:
      10 s, a land vehicle's turns and accelerations; shorter for a walker).
    - `pseudorange_correlation_time`: correlation time of the code's fast
      errors (multipath), s (None: 0, white); each pseudorange's std is
      inflated by sqrt((1 + rho)/(1 - rho)), rho = exp(-dt/tau) over the
      epoch interval dt, so that epochs sampling one error carry it once
      (docs/how-to/multi-gnss.md, "Correlated code errors").
    """

    def __new__(
        cls,
        imu: ImuModel,
        *,
        settings: dict[str, dict[str, Any]] | None = None,
        scale_factor_states: bool = False,
        accel_noise_density: float | None = None,
        gyro_noise_density: float | None = None,
        accel_bias_psd: float | None = None,
        gyro_bias_psd: float | None = None,
        gate_probability: float | None = None,
        initial_position_std: float | None = None,
        initial_velocity_std: float | None = None,
        initial_tilt_std: float | None = None,
        initial_heading_std: float | None = None,
        initial_accel_bias_std: float | None = None,
        initial_gyro_bias_std: float | None = None,
        initial_clock_offset_std: float | None = None,
        initial_clock_drift_std: float | None = None,
        use_pseudorange_rate: bool = True,
        use_carrier_phase: bool = False,
        clock_h0: float | None = None,
        clock_h_minus2: float | None = None,
        manoeuvre_correlation_time: float | None = None,
        pseudorange_correlation_time: float | None = None,
    ) -> TightlyCoupledFilter: ...
    @property
    def tuning(self) -> dict[str, float | bool | str]:
        """The tuning in effect (PSDs, correlation times, initial one-sigmas,
        the unmodelled errors' one-sigmas ``unmodelled_*_std`` and
        ``manoeuvre_correlation_time``), SI, and the optional state blocks
        (``scale_factor_states``, ``installation_states``,
        ``range_bias_states``: False, True for 12 shared slots or
        "every_satellite"), and the ``aids`` `run` applies ("zupt, zaru"
        from `settings` by default, "" without them).
        """

    def run(
        self,
        time: npt.ArrayLike,
        specific_force: npt.ArrayLike,
        angular_rate: npt.ArrayLike,
        gnss: GnssMeasurements | Any,
        *,
        initial_attitude: npt.ArrayLike | None = None,
        initial_state: dict[str, Any] | Any | None = None,
        smooth: bool = False,
    ) -> FilterSolution:
        """Filters the whole series in one call (GIL released); with ``smooth``
        also the fixed-interval smoothed solution, as ``.smoothed``
        (docs/explanation/smoother.md).

        ``time`` (N,) s, increasing; ``specific_force`` (N, 3) m/s² and
        ``angular_rate`` (N, 3) rad/s: raw IMU samples (instantaneous values).
        ``gnss``: a ``simulate_gnss`` result, or an object/dict with padded
        arrays ``time`` (T,) on the IMU time scale, ``sat_id`` (T, n), negative
        = padding, ``satellite_position_ecef`` / ``satellite_velocity_ecef``
        (T, n, 3), ``pseudorange`` and ``pseudorange_std`` (T, n), optional
        ``pseudorange_rate`` and ``pseudorange_rate_std`` (T, n). Epoch times
        must increase and lie in the IMU span; NaN or absurd measurements are
        rejected and reported, not fatal.

        Initialisation: position, velocity and clock of the least-squares fix
        of the first epoch (≥ 4 satellites, else ValueError), moved back to
        ``time[0]``; attitude ``initial_attitude`` (C_b^e, 3x3) or a coarse one
        (levelling on the first second of specific force, heading from the fix
        velocity; needs ≥ 1 m/s ground speed); zero bias estimates.

        ``initial_state`` replaces that initialisation with the caller's own
        (e.g. an alignment): a dict (no other keys) or an object with
        ``position_ecef`` (3,) m and ``velocity_ecef`` (3,) m/s at ``time[0]``,
        ``attitude`` C_b^e (3, 3), optional ``clock_offset`` m and
        ``clock_drift`` m/s (absent or None: the median pseudorange (rate)
        residual of the first epoch). Give it or ``initial_attitude``, not both.
        Outages: leave the epochs out of ``gnss``.
        """

    def run_increments(
        self,
        time: npt.ArrayLike,
        delta_v: npt.ArrayLike,
        delta_theta: npt.ArrayLike,
        gnss: GnssMeasurements | Any,
        *,
        initial_attitude: npt.ArrayLike | None = None,
        initial_state: dict[str, Any] | Any | None = None,
        smooth: bool = False,
    ) -> FilterSolution:
        """`run` on an integrating IMU's output: `time` (N + 1,) s and the
        increments of each interval, `delta_v` (N, 3) m/s and
        `delta_theta` (N, 3) rad (row k over [time[k], time[k + 1]], as
        `imu_increments` gives them), integrated by the increments
        mechanization with coning and sculling (`strapdown_increments`'s)
        instead of from samples; an epoch between two times takes its
        share of the interval's increments at constant rates. The rest
        (aiding, start, smoothing, the solution at every time) as `run`;
        the mean rates of the intervals stand for samples where one is
        looked at (levelling the start).
        """

    def start(
        self,
        time: float,
        specific_force: npt.ArrayLike,
        angular_rate: npt.ArrayLike,
        initial_state: dict[str, Any] | Any,
        *,
        inter_system_biases: bool = False,
    ) -> RunningFilter:
        """The filter started at `time` (s) from `initial_state` (the dict
        `run` takes: position_ecef m, velocity_ecef m/s, attitude C_b^e,
        optional clock_offset m, clock_drift m/s) with the raw sample
        there (`specific_force` (3,) m/s², `angular_rate` (3,) rad/s),
        to be driven one call at a time: a `RunningFilter` with this
        filter's tuning. `inter_system_biases` (tight only): with the
        Galileo, BeiDou and GLONASS inter-system-bias states, to
        update with satellites of those systems.
        """

@final
class FilterEstimate:
    """What a running filter estimates now (`RunningFilter.state`): the
    corrected navigation solution and the sensor, clock and optional
    states' estimates (totals, not errors).
    """

    @property
    def time(self) -> float:
        """The filter's time, s."""

    @property
    def position_ecef(self) -> npt.NDArray[np.float64]:
        """Position of the IMU, ECEF m, (3,)."""

    @property
    def velocity_ecef(self) -> npt.NDArray[np.float64]:
        """Velocity, ECEF m/s, (3,)."""

    @property
    def attitude(self) -> npt.NDArray[np.float64]:
        """Attitude C_b^e (body to ECEF), (3, 3)."""

    @property
    def accel_bias(self) -> npt.NDArray[np.float64]:
        """Accelerometer bias, m/s², (3,)."""

    @property
    def gyro_bias(self) -> npt.NDArray[np.float64]:
        """Gyro bias, rad/s, (3,)."""

    @property
    def clock_offset(self) -> float:
        """Receiver clock offset, m."""

    @property
    def clock_drift(self) -> float:
        """Receiver clock drift, m/s."""

    @property
    def accel_scale_factor(self) -> npt.NDArray[np.float64] | None:
        """Accelerometer scale-factor errors, (3,); None without their states."""

    @property
    def gyro_scale_factor(self) -> npt.NDArray[np.float64] | None:
        """Gyro scale-factor errors, (3,); None without their states."""

    @property
    def inter_system_bias(self) -> list[float] | None:
        """Inter-system biases (Galileo, BeiDou, GLONASS minus GPS), m;
        None without their states.
        """

    @property
    def range_biases(self) -> dict[str, float] | None:
        """Range biases, m, by satellite ("G05"; the loosely coupled filter's
        fix errors by ECEF axis, "x", "y", "z"); None without their states.
        """

    def to_dict(self) -> dict[str, Any]:
        """The fields as a dict, by attribute name (records inside stay
        records; arrays stay arrays).
        """

@final
class RunningFilter:
    """A coupled GNSS/INS filter driven one call at a time: `predict` (or
    `predict_increments`) at each IMU sample, then any updates at that
    time. Made by `TightlyCoupledFilter.start` or
    `LooselyCoupledFilter.start`, with that filter's tuning; the batch
    `run` is this same sequence of calls, so the same calls give the same
    numbers, bit for bit.

    Times are the IMU's time stamps, s (not intervals: the records and the
    GNSS epochs are matched on them); each must follow the last by more
    than 0 and at most 1 s. Updates apply at the filter's time (that of the
    last predict); a GNSS epoch stamped more than the time tolerance
    (1e-4 s) away is refused: predict to its time first. Every update
    applies its rows as batches (one per block of a fix or GNSS epoch)
    tested by the chi-square gate, and returns whether it was applied
    whole (every batch accepted). Measurement records
    accumulate until `take_records()` hands them over. Every update is a
    transaction: refused calls (ValueError naming the argument: stds within
    1e-9 to 1e9 of their unit, lever arms within 100 m, a fix's position
    near the Earth's surface) and updates that fail on the way
    (DivergenceError) leave the filter exactly as it was, records included.
    """

    def predict(
        self, time: float, specific_force: npt.ArrayLike, angular_rate: npt.ArrayLike
    ) -> None:
        """Steps the INS and the covariance to `time` (s) with the raw sample
        there: `specific_force` (3,) m/s² and `angular_rate` (3,) rad/s in
        body axes (the mechanization integrates between the previous
        sample and this one, as `run` does).
        """

    def predict_increments(
        self, time: float, delta_v: npt.ArrayLike, delta_theta: npt.ArrayLike
    ) -> None:
        """Steps to `time` (s) with the raw increments of the interval since
        the filter's time: `delta_v` (3,) m/s and `delta_theta` (3,) rad
        (∫f dt, ∫ω dt, what integrating IMUs log), with coning and sculling
        from the previous interval's increments.
        """

    def update_gnss(self, gnss: GnssMeasurements | Any, epoch: int = 0) -> bool:
        """Applies epoch `epoch` of `gnss` (anything `TightlyCoupledFilter.run`
        takes: `GnssMeasurements` or its dict) at the filter's time: the
        pseudoranges as one batch, then the rates. Only for a filter started
        by `TightlyCoupledFilter` (the loose one holds the clock fixed).
        Returns whether the epoch was applied whole: every batch it made
        passed its gate (pseudoranges after any fault exclusion, rates); the
        records say which failed.
        """

    def update_fix(
        self,
        position_ecef: npt.ArrayLike,
        position_covariance: npt.ArrayLike,
        velocity_ecef: npt.ArrayLike | None = None,
        velocity_covariance: npt.ArrayLike | None = None,
    ) -> bool:
        """Applies a position fix of the antenna at the filter's time:
        `position_ecef` (3,) m with `position_covariance` (3, 3) m², and
        optionally `velocity_ecef` (3,) m/s with `velocity_covariance`
        (3, 3) m²/s² (each block tested as one batch, as `run` does).
        Returns whether the fix was applied whole: every block passed its
        gate; the records say which failed.
        """

    def update_zupt(self, std: float) -> bool:
        """Zero-velocity update, ``std`` m/s per axis. Returns whether it
        passed its gate (as every update method does)."""

    def update_zaru(self, mean_angular_rate: npt.ArrayLike, std: npt.ArrayLike | float) -> bool:
        """Zero-angular-rate update at rest: `mean_angular_rate` (3,) rad/s is
        the raw gyro reading averaged over the standstill, `std` rad/s (of
        the mean; a scalar or per axis). Returns whether it was accepted.
        """

    def update_non_holonomic(self, std: float, lever_arm: npt.ArrayLike | None = None) -> bool:
        """Non-holonomic constraint of a land vehicle: the point at
        `lever_arm` (3,) m from the IMU in body axes (None: the IMU) has no
        lateral and no vertical velocity, `std` m/s. Body x must point
        forward along the vehicle. Returns whether it was accepted.
        """

    def update_speed(
        self, speed: float, std: float, lever_arm: npt.ArrayLike | None = None
    ) -> bool:
        """Odometer (wheel speed): the forward speed `speed` m/s (negative when
        reversing) of the point at `lever_arm` (3,) m in body axes (None:
        the IMU), `std` m/s. Returns whether it was accepted.
        """

    def update_height(self, height: float, std: float) -> bool:
        """Height (a barometer referenced to the ellipsoid): the IMU's WGS 84
        ellipsoidal height `height` m, `std` m. Returns whether it was
        accepted.
        """

    def update_heading(self, yaw: float, std: float) -> bool:
        """Heading (dual antenna; a magnetometer corrected for declination):
        the body's yaw `yaw` rad from north, positive east (NED), `std` rad.
        Returns whether it was accepted.
        """

    @property
    def time(self) -> float:
        """The filter's time, s (that of the last predict)."""

    @property
    def position_ecef(self) -> npt.NDArray[np.float64]:
        """Position r^e of the IMU, (3,) m."""

    @property
    def velocity_ecef(self) -> npt.NDArray[np.float64]:
        """Velocity v^e of the IMU, (3,) m/s."""

    @property
    def attitude(self) -> npt.NDArray[np.float64]:
        """Attitude C_b^e, (3, 3)."""

    @property
    def state(self) -> FilterEstimate:
        """The whole estimate, a `FilterEstimate`: `time` s, `position_ecef` m,
        `velocity_ecef` m/s, `attitude` C_b^e, `accel_bias` m/s²,
        `gyro_bias` rad/s, `clock_offset` m, `clock_drift` m/s, and the
        optional blocks' estimates (None without their states).
        """

    @property
    def covariance(self) -> npt.NDArray[np.float64]:
        """The error-state covariance P, (n, n), in the order of
        `state_names` and the units of the error states (rad, m/s, m, m/s²,
        rad/s, m, m/s; attitude and velocity in ECEF axes).
        """

    @property
    def state_names(self) -> list[str]:
        """Error-state names, in covariance order."""

    def take_records(self) -> dict[str, dict[str, Any]]:
        """The records since the last call, handed over and cleared: a dict
        with `measurements`, `batches` and `resets`, each as in
        `FilterSolution`.
        """

@final
class LooselyCoupledFilter:
    """Closed-loop error-state EKF on GNSS position (and velocity) fixes (Groves
    §14.3.2): each fix (floored at 2 cm, 2 cm/s) is whitened by its
    covariance's Cholesky factor into unit-variance updates tested together
    (a fix is applied whole or not at all); after 3 failed fixes in a row the
    position (velocity) is reset to the fix. The clock states are not
    observed (their process noise is off). Same states, tuning, defaults and
    overrides as `TightlyCoupledFilter` (`use_pseudorange_rate`, `use_carrier_phase`,
    `pseudorange_correlation_time` and the clock settings have no effect).

    Raises ValueError naming the argument for a bad value.

    Tuning from `imu.spec` at `imu.sample_rate` (`FilterTuning::from_imu_spec`):
    white-noise PSDs = noise density² (or per-sample std² / rate); bias
    processes from bias instability (2 sigma²/tau) and random walk, the
    instability taken as a random walk when the bias has a turn-on part
    (nothing makes a turn-on bias fade); initial bias std =
    sqrt(bias_std² + instability²), floored at 1e-6 m/s² and 1e-9 rad/s;
    errors the states lack (scale factor unless estimated, misalignment,
    nonlinearity, g-sensitivity): their part driven by the specific force at
    rest widens the initial bias std, their part driven by the motion is
    process noise shaped by the sensed specific force and rate at every step,
    2 sigma² tau with the manoeuvres' correlation time tau = 10 s
    (`filter::input_noise`). Receiver clock: the simulator's TCXO
    (`clock_h0` 2e-19, `clock_h_minus2` 2e-20, the same names and model
    as `simulate_gnss`: S_cφ = c² h0 / 2, S_cf = 2π² c² h−2). Every default
    below can be overridden; an argument left None takes the core's
    default, listed by `memsnav.defaults()` under the class name
    (`tuning` shows the values in effect):

    - `imu`: the `ImuModel` whose spec and sample rate tune the filter.
    - `settings` [None]: a `navigate` configuration's tables as a dict
      (`{"filter": {...}, "gnss": {...}, "imu": {...}, "imu_spec": {...},
      "standstill": {...}, "aids": {...}}`, the keys `navigate_settings()`
      lists, with their units and defaults): the filter is navigate's for
      those keys, defaults included (range-bias states on for pseudoranges;
      `gnss.range_bias_states = "every_satellite"` gives each of up to 40
      satellites one), tuned from `imu.spec`, and `run` applies navigate's
      aids as a navigate run does: zero-velocity and zero-rate updates at the
      standstills it detects (on unless `aids.zupt`/`aids.zaru` are false)
      and, with `aids.nhc`, the non-holonomic constraint (give
      `aids.nhc_std_m_s`). Tables and keys that prepare a navigate run
      (`[alignment]`, `[outages]`, `filter.imu_preset`, `filter.smoother`,
      `imu.time_offset_s`, `imu.mounting_rpy_deg`, any `"auto"`) raise
      ValueError naming them, and `start` raises while an aid is on. Not with
      the keywords below.
    - `scale_factor_states` [False]: six more states, the accelerometer and
      gyro scale factors (23 in all).
    - `accel_noise_density` (m/s²/√Hz), `gyro_noise_density` (rad/s/√Hz):
      replace the sensor's white PSDs by density² (the input-shaped noise of
      the unmodelled errors stays).
    - `accel_bias_psd` ((m/s²)²/s), `gyro_bias_psd` ((rad/s)²/s): bias
      driving-noise PSDs.
    - `gate_probability`: chi-square(1) gate, 0.999 (|nu| > 3.29 sigma rejected
      and reported); 1.0 disables it.
    - initial one-sigmas: `initial_position_std` 5 m and
      `initial_velocity_std` 0.5 m/s per ECEF axis (a code fix),
      `initial_tilt_std` 1° and `initial_heading_std` 5° (in rad),
      `initial_accel_bias_std` / `initial_gyro_bias_std` (None: from the
      spec as above), `initial_clock_offset_std` 50 m,
      `initial_clock_drift_std` 10 m/s; scale factors (23 states): the
      spec's scale_factor_std (floored at 1e-6).
    - `use_pseudorange_rate`: use rates when the epoch carries them.
    - `use_carrier_phase`: use each satellite's carrier-phase change
      between consecutive epochs (time-differenced carrier phase, as a
      velocity measurement; cycle slips found from the receiver's flags,
      the Doppler and the residual test) when the epochs carry it.
    - `clock_h0`, `clock_h_minus2`: the receiver oscillator's Allan
      coefficients (None: the TCXO above).
    - `manoeuvre_correlation_time`: tau of the input-shaped noise, s (None:
      10 s, a land vehicle's turns and accelerations; shorter for a walker).
    - `pseudorange_correlation_time`: correlation time of the code's fast
      errors (multipath), s (None: 0, white); each pseudorange's std is
      inflated by sqrt((1 + rho)/(1 - rho)), rho = exp(-dt/tau) over the
      epoch interval dt, so that epochs sampling one error carry it once
      (docs/how-to/multi-gnss.md, "Correlated code errors").
    """

    def __new__(
        cls,
        imu: ImuModel,
        *,
        settings: dict[str, dict[str, Any]] | None = None,
        scale_factor_states: bool = False,
        accel_noise_density: float | None = None,
        gyro_noise_density: float | None = None,
        accel_bias_psd: float | None = None,
        gyro_bias_psd: float | None = None,
        gate_probability: float | None = None,
        initial_position_std: float | None = None,
        initial_velocity_std: float | None = None,
        initial_tilt_std: float | None = None,
        initial_heading_std: float | None = None,
        initial_accel_bias_std: float | None = None,
        initial_gyro_bias_std: float | None = None,
        initial_clock_offset_std: float | None = None,
        initial_clock_drift_std: float | None = None,
        use_pseudorange_rate: bool = True,
        use_carrier_phase: bool = False,
        clock_h0: float | None = None,
        clock_h_minus2: float | None = None,
        manoeuvre_correlation_time: float | None = None,
        pseudorange_correlation_time: float | None = None,
    ) -> LooselyCoupledFilter: ...
    @property
    def tuning(self) -> dict[str, float | bool | str]:
        """The tuning in effect (PSDs, correlation times, initial one-sigmas,
        the unmodelled errors' one-sigmas ``unmodelled_*_std`` and
        ``manoeuvre_correlation_time``), SI, and the optional state blocks
        (``scale_factor_states``, ``installation_states``,
        ``range_bias_states``: False, True for 12 shared slots or
        "every_satellite"), and the ``aids`` `run` applies ("zupt, zaru"
        from `settings` by default, "" without them).
        """

    def run(
        self,
        time: npt.ArrayLike,
        specific_force: npt.ArrayLike,
        angular_rate: npt.ArrayLike,
        fixes: FixSeries | PositionFixes | Any,
        *,
        initial_attitude: npt.ArrayLike | None = None,
        initial_state: dict[str, Any] | Any | None = None,
        smooth: bool = False,
    ) -> FilterSolution:
        """Filters the whole series in one call (GIL released); with ``smooth``
        also the fixed-interval smoothed solution, as ``.smoothed``.

        ``time`` (N,) s, ``specific_force`` (N, 3) m/s², ``angular_rate`` (N, 3)
        rad/s and ``initial_attitude`` (C_b^e) as for the tight filter's ``run``.
        ``fixes``: a ``solve_fix`` result (invalid epochs skipped; covariances =
        the position and velocity blocks of the LS covariance) or an
        object/dict with ``time`` (T,), ``position_ecef`` (T, 3) m,
        ``position_covariance`` (T, 3, 3) m², optional ``velocity_ecef`` (T, 3)
        m/s and ``velocity_covariance`` (T, 3, 3). Initial position and velocity
        from the first fix (moved back to ``time[0]``); attitude as for the
        tight filter. ``initial_state`` as for the tight filter (a clock there
        is carried but never observed).
        """

    def run_increments(
        self,
        time: npt.ArrayLike,
        delta_v: npt.ArrayLike,
        delta_theta: npt.ArrayLike,
        fixes: FixSeries | PositionFixes | Any,
        *,
        initial_attitude: npt.ArrayLike | None = None,
        initial_state: dict[str, Any] | Any | None = None,
        smooth: bool = False,
    ) -> FilterSolution:
        """`run` on an integrating IMU's output: `time` (N + 1,) s and the
        increments of each interval, `delta_v` (N, 3) m/s and
        `delta_theta` (N, 3) rad (row k over [time[k], time[k + 1]], as
        `imu_increments` gives them), integrated by the increments
        mechanization with coning and sculling (`strapdown_increments`'s)
        instead of from samples; an epoch between two times takes its
        share of the interval's increments at constant rates. The rest
        (aiding, start, smoothing, the solution at every time) as `run`;
        the mean rates of the intervals stand for samples where one is
        looked at (levelling the start).
        """

    def start(
        self,
        time: float,
        specific_force: npt.ArrayLike,
        angular_rate: npt.ArrayLike,
        initial_state: dict[str, Any] | Any,
        *,
        inter_system_biases: bool = False,
    ) -> RunningFilter:
        """The filter started at `time` (s) from `initial_state` (the dict
        `run` takes: position_ecef m, velocity_ecef m/s, attitude C_b^e,
        optional clock_offset m, clock_drift m/s) with the raw sample
        there (`specific_force` (3,) m/s², `angular_rate` (3,) rad/s),
        to be driven one call at a time: a `RunningFilter` with this
        filter's tuning. `inter_system_biases` (tight only): with the
        Galileo, BeiDou and GLONASS inter-system-bias states, to
        update with satellites of those systems.
        """

def navigation_experiment(
    imus: Sequence[tuple[str, str | ImuModel | tuple[str, dict[str, float]]]],
    *,
    runs: int | None = None,
    duration: float | None = None,
    seed: int | None = None,
    n_satellites: int | None = None,
    outage: tuple[float, float] | tuple[float, float, int] | None = None,
    calibration_duration: float | None = None,
    early_window: float | None = None,
    pseudorange_rate: bool | None = None,
    pseudorange_std: float | None = None,
    pseudorange_rate_std: float | None = None,
    initial_attitude_std_deg: tuple[float, float, float] | None = None,
    scale_factor_states: bool = False,
    absorb_unmodelled: bool | None = None,
    smooth: bool = False,
    keep_runs: bool = False,
    threads: int | None = None,
    progress: Callable[[int, int], object] | None = None,
    run_range: tuple[int, int] | None = None,
    chunks: Sequence[bytes] | None = None,
    systems: Sequence[str] | None = None,
    inter_system_bias: tuple[float, float] | Sequence[float] | None = None,
    carrier_phase_std: float | None = None,
    cycle_slip_probability: float | None = None,
) -> Any:
    """Navigation Monte Carlo (paper §5.3) as a dict of arrays (bytes with
    ``run_range``; ``run_range`` / ``chunks`` as in
    ``calibration_experiment``); use
    ``memsnav.experiments.navigation``, which documents it. ``imus``: (name,
    source) with source a preset name, ``(preset name, spec overrides)``,
    ``"calibrated:<raw name>"`` or an ``ImuModel``. ``pseudorange_std`` m,
    ``pseudorange_rate_std`` m/s, ``initial_attitude_std_deg`` (north tilt,
    east tilt, heading) degrees, None for (1, 1, 5). ``outage``: (start_s,
    length_s) total or (start_s, length_s, n_visible) keeping n_visible (0-3)
    satellites. ``systems``: RINEX letters of the simulated systems (None:
    ["G"]), ``inter_system_bias``: Galileo, BeiDou[, GLONASS] pseudorange
    biases against GPS, m (None: 0, 0, 0). ``carrier_phase_std``: simulated carrier
    range noise, m (None: 0, no carrier phase; above 0 the tight filters use
    its changes between epochs), ``cycle_slip_probability``: silent slips
    per satellite and epoch (None: 0)."""

# --- real data: RINEX observations and the coupled filters on logs ---

@final
class BroadcastEphemerides:
    """Broadcast ephemerides of GPS, Galileo, BeiDou and GLONASS satellites
    (read_broadcast_nav, UbxLog.broadcast_ephemerides)."""

    @property
    def satellites(self) -> list[str]:
        """The satellites with at least one ephemeris, RINEX names
        (``["C11", "E07", "G10", ...]``), sorted.
        """

    @property
    def healthy_satellites(self) -> list[str]:
        """The satellites whose ephemerides say they are healthy, RINEX names."""

    @property
    def skipped(self) -> dict[str, int]:
        """Records left out, by reason, with counts (a RINEX file's other
        systems, Galileo F/NAV records, repeated GLONASS records).
        """

    @property
    def klobuchar(self) -> tuple[list[float], list[float]] | None:
        """The GPS Klobuchar coefficients ``(alpha, beta)`` the ephemerides
        carry (a RINEX header's, a UBX log's CNAV type 30), or None:
        ``measurements``' default.
        """

    @property
    def gps_cnav_ephemerides(self) -> list[dict[str, Any]]:
        """The GPS CNAV ephemerides (a RINEX 4 file's ``CNAV`` records, a UBX
        log's L2C/L5 messages), dicts as ``UbxLog.gps_cnav_ephemerides``;
        those with an L1 C/A group delay are among the GPS ephemerides the
        measurements use too.
        """
    @property
    def glonass_channels(self) -> dict[str, int]:
        """Each GLONASS slot's FDMA frequency channel k (G1 = 1602 + 0.5625 k
        MHz), from its latest ephemeris: ``{"R01": 1, ...}``.
        """

    def satellite_states(
        self, gps_time: float | npt.ArrayLike, satellites: Sequence[str] | None = None
    ) -> tuple[npt.NDArray[np.float64], npt.NDArray[np.float64], npt.NDArray[np.float64]]:
        """Satellite positions, velocities (ECEF, m, m/s) and clock
        corrections (s) at GPS times ``gps_time`` (s since 1980-01-06, a
        number or ``(T,)``) of ``satellites`` (RINEX names, default
        ``satellites``), from the healthy ephemeris the measurements would
        use: ``(position (T, S, 3), velocity (T, S, 3), clock (T, S))``, one
        time's ``(S, 3), (S, 3), (S,)`` for a number. NaN where no
        ephemeris covers the time (t_oe within 2 h; GLONASS t_b within 30
        min), counted in a ``UserWarning``. Clocks are for GPS L1 C/A,
        Galileo E1, BeiDou B3I and GLONASS G1, relativity included.
        """

    def __len__(self) -> int: ...

def satellite_name(number: int) -> str:
    """The RINEX name of a satellite number (``107`` → ``"E07"``; G n → n,
    E n → 100 + n, C n → 200 + n), or the number as text beyond them.

    `number`: a satellite number, as `satellite_number` gives it.
    """

def read_broadcast_nav(path: str | os.PathLike[str]) -> BroadcastEphemerides:
    """The GPS, Galileo, BeiDou and GLONASS ephemerides of a RINEX 2 (GPS
    ``n``, GLONASS ``g``, 2.12 Galileo ``e``) or RINEX 3 navigation file
    (other systems, Galileo F/NAV records and ephemerides in conflict, two
    of one satellite and t_oc or issue of data with other values, counted
    in ``skipped``).

    `path`: the file to read (str or path-like).
    """

@final
class RinexObservations:
    """A RINEX 3 or RINEX 2.10/2.11 observation file (2.x codes read as the
    RINEX 3 codes of their signals, docs/reference/readers.md).
    """

    @property
    def time(self) -> npt.NDArray[np.float64]:
        """Epoch times, GPS s since 1980-01-06, ``(T,)``."""

    @property
    def satellites(self) -> list[str]:
        """Every satellite seen, e.g. ``["E07", "G10", ...]`` (sorted)."""

    @property
    def observation_types(self) -> dict[str, list[str]]:
        """Observation types per system letter, in header order."""

    @property
    def glonass_channels(self) -> dict[str, int]:
        """Each GLONASS slot's FDMA frequency channel k of the header's
        ``GLONASS SLOT / FRQ #`` (G1 = 1602 + 0.5625 k MHz):
        ``{"R01": 1, ...}``; empty without the record.
        """
    @property
    def approx_position_ecef(self) -> npt.NDArray[np.float64] | None:
        """``APPROX POSITION XYZ`` of the header, ECEF m, or None."""

    @property
    def warnings(self) -> list[str]:
        """Non-fatal problems met while reading (a truncated last record)."""

    @property
    def skipped(self) -> dict[str, int]:
        """Records not read, by kind, with counts: event records (flags 2-5,
        their header lines not applied) and cycle-slip records (flag 6)."""

    def observation(self, code: str) -> npt.NDArray[np.float64]:
        """Values of observation ``code`` (e.g. ``"C1C"`` m, ``"D1C"`` Hz,
        ``"S1C"`` dB-Hz), ``(T, len(satellites))``; NaN where absent.
        """

    def gps_l1(
        self,
        constellation: Constellation,
        reference_position_ecef: npt.ArrayLike | None = None,
        *,
        elevation_mask_deg: float | None = None,
        min_cn0_db_hz: float | None = None,
        ionosphere: bool = True,
        klobuchar: tuple[Sequence[float], Sequence[float]] | None = None,
        troposphere: bool = True,
        pseudorange_std: float | None = None,
        pseudorange_rate_std: float | None = None,
        satellites: Sequence[int] | None = None,
        carrier_phase_std: float | None = None,
        weighting: str | None = None,
    ) -> GnssMeasurements:
        """GPS L1 C/A measurements (time = GPS time) for the coupled filters and
        ``solve_fix``: satellite states at transmission time, pseudoranges
        corrected for the satellite clock, the Klobuchar ionosphere
        (``klobuchar=(alpha, beta)``, default RTKLIB's coefficients) and the
        Saastamoinen troposphere at ``reference_position_ecef`` (default the
        header's approximate position); rates from the Doppler; carrier ranges
        from the phase, corrected alike with the ionosphere's sign reversed,
        lock lost where the loss-of-lock indicator says so
        (``carrier_phase_std=0``: no carrier phase). Pseudorange sigma by
        ``weighting``: ``"rtklib"`` (default) RTKLIB 2.4.3's single-point
        error model, sigma^2 = F^2 (0.3^2 + 0.3^2/sin(el)) + URA^2 + 0.3^2 +
        (0.5 Klobuchar)^2 + (0.3/(sin(el) + 0.1))^2 (F = 1.5 for GLONASS, else
        1); ``"signal-strength"``: ``pseudorange_std`` (default 3 m, only with
        this model) at 45 dB-Hz and zenith, scaled by
        sqrt(10^((45-C/N0)/10))/sin(el). Rate and carrier sigma (m/s, m) at 45
        dB-Hz and zenith, scaled alike in both."""

    def measurements(
        self,
        ephemerides: BroadcastEphemerides,
        reference_position_ecef: npt.ArrayLike | None = None,
        *,
        systems: Sequence[str] | None = None,
        elevation_mask_deg: float | None = None,
        min_cn0_db_hz: float | None = None,
        ionosphere: bool = True,
        klobuchar: tuple[Sequence[float], Sequence[float]] | None = None,
        troposphere: bool = True,
        pseudorange_std: float | None = None,
        pseudorange_rate_std: float | None = None,
        satellites: Sequence[str] | None = None,
        carrier_phase_std: float | None = None,
        dual_frequency: bool = False,
        weighting: str | None = None,
    ) -> GnssMeasurements:
        """Measurements of several systems for the tight filter and
        ``solve_fix``: GPS L1 C/A, Galileo E1 and BeiDou B1I/B2I/B3I (the
        first the file has), GLONASS G1 C/A on each satellite's channel, with
        ``ephemerides`` (``read_broadcast_nav``, or a UBX log's
        ``broadcast_ephemerides``), corrected as ``gps_l1`` does with each
        signal's group delay and the Klobuchar delay scaled to its
        frequency. ``systems``: RINEX letters (``"G"``, ``"E"``, ``"C"``,
        ``"R"``; default G, E, C: GLONASS on request, for ``solve_fix`` and
        the tight filter). ``satellites``: RINEX names
        (``"G10"``, ``"E07"``, ``"R05"``) to keep. Satellite numbers in the
        result: G n → n, E n → 100 + n, C n → 200 + n, R n → 300 + n; each
        system's pseudoranges keep the receiver's inter-system bias, which
        the tight filter and ``solve_fix`` estimate. Epochs whose satellites
        no ephemeris covers are counted in a ``UserWarning``; when none is
        covered, a ``ValueError`` says so. With the troposphere on, the
        elevation mask must be at least 5° (``MIN_TROPOSPHERE_MASK_DEG``).
        ``klobuchar``: default the ephemerides' own (``klobuchar``: the
        navigation file's header, a UBX log's CNAV), else RTKLIB's.
        ``reference_position_ecef`` (also ``gps_l1``'s): ``(3,)``, or
        ``(T, 3)`` with one position per epoch for a moving receiver (the
        masks and the atmosphere at each); default the file's APPROX
        POSITION XYZ. Each measurement's signal, C/N0 and
        elevation in ``signal``, ``cn0_db_hz``, ``elevation_rad``.
        ``dual_frequency=True``: each satellite's ionospheric delay measured
        from a second signal's pseudorange where the file has one whose
        group delay the ephemerides give (GPS L5 or L2C with CNAV's
        inter-signal corrections, Galileo E5a or E5b, BeiDou another D1
        band), smoothed per satellite; the Klobuchar delay for the rest.
        ``weighting``, ``pseudorange_std``: as ``gps_l1``.
        """

    def __len__(self) -> int: ...

def read_rinex_obs(path: str | os.PathLike[str]) -> RinexObservations:
    """Reads a RINEX 3 or RINEX 2.10/2.11 observation file (errors name the
    file and line; a truncated last record is dropped and reported in
    ``warnings``; event records are counted in ``skipped``).

    `path`: the file to read (str or path-like).
    """

def read_klobuchar(path: str | os.PathLike[str]) -> tuple[list[float], list[float]] | None:
    """The Klobuchar coefficients ``(alpha, beta)`` of a RINEX navigation
    header (``ION ALPHA``/``ION BETA`` or ``IONOSPHERIC CORR GPSA/GPSB``),
    or None when it has none.

    `path`: the file to read (str or path-like).
    """

def defaults() -> dict[str, dict[str, Any]]:
    """The core's default of every optional modelling argument, by the
    Python name of the function or class that takes it
    (``"TightlyCoupledFilter"``, ``"RinexObservations.gps_l1"``,
    ``"navigation_experiment"``, ``"Constellation.walker"``, the sample
    rates of the sensor models, presets, trajectories and calibrations): a
    ``None`` in that signature means this value. The coupled filters' noise
    densities, bias processes and initial bias spreads come from the IMU
    model and are not listed."""

def navigate_settings_schema() -> str:
    """The JSON schema (a JSON text) of the engine's tables of a ``navigate``
    configuration: per table an object of its keys, each with its kind of
    value, bounds and description, and no other key
    (``memsnav.realdata.config.json_schema()`` joins the reading keys')."""

def navigate_settings() -> dict[str, dict[str, str]]:
    """The tables and keys ``navigate_log(settings=...)`` reads (the engine's
    part of a ``navigate`` configuration), each with what it holds."""

def mounting_matrix(rpy_deg: Sequence[Sequence[float]]) -> npt.NDArray[np.float64]:
    """C_b^s, the sensor-to-body rotation of a chain of [roll, pitch, yaw]
    triples in degrees applied in order (`[imu] mounting_rpy_deg`):
    f_b = C(last) ··· C(first) f_s, (3, 3).

    `rpy_deg`: a list of [roll, pitch, yaw] triples, degrees.
    """

def check_navigate_settings(settings: dict[str, dict[str, Any]]) -> None:
    """Checks `settings` (`{table: {key: value}}`) as `navigate_log` would,
    without data: unknown tables or keys, values of the wrong kind or out of
    range raise `ValueError` naming `table.key`.
    """

@final
class PositionFixes:
    """Position (and velocity) fixes of an antenna, ready for
    `navigate_log` or `LooselyCoupledFilter.run`.
    """

    @property
    def time(self) -> npt.NDArray[np.float64]:
        """Fix times, s, (T,)."""

    @property
    def position_ecef(self) -> npt.NDArray[np.float64]:
        """Antenna positions, ECEF m, (T, 3)."""

    @property
    def position_covariance(self) -> npt.NDArray[np.float64]:
        """Their covariances, m², (T, 3, 3)."""

    @property
    def velocity_ecef(self) -> npt.NDArray[np.float64]:
        """Antenna velocities, ECEF m/s, (T, 3); NaN where a fix has none."""

    @property
    def velocity_horizontal_only(self) -> npt.NDArray[np.bool_]:
        """Whether each fix's velocity is horizontal only (a speed and course
        over ground: NMEA; the filter takes its north and east components
        and nothing along the vertical), (T,)."""

    def __len__(self) -> int: ...

def fixes_from_solution(
    time: npt.ArrayLike,
    geodetic: npt.ArrayLike,
    std_ned: npt.ArrayLike | None = None,
    *,
    covariance_ned: npt.ArrayLike | None = None,
    velocity_ned: npt.ArrayLike | None = None,
    velocity_std_ned: npt.ArrayLike | None = None,
    velocity_covariance_ned: npt.ArrayLike | None = None,
    rate_hz: float | None = None,
    added_position_noise_ned: npt.ArrayLike | None = None,
    added_velocity_noise: float | None = None,
    use_velocity: bool | None = None,
    seed: int | None = None,
) -> PositionFixes:
    """Fixes from a geodetic solution (a `PosSolution` of `read_pos`,
    `read_fixes_csv` or `read_nmea`, or arrays): `time` (T,) s, `geodetic`
    (T, 3) [lat rad, lon rad, h m], the position uncertainty as `std_ned`
    (T, 3) m or `covariance_ned` (T, 3, 3) m² (exactly one), optional
    `velocity_ned` (T, 3) with `velocity_std_ned` (T, 3) or
    `velocity_covariance_ned` (T, 3, 3) (NaN where absent; north and east
    with a NaN down is a horizontal-only velocity, NMEA's). Keeps the epochs
    on the `rate_hz` grid, adds seeded white noise of
    `added_position_noise_ned` (N, E, D one-sigma, m) and
    `added_velocity_noise` (m/s), and rotates the covariance (+ noise²) into
    ECEF.
    """

def truth_at_point(
    geodetic: npt.ArrayLike,
    attitude: npt.ArrayLike | None = None,
    *,
    lever_arm: npt.ArrayLike | None = None,
    offset_ned: npt.ArrayLike | None = None,
) -> npt.NDArray[np.float64]:
    """The truth moved to the point being scored
    (`memsnav_core::navigate::truth::truth_at_point`): `geodetic` (N, 3)
    [lat rad, lon rad, h m] at the truth's own point, `attitude` (N, 3, 3)
    its C_b^n (needed for a lever arm), `lever_arm` (3,) the scored point
    from the truth's point in the truth's body axes (forward, right, down),
    m, `offset_ned` (3,) a datum offset added in local NED, m (None: zero).
    ECEF (N, 3), m: r_truth + C_n^e (C_b^n l + o).
    """

@final
class InitialState:
    """The filter's state at the sample a log run starts at, as the filter
    classes' `initial_state=` takes it.
    """

    @property
    def position_ecef(self) -> npt.NDArray[np.float64]:
        """Position of the IMU, ECEF m, (3,)."""

    @property
    def velocity_ecef(self) -> npt.NDArray[np.float64]:
        """Velocity, ECEF m/s, (3,)."""

    @property
    def attitude(self) -> npt.NDArray[np.float64]:
        """Attitude C_b^e (body to ECEF), (3, 3)."""

    def to_dict(self) -> dict[str, Any]:
        """The fields as a dict, by attribute name (records inside stay
        records; arrays stay arrays).
        """

@final
class RunStart:
    """How a log run started (`LogRun.start`)."""

    @property
    def kind(self) -> str:
        """ "static", "static_with_heading" or "moving"."""

    @property
    def time(self) -> float:
        """When, s."""

    @property
    def epoch(self) -> int:
        """The GNSS epoch (index) it started at."""

    @property
    def heading_known(self) -> bool:
        """Whether the heading was known at the start."""

    @property
    def first_imu_time(self) -> float:
        """The log's first IMU sample, s."""

    @property
    def first_gnss_time(self) -> float:
        """The log's first GNSS epoch, s."""

    @property
    def earliest_time(self) -> float:
        """The earliest start the log allows (its first GNSS epoch with
        `standstill.window_s` of IMU data before it), s: the outages
        count from it.
        """

    @property
    def late_reason(self) -> str | None:
        """Where and why the run started more than 10 s after that (late),
        None when it did not.
        """

    @property
    def first_sample(self) -> int:
        """The index of the IMU sample it starts at."""

    @property
    def initial_state(self) -> InitialState:
        """The filter's start at that sample (`initial_state=` of the filter
        classes).
        """

    @property
    def position_std(self) -> float:
        """Its position one-sigma, m (before any `[filter]` override)."""

    @property
    def velocity_std(self) -> float:
        """Its velocity one-sigma, m/s."""

    @property
    def tilt_std(self) -> float:
        """Its roll and pitch one-sigma, rad."""

    @property
    def heading_std(self) -> float:
        """Its heading one-sigma, rad."""

    def to_dict(self) -> dict[str, Any]:
        """The fields as a dict, by attribute name (records inside stay
        records; arrays stay arrays).
        """

@final
class RunFailure:
    """Why a log run stopped before the end of the log (`LogRun.failure`)."""

    @property
    def time(self) -> float:
        """When, GNSS time, s."""

    @property
    def message(self) -> str:
        """What went wrong."""

    def to_dict(self) -> dict[str, Any]:
        """The fields as a dict, by attribute name (records inside stay
        records; arrays stay arrays).
        """

@final
class GyroScaleCheck:
    """The gyro's turns against the GNSS course's over a whole log
    (`LogRun.gyro_scale`).
    """

    @property
    def ratio(self) -> float:
        """The gyro's turn over the course's: 1 for a gyro read in its unit,
        π/180 for radians read as degrees, 180/π the reverse.
        """

    @property
    def relative_std(self) -> float:
        """Its relative std."""

    @property
    def course_turn_deg(self) -> float:
        """The course's turn over the pairs of epochs used, deg."""

    @property
    def pairs(self) -> int:
        """The pairs of GNSS epochs used."""

    @property
    def conclusive(self) -> bool:
        """Enough turning for a verdict."""

    @property
    def warning(self) -> str | None:
        """A conclusive ratio beyond √(180/π) either way: the warning naming
        `gyro_unit` and the likely unit (also in `solution.warnings`);
        else None.
        """

    def to_dict(self) -> dict[str, Any]:
        """The fields as a dict, by attribute name (records inside stay
        records; arrays stay arrays).
        """

@final
class CarrierPhaseUse:
    """A run's carrier-phase changes between epochs by fate
    (`LogRun.carrier_phase`).
    """

    @property
    def changes(self) -> int:
        """Every change between consecutive epochs of a satellite."""

    @property
    def used(self) -> int:
        """Applied."""

    @property
    def slips(self) -> int:
        """Cycle slips (receiver flag or Doppler test)."""

    @property
    def excluded(self) -> int:
        """Excluded by the residual test."""

    @property
    def too_few(self) -> int:
        """Clean, but the epoch had fewer than the 5 clean changes a batch
        needs.
        """

    @property
    def rejected(self) -> int:
        """Rejected by their batch's gate, an invalid value or a reset."""

    @property
    def warning(self) -> str | None:
        """Why none was used (also in `solution.warnings`); else None."""

    def to_dict(self) -> dict[str, Any]:
        """The fields as a dict, by attribute name (records inside stay
        records; arrays stay arrays).
        """

@final
class LogRun:
    """A real log's navigation (``navigate_log``): the solution at the antenna in
    local terms at every IMU sample from the start, the filter's own solution
    at the IMU, the start, the GNSS epochs, outages, standstills and range
    biases, and the scoring against a truth."""

    @property
    def time(self) -> npt.NDArray[np.float64]:
        """Times, s (GNSS time), (N,)."""

    @property
    def position_ecef(self) -> npt.NDArray[np.float64]:
        """Antenna position, ECEF m, (N, 3)."""

    @property
    def geodetic(self) -> npt.NDArray[np.float64]:
        """Antenna latitude, longitude (rad), ellipsoidal height (m), (N, 3)."""

    @property
    def velocity_ned(self) -> npt.NDArray[np.float64]:
        """Velocity (of the IMU) north, east, down, m/s, (N, 3)."""

    @property
    def euler(self) -> npt.NDArray[np.float64]:
        """Roll, pitch, yaw of the body relative to local NED, rad, (N, 3)."""

    @property
    def position_std_ned(self) -> npt.NDArray[np.float64]:
        """One-sigma position north, east, down, m, (N, 3)."""

    @property
    def velocity_std_ned(self) -> npt.NDArray[np.float64]:
        """One-sigma velocity north, east, down, m/s, (N, 3)."""

    @property
    def attitude_std_ned(self) -> npt.NDArray[np.float64]:
        """One-sigma attitude about north, east, down, rad, (N, 3)."""

    @property
    def solution(self) -> FilterSolution:
        """The filter's own solution at the IMU (ECEF, covariance, every
        measurement, batch and reset)."""

    @property
    def smoothed(self) -> LogRun | None:
        """The fixed-interval smoothed run (``[filter] smoother = true``): the same
        views of the smoothed solution; None without."""

    @property
    def start(self) -> RunStart:
        """How the run started: a `RunStart` (its kind and time, the log's
        first IMU sample and GNSS epoch, the earliest start the log allows
        and why it started late if it did, the IMU sample it starts at, the
        filter's `initial_state` there and its one-sigmas).
        """

    @property
    def gnss(self) -> dict[str, npt.NDArray[Any]]:
        """Every GNSS epoch's antenna position and velocity (the fixes, or the
        single-point solution of the pseudoranges; NaN where none) and
        whether it reached the filter: dict `time`, `position_ecef`,
        `velocity_ecef`, `used`.
        """

    @property
    def outages(self) -> npt.NDArray[np.float64]:
        """The outage windows, absolute (start, end) times, s, (K, 2) (as
        configured: s after ``start.earliest_time``).
        """

    @property
    def standstills(self) -> npt.NDArray[np.float64]:
        """The detected standstills, (start, end) times, s, (M, 2)."""

    @property
    def range_biases(self) -> dict[int, float]:
        """The satellites holding range-bias states at the end: {prn: bias m}."""

    @property
    def failure(self) -> RunFailure | None:
        """Why the run stopped before the end of the log, when it did (the
        filter's error, or a state beyond what a solution holds: height
        outside -10 km to 10 000 km, speed above 10 km/s, a σ above 10 000 km):
        a `RunFailure` (``time``, GNSS time, s, and ``message``). The solution
        ends at the last sample before it and has no smoothed run;
        ``navigate_log`` also warns. None for a run to the end.
        """

    @property
    def gyro_scale(self) -> GyroScaleCheck | None:
        """The gyro's turns against the GNSS course's over the whole log: a
        `GyroScaleCheck` (its ratio, whether it is conclusive, the unit
        warning). None without a usable pair of GNSS epochs.
        """

    @property
    def carrier_phase(self) -> CarrierPhaseUse | None:
        """The run's carrier changes between epochs by fate: a
        `CarrierPhaseUse`. None when the run did not use carrier phase.
        """

    @property
    def adaptation(self) -> dict[str, Any]:
        """What the run learnt from the log before the run it reports
        (docs/results/foreign-drive.md): dict `imu_preset` (the IMU model chosen,
        None when the configuration names one), `imu_candidates` (a list of
        dicts `preset`, `log_likelihood`, `measurements`, `resets`: each
        candidate's first pass), `nhc_std_m_s` (the non-holonomic
        constraint's std chosen, m/s, None when configured) and
        `nhc_candidates` (dicts `std_m_s`, `log_likelihood`,
        `measurements`, `resets`), `fix_correlation` (None, or dict
        `component_s` (three correlation times, s, None where not
        determined), `innovation_to_fix_variance` (three ratios),
        `correlation_time_s` (0: white), `variance_ratio`), and
        `fix_error_std_m` and `fix_error_correlation_time_s` (the fix-error
        states learnt from it; None when the fixes stay white).
        """

    def score(
        self,
        time: npt.ArrayLike,
        position_ecef: npt.ArrayLike,
        *,
        remove_mean_offset: bool = False,
    ) -> dict[str, Any]:
        """Errors of the antenna solution against a truth (`time` (T,) s,
        `position_ecef` (T, 3)), interpolated at the truth epochs: dict
        `time`, `error_ned` (T', 3), `std_ned`, `outage` (index or −1),
        `offset_removed_ned` (3,), and statistics `all`, `aided`,
        `in_outages` (every outage epoch), `outages` (list, each also with
        `standstill_s`, the time it spent at a standstill, and
        `at_standstill`, at least half of it), `by_outage_length` ({length s:
        stats} over the outages not at a standstill); each statistic
        `epochs`, `rms_horizontal_m`, `rms_vertical_m`, `max_horizontal_m`,
        `within_3sigma_share` (N, E and D), `within_3sigma_share_horizontal`
        (N and E), `nees_per_dof` (mean (e/σ)² over the epochs and N, E, D). `remove_mean_offset`:
        the precision score,
        the errors less their mean over the aided epochs (a truth with a
        constant unknown offset).
        """

    def score_gnss(
        self,
        time: npt.ArrayLike,
        position_ecef: npt.ArrayLike,
        *,
        tolerance: float | None = None,
        interpolate: bool = False,
        remove_mean_offset: bool = False,
    ) -> dict[str, Any]:
        """Errors of the GNSS epochs' own positions (the fixes for loose
        coupling, the single-point solution for tight) against a truth:
        each paired with the truth epoch within `tolerance` s [0.02], or with
        `interpolate` with the truth interpolated linearly at its time
        between truth epochs at most `score::TRUTH_MAX_GAP_S` (1 s) apart
        (a truth at its own rate). Dict `time`,
        `error_ned`, `stats`, `offset_removed_ned`. `remove_mean_offset`:
        the errors less their mean (precision; the mean is then
        `offset_removed_ned`).
        """

    def calibration_references(
        self,
        time: npt.ArrayLike,
        specific_force: npt.ArrayLike,
        angular_rate: npt.ArrayLike,
        *,
        window_s: float | None = None,
        until_s: float | None = None,
    ) -> dict[str, Any]:
        """The GNSS-derived calibration references of this run's solution (use
        the smoothed run): window means of the measured and the reference
        specific force and angular rate in the sensor's axes
        (`memsnav_core::navigate::references`). `time`, `specific_force`,
        `angular_rate`: the arrays given to `navigate_log`; `window_s` the
        window length, s [1]; `until_s` only windows ending that long after the
        start. Dict `time`, `measured_specific_force`, `measured_angular_rate`,
        `reference_specific_force`, `reference_angular_rate` ((W, 3), SI),
        `window_s`, `skipped_for_resets`, `skipped_before_heading`, `accel_bias_covariance`,
        `gyro_bias_covariance`,
        `accel_scale_factor_covariance`, `gyro_scale_factor_covariance` ((3, 3),
        the solution's own uncertainty of them in sensor axes; zero scale
        factors without their states).
        """

    def write(
        self,
        path: str | os.PathLike[str],
        format: str | None = None,
        *,
        rate_hz: float | None = None,
        name: str | None = None,
        overwrite: bool = False,
    ) -> None:
        """Writes the solution at the antenna to `path` in `format`: "csv" (`columns()`,
        every sample), "pos" (RTKLIB, GPST; `read_pos` reads it), "kml" (KML
        2.2: the track as a LineString, start and end placemarks), "gpx" (GPX
        1.1: trk/trkseg/trkpt, times in UTC) or "geojson" (RFC 7946: a
        LineString Feature of [lon, lat, h] with the times as properties);
        None: from the extension (.csv, .pos, .kml, .gpx, .geojson or .json).
        Heights are ellipsoidal (WGS 84); UTC is GPS time less the leap
        seconds (18 s since 2017). `rate_hz`: the rows' rate (the first sample
        of each interval); None: every sample for "csv", 10 Hz for the others
        (a rate at or above the sample rate keeps every sample). `name` titles
        a map track (default the file's stem). The file is written whole or
        not at all; its folder must exist (`OSError` naming it). An existing
        file is replaced only when memsnav wrote it (a solution file of any of
        these formats) or with `overwrite=True`, a folder never (`ValueError`);
        an unknown format is a `ValueError` naming `format` and the accepted
        names.
        """

    def columns(self, rate_hz: float | None = None) -> dict[str, npt.NDArray[np.float64]]:
        """The solution at the antenna as columns named with their units, (N,) each:
        `gps_time_s`, `lat_deg`, `lon_deg`, `height_m` (ellipsoidal), `vn_m_s`,
        `ve_m_s`, `vd_m_s`, `roll_deg`, `pitch_deg`, `yaw_deg`, `sdn_m`, `sde_m`,
        `sdd_m`, `sdvn_m_s`, `sdve_m_s`, `sdvd_m_s` (one-sigma, local
        north/east/down); `rate_hz` thins as in `write` (None: every sample).
        """

    def to_pandas(self, rate_hz: float | None = None) -> Any:
        """`columns(rate_hz)` as a pandas `DataFrame`; `ImportError` saying what
        to install when pandas is not installed.
        """

    def to_polars(self, rate_hz: float | None = None) -> Any:
        """`columns(rate_hz)` as a polars `DataFrame`; `ImportError` saying what
        to install when polars is not installed.
        """

    def __len__(self) -> int: ...

def navigate_log(
    time: npt.ArrayLike,
    specific_force: npt.ArrayLike,
    angular_rate: npt.ArrayLike,
    gnss: GnssMeasurements | PositionFixes | FixSeries | Any,
    *,
    settings: dict[str, dict[str, Any]] | None = None,
    duration_s: float | None = None,
) -> LogRun:
    """Navigates a real log: `time` (N,) IMU time stamps on GNSS time, s;
    `specific_force`, `angular_rate` (N, 3) in the sensor's axes, SI; `gnss`
    the GNSS measurements (`GnssMeasurements` or its padded arrays: tight
    coupling) or position fixes (`PositionFixes`, `FixSeries` or a dict of
    arrays: loose coupling). `settings`: `{table: {key: value}}` as in a
    `navigate` configuration (`navigate_settings()` lists them; left-out
    keys keep the engine's defaults). `duration_s` stops that long after
    the start.
    """

# --- real logs: readers, writers and time alignment (memsnav_core::logs, ::timing) ---

@final
class ImuLog:
    """IMU samples read from a CSV log, SI units, sensor axes."""

    @property
    def time(self) -> npt.NDArray[np.float64]:
        """The log's own clock, s, ``(N,)``."""

    @property
    def specific_force(self) -> npt.NDArray[np.float64]:
        """Specific force, m/s², ``(N, 3)``."""

    @property
    def angular_rate(self) -> npt.NDArray[np.float64]:
        """Angular rate, rad/s, ``(N, 3)``."""

    @property
    def line_time(self) -> npt.NDArray[np.float64]:
        """The time stamp written on each sample's line, s, ``(N,)``: ``time``
        for rates, the end of the interval for increments.
        """

    @property
    def timing(self) -> dict[str, float]:
        """The sampling of the lines: ``median_interval_s``,
        ``interval_std_s`` (jitter, gaps left out), ``min_interval_s``,
        ``max_interval_s``, ``gap_threshold_s``, ``gap_count``,
        ``largest_gap_s``, ``largest_gap_line``.
        """

    @property
    def line(self) -> npt.NDArray[np.int64]:
        """The 1-based line of each sample, ``(N,)``."""

    @property
    def line_end_offset(self) -> npt.NDArray[np.int64]:
        """Byte offset of each sample line's newline, ``(N,)``."""

    @property
    def file_bytes(self) -> int:
        """Size of the file, bytes."""

    @property
    def newline_count(self) -> int:
        """Newline characters in the file."""

    @property
    def warnings(self) -> list[str]:
        """Lines skipped and implausible contents, one sentence each."""

    def __len__(self) -> int: ...

def read_imu_csv(
    path: str | os.PathLike[str],
    columns: Sequence[str] | Mapping[str, str | int],
    accel_unit: str,
    gyro_unit: str,
    time_unit: str,
    skip_first_line: bool,
    header_lines: int,
    axes: str | npt.ArrayLike,
) -> ImuLog:
    """Reads an IMU CSV log with a declared layout (see ``memsnav.read_imu_csv``)."""

@final
class TimeTag:
    """An RTKLIB time-tag file."""

    @property
    def start_gps_time(self) -> float:
        """GPS time of the log's opening, s since 1980-01-06."""

    @property
    def start_tick_ms(self) -> int:
        """The logger's absolute tick at the opening, ms."""

    @property
    def tick_ms(self) -> npt.NDArray[np.float64]:
        """Per write: ms since the opening, ``(M,)``."""

    @property
    def file_offset(self) -> npt.NDArray[np.int64]:
        """Per write: size of the log after it, bytes, ``(M,)``."""

    @property
    def warnings(self) -> list[str]:
        """A cut last record, one sentence."""

    def arrival_gps_time(self, byte_offset: npt.ArrayLike) -> npt.NDArray[np.float64]:
        """GPS time (s since 1980-01-06) at which the write holding each byte
        of the log (counted as the logger counted them) began; NaN past the
        last tagged write or for a negative offset.
        """

    def __len__(self) -> int: ...

def read_time_tag(path: str | os.PathLike[str]) -> TimeTag:
    """Reads an RTKLIB ``.tag`` file (see ``memsnav.read_time_tag``)."""

@final
class TagClock:
    """The GPS times of a log's samples from its time tag, and how they were found."""

    @property
    def gps_time(self) -> npt.NDArray[np.float64]:
        """GPS time of every sample, s since 1980-01-06, ``(N,)``."""

    @property
    def offset_s(self) -> float:
        """GPS time minus IMU time at the first sample, s."""

    @property
    def rate_ppm(self) -> float:
        """Rate of the mapped time against the IMU clock, minus one, ppm."""

    @property
    def arrival_lag_spread_s(self) -> float:
        """Largest arrival lag above the fitted line, s (the logger's buffering)."""

    @property
    def line_ends(self) -> str:
        """How the tag counted line ends: ``"as_in_file"`` or ``"crlf_counted"``."""

    @property
    def tagged_samples(self) -> int:
        """Samples inside the tagged part of the log."""

    @property
    def warnings(self) -> list[str]:
        """Implausible results, one sentence each."""

def fit_tag_clock(imu: ImuLog, tag: TimeTag, line_ends: str | None) -> TagClock:
    """Maps the IMU clock of ``imu`` to GPS time with its time tag (see
    ``memsnav.fit_tag_clock``).
    """

@final
class PosSolution:
    """A GNSS solution in geodetic form (RTKLIB ``.pos``, fixes CSV, NMEA)."""

    @property
    def gps_time(self) -> npt.NDArray[np.float64]:
        """Epochs, GPS s since 1980-01-06, ``(N,)``."""

    @property
    def lla(self) -> npt.NDArray[np.float64]:
        """[latitude rad, longitude rad, ellipsoidal height m], ``(N, 3)``."""

    @property
    def quality(self) -> npt.NDArray[np.int64]:
        """RTKLIB's Q (1 fix, 2 float, 5 single, ...), ``(N,)``."""

    @property
    def n_satellites(self) -> npt.NDArray[np.int64]:
        """Satellites used, ``(N,)``."""

    @property
    def std_ned(self) -> npt.NDArray[np.float64]:
        """One-sigma position uncertainty N, E, D, m, ``(N, 3)``; NaN when the
        file gives none (a fixes CSV truth).
        """

    @property
    def velocity_ned(self) -> npt.NDArray[np.float64]:
        """NED velocity, m/s, ``(N, 3)``; NaN when the file has none."""

    @property
    def velocity_std_ned(self) -> npt.NDArray[np.float64]:
        """One-sigma velocity uncertainty N, E, D, m/s, ``(N, 3)``; NaN likewise."""

    @property
    def covariance_ned(self) -> npt.NDArray[np.float64]:
        """Position covariance N, E, D, m², ``(N, 3, 3)``: the file's full one,
        else diag(std²).
        """

    @property
    def velocity_covariance_ned(self) -> npt.NDArray[np.float64]:
        """Velocity covariance N, E, D, (m/s)², ``(N, 3, 3)``: the file's full
        one, else diag(std²); NaN where the std is.
        """

    @property
    def attitude(self) -> npt.NDArray[np.float64] | None:
        """The attitude C_b^n (body to local NED) of every epoch, ``(N, 3,
        3)``, when the file gives one (a fixes CSV's quaternion or Euler
        columns), else None.
        """

    @property
    def has_full_covariance(self) -> bool:
        """Whether the file gives full position covariances (not only stds)."""

    @property
    def warnings(self) -> list[str]:
        """Lines skipped, one sentence each."""

    def __len__(self) -> int: ...

def read_pos(path: str | os.PathLike[str]) -> PosSolution:
    """Reads an RTKLIB ``.pos`` file (see ``memsnav.read_pos``)."""

def decimate(time: npt.ArrayLike, rate_hz: float | None = None) -> npt.NDArray[np.uintp]:
    """The indices of the samples kept at ``rate_hz`` (the first of each
    1/``rate_hz`` interval from the first sample; None: every one), as the
    solution writers thin a solution."""

def read_fixes_csv(
    path: str | os.PathLike[str],
    columns: dict[str, str] | None = None,
    time_reference: str | None = None,
) -> PosSolution:
    """Reads a fixes CSV (see ``memsnav.read_fixes_csv``): ``columns`` a dict
    from memsnav's column names to the file's header names (None: the
    header names memsnav's), ``time_reference`` what the time column
    counts (None: ``"column_gps"``).
    """

#: Seconds from 1970-01-01 to the GPS epoch 1980-01-06: GPS time counted
#: from 1970 without leap seconds is GPS time plus this.
UNIX_TO_GPS_S: float

def read_nmea(path: str | os.PathLike[str]) -> PosSolution:
    """Reads an NMEA 0183 log (see ``memsnav.read_nmea``)."""

def write_pos(
    path: str | os.PathLike[str],
    gps_time: npt.ArrayLike,
    lla: npt.ArrayLike,
    std_ned: npt.ArrayLike,
    velocity_ned: npt.ArrayLike,
    velocity_std_ned: npt.ArrayLike,
    quality: int,
    n_satellites: npt.ArrayLike,
    program: str,
) -> None:
    """Writes an RTKLIB-compatible ``.pos`` (see ``memsnav.realdata.readers.write_pos``)."""

@final
class LagEstimate:
    """A lag found by a search: the best lag, its score and spread, the curve."""

    @property
    def lag_s(self) -> float:
        """The refined best lag, s."""

    @property
    def score(self) -> float:
        """The score there: the correlation, or the RMS difference."""

    @property
    def curvature(self) -> float:
        """Second derivative of the correlation (or mean square) at the best lag, per s²."""

    @property
    def std_s(self) -> float:
        """Standard error of the lag from its spread over the blocks, s."""

    @property
    def block_lag_s(self) -> npt.NDArray[np.float64]:
        """Best lag of each consecutive block of the data, s."""

    @property
    def curve_lag_s(self) -> npt.NDArray[np.float64]:
        """The searched lags, s."""

    @property
    def curve_score(self) -> npt.NDArray[np.float64]:
        """The score at each searched lag."""

    @property
    def samples(self) -> int:
        """Epochs that entered the score."""

def estimate_time_offset(
    imu_time: npt.ArrayLike,
    specific_force: npt.ArrayLike,
    angular_rate: npt.ArrayLike,
    gnss_time: npt.ArrayLike,
    lla: npt.ArrayLike,
    signal: str,
    max_offset_s: float,
    step_s: float,
    min_speed_m_s: float,
    blocks: int,
) -> LagEstimate:
    """The offset to add to IMU times that aligns them with GNSS positions
    (see ``memsnav.estimate_time_offset``).
    """

def estimate_velocity_latency(
    gnss_time: npt.ArrayLike,
    lla: npt.ArrayLike,
    velocity_ned: npt.ArrayLike,
    max_latency_s: float,
    step_s: float,
    blocks: int,
) -> LagEstimate:
    """The latency of a GNSS solution's velocity behind its positions (see
    ``memsnav.estimate_velocity_latency``).
    """

def _panic_for_test(message: str) -> None:
    """Test hook: panics with `message`, so the tests can show that a panic
    reaches Python as a `MemsnavError` (no public function is known to
    panic).
    """

@final
class GnssLoggerLog:
    """What an Android GnssLogger file holds (``read_gnsslogger``)."""

    @property
    def observations(self) -> RinexObservations:
        """The ``Raw`` records as observations (the class ``read_rinex_obs``
        returns): per signal ``C`` pseudorange m, ``L`` carrier cycles
        (valid accumulated delta range only), ``D`` Doppler Hz, ``S`` C/N0
        dB-Hz, RINEX 3 codes (``C1C``, ``C5Q``, ...), epochs on GPS time.
        """
    @property
    def imu(self) -> ImuLog | None:
        """``UncalAccel`` with ``UncalGyro`` interpolated to its times, on GPS
        time, Android sensor axes (x right, y up, z out of the screen), the
        phone's bias estimates not applied; None without both sensors or
        without a ``Raw`` record tying their clock to GPS time.
        """
    @property
    def skipped(self) -> dict[str, int]:
        """``Raw`` measurements left out, counted by reason (no code lock, time
        of week not decoded, SBAS, ...).
        """
    @property
    def warnings(self) -> list[str]:
        """Non-fatal problems met while reading."""

def read_gnsslogger(path: str | os.PathLike[str]) -> GnssLoggerLog:
    """Reads an Android GnssLogger file (``gnss_log_*.txt``): pseudoranges
    from the ``Raw`` records' clock and satellite times per constellation
    (GPS, Galileo, BeiDou weeks, the GLONASS day), only where the
    measurement ``State`` makes them unambiguous (the rest counted in
    ``skipped``); errors name the file and the line.

    `path`: the file to read (str or path-like).
    """

def closest_name(key: str, known: list[str]) -> str | None:
    """The name of `known` that `key` is probably a misspelling of (the core's
    `known_keys::closest`: the one rule of every "did you mean"), or None.
    """

@final
class UbxLog:
    """What a u-blox UBX log holds (``read_ubx``)."""

    @property
    def broadcast_ephemerides(self) -> BroadcastEphemerides:
        """Every decoded ephemeris (GPS LNAV and CNAV, Galileo, BeiDou) as one
        set, for ``observations.measurements``."""

    @property
    def observations(self) -> RinexObservations:
        """RXM-RAWX as observations (the class ``read_rinex_obs`` returns):
        per signal ``C`` pseudorange m (``prValid`` only), ``L`` carrier
        cycles (``cpValid`` only), ``D`` Doppler Hz, ``S`` C/N0 dB-Hz, RINEX
        3 codes (``C1C``, ``C2L``, ``C5Q``, ``C6B``, ...), epochs on the
        receiver's GPS time; the approximate position is the first NAV-PVT fix.
        """
    @property
    def constellation(self) -> Constellation:
        """The GPS satellites of the decoded LNAV ephemerides, for
        ``observations.gps_l1`` and ``solve_fix``.
        """
    @property
    def ephemerides(self) -> list[dict[str, Any]]:
        """The GPS LNAV ephemerides decoded from RXM-SFRBX, one dict each with
        the RINEX navigation record's fields (SI units, angles rad, times
        GPS s since 1980-01-06) and the message's flags.
        """
    @property
    def gps_cnav_ephemerides(self) -> list[dict[str, Any]]:
        """The GPS CNAV ephemerides decoded from RXM-SFRBX (L2C or L5, CRC
        checked), one dict each with the orbit and clock under the RINEX
        record's names (SI units, angles rad, times GPS s since 1980-01-06;
        ``sqrt_a`` is √(A_REF + ΔA), ``omega_dot`` Ω̇_REF + ΔΩ̇), CNAV's
        rates ``a_dot`` m/s and ``delta_n_dot`` rad/s², the health bits
        ``l1_health``, ``l2_health``, ``l5_health``, the accuracy indices
        ``ura_ed_index`` (and its nominal ``ura_ed_m``, NaN for none),
        ``ura_ned0_index``, ``ura_ned1_index``, ``ura_ned2_index``, ``top``,
        ``week`` (13 bits), ``integrity_status_flag``, ``l2c_phasing``, and
        type 30's ``tgd``, ``isc_l1ca``, ``isc_l2c``, ``isc_l5i5``,
        ``isc_l5q5`` s (None when not available). The clock is referred to
        L1/L2 P(Y) ionosphere-free, as LNAV's; a signal's user subtracts
        T_GD − ISC.
        """
    @property
    def klobuchar(self) -> tuple[list[float], list[float]] | None:
        """The Klobuchar coefficients ``(alpha, beta)`` of the latest GPS CNAV
        message type 30 (s, s/semicircleⁿ), or None when the log has none;
        what ``klobuchar=`` of the fix and the observables takes.
        """
    @property
    def galileo_ephemerides(self) -> list[dict[str, Any]]:
        """The Galileo I/NAV ephemerides decoded from RXM-SFRBX (E1-B), one
        dict each with the RINEX navigation record's fields (SI units,
        angles rad, times GPS s since 1980-01-06) and the health, data
        validity and accuracy (SISA) flags.
        """
    @property
    def beidou_ephemerides(self) -> list[dict[str, Any]]:
        """The BeiDou D1 ephemerides (MEO and IGSO satellites) decoded from
        RXM-SFRBX, one dict each with the RINEX navigation record's fields
        (SI units, angles rad, times GPS s since 1980-01-06: BDT + 14 s),
        the group delays ``tgd1`` (B1I) and ``tgd2`` (B2I) to B3I, the clock's
        reference, and the health (SatH1) and accuracy (URAI) flags.
        """
    @property
    def glonass_ephemerides(self) -> list[dict[str, Any]]:
        """The GLONASS ephemerides decoded from RXM-SFRBX (L1OF/L2OF strings
        1-4, Hamming checked), one dict each: ``sat`` (``"R05"``),
        ``slot``, ``frequency_channel`` k, ``tb`` (GPS s), ``tau_n`` (s),
        ``gamma_n``, ``position``, ``velocity`` and ``lunisolar_acceleration``
        (PZ-90 at t_b, m, m/s, m/s²), ``health`` (RINEX's), ``age_days``,
        ``healthy``.
        """
    @property
    def rawx(self) -> dict[str, Any]:
        """RXM-RAWX as the receiver reports it, one row per epoch and signal:
        ``epoch`` (index into ``epoch_gps_time``), ``sat`` ("G10"),
        ``code`` (RINEX band and attribute), ``gnss_id``, ``sv_id``,
        ``sig_id``, ``pseudorange`` m, ``carrier_phase`` cycles, ``doppler``
        Hz, ``cn0`` dB-Hz, ``lock_time`` s, the receiver's σ
        (``pseudorange_std`` m, ``carrier_phase_std`` cycles,
        ``doppler_std`` Hz), the tracking flags (``pseudorange_valid``,
        ``carrier_phase_valid``, ``half_cycle_resolved``,
        ``half_cycle_subtracted``); per epoch ``epoch_gps_time``,
        ``receiver_tow`` s, ``week``, ``leap_seconds`` (-1: not known yet),
        ``clock_reset``.
        """
    @property
    def nav_pvt(self) -> dict[str, npt.NDArray[Any]]:
        """Every NAV-PVT solution, fix or not, as arrays: ``gps_time`` s,
        ``lla`` (N, 3) rad, rad, m ellipsoidal, ``height_msl`` m,
        ``velocity_ned`` (N, 3) m/s, ``horizontal_accuracy``,
        ``vertical_accuracy`` m, ``speed_accuracy`` m/s, ``fix_type``,
        ``fix_ok``, ``carrier_solution`` (0 none, 1 float, 2 fixed),
        ``n_satellites``, ``quality`` (RTKLIB's Q).
        """
    @property
    def fixes(self) -> PosSolution:
        """The NAV-PVT position fixes as the other fix readers give them
        (σ north and east hAcc/√2, down vAcc; velocity σ sAcc per axis).
        """
    @property
    def messages(self) -> dict[str, int]:
        """Messages read, by name (``RXM-RAWX``, ``NAV-PVT``, ``RXM-SFRBX``,
        ``0xCC-0xII`` for the others).
        """
    @property
    def skipped(self) -> dict[str, int]:
        """What was left out, by reason, with counts."""
    @property
    def warnings(self) -> list[str]:
        """Non-fatal problems met while reading."""
    def write_rinex_obs(self, path: str | os.PathLike[str]) -> None:
        """Writes the observations as a RINEX 3.04 observation file at ``path``."""
    def write_rinex_nav(
        self, path: str | os.PathLike[str], rinex_version: str | None = None
    ) -> None:
        """Writes the decoded ephemerides as a RINEX navigation file at
        ``path``: RINEX 4.00 by default (GPS LNAV and CNAV, Galileo I/NAV,
        BeiDou D1 records), or ``rinex_version="3.04"``, which has no CNAV
        record (the CNAV ephemerides are then not written). The file is
        written once memsnav's reader reads every record back.
        """

def read_ubx(path: str | os.PathLike[str]) -> UbxLog:
    """Reads a u-blox UBX log: RXM-RAWX, GPS LNAV (parity checked), GPS
    CNAV and Galileo I/NAV (CRC checked) and BeiDou D1 (BCH checked)
    ephemerides and the CNAV Klobuchar from RXM-SFRBX, NAV-PVT; frames
    with a bad checksum, a cut last frame and messages not decoded are
    skipped and counted; a file without a UBX
    frame is a ParseError naming it.

    `path`: the file to read (str or path-like).
    """
