"""Run under ``mpiexec -n 2``: a case gives bit-identical results on every rank."""

import numpy as np
import pytest

import solver

pytestmark = pytest.mark.mpi


def test_same_case_same_bits_on_every_rank(hertz_table):
    from mpi4py import MPI

    comm = MPI.COMM_WORLD
    hertz_table["friction"]["coefficient"] = 0.2
    result = solver.solve(solver.Case.from_dict(hertz_table))
    gathered = comm.allgather(result.pressure.tobytes())
    assert all(g == gathered[0] for g in gathered)
    assert comm.allreduce(int(result.converged), op=MPI.MIN) == 1
    assert np.isfinite(result.pressure).all()
