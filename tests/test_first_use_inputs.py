"""Bad inputs a first user gives that used to get through (issue 35, items 6 and 9).

Each is refused in one line naming the field (and the file where there is one) with a
:class:`solver.SpecError` or :class:`solver.bodies.heights.SurfaceError`, never a bare numpy or
Python exception, and ``python -m study validate`` exits with status 2:

* surfaces too steep for small-slope theory: a height map whose heights resampled onto the
  case grid have an rms slope above :data:`solver.keys.MAX_SURFACE_SLOPE` (finite differences
  between cells), a roughness given by ``rms`` whose realisation is that steep (spectral);
* heights or coordinates that are not numbers, ragged nested lists, surface tables that do
  not name one file;
* a normal force whose mean pressure W / (Lx Ly) over a heights-only domain is out of the
  p/E* range;
* pairs and lists of numbers: a list, a tuple and a 1-D numpy array are one spelling (the same
  case id), strings, tables and 2-D arrays are refused.

The expected numbers are computed here from the constants and the definitions (an independent
finite-difference or Fourier computation), never typed in.
"""

from __future__ import annotations

import copy
import importlib
import math
import re
import subprocess
import sys
from pathlib import Path

import numpy as np
import pytest
import xarray as xr
from scipy import ndimage

from solver import Case, SpecError
from solver.bodies.heights import HeightMap, Roughness, SurfaceError, _roughness_lattice
from solver.keys import MAX_SURFACE_SLOPE, PRESSURE_RATIO_RANGE
from study.campaign.surfaces import read_surface

REPO = Path(__file__).resolve().parents[1]
STEEL = {"behaviour": "elastic", "E": 210e9, "nu": 0.3}
#: Composite modulus (Pa) of a rigid body on :data:`STEEL`.
E_STAR = STEEL["E"] / (1 - STEEL["nu"] ** 2)
#: A rigid sphere (R = 15 mm) pressed with 60 N on a steel half-space (a_H = 0.14 mm).
SPHERE = {
    "body1": {"behaviour": "rigid", "radius": 0.015},
    "body2": {**STEEL, "radius": "inf"},
    "load": {"normal_force": 60.0},
    "grid": {"n": 64},
}
#: A heights-only contact: a rigid flat on a rough steel flat, the domain in metres.
SIDE = 4e-4
ROUGH = {"rms": 2e-7, "hurst": 0.8, "long_cutoff": 2e-4, "short_cutoff": 2e-5, "seed": 7}
FLAT = {
    "body1": {"behaviour": "rigid"},
    "body2": {**STEEL, "roughness": ROUGH},
    "load": {"normal_force": 0.5},
    "grid": {"n": 64, "size": SIDE},
}


def _table(base: dict, **changes) -> dict:
    """A deep copy of ``base`` with dotted keys set (``body2__roughness`` for body2.roughness)."""
    table = copy.deepcopy(base)
    for key, value in changes.items():
        *head, last = key.split("__")
        inner = table
        for name in head:
            inner = inner[name]
        inner[last] = value
    return table


def _refused(error, field: str, exception=SpecError) -> str:
    """The one-line message of ``error`` (a pytest ExceptionInfo); it starts with ``field``."""
    assert error.type is exception, error.type
    message = str(error.value)
    assert "\n" not in message, message
    assert message.startswith(f"{field}:"), message
    return message


def _smooth_map(points: int = 301, half: float = 3e-4, seed: int = 0) -> tuple:
    """A smooth random map (correlated over a few points), rms height 1 um, over +-half (m)."""
    x = np.linspace(-half, half, points)
    noise = np.random.default_rng(seed).standard_normal((points, points))
    height = ndimage.gaussian_filter(noise, 3.0)
    return x, x, height * (1e-6 / height.std())


def _grid_slope(case: Case, surface) -> float:
    """Rms slope of ``surface`` resampled at the case's cell centres: forward differences."""
    grid = case.surface_grid
    xx, yy = grid.mesh()  # (nx, ny)
    h = surface.sample(xx, yy)
    gx = np.diff(h, axis=0) / grid.dx
    gy = np.diff(h, axis=1) / grid.dy
    return math.sqrt(np.mean(gx**2) + np.mean(gy**2))


def _number_after(message: str, words: str) -> float:
    """The number that follows ``words`` in ``message``."""
    found = re.search(re.escape(words) + r"\s*([-+0-9.eE]+)", message)
    assert found, (words, message)
    return float(found.group(1).rstrip("."))


# -- 1. height maps steeper than small-slope theory ---------------------------------------------
@pytest.fixture(scope="module")
def unit_map():
    """A smooth map, the valid case it gives under the sphere, and its rms slope on that grid."""
    x, y, height = _smooth_map()
    case = Case.from_dict(_table(SPHERE, body2__surface=HeightMap(x, y, height, "unit map")))
    slope = _grid_slope(case, case.body2.surface)
    assert 0 < slope < MAX_SURFACE_SLOPE
    return x, y, height, slope


@pytest.mark.parametrize("multiple", [3.0, 1.05])
def test_a_map_steeper_than_the_limit_is_refused_with_its_slope(unit_map, multiple):
    x, y, height, slope = unit_map
    target = multiple * MAX_SURFACE_SLOPE
    surface = HeightMap(x, y, height * (target / slope), "steep map")
    with pytest.raises(SpecError) as error:
        Case.from_dict(_table(SPHERE, body2__surface=surface))
    message = _refused(error, "body2.surface")
    assert "steep map" in message and "rms slope" in message
    assert _number_after(message, "rms slope of") == pytest.approx(target, rel=2e-3)
    scale = _number_after(message, "scale its heights by at most")
    assert scale <= MAX_SURFACE_SLOPE / target
    # the scale it suggests passes (slopes scale with the heights)
    scaled = HeightMap(x, y, height * (target / slope) * scale, "scaled map")
    Case.from_dict(_table(SPHERE, body2__surface=scaled))


def test_a_map_just_under_the_limit_passes(unit_map):
    x, y, height, slope = unit_map
    surface = HeightMap(x, y, height * (0.95 * MAX_SURFACE_SLOPE / slope), "gentle map")
    case = Case.from_dict(_table(SPHERE, body2__surface=surface))
    assert _grid_slope(case, case.body2.surface) == pytest.approx(0.95 * MAX_SURFACE_SLOPE)


def test_a_steep_map_file_is_refused_naming_the_file(tmp_path, unit_map):
    x, y, height, slope = unit_map
    path = tmp_path / "profilometer.nc"
    height = height * (4 * MAX_SURFACE_SLOPE / slope)
    xr.Dataset({"height": (("y", "x"), height, {"units": "m"})}, coords={"x": x, "y": y}).to_netcdf(
        path
    )
    with pytest.raises(SpecError) as error:
        Case.from_dict(_table(SPHERE, body2__surface=str(path)), read_surface)
    message = _refused(error, "body2.surface")
    assert str(path) in message and "rms slope" in message


def test_a_steep_map_on_a_heights_only_domain_is_refused():
    """Heights only (no radius), a sinusoid of rms slope twice the limit on the rigid body."""
    x = np.linspace(-SIDE, SIDE, 401)
    wavelength = 8 * SIDE / 64  # 8 cells
    amplitude = 2 * MAX_SURFACE_SLOPE * math.sqrt(2) * wavelength / (2 * math.pi)  # A k / sqrt 2
    xx, _ = np.meshgrid(x, x)
    surface = HeightMap(x, x, amplitude * np.sin(2 * math.pi * xx / wavelength), "waves")
    table = _table(FLAT, body1__surface=surface)
    del table["body2"]["roughness"]
    with pytest.raises(SpecError) as error:
        Case.from_dict(table)
    message = _refused(error, "body1.surface")
    # the continuous rms slope is 2 x the limit; finite differences over 8 cells a wavelength
    # see sin(pi/8)/(pi/8) of it
    expected = 2 * MAX_SURFACE_SLOPE * math.sin(math.pi / 8) / (math.pi / 8)
    assert _number_after(message, "rms slope of") == pytest.approx(expected, rel=1e-2)


# -- 2. roughness given by rms whose realisation is too steep -----------------------------------
def _spectral_slope(roughness: Roughness, case_grid) -> float:
    """Rms slope of the realisation on its lattice: the gradient's mean square by Fourier."""
    side = 2.0 * float(max(np.abs(case_grid.x).max(), np.abs(case_grid.y).max())) + 1e-300
    points, spacing = roughness.lattice(side)
    h = _roughness_lattice(roughness, points, spacing)
    q = 2 * math.pi * np.fft.fftfreq(points, spacing)
    spectrum = np.fft.fft2(h)  # axes (y, x)
    gx = np.fft.ifft2(1j * q[None, :] * spectrum).real
    gy = np.fft.ifft2(1j * q[:, None] * spectrum).real
    return math.sqrt(np.mean(gx**2 + gy**2))


def test_roughness_by_rms_too_steep_says_its_slope_and_the_largest_rms():
    steep = {"rms": 1e-4, "hurst": 0.8, "long_cutoff": 2e-4, "short_cutoff": 2e-5, "seed": 0}
    with pytest.raises(SpecError) as error:
        Case.from_dict(_table(SPHERE, body2__roughness=steep))
    message = _refused(error, "body2.roughness.rms")
    grid = Case.from_dict(_table(SPHERE, body2__roughness={**steep, "rms": 1e-7})).surface_grid
    slope = _spectral_slope(Roughness(0.8, 2e-4, 2e-5, rms=1e-4, seed=0), grid)
    assert slope > MAX_SURFACE_SLOPE
    assert _number_after(message, "rms slope") == pytest.approx(slope, rel=2e-3)
    largest = steep["rms"] * MAX_SURFACE_SLOPE / slope
    told = _number_after(message, "give rms <=")
    assert largest * (1 - 1e-2) <= told <= largest
    assert "rms_slope" in message
    Case.from_dict(_table(SPHERE, body2__roughness={**steep, "rms": told}))  # it passes
    with pytest.raises(SpecError, match="body2.roughness.rms"):
        Case.from_dict(_table(SPHERE, body2__roughness={**steep, "rms": 1.01 * largest}))


def test_roughness_on_a_heights_only_flat_too_steep_names_body1():
    short = 2e-5
    rms = 2 * MAX_SURFACE_SLOPE * short / (2 * math.pi) * 4  # far past the bound
    rough = {**ROUGH, "rms": rms}
    table = _table(FLAT, body1__roughness=rough)
    del table["body2"]["roughness"]
    with pytest.raises(SpecError) as error:
        Case.from_dict(table)
    _refused(error, "body1.roughness.rms")


def test_roughness_under_its_slope_bound_is_not_realised_at_validation():
    """rms x 2 pi / short_cutoff <= the limit: no realisation is computed to accept it."""
    rms = 0.9 * MAX_SURFACE_SLOPE * ROUGH["short_cutoff"] / (2 * math.pi)
    roughness = Roughness(0.8, 2e-4, 2e-5, rms=rms, seed=123)
    assert roughness.slope_bound() <= MAX_SURFACE_SLOPE
    before = _roughness_lattice.cache_info().misses
    Case.from_dict(_table(FLAT, body2__roughness={**ROUGH, "rms": rms, "seed": 123}))
    assert _roughness_lattice.cache_info().misses == before


# -- 3. heights and coordinates that are not numbers ---------------------------------------------
GOOD_AXIS = [0.0, 1e-5, 2e-5, 3e-5]
GOOD_HEIGHT = np.zeros((4, 4))
NOT_NUMBERS = [
    ("ragged height", GOOD_AXIS, GOOD_AXIS, [[0.0] * 4, [0.0] * 2, [0.0] * 4, [0.0] * 4], "height"),
    ("ragged x", [[0.0, 1e-5], [2e-5]], GOOD_AXIS, GOOD_HEIGHT, "coordinate x"),
    ("text x", ["a", "b", "c", "d"], GOOD_AXIS, GOOD_HEIGHT, "coordinate x"),
    ("numeric text y", GOOD_AXIS, ["0", "1e-5", "2e-5", "3e-5"], GOOD_HEIGHT, "coordinate y"),
    ("text height", GOOD_AXIS, GOOD_AXIS, np.full((4, 4), "1e-6"), "height"),
    ("complex height", GOOD_AXIS, GOOD_AXIS, GOOD_HEIGHT + 1e-9j, "height"),
    ("boolean height", GOOD_AXIS, GOOD_AXIS, np.ones((4, 4), dtype=bool), "height"),
    ("mixed height", GOOD_AXIS, GOOD_AXIS, [[0.0, "x", 0.0, 0.0]] + [[0.0] * 4] * 3, "height"),
    ("huge int height", GOOD_AXIS, GOOD_AXIS, [[10**400, 0, 0, 0]] + [[0] * 4] * 3, "height"),
    ("dates x", np.arange(4).astype("datetime64[D]"), GOOD_AXIS, GOOD_HEIGHT, "coordinate x"),
]


@pytest.mark.parametrize(("name", "x", "y", "height", "argument"), NOT_NUMBERS)
def test_a_height_map_of_non_numbers_is_a_surface_error_naming_the_argument(
    name, x, y, height, argument
):
    with pytest.raises(SurfaceError) as error:
        HeightMap(x, y, height, source="my map")
    assert error.type is SurfaceError
    message = str(error.value)
    assert "\n" not in message and message.startswith(f"my map: {argument} ")


@pytest.mark.parametrize(
    ("variable", "values"),
    [("x", np.array(["a"] * 12)), ("height", np.full((12, 12), "deep"))],
)
def test_a_netcdf_map_of_text_is_refused_naming_the_file_and_the_variable(
    tmp_path, variable, values
):
    x = np.linspace(-4e-4, 4e-4, 12)
    data = {"x": x, "y": x, "height": np.zeros((12, 12))}
    data[variable] = values
    path = tmp_path / "text.nc"
    xr.Dataset(
        {"height": (("y", "x"), data["height"])}, coords={"x": data["x"], "y": data["y"]}
    ).to_netcdf(path)
    with pytest.raises(SurfaceError) as error:
        read_surface({"file": str(path)})
    assert str(path) in str(error.value) and variable in str(error.value)
    with pytest.raises(SpecError) as error:
        Case.from_dict(_table(SPHERE, body2__surface=str(path)), read_surface)
    message = _refused(error, "body2.surface")
    assert str(path) in message and f"{variable} " in message


@pytest.mark.parametrize(
    ("table", "words"),
    [
        ({"file": 5}, "surface file: must be a file name"),
        ({"spacing": 1e-5}, "give one of file"),
        ({"file": "map.npy", "case": "case.nc"}, "give one of file"),
        ({"file": "{npy}", "spacing": "abc"}, "spacing must be"),
        ({"file": "{npy}", "spacing": [[1e-5, 1e-5]]}, "spacing must be"),
        ({"file": "{npy}", "spacing": 1e-5, "offset": {"x": 1.0}}, "offset must be"),
        ({"file": "{npy}", "spacing": 1e-5, "offset": (1e300, 0.0)}, "offset = [1e+300"),
    ],
)
def test_read_surface_refuses_bad_tables_in_one_line(tmp_path, table, words):
    npy = tmp_path / "map.npy"
    np.save(npy, np.zeros((8, 8)))
    table = {k: (str(npy) if v == "{npy}" else v) for k, v in table.items()}
    with pytest.raises(SurfaceError) as error:
        read_surface(table)
    assert error.type is SurfaceError
    message = str(error.value)
    assert "\n" not in message and words in message


def test_a_surface_offset_beyond_the_map_spacing_is_refused_naming_the_field(tmp_path):
    npy = tmp_path / "map.npy"
    np.save(npy, np.zeros((200, 200)))
    surface = {"file": str(npy), "spacing": 5e-6, "offset": [1e300, 0.0]}
    with pytest.raises(SpecError) as error:
        Case.from_dict(_table(SPHERE, body2__surface=surface), read_surface)
    message = _refused(error, "body2.surface")
    assert str(npy) in message and "offset" in message


def test_a_recorded_map_hash_that_is_not_text_is_refused(tmp_path):
    npy = tmp_path / "map.npy"
    np.save(npy, np.zeros((200, 200)))
    surface = {"file": str(npy), "spacing": 5e-6, "sha256": 12345}
    with pytest.raises(SpecError) as error:
        Case.from_dict(_table(SPHERE, body2__surface=surface), read_surface)
    assert "content hash" in _refused(error, "body2.surface.sha256")


# -- 4. a heights-only domain: the mean pressure over E* -----------------------------------------
@pytest.mark.parametrize("force", [1e300, 1e20, 1e-12])
def test_heights_only_force_out_of_the_pressure_range_is_refused(force):
    with pytest.raises(SpecError) as error:
        Case.from_dict(_table(FLAT, load={"normal_force": force}))
    message = _refused(error, "load.normal_force")
    low, high = (r * E_STAR * SIDE * SIDE for r in PRESSURE_RATIO_RANGE)
    assert f"W in [{low:.3g}, {high:.3g}] N" in message
    ratio = force / (SIDE * SIDE) / E_STAR
    assert _number_after(message, "W/(Lx Ly) =") == pytest.approx(ratio, rel=2e-3)


def test_heights_only_force_in_a_later_stage_names_that_stage():
    high = PRESSURE_RATIO_RANGE[1] * E_STAR * SIDE * SIDE
    path = [{"normal_force": 0.5}, {"normal_force": 0.99 * high}, {"normal_force": 1.01 * high}]
    with pytest.raises(SpecError) as error:
        Case.from_dict(_table(FLAT, load={"path": path}))
    _refused(error, "load.path[2].normal_force")
    Case.from_dict(_table(FLAT, load={"path": path[:2]}))  # under the bound it passes


# -- 5. the study-layer reader named where it lives ----------------------------------------------
def test_the_message_names_the_reader_where_it_lives(tmp_path):
    with pytest.raises(SpecError) as error:
        Case.from_dict(_table(SPHERE, body2__surface=str(tmp_path / "map.nc")))
    message = _refused(error, "body2.surface")
    named = re.search(r"read_surface=([\w.]+)\.read_surface", message)
    assert named and named.group(1) == "study.campaign.surfaces"
    assert hasattr(importlib.import_module(named.group(1)), "read_surface")


# -- 6. pairs and lists: one spelling ------------------------------------------------------------
SPELLINGS = (list, tuple, np.array)
ROLLING = {
    "body1": {"behaviour": "rigid", "radius": 0.015},
    "body2": {**STEEL, "radius": "inf"},
    "friction": {"coefficient": 0.3},
    "grid": {"n": 64},
}


def _spelled(spell) -> list[dict]:
    """Valid tables whose pairs and lists are written with ``spell``."""
    rolling = _table(
        ROLLING,
        load={"path": [
            {"normal_force": 60.0},
            {"roll": spell([1e-4, 0.0]), "creepage": spell([1e-3, -2e-4]), "steps": 2},
        ]},
        grid={"n": spell([64, 64])},
    )  # fmt: skip
    tangential = _table(
        ROLLING,
        load={"normal_force": 60.0, "tangential_force": spell([5.0, -2.0])},
        grid={"n": spell([64, 32, 16]), "size": spell([8e-4, 4e-4])},
        output={"fields": spell(["stress"])},
    )
    sliding = _table(
        ROLLING,
        load={"path": [{"normal_force": 60.0}, {"slide": spell([2e-5, 1e-5]), "steps": 2}]},
    )
    unloading = _table(
        ROLLING, load={"path": spell([{"normal_force": 60.0}, {"normal_force": 30.0}])}
    )
    return [rolling, tangential, sliding, unloading]


def test_a_list_a_tuple_and_an_array_give_the_same_case_id():
    ids = {}
    for spell in SPELLINGS:
        tables = _spelled(spell)
        if spell is np.array:  # a load path is a list of tables, not an array of numbers
            tables = tables[:3]
        ids[spell] = [Case.from_dict(table).case_id for table in tables]
    assert ids[list] == ids[tuple]
    assert ids[np.array] == ids[list][:3]
    assert len(set(ids[list])) == len(ids[list])


def test_a_map_offset_and_spacing_as_a_tuple_or_an_array_give_the_same_case_id(tmp_path):
    npy = tmp_path / "map.npy"
    np.save(npy, np.zeros((200, 200)))
    ids = set()
    for spell in SPELLINGS:
        surface = {"file": str(npy), "spacing": spell([5e-6, 5e-6]), "offset": spell([1e-6, 0.0])}
        ids.add(Case.from_dict(_table(SPHERE, body2__surface=surface), read_surface).case_id)
    surface = {"file": npy, "spacing": [5e-6, 5e-6], "offset": [1e-6, 0.0]}  # a path: its name
    ids.add(Case.from_dict(_table(SPHERE, body2__surface=surface), read_surface).case_id)
    assert len(ids) == 1


def test_a_roughness_object_is_its_table_and_checked_alike():
    rough = Roughness(ROUGH["hurst"], ROUGH["long_cutoff"], ROUGH["short_cutoff"], ROUGH["rms"])
    table = _table(FLAT, body2__roughness={**ROUGH, "seed": 0})
    expected = Case.from_dict(table).case_id
    assert Case.from_dict(_table(FLAT, body2__roughness=rough)).case_id == expected
    steep = Roughness(0.8, 2e-4, 2e-5, rms=1e-4)
    with pytest.raises(SpecError) as error:
        Case.from_dict(_table(FLAT, body2__roughness=steep))
    _refused(error, "body2.roughness.rms")
    with pytest.raises(SpecError) as error:
        Case.from_dict(_table(FLAT, body2__roughness=Roughness(2.0, 2e-4, 2e-5, rms=2e-7)))
    _refused(error, "body2.roughness.hurst")


#: (field, a bad value, words the message holds): strings, tables, 2-D arrays, wrong lengths.
BAD_PAIRS = [
    ("load.path[1].roll", "1e-4, 0", "must be [dx, dy] (m)"),
    ("load.path[1].roll", {"x": 1e-4}, "must be [dx, dy] (m)"),
    ("load.path[1].roll", np.zeros((2, 2)), "2-D array of shape (2, 2)"),
    ("load.path[1].roll", (1e-4, 0.0, 0.0), "got 3 entries"),
    ("load.path[1].creepage", np.array([[1e-3, 0.0]]), "2-D array"),
    ("load.path[1].creepage", {"xi": 1e-3}, "must be xi or [xi, eta]"),
    ("load.path[1].creepage", ([1e-3], [0.0]), "nested lists"),
    ("load.tangential_force", "5 N", "must be Q or [Qx, Qy] (N)"),
    ("load.tangential_force", np.ones((1, 2)), "2-D array"),
    ("grid.size", np.full((2, 1), 8e-4), "2-D array"),
    ("grid.size", "8e-4", "must be L or [Lx, Ly] (m)"),
    ("grid.n", "64", "must be an integer or [nx, ny]"),
    ("grid.n", np.array([[64, 64]]), "2-D array"),
    ("output.fields", "stress", "must be a list drawn from"),
    ("output.fields", ("stress", ["stress"]), "nested lists"),
]


@pytest.mark.parametrize(("field", "value", "words"), BAD_PAIRS)
def test_a_bad_pair_is_refused_naming_the_field(field, value, words):
    if field.startswith("load.path[1]"):
        stage = {"roll": [1e-4, 0.0], "creepage": [1e-3, 0.0], "steps": 2}
        stage[field.rsplit(".", 1)[1]] = value
        table = _table(ROLLING, load={"path": [{"normal_force": 60.0}, stage]})
    elif field == "load.tangential_force":
        table = _table(ROLLING, load={"normal_force": 60.0, "tangential_force": value})
    elif field == "output.fields":
        table = _table(ROLLING, load={"normal_force": 60.0}, output={"fields": value})
    else:
        grid = {"n": 64, field.split(".")[1]: value}
        table = _table(ROLLING, load={"normal_force": 60.0}, grid=grid)
    with pytest.raises(SpecError) as error:
        Case.from_dict(table)
    assert words in _refused(error, field)


# -- the command line: status 2 and one line -----------------------------------------------------
def _validate(tmp_path: Path, text: str) -> subprocess.CompletedProcess:
    path = tmp_path / "campaign.toml"
    path.write_text(text)
    return subprocess.run(
        [sys.executable, "-m", "study", "validate", str(path)],
        capture_output=True,
        text=True,
        cwd=REPO,
        timeout=120,
    )


CAMPAIGN = """
[campaign]
name = "first_use"

[base]
body1 = {{ behaviour = "rigid"{body1} }}
body2 = {{ behaviour = "elastic", radius = "inf", E = 210e9, nu = 0.3{body2} }}
load = {{ normal_force = {force} }}
grid = {grid}

[sweep]
"friction.coefficient" = [0.0, 0.2]
"""


def _one_line_error(done: subprocess.CompletedProcess, words: str) -> None:
    assert done.returncode == 2, (done.stdout, done.stderr)
    assert done.stdout == "" and "Traceback" not in done.stderr
    assert done.stderr.startswith("error: ") and done.stderr.count("\n") == 1, done.stderr
    assert words in done.stderr, done.stderr


def test_command_line_refuses_a_steep_map_file_with_status_2(tmp_path, unit_map):
    x, _, height, slope = unit_map
    npy = tmp_path / "steep.npy"
    np.save(npy, height * (5 * MAX_SURFACE_SLOPE / slope))
    body2 = f', surface = {{ file = "{npy.name}", spacing = {float(x[1] - x[0])!r} }}'
    text = CAMPAIGN.format(body1=", radius = 0.015", body2=body2, force=60.0, grid="{ n = 64 }")
    done = _validate(tmp_path, text)
    _one_line_error(done, "body2.surface")
    assert "steep.npy" in done.stderr and "rms slope" in done.stderr


def test_command_line_refuses_steep_roughness_and_a_huge_heights_only_force(tmp_path):
    rough = ", roughness = { rms = 1e-4, hurst = 0.8, long_cutoff = 2e-4, short_cutoff = 2e-5 }"
    text = CAMPAIGN.format(body1=", radius = 0.015", body2=rough, force=60.0, grid="{ n = 64 }")
    _one_line_error(_validate(tmp_path, text), "body2.roughness.rms")
    rough = rough.replace("1e-4", "2e-7")
    grid = f"{{ n = 64, size = {SIDE!r} }}"
    text = CAMPAIGN.format(body1="", body2=rough, force="1e300", grid=grid)
    _one_line_error(_validate(tmp_path, text), "load.normal_force: W = 1e+300 N")
