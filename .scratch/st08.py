exec(open(".scratch/c2d.py").read().split("only = sys.argv")[0])
from hbmfric.validation.steady_state import steady_state
s = struct([hf.Contact(el(), 2, normal=4)])
omega = float(sys.argv[1])
a = hf.periodic_solution(s, 0.1, omega, harmonics="auto")
t = time.process_time()
try:
    st = a.stability()
    print("stability", st.stable if hasattr(st, "stable") else st, getattr(st, "method", None), "max|mu|", np.max(np.abs(getattr(st, "multipliers", [np.nan]))), f"{time.process_time()-t:.0f}s")
except Exception as e:
    print("stability error", type(e).__name__, str(e)[:300])
X = a.coefficients; hn = a.harmonic_numbers
x0 = np.zeros(X.shape[0]); v0 = np.zeros(X.shape[0]); c = 0
for k in hn:
    if k == 0: x0 += X[:, c]; c += 1
    else: x0 += X[:, c]; v0 += k*omega*X[:, c+1]; c += 2
ref = steady_state(s, 0.1, omega, harmonics=15, steps_per_period=2048, tol=1e-9, max_periods=3000, initial_state=(x0, v0))
print("TI from orbit: conv", ref.converged, ref.periods, "change", ref.change, "a1(5)", np.hypot(*ref.coefficients[5,1:3]), "vs", np.hypot(*X[5,1:3]))
