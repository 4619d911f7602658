import os, sys, resource, time, warnings
import numpy as np, hbmfric as hf
from hbmfric.condensation import CondensedHBMProblem
warnings.simplefilter("ignore")
def peak(): return resource.getrusage(resource.RUSAGE_SELF).ru_maxrss/1024
n = int(sys.argv[1]); npts = int(sys.argv[2]); multi = len(sys.argv) > 3
K = np.zeros((n, n))
for i in range(n):
    K[i, i] += 1.0
    if i + 1 < n: K[i, i] += 1.0; K[i, i+1] = K[i+1, i] = -1.0
C = 0.02*np.eye(n); C[0, 1] = C[1, 0] = 0.01
contacts = [hf.Contact(hf.Jenkins(stiffness=1.0, slip_force=0.05), n//2)]
if multi: contacts.append(hf.Contact(hf.Jenkins(stiffness=1.0, slip_force=0.05), n//3))
s = hf.LinearStructure(np.eye(n), K, C, contacts=contacts, load={n-1: 0.1})
p = CondensedHBMProblem(s, 0.1, harmonics=7, receptance="direct")
print("method", p.receptance_method, "unknowns", p.n_unknowns)
pts = np.zeros((npts, p.n_unknowns + 1)); pts[:, -1] = np.linspace(0.1, 2, npts)
b = peak(); t = time.process_time()
X = p.full_coefficients(pts)
print(f"n_dof {n} points {npts}: peak +{peak()-b:.0f} MB (Z stack {npts*n*n*16/1e6:.0f} MB; result {X.nbytes/1e6:.0f} MB) cpu {time.process_time()-t:.1f}s")
