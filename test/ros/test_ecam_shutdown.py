"""Ctrl-C on an e-cam node that follows a running master: a clean exit logs no error."""
from __future__ import annotations

import math
import signal
import time

from conftest import CONFIG_DIR
from ecam_support import master_message, MasterLink

DEFAULT = CONFIG_DIR / 'default.yaml'
DT = 0.002


def test_sigint_while_following_the_master_logs_no_error(start_cam_node, executor):
    process, _ = start_cam_node(DEFAULT, '-p', 'master.source:=topic')
    link = MasterLink(executor)
    link.connect(process, stamp_ns=time.time_ns() - 10 ** 9)
    stop = time.monotonic() + 30.0
    sent = 0
    while process.process.poll() is None and time.monotonic() < stop:
        now = time.time_ns()
        link.publisher.publish(master_message(now, position=(2 * math.pi * now * 1e-9,),
                                              velocity=(2 * math.pi,)))
        sent += 1
        if sent == 500:  # a second of master: then Ctrl-C while the messages go on
            process.process.send_signal(signal.SIGINT)
        time.sleep(DT)
    assert process.process.wait(timeout=10.0) == 0
    log = process.log()
    assert '[ERROR]' not in log and 'Traceback' not in log, log
    assert 'Failed to publish' not in log, log
