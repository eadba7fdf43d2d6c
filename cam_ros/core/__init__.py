"""Pure NumPy/SciPy kinematics core of cam_ros: laws, programs, geometry, config, designs.

Nothing here imports ROS; the node and the CLI are thin shells around these names.
"""
from .config import CamConfig, PARAMETERS, load_config, parse_parameters, read_parameters_file
from .design import CamDesign, CamState, build_design, check_angles
from .dynamics import DynamicsConfig, DynamicsValues, FollowerDynamics
from .errors import CamError, InvalidParameter, RecordingError
from .followers import (Follower, OscillatingFlat, OscillatingRoller, TranslatingFlat,
                        TranslatingRoller)
from .geometry import CamGeometry, cam_geometry
from .geometry_check import GeometryCheck, check_geometry
from .laws import LAWS, LawValues, MotionLaw, make_law
from .program import Discontinuity, MotionProgram, ProgramValues, Segment
from .sizing import BaseRadiusEstimate, BaseRadiusSizing, estimate_base_radius, size_base_radius

__all__ = [
    'BaseRadiusEstimate', 'BaseRadiusSizing', 'CamConfig', 'CamDesign', 'CamError',
    'CamGeometry', 'CamState', 'Discontinuity', 'DynamicsConfig', 'DynamicsValues', 'Follower',
    'FollowerDynamics', 'GeometryCheck', 'InvalidParameter',
    'LAWS', 'LawValues', 'MotionLaw', 'MotionProgram', 'OscillatingFlat', 'OscillatingRoller',
    'PARAMETERS', 'ProgramValues', 'RecordingError', 'Segment', 'TranslatingFlat',
    'TranslatingRoller', 'build_design', 'cam_geometry', 'check_angles', 'check_geometry',
    'estimate_base_radius', 'load_config', 'make_law', 'parse_parameters', 'read_parameters_file',
    'size_base_radius',
]
