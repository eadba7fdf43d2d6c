"""Engage modes, master loss, one-shot cams and offset changes of the Follower, without ROS."""
from __future__ import annotations

import math
from dataclasses import replace
from pathlib import Path

import numpy as np
import pytest

from cam_ros.core import build_design, parse_parameters, read_parameters_file
from cam_ros.core.ecam.axes import SlaveAxes
from cam_ros.core.ecam.follow import (END_OF_PROFILE, ENGAGED, EngageConfig, ENGAGING, Follower,
                                      HOLDING, WAITING_CYCLE)
from cam_ros.core.ecam.master import CamMapping, ElectronicCam
from cam_ros.core.ecam.master_tracker import MasterState

DEFAULT = Path(__file__).resolve().parents[2] / 'config' / 'default.yaml'
CAM = ElectronicCam(build_design(parse_parameters(read_parameters_file(DEFAULT))).program,
                    CamMapping(0.0, 1.0, 0.0, 1.0))
OMEGA = 20 * math.pi  # 600 rpm
DT = 0.001
DISTANCE = math.radians(30.0)


def drive(follower, q):
    """Run master positions q at OMEGA; return the commanded positions and the phases."""
    points, phases = [], []
    for k, position in enumerate(q):
        state = MasterState(k * 10 ** 6, position, OMEGA, 0.0, OMEGA * DT, position)
        point = follower.command(state)
        points.append(None if point is None else float(point.position))
        phases.append(follower.phase)
    return points, phases


def test_ramp_waits_for_the_master_at_rest_then_moves_onto_the_cam_in_the_least_time():
    # Without limits a move is bounded by the cam's own peaks at cam_speed: from a dense scan,
    # velocity V = max |y'| w and acceleration A = max |y''| w^2; with no jerk limit the least
    # time over a distance d is d / V + V / A (a trapezoid), or 2 sqrt(d / A) (a triangle).
    # A follower alone holds: its move is its machine's to plan, with the line shaft at rest.
    follower = Follower(CAM, EngageConfig(distance=DISTANCE, nominal_speed=OMEGA), engage=True)
    follower.present = 0.012
    q = 2.0 + OMEGA * DT * np.arange(20)
    points, phases = drive(follower, q)
    assert points == [0.012] * 20 and set(phases) == {HOLDING} and follower.needs_move
    axes = SlaveAxes(['follower'], [follower], ['position'])  # a machine of one axis
    theta = float(q[-1])
    positions, velocities, phases = [], [], []
    for k in range(20, 2000):
        commands = axes.command(MasterState(k * 10 ** 6, theta, OMEGA if k == 20 else 0.0, 0.0,
                                            0.0, theta))  # running at first: theta_v rests
        positions.append(commands.position[0])
        velocities.append(commands.velocity[0])
        phases.append(follower.phase)
    dense = CAM.derivatives(np.linspace(0.0, 2 * math.pi, 400_001))
    fastest, hardest = np.abs(dense.dy).max() * OMEGA, np.abs(dense.d2y).max() * OMEGA ** 2
    target = float(CAM.setpoints(theta).position)
    distance = abs(target - 0.012)
    least = distance / fastest + fastest / hardest if distance >= fastest ** 2 / hardest \
        else 2.0 * math.sqrt(distance / hardest)
    moving = phases.count(ENGAGING)
    assert phases[0] == ENGAGING and set(phases[moving:]) == {ENGAGED}
    assert abs(moving * DT - least) <= DT + least * 1e-5
    assert positions[0] == pytest.approx(0.012, abs=1e-15)
    assert positions[moving:] == [target] * (len(positions) - moving)  # on the cam, exactly
    assert max(np.abs(velocities)) <= fastest * (1.0 + 1e-9)
    assert np.all(np.sign(target - 0.012) * np.diff(positions) >= 0.0)  # straight there


@pytest.mark.parametrize('mode', ['immediate', 'ramp', 'next_cycle'])
def test_each_mode_engages_from_the_held_position(mode):
    follower = Follower(CAM, EngageConfig(mode=mode, distance=DISTANCE), engage=False)
    held = follower.present = float(CAM.setpoints(1.0).position)  # the dwell at 0 deg's height
    assert follower.engage()[0]
    q = 1.0 + 2 * math.pi - 0.3 + OMEGA * DT * np.arange(100)  # back 0.3 rad before angle 0
    points, phases = drive(follower, q)
    if mode == 'immediate':
        assert points[0] == float(CAM.setpoints(q[0]).position)
    else:
        assert points[0] == held
    if mode == 'next_cycle':  # held at the dwell's position: waits for angle 0
        crossing = int(np.argmax(q >= 4 * math.pi))
        assert set(phases[:crossing]) == {WAITING_CYCLE} and phases[crossing] == ENGAGED


def test_next_cycle_refuses_a_held_position_off_the_cycle_start():
    follower = Follower(CAM, EngageConfig(mode='next_cycle'), engage=False)
    follower.present = 0.005
    ok, message = follower.engage()
    assert not ok and 'next_cycle cannot engage' in message and follower.phase == HOLDING


def test_a_one_shot_cam_holds_its_end_and_runs_again_on_engage():
    follower = Follower(CAM, EngageConfig(mode='immediate', periodic=False), engage=True)
    q = 0.5 + OMEGA * DT * np.arange(150)  # 1.5 turns
    points, phases = drive(follower, q)
    end = int(np.argmax(q - q[0] >= 2 * math.pi))
    assert set(phases[:end]) == {ENGAGED} and set(phases[end:]) == {END_OF_PROFILE}
    assert points[end:] == [float(CAM.setpoints(q[0] + 2 * math.pi).position)] * (150 - end)
    assert follower.engage()[0]
    again, phases = drive(follower, q[-1] + OMEGA * DT * np.arange(1, 5))
    assert phases == [ENGAGED] * 4


def test_an_offset_change_while_running_is_a_move_due_and_the_old_cam_until_it_begins():
    # The move itself is its machine's (test_slave_limits, test_axes_moves); until it begins
    # the follower commands its old cam exactly. An unchanged cam is no move.
    follower = Follower(CAM, EngageConfig(mode='immediate'), engage=True)
    drive(follower, [1.0])
    assert follower.change(CAM, EngageConfig()) == 'cam unchanged'
    assert not (follower.needs_move or follower.changing)
    moved = ElectronicCam(CAM.program, replace(CAM.mapping, slave_offset=0.002))
    said = follower.change(moved, EngageConfig())
    assert said == 'moves onto the new cam in time, with the line shaft at rest'
    assert follower.needs_move and follower.changing and follower.cam is CAM
    q = 1.0 + OMEGA * DT * np.arange(1, 40)
    points, phases = drive(follower, q)
    np.testing.assert_array_equal(points, CAM.setpoints(q).position)
    assert set(phases) == {ENGAGED}


def test_a_design_sharing_no_place_with_the_running_one_is_a_move_never_a_step():
    # A handover needs a common position and velocity; without one (here the master scaling
    # changes) the change is a move like an offset change, not a step at standstill.
    follower = Follower(CAM, EngageConfig(mode='immediate'), engage=True)
    drive(follower, [1.0])
    other = ElectronicCam(CAM.program, replace(CAM.mapping, master_scaling=2.0))
    said = follower.change(other, EngageConfig())
    assert said == 'moves onto the new cam in time, with the line shaft at rest'
    assert follower.handover is None and follower.needs_move and follower.changing
    at_rest = MasterState(10 ** 6, 1.0, 0.0, 0.0, 0.0, 1.0)
    assert float(follower.command(at_rest).position) == float(CAM.setpoints(1.0).position)
