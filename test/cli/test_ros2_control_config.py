"""config/ros2_control: the URDF and controllers name exactly cam_node's joints and interfaces."""
from __future__ import annotations

import xml.etree.ElementTree as ET

import yaml
from cli_support import CONFIG_DIR, REPO

from cam_ros.core.config.parameters import PARAMETERS
from cam_ros.node.joints import CAM_JOINT, FOLLOWER_JOINT, JOINT_NAMES

FOLDER = CONFIG_DIR / 'ros2_control'
FORWARD = 'forward_command_controller/ForwardCommandController'
TRAJECTORY = 'joint_trajectory_controller/JointTrajectoryController'


def command_interfaces() -> set[str]:
    """Return the schema's choices of command.interface (what ~/commands carries)."""
    return {choice for spec in PARAMETERS if spec.name == 'command.interface'
            for choice in spec.choices}


def urdf() -> ET.Element:
    return ET.parse(FOLDER / 'cam.urdf').getroot()


def controllers() -> dict:
    return yaml.safe_load((FOLDER / 'controllers.yaml').read_text())


def by_type(kind: str) -> dict[str, dict]:
    """Return the parameters of each controller of a type, by controller name."""
    config = controllers()
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
