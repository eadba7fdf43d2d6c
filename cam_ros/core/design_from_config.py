"""Build a CamDesign from a CamConfig: the follower, then the checks a design must pass.

Errors are InvalidParameter naming what the user wrote: the follower.* parameter, or the
segment and cam angle where the follower cannot follow the motion.
"""
from __future__ import annotations

import math
import re
from typing import Callable

from .cam_angles import TWO_PI
from .config.schema import CamConfig
from .design import CamDesign
from .errors import InvalidParameter
from .extremes import CHECK_SAMPLES
from .geometry.closure import second_roller_problem
from .geometry.followers import (Follower, OscillatingFlat, OscillatingRoller, TranslatingFlat,
                                 TranslatingRoller)
from .motion.program import MotionProgram
from .program_from_config import build_program, in_file_units


def build_follower(config: CamConfig) -> Follower | None:
    """Build the configured follower (None: motion only); errors name the follower.* parameter."""
    f = config.follower
    if config.motion_only:
        return None
    builders: dict[str, Callable[[], Follower]] = {
        'translating_roller': lambda: TranslatingRoller(f.base_radius, f.roller_radius, f.offset),
        'translating_flat': lambda: TranslatingFlat(f.base_radius),
        'oscillating_roller': lambda: OscillatingRoller(f.base_radius, f.roller_radius,
                                                        f.pivot_distance, f.arm_length,
                                                        f.arm_turns_with_cam),
        'oscillating_flat': lambda: OscillatingFlat(f.base_radius, f.pivot_distance,
                                                    f.face_offset, f.arm_turns_with_cam),
    }
    try:
        return builders[f.type]()
    except InvalidParameter as err:
        name = f'follower.{err.parameter}'
        written = config.parameters.get(name, err.value)
        raise InvalidParameter(name, written, in_file_units(err.rule, config)) from err


def build_design(config: CamConfig) -> CamDesign:
    """Build and validate the whole design; raises InvalidParameter naming the parameter."""
    program = build_program(config)
    follower = build_follower(config)
    design = CamDesign(config, program, follower)
    if follower is None:
        return design
    try:
        design.geometry()  # the follower must be able to follow the motion everywhere
    except InvalidParameter as err:
        raise _at_cam_angle(err, program, config) from err
    if config.follower.closure == 'conjugate':
        _check_second_cam(design)
    return design


def _check_second_cam(design: CamDesign) -> None:
    """Check that the conjugate pair's second roller can follow the motion everywhere."""
    f = design.config.follower
    name, value = (('follower.conjugate_angle_deg', math.degrees(f.conjugate_angle))
                   if design.config.oscillating else ('follower.closure', f.closure))
    problem = second_roller_problem(design.cam_follower, design.surface, f.conjugate_angle)
    if problem is not None:
        raise InvalidParameter(name, value, in_file_units(problem, design.config))


def _at_cam_angle(err: InvalidParameter, program: MotionProgram,
                  config: CamConfig) -> InvalidParameter:
    """Restate a geometry error at a check sample ('s[2812]') as the segment and cam angle.

    A follower position s is quoted in the file's units (its length_unit, or deg of arm angle).
    """
    match = re.fullmatch(r'(\w+)\[(\d+)\]', err.parameter)
    if not match:
        return err
    angle = int(match.group(2)) * TWO_PI / CHECK_SAMPLES
    index = program.segment_at(angle)
    value = err.value
    if match.group(1) == 's' and isinstance(value, float):
        value = value * config.file_position_unit[1]
    return InvalidParameter(f'motion.laws[{index}] ({program.segments[index].law.name}): '
                            f'{match.group(1)} at {math.degrees(angle):.2f} deg', value,
                            in_file_units(err.rule, config))
