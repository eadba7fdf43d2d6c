"""Electronic cam core: MC_CamIn mapping, chain-rule setpoints, the master parameters."""
from __future__ import annotations

import math
from pathlib import Path

import numpy as np
import pytest

from cam_ros.core import InvalidParameter, build_design, parse_parameters, read_parameters_file
from cam_ros.core.ecam.master import CamMapping, ElectronicCam, MasterConfig

DEFAULT = Path(__file__).resolve().parents[2] / 'config' / 'default.yaml'
DESIGN = build_design(parse_parameters(read_parameters_file(DEFAULT)))
MAPPING = CamMapping(master_offset=0.3, master_scaling=2.5, slave_offset=0.01,
                     slave_scaling=-1.5)
CAM = ElectronicCam(DESIGN.program, MAPPING)
#: Relative agreement of an exact chain rule with central differences of step H_S.
DIFFERENCE_RTOL = 1e-6
H_S = 1e-4
SECOND = 1_000_000_000


def reference_setpoint(q: float) -> float:
    """Follower position at master q, by the MC_CamIn formula written out here."""
    theta = math.fmod((q - MAPPING.master_offset) / MAPPING.master_scaling, 2 * math.pi)
    theta += 2 * math.pi if theta < 0 else 0.0
    s = float(DESIGN.program.evaluate(theta).s)
    return MAPPING.slave_scaling * s + MAPPING.slave_offset


@pytest.mark.parametrize('q', [0.0, 0.3, 1.7, -2.0, 12.0 * math.pi + 4.0, -101.3, 1e4 + 0.5])
def test_master_positions_map_modulo_one_cam_revolution(q):
    assert float(CAM.setpoints(q).position) == pytest.approx(reference_setpoint(q), abs=1e-12)
    assert 0.0 <= float(MAPPING.cam_angle(q)) < 2 * math.pi


def follower_law(theta: float) -> tuple[float, float, float]:
    """Return s', s'', s''' (per rad of cam) of default.yaml's moving segments in closed form."""
    stroke = 0.02  # m: a cycloidal rise over 90-180 deg, a simple harmonic return over 240-360
    if math.radians(90.0) < theta < math.radians(180.0):
        beta = math.radians(90.0)
        phase = 2 * math.pi * (theta - math.radians(90.0)) / beta
        return (stroke / beta * (1 - math.cos(phase)),
                stroke / beta ** 2 * 2 * math.pi * math.sin(phase),
                stroke / beta ** 3 * 4 * math.pi ** 2 * math.cos(phase))
    assert math.radians(240.0) < theta < 2 * math.pi, 'a case outside the moving segments'
    beta = math.radians(120.0)
    phase = math.pi * (theta - math.radians(240.0)) / beta
    half = -stroke / 2  # the return falls by the stroke: s = stroke + half (1 - cos(phase))
    return (half * math.pi / beta * math.sin(phase),
            half * (math.pi / beta) ** 2 * math.cos(phase),
            -half * (math.pi / beta) ** 3 * math.sin(phase))


#: Cases inside both moving segments (cam angle in deg, whole master turns, some negative),
#: where s', s'' and s''' are all far from zero, so that every term of the chain rule counts.
MOVING = [(110.0, 0), (153.0, 4), (276.0, 0), (342.0, -3), (130.0, -1)]


@pytest.mark.parametrize('theta_deg, turns', MOVING)
def test_velocity_acceleration_jerk_are_the_chain_rule_of_the_master_motion(theta_deg, turns):
    omega, alpha = 7.0, -3.0  # constant master acceleration: q = q0 + omega t + alpha t^2 / 2
    m, k = MAPPING.master_scaling, MAPPING.slave_scaling
    q0 = MAPPING.master_offset + m * (math.radians(theta_deg) + 2 * math.pi * turns)
    point = CAM.setpoints(q0, omega, alpha)
    # The chain rule in closed form, term by term: no term of it vanishes here.
    ds, d2s, d3s = follower_law(math.radians(theta_deg))
    velocity = k * ds * omega / m
    speed_acceleration, master_acceleration = k * d2s * omega ** 2 / m ** 2, k * ds * alpha / m
    speed_jerk = k * d3s * omega ** 3 / m ** 3
    acceleration_jerk = 3 * k * d2s * omega * alpha / m ** 2
    for term in (velocity, speed_acceleration, master_acceleration, speed_jerk, acceleration_jerk):
        assert abs(term) > 1e-3, (theta_deg, term)
    assert float(point.velocity) == pytest.approx(velocity, rel=1e-9)
    assert float(point.acceleration) == pytest.approx(speed_acceleration + master_acceleration,
                                                      rel=1e-9)
    assert float(point.jerk) == pytest.approx(speed_jerk + acceleration_jerk, rel=1e-9)
    # And they are the time derivatives of the positions along the master's motion.
    t = H_S * np.arange(-2, 3)
    y = CAM.setpoints(q0 + omega * t + 0.5 * alpha * t ** 2).position
    assert float(point.velocity) == pytest.approx((y[3] - y[1]) / (2 * H_S), rel=DIFFERENCE_RTOL)
    assert float(point.acceleration) == pytest.approx((y[3] - 2 * y[2] + y[1]) / H_S ** 2,
                                                      rel=1e-4)
    assert float(point.jerk) == pytest.approx((y[4] - 2 * y[3] + 2 * y[1] - y[0]) / (2 * H_S ** 3),
                                              rel=1e-2)


def test_setpoints_broadcast_over_arrays_like_single_samples():
    """One sample in floats (a master message) gives the very numbers of the array path."""
    q = np.linspace(-20.0, 20.0, 101)
    omega = np.linspace(-60.0, 60.0, 101)
    together = CAM.setpoints(q, omega, 2.0)
    for index in range(q.size):
        for alone in (CAM.setpoints(float(q[index]), float(omega[index]), 2.0),
                      CAM.setpoints(q[index], omega[index], 2.0)):  # NumPy scalars
            for field in together._fields:
                assert getattr(together, field)[index] == getattr(alone, field), (index, field)
    assert all(type(value) is float for value in CAM.setpoints(1.0, 3.0, 2.0))


def test_parameters_convert_to_si(tmp_path):
    values = read_parameters_file(DEFAULT)  # length_unit cm
    values.update({'master.offset_deg': 90.0, 'master.scaling': 2.0, 'slave.offset': 1.5,
                   'slave.scaling': -1.0, 'master.source': 'topic', 'master.timeout': 0.2,
                   'command.interface': 'velocity', 'command.trajectory_horizon': 0.05,
                   'command.trajectory_points': 7})
    config = MasterConfig.from_config(parse_parameters(values))
    assert config.mapping == CamMapping(math.pi / 2, 2.0, pytest.approx(0.015), -1.0)
    assert (config.source, config.topic, config.joint) == ('topic', '~/master', 'cam')
    assert (config.timeout, config.interface, config.trajectory_horizon) == (0.2, 'velocity',
                                                                             0.05)
    assert config.trajectory_points == 7


def test_oscillating_slave_offset_is_in_degrees():
    values = read_parameters_file(DEFAULT)
    values.update({'follower.type': 'oscillating_roller', 'slave.offset': 10.0})
    config = parse_parameters(values)  # parsing builds no geometry
    assert MasterConfig.from_config(config).mapping.slave_offset == pytest.approx(
        math.radians(10.0))


@pytest.mark.parametrize('max_speed, jump, expected', [
    (0.0, None, (math.inf, 'no limit')),
    (0.0, 30.0, (60.0, 'the jump speed')),  # cam rad/s times master.scaling 2
    (50.0, 30.0, (50.0, 'master.max_speed')),
    (50.0, 20.0, (40.0, 'the jump speed')),
    (50.0, 0.0, (0.0, 'the jump speed')),  # contact lost at rest: any motion warns
])
def test_the_speed_limit_is_the_lower_of_max_speed_and_the_jump_speed(max_speed, jump,
                                                                      expected):
    values = read_parameters_file(DEFAULT)
    values.update({'master.scaling': 2.0, 'master.max_speed': max_speed})
    assert MasterConfig.from_config(parse_parameters(values)).speed_limit(jump) == expected


@pytest.mark.parametrize('name, value, fragment', [
    ('master.scaling', 0.0, '>= 1e-06'),
    ('master.source', 'encoder', 'one of clock, topic'),
    ('command.interface', 'effort', 'one of position, velocity'),
    ('master.timeout', -1.0, '>= 0.001'),
    ('command.trajectory_points', 0, '>= 1'),
    ('slave.offset', 1e6, 'must not exceed'),
])
def test_bad_master_parameters_are_refused_by_name(name, value, fragment):
    values = read_parameters_file(DEFAULT)
    values[name] = value
    with pytest.raises(InvalidParameter, match=fragment) as caught:
        parse_parameters(values)
    assert caught.value.parameter == name


# Master messages ------------------------------------------------------------------------------


@pytest.mark.parametrize('mapping', [CamMapping(), MAPPING, CamMapping(-0.5, 0.5)],
                         ids=['identity', 'offset, 2.5', 'two cycles a turn'])
@pytest.mark.parametrize('low, high', [(0.0, 2 * math.pi), (100.0, 130.0), (-50.0, -20.0),
                                       (-7.0, 40.0)])
def test_the_breaks_are_the_master_positions_of_every_program_break(mapping, low, high):
    """Each break b of the program recurs at every cam angle b + 2 pi k: in the cam angles of
    [low, high] that is floor((t_high - b) / 2 pi) - ceil((t_low - b) / 2 pi) + 1 times."""
    cam = ElectronicCam(DESIGN.program, mapping)
    found = cam.breaks(low, high)
    assert np.all((found >= low) & (found <= high))
    angles = (found - mapping.master_offset) / mapping.master_scaling
    program_breaks = np.array(DESIGN.program.breaks)
    off = np.remainder(angles[:, np.newaxis] - program_breaks + math.pi, 2 * math.pi) - math.pi
    assert np.abs(off).min(axis=1).max() <= 1e-9
    t_low, t_high = ((value - mapping.master_offset) / mapping.master_scaling
                     for value in (low, high))
    turn = 2 * math.pi
    expected = sum(math.floor((t_high - b) / turn) - math.ceil((t_low - b) / turn) + 1
                   for b in program_breaks)
    assert found.size == expected > 0
