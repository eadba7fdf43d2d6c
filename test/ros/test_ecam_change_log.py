"""The e-cam says a design change is pending before it says the change was applied."""
from __future__ import annotations

import threading

from conftest import CONFIG_DIR
from ecam_support import ecam_design, master_message
from sensor_msgs.msg import JointState

from cam_ros.node.joints import FOLLOWER_JOINT
from cam_ros.node.master_follower import MasterFollower

DEFAULT = CONFIG_DIR / 'default.yaml'
MASTER = {'master.source': 'topic', 'master.timeout': 30.0}
#: Another rise: the designs share the dwell at 0-90 deg, where the master stands.
RISE = {'motion.start_position': [0.0, 0.0, 3.0, 3.0], 'motion.end_position': [0.0, 3.0, 3.0, 0.0]}
#: How long the master thread may be held up while the node says 'pending'.
RACE_S = 0.5


def test_pending_is_said_before_applied_even_when_the_master_applies_it_at_once(executor):
    """The master sample that applies the change arrives while 'pending' is being logged."""
    node = executor.node('change_log')
    design = ecam_design(DEFAULT, **MASTER)
    follower = MasterFollower(node, [(FOLLOWER_JOINT, design)], design.config.parameters, False,
                              node.create_publisher(JointState, '~/joints', 10), lambda: None)
    try:
        said: list[str] = []
        logger, info = node.get_logger(), node.get_logger().info
        now = node.get_clock().now().nanoseconds

        def still(k: int) -> JointState:  # a master standing at 1 rad: any change is due
            return master_message(now + k * 10 ** 6, position=(1.0,), velocity=(0.0,))

        def take(k: int) -> None:  # the intake's call: the message, when it arrived, 0 skipped
            follower._on_master(still(k), node.get_clock().now().nanoseconds, 0)

        def log(message: str, **kwargs: object) -> bool:
            if message.startswith('design change pending'):
                racer = threading.Thread(target=take, args=(3,))
                racer.start()
                racer.join(RACE_S)
            said.append(message)
            return info(message, **kwargs)

        for k in range(2):
            take(k)
        logger.info = log
        changed = ecam_design(DEFAULT, **MASTER, **RISE)  # both dwell at 1 rad
        follower.change([(FOLLOWER_JOINT, changed)], changed.config.parameters)
        take(4)
    finally:
        follower.stop()
    changes = [message for message in said if message.startswith('design change')]
    assert [message.split()[2] for message in changes] == ['pending:', 'applied'], changes
