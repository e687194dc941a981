"""Type stubs of the native module (checked by ``mypy.stubtest``)."""

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
