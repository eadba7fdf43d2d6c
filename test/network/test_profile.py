"""The shipped Fast DDS profile: who applies it, and that Fast DDS accepts it."""
from __future__ import annotations

import os
import subprocess
import sys
import xml.etree.ElementTree as ET

import pytest

from cam_ros.node.middleware import PROFILE_VARIABLES, use_shipped_profile
from cam_ros.paths import fastdds_profile_path

from .conftest import DEFAULT

NAMESPACE = '{http://www.eprosima.com/XMLSchemas/fastRTPS_Profiles}'
#: Fast DDS's defaults (ns): writer heartbeat period, NACK and heartbeat response delays.
FAST_DDS_DEFAULTS_NS = {'heartbeatPeriod': 3 * 10**9, 'nackResponseDelay': 5 * 10**6,
                        'heartbeatResponseDelay': 5 * 10**6}
START_TIMEOUT_S = 60.0


def duration_ns(element: ET.Element) -> int:
    """Return a Fast DDS XML duration (sec, nanosec) in ns."""
    return (int(element.findtext(f'{NAMESPACE}sec', '0')) * 10**9
            + int(element.findtext(f'{NAMESPACE}nanosec', '0')))


def test_the_profile_shortens_every_repair_delay_and_keeps_the_rest_default():
    root = ET.parse(fastdds_profile_path()).getroot()
    defaults = {element.tag.removeprefix(NAMESPACE): element
                for element in root.iter() if element.get('is_default_profile') == 'true'}
    assert set(defaults) == {'data_writer', 'data_reader'}  # no participant: discovery as is
    times = {element.tag.removeprefix(NAMESPACE): duration_ns(element)
             for profile in defaults.values() for element in profile.iter()
             if element.tag.removeprefix(NAMESPACE) in FAST_DDS_DEFAULTS_NS}
    assert set(times) == set(FAST_DDS_DEFAULTS_NS)
    assert all(times[name] < FAST_DDS_DEFAULTS_NS[name] for name in times), times
    assert times['heartbeatPeriod'] <= 100 * 10**6


def test_the_profile_is_used_unless_the_user_chose_one():
    environ: dict[str, str] = {}
    use_shipped_profile(environ)
    assert environ == {'FASTRTPS_DEFAULT_PROFILES_FILE': str(fastdds_profile_path())}
    for name in PROFILE_VARIABLES:
        for value in ('/etc/my_profile.xml', ''):
            environ = {name: value}
            use_shipped_profile(environ)
            assert environ == {name: value}


def node_output(profile_env: dict[str, str], ros_domain: int) -> str:
    """Start cam_node with the given profile variables, stop it once it serves, return its log."""
    env = {key: value for key, value in os.environ.items() if key not in PROFILE_VARIABLES}
    env.update(profile_env, ROS_DOMAIN_ID=str(ros_domain))
    process = subprocess.Popen([sys.executable, '-m', 'cam_ros.node', '--ros-args',
                                '--params-file', str(DEFAULT)], env=env, text=True,
                               stdout=subprocess.PIPE, stderr=subprocess.STDOUT)
    try:
        lines = []
        for line in process.stdout:
            lines.append(line)
            if 'serving /cam/evaluate' in line:
                break
        process.send_signal(2)
        rest, _ = process.communicate(timeout=START_TIMEOUT_S)
        return ''.join(lines) + rest
    finally:
        if process.poll() is None:
            process.kill()
            process.wait()


@pytest.mark.parametrize('broken', [False, True])
def test_cam_node_loads_the_profile_without_a_parse_error(ros_domain, tmp_path, broken):
    if broken:  # the check can fail: Fast DDS reports a bad profile on the node's output
        path = tmp_path / 'broken.xml'
        path.write_text(fastdds_profile_path().read_text().replace('<sec>0</sec>',
                                                                   '<sec>zero</sec>', 1))
        output = node_output({'FASTRTPS_DEFAULT_PROFILES_FILE': str(path)}, ros_domain)
        assert 'XMLPARSER' in output and 'serving /cam/evaluate' in output
    else:
        output = node_output({}, ros_domain)
        assert 'serving /cam/evaluate' in output
        assert 'XMLPARSER' not in output, output
