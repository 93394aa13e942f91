"""Contact on the surface: influence coefficients, DC-FFT, the normal and tangential solvers.

- :mod:`.influence`: the influence coefficients of a pair of half-spaces (uniform cells);
- :mod:`.convolution`: the DC-FFT surface operators built on them;
- :mod:`.periodic`: the operators of a surface that is one period (Fourier-space forms);
- :mod:`.normal`: normal contact, conjugate gradient with an active set (the contact CG loop);
- :mod:`.tangential`: tangential contact at a given pressure, slip and stick.

Imports: :mod:`solver.bodies`, :mod:`solver.theory`, :mod:`solver.numerics` and the
declarations.  A new surface solver (a periodic operator, a steady-rolling solver) goes here.
"""
