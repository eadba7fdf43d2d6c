"""Sphinx configuration of cam_ros's documentation: MyST Markdown pages, autodoc API reference.

Built by `make docs` (warnings are errors) and by test/docs/test_build.py in `make test`; rosdoc2
builds the same pages with the same stack.
"""
import sys
from pathlib import Path

sys.path.insert(0, str(Path(__file__).resolve().parents[1]))

project = 'cam_ros'
author = 'cam_ros contributors'
copyright = 'cam_ros contributors'
extensions = ['myst_parser', 'sphinx.ext.autodoc']
source_suffix = {'.md': 'markdown'}
root_doc = 'index'
exclude_patterns = ['_build']
myst_heading_anchors = 3
myst_enable_extensions = ['dollarmath']
autodoc_default_options = {'members': True, 'show-inheritance': True}
autodoc_member_order = 'bysource'
autodoc_typehints = 'description'
html_theme = 'alabaster'
html_title = 'cam_ros'


def plain_text_docstring(app, what, name, obj, options, lines):
    """Keep the docstrings' plain-text notation: |x| is an absolute value, *_ok a wildcard."""
    for index, line in enumerate(lines):
        line = line.replace('|', r'\|')
        singles = line.replace('**', '').count('*')
        lines[index] = line.replace('*', r'\*') if singles % 2 else line


def setup(app):
    """Register the docstring filter."""
    app.connect('autodoc-process-docstring', plain_text_docstring)
