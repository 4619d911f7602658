import warnings, time, sys
import numpy as np
import hbmfric as hf
n = 5; k = 2e5; m = 0.2
K = k * (2*np.eye(n) - np.eye(n, k=1) - np.eye(n, k=-1)); K[-1,-1] = k
M = m*np.eye(n)
law_g = hf.Jenkins(1e6, 5.0)
law_r = hf.Menq.from_stiffness(5e5, 3.0, 0.3)
s = hf.LinearStructure(M, K, modal_damping=0.005, load={0: 1.0},
    contacts=[hf.Contact(law_g, 4), hf.Contact(law_r, 1, other=2)])
F = float(sys.argv[1]) if len(sys.argv) > 1 else 20.0
w1 = 2*np.pi*s.natural_frequencies(1)[0]
print("w1 free", w1)
with warnings.catch_warnings(record=True) as ws:
    warnings.simplefilter("always")
    t = time.process_time()
    b = hf.frf(s, F, (0.5*w1, 2.0*w1))
    print("frf", len(b), f"{time.process_time()-t:.1f}s", b.complete, [str(x.message)[:120] for x in ws])
i = np.argmax(b.amplitude(1, dof=0)); print("peak at", b.omega[i], b.amplitude(1, dof=0)[i])
idx = np.linspace(0, len(b)-1, 7).astype(int)[1:-1].tolist() + [i]
for j in idx:
    p = b.point(j)
    with warnings.catch_warnings(record=True) as ws:
        warnings.simplefilter("always")
        r = hf.validation.steady_state(s, F, float(p.omega), steps_per_period=8192, check_halving=True, initial_state="linear")
    H = p.harmonic_numbers
    # harmonic 1 coefficients: find column for cos1, sin1 in p layout
    def h1(coef_row, hn):
        # layout [X0?, Xc1, Xs1, ...] for harmonic_numbers
        col = 0; out = {}
        for h in hn:
            if h == 0: out[0] = coef_row[col]; col += 1
            else: out[h] = (coef_row[col], coef_row[col+1]); col += 2
        return out
    errs = []
    for d in range(n):
        a_h = p.amplitude(1, dof=d); a_r = r.amplitude(1, dof=d)
        ch = h1(p.coefficients[d], H)[1]; cr = (r.coefficients[d, 1], r.coefficients[d, 2])
        ph_h = np.arctan2(ch[1], ch[0]); ph_r = np.arctan2(cr[1], cr[0])
        pp_h = p.amplitude(None, dof=d); pp_r = r.amplitude(None, dof=d)
        errs.append((a_h/a_r-1, (ph_h-ph_r+np.pi)%(2*np.pi)-np.pi, pp_h/pp_r-1))
    rel_h = np.hypot(*(np.array(h1(p.coefficients[1], H)[1]) - np.array(h1(p.coefficients[2], H)[1])))
    rel_r = np.hypot(r.coefficients[1,1]-r.coefficients[2,1], r.coefficients[1,2]-r.coefficients[2,2])
    print(f"w {p.omega:.2f} H {H.max()} te {b.truncation_error[j]:.1e} ref est {r.error_estimate:.1e} conv {r.converged}", 
          "a1:", " ".join(f"{e[0]:+.1e}" for e in errs), "| ph:", " ".join(f"{e[1]:+.1e}" for e in errs), "| pp:", " ".join(f"{e[2]:+.1e}" for e in errs), f"| rel12 {rel_h/rel_r-1:+.1e}", [str(x.message)[:80] for x in ws], flush=True)
