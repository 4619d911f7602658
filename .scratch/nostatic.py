exec(open(".scratch/c2d.py").read().split("only = sys.argv")[0])
from hbmfric.hbm import HBMProblem
for soft in (1e-7, 1e-9):
    M, K = mats(soft=soft)
    s = hf.LinearStructure(M, K, contacts=[hf.Contact(el(), 2, normal=4)], load={N-1: 1.0, 4: 0.5, 2: 0.3-0.2j}, rayleigh=(0.01, 0.02))
    full = HBMProblem(s, 0.1, harmonics=7, symmetry=False)
    out = []
    for omega in (0.3, 0.8, 1.5):
        with warnings.catch_warnings():
            warnings.simplefilter("ignore")
            a = hf.periodic_solution(s, 0.1, omega, harmonics=7)
            b = hf.periodic_solution(s, 0.1, omega, harmonics=7, condense=False)
        R = full.residual(np.append(a.coefficients.reshape(-1), omega))[0]
        out.append(f"{np.max(np.abs(a.coefficients-b.coefficients))/np.max(np.abs(b.coefficients)):.1e}/res {np.max(np.abs(R))/np.max(np.abs(full.load)):.1e}")
    print(soft, out)
