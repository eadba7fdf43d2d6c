"""Each table segment has its own points: motion.table_counts splits table_u/table_y."""
from __future__ import annotations

from pathlib import Path

import numpy as np
import pytest

from cam_ros.core import InvalidParameter, build_design, parse_parameters, read_parameters_file

DEFAULT = Path(__file__).resolve().parents[2] / 'config' / 'default.yaml'
#: Two different shapes: a rise that is early (fast start) and one that is late.
EARLY = ([0.0, 0.3, 1.0], [0.0, 0.6, 1.0])
LATE = ([0.0, 0.5, 0.8, 1.0], [0.0, 0.2, 0.5, 1.0])


def table_design(**motion):
    values = read_parameters_file(DEFAULT)
    values.update({'motion.laws': ['dwell', 'table', 'dwell', 'table'], **motion})
    return build_design(parse_parameters(values))


def test_each_table_segment_passes_through_its_own_points():
    design = table_design(**{'motion.table_u': EARLY[0] + LATE[0],
                             'motion.table_y': EARLY[1] + LATE[1],
                             'motion.table_counts': [3, 4]})
    rise, back = design.program.segments[1], design.program.segments[3]
    for segment, (u, y) in ((rise, EARLY), (back, LATE)):
        theta = segment.start + np.asarray(u) * segment.span
        s = design.program.evaluate(theta).s
        expected = segment.s_start + (segment.s_end - segment.s_start) * np.asarray(y)
        np.testing.assert_allclose(s, expected, rtol=0, atol=1e-12)


def test_two_table_segments_without_counts_are_refused_not_shared():
    with pytest.raises(InvalidParameter) as caught:
        table_design(**{'motion.table_u': EARLY[0], 'motion.table_y': EARLY[1]})
    message = str(caught.value)
    assert message.startswith('motion.table_counts = []')
    assert 'one entry per table segment (2: segments 1, 3)' in message


@pytest.mark.parametrize('counts, fragment', [
    ([3], 'one entry per table segment (2'),
    ([3, 3], 'adding up to the 7 motion.table_u points'),
    ([1, 6], 'counts of at least 2'),
])
def test_bad_counts_name_the_rule(counts, fragment):
    with pytest.raises(InvalidParameter) as caught:
        table_design(**{'motion.table_u': EARLY[0] + LATE[0],
                        'motion.table_y': EARLY[1] + LATE[1], 'motion.table_counts': counts})
    assert str(caught.value).startswith(f'motion.table_counts = {counts}') and \
        fragment in str(caught.value)


def test_one_table_segment_still_takes_all_points():
    values = read_parameters_file(DEFAULT)
    values.update({'motion.laws': ['dwell', 'table', 'dwell', 'simple_harmonic'],
                   'motion.table_u': LATE[0], 'motion.table_y': LATE[1]})
    program = build_design(parse_parameters(values)).program
    segment = program.segments[1]
    inner = segment.start + np.asarray(LATE[0]) * segment.span
    expected = segment.s_start + (segment.s_end - segment.s_start) * np.asarray(LATE[1])
    np.testing.assert_allclose(program.evaluate(inner).s, expected, rtol=0, atol=1e-12)
