"""REP 103 conventions of ~/joint_states, ~/profile and ~/markers, checked on a real cam_node.

The `cam` joint is the cam's rotation about +z and `cam` is the frame of the markers, so the
follower's contact point, placed with the follower joint alone, must lie on the marker pitch
curve turned about +z by the cam joint: the check a robot model makes visually.
"""
from __future__ import annotations

import math

import numpy as np
import pytest
import yaml
from conftest import CONFIG_DIR
from rclpy.qos import DurabilityPolicy, QoSProfile, ReliabilityPolicy
from sensor_msgs.msg import JointState
from test_node import Inbox
from trajectory_msgs.msg import JointTrajectory
from visualization_msgs.msg import MarkerArray

from cam_ros.core import build_design, load_config

LATCHED_QOS = QoSProfile(depth=1, durability=DurabilityPolicy.TRANSIENT_LOCAL,
                         reliability=ReliabilityPolicy.RELIABLE)
CM = 0.01
STATE_COUNT = 60  # 1.2 s at 50 Hz: more than one revolution at 2 pi rad/s
ON_CURVE_M = 2e-5  # chord error of the 360-point marker polyline is ~3e-6 m
OFF_CURVE_M = 1e-3  # the same check with the rotation reversed misses by centimetres

# name: (config edits, expected sigma, expected lam: +1 if the arm turns counter-clockwise
# while rising; a clockwise cam's arm does so when it does not turn with the cam)
CASES = {
    'clockwise translating roller': ({}, -1, None),
    'counterclockwise translating roller': ({'rotation': 'counterclockwise'}, 1, None),
    'oscillating roller, arm against the cam': (
        {'follower': {'type': 'oscillating_roller', 'base_radius': 4.0, 'roller_radius': 1.0,
                      'pivot_distance': 9.0, 'arm_length': 7.0}}, -1, 1),
    'oscillating roller, arm with the cam': (
        {'follower': {'type': 'oscillating_roller', 'base_radius': 4.0, 'roller_radius': 1.0,
                      'pivot_distance': 9.0, 'arm_length': 7.0, 'arm_turns_with_cam': True}},
        -1, -1),
}
ARM_START_DEG, ARM_END_DEG = [0.0, 0.0, 15.0, 15.0], [0.0, 15.0, 15.0, 0.0]  # seed 000's motion


def write_config(tmp_path, edits):
    parameters = yaml.safe_load((CONFIG_DIR / 'default.yaml').read_text())['/**'][
        'ros__parameters']
    parameters.update(edits)
    if 'follower' in edits:  # oscillating: positions are arm angles in degrees
        motion = parameters['motion']
        motion['start_position'], motion['end_position'] = ARM_START_DEG, ARM_END_DEG
    path = tmp_path / 'cam.yaml'
    path.write_text(yaml.safe_dump({'/**': {'ros__parameters': parameters}}))
    return path


def rotation(angle):
    """Return rotation matrices about +z, shape (..., 2, 2)."""
    c, s = np.cos(angle), np.sin(angle)
    return np.stack([np.stack([c, -s], -1), np.stack([s, c], -1)], -2)


def distance_to_polyline(points, vertices):
    """Return each point's distance to the closed polyline through vertices (brute force)."""
    a, b = vertices[:-1], vertices[1:]
    ab = b - a
    t = np.clip(np.einsum('pnk,nk->pn', points[:, None] - a, ab) / np.sum(ab ** 2, 1), 0, 1)
    nearest = a + t[..., None] * ab
    return np.min(np.linalg.norm(points[:, None] - nearest, axis=-1), axis=1)


def contact_centre(config, follower_joint):
    """Place the roller centre (fixed frame, m) from the follower joint and the file alone."""
    follower = config['follower']
    rp = (follower['base_radius'] + follower['roller_radius']) * CM
    if follower['type'] == 'translating_roller':
        e = follower['offset'] * CM
        return np.stack([np.full_like(follower_joint, e),
                         math.sqrt(rp ** 2 - e ** 2) + follower_joint], -1)
    pivot, arm = follower['pivot_distance'] * CM, follower['arm_length'] * CM
    # The joint is the arm's angle about +z from the direction pivot -> cam centre (-y).
    return np.stack([arm * np.sin(follower_joint), pivot - arm * np.cos(follower_joint)], -1)


@pytest.mark.parametrize('case', list(CASES))
def test_joints_turn_the_markers_as_the_cam_turns(case, start_cam_node, executor, tmp_path):
    edits, sigma, lam = CASES[case]
    path = write_config(tmp_path, edits)
    config = yaml.safe_load(path.read_text())['/**']['ros__parameters']
    design = build_design(load_config(path))
    omega = design.config.cam_speed
    start_cam_node(path)
    listener = executor.node('convention_listener')
    markers = Inbox(listener, MarkerArray, '/cam/markers', LATCHED_QOS)
    profile = Inbox(listener, JointTrajectory, '/cam/profile', LATCHED_QOS)
    joints = Inbox(listener, JointState, '/cam/joint_states', 100).wait(STATE_COUNT)
    q = np.array([m.position[0] for m in joints])
    follower = np.array([m.position[1] for m in joints])

    # The cam joint turns with the cam's sense about +z: it falls for a clockwise cam.
    assert all(m.velocity[0] == sigma * omega for m in joints)
    stamps = np.array([m.header.stamp.sec * 10**9 + m.header.stamp.nanosec for m in joints])
    np.testing.assert_allclose(np.mod(sigma * np.diff(q), 2 * math.pi),
                               omega * np.diff(stamps) * 1e-9, atol=1e-9)

    # The follower joint: travel s, or the absolute arm angle lam * (psi0 + s).
    theta = sigma * q  # the design's cam angle, as ~/evaluate takes it
    s = design.evaluate(theta).position
    if lam is None:
        np.testing.assert_allclose(follower, s, atol=1e-12)
    else:
        f = config['follower']
        rp = f['base_radius'] + f['roller_radius']
        c, arm = f['pivot_distance'], f['arm_length']
        psi0 = math.acos((c ** 2 + arm ** 2 - rp ** 2) / (2 * c * arm))  # law of cosines
        np.testing.assert_allclose(follower, lam * (psi0 + s), atol=1e-12)
        first = profile.wait()[0].points[0].positions[0]
        assert first == pytest.approx(lam * (psi0 + design.evaluate([0.0]).position[0]), abs=1e-12)

    # The roller centre lies on the marker pitch curve turned about +z by the cam joint.
    [pitch] = [m for m in markers.wait()[0].markers if m.ns == 'pitch_curve']
    assert pitch.header.frame_id == 'cam'
    curve = np.array([(p.x, p.y) for p in pitch.points])
    centre = contact_centre(config, follower)
    in_cam_frame = np.einsum('nij,nj->ni', rotation(-q), centre)
    assert np.max(distance_to_polyline(in_cam_frame, curve)) < ON_CURVE_M
    reversed_turn = np.einsum('nij,nj->ni', rotation(q), centre)
    assert np.max(distance_to_polyline(reversed_turn, curve)) > OFF_CURVE_M
