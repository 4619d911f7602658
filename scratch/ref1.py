import time, warnings, sys
import numpy as np
import hbmfric as hf
V = hf.validation
warnings.simplefilter("always")
cases = []
osc = lambda kt, c=0.02: hf.Oscillator(1.0, c, 1.0, contact=hf.Jenkins(kt, 1.0))
cases.append(("sdof kt3 F.5 w1.2", osc(3.0), 0.5, 1.2))
cases.append(("sdof kt3 F2 w1.5", osc(3.0), 2.0, 1.5))
cases.append(("sdof kt1e3 F2 w3", osc(1e3), 2.0, 3.0))
cases.append(("sdof kt1e4 F2 w1", osc(1e4), 2.0, 1.0))
cases.append(("sdof kt1e4 F2 w0.1", osc(1e4), 2.0, 0.1))
n = 3
K = 1.0 * (2*np.eye(n) - np.eye(n, k=1) - np.eye(n, k=-1)); K[-1,-1] = 1.0
s3 = hf.LinearStructure(np.eye(n), K, modal_damping=0.01, load={0: 1.0}, contact=hf.Jenkins(100.0, 1.0), contact_dof=2)
cases.append(("chain3 kt100 F1 w0.6", s3, 1.0, 0.6))
cases.append(("chain3 kt100 F1 w1.6", s3, 1.0, 1.6))
for name, sysm, F, w in cases:
    t = time.process_time()
    ex = V.exact_periodic_solution(sysm, F, w)
    te = time.process_time() - t
    a_ex = ex.amplitude(1)
    row = [name, f"exact {a_ex:.10g} res {ex.residual:.1e} ({te:.1f}s)"]
    for N in (512, 2048, 8192):
        t = time.process_time()
        with warnings.catch_warnings(record=True) as ws:
            warnings.simplefilter("always")
            r = V.steady_state(sysm, F, w, steps_per_period=N, initial_state="linear")
        row.append(f"N{N}: {r.amplitude(1)/a_ex-1:+.2e} conv={r.converged} p={r.periods} ({time.process_time()-t:.1f}s){' W' if ws else ''}")
    print(" | ".join(row), flush=True)
