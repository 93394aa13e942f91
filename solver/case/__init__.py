"""The case: its tables parsed and checked, its grid sized, its notes written, the :class:`Case`.

One module per table of a case file, each with the parser of that table:

- :mod:`.reading`: :class:`SpecError` and the checks every parser shares;
- :mod:`.bodies`: ``[body1]``, ``[body2]`` (shape, height map, roughness, hardening);
- :mod:`.path`: ``[load]``: the load path, its stages, cycles, motion and creepage;
- :mod:`.friction`: ``[friction]``: Coulomb's coefficient and the shear limit that caps it;
- :mod:`.wear`: ``[wear]``: the wear law and each body's coefficient, the cycle jump;
- :mod:`.fatigue`: ``[fatigue]``: body 2's fatigue limits, and the passes the criteria read;
- :mod:`.substeps`: the load sub-steps of coupled scenes, for the solve and its cost;
- :mod:`.grid`: ``[grid]`` and the resolution checks;
- :mod:`.options`: ``[solver]`` and ``[output]``;
- :mod:`.batch`: the case id, and the sub-tables a batch of cases from one base shares;
- :mod:`.sizing`: the window, depth and plastic box a case without them gets;
- :mod:`.notes`: every note a case carries and the plastic regimes it refuses;
- :mod:`.volume`: an open case's window, depths and plastic box sized, its volume grids checked;
- :mod:`.case`: :class:`Case`, which holds the validated values and the quantities derived
  from them.

Imports: every package below (a trial elastic solve sizes the plastic box) and the
declarations; inside, the order above.  A new key is declared in :mod:`solver.keys` and parsed
by the module of its table; a new kind of load stage goes in :mod:`.path`.
"""
