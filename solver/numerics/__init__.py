"""Numerical plumbing every physics package shares: grids, FFTW plans, threads, tensors, Anderson.

- :mod:`.grid`: cell-centred surface and volume grids, index boxes, padded FFT lengths;
- :mod:`.images`: the periodic images of a kernel, a laterally periodic grid's kernels;
- :mod:`.fftw`: FFTW plans from one place, the planner modes, wisdom handed in and out;
- :mod:`.threads`: the worker threads of the parallel loops;
- :mod:`.tensor`: symmetric 3x3 tensors as six components, the one convention of the solver;
- :mod:`.anderson`: Anderson acceleration of a fixed-point iteration;
- :mod:`.lazy`: a package's public names imported on first use.

Imports: :mod:`solver.variables` and :mod:`solver.keys` only (the declarations); no physics.
"""
