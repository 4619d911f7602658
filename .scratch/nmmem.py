import os, sys, resource, time, warnings
import numpy as np, hbmfric as hf
from hbmfric import _memory
warnings.simplefilter("ignore")
def peak(): return resource.getrusage(resource.RUSAGE_SELF).ru_maxrss/1024
def chain(n, ne):
    K = np.zeros((n, n))
    for i in range(n):
        K[i, i] += 1.0
        if i + 1 < n: K[i, i] += 1.0; K[i, i+1] = K[i+1, i] = -1.0
    el = hf.Contact2D(tangential_stiffness=1.0, normal_stiffness=2.0, friction_coefficient=0.3, preload=0.05)
    return hf.LinearStructure(np.eye(n), K, rayleigh=(0.01, 0.02), contacts=[hf.Contact(el, 2*i+1, normal=2*i+2) for i in range(ne)], load={n-1: 0.1})
n = int(sys.argv[1]); H = int(sys.argv[2]); ne = int(sys.argv[3])
hf.nonlinear_mode(chain(12, ne), amplitude=(1e-3, 1e-1), points=4, harmonics=3)
b = peak(); t = time.process_time()
m = hf.nonlinear_mode(chain(n, ne), amplitude=(1e-3, 1e-1), points=8, harmonics=H)
plan = _memory.level_plan_bytes(n, False, [H], [2*H+1])
print(f"nonlinear_mode n={n} H={H} ne={ne}: peak +{peak()-b:.0f} MB, plan-style {plan/1e6:.0f} MB, cpu {time.process_time()-t:.1f}s")
