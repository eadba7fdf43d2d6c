"""The elastic follower train: residual vibration, periodic response, VDI 2149, the config.

References independent of cam_ros/core/dynamics/vibration.py: the handbooks' closed forms of the
residual-vibration spectrum, and the train's ODE integrated by SciPy (DOP853) piece by piece.
"""
from __future__ import annotations

import math

import numpy as np
import pytest
from scipy.integrate import solve_ivp
from test_laws import LAW_PARAMS, law_named
from test_periodic import CV_DESIGN, SEED as DESIGN  # seed 000 on a 6 Hz train at 1 rev/s

from cam_ros.core import build_design, InvalidParameter, parse_parameters
from cam_ros.core.dynamics.periodic import periodic_response
from cam_ros.core.dynamics.train import TrainConfig
from cam_ros.core.dynamics.vibration import residual_ratio, vibration_report

#: Duration ratios r = T fn away from the closed forms' removable singularities.
RATIOS = np.array([0.05, 0.3, 0.7, 1.3, 1.5, 2.0, 2.5, 3.0, 4.2, 6.6, 9.9])
CLOSED_FORM_TOLERANCE = 1e-12
ODE_TOLERANCE = 1e-8  # of R/h: the integrator's, set to rtol 1e-12
ODE_RATIOS = (0.4, 1.0, 1.7, 3.2)
#: config/flying_shear.yaml with a cycloidal G-G section (20 to 56 mm over 80-140 deg at
#: 0.5 mm/deg) in place of its constant-velocity one, on a 20 Hz train.
GG_DESIGN = {
    'length_unit': 'mm', 'rotation': 'clockwise', 'cam_speed': 2.0 * math.pi,
    'follower.type': 'translating_roller', 'follower.base_radius': 60.0,
    'follower.roller_radius': 15.0,
    'motion.laws': ['poly5', 'cycloidal', 'poly5', 'cycloidal'],
    'motion.start_deg': [0.0, 80.0, 140.0, 220.0], 'motion.end_deg': [80.0, 140.0, 220.0, 360.0],
    'motion.start_position': [0.0, 20.0, 56.0, 70.0],
    'motion.end_position': [20.0, 56.0, 70.0, 0.0],
    'motion.start_velocity': [math.nan, 0.5, math.nan, math.nan],
    'motion.end_velocity': [math.nan, 0.5, math.nan, math.nan],
    'limits.pressure_angle_deg': 60.0, 'dynamics.train_natural_frequency': 20.0,
}


def test_cycloidal_spectrum_is_the_closed_form():
    expected = np.abs(np.sin(np.pi * RATIOS)) / (np.pi * RATIOS * np.abs(1.0 - RATIOS ** 2))
    found = residual_ratio(law_named('cycloidal'), RATIOS)
    np.testing.assert_allclose(found, expected, rtol=0.0, atol=CLOSED_FORM_TOLERANCE)
    assert residual_ratio(law_named('cycloidal'), 1.0) == pytest.approx(0.5, abs=1e-12)
    assert residual_ratio(law_named('cycloidal'), 0.0) == pytest.approx(1.0)  # a step


def test_harmonic_spectrum_is_the_closed_form():
    expected = np.abs(np.cos(np.pi * RATIOS)) / np.abs(1.0 - 4.0 * RATIOS ** 2)
    found = residual_ratio(law_named('simple_harmonic'), RATIOS)
    np.testing.assert_allclose(found, expected, rtol=0.0, atol=CLOSED_FORM_TOLERANCE)
    assert residual_ratio(law_named('simple_harmonic'), 1.0) == pytest.approx(1 / 3, abs=1e-12)


def residual_by_ode(law, r: float) -> float:
    """Integrate x'' + W^2 x = W^2 f(u) over the segment (u = t / T), return R / h after it.

    The train enters following the cam exactly (x = f, x' = f' at u = 0); afterwards the cam
    goes on at the end slope, so the amplitude is that of x - f about it.
    """
    w = 2.0 * math.pi * r
    start = law.evaluate(np.array([0.0]))
    state = np.array([0.0, start.y1[0]])
    edges = [0.0, *law.breakpoints, 1.0]
    for a, b in zip(edges[:-1], edges[1:]):
        def train(u, z):
            return [z[1], w * w * (float(law.evaluate(min(max(u, 0.0), 1.0)).y) - z[0])]
        solved = solve_ivp(train, (a, b), state, method='DOP853', rtol=1e-12, atol=1e-14)
        state = solved.y[:, -1]
    end = law.evaluate(np.array([1.0]))
    return math.hypot(state[0] - end.y[0], (state[1] - end.y1[0]) / w)


@pytest.mark.parametrize('name', [name for name in LAW_PARAMS if name != 'dwell'])
def test_every_law_s_spectrum_matches_the_integrated_train(name):
    law = law_named(name)
    found = residual_ratio(law, np.array(ODE_RATIOS))
    expected = [residual_by_ode(law, r) for r in ODE_RATIOS]
    np.testing.assert_allclose(found, expected, rtol=0.0, atol=ODE_TOLERANCE)


def test_constant_velocity_excites_nothing_of_its_own():
    assert np.all(residual_ratio(law_named('constant_velocity'), RATIOS) < 1e-14)


def test_bad_ratios_are_refused():
    with pytest.raises(InvalidParameter, match='must be finite and >= 0'):
        residual_ratio(law_named('cycloidal'), [1.0, -0.5])


def test_the_report_refines_its_extremes_and_warns_under_vdi_2149():
    design = build_design(parse_parameters(DESIGN))
    report = design.vibration_check
    assert report.frequency_ratio == pytest.approx(6.0) and report.rigid_ok is False
    assert any('VDI 2149' in warning for warning in design.warnings())
    [rise, fall] = report.segments
    assert (rise.index, fall.index) == (1, 3)
    assert rise.r == pytest.approx(0.25 * 6.0) and fall.r == pytest.approx(1 / 3 * 6.0)
    assert rise.residual_amplitude == pytest.approx(0.02 * rise.residual_ratio)
    response = periodic_response(design.program, design.config.cam_speed, design.config.train)
    dense = np.linspace(0.0, 2.0 * math.pi, 20_001)
    deviation = np.abs(response.at(dense) - design.program.evaluate(dense).s)
    assert deviation.max() <= report.max_output_deviation + 1e-15
    assert report.max_output_deviation - deviation.max() < 1e-6 * 0.02
    acceleration = np.abs(response.at(dense, 2))
    assert acceleration.max() <= report.peak_output_acceleration + 1e-12
    assert report.peak_rigid_acceleration == pytest.approx(
        np.abs(design.evaluate(dense).acceleration).max(), rel=1e-6)


def test_a_stiff_train_is_rigid_and_its_output_is_the_cam_motion():
    design = build_design(parse_parameters({**DESIGN, 'dynamics.train_natural_frequency': 500.0}))
    report = design.vibration_check
    assert report.rigid_ok and not any('VDI 2149' in w for w in design.warnings())
    # A stiff train lags the cam by x - s ~ -(2 zeta / wn) ds/dt - d2s/dt2 / wn^2.
    train = design.config.train
    dense = design.evaluate(np.linspace(0.0, 2.0 * math.pi, 100_000, endpoint=False))
    lag = np.abs(2.0 * train.damping_ratio / train.omega_n * dense.velocity
                 + dense.acceleration / train.omega_n ** 2)
    assert report.max_output_deviation == pytest.approx(lag.max(), rel=0.01)


def test_the_elastic_train_can_lift_the_follower_off_and_fail_the_verdict():
    # A weak spring: the rigid follower stays on (Q >= 1 N); the output of a 6 Hz train
    # accelerates over twice as hard (4.5 against 2.0 m/s^2) and lifts off.
    dynamics = {'dynamics.mass': 2.0, 'dynamics.spring_rate': 100.0,
                'dynamics.spring_preload': 5.0, 'contact.face_width': 1.0}
    rigid = build_design(parse_parameters({**DESIGN, **dynamics,
                                           'dynamics.train_natural_frequency': 0.0}))
    assert rigid.ok and rigid.vibration_check is None
    elastic = build_design(parse_parameters({**DESIGN, **dynamics}))
    report = elastic.vibration_check
    assert report.elastic_force_min < 0.0 and not elastic.ok
    # The force is m x'' + c v + k s + P + F with the output's acceleration: check at its angle.
    at = report.elastic_force_min_at
    response = periodic_response(elastic.program, elastic.config.cam_speed, elastic.config.train)
    motion = elastic.program.evaluate(at)
    c = elastic.config.dynamics
    force = (c.inertia * float(response.at(at, 2)) + c.damping * 2.0 * math.pi * float(motion.ds)
             + c.spring_rate * float(motion.s) + c.spring_preload)
    assert report.elastic_force_min == pytest.approx(force, abs=1e-9)
    assert any('with the elastic train the follower leaves the cam' in w
               for w in elastic.warnings())


def test_train_parameters_follow_their_rules():
    stiff = parse_parameters({**DESIGN, 'dynamics.train_natural_frequency': 0.0,
                              'dynamics.mass': 2.0, 'dynamics.train_stiffness': 8.0e5,
                              'contact.face_width': 1.0})
    assert stiff.train.natural_frequency == pytest.approx(math.sqrt(8.0e5 / 2.0) / (2 * math.pi))
    with pytest.raises(InvalidParameter, match='not both'):
        parse_parameters({**DESIGN, 'dynamics.train_stiffness': 1e5})
    with pytest.raises(InvalidParameter, match='needs dynamics.mass'):
        parse_parameters({**DESIGN, 'dynamics.train_natural_frequency': 0.0,
                          'dynamics.train_stiffness': 1e5})
    assert parse_parameters({**DESIGN, 'dynamics.train_natural_frequency': 0.0}).train is None
    assert TrainConfig(2.0, 0.0).omega_n == pytest.approx(4.0 * math.pi)


def test_the_vibration_report_takes_any_program_and_speed():
    design = build_design(parse_parameters(DESIGN))
    slow = vibration_report(design.program, math.pi, design.config.train)
    assert slow.frequency_ratio == pytest.approx(12.0) and slow.rigid_ok
    assert [s.r for s in slow.segments] == pytest.approx([3.0, 4.0])


def test_the_rigid_acceleration_is_unbounded_where_the_velocity_jumps():
    # A constant-velocity rise and return: s' jumps at all four joints, s'' is an impulse
    # there. The largest |s''| is unbounded, not 0 (the laws' own peaks), nor a smooth peak.
    design = build_design(parse_parameters(CV_DESIGN))
    report = design.vibration_check
    assert report.peak_rigid_acceleration == math.inf
    assert report.velocity_jumps == pytest.approx(np.radians([0.0, 100.0, 180.0, 280.0]))
    # One jump is enough: the cycloidal return leaves the rise's two jumps (at 0 and 100 deg).
    mixed = build_design(parse_parameters({**CV_DESIGN, 'motion.laws': [
        'constant_velocity', 'dwell', 'cycloidal', 'dwell']})).vibration_check
    assert mixed.peak_rigid_acceleration == math.inf
    assert mixed.velocity_jumps == pytest.approx(np.radians([0.0, 100.0]))
    # Without jumps: the largest |s''| of the laws, as before.
    smooth = build_design(parse_parameters(DESIGN)).vibration_check
    assert smooth.velocity_jumps == ()
    assert smooth.peak_rigid_acceleration == pytest.approx(
        0.02 * 2.0 * math.pi / (math.pi / 2) ** 2 * (2.0 * math.pi) ** 2)  # cycloidal 2 pi h/b^2


def test_the_residual_of_a_g_g_segment_is_of_the_law_s_amplitude_not_the_stroke():
    # The flying shear's synchronous section as a cycloidal G-G rise of 36 mm at 0.5 mm/deg
    # over 60 deg: the ramp carries 30 mm, the law the other H - v X = 6 mm.
    design = build_design(parse_parameters(GG_DESIGN))
    [rise] = [s for s in design.vibration_check.segments if s.index == 1]
    r = math.radians(60.0) / (2.0 * math.pi) * 20.0
    closed = abs(math.sin(math.pi * r)) / (math.pi * r * abs(1.0 - r * r))
    assert rise.r == pytest.approx(r) and rise.residual_ratio == pytest.approx(closed, abs=1e-12)
    assert rise.law_amplitude == pytest.approx(0.006, rel=1e-12)
    assert rise.residual_amplitude == pytest.approx(closed * 0.006, rel=1e-12)


@pytest.mark.filterwarnings('error')
def test_an_undamped_train_at_resonance_is_unbounded_and_fails_the_verdict():
    # fn 6 Hz, the cam at 1 Hz, no damping: harmonic 6 of the motion drives the train at its
    # natural frequency and the output grows without bound; no NumPy warning on the way.
    dynamics = {'dynamics.mass': 2.0, 'dynamics.spring_rate': 100.0,
                'dynamics.spring_preload': 50.0, 'contact.face_width': 1.0}
    for extra, force in (({}, None), (dynamics, -math.inf)):
        design = build_design(parse_parameters({**DESIGN, **extra,
                                                'dynamics.train_damping_ratio': 0.0}))
        report = design.vibration_check
        assert report.resonance == 6 and not report.ok and not design.ok
        assert report.max_output_deviation == math.inf
        assert report.peak_output_acceleration == math.inf
        assert report.elastic_force_min == force and report.elastic_force_min_at is None
        notes = [note for note in design.warnings() if 'resonates' in note]
        assert notes == [report.resonance_note()]
        assert 'is 6 x the cam frequency' in notes[0] and 'grows without bound' in notes[0]
        assert not any('leaves the cam at' in note for note in design.warnings())
    # Off the multiple the undamped train has its periodic output (large, finite).
    near = build_design(parse_parameters({**DESIGN, 'dynamics.train_damping_ratio': 0.0,
                                          'dynamics.train_natural_frequency': 6.01}))
    assert near.vibration_check.resonance is None
    assert 0.0 < near.vibration_check.max_output_deviation < math.inf
