"""First-harmonic response of the linear structure, compiled.

Used for the displacement scale of a continuation run and for the linear
starting guesses (:meth:`hbmfric.hbm.HBMProblem.linear_response`), once per
run: a NumPy version costs about 0.1 ms per call in array overhead on a
one-DOF system, as much as a few continuation steps.
"""

import numpy as np

from ..._jit import jit
from .lu import solve_inplace


@jit
def first_harmonic_response(omegas, mass, damping, stiffness, load_cos, load_sin, out):
    """Solve ``(K - Ω² M + iΩ C) x = p`` at every ``Ω`` of ``omegas``.

    The complex system of ``n`` equations is solved as the real one of
    ``2n`` (real and imaginary parts), by LU with partial pivoting.

    Parameters
    ----------
    omegas : ndarray, shape (n_omega,)
        Pulsations, rad/s.
    mass, damping, stiffness : ndarray, shape (n, n)
        ``M`` (kg), ``C`` (N s/m), ``K`` (N/m).
    load_cos, load_sin : ndarray, shape (n,)
        Load ``p_c cos Ωt + p_s sin Ωt``, N.
    out : ndarray, shape (n_omega, 2, n)
        Out: cosine and sine coefficients of ``x(t)``, m; zero where the
        dynamic stiffness is singular.

    Returns
    -------
    int
        Number of frequencies at which the dynamic stiffness is singular.
    """
    n = mass.shape[0]
    A = np.empty((2 * n, 2 * n))
    b = np.empty(2 * n)
    singular = 0
    for q in range(omegas.size):
        w = omegas[q]
        # x = a cos + b sin: (K - w²M) a + w C b = p_c, -w C a + (K - w²M) b = p_s
        for i in range(n):
            for j in range(n):
                d = stiffness[i, j] - w * w * mass[i, j]
                v = w * damping[i, j]
                A[i, j] = d
                A[i, n + j] = v
                A[n + i, j] = -v
                A[n + i, n + j] = d
            b[i] = load_cos[i]
            b[n + i] = load_sin[i]
        if solve_inplace(A, b):
            for i in range(n):
                out[q, 0, i] = b[i]
                out[q, 1, i] = b[n + i]
        else:
            singular += 1
            for i in range(n):
                out[q, 0, i] = 0.0
                out[q, 1, i] = 0.0
    return singular
