"""The studio's remembered answers are the core's for the values of each edit, bit for bit."""
from __future__ import annotations

import numpy as np
import pytest

from .studio_support import CONFIG_DIR

from cam_ros.core import InvalidParameter, read_parameters_file
from cam_ros.core.machine import check_interference
from cam_ros.core.machine.served import machine_from_values
from cam_ros.studio.document import typed_value
from cam_ros.studio.memory import machine_and_checks

#: Edits made one after the other: an axis's phase, a pair's limit, the machine's speed, back.
EDITS = [('knife.master.offset_deg', 60.0), ('interference.min_clearance', [40.0, 0.0]),
         ('cam_speed', 12.0), ('jaw.motion.end_position', [0.0, 70.0, 70.0, 0.0, 0.0]),
         ('jaw.motion.start_position', [0.0, 0.0, 70.0, 70.0, 0.0]),
         ('knife.master.offset_deg', 100.0), ('cam_speed', 10.471975511965978)]


def test_each_edit_gets_the_cores_own_answers() -> None:
    values = read_parameters_file(CONFIG_DIR / 'machine.yaml')
    theta = np.linspace(0.0, 2.0 * np.pi, 997)
    refused, collided = 0, 0
    for key, value in EDITS:
        values[key] = value
        try:
            fresh = machine_from_values(values)
        except InvalidParameter as err:
            with pytest.raises(InvalidParameter) as raised:
                machine_and_checks(values)
            assert str(raised.value) == str(err)
            refused += 1
            continue
        machine, checks = machine_and_checks(values)
        assert checks == check_interference(fresh)
        collided += not all(check.ok for check in checks)
        assert np.array_equal(machine.positions(theta), fresh.positions(theta))
        for kept, built in zip(machine.axes, fresh.axes):
            assert kept.design.ok == built.design.ok
            assert kept.design.warnings() == built.design.warnings()
            assert kept.design.config.cam_speed == built.design.config.cam_speed
    assert (refused, collided) == (1, 2)  # the jaw's end alone; gap < 40 mm at 200 mm, 80 mm


def test_a_text_typed_again_is_its_kept_value_and_a_refusal_names_each_key() -> None:
    assert typed_value('cam_speed', '.nan') is typed_value('cam_speed', '.nan')  # kept
    assert typed_value('a.offset', '4') == 4 and type(typed_value('a.offset', '4')) is int
    assert type(typed_value('a.offset', '4.0')) is float
    for key in ('a.motion.laws[1]', 'b.motion.laws[1]'):  # a refusal is never kept
        with pytest.raises(InvalidParameter) as raised:
            typed_value(key, '[cycloidal, dwell]')
        assert raised.value.parameter == key


def test_a_new_cam_speed_checks_no_pair_again_and_a_phase_shift_its_pairs_only() -> None:
    values = read_parameters_file(CONFIG_DIR / 'machine.yaml')
    _, checks = machine_and_checks(values)
    values['cam_speed'] = 2.0 * values['cam_speed']  # the positions over the angle stay
    _, again = machine_and_checks(values)
    assert all(kept is before for kept, before in zip(again, checks))
    values['knife.master.offset_deg'] = 90.0  # pair 1 (jaw-knife) reads the knife
    _, shifted = machine_and_checks(values)
    assert shifted[0] is again[0] and shifted[1] is not again[1]
    assert shifted == check_interference(machine_from_values(values))
