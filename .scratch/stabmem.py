import os, sys, resource, time, warnings
import numpy as np, hbmfric as hf
from hbmfric import _memory
warnings.simplefilter("ignore")
def peak(): return resource.getrusage(resource.RUSAGE_SELF).ru_maxrss/1024
exec(open(".scratch/nmmem.py").read().split("n = int(sys.argv[1])")[0].split("def peak")[1].split("\n",1)[1])
n = int(sys.argv[1]); H = int(sys.argv[2]); method = sys.argv[3]
s0 = chain(12, 1); b0 = hf.frf(s0, 0.1, (0.3, 0.32), harmonics=3, condense=False); b0.stability(method=method)
s = chain(n, 1)
b = hf.frf(s, 0.1, (0.30, 0.31), harmonics=H, condense=False, max_steps=6)
p0 = peak(); t = time.process_time()
st = b.stability(method=method)
N = n * (2*H+1)
print(f"stability {method} n={n} H={H} unknowns={N} points={len(b.omega)}: peak +{peak()-p0:.0f} MB (after frf peak {p0:.0f}); one n^2 {8*N*N/1e6:.0f} MB; frf plan {_memory.level_plan_bytes(n, False, [H], [31 if H==15 else 2*H+1])/1e6:.0f} MB cpu {time.process_time()-t:.1f}")
