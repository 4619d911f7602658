exec(open(".scratch/c2d.py").read().split("only = sys.argv")[0])
from hbmfric.hbm import HBMProblem
from hbmfric.condensation import CondensedHBMProblem
import sys
soft = float(sys.argv[1]); damping = sys.argv[2]; rec = sys.argv[3] if len(sys.argv)>3 else "auto"
s = struct([hf.Contact(el(), 2, normal=4)], damping=damping, soft=soft)
full = HBMProblem(s, 0.1, harmonics=7, symmetry=False)
cp = CondensedHBMProblem(s, 0.1, harmonics=7, receptance=rec)
print("receptance", cp.receptance_method, "shift", cp.shift)
for omega in (0.3, 1.5):
    b = hf.periodic_solution(s, 0.1, omega, harmonics=7, condense=False)
    a = hf.periodic_solution(s, 0.1, omega, harmonics=7, condense=rec if rec!="auto" else None)
    yq_true = np.append(cp.unknowns_from_full(b.coefficients), omega)
    yq_cond = np.append(cp.unknowns_from_full(a.coefficients), omega)
    for nm, y in (("true", yq_true), ("cond", yq_cond)):
        R, J, st = cp.residual(y)
        print(f"Ω={omega} {nm}: condensed |R| {np.max(np.abs(R)):.2e} rounding {cp.rounding_level():.2e} cond(J) {np.linalg.cond(J[:, :-1]):.2e} q0 {y[0]:.4f},{y[cp.n_coef]:.4f}")
