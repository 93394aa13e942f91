"""The code's shape: no import cycle in ``solver/`` or ``study/``, and both packages' parts layered.

Imports are read with :mod:`ast` (module level and inside functions, absolute and relative), so
a lazy import inside a function counts as much as one at the top.  A package's ``__init__`` only
hands its modules' names on, so it is a target of imports but not a source.
"""

from __future__ import annotations

import ast
from pathlib import Path

import solver
import study

ROOT = Path(__file__).resolve().parents[1]
SOLVER_LAYERS, STUDY_LAYERS = solver.PARTS, study.PARTS


def _modules(package: str) -> dict[str, Path]:
    found = {}
    for path in sorted((ROOT / package).rglob("*.py")):
        name = ".".join(path.relative_to(ROOT).with_suffix("").parts)
        found[name.removesuffix(".__init__")] = path
    return found


def _imports(name: str, path: Path, known: set[str]) -> set[str]:
    package = name if path.name == "__init__.py" else name.rsplit(".", 1)[0]
    out = set()
    for node in ast.walk(ast.parse(path.read_text())):
        if isinstance(node, ast.Import):
            targets = [alias.name for alias in node.names]
        elif isinstance(node, ast.ImportFrom):
            base = node.module or ""
            if node.level:
                parts = package.split(".")[: len(package.split(".")) - node.level + 1]
                base = ".".join(parts + ([base] if base else []))
            targets = [base] + [f"{base}.{alias.name}" for alias in node.names]
        else:
            continue
        out |= {t for t in targets if t in known and t != name}
    return out


def _graph(packages=("solver", "study")) -> dict[str, set[str]]:
    found = {}
    for package in packages:
        found.update(_modules(package))
    known = set(found)
    return {
        name: set() if path.name == "__init__.py" else _imports(name, path, known)
        for name, path in found.items()
    }


def _cycles(edges: dict[str, set[str]]) -> list[list[str]]:
    """Strongly connected components of more than one module (Tarjan, iterative)."""
    index, low, on, stack, out = {}, {}, set(), [], []
    for root in edges:
        if root in index:
            continue
        work = [(root, iter(sorted(edges[root])))]
        index[root] = low[root] = len(index)
        stack.append(root)
        on.add(root)
        while work:
            node, children = work[-1]
            child = next(children, None)
            if child is not None:
                if child not in index:
                    index[child] = low[child] = len(index)
                    stack.append(child)
                    on.add(child)
                    work.append((child, iter(sorted(edges[child]))))
                elif child in on:
                    low[node] = min(low[node], index[child])
                continue
            work.pop()
            if work:
                low[work[-1][0]] = min(low[work[-1][0]], low[node])
            if low[node] == index[node]:
                component = []
                while True:
                    member = stack.pop()
                    on.discard(member)
                    component.append(member)
                    if member == node:
                        break
                if len(component) > 1:
                    out.append(sorted(component))
    return out


def test_the_cycle_finder_finds_a_planted_cycle():
    edges = {"a": {"b"}, "b": {"c"}, "c": {"a"}, "d": {"a"}, "e": set()}
    assert _cycles(edges) == [["a", "b", "c"]]
    assert _cycles({"a": {"b"}, "b": set()}) == []


def test_no_import_cycle_in_solver_or_study():
    assert _cycles(_graph()) == []


def _upward(package: str, layers: tuple[str, ...]) -> list[str]:
    """Imports of ``package``'s parts that reach a part above them."""
    edges = _graph((package,))
    layer = {name: layers.index(name.split(".")[1]) for name in edges if name != package}
    return [
        f"{name} -> {target}"
        for name, targets in edges.items()
        for target in targets
        if name != package and target != package and layer[target] > layer[name]
    ]


def test_study_parts_import_only_the_parts_below_them():
    assert _upward("study", STUDY_LAYERS) == []


def test_solver_parts_import_only_the_parts_below_them():
    assert _upward("solver", SOLVER_LAYERS) == []


def test_the_layer_check_sees_an_upward_import(tmp_path, monkeypatch):
    """A planted import of the driver from a closed form is reported (the check can fail)."""
    for part in ("theory", "drive"):
        (tmp_path / "solver" / part).mkdir(parents=True)
        (tmp_path / "solver" / part / "__init__.py").write_text("")
    (tmp_path / "solver" / "__init__.py").write_text("")
    (tmp_path / "solver" / "theory" / "hertz.py").write_text("from ..drive.loops import solve\n")
    (tmp_path / "solver" / "drive" / "loops.py").write_text("def solve():\n    pass\n")
    monkeypatch.setitem(globals(), "ROOT", tmp_path)
    assert _upward("solver", SOLVER_LAYERS) == ["solver.theory.hertz -> solver.drive.loops"]


def test_the_solver_docstring_lists_the_layers_in_order():
    """The order stated in ``solver/__init__.py`` is the order tested here."""
    text = (ROOT / "solver" / "__init__.py").read_text()
    named = [p for p in SOLVER_LAYERS if f":mod:`solver.{p}`" in text]
    assert named == list(SOLVER_LAYERS)
    assert sorted(named, key=lambda p: text.index(f":mod:`solver.{p}`")) == list(SOLVER_LAYERS)


def test_every_solver_sub_package_says_what_it_holds_and_may_import():
    for init in sorted((ROOT / "solver").glob("*/__init__.py")):
        doc = ast.get_docstring(ast.parse(init.read_text())) or ""
        assert "Imports:" in doc, init
        modules = {p.stem for p in init.parent.glob("*.py")} - {"__init__"}
        assert len(modules) >= 2, init
        assert all(f":mod:`.{m}`" in doc for m in modules), (init, modules)


def test_solver_imports_nothing_of_study():
    edges = _graph()
    assert not [t for n, ts in edges.items() if n.startswith("solver") for t in ts if "study" in t]


def test_a_solve_loads_no_analysis_library():
    """Solving a case (a tangential load, a steady rolling state) loads neither dask, xarray,
    pandas (pyFFTW's dask interface, hidden: :func:`solver.numerics.fftw._pyfftw`), nor
    scipy.optimize (the shakedown theorem's, imported by its method) nor scipy.signal; a
    process that imported dask's FFT first keeps it, and pyFFTW's dask interface can still be
    imported after the solve."""
    import subprocess
    import sys

    code = """
import sys, solver
elastic = {"behaviour": "elastic", "E": 210e9, "nu": 0.3}
base = {"body1": {**elastic, "radius": 0.05}, "body2": elastic, "friction": {"coefficient": 0.3},
        "grid": {"n": [20, 20], "size": [0.0025, 0.0025]}}
shear = {**base, "load": {"normal_force": 3000.0, "tangential_force": [300.0, 0.0]}}
steady = {**base, "load": {"path": [{"normal_force": 3000.0},
                                    {"steady": True, "creepage": [0.002, 0.0]}]}}
for table in (shear, steady):
    assert solver.solve(solver.Case.from_dict(table)).converged
heavy = {"dask", "xarray", "pandas", "scipy.optimize", "scipy.signal"} & set(sys.modules)
assert not heavy, heavy
assert "pyfftw" in sys.modules and "dask.array.fft" not in sys.modules
import pyfftw.interfaces.dask_fft
"""
    done = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True, cwd=ROOT)
    assert done.returncode == 0, done.stderr
    first = "import dask.array.fft, sys, solver.numerics.fftw as f; f._pyfftw(); "
    first += "assert sys.modules['dask.array.fft'] is not None"
    done = subprocess.run([sys.executable, "-c", first], capture_output=True, text=True, cwd=ROOT)
    assert done.returncode == 0, done.stderr


def test_reading_cases_loads_no_solve_library_and_every_module_stays_reachable():
    """``import solver``, a case table read and a campaign expanded load neither pyFFTW,
    scipy.signal nor scipy.optimize (seconds that ``study validate`` and ``status`` do not
    need: a case's memory estimate must not import the shakedown programs);
    ``solver.<part>.<module>`` still works after ``import solver``, and ``python -m study``
    builds its parser without the report."""
    import subprocess
    import sys

    code = """
import sys, solver
from study.campaign import expand_campaign
base = {"body1": {"behaviour": "elastic", "radius": 0.01, "E": 210e9, "nu": 0.3},
        "body2": {"behaviour": "elastic", "radius": "inf", "E": 210e9, "nu": 0.3},
        "load": {"normal_force": 100.0}, "grid": {"n": 16}}
solver.Case.from_dict(base).case_id
expand_campaign({"base": base, "sweep": {"friction.coefficient": [0.1, 0.2]}})
heavy = {"pyfftw", "scipy.signal", "scipy.optimize", "solver.drive.loops"} & set(sys.modules)
assert not heavy, heavy
assert solver.bodies.heights.HeightMap and solver.result.STICK is not None
try:
    solver.no_such_part
except AttributeError as error:
    assert "no_such_part" in str(error)
else:
    raise SystemExit("no AttributeError")
from study.cli import build_parser
build_parser()
assert "study.report.builder" not in sys.modules
import study.report
assert callable(study.report.build_report) and "study.report.builder" in sys.modules
"""
    done = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True, cwd=ROOT)
    assert done.returncode == 0, done.stderr
