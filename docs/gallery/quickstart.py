import matplotlib.pyplot as plt
import xarray as xr

from study.report.figures import series_style

ds = xr.open_dataset("out/quickstart/quickstart.nc")
ds.max_pressure.sel(friction_coefficient=0.1, method="nearest")  # over dundurs_beta
fig, (left, right) = plt.subplots(1, 2, figsize=(10, 4), constrained_layout=True)
# a ratio keeps the numerator's units (xarray keeps attrs): say it is dimensionless
ratio = (ds.stick_radius / ds.hertz_radius).assign_attrs(units="1")
lines = ratio.plot(x="friction_coefficient", hue="dundurs_beta", ax=left, add_legend=False)
for j, line in enumerate(lines):  # beta = -0.12 and 0.12 coincide: own marker and style each
    line.set(**series_style(j, len(lines)))
left.legend(lines, [f"{beta:g}" for beta in ds.dundurs_beta.values], title="dundurs_beta")
left.set(
    xlabel="friction coefficient (1)",
    ylabel="stick radius / Hertz radius (1)",
    title="stick zone at the end of loading",
)
case = ds.sel(friction_coefficient=0.4, dundurs_beta=0.12, method="nearest")
(case.pressure_profile / case.hertz_pressure).assign_attrs(units="1").plot(ax=right)
right.set(xlabel="r / a_H (1), along +x at y = 0", ylabel="pressure / p_H (1)")
right.set_title("friction_coefficient = 0.4, dundurs_beta = 0.12")
fig.savefig("quickstart.png")
