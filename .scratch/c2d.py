import os, sys, warnings, time, traceback
os.environ.setdefault("OPENBLAS_NUM_THREADS", "1")
import numpy as np
import hbmfric as hf
warnings.simplefilter("ignore", hf.AccuracyWarning)
N = 6
def mats(n=N, clamped=True, soft=None):
    m = 1.0 + 0.1*np.arange(n); k = 1.0 + 0.3*np.cos(np.arange(n))
    if not clamped: k[0] = 0.0
    if soft is not None: k[0] = soft
    K = np.zeros((n, n))
    for i in range(n):
        K[i, i] += k[i]
        if i+1 < n: K[i, i] += k[i+1]; K[i, i+1] = K[i+1, i] = -k[i+1]
    return np.diag(m), K
def el(kn=2.0, n0=0.05, mu=0.3, kt=1.0):
    return hf.Contact2D(tangential_stiffness=kt, normal_stiffness=kn, friction_coefficient=mu, preload=n0)
C_D = 0.02*np.eye(N) + 0.01*np.diag(np.ones(N-1), 1); C_D = C_D + C_D.T
def struct(contacts, damping="modal", **kw):
    M, K = mats(**kw)
    d = {"rayleigh": (0.01, 0.02)} if damping == "modal" else {"damping": C_D}
    return hf.LinearStructure(M, K, contacts=contacts, load={N-1: 1.0, 4: 0.5, 2: 0.3-0.2j}, static_load={4: 0.01}, **d)
cases = {
 "gap (n0<0)": lambda: struct([hf.Contact(el(n0=-0.02), 2, normal=4)]),
 "kn 1e3": lambda: struct([hf.Contact(el(kn=1e3), 2, normal=4)]),
 "kn 1e5": lambda: struct([hf.Contact(el(kn=1e5), 2, normal=4)]),
 "mu 0": lambda: struct([hf.Contact(el(mu=0.0), 2, normal=4)]),
 "two 2D share normal DOF": lambda: struct([hf.Contact(el(), 2, normal=4), hf.Contact(el(), 3, normal=4)]),
 "two 2D swapped dofs": lambda: struct([hf.Contact(el(), 2, normal=4), hf.Contact(el(), 4, normal=2)]),
 "2D + Menq": lambda: struct([hf.Contact(el(), 2, normal=4), hf.Contact(hf.Menq(stiffness=1.0, slip_force=0.04, alpha=2.0) if hasattr(hf,'Menq') else None, 5)]),
 "free-free held by one 2D only": lambda: struct([hf.Contact(el(), 2, normal=4)], clamped=False),
 "free-free 2D between DOFs + ground 2D": lambda: struct([hf.Contact(el(), 1, 2, normal=3, normal_other=4), hf.Contact(el(), 5, normal=0)], clamped=False),
 "nearly free (k0=1e-9)": lambda: struct([hf.Contact(el(), 2, normal=4)], soft=1e-9),
 "nearly free direct": lambda: struct([hf.Contact(el(), 2, normal=4)], damping="direct", soft=1e-9),
}
only = sys.argv[1:] 
for name, make in cases.items():
    if only and not any(o in name for o in only): continue
    try:
        s = make()
    except Exception as e:
        print(f"{name}: construct {type(e).__name__}: {e}"); continue
    for omega in (0.3, 0.8, 1.5):
        try:
            t = time.process_time()
            with warnings.catch_warnings(record=True) as w:
                warnings.simplefilter("always")
                a = hf.periodic_solution(s, 0.1, omega, harmonics=7)
                b = hf.periodic_solution(s, 0.1, omega, harmonics=7, condense=False)
            ws = sorted(set(type(x.message).__name__ for x in w))
            scale = np.max(np.abs(b.coefficients)); err = np.max(np.abs(a.coefficients - b.coefficients))/scale
            cond = a.info.get("condensed") if hasattr(a, "info") else "?"
            print(f"{name:40s} Ω={omega}: cond={cond} conv={a.converged},{b.converged} relerr={err:.2e} warns={ws} cpu={time.process_time()-t:.1f}", flush=True)
        except Exception as e:
            print(f"{name:40s} Ω={omega}: {type(e).__name__}: {str(e)[:200]}", flush=True)
