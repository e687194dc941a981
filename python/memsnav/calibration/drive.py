"""The paper's calibration on a real drive (method §3): GNSS-derived
references of specific force and angular rate, taken from a smoothed
GNSS/INS solution of the drive itself, and least squares against the IMU's
outputs (see docs/how-to/calibrate-an-imu.md, "A drive").

The numbers come from the core: ``navigate_log`` navigates the log with the
smoother on and no outages, ``LogRun.calibration_references`` forms the
window means (``memsnav_core::navigate::references``, equations there), and
``calibrate_accelerometer`` / ``calibrate_gyroscope`` fit the models. This
module chains them and makes the uncertainty honest: the fits' covariance
comes from the residual variance as if the windows were independent, which
they are not quite (the smoothed solution's errors are correlated over a few
windows), so each output axis's covariance is scaled by the AR(1) variance
factor (1 + ρ) / (1 − ρ) of its residuals' lag-one autocorrelation ρ (the
effective-sample-size correction for a mean; e.g. Wilks, *Statistical
Methods in the Atmospheric Sciences*, eq. 5.12), never below 1
(``inflate_calibration_covariance``: ``memsnav_core::calibration::inflation``).
The calibrations drawn from that covariance come from the core too
(``draw_imu_calibrations``: ``memsnav_core::calibration::draws``), draw i
from its own random stream of (seed, i).
"""

from __future__ import annotations

import copy
from collections.abc import Mapping
from dataclasses import dataclass, field
from typing import Any

import numpy as np
from numpy.typing import ArrayLike, NDArray

from memsnav import _memsnav
from memsnav._memsnav import (
    AccelerometerModel,
    Calibration,
    CalibrationLayout,
    GyroscopeModel,
    LogRun,
)

#: Window length of the references, s: long against the GNSS epoch interval
#: (0.25 s on the shipped drive), so that a window's velocity and attitude
#: change come from the GNSS more than from the IMU being calibrated; short
#: enough that a car's manoeuvres are resolved (docs/how-to/calibrate-an-imu.md).
DEFAULT_WINDOW_S = 2.0

_LAYOUTS = {sensor: CalibrationLayout(sensor) for sensor in ("accelerometer", "gyroscope")}


@dataclass(frozen=True)
class DriveCalibration:
    """A calibration from a drive (:func:`calibrate_drive`).

    ``accelerometer`` / ``gyroscope``: the fits (``Calibration``: ``.model``,
    ``.std``, ``.covariance``, ``.held``, ...), their covariance already
    scaled by ``inflation`` (per output axis, accelerometer then gyroscope);
    ``references``: the window means (``LogRun.calibration_references``);
    ``residual_before`` / ``residual_after``: measured − reference per window
    before and after the calibration, (W, 6) [accel m/s², gyro rad/s];
    ``run``: the smoothed navigation the references came from;
    ``warnings``: the fits' warnings (each also raised as a UserWarning).
    """

    accelerometer: Calibration
    gyroscope: Calibration
    accelerometer_covariance: NDArray[np.float64]
    gyroscope_covariance: NDArray[np.float64]
    inflation: NDArray[np.float64]
    references: dict[str, Any]
    residual_before: NDArray[np.float64]
    residual_after: NDArray[np.float64]
    run: LogRun
    window_s: float
    until_s: float | None
    warnings: list[str] = field(default_factory=list)

    def std(self, which: str) -> AccelerometerModel | GyroscopeModel:
        """One-sigma of the ``"accelerometer"`` or ``"gyroscope"`` parameters
        after the inflation, as a model of the same class."""
        if which == "accelerometer":
            fit, cov = self.accelerometer, self.accelerometer_covariance
        else:
            fit, cov = self.gyroscope, self.gyroscope_covariance
        return _model_of(fit, np.sqrt(np.maximum(np.diag(cov), 0.0)))

    def correct(
        self, specific_force: ArrayLike, angular_rate: ArrayLike
    ) -> tuple[NDArray[np.float64], NDArray[np.float64]]:
        """SI specific force and angular rate (N, 3) of SI readings in the
        sensor's axes: the exact inverses of the fitted models."""
        return _correct(
            self.accelerometer.model, self.gyroscope.model, specific_force, angular_rate
        )


def calibrate_drive(
    time: ArrayLike,
    specific_force: ArrayLike,
    angular_rate: ArrayLike,
    gnss: Any,
    *,
    settings: Mapping[str, Mapping[str, Any]] | None = None,
    window_s: float = DEFAULT_WINDOW_S,
    until_s: float | None = None,
    estimate: str = "determinable",
    scale_factor_states: bool = True,
) -> DriveCalibration:
    """Calibrates an IMU on a drive (module docs; method §3 on real data).

    ``time``, ``specific_force``, ``angular_rate``, ``gnss``, ``settings``:
    as for :func:`memsnav.navigate_log` (sensor axes, SI; the settings'
    mounting, lever arms, aids and filter apply; their outages are dropped
    and the smoother is switched on). ``window_s``: the references' window
    length, s; ``until_s``: use only the first ``until_s`` seconds after the
    start (keep the rest to test the calibration on); ``estimate``:
    "determinable" (default: parameters the drive does not determine are
    held at zero and listed in ``.held``) or "all".
    """
    tables = {k: dict(v) for k, v in copy.deepcopy(dict(settings or {})).items()}
    tables.pop("outages", None)
    tables.setdefault("filter", {})["smoother"] = True
    tables["filter"].setdefault("scale_factor_states", scale_factor_states)
    run = _memsnav.navigate_log(time, specific_force, angular_rate, gnss, settings=tables)
    smoothed = run.smoothed
    assert smoothed is not None  # the smoother is on
    refs = smoothed.calibration_references(
        time, specific_force, angular_rate, window_s=window_s, until_s=until_s
    )
    # Each fit raises its own warnings (UserWarning) and keeps them.
    rate = 1.0 / refs["window_s"]
    accel = _memsnav.calibrate_accelerometer(
        refs["measured_specific_force"],
        refs["reference_specific_force"],
        sample_rate=rate,
        estimate=estimate,
    )
    gyro = _memsnav.calibrate_gyroscope(
        refs["measured_angular_rate"],
        refs["reference_angular_rate"],
        refs["reference_specific_force"],
        sample_rate=rate,
        estimate=estimate,
    )
    accel_model, gyro_model = _noise_free(accel), _noise_free(gyro)
    assert isinstance(accel_model, AccelerometerModel)
    assert isinstance(gyro_model, GyroscopeModel)
    predicted_f = accel_model.measure(refs["reference_specific_force"])
    predicted_w = gyro_model.measure(
        refs["reference_angular_rate"], refs["reference_specific_force"]
    )
    before = np.hstack(
        [
            refs["measured_specific_force"] - refs["reference_specific_force"],
            refs["measured_angular_rate"] - refs["reference_angular_rate"],
        ]
    )
    after = np.hstack(
        [
            refs["measured_specific_force"] - predicted_f,
            refs["measured_angular_rate"] - predicted_w,
        ]
    )
    accel_covariance, accel_inflation = _inflate(accel, after[:, :3], refs, "accel")
    gyro_covariance, gyro_inflation = _inflate(gyro, after[:, 3:], refs, "gyro")
    return DriveCalibration(
        accelerometer=accel,
        gyroscope=gyro,
        accelerometer_covariance=accel_covariance,
        gyroscope_covariance=gyro_covariance,
        inflation=np.concatenate([accel_inflation, gyro_inflation]),
        references=refs,
        residual_before=before,
        residual_after=after,
        run=run,
        window_s=float(refs["window_s"]),
        until_s=until_s,
        warnings=[*accel.warnings, *gyro.warnings],
    )


def _correct(
    accel: AccelerometerModel | GyroscopeModel,
    gyro: AccelerometerModel | GyroscopeModel,
    specific_force: ArrayLike,
    angular_rate: ArrayLike,
) -> tuple[NDArray[np.float64], NDArray[np.float64]]:
    """SI readings corrected by the exact inverses of the models."""
    one, zero = np.ones(3), np.zeros(3)
    return _memsnav.correct_imu(
        specific_force,
        angular_rate,
        accel,  # type: ignore[arg-type]
        gyro,  # type: ignore[arg-type]
        accel_scale=one,
        accel_offset=zero,
        gyro_scale=one,
        gyro_offset=zero,
    )


def _layout(fit: Calibration) -> CalibrationLayout:
    """The parameter layout of the fit's sensor."""
    return _LAYOUTS["accelerometer" if isinstance(fit.model, AccelerometerModel) else "gyroscope"]


def _inflate(
    fit: Calibration, residual: NDArray[np.float64], refs: dict[str, Any], sensor: str
) -> tuple[NDArray[np.float64], NDArray[np.float64]]:
    """The fit's covariance with each output axis scaled by the AR(1)
    factor of its ``residual`` column, plus the solution's own covariance
    of the biases and scale factors on those blocks: the references inherit
    it (``LogRun.calibration_references``). A held parameter stays at zero.
    Returns the covariance and the three factors."""
    return _memsnav.inflate_calibration_covariance(
        _layout(fit).sensor,
        fit.covariance,
        residual,
        held=[name for name, _ in fit.held],
        bias_covariance=refs[f"{sensor}_bias_covariance"],
        scale_factor_covariance=refs[f"{sensor}_scale_factor_covariance"],
    )


def parameter_index(name: str) -> tuple[str, tuple[int, ...]]:
    """The model attribute and the index in it of a parameter name
    (``bias_u`` → ("bias", (0,)), ``misalignment_uv`` → ("misalignment",
    (0, 1)), ``g_sensitivity_pw`` → ("g_sensitivity", (0, 2))), from the
    core's ``CalibrationLayout`` of the sensor whose parameter it is."""
    for layout in _LAYOUTS.values():
        if name in layout.names:
            return layout.parameter(layout.index(name))
    raise ValueError(f"name: {name!r} is not a calibration parameter")


def _noise_free(fit: Calibration) -> AccelerometerModel | GyroscopeModel:
    """The fitted model without its noise terms (its deterministic output)."""
    return _model_of(fit, _values(fit))


def _model_of(fit: Calibration, values: NDArray[np.float64]) -> AccelerometerModel | GyroscopeModel:
    """A noise-free model of the fit's class whose attributes are ``values``
    in the order of ``fit.parameter_names``."""
    return _layout(fit).model(values, sample_rate=fit.model.sample_rate)


def compare_navigation(
    time: ArrayLike,
    specific_force: ArrayLike,
    angular_rate: ArrayLike,
    gnss: Any,
    calibration: DriveCalibration,
    *,
    settings: Mapping[str, Mapping[str, Any]] | None,
    truth_time: ArrayLike,
    truth_position_ecef: ArrayLike,
    draws: int = 0,
    seed: int = 0,
) -> dict[str, Any]:
    """The drive navigated with the raw and with the calibrated readings,
    with the settings' outages and the smoother on, scored against a truth:
    ``{"raw"|"calibrated": {"forward"|"smoothed": {...}}}``, each with the
    pooled horizontal RMS and max over the outages inside the calibration
    span (``in_fit``, where the calibration saw the GNSS) and after it
    (``after_fit``, the honest test), the first outage alone (``first``: the
    first minutes), and ``all`` (every outage).

    ``draws`` > 0 adds ``"draws"``: the same scores of the drive navigated
    with ``draws`` calibrations drawn from the calibration's covariance
    (draw i from the random stream (``seed``, i) alone, so the first draws
    are the same whatever ``draws``), the calibration's uncertainty in
    navigation terms.
    """
    tables = {k: dict(v) for k, v in copy.deepcopy(dict(settings or {})).items()}
    tables.setdefault("filter", {})["smoother"] = True
    until = np.inf if calibration.until_s is None else calibration.until_s

    def scores(f: ArrayLike, w: ArrayLike) -> dict[str, Any]:
        run = _memsnav.navigate_log(time, f, w, gnss, settings=tables)
        windows = np.asarray(run.outages, dtype=float).reshape(-1, 2) - run.start.time
        subsets = {
            "in_fit": windows[:, 1] <= until,
            "after_fit": windows[:, 0] >= until,
            "first": np.arange(len(windows)) == 0,
            "all": np.ones(len(windows), dtype=bool),
        }
        out: dict[str, Any] = {}
        for view, solution in (("forward", run), ("smoothed", run.smoothed)):
            assert solution is not None
            per_outage = solution.score(truth_time, truth_position_ecef)["outages"]
            out[view] = {
                name: _pooled([s for s, k in zip(per_outage, keep, strict=True) if k])
                for name, keep in subsets.items()
            }
        return out

    result: dict[str, Any] = {
        "raw": scores(specific_force, angular_rate),
        "calibrated": scores(*calibration.correct(specific_force, angular_rate)),
    }
    if draws > 0:
        accel_fit, gyro_fit = calibration.accelerometer, calibration.gyroscope
        accel_draws, gyro_draws = _memsnav.draw_imu_calibrations(
            _values(accel_fit),
            calibration.accelerometer_covariance,
            _values(gyro_fit),
            calibration.gyroscope_covariance,
            draws=draws,
            seed=seed,
        )
        result["draws"] = [
            scores(
                *_correct(
                    _model_of(accel_fit, a), _model_of(gyro_fit, g), specific_force, angular_rate
                )
            )
            for a, g in zip(accel_draws, gyro_draws, strict=True)
        ]
    return result


def _values(fit: Calibration) -> NDArray[np.float64]:
    """The fitted parameters in the order of ``fit.parameter_names``."""
    return _layout(fit).values(fit.model)


def _pooled(stats: list[dict[str, Any]]) -> dict[str, Any]:
    """Horizontal RMS pooled over outages (weighted by their epochs), the
    largest max, and the number of outages."""
    scored = [s for s in stats if s["epochs"] > 0]
    if not scored:
        return {"outages": 0}
    epochs = np.array([s["epochs"] for s in scored], dtype=float)
    rms = np.array([s["rms_horizontal_m"] for s in scored])
    return {
        "outages": len(scored),
        "rms_horizontal_m": float(np.sqrt(np.sum(epochs * rms**2) / epochs.sum())),
        "max_horizontal_m": float(max(s["max_horizontal_m"] for s in scored)),
    }
