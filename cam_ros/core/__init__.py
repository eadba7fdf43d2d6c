"""Pure NumPy/SciPy core of cam_ros: motion, geometry, dynamics, e-cam maths, config, designs.

Nothing here imports ROS; the node and the CLI are thin shells around these names. Subpackages by
concern: motion (laws, programs), geometry (followers, profile, checks, sizing), dynamics (forces,
contact), ecam (master tracking, handover, cam tables, switches), config (parameters, schema,
files).

The names are imported when first used (PEP 562 __getattr__): a command that needs a few of
them (`cam_ros call`, `param`, ...) does not pay for the rest at start-up.
"""
from __future__ import annotations

import importlib
from typing import TYPE_CHECKING

if TYPE_CHECKING:
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

#: Each public name's module, relative to this package.
_HOMES = {
    'check_angles': '.cam_angles',
    'PARAMETERS': '.config.parameters',
    'read_parameters_file': '.config.params_file',
    'CamConfig': '.config.schema',
    'load_config': '.config.schema',
    'parse_parameters': '.config.schema',
    'CamDesign': '.design',
    'CamState': '.design',
    'build_design': '.design_from_config',
    'DynamicsConfig': '.dynamics.follower',
    'DynamicsValues': '.dynamics.follower',
    'FollowerDynamics': '.dynamics.follower',
    'CamError': '.errors',
    'InvalidParameter': '.errors',
    'RecordingError': '.errors',
    'cam_geometry': '.geometry.cam_geometry',
    'CamGeometry': '.geometry.cam_geometry',
    'check_geometry': '.geometry.check',
    'GeometryCheck': '.geometry.check',
    'Follower': '.geometry.followers',
    'OscillatingFlat': '.geometry.followers',
    'OscillatingRoller': '.geometry.followers',
    'TranslatingFlat': '.geometry.followers',
    'TranslatingRoller': '.geometry.followers',
    'BaseRadiusEstimate': '.geometry.sizing',
    'BaseRadiusSizing': '.geometry.sizing',
    'estimate_base_radius': '.geometry.sizing',
    'size_base_radius': '.geometry.sizing',
    'LAWS': '.motion.laws',
    'LawValues': '.motion.laws',
    'make_law': '.motion.laws',
    'MotionLaw': '.motion.laws',
    'Discontinuity': '.motion.program',
    'MotionProgram': '.motion.program',
    'ProgramValues': '.motion.program',
    'Segment': '.motion.segment',
}

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


def __getattr__(name: str) -> object:
    """Import a public name from its module when it is first asked for."""
    home = _HOMES.get(name)
    if home is None:
        raise AttributeError(f'module {__name__!r} has no attribute {name!r}')
    value = getattr(importlib.import_module(home, __name__), name)
    globals()[name] = value
    return value


def __dir__() -> list[str]:
    """List the public names too, imported yet or not (help(), the API docs)."""
    return sorted({*globals(), *__all__})
