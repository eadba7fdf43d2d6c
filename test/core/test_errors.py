"""Error messages: one short line whatever value is quoted."""
from __future__ import annotations

import math

import pytest

from cam_ros.core import InvalidParameter
from cam_ros.core.errors import QUOTE_LIMIT, quote


@pytest.mark.parametrize('value', [0.5, -1e300, math.nan, None, True, 'cm', [0.0, 90.0],
                                   (0.0, 0.7), [], {'a': 1}, 'x' * (QUOTE_LIMIT - 2)])
def test_short_values_are_quoted_as_repr(value):
    assert quote(value) == repr(value)


def test_a_long_list_shows_whole_leading_entries_and_its_length():
    text = quote([0.25] * 1_000_000)
    assert text.startswith('[0.25, 0.25, ') and text.endswith(', ... (1000000 items)')
    shown = text.removesuffix('... (1000000 items)')
    assert len(shown) <= QUOTE_LIMIT and shown.count('0.25') == shown.count(',')


def test_a_long_string_shows_its_start_its_end_and_length():
    text = quote('/' + 'd' * 1000 + '/cam.yaml')
    assert text.startswith("'/ddd") and text.endswith("ddd/cam.yaml' (1010 characters)")
    assert len(text.removesuffix(' (1010 characters)')) <= QUOTE_LIMIT
    assert len(quote('\x00' * 1000)) <= QUOTE_LIMIT + len(' (1000 characters)')


def test_nested_and_mapping_values_are_cut_too():
    assert len(quote({'a': [1] * 1000})) <= QUOTE_LIMIT
    assert len(quote([['x' * 500] * 10])) <= QUOTE_LIMIT + len(' (1 items)')


def test_the_message_bounds_the_value_and_the_name():
    message = str(InvalidParameter('n' * 1000, list(range(10**6)), 'must be short'))
    assert message == (f'{"n" * QUOTE_LIMIT}... = {quote(list(range(10**6)))}: must be short')
    assert len(message) < 3 * QUOTE_LIMIT
