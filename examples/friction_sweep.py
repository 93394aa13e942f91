"""A campaign: the stick zone of a sheared steel contact against the friction coefficient.

Writes a campaign file (a steel sphere on a steel flat, 1 GPa, Q = 3 N in 10 steps, mu from
0.05 to 0.8), runs it with ``python -m study run`` into a temporary folder, opens the assembled
dataset with xarray and plots c / a against mu beside Cattaneo-Mindlin's (1 - Q/(mu W))^(1/3).
Exits with status 1 if a case did not converge or c / a misses the closed form by more than 0.03.

Run: ``python examples/friction_sweep.py --out figures`` (run time: docs/run-times.md; the
campaign's own command is ``mpiexec -n 2 python -m study run FILE``).
"""

from __future__ import annotations

import pathlib
import subprocess
import sys
import tempfile

import matplotlib.pyplot as plt
import numpy as np
import xarray as xr
from _common import output_folder

from solver.result import STATUS_FLAGS
from solver.theory.friction import cattaneo_stick_ratio

CAMPAIGN = """
[campaign]
name = "friction_sweep"
output = "{output}"

[base]
body1 = {{ behaviour = "elastic", radius = 0.015, E = 210e9, nu = 0.3 }}
body2 = {{ behaviour = "elastic", radius = "inf", E = 210e9, nu = 0.3 }}
grid = {{ n = 64 }}

[base.load]
path = [
  {{ hertz_pressure = 1e9, steps = 1 }},
  {{ tangential_force = 3.0, steps = 10 }},
]

[sweep]
"friction.coefficient" = [0.05, 0.1, 0.2, 0.3, 0.5, 0.8]

[alias]
"friction.coefficient" = "mu"
"""


def main() -> int:
    """Solve, print the check, draw the figure; 0 when the check passes, else 1."""
    out = output_folder(__doc__.splitlines()[0])
    with tempfile.TemporaryDirectory() as tmp:
        folder = pathlib.Path(tmp) / "out"
        campaign = pathlib.Path(tmp) / "friction_sweep.toml"
        campaign.write_text(CAMPAIGN.format(output=folder))
        subprocess.run([sys.executable, "-m", "study", "run", str(campaign)], check=True)
        with xr.open_dataset(folder / "friction_sweep.nc") as ds:
            ds = ds.load()
    mu = ds.mu.values
    ratio = (ds.stick_radius / ds.contact_radius).values
    force = float(ds.normal_force.values.flat[0])
    exact = np.array([cattaneo_stick_ratio(3.0, m, force) if 3.0 < m * force else 0.0 for m in mu])
    for m, r, e in zip(mu, ratio, exact, strict=True):
        print(f"mu = {m:4.2f}: c/a {r:.3f}, Cattaneo-Mindlin {e:.3f}")
    fig, ax = plt.subplots(figsize=(6, 4), constrained_layout=True)
    ax.plot(mu, ratio, "o", label="computed (64^2)")
    fine = np.linspace(3.0 / force * 1.0001, mu.max(), 200)
    ax.plot(
        fine,
        [cattaneo_stick_ratio(3.0, m, force) for m in fine],
        "k-",
        lw=1,
        label="Cattaneo-Mindlin",
    )
    ax.set(
        xlabel="friction coefficient mu (1)",
        ylabel="stick radius / contact radius (1)",
        title=f"steel on steel, W = {force:.0f} N, Q = 3 N",
    )
    ax.legend()
    fig.savefig(out / "friction_sweep.png", dpi=120)
    converged = bool((ds.status == STATUS_FLAGS["converged"]).all())  # int8 flags per case
    return 0 if converged and np.abs(ratio - exact).max() < 0.03 else 1


if __name__ == "__main__":
    sys.exit(main())
