"""
Record in a child process for the crash tests (run by test_robustness.py, not by pytest).

Usage: recorder_child.py PATH CHUNK_SIZE [FSIZE_HEADROOM]. Publishes JointState messages whose
position[0] is their index, one at a time, and prints a JSON line {"written": n} after each is
recorded, forever (until killed). With FSIZE_HEADROOM, the file-size limit (RLIMIT_FSIZE) of the
recorder's writer process is set to the file's size plus that many bytes once recording runs; the
child then goes on until the recorder fails, checks it is still alive and prints a final JSON
status line.
"""

import json
import resource
import sys
import threading
import time

from domain_coordinator import domain_id
import rclpy
from rclpy.context import Context
from rclpy.executors import SingleThreadedExecutor
from rclpy.qos import QoSProfile
from sensor_msgs.msg import JointState

from cam_ros.recording import Recorder, TopicSpec

QOS = QoSProfile(depth=100)
TOPIC = '/crash'
TIMEOUT = 5.0


def wait(predicate) -> bool:
    """Poll until the predicate holds or TIMEOUT passes."""
    deadline = time.monotonic() + TIMEOUT
    while not predicate() and time.monotonic() < deadline:
        time.sleep(0.001)
    return predicate()


def record(node, path: str, chunk_size: int, headroom: int) -> dict:
    """Publish and record until killed, or until the recorder fails under a file-size limit."""
    publisher = node.create_publisher(JointState, TOPIC, QOS)
    recorder = Recorder(node, path, [TopicSpec(TOPIC, JointState, QOS)], chunk_size=chunk_size,
                        flush_period=None)
    assert wait(lambda: publisher.get_subscription_count() == 1)
    limit = None
    if headroom:
        with open(path, 'rb') as file:
            limit = file.seek(0, 2) + headroom
        resource.prlimit(recorder.writer_pid, resource.RLIMIT_FSIZE,
                         (limit, resource.getrlimit(resource.RLIMIT_FSIZE)[1]))
    index = 0
    while not recorder.failed:
        publisher.publish(JointState(name=['cam'], position=[float(index)]))
        index += 1
        assert wait(lambda: recorder.message_count == index or recorder.failed)
        print(json.dumps({'written': recorder.message_count}), flush=True)
    publisher.publish(JointState(name=['cam'], position=[-1.0]))  # nobody records it now
    time.sleep(0.2)
    recorder.close()
    return {'error': str(recorder.error), 'written': recorder.message_count,
            'published': index + 1, 'subscriptions': len(list(node.subscriptions)),
            'limit': limit, 'alive': True}


def main() -> None:
    """Run the child on its own ROS domain."""
    path, chunk_size = sys.argv[1], int(sys.argv[2])
    headroom = int(sys.argv[3]) if len(sys.argv) > 3 else 0
    with domain_id() as domain:
        context = Context()
        rclpy.init(context=context, domain_id=domain)
        node = rclpy.create_node('recorder_child', context=context)
        executor = SingleThreadedExecutor(context=context)
        executor.add_node(node)
        thread = threading.Thread(target=executor.spin, daemon=True)
        thread.start()
        try:
            print(json.dumps(record(node, path, chunk_size, headroom)), flush=True)
        finally:
            executor.shutdown()
            thread.join()
            node.destroy_node()
            rclpy.shutdown(context=context)


if __name__ == '__main__':
    main()
