"""Draw the guide's gallery: every example's figure and the report figures of shipped campaigns.

Run from the repository's root::

    python docs/gallery.py                 # every figure (runs the campaigns not yet run)
    python docs/gallery.py --only NAME ... # some figures (names: --list)

Each figure is drawn by the code that a user runs (an example script, the README's quickstart
snippet, ``python -m study report``) and copied to ``docs/gallery/NAME.png``.  Campaigns run
with ``mpiexec -n 2 python -m study run`` into ``out/gallery/<campaign>`` and are reused when
run again (finished cases are skipped), so redrawing a report figure after a change of the
drawing code costs seconds; the shakedown map's campaign is the long one the first time
(``docs/tables/timings.md``).

The script writes ``docs/gallery/manifest.json``: for each figure the command that regenerates
it, the sha256 of every source file that draws it (for the quickstart, of the README's
quickstart snippet) and of the PNG.  ``tests/test_docs.py`` recomputes the hashes, so a figure
whose drawing code changed after it was drawn fails the test with the command to run; content
hashes, not file times, because a fresh clone resets every file's time.
"""

from __future__ import annotations

import argparse
import datetime
import hashlib
import json
import os
import re
import shutil
import subprocess
import sys
from dataclasses import dataclass
from pathlib import Path

ROOT = Path(__file__).resolve().parents[1]
GALLERY = ROOT / "docs" / "gallery"
MANIFEST = GALLERY / "manifest.json"
RUNS = ROOT / "out" / "gallery"
#: The report's drawing code every report figure goes through.
REPORT = ("study/report/builder.py", "study/report/figures.py")
EXAMPLE = ("examples/_common.py",)
#: A source named so is the README's quickstart Python snippet, not a file.
QUICKSTART_SNIPPET = "README.md#quickstart-python"


@dataclass(frozen=True)
class Figure:
    """One gallery figure: how it is made and what draws it."""

    name: str  #: docs/gallery/NAME.png
    kind: str  #: "example", "quickstart" or "report"
    sources: tuple[str, ...]  #: files (relative to the root) whose change makes it stale
    campaign: str = ""  #: campaigns/CAMPAIGN.toml, for "quickstart" and "report"
    drawn_as: str = ""  #: the PNG the report writes (report figures)
    cost: str = "seconds"  #: what drawing it costs the first time

    @property
    def command(self) -> str:
        """The command that redraws this figure alone."""
        return f"python docs/gallery.py --only {self.name}"


def _example(name: str, cost: str = "seconds") -> Figure:
    return Figure(name, "example", (f"examples/{name}.py", *EXAMPLE), cost=cost)


def _report(campaign: str, drawn: str, module: str, cost: str) -> Figure:
    return Figure(
        f"{campaign}_{drawn}",
        "report",
        (f"campaigns/{campaign}.toml", *REPORT, f"study/report/{module}.py"),
        campaign=campaign,
        drawn_as=f"{campaign}_{drawn}.png",
        cost=cost,
    )


FIGURES: tuple[Figure, ...] = (
    Figure(
        "quickstart",
        "quickstart",
        ("campaigns/quickstart.toml", QUICKSTART_SNIPPET),
        campaign="quickstart",
    ),
    _example("hertz_pressure"),
    _example("cattaneo_stick_zone"),
    _example("friction_sweep"),
    _example("plastic_indentation"),
    _example("fretting_loop"),
    _example("creep_curve"),
    _example("steady_rolling"),
    _example("your_surface"),
    _report("convergence_hertz", "convergence_grid_n", "elastic", "a small campaign"),
    _report("paper_load_sweep", "load_curves", "plastic", "a 20-case campaign"),
    _report("paper_load_sweep", "plastic_sections", "plastic", "a 20-case campaign"),
    _report("shakedown_map", "shakedown_map", "shakedown", "the longest campaign"),
    _report("steady_creep_curves", "steady_creep_curves", "rolling", "a 9-case campaign"),
    _report("periodic_rough", "spot_sizes", "rough", "a 4-case campaign"),
    _report("periodic_rough_plastic", "residual_topography", "rough", "a 4-case campaign"),
    _report("running_in", "topography_spectra", "rough", "a 4-case campaign of passes"),
    _report("sobol_swift_sphere", "saltelli", "global_sensitivity", "a 3072-case campaign"),
    _report("hard_cases", "atlas", "atlas", "a 24-case campaign"),
)
BY_NAME = {figure.name: figure for figure in FIGURES}


# -- hashes ---------------------------------------------------------------------------------------
def quickstart_snippet(readme: str | None = None) -> str:
    """The first Python block of the README's quickstart that saves a figure (``savefig``)."""
    readme = (ROOT / "README.md").read_text() if readme is None else readme
    section = readme.split("\n## Quickstart", 1)[-1].split("\n## ", 1)[0]
    blocks = re.findall(r"```python\n(.*?)```", section, flags=re.S)
    drawing = [code for code in blocks if "savefig(" in code]
    if not drawing:
        raise LookupError("README.md: no Python block of the quickstart saves a figure")
    return drawing[0]


def snippet_figure(code: str) -> str:
    """The file name the quickstart snippet saves its figure as."""
    found = re.search(r"savefig\(\s*[\"']([^\"']+)[\"']", code)
    return found.group(1) if found else "quickstart.png"


def source_hash(source: str) -> str:
    """sha256 of a source file's bytes (or of the README's quickstart snippet)."""
    if source == QUICKSTART_SNIPPET:
        try:
            return hashlib.sha256(quickstart_snippet().encode()).hexdigest()
        except LookupError:
            return "(no quickstart snippet that saves a figure)"
    return hashlib.sha256((ROOT / source).read_bytes()).hexdigest()


def file_hash(path: Path) -> str:
    """sha256 of a file's bytes."""
    return hashlib.sha256(path.read_bytes()).hexdigest()


def stale(manifest: dict) -> dict[str, list[str]]:
    """{figure: reasons} for every figure whose record no longer matches its sources or PNG."""
    found: dict[str, list[str]] = {}
    records = manifest.get("figures", {})
    for figure in FIGURES:
        record = records.get(figure.name)
        png = GALLERY / f"{figure.name}.png"
        if record is None:
            found[figure.name] = ["not in the manifest"]
            continue
        reasons = [
            f"{source} changed since it was drawn"
            for source in figure.sources
            if record["sources"].get(source) != source_hash(source)
        ]
        if not png.exists():
            reasons.append(f"{png.relative_to(ROOT)} is missing")
        elif record.get("png_sha256") != file_hash(png):
            reasons.append(f"{png.relative_to(ROOT)} is not the PNG the manifest records")
        if reasons:
            found[figure.name] = reasons
    for name in sorted(set(records) - set(BY_NAME)):
        found[name] = ["in the manifest but no longer in docs/gallery.py"]
    return found


# -- drawing --------------------------------------------------------------------------------------
def _run(command: list[str], cwd: Path = ROOT) -> None:
    print("+", " ".join(command), flush=True)
    env = os.environ | {"MPLBACKEND": "Agg"}
    subprocess.run(command, cwd=cwd, check=True, env=env)


def _campaign(name: str, ranks: int) -> Path:
    """Run (or resume) a campaign into out/gallery/NAME; returns the output folder."""
    out = RUNS / name
    launcher = ["mpiexec", "-n", str(ranks)] if ranks > 1 and shutil.which("mpiexec") else []
    command = [*launcher, sys.executable, "-m", "study", "run", f"campaigns/{name}.toml"]
    _run([*command, "--out", str(out.relative_to(ROOT))])
    return out


def draw(figure: Figure, ranks: int) -> None:
    """Make docs/gallery/NAME.png the way its user would."""
    GALLERY.mkdir(parents=True, exist_ok=True)
    target = GALLERY / f"{figure.name}.png"
    if figure.kind == "example":
        scratch = RUNS / "examples"  # the scripts write more than their figure (height maps)
        _run([sys.executable, figure.sources[0], "--out", str(scratch)])
        shutil.copyfile(scratch / f"{figure.name}.png", target)
    elif figure.kind == "quickstart":
        out = _campaign(figure.campaign, ranks)
        scratch = out.parent / "quickstart_snippet"
        (scratch / "out").mkdir(parents=True, exist_ok=True)
        link = scratch / "out" / "quickstart"
        if link.is_symlink() or link.exists():
            link.unlink()
        link.symlink_to(out.resolve())
        code = quickstart_snippet()
        (GALLERY / "quickstart.py").write_text(code)  # shown in the gallery
        _run([sys.executable, "-c", code], cwd=scratch)
        shutil.copyfile(scratch / snippet_figure(code), target)
    else:
        out = _campaign(figure.campaign, ranks)
        _run([sys.executable, "-m", "study", "report", str(out.relative_to(ROOT))])
        shutil.copyfile(out / figure.drawn_as, target)


def record(figure: Figure) -> dict:
    """The manifest's entry of a figure just drawn."""
    png = GALLERY / f"{figure.name}.png"
    return {
        "command": figure.command,
        "cost": figure.cost,
        "sources": {source: source_hash(source) for source in figure.sources},
        "png_sha256": file_hash(png),
        "drawn": datetime.datetime.now(datetime.UTC).strftime("%Y-%m-%dT%H:%M:%SZ"),
    }


def read_manifest() -> dict:
    """docs/gallery/manifest.json (empty when there is none yet)."""
    return json.loads(MANIFEST.read_text()) if MANIFEST.exists() else {"figures": {}}


def write_manifest(manifest: dict) -> None:
    """Write docs/gallery/manifest.json, figures sorted by name."""
    manifest["about"] = (
        "Written by docs/gallery.py: per figure, the sha256 of the files that draw it and of "
        "the PNG; tests/test_docs.py fails when they no longer match."
    )
    manifest["figures"] = {name: manifest["figures"][name] for name in sorted(manifest["figures"])}
    MANIFEST.write_text(json.dumps(manifest, indent=2) + "\n")


def main(argv: list[str] | None = None) -> int:
    """Draw the chosen figures and record them in the manifest."""
    parser = argparse.ArgumentParser(description=__doc__.split("\n", 1)[0])
    parser.add_argument("--only", nargs="+", metavar="NAME", help="draw these figures only")
    parser.add_argument("--stale", action="store_true", help="draw the stale figures only")
    parser.add_argument("--list", action="store_true", help="list the figures and exit")
    parser.add_argument("--check", action="store_true", help="exit 1 if a figure is stale")
    parser.add_argument("--ranks", type=int, default=2, help="MPI ranks of campaigns (2)")
    args = parser.parse_args(argv)
    manifest = read_manifest()
    old = stale(manifest)
    if args.list or args.check:
        for figure in FIGURES:
            state = "; ".join(old.get(figure.name, [])) or "current"
            print(f"{figure.name:42s} {figure.kind:10s} {figure.cost:26s} {state}")
        return 1 if args.check and old else 0
    unknown = set(args.only or ()) - set(BY_NAME)
    if unknown:
        parser.error(f"unknown figure(s) {sorted(unknown)}; known: {sorted(BY_NAME)}")
    chosen = [
        f
        for f in FIGURES
        if (not args.only or f.name in args.only) and (not args.stale or f.name in old)
    ]
    for figure in chosen:
        draw(figure, args.ranks)
        manifest["figures"][figure.name] = record(figure)
        write_manifest(manifest)  # after every figure: a later failure keeps the earlier ones
    for name in set(manifest["figures"]) - set(BY_NAME):
        del manifest["figures"][name]
    write_manifest(manifest)
    print(f"drew {len(chosen)} figure(s) into {GALLERY.relative_to(ROOT)}")
    return 0


if __name__ == "__main__":
    sys.exit(main())
