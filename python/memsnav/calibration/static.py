"""Multi-position ("no turntable") calibration: the Python face of
``memsnav_core::calibration::static_poses`` (see docs/how-to/calibrate-an-imu.md)."""

from __future__ import annotations

import warnings
from typing import Any

import numpy as np
from numpy.typing import ArrayLike

from memsnav import _memsnav
from memsnav._memsnav import StaticCalibration

_DEFAULTS = _memsnav.static_calibration_defaults()


def calibrate_static(
    time: ArrayLike,
    accel: ArrayLike,
    gyro: ArrayLike,
    *,
    gravity: float,
    accel_scale: ArrayLike | None = None,
    gyro_scale: ArrayLike | None = None,
    accel_offset: ArrayLike | None = None,
    gyro_offset: ArrayLike | None = None,
    window: float = _DEFAULTS["window"],
    threshold_factor: float = _DEFAULTS["threshold_factor"],
    initial_rest: float = _DEFAULTS["initial_rest"],
    min_pose: float = _DEFAULTS["min_pose"],
    estimate: str = "determinable",
    holdout_every: int | None = None,
    holdout_from: float | None = None,
) -> StaticCalibration:
    """Calibrates an IMU from a multi-position session: a rest of
    ``initial_rest`` seconds, then poses held still for a few seconds each,
    joined by turns by hand (Tedaldi et al., ICRA 2014).

    ``time`` (N,) s, increasing; ``accel`` and ``gyro`` (N, 3) raw readings,
    counts or any unit. ``gravity``: local gravity magnitude, m/s² (no
    default: it varies by 0.05 m/s² over the Earth). The nominal reading is
    ``scale * (raw - offset)`` per axis (scalars or (3,)): ``accel_scale``
    m/s² and ``gyro_scale`` rad/s per count, ``accel_offset`` and
    ``gyro_offset`` the counts at zero input; None means 1 and 0 (readings
    already in SI). They are first guesses: the calibration fits the
    scale factors and biases relative to them, and warns when a fitted scale
    is more than 20 % away (with the value to use instead).

    The static-interval detector (docs/how-to/calibrate-an-imu.md): a sample is static
    when the variance magnitude of the accelerometer over a ``window`` (s)
    around it is below ``threshold_factor`` times that of the initial rest;
    static runs of at least ``min_pose`` s are poses.

    ``estimate``: "determinable" (default) estimates the nonlinearity, the
    g-sensitivity and the gyroscope scale factors and misalignments only when
    the poses determine them, holding the rest at zero (the nominal scale for
    the gyroscope) and listing them in ``.held``; "all" estimates everything
    and raises ``UnobservableError`` or ``ValueError`` when the data cannot.
    ``holdout_every=h`` leaves poses h-1, 2h-1, ... and ``holdout_from=t``
    every pose that ends at or after ``t`` (s, the axis of ``time``: the
    middle of the log fits on its first half) out of the fits; their errors
    are reported apart (``.pose_held_out``, ``.turn_held_out``). A pose
    either names is held out; the initial rest never is.

    Under "determinable" the nonlinearity and the g-sensitivity are chosen
    by the small-sample Akaike information criterion (AICc) among what the
    poses determine; ``.model_selection`` lists every candidate with its
    AICc and the one chosen (docs/how-to/calibrate-an-imu.md).

    Returns a ``StaticCalibration``: ``.accelerometer`` / ``.gyroscope`` (the
    models of the nominal readings, SI, method §2), ``.accelerometer_std`` /
    ``.gyroscope_std``, ``.covariance`` (36, 36) of ``.parameter_names``,
    ``.poses`` (P, 2) sample indices, ``.magnitude_error_before`` /
    ``_after`` (P,) m/s², ``.turn_error_before`` / ``_after`` (P-1,) rad,
    ``.held``, ``.model_selection``, ``.warnings`` (each also emitted as a
    ``UserWarning``) and ``.correct(accel, gyro)`` → SI specific force and
    angular rate of raw readings.
    """

    def nominal(value: ArrayLike | None, default: float) -> ArrayLike:
        return default if value is None else value

    cal = _memsnav.calibrate_static(
        time,
        accel,
        gyro,
        gravity=gravity,
        accel_scale=nominal(accel_scale, _DEFAULTS["scale"]),
        accel_offset=nominal(accel_offset, _DEFAULTS["offset"]),
        gyro_scale=nominal(gyro_scale, _DEFAULTS["scale"]),
        gyro_offset=nominal(gyro_offset, _DEFAULTS["offset"]),
        window=window,
        threshold_factor=threshold_factor,
        initial_rest=initial_rest,
        min_pose=min_pose,
        estimate=estimate,
        holdout_every=holdout_every,
        holdout_from=holdout_from,
    )
    for message in cal.warnings:
        warnings.warn(message, UserWarning, stacklevel=2)
    return cal


def _rms(values: np.ndarray, keep: np.ndarray) -> float | None:
    return float(np.sqrt(np.mean(values[keep] ** 2))) if keep.any() else None


def static_summary(cal: StaticCalibration) -> dict[str, Any]:
    """The figures of merit of a static calibration as a plain dict: RMS of
    ‖f‖ − g over the poses (m/s²) and of the turns' gravity-direction error
    (degrees), before (nominal readings) and after, in the fit and held out
    (None when no pose is held out), and under "model" the second-order
    terms each stage chose by its AICc (``.model_selection``)."""
    pose_out = np.asarray(cal.pose_held_out, dtype=bool)
    turn_out = np.asarray(cal.turn_held_out, dtype=bool)
    out: dict[str, Any] = {
        "poses": len(pose_out),
        "poses_held_out": int(pose_out.sum()),
        "turns": len(turn_out),
        "turns_held_out": int(turn_out.sum()),
    }
    for when in ("before", "after"):
        magnitude = np.asarray(getattr(cal, f"magnitude_error_{when}"))
        turn = np.degrees(np.asarray(getattr(cal, f"turn_error_{when}")))
        for subset, pk, tk in (("fit", ~pose_out, ~turn_out), ("held_out", pose_out, turn_out)):
            out[f"magnitude_rms_{when}_{subset}_m_s2"] = _rms(magnitude, pk)
            out[f"turn_rms_{when}_{subset}_deg"] = _rms(turn, tk)
    out["model"] = {
        m["stage"]: list(m["candidates"][m["chosen"]]["terms"]) for m in cal.model_selection
    }
    return out
