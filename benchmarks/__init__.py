"""
Benchmarks of cam_ros, run by ``make bench`` (``python -m benchmarks``).

Every figure is a ratio to a reference measured in the same run (absolute times on a shared
machine are noisy): the core against one ``np.sin`` over the same array and against a per-sample
Python loop, the service against a trivial SetBool service, the recorder against a bare
subscription, start-up and memory against a bare rclpy node. Results go to stdout,
``benchmarks/results.json`` and ``benchmarks/results.md``.
"""
