"""Follower dynamics against closed forms, brute force, energy balance and a force balance."""
from __future__ import annotations

import math

import numpy as np
import pytest

from cam_ros.core import InvalidParameter, build_design
from cam_ros.core.config.schema import parse_parameters
from cam_ros.core.dynamics.contact import effective_modulus
from cam_ros.core.geometry.cam_geometry import cam_geometry

TWO_PI = 2.0 * math.pi
H, RB, WIDTH = 0.02, 0.05, 0.01  # m: stroke, base radius, face width
M, K, P, F, ZETA = 1.2, 8000.0, 60.0, 15.0, 0.1  # kg, N/m, N, N, -
E_STAR = effective_modulus(207e9, 0.3, 207e9, 0.3)


def cosine_cam(**updates: object) -> dict:
    """Return a translating flat-faced cam whose lift is exactly s = H/2 (1 - cos theta).

    A simple harmonic rise over 0-180 deg and return over 180-360 deg, in m.
    """
    flat = {
        'length_unit': 'm', 'rotation': 'counterclockwise', 'cam_speed': 30.0,
        'follower.type': 'translating_flat', 'follower.base_radius': RB,
        'motion.laws': ['simple_harmonic', 'simple_harmonic'],
        'motion.start_deg': [0.0, 180.0], 'motion.end_deg': [180.0, 360.0],
        'motion.start_position': [0.0, H], 'motion.end_position': [H, 0.0],
        'dynamics.mass': M, 'dynamics.spring_rate': K, 'dynamics.spring_preload': P,
        'dynamics.damping_ratio': ZETA, 'dynamics.external_force': F,
        'contact.face_width': WIDTH,
    }
    flat.update(updates)
    return flat


def build(flat: dict):
    return build_design(parse_parameters(flat))


def cosine_terms(omega: float, zeta: float = ZETA) -> tuple[float, float, float]:
    """Return (K0, alpha, beta): Q = K0 + alpha cos theta + beta sin theta on the cosine cam."""
    c = 2.0 * zeta * math.sqrt(K * M)
    return K * H / 2 + P + F, (M * omega ** 2 - K) * H / 2, c * omega * H / 2


def test_cosine_cam_forces_torque_and_stress_in_closed_form():
    omega, mu = 30.0, 0.08
    cam = build(cosine_cam(**{'contact.friction': mu}))
    theta = np.linspace(0.0, TWO_PI, 97)
    forces = cam.evaluate(theta).dynamics
    k0, alpha, beta = cosine_terms(omega)
    q = k0 + alpha * np.cos(theta) + beta * np.sin(theta)
    s, ds = H / 2 * (1 - np.cos(theta)), H / 2 * np.sin(theta)
    np.testing.assert_allclose(forces.follower_force, q, rtol=1e-12)
    np.testing.assert_allclose(forces.spring_force, K * s + P, rtol=1e-12)
    np.testing.assert_allclose(forces.contact_force, q, rtol=1e-12)  # flat face: N = Q
    # the face slides at (Rb + s) per unit cam speed: friction adds mu N (Rb + s)
    np.testing.assert_allclose(forces.camshaft_torque, q * ds + mu * q * (RB + s), rtol=1e-12,
                               atol=1e-12)
    # rho = Rb + s + s'' = Rb + H/2 everywhere: p0 = sqrt(N/L E* / (pi (Rb + H/2)))
    np.testing.assert_allclose(forces.contact_stress,
                               np.sqrt(q / WIDTH * E_STAR / (math.pi * (RB + H / 2))),
                               rtol=1e-12)


def test_cosine_cam_report_in_closed_form():
    omega = 30.0
    report = build(cosine_cam()).dynamics_check
    k0, alpha, beta = cosine_terms(omega)
    amplitude = math.hypot(alpha, beta)
    assert math.isclose(report.contact_force_min, k0 - amplitude, rel_tol=1e-12)
    assert math.isclose(report.contact_force_min_at, math.atan2(-beta, -alpha) % TWO_PI,
                        abs_tol=1e-6)
    assert math.isclose(report.contact_force_max, k0 + amplitude, rel_tol=1e-12)
    assert not report.jump and report.ok
    # T = (H/2)(K0 sin + alpha/2 sin 2t + beta/2 (1 - cos 2t)): mean square and mean exact
    rms = H / 2 * math.sqrt(k0 ** 2 / 2 + alpha ** 2 / 8 + 3 * beta ** 2 / 8)
    assert math.isclose(report.camshaft_torque_rms, rms, rel_tol=1e-12)
    assert math.isclose(report.cycle_work, TWO_PI * H / 2 * beta / 2, rel_tol=1e-9)
    fine = np.linspace(0.0, TWO_PI, 2_000_001)
    torque = (k0 + alpha * np.cos(fine) + beta * np.sin(fine)) * H / 2 * np.sin(fine)
    assert math.isclose(report.camshaft_torque_max, np.abs(torque).max(), rel_tol=1e-10)
    assert math.isclose(report.power_max, omega * report.camshaft_torque_max, rel_tol=1e-15)
    peak = math.sqrt((k0 + amplitude) / WIDTH * E_STAR / (math.pi * (RB + H / 2)))
    assert math.isclose(report.contact_stress_max, peak, rel_tol=1e-12)
    assert math.isclose(report.contact_half_width,
                        2 * (k0 + amplitude) / WIDTH / (math.pi * peak), rel_tol=1e-9)


@pytest.mark.parametrize('omega, safety', [(30.0, 1.5), (100.0, 1.5), (100.0, 2.5)])
def test_cosine_cam_spring_sizing_in_closed_form(omega, safety):
    # the preload P with min over theta of k s + P + SF (m a + c v + F) = 0 (none below 0)
    cam = build(cosine_cam(cam_speed=omega, **{'dynamics.jump_safety_factor': safety}))
    report = cam.dynamics_check
    c = 2 * ZETA * math.sqrt(K * M)
    needed = -(K * H / 2 + safety * F) + H / 2 * math.hypot(K - safety * M * omega ** 2,
                                                            safety * c * omega)
    assert math.isclose(report.spring_preload_needed, max(0.0, needed), rel_tol=1e-12)
    assert (report.spring_preload_needed > 0.0) == (omega > 50.0)  # the clamp and the rest
    # with that preload the factored force just touches zero
    theta = np.linspace(0.0, TWO_PI, 1_000_001)
    s, ds, d2s = H / 2 * (1 - np.cos(theta)), H / 2 * np.sin(theta), H / 2 * np.cos(theta)
    margin = K * s + report.spring_preload_needed + safety * (
        M * omega ** 2 * d2s + c * omega * ds + F)
    assert margin.min() >= -1e-9 * K * H and (needed < 0 or margin.min() < 1e-6 * K * H)


def test_cosine_cam_jump_speed_and_jump_angles_in_closed_form():
    # min Q = K0 - sqrt(alpha^2 + beta^2) = 0: a quadratic in x = omega^2:
    # M^2 x^2 + (c^2 - 2 M K) x + K^2 - (2 K0 / H)^2 = 0
    c = 2 * ZETA * math.sqrt(K * M)
    k0 = K * H / 2 + P + F
    x = np.roots([M ** 2, c ** 2 - 2 * M * K, K ** 2 - (2 * k0 / H) ** 2])
    expected = math.sqrt(min(root.real for root in x if root.real > 0))
    slow = build(cosine_cam()).dynamics_check
    assert math.isclose(slow.jump_speed, expected, rel_tol=1e-12)
    # undamped: omega_j = sqrt((2 K + 2 (P + F) / H) / M)
    undamped = build(cosine_cam(**{'dynamics.damping_ratio': 0.0})).dynamics_check
    assert math.isclose(undamped.jump_speed, math.sqrt((2 * K + 2 * (P + F) / H) / M),
                        rel_tol=1e-12)
    omega = 1.3 * expected
    fast = build(cosine_cam(cam_speed=omega)).dynamics_check
    k0, alpha, beta = cosine_terms(omega)
    centre, half = math.atan2(-beta, -alpha), math.acos(k0 / math.hypot(alpha, beta))
    assert fast.jump and not fast.ok and fast.contact_force_min < 0.0
    ((start, end),) = fast.jump_angles
    assert math.isclose(start, (centre - half) % TWO_PI, abs_tol=1e-9)
    assert math.isclose(end, (centre + half) % TWO_PI, abs_tol=1e-9)
    assert math.isclose(fast.jump_speed, expected, rel_tol=1e-12)  # not a function of speed


def roller_cam(**updates: object) -> dict:
    """Return seed 000's cam (cycloidal rise, simple harmonic return) with a follower train."""
    flat = {
        'length_unit': 'cm', 'rotation': 'clockwise', 'cam_speed': 40.0,
        'follower.type': 'translating_roller', 'follower.base_radius': 4.0,
        'follower.roller_radius': 1.0, 'follower.offset': 0.5,
        'motion.laws': ['dwell', 'cycloidal', 'dwell', 'simple_harmonic'],
        'motion.start_deg': [0.0, 90.0, 180.0, 240.0],
        'motion.end_deg': [90.0, 180.0, 240.0, 360.0],
        'motion.start_position': [0.0, 0.0, 2.0, 2.0],
        'motion.end_position': [0.0, 2.0, 2.0, 0.0],
        'dynamics.mass': 0.8, 'dynamics.spring_rate': 3000.0, 'dynamics.spring_preload': 20.0,
        'dynamics.damping_ratio': 0.06, 'contact.face_width': 1.0,
    }
    flat.update(updates)
    return flat


def test_jump_speed_matches_a_brute_force_search():
    cam = build(roller_cam())
    report = cam.dynamics_check
    theta = np.linspace(0.0, TWO_PI, 400_001)
    motion = cam.program.evaluate(theta)
    m, k, p, c = 0.8, 3000.0, 20.0, 2 * 0.06 * math.sqrt(3000.0 * 0.8)

    def leaves(omega: float) -> bool:
        q = m * omega ** 2 * motion.d2s + c * omega * motion.ds + k * motion.s + p
        return bool(q.min() < 0.0)

    speeds = np.linspace(1.0, 400.0, 400)
    first = next(index for index, omega in enumerate(speeds) if leaves(omega))
    low, high = speeds[first - 1], speeds[first]
    for _ in range(60):
        middle = 0.5 * (low + high)
        low, high = (low, middle) if leaves(middle) else (middle, high)
    assert math.isclose(report.jump_speed, high, rel_tol=1e-8)
    assert not report.jump  # 40 rad/s is below it


def test_conservative_train_does_no_net_work_and_damping_dissipates():
    conservative = build(roller_cam(**{'dynamics.damping_ratio': 0.0})).dynamics_check
    # the report averages 7200 samples; T has kinks at the joints: error O(spacing^2) ~ 1e-6
    assert abs(conservative.cycle_work) < 1e-6 * conservative.camshaft_torque_rms * TWO_PI
    cam = build(roller_cam())
    damped = cam.dynamics_check
    # net work = c omega * integral of (ds/dtheta)^2 over the turn, by an independent quadrature
    theta = np.linspace(0.0, TWO_PI, 1_000_001)
    ds = cam.program.evaluate(theta).ds
    c = 2 * 0.06 * math.sqrt(3000.0 * 0.8)
    assert math.isclose(damped.cycle_work, c * 40.0 * np.trapezoid(ds ** 2, theta),
                        rel_tol=1e-6)


def fixed_frame_moment(cam, theta: np.ndarray, contact: np.ndarray) -> np.ndarray:
    """Return sigma N (c x n): the drive torque from the normal force's moment about the cam."""
    motion = cam.program.evaluate(theta)
    shape = cam_geometry(cam.follower, theta, motion.s, motion.ds, motion.d2s,
                         clockwise=cam.clockwise)
    point = np.array((shape.surface_x, shape.surface_y))
    if hasattr(cam.follower, 'roller_radius'):
        normal = (np.array((shape.pitch_x, shape.pitch_y)) - point) / cam.follower.roller_radius
    else:  # square to the surface's tangent (central differences), pointing away from the cam
        step = 1e-6
        ahead = cam_geometry(cam.follower, theta + step, *_motion(cam, theta + step),
                             clockwise=cam.clockwise)
        behind = cam_geometry(cam.follower, theta - step, *_motion(cam, theta - step),
                              clockwise=cam.clockwise)
        tangent = np.array((ahead.surface_x - behind.surface_x,
                            ahead.surface_y - behind.surface_y))
        normal = np.array((tangent[1], -tangent[0])) / np.hypot(*tangent)
        normal *= np.sign(normal[0] * point[0] + normal[1] * point[1])
    sigma = -1.0 if cam.clockwise else 1.0
    return sigma * contact * (point[0] * normal[1] - point[1] * normal[0])


def _motion(cam, theta):
    motion = cam.program.evaluate(theta)
    return motion.s, motion.ds, motion.d2s


OSCILLATING = {
    'follower.pivot_distance': 10.0, 'follower.arm_length': 8.0,
    'motion.start_position': [0.0, 0.0, 12.0, 12.0], 'motion.end_position': [0.0, 12.0, 12.0, 0.0],
    'dynamics.mass': 0.0, 'dynamics.arm_inertia': 0.004, 'dynamics.spring_rate': 30.0,
    'dynamics.spring_preload': 3.0,
}


@pytest.mark.parametrize('updates', [
    {},
    {'rotation': 'counterclockwise', 'follower.offset': -0.7},
    {'follower.type': 'translating_flat'},
    {'follower.type': 'oscillating_roller', **OSCILLATING},
    {'follower.type': 'oscillating_roller', 'follower.arm_turns_with_cam': True, **OSCILLATING},
    {'follower.type': 'oscillating_flat', 'follower.face_offset': 1.0, **OSCILLATING},
    {'follower.type': 'oscillating_flat', 'follower.face_offset': -1.5,
     'follower.arm_turns_with_cam': True, **OSCILLATING},
], ids=['roller', 'roller-ccw-offset', 'flat', 'arm-roller', 'arm-roller-with-cam', 'arm-flat',
        'arm-flat-with-cam'])
def test_power_balance_torque_equals_the_normal_force_moment_about_the_cam(updates):
    cam = build(roller_cam(**updates))
    theta = np.linspace(0.0, TWO_PI, 721)[:-1] + 1e-3
    forces = cam.evaluate(theta).dynamics
    expected = fixed_frame_moment(cam, theta, forces.contact_force)
    scale = np.abs(forces.camshaft_torque).max()
    np.testing.assert_allclose(forces.camshaft_torque, expected, atol=1e-7 * scale)


def test_normal_force_of_an_oscillating_roller_through_its_lever_arm():
    cam = build(roller_cam(**{'follower.type': 'oscillating_roller', **OSCILLATING}))
    state = cam.evaluate(np.linspace(0.0, TWO_PI, 50))
    forces = state.dynamics
    np.testing.assert_allclose(forces.contact_force * 0.08 * np.cos(state.pressure_angle),
                               forces.follower_force, rtol=1e-12)


@pytest.mark.parametrize('updates, parameter, fragment', [
    ({'dynamics.mass': -1.0}, 'dynamics.mass', '>= 0'),
    ({'contact.cam_poisson': 0.5}, 'contact.cam_poisson', '[0, 0.5)'),
    ({'contact.follower_poisson': -0.1}, 'contact.follower_poisson', '>= 0'),
    ({'contact.face_width': 0.0}, 'contact.face_width', 'must be > 0'),
    ({'contact.cam_modulus': 0.0}, 'contact.cam_modulus', 'must be > 0'),
    ({'contact.friction': 0.1}, 'contact.friction', 'flat faces only'),
    ({'dynamics.arm_inertia': 0.1}, 'dynamics.arm_inertia', 'takes dynamics.mass'),
    ({'follower.type': 'oscillating_roller', **OSCILLATING, 'dynamics.mass': 1.0},
     'dynamics.mass', 'takes dynamics.arm_inertia'),
    ({'dynamics.spring_rate': 1}, 'dynamics.spring_rate', 'write 1.0'),
    ({'dynamics.damping_ratio': math.nan}, 'dynamics.damping_ratio', 'finite'),
    ({'limits.contact_stress': -5.0}, 'limits.contact_stress', '>= 0'),
])
def test_bad_dynamics_values_are_named(updates, parameter, fragment):
    with pytest.raises(InvalidParameter) as caught:
        build(roller_cam(**updates))
    assert caught.value.parameter == parameter
    assert fragment in caught.value.rule
    assert '\n' not in str(caught.value)


def test_a_design_without_mass_has_no_dynamics():
    flat = roller_cam()
    for name in ('mass', 'spring_rate', 'spring_preload', 'damping_ratio'):
        del flat[f'dynamics.{name}']  # a spring without a mass is refused (test_hostile_values)
    del flat['contact.face_width']
    cam = build(flat)
    assert cam.dynamics is None and cam.evaluate([0.3]).dynamics is None
    assert cam.dynamics_check is None


def test_face_width_is_in_the_length_unit_and_stress_limit_is_checked():
    cam = build(roller_cam(**{'limits.contact_stress': 1e6}))
    assert cam.config.dynamics.face_width == pytest.approx(0.01)
    report = cam.dynamics_check
    assert report.contact_stress_ok is False and not report.ok and not report.jump
    relaxed = build(roller_cam(**{'limits.contact_stress': 5e9})).dynamics_check
    assert relaxed.contact_stress_ok is True and relaxed.ok


@pytest.mark.parametrize('updates', [
    {'follower.type': 'translating_flat'},
    {'follower.type': 'oscillating_flat', 'follower.face_offset': 1.0, **OSCILLATING},
    {'follower.type': 'oscillating_flat', 'follower.face_offset': -1.5,
     'follower.arm_turns_with_cam': True, **OSCILLATING},
], ids=['flat', 'arm-flat', 'arm-flat-with-cam'])
def test_flat_face_friction_against_the_force_and_moment_balance(updates):
    mu = 0.15
    cam = build(roller_cam(**updates, **{'contact.friction': mu}))
    theta = np.linspace(0.0, TWO_PI, 361)[:-1] + 1e-3
    forces = cam.evaluate(theta).dynamics
    s, ds, d2s = _motion(cam, theta)
    shape = cam_geometry(cam.follower, theta, s, ds, d2s, clockwise=cam.clockwise)
    sigma = -1.0 if cam.clockwise else 1.0
    turn = np.array(((np.cos(sigma * theta), -np.sin(sigma * theta)),
                     (np.sin(sigma * theta), np.cos(sigma * theta))))
    contact = np.einsum('ijn,jn->in', turn, np.array((shape.surface_x, shape.surface_y)))
    # the face's normal and the material velocities (per unit cam speed) at the contact
    if cam.config.follower.type == 'translating_flat':
        normal = np.array((np.zeros_like(s), np.ones_like(s)))
        face_velocity, lever_point = np.array((np.zeros_like(s), ds)), None
    else:
        f = cam.follower
        lam = sigma if f.arm_turns_with_cam else -sigma
        psi = f.initial_arm_angle + s
        normal = np.array((lam * np.cos(psi), np.sin(psi)))
        lever_point = contact - np.array([[0.0], [f.pivot_distance]])
        face_velocity = lam * ds * np.array((-lever_point[1], lever_point[0]))
    slip = sigma * np.array((-contact[1], contact[0])) - face_velocity  # cam minus face
    np.testing.assert_allclose(np.einsum('in,in->n', slip, normal), 0.0, atol=1e-12)
    along = slip / np.hypot(*slip)
    load = forces.contact_force * (normal + mu * along)  # on the follower: normal + friction
    if lever_point is None:
        generalised = load[1]
    else:
        generalised = lam * (lever_point[0] * load[1] - lever_point[1] * load[0])
    np.testing.assert_allclose(generalised, forces.follower_force, rtol=1e-9)
    moment = sigma * (contact[0] * load[1] - contact[1] * load[0])
    np.testing.assert_allclose(forces.camshaft_torque, moment, rtol=1e-9,
                               atol=1e-12 * np.abs(moment).max())
    assert np.all(forces.camshaft_torque * 40.0 - forces.follower_force * ds * 40.0 >= 0.0)


def test_a_jump_span_through_zero_degrees_wraps():
    # s = H/2 (1 + cos theta): the fall first, so the least force lies just after 0 deg
    c = 2 * ZETA * math.sqrt(K * M)
    omega = 1.3 * math.sqrt((2 * K + 2 * (P + F) / H) / M)
    cam = build(cosine_cam(cam_speed=omega, **{'motion.start_position': [H, 0.0],
                                               'motion.end_position': [0.0, H]}))
    alpha, beta = (K - M * omega ** 2) * H / 2, -c * omega * H / 2
    k0 = K * H / 2 + P + F
    centre, half = math.atan2(-beta, -alpha), math.acos(k0 / math.hypot(alpha, beta))
    assert centre < half  # the span starts before 0 deg
    ((start, end),) = cam.dynamics_check.jump_angles
    assert math.isclose(start, centre - half + TWO_PI, abs_tol=1e-9)
    assert math.isclose(end, centre + half, abs_tol=1e-9)


def test_a_preload_needed_at_rounding_level_reads_zero():
    # Seed 003's 4-5-6-7 cam at 0.5 rad/s on a 1 kg, 1000 N/m train: the return decelerates
    # into the dwell at s = 0, where k s = m a = c v = 0, so no preload is needed at all; the
    # refined shortfall there is rounding (some 1e-13 N) and must read 0, not 8.8e-14 N.
    cam = build({
        'length_unit': 'in', 'rotation': 'counterclockwise', 'cam_speed': 0.5,
        'follower.type': 'translating_roller', 'follower.base_radius': 1.5,
        'follower.roller_radius': 0.25,
        'motion.laws': ['polynomial_4567', 'dwell', 'polynomial_4567', 'dwell'],
        'motion.start_deg': [0.0, 60.0, 180.0, 240.0],
        'motion.end_deg': [60.0, 180.0, 240.0, 360.0],
        'motion.start_position': [0.0, 0.5, 0.5, 0.0],
        'motion.end_position': [0.5, 0.5, 0.0, 0.0], 'dynamics.mass': 1.0,
        'dynamics.spring_rate': 1000.0, 'contact.face_width': 1.0})
    assert cam.dynamics_check.spring_preload_needed == 0.0
    # brute force: the factored force without preload, k s + SF m a, never falls below 0
    theta = np.linspace(0.0, TWO_PI, 400_001)
    state = cam.evaluate(theta)
    factored = 1000.0 * state.position + 1.5 * 1.0 * state.acceleration
    assert factored.min() >= -1e-12 * 1000.0 * 0.0127
