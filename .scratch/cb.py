import numpy as np, hbmfric as hf, warnings, time
warnings.simplefilter("ignore", hf.AccuracyWarning)
n = 20
K = np.zeros((n, n))
for i in range(n):
    K[i, i] += 1.0
    if i + 1 < n: K[i, i] += 1.0; K[i, i+1] = K[i+1, i] = -1.0
K *= 100.0
el = hf.Contact2D(tangential_stiffness=50.0, normal_stiffness=200.0, friction_coefficient=0.3, preload=0.5)
names = {"t1": 5, "n1": 6, "t2": 12, "n2": 13, "tip": 19}
s = hf.LinearStructure(np.eye(n), K, rayleigh=(0.01, 1e-4), contacts=[hf.Contact(el, "t1", normal="n1"), hf.Contact(el, "t2", "t1", normal="n2", normal_other="n1")], load={"tip": 1.0}, dof_names=names, static_load={"n2": 0.2})
r = hf.craig_bampton(s, ["t1", "n1", "t2", "n2", "tip"], n_modes=4)
print("reduced n_dof", r.n_dof, "cutoff", r.cutoff_frequency)
for sys_, name in ((s, "full model"), (r, "CB")):
    for omega in (1.0, 2.0, 3.0):
        with warnings.catch_warnings(record=True) as w:
            warnings.simplefilter("always")
            a = hf.periodic_solution(sys_, 0.3, omega, harmonics=7)
            b = hf.periodic_solution(sys_, 0.3, omega, harmonics=7, condense=False)
        ws = sorted(set(type(x.message).__name__ + ":" + str(x.message)[:50] for x in w if "truncation" not in str(x.message)))
        err = np.max(np.abs(a.coefficients - b.coefficients)) / np.max(np.abs(b.coefficients))
        X = a.coefficients
        v = X[names["n1"]]; 
        print(name, omega, f"err {err:.1e}", a.converged, b.converged, ws)
from hbmfric.hbm import HBMProblem
for sys_, name, omega in ((s, "full model", 3.0), (r, "CB", 2.0)):
    full = HBMProblem(sys_, 0.3, harmonics=7, symmetry=False)
    load = np.max(np.abs(full.load))
    a = hf.periodic_solution(sys_, 0.3, omega, harmonics=7)
    b = hf.periodic_solution(sys_, 0.3, omega, harmonics=7, condense=False)
    for nm, sol in (("cond", a), ("full", b)):
        y = np.append(sol.coefficients.reshape(-1), omega)
        R, J, st = full.residual(y)
        X = sol.coefficients
        print(name, omega, nm, f"res/load {np.max(np.abs(R))/load:.1e}", sol.method, "mean t1,n1,t2,n2", np.round(X[[5,6,12,13] if sys_ is s else [0,1,2,3], 0], 4), "a1 tip", np.round(np.hypot(*X[19 if sys_ is s else 4, 1:3]), 5), sol.contact_state)
print("---")
from hbmfric.validation.steady_state import steady_state
for sys_, name, omega in ((s, "full model", 3.0),):
    a = hf.periodic_solution(sys_, 0.3, omega, harmonics=7)
    b = hf.periodic_solution(sys_, 0.3, omega, harmonics=7, condense=False)
    for nm, sol in (("cond", a), ("full", b)):
        try:
            st = sol.stability()
            print(nm, "stable", st.stable, "max|mu|", np.max(np.abs(st.multipliers)))
        except Exception as e:
            print(nm, "stability", type(e).__name__, str(e)[:200])
    t = time.process_time()
    ref = steady_state(sys_, 0.3, omega, harmonics=7, steps_per_period=1024, tol=1e-9, max_periods=5000)
    print("TI from rest", ref.converged, ref.periods, "a1 tip", np.hypot(*ref.coefficients[19, 1:3]), "means", np.round(ref.coefficients[[5,6,12,13],0],4), f"{time.process_time()-t:.0f}s")
