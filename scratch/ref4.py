import time, warnings, sys
import numpy as np
import hbmfric as hf
V = hf.validation
warnings.simplefilter("ignore")
n = 3
K = 1.0 * (2*np.eye(n) - np.eye(n, k=1) - np.eye(n, k=-1)); K[-1,-1] = 1.0
kt, zeta, w, F = float(sys.argv[1]), float(sys.argv[2]), float(sys.argv[3]), float(sys.argv[4])
s3 = hf.LinearStructure(np.eye(n), K, modal_damping=zeta, load={0: 1.0}, contact=hf.Jenkins(kt, 1.0), contact_dof=2)
ex = V.exact_periodic_solution(s3, F, w)
a = ex.amplitude(1)
print("exact", a, ex.residual, [ex.amplitude(1, dof=d) for d in range(3)])
print(ex)
for N in (2048, 8192, 32768):
    for init in ("linear", None):
        r = V.steady_state(s3, F, w, initial_state=init, steps_per_period=N)
        print(N, init, r.amplitude(1)/a-1, r.converged, r.periods, [r.amplitude(1, dof=d) for d in range(3)], flush=True)
sol = hf.periodic_solution(s3, F, w, harmonics=63)
print("hbm63", sol.amplitude(1)/a-1, sol.converged)
