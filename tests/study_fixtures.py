"""Small campaign files for the study tests (tiny grids: each case takes milliseconds)."""

import textwrap
from pathlib import Path

#: Elastic sphere on a half-space of the same steel: beta = 0, so friction without a tangential
#: load runs the normal loop only (fast).
NORMAL_BASE = """
[base]
body1 = { behaviour = "elastic", radius = 0.01, E = 210e9, nu = 0.3 }
body2 = { behaviour = "elastic", radius = "inf", E = 210e9, nu = 0.3 }
load = { hertz_pressure = 1e9, steps = 1 }
grid = { n = 24, half_width = 1.5 }
"""

#: Cattaneo-Mindlin: identical spheres, W = 100 N then Q along x at mu = 0.3 (beta = 0).
CATTANEO_BASE = """
[base]
body1 = { behaviour = "elastic", radius = 0.01, E = 210e9, nu = 0.3 }
body2 = { behaviour = "elastic", radius = 0.01, E = 210e9, nu = 0.3 }
friction = { coefficient = 0.3 }
grid = { n = 24, half_width = 1.5 }

[[base.load.path]]
normal_force = 100.0
steps = 1

[[base.load.path]]
tangential_force = 10.0
steps = 1
"""

#: The case table of the sampled-design checks (tests/test_sample.py,
#: tests/test_global_sensitivity.py): an elastic sphere on a rigid flat, 16^2 cells.
DESIGN_BASE = {
    "body1": {"behaviour": "elastic", "radius": 0.01, "E": 210e9, "nu": 0.3},
    "body2": {"behaviour": "rigid"},
    "load": {"normal_force": 100.0},
    "grid": {"n": [16, 16]},
}
#: Ranges of their three sampled keys: force (N), body 1's modulus (Pa), its radius (m).
DESIGN_RANGES = {
    "load.normal_force": (10.0, 1000.0), "body1.E": (70e9, 400e9), "body1.radius": (5e-3, 5e-2)
}  # fmt: skip

#: 4 cases: mu x (grid.n zipped with load.steps), different step counts.
SMALL_SWEEP = """
[campaign]
name = "small"

[sweep]
"friction.coefficient" = [0.0, 0.2]

[zip.mesh]
"grid.n" = [24, 32]
"load.steps" = [1, 3]

[alias]
"friction.coefficient" = "mu"
"""

#: 8 Cattaneo cases of mixed cost.
MIXED_SWEEP = """
[campaign]
name = "mixed"

[sweep]
"grid.n" = [24, 48]
"load.path.1.tangential_force" = [5.0, 10.0, 15.0, 20.0]

[alias]
"load.path.1.tangential_force" = "tangential_force"
"""


def write(folder: Path, text: str, name: str = "campaign.toml") -> Path:
    """Write a campaign file and return its path."""
    path = Path(folder) / name
    path.write_text(textwrap.dedent(text))
    return path


def small_campaign(folder: Path) -> Path:
    """The 4-case normal-contact campaign."""
    return write(folder, SMALL_SWEEP + NORMAL_BASE, "small.toml")


def mixed_campaign(folder: Path) -> Path:
    """The 8-case Cattaneo campaign."""
    return write(folder, MIXED_SWEEP + CATTANEO_BASE, "mixed.toml")


#: Value of :func:`set_path` that removes the key instead.
DELETE = object()


def set_path(table: dict, where: str, value) -> None:
    """Set (or with :data:`DELETE` remove) the entry at dotted path ``where``, in place."""
    node = table
    keys = where.split(".")
    for key in keys[:-1]:
        node = node[key]
    if value is DELETE:
        del node[keys[-1]]
    else:
        node[keys[-1]] = value


def pair_campaign(base: str, hardening: str, extra: str = "") -> str:
    """A campaign "pairs" of E-E / E-EP / EP-EP steel spheres (R = 15 mm) on one zipped axis.

    ``base``: the lines of ``[base]`` (grid, load, friction); ``hardening``: the inline table of
    the elastic-plastic steel; ``extra``: more tables ([sweep], [alias]).
    """
    steel = "radius = 0.015\nE = 210e9\nnu = 0.3\n"
    return (
        f'[campaign]\nname = "pairs"\n\n[base]\n{base}\n'
        f'[define.steel]\nbehaviour = "elastic"\n{steel}\n'
        f'[define.swift]\nbehaviour = "elastic-plastic"\n{steel}hardening = {hardening}\n\n'
        '[zip.pair]\nbody1 = ["steel", "steel", "swift"]\nbody2 = ["steel", "swift", "swift"]\n'
        f"\n{extra}"
    )


def copy_cases(out: Path, copy: Path, keep) -> Path:
    """A copy of an output folder holding only the finished cases whose id is in ``keep``.

    The kept cases go into one new bundle (as a run writes them); ``campaign.json`` is copied.
    """
    from study import bundle
    from study.run import storage

    (copy / "cases").mkdir(parents=True)
    (copy / "campaign.json").write_bytes((Path(out) / "campaign.json").read_bytes())
    index = storage.case_index(out)
    entries = [
        bundle.Entry(case_id, status, record=storage.read_record(out, case_id, index))
        for case_id, (_, status) in sorted(index.results.items())
        if case_id in keep
    ]
    return bundle.write_bundle(copy / "cases" / f"copy{bundle.SUFFIX}", entries, {})


def capture_figures(monkeypatch) -> dict:
    """Every figure the code under test saves, by file name (still written to its file)."""
    from matplotlib.figure import Figure

    saved, original = {}, Figure.savefig

    def savefig(self, path, *args, **kwargs):
        done = original(self, path, *args, **kwargs)
        saved[Path(path).name] = self
        return done

    monkeypatch.setattr(Figure, "savefig", savefig)
    return saved
