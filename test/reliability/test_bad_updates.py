"""Rejected parameter updates on a running node: a clear reason, and nothing else changes.

Every case is sent to one live cam_node, as a single update (set_parameters, one result per
parameter) where it holds one parameter, and always as an atomic one (set_parameters_atomically).
After each rejection the node must answer evaluate exactly like the core's evaluation of its
unchanged design, keep its parameter values, publish no parameter event and no new profile.
"""
from __future__ import annotations

import math
import threading
import time
from dataclasses import dataclass

from rcl_interfaces.msg import ParameterEvent
from rclpy.parameter import Parameter
from rclpy.parameter_client import AsyncParameterClient
from rclpy.qos import DurabilityPolicy, QoSProfile, ReliabilityPolicy
from std_msgs.msg import Float64MultiArray

from .support import (CALL_TIMEOUT_S, DEFAULT, assert_serves, design_with, evaluate,
                      SAMPLE_ANGLES, wait_until, WITNESS_QOS)

LATCHED = QoSProfile(depth=1, durability=DurabilityPolicy.TRANSIENT_LOCAL,
                     reliability=ReliabilityPolicy.RELIABLE)
#: Time allowed for a (wrongly) published profile or parameter event to arrive.
QUIET_S = 0.5
#: Longest reason: parameter, a value quoted in at most 100 characters (and its size), rule.
MESSAGE_LIMIT = 400


@dataclass(frozen=True)
class Update:
    """A rejected update: the parameters, and fragments its reason must contain."""

    id: str
    parameters: tuple[Parameter, ...]
    reason: tuple[str, ...]


def update(id_: str, *reason: str, **values: object) -> Update:
    """Build an update of dotted parameters given as keywords with '__' for '.'."""
    return Update(id_, tuple(Parameter(name.replace('__', '.'), value=value)
                             for name, value in values.items()), reason)


UPDATES = [
    # Types and names: checked by the core as a file is, with the same messages.
    update('int_for_double', 'follower.base_radius = 4: must be a double (write 1.0, not 1)',
           follower__base_radius=4),
    update('string_for_double', "follower.base_radius = 'big': must be a double",
           follower__base_radius='big'),
    update('doubles_for_strings', 'motion.laws = [1.0, 2.0, 3.0, 4.0]: must be a list of strings',
           motion__laws=[1.0, 2.0, 3.0, 4.0]),
    update('ints_for_doubles', 'motion.start_deg = [0, 90, 180, 240]: must be a list of doubles',
           motion__start_deg=[0, 90, 180, 240]),
    update('undeclared', 'follower.rollr_radius = 1.0: is not a cam parameter (did you mean '
           'follower.roller_radius?)', follower__rollr_radius=1.0),
    Update('undeclare', (Parameter('follower.base_radius'),),
           ('follower.base_radius = None: cannot be undeclared',)),
    # Sizes: refused before anything is built, the value quoted in at most 100 characters.
    update('huge_array', 'motion.start_deg = [0.0, 0.0, ', '... (1000000 items): must have at '
           'most 1000 entries', motion__start_deg=[0.0] * 1_000_000),
    update('huge_string', "recording.directory = 'ddd", "ddd' (100000 characters): must have at "
           'most 4096 characters', recording__directory='d' * 100_000),
    # Ranges: refused by rclpy from the declared descriptors.
    update('out_of_range', 'limits.pressure_angle_deg', 'out of range', '95.0',
           limits__pressure_angle_deg=95.0),
    update('zero_pressure_limit', 'limits.pressure_angle_deg', 'out of range', '0.0',
           limits__pressure_angle_deg=0.0),
    update('nan_out_of_range', 'output.state_rate_hz', 'out of range', 'nan',
           output__state_rate_hz=math.nan),
    update('integer_out_of_range', 'output.sample_count', 'out of range',
           output__sample_count=2),
    # Refused by the core (the whole design is rebuilt and checked).
    update('negative_radius', 'follower.roller_radius = -1.0: must be >= 0',
           follower__roller_radius=-1.0),
    update('zero_base_radius', 'follower.base_radius = 0.0: must be > 0 (cm)',
           follower__base_radius=0.0),
    update('nan_radius', 'follower.base_radius = nan: must be finite',
           follower__base_radius=math.nan),
    update('inf_offset', 'follower.offset = inf: must be finite', follower__offset=math.inf),
    update('offset_at_prime_circle', 'follower.offset = 5.0: needs |offset| < base_radius + '
           'roller_radius = 5 cm', follower__offset=5.0),
    update('unknown_unit', "length_unit = 'furlong': must be one of m, cm, mm, in",
           length_unit='furlong'),
    update('unknown_law', "motion.laws[1] (cycloid): law = 'cycloid': must be one of",
           motion__laws=['dwell', 'cycloid', 'dwell', 'simple_harmonic']),
    update('gap', 'motion.start_deg[1] = 95.0: must equal motion.end_deg[0] = 90.0 (leaves a gap '
           'of 5 deg)',
           motion__start_deg=[0.0, 95.0, 180.0, 240.0]),
    update('total', 'motion.end_deg[3] = 350.0', 'must cover 360 deg',
           motion__end_deg=[90.0, 180.0, 240.0, 350.0]),
    update('position_jump', 'motion.start_position[3] = 2.5', 'cannot jump',
           motion__start_position=[0.0, 0.0, 2.0, 2.5]),
    update('arrays_of_two_lengths', 'motion.start_deg = [0.0, 90.0, 180.0, 240.0]',
           'must have 3 entries', motion__laws=['dwell', 'cycloidal', 'simple_harmonic']),
    update('huge_radius', 'follower.base_radius = 1e+300: must not exceed 100000 cm',
           follower__base_radius=1e300),
    update('via_segment_out_of_range', 'motion.via_segment[0] = 9', 'segment index',
           motion__via_segment=[9], motion__via_deg=[100.0], motion__via_position=[1.0]),
    update('roller_under_the_cam_centre', 'motion.laws[0] (dwell): s at 0.00 deg = -6.0',
           'roller centre must stay above', motion__start_position=[-6.0, -6.0, -4.0, -4.0],
           motion__end_position=[-6.0, -4.0, -4.0, -6.0]),
    update('scca_without_fractions', 'motion.scca_fractions = []: needs 3 entries b, c, d',
           motion__laws=['dwell', 'scca', 'dwell', 'simple_harmonic']),
    update('follower_without_arm', 'follower.pivot_distance = 0.0: must be > 0 (cm)',
           follower__type='oscillating_roller'),
    # Atomic only: several parameters that are only wrong, or only right, together.
    update('arm_cannot_reach', 'follower.base_radius = 4.0', 'so that the roller reaches the cam',
           follower__type='oscillating_roller', follower__pivot_distance=10.0,
           follower__arm_length=2.0),
    update('good_with_bad', 'follower.roller_radius = -1.0', follower__base_radius=5.0,
           follower__roller_radius=-1.0),
    update('shifted_segments_with_a_gap', 'motion.start_deg[2] = 185.0', 'gap',
           motion__laws=['cycloidal', 'dwell', 'simple_harmonic', 'dwell'],
           motion__start_deg=[0.0, 90.0, 185.0, 240.0],
           motion__end_deg=[90.0, 180.0, 240.0, 360.0],
           motion__start_position=[0.0, 2.0, 2.0, 0.0],
           motion__end_position=[2.0, 2.0, 0.0, 0.0]),
]
#: Changing this after all the rejections must be accepted (the node is not wedged).
ACCEPTED = {'follower.base_radius': 5.0, 'follower.offset': 0.0}


class Counter:
    """Count the messages of one topic that pass a filter."""

    def __init__(self, node, msg_type, topic, qos, keep=lambda message: True):
        self.count = 0
        self._lock = threading.Lock()
        self._keep = keep
        node.create_subscription(msg_type, topic, self._receive, qos)

    def _receive(self, message) -> None:
        if self._keep(message):
            with self._lock:
                self.count += 1


def wait_future(future):
    """Wait for a parameter client's future (the test executor spins it)."""
    wait_until(future.done, CALL_TIMEOUT_S, 'a parameter service answer')
    return future.result()


def test_rejected_updates_change_nothing(start_cam_node, executor, report):
    process, client = start_cam_node(DEFAULT)
    node = executor.node('update_client')
    parameters = AsyncParameterClient(node, 'cam')
    assert parameters.wait_for_services(timeout_sec=CALL_TIMEOUT_S)
    profiles = Counter(node, Float64MultiArray, '/cam/pressure_angle', LATCHED)
    events = Counter(node, ParameterEvent, '/parameter_events', WITNESS_QOS,
                     keep=lambda event: event.node == '/cam')
    wait_until(lambda: profiles.count == 1, CALL_TIMEOUT_S, 'the latched pressure angle')
    design = design_with()
    names = sorted({p.name for case in UPDATES for p in case.parameters}
                   - {'follower.rollr_radius'})
    before = wait_future(parameters.get_parameters(names)).values

    rejected = 0
    for case in UPDATES:
        attempts = [('atomic', lambda: [wait_future(
            parameters.set_parameters_atomically(list(case.parameters))).result])]
        if len(case.parameters) == 1:
            attempts.append(('single', lambda: wait_future(
                parameters.set_parameters(list(case.parameters))).results))
        for kind, attempt in attempts:
            results = attempt()
            assert len(results) == 1, (case.id, kind, results)
            assert not results[0].successful, (case.id, kind)
            assert len(results[0].reason) <= MESSAGE_LIMIT, (case.id, results[0].reason)
            for fragment in case.reason:
                assert fragment in results[0].reason, (case.id, kind, results[0].reason)
            assert_serves(evaluate(client, SAMPLE_ANGLES), design)
            rejected += 1
    time.sleep(QUIET_S)
    assert wait_future(parameters.get_parameters(names)).values == before
    assert (profiles.count, events.count) == (1, 0)
    assert process.process.poll() is None

    result = wait_future(parameters.set_parameters_atomically(
        [Parameter(name, value=value) for name, value in ACCEPTED.items()])).result
    assert result.successful, result.reason
    assert_serves(evaluate(client, SAMPLE_ANGLES), design_with(**ACCEPTED))
    wait_until(lambda: (profiles.count, events.count) == (2, 1), CALL_TIMEOUT_S,
               'one new profile and one parameter event')
    report('rejected parameter updates (single + atomic)', rejected)
