"""Multiaxial high-cycle fatigue on the stress paths of repeated contact.

- :mod:`.ball`: the smallest ball enclosing each of many point sets (a deviatoric stress
  path's hypersphere), exact, by farthest-point insertion into its support;
- :mod:`.criteria`: Dang Van's and Crossland's criteria of stress paths, their parameters from
  the fully reversed bending and torsion limits, the factors of safety; a steady pass's
  criteria from one snapshot of the moving load's field;
- :mod:`.hertz_pass`: the criteria of a Hertz contact passing over a half-space from the
  closed-form fields (Hamilton; McEwen): the reference of a solved pass.

Imports: :mod:`solver.numerics` (the tensor convention), :mod:`solver.theory` (the
closed-form fields).
"""
