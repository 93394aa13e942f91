"""Below the surface: the stress of the tractions and the eigenstrain (plastic strain) operator.

- :mod:`.stress`: the layer kernels and the FFT operator of the tractions' stresses;
- :mod:`.plane_strain`: a line contact's (plane-strain) stresses, 1-D per layer;
- :mod:`.cuboid`: a uniform eigenstrain in a cuboid (Chiu's closed forms);
- :mod:`.eigenstrain`: residual stress and surface displacement of a plastic strain field;
- :mod:`.eigenstrain_kernels`: its kernel spectra (Chiu's source and image cuboids, the
  per-layer surface kernels);
- :mod:`.eigenstrain_convolution`: its FFT convolution (per-layer 2-D transforms, the
  symmetric depth convolution by row blocks).

Imports: :mod:`solver.surface` (the surface cell integrals), :mod:`solver.theory`,
:mod:`solver.numerics` and the declarations.
"""
