"""Benchmarks: speed against error, ours and the peers' in the same run.

The package: :mod:`.timing` (isolated child processes, peak memory, tables) at the bottom; one
module per scene on it (:mod:`.hertz`, :mod:`.cattaneo`, :mod:`.slipstick`, :mod:`.cycles`,
:mod:`.plastic`, :mod:`.subsurface`); the peer adapters :mod:`.peers` and
:mod:`.peers_plastic`; the registry :mod:`.registry` on top
(``python -m study bench SCENE [--peers]``).
"""

from .registry import DEFAULT_SIZES, SCENES, run_benchmark

__all__ = ["DEFAULT_SIZES", "SCENES", "run_benchmark"]
