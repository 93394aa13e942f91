"""Closed forms: the references the numerics are checked against, and the rules they use.

- :mod:`.hertz`: Hertz contact (circular, elliptic), its subsurface yield and first yield;
- :mod:`.friction`: Cattaneo-Mindlin, Mindlin-Deresiewicz, Kalker's linear creep;
- :mod:`.line`: line contact (plane strain): Hertz's cylinder, Carter's steady rolling;
- :mod:`.sneddon`: frictionless axisymmetric profiles (Sneddon 1965);
- :mod:`.half_space`: half-space stresses of surface loads: Love's rectangle, Boussinesq and
  Cerruti point forces, Hamilton's sliding Hertz contact;
- :mod:`.wear`: the limit of fretting wear in partial slip (Ciavarella and Hills);
- :mod:`.mdr`: gross-slip wear of an axisymmetric contact by the method of dimensionality
  reduction (Popov and Heß);
- :mod:`.shakedown`: shakedown classification of cyclic results, Melan's bound, first yield in
  sliding.

Imports: :mod:`solver.numerics` and the declarations.  A new closed form goes here, with a test
that compares the numerics with it.
"""
