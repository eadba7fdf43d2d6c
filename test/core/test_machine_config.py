"""Machine files: the shipped machine parses, units convert, and every bad file names its key."""
from __future__ import annotations

import math
from dataclasses import replace
from pathlib import Path

import numpy as np
import pytest

from cam_ros.core import InvalidParameter
from cam_ros.core.config.params_file import read_parameters_file
from cam_ros.core.config.schema import parse_parameters
from cam_ros.core.design_from_config import build_design
from cam_ros.core.ecam.master import ElectronicCam, MasterConfig
from cam_ros.core.machine import build_machine, is_machine, parse_machine

CONFIG_DIR = Path(__file__).resolve().parents[2] / 'config'
MACHINE = read_parameters_file(CONFIG_DIR / 'machine.yaml')


def test_the_shipped_machine_parses_into_one_config_per_axis():
    config = parse_machine(MACHINE)
    assert is_machine(MACHINE) and not is_machine(read_parameters_file(CONFIG_DIR
                                                                       / 'default.yaml'))
    assert config.names == ('feeder', 'knife', 'jaw') and config.length_unit == 'mm'
    knife = config.axis('knife')
    assert knife is config.axes[1] and knife.length_unit == 'deg' and knife.angular
    assert knife.parameters['master.offset_deg'] == 100.0
    assert knife.parameters['slave.offset'] == -20.0
    for axis in config.axes:  # machine-wide keys shared, the switches the machine's alone
        assert axis.cam_speed == MACHINE['cam_speed'] and axis.parameters['switches.names'] == ()
        assert axis.parameters['master.joint'] == 'line_shaft'
    assert config.parameters['switches.names'] == ('glue',)
    assert config.parameters['axes'] == ('feeder', 'knife', 'jaw')


def test_interference_pairs_are_converted_to_si():
    values = {**MACHINE, 'interference.gain_b': [-1.0, 2.5], 'length_unit': 'cm'}
    clearance, zones = parse_machine(values).interference
    assert (clearance.axis_a, clearance.axis_b, clearance.type) == ('feeder', 'jaw', 'clearance')
    cm, mm = 0.01, 0.001
    assert clearance.offset == pytest.approx(310.0 * cm, rel=1e-15)
    assert clearance.min_clearance == pytest.approx(15.0 * cm, rel=1e-15)
    assert clearance.gain_a == pytest.approx(-1.0 * cm / mm, rel=1e-15)  # cm of gap per m
    assert zones.gain_b == pytest.approx(2.5 * cm / math.radians(1.0), rel=1e-15)  # per rad
    assert zones.zone_a == pytest.approx(60.0 * mm, rel=1e-15)
    assert zones.zone_b == pytest.approx(math.radians(320.0), rel=1e-15)
    assert zones.min_margin == pytest.approx(math.radians(20.0), rel=1e-15)


def test_a_machine_of_one_axis_is_exactly_the_single_cam():
    single = read_parameters_file(CONFIG_DIR / 'rotary_knife.yaml')
    wide = ('cam_speed', 'master.source', 'master.joint')
    values = {'axes': ['knife'], 'length_unit': 'mm', **{key: single[key] for key in wide},
              **{f'knife.{key}': value for key, value in single.items() if key not in wide}}
    # A machine's cam_speed is its master's (machine angle) speed: the single cam's times the
    # master travel per rad of cam.
    values['cam_speed'] = single['cam_speed'] * single['master.scaling']
    config = parse_machine(values)
    alone = parse_parameters(single)
    (axis,) = config.axes  # repr: the .nan velocities compare unequal; the keys in any order
    assert repr(replace(axis, parameters={})) == repr(replace(alone, parameters={}))
    items = [sorted(map(repr, config.parameters.items())) for config in (axis, alone)]
    assert items[0] == items[1]
    machine = build_machine(config)
    design = build_design(alone)
    cam = ElectronicCam(design.program, MasterConfig.from_config(alone).mapping)
    q = np.linspace(-20.0, 20.0, 40001)
    assert np.array_equal(machine.positions(q)[:, 0], cam.setpoints(q).position)
    assert np.array_equal(machine.axes[0].design.program.evaluate(q).s,
                          design.program.evaluate(q).s)


def changed(**edits: object) -> dict[str, object]:
    """Return the shipped machine's flat values with keys (__ for .) set, or removed by None."""
    values = dict(MACHINE)
    for key, value in edits.items():
        name = key.replace('__', '.')
        if value is None:
            values.pop(name)
        else:
            values[name] = value
    return values


BAD = {
    'per-axis error named with its axis': (
        changed(knife__motion__end_deg=[6.25, 353.75]), 'knife.motion.end_deg = [6.25, 353.75]',
        'must have 3 entries'),
    'per-axis key required': (changed(feeder__motion__laws=None), 'feeder.motion.laws = None',
                              'is required'),
    'per-axis range': (changed(jaw__slave__scaling=2e3), 'jaw.slave.scaling = 2000.0',
                       'must be <= 1000'),
    'machine-wide key under an axis': (changed(knife__recording__enabled=True),
                                       'knife.recording.enabled = True', 'is machine-wide'),
    'switches under an axis': (changed(jaw__switches__names=['seal']), 'jaw.switches.names',
                               'is machine-wide'),
    'axis key at the top': (changed(**{'motion.laws': ['dwell']}), "motion.laws = ['dwell']",
                            'is per axis in a machine file (write feeder.motion.laws, ...)'),
    'unknown key': (changed(knife__motion__lawz=['dwell']), 'knife.motion.lawz',
                    'is not a machine parameter (did you mean knife.motion.laws?)'),
    'unknown axis prefix': (changed(jaws__slave__offset=1.0), 'jaws.slave.offset',
                            'did you mean jaw.slave.offset?'),
    'no machine length unit': (changed(length_unit=None), 'length_unit = None',
                               'is required in a machine file'),
    'machine length unit not a length': (changed(length_unit='deg'), "length_unit = 'deg'",
                                         'must be one of m, cm, mm, in'),
    'no axes': (changed(axes=[]), 'axes = []', 'must name at least one axis'),
    'axes not strings': (changed(axes=[1, 2]), 'axes = [1, 2]', 'must be a list of strings'),
    'duplicate axis': (changed(axes=['feeder', 'knife', 'feeder']), "axes[2] = 'feeder'",
                       'must be given once'),
    'axis name with a dash': (changed(axes=['feeder', 'knife-1']), "axes[1] = 'knife-1'",
                              'letters, digits and _'),
    'axis name starting with a digit': (changed(axes=['2nd']), "axes[0] = '2nd'",
                                        'not starting with a digit'),
    'empty axis name': (changed(axes=['']), "axes[0] = ''", 'must be a joint name'),
    'axis named master': (changed(axes=['master']), "axes[0] = 'master'",
                          'is a parameter word'),
    'axis named interference': (changed(axes=['interference']), "axes[0] = 'interference'",
                                'is a parameter word'),
    'axis named motion': (changed(axes=['motion']), "axes[0] = 'motion'", 'is a parameter word'),
    'scaling not 1/n': (changed(knife__master__scaling=0.4), 'knife.master.scaling = 0.4',
                        'must be 1 / n for a whole n'),
    'scaling above 1': (changed(jaw__master__scaling=2.0), 'jaw.master.scaling = 2.0',
                        'must be 1 / n for a whole n'),
    'interference arrays of unequal lengths': (
        changed(interference__gain_a=[-1.0]), 'interference.gain_a = [-1.0]',
        'must have 2 entries, one per entry of interference.axis_a'),
    'interference array missing': (
        changed(interference__zone_b=None), 'interference.zone_b = []', 'must have 2 entries'),
    'interference unknown axis': (
        changed(interference__axis_b=['jaws', 'knife']), "interference.axis_b[0] = 'jaws'",
        'must be an axis of axes (did you mean jaw?)'),
    'interference pair of an axis with itself': (
        changed(interference__axis_b=['feeder', 'knife']), "interference.axis_b[0] = 'feeder'",
        'must differ from interference.axis_a'),
    'interference bad type': (
        changed(interference__type=['clearence', 'zones']), "interference.type[0] = 'clearence'",
        'must be one of clearance, zones (did you mean clearance?)'),
    'interference double given as integer': (
        changed(interference__offset=[310, 0.0]), 'interference.offset = [310, 0.0]',
        'must be a list of doubles (write 1.0, not 1)'),
    'interference margin out of range': (
        changed(interference__min_margin_deg=[0.0, -5.0]),
        'interference.min_margin_deg = [0.0, -5.0]', 'must be >= 0'),
    'interference not finite': (
        changed(interference__offset=[math.inf, 0.0]), 'interference.offset = [inf, 0.0]',
        'must be finite'),
    'interference array too long': (
        changed(interference__offset=[0.0] * 1001), 'interference.offset',
        'must have at most 1000 entries'),
    'machine switch table checked': (
        changed(switches__off_deg=[20.0]), 'switches.off_deg[0] = 20.0',
        'must differ from switches.on_deg[0]'),
}


@pytest.mark.parametrize('values, name, rule', BAD.values(), ids=BAD)
def test_bad_machine_files_are_refused_by_name(values, name, rule):
    with pytest.raises(InvalidParameter) as caught:
        parse_machine(values)
    message = str(caught.value)
    assert message.startswith(name) and rule in message, message
    assert '\n' not in message


def test_design_errors_name_the_axis_prefixed_key():
    values = changed(knife__motion__laws=['constant_velocity', 'cycloidl', 'constant_velocity'])
    with pytest.raises(InvalidParameter, match=r"^knife\.motion\.laws\[1\] \(cycloidl\): law "
                       r"= 'cycloidl': must be one of .*\(did you mean cycloidal\?\)"):
        build_machine(parse_machine(values))


def test_a_third_is_a_whole_number_of_cycles():
    config = parse_machine(changed(jaw__master__scaling=1.0 / 3.0))
    assert config.axis('jaw').parameters['master.scaling'] == 1.0 / 3.0


def test_an_unknown_axis_is_refused_by_name():
    with pytest.raises(InvalidParameter, match=r"^axis = 'jow': is not an axis of the machine "
                       r'\(axes: feeder, knife, jaw\) \(did you mean jaw\?\)'):
        parse_machine(MACHINE).axis('jow')
