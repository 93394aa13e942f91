"""The constitutive laws of an elastic-plastic body: hardening and the return mapping.

- :mod:`.hardening`: Swift, linear and perfect hardening, a Prager or Armstrong-Frederick back
  stress, the largest shear a law carries;
- :mod:`.return_mapping`: von Mises radial return, point by point (the innermost loop).

Imports: :mod:`solver.numerics`, :mod:`solver.theory` and the declarations.  The plasticity
loop, which wraps a contact step, is a loop of the driver (:mod:`solver.drive.plastic_loop`); a
new hardening law goes in :mod:`.hardening` (and its keys in :mod:`solver.keys`).
"""
