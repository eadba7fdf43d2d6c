"""Set-up on a new machine: `make setup` says first what the system lacks, and needs no CMake.

The tests run `make setup` in a copy of the checkout's tracked files (what a clone holds) with a
PATH of one folder that links every program on the real PATH except the ones a test hides, and an
environment without the running venv's variables.
"""
from __future__ import annotations

import importlib.metadata
import os
import re
import shutil
import subprocess
import sys
from pathlib import Path

import pytest

from conftest import REPO

VERSION = f'{sys.version_info.major}.{sys.version_info.minor}'
MAKE_ERROR = re.compile(r'make(\[\d+\])?: \*\*\* ')  # make's own 'Error 1' line
C_COMPILERS = {'cc', 'gcc', 'clang'}
CXX_COMPILERS = {'c++', 'g++', 'clang++'}
# Set by the venv's ROS bootstrapper, build tools or a calling make; a new user's shell has none.
SESSION_VARIABLES = ('LD_LIBRARY_PATH', '_ROS_WHEELS_BOOTSTRAP_COMPLETE', 'VIRTUAL_ENV',
                     'PYTHONPATH', 'PYTHONHOME', 'AMENT_PREFIX_PATH', 'CMAKE_PREFIX_PATH', 'CC',
                     'CXX', 'MAKEFLAGS', 'MFLAGS', 'MAKELEVEL')


def clean_checkout(destination: Path) -> Path:
    """Copy the tracked files of the checkout, as they are now, into destination."""
    listed = subprocess.run(['git', 'ls-files', '-z'], cwd=REPO, capture_output=True, check=True)
    for name in listed.stdout.decode().split('\0'):
        source = REPO / name
        if name and os.path.lexists(source):
            (destination / name).parent.mkdir(parents=True, exist_ok=True)
            shutil.copy2(source, destination / name, follow_symlinks=False)
    return destination


def shim_path(folder: Path, hide: frozenset[str] = frozenset(), python: str = '') -> str:
    """Return a PATH of one folder linking the programs on PATH but hide (and python3 = python).

    The running venv's own folders are left out, as they are not on a new user's PATH.
    """
    folder.mkdir()
    if python:
        (folder / 'python3').write_text(python)
        (folder / 'python3').chmod(0o755)
    venv = Path(sys.prefix).resolve()
    for directory in os.environ['PATH'].split(os.pathsep):
        if not directory or Path(directory).resolve().is_relative_to(venv):
            continue
        for program in sorted(Path(directory).glob('*')):
            link = folder / program.name
            if (program.name not in hide and not os.path.lexists(link)
                    and program.is_file() and os.access(program, os.X_OK)):
                link.symlink_to(program)
    return str(folder)


def fake_python(folder: Path, prelude: str) -> str:
    """Return a `python3` script: this base interpreter, running prelude first (sitecustomize)."""
    folder.mkdir()
    (folder / 'sitecustomize.py').write_text(prelude)
    base = Path(sys.base_prefix) / 'bin' / f'python{VERSION}'
    return f'#!/bin/sh\nPYTHONPATH={folder} exec {base} "$@"\n'


def user_env(path: str, **extra: str) -> dict[str, str]:
    """Return this process's environment as a new user's shell would have it, with PATH = path."""
    env = {key: value for key, value in os.environ.items() if key not in SESSION_VARIABLES}
    return {**env, 'PATH': path, **extra}


def make_setup(tree: Path, env: dict[str, str], timeout: float) -> subprocess.CompletedProcess:
    """Run `make setup` in tree."""
    return subprocess.run(['make', 'setup'], cwd=tree, env=env, capture_output=True, text=True,
                          timeout=timeout)


def fake_version(major: int, minor: int) -> str:
    """Return a prelude that makes Python report version major.minor (its paths stay true)."""
    return ('import sys, sysconfig; sysconfig.get_config_vars(); '
            f'sys.version_info = ({major}, {minor}, 0, "final", 0)')


NO_HEADERS = ('import sysconfig; paths = sysconfig.get_paths; sysconfig.get_paths = '
              'lambda *a, **k: dict(paths(*a, **k), include="/nonexistent")')
#: What the system lacks (programs hidden, or a python3 that runs a prelude), and the message.
MISSING = [
    pytest.param(C_COMPILERS, '', 'no working C compiler', 'gcc', id='no C compiler'),
    pytest.param(CXX_COMPILERS, '', 'no working C++ compiler', 'g++', id='no C++ compiler'),
    pytest.param({'python3'}, '', 'python3 not found', 'python3', id='no python3'),
    pytest.param(set(), fake_version(3, 10), 'is CPython 3.10; the pinned wheels '
                 '(requirements.lock) exist for CPython 3.11, 3.12 and 3.13 only', 'python3.11',
                 id='python 3.10'),
    pytest.param(set(), fake_version(3, 14), 'is CPython 3.14;', 'python3.11', id='python 3.14'),
    pytest.param(set(), 'import sys; sys.modules["ensurepip"] = None',
                 'python3 -m venv cannot install pip', f'python{VERSION}-venv', id='no venv'),
    pytest.param(set(), NO_HEADERS, 'the Python headers (Python.h) for the interface build are '
                 'missing', f'python{VERSION}-dev', id='no Python headers'),
]


@pytest.mark.parametrize('hide, prelude, problem, package', MISSING)
def test_setup_stops_before_any_download_naming_what_is_missing(
        hide, prelude, problem, package, tmp_path):
    python = fake_python(tmp_path / 'site', prelude) if prelude else ''
    path = shim_path(tmp_path / 'bin', frozenset(hide), python)
    tree = clean_checkout(tmp_path / 'clone')
    # PIP_NO_INDEX: should the check let it through, pip fails at once instead of downloading.
    result = make_setup(tree, user_env(path, PIP_NO_INDEX='1'), timeout=120)
    assert result.returncode != 0
    assert result.stdout == ''
    message = [line for line in result.stderr.splitlines() if not MAKE_ERROR.match(line)]
    assert len(message) == 1, result.stderr
    assert message[0].startswith('make setup: ') and problem in message[0], message[0]
    assert f': on Debian/Ubuntu, sudo apt install {package}' in message[0], message[0]
    assert not (tree / '.venv').exists()


@pytest.mark.parametrize('minor', [11, 12, 13])
def test_preflight_accepts_the_python_versions_the_wheels_exist_for(minor, tmp_path):
    python = tmp_path / 'python3'
    python.write_text(fake_python(tmp_path / 'site', fake_version(3, minor)))
    python.chmod(0o755)
    check = subprocess.run(['sh', str(REPO / 'tools' / 'preflight.sh'), str(python)],
                           env=user_env(os.environ['PATH']), capture_output=True, text=True)
    assert (check.returncode, check.stdout, check.stderr) == (0, '', '')


def test_make_lock_keeps_the_cmake_wheel_pinned():
    cmake = f'cmake=={importlib.metadata.version("cmake")}'
    assert cmake in (REPO / 'requirements.lock').read_text().splitlines()
    lock_py = (REPO / 'Makefile').read_text().split('define LOCK_PY\n')[1].split('endef')[0]
    pins = subprocess.run([sys.executable, '-c', lock_py], capture_output=True, text=True,
                          check=True).stdout.splitlines()
    assert cmake in pins


def test_clean_clone_sets_up_without_a_system_cmake(tmp_path, pytestconfig):
    if not pytestconfig.getoption('--heavy'):
        pytest.skip('a full set-up from nothing (a minute or two with a warm pip cache): --heavy')
    path = shim_path(tmp_path / 'bin', frozenset({'cmake'}))
    assert shutil.which('cmake', path=path) is None
    tree = clean_checkout(tmp_path / 'clone')
    env = user_env(path)
    try:
        result = make_setup(tree, env, timeout=1800)
        assert result.returncode == 0, result.stdout[-3000:] + result.stderr[-3000:]
        cache = (tree / '.venv/build/cam_ros_interfaces/CMakeCache.txt').read_text()
        assert f'CMAKE_COMMAND:INTERNAL={tree}/.venv/' in cache
        probe = ('import cam_ros, cam_ros_interfaces.srv as srv; request = srv.EvaluateCam.Request'
                 '(angles=[1.5]); print(request.angles[0], srv.__file__, cam_ros.__file__)')
        # From a neutral folder: `python -c` imports from its working directory first.
        answer = subprocess.run([str(tree / '.venv/bin/python'), '-c', probe], env=env,
                                cwd=tmp_path, capture_output=True, text=True, timeout=120)
        value, interfaces, package = answer.stdout.split()
        assert float(value) == 1.5
        assert interfaces.startswith(f'{tree}/.venv/') and package.startswith(f'{tree}/'), answer
        again = make_setup(tree, env, timeout=120)
        assert (again.returncode, again.stdout, again.stderr) == (0, '', '')
    finally:
        shutil.rmtree(tree / '.venv', ignore_errors=True)
