"""Write a motion function as IEC 61131-3 ST: a constant ARRAY OF MC_MotionFunctionPoint.

Field names, function types and point types are Beckhoff's Tc2_MC2_Camming ones (sources:
docs/cam-tables.md).  A point's FunctionType is the function from it to the next point; master
in degrees, slave in the file's unit, SlaveVelo, SlaveAcc and SlaveJerk per degree, degree^2
and degree^3 of master (master velocity 1).  A header comment per segment says whether it is
written natively (exact) or as quintic pieces, with the pieces' worst deviation (rounded up).
"""
from __future__ import annotations

import math
from typing import Sequence

from cam_ros.core import CamDesign
from cam_ros.core.ecam.motion_functions import LINE, MotionFunction, REST_QUINTIC
from cam_ros.core.rounding import ceil_sig
from cam_ros.output.vendor_formats import number

DEGREE = math.pi / 180.0
#: Name of the array in the file.
NAME = 'CamFunction'
INDENT = '    '
#: MC_MotionFunctionType of each interval kind.
FUNCTION_TYPES = {LINE: 'MOTIONFUNCTYPE_POLYNOM1', REST_QUINTIC: 'MOTIONFUNCTYPE_POLYNOM5',
                  'quintic': 'MOTIONFUNCTYPE_POLYNOM5_MM'}
#: Beckhoff's documentation states no formula for these: they are not used.
UNUSED = ('MOTIONFUNCTYPE_SINUSLINIE', 'MOTIONFUNCTYPE_MODSINUSLINIE',
          'MOTIONFUNCTYPE_BESTEHORN', 'MOTIONFUNCTYPE_HARMONIC_KOMBI_*')


def point_type(ds: float, d2s: float) -> str:
    """Return the MC_MotionPointType of a point (VDI 2143: rest, velocity, turn, motion)."""
    if ds == 0.0:
        return 'MOTIONPOINTTYPE_REST' if d2s == 0.0 else 'MOTIONPOINTTYPE_TURN'
    return 'MOTIONPOINTTYPE_VELOCITY' if d2s == 0.0 else 'MOTIONPOINTTYPE_MOTION'


def segment_notes(function: MotionFunction, design: CamDesign) -> list[str]:
    """Return one note per segment: its function type (exact) or its quintic pieces."""
    unit, factor = design.config.file_position_unit
    notes = []
    for number_, segment in enumerate(design.program.segments):
        where = (f'segment {number_} ({segment.law.name}, {math.degrees(segment.start):.10g}-'
                 f'{math.degrees(segment.end):.10g} deg): ')
        kinds = {kind for kind, owner in zip(function.kinds, function.owner) if owner == number_}
        if number_ in function.pieced:
            pieces = function.owner.count(number_)
            notes.append(where + f'no native function: {pieces} quintic pieces '
                         f'(MOTIONFUNCTYPE_POLYNOM5_MM), worst deviation '
                         f'{ceil_sig(function.pieced[number_] * factor)} {unit} within the '
                         f'tolerance {ceil_sig(function.tolerance * factor)} {unit} '
                         '(refined, rounded up)')
        else:
            notes.append(where + ', '.join(sorted(FUNCTION_TYPES[kind] for kind in kinds))
                         + ' with its boundary values: exact')
    return notes


def motion_function_text(function: MotionFunction, design: CamDesign,
                         notes: Sequence[str]) -> str:
    """Return the ST text: the notes as comments, then VAR_GLOBAL CONSTANT with the array."""
    unit, factor = design.config.file_position_unit
    count = len(function.angle)
    kinds = list(function.kinds) + [function.kinds[-1]]  # the end point starts no interval
    lines = [f'(* {note} *)' for note in notes]
    lines += ['VAR_GLOBAL CONSTANT',
              f'{INDENT}{NAME} : ARRAY[1..{count}] OF MC_MotionFunctionPoint := [']
    columns = zip(function.angle.tolist(), function.s.tolist(), function.ds.tolist(),
                  function.d2s.tolist(), function.d3s.tolist(), kinds)
    rows = []
    for index, (angle, s, ds, d2s, d3s, kind) in enumerate(columns, 1):
        rows.append(f'{INDENT * 2}(PointIndex := {index}, FunctionType := '
                    f'{FUNCTION_TYPES[kind]}, PointType := {point_type(ds, d2s)}, '
                    f'RelIndexNextPoint := 1, MasterPos := {number(math.degrees(angle))}, '
                    f'SlavePos := {number(s * factor)}, '
                    f'SlaveVelo := {number(ds * factor * DEGREE)}, '
                    f'SlaveAcc := {number(d2s * factor * DEGREE ** 2)}, '
                    f'SlaveJerk := {number(d3s * factor * DEGREE ** 3)})')
    lines += [row + ',' for row in rows[:-1]] + [rows[-1] + '];', 'END_VAR']
    return '\n'.join(lines) + '\n'
