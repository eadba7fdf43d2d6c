"""
Serve a trivial std_srvs/SetBool service: the reference for the cam node's service and start-up.

Run as ``python -m benchmarks.setbool_server --ros-args -r __node:=NAME``; serves
``/NAME/set_bool`` with a SingleThreadedExecutor, answering success = request.data, until SIGINT
or SIGTERM.
Served as cam_node is (serve_over_udp: UDP only), so the ratio measures the node, not the
transport.
"""
from __future__ import annotations

import sys
from typing import Sequence

import rclpy
from rclpy.node import Node
from std_srvs.srv import SetBool

from benchmarks.spin import spin_until_shutdown
from cam_ros.node.middleware import serve_over_udp


def answer(request: SetBool.Request, response: SetBool.Response) -> SetBool.Response:
    """Echo the request's flag as success, with no other work."""
    response.success = request.data
    return response


def main(args: Sequence[str] | None = None) -> int:
    """Serve ~/set_bool until Ctrl-C or SIGTERM."""
    serve_over_udp()
    rclpy.init(args=list(sys.argv if args is None else args))
    node = Node('setbool_server')
    node.create_service(SetBool, '~/set_bool', answer)
    return spin_until_shutdown(node)


if __name__ == '__main__':
    sys.exit(main())
