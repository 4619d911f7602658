import time, warnings, sys
import numpy as np
import hbmfric as hf
V = hf.validation
osc = hf.Oscillator(1.0, 0.02, 1.0, contact=hf.Jenkins(1e4, 1.0))
F, w = 2.0, 0.1
ex = V.exact_periodic_solution(osc, F, w)
a = ex.amplitude(1)
_, f = ex.contact_force(n=200000)
print("exact", a, "max|f|", np.max(np.abs(f)), ex.residual)
for N in (2048, 8192, 32768, 131072):
    t = time.process_time()
    r = V.steady_state(osc, F, w, steps_per_period=N, initial_state="linear")
    print(N, r.amplitude(1), r.amplitude(1)/a-1, r.converged, r.periods, f"{time.process_time()-t:.1f}s", flush=True)
