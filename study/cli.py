"""Command line: ``python -m study {bench} ...``."""

from __future__ import annotations

import argparse
import os


def _single_threaded_blas() -> None:
    """One BLAS/OpenMP thread per process: ranks own the cores, and idle BLAS threads stall."""
    for name in ("OMP_NUM_THREADS", "OPENBLAS_NUM_THREADS", "MKL_NUM_THREADS"):
        os.environ.setdefault(name, "1")


def build_parser() -> argparse.ArgumentParser:
    """The argument parser of ``python -m study``."""
    parser = argparse.ArgumentParser(
        prog="python -m study", description="slipstick parametric studies and benchmarks"
    )
    sub = parser.add_subparsers(dest="command", required=True)
    bench = sub.add_parser("bench", help="benchmarks against closed forms and peer codes")
    bench.add_argument("scene", choices=["hertz", "cattaneo"], help="benchmark scene")
    bench.add_argument("--sizes", type=int, nargs="+", help="grid sizes n (cells per side)")
    bench.add_argument("--peers", action="store_true", help="also run installed peer codes")
    bench.add_argument("--repeat", type=int, default=3, help="timing repetitions (best of)")
    return parser


def main(argv: list[str] | None = None) -> int:
    """Entry point; returns the process exit status."""
    _single_threaded_blas()
    args = build_parser().parse_args(argv)
    if args.command == "bench":
        from .bench import run_benchmark

        return run_benchmark(args.scene, sizes=args.sizes, peers=args.peers, repeat=args.repeat)
    return 2
