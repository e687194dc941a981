"""Numbers as the reports print them (memsnav.report.numbers): the
findings of the report review ("171 ± 1e+01" in the partial-outage table, held
parameters as "-0", "132 windows of 2.00002 s") each as a case, and the
rounding checked against the value it stands for."""

import math

import pytest

from memsnav.report.numbers import MISSING, beside, interval, number, percent, plus_minus


@pytest.mark.parametrize(
    ("value", "text"),
    [
        (-0.0, "0"),
        (-1e-12, "-1e-12"),  # a tiny negative number is not rounded to "-0"
        (-0.0004, "-4e-04"),
        (0.00049999, "5e-04"),
        (-0.0000001, "-1e-07"),
        (2.00002, "2"),  # a window of 2.00002 s
        (1463.0, "1463"),
        (1463.4, "1463"),
        (0.05123, "0.0512"),
        (1.46e7, "1.46e+07"),
        (None, MISSING),
        (math.nan, MISSING),
        (math.inf, MISSING),
    ],
)
def test_number(value, text):
    assert number(value) == text


def test_number_never_prints_minus_zero():
    """A value that rounds to zero at the digits shown reads "0"."""
    for value in (-0.0, -1e-300, -4e-13):
        assert not number(value).startswith("-0")
    for digits in (1, 2, 3, 5):
        for value in (-0.0049, -0.4, -0.00049):
            text = number(value, digits)
            assert text != "-0" and float(text) == pytest.approx(value, rel=10 ** (1 - digits))


@pytest.mark.parametrize(
    ("value", "error", "text"),
    [
        (171.3, 12.0, "170 ± 10"),  # was "171 ± 1e+01"
        (171.0, 0.96, "171 ± 1"),
        (0.0512, 0.0061, "0.051 ± 0.006"),
        (0.0512, 0.0096, "0.05 ± 0.01"),  # 0.0096 rounds up to the next power of ten
        (-0.0004, 0.01, "0.00 ± 0.01"),  # not "-0.00"
        (99.6, 0.04, "99.60 ± 0.04"),
        (1.5e7, 2e5, "(1.50 ± 0.02)e+07"),
        (3.0e-8, 1e-9, "(3.0 ± 0.1)e-08"),
        (171.3, None, "171"),
        (171.3, 0.0, "171"),
        (None, 1.0, MISSING),
    ],
)
def test_plus_minus(value, error, text):
    assert plus_minus(value, error) == text


def test_plus_minus_rounds_the_value_to_its_error():
    """Over many magnitudes: the printed error has one significant digit
    and is within rounding of the true one, and the printed value within
    half that digit of the true value."""
    for value in (-0.0731, 0.51234, 3.14159, 171.3, 2.0e3 + 7.1, 65432.1):
        for error in (3e-4, 0.0123, 0.25, 4.4, 96.0, 1234.0):
            text = plus_minus(value, error)
            shown, shown_error = (float(t) for t in text.split(" ± "))
            assert "e" not in text and not text.startswith("-0 ")
            digits = shown_error / 10 ** math.floor(math.log10(shown_error))
            assert digits == pytest.approx(round(digits)), text
            assert 0.5 * error <= shown_error <= 2.0 * error, text
            assert abs(shown - value) <= 0.5 * shown_error + 1e-12, text


def test_interval_and_percent():
    assert interval(7.5, 12.26) == "[7.5, 12.3]"
    assert interval(7.5, None) == "[7.5, ∞)"
    assert interval(7.5, math.inf) == "[7.5, ∞)"
    assert interval(None, 3.0) == "(−∞, 3]"
    assert percent(0.989) == "99 %"
    assert percent(0.9891, 1) == "98.9 %"
    assert percent(None) == MISSING


@pytest.mark.parametrize(
    ("value", "limit", "text"),
    [
        (9.994908, 10.0, "9.99"),  # the study's p95 that printed "10" against 10 m
        (10.04, 10.0, "10.04"),
        (10.0, 10.0, "10"),
        (9.4, 10.0, "9.4"),
        (5.585, 10.0, "5.6"),
        (9.9999999, 10.0, "10"),  # beyond six digits: as close as it prints
        (0.0999, 0.1, "0.0999"),
        (7.3, None, "7.3"),
        (None, 10.0, MISSING),
    ],
)
def test_beside_keeps_a_figure_on_its_side_of_the_limit(value, limit, text):
    assert beside(value, limit) == text


def test_an_interval_end_on_its_side_of_the_limit():
    assert interval(7.006, 10.02, digits=2, limit=10.0) == "[7, 10.02]"
    assert interval(7.006, None, digits=2, limit=10.0) == "[7, ∞)"
