"""``memsnav simulate``: a trajectory, the IMU's outputs along it and the GNSS
measurements, written as CSV files a user can feed to any tool."""

from __future__ import annotations

import io
import json
from collections.abc import Sequence
from dataclasses import dataclass
from pathlib import Path

import numpy as np
import numpy.typing as npt

import memsnav as mn
from memsnav._files import output_folder, write_text

_DRAWS = ("trajectory", "imu errors", "imu noise", "gnss")
"""The independent draws of a simulation, each seeded by ``derive_seed``."""


@dataclass(frozen=True)
class SimulationFiles:
    """Paths of the files :func:`simulate` wrote."""

    trajectory: Path
    imu: Path
    imu_truth: Path
    gnss: Path
    metadata: Path


#: The digits of a GPS time column: 1e-9 s of a time of 1e9 s.
_TIME_FORMAT = "%.19g"
#: RTKLIB's best quality (Q = 1, fix) for the exact simulated positions, so
#: that ``[truth] pos`` takes them with its default qualities.
_TRUTH_QUALITY = 1


def _csv(
    header: Sequence[str], columns: Sequence[npt.ArrayLike], fmt: str | Sequence[str] = "%.10g"
) -> str:
    table = np.column_stack([np.asarray(c, dtype=float) for c in columns])
    out = io.StringIO()
    np.savetxt(out, table, delimiter=",", header=",".join(header), comments="", fmt=fmt)
    return out.getvalue()


def simulate(
    out: str | Path = "simulation",
    *,
    duration: float = 600.0,
    rate: float = 100.0,
    imu: str = "paper-mems",
    seed: int = 0,
    n_satellites: int = 6,
    gnss_rate: float = 1.0,
    constellation: str | Path = "walker",
    outages: Sequence[tuple[float, float]] = (),
    systems: Sequence[str] = ("G",),
    inter_system_bias: Sequence[float] = (0.0, 0.0),
    carrier_phase_std: float = 0.0,
    cycle_slip_probability: float = 0.0,
) -> SimulationFiles:
    """Simulates a random land-vehicle trajectory (``duration`` s at ``rate``
    Hz), the outputs of the IMU preset ``imu`` along it, and GNSS
    pseudoranges and rates of ``n_satellites`` satellites at ``gnss_rate`` Hz
    from ``constellation`` ("walker" for the nominal Walker constellations
    of ``systems``: "G" GPS, "E" Galileo, "C" BeiDou MEO, "R" GLONASS, 24 satellites
    each, see :meth:`memsnav.Constellation.nominal`; or the path of a RINEX
    navigation file, GPS only), with total outages ``[(start_s, length_s),
    ...]``. The Galileo, BeiDou and GLONASS pseudoranges carry
    ``inter_system_bias`` (m, against GPS; two values leave GLONASS's 0).
    With ``carrier_phase_std`` (m; 0: none) the receiver also measures
    carrier phase, which slips silently with
    ``cycle_slip_probability`` per satellite and epoch
    (:func:`memsnav.simulate_gnss`). Writes into ``out``:

    - ``trajectory.csv``: the truth, in the fixes CSV's names (so that
      ``[truth] pos`` and ``memsnav.read_fixes_csv`` read it as it is; with
      added noise ``[gnss] pos`` too): ``gps_time_s``, the ECEF position
      ``x_ecef_m, y_ecef_m, z_ecef_m``, the NED velocity ``vn_m_s, ve_m_s,
      vd_m_s``, the attitude ``roll_deg, pitch_deg, yaw_deg`` (body to NED)
      and ``quality`` 1 (exact);
    - ``imu.csv``: time s, GPS time s, accelerometer m/s², gyroscope rad/s
      (body axes);
    - ``imu_truth.csv``: the same columns without the IMU's errors (the true
      specific force and angular rate);
    - ``gnss.csv``: one row per satellite per epoch: time s, GPS time s,
      satellite id (its system too: G n → n, E n → 100 + n, C n → 200 + n),
      satellite ECEF position m and velocity m/s at transmission,
      pseudorange m, pseudorange rate m/s; with carrier phase also the
      carrier range m, its one-sigma m and the loss-of-lock flag (1, 0);
    - ``simulation.json``: the parameters, the IMU's drawn errors and seeds,
      and the injected cycle slips (time s, satellite id, L1 cycles).

    Every draw comes from ``seed``, each from its own seed
    ``memsnav.derive_seed(seed, name)`` with the names ``"trajectory"``,
    ``"imu errors"``, ``"imu noise"`` and ``"gnss"`` (recorded in
    ``simulation.json``): independent draws, none shared with another
    ``seed``.
    """
    directory = output_folder(out)
    if isinstance(constellation, str) and constellation == "walker":
        sky = mn.Constellation.nominal(list(systems))
    elif list(systems) != ["G"]:
        raise ValueError(
            f"systems: a RINEX navigation file gives GPS satellites only, got {list(systems)}"
        )
    else:
        sky = mn.Constellation.from_rinex_nav(constellation)
    seeds = {name: mn.derive_seed(seed, name) for name in _DRAWS}
    trajectory = mn.Trajectory.random(duration=duration, rate=rate, seed=seeds["trajectory"])
    model = mn.ImuModel.preset(imu, seed=seeds["imu errors"], sample_rate=rate)
    accel, gyro = model.measure(
        trajectory.specific_force, trajectory.angular_rate, seed=seeds["imu noise"]
    )
    gnss = mn.simulate_gnss(
        trajectory.time,
        trajectory.position_ecef,
        trajectory.velocity_ecef,
        sky,
        rate=gnss_rate,
        n_satellites=n_satellites,
        outages=[(float(s), float(length)) for s, length in outages],
        seed=seeds["gnss"],
        inter_system_bias=inter_system_bias,
        carrier_phase_std=carrier_phase_std,
        cycle_slip_probability=cycle_slip_probability,
    )

    files = SimulationFiles(
        directory / "trajectory.csv",
        directory / "imu.csv",
        directory / "imu_truth.csv",
        directory / "gnss.csv",
        directory / "simulation.json",
    )
    # The samples on GPS time as the GNSS epochs are (gnss.csv's gps_time_s
    # against its time_s), so that navigate pairs them.
    gps_time = trajectory.time + (float(gnss.gps_time[0]) - float(gnss.time[0]))
    xyz = ("x", "y", "z")
    write_text(
        files.trajectory,
        _csv(
            [
                "gps_time_s",
                *("x_ecef_m", "y_ecef_m", "z_ecef_m"),
                *("vn_m_s", "ve_m_s", "vd_m_s"),
                *("roll_deg", "pitch_deg", "yaw_deg"),
                "quality",
            ],
            [
                gps_time,
                *trajectory.position_ecef.T,
                *trajectory.velocity_ned().T,
                *np.degrees(trajectory.euler_ned()).T,
                np.full(len(gps_time), _TRUTH_QUALITY),
            ],
            fmt=[_TIME_FORMAT] + ["%.12g"] * 9 + ["%d"],
        ),
    )
    imu_header = (
        ["time_s", "gps_time_s"]
        + [f"accel_{a}_m_s2" for a in xyz]
        + [f"gyro_{a}_rad_s" for a in xyz]
    )
    imu_format = ["%.10g", _TIME_FORMAT] + ["%.10g"] * 6
    write_text(
        files.imu,
        _csv(imu_header, [trajectory.time, gps_time, *accel.T, *gyro.T], fmt=imu_format),
    )
    write_text(
        files.imu_truth,
        _csv(
            imu_header,
            [
                trajectory.time,
                gps_time,
                *trajectory.specific_force.T,
                *trajectory.angular_rate.T,
            ],
            fmt=imu_format,
        ),
    )
    tracked = gnss.sat_id >= 0
    epoch, slot = np.nonzero(tracked)
    carrier_header, carrier_columns = [], []
    if carrier_phase_std > 0:
        carrier_header = ["carrier_phase_m", "carrier_phase_std_m", "loss_of_lock"]
        carrier_columns = [
            gnss.carrier_phase[epoch, slot],
            gnss.carrier_phase_std[epoch, slot],
            gnss.loss_of_lock[epoch, slot],
        ]
    write_text(
        files.gnss,
        _csv(
            ["time_s", "gps_time_s", "sat_id"]
            + [f"sat_position_ecef_{a}_m" for a in xyz]
            + [f"sat_velocity_ecef_{a}_m_s" for a in xyz]
            + ["pseudorange_m", "pseudorange_rate_m_s"]
            + carrier_header,
            [
                gnss.time[epoch],
                gnss.gps_time[epoch],
                gnss.sat_id[epoch, slot],
                *gnss.satellite_position_ecef[epoch, slot].T,
                *gnss.satellite_velocity_ecef[epoch, slot].T,
                gnss.pseudorange[epoch, slot],
                gnss.pseudorange_rate[epoch, slot],
                *carrier_columns,
            ],
            fmt="%.12g",
        ),
    )
    slips = gnss.cycle_slips
    metadata = {
        "memsnav_version": mn.__version__,
        "duration_s": duration,
        "start_gps_time_s": float(gps_time[0]),
        "rate_hz": rate,
        "imu": imu,
        "imu_errors": {
            "accelerometer": {
                "bias_m_s2": model.accelerometer.bias.tolist(),
                "scale_factor": model.accelerometer.scale_factor.tolist(),
                "misalignment": model.accelerometer.misalignment.tolist(),
                "nonlinearity_s2_m": model.accelerometer.nonlinearity.tolist(),
            },
            "gyroscope": {
                "bias_rad_s": model.gyroscope.bias.tolist(),
                "scale_factor": model.gyroscope.scale_factor.tolist(),
                "misalignment": model.gyroscope.misalignment.tolist(),
                "g_sensitivity_rad_s_per_m_s2": model.gyroscope.g_sensitivity.tolist(),
            },
            "spec": model.spec,
        },
        "seed": seed,
        "derived_seeds": seeds,
        "n_satellites": n_satellites,
        "gnss_rate_hz": gnss_rate,
        "constellation": str(constellation),
        "systems": list(sky.systems),
        "inter_system_bias_m": [float(b) for b in inter_system_bias],
        "carrier_phase_std_m": carrier_phase_std,
        "cycle_slip_probability": cycle_slip_probability,
        "cycle_slips": [
            {"time_s": float(t), "sat_id": int(s), "cycles": int(c)}
            for t, s, c in zip(slips["time"], slips["sat_id"], slips["cycles"], strict=True)
        ],
        "outages": [list(o) for o in outages],
    }
    write_text(files.metadata, json.dumps(metadata, indent=2) + "\n")
    return files
