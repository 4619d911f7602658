exec(open(".scratch/c2d.py").read().split("only = sys.argv")[0])
from hbmfric.validation.steady_state import steady_state
import sys
which = sys.argv[1]
if which == "ground":
    s = struct([hf.Contact(el(), 2, normal=4)])
elif which == "between":
    s = struct([hf.Contact(el(), 1, 2, normal=3, normal_other=4), hf.Contact(hf.Jenkins(stiffness=1.0, slip_force=0.04), 5)])
elif which == "soft":
    s = struct([hf.Contact(el(), 2, normal=4)], soft=1e-7)
elif which == "gap":
    s = struct([hf.Contact(el(n0=-0.01), 2, normal=4)])
elif which == "stiffkn":
    s = struct([hf.Contact(el(kn=50.0), 2, normal=4)])
def amp(X, d):
    return np.hypot(X[d, 1], X[d, 2])
for omega in [float(x) for x in sys.argv[2].split(",")]:
    t = time.process_time()
    with warnings.catch_warnings(record=True) as w:
        warnings.simplefilter("always")
        a = hf.periodic_solution(s, 0.1, omega, harmonics="auto")
    ws = [str(x.message)[:100] for x in w]
    ref = steady_state(s, 0.1, omega, harmonics=a.coefficients.shape[1]//2, steps_per_period=4096, tol=1e-11, max_periods=40000)
    X, R = a.coefficients, ref.coefficients
    n = min(X.shape[1], R.shape[1])
    scale = np.max(np.abs(R))
    err = np.max(np.abs(X[:, :n] - R[:, :n]))/scale
    print(f"{which} Ω={omega}: H={a.harmonic_numbers[-1]} cond? err vs TI {err:.1e} a1(5) {amp(X,5):.5f}/{amp(R,5):.5f} mean4 {X[4,0]:.5f}/{R[4,0]:.5f} TI conv {ref.converged} periods {ref.periods} warns {ws} cpu {time.process_time()-t:.0f}s", flush=True)
