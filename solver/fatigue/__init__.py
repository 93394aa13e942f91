"""Multiaxial high-cycle fatigue on the stress paths of repeated contact.

- :mod:`.ball`: the smallest ball enclosing each of many point sets (a deviatoric stress
  path's hypersphere), by Frank and Wolfe's method with away steps, certified by its gap;
- :mod:`.criteria`: Dang Van's and Crossland's criteria of stress paths, their parameters from
  the fully reversed bending and torsion limits, the factors of safety.

Imports: :mod:`solver.numerics` (the tensor convention).
"""
