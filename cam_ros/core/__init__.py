"""Pure NumPy/SciPy core of cam_ros: motion, geometry, dynamics, e-cam maths, config, designs.

Nothing here imports ROS; the node and the CLI are thin shells around these names. Subpackages by
concern: motion (laws, programs), geometry (followers, profile, checks, sizing), dynamics (forces,
contact), ecam (master tracking, handover, cam tables, switches), config (parameters, schema,
files).
"""
from .config.parameters import PARAMETERS
from .config.params_file import read_parameters_file
from .config.schema import CamConfig, load_config, parse_parameters
from .cam_angles import check_angles
from .design import CamDesign, CamState
from .design_from_config import build_design
from .dynamics.follower import DynamicsConfig, DynamicsValues, FollowerDynamics
from .errors import CamError, InvalidParameter, RecordingError
from .geometry.cam_geometry import CamGeometry, cam_geometry
from .geometry.check import GeometryCheck, check_geometry
from .geometry.followers import (Follower, OscillatingFlat, OscillatingRoller, TranslatingFlat,
                                 TranslatingRoller)
from .geometry.sizing import (BaseRadiusEstimate, BaseRadiusSizing, estimate_base_radius,
                              size_base_radius)
from .motion.laws import LAWS, LawValues, MotionLaw, make_law
from .motion.program import Discontinuity, MotionProgram, ProgramValues
from .motion.segment import Segment

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
