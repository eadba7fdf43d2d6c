"""config/ros2_control: the URDF and controllers name exactly cam_node's joints and interfaces.

The single cam's (cam.urdf, controllers.yaml) and config/machine.yaml's (machine.urdf,
machine_controllers.yaml: every axis joint, limits covering each axis's commanded range).
"""
from __future__ import annotations

import xml.etree.ElementTree as ET

import numpy as np
import yaml
from cli_support import CONFIG_DIR, REPO
from scipy.optimize import minimize_scalar

from cam_ros.core.config.parameters import PARAMETERS
from cam_ros.core.machine import load_machine
from cam_ros.node.joints import CAM_JOINT, FOLLOWER_JOINT, JOINT_NAMES

FOLDER = CONFIG_DIR / 'ros2_control'
FORWARD = 'forward_command_controller/ForwardCommandController'
TRAJECTORY = 'joint_trajectory_controller/JointTrajectoryController'


def command_interfaces() -> set[str]:
    """Return the schema's choices of command.interface (what ~/commands carries)."""
    return {choice for spec in PARAMETERS if spec.name == 'command.interface'
            for choice in spec.choices}


def urdf(name: str = 'cam.urdf') -> ET.Element:
    return ET.parse(FOLDER / name).getroot()


def controllers(name: str = 'controllers.yaml') -> dict:
    return yaml.safe_load((FOLDER / name).read_text())


def by_type(kind: str, name: str = 'controllers.yaml') -> dict[str, dict]:
    """Return the parameters of each controller of a type, by controller name."""
    config = controllers(name)
    manager = config['controller_manager']['ros__parameters']
    return {name: config[name]['ros__parameters'] for name, value in manager.items()
            if isinstance(value, dict) and value.get('type') == kind}


def test_urdf_joints_are_the_nodes_joint_states():
    joints = {joint.get('name'): joint for joint in urdf().findall('joint')}
    assert tuple(sorted(joints)) == tuple(sorted(JOINT_NAMES))
    cam, follower = joints[CAM_JOINT], joints[FOLLOWER_JOINT]
    assert cam.get('type') == 'revolute' and cam.find('axis').get('xyz') == '0 0 1'
    assert follower.get('type') == 'prismatic' and follower.find('axis').get('xyz') == '0 1 0'
    limit = cam.find('limit')  # the published cam joint lies in (-2 pi, 2 pi)
    assert float(limit.get('lower')) <= -6.283185307179586 <= 6.283185307179586 <= float(
        limit.get('upper'))


def test_ros2_control_commands_the_follower_by_the_schemas_interfaces():
    (system,) = urdf().findall('ros2_control')
    (joint,) = system.findall('joint')
    assert joint.get('name') == FOLLOWER_JOINT
    commands = {item.get('name') for item in joint.findall('command_interface')}
    states = {item.get('name') for item in joint.findall('state_interface')}
    assert commands == command_interfaces()
    assert states == {'position', 'velocity'}


def test_forward_controllers_cover_each_command_interface_on_the_follower():
    forward = by_type(FORWARD)
    assert sorted(params['interface_name'] for params in forward.values()) == sorted(
        command_interfaces())
    for params in forward.values():
        assert params['joints'] == [FOLLOWER_JOINT]


def test_trajectory_controller_takes_the_follower_from_the_urdfs_interfaces():
    (params,) = by_type(TRAJECTORY).values()
    (joint,) = urdf().find('ros2_control').findall('joint')
    assert params['joints'] == [FOLLOWER_JOINT]
    assert set(params['command_interfaces']) <= {
        item.get('name') for item in joint.findall('command_interface')}
    assert set(params['state_interfaces']) <= {
        item.get('name') for item in joint.findall('state_interface')}
    assert params['allow_nonzero_velocity_at_trajectory_end'] is True  # a look-ahead still moves


def test_docs_remap_the_nodes_topics_to_each_controllers_input():
    readme = (REPO / 'docs' / 'ros-interface.md').read_text()
    for name in by_type(FORWARD):
        assert f'/cam/commands:=/{name}/commands' in readme, name
    for name in by_type(TRAJECTORY):
        assert f'/cam/joint_trajectory:=/{name}/joint_trajectory' in readme, name


MACHINE_FILE = CONFIG_DIR / 'machine.yaml'
MACHINE_URDF, MACHINE_CONTROLLERS = 'machine.urdf', 'machine_controllers.yaml'
BROADCASTER = 'joint_state_broadcaster/JointStateBroadcaster'


def refined_range(values, q: np.ndarray) -> tuple[float, float]:
    """Return the smallest and largest of values(q) over a cycle: dense scan, then refined."""
    dense = values(q)
    step = q[1] - q[0]
    found = []
    for sign, index in ((1.0, np.argmin(dense)), (-1.0, np.argmax(dense))):
        best = minimize_scalar(lambda x: sign * float(values(np.array([x]))[0]),
                               bounds=(q[index] - step, q[index] + step), method='bounded',
                               options={'xatol': 1e-12})
        found.append(sign * min(best.fun, sign * dense[index]))  # the more extreme of both
    return found[0], found[1]


def test_machine_urdf_has_the_master_and_every_axis_joint():
    machine = load_machine(MACHINE_FILE)
    joints = {joint.get('name'): joint for joint in urdf(MACHINE_URDF).findall('joint')}
    assert sorted(joints) == sorted((CAM_JOINT, *machine.config.names))
    assert joints[CAM_JOINT].get('type') == 'continuous'  # the machine angle is unbounded
    for axis in machine.axes:
        rotary = axis.design.config.length_unit == 'deg'
        assert joints[axis.name].get('type') == ('continuous' if rotary else 'prismatic')
    (system,) = urdf(MACHINE_URDF).findall('ros2_control')
    assert [joint.get('name') for joint in system.findall('joint')] == list(
        machine.config.names)
    for joint, config in zip(system.findall('joint'), machine.config.axes):
        assert [item.get('name') for item in joint.findall('command_interface')] == [
            config.parameters['command.interface']]
        assert {item.get('name') for item in joint.findall('state_interface')} == {
            'position', 'velocity'}


def test_machine_limits_cover_each_axis_commanded_range_and_speed():
    machine = load_machine(MACHINE_FILE)
    speed = machine.config.parameters['cam_speed']
    q = np.linspace(0.0, 2.0 * np.pi, 100001)
    joints = {joint.get('name'): joint for joint in urdf(MACHINE_URDF).findall('joint')}
    for index, axis in enumerate(machine.axes):
        limit = joints[axis.name].find('limit')
        velocity = np.abs(axis.cam.setpoints(q, speed).velocity)
        assert velocity.max() <= float(limit.get('velocity')), axis.name
        if joints[axis.name].get('type') == 'continuous':
            assert limit.get('lower') is None and limit.get('upper') is None
            continue
        low, high = refined_range(lambda x: machine.positions(x)[..., index], q)
        assert float(limit.get('lower')) <= low and high <= float(limit.get('upper')), (
            axis.name, low, high)
        assert high - low >= 0.9 * (float(limit.get('upper')) - float(limit.get('lower')))


def test_machine_controllers_forward_every_axis_in_order_and_broadcast_states():
    machine = load_machine(MACHINE_FILE)
    (forward,) = by_type(FORWARD, MACHINE_CONTROLLERS).values()
    assert forward['joints'] == list(machine.config.names)
    (interface,) = {config.parameters['command.interface'] for config in machine.config.axes}
    assert forward['interface_name'] == interface
    manager = controllers(MACHINE_CONTROLLERS)['controller_manager']['ros__parameters']
    assert [value['type'] for value in manager.values() if isinstance(value, dict)].count(
        BROADCASTER) == 1
