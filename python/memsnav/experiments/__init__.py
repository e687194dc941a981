"""The paper's experiments (de Boer et al., ION GNSS 2008, §5).

``calibration`` reproduces figures 3-10 (MSE of every calibrated parameter
over random parameter sets, with the Cramér-Rao bound) and ``inversion``
figures 11-12 (MSE of the specific force and angular rate recovered by the
inversion filters), ``navigation`` figures 14-18 (position error of the
tightly coupled GNSS/INS filter with INS, raw and calibrated MEMS);
``partial_outage`` and ``outage_study`` go beyond the paper (which IMU
grade is good enough through which outage). Each runs a whole Monte Carlo
set in Rust, on local threads or, given ``client=``, on a Dask cluster.
"""

from memsnav.experiments.calibration import (
    CalibrationResult,
    calibration,
    land_vehicle_motion,
)
from memsnav.experiments.inversion import InversionResult, inversion
from memsnav.experiments.navigation import NavigationResult, navigation
from memsnav.experiments.outage_study import OutageStudyResult, outage_study
from memsnav.experiments.partial_outage import PartialOutageResult, partial_outage

__all__ = [
    "CalibrationResult",
    "InversionResult",
    "NavigationResult",
    "OutageStudyResult",
    "PartialOutageResult",
    "calibration",
    "inversion",
    "land_vehicle_motion",
    "navigation",
    "outage_study",
    "partial_outage",
]
