exec(open(".scratch/c2d.py").read().split("only = sys.argv")[0])
from hbmfric.hbm import HBMProblem
J1 = hf.Jenkins(stiffness=1.0, slip_force=0.04)
for soft in (1e-9,):
    s = struct([hf.Contact(J1, 2), hf.Contact(hf.Jenkins(stiffness=2.0, slip_force=0.05), 4)], soft=soft)
    full = HBMProblem(s, 0.1, harmonics=7, symmetry=False)
    for omega in (0.3, 0.8):
        a = hf.periodic_solution(s, 0.1, omega, harmonics=7)
        b = hf.periodic_solution(s, 0.1, omega, harmonics=7, condense=False)
        for nm, sol in (("cond", a), ("full", b)):
            y = np.append(sol.coefficients.reshape(-1), omega)
            R, J, st = full.residual(y)
            print(omega, nm, f"{np.max(np.abs(R)):.1e}", f"condJ {np.linalg.cond(J[:,:-1]):.1e}", sol.coefficients[:3,0])
