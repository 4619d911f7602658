exec(open(".scratch/c2d.py").read().split("only = sys.argv")[0])
import sys
kind = sys.argv[1]
J1 = hf.Jenkins(stiffness=1.0, slip_force=0.04)
for soft in (1e-3, 1e-5, 1e-6, 1e-7, 1e-8, 1e-9, 1e-11):
    if kind == "2d":
        s = struct([hf.Contact(el(), 2, normal=4)], soft=soft)
    else:
        s = struct([hf.Contact(J1, 2), hf.Contact(hf.Jenkins(stiffness=2.0, slip_force=0.05), 4)], soft=soft)
    out = []
    for omega in (0.3, 0.8, 1.5):
        with warnings.catch_warnings(record=True) as w:
            warnings.simplefilter("always")
            a = hf.periodic_solution(s, 0.1, omega, harmonics=7)
            b = hf.periodic_solution(s, 0.1, omega, harmonics=7, condense=False)
        err = np.max(np.abs(a.coefficients - b.coefficients))/np.max(np.abs(b.coefficients))
        nw = [type(x.message).__name__ for x in w if "truncation" not in str(x.message)]
        out.append(f"{err:.1e}{'!' if nw else ''}")
    print(kind, soft, out, flush=True)
