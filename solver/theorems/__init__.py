"""Shakedown theorems solved directly: Melan's static limit of a load passing along a track.

- :mod:`.residual`: every residual stress field that does not change along the track (Prandtl
  and Airy stress functions on the cross-section);
- :mod:`.melan`: the static theorem as a second-order cone program (Clarabel), its certified
  factor, the pointwise upper bound;
- :mod:`.koiter`: the kinematic theorem: the best mechanism (six-node triangles on the
  cross-section, the plastic strain rates released at the load's positions) gives an upper
  bound that converges to the limit from above;
- :mod:`.track`: a Hertz point or line contact sliding along a track: the static limit, the
  upper bounds beside it, first yield and surface flow;
- :mod:`.loads`: any tractions given on cells passing along x (an elliptical Hertz contact, a
  solved case's pressure), through the subsurface stress operator.

Imports: :mod:`solver.volume` (the traction stresses), :mod:`solver.theory` (the closed-form
elastic fields, first yield), :mod:`solver.numerics` and the declarations; scipy, clarabel.
"""
