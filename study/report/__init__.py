"""Campaign report: convergence, sensitivity and speed-versus-error tables, figures, Markdown.

``python -m study report OUT [--no-plots]`` reads ``OUT/<name>.nc`` (assembling it first when
it is missing) and writes next to it:

- ``OUT/report.md``: provenance, the tables of :mod:`study.analysis` and links to the figures;
- ``OUT/<name>_convergence_<mesh axis>.png``: log-log error against cells per side, with the
  fitted orders;
- ``OUT/<name>_speed_error.png``: wall time and peak memory against the error, Pareto front;
- ``OUT/<name>_profiles.png``: pressure and shear along y = 0 against r / a;
- ``OUT/<name>_stick_slip.png``: contact-state maps from the per-case files;
- ``OUT/<name>_wear_*.png``: worn volume against friction energy, worn profile and pressure at
  checkpoints (cases that wear, :mod:`.wear`).

Plots need matplotlib (the ``plot`` extra); it is imported lazily with the Agg backend, and the
report is written without figures when it is missing.

The package: :mod:`.figures` (panel grids, titles, notes, markdown) at the bottom; the
sections :mod:`.elastic` (every campaign), :mod:`.plastic`, :mod:`.cycles` and :mod:`.wear`
on it; the builder :mod:`.builder` on top.
"""

from solver.numerics.lazy import lazy_exports

from .command import add_parser, main

#: Where each further public name is defined; imported when first used, so that
#: ``python -m study`` builds its parser without loading the report's sections.
_PUBLIC = {
    "build_report": ".builder",
    "provenance": ".builder",
    "plot_convergence": ".elastic",
    "plot_profiles": ".elastic",
    "plot_speed_error": ".elastic",
    "plot_stick_slip": ".elastic",
    "markdown_table": ".figures",
}
__all__ = ["add_parser", "main", *_PUBLIC]
__getattr__, __dir__ = lazy_exports(__name__, _PUBLIC)
