"""Compiled cam tables against the exact programs: every shipped program, mappings, breaks."""
from __future__ import annotations

import math
from pathlib import Path

import numpy as np
import pytest

from cam_ros.core import build_design, load_config
from cam_ros.core.cam_angles import TWO_PI
from cam_ros.core.ecam.compiled import (_table, ACCURACY, compile_program, CompiledCams,
                                        ProgramTable, ROUNDING, SAFETY)
from cam_ros.core.ecam.master import CamMapping, ElectronicCam
from cam_ros.core.machine.machine import load_machine
from cam_ros.core.motion.laws import Polynomial345
from cam_ros.core.motion.program import MotionProgram
from cam_ros.core.motion.segment import Segment

CONFIG = Path(__file__).resolve().parents[2] / 'config'
EPS = float(np.finfo(float).eps)


def shipped_programs() -> list[tuple[str, MotionProgram]]:
    """Return every shipped config's program, and each axis's of the machine files."""
    found = []
    for path in sorted(CONFIG.glob('*.yaml')):
        if path.stem.startswith('machine') and path.stem != 'machine_dynamics':
            found += [(f'{path.name}:{axis.name}', axis.cam.program)
                      for axis in load_machine(path).axes]
        else:
            found.append((path.name, build_design(load_config(path)).program))
    return found


PROGRAMS = shipped_programs()
TABLES = {name: compile_program(program) for name, program in PROGRAMS}


def dense(program: MotionProgram, count: int = 200_001) -> np.ndarray:
    """Return rows s, s', s'', s''' of the exact program on a dense cycle plus its breaks."""
    theta = np.concatenate((program.start + np.linspace(0.0, TWO_PI, count), program.breaks))
    values = program.evaluate(theta)
    return np.array([values.s, values.ds, values.d2s, values.d3s])


def test_the_shipped_programs_include_the_machine_axes():
    names = [name for name, _ in PROGRAMS]
    assert {'machine.yaml:feeder', 'machine.yaml:knife', 'machine.yaml:jaw',
            'default.yaml', 'rotary_knife.yaml'} <= set(names)


@pytest.mark.parametrize('name,program', PROGRAMS, ids=[name for name, _ in PROGRAMS])
def test_a_table_is_within_its_stated_error_at_random_angles(name, program):
    table = TABLES[name]
    reference = dense(program)
    stroke = np.ptp(reference[0])
    peaks = np.abs(reference).max(axis=1)
    theta = np.random.default_rng(39).uniform(-50.0, 50.0, 100_000)  # any real cam angle
    exact = program.evaluate(theta)
    error = np.abs(table.evaluate(theta) - np.array([exact.s, exact.ds, exact.d2s, exact.d3s]))
    worst = error.max(axis=1)
    noise = 4.0 * EPS * peaks[0]  # rounding of s itself
    assert worst[0] <= ACCURACY * stroke
    assert worst[1] <= ACCURACY * peaks[1]
    assert worst[2] <= 1e-6 * peaks[2]  # acceleration: stated, not a bound of the issue
    assert worst[3] <= 1e-4 * peaks[3]  # jerk
    errors = table.errors  # stated: never below what is seen, within the bound
    assert worst[0] <= errors.position + noise and worst[1] <= errors.velocity + noise
    assert errors.accurate
    assert errors.position <= ACCURACY * errors.stroke
    assert errors.velocity <= ACCURACY * errors.slope
    assert errors.stroke <= stroke * (1.0 + 1e-12) and errors.slope <= peaks[1] * (1.0 + 1e-12)


def scanned_errors(table: ProgramTable) -> np.ndarray:
    """Return the largest |error| of s and s' on 63 points inside every interval."""
    program, knots = table.program, table.knots
    fractions = np.linspace(0.0, 1.0, 65)[1:-1]
    local = (knots[:-1, np.newaxis] + np.diff(knots)[:, np.newaxis] * fractions).reshape(-1)
    exact = program.evaluate(program.start + local)
    return np.abs(table.evaluate(program.start + local)[:2]
                  - np.array([exact.s, exact.ds])).max(axis=1)


@pytest.mark.parametrize('name', ['default.yaml', 'machine.yaml:jaw', 'polydyne.yaml'])
def test_the_stated_errors_are_safe_and_refined_from_a_scan_of_every_interval(name):
    table = TABLES[name]
    for stated, seen in zip(table.errors[:2], scanned_errors(table)):
        assert seen <= stated
    # On a coarse grid, far above rounding: the refined largest, at least the scan's.
    coarse = _table(table.program, 64)
    for stated, seen in zip(coarse.errors[:2], scanned_errors(coarse)):
        assert seen <= stated / SAFETY <= 1.01 * seen


def test_a_jump_of_a_derivative_is_kept_on_its_side():
    table = TABLES['default.yaml']
    program = table.program
    peak = np.abs(dense(program)[2]).max()
    jumps = [jump for jump in program.continuity_report()
             if jump.order == 2 and abs(jump.jump) > 1e-3 * peak]
    assert len(jumps) >= 2  # the simple harmonic return's ends
    for jump in jumps:
        after = table.evaluate(np.array([jump.angle + 1e-12]))[2, 0]
        before = table.evaluate(np.array([jump.angle - 1e-12]))[2, 0]
        assert after == pytest.approx(jump.right, abs=1e-6 * peak)
        assert before == pytest.approx(jump.left, abs=1e-6 * peak)


@pytest.mark.parametrize('name', ['machine.yaml:knife', 'default.yaml'])
def test_an_angle_just_below_a_whole_turn_that_rounds_up_to_it_is_the_turn_s_end(name):
    table = TABLES[name]
    program = table.program
    theta = np.array([program.start - 1e-300, program.start - 1e-17])
    assert np.all(np.mod(theta - program.start, TWO_PI) == TWO_PI)  # rounded up onto the turn
    exact = program.evaluate(theta)
    got = table.evaluate(theta)
    assert np.abs(got[0] - exact.s).max() <= ACCURACY * table.errors.stroke
    assert np.abs(got[1] - exact.ds).max() <= ACCURACY * table.errors.slope


def test_the_feeder_rise_is_the_cycloid_written_out():
    table = TABLES['machine.yaml:feeder']
    beta, stroke = math.radians(140.0), 0.2  # 200 mm over 0-140 deg
    x = np.random.default_rng(1).uniform(0.0, beta, 10_000)
    cycloid = stroke * (x / beta - np.sin(TWO_PI * x / beta) / TWO_PI)
    slope = stroke / beta * (1.0 - np.cos(TWO_PI * x / beta))
    values = table.evaluate(x)
    assert np.abs(values[0] - cycloid).max() <= ACCURACY * stroke
    assert np.abs(values[1] - slope).max() <= ACCURACY * slope.max()


def test_a_quintic_law_is_reproduced_to_rounding():
    program = MotionProgram((Segment(Polynomial345(), 0.0, math.pi, 0.0, 0.1),
                             Segment(Polynomial345(), math.pi, TWO_PI, 0.1, 0.0)))
    table = compile_program(program)
    x = np.random.default_rng(2).uniform(0.0, TWO_PI, 10_000)
    u = np.where(x < math.pi, x / math.pi, 2.0 - x / math.pi)
    written = 0.1 * (10 * u ** 3 - 15 * u ** 4 + 6 * u ** 5)
    assert table.errors.position <= 10 * ROUNDING * table.errors.stroke
    assert np.abs(table.evaluate(x)[0] - written).max() <= 10 * ROUNDING * 0.1


MAPPINGS = [CamMapping(), CamMapping(math.radians(100.0), 1.0, -0.35, 1.0),
            CamMapping(math.radians(-30.0), 0.5, 0.02, -2.0),  # two cycles per master turn
            CamMapping(1.0, 1.0 / 3.0, 3 * TWO_PI, 1.0)]  # a rotary axis three turns on


@pytest.mark.parametrize('name', ['default.yaml', 'machine.yaml:knife', 'machine.yaml:jaw'])
def test_stacked_cams_give_every_axis_its_exact_commands_through_its_mapping(name):
    others = [TABLES['machine.yaml:feeder'], TABLES['machine.yaml:knife']]
    tables = [*others, *([TABLES[name]] * len(MAPPINGS))]
    cams = [*(ElectronicCam(table.program, MAPPINGS[1]) for table in others),
            *(ElectronicCam(TABLES[name].program, mapping) for mapping in MAPPINGS)]
    assert_exact_commands(cams, tables, seed=3)


def assert_exact_commands(cams, tables, seed):
    """Check a stack's commands at 300 random master samples against each cam's setpoints."""
    stacked = CompiledCams(cams, tables)
    scans = [dense(table.program) for table in tables]
    strokes = [np.ptp(scan[0]) for scan in scans]
    peaks = [np.abs(scan).max(axis=1) for scan in scans]
    rng = np.random.default_rng(seed)
    for _ in range(300):
        master, omega = rng.uniform(-300.0, 300.0), rng.uniform(-70, 70)
        position, velocity = stacked.commands(master, omega)
        for index, cam in enumerate(cams):
            k, m = cam.mapping.slave_scaling, cam.mapping.master_scaling
            exact = cam.setpoints(master, omega, rng.normal())  # alpha moves neither
            assert abs(position[index] - exact.position) <= ACCURACY * abs(k) * strokes[index]
            assert abs(velocity[index] - exact.velocity) <= \
                ACCURACY * abs(k / m * omega) * peaks[index][1]


def test_cams_that_never_advance_give_their_exact_commands_modulo_a_cycle():
    """No program of the stack advances (no rotary axis): each command is the table's at the
    master's angle modulo a cycle, against the exact program through each mapping."""
    names = ['default.yaml', 'machine.yaml:jaw', 'machine.yaml:feeder']
    tables = [TABLES[name] for name in names for _ in MAPPINGS]
    assert not any(table.program.advance for table in tables)
    cams = [ElectronicCam(TABLES[name].program, mapping) for name in names
            for mapping in MAPPINGS]
    assert_exact_commands(cams, tables, seed=4)
