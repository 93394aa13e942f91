"""What the contacting bodies are: shapes, height maps, elastic constants, Dundurs' beta.

- :mod:`.geometry`: quadrics and axisymmetric profiles (cone, flat punch, power law), the gap;
- :mod:`.heights`: surfaces given point by point: height maps and self-affine roughness;
- :mod:`.materials`: a body (behaviour, constants, shape, hardening) and a pair's composite
  constants;
- :mod:`.dundurs`: body 1's elastic constants for a given Dundurs beta (a design variable).

Imports: :mod:`solver.plasticity` (a body's hardening law), :mod:`solver.theory`,
:mod:`solver.numerics` and the declarations.  A new body shape goes in :mod:`.geometry` (or
:mod:`.heights` for one given point by point), its table in :mod:`solver.case.bodies`.
"""
