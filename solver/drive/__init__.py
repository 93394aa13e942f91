"""The driver: operators built once per case, contact steps, the plasticity loop, the load path.

- :mod:`.operators`: the bundle of surface, stress and eigenstrain operators of a case;
- :mod:`.steps`: one load increment of the contact problem: normal, slip-stick or sliding;
- :mod:`.plastic_loop`: the plasticity loop around any contact step;
- :mod:`.window`: the window that follows a moving contact over body 2's track;
- :mod:`.wear`: the worn surfaces of a case that wears, fed back into the gap (and the
  automatic cycle jump);
- :mod:`.fatigue`: body 2's fatigue criteria under a steady pass, its track's residual stress;
- :mod:`.record`: the histories, fields and notes a solve records;
- :mod:`.loops`: :func:`~.loops.solve`, the load-path driver that runs the loops a scene needs;
- :mod:`.theorem`: a case solved by Melan's theorem on its sliding track instead of its path
  (``solver.method = "static_shakedown"``).

Imports: everything below (:mod:`solver.result` included).  A new loop or a new kind of step
goes here: a step in :mod:`.steps`, a loop around it beside :mod:`.plastic_loop`, its histories
declared in :mod:`solver.variables` and recorded in :mod:`.record`.
"""
