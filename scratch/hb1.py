import warnings, sys, time
import numpy as np
import hbmfric as hf
V = hf.validation
n = 3
K = 1.0 * (2*np.eye(n) - np.eye(n, k=1) - np.eye(n, k=-1)); K[-1,-1] = 1.0
kt, zeta, w, F = float(sys.argv[1]), float(sys.argv[2]), float(sys.argv[3]), float(sys.argv[4])
s3 = hf.LinearStructure(np.eye(n), K, modal_damping=zeta, load={0: 1.0}, contact=hf.Jenkins(kt, 1.0), contact_dof=2)
ex = V.exact_periodic_solution(s3, F, w)
a = [ex.amplitude(1, dof=d) for d in range(3)]
hpp = [ex.amplitude(None, dof=d) for d in range(3)]
for H in (7, 15, 31, 63, 127, "auto"):
    with warnings.catch_warnings(record=True) as ws:
        warnings.simplefilter("always")
        t = time.process_time()
        sol = hf.periodic_solution(s3, F, w, harmonics=H)
        dt = time.process_time() - t
    print(H, sol.harmonic_numbers.max() if hasattr(sol,'harmonic_numbers') else '', "err a1", ["%.1e" % (sol.amplitude(1, dof=d)/a[d]-1) for d in range(3)],
          "err pp", ["%.1e" % (sol.amplitude(None, dof=d)/hpp[d]-1) for d in range(3)], "est", getattr(sol, "truncation_error", None), f"{dt:.1f}s", [str(x.message)[:150] for x in ws], flush=True)
