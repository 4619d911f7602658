exec(open(".scratch/c2d.py").read().split("only = sys.argv")[0])
from hbmfric.hbm import HBMProblem
import sys
soft = float(sys.argv[1]); damping = sys.argv[2]
s = struct([hf.Contact(el(), 2, normal=4)], damping=damping, soft=soft)
full = HBMProblem(s, 0.1, harmonics=7, symmetry=False)
load = np.max(np.abs(full.load))
for omega in (0.3, 0.8, 1.5):
    with warnings.catch_warnings(record=True) as w:
        warnings.simplefilter("always")
        a = hf.periodic_solution(s, 0.1, omega, harmonics=7)
        b = hf.periodic_solution(s, 0.1, omega, harmonics=7, condense=False)
    for name, sol in (("cond", a), ("full", b)):
        y = np.append(sol.coefficients.reshape(-1), omega)
        R, _, st = full.residual(y)
        print(f"Ω={omega} {name}: full-residual {np.max(np.abs(R))/load:.2e} mean x {np.round(sol.coefficients[:,0],4)} a1 dof5 {np.hypot(*sol.coefficients[5,1:3]):.5f} method {getattr(sol,'method','?')}")
    for x in w: print("   warn:", type(x.message).__name__, str(x.message)[:300])
