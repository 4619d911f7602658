import os, sys, warnings
exec(open(".scratch/mem.py").read().split("what = sys.argv[1]")[0])
n=int(sys.argv[1]); H=int(sys.argv[2]); cond = sys.argv[3] if len(sys.argv)>3 else "False"
s = chain(n)
r0 = rss()
p = _problem(s, 0.1, H, None, None, "auto", eval(cond))
r1 = rss()
N = p.n_unknowns
kp = p.kernel_problem
big = []
def walk(obj, name):
    if isinstance(obj, np.ndarray):
        if obj.nbytes > 1e6: big.append((name, obj.shape, obj.nbytes/1e6))
    elif isinstance(obj, tuple):
        fields = getattr(obj, "_fields", None)
        for i, o in enumerate(obj): walk(o, f"{name}.{fields[i] if fields else i}")
walk(kp, "kp")
for k, v in vars(p).items(): walk(v, k) if not k=="kernel_problem" else None
print(f"n_unknowns {N} one n^2 matrix {8*N*N/1e6:.0f}MB; problem construction rss +{r1-r0:.0f}MB")
for b in big: print(b)
y = np.zeros(N+1); y[-1]=0.4
p.residual(y); r2=rss(); print(f"after residual rss +{r2-r0:.0f}MB")
