"""Shared by the example scripts: the ``--out`` argument, a headless matplotlib, line styles.

``series_style`` is the report's (:func:`study.report.figures.series_style`): every series of a
line plot gets its own colour, marker and line style, drawn so that coinciding ones stay
visible.
"""

from __future__ import annotations

import argparse
import pathlib

import matplotlib

matplotlib.use("Agg")

from study.report.figures import series_style  # noqa: E402  (after the backend is chosen)

__all__ = ["output_folder", "series_style"]


def output_folder(description: str) -> pathlib.Path:
    """Parse ``--out DIR`` (default: the current folder), create it and return it."""
    parser = argparse.ArgumentParser(description=description)
    parser.add_argument("--out", default=".", help="folder for the figure (created)")
    folder = pathlib.Path(parser.parse_args().out)
    folder.mkdir(parents=True, exist_ok=True)
    return folder
