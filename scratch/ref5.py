import warnings
import numpy as np
import hbmfric as hf
V = hf.validation
for zeta in (1e-2, 1e-3, 1e-4):
    c = 2*zeta*2.0  # stuck: k_eff = 4, m = 1, w0 = 2
    osc = hf.Oscillator(1.0, c, 1.0, contact=hf.Jenkins(3.0, 1.0))
    F = 1e-3 * zeta / 1e-2
    for w in (2.0*(1-zeta), 2.0, 2.0*(1+zeta), 1.0, 3.0):
        exact = F / abs(4 - w**2 + 1j*c*w)
        with warnings.catch_warnings(record=True) as ws:
            warnings.simplefilter("always")
            r = V.steady_state(osc, F, w)
            rl = V.steady_state(osc, F, w, initial_state="linear", check_halving=True)
        ex = V.exact_periodic_solution(osc, F, w)
        print(f"zeta {zeta:g} w {w:.5f}: exact {exact:.6e} (exact ref {ex.amplitude(1)/exact-1:+.1e}) ss {r.amplitude(1)/exact-1:+.2e} conv {r.converged} p {r.periods}  ss-lin {rl.amplitude(1)/exact-1:+.2e} est {rl.error_estimate:.1e} maxf {np.max(np.abs(r.contact_force)):.2g} W{len(ws)}", flush=True)
