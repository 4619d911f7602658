"""The contact law's state on the hysteresis loop of a periodic orbit.

A monodromy matrix starts from a point of the periodic orbit, and for a law
with memory (Jenkins, the modified Dahl) that point includes the law's
state: the slider position, the force on the loop. Starting the law virgin
at the start's displacement puts it off the loop; the time integration then
forgets that start only at the rate of the slowest Floquet multiplier
(about 0.93 per period on a lightly damped structure, so tens of periods).
Marching the law along the orbit's own displacement history, sampled as the
integrator samples it, puts the state on the loop at once (after one pass
for a loop that slips; a contact that never slips keeps the virgin state,
which is the harmonic balance's convention for a stuck contact).
"""

import numpy as np

from .._jit import jit
from ..kernels.laws.updates import law_init, law_step


@jit
def loop_state(code, params, coordinate, loops, state):
    """March a 1D contact law around a periodic displacement history.

    Parameters
    ----------
    code : int
        Law code (:mod:`hbmfric.kernels.laws.updates`).
    params : ndarray, shape (n_params,)
        Law parameters.
    coordinate : ndarray, shape (n_samples,)
        The contact coordinate at the instants ``t_i = i T / n_samples`` of
        one period, m.
    loops : int
        Periods marched (2 is enough for Jenkins and the modified Dahl law;
        a second loop checks that the first closed).
    state : ndarray, shape (state_size(code, params),)
        Output: the law state at ``t_0`` after ``loops`` periods
        (``state[0]`` the force, N).

    Returns
    -------
    float
        The force at ``t_0`` after the last period minus the one before
        (0 on a closed loop), N.
    """
    n = coordinate.size
    law_init(code, params, coordinate[0], state)
    before = state[0]
    u_prev = coordinate[0]
    for _ in range(loops):
        before = state[0]
        for i in range(1, n + 1):
            u = coordinate[i % n]
            law_step(code, params, state, u_prev, u, np.bool_(True))
            u_prev = u
    return state[0] - before
