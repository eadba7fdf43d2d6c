"""Following error: the command at a report's stamp from the commands issued, and the watch."""
from __future__ import annotations

import numpy as np
import pytest

from cam_ros.core.ecam.following_error import CommandHistory, ErrorWatch

MS = 1_000_000


def cubic(t):
    """A command whose position is a cubic of time (s): Hermite interpolation is exact for it."""
    return 0.1 + 0.5 * t - 2.0 * t ** 2 + 3.0 * t ** 3, 0.5 - 4.0 * t + 9.0 * t ** 2


def test_the_reference_between_commands_is_the_cubic_through_them():
    history = CommandHistory()
    stamps = np.cumsum([0, 4, 3, 5, 4]) * MS + 10 * MS  # irregular: 250 to 333 Hz
    for stamp in stamps:
        position, velocity = cubic(stamp * 1e-9)
        history.add(int(stamp), [position, -position], [velocity, -velocity])
    for stamp in np.linspace(stamps[0], stamps[-1], 57).astype(int):
        reference = history.reference(1, int(stamp))
        position, velocity = cubic(stamp * 1e-9)
        assert reference.position == pytest.approx(-position, abs=1e-15)
        assert reference.velocity == pytest.approx(-velocity, abs=1e-12)
    at_a_command = history.reference(0, int(stamps[2]))
    assert at_a_command == cubic(stamps[2] * 1e-9)  # exact at a command's own stamp


def test_a_report_after_the_last_command_carries_it_on_and_one_before_the_first_has_none():
    history = CommandHistory(keep_ns=100 * MS)
    history.add(50 * MS, [1.0], [2.0])
    history.add(60 * MS, [1.02], [2.0])
    assert history.reference(0, 49 * MS) is None
    assert history.reference(0, 70 * MS) == pytest.approx((1.04, 2.0), abs=1e-15)
    history.add(200 * MS, [5.0], [0.0])  # the first two fall out of the kept 100 ms
    assert history.reference(0, 60 * MS) is None
    history.add(150 * MS, [9.0], [0.0])  # older than the last: the last command stands
    assert history.reference(0, 250 * MS) == (5.0, 0.0)


def test_the_watch_faults_after_the_error_stayed_over_the_limit_for_its_time():
    watch = ErrorWatch(0.002, 30 * MS)
    over = [watch.update(k * MS, 0.0025) for k in range(0, 40, 5)]
    assert over == [False] * 6 + [True] * 2  # from 0 ms on: at 30 ms, not before
    assert not watch.update(41 * MS, 0.001)  # back within: the time starts again
    assert not watch.update(45 * MS, -0.003) and watch.update(75 * MS, -0.003)
    assert not ErrorWatch(0.0, 0).update(0, 1e9)  # limit 0: not checked
    assert ErrorWatch(0.001, 0).update(5, 0.0011)  # time 0: at once
