"""CamDesign.evaluate at one angle (computed in floats) gives a batch's numbers, bit for bit."""
from __future__ import annotations

import math
from pathlib import Path

import numpy as np
import pytest

from cam_ros.core import build_design
from cam_ros.core.config.params_file import read_parameters_file
from cam_ros.core.config.schema import parse_parameters
from test_dynamics import OSCILLATING, roller_cam

CONFIG_DIR = Path(__file__).resolve().parents[2] / 'config'
TWO_PI = 2.0 * math.pi
FIELDS = ('angle', 'position', 'velocity', 'acceleration', 'jerk', 'ds', 'd2s', 'd3s',
          'pressure_angle', 'radius_of_curvature')
FORCES = ('follower_force', 'spring_force', 'contact_force', 'camshaft_torque', 'contact_stress')
#: Joints, their neighbours one ulp away, both ends of a turn, turns before and after.
ANGLES = np.concatenate([
    np.linspace(-3 * TWO_PI, 4 * TWO_PI, 97),
    [0.0, -0.0, -1e-20, TWO_PI, np.nextafter(TWO_PI, 0.0), math.pi / 2, np.nextafter(math.pi, 4),
     4 * math.pi / 3, np.nextafter(4 * math.pi / 3, 0.0), 1e6, -12.5]])


def config_design(name: str):
    return build_design(parse_parameters(read_parameters_file(CONFIG_DIR / name)))


DESIGNS = {
    **{path.stem: path.name for path in sorted(CONFIG_DIR.glob('*.yaml'))
       if 'axes' not in read_parameters_file(path)},  # single cams, not machine files
    'arm-roller': {'follower.type': 'oscillating_roller', **OSCILLATING},
    'arm-flat-with-cam': {'follower.type': 'oscillating_flat', 'follower.face_offset': -1.5,
                          'follower.arm_turns_with_cam': True, **OSCILLATING},
    'flat-dynamics': {'follower.type': 'translating_flat'},
    'roller-ccw-dynamics': {'rotation': 'counterclockwise', 'follower.offset': -0.7},
}


@pytest.mark.parametrize('name', DESIGNS)
def test_one_angle_gives_the_batch_numbers_bit_for_bit(name):
    source = DESIGNS[name]
    cam = (config_design(source) if isinstance(source, str)
           else build_design(parse_parameters(roller_cam(**source))))
    batch = cam.evaluate(ANGLES)
    for index, angle in enumerate(ANGLES):
        one = cam.evaluate([angle])
        for field in FIELDS:
            value = getattr(one, field)
            expected = getattr(batch, field)
            assert value.shape == (1,), field
            assert (value.dtype, value.flags.writeable) == (
                expected.dtype, expected.flags.writeable), field
            np.testing.assert_array_equal(value, expected[index:index + 1],
                                          err_msg=f'{name}: {field} at {angle!r}')
        assert (one.dynamics is None) == (batch.dynamics is None)
        for field in FORCES if one.dynamics is not None else ():
            np.testing.assert_array_equal(getattr(one.dynamics, field),
                                          getattr(batch.dynamics, field)[index:index + 1],
                                          err_msg=f'{name}: {field} at {angle!r}')
