"""Per-point: true error vs first-order change c1 and converged changes d1, d2."""
import os
for v in ("OPENBLAS_NUM_THREADS", "OMP_NUM_THREADS"): os.environ.setdefault(v, "1")
import sys, pickle, time
import numpy as np
import hbmfric as hf
from hbmfric import api
from hbmfric.continuation.adaptive import _Level
from hbmfric.continuation.palc import Continuation
from hbmfric.continuation.options import ContinuationOptions
from hbmfric.validation import branch_errors

from bench.exact_reference import scenes

def measures(problem, pt, dof, n=4096):
    C = problem.full_coefficients(pt[None, :])[0]  # (n_dof, n_coef)
    hn = problem.harmonic_numbers
    c = C[dof]
    t = np.linspace(0, 2*np.pi, n, endpoint=False)
    x = np.zeros(n); col = 0; a1 = 0
    for k in hn:
        if k == 0:
            x += c[col]; col += 1
        else:
            x += c[col]*np.cos(k*t) + c[col+1]*np.sin(k*t)
            if k == 1: a1 = np.hypot(c[col], c[col+1])
            col += 2
    return a1, 0.5*(x.max()-x.min())

name = sys.argv[1]; Hs = [int(h) for h in sys.argv[2].split(",")]
sc = [s for s in scenes() if s.name == name][0]
out = {}
for H in Hs:
    t0 = time.time()
    br = hf.frf(sc.system, sc.force, sc.omega, H)
    err = branch_errors(br, sc.system, on_failure="warn")
    true = np.maximum(err.error_h1, err.error_hpp)
    prob = api._problem(sc.system, sc.force, H, None, None, "auto", None)
    lev = _Level(prob, None)
    dof_full = int(getattr(sc.system, "contact_dof", 0))
    opts = ContinuationOptions()
    res = {"omega": err.omega, "true": true, "e1": err.error_h1, "epp": err.error_hpp, "est": br.truncation_error[err.index]}
    # raw points
    cont = Continuation(prob, sc.omega, 1, opts, None)
    st, _ = cont.run()
    pts = np.array(st.points)
    assert len(pts) == len(br), (len(pts), len(br))
    assert np.allclose(pts[:, -1], br.omega)
    pts = pts[err.index]
    from hbmfric.continuation.accuracy import next_level
    H1 = next_level(H); H2 = next_level(H1)
    L1 = _Level(prob.with_harmonics(H1), None)
    P1 = prob.with_harmonics(H1); P2 = prob.with_harmonics(H2)
    c1 = np.array([L1.change(p) for p in pts])
    C1 = Continuation(P1, sc.omega, 1, opts, None); C2 = Continuation(P2, sc.omega, 1, opts, None)
    def pad(p, Psrc, Pdst):
        nd = Psrc.n_unknowns // Psrc.n_coef
        o = np.zeros(Pdst.n_unknowns + 1)
        o[:-1].reshape(nd, Pdst.n_coef)[:, :Psrc.n_coef] = p[:-1].reshape(nd, Psrc.n_coef)
        o[-1] = p[-1]; return o
    d1 = np.full(len(pts), np.nan); d2 = np.full(len(pts), np.nan); ex = np.full(len(pts), np.nan)
    for i, p in enumerate(pts):
        m0 = measures(prob, p, dof_full)
        g = pad(p, prob, P1)
        y1, s1, _ = C1.solve_at(p[-1], g[:-1], 100)
        if s1 != 0: continue
        m1 = measures(P1, y1, dof_full)
        d1[i] = max(abs(m1[0]-m0[0])/m0[0], abs(m1[1]-m0[1])/m0[1])
        y2, s2, _ = C2.solve_at(p[-1], pad(y1, P1, P2)[:-1], 100)
        if s2 != 0: continue
        m2 = measures(P2, y2, dof_full)
        d2[i] = max(abs(m2[0]-m1[0])/m1[0], abs(m2[1]-m1[1])/m1[1])
    res.update(c1=c1, d1=d1, d2=d2, H1=H1, H2=H2, time=br.elapsed)
    out[H] = res
    big = true > 1e-7
    r = true[big] / c1[big]
    print(f"{name} H={H} ->{H1}->{H2}: true max {true.max():.3g}, est max {res['est'].max():.3g}, c1 max {c1.max():.3g}, d1 max {np.nanmax(d1):.3g} "
          f"true/c1 pct 50/90/100 {np.percentile(r,50):.3g}/{np.percentile(r,90):.3g}/{r.max():.3g}; "
          f"d1/c1 med {np.nanmedian(d1[big]/c1[big]):.3g} max {np.nanmax(d1[big]/c1[big]):.3g}; true/d1 med {np.nanmedian(true[big]/d1[big]):.3g} max {np.nanmax(true[big]/d1[big]):.3g}; ({time.time()-t0:.0f}s)", flush=True)
pickle.dump(out, open(f"/tmp/est/{name.replace(' ','_').replace('/','_')}.pkl", "wb"))
