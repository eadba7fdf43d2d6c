"""Pure NumPy/SciPy kinematics core of cam_ros: laws, programs, geometry, config, designs.

Nothing here imports ROS; the node and the CLI are thin shells around these names.
"""
from .config import CamConfig, PARAMETERS, load_config, parse_parameters, read_parameters_file
from .design import CamDesign, CamState, build_design, check_angles
from .errors import CamError, InvalidParameter, RecordingError
from .geometry import (CamGeometry, GeometryCheck, OscillatingFlat, OscillatingRoller,
                       TranslatingFlat, TranslatingRoller, cam_geometry, check_geometry)
from .laws import LAWS, MotionLaw, make_law
from .program import MotionProgram, Segment

__all__ = [
    'CamConfig', 'CamDesign', 'CamError', 'CamGeometry', 'CamState', 'GeometryCheck',
    'InvalidParameter', 'LAWS', 'MotionLaw', 'MotionProgram', 'OscillatingFlat',
    'OscillatingRoller', 'PARAMETERS', 'RecordingError', 'Segment', 'TranslatingFlat',
    'TranslatingRoller', 'build_design', 'cam_geometry', 'check_angles', 'check_geometry',
    'load_config', 'make_law', 'parse_parameters', 'read_parameters_file',
]
