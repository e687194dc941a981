"""The paper's experiments (de Boer et al., ION GNSS 2008, §5).

``calibration`` reproduces figures 3-10 (MSE of every calibrated parameter
over random parameter sets, with the Cramér-Rao bound) and ``inversion``
figures 11-12 (MSE of the specific force and angular rate recovered by the
inversion filters), ``navigation`` figures 14-18 (position error of the
tightly coupled GNSS/INS filter with INS, raw and calibrated MEMS).
Each runs a whole Monte Carlo set in Rust.
"""

from memsnav.experiments.calibration import (
    CalibrationResult,
    calibration,
    land_vehicle_motion,
)
from memsnav.experiments.inversion import InversionResult, inversion
from memsnav.experiments.navigation import NavigationResult, navigation
from memsnav.experiments.partial_outage import PartialOutageResult, partial_outage

__all__ = [
    "CalibrationResult",
    "InversionResult",
    "NavigationResult",
    "PartialOutageResult",
    "calibration",
    "inversion",
    "land_vehicle_motion",
    "navigation",
    "partial_outage",
]
