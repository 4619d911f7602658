exec(open(".scratch/c2d.py").read().split("only = sys.argv")[0])
J1 = hf.Jenkins(stiffness=1.0, slip_force=0.04)
for soft in (1e-5, 1e-7, 1e-9):
    s = struct([hf.Contact(J1, 2)], soft=soft)
    out = []
    for omega in (0.3, 0.8, 1.5):
        with warnings.catch_warnings(record=True) as w:
            warnings.simplefilter("always")
            a = hf.periodic_solution(s, 0.1, omega, harmonics=7)
            b = hf.periodic_solution(s, 0.1, omega, harmonics=7, condense=False)
        err = np.max(np.abs(a.coefficients - b.coefficients))/np.max(np.abs(b.coefficients))
        nw = [type(x.message).__name__ for x in w if "truncation" not in str(x.message)]
        out.append(f"{err:.1e}{'!' if nw else ''}")
    print("single", soft, out, flush=True)
