import os, sys, resource, time, warnings
os.environ.setdefault("OPENBLAS_NUM_THREADS", "1")
import numpy as np
import hbmfric as hf
from hbmfric import _memory
from hbmfric.api import _problem
warnings.simplefilter("ignore")

def rss():  # current RSS MB
    with open("/proc/self/status") as f:
        for l in f:
            if l.startswith("VmRSS"): return int(l.split()[1])/1024
def peak():
    return resource.getrusage(resource.RUSAGE_SELF).ru_maxrss/1024

def chain(n, kind="2d"):
    m = np.ones(n); k = np.ones(n)
    K = np.zeros((n, n))
    for i in range(n):
        K[i, i] += k[i]
        if i + 1 < n:
            K[i, i] += k[i+1]; K[i, i+1] = K[i+1, i] = -k[i+1]
    if kind == "2d":
        el = hf.Contact2D(tangential_stiffness=1.0, normal_stiffness=2.0, friction_coefficient=0.3, preload=0.05)
        ne = int(os.environ.get("NE", "1"))
        contacts = [hf.Contact(el, 2*i+1, normal=2*i+2) for i in range(ne)]
    else:
        contacts = [hf.Contact(hf.Jenkins(stiffness=1.0, slip_force=0.05), n//2)]
    return hf.LinearStructure(np.diag(m), K, contacts=contacts, rayleigh=(0.01, 0.02), load={n-1: 0.1})

what = sys.argv[1]; n = int(sys.argv[2]); H = int(sys.argv[3])
kind = sys.argv[4] if len(sys.argv) > 4 else "2d"
# warm: compile kernels on tiny problem
s0 = chain(20, kind)
hf.frf(s0, 0.1, (0.3, 0.4), harmonics=3, condense=False)
s = chain(n, kind)
prob = _problem(s, 0.1, H, None, None, "auto", False)
from hbmfric.continuation.adaptive import LADDER, probe_level
est = _memory.level_plan_bytes(n, prob.odd, [H], [probe_level(H, LADDER)])
base_peak, base = peak(), rss()
t = time.process_time()
if what == "frf":
    b = hf.frf(s, 0.1, (0.3, 0.5), harmonics=H, condense=False, max_steps=30)
    out = f"points {len(b.omega)}"
elif what == "ps":
    p = hf.periodic_solution(s, 0.1, 0.4, harmonics=H, condense=False)
    out = "ok"
elif what == "stab":
    b = hf.frf(s, 0.1, (0.3, 0.35), harmonics=H, condense=False, max_steps=5)
    mid = peak()
    st = b.stability()
    out = f"points {len(b.omega)} peak-after-frf {mid-base_peak:.0f}MB"
elif what == "nm":
    m = hf.nonlinear_mode(s, (0.01, 0.1), harmonics=H, condense=False) if False else None
    out = "skip"
print(f"{what} n_dof={n} H={H} unknowns={prob.n_unknowns} est={est/1e6:.0f}MB delta_peak={peak()-base_peak:.0f}MB (base rss {base:.0f}) cpu={time.process_time()-t:.1f}s {out}", flush=True)
