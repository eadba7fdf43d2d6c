"""Results the core keeps for inputs it sees again are those it computes anew, bit for bit.

A law's characteristic values are kept for equal laws, a design's geometry check for an equal
follower, surface, sense and limits (core/kept.py: a design is built anew on every edit or
parameter change); a design's check geometry is computed once per design.
"""
from __future__ import annotations

from pathlib import Path

import numpy as np
import pytest

from cam_ros.core import build_design, cam_geometry
from cam_ros.core.config.params_file import read_parameters_file
from cam_ros.core.config.schema import parse_parameters
from cam_ros.core.design import CamDesign, checked_geometry
from cam_ros.core.extremes import CHECK_SAMPLES
from cam_ros.core.geometry.check import GeometryCheck
from cam_ros.core.kept import forget
from cam_ros.core.motion.inflection import inflected
from cam_ros.core.motion.laws import make_law, SccaLaw

CONFIG_DIR = Path(__file__).resolve().parents[2] / 'config'
#: Laws of each kind of field: none, floats, tuples of floats, a law (inflected), solved.
LAWS = {'cycloidal': lambda: make_law('cycloidal'),
        'constant_acceleration': lambda: make_law('constant_acceleration'),
        'scca': lambda: SccaLaw(0.3, 0.2, 0.5),
        'table': lambda: make_law('table', u=[0.0, 0.4, 1.0], y=[0.0, 0.3, 1.0]),
        'via_point': lambda: make_law('via_point', u_via=0.3, y_via=0.2),
        'inflected': lambda: inflected(make_law('modified_sine'), 0.4),
        'poly5': lambda: make_law('poly5', stroke=1.0, span=1.0, start=(0.5, 0.0),
                                  end=(0.0, -1.0))}


@pytest.mark.parametrize('name', LAWS)
def test_a_law_built_again_gets_the_values_searched_for_its_equal(name: str) -> None:
    first, again = LAWS[name](), LAWS[name]()
    assert first is not again and first == again
    kept_values = first._characteristic_values
    assert again._characteristic_values is kept_values  # searched once
    forget()
    searched = LAWS[name]()._characteristic_values  # nothing kept: searched anew
    assert searched is not kept_values and searched == kept_values


def test_laws_told_apart_by_a_field_or_the_sign_of_a_zero_are_searched_each() -> None:
    laws = [SccaLaw(0.3, 0.2, 0.5), SccaLaw(0.25, 0.25, 0.5), SccaLaw(0.5, 0.0, 0.5),
            SccaLaw(0.5, -0.0, 0.5)]
    assert laws[2] == laws[3]  # equal as dataclasses: 0.0 == -0.0
    searched = []
    for law in laws:  # each searched anew, nothing kept
        forget()
        searched.append((law.cv, law.ca, law.cj))
    forget()
    again = [SccaLaw(0.3, 0.2, 0.5), SccaLaw(0.25, 0.25, 0.5), SccaLaw(0.5, 0.0, 0.5),
             SccaLaw(0.5, -0.0, 0.5)]  # the same laws built again, all kept together
    assert [(law.cv, law.ca, law.cj) for law in again] == searched
    assert again[3]._characteristic_values is not again[2]._characteristic_values
    assert laws[0].ca != laws[1].ca
    assert laws[3]._characteristic_values is not laws[2]._characteristic_values


def design_of(name: str = 'default.yaml', **changes: object) -> CamDesign:
    values = read_parameters_file(CONFIG_DIR / name)
    values.update(changes)
    return build_design(parse_parameters(values))


def same_check(a: GeometryCheck, b: GeometryCheck) -> bool:
    """Say whether two checks hold the same figures, array for array, bit for bit."""
    return vars(a).keys() == vars(b).keys() and all(
        np.array_equal(value, vars(b)[name], equal_nan=True) if isinstance(value, np.ndarray)
        else repr(value) == repr(vars(b)[name]) for name, value in vars(a).items())


def test_a_new_cam_speed_alone_keeps_the_check_and_a_new_limit_does_not() -> None:
    first = design_of()
    faster = design_of(cam_speed=2.0 * first.config.cam_speed)
    assert faster.check is first.check  # the same follower, motion, sense and limits
    config = faster.config
    fresh = checked_geometry(faster.cam_follower, faster.surface, faster.clockwise,
                             config.pressure_angle_limit, config.min_radius_of_curvature,
                             config.pressure_angle_return_limit)  # not kept
    assert fresh is not first.check and same_check(fresh, first.check)
    stricter = design_of(**{'limits.pressure_angle_deg': 20.0})
    assert stricter.check is not first.check
    assert stricter.check.pressure_angle_limit < first.check.pressure_angle_limit


def test_a_polydyne_cam_is_checked_anew_at_a_new_cam_speed() -> None:
    first = design_of('polydyne.yaml')
    faster = design_of('polydyne.yaml', cam_speed=1.5 * first.config.cam_speed)
    assert faster.surface is not faster.program  # the surface is made at the cam speed
    assert faster.check is not first.check
    assert faster.check.max_pressure_angle != first.check.max_pressure_angle


def test_the_check_geometry_is_computed_once_and_is_the_geometry_at_its_samples() -> None:
    design = design_of()
    kept = design.geometry()
    assert design.geometry(CHECK_SAMPLES) is kept and kept.theta.size == CHECK_SAMPLES
    theta = np.linspace(0.0, 2.0 * np.pi, CHECK_SAMPLES, endpoint=False)
    motion = design.surface.evaluate(theta)
    fresh = cam_geometry(design.cam_follower, theta, motion.s, motion.ds, motion.d2s,
                         clockwise=design.clockwise)
    for name in ('theta', 'pitch_x', 'pitch_y', 'surface_x', 'surface_y', 'pressure_angle'):
        assert np.array_equal(getattr(kept, name), getattr(fresh, name))
        assert not getattr(kept, name).flags.writeable  # shared, so never changed in place
    other = design.geometry(360)
    assert other.theta.size == 360 and design.geometry(360) is not other
