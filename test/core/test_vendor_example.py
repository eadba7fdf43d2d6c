"""A vendor's published motion-task cam rebuilt with the core: the CODESYS SoftMotion default cam.

Source: CODESYS Online Help, CODESYS SoftMotion, "Creating Cams Programmatically", section "Using
the CamBuilder function block (as of SM 4.17.0.0)",
https://content.helpme-codesys.com/en/CODESYS%20SoftMotion/_sm_basic_cam_programmatic_creation.html
(example project BasicMotion_CreateCamTableOnline.project). The cam "created by default when a
cam object is created" is "three fifth-degree polynomials" with the boundary values

    X    Y    V  A
    0    0    0  0
    120  120  1  0
    240  240  1  0
    360  360  0  0

built as Poly5(BoundImplicit(), Bound(120, 120, 1)), Poly5(BoundImplicit(), Bound(240, 240, 1)),
Poly5(BoundImplicit(), Bound(360, 360)): BoundImplicit takes the previous segment's right bound
(zero for the first). In VDI 2143 terms: R-G rise, G-G synchronous section (V = 1), G-R.

Every input below is from that table. The page prints no peaks or coefficients, so the expected
values are closed-form derivations from its inputs (derived here, not the source's figures):
with H = 120, X = 120 (master units) and V = 1 at the G end, the general quintic of
motion-tasks.md gives for 0-120: y = H (6 z^3 - 8 z^4 + 3 z^5), z = x / X (H = V X), so
y' = 18 z^2 - 32 z^3 + 15 z^4, peaking at z = 3/5 with 1.512 (a 51.2 % overshoot of V);
y'' = (36 z - 96 z^2 + 60 z^3) / X, extreme where 15 z^2 - 16 z + 3 = 0, z = (16 -+ sqrt 76) / 30.
120-240 is the line y = x (H = V X). 240-360 is the point mirror: y(360 - x) = 360 - y(x), since
its boundary data are those of 0-120 mirrored and the quintic is unique.

Units: one master cycle, X 0..360, is one cam revolution, theta = x pi / 180 rad. The slave is
scaled by the same factor (slave unit u -> u pi / 180, as for a slave in degrees), so the gear
ratio V keeps its value per rad; accelerations per rad^2 are u/deg^2 times 180 / pi, jerks u/deg^3
times (180 / pi)^2. The slave ends 360 u above its start: a program that advances by 2 pi.
"""

import math

import numpy as np
import pytest

from cam_ros.core.motion.program import MotionProgram
from cam_ros.core.motion.tasks import build_segments, TaskSpec

NAN = math.nan
K = math.pi / 180.0  # master deg -> rad of cam angle; slave u -> rad (same factor)
#: The CODESYS table (X, Y, V, A): master, slave, slave per master, slave per master^2.
TABLE = ((0.0, 0.0, 0.0, 0.0), (120.0, 120.0, 1.0, 0.0), (240.0, 240.0, 1.0, 0.0),
         (360.0, 360.0, 0.0, 0.0))
RTOL = 1e-12  # the table's values are exact; the closed forms too


def codesys_default_cam():
    """Build the three Poly5 segments: left bounds automatic (BoundImplicit), right ones given."""
    specs = []
    for (x0, y0, _, _), (x1, y1, v1, a1) in zip(TABLE[:-1], TABLE[1:]):
        finish = (v1, a1 / K, NAN)  # V stays a ratio; A u/deg^2 -> per rad^2
        specs.append(TaskSpec('poly5', x0 * K, x1 * K, y0 * K, y1 * K, finish=finish))
    return MotionProgram(build_segments(specs), advance=360.0 * K)


def rise(x):
    """Closed form of the 0-120 R-G quintic in the source's units: y, y', y'', y''' (u, deg)."""
    z, h, span = np.asarray(x, dtype=float) / 120.0, 120.0, 120.0
    return (h * (6 * z**3 - 8 * z**4 + 3 * z**5), 18 * z**2 - 32 * z**3 + 15 * z**4,
            (36 * z - 96 * z**2 + 60 * z**3) / span, (36 - 192 * z + 180 * z**2) / span**2)


def expected(x):
    """The whole cam in the source's units (see the module docstring), x in [0, 360)."""
    x = np.asarray(x, dtype=float)
    up, down = rise(x), rise(360.0 - x)
    line = (x, np.ones_like(x), np.zeros_like(x), np.zeros_like(x))
    mirror = (360.0 - down[0], down[1], -down[2], down[3])
    return tuple(np.select([x < 120.0, x < 240.0], [u, g], m)
                 for u, g, m in zip(up, line, mirror))


def in_source_units(values):
    """Return s, ds, d2s, d3s per rad back in u, u/deg, u/deg^2, u/deg^3."""
    return values.s / K, values.ds, values.d2s * K, values.d3s * K**2


@pytest.fixture(scope='module')
def program():
    return codesys_default_cam()


def test_tasks_are_rise_to_synchronous_and_back(program):
    assert [s.task for s in program.segment_summary()] == ['R-G', 'G-G', 'G-R']


def test_table_points_are_met(program):
    """The boundary values X, Y, V, A of the source's table, at every joint."""
    values = in_source_units(program.evaluate(np.array([row[0] for row in TABLE]) * K))
    for k in range(3):
        want = [row[k + 1] for row in TABLE]
        if k == 0:
            want[-1] = 360.0  # the wrap: one advance above the start
        assert values[k] == pytest.approx(want, rel=RTOL, abs=RTOL * 360.0)


def test_whole_cam_is_the_closed_form(program):
    x = np.linspace(0.0, 360.0, 721)[:-1]
    got, want = in_source_units(program.evaluate(x * K)), expected(x)
    for k, scale in enumerate((360.0, 1.512, 0.02, 0.0025)):
        assert np.max(np.abs(got[k] - want[k])) <= RTOL * scale * 100, f'order {k}'
    assert rise(60.0)[0] == 41.25  # y(X/2) = H (6/8 - 8/16 + 3/32)
    assert got[0][120] == pytest.approx(41.25, rel=RTOL)
    assert got[0][600] == pytest.approx(318.75, rel=RTOL)  # the mirror at x = 300


def test_peaks_and_overshoot(program):
    """Peak slave velocity 1.512 at x = 72 and 288 (51.2 % over V = 1); peak acceleration."""
    z1, z2 = (16.0 - math.sqrt(76.0)) / 30.0, (16.0 + math.sqrt(76.0)) / 30.0
    peak_acc = max(abs(float(rise(120.0 * z)[2])) for z in (z1, z2))
    rise_summary, sync, fall = program.segment_summary()
    for summary in (rise_summary, fall):
        assert summary.peak_ds == pytest.approx(1.512, rel=1e-9)
        assert summary.overshoot == pytest.approx(0.512, rel=1e-9)
        assert summary.peak_d2s * K == pytest.approx(peak_acc, rel=1e-9)
        assert summary.peak_d3s * K**2 == pytest.approx(36.0 / 120.0**2, rel=1e-9)
    assert sync.peak_ds == pytest.approx(1.0, rel=1e-9)
    assert sync.peak_d2s * K == pytest.approx(0.0, abs=1e-12)
    at = in_source_units(program.evaluate(np.array([72.0, 288.0]) * K))
    assert at[1] == pytest.approx([1.512, 1.512], rel=RTOL)
    assert at[0] == pytest.approx([120.0 * 0.49248, 360.0 - 120.0 * 0.49248], rel=RTOL)


def test_smooth_to_acceleration_and_advancing(program):
    jumps = program.continuity_report()  # only the jerk steps, where the line meets a quintic
    assert [(round(math.degrees(j.angle), 9), j.order) for j in jumps] == [(120.0, 3), (240.0, 3)]
    x = np.array([30.0, 180.0, 330.0]) * K
    one, two = program.evaluate(x), program.evaluate(x + 2.0 * math.pi)
    assert two.s == pytest.approx(one.s + 2.0 * math.pi, rel=RTOL)
    assert two.ds == pytest.approx(one.ds, rel=RTOL)
