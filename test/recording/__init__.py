"""Tests of cam_ros.recording (a package, so its conftest never shadows test/conftest.py)."""
