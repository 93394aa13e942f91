"""Sphinx configuration of the slipstick guide (MyST Markdown pages).

Build offline, warnings as errors::

    python -m sphinx -W -b html docs docs/_build/html

The reference pages (``reference/*.md``) are written by :mod:`docs.generate` from the code's
own declarations before every build, so they cannot drift from the code (the repository keeps
them too, checked by ``tests/test_docs.py``).
"""

from __future__ import annotations

import sys
from pathlib import Path

HERE = Path(__file__).resolve().parent
sys.path.insert(0, str(HERE.parent))
sys.path.insert(0, str(HERE))

import generate  # noqa: E402  (docs/generate.py, beside this file)

project = "slipstick"
author = "the slipstick developers"
copyright = "2026, the slipstick developers"  # noqa: A001
extensions = ["myst_parser", "sphinx.ext.autodoc", "sphinx.ext.napoleon", "sphinx.ext.mathjax"]
source_suffix = {".md": "markdown", ".rst": "restructuredtext"}
exclude_patterns = ["_build"]
myst_enable_extensions = ["dollarmath", "colon_fence"]
myst_heading_anchors = 3
html_theme = "alabaster"
html_static_path: list[str] = []
autodoc_typehints = "description"
autodoc_member_order = "bysource"
napoleon_numpy_docstring = True
napoleon_google_docstring = False
nitpicky = False
suppress_warnings = ["myst.header"]


def setup(app):
    """Write the generated reference pages before the build reads the sources."""
    app.connect("builder-inited", lambda _app: generate.write_all(HERE / "reference"))
