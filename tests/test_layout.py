"""The code's shape: no import cycle in ``solver/`` or ``study/``, and ``study``'s parts layered.

Imports are read with :mod:`ast` (module level and inside functions, absolute and relative), so
a lazy import inside a function counts as much as one at the top.  A package's ``__init__`` only
hands its modules' names on, so it is a target of imports but not a source.
"""

from __future__ import annotations

import ast
import importlib
import subprocess
import sys
import warnings
from pathlib import Path

import pytest

import study

ROOT = Path(__file__).resolve().parents[1]
#: ``study``'s parts from the bottom up: each may import those before it (and ``solver``).
STUDY_LAYERS = ("campaign", "run", "analysis", "report", "bench", "cli", "__main__")


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


def test_study_parts_import_only_the_parts_below_them():
    edges = _graph(("study",))
    layer = {name: STUDY_LAYERS.index(name.split(".")[1]) for name in edges if name != "study"}
    upward = [
        f"{name} -> {target}"
        for name, targets in edges.items()
        for target in targets
        if name != "study" and target != "study" and layer[target] > layer[name]
    ]
    assert upward == []


def test_solver_imports_nothing_of_study():
    edges = _graph()
    assert not [t for n, ts in edges.items() if n.startswith("solver") for t in ts if "study" in t]


@pytest.mark.parametrize(("former", "now"), sorted(study.MOVED.items()))
def test_former_module_names_import_as_the_moved_modules(former, now):
    with warnings.catch_warnings(record=True) as caught:
        warnings.simplefilter("always")
        module = importlib.import_module(former)
    assert module is importlib.import_module(now)
    assert sys.modules[former] is module
    if caught:  # the first import of the former name warns (later ones hit sys.modules)
        assert issubclass(caught[0].category, DeprecationWarning) and now in str(caught[0].message)


def test_python_m_a_former_bench_name_runs_the_moved_module():
    done = subprocess.run(
        [sys.executable, "-m", "study.bench_cycles", "--help"],
        capture_output=True,
        text=True,
        cwd=ROOT,
        timeout=120,
    )
    assert done.returncode == 0, done.stderr
    assert "--plastic" in done.stdout
