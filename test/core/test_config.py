"""The config format: shipped files load, units convert, and every bad file names its problem."""
from __future__ import annotations

import math
from pathlib import Path

import numpy as np
import pytest
import yaml

from cam_ros.core import InvalidParameter, build_design, load_config
from cam_ros.core.config.parameters import PARAMETERS
from cam_ros.core.config.params_file import flatten, read_parameters_file
from cam_ros.core.config.schema import parse_parameters

CONFIG_DIR = Path(__file__).resolve().parents[2] / 'config'
SHIPPED = sorted(path for path in CONFIG_DIR.glob('*.yaml')  # single cams; machines: test_machine
                 if 'axes' not in read_parameters_file(path))
DEFAULT_TEXT = (CONFIG_DIR / 'default.yaml').read_text()


def write(tmp_path: Path, text: str) -> Path:
    path = tmp_path / 'cam.yaml'
    path.write_text(text)
    return path


def edited(old: str, new: str) -> str:
    assert old in DEFAULT_TEXT, old
    return DEFAULT_TEXT.replace(old, new)


@pytest.mark.parametrize('path', SHIPPED, ids=[p.name for p in SHIPPED])
def test_every_shipped_config_builds_a_design(path):
    design = build_design(load_config(path))
    assert design.profile(36).position.shape == (36,)


def test_default_is_seed_roller():
    default, seed = CONFIG_DIR / 'default.yaml', CONFIG_DIR / 'seed_roller.yaml'
    assert default.read_text() == seed.read_text()


def test_lengths_convert_from_the_declared_unit_and_angles_from_degrees():
    config = load_config(CONFIG_DIR / 'default.yaml')  # cm
    assert config.follower.base_radius == pytest.approx(0.04)
    assert config.follower.offset == pytest.approx(0.005)
    assert config.motion.end_position[1] == pytest.approx(0.02)
    assert config.motion.start[3] == pytest.approx(4 * math.pi / 3)
    inches = load_config(CONFIG_DIR / 'handbook_4567.yaml')
    assert inches.motion.end_position[0] == pytest.approx(0.5 * 0.0254)
    millimetres = load_config(CONFIG_DIR / 'seed_via_point.yaml')
    assert millimetres.motion.via_position == pytest.approx((0.16, 0.16))


def test_exponent_floats_read_as_numbers_as_ros_reads_them(tmp_path):
    # PyYAML's YAML 1.1 reads 6.0e0 and 1e3 as strings; ROS's parameter parser as doubles.
    text = edited('cam_speed: 6.283185307179586', 'cam_speed: 6.0e0')
    text = text.replace('sample_count: 360', 'sample_count: 360\n      state_rate_hz: 1e2')
    text = text.replace('      state_rate_hz: 50.0\n', '')
    config = load_config(write(tmp_path, text))
    assert (config.cam_speed, config.state_rate_hz) == (6.0, 100.0)


def test_the_same_cam_in_two_units_is_the_same_design():
    metres = edited('length_unit: cm', 'length_unit: m')
    for name in ('base_radius: 4.0', 'roller_radius: 1.0', 'offset: 0.5'):
        key, value = name.split(': ')
        metres = metres.replace(name, f'{key}: {float(value) / 100!r}')
    metres = metres.replace('[0.0, 0.0, 2.0, 2.0]', '[0.0, 0.0, 0.02, 0.02]')
    metres = metres.replace('[0.0, 2.0, 2.0, 0.0]', '[0.0, 0.02, 0.02, 0.0]')
    metres = metres.replace('min_radius_of_curvature: 0.5', 'min_radius_of_curvature: 0.005')
    in_cm = build_design(parse_parameters(read_parameters_file(CONFIG_DIR / 'default.yaml')))
    in_m = build_design(parse_parameters(flatten(yaml.safe_load(metres)['/**'][
        'ros__parameters'])))
    a, b = in_cm.profile(90), in_m.profile(90)
    np.testing.assert_allclose(a.position, b.position, rtol=1e-12, atol=1e-15)
    np.testing.assert_allclose(a.radius_of_curvature, b.radius_of_curvature, rtol=1e-9)


@pytest.mark.parametrize('text, parameter, fragment', [
    (edited('roller_radius: 1.0', 'rollr_radius: 1.0'), 'follower.rollr_radius',
     'did you mean follower.roller_radius'),
    (edited('base_radius: 4.0', 'base_radius: 4'), 'follower.base_radius', 'write 1.0, not 1'),
    (edited('base_radius: 4.0', 'base_radius: "big"'), 'follower.base_radius', 'must be a double'),
    (edited('length_unit: cm', 'length_unit: furlong'), 'length_unit', 'one of m, cm, mm, in'),
    (edited('type: translating_roller', 'type: rocking_horse'), 'follower.type', 'one of'),
    (edited('      base_radius: 4.0\n', ''), 'follower.base_radius', 'is required'),
    (edited('base_radius: 4.0', 'base_radius: .nan'), 'follower.base_radius', 'finite'),
    (edited('roller_radius: 1.0', 'roller_radius: -1.0'), 'follower.roller_radius', '>= 0'),
    (edited('end_deg: [90.0, 180.0, 240.0, 360.0]', 'end_deg: [90.0, 180.0, 360.0]'),
     'motion.end_deg', 'must have 4 entries'),
    (edited('start_deg: [0.0, 90.0, 180.0, 240.0]', 'start_deg: [0, 90, 180, 240]'),
     'motion.start_deg', 'list of doubles'),
    (edited('sample_count: 360', 'sample_count: 360.0'), 'output.sample_count',
     'must be an integer'),
    (edited('sample_count: 360', 'sample_count: 2'), 'output.sample_count', '>= 8'),
])
def test_bad_values_name_parameter_value_and_rule(tmp_path, text, parameter, fragment):
    with pytest.raises(InvalidParameter) as caught:
        load_config(write(tmp_path, text))
    assert caught.value.parameter == parameter
    assert fragment in str(caught.value)


@pytest.mark.parametrize('text, fragment', [
    ('', 'must be a mapping'),
    ('cam: [1, 2\n', 'not valid YAML'),
    ('other_node:\n  ros__parameters:\n    length_unit: m\n', 'needs one of cam, /cam, /**'),
])
def test_broken_files_say_what_is_wrong(tmp_path, text, fragment):
    with pytest.raises(InvalidParameter) as caught:
        load_config(write(tmp_path, text))
    assert caught.value.parameter == 'config'
    assert fragment in str(caught.value)


def test_missing_file_is_a_clear_error(tmp_path):
    with pytest.raises(InvalidParameter, match='cannot be read'):
        load_config(tmp_path / 'nope.yaml')


def test_every_parameter_has_a_description_and_a_ros_type():
    names = [spec.name for spec in PARAMETERS]
    assert len(names) == len(set(names))
    for spec in PARAMETERS:
        assert spec.description
        assert spec.type in {'double', 'integer', 'string', 'bool', 'double_array',
                             'integer_array', 'string_array'}


def test_rclpy_node_parameters_are_type_checked_and_left_out_of_the_design(tmp_path):
    text = edited('    length_unit: cm', '    use_sim_time: true\n    length_unit: cm')
    config = load_config(write(tmp_path, text))
    assert 'use_sim_time' not in config.parameters
    with pytest.raises(InvalidParameter, match=r'^use_sim_time = 1: must be a bool$'):
        load_config(write(tmp_path, text.replace('use_sim_time: true', 'use_sim_time: 1')))
    with pytest.raises(InvalidParameter, match='is not a cam parameter'):
        load_config(write(tmp_path, text.replace('use_sim_time', 'use_sim_tme')))
