"""The recording package's public surface and its place in the layers."""

import subprocess

import cam_ros.recording

#: Modules above the recording layer, which it must never load.
UPPER_LAYERS = ('cam_ros.node', 'cam_ros.cli')


def test_public_names_resolve():
    assert sorted(cam_ros.recording.__all__) == sorted(set(cam_ros.recording.__all__))
    for name in cam_ros.recording.__all__:
        assert getattr(cam_ros.recording, name).__doc__


def test_importing_recording_loads_neither_node_nor_cli(python, child_env):
    check = ('import sys, cam_ros.recording; '
             f'print([m for m in {UPPER_LAYERS!r} if m in sys.modules])')
    result = subprocess.run([python, '-c', check], env=child_env, capture_output=True,
                            text=True, timeout=30, check=True)
    assert result.stdout.strip() == '[]'
