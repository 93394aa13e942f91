import copy
import os
import tempfile

import pytest

STEEL = {"behaviour": "elastic", "E": 210e9, "nu": 0.3}

RIGID_SPHERE_ON_STEEL = {
    "body1": {"radius": 0.015, "behaviour": "rigid"},
    "body2": {"radius": "inf", **STEEL},
    "load": {"hertz_pressure": 6e9, "steps": 1},
    "friction": {"coefficient": 0.0},
    "grid": {"n": 64, "half_width": 1.6},
}


def pytest_configure(config):
    """Under ``mpiexec`` each rank gets a temporary folder of its own.

    Two ranks sharing pytest's numbered folders both prune the old ones, and one finds a
    folder the other is removing (a PytestWarning in CI).  ``--basetemp`` wins when given.
    """
    rank = os.environ.get("PMI_RANK", os.environ.get("OMPI_COMM_WORLD_RANK"))
    if rank is not None and config.option.basetemp is None:
        config.option.basetemp = os.path.join(tempfile.gettempdir(), f"pytest-mpi-rank{rank}")


@pytest.fixture
def hertz_table():
    """A fresh copy of the rigid-sphere-on-steel case table (p_H = 6 GPa)."""
    return copy.deepcopy(RIGID_SPHERE_ON_STEEL)


# --- the guide's validation table, written by the tests that compute it -------------------------

VALIDATION_ROWS = pytest.StashKey[dict]()


def pytest_addoption(parser):
    parser.addoption(
        "--validation-table",
        metavar="FILE",
        default=None,
        help="write the numbers the validation tests measured to FILE (Markdown), one row per "
        "check, from the tests that passed (the guide's docs/tables/validation.md)",
    )


@pytest.fixture
def validation(request):
    """``record(check, reference, result)``: this test's row of the guide's validation table.

    ``result`` holds the measured numbers (formatted by the test from what it computed), or one
    relative error (a float). Rows of parametrised tests that share ``check`` and ``reference``
    are one row: their texts joined, or the largest of their errors.
    """
    rows = request.config.stash.setdefault(VALIDATION_ROWS, {})

    def record(check: str, reference: str, result: str | float) -> None:
        rows.setdefault(request.node.nodeid, []).append((check, reference, result))

    return record


@pytest.hookimpl(wrapper=True)
def pytest_runtest_makereport(item, call):
    report = yield
    if report.when == "call" and report.failed:  # a failed test's numbers are not evidence
        item.config.stash.get(VALIDATION_ROWS, {}).pop(item.nodeid, None)
    return report


def pytest_sessionfinish(session):
    path = session.config.getoption("--validation-table")
    if not path:
        return
    import shlex
    import sys

    from study.bench.timing import provenance_line

    merged: dict[tuple[str, str], list] = {}
    for rows in session.config.stash.get(VALIDATION_ROWS, {}).values():
        for check, reference, result in rows:
            merged.setdefault((check, reference), []).append(result)
    for key, results in merged.items():
        if all(isinstance(result, float) for result in results):
            merged[key] = [f"largest relative error {max(results):.1e} (of {len(results)} cases)"]
    lines = [
        provenance_line(["python -m pytest", *map(shlex.quote, sys.argv[1:])]),
        "",
        "| check | reference | result |",
        "|---|---|---|",
        *(
            "| " + " | ".join(cell.replace("|", "\\|") for cell in (c, r, "; ".join(res))) + " |"
            for (c, r), res in merged.items()
        ),
    ]
    with open(path, "w") as handle:
        handle.write("\n".join(lines) + "\n")
