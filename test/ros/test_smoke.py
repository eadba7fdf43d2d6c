"""End-to-end smoke test: cam_node as a real process, a separate rclpy client, a clean SIGINT."""
from __future__ import annotations

import math
import signal

import numpy as np
from cam_ros_interfaces.srv import EvaluateCam
from conftest import CONFIG_DIR

from cam_ros.core import build_design, load_config

CALL_TIMEOUT_S = 10.0
# Seed 000's table (cycloidal rise of 2 cm over 90-180 deg, harmonic return 240-360 deg): follower
# position in cm at these cam angles, independent of our code.
SEED_000_POSITION_CM = {100.0: 0.018, 130.0: 0.780, 150.0: 1.609, 200.0: 2.000, 300.0: 1.000}
TABLE_TOLERANCE_M = 0.0005e-2
CAM_SPEED = 2 * math.pi  # rad/s in config/default.yaml


def test_node_serves_the_default_cam_and_stops_cleanly_on_sigint(start_cam_node):
    process, client = start_cam_node(CONFIG_DIR / 'default.yaml')
    degrees = np.array(sorted(SEED_000_POSITION_CM))
    angles = np.radians(degrees)
    # One angle written outside [0, 2 pi) to prove the modulo.
    angles[0] += 4 * math.pi
    response = client.call(EvaluateCam.Request(angles=angles.tolist()),
                           timeout_sec=CALL_TIMEOUT_S)
    assert response is not None and response.success, response
    np.testing.assert_allclose(response.position,
                               [SEED_000_POSITION_CM[d] * 1e-2 for d in degrees],
                               atol=TABLE_TOLERANCE_M)

    expected = build_design(load_config(CONFIG_DIR / 'default.yaml')).evaluate(angles)
    for field in ('position', 'velocity', 'acceleration', 'jerk', 'pressure_angle',
                  'radius_of_curvature'):
        np.testing.assert_array_equal(getattr(response, field), getattr(expected, field))
    # Velocity at the configured cam speed: seed 000's f' (cm/rad) at 130 deg is 2.470.
    np.testing.assert_allclose(response.velocity[1], 2.470e-2 * CAM_SPEED,
                               atol=TABLE_TOLERANCE_M * CAM_SPEED)

    assert process.stop(signal.SIGINT) == 0, process.log()
    assert 'Traceback' not in process.log()
