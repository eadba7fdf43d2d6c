"""Package-level checks: lint, types, layering, packaging metadata."""
from __future__ import annotations

import shutil
import subprocess
import sys
import xml.etree.ElementTree as ET
from pathlib import Path

from conftest import REPO

LINTED = ['cam_ros', 'test', 'benchmarks', 'setup.py']


def run(*command: str) -> subprocess.CompletedProcess:
    """Run a command in the repository and capture its output."""
    return subprocess.run(command, cwd=REPO, capture_output=True, text=True, timeout=300)


def test_flake8_clean():
    result = run(sys.executable, '-m', 'flake8', *LINTED)
    assert result.returncode == 0, result.stdout + result.stderr


def test_mypy_clean_on_core():
    result = run(sys.executable, '-m', 'mypy', '--ignore-missing-imports', 'cam_ros/core')
    assert result.returncode == 0, result.stdout + result.stderr


def test_core_never_imports_ros():
    probe = ('import sys, cam_ros.core; '
             'bad = sorted(m for m in sys.modules if m.split(".")[0] in '
             '{"rclpy", "rosidl_parser", "cam_ros_interfaces", "std_msgs"}); print(bad)')
    result = run(sys.executable, '-c', probe)
    assert result.returncode == 0, result.stderr
    assert result.stdout.strip() == '[]'


def test_package_xml_declares_ament_python_and_runtime_deps():
    root = ET.parse(REPO / 'package.xml').getroot()
    assert root.get('format') == '3'
    assert root.findtext('export/build_type') == 'ament_python'
    exec_deps = {element.text for element in root.iter('exec_depend')}
    imported = {'rclpy', 'std_srvs', 'sensor_msgs', 'trajectory_msgs', 'visualization_msgs',
                'geometry_msgs', 'std_msgs', 'cam_ros_interfaces', 'rcl_interfaces'}
    assert imported <= exec_deps


def test_executables_sit_where_ros2_run_looks_and_on_the_venv_path():
    for script in ('cam_node', 'cam_ros'):
        assert (Path(sys.prefix) / 'lib' / 'cam_ros' / script).is_file(), script
        assert shutil.which(script, path=str(Path(sys.executable).parent)), script


def test_evaluate_service_has_exactly_the_specified_fields():
    from cam_ros_interfaces.srv import EvaluateCam

    assert EvaluateCam.Request.get_fields_and_field_types() == {'angles': 'sequence<double>'}
    arrays = ('position', 'velocity', 'acceleration', 'jerk', 'pressure_angle',
              'radius_of_curvature', 'contact_force', 'camshaft_torque', 'contact_stress')
    expected = {'success': 'boolean', 'message': 'string'}
    expected.update((name, 'sequence<double>') for name in arrays)
    assert EvaluateCam.Response.get_fields_and_field_types() == expected
