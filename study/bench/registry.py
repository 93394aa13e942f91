"""The benchmark scenes by name: ``python -m study bench SCENE`` dispatches here.

The top of :mod:`study.bench`: :data:`SCENES` names each scene's runner (a module of its own
below, on the helpers of :mod:`.timing`), imported only when it runs.
"""

from __future__ import annotations

import importlib

#: Scene -> (module, runner, the options it takes of ``peers``, ``repeat``, ``error``,
#: ``periodic``, ``incremental``, ``steady``, ``shapes`` and ``travel``).
SCENES = {
    "hertz": ("hertz", "run_hertz", ("peers", "repeat")),
    "cattaneo": ("cattaneo", "run_cattaneo", ("peers", "repeat")),
    "plastic": ("plastic", "run_plastic", ("peers", "error")),
    "slipstick": ("slipstick", "run_slipstick", ()),
    "cycles": ("cycles", "run_cycles", ()),
    "rough": ("rough", "run_rough", ("peers", "periodic", "error")),
    "moving": ("moving", "run_moving", ("periodic", "travel")),
    "rolling": ("rolling", "run_rolling", ("peers", "steady", "shapes", "repeat")),
    "shakedown": ("shakedown", "run_shakedown", ("incremental",)),
    "hard": ("hard_cases", "run_hard", ()),
    "wear": ("wear", "run_wear", ()),
    "fatigue": ("fatigue", "run_fatigue", ()),
}


class BenchOptionError(ValueError):
    """An option the scene does not take (told as one line by ``python -m study bench``)."""


DEFAULT_SIZES = {
    "hertz": [64, 128, 256, 512],
    "cattaneo": [64, 128, 256],
    "plastic": [32, 64],
    "slipstick": [64, 128],
    "cycles": [32, 64, 128],
    "rough": [128, 256],
    "rough --periodic": [32, 64, 128],
    "moving": [16, 32],
    "moving --periodic": [64, 128, 256],
    "rolling": [32, 64],
    "shakedown": [],  # the campaign fixes the cases
    "hard": [16, 24, 32],  # the limit's refinement (the scenes' meshes are fixed)
    "wear": [32],
    "fatigue": [64, 96, 128],
}


def run_benchmark(
    scene: str,
    sizes: list[int] | None = None,
    peers: bool = False,
    repeat: int = 3,
    error: bool = False,
    periodic: bool = False,
    incremental: bool = False,
    steady: bool = False,
    shapes: list[float] | None = None,
    travel: float | None = None,
) -> int:
    """Run a benchmark scene, print its table, and return an exit status."""
    module, runner, takes = SCENES[scene]
    if repeat < 1:
        raise BenchOptionError(f"--repeat: give 1 or more timing repetitions, got {repeat}")
    if error and "error" not in takes:
        raise BenchOptionError(
            f"--error: scene {scene!r} has no error table (only plastic and rough --periodic)"
        )
    if periodic and "periodic" not in takes:
        raise BenchOptionError(
            f"--periodic: scene {scene!r} has no periodic form (only rough and moving)"
        )
    run = getattr(importlib.import_module(f"{__package__}.{module}"), runner)
    if incremental and "incremental" not in takes:
        raise BenchOptionError(f"--incremental: scene {scene!r} has no such run (only shakedown)")
    if steady and "steady" not in takes:
        raise BenchOptionError(f"--steady: scene {scene!r} has no steady form (only rolling)")
    if shapes and "shapes" not in takes:
        raise BenchOptionError(f"--shapes: scene {scene!r} has one contact (only rolling has more)")
    if travel is not None and not ("travel" in takes and periodic):
        raise BenchOptionError("--travel: only moving --periodic slides a rough pass")
    options = {
        "peers": peers, "repeat": repeat, "error": error, "periodic": periodic,
        "incremental": incremental, "steady": steady, "shapes": shapes, "travel": travel,
    }  # fmt: skip
    default = DEFAULT_SIZES[f"{scene} --periodic" if periodic else scene]
    return run(sizes or default, **{k: options[k] for k in takes})
