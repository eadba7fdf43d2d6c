"""The design commands of `cam_ros`: report, sample, plot, export and their options."""
from __future__ import annotations

import argparse

from cam_ros.cli.arguments import (axis_option, add_command, exit_codes, FINITE, LIMITS_FAILED,
                                   POINTS, SAMPLES, STEP_DEG)
from cam_ros.core.ecam.cam_table import INTERPOLATIONS
from cam_ros.output.cam_table_formats import FORMATS as TABLE_FORMATS
from cam_ros.output.gcode import MACHINING_FORMATS


def design_commands(sub: argparse._SubParsersAction) -> None:
    config_help = ('cam config: a ROS 2 parameters file (e.g. config/default.yaml), or a '
                   'machine file (with axes, e.g. config/machine.yaml)')
    parser = add_command(sub, 'report', 'cam_ros.commands.design:report', 'Report on a cam design',
                         'Pressure angle, radius of curvature, undercut, smallest base radius, '
                         'face width, per-segment Cv/Ca/Cj and peaks at the cam speed, '
                         'discontinuities. SI units, angles in degrees. A machine file: each '
                         'axis\'s report and each interference pair (smallest gap or margin, '
                         'rounded down).', exit_codes(LIMITS_FAILED))
    parser.add_argument('config', metavar='CONFIG', help=config_help)
    parser.add_argument('--json', dest='json_output', action='store_true',
                        help='print one JSON object instead of text')
    axis_option(parser)

    parser = add_command(sub, 'sample', 'cam_ros.commands.design:sample', 'Sample a cam design',
                         'Arrays over one revolution from 0: angle (rad), position, velocity, '
                         'acceleration, jerk (SI), their derivatives per rad of cam angle, '
                         'pressure angle (rad) and radius of curvature (m). A machine file: '
                         'each axis\'s position, velocity, acceleration, jerk as commanded at '
                         'cam_speed over the machine angle.',
                         exit_codes(LIMITS_FAILED))
    parser.add_argument('config', metavar='CONFIG', help=config_help)
    parser.add_argument('--step-deg', type=STEP_DEG, default=1.0, metavar='D',
                        help='cam angle step in degrees (default 1)')
    form = parser.add_mutually_exclusive_group()
    form.add_argument('--json', dest='json_output', action='store_true',
                      help='print one JSON object of arrays (with units)')
    form.add_argument('--csv', dest='csv_output', action='store_true',
                      help='print CSV with units in the header')
    axis_option(parser)

    parser = add_command(sub, 'plot', 'cam_ros.commands.design:plot', 'Plot a cam design',
                         'S-V-A-J diagrams over cam angle and a drawing of the cam (surface, '
                         'pitch curve, base circle) with the follower at the chosen angle.',
                         exit_codes(LIMITS_FAILED))
    parser.add_argument('config', metavar='CONFIG', help=config_help)
    parser.add_argument('-o', '--output', required=True, metavar='FILE',
                        help='image to write: .png or .svg')
    parser.add_argument('--angle-deg', type=FINITE, default=0.0, metavar='A',
                        help='cam angle at which the follower is drawn, deg (default 0)')
    parser.add_argument('--vibration', action='store_true',
                        help='draw the follower train instead: residual-vibration spectrum of '
                             'each moving segment\'s law over r = 0.5..10 with this design\'s '
                             'operating points, and the periodic output against s')
    axis_option(parser)
    parser.add_argument('--timing-diagram', action='store_true',
                        help='a machine file: every axis over one machine cycle (each in its '
                             'own unit), the switch tracks, every collision or too small a '
                             'margin shaded')

    parser = add_command(sub, 'export', 'cam_ros.commands.design:export',
                         'Export the cam surface for manufacturing, a cutter path, or a cam table '
                         'for a PLC',
                         'The surface: one closed curve in mm in the cam frame (cam centre at the '
                         'origin): CSV (x_mm,y_mm), DXF (closed LWPOLYLINE, $INSUNITS = mm) or '
                         'SVG '
                         '(closed path); a groove cam: both flanks, a conjugate pair: both cams, '
                         'each its own curve. With --machining: the cutter-location path (the '
                         'surface offset by the cutter radius) or the nominal contour, points '
                         'placed '
                         'by a '
                         'chordal tolerance, in mm (inch for length_unit in). With --cam-table: '
                         'master position (deg) -> slave position (length_unit, deg for '
                         'oscillating followers), optionally velocity and acceleration per deg '
                         'and '
                         'deg^2 of master.', exit_codes(LIMITS_FAILED))
    parser.add_argument('config', metavar='CONFIG', help=config_help)
    parser.add_argument('-o', '--output', required=True, metavar='FILE',
                        help='file to write: .csv, .dxf or .svg (a cam table or a cutter path: '
                             'any name)')
    parser.add_argument('--samples', type=SAMPLES, default=None, metavar='N',
                        help='points on the surface, equally spaced in cam angle '
                             '(default 3600)')
    parser.add_argument('--format', dest='file_format', default=None,
                        choices=tuple(TABLE_FORMATS) + tuple(f for f in MACHINING_FORMATS
                                                             if f not in TABLE_FORMATS),
                        help='a cam table: csv (default), sew (MOVI-C point list), xyva '
                             '(CODESYS SMC_CAMXYVA columns), st (IEC 61131-3 ARRAY OF LREAL), '
                             'lenze (Global Drive Cam Loader text), kollmorgen (KAS cam CSV), '
                             'rockwell (L5X tag of CAM[N] for MCCP), twincat-functions (ST '
                             'ARRAY OF MC_MotionFunctionPoint: polynomial laws exact, others '
                             'quintic pieces within --tolerance); '
                             'a cutter path: gcode (default), csv (the nominal contour with '
                             'its unit normals, for a CMM), dxf')
    spacing = parser.add_mutually_exclusive_group()
    spacing.add_argument('--tolerance', default=None, metavar='T', action='append',
                         help='a cam table: place points so that the interpolation stays '
                              'within T of the exact law, T in the table\'s unit (the config\'s '
                              'length_unit, deg for oscillating followers); a cutter path: the '
                              'chordal tolerance in length_unit (required); or with a unit: '
                              '0.01mm, 10um, 1e-5m, 0.1deg. A cam table may take one per kind '
                              'of unit (--tolerance 10um --tolerance 0.001deg): each axis takes '
                              'the one of its unit')
    machining = parser.add_argument_group('cutter path')
    machining.add_argument('--machining', action='store_true',
                           help='write a cutter path (G-code) or the nominal contour instead of '
                                'the surface')
    machining.add_argument('--cutter-radius', default=None, metavar='R',
                           help='cutter radius in length_unit or with a unit (required but for '
                                '--format csv); a cutter larger than the smallest concave '
                                'radius of the cam is refused')
    machining.add_argument('--compensation', default=None, choices=('left', 'right'),
                           help='gcode: write the nominal contour with G41 (left) or G42 '
                                '(right) and the cutter radius in register D1, instead of the '
                                'offset path')
    machining.add_argument('--arcs', action='store_true',
                           help='gcode: join runs of points into arcs (G2/G3) where an arc stays '
                                'within --tolerance of the exact curve')
    table = parser.add_argument_group('cam table')
    table.add_argument('--cam-table', action='store_true',
                       help='write a cam table instead of the surface')
    spacing.add_argument('--points', type=POINTS, default=None, metavar='N',
                         help='a cam table: N equidistant master steps over one revolution '
                              '(default 360): N + 1 rows with the end point 360 deg, N without')
    table.add_argument('--interpolation', default=None, choices=INTERPOLATIONS,
                       help='what the target does between points (default linear; xyva: '
                            'quintic, its only one); cubic: Hermite with the velocity column as '
                            'slopes (csv); quintic: fifth-degree pieces through position, '
                            'velocity and acceleration (csv, xyva)')
    table.add_argument('--end-point', action=argparse.BooleanOptionalAction, default=None,
                       help='write the periodic end point 360 deg (default: yes)')
    table.add_argument('--derivatives', action='store_true',
                       help='csv: add velocity and acceleration columns')
    parser.add_argument('--switches', action='store_true',
                        help='write the cam switch tracks (switches.*) for a PLC\'s cam '
                             'controller instead: --format csv (default) or st (PLCopen '
                             'MC_CAMSWITCH_TR / MC_TRACK_TR field names)')
    axis_option(parser)
    parser.add_argument('--timing-diagram', action='store_true',
                        help='a machine file: each axis\'s commanded position over one machine '
                             'cycle, --format csv: machine angle (deg) and a column per axis in '
                             'its file unit, --points N steps (default 360: N + 1 rows)')

    parser = add_command(sub, 'studio', 'cam_ros.commands.studio:studio',
                         'Edit a design in the browser',
                         'Serve a web app for one design file, a cam or a machine: edit it with '
                         'every check of the core as you type, see its S-V-A-J, pressure angle, '
                         'curvature, cam drawing or timing diagram, save it (comments kept) and '
                         'download what export writes. Binds 127.0.0.1 by default; another '
                         '--host needs the token in the printed URL.', exit_codes(None))
    parser.add_argument('config', metavar='FILE', nargs='?', default=None,
                        help='the design file (default: the shipped default design, '
                             'read-only)')
    parser.add_argument('--port', type=int, default=8770, metavar='N',
                        help='TCP port (default 8770; 0: a free one)')
    parser.add_argument('--host', default='127.0.0.1', metavar='H',
                        help='address to serve on (default 127.0.0.1, this computer only; '
                             'another needs the token printed with the URL)')
    parser.add_argument('--open', dest='open_browser', action='store_true',
                        help='open the page in the default browser')
    parser.add_argument('--node', default=None, metavar='NAME',
                        help='a running cam_node (e.g. /cam) on this ROS domain: show its master, '
                             'commands, reported positions and state, engage, disengage, apply '
                             'the edits to it through its parameters')

    parser = add_command(sub, 'plan', 'cam_ros.commands.plan:plan', 'Plan the moves onto the cams',
                         'The moves an engagement or a recovery makes from the axes\' positions '
                         'onto their cams, in time, with the master at a position and a constant '
                         'speed (default at rest): each move\'s duration and peaks against the '
                         'axis\'s limits, the order when moving together would collide, and each '
                         'interference pair\'s smallest gap or margin during the moves.',
                         exit_codes('a move cannot be made within its axis\'s limits, or the '
                                    'moves '
                                    'collide together and in every order'))
    parser.add_argument('config', metavar='CONFIG', help=config_help)
    parser.add_argument('--position', action='append', required=True, metavar='AXIS=VALUE',
                        help='where an axis is (repeat per axis; the others are on their cams): '
                             'in its length_unit (deg for a rotary or oscillating axis) or with '
                             'a unit: knife=330, jaw=12mm; a single cam\'s axis is follower, or '
                             'give VALUE alone')
    parser.add_argument('--master-speed', type=FINITE, default=0.0, metavar='W',
                        help='the master\'s constant speed during the moves, rad/s of machine '
                             'angle as cam_speed (default 0: at rest)')
    parser.add_argument('--master-position', default='0', metavar='A',
                        help='machine angle where the moves start, deg or with a unit (0.5rad; '
                             'default 0)')
    parser.add_argument('--json', dest='json_output', action='store_true',
                        help='print one JSON object instead of text')
