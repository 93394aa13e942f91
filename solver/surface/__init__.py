"""Contact on the surface: influence coefficients, DC-FFT, the normal and tangential solvers.

- :mod:`.influence`: the influence coefficients of a pair of half-spaces (uniform cells);
- :mod:`.convolution`: the DC-FFT surface operators built on them;
- :mod:`.periodic`: the operators of a surface that is one period (Fourier-space forms);
- :mod:`.normal`: normal contact, conjugate gradient with an active set (the contact CG loop);
- :mod:`.tangential`: tangential contact at a given pressure, slip and stick;
- :mod:`.steady`: steady rolling at a given pressure (Kalker's steady slip, upwind
  differences, a semi-smooth Newton method).

Imports: :mod:`solver.bodies`, :mod:`solver.theory`, :mod:`solver.numerics` and the
declarations.  A new surface solver goes here.
"""
