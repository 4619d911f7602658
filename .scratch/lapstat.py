import numpy as np, hbmfric as hf, warnings, time
s = hf.lap_joint(10)
M, C, K = s.matrices()
load = np.asarray(s.load) if hasattr(s, "load") else None
print("contacts", len(s.contacts), "load", getattr(s, "load", None) is not None)
Fex = 0.72
for P0 in (0.0, 50.0):
    t = hf.LinearStructure(M, K, C, contacts=list(s.contacts), load={0: 1.0}, static_load={1: P0} if P0 else None)
    for omega in (800.0, 1100.0, 1400.0):
        with warnings.catch_warnings(record=True) as w:
            warnings.simplefilter("always")
            a = hf.periodic_solution(t, Fex, omega, harmonics=5, symmetry=False)
            b = hf.periodic_solution(t, Fex, omega, harmonics=5, symmetry=False, condense=False)
        err = np.max(np.abs(a.coefficients - b.coefficients))/np.max(np.abs(b.coefficients))
        print(P0, omega, f"{err:.1e}", a.converged, b.converged, sorted(set(str(x.message)[:60] for x in w)), flush=True)
