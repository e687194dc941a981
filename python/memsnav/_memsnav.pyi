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

# --- GNSS (constellations, SP3, measurement simulation, least-squares fix) ---

@final
class Constellation:
    """GPS satellites from broadcast ephemerides, or a synthetic Walker constellation.

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
        n_satellites: int = 24,
        planes: int = 6,
        inclination_deg: float = 55.0,
        semi_major_axis_m: float = 26560000.0,
        phasing: int = 1,
        raan0_deg: float = 0.0,
    ) -> Constellation:
        """Walker delta constellation i: t/p/f, circular orbits, ECEF with Earth rotation."""

    @property
    def prns(self) -> list[str]:
        """Satellite names, e.g. ["G01", "G02", ...] (Walker slots are named G01..GNN)."""

    def __len__(self) -> int: ...
    def position_velocity(
        self, gps_time: float
    ) -> tuple[npt.NDArray[np.float64], npt.NDArray[np.float64]]:
        """ECEF positions (m) and velocities (m/s), each (n_sat, 3); NaN rows without a
        valid ephemeris (healthy, t_oe within ±2 h)."""

    def clock_correction(self, gps_time: float) -> npt.NDArray[np.float64]:
        """Satellite clock corrections Δt_sv, s, (n_sat,): a_f0 + a_f1 dt + a_f2 dt² +
        relativistic term - T_GD; NaN without a valid ephemeris; zero for Walker."""

@final
class Sp3:
    """Precise orbits from an SP3 file (centre of mass), in SI units."""

    @property
    def time(self) -> npt.NDArray[np.float64]:
        """Epochs, GPS s since 1980-01-06, (n_epochs,)."""

    @property
    def satellites(self) -> list[str]:
        """Satellite names as in the file ("G01", "E05", ...)."""

    @property
    def position_ecef(self) -> npt.NDArray[np.float64]:
        """Positions, ECEF m, (n_epochs, n_sat, 3); NaN where missing."""

    @property
    def clock(self) -> npt.NDArray[np.float64]:
        """Satellite clocks, s, (n_epochs, n_sat); NaN where missing."""

def read_sp3(path: str | os.PathLike[str]) -> Sp3:
    """Reads an SP3-c/d file (GPS time system; km and µs converted to m and s)."""

@final
class GnssMeasurements:
    """Simulated measurements; per-epoch arrays padded to n_max = n_satellites
    (NaN for values, -1 for sat_id, where fewer satellites are tracked)."""

    @property
    def time(self) -> npt.NDArray[np.float64]:
        """Epoch times on the trajectory's time axis, s, (T,)."""

    @property
    def gps_time(self) -> npt.NDArray[np.float64]:
        """Epoch times, GPS s since 1980-01-06, (T,)."""

    @property
    def n_satellites(self) -> npt.NDArray[np.int64]:
        """Satellites tracked per epoch, (T,)."""

    @property
    def sat_id(self) -> npt.NDArray[np.int64]:
        """Satellite ids (PRN numbers), (T, n_max), -1 where padded."""

    @property
    def satellite_position_ecef(self) -> npt.NDArray[np.float64]:
        """Satellite positions at transmission time (ECEF of that time), m, (T, n_max, 3)."""

    @property
    def satellite_velocity_ecef(self) -> npt.NDArray[np.float64]:
        """Satellite velocities at transmission time, m/s, (T, n_max, 3)."""

    @property
    def pseudorange(self) -> npt.NDArray[np.float64]:
        """Pseudoranges (satellite clock corrected), m, (T, n_max)."""

    @property
    def pseudorange_rate(self) -> npt.NDArray[np.float64]:
        """Pseudorange rates, m/s, (T, n_max)."""

    @property
    def pseudorange_std(self) -> npt.NDArray[np.float64]:
        """Pseudorange noise one-sigma, m, (T, n_max)."""

    @property
    def pseudorange_rate_std(self) -> npt.NDArray[np.float64]:
        """Pseudorange-rate noise one-sigma, m/s, (T, n_max)."""

    @property
    def clock_offset(self) -> npt.NDArray[np.float64]:
        """True receiver clock offset, m, (T,)."""

    @property
    def clock_drift(self) -> npt.NDArray[np.float64]:
        """True receiver clock drift, m/s, (T,)."""

    def __len__(self) -> int: ...

def simulate_gnss(
    time: npt.ArrayLike,
    position_ecef: npt.ArrayLike,
    velocity_ecef: npt.ArrayLike,
    constellation: Constellation,
    rate: float = 1.0,
    n_satellites: int = 6,
    elevation_mask_deg: float = 10.0,
    pseudorange_std: float = 3.0,
    pseudorange_rate_std: float = 0.1,
    residual_std: float = 0.0,
    residual_correlation_time: float = 300.0,
    clock_h0: float = 2e-19,
    clock_h_minus2: float = 2e-20,
    clock_initial_offset_std: float = 30.0,
    clock_initial_drift_std: float = 1.0,
    outages: Sequence[tuple[float, float] | tuple[float, float, int]] | None = None,
    seed: int = 0,
    start_gps_time: float | None = None,
) -> GnssMeasurements:
    """Pseudoranges (m) and rates (m/s) along a trajectory (method §5).

    time (N,) s, position_ecef (N, 3) m, velocity_ecef (N, 3) m/s. Epochs at
    ``rate`` Hz fall on the trajectory samples nearest to t0 + k/rate. At the
    first epoch the ``n_satellites`` with the best GDOP above the mask are
    chosen (greedy elimination) and kept while visible; a setting satellite
    is replaced by the one giving the best GDOP. Pseudorange = exact
    light-time range with Earth rotation + receiver clock + optional
    Gauss-Markov residual (residual_std m, residual_correlation_time s) +
    white noise. Clock: two-state, h0 and h_minus2 Allan coefficients (TCXO
    defaults). Outages: (start s, length s) total, or (start, length,
    n_satellites) partial, on the trajectory's time axis. start_gps_time:
    GPS time of time[0] (default: earliest t_oe of a broadcast file, 0 for
    Walker).
    """

@final
class FixSeries:
    """Least-squares fixes per epoch; NaN rows where ``valid`` is False."""

    @property
    def time(self) -> npt.NDArray[np.float64]:
        """Epoch times, s, (T,)."""

    @property
    def valid(self) -> npt.NDArray[np.bool_]:
        """True where the epoch had at least 4 satellites, (T,)."""

    @property
    def position_ecef(self) -> npt.NDArray[np.float64]:
        """ECEF position, m, (T, 3)."""

    @property
    def velocity_ecef(self) -> npt.NDArray[np.float64]:
        """ECEF velocity, m/s, (T, 3)."""

    @property
    def clock_offset(self) -> npt.NDArray[np.float64]:
        """Receiver clock offset, m, (T,)."""

    @property
    def clock_drift(self) -> npt.NDArray[np.float64]:
        """Receiver clock drift, m/s, (T,)."""

    @property
    def position_clock_covariance(self) -> npt.NDArray[np.float64]:
        """Covariance of (x, y, z, clock offset), m², (T, 4, 4)."""

    @property
    def velocity_drift_covariance(self) -> npt.NDArray[np.float64]:
        """Covariance of (vx, vy, vz, clock drift), (m/s)², (T, 4, 4)."""

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

def solve_fix(
    measurements: GnssMeasurements, prior: npt.ArrayLike | None = None, strict: bool = False
) -> FixSeries:
    """Gauss-Newton position/velocity/clock fix of every epoch (Sagnac-corrected
    predicted ranges). prior: (3,) ECEF start for the first epoch (default the
    Earth's centre; later epochs start from the previous fix). Epochs with
    fewer than 4 satellites give NaN rows, or ValueError when strict=True."""
