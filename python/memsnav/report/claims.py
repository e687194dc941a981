"""The paper's claims and their verdicts, computed from ``summary.json``.

Each claim has a stable id, a title in words, the paper's statement, the
figure memsnav measures for it (with its Monte Carlo standard error), and
a criterion fixed here, before any run, with its thresholds as named
constants. A criterion is a list of rules, each a verdict, the words that
say when it applies and the test of those words; the first rule that
applies gives the verdict, and the criterion the report prints is the
rules' own words. The verdict is one of ``holds``, ``partly``, ``does not
hold`` and ``not evaluated`` (an experiment it needs did not run to
completion). Verdicts compare point estimates with the thresholds, except
where a criterion asks for a significant difference (then in units of its
standard error); the standard errors are printed beside each figure so a
reader sees how close a verdict is.

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
from memsnav.report.numbers import number, plus_minus

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
class Measured:
    """What a claim's figures came to: the numbers a verdict uses, and the
    text that states them with their standard errors."""

    values: dict[str, float]
    memsnav: str


@dataclass(frozen=True)
class Rule:
    """One verdict of a criterion: the words that state when it applies and
    the test of those words on the measured values."""

    verdict: str
    condition: str
    applies: Callable[[dict[str, float]], bool]


def otherwise(verdict: str = DOES_NOT_HOLD) -> Rule:
    """The verdict when no earlier rule applies."""
    return Rule(verdict, "otherwise", lambda _: True)


@dataclass(frozen=True)
class Claim:
    """A claim of the paper and how memsnav judges it: ``rules`` in order,
    the first that applies gives the verdict, and the criterion printed
    beside it is those rules' own words, so the two cannot part."""

    id: str
    title: str
    paper: str
    figures: str
    needs: tuple[str, ...]
    measure: Callable[[dict[str, Any]], Measured]
    rules: tuple[Rule, ...]
    terms: str = ""
    """What the criterion's words mean, stated once before its rules."""

    @property
    def criterion(self) -> str:
        rules = "; ".join(
            f"{r.verdict} {r.condition}"
            if r.condition == "otherwise"
            else f"{r.verdict} if {r.condition}"
            for r in self.rules
        )
        return f"{self.terms}: {rules}" if self.terms else rules

    def verdict(self, values: dict[str, float]) -> str:
        """The first rule that applies to ``values``."""
        return next(r.verdict for r in self.rules if r.applies(values))


def _pm(value: float, se: float | None, digits: int = 3) -> str:
    """``value ± se`` (no ± when the standard error is unknown)."""
    if se is None or not math.isfinite(se):
        return f"{number(value, digits)} (standard error unknown)"
    return plus_minus(value, se, digits)


def window_words(window_key: str) -> str:
    """``first_150s`` -> ``first 150 s``."""
    return window_key.replace("_", " ").removesuffix("s") + " s"


def _normalized_rms(entry: dict[str, Any]) -> float:
    return math.sqrt(entry["normalized_mse_eiv"])


def _words(group: str) -> str:
    return group.replace("_", " ")


def _axes_measure(
    sensor: str, good: tuple[str, str], worse: tuple[str, str]
) -> Callable[[dict[str, Any]], Measured]:
    """Per output axis, the normalised RMS errors of the ``good`` groups and
    the ``worse`` ones, and the number of axes that pass (``axes_passing``
    of ``axes``): an axis passes when its ``good`` groups are well estimated
    and each ``worse`` group is estimated worse than both."""

    def measure(summary: dict[str, Any]) -> Measured:
        cal = summary["calibration"][sensor]
        axes = AXES[sensor]
        values: dict[str, float] = {
            f"{g}_{a}": _normalized_rms(cal[g]["per_axis"][a]) for g in good + worse for a in axes
        }
        passing = [
            a
            for a in axes
            if all(values[f"{g}_{a}"] <= WELL_ESTIMATED_NORMALIZED_RMS for g in good)
            and min(values[f"{w}_{a}"] for w in worse) > max(values[f"{g}_{a}"] for g in good)
        ]
        values["axes"] = len(axes)
        values["axes_passing"] = len(passing)
        text = "; ".join(
            f"{_words(g)}: " + ", ".join(f"{a} {number(values[f'{g}_{a}'], 2)}" for a in axes)
            for g in good + worse
        )
        return Measured(
            values,
            f"normalised RMS error (EIV): {text}; axes that pass: "
            + (", ".join(passing) or "none"),
        )

    return measure


_AXES_RULES = (
    Rule(HOLDS, "every output axis passes", lambda v: v["axes_passing"] == v["axes"]),
    Rule(PARTLY, "some axes pass", lambda v: v["axes_passing"] > 0),
    otherwise(),
)


def _axes_terms(good: tuple[str, str], worse: tuple[str, str]) -> str:
    return (
        f"an output axis passes when its {_words(good[0])} and {_words(good[1])} are well "
        f"estimated (normalised RMS error ≤ {WELL_ESTIMATED_NORMALIZED_RMS}: RMS error over the "
        f"sets at most {WELL_ESTIMATED_NORMALIZED_RMS:.0%} of the parameters' own RMS, "
        f"errors-in-variables estimator) and its {_words(worse[0])} and {_words(worse[1])} are "
        "estimated worse than both (larger normalised RMS error)"
    )


def _inversion(key: str, paper: float, unit: str) -> Callable[[dict[str, Any]], Measured]:
    def measure(summary: dict[str, Any]) -> Measured:
        inv = summary["inversion"]
        ours, se = inv[key], inv[key.replace("_mse_", "_mse_se_")]
        factor = max(ours / paper, paper / ours)
        return Measured(
            {"memsnav": ours, "standard_error": se, "paper": paper, "factor": factor},
            f"{_pm(ours, se)} {unit} (a factor {number(factor, 2)} from the paper's)",
        )

    return measure


def _inversion_rules(paper: float, unit: str) -> tuple[Rule, ...]:
    return (
        Rule(
            HOLDS,
            f"within a factor {INVERSION_HOLDS_FACTOR:g} of {paper:g} {unit}",
            lambda v: v["factor"] <= INVERSION_HOLDS_FACTOR,
        ),
        Rule(
            PARTLY,
            f"within a factor {INVERSION_PARTLY_FACTOR:g}",
            lambda v: v["factor"] <= INVERSION_PARTLY_FACTOR,
        ),
        otherwise(),
    )


def _nominal(summary: dict[str, Any]) -> dict[str, Any]:
    nominal: dict[str, Any] = summary["navigation"]["nominal"]
    return nominal


def _calibration_helps_early(summary: dict[str, Any]) -> Measured:
    nav = _nominal(summary)
    early, late = nav["early_key"], nav["late_key"]
    mems, cal = nav["imus"]["mems"], nav["imus"]["calibrated_mems"]
    d_early = nav["paired"][f"rms_position_error_{early}_m"]
    d_late = nav["paired"][f"rms_position_error_{late}_m"]
    base_early = mems[f"rms_position_error_{early}_m"]
    base_late = mems[f"rms_position_error_{late}_m"]
    se = d_early["standard_error"]
    key = f"rms_position_error_{early}_m"
    return Measured(
        {
            "gain_early_m": d_early["difference"],
            # Without a standard error (a single run) nothing is significant.
            "gain_early_standard_error_m": se if se is not None else math.nan,
            "relative_gain_early": d_early["difference"] / base_early,
            "relative_gain_late": d_late["difference"] / base_late,
        },
        f"RMS position error {window_words(early)}: MEMS "
        f"{_pm(base_early, mems['standard_error'][key])} m, "
        f"calibrated {_pm(cal[key], cal['standard_error'][key])} m; "
        f"paired gain {_pm(d_early['difference'], se)} m "
        f"({d_early['difference'] / base_early:.1%}); {window_words(late)}: gain "
        f"{_pm(d_late['difference'], d_late['standard_error'])} m "
        f"({d_late['difference'] / base_late:.1%})",
    )


def _significant(v: dict[str, float]) -> bool:
    se = v["gain_early_standard_error_m"]
    return math.isfinite(se) and v["gain_early_m"] > SIGNIFICANT_STANDARD_ERRORS * se


def _calibrated_like_ins(summary: dict[str, Any]) -> Measured:
    nav = _nominal(summary)
    key = f"rms_position_error_{nav['late_key']}_m"
    cal, ins = nav["imus"]["calibrated_mems"], nav["imus"]["ins"]
    ratio = cal[key] / ins[key]
    return Measured(
        {"calibrated_mems_m": cal[key], "ins_m": ins[key], "ratio": ratio},
        f"RMS position error {window_words(nav['late_key'])}: calibrated MEMS "
        f"{_pm(cal[key], cal['standard_error'][key])} m, INS "
        f"{_pm(ins[key], ins['standard_error'][key])} m (ratio {ratio:.2f})",
    )


_OUTAGE_KEY = "max_position_error_during_outage_m"


def _outage(summary: dict[str, Any]) -> dict[str, Any]:
    imus: dict[str, Any] = summary["navigation"]["outage"]["imus"]
    return imus


def _mems_drifts(summary: dict[str, Any]) -> Measured:
    o = _outage(summary)
    mems, ins = o["mems"], o["ins"]
    ratio = mems[_OUTAGE_KEY] / ins[_OUTAGE_KEY]
    return Measured(
        {"mems_m": mems[_OUTAGE_KEY], "ins_m": ins[_OUTAGE_KEY], "ratio": ratio},
        f"largest mean error in the outage: MEMS "
        f"{_pm(mems[_OUTAGE_KEY], mems['standard_error'][_OUTAGE_KEY])} m, INS "
        f"{_pm(ins[_OUTAGE_KEY], ins['standard_error'][_OUTAGE_KEY])} m (ratio {ratio:.1f})",
    )


def _helps_little_in_outage(summary: dict[str, Any]) -> Measured:
    o = _outage(summary)
    mems, cal = o["mems"], o["calibrated_mems"]
    reduction = 1.0 - cal[_OUTAGE_KEY] / mems[_OUTAGE_KEY]
    return Measured(
        {
            "mems_m": mems[_OUTAGE_KEY],
            "calibrated_mems_m": cal[_OUTAGE_KEY],
            "reduction": reduction,
        },
        f"largest mean error in the outage: MEMS "
        f"{_pm(mems[_OUTAGE_KEY], mems['standard_error'][_OUTAGE_KEY])} m, calibrated MEMS "
        f"{_pm(cal[_OUTAGE_KEY], cal['standard_error'][_OUTAGE_KEY])} m: calibration "
        f"removes {reduction:.0%} of it",
    )


_ACCEL = (("bias", "misalignment"), ("scale_factor", "nonlinearity"))
_GYRO = (("bias", "misalignment"), ("scale_factor", "g_sensitivity"))

CLAIMS: tuple[Claim, ...] = (
    Claim(
        "accel_bias_misalignment_well_estimated",
        "Accelerometer biases and misalignments well estimated",
        "The accelerometer biases and misalignments are well estimated; the scale factors and "
        "the nonlinearity are estimated worse (§5.1).",
        "figs 3-6",
        ("calibration",),
        _axes_measure("accelerometer", *_ACCEL),
        _AXES_RULES,
        _axes_terms(*_ACCEL),
    ),
    Claim(
        "gyro_bias_misalignment_well_estimated",
        "Gyro biases and misalignments well estimated",
        "The gyro biases and misalignments are well estimated; the scale factors and the "
        "g-sensitivity are estimated worse (§5.1).",
        "figs 7-10",
        ("calibration",),
        _axes_measure("gyroscope", *_GYRO),
        _AXES_RULES,
        _axes_terms(*_GYRO),
    ),
    Claim(
        "inversion_accel_mse",
        "Inversion recovers the specific force",
        f"The inversion recovers the specific force with an MSE of about {PAPER_ACCEL_MSE_G2:g} "
        "g² (§5.2).",
        "fig 11",
        ("inversion",),
        _inversion("accel_mse_g2", PAPER_ACCEL_MSE_G2, "g²"),
        _inversion_rules(PAPER_ACCEL_MSE_G2, "g²"),
    ),
    Claim(
        "inversion_gyro_mse",
        "Inversion recovers the angular rate",
        f"The inversion recovers the angular rate with an MSE of about {PAPER_GYRO_MSE_DPS2:g} "
        "(°/s)² (§5.2).",
        "fig 12",
        ("inversion",),
        _inversion("gyro_mse_dps2", PAPER_GYRO_MSE_DPS2, "(°/s)²"),
        _inversion_rules(PAPER_GYRO_MSE_DPS2, "(°/s)²"),
    ),
    Claim(
        "calibration_helps_first_150s",
        "Calibration clearly helps, most in the first 150 s",
        "With 6 satellites the calibration clearly improves the navigation, especially during "
        "the first 150 s (§5.3.1).",
        "figs 14-15",
        ("navigation_nominal",),
        _calibration_helps_early,
        (
            Rule(
                HOLDS,
                f"calibration lowers the RMS position error of the first 150 s by more than "
                f"{SIGNIFICANT_STANDARD_ERRORS:g} standard errors of the paired difference and "
                f"by at least {CLEAR_IMPROVEMENT:.0%} of the raw MEMS's, and the relative gain "
                "is larger than after 150 s",
                lambda v: (
                    _significant(v)
                    and v["relative_gain_early"] >= CLEAR_IMPROVEMENT
                    and v["relative_gain_early"] > v["relative_gain_late"]
                ),
            ),
            Rule(
                PARTLY,
                f"the gain exceeds {SIGNIFICANT_STANDARD_ERRORS:g} standard errors but is "
                "smaller or not concentrated early",
                _significant,
            ),
            otherwise(),
        ),
    ),
    Claim(
        "calibrated_mems_like_ins",
        "Calibrated MEMS performs like the INS",
        "GPS/calibrated MEMS performs similarly to the usual GPS/INS coupling (§5.3.1).",
        "fig 15",
        ("navigation_nominal",),
        _calibrated_like_ins,
        (
            Rule(
                HOLDS,
                f"the calibrated MEMS's RMS position error after 150 s is at most "
                f"{LIKE_INS_HOLDS_RATIO:g} times the INS's",
                lambda v: v["ratio"] <= LIKE_INS_HOLDS_RATIO,
            ),
            Rule(
                PARTLY,
                f"at most {LIKE_INS_PARTLY_RATIO:g} times",
                lambda v: v["ratio"] <= LIKE_INS_PARTLY_RATIO,
            ),
            otherwise(),
        ),
    ),
    Claim(
        "mems_drifts_in_outage",
        "MEMS drifts much more than the INS in a 30 s outage",
        "During a 30 s total outage the MEMS drifts much more than the INS (§5.3.2).",
        "figs 16-18",
        ("navigation_outage",),
        _mems_drifts,
        (
            Rule(
                HOLDS,
                f"the MEMS's largest mean position error in the outage is at least "
                f"{DRIFTS_MUCH_MORE_RATIO:g} times the INS's",
                lambda v: v["ratio"] >= DRIFTS_MUCH_MORE_RATIO,
            ),
            Rule(
                PARTLY,
                f"at least {DRIFTS_PARTLY_RATIO:g} times",
                lambda v: v["ratio"] >= DRIFTS_PARTLY_RATIO,
            ),
            otherwise(),
        ),
    ),
    Claim(
        "calibration_helps_little_in_outage",
        "Calibration helps only lightly in the outage",
        "In the outage the calibration improves the MEMS only lightly; the drift comes from "
        "the sensors' noise (§5.3.2).",
        "figs 16-18",
        ("navigation_outage",),
        _helps_little_in_outage,
        (
            Rule(
                HOLDS,
                f"calibration removes at most {LIGHT_IMPROVEMENT:.0%} of the raw MEMS's largest "
                "mean outage error",
                lambda v: v["reduction"] <= LIGHT_IMPROVEMENT,
            ),
            Rule(
                PARTLY,
                f"at most {LIGHT_PARTLY_IMPROVEMENT:.0%}",
                lambda v: v["reduction"] <= LIGHT_PARTLY_IMPROVEMENT,
            ),
            otherwise(),
        ),
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
    written as ``summary.json``): ``id``, ``title``, ``paper``, ``figures``,
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
            measured, verdict = Measured({}, f"not evaluated: {states}"), NOT_EVALUATED
        else:
            measured = claim.measure(summary)
            verdict = claim.verdict(measured.values)
        out.append(
            {
                "id": claim.id,
                "title": claim.title,
                "paper": claim.paper,
                "figures": claim.figures,
                "memsnav": measured.memsnav,
                "criterion": claim.criterion,
                "verdict": verdict,
                "values": measured.values,
            }
        )
    return out
