"""memsnav: MEMS inertial sensors aided by GNSS.

Error models of low-cost accelerometers and gyroscopes, their calibration
and inversion (de Boer et al., ION GNSS 2008), a strapdown INS in ECEF,
GNSS simulation, and tightly/loosely coupled GNSS/INS filters. The
numerics run in Rust (``memsnav._memsnav``); this package drives them.

Conventions: SI units everywhere (m, m/s, m/s², rad, rad/s, s); frames in
names (``position_ecef``); series of vectors are ``(N, 3)`` float arrays.
"""

from memsnav import experiments
from memsnav._memsnav import (
    AccelerometerModel,
    Calibration,
    Constellation,
    DivergenceError,
    FilterSolution,
    FixSeries,
    GnssMeasurements,
    GyroscopeModel,
    ImuModel,
    LooselyCoupledFilter,
    MemsnavError,
    NavSolution,
    ParseError,
    RinexObservations,
    Sp3,
    TightlyCoupledFilter,
    Trajectory,
    UnobservableError,
    __version__,
    calibrate_accelerometer,
    calibrate_gyroscope,
    calibrated_imu,
    derive_seed,
    ecef_to_geodetic,
    geodetic_to_ecef,
    gravity_ecef,
    imu_increments,
    invert_accelerometer,
    invert_gyroscope,
    read_klobuchar,
    read_rinex_obs,
    read_sp3,
    simulate_gnss,
    solve_fix,
    strapdown,
    strapdown_increments,
)
from memsnav.allan import allan_deviation
from memsnav.realdata.config import load_config
from memsnav.realdata.pipeline import NavigationResult, navigate
from memsnav.realdata.readers import read_imu_csv, read_pos, read_time_tag

__all__ = [
    "AccelerometerModel",
    "Calibration",
    "Constellation",
    "DivergenceError",
    "FilterSolution",
    "FixSeries",
    "GnssMeasurements",
    "GyroscopeModel",
    "ImuModel",
    "LooselyCoupledFilter",
    "MemsnavError",
    "NavSolution",
    "NavigationResult",
    "ParseError",
    "RinexObservations",
    "Sp3",
    "TightlyCoupledFilter",
    "Trajectory",
    "UnobservableError",
    "__version__",
    "allan_deviation",
    "calibrate_accelerometer",
    "calibrate_gyroscope",
    "calibrated_imu",
    "derive_seed",
    "ecef_to_geodetic",
    "experiments",
    "geodetic_to_ecef",
    "gravity_ecef",
    "imu_increments",
    "invert_accelerometer",
    "invert_gyroscope",
    "load_config",
    "navigate",
    "read_imu_csv",
    "read_klobuchar",
    "read_pos",
    "read_rinex_obs",
    "read_sp3",
    "read_time_tag",
    "simulate_gnss",
    "solve_fix",
    "strapdown",
    "strapdown_increments",
]
