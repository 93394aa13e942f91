"""Campaign report: convergence, sensitivity and speed-versus-error tables, figures, Markdown.

``python -m study report OUT [--no-plots]`` reads ``OUT/<name>.nc`` (assembling it first when
it is missing) and writes next to it:

- ``OUT/report.md``: provenance, the tables of :mod:`study.analysis` and links to the figures;
- ``OUT/<name>_convergence_<mesh axis>.png``: log-log error against cells per side, with the
  fitted orders;
- ``OUT/<name>_speed_error.png``: wall time and peak memory against the error, Pareto front;
- ``OUT/<name>_profiles.png``: pressure and shear along y = 0 against r / a;
- ``OUT/<name>_stick_slip.png``: contact-state maps from the per-case files.

Plots need matplotlib (the ``plot`` extra); it is imported lazily with the Agg backend, and the
report is written without figures when it is missing.

The package: :mod:`.figures` (panel grids, titles, notes, markdown) at the bottom; the
sections :mod:`.elastic` (every campaign), :mod:`.plastic` and :mod:`.cycles` on it; the
builder :mod:`.builder` on top.
"""

from .builder import add_parser, build_report, main, provenance
from .elastic import plot_convergence, plot_profiles, plot_speed_error, plot_stick_slip
from .figures import markdown_table

__all__ = [
    "add_parser",
    "build_report",
    "main",
    "markdown_table",
    "plot_convergence",
    "plot_profiles",
    "plot_speed_error",
    "plot_stick_slip",
    "provenance",
]
