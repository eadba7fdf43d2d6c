"""An engagement's moves checked together (core/ecam/engagement.py) when one axis cannot move:
the check sees it holding where it stands (its start position, at rest, over the other axis's
whole move), its own reason is kept, and a refusal of the check refuses every move with its
reason. References: the requests' own start positions and plan_move's answers.
"""
from __future__ import annotations

import numpy as np
from test_move_references import axis, DEFAULT

from cam_ros.core.ecam.engagement import plan_engagement
from cam_ros.core.ecam.moves import AxisState, MasterMotion, Move, MoveRequest
from cam_ros.core.ecam.slave_limits import CamPeaks

MASTER = MasterMotion(2.0)


def request(offset: float, **changes) -> MoveRequest:
    """config/default.yaml's axis (with changes) asked onto its cam from offset m off it."""
    cam, limits, unit, nominal = axis(DEFAULT, **changes)
    start = AxisState(float(cam.derivatives(MASTER.theta).y) + offset)
    return MoveRequest(cam, limits, start, MASTER, nominal, unit, CamPeaks.of(cam))


def requests() -> dict[str, MoveRequest]:
    """'slide' can move 1 cm up onto its cam; 'stuck' (negative-only, its cam 1 cm above it)
    cannot."""
    return {'slide': request(-0.01), 'stuck': request(-0.01, **{'slave.direction': 'negative'})}


def test_an_axis_that_cannot_move_is_checked_holding_where_it_stands():
    asked = requests()
    seen = []

    def check(moves, master):
        seen.append((dict(moves), master))
        return moves

    planned = plan_engagement(asked, {}, MASTER, check)
    assert planned['stuck'] == asked['stuck'].plan()
    assert 'against slave.direction' in planned['stuck']
    assert isinstance(planned['slide'], Move)
    ((moves, master),) = seen
    assert master == MASTER
    assert set(moves) == {'slide', 'stuck'}
    held = moves['stuck']
    assert held.duration == 0.0
    assert held.limits == asked['stuck'].limits
    times = np.linspace(0.0, moves['slide'].duration, 101)
    position, velocity, acceleration, _ = held.commands(times)
    np.testing.assert_array_equal(position, asked['stuck'].start.position)
    np.testing.assert_array_equal(velocity, 0.0)
    np.testing.assert_array_equal(acceleration, 0.0)


def test_a_refused_check_refuses_every_move_and_keeps_each_own_reason():
    asked = requests()
    planned = plan_engagement(asked, {}, MASTER, lambda moves, master: 'slide and stuck meet')
    assert planned == {'slide': 'slide and stuck meet', 'stuck': asked['stuck'].plan()}
