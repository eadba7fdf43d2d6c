"""The dynamics figures of a design: contact force, jump, spring sizing, torque, contact stress.

Extremes and sign changes are found on the design checks' dense sampling (CHECK_SAMPLES per
revolution) and refined on the exact functions by :mod:`.extremes`, so a peak between samples
or at a segment joint is reported at its true value and angle. SI throughout; angles in rad.
"""
from __future__ import annotations

import math
from dataclasses import dataclass
from typing import Any, Callable, Optional, cast

import numpy as np
import numpy.typing as npt

from ..extremes import CHECK_SAMPLES, refine_extremum, refine_roots, TWO_PI
from ..motion.program import MotionProgram
from .follower import DynamicsValues, FollowerDynamics

Array = npt.NDArray[np.float64]

#: A preload needed below this fraction of the design's force scale (the largest |k s| plus the
#: safety factor times the largest |m a + c v + F_ext|) is rounding noise and reads 0.
PRELOAD_TOLERANCE = 1e-9


@dataclass(frozen=True)
class DynamicsReport:
    """Dynamics of a design at its cam speed (N, N m, W, Pa, m, rad, rad/s).

    Forces and torques are in N and N m (moments in N m for oscillating arms: spring preload).
    spring_preload_needed is 0 when none is needed (or less than PRELOAD_TOLERANCE of the
    forces: rounding). jump_angles are the (start, end) spans where the contact force is
    negative (the follower would leave the cam), a span may wrap through 0; jump_speed is the
    lowest cam speed at which the contact force reaches zero somewhere (None if never, 0 if
    already at rest).
    camshaft_torque_max is the largest |T|, power_max that times the cam speed; cycle_work is
    the net work per revolution (damping and friction; 0 for a conservative train).
    contact_stress_ok is None when no allowable is configured. contact_stress_max is NaN (at the
    first such angle, half-width NaN) where the surface is undercut: no Hertz contact exists.
    """

    contact_force_min: float
    contact_force_min_at: float
    contact_force_max: float
    contact_force_max_at: float
    jump_angles: tuple[tuple[float, float], ...]
    jump_speed: Optional[float]
    spring_preload: float
    spring_preload_needed: float
    camshaft_torque_max: float
    camshaft_torque_max_at: float
    camshaft_torque_rms: float
    power_max: float
    cycle_work: float
    contact_stress_max: float
    contact_stress_max_at: float
    contact_half_width: float
    contact_stress_limit: Optional[float]

    @property
    def jump(self) -> bool:
        """Return True when the follower leaves the cam at the configured speed."""
        return bool(self.jump_angles)

    @property
    def contact_stress_ok(self) -> Optional[bool]:
        """Return whether the peak contact pressure is within the allowable (None: no limit).

        An undefined stress (NaN: the surface is undercut, no Hertz contact) is not within it.
        """
        if self.contact_stress_limit is None:
            return None
        return bool(self.contact_stress_max <= self.contact_stress_limit)

    @property
    def ok(self) -> bool:
        """Return True when the follower stays on the cam and the stress is allowed."""
        return not self.jump and self.contact_stress_ok is not False


def _negative_spans(func: Callable[[Array], Array], theta: Array, values: Array,
                    breaks: Array) -> tuple[tuple[float, float], ...]:
    """Return the (start, end) angle spans where func < 0, ends refined, wrapping through 0."""
    roots = refine_roots(func, theta, values, breaks=breaks)
    if roots.size == 0:
        return ((0.0, TWO_PI),) if values.max() < 0.0 else ()
    ends = np.append(roots[1:], roots[0] + TWO_PI)
    negative = func(np.mod(0.5 * (roots + ends), TWO_PI)) < 0.0
    return tuple((float(start), float(end % TWO_PI))
                 for start, end in zip(roots[negative], ends[negative]))


def dynamics_report(model: FollowerDynamics, program: MotionProgram,
                    evaluate: Callable[[Array], Any]) -> DynamicsReport:
    """Compute the dynamics figures of a design at its cam speed.

    model is its follower train, program its motion and evaluate(angles) its full evaluation
    (a CamState: position, ds, d2s, radius_of_curvature and dynamics at those angles).
    """
    config = model.config
    theta = np.linspace(0.0, TWO_PI, CHECK_SAMPLES, endpoint=False)
    breaks = program.breaks

    def values(angles: Array) -> DynamicsValues:
        return cast(DynamicsValues, evaluate(angles).dynamics)

    def per_motion(method: Callable[..., Array]) -> Callable[[Array], Array]:
        def func(angles: Array) -> Array:
            motion = program.evaluate(angles)
            return method(motion.s, motion.ds, motion.d2s)
        return func

    def extreme(name: str, kind: str, grid: Array) -> tuple[float, float]:
        return refine_extremum(lambda angles: getattr(values(angles), name), theta, grid, kind,
                               breaks=breaks)

    def stress(angles: Array) -> Array:
        return values(angles).contact_stress

    dense = evaluate(theta)  # the one dense pass; refinement evaluates only brackets
    grid = cast(DynamicsValues, dense.dynamics)
    motion = (dense.position, dense.ds, dense.d2s)  # position is s (at_speed keeps it)
    force_min, force_min_at = extreme('contact_force', 'min', grid.contact_force)
    force_max, force_max_at = extreme('contact_force', 'max', grid.contact_force)
    torque_high = extreme('camshaft_torque', 'max', grid.camshaft_torque)
    torque_low = extreme('camshaft_torque', 'min', grid.camshaft_torque)
    torque, torque_at = max(torque_high, (-torque_low[0], torque_low[1]))
    undefined = np.isnan(grid.contact_stress)  # undercut: no Hertz contact there
    if undefined.any():
        stress_max, stress_at = math.nan, float(theta[np.argmax(undefined)])
    else:
        stress_max, stress_at = refine_extremum(stress, theta, grid.contact_stress, 'max',
                                                breaks=breaks)

    def inverse(speeds: Array) -> Array:  # 1 / jump speed: finite where the speed is inf
        with np.errstate(divide='ignore'):
            return 1.0 / speeds

    speeds = per_motion(model.jump_speeds)
    with np.errstate(invalid='ignore'):  # inf - inf where contact is lost at rest
        rate, _ = refine_extremum(lambda angles: inverse(speeds(angles)), theta,
                                  inverse(model.jump_speeds(*motion)), 'max', breaks=breaks)
    needed, _ = refine_extremum(per_motion(model.preload_shortfall), theta,
                                model.preload_shortfall(*motion), 'max', breaks=breaks)
    force, spring = model.follower_force(*motion)
    scale = (np.max(np.abs(spring - config.spring_preload))
             + config.jump_safety_factor * np.max(np.abs(force - spring)))
    at_peak = evaluate(np.array([stress_at]))
    width = model.half_width(cast(DynamicsValues, at_peak.dynamics).contact_force,
                             at_peak.radius_of_curvature)
    limit = config.contact_stress_limit
    return DynamicsReport(
        contact_force_min=force_min, contact_force_min_at=force_min_at,
        contact_force_max=force_max, contact_force_max_at=force_max_at,
        jump_angles=_negative_spans(lambda angles: values(angles).contact_force, theta,
                                    grid.contact_force, breaks),
        jump_speed=1.0 / rate if rate > 0.0 else None,
        spring_preload=config.spring_preload,
        spring_preload_needed=needed if needed > PRELOAD_TOLERANCE * scale else 0.0,
        camshaft_torque_max=torque, camshaft_torque_max_at=torque_at,
        camshaft_torque_rms=float(np.sqrt(np.mean(grid.camshaft_torque ** 2))),
        power_max=torque * model.omega,
        cycle_work=float(np.mean(grid.camshaft_torque)) * TWO_PI,
        contact_stress_max=stress_max, contact_stress_max_at=stress_at,
        contact_half_width=float(width[0]),
        contact_stress_limit=limit if limit > 0.0 else None,
    )
