"""Shared by the example scripts: the ``--out`` argument and a headless matplotlib."""

from __future__ import annotations

import argparse
import pathlib

import matplotlib

matplotlib.use("Agg")


def output_folder(description: str) -> pathlib.Path:
    """Parse ``--out DIR`` (default: the current folder), create it and return it."""
    parser = argparse.ArgumentParser(description=description)
    parser.add_argument("--out", default=".", help="folder for the figure (created)")
    folder = pathlib.Path(parser.parse_args().out)
    folder.mkdir(parents=True, exist_ok=True)
    return folder
