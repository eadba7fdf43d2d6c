"""Elastic follower train: residual vibration, periodic response at speed, the rigid criterion.

The train between cam and output is one spring-mass stage of natural frequency fn (omega_n =
2 pi fn) and damping ratio zeta; the cam drives its input y, the output x follows

    x'' + 2 zeta omega_n x' + omega_n^2 x = omega_n^2 y        (time derivatives).

* Residual vibration of a moving segment (undamped train, Rothbart ch. 13): a segment of
  duration T and stroke h with normalised law f leaves the output oscillating about the cam
  motion with amplitude R, R/h = |V(2 pi r)| at r = T fn, where for a law at rest at both ends
  V(W) = int_0^1 f'(u) exp(-i W u) du. For any other law the same R is the vibration its own
  acceleration excites in a train that entered it without vibration,
  R/h = |int_0^1 f''(u) exp(-i W u) du| / W (equal to |V| at rest ends); a velocity jump at a
  joint is an impulse of its own and not included. Computed by Gauss-Legendre quadrature on
  the law's smooth pieces, fine enough for the oscillation: exact to rounding, no simulation.
* Periodic response: at a constant cam speed y is periodic; the steady state is the periodic
  solution, computed from the Fourier series of y (each harmonic k omega multiplied by the
  train's frequency response), not by running a transient until it decays.
* VDI 2149 Blatt 1 allows the rigid-body analysis only when fn is at least RIGID_RATIO times
  the cam frequency.
"""
from __future__ import annotations

import math
from dataclasses import dataclass
from typing import Any, Mapping, Optional

import numpy as np
import numpy.typing as npt

from ..arrays import FloatArray
from ..extremes import refine_extrema
from ..errors import InvalidParameter
from ..motion.laws import MotionLaw
from ..motion.program import MotionProgram
from ..motion.segment import motion_task

#: VDI 2149: the rigid model holds when the train's natural frequency is this many times the
#: cam frequency or more.
RIGID_RATIO = 10.0
#: Gauss-Legendre nodes per quadrature panel, and panels per oscillation of exp(-i W u).
GAUSS_NODES = 20
PANELS_PER_CYCLE = 2
#: End slopes f'(0), f'(1) closer than this are equal (sin(pi) is not quite 0).
SLOPE_TOLERANCE = 1e-12
#: Samples of the cam motion per revolution for the periodic response (a power of two).
RESPONSE_SAMPLES = 2 ** 14
#: Harmonics per block when the Fourier series is evaluated at arbitrary angles: e^(ik theta)
#: is e^(i m theta) e^(i B j theta), k = B j + m, so only 2 sqrt(K) exponentials per angle.
HARMONIC_BLOCK = 64


@dataclass(frozen=True)
class TrainConfig:
    """The follower train's lowest natural frequency (Hz, cam side held) and damping ratio.

    compensate: the cam is shaped so that the train's output is the designed motion (polydyne).
    """

    natural_frequency: float
    damping_ratio: float
    compensate: bool = False

    @property
    def omega_n(self) -> float:
        """Return the natural angular frequency (rad/s)."""
        return 2.0 * math.pi * self.natural_frequency


def parse_train(values: Mapping[str, Any], inertia: float,
                inertia_name: str) -> Optional[TrainConfig]:
    """Return the train of checked flat values, None without a frequency or a stiffness.

    inertia is the follower's mass (kg) or arm inertia (kg m^2) named inertia_name, needed to
    turn dynamics.train_stiffness into a frequency: fn = sqrt(k / m) / (2 pi).
    """
    frequency = values['dynamics.train_natural_frequency']
    stiffness = values['dynamics.train_stiffness']
    if frequency and stiffness:
        raise InvalidParameter('dynamics.train_stiffness', stiffness,
                               'give dynamics.train_natural_frequency or '
                               'dynamics.train_stiffness, not both')
    if stiffness:
        if not inertia:
            raise InvalidParameter('dynamics.train_stiffness', stiffness,
                                   f'needs {inertia_name} to give a natural frequency (or give '
                                   'dynamics.train_natural_frequency instead)')
        frequency = math.sqrt(stiffness / inertia) / (2.0 * math.pi)
    compensate = values['dynamics.compensate']
    if not frequency:
        if compensate:
            raise InvalidParameter('dynamics.compensate', compensate,
                                   'needs the follower train: give '
                                   'dynamics.train_natural_frequency or dynamics.train_stiffness')
        return None
    return TrainConfig(frequency, values['dynamics.train_damping_ratio'], compensate)


def _panels(law: MotionLaw, count: int) -> FloatArray:
    """Return the panel edges on [0, 1]: the law's breakpoints, each piece cut into equal parts."""
    edges = np.array([0.0, *law.breakpoints, 1.0])
    pieces = [np.linspace(a, b, max(1, math.ceil(count * (b - a))) + 1)[:-1]
              for a, b in zip(edges[:-1], edges[1:]) if b > a]
    return np.append(np.concatenate(pieces), 1.0)


def residual_ratio(law: MotionLaw, r: npt.ArrayLike) -> FloatArray:
    """Return R/h of a segment with this law at duration ratios r = T fn >= 0 (see above)."""
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
    """Residual vibration after one moving segment: r = T fn, amplitude R (m or rad), R/h."""

    index: int
    r: float
    residual_amplitude: float
    residual_ratio: float


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
        found.append(SegmentVibration(index, r, ratio * abs(segment.amplitude), ratio))
    return tuple(found)


@dataclass(frozen=True, eq=False)
class PeriodicResponse:
    """The train's steady output over one revolution (SI, time derivatives at the cam speed).

    angle are RESPONSE_SAMPLES cam angles from 0 (rad); input is the cam motion s there, output
    x, output_velocity and output_acceleration the train's; `at(theta)` evaluates the output's
    Fourier series anywhere.
    """

    omega: float
    angle: FloatArray
    input: FloatArray
    output: FloatArray
    output_velocity: FloatArray
    output_acceleration: FloatArray
    coefficients: npt.NDArray[np.complex128]  # of x, per harmonic k of the cam angle

    def at(self, theta: npt.ArrayLike, derivative: int = 0) -> FloatArray:
        """Return the output's derivative (0: x, 1: dx/dt, 2: d2x/dt2) at cam angles theta."""
        angles = np.asarray(theta, dtype=float)
        k = np.arange(self.coefficients.size)
        factor = (1j * k * self.omega) ** derivative * self.coefficients
        factor[1:] *= 2.0  # the negative harmonics: real signal
        blocks = -(-factor.size // HARMONIC_BLOCK)
        factor = np.resize(factor, blocks * HARMONIC_BLOCK)
        factor[self.coefficients.size:] = 0.0
        flat = angles.reshape(-1)
        low = np.exp(1j * np.multiply.outer(flat, np.arange(HARMONIC_BLOCK)))
        high = np.exp(1j * np.multiply.outer(flat, HARMONIC_BLOCK * np.arange(blocks)))
        values = np.real(np.sum(high * (low @ factor.reshape(blocks, HARMONIC_BLOCK).T), axis=1))
        return (values / self.angle.size).reshape(angles.shape)


def periodic_response(program: MotionProgram, omega: float, train: TrainConfig,
                      samples: int = RESPONSE_SAMPLES) -> PeriodicResponse:
    """Return the steady periodic output of the train driven by the program at speed omega."""
    angle = 2.0 * math.pi * np.arange(samples) / samples
    s = program.evaluate(angle).s
    spectrum = np.fft.rfft(s)
    frequency = omega * np.arange(spectrum.size)  # rad/s of each harmonic
    wn, zeta = train.omega_n, train.damping_ratio
    response = wn * wn / (wn * wn - frequency ** 2 + 2j * zeta * wn * frequency)
    x = response * spectrum
    if samples % 2 == 0:
        x[-1] = x[-1].real  # the Nyquist harmonic of a real signal
    output, velocity, acceleration = (np.fft.irfft((1j * frequency) ** order * x, samples)
                                      for order in range(3))
    coefficients = x.copy()
    if samples % 2 == 0:
        coefficients[-1] *= 0.5  # at() doubles every harmonic above 0
    return PeriodicResponse(omega, angle, s, output, velocity, acceleration, coefficients)


@dataclass(frozen=True)
class VibrationReport:
    """The elastic train at the cam speed omega (SI; angles rad; positions m or rad).

    frequency_ratio is fn over the cam frequency, rigid_ok whether it reaches RIGID_RATIO;
    segments the residual vibration after each moving segment (undamped train); the rest comes
    from the damped periodic response: the largest |x - s|, the largest |x''| against the rigid
    cam's largest |s''|, and with a dynamics model the least follower force Q with the output's
    acceleration (< 0: the follower leaves the cam; None without a model). Extremes are refined
    on the exact Fourier series by extremes.refine_extrema, not read off the grid.
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

    @property
    def leaves_cam(self) -> bool:
        """Return True when the output's acceleration makes the follower leave the cam."""
        return self.elastic_force_min is not None and self.elastic_force_min < 0.0


def vibration_report(program: MotionProgram, omega: float, train: TrainConfig,
                     model: Any = None, output: Optional[MotionProgram] = None) -> VibrationReport:
    """Return the vibration figures of a cam driving a train at cam speed omega.

    program is the cam's motion (the train's input); output the designed follower motion the
    train's output is measured against (default: the program; a polydyne cam's own motion).
    model is the design's FollowerDynamics (or None): its follower_force(s, ds, d2s) gives the
    force with the output's acceleration in place of the rigid one.
    """
    target = program if output is None else output
    response = periodic_response(program, omega, train)
    designed = target.evaluate(response.angle)

    def measures(theta: FloatArray) -> FloatArray:
        """|x - s|, |x''| and (with a model) the follower force Q at cam angles."""
        at, acceleration = target.evaluate(theta), response.at(theta, 2)
        rows = [np.abs(response.at(theta) - at.s), np.abs(acceleration)]
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
    force_min, force_min_at = force[0] if force else (None, None)
    rigid = max(summary.peaks_at_speed(omega)[1] for summary in target.segment_summary())
    ratio = train.natural_frequency / (omega / (2.0 * math.pi))
    return VibrationReport(
        natural_frequency_hz=train.natural_frequency, damping_ratio=train.damping_ratio,
        frequency_ratio=ratio, rigid_ok=ratio >= RIGID_RATIO,
        segments=segment_vibrations(program, omega, train),
        max_output_deviation=deviation, max_output_deviation_at=deviation_at,
        peak_output_acceleration=acceleration, peak_output_acceleration_at=acceleration_at,
        peak_rigid_acceleration=rigid, elastic_force_min=force_min,
        elastic_force_min_at=force_min_at, compensated=target is not program)
