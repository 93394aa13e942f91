"""The ``report`` subcommand: its arguments and its entry point.

Apart from the builder so that ``python -m study`` builds its parser without importing the
report's sections (xarray, the analysis, matplotlib's helpers).
"""

from __future__ import annotations

import argparse


def add_parser(subparsers) -> argparse.ArgumentParser:
    """Add the ``report`` subcommand to an :mod:`argparse` subparsers object."""
    parser = subparsers.add_parser(
        "report",
        help="convergence, sensitivity and speed-versus-error report of a campaign",
        description="Write OUT/report.md with convergence, sensitivity and speed-versus-error "
        "tables, and PNG figures next to the dataset (matplotlib, the 'plot' extra).",
    )
    parser.add_argument("out", metavar="OUT", help="campaign output folder (or its .nc dataset)")
    parser.add_argument("--no-plots", action="store_true", help="write the tables only")
    return parser


def main(args: argparse.Namespace | list[str] | None = None) -> int:
    """Run the ``report`` subcommand; returns the exit status.

    Parameters
    ----------
    args : argparse.Namespace or list of str, optional
        Parsed arguments (``out``, ``no_plots``), or a command line after ``report``.
    """
    if not isinstance(args, argparse.Namespace):
        parser = argparse.ArgumentParser(prog="python -m study")
        add_parser(parser.add_subparsers(dest="command", required=True))
        args = parser.parse_args(["report", *(args or [])])
    from .builder import build_report

    report = build_report(args.out, plots=not args.no_plots)
    print(f"report {report}")
    return 0
