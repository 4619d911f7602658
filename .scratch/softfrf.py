exec(open(".scratch/c2d.py").read().split("only = sys.argv")[0])
from hbmfric.hbm import HBMProblem
s = struct([hf.Contact(el(), 2, normal=4)], soft=1e-7)
t = time.process_time()
a = hf.frf(s, 0.1, (0.7, 0.9), harmonics=7)
ta = time.process_time() - t; t = time.process_time()
b = hf.frf(s, 0.1, (0.7, 0.9), harmonics=7, condense=False)
tb = time.process_time() - t
print("cond", a.info["condensed"], a.info.get("receptance"), len(a.omega), a.complete, f"{ta:.1f}s", "| full", len(b.omega), b.complete, f"{tb:.1f}s")
full = HBMProblem(s, 0.1, harmonics=7, symmetry=False)
load = np.max(np.abs(full.load))
worst = max(np.max(np.abs(full.residual(np.append(a.coefficients[i].reshape(-1), w))[0])) for i, w in enumerate(a.omega))
print("worst full residual of condensed branch / load", worst / load)
from hbmfric.condensation import CondensedHBMProblem
p = CondensedHBMProblem(s, 0.1, harmonics=7); print("method", p.receptance_method, "shift", p.shift)
try:
    CondensedHBMProblem(s, 0.1, harmonics=7, receptance="modal")
except ValueError as e: print("modal:", e)
