"""A machine's new limits taken at once when every axis runs its cam, against the cam's own
velocity bound; a refused offset change keeps the limits of both cams; the setpoints ahead; a
disengaged line at rest; the command each interface is sent."""
from __future__ import annotations

import math
from dataclasses import replace

import numpy as np

from cam_ros.core.ecam.axes import SlaveAxes
from cam_ros.core.ecam.follow import ENGAGED, EngageConfig, Follower
from cam_ros.core.ecam.master import ElectronicCam
from cam_ros.core.ecam.master_tracker import MasterState
from cam_ros.core.ecam.path_limits import PathLimits
from cam_ros.core.ecam.slave_limits import SlaveLimits

from line_shaft_support import LIMITS, line, NOMINAL

DT = 0.004
FEEDER, KNIFE, _ = line().cams
SLOW = SlaveLimits(1.0, 10.0)


def test_new_limits_with_every_axis_on_its_cam_bound_the_commands_at_once():
    # The feeder at cam_speed runs at 2 m/s; limited to 1 m/s (a design change's new limits,
    # every axis on its cam) its velocity commands come under 1 m/s once theta_v has braked
    # within the new acceleration limit; they are what a velocity interface is sent.
    follower = Follower(FEEDER, EngageConfig(nominal_speed=NOMINAL), engage=True,
                        limits=LIMITS[0])
    axes = SlaveAxes(['feeder'], [follower], ['velocity'])
    velocities = []
    for k in range(1500):
        if k == 500:
            slow = PathLimits.of([FEEDER], [SLOW], NOMINAL, math.radians(30.0))
            axes.retarget(slow, False, slow, False)
            assert axes.shaft.limits is slow
        theta = NOMINAL * k * DT
        commands = axes.command(MasterState(round(k * DT * 1e9), theta, NOMINAL, 0.0,
                                            NOMINAL * DT, theta))
        if commands is not None:
            assert axes.values(commands) == commands.velocity
            velocities.append((k, commands.velocity[0]))
    k, v = np.array(velocities).T
    assert np.abs(v[(k > 250) & (k < 500)]).max() > 1.5  # the cam's own at cam_speed
    assert np.abs(v[k >= 1000]).max() <= SLOW.max_velocity * (1 + 1e-6)


def run(axes, steps):
    """Drive the axes with a master at cam_speed over these steps (DT apart)."""
    for k in steps:
        theta = NOMINAL * k * DT
        axes.command(MasterState(round(k * DT * 1e9), theta, NOMINAL, 0.0, NOMINAL * DT, theta))


def test_a_refused_offset_change_keeps_the_limits_of_both_cams():
    # A positive-only knife (not rotary) whose phase shift puts its cam behind it with the
    # line shaft at rest cannot move onto it: it stays on its old cam, and the line shaft keeps
    # the limits of both cams (it could have run either) until the next change, not the new's.
    limits = SlaveLimits(15.0, 30.0, 1)
    follower = Follower(KNIFE, EngageConfig(nominal_speed=NOMINAL), engage=True, limits=limits)
    axes = SlaveAxes(['knife'], [follower], ['position'])
    run(axes, range(300))
    shifted = ElectronicCam(KNIFE.program, replace(KNIFE.mapping, master_offset=KNIFE.mapping
                                                   .master_offset + 0.5))
    assert follower.change(shifted, follower.config).startswith('moves onto the new cam')
    new, both = (PathLimits.of(cams, [limits] * len(cams), NOMINAL, math.radians(30.0))
                 for cams in ([shifted], [KNIFE, shifted]))
    axes.retarget(new, True, both, True)
    run(axes, range(300, 1000))
    assert any('offset change refused' in event for event in axes.events())
    assert follower.phase == ENGAGED and follower.cam is KNIFE and not follower.changing
    assert axes.shaft.limits is both


def test_the_setpoints_ahead_are_the_cams_at_constant_speed_and_disengaging_stops_the_line():
    # Running at cam_speed, the setpoints t ahead are the cam's at theta_v + w t: y and y' w,
    # at cam angle (theta_v + w t) mod 2 pi. Disengaged, the line shaft stops every axis on its
    # cam while the master runs on: the commands come to rest and stay.
    follower = Follower(FEEDER, EngageConfig(nominal_speed=NOMINAL), engage=True,
                        limits=LIMITS[0])
    axes = SlaveAxes(['feeder'], [follower], ['position'])
    run(axes, range(500))
    state, times = axes.virtual, DT * np.arange(50)
    assert state.omega == NOMINAL
    ahead = axes.ahead(times)[0]
    theta = state.track + NOMINAL * times
    exact = FEEDER.derivatives(theta)
    np.testing.assert_allclose(ahead.position, exact.y, rtol=0, atol=1e-12)
    np.testing.assert_allclose(ahead.velocity, exact.dy * NOMINAL, rtol=0, atol=1e-9)
    np.testing.assert_allclose(ahead.cam_angle, np.mod(theta, 2 * np.pi), rtol=0, atol=1e-9)
    assert axes.engage(False)[0] and not axes.engaged
    held = []
    for k in range(500, 1500):
        theta = NOMINAL * k * DT
        commands = axes.command(MasterState(round(k * DT * 1e9), theta, NOMINAL, 0.0,
                                            NOMINAL * DT, theta))
        held.append((commands.position[0], commands.velocity[0]))
        assert axes.values(commands) == commands.position
    position, velocity = np.array(held[-250:]).T
    assert np.ptp(position) == 0.0 and not velocity.any()
    assert axes.status.startswith('at rest: disengaged')
