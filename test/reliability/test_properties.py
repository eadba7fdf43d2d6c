"""Properties over random valid designs (hypothesis): finite, continuous where promised, monotone.

Random motion programs split 360 deg at random angles into 2-6 segments from a random start, with
random laws from the registry (the laws that need parameters get sensible random ones) and random
strokes; random followers of every kind with valid radii, offsets and arms. They go through the
public path (flat config values -> parse_parameters -> build_design). The expectations come from
the laws' end conditions written out here (docs/motion.md's continuity column), not from the code.
"""
from __future__ import annotations

import math
from dataclasses import dataclass, field
from typing import Any

import numpy as np
import pytest
from hypothesis import given, HealthCheck, settings
from hypothesis import strategies as st

from cam_ros.core import (build_design, LAWS, make_law, parse_parameters, size_base_radius,
                          TranslatingFlat, TranslatingRoller)

#: Highest derivative order k such that y', ..., y^(k) all vanish at both ends (u = 0 and 1):
#: where two segments meet, s and its derivatives up to min(k_left, k_right) are continuous.
REST_ORDER = {
    'dwell': 3, 'constant_velocity': 0, 'constant_acceleration': 1, 'simple_harmonic': 1,
    'cycloidal': 2, 'polynomial_345': 2, 'polynomial_4567': 3, 'polynomial_9': 3,
    'modified_trapezoid': 2,
    'modified_sine': 2, 'polynomial': 2, 'table': 2, 'via_point': 2,
    'scca': 2,  # with b > 0; b = 0 starts and ends at full acceleration (order 1)
    'poly5': 2, 'poly7': 3,  # drawn with all given end values 0: rest to rest (R-R)
}
#: The boundary polynomials at rest at both ends (unit stroke and span: the normalised law).
AT_REST = {'poly5': {'stroke': 1.0, 'span': 1.0, 'start': (0.0, 0.0), 'end': (0.0, 0.0)},
           'poly7': {'stroke': 1.0, 'span': 1.0, 'start': (0.0, 0.0, 0.0),
                     'end': (0.0, 0.0, 0.0)}}
#: End values (y'(0), y''(0), y'''(0)) and (y'(1), y''(1), y'''(1)) written out from the formulas.
PI = math.pi
END_VALUES = {
    'constant_velocity': ((1.0, 0.0, 0.0), (1.0, 0.0, 0.0)),
    'constant_acceleration': ((0.0, 4.0, 0.0), (0.0, -4.0, 0.0)),
    'simple_harmonic': ((0.0, PI ** 2 / 2, 0.0), (0.0, -PI ** 2 / 2, 0.0)),
    'cycloidal': ((0.0, 0.0, 4 * PI ** 2), (0.0, 0.0, 4 * PI ** 2)),
    'polynomial_345': ((0.0, 0.0, 60.0), (0.0, 0.0, 60.0)),
    'polynomial_4567': ((0.0, 0.0, 0.0), (0.0, 0.0, 0.0)),
    'polynomial_9': ((0.0, 0.0, 0.0), (0.0, 0.0, 0.0)),
}
#: y(0), y(1) and the end derivatives written above (relative); a law solved from conditions
#: (polynomial) is exact to its linear solve, like its own END_TOLERANCE.
BOUNDARY_TOLERANCE = 1e-9
#: A derivative promised continuous changes across a joint (+-JOINT_STEP rad) by at most this
#: fraction of its scale |h| / beta**k on either side; a real jump is of order 1.
JOINT_STEP = 1e-11
CONTINUITY_RTOL = 1e-6
MIN_SPAN_DEG = 6.0
PROGRAM_ANGLES = 997  # random evaluation angles per design
SIZING_SAMPLES = 720
SIZING_TOLERANCE = 1e-9  # m, sizing.SIZING_TOLERANCE (the radius is within it of the exact one)
#: SCCA fractions are drawn on a grid of this many steps (see the report on tiny fractions).
SCCA_STEPS = 64
MOVING_LAWS = sorted(set(LAWS) - {'dwell'})
HYPOTHESIS = dict(deadline=None, database=None,
                  suppress_health_check=[HealthCheck.too_slow, HealthCheck.data_too_large,
                                         HealthCheck.function_scoped_fixture])


@dataclass
class Program:
    """A random motion program as config values (deg; positions in m or arm deg)."""

    laws: list[str]
    start_deg: list[float]
    end_deg: list[float]
    start_position: list[float]
    end_position: list[float]
    extra: dict[str, Any] = field(default_factory=dict)

    def values(self) -> dict[str, Any]:
        """Return the motion.* parameters."""
        return {'motion.laws': self.laws, 'motion.start_deg': self.start_deg,
                'motion.end_deg': self.end_deg, 'motion.start_position': self.start_position,
                'motion.end_position': self.end_position, **self.extra}


@st.composite
def scca_fractions(draw) -> tuple[float, float, float]:
    """Draw SCCA fractions b > 0, c, d >= 0 adding up to 1, in steps of 1/SCCA_STEPS."""
    b = draw(st.integers(1, SCCA_STEPS))
    c = draw(st.integers(0, SCCA_STEPS - b))
    return b / SCCA_STEPS, c / SCCA_STEPS, (SCCA_STEPS - b - c) / SCCA_STEPS


@st.composite
def table_points(draw) -> tuple[list[float], list[float]]:
    """Draw a table law: rising u with y of a smooth monotone curve through them."""
    inner = sorted(draw(st.sets(st.floats(0.1, 0.9).map(lambda x: round(x, 3)),
                                min_size=0, max_size=4)))
    u = [0.0, *inner, 1.0]
    if any(b - a < 0.05 for a, b in zip(u, u[1:])):
        u = [0.0, 1.0]
    power = draw(st.floats(0.7, 1.5))
    y = [float(3 * x ** 2 - 2 * x ** 3) ** power for x in u]
    y[0], y[-1] = 0.0, 1.0
    return u, y


@st.composite
def programs(draw, unit_range: tuple[float, float]) -> Program:
    """Draw a closed program over 360 deg: dwells where levels repeat, random laws elsewhere."""
    count = draw(st.integers(2, 6))
    cuts = sorted(draw(st.lists(st.floats(MIN_SPAN_DEG, 360.0 - MIN_SPAN_DEG).map(round),
                                min_size=count - 1, max_size=count - 1, unique=True)))
    edges = [0.0, *map(float, cuts), 360.0]
    if any(b - a < MIN_SPAN_DEG for a, b in zip(edges, edges[1:])):
        edges = [360.0 * k / count for k in range(count + 1)]
    start = float(draw(st.integers(-180, 180)))
    unit = draw(st.floats(*unit_range))
    levels = draw(st.lists(st.integers(0, 4), min_size=count, max_size=count))
    levels[0] = 0
    if len(set(levels)) == 1:
        levels[1] = 1
    positions = [unit * level for level in levels] + [0.0]
    laws = [draw(st.sampled_from(MOVING_LAWS)) if a != b else 'dwell'
            for a, b in zip(positions, positions[1:])]
    program = Program(laws, [start + a for a in edges[:-1]], [start + b for b in edges[1:]],
                      positions[:-1], positions[1:])
    if 'scca' in laws:
        program.extra['motion.scca_fractions'] = list(draw(scca_fractions()))
    tables = [draw(table_points()) for law in laws if law == 'table']
    if tables:
        program.extra.update({'motion.table_u': [x for u, _ in tables for x in u],
                              'motion.table_y': [x for _, y in tables for x in y]})
    if len(tables) > 1:
        program.extra['motion.table_counts'] = [len(u) for u, _ in tables]
    if AT_REST.keys() & set(laws):  # every end of a boundary polynomial given: rest
        program.extra.update({f'motion.{side}_{name}': [
            0.0 if law in AT_REST and (name != 'jerk' or law == 'poly7') else math.nan
            for law in laws] for side in ('start', 'end')
            for name in ('velocity', 'acceleration', 'jerk')})
    vias = [index for index, law in enumerate(laws) if law in ('via_point', 'polynomial')]
    if vias:
        fractions = [(draw(st.floats(0.15, 0.85)), draw(st.floats(0.15, 0.85))) for _ in vias]
        program.extra.update({
            'motion.via_segment': vias,
            'motion.via_deg': [program.start_deg[i] + u * (program.end_deg[i] -
                                                           program.start_deg[i])
                               for i, (u, _) in zip(vias, fractions)],
            'motion.via_position': [program.start_position[i] + y * (program.end_position[i] -
                                                                     program.start_position[i])
                                    for i, (_, y) in zip(vias, fractions)]})
    return program


@st.composite
def followers(draw, kind: str) -> dict[str, Any]:
    """Draw a valid follower of a kind (m; the arm geometry built from its initial angle)."""
    if kind == 'translating_roller':
        base, roller = draw(st.floats(0.02, 0.1)), draw(st.floats(0.005, 0.03))
        offset = draw(st.floats(-0.8, 0.8)) * (base + roller)
        return {'base_radius': base, 'roller_radius': roller, 'offset': offset}
    if kind == 'translating_flat':
        return {'base_radius': draw(st.floats(0.02, 0.1))}
    pivot = draw(st.floats(0.08, 0.2))
    turns = draw(st.booleans())
    if kind == 'oscillating_roller':
        arm, psi0 = draw(st.floats(0.04, 0.15)), math.radians(draw(st.floats(35.0, 110.0)))
        prime = math.sqrt(pivot ** 2 + arm ** 2 - 2 * pivot * arm * math.cos(psi0))
        roller = draw(st.floats(0.05, 0.4)) * prime
        return {'base_radius': prime - roller, 'roller_radius': roller, 'pivot_distance': pivot,
                'arm_length': arm, 'arm_turns_with_cam': turns}
    base = draw(st.floats(0.02, 0.05))
    face = draw(st.floats(-0.01, 0.02))
    return {'base_radius': base, 'pivot_distance': max(pivot, 2 * (base + face)),
            'face_offset': face, 'arm_turns_with_cam': turns}


#: Stroke unit per follower kind: m for translating, arm deg for oscillating followers.
UNITS = {'translating_roller': (0.002, 0.01), 'translating_flat': (0.002, 0.01),
         'oscillating_roller': (1.0, 4.0), 'oscillating_flat': (0.5, 2.0)}
#: Share of the follower's free travel (to its nearest geometric limit) a drawn motion may use,
#: overshoot included: a polynomial through a via point can overshoot its stroke several times.
ROOM_SHARE = 0.5
#: Largest arm speed |ds/dtheta| drawn for the oscillating flat face (its arm must turn slower
#: than the cam).
FLAT_ARM_SPEED = 0.5
#: Normalised rise samples used to find a program's extreme positions.
EXCURSION_U = np.linspace(0.0, 1.0, 2001)


def room(kind: str, follower: dict[str, Any]) -> tuple[float, float]:
    """Return how far the follower may travel below and above its rest position (m or arm deg).

    Derived here from the geometry (not taken from the core): a translating follower must stay
    above the cam centre, an arm angle psi0 + s inside (0, pi), a flat face clear of the centre.
    """
    if kind == 'translating_roller':
        prime = follower['base_radius'] + follower['roller_radius']
        return math.sqrt(prime ** 2 - follower['offset'] ** 2), math.inf
    if kind == 'translating_flat':
        return follower['base_radius'], math.inf
    pivot = follower['pivot_distance']
    if kind == 'oscillating_roller':
        arm, prime = follower['arm_length'], follower['base_radius'] + follower['roller_radius']
        psi0 = math.acos((pivot ** 2 + arm ** 2 - prime ** 2) / (2 * pivot * arm))
        lowest = 0.0
    else:
        psi0 = math.asin((follower['base_radius'] + follower['face_offset']) / pivot)
        lowest = math.asin(max(follower['face_offset'], 0.0) / pivot)
    return math.degrees(psi0 - lowest), math.degrees(math.pi - lowest - psi0)


def fit(kind: str, follower: dict[str, Any], program: Program) -> Program:
    """Scale a program's positions so the follower uses at most ROOM_SHARE of its free travel
    and an oscillating flat face's arm turns at most FLAT_ARM_SPEED."""
    lowest = highest = peak_speed = 0.0
    for index, name in enumerate(program.laws):
        if name == 'dwell':
            continue
        law, start, end = (law_of(program, index), program.start_position[index],
                           program.end_position[index])
        y = law.evaluate(EXCURSION_U)[0]
        lowest = min(lowest, float(np.min(start + (end - start) * y)))
        highest = max(highest, float(np.max(start + (end - start) * y)))
        span = math.radians(program.end_deg[index] - program.start_deg[index])
        peak_speed = max(peak_speed, math.radians(abs(end - start)) * law.cv / span)
    below, above = room(kind, follower)
    scale = min(1.0, ROOM_SHARE * below / -lowest if lowest < 0.0 else 1.0,
                ROOM_SHARE * above / highest if highest > 0.0 else 1.0)
    if kind == 'oscillating_flat':
        scale = min(scale, FLAT_ARM_SPEED / peak_speed)
    extra = dict(program.extra)
    if 'motion.via_position' in extra:
        extra['motion.via_position'] = [p * scale for p in extra['motion.via_position']]
    return Program(program.laws, program.start_deg, program.end_deg,
                   [p * scale for p in program.start_position],
                   [p * scale for p in program.end_position], extra)


def law_of(program: Program, index: int):
    """Build segment index's law from the drawn parameters (to size strokes and spans)."""
    name, extra = program.laws[index], program.extra
    if name == 'scca':
        b, c, d = extra['motion.scca_fractions']
        return make_law('scca', b=b, c=c, d=d)
    if name == 'table':
        slot = program.laws[:index].count('table')
        counts = extra.get('motion.table_counts', [len(extra['motion.table_u'])])
        first = sum(counts[:slot])
        points = slice(first, first + counts[slot])
        return make_law('table', u=extra['motion.table_u'][points],
                        y=extra['motion.table_y'][points])
    if name in AT_REST:
        return make_law(name, **AT_REST[name])
    if name in ('via_point', 'polynomial'):
        slot = extra['motion.via_segment'].index(index)
        span = program.end_deg[index] - program.start_deg[index]
        stroke = program.end_position[index] - program.start_position[index]
        u = (extra['motion.via_deg'][slot] - program.start_deg[index]) / span
        y = (extra['motion.via_position'][slot] - program.start_position[index]) / stroke
        if name == 'via_point':
            return make_law(name, u_via=u, y_via=y)
        rest = ((0.0, 0, 0.0), (0.0, 1, 0.0), (0.0, 2, 0.0), (1.0, 0, 1.0), (1.0, 1, 0.0),
                (1.0, 2, 0.0))
        return make_law(name, conditions=[*rest, (u, 0, y)])
    return make_law(name)


@st.composite
def designs(draw) -> tuple[str, dict[str, Any], Program]:
    """Draw a follower kind, a follower and a program it can follow; return them as config."""
    kind = draw(st.sampled_from(sorted(UNITS)))
    follower = draw(followers(kind))
    program = draw(programs(UNITS[kind]))
    return kind, follower, fit(kind, follower, program)


def config_values(kind: str, follower: dict[str, Any], program: Program,
                  clockwise: bool) -> dict[str, Any]:
    """Return the flat parameters of a whole design (lengths in m)."""
    values = {'length_unit': 'm', 'rotation': 'clockwise' if clockwise else 'counterclockwise',
              'follower.type': kind, **{f'follower.{k}': v for k, v in follower.items()},
              **program.values()}
    return values


def rest_order(program: Program, index: int) -> int:
    """Return REST_ORDER of segment index (SCCA with b = 0 rests to order 1 only)."""
    name = program.laws[index]
    if name == 'scca' and program.extra['motion.scca_fractions'][0] == 0.0:
        return 1
    return REST_ORDER[name]


def test_every_law_has_a_rest_order():
    assert set(REST_ORDER) == set(LAWS)


def test_random_designs_are_finite_and_continuous_where_promised(effort, report):
    checked = {'designs': 0, 'joints': 0}

    @settings(max_examples=effort.examples, **HYPOTHESIS)
    @given(drawn=designs(), clockwise=st.booleans(), seed=st.integers(0, 2**32 - 1))
    def check(drawn, clockwise, seed):
        kind, follower, program = drawn
        design = build_design(parse_parameters(config_values(kind, follower, program,
                                                             clockwise)))
        angles = np.random.default_rng(seed).uniform(-20.0, 20.0, PROGRAM_ANGLES)
        state = design.evaluate(angles)
        for name in ('position', 'velocity', 'acceleration', 'jerk', 'pressure_angle'):
            assert np.all(np.isfinite(getattr(state, name))), name
        assert not np.any(np.isnan(state.radius_of_curvature))  # +-inf at an inflection

        motion = design.program
        listed = {(round(jump.angle, 9), jump.order) for jump in motion.continuity_report()}
        for index, segment in enumerate(motion.segments):
            before = motion.segments[index - 1]
            joint = segment.start
            left, right = motion.evaluate([joint - JOINT_STEP]), motion.evaluate(
                [joint + JOINT_STEP])
            promised = min(rest_order(program, index - 1 if index else len(motion.segments) - 1),
                           rest_order(program, index))
            for order, name in enumerate(('s', 'ds', 'd2s', 'd3s')):
                if order > promised:
                    break
                scale = max(abs(seg.stroke) / seg.span ** order for seg in (before, segment))
                change = abs(float(getattr(right, name)[0] - getattr(left, name)[0]))
                assert change <= CONTINUITY_RTOL * scale, (index, name, change, scale)
                assert (round(joint, 9), order) not in listed, (index, order)
            checked['joints'] += 1
        checked['designs'] += 1

    check()
    report('random designs evaluated (finite, continuous where promised)', checked['designs'])
    report('joints checked', checked['joints'])


def law_params(name: str) -> st.SearchStrategy[dict[str, Any]]:
    """Return a strategy of sensible parameters of a law (none for most)."""
    if name == 'scca':
        return scca_fractions().map(lambda f: dict(zip('bcd', f)))
    if name == 'table':
        return table_points().map(lambda p: {'u': p[0], 'y': p[1]})
    if name == 'via_point':
        return st.tuples(st.floats(0.05, 0.95), st.floats(0.05, 0.95)).map(
            lambda p: {'u_via': p[0], 'y_via': p[1]})
    if name in AT_REST:
        return st.just(AT_REST[name])
    if name == 'polynomial':
        return st.tuples(st.floats(0.05, 0.95), st.floats(0.05, 0.95)).map(
            lambda p: {'conditions': [(0.0, 0, 0.0), (0.0, 1, 0.0), (0.0, 2, 0.0),
                                      (1.0, 0, 1.0), (1.0, 1, 0.0), (1.0, 2, 0.0),
                                      (p[0], 0, p[1])]})
    return st.just({})


@pytest.mark.parametrize('name', sorted(LAWS))
def test_every_law_starts_at_0_and_ends_at_1_at_rest_as_promised(name, effort):
    @settings(max_examples=max(1, effort.examples // 4), **HYPOTHESIS)
    @given(params=law_params(name))
    def check(params):
        law = make_law(name, **params)
        y, y1, y2, y3 = law.evaluate(np.array([0.0, 1.0]))
        assert abs(y[0]) <= BOUNDARY_TOLERANCE
        assert abs(y[1] - (0.0 if name == 'dwell' else 1.0)) <= BOUNDARY_TOLERANCE
        order = REST_ORDER[name] if name != 'scca' or params['b'] > 0 else 1
        for k, values in enumerate((y1, y2, y3), start=1):
            if k <= order:
                scale = max(1.0, (law.cv, law.ca, law.cj)[k - 1])
                assert abs(values[0]) <= BOUNDARY_TOLERANCE * scale, (k, values)
                assert abs(values[1]) <= BOUNDARY_TOLERANCE * scale, (k, values)
        if name in END_VALUES:
            np.testing.assert_allclose(np.array([y1, y2, y3]).T, END_VALUES[name],
                                       rtol=BOUNDARY_TOLERANCE, atol=BOUNDARY_TOLERANCE)

    check()


@st.composite
def translating_programs(draw) -> tuple[np.ndarray, ...]:
    """Draw a translating program and sample it densely: theta, s, ds, d2s."""
    program = draw(programs(UNITS['translating_roller']))
    values = {'length_unit': 'm', 'follower.type': 'translating_flat',
              'follower.base_radius': 1.0, **program.values()}
    motion = build_design(parse_parameters(values)).program
    theta = np.linspace(0.0, 2 * math.pi, SIZING_SAMPLES, endpoint=False)
    sampled = motion.evaluate(theta)
    return theta, sampled.s, sampled.ds, sampled.d2s


def test_a_tighter_limit_never_needs_a_smaller_base_radius(effort, report):
    sized = []

    @settings(max_examples=effort.scaled(30, 300), **HYPOTHESIS)
    @given(motion=translating_programs(), clockwise=st.booleans(),
           roller=st.floats(0.005, 0.03), offset=st.floats(-0.01, 0.01),
           limits=st.tuples(st.floats(15.0, 60.0), st.floats(15.0, 60.0)),
           radii=st.tuples(st.floats(0.0, 0.02), st.floats(0.0, 0.02)))
    def check(motion, clockwise, roller, offset, limits, radii):
        loose_deg, tight_deg = max(limits), min(limits)
        follower = TranslatingRoller(1.0, roller, offset)
        loose = size_base_radius(follower, *motion, clockwise=clockwise,
                                 max_pressure_angle=math.radians(loose_deg))
        tight = size_base_radius(follower, *motion, clockwise=clockwise,
                                 max_pressure_angle=math.radians(tight_deg))
        assert_not_smaller(tight, loose)
        flat = TranslatingFlat(1.0)
        lax = size_base_radius(flat, *motion, min_radius=min(radii))
        strict = size_base_radius(flat, *motion, min_radius=max(radii))
        assert_not_smaller(strict, lax)
        sized.append(loose.base_radius)

    check()
    report('sizing pairs checked', 2 * len(sized))


def assert_not_smaller(tight, loose) -> None:
    """A tighter limit's radius is at least the looser one's (infeasible counts as infinite)."""
    if tight.feasible:
        assert loose.feasible, (tight, loose)
        assert tight.base_radius >= loose.base_radius - 2 * SIZING_TOLERANCE, (tight, loose)
