"""Printed figures: ceil_sig reads back at or above the value (as a double), floor_sig at or
below, within one unit of the last digit, checked with exact rational arithmetic (fractions)."""
from fractions import Fraction

import numpy as np
import pytest

from cam_ros.core.rounding import ceil_sig, floor_sig


def last_digit(value: Fraction, digits: int) -> Fraction:
    """Return one unit of the last of digits significant digits of value, exactly."""
    magnitude = abs(value)
    exponent = 0  # floor(log10 |value|), exactly
    while Fraction(10) ** exponent > magnitude:
        exponent -= 1
    while Fraction(10) ** (exponent + 1) <= magnitude:
        exponent += 1
    return Fraction(10) ** (exponent - digits + 1)


def check(value: float, digits: int = 6) -> str:
    text = ceil_sig(value, digits)
    assert 'e' not in text.lower()
    printed, exact = Fraction(text), Fraction(value)
    unit = last_digit(exact, digits)
    assert float(text) >= value and printed < exact + unit, (value, text)
    significant = text.replace('.', '').lstrip('0')
    assert len(significant.rstrip('0')) <= digits or printed == int(printed)
    return text


@pytest.mark.parametrize('value, text', [
    (0.5, '0.5'), (1.0, '1'), (0.99999999, '1'), (1.0000001, '1.00001'),
    (9.999941e-5, '0.0000999995'), (9.999995e-5, '0.0001'), (123456.1, '123457'),
    (999999.5, '1000000'),
    (2.0e-7, '0.0000002'), (0.1, '0.1'), (1 / 3, '0.333334'), (2 / 3, '0.666667')])
def test_known_values_round_up(value, text):
    assert check(value) == text


def test_a_figure_rounded_to_nearest_would_read_below_it():
    # 0.1234564 rounds to 0.123456 to nearest, below the truth; rounded up it is 0.123457.
    assert f'{0.1234564:.6g}' == '0.123456' and check(0.1234564) == '0.123457'


def test_random_values_over_many_decades_read_back_at_or_above_within_one_unit():
    generator = np.random.default_rng(38)
    for value in 10.0 ** generator.uniform(-12, 9, 3000):
        check(float(value))
    for value in generator.uniform(0, 1, 300):
        check(float(value), 3)


@pytest.mark.parametrize('value', [0.0, -0.0])
def test_zero_is_zero(value):
    assert ceil_sig(value) == '0.0'


def check_floor(value: float, digits: int = 6) -> str:
    """Check floor_sig: reads back at or below value, within one unit of its last digit."""
    text = floor_sig(value, digits)
    assert 'e' not in text.lower()
    printed, exact = Fraction(text), Fraction(value)
    unit = last_digit(exact, digits)
    assert float(text) <= value and printed > exact - unit, (value, text)
    return text


@pytest.mark.parametrize('value, text', [
    (0.5, '0.5'), (1.0, '1'), (0.99999999, '0.999999'), (1.0000001, '1'),
    (0.032488502324677, '0.0324885'), (32.488502324677, '32.4885'), (0.1, '0.1'),
    (1 / 3, '0.333333'), (2 / 3, '0.666666'), (-1 / 3, '-0.333334'), (-0.5, '-0.5'),
    (70.54, '70.54'), (999999.5, '999999')])
def test_known_values_round_down(value, text):
    assert check_floor(value) == text


def test_a_smallest_gap_rounded_to_nearest_would_read_above_it():
    # 0.1234566 rounds to 0.123457 to nearest, above the truth; rounded down it is 0.123456.
    assert f'{0.1234566:.6g}' == '0.123457' and check_floor(0.1234566) == '0.123456'


def test_random_values_of_both_signs_read_back_at_or_below_within_one_unit():
    generator = np.random.default_rng(39)
    signs = generator.choice((-1.0, 1.0), 3000)
    for value in signs * 10.0 ** generator.uniform(-12, 9, 3000):
        check_floor(float(value))
    for value in generator.uniform(-1, 1, 300):
        check_floor(float(value), 3)
