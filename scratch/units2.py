import time, warnings, sys
import numpy as np
import hbmfric as hf
def build(L, T, Fs, reduce):
    n = 8; k = 1e5; m = 0.05
    kU = Fs / L ; mU = Fs * T**2 / L
    K = k * (2*np.eye(n) - np.eye(n, k=1) - np.eye(n, k=-1)); K[-1,-1] = k
    M = m * np.eye(n)
    contacts = [hf.Contact(hf.Jenkins(1e6 / kU, 2.0 / Fs), 7), hf.Contact(hf.Menq.from_stiffness(5e5 / kU, 1.0 / Fs, 0.3), 3, other=4)]
    s = hf.LinearStructure(M / mU, K / kU, modal_damping=0.01, load={0: 1.0}, contacts=contacts)
    if reduce:
        s = hf.craig_bampton(s, [0, 3, 4, 7], n_modes=3)
    return s
systems = {"SI": (1, 1, 1), "mm-t-s": (1e-3, 1, 1), "mm-ms-N": (1e-3, 1e-3, 1), "m-s-kN": (1, 1, 1e3)}
reduce = len(sys.argv) > 1 and sys.argv[1] == "cb"
F = float(sys.argv[2]) if len(sys.argv) > 2 else 1.5
res = {}
for name, (L, T, Fs) in systems.items():
    s = build(L, T, Fs, reduce)
    w1 = 2*np.pi*s.natural_frequencies(1)[0] / 1.0
    with warnings.catch_warnings(record=True) as ws:
        warnings.simplefilter("always")
        t = time.process_time()
        b = hf.frf(s, F / Fs, (0.6 * w1, 1.6 * w1))
        dt = time.process_time() - t
        st = b.stability()
    res[name] = (b, L, T)
    print(name, len(b), f"{dt:.1f}s", "w1", w1 / T if False else w1, "H max", b.point_harmonics.max() if b.point_harmonics is not None else None, "unstable", int(np.sum(~b.stable)), [str(x.message)[:90] for x in ws], flush=True)
b0 = res["SI"][0]
w1 = 2*np.pi*build(1,1,1,reduce).natural_frequencies(1)[0]
grid = np.linspace(0.62*w1, 1.58*w1, 300)
for name, (b, L, T) in res.items():
    out = []
    for d in ((0, 1, 2, 3) if reduce else (0, 3, 4, 7)):
        a0 = b0.amplitude_at(grid, dof=d)[:, 0]; a1 = b.amplitude_at(grid * T, dof=d)[:, 0] * L
        out.append(np.nanmax(np.abs(a1 - a0) / np.nanmax(a0)))
    print(name, "dense diff per dof", ["%.1e" % x for x in out], "n points", len(b), "peak", np.max(b.amplitude(1)) * L)
