"""Contact laws as time-domain updates, selected by integer codes.

Every law is a pure function of its flat parameter array, its previous force
and the displacement increment: ``law_update(code, params, f_prev, u_prev, u)``
returns the new force and its partial derivatives. The AFT march and the
time-integration reference both call this one function, so the two paths
share the law definitions instead of re-typing them.

Law codes and their parameter arrays
------------------------------------
``JENKINS`` (Masing macroslip): ``params = [tangential_stiffness, slip_force]``
    A spring ``kt`` in series with a Coulomb slider (slip force ``f_s``).
    Predictor ``f = f_prev + kt (u - u_prev)``, then ``|f| <= f_s``.
``CUBIC`` (smooth, memoryless): ``params = [coefficient]``
    ``f = k3 u**3``.
``DAHL`` (modified Dahl restoring force): ``params = [β, μ, a, b, d, e]``
    Rate-independent relaxation towards the envelopes ``h_u = a u + b``
    (loading) and ``h_l = d u + e`` (unloading); see
    :mod:`hbmfric.kernels.dahl`.
"""

from .._jit import jit
from .dahl import dahl_update

JENKINS = 0
CUBIC = 1
DAHL = 2

#: laws whose force depends on the displacement history
HYSTERETIC = (JENKINS, DAHL)

STICK = 0
SLIP = 1


@jit
def law_update(code, params, f_prev, u_prev, u):
    """Advance a contact law from ``u_prev`` to ``u``.

    Parameters
    ----------
    code : int
        Law code (``JENKINS``, ``CUBIC``).
    params : ndarray, shape (n_params,)
        Law parameters, see the module docstring.
    f_prev : float
        Force at ``u_prev``, N (ignored by memoryless laws).
    u_prev, u : float
        Relative displacement before and after the increment, m.

    Returns
    -------
    f : float
        Force at ``u``, N.
    df_dfprev, df_duprev, df_du : float
        Partial derivatives of ``f`` with respect to ``f_prev``, ``u_prev``
        and ``u``; they drive the analytic AFT Jacobian.
    """
    if code == JENKINS:
        kt = params[0]
        slip_force = params[1]
        trial = f_prev + kt * (u - u_prev)
        if trial > slip_force:
            return slip_force, 0.0, 0.0, 0.0
        if trial < -slip_force:
            return -slip_force, 0.0, 0.0, 0.0
        return trial, 1.0, -kt, kt
    if code == DAHL:
        return dahl_update(params, f_prev, u_prev, u)
    # CUBIC
    k3 = params[0]
    return k3 * u * u * u, 0.0, 0.0, 3.0 * k3 * u * u


@jit
def linear_stiffness(code, params):
    """Tangent stiffness of the law at rest (stuck contact), N/m."""
    if code == JENKINS:
        return params[0]
    if code == DAHL:
        # small-loop stiffness at u = 0: β ((b - e) / 2)^μ
        return params[0] * max(0.5 * (params[3] - params[5]), 0.0) ** params[1]
    return 0.0
