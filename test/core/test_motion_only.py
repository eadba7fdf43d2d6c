"""Motion-only designs (follower.type none): a rotary slave in deg that advances per cycle."""
from __future__ import annotations

import math

import numpy as np
import pytest
from conftest import CONFIG_DIR

from cam_ros.core import (build_design, InvalidParameter, load_config, parse_parameters,
                          read_parameters_file)
from cam_ros.core.ecam.cam_table import equidistant_table
from cam_ros.core.ecam.master import ElectronicCam, MasterConfig
from cam_ros.core.motion.laws import Cycloidal
from cam_ros.core.report import design_report

KNIFE = CONFIG_DIR / 'rotary_knife.yaml'
TWO_PI = 2.0 * math.pi
#: The knife of config/rotary_knife.yaml as its comments state it (independent of the file).
DRUM_RADIUS = 0.125  # m
CUT_LENGTH = 0.2 * math.pi  # m of web per cycle
LINE_SPEED = 1.0  # m/s
SYNC_DEG = 5.0  # knife degrees either side of the cut


@pytest.fixture(scope='module')
def knife():
    return build_design(load_config(KNIFE))


def knife_values(**changes):
    values = read_parameters_file(KNIFE)
    values.update(changes)
    return values


def test_the_knife_is_a_rotary_slave_that_advances_a_full_turn_per_cut(knife):
    config = knife.config
    assert config.motion_only and config.angular and knife.follower is None
    assert config.position_unit == 'rad' and config.file_position_unit == ('deg', 180 / math.pi)
    assert knife.program.advance == pytest.approx(TWO_PI, abs=1e-15)
    theta = np.linspace(-3 * TWO_PI, 3 * TWO_PI, 2001)
    state = knife.evaluate(theta)
    turns = np.floor(theta / TWO_PI)
    once = knife.evaluate(np.mod(theta, TWO_PI))
    np.testing.assert_allclose(state.position, once.position + TWO_PI * turns, atol=1e-12)
    np.testing.assert_allclose(state.velocity, once.velocity, atol=1e-12)
    assert np.isnan(state.pressure_angle).all() and np.isnan(state.radius_of_curvature).all()
    # Across the cut (the wrap) the knife keeps going: s and ds/dtheta continuous.
    eps = 1e-7
    around = knife.evaluate(np.array([TWO_PI - eps, TWO_PI + eps]))
    assert around.position[1] - around.position[0] == pytest.approx(2 * eps * 0.8, rel=1e-6)
    assert around.ds[0] == pytest.approx(around.ds[1], abs=1e-9)


def test_the_knife_runs_with_the_web_while_it_cuts_and_recovers_as_a_g_g_cycloid(knife):
    omega = LINE_SPEED / knife.config.parameters['master.scaling']  # rad/s of cam angle
    assert knife.config.cam_speed == pytest.approx(omega)
    assert knife.config.parameters['master.scaling'] * TWO_PI == pytest.approx(CUT_LENGTH)
    sync = np.radians([0.0, 3.0, 6.25, 353.75, 358.0])
    state = knife.evaluate(sync)
    np.testing.assert_allclose(state.velocity * DRUM_RADIUS, LINE_SPEED, rtol=1e-12)
    np.testing.assert_allclose(np.degrees(knife.evaluate(np.radians([6.25, 353.75])).position),
                               [SYNC_DEG, 360.0 - SYNC_DEG], atol=1e-9)
    # Recovery: s = s0 + v x + (H - v X) g(x / X) with the cycloid g (motion-tasks note).
    v = LINE_SPEED / (DRUM_RADIUS * omega)  # knife rad per rad of cam in sync
    start, span = math.radians(6.25), math.radians(347.5)
    rise = math.radians(350.0)
    x = np.linspace(0.0, span, 501)
    law = Cycloidal().evaluate(x / span)
    recovery = knife.evaluate(start + x)
    np.testing.assert_allclose(recovery.position,
                               math.radians(SYNC_DEG) + v * x + (rise - v * span) * law.y,
                               atol=1e-12)
    summary = knife.program.segment_summary()[1]
    peak_v, peak_a, _ = summary.peaks_at_speed(omega)
    assert summary.task == 'G-G'
    assert peak_v == pytest.approx(omega * (v + 2.0 * (rise / span - v)), rel=1e-9)
    assert peak_a == pytest.approx(omega ** 2 * TWO_PI * (rise - v * span) / span ** 2, rel=1e-9)
    assert (peak_v, peak_a) == (pytest.approx(12.144, abs=5e-4), pytest.approx(21.465, abs=5e-4))


def test_the_e_cam_follows_the_web_over_several_cuts_without_a_jump(knife):
    cam = ElectronicCam(knife.program, MasterConfig.from_config(knife.config).mapping)
    web = np.linspace(-0.3, 3.0, 3301)  # m: more than five cut lengths, from before the start
    point = cam.setpoints(web, LINE_SPEED, 0.0)
    turns = np.floor(web / 0.1 / TWO_PI)
    np.testing.assert_allclose(point.position,
                               knife.evaluate(np.mod(web / 0.1, TWO_PI)).position
                               + TWO_PI * turns, atol=1e-12)
    assert np.diff(point.position).max() < 0.02 and np.diff(point.position).min() > 0.0
    np.testing.assert_allclose(point.velocity, knife.evaluate(web / 0.1).velocity, atol=1e-12)


def test_a_slave_offset_in_deg_is_taken_in_rad():
    config = parse_parameters(knife_values(**{'slave.offset': 90.0}))
    assert MasterConfig.from_config(config).mapping.slave_offset == pytest.approx(math.pi / 2)


def test_the_cam_table_of_a_rotary_slave_ends_a_turn_above_its_start(knife):
    table = equidistant_table(knife.program, 360)
    assert table.position[0] == pytest.approx(0.0, abs=1e-15)
    assert table.position[-1] == pytest.approx(TWO_PI, abs=1e-12)
    assert np.all(np.diff(table.position) > 0.0)
    np.testing.assert_allclose(table.position, knife.evaluate(np.radians(table.master_deg))
                               .position, atol=1e-12)


def test_a_motion_only_report_has_the_motion_and_no_cam(knife):
    report = design_report(knife)
    assert report.ok and math.isnan(report.pressure_angle_max)
    assert report.min_base_radius is None and report.smallest_cam is None
    assert [s.task for s in report.segments] == ['G-G', 'G-G', 'G-G']
    assert 'motion only' in knife.summary() and 'advancing 360 deg per cycle' in knife.summary()
    with pytest.raises(InvalidParameter, match='follower.type') as err:
        knife.geometry()
    assert 'motion-only design has no cam' in str(err.value)


@pytest.mark.parametrize('name, value', [
    ('follower.base_radius', 10.0), ('follower.roller_radius', 2.0),
    ('limits.pressure_angle_deg', 45.0), ('dynamics.mass', 1.0), ('contact.face_width', 5.0),
    ('follower.closure', 'groove')])
def test_a_cam_parameter_in_a_motion_only_design_is_refused(name, value):
    with pytest.raises(InvalidParameter) as err:
        parse_parameters(knife_values(**{name: value}))
    assert err.value.parameter == name
    assert 'follower.type none is a motion-only design' in err.value.rule


def test_deg_as_a_length_unit_needs_a_motion_only_design():
    values = read_parameters_file(CONFIG_DIR / 'default.yaml')
    values['length_unit'] = 'deg'
    with pytest.raises(InvalidParameter) as err:
        parse_parameters(values)
    assert err.value.parameter == 'length_unit' and 'follower.type none' in err.value.rule


def test_only_a_motion_only_design_may_end_elsewhere_than_it_starts():
    values = read_parameters_file(CONFIG_DIR / 'default.yaml')
    ends = list(values['motion.end_position'])
    ends[-1] += 1.0
    values['motion.end_position'] = ends
    with pytest.raises(InvalidParameter, match='the follower cannot jump'):
        build_design(parse_parameters(values))


def test_a_motion_only_design_in_a_length_unit_advances_in_that_unit():
    values = knife_values(length_unit='mm')
    design = build_design(parse_parameters(values))
    assert design.config.position_unit == 'm' and design.config.file_position_unit[0] == 'mm'
    assert design.program.advance == pytest.approx(0.36)
