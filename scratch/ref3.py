import time, warnings, sys
import numpy as np
import hbmfric as hf
V = hf.validation
warnings.simplefilter("ignore")
n = 3
K = 1.0 * (2*np.eye(n) - np.eye(n, k=1) - np.eye(n, k=-1)); K[-1,-1] = 1.0
for kt in (1e2, 1e4):
  for zeta in (0.01, 0.001):
    s3 = hf.LinearStructure(np.eye(n), K, modal_damping=zeta, load={0: 1.0}, contact=hf.Jenkins(kt, 1.0), contact_dof=2)
    for w in (0.3, 0.6, 1.2, 1.6):
      for F in (1.0, 3.0):
        try:
            ex = V.exact_periodic_solution(s3, F, w, on_failure="raise")
        except Exception as e:
            print(kt, zeta, w, F, "exact failed", e); continue
        a = ex.amplitude(1)
        r = V.steady_state(s3, F, w, initial_state="linear", check_halving=True)
        print(f"kt {kt:g} z {zeta} w {w} F {F}: a {a:.4e} err2048 {r.amplitude(1)/a-1:+.2e} est {r.error_estimate:.1e} conv {r.converged} p {r.periods}", flush=True)
