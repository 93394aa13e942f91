"""Benchmark of the residual-field operators of issue 4 on n^3 grids.

Cost of eigenstrain -> residual stress and eigenstrain -> surface residual displacement:
``python -m study.bench.subsurface [--sizes 32 64 96 128] [--repeat 3] [--threads 1]``.

Each grid size runs in a fresh child process (:func:`study.bench.isolated`).  Times are
wall-clock seconds, best of ``repeat``; ``setup`` (kernels and FFTW plans, built once per grid
and material and reused by every later call) is reported apart.  Memory: ``peak_MB`` is the
high-water mark of the process's resident set over setup plus one residual-stress and one
displacement evaluation, minus the resident set before (sampled every 2 ms,
:func:`study.bench.peak_memory`; numpy and FFTW allocations alike; the input eigenstrain is
excluded); ``setup_MB`` the same over setup alone (what the operator keeps, plus construction
transients); ``stress_MB`` and ``disp_MB`` the tracemalloc peaks of one evaluation (its numpy
temporaries and output); ``est_MB`` is
:meth:`solver.volume.eigenstrain.EigenstrainOperator.memory_bytes`.
The last lines fit ``time ~ N^p`` (N = n^3) and compare p with the exponent of N log N over
the same sizes.
"""

from __future__ import annotations

import argparse
import math
import time
import tracemalloc

import numpy as np

from .timing import format_table, isolated, peak_memory

DEFAULT_SIZES = [32, 64, 96, 128]


def _traced_peak(function, *args) -> float:
    """Peak of traced (numpy) allocations during one call (MB)."""
    tracemalloc.start()
    try:
        function(*args)
        return tracemalloc.get_traced_memory()[1] / 2**20
    finally:
        tracemalloc.stop()


def _run(n: int, repeat: int, threads: int) -> dict:
    from solver.numerics.grid import SurfaceGrid, VolumeGrid
    from solver.volume.eigenstrain import EigenstrainOperator

    grid = VolumeGrid(SurfaceGrid(n, n, 1.0, 1.0), n, 1.0)
    rng = np.random.default_rng(0)
    eigenstrain = rng.normal(size=(6,) + grid.shape) * 1e-3
    with peak_memory() as whole_run:
        with peak_memory() as setup_memory:
            t0 = time.perf_counter()
            operator = EigenstrainOperator(grid, 210e9, 0.3, threads=threads)
            operator.prepare(stress=True, displacement=True)
            setup = time.perf_counter() - t0
        stress_peak = _traced_peak(operator.stress, eigenstrain)
        disp_peak = _traced_peak(operator.surface_displacement, eigenstrain)
    best_stress = best_disp = math.inf
    for _ in range(repeat):
        t0 = time.perf_counter()
        stress = operator.stress(eigenstrain)
        best_stress = min(best_stress, time.perf_counter() - t0)
        del stress
    for _ in range(repeat):
        t0 = time.perf_counter()
        displacement = operator.surface_displacement(eigenstrain)
        best_disp = min(best_disp, time.perf_counter() - t0)
        del displacement
    return {
        "n": n,
        "N": n**3,
        "setup_s": setup,
        "stress_s": best_stress,
        "disp_s": best_disp,
        "setup_MB": setup_memory["peak_MB"],
        "stress_MB": stress_peak,
        "disp_MB": disp_peak,
        "peak_MB": whole_run["peak_MB"],
        "est_MB": EigenstrainOperator.memory_bytes(grid) / 2**20,
    }


def growth_exponents(sizes: list[int], times: list[float]) -> tuple[float, float]:
    """Least-squares exponent p of ``time ~ N^p`` and that of ``N log N`` over the same N."""
    big_n = np.array([float(n) ** 3 for n in sizes])
    log_n = np.log(big_n)
    a = np.stack([np.ones_like(log_n), log_n], axis=1)
    p = np.linalg.lstsq(a, np.log(np.asarray(times)), rcond=None)[0][1]
    reference = np.linalg.lstsq(a, np.log(big_n * np.log(big_n)), rcond=None)[0][1]
    return float(p), float(reference)


def main(argv: list[str] | None = None) -> int:
    """Run the benchmark and print its table; return an exit status."""
    parser = argparse.ArgumentParser(prog="python -m study.bench.subsurface", description=__doc__)
    parser.add_argument("--sizes", type=int, nargs="+", default=DEFAULT_SIZES)
    parser.add_argument("--repeat", type=int, default=3)
    parser.add_argument("--threads", type=int, default=1)
    args = parser.parse_args(argv)
    rows, failures = [], 0
    for n in args.sizes:
        status, out = isolated(_run, n, args.repeat, args.threads, timeout=3600.0)
        if status == "ok":
            rows.append(out)
            print(f"n = {n}: stress {out['stress_s']:.3g} s, displacement {out['disp_s']:.3g} s")
        else:
            failures += 1
            print(f"n = {n}: {out}")
    print(
        f"Residual fields of a random eigenstrain on n^3 cells, E = 210 GPa, nu = 0.3, "
        f"{args.threads} FFTW thread(s); peak_MB/setup_MB: resident-set growth, "
        "stress_MB/disp_MB: tracemalloc peak of one evaluation"
    )
    print(format_table(rows))
    if len(rows) >= 2:
        sizes = [row["n"] for row in rows]
        for key, label in (("stress_s", "residual stress"), ("disp_s", "surface displacement")):
            p, reference = growth_exponents(sizes, [row[key] for row in rows])
            print(
                f"{label}: time ~ N^{p:.3f}; N log N over these sizes ~ N^{reference:.3f} "
                f"(ratio {p / reference:.2f})"
            )
    return 1 if failures else 0


if __name__ == "__main__":
    raise SystemExit(main())
