"""Numbers as a reader meets them in a report or on the terminal: plain
digits where they fit ("1463", not "1.46e+03"), no "-0", a value and its
standard error rounded to the same place ("170 ± 10", not "171 ± 1e+01"),
an open interval written as such."""

from __future__ import annotations

import math
from typing import Any

MISSING = "—"
"""What a missing (None or non-finite) number reads as."""


def _finite(value: Any) -> bool:
    return value is not None and isinstance(value, int | float) and math.isfinite(value)


def number(value: Any, digits: int = 3) -> str:
    """``value`` to ``digits`` significant digits without trailing zeros, in
    plain notation from 1e-3 to 1e6 (integers in that range keep all their
    digits: "1463") and in scientific notation beyond; "—" when missing;
    never "-0"."""
    if not _finite(value):
        return MISSING
    if value == 0:
        return "0"
    magnitude = math.floor(math.log10(abs(value)))
    if -3 <= magnitude < 6:
        text, exponent = f"{value:.{max(digits - 1 - magnitude, 0)}f}", ""
    else:
        text, exponent = f"{value:.{digits - 1}e}".split("e")
        exponent = "e" + exponent
    if "." in text:
        text = text.rstrip("0").rstrip(".")
    # A value that rounds to zero reads "0", whatever its sign.
    return "0" if float(text) == 0 else text + exponent


def beside(value: Any, limit: Any, digits: int = 2) -> str:
    """``value`` as :func:`number` writes it, with more digits (up to six)
    where fewer would print it equal to ``limit`` or on its other side: a
    p95 of 9.995 m against a 10 m requirement reads "9.995", not "10"."""
    text = number(value, digits)
    if not (_finite(value) and _finite(limit)) or value == limit:
        return text
    while digits < 6 and (float(text) - limit) * (value - limit) <= 0:
        digits += 1
        text = number(value, digits)
    return text


def plus_minus(value: Any, standard_error: Any, digits: int = 3) -> str:
    """``value ± standard_error``, the error to one significant digit and the
    value rounded to the same decimal place ("0.051 ± 0.006", "170 ± 10");
    just the value when the error is missing or zero."""
    if not _finite(value):
        return MISSING
    if not _finite(standard_error) or standard_error == 0:
        return number(value, digits)
    error = abs(standard_error)
    place = math.floor(math.log10(error))
    # One significant digit, unless it rounds up to the next power of ten.
    error = round(error, -place)
    place = math.floor(math.log10(error))
    magnitude = math.floor(math.log10(max(abs(value), error)))
    if -3 <= magnitude < 6 and place >= -6:
        decimals = max(-place, 0)
        # + 0.0 turns a rounded -0.0 into 0.0.
        return f"{round(value, -place) + 0.0:.{decimals}f} ± {error:.{decimals}f}"
    # Scientific: both on the value's power of ten.
    scale = 10.0**magnitude
    decimals = max(magnitude - place, 0)
    return f"({value / scale:.{decimals}f} ± {error / scale:.{decimals}f})e{magnitude:+03d}"


def interval(lower: Any, upper: Any, digits: int = 3, limit: Any = None) -> str:
    """A confidence interval "[a, b]", an open end as "∞" ("[7.5, ∞)");
    each end on its side of ``limit`` when one is given (:func:`beside`)."""
    low = beside(lower, limit, digits) if _finite(lower) else "−∞"
    high = beside(upper, limit, digits) if _finite(upper) else "∞"
    return f"{'[' if _finite(lower) else '('}{low}, {high}{']' if _finite(upper) else ')'}"


def percent(share: Any, digits: int = 0) -> str:
    """A share (0-1) as a percentage, "—" when missing."""
    return MISSING if not _finite(share) else f"{100.0 * share:.{digits}f} %"
