"""The design report: the numbers `cam_ros report` prints, computed from a CamDesign.

Everything is SI (m, rad, s); positions and their derivatives are in rad (arm angle) for
oscillating followers. Extremes are the design check's: located on CHECK_SAMPLES samples per
revolution and refined between them on the exact motion, so the report and the verdict agree;
the sizing refines its extremes the same way.
"""
from __future__ import annotations

import math
from dataclasses import dataclass
from typing import Optional

import numpy as np

from .design import CamDesign
from .extremes import CHECK_SAMPLES
from .dynamics.report import DynamicsReport
from .ecam.axis_limits import axis_limits, AxisLimits
from .geometry.followers import TranslatingRoller
from .geometry.joint_sizing import SmallestCam, smallest_cam
from .motion.program import Discontinuity
from .motion.segment import SegmentSummary
from .geometry.sizing import BaseRadiusEstimate, estimate_base_radius, size_base_radius


@dataclass(frozen=True)
class QuickEstimate:
    """Seed 002's base-radius estimate from the steepest rise, without offset (m).

    base_radius is the estimated prime radius minus the roller radius, None when that is not
    positive: the pressure-angle limit then needs no base radius at mid-rise (the estimate does
    not apply; the exact sizing says what governs).
    """

    segment: int
    estimate: BaseRadiusEstimate
    base_radius: Optional[float]


@dataclass(frozen=True)
class DesignReport:
    """What a designer needs to judge a cam; angles in rad, lengths in m.

    pressure_angle_max/min are the signed extremes; radius_of_curvature_min is the smallest radius
    of the convex parts of the surface (inf if none is convex); min_base_radius is the smallest
    base radius meeting the configured limits with every other parameter kept (None if none
    does), governing says which limit sets it; max_base_radius is the upper end of that feasible
    interval where the base radius is bounded (oscillating followers; None otherwise); face_range
    is the signed interval (m) of contact offsets a flat face must cover (None for rollers).
    pressure_angle_rise/return are each side's largest |pressure angle| and where (check.py).
    smallest_cam is the smallest translating-roller cam meeting both pressure-angle limits with
    base radius and offset chosen together (joint_sizing.py; None for other followers or when
    the limits bound nothing); max_roller_radius is the largest roller radius that avoids
    undercut on this pitch curve (see max_roller_radius; m, inf if none; None for flat faces).
    """

    design: CamDesign
    pressure_angle_max: float
    pressure_angle_max_at: float
    pressure_angle_min: float
    pressure_angle_min_at: float
    radius_of_curvature_min: float
    radius_of_curvature_min_at: float
    undercut: bool
    cusp_angles: tuple[float, ...]
    min_base_radius: Optional[float]
    min_base_radius_governing: str
    max_base_radius: Optional[float]
    max_base_radius_governing: str
    face_range: Optional[tuple[float, float]]
    segments: tuple[SegmentSummary, ...]
    continuity: tuple[Discontinuity, ...]
    quick_estimate: Optional[QuickEstimate]
    warnings: tuple[str, ...]
    dynamics: Optional[DynamicsReport] = None  # None: the design has no dynamics
    pressure_angle_rise: tuple[float, float] = (math.nan, math.nan)
    pressure_angle_return: tuple[float, float] = (math.nan, math.nan)
    smallest_cam: Optional[SmallestCam] = None
    max_roller_radius: Optional[float] = None
    slave_limits: Optional[AxisLimits] = None  # None: no slave.* limit or direction set

    @property
    def ok(self) -> bool:
        """Return True when the design meets its limits, is not undercut and does not jump."""
        return self.design.ok


def quick_estimate(design: CamDesign) -> Optional[QuickEstimate]:
    """Return seed 002's estimate for a translating roller from its steepest rise, else None."""
    follower = design.follower
    segments = design.program.segments  # with a ramp, h cv / beta is not the peak slope
    rises = [s for s in design.program.segment_summary()
             if s.s_end > s.s_start and s.cv > 0 and not segments[s.index].ramp]
    if not isinstance(follower, TranslatingRoller) or not rises:
        return None
    steepest = max(rises, key=lambda s: s.peak_ds)
    estimate = estimate_base_radius(steepest.s_end - steepest.s_start,
                                    steepest.end - steepest.start, steepest.cv,
                                    design.config.pressure_angle_limit)
    base_radius = estimate.prime_radius - follower.roller_radius
    return QuickEstimate(steepest.index, estimate, base_radius if base_radius > 0.0 else None)


def design_report(design: CamDesign) -> DesignReport:
    """Compute the report of a design (its refined check plus the base-radius sizing).

    A motion-only design reports its motion only: the cam's figures are nan, None or empty.
    """
    if design.follower is None:
        return DesignReport(design, *(math.nan,) * 6, undercut=False, cusp_angles=(),
                            min_base_radius=None, min_base_radius_governing='',
                            max_base_radius=None, max_base_radius_governing='', face_range=None,
                            segments=design.program.segment_summary(),
                            continuity=design.program.continuity_report(), quick_estimate=None,
                            warnings=tuple(design.warnings()),
                            slave_limits=axis_limits(design.config, design.electronic_cam))
    theta = np.linspace(0.0, 2.0 * math.pi, CHECK_SAMPLES, endpoint=False)
    motion = design.surface.evaluate(theta)  # the cam's own motion (polydyne: compensated)
    check = design.check
    sizing = size_base_radius(design.cam_follower, theta, motion.s, motion.ds, motion.d2s,
                              clockwise=design.clockwise,
                              max_pressure_angle=design.config.pressure_angle_limit,
                              max_pressure_angle_return=design.config.pressure_angle_return_limit,
                              min_radius=design.config.min_radius_of_curvature,
                              program=design.surface)
    face = None if check.face_min is None or check.face_max is None \
        else (check.face_min, check.face_max)
    return DesignReport(
        design=design,
        pressure_angle_max=check.pressure_angle_high[0],
        pressure_angle_max_at=check.pressure_angle_high[1],
        pressure_angle_min=check.pressure_angle_low[0],
        pressure_angle_min_at=check.pressure_angle_low[1],
        radius_of_curvature_min=check.min_radius,
        radius_of_curvature_min_at=check.min_radius_at,
        undercut=check.undercut,
        cusp_angles=tuple(float(angle) for angle in check.cusp_angles),
        min_base_radius=sizing.base_radius,
        min_base_radius_governing=sizing.governing,
        max_base_radius=sizing.max_base_radius,
        max_base_radius_governing=sizing.max_governing,
        face_range=face,
        segments=design.program.segment_summary(),
        continuity=design.program.continuity_report(),
        quick_estimate=quick_estimate(design),
        warnings=tuple(design.warnings()),
        dynamics=design.dynamics_check,
        pressure_angle_rise=check.pressure_angle_rise,
        pressure_angle_return=check.pressure_angle_return,
        smallest_cam=_smallest_cam(design),
        max_roller_radius=max_roller_radius(design),
        slave_limits=axis_limits(design.config, design.electronic_cam),
    )


def max_roller_radius(design: CamDesign) -> Optional[float]:
    """Return the largest roller radius without undercut on this pitch curve (m; None: flat).

    The pitch curve's smallest convex radius; a groove's roller also meets the outer flank,
    so its smallest concave radius bounds it too, less half the groove's clearance.
    """
    check = design.check
    if check.pitch_convex_radius_min is None or check.pitch_concave_radius_min is None:
        return None
    if design.config.follower.closure != 'groove':
        return check.pitch_convex_radius_min
    return (min(check.pitch_convex_radius_min, check.pitch_concave_radius_min)
            - 0.5 * design.config.follower.groove_clearance)


def _smallest_cam(design: CamDesign) -> Optional[SmallestCam]:
    """Return the jointly sized cam of a translating roller design, else None."""
    follower = design.follower
    if not isinstance(follower, TranslatingRoller):
        return None
    return smallest_cam(follower.roller_radius, design.surface,
                        max_pressure_angle=design.config.pressure_angle_limit,
                        max_pressure_angle_return=design.config.pressure_angle_return_limit,
                        clockwise=design.clockwise)
