"""Write the cam switch tracks (switches.*) for a PLC's cam controller (PLS): CSV or IEC ST.

One row or struct per track: on and off cam angle (deg, taken modulo 360; off < on wraps
through 0), lead time (s) and hysteresis (deg).  The ST struct follows the PLCopen names of
MC_CAMSWITCH_TR (TrackNumber from 1, FirstOnPosition, LastOnPosition) and MC_TRACK_TR
(OnCompensation, OffCompensation: s, negative switches earlier; Hysteresis).
"""
from __future__ import annotations

from typing import Any, Mapping

import numpy as np

from cam_ros.core import InvalidParameter
from cam_ros.output.cam_table_formats import number, ST_INDENT

#: Switch table formats of `export --switches`.
SWITCH_FORMATS = ('csv', 'st')
#: CSV columns, one row per track.
CSV_COLUMNS = ('name', 'on_deg', 'off_deg', 'lead_time_s', 'hysteresis_deg')
#: Names of the ST struct type and of the constant array of tracks.
ST_TYPE = 'CamRosSwitchTrack'
ST_NAME = 'CamSwitches'


def switch_rows(parameters: Mapping[str, Any]) -> list[tuple[str, float, float, float, float]]:
    """Return (name, on_deg, off_deg, lead_time_s, hysteresis_deg) per track; raise if none."""
    names = list(parameters['switches.names'])
    if not names:
        raise InvalidParameter('switches.names', names, 'must name at least one track to '
                                                        'export --switches')
    on = np.mod(np.asarray(parameters['switches.on_deg'], dtype=float), 360.0)
    off = np.mod(np.asarray(parameters['switches.off_deg'], dtype=float), 360.0)
    lead = parameters['switches.lead_time'] or [0.0] * len(names)
    hysteresis = float(parameters['switches.hysteresis_deg'])
    return [(name, float(a), float(b), float(t), hysteresis)
            for name, a, b, t in zip(names, on, off, lead)]


def _notes(source: str, parameters: Mapping[str, Any], rows: list) -> list[str]:
    wrapping = [str(track) for track, row in enumerate(rows, start=1) if row[2] < row[1]]
    return [
        f'cam switch tracks of {source} from cam_ros: {len(rows)} tracks, in order: '
        'TrackNumber k is bit k - 1 of ~/switches',
        'on over cam angles [on, off) in deg; off < on wraps through 0'
        + (f' (TrackNumber {", ".join(wrapping)})' if wrapping else ''),
        f'cam angle = (master - {number(parameters["master.offset_deg"])} deg) / '
        f'{number(parameters["master.scaling"])} (master.offset_deg, master.scaling)',
        'lead time: each edge earlier by lead time x master speed (OnCompensation = '
        'OffCompensation = -lead time); hysteresis: the lag of a track when the master reverses',
    ]


def _csv(notes: list[str], rows: list) -> str:
    lines = [f'# {note}' for note in notes] + [','.join(CSV_COLUMNS)]
    for name, *values in rows:
        quoted = '"' + name.replace('"', '""') + '"'  # a name may hold ',' or start with '#'
        lines.append(','.join([quoted] + [number(value) for value in values]))
    return '\n'.join(lines) + '\n'


def _st_string(text: str) -> str:
    """Return text as an IEC 61131-3 STRING literal ('$' escapes)."""
    return "'" + text.replace('$', '$$').replace("'", "$'") + "'"


def _st(notes: list[str], rows: list) -> str:
    width = max(len(row[0]) for row in rows)
    fields = (('TrackNumber', 'INT', 'bit TrackNumber - 1 of ~/switches'),
              ('Name', f'STRING({width})', 'switches.names'),
              ('FirstOnPosition', 'LREAL', 'cam angle, deg: switches on'),
              ('LastOnPosition', 'LREAL', 'cam angle, deg: switches off'),
              ('OnCompensation', 'LREAL', 's, negative: earlier (-switches.lead_time)'),
              ('OffCompensation', 'LREAL', 's, negative: earlier (-switches.lead_time)'),
              ('Hysteresis', 'LREAL', 'deg'))
    lines = [f'(* {note} *)' for note in notes] + [f'TYPE {ST_TYPE} :', 'STRUCT']
    lines += [f'{ST_INDENT}{name} : {kind}; (* {text} *)' for name, kind, text in fields]
    lines += ['END_STRUCT', 'END_TYPE', '', 'VAR_GLOBAL CONSTANT',
              f'{ST_INDENT}{ST_NAME} : ARRAY[1..{len(rows)}] OF {ST_TYPE} := [']
    items = []
    for index, (name, on, off, lead, hysteresis) in enumerate(rows, start=1):
        values = (str(index), _st_string(name), number(on), number(off), number(-lead),
                  number(-lead), number(hysteresis))
        items.append('(' + ', '.join(f'{field[0]} := {value}'
                                     for field, value in zip(fields, values)) + ')')
    lines += [f'{ST_INDENT * 2}{item},' for item in items[:-1]]
    lines += [f'{ST_INDENT * 2}{items[-1]}];', 'END_VAR']
    return '\n'.join(lines) + '\n'


def switch_table_text(parameters: Mapping[str, Any], name: str, source: str) -> str:
    """Return the file text of the switch tracks in format name (csv or st)."""
    rows = switch_rows(parameters)
    notes = _notes(source, parameters, rows)
    return _csv(notes, rows) if name == 'csv' else _st(notes, rows)
