"""The package layout's rules: import-linter contracts, no import cycles, no private names."""
from __future__ import annotations

import ast
import subprocess
import sys
from pathlib import Path

import grimp

from conftest import REPO

PACKAGE = REPO / 'cam_ros'
#: The one module allowed to use rclpy internals (it names the upstream gap it bridges).
RCLPY_GAPS = PACKAGE / 'rclpy_gaps.py'
#: rclpy's implementation modules: not public API even where no name starts with '_'.
RCLPY_INTERNALS = ('rclpy.impl.', 'rclpy._')


def test_import_linter_contracts_are_kept():
    lint = Path(sys.executable).parent / 'lint-imports'
    result = subprocess.run([str(lint), '--no-cache', '--config', str(REPO / '.importlinter')],
                            cwd=REPO, capture_output=True, text=True, timeout=300)
    assert result.returncode == 0, result.stdout + result.stderr
    assert '0 broken' in result.stdout


def test_no_module_of_cam_ros_imports_itself_back():
    graph = grimp.build_graph('cam_ros')
    cycles = sorted((importer, imported)
                    for importer in graph.modules
                    for imported in graph.find_modules_directly_imported_by(importer)
                    if imported.startswith('cam_ros.') and not importer.startswith(imported + '.')
                    and not imported.startswith(importer + '.')
                    and graph.chain_exists(importer=imported, imported=importer))
    assert cycles == []


def _folder(module: str) -> str:
    """Return the package that owns the names of a dotted module or package path."""
    path = REPO.joinpath(*module.split('.'))
    return module if (path / '__init__.py').is_file() else module.rpartition('.')[0]


def _private_imports(text: str, module: str) -> list[str]:
    """Return 'module.name' for every private name text imports from another module.

    A private name (`_name`) stays in its module: what modules share is public. A private
    module (`motion/_law_base.py`) is its package's: its own folder may import it (its public
    names), nothing outside may.
    """
    package = _folder(module)
    found = []
    for node in ast.walk(ast.parse(text)):
        if isinstance(node, ast.ImportFrom):
            source = node.module or ''
            if node.level:
                base = package.split('.')[:len(package.split('.')) - node.level + 1]
                source = '.'.join(base + ([source] if source else []))
            names = [f'{source}.{alias.name}' for alias in node.names]
        elif isinstance(node, ast.Import):
            names = [alias.name for alias in node.names]
        else:
            continue
        for name in names:
            pieces = name.split('.')
            private = [i for i, piece in enumerate(pieces)
                       if piece.startswith('_') and not piece.startswith('__')]
            imported_name = isinstance(node, ast.ImportFrom) and private[-1:] == [
                len(pieces) - 1] and '.'.join(pieces[:-1]) != module
            if name.startswith(RCLPY_INTERNALS) or imported_name or (
                    private and _folder('.'.join(pieces[:private[0]])) != package):
                found.append(name)
    return found


def _module(path: Path) -> str:
    parts = path.relative_to(REPO).with_suffix('').parts
    return '.'.join(parts[:-1] if parts[-1] == '__init__' else parts)


def test_no_file_imports_a_private_name_of_another_module():
    offenders = {_module(path): names for path in sorted(PACKAGE.rglob('*.py'))
                 if path != RCLPY_GAPS and (names := _private_imports(path.read_text(),
                                                                      _module(path)))}
    assert offenders == {}


def test_the_private_name_check_sees_rclpy_internals_and_foreign_private_names():
    text = ('from rclpy._rclpy_pybind11 import RCLError\n'
            'from rclpy.impl.implementation_singleton import rclpy_implementation\n'
            'from cam_ros.recording.intake import _Hidden\n'
            'from ..core.motion._law_base import MotionLaw\n'
            'from .parameters import _own_folder\n'
            'from .parameters import shared\n'
            'from cam_ros.node import _package_private\n')
    assert _private_imports(text, 'cam_ros.node.node') == [
        'rclpy._rclpy_pybind11.RCLError',
        'rclpy.impl.implementation_singleton.rclpy_implementation',
        'cam_ros.recording.intake._Hidden',
        'cam_ros.core.motion._law_base.MotionLaw',
        'cam_ros.node.parameters._own_folder',
        'cam_ros.node._package_private']
    # A package's own private module, by its public names: allowed inside the package only.
    assert _private_imports('from ._law_base import MotionLaw\n',
                            'cam_ros.core.motion.laws') == []
