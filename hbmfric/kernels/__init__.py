"""Numba kernels: flat arrays and scalars in, arrays and status codes out.

One folder per stage of a harmonic-balance step:

* :mod:`~hbmfric.kernels.fourier` — discrete Fourier operators and Fourier
  integrals over pieces of the period;
* :mod:`~hbmfric.kernels.linalg` — dense LU and the linear first-harmonic
  response;
* :mod:`~hbmfric.kernels.laws` — contact laws as time-domain updates
  (the law contract, integer codes);
* :mod:`~hbmfric.kernels.aft` — alternating frequency–time schemes: the
  sampled march, Jenkins with located events, Masing laws with located
  reversals, the modified Dahl law, the 2D contact element;
* :mod:`~hbmfric.kernels.dlft` — dynamic Lagrangian frequency–time for the
  rigid Coulomb contact;
* :mod:`~hbmfric.kernels.residuals` — harmonic-balance residuals and
  Jacobians, full and condensed onto the contact coordinates, and the one
  entry point the Newton kernels call;
* :mod:`~hbmfric.kernels.steps` — the continuation step: corrector,
  tangent, acceptance rules, truncation estimate;
* :mod:`~hbmfric.kernels.stability` — Hill's Jacobians along a branch and
  determinant signs.

A folder imports only from folders above it in this list (checked by
``tests/test_import.py``).
"""
