"""The exact periodic response of the elastic follower train to a cam at constant speed.

The train's output x answers the cam's motion y (time derivatives at the cam speed omega):
x'' + 2 zeta wn x' + wn^2 x = wn^2 y. Its deviation d = (x - y, x' - y') obeys

    d' = A d - e2 c(t),   A = [[0, 1], [-wn^2, -2 zeta wn]],   e2 = (0, 1),
    c = y'' + 2 zeta wn y',

and where y' jumps (a velocity jump at a joint: an impulse in y'') d jumps by (0, -jump) while
x and x' go on. Over a stretch of duration tau holding no break

    d(t + tau) = Phi(tau) d(t) - int_0^tau Phi(tau - u) e2 c(t + u) du,   Phi(t) = exp(A t)

in closed form, exp(m t) (cosh(k t) I + sinh(k t) / k (A - m I)) with m = -zeta wn,
k = wn sqrt(zeta^2 - 1) (cos and sin of the damped frequency below critical damping). The
integral is Gauss-Legendre quadrature of RESPONSE_NODES nodes on stretches that hold no break
and span at most STEP_PHASE rad of the train's fastest mode: exact to rounding whatever jumps
y', y'' or y''' make (a Fourier series of y, cut off, misses the ringing a jump starts). The
stretches' affine maps compose, a prefix scan in log2(N) vectorised passes, to one turn's
d(T) = P d(0) + q, and the periodic state solves (I - P) d(0) = q: unique unless the train is
undamped and fn is a whole multiple of the cam frequency (see resonant_harmonic).
"""
from __future__ import annotations

import math
from dataclasses import dataclass
from typing import Optional

import numpy as np
import numpy.typing as npt

from ..arrays import FloatArray
from ..cam_angles import TWO_PI
from ..errors import InvalidParameter
from ..motion.program import MotionProgram
from .train import TrainConfig

#: Fewest stretches per revolution (a power of two above the design checks' 7200 samples): the
#: grid the report's extremes start from.
RESPONSE_SAMPLES = 2 ** 13
#: Most stretches per revolution: a train stiffer than this allows (fn some 80,000 times the
#: cam frequency) is refused rather than integrated coarsely.
MAX_RESPONSE_SAMPLES = 2 ** 20
#: Stretches evaluated at a time (bounds the memory of the quadrature nodes).
RESPONSE_BLOCK = 2 ** 14
#: Gauss-Legendre nodes per stretch, and the largest phase |lambda| tau (rad) of the train's
#: fastest mode over one stretch: the quadrature's error is then far below rounding.
RESPONSE_NODES = 8
STEP_PHASE = 0.5
_NODES, _WEIGHTS = np.polynomial.legendre.leggauss(RESPONSE_NODES)
#: An undamped train whose fn is within this fraction of a whole multiple of the cam frequency
#: resonates: there is no periodic solution (the vibration grows without bound).
RESONANCE_TOLERANCE = 1e-9
#: One-sided limits of y' at a break are taken this far (rad) to either side of it.
SIDE_GAP = 16.0 * float(np.finfo(float).eps) * TWO_PI
#: A grid point closer to a break than this fraction of a step gives way to the break.
MERGE_FRACTION = 1e-3


def resonant_harmonic(omega: float, train: TrainConfig) -> Optional[int]:
    """Return k when an undamped train's fn is k times the cam frequency (k >= 1), else None.

    Then the cam's k-th harmonic drives the train at its natural frequency: no steady state,
    the vibration grows without bound (or, were that harmonic exactly zero, any vibration
    started never decays: no unique steady state either).
    """
    if train.damping_ratio > 0.0:
        return None
    ratio = train.natural_frequency * TWO_PI / omega
    harmonic = round(ratio)
    if harmonic >= 1 and abs(ratio - harmonic) <= RESONANCE_TOLERANCE * ratio:
        return int(harmonic)
    return None


def transition(train: TrainConfig, t: npt.ArrayLike) -> tuple[FloatArray, ...]:
    """Return the entries p11, p12, p21, p22 of Phi(t) = exp(A t) at times t >= 0 (s)."""
    time = np.asarray(t, dtype=float)
    wn, zeta = train.omega_n, train.damping_ratio
    decay = np.exp(-zeta * wn * time)
    if zeta < 1.0:
        damped = wn * math.sqrt(1.0 - zeta * zeta)
        even, odd = np.cos(damped * time), np.sin(damped * time) / damped
    elif zeta > 1.0:
        rate = wn * math.sqrt(zeta * zeta - 1.0)
        even, odd = np.cosh(rate * time), np.sinh(rate * time) / rate
    else:
        even, odd = np.ones_like(time), time.copy()
    even *= decay
    odd *= decay
    return even + zeta * wn * odd, odd, -wn * wn * odd, even - zeta * wn * odd


def _fastest_rate(train: TrainConfig) -> float:
    """Return the largest |eigenvalue| of A (1/s): wn, or wn (zeta + sqrt(zeta^2 - 1))."""
    zeta = train.damping_ratio
    return train.omega_n * (zeta + math.sqrt(zeta * zeta - 1.0) if zeta > 1.0 else 1.0)


def _stretch_count(omega: float, train: TrainConfig, samples: int) -> int:
    """Return the stretches per revolution: samples, more (a power of two) for a stiff train."""
    phase = _fastest_rate(train) * TWO_PI / omega  # of the fastest mode over one turn
    needed = 2 ** max(0, math.ceil(math.log2(max(phase / STEP_PHASE, 1.0))))
    if needed > MAX_RESPONSE_SAMPLES:
        ratio = train.natural_frequency * TWO_PI / omega
        raise InvalidParameter('dynamics.train_natural_frequency', train.natural_frequency,
                               f'is {ratio:.6g} times the cam frequency (damping ratio '
                               f'{train.damping_ratio:g}): the periodic response is computed '
                               f'up to {MAX_RESPONSE_SAMPLES * STEP_PHASE / TWO_PI:.6g} times; '
                               'a train this stiff is rigid, leave it out')
    return max(samples, needed)


def _knots(program: MotionProgram, count: int) -> tuple[FloatArray, FloatArray, FloatArray]:
    """Return the stretch starts in [0, 2 pi), their spans (rad) and the breaks.

    The starts are count equal steps and every break (a step closer to a break than
    MERGE_FRACTION gives way to it); between two grid points the span is one step exactly.
    """
    breaks = np.unique(np.mod(program.breaks, TWO_PI))  # a segment start at least
    step = TWO_PI / count
    grid = step * np.arange(count)
    position = np.searchsorted(breaks, grid)
    after = breaks[position % breaks.size] + TWO_PI * (position == breaks.size)
    before = breaks[position - 1] - TWO_PI * (position == 0)
    grid = grid[np.minimum(after - grid, grid - before) > MERGE_FRACTION * step]
    knots = np.union1d(grid, breaks)
    on_grid = np.isin(knots, grid)
    span = np.diff(np.append(knots, TWO_PI))
    span[on_grid & np.append(on_grid[1:], True)] = step  # one span: one kernel to compute
    return knots, span, breaks


def _forcing(program: MotionProgram, omega: float, train: TrainConfig, start: FloatArray,
             span: FloatArray, kernel: Optional[tuple[FloatArray, FloatArray]] = None
             ) -> tuple[FloatArray, FloatArray]:
    """Return int_0^tau Phi(tau - u) e2 c du over stretches from angles start, span rad long.

    kernel: Phi(tau - u) e2 at the nodes of each stretch, (n, RESPONSE_NODES) twice, when known.
    """
    fraction = 0.5 * (_NODES + 1.0)
    angles = start[:, np.newaxis] + span[:, np.newaxis] * fraction
    motion = program.evaluate(angles)
    damping = 2.0 * train.damping_ratio * train.omega_n * omega
    c = omega * omega * motion.d2s + damping * motion.ds
    tau = span[:, np.newaxis] / omega
    p12, p22 = _kernel(train, omega, span) if kernel is None else kernel
    weighted = c * (0.5 * _WEIGHTS) * tau
    return np.sum(p12 * weighted, axis=1), np.sum(p22 * weighted, axis=1)


def _kernel(train: TrainConfig, omega: float,
            span: FloatArray) -> tuple[FloatArray, FloatArray]:
    """Return Phi(tau - u) e2 at the quadrature nodes u of stretches span rad long."""
    _, p12, _, p22 = transition(train, np.multiply.outer(span / omega, 0.5 * (1.0 - _NODES)))
    return p12, p22


def _compose(maps: FloatArray) -> None:
    """Turn affine maps d -> M_k d + g_k in place into their running compositions.

    maps rows are M11, M12, M21, M22, g1, g2 of each map (6, n); afterwards column k maps
    d_0 to d_(k+1). A Hillis-Steele scan: log2(n) passes, each vectorised over the maps.
    """
    step = 1
    while step < maps.shape[1]:
        a, b, c, d, g, h = maps[:, step:]
        e11, e12, e21, e22, f, k = maps[:, :-step]
        maps[:, step:] = (a * e11 + b * e21, a * e12 + b * e22, c * e11 + d * e21,
                          c * e12 + d * e22, a * f + b * k + g, c * f + d * k + h)
        step *= 2


@dataclass(frozen=True, eq=False)
class PeriodicResponse:
    """The train's steady output over one revolution (SI, time derivatives at the cam speed).

    angle are the stretch starts from 0 (rad; at least RESPONSE_SAMPLES, every break among
    them), input the cam motion y there, output x, output_velocity and output_acceleration the
    train's; deviation the periodic state (x - y, x' - y') there, right after any velocity
    jump. `at(theta)` evaluates the output exactly at any angles.
    """

    program: MotionProgram
    omega: float
    train: TrainConfig
    angle: FloatArray
    input: FloatArray
    output: FloatArray
    output_velocity: FloatArray
    output_acceleration: FloatArray
    deviation: FloatArray  # (2, n)

    def deviation_at(self, theta: npt.ArrayLike) -> tuple[FloatArray, FloatArray]:
        """Return x - y and x' - y' at cam angles theta (right-hand values at a velocity jump)."""
        angles = np.asarray(theta, dtype=float)
        local = np.mod(angles.reshape(-1), TWO_PI)
        index = np.searchsorted(self.angle, local, side='right') - 1
        start = self.angle[index]
        span = local - start
        f1, f2 = _forcing(self.program, self.omega, self.train, start, span)
        p11, p12, p21, p22 = transition(self.train, span / self.omega)
        d0, d1 = self.deviation[:, index]
        return ((p11 * d0 + p12 * d1 - f1).reshape(angles.shape),
                (p21 * d0 + p22 * d1 - f2).reshape(angles.shape))

    def at(self, theta: npt.ArrayLike, derivative: int = 0) -> FloatArray:
        """Return the output's derivative (0: x, 1: dx/dt, 2: d2x/dt2) at cam angles theta."""
        return self.outputs(theta)[derivative]

    def outputs(self, theta: npt.ArrayLike) -> tuple[FloatArray, FloatArray, FloatArray]:
        """Return x, dx/dt and d2x/dt2 at cam angles theta (m or rad, per s, per s^2)."""
        d0, d1 = self.deviation_at(theta)
        motion = self.program.evaluate(theta)
        velocity = self.omega * motion.ds + d1
        wn = self.train.omega_n
        return (motion.s + d0, velocity,
                -wn * wn * d0 - (2.0 * self.train.damping_ratio * wn) * velocity)


def periodic_response(program: MotionProgram, omega: float, train: TrainConfig,
                      samples: int = RESPONSE_SAMPLES) -> PeriodicResponse:
    """Return the steady periodic output of the train driven by the program at speed omega.

    Raises InvalidParameter naming dynamics.train_damping_ratio at a resonance of an undamped
    train (no periodic output exists: see resonant_harmonic; vibration_report says so instead)
    and naming dynamics.train_natural_frequency for a train too stiff to integrate.
    """
    harmonic = resonant_harmonic(omega, train)
    if harmonic is not None:
        raise InvalidParameter('dynamics.train_damping_ratio', train.damping_ratio,
                               f'an undamped train at fn = {harmonic} x the cam frequency '
                               'resonates: no periodic output (it grows without bound)')
    angle, span, breaks = _knots(program, _stretch_count(omega, train, samples))
    count = angle.size
    sides = program.evaluate(np.concatenate((breaks + SIDE_GAP, breaks - SIDE_GAP))).ds
    at_knots = program.evaluate(angle)
    ds = at_knots.ds.copy()
    where = np.searchsorted(angle, breaks)
    ds[where] = sides[:breaks.size]  # right-hand values at every break
    jumps = np.zeros(count)
    jumps[where] = omega * (sides[:breaks.size] - sides[breaks.size:])
    spans, which = np.unique(span, return_inverse=True)  # a few: the step, those at breaks
    kernel = _kernel(train, omega, spans)
    maps = np.empty((6, count))
    maps[:4] = np.array(transition(train, spans / omega))[:, which]
    for first in range(0, count, RESPONSE_BLOCK):
        part = slice(first, first + RESPONSE_BLOCK)
        mine = which[part]
        maps[4:, part] = np.negative(_forcing(program, omega, train, angle[part], span[part],
                                              (kernel[0][mine], kernel[1][mine])))
    maps[5] -= np.roll(jumps, -1)  # the jump where each stretch ends
    _compose(maps)
    (p11, p12, p21, p22), (q1, q2) = maps[:4, -1], maps[4:, -1]
    start = np.linalg.solve(np.array([[1.0 - p11, -p12], [-p21, 1.0 - p22]]), [q1, q2])
    deviation = np.empty((2, count))
    deviation[:, 0] = start
    deviation[0, 1:] = maps[0, :-1] * start[0] + maps[1, :-1] * start[1] + maps[4, :-1]
    deviation[1, 1:] = maps[2, :-1] * start[0] + maps[3, :-1] * start[1] + maps[5, :-1]
    wn = train.omega_n
    velocity = omega * ds + deviation[1]
    return PeriodicResponse(
        program, omega, train, angle, at_knots.s, at_knots.s + deviation[0], velocity,
        -wn * wn * deviation[0] - (2.0 * train.damping_ratio * wn) * velocity, deviation)
