"""The motion program of a config: one law per segment from the motion.* arrays.

Errors name the motion.* parameter as written in the file, its index and the file's units, so
that a core rule ('segments[2].end') reads in the user's own terms.
"""
from __future__ import annotations

import math
import re
from typing import Any, Mapping

from .config.parameters import UNITS
from .config.schema import CamConfig, MotionConfig
from .errors import InvalidParameter, quote
from .motion.laws import MotionLaw, make_law
from .motion.program import MotionProgram
from .motion.tasks import BOUNDARY_LAWS, build_segments, TaskSpec

#: Boundary conditions of the 3-4-5 law (u, derivative order, value) that a polynomial segment
#: with via points keeps: rest to rest with zero acceleration at both ends.
REST_TO_REST = ((0.0, 0, 0.0), (0.0, 1, 0.0), (0.0, 2, 0.0),
                (1.0, 0, 1.0), (1.0, 1, 0.0), (1.0, 2, 0.0))
SEGMENT_FIELDS = {'start': 'motion.start_deg', 'end': 'motion.end_deg',
                  's_start': 'motion.start_position', 's_end': 'motion.end_position',
                  'law': 'motion.laws', 'inflection': 'motion.inflection',
                  **{f'{side}_{name}': f'motion.{side}_{name}' for side in ('start', 'end')
                     for name in ('velocity', 'acceleration', 'jerk')}}
#: The config array that gives each law parameter (via points, SCCA fractions, table points).
LAW_FIELDS = {'u_via': 'motion.via_deg', 'y_via': 'motion.via_position',
              'conditions': 'motion.via_deg', 'b': 'motion.scca_fractions',
              'c': 'motion.scca_fractions', 'd': 'motion.scca_fractions',
              'b + c + d': 'motion.scca_fractions', 'u': 'motion.table_u', 'y': 'motion.table_y'}
#: A number as the core quotes it (repr, :g or pi), and one or a pair of them with an SI unit.
NUMBER = r'-?(?:\d+\.?\d*|\.\d+)(?:e[-+]?\d+)?|pi'
SI_QUANTITY = re.compile(
    rf'(?<![\w.])((?:{NUMBER})|\((?:{NUMBER}), (?:{NUMBER})\)) (m|rad)(?![\w/^])')


def in_file_units(text: str, config: CamConfig) -> str:
    """Restate the lengths (m) and angles (rad) a core message quotes in the file's units."""
    metre, unit = UNITS[config.length_unit], config.length_unit

    def restate(match: re.Match) -> str:
        numbers = [math.pi if n == 'pi' else float(n) for n in re.findall(NUMBER, match.group(1))]
        angle = match.group(2) == 'rad'
        shown = ', '.join(f'{math.degrees(n) if angle else n / metre:g}' for n in numbers)
        if match.group(1).startswith('('):
            shown = f'({shown})'
        return f'{shown} {"deg" if angle else unit}'

    return SI_QUANTITY.sub(restate, text.replace('(m)', f'({unit})'))


def build_law(motion: MotionConfig, index: int, written: Mapping[str, Any]) -> MotionLaw:
    """Build segment index's law with the parameters the config gives for it.

    Errors name the config entry (motion.via_deg[i], motion.scca_fractions, ...) as written.
    """
    name = motion.laws[index]
    params: dict[str, object] = {}
    vias = [number for number, segment in enumerate(motion.via_segment) if segment == index]
    if vias and name not in ('via_point', 'polynomial'):
        raise InvalidParameter(f'motion.via_segment[{vias[0]}]', index,
                               f'law {name} takes no via points (via_point and polynomial do)')
    start, span = motion.start[index], motion.end[index] - motion.start[index]
    stroke = motion.end_position[index] - motion.start_position[index]
    for number in vias:
        if not 0.0 < motion.via_angle[number] - start < span:
            raise InvalidParameter(
                f'motion.via_deg[{number}]', written['motion.via_deg'][number],
                f'must lie strictly inside segment {index}, between motion.start_deg[{index}] = '
                f'{written["motion.start_deg"][index]!r} and motion.end_deg[{index}] = '
                f'{written["motion.end_deg"][index]!r}')
    if name == 'via_point':
        if len(vias) != 1:
            raise InvalidParameter(f'motion.laws[{index}]', name,
                                   f'needs exactly one via point (motion.via_segment has '
                                   f'{len(vias)} entries equal to {index})')
        lift = motion.via_position[vias[0]] - motion.start_position[index]
        rise = lift / stroke if stroke else math.nan  # nan: no rise to pass through
        if not 0.0 < rise < 1.0:
            raise InvalidParameter(
                f'motion.via_position[{vias[0]}]', written['motion.via_position'][vias[0]],
                f'must lie strictly between motion.start_position[{index}] = '
                f'{written["motion.start_position"][index]!r} and motion.end_position[{index}]'
                f' = {written["motion.end_position"][index]!r} (the via_point law rises '
                'through it without stopping)')
        params = {'u_via': (motion.via_angle[vias[0]] - start) / span, 'y_via': rise}
    elif name == 'polynomial':
        params = {'conditions': [*REST_TO_REST, *(
            ((motion.via_angle[number] - start) / span, 0,
             (motion.via_position[number] - motion.start_position[index]) / stroke)
            for number in vias if stroke)]}
    elif name == 'scca':
        if len(motion.scca_fractions) != 3:
            raise InvalidParameter('motion.scca_fractions', list(motion.scca_fractions),
                                   f'needs 3 entries b, c, d for the scca law of segment {index}')
        params = dict(zip('bcd', motion.scca_fractions))
    elif name == 'table':
        params = dict(zip('uy', table_points(motion, index)))
    return make_law(name, **params)


def table_points(motion: MotionConfig, index: int) -> tuple[tuple[float, ...], ...]:
    """Return the (u, y) points of the table segment index: its share of table_u/table_y.

    One table segment takes them all; with more, motion.table_counts says how many each takes,
    in segment order, so no two segments ever share a shape by accident.
    """
    tables = [number for number, law in enumerate(motion.laws) if law == 'table']
    counts, total = motion.table_counts, len(motion.table_u)
    if not counts and len(tables) == 1:
        return motion.table_u, motion.table_y
    if len(counts) != len(tables):
        raise InvalidParameter('motion.table_counts', list(counts),
                               f'needs one entry per table segment ({len(tables)}: segments '
                               f'{", ".join(map(str, tables))}) giving how many of the '
                               f'motion.table_u/table_y points each takes, in segment order')
    if any(count < 2 for count in counts) or sum(counts) != total:
        raise InvalidParameter('motion.table_counts', list(counts),
                               f'must be counts of at least 2 adding up to the {total} '
                               f'motion.table_u points')
    first = sum(counts[:tables.index(index)])
    end = first + counts[tables.index(index)]
    return motion.table_u[first:end], motion.table_y[first:end]


def build_program(config: CamConfig) -> MotionProgram:
    """Build the motion program; errors name the motion.* parameter (as written) and index."""
    motion, written = config.motion, config.parameters
    for index, segment in enumerate(motion.via_segment):
        if not 0 <= segment < len(motion.laws):
            raise InvalidParameter(f'motion.via_segment[{index}]', segment,
                                   f'must be a segment index in [0, {len(motion.laws) - 1}]')
    specs = []
    for index in range(len(motion.laws)):
        try:
            law = (motion.laws[index] if motion.laws[index] in BOUNDARY_LAWS
                   else build_law(motion, index, written))
        except InvalidParameter as err:
            if err.parameter.startswith('motion.'):
                raise
            field = LAW_FIELDS.get(err.parameter)
            if field is None:
                raise InvalidParameter(f'motion.laws[{index}] ({motion.laws[index]}): '
                                       f'{err.parameter}', err.value, err.rule) from err
            what = '' if err.parameter in ('u', 'y', 'conditions') else (
                f'{err.parameter} = {quote(err.value)}: ')
            raise InvalidParameter(field, list(written.get(field, ())), f'{what}{err.rule} '
                                   f'({motion.laws[index]} law of segment {index})') from err
        specs.append(TaskSpec(law, motion.start[index], motion.end[index],
                              motion.start_position[index], motion.end_position[index],
                              motion.begin[index], motion.finish[index],
                              motion.inflection[index]))
    # A motion-only design may end elsewhere than it starts: it advances by that each cycle.
    advance = motion.end_position[-1] - motion.start_position[0] if config.motion_only else 0.0
    try:
        return MotionProgram(build_segments(specs), advance=advance)
    except InvalidParameter as err:
        restated = _in_config_terms(err, written)
        raise InvalidParameter(restated.parameter, restated.value,
                               _slopes_in_file_units(restated.rule, config)) from err


def _slopes_in_file_units(text: str, config: CamConfig) -> str:
    """Restate the derivatives per rad a core message quotes ('0.5 per rad^2') per degree."""
    unit, scale = config.file_position_unit

    def restate(match: re.Match) -> str:
        order = int(match.group(2))
        value = float(match.group(1)) * scale * math.radians(1.0) ** order + 0.0  # no -0
        return f'{value:.6g} {unit}/deg' + (f'^{order}' if order > 1 else '')

    return re.sub(rf'({NUMBER}) per rad\^([123])', restate, text)


def _in_config_terms(err: InvalidParameter, written: Mapping[str, Any]) -> InvalidParameter:
    """Restate a program error ('segments[2].end') with the config's names and written values.

    Values the rule quotes in SI (segments[1].end = 1.5707963267948966 rad) become the entries
    as the file gives them (motion.end_deg[1] = 90.0).
    """
    def entry(match: re.Match) -> str:
        field, number = SEGMENT_FIELDS.get(match.group(2)), int(match.group(1))
        if field is None:
            return match.group(0)
        values = written.get(field)
        value = values[number] if isinstance(values, (list, tuple)) and number < len(values) \
            else None
        quoted = f' = {value!r}' if match.group(3) and value is not None else match.group(3)
        return f'{field}[{number}]{quoted or ""}'

    match = re.fullmatch(r'segments\[(\d+)\]\.(\w+)', err.parameter)
    if not match or match.group(2) not in SEGMENT_FIELDS:
        return InvalidParameter(f'motion ({err.parameter})', err.value, err.rule)
    field, index = SEGMENT_FIELDS[match.group(2)], int(match.group(1))
    values = written.get(field)
    value = values[index] if isinstance(values, (list, tuple)) and index < len(values) \
        else err.value
    rule = re.sub(r'(?<![\w.])(s_start|start) = ', rf'segments[{index}].\1 = ', err.rule)
    rule = re.sub(r'segments\[(\d+)\]\.(\w+)( = [-+\w.]+(?: rad)?)?', entry, rule)
    return InvalidParameter(f'{field}[{index}]', value, rule)
