"""The paper's claims and their verdicts, computed from ``summary.json``.

Each claim has a stable id, the paper's statement, the figure memsnav
measures for it (with its Monte Carlo standard error), and a criterion
fixed here, before any run, with its thresholds as named constants. The
verdict is one of ``holds``, ``partly``, ``does not hold`` and ``not
evaluated`` (an experiment it needs did not run to completion). Verdicts
compare point estimates with the thresholds, except where a criterion
asks for a significant difference (then in units of its standard error);
the standard errors are printed beside each figure so a reader sees how
close a verdict is.

:func:`evaluate_claims` reads only the summary dict that ``memsnav
reproduce`` writes as ``summary.json``, so anyone can recompute the
verdicts from that file.
"""

from __future__ import annotations

import math
from collections.abc import Callable
from dataclasses import dataclass
from typing import Any

from memsnav.experiments.calibration import AXES

HOLDS = "holds"
PARTLY = "partly"
DOES_NOT_HOLD = "does not hold"
NOT_EVALUATED = "not evaluated"
VERDICTS = (HOLDS, PARTLY, DOES_NOT_HOLD, NOT_EVALUATED)

WELL_ESTIMATED_NORMALIZED_RMS = 0.3
"""A parameter is "well estimated" when its RMS error is at most this share
of the parameters' own RMS (normalised MSE ≤ 0.09)."""

INVERSION_HOLDS_FACTOR = 2.0
"""An inversion MSE "≈" the paper's when within this factor of it (the
paper reads it off a log-scale figure); within INVERSION_PARTLY_FACTOR:
partly."""
INVERSION_PARTLY_FACTOR = 10.0
PAPER_ACCEL_MSE_G2 = 1e-5
PAPER_GYRO_MSE_DPS2 = 1e-3

CLEAR_IMPROVEMENT = 0.10
""""Clearly improves": the RMS position error falls by at least this share."""
SIGNIFICANT_STANDARD_ERRORS = 3.0
"""A paired difference is significant beyond this many standard errors."""

LIKE_INS_HOLDS_RATIO = 1.25
"""Calibrated MEMS "similar to" the INS: RMS ratio at most this; partly up
to LIKE_INS_PARTLY_RATIO."""
LIKE_INS_PARTLY_RATIO = 2.0

DRIFTS_MUCH_MORE_RATIO = 3.0
""""Much more" drift: outage error ratio MEMS / INS at least this; partly
from DRIFTS_PARTLY_RATIO."""
DRIFTS_PARTLY_RATIO = 1.5

LIGHT_IMPROVEMENT = 0.25
"""A "light" improvement in the outage: calibration removes at most this
share of the raw MEMS error; partly up to LIGHT_PARTLY_IMPROVEMENT."""
LIGHT_PARTLY_IMPROVEMENT = 0.50


@dataclass(frozen=True)
class Evaluation:
    """A verdict, the figure behind it (text) and the numbers it used."""

    verdict: str
    memsnav: str
    values: dict[str, float]


@dataclass(frozen=True)
class Claim:
    """A claim of the paper and how memsnav judges it."""

    id: str
    paper: str
    figures: str
    criterion: str
    needs: tuple[str, ...]
    evaluate: Callable[[dict[str, Any]], Evaluation]


def _pm(value: float, se: float, digits: int = 2) -> str:
    """``value ± se`` (no ± when the standard error is unknown)."""
    if se is None or not math.isfinite(se):
        return f"{value:.{digits}g} (standard error unknown)"
    return f"{value:.{digits}g} ± {se:.1g}"


def window_words(window_key: str) -> str:
    """``first_150s`` -> ``first 150 s``."""
    return window_key.replace("_", " ").removesuffix("s") + " s"


def _normalized_rms(entry: dict[str, Any]) -> float:
    return math.sqrt(entry["normalized_mse_eiv"])


def _well_estimated(sensor: str, good: tuple[str, str], worse: tuple[str, str]) -> Callable:
    def evaluate(summary: dict[str, Any]) -> Evaluation:
        cal = summary["calibration"][sensor]
        rms = {(g, a): _normalized_rms(cal[g]["per_axis"][a]) for g in good for a in AXES[sensor]}
        worse_rms = {g: _normalized_rms(cal[g]) for g in worse}
        well = [k for k, v in rms.items() if v <= WELL_ESTIMATED_NORMALIZED_RMS]
        best_of_worse = min(worse_rms.values())
        worse_ok = all(rms[k] < best_of_worse for k in well)
        if len(well) == len(rms) and worse_ok:
            verdict = HOLDS
        elif well and worse_ok:
            verdict = PARTLY
        else:
            verdict = DOES_NOT_HOLD
        text = "; ".join(
            f"{g.replace('_', ' ')}: " + ", ".join(f"{a} {rms[(g, a)]:.2g}" for a in AXES[sensor])
            for g in good
        )
        text += "; " + ", ".join(
            f"{g.replace('_', ' ')} {v:.2g} (all axes)" for g, v in worse_rms.items()
        )
        values = {f"{g}_{a}": v for (g, a), v in rms.items()}
        values.update(worse_rms)
        return Evaluation(verdict, f"normalised RMS error (EIV): {text}", values)

    return evaluate


def _inversion(key: str, paper: float, unit: str) -> Callable:
    def evaluate(summary: dict[str, Any]) -> Evaluation:
        inv = summary["inversion"]
        ours, se = inv[key], inv[key.replace("_mse_", "_mse_se_")]
        factor = max(ours / paper, paper / ours)
        verdict = (
            HOLDS
            if factor <= INVERSION_HOLDS_FACTOR
            else PARTLY
            if factor <= INVERSION_PARTLY_FACTOR
            else DOES_NOT_HOLD
        )
        return Evaluation(
            verdict,
            f"{_pm(ours, se)} {unit} (a factor {factor:.2g} from the paper's)",
            {"memsnav": ours, "standard_error": se, "paper": paper, "factor": factor},
        )

    return evaluate


def _nominal(summary: dict[str, Any]) -> dict[str, Any]:
    return summary["navigation"]["nominal"]


def _calibration_helps_early(summary: dict[str, Any]) -> Evaluation:
    nav = _nominal(summary)
    early, late = nav["early_key"], nav["late_key"]
    mems, cal = nav["imus"]["mems"], nav["imus"]["calibrated_mems"]
    d_early = nav["paired"][f"rms_position_error_{early}_m"]
    d_late = nav["paired"][f"rms_position_error_{late}_m"]
    base_early = mems[f"rms_position_error_{early}_m"]
    base_late = mems[f"rms_position_error_{late}_m"]
    gain_early = d_early["difference"] / base_early
    gain_late = d_late["difference"] / base_late
    se = d_early["standard_error"]
    # Without a standard error (a single run) nothing is significant.
    significant = (
        se is not None
        and math.isfinite(se)
        and d_early["difference"] > SIGNIFICANT_STANDARD_ERRORS * se
    )
    if significant and gain_early >= CLEAR_IMPROVEMENT and gain_early > gain_late:
        verdict = HOLDS
    elif significant:
        verdict = PARTLY
    else:
        verdict = DOES_NOT_HOLD
    key = f"rms_position_error_{early}_m"
    return Evaluation(
        verdict,
        f"RMS position error {window_words(early)}: MEMS "
        f"{_pm(base_early, mems['standard_error'][key], 3)} m, "
        f"calibrated {_pm(cal[key], cal['standard_error'][key], 3)} m; "
        f"paired gain {_pm(d_early['difference'], d_early['standard_error'])} m "
        f"({gain_early:.1%}); {window_words(late)}: gain "
        f"{_pm(d_late['difference'], d_late['standard_error'])} m ({gain_late:.1%})",
        {
            "gain_early_m": d_early["difference"],
            "gain_early_standard_error_m": d_early["standard_error"],
            "relative_gain_early": gain_early,
            "relative_gain_late": gain_late,
        },
    )


def _calibrated_like_ins(summary: dict[str, Any]) -> Evaluation:
    nav = _nominal(summary)
    key = f"rms_position_error_{nav['late_key']}_m"
    cal, ins = nav["imus"]["calibrated_mems"], nav["imus"]["ins"]
    ratio = cal[key] / ins[key]
    verdict = (
        HOLDS
        if ratio <= LIKE_INS_HOLDS_RATIO
        else PARTLY
        if ratio <= LIKE_INS_PARTLY_RATIO
        else DOES_NOT_HOLD
    )
    return Evaluation(
        verdict,
        f"RMS position error {window_words(nav['late_key'])}: calibrated MEMS "
        f"{_pm(cal[key], cal['standard_error'][key], 3)} m, INS "
        f"{_pm(ins[key], ins['standard_error'][key], 3)} m (ratio {ratio:.2f})",
        {"calibrated_mems_m": cal[key], "ins_m": ins[key], "ratio": ratio},
    )


_OUTAGE_KEY = "max_position_error_during_outage_m"


def _outage(summary: dict[str, Any]) -> dict[str, Any]:
    return summary["navigation"]["outage"]["imus"]


def _mems_drifts(summary: dict[str, Any]) -> Evaluation:
    o = _outage(summary)
    mems, ins = o["mems"], o["ins"]
    ratio = mems[_OUTAGE_KEY] / ins[_OUTAGE_KEY]
    verdict = (
        HOLDS
        if ratio >= DRIFTS_MUCH_MORE_RATIO
        else PARTLY
        if ratio >= DRIFTS_PARTLY_RATIO
        else DOES_NOT_HOLD
    )
    return Evaluation(
        verdict,
        f"largest mean error in the outage: MEMS "
        f"{_pm(mems[_OUTAGE_KEY], mems['standard_error'][_OUTAGE_KEY], 3)} m, INS "
        f"{_pm(ins[_OUTAGE_KEY], ins['standard_error'][_OUTAGE_KEY], 3)} m (ratio {ratio:.1f})",
        {"mems_m": mems[_OUTAGE_KEY], "ins_m": ins[_OUTAGE_KEY], "ratio": ratio},
    )


def _helps_little_in_outage(summary: dict[str, Any]) -> Evaluation:
    o = _outage(summary)
    mems, cal = o["mems"], o["calibrated_mems"]
    reduction = 1.0 - cal[_OUTAGE_KEY] / mems[_OUTAGE_KEY]
    verdict = (
        HOLDS
        if reduction <= LIGHT_IMPROVEMENT
        else PARTLY
        if reduction <= LIGHT_PARTLY_IMPROVEMENT
        else DOES_NOT_HOLD
    )
    return Evaluation(
        verdict,
        f"largest mean error in the outage: MEMS "
        f"{_pm(mems[_OUTAGE_KEY], mems['standard_error'][_OUTAGE_KEY], 3)} m, calibrated MEMS "
        f"{_pm(cal[_OUTAGE_KEY], cal['standard_error'][_OUTAGE_KEY], 3)} m: calibration "
        f"removes {reduction:.0%} of it",
        {
            "mems_m": mems[_OUTAGE_KEY],
            "calibrated_mems_m": cal[_OUTAGE_KEY],
            "reduction": reduction,
        },
    )


WELL = f"normalised RMS error ≤ {WELL_ESTIMATED_NORMALIZED_RMS}"

CLAIMS: tuple[Claim, ...] = (
    Claim(
        "accel_bias_misalignment_well_estimated",
        "The accelerometer biases and misalignments are well estimated; the scale factors and "
        "the nonlinearity are estimated worse (§5.1).",
        "figs 3-6",
        f"holds if the bias and the misalignments of every output axis are well estimated "
        f"({WELL}: RMS error over the sets at most {WELL_ESTIMATED_NORMALIZED_RMS:.0%} of the "
        "parameters' own RMS, errors-in-variables estimator) and the scale factors and the "
        "nonlinearity are estimated worse (larger normalised error) than each of them; partly "
        "if that holds on some axes only; does not hold otherwise",
        ("calibration",),
        _well_estimated(
            "accelerometer", ("bias", "misalignment"), ("scale_factor", "nonlinearity")
        ),
    ),
    Claim(
        "gyro_bias_misalignment_well_estimated",
        "The gyro biases and misalignments are well estimated; the scale factors and the "
        "g-sensitivity are estimated worse (§5.1).",
        "figs 7-10",
        f"as for the accelerometer ({WELL} per output axis p, q, r for bias and misalignment; "
        "scale factors and g-sensitivity worse)",
        ("calibration",),
        _well_estimated("gyroscope", ("bias", "misalignment"), ("scale_factor", "g_sensitivity")),
    ),
    Claim(
        "inversion_accel_mse",
        f"The inversion recovers the specific force with an MSE of about {PAPER_ACCEL_MSE_G2:g} "
        "g² (§5.2).",
        "fig 11",
        f"holds within a factor {INVERSION_HOLDS_FACTOR:g} of {PAPER_ACCEL_MSE_G2:g} g², partly "
        f"within a factor {INVERSION_PARTLY_FACTOR:g}",
        ("inversion",),
        _inversion("accel_mse_g2", PAPER_ACCEL_MSE_G2, "g²"),
    ),
    Claim(
        "inversion_gyro_mse",
        f"The inversion recovers the angular rate with an MSE of about {PAPER_GYRO_MSE_DPS2:g} "
        "(°/s)² (§5.2).",
        "fig 12",
        f"holds within a factor {INVERSION_HOLDS_FACTOR:g} of {PAPER_GYRO_MSE_DPS2:g} (°/s)², "
        f"partly within a factor {INVERSION_PARTLY_FACTOR:g}",
        ("inversion",),
        _inversion("gyro_mse_dps2", PAPER_GYRO_MSE_DPS2, "(°/s)²"),
    ),
    Claim(
        "calibration_helps_first_150s",
        "With 6 satellites the calibration clearly improves the navigation, especially during "
        "the first 150 s (§5.3.1).",
        "figs 14-15",
        f"holds if calibration lowers the RMS position error of the first 150 s by at least "
        f"{CLEAR_IMPROVEMENT:.0%} of the raw MEMS's, the paired difference exceeds "
        f"{SIGNIFICANT_STANDARD_ERRORS:g} standard errors, and the relative gain is larger than "
        "after 150 s; partly if the gain is significant but smaller or not concentrated early; "
        "does not hold otherwise",
        ("navigation_nominal",),
        _calibration_helps_early,
    ),
    Claim(
        "calibrated_mems_like_ins",
        "GPS/calibrated MEMS performs similarly to the usual GPS/INS coupling (§5.3.1).",
        "fig 15",
        f"holds if the calibrated MEMS's RMS position error after 150 s is at most "
        f"{LIKE_INS_HOLDS_RATIO:g} times the INS's, partly up to {LIKE_INS_PARTLY_RATIO:g} times",
        ("navigation_nominal",),
        _calibrated_like_ins,
    ),
    Claim(
        "mems_drifts_in_outage",
        "During a 30 s total outage the MEMS drifts much more than the INS (§5.3.2).",
        "figs 16-18",
        f"holds if the largest mean position error in the outage is at least "
        f"{DRIFTS_MUCH_MORE_RATIO:g} times the INS's, partly from {DRIFTS_PARTLY_RATIO:g} times",
        ("navigation_outage",),
        _mems_drifts,
    ),
    Claim(
        "calibration_helps_little_in_outage",
        "In the outage the calibration improves the MEMS only lightly; the drift comes from "
        "the sensors' noise (§5.3.2).",
        "figs 16-18",
        f"holds if calibration removes at most {LIGHT_IMPROVEMENT:.0%} of the raw MEMS's "
        f"largest mean outage error, partly up to {LIGHT_PARTLY_IMPROVEMENT:.0%}, does not "
        "hold beyond",
        ("navigation_outage",),
        _helps_little_in_outage,
    ),
)
"""The claims, in report order; their ids are stable."""


def completed(summary: dict[str, Any], experiment: str) -> bool:
    """Whether ``experiment`` (a key of ``summary["experiments"]``) ran to
    completion."""
    state = summary.get("experiments", {}).get(experiment)
    return state is not None and state["state"] == "completed"


def evaluate_claims(summary: dict[str, Any]) -> list[dict[str, Any]]:
    """Every claim of :data:`CLAIMS` judged from ``summary`` (the dict
    written as ``summary.json``): ``id``, ``paper``, ``figures``,
    ``memsnav`` (our figure with its standard error), ``criterion``,
    ``verdict`` and ``values`` (the numbers the verdict used)."""
    out = []
    for claim in CLAIMS:
        missing = [e for e in claim.needs if not completed(summary, e)]
        if missing:
            states = ", ".join(
                f"{e} {summary.get('experiments', {}).get(e, {}).get('state', 'not run')}"
                for e in missing
            )
            evaluation = Evaluation(NOT_EVALUATED, f"not evaluated: {states}", {})
        else:
            evaluation = claim.evaluate(summary)
        out.append(
            {
                "id": claim.id,
                "paper": claim.paper,
                "figures": claim.figures,
                "memsnav": evaluation.memsnav,
                "criterion": claim.criterion,
                "verdict": evaluation.verdict,
                "values": evaluation.values,
            }
        )
    return out
