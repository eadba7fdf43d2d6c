"""Cam table files for Lenze, Kollmorgen and Rockwell targets (sources: docs/cam-tables.md).

- lenze: Global Drive Cam Loader text, `x y` per line (ascending x), notes as `//` comments
  after the values (the manual allows a comment after the two positions; comment-only lines are
  not documented, so none are written).
- kollmorgen: KAS IDE cam profile CSV, `CYCLIC;YES;`, `TABLE_BEGIN;;`, rows `x;y;SPLINE`,
  `TABLE_END;;`; at least 4 spline segments; the IDE normalises X and Y to their largest values
  on import.  The manual shows no comment syntax: the notes are not written.
- rockwell: Logix Designer L5X holding the tag `CamTable : CAM[N]` (Master, Slave: REAL;
  SegmentType: DINT, 0 linear, 1 cubic), decorated data; notes in the tag's description.
  Master and Slave are single precision: `real_rounding` is what that adds.
"""
from __future__ import annotations

from typing import Sequence
from xml.sax.saxutils import escape

import numpy as np

#: Name of the CAM array tag in the L5X file.
ROCKWELL_TAG = 'CamTable'
#: SegmentType of a CAM element by interpolation (Logix CAM data type).
SEGMENT_TYPES = {'linear': 0, 'cubic': 1}
#: Fewest rows of a KAS CSV: at least 4 spline segments.
KOLLMORGEN_MIN_POINTS = 5


def number(value: float) -> str:
    """Return a double in positional notation that reads back exactly ('-0.0' as '0.0')."""
    return np.format_float_positional(value + 0.0, unique=True, trim='0')


def real(value: float) -> str:
    """Return the single-precision REAL nearest value, in its shortest positional digits."""
    return np.format_float_positional(np.float32(value + 0.0), unique=True, trim='0')


def real_rounding(master: np.ndarray, slave: np.ndarray) -> float:
    """Return the largest |p32 - p| of the lines p through (master, slave) and p32 through
    the same points rounded to single precision, over the master range.

    Both are piecewise linear, so their difference is too, with its extremes at the union of
    their knots: the value there is exact (no sampling).  Raise ValueError when rounding makes
    two master positions equal.
    """
    master32 = master.astype(np.float32).astype(float)
    slave32 = slave.astype(np.float32).astype(float)
    if not np.all(np.diff(master32) > 0.0):
        raise ValueError('two master positions round to the same REAL')
    at = np.union1d(master, master32)
    at = at[(at >= max(master[0], master32[0])) & (at <= min(master[-1], master32[-1]))]
    return float(np.max(np.abs(np.interp(at, master32, slave32) - np.interp(at, master, slave))))


def write_lenze(notes: Sequence[str], values: np.ndarray, names: Sequence[str],
                interpolation: str) -> str:
    """Return `x y` lines, the notes as `//` comments after the values, one per line."""
    rows = [f'{number(x)} {number(y)}' for x, y in values[:, :2].tolist()]
    comments = list(notes) + [' '.join(names[:2])]
    if len(comments) > len(rows):  # a short table: the last row carries the rest
        comments[len(rows) - 1:] = [' | '.join(comments[len(rows) - 1:])]
    rows = [f'{row} // {comment}' if index < len(comments) else row
            for index, (row, comment) in enumerate(zip(rows, comments + [''] * len(rows)))]
    return '\n'.join(rows) + '\n'


def write_kollmorgen(notes: Sequence[str], values: np.ndarray, names: Sequence[str],
                     interpolation: str) -> str:
    """Return the KAS CSV: CYCLIC;YES;, TABLE_BEGIN;;, x;y;SPLINE rows, TABLE_END;;."""
    rows = [f'{number(x)};{number(y)};SPLINE' for x, y in values[:, :2].tolist()]
    return '\n'.join(['CYCLIC;YES;', 'TABLE_BEGIN;;', *rows, 'TABLE_END;;']) + '\n'


def write_rockwell(notes: Sequence[str], values: np.ndarray, names: Sequence[str],
                   interpolation: str) -> str:
    """Return an L5X file with one controller tag: an array of CAM, decorated data."""
    count = len(values)
    segment_type = SEGMENT_TYPES[interpolation]
    description = '\n'.join(notes).replace(']]>', ']] >')
    lines = ['<?xml version="1.0" encoding="UTF-8" standalone="yes"?>',
             '<RSLogix5000Content SchemaRevision="1.0" TargetName="' + ROCKWELL_TAG + '" '
             'TargetType="Tag" ContainsContext="true" ExportOptions="References DecoratedData '
             'Context Dependencies">',
             '<Controller Use="Context" Name="cam_ros">',
             '<Tags Use="Context">',
             f'<Tag Name="{ROCKWELL_TAG}" TagType="Base" DataType="CAM" Dimensions="{count}" '
             'Constant="false" ExternalAccess="Read/Write" Use="Target">',
             f'<Description><![CDATA[{description}]]></Description>',
             '<Data Format="Decorated">',
             f'<Array DataType="CAM" Dimensions="{count}">']
    for index, (master, slave) in enumerate(values[:, :2].tolist()):
        lines += [f'<Element Index="[{index}]">', '<Structure DataType="CAM">',
                  f'<DataValueMember Name="Master" DataType="REAL" Radix="Float" '
                  f'Value="{escape(real(master))}"/>',
                  f'<DataValueMember Name="Slave" DataType="REAL" Radix="Float" '
                  f'Value="{escape(real(slave))}"/>',
                  f'<DataValueMember Name="SegmentType" DataType="DINT" Radix="Decimal" '
                  f'Value="{segment_type}"/>',
                  '</Structure>', '</Element>']
    lines += ['</Array>', '</Data>', '</Tag>', '</Tags>', '</Controller>',
              '</RSLogix5000Content>']
    return '\n'.join(lines) + '\n'
