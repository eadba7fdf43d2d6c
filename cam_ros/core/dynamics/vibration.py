"""Elastic follower train: residual vibration, periodic response at speed, the rigid criterion.

The train between cam and output is one spring-mass stage of natural frequency fn (omega_n =
2 pi fn) and damping ratio zeta; the cam drives its input y, the output x follows

    x'' + 2 zeta omega_n x' + omega_n^2 x = omega_n^2 y        (time derivatives).

* Residual vibration of a moving segment (undamped train, Rothbart ch. 13): a segment of
  duration T whose law f (0 to 1) moves the follower by the law's amplitude a leaves the output
  oscillating about the cam motion with amplitude R, R/a = |V(2 pi r)| at r = T fn, where for
  a law at rest at both ends V(W) = int_0^1 f'(u) exp(-i W u) du. a is the stroke h of a
  rest-to-rest segment and h - v beta (stroke less the ramp's travel, VDI 2143's H - v X) of a
  motion task under a ramp v (G-G, R-G, ...): the ramp itself excites nothing. For any law
  not at rest at both ends the same R is the vibration its own acceleration excites in a train
  that entered it without vibration, R/a = |int_0^1 f''(u) exp(-i W u) du| / W (equal to |V|
  at rest ends); a velocity jump at a joint is an impulse of its own and not included.
  Computed by Gauss-Legendre quadrature on the law's smooth pieces, fine enough for the
  oscillation: exact to rounding, no simulation.
* Periodic response at speed: the exact periodic solution of the ODE (periodic.py), jumps in
  y and its derivatives included; an undamped train at fn = k x the cam frequency has none (it
  resonates: the report says the output is unbounded).
* VDI 2149 Blatt 1 allows the rigid-body analysis only when fn is at least RIGID_RATIO times
  the cam frequency.
"""
from __future__ import annotations

import math
from dataclasses import dataclass
from typing import Any, Optional

import numpy as np
import numpy.typing as npt

from ..arrays import FloatArray
from ..extremes import refine_extrema
from ..errors import InvalidParameter
from ..motion.laws import MotionLaw
from ..motion.program import MotionProgram
from ..motion.segment import motion_task
from .periodic import periodic_response, resonant_harmonic
from .train import TrainConfig

#: VDI 2149: the rigid model holds when the train's natural frequency is this many times the
#: cam frequency or more.
RIGID_RATIO = 10.0
#: Gauss-Legendre nodes per quadrature panel, and panels per oscillation of exp(-i W u).
GAUSS_NODES = 20
PANELS_PER_CYCLE = 2
#: End slopes f'(0), f'(1) closer than this are equal (sin(pi) is not quite 0).
SLOPE_TOLERANCE = 1e-12


def _panels(law: MotionLaw, count: int) -> FloatArray:
    """Return the panel edges on [0, 1]: the law's breakpoints, each piece cut into equal parts."""
    edges = np.array([0.0, *law.breakpoints, 1.0])
    pieces = [np.linspace(a, b, max(1, math.ceil(count * (b - a))) + 1)[:-1]
              for a, b in zip(edges[:-1], edges[1:]) if b > a]
    return np.append(np.concatenate(pieces), 1.0)


def residual_ratio(law: MotionLaw, r: npt.ArrayLike) -> FloatArray:
    """Return R/a of a segment with this law at duration ratios r = T fn >= 0 (see above).

    a is the law's amplitude: the stroke of a rest-to-rest segment, h - v beta under a ramp v.
    """
    ratio = np.asarray(r, dtype=float)
    if ratio.size == 0:
        return ratio.copy()
    if not np.all(np.isfinite(ratio) & (ratio >= 0.0)):
        raise InvalidParameter('r', ratio.tolist(), 'must be finite and >= 0')
    omega = 2.0 * math.pi * ratio.reshape(-1)
    edges = _panels(law, PANELS_PER_CYCLE * math.ceil(float(omega.max()) / (2.0 * math.pi)) + 8)
    nodes, weights = np.polynomial.legendre.leggauss(GAUSS_NODES)
    half = 0.5 * np.diff(edges)
    u = (edges[:-1, None] + half[:, None] * (nodes + 1.0)).reshape(-1)
    w = (half[:, None] * weights).reshape(-1)
    values = law.evaluate(np.clip(u, 0.0, 1.0))
    ends = law.evaluate(np.array([0.0, 1.0])).y1
    phase = np.exp(-1j * np.outer(omega, u))
    transform = phase @ (w * values.y1)  # int f' exp(-i W u) du
    moving = omega > 0.0
    boundary = np.zeros_like(transform)
    boundary[moving] = (ends[1] * np.exp(-1j * omega[moving]) - ends[0]) / (1j * omega[moving])
    result = np.abs(transform + boundary)
    # At W = 0 (an instant segment): |1 - f'(1)| with equal end slopes, unbounded without.
    equal = abs(ends[1] - ends[0]) <= SLOPE_TOLERANCE
    result[~moving] = abs(1.0 - ends[1]) if equal else np.inf
    return result.reshape(ratio.shape)


@dataclass(frozen=True)
class SegmentVibration:
    """Residual vibration after one moving segment: r = T fn, amplitude R (m or rad), R/a.

    law_amplitude a = |h - v beta| (m or rad) is what the ratio divides by: the stroke |h| of a
    rest-to-rest segment, the stroke less the ramp's travel under a ramp v (span beta).
    """

    index: int
    r: float
    residual_amplitude: float
    residual_ratio: float
    law_amplitude: float


def segment_vibrations(program: MotionProgram, omega: float,
                       train: TrainConfig) -> tuple[SegmentVibration, ...]:
    """Return the residual vibration after every rise and return of a program at speed omega.

    A motion task's ramp (constant velocity under the law) leaves no vibration, so R scales with
    the law's amplitude; segments with a reversal or general-motion end (U, B: accelerating at a
    joint) have no steady state to leave and are not listed.
    """
    found = []
    for index, segment in enumerate(program.segments):
        if segment.amplitude == 0.0 or {'U', 'B'} & set(motion_task(segment)):
            continue
        r = segment.span / omega * train.natural_frequency
        ratio = float(residual_ratio(segment.law, r))
        found.append(SegmentVibration(index, r, ratio * abs(segment.amplitude), ratio,
                                      abs(segment.amplitude)))
    return tuple(found)


@dataclass(frozen=True)
class VibrationReport:
    """The elastic train at the cam speed omega (SI; angles rad; positions m or rad).

    frequency_ratio is fn over the cam frequency, rigid_ok whether it reaches RIGID_RATIO;
    segments the residual vibration after each moving segment (undamped train); the rest comes
    from the damped periodic response: the largest |x - s|, the largest |x''| against the rigid
    cam's largest |s''|, and with a dynamics model the least follower force Q with the output's
    acceleration (< 0: the follower leaves the cam; None without a model). Extremes are refined
    on the exact periodic solution by extremes.refine_extrema, not read off the grid.
    velocity_jumps are the angles where the designed motion's velocity jumps: its acceleration
    is an impulse there and peak_rigid_acceleration is inf (unbounded). resonance is k when the
    train is undamped and fn is k times the cam frequency: no steady state, the output grows
    without bound, so the deviation and the output's acceleration are inf (at nan) and the least
    force -inf (at None).
    """

    natural_frequency_hz: float
    damping_ratio: float
    frequency_ratio: float
    rigid_ok: bool
    segments: tuple[SegmentVibration, ...]
    max_output_deviation: float
    max_output_deviation_at: float
    peak_output_acceleration: float
    peak_output_acceleration_at: float
    peak_rigid_acceleration: float
    elastic_force_min: Optional[float]
    elastic_force_min_at: Optional[float]
    compensated: bool  # the cam is not the designed motion but shaped for the train (polydyne)
    velocity_jumps: tuple[float, ...] = ()
    resonance: Optional[int] = None

    @property
    def leaves_cam(self) -> bool:
        """Return True when the output's acceleration makes the follower leave the cam."""
        return self.elastic_force_min is not None and self.elastic_force_min < 0.0

    @property
    def ok(self) -> bool:
        """Return True when the output has a steady state and the follower stays on the cam."""
        return self.resonance is None and not self.leaves_cam

    def resonance_note(self) -> str:
        """Say what a resonance of the undamped train means ('' without one)."""
        if self.resonance is None:
            return ''
        return (f'the undamped follower train resonates: fn {self.natural_frequency_hz:.6g} Hz '
                f'is {self.resonance} x the cam frequency, so harmonic {self.resonance} of the '
                "cam's motion drives it at its natural frequency and the output's vibration "
                'grows without bound (no steady state); give dynamics.train_damping_ratio > 0 '
                'or move fn off the multiple')


def vibration_report(program: MotionProgram, omega: float, train: TrainConfig,
                     model: Any = None, output: Optional[MotionProgram] = None) -> VibrationReport:
    """Return the vibration figures of a cam driving a train at cam speed omega.

    program is the cam's motion (the train's input); output the designed follower motion the
    train's output is measured against (default: the program; a polydyne cam's own motion).
    model is the design's FollowerDynamics (or None): its follower_force(s, ds, d2s) gives the
    force with the output's acceleration in place of the rigid one.
    """
    target = program if output is None else output
    ratio = train.natural_frequency / (omega / (2.0 * math.pi))
    jumps = tuple(jump.angle for jump in target.continuity_report() if jump.order == 1)
    rigid = math.inf if jumps else max(
        summary.peaks_at_speed(omega)[1] for summary in target.segment_summary())
    resonance = resonant_harmonic(omega, train)
    if resonance is None:
        figures = _response_extremes(program, target, omega, train, model)
    else:
        figures = (math.inf, math.nan, math.inf, math.nan,
                   *((None, None) if model is None else (-math.inf, None)))
    deviation, deviation_at, acceleration, acceleration_at, force_min, force_min_at = figures
    return VibrationReport(
        natural_frequency_hz=train.natural_frequency, damping_ratio=train.damping_ratio,
        frequency_ratio=ratio, rigid_ok=ratio >= RIGID_RATIO,
        segments=segment_vibrations(program, omega, train),
        max_output_deviation=deviation, max_output_deviation_at=deviation_at,
        peak_output_acceleration=acceleration, peak_output_acceleration_at=acceleration_at,
        peak_rigid_acceleration=rigid, elastic_force_min=force_min,
        elastic_force_min_at=force_min_at, compensated=target is not program,
        velocity_jumps=jumps, resonance=resonance)


def _response_extremes(program: MotionProgram, target: MotionProgram, omega: float,
                       train: TrainConfig, model: Any) -> tuple[Any, ...]:
    """Return max |x - s|, max |x''|, the least force (None without a model), each with its at."""
    response = periodic_response(program, omega, train)
    designed = target.evaluate(response.angle)

    def measures(theta: FloatArray) -> FloatArray:
        """|x - s|, |x''| and (with a model) the follower force Q at cam angles."""
        at, (output, _, acceleration) = target.evaluate(theta), response.outputs(theta)
        rows = [np.abs(output - at.s), np.abs(acceleration)]
        if model is not None:
            rows.append(model.follower_force(at.s, at.ds, acceleration / omega ** 2)[0])
        return np.array(rows)

    grid = [np.abs(response.output - designed.s), np.abs(response.output_acceleration)]
    if model is not None:
        grid.append(model.follower_force(designed.s, designed.ds,
                                         response.output_acceleration / omega ** 2)[0])
    (deviation, deviation_at), (acceleration, acceleration_at), *force = refine_extrema(
        measures, response.angle, np.array(grid), ('max', 'max', 'min')[:len(grid)],
        breaks=np.union1d(program.breaks, target.breaks))
    return (deviation, deviation_at, acceleration, acceleration_at,
            *(force[0] if force else (None, None)))
