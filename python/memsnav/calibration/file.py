"""The calibration file: an IMU's models, their uncertainty and where they
came from, as versioned, human-readable JSON (docs/how-to/calibrate-an-imu.md).

JSON rather than TOML: Python writes and reads it with the standard library
(``tomllib`` only reads TOML), floats round-trip exactly (``repr``), the
36 x 36 covariance is a plain array of rows, and every language reads it.
The layout, version 1::

    {"format": "memsnav-imu-calibration", "version": 1,
     "session": "static-poses" or "drive", "created": ISO-8601 UTC, "memsnav": version,
     "source": {...what the data were...},
     "units": {...per field...},
     "nominal": {"accel_scale": [3], "accel_offset": [3],
                 "gyro_scale": [3], "gyro_offset": [3]},
     "sample_rate_hz": float, "gravity_m_s2": float or null,
     "accelerometer": {"bias", "scale_factor", "misalignment", "nonlinearity"},
     "accelerometer_std": {...same...},
     "gyroscope": {"bias", "scale_factor", "misalignment", "g_sensitivity"},
     "gyroscope_std": {...same...},
     "parameter_names": [36], "covariance": [[36] x 36],
     "held": [{"parameter", "reason"}], "warnings": [...], "fit": {...}}

A reader refuses another ``format``, a newer ``version`` and a missing
field, naming the file and the field.
"""

from __future__ import annotations

import datetime
import json
import math
from collections.abc import Mapping
from dataclasses import dataclass, field
from pathlib import Path
from typing import TYPE_CHECKING, Any

import numpy as np
from numpy.typing import ArrayLike, NDArray

from memsnav import _memsnav
from memsnav._files import write_text
from memsnav._memsnav import AccelerometerModel, GyroscopeModel, StaticCalibration

if TYPE_CHECKING:
    from memsnav.calibration.drive import DriveCalibration

FORMAT = "memsnav-imu-calibration"
VERSION = 1
#: Kinds of calibration session a file can come from: a multi-position
#: session of raw readings, or the paper's GNSS-reference calibration on a
#: drive (SI readings: nominal scale 1, offset 0).
SESSIONS = ("static-poses", "drive")

_UNITS = {
    "accelerometer": {
        "bias": "m/s^2",
        "scale_factor": "1",
        "misalignment": "1 (M[i][j]: input axis j into output axis i)",
        "nonlinearity": "1/(m/s^2)",
    },
    "gyroscope": {
        "bias": "rad/s",
        "scale_factor": "1",
        "misalignment": "1 (M[i][j]: input axis j into output axis i)",
        "g_sensitivity": "(rad/s)/(m/s^2)",
    },
    "nominal": "reading = scale * (raw - offset); accel scale m/s^2 per count, gyro scale "
    "rad/s per count, offsets in counts",
    "covariance": "SI units of parameter_names",
}
_NOMINAL = ("accel_scale", "accel_offset", "gyro_scale", "gyro_offset")
_ACCEL_FIELDS = ("bias", "scale_factor", "misalignment", "nonlinearity")
_GYRO_FIELDS = ("bias", "scale_factor", "misalignment", "g_sensitivity")


@dataclass(frozen=True)
class ImuCalibration:
    """A calibration of both triads as stored in a calibration file.

    ``accelerometer`` / ``gyroscope``: models of the nominal readings
    ``scale * (raw - offset)`` (SI, method §2); ``*_std`` their one-sigma
    values; ``covariance`` (36, 36) ordered as ``parameter_names``;
    ``nominal`` the four (3,) arrays ``accel_scale``, ``accel_offset``,
    ``gyro_scale``, ``gyro_offset``. :meth:`correct` turns raw readings into
    SI specific force and angular rate.
    """

    session: str
    accelerometer: AccelerometerModel
    gyroscope: GyroscopeModel
    accelerometer_std: AccelerometerModel
    gyroscope_std: GyroscopeModel
    parameter_names: list[str]
    covariance: NDArray[np.float64]
    nominal: dict[str, NDArray[np.float64]]
    sample_rate: float
    gravity: float | None = None
    source: dict[str, Any] = field(default_factory=dict)
    held: list[tuple[str, str]] = field(default_factory=list)
    warnings: list[str] = field(default_factory=list)
    fit: dict[str, Any] = field(default_factory=dict)
    created: str = ""

    def __repr__(self) -> str:
        held = f", {len(self.held)} held" if self.held else ""
        warned = f", {len(self.warnings)} warnings" if self.warnings else ""
        return (
            f"ImuCalibration({self.session!r} session, {self.sample_rate:g} Hz, "
            f"{len(self.parameter_names)} parameters{held}{warned})"
        )

    @property
    def identity_nominal(self) -> bool:
        """Whether the file calibrates SI readings (nominal scale 1, offset
        0), as the ``navigate`` reader produces them."""
        return all(
            np.allclose(self.nominal[k], 1.0 if k.endswith("scale") else 0.0) for k in _NOMINAL
        )

    def correct(
        self, accel: ArrayLike, gyro: ArrayLike
    ) -> tuple[NDArray[np.float64], NDArray[np.float64]]:
        """SI specific force and angular rate, each (N, 3), of raw (N, 3)
        readings: nominal scale and offset, then the exact inverses of the
        models (the gyroscope's g-sensitivity uses the corrected specific
        force)."""
        return _memsnav.correct_imu(accel, gyro, self.accelerometer, self.gyroscope, **self.nominal)

    @classmethod
    def from_static(
        cls, cal: StaticCalibration, source: Mapping[str, Any] | None = None
    ) -> ImuCalibration:
        """The file's view of a :func:`memsnav.calibrate_static` result;
        ``source`` describes the data (paths, lengths), stored as given."""
        from memsnav.calibration.static import static_summary

        return cls(
            session="static-poses",
            accelerometer=cal.accelerometer,
            gyroscope=cal.gyroscope,
            accelerometer_std=cal.accelerometer_std,
            gyroscope_std=cal.gyroscope_std,
            parameter_names=list(cal.parameter_names),
            covariance=np.asarray(cal.covariance),
            nominal={k: np.asarray(cal.nominal[k]) for k in _NOMINAL},
            sample_rate=cal.sample_rate,
            gravity=cal.gravity,
            source=dict(source or {}),
            held=[tuple(h) for h in cal.held],  # type: ignore[misc]
            warnings=list(cal.warnings),
            fit={
                **static_summary(cal),
                "accelerometer_residual_std_m_s2": cal.accelerometer_residual_std,
                "rest_residual_std_rad_s": np.asarray(cal.rest_residual_std).tolist(),
                "turn_residual_std_rad": cal.turn_residual_std,
                "condition_number": np.asarray(cal.condition_number).tolist(),
                "pose_samples": np.asarray(cal.poses).tolist(),
                "pose_held_out": list(cal.pose_held_out),
            },
        )

    @classmethod
    def from_drive(
        cls, cal: DriveCalibration, sample_rate: float, source: Mapping[str, Any] | None = None
    ) -> ImuCalibration:
        """The file's view of a :func:`memsnav.calibration.calibrate_drive`
        result (readings in SI: nominal scale 1, offset 0), its covariance
        the inflated one, block-diagonal (the two fits are separate);
        ``sample_rate`` the IMU's, Hz."""
        a_names = list(cal.accelerometer.parameter_names)
        g_names = list(cal.gyroscope.parameter_names)
        covariance = np.zeros((len(a_names) + len(g_names),) * 2)
        covariance[: len(a_names), : len(a_names)] = cal.accelerometer_covariance
        covariance[len(a_names) :, len(a_names) :] = cal.gyroscope_covariance
        rms = (
            np.sqrt(np.mean(cal.residual_before**2, axis=0)),
            np.sqrt(np.mean(cal.residual_after**2, axis=0)),
        )
        return cls(
            session="drive",
            accelerometer=cal.accelerometer.model,  # type: ignore[arg-type]
            gyroscope=cal.gyroscope.model,  # type: ignore[arg-type]
            accelerometer_std=cal.std("accelerometer"),  # type: ignore[arg-type]
            gyroscope_std=cal.std("gyroscope"),  # type: ignore[arg-type]
            parameter_names=[f"accelerometer {n}" for n in a_names]
            + [f"gyroscope {n}" for n in g_names],
            covariance=covariance,
            nominal={k: np.ones(3) if k.endswith("scale") else np.zeros(3) for k in _NOMINAL},
            sample_rate=sample_rate,
            source=dict(source or {}),
            held=[tuple(h) for h in (*cal.accelerometer.held, *cal.gyroscope.held)],  # type: ignore[misc]
            warnings=list(cal.warnings),
            fit={
                "windows": len(cal.references["time"]),
                "window_s": cal.window_s,
                "until_s": cal.until_s,
                "skipped_for_resets": cal.references["skipped_for_resets"],
                "skipped_before_heading": cal.references["skipped_before_heading"],
                "residual_rms_before": {
                    "accelerometer_m_s2": rms[0][:3].tolist(),
                    "gyroscope_deg_s": np.degrees(rms[0][3:]).tolist(),
                },
                "residual_rms_after": {
                    "accelerometer_m_s2": rms[1][:3].tolist(),
                    "gyroscope_deg_s": np.degrees(rms[1][3:]).tolist(),
                },
                "covariance_inflation": cal.inflation.tolist(),
                "condition_number": {
                    "accelerometer": np.asarray(cal.accelerometer.condition_number).tolist(),
                    "gyroscope": np.asarray(cal.gyroscope.condition_number).tolist(),
                },
            },
        )

    def to_json(self) -> dict[str, Any]:
        """The file's content as a plain dict (module docs)."""

        def fields(model: Any, names: tuple[str, ...]) -> dict[str, Any]:
            return {n: np.asarray(getattr(model, n)).tolist() for n in names}

        content: dict[str, Any] = _plain(
            {
                "format": FORMAT,
                "version": VERSION,
                "session": self.session,
                "created": self.created
                or datetime.datetime.now(datetime.UTC).isoformat(timespec="seconds"),
                "memsnav": _memsnav.__version__,
                "source": self.source,
                "units": _UNITS,
                "nominal": {k: np.asarray(self.nominal[k]).tolist() for k in _NOMINAL},
                "sample_rate_hz": self.sample_rate,
                "gravity_m_s2": self.gravity,
                "accelerometer": fields(self.accelerometer, _ACCEL_FIELDS),
                "accelerometer_std": fields(self.accelerometer_std, _ACCEL_FIELDS),
                "gyroscope": fields(self.gyroscope, _GYRO_FIELDS),
                "gyroscope_std": fields(self.gyroscope_std, _GYRO_FIELDS),
                "parameter_names": self.parameter_names,
                "covariance": np.asarray(self.covariance).tolist(),
                "held": [{"parameter": p, "reason": r} for p, r in self.held],
                "warnings": self.warnings,
                "fit": self.fit,
            }
        )
        return content

    def save(self, path: str | Path) -> Path:
        """Writes the calibration file (atomically) and returns its path."""
        path = Path(path)
        write_text(path, _dumps(self.to_json()) + "\n")
        return path


def save_calibration(
    cal: StaticCalibration | ImuCalibration,
    path: str | Path,
    *,
    source: Mapping[str, Any] | None = None,
) -> Path:
    """Writes a calibration (a :func:`memsnav.calibrate_static` result or an
    :class:`ImuCalibration`) to ``path`` as a calibration file."""
    if isinstance(cal, StaticCalibration):
        cal = ImuCalibration.from_static(cal, source)
    return cal.save(path)


def load_calibration(path: str | Path) -> ImuCalibration:
    """Reads a calibration file (module docs): an :class:`ImuCalibration`
    whose ``.correct(accel, gyro)`` applies it to raw readings. Errors name
    the file and the field.

    ``path``: the file to read (str or path-like).
    """
    path = Path(path)
    try:
        raw = json.loads(path.read_text())
    except OSError as e:
        raise ValueError(f"calibration: cannot read {path}: {e.strerror}") from None
    except json.JSONDecodeError as e:
        raise ValueError(
            f"{path}:{e.lineno}: not a calibration file (invalid JSON: {e.msg})"
        ) from None

    def need(mapping: Any, key: str, where: str = "") -> Any:
        if not isinstance(mapping, dict) or key not in mapping:
            raise ValueError(f"{path}: missing field {where}{key}")
        return mapping[key]

    if need(raw, "format") != FORMAT:
        raise ValueError(f"{path}: format is {raw['format']!r}, expected {FORMAT!r}")
    version = need(raw, "version")
    if not isinstance(version, int) or version > VERSION:
        raise ValueError(
            f"{path}: version {version!r} is newer than this memsnav reads ({VERSION}); upgrade"
        )
    session = need(raw, "session")
    if session not in SESSIONS:
        raise ValueError(f"{path}: session must be one of {list(SESSIONS)}, got {session!r}")
    rate = float(need(raw, "sample_rate_hz"))

    def model(key: str, kind: type, names: tuple[str, ...]) -> Any:
        table = need(raw, key)
        values = [np.asarray(need(table, n, f"{key}."), dtype=float) for n in names]
        try:
            return kind(*values, sample_rate=rate)
        except ValueError as e:
            raise ValueError(f"{path}: {key}: {e}") from None

    nominal_table = need(raw, "nominal")
    nominal = {k: np.asarray(need(nominal_table, k, "nominal."), dtype=float) for k in _NOMINAL}
    names = list(need(raw, "parameter_names"))
    covariance = np.asarray(need(raw, "covariance"), dtype=float)
    if covariance.shape != (len(names), len(names)):
        raise ValueError(
            f"{path}: covariance must be {len(names)} x {len(names)} (parameter_names), "
            f"got shape {covariance.shape}"
        )
    gravity = raw.get("gravity_m_s2")
    return ImuCalibration(
        session=session,
        accelerometer=model("accelerometer", AccelerometerModel, _ACCEL_FIELDS),
        gyroscope=model("gyroscope", GyroscopeModel, _GYRO_FIELDS),
        accelerometer_std=model("accelerometer_std", AccelerometerModel, _ACCEL_FIELDS),
        gyroscope_std=model("gyroscope_std", GyroscopeModel, _GYRO_FIELDS),
        parameter_names=names,
        covariance=covariance,
        nominal=nominal,
        sample_rate=rate,
        gravity=None if gravity is None else float(gravity),
        source=dict(raw.get("source", {})),
        held=[(h["parameter"], h["reason"]) for h in raw.get("held", [])],
        warnings=list(raw.get("warnings", [])),
        fit=dict(raw.get("fit", {})),
        created=str(raw.get("created", "")),
    )


def _plain(value: Any) -> Any:
    """JSON-ready: numpy scalars and arrays to Python, NaN to None."""
    if isinstance(value, dict):
        return {k: _plain(v) for k, v in value.items()}
    if isinstance(value, list | tuple):
        return [_plain(v) for v in value]
    if isinstance(value, np.ndarray):
        return _plain(value.tolist())
    if isinstance(value, np.generic):
        return _plain(value.item())
    if isinstance(value, float) and not math.isfinite(value):
        return None
    return value


def _dumps(value: Any, indent: int = 0) -> str:
    """JSON with one line per table entry and each list of numbers (a
    vector, a matrix row) on one line: a 36 x 36 covariance is 36 lines."""
    pad = "  " * (indent + 1)
    if isinstance(value, dict) and value:
        items = [f"{pad}{json.dumps(k)}: {_dumps(v, indent + 1)}" for k, v in value.items()]
        return "{\n" + ",\n".join(items) + "\n" + "  " * indent + "}"
    if isinstance(value, list) and value and any(isinstance(v, dict | list) for v in value):
        items = [pad + _dumps(v, indent + 1) for v in value]
        return "[\n" + ",\n".join(items) + "\n" + "  " * indent + "]"
    return json.dumps(value, allow_nan=False)
