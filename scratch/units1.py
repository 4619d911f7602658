import time, warnings, sys
import numpy as np
import hbmfric as hf

def build(L=1.0, T=1.0, Fs=1.0, law="jenkins", condense=None, kscale=100.0):
    # SI base: 5-DOF chain, m 0.01 kg, k 1e6 N/m (-> kHz), contacts
    # units: length unit L (m), time unit T (s), force unit Fs (N)
    n = 5
    k = 1e6 ; m = 0.01
    kU = Fs / L ; mU = Fs * T**2 / L ; cU = Fs * T / L
    K = k * (2*np.eye(n) - np.eye(n, k=1) - np.eye(n, k=-1)); K[-1,-1] = k
    M = m * np.eye(n)
    def mk(kt, fs):
        if law == "jenkins":
            return hf.Jenkins(stiffness=kt / kU, slip_force=fs / Fs)
        if law == "menq":
            return hf.Menq.from_stiffness(kt / kU, fs / Fs, 0.3)
        if law == "iwan":
            return hf.Iwan(np.array([0.5, 0.3, 0.2]) * kt / kU, np.array([0.3, 0.6, 1.0]) * fs / Fs)
    contacts = [hf.Contact(mk(kscale*k, 20.0), 4), hf.Contact(mk(0.5*kscale*k, 10.0), 2, other=3)]
    s = hf.LinearStructure(M / mU, K / kU, modal_damping=0.01, load={1: 1.0}, contacts=contacts)
    return s

def run(L, T, Fs, law, F, **kw):
    s = build(L, T, Fs, law)
    w = 2*np.pi*s.natural_frequencies(1)[0]
    # band in SI around stuck first mode -> compute stuck? use a wide band
    with warnings.catch_warnings(record=True) as ws:
        warnings.simplefilter("always")
        t = time.process_time()
        b = hf.frf(s, F / Fs, (0.3 * w, 3.0 * w), **kw)
        dt = time.process_time() - t
    return s, b, [str(x.category.__name__) + ": " + str(x.message)[:100] for x in ws], dt

law = sys.argv[1] if len(sys.argv) > 1 else "jenkins"
F = float(sys.argv[2]) if len(sys.argv) > 2 else 30.0
H = sys.argv[3] if len(sys.argv) > 3 else 7
H = H if H == "auto" else int(H)
res = {}
for name, (L, T, Fs) in {"SI": (1,1,1), "mm-t-s": (1e-3, 1, 1), "mm-ms-N": (1e-3, 1e-3, 1)}.items():
    s, b, ws, dt = run(L, T, Fs, law, F, harmonics=H)
    om = b.omega * (1 / T)  # back to rad/s SI: omega in 1/T -> rad/s divide by T
    om = b.omega / T
    res[name] = (om, [b.amplitude(dof=d, harmonic=1) * L for d in range(5)], b)
    print(name, len(b), "pts", f"{dt:.2f}s", "peak dof4", max(res[name][1][4]), "at", om[np.argmax(res[name][1][4])], ws)
base = res["SI"]
for name in res:
    om, amps, b = res[name]
    T = {"SI":1, "mm-t-s":1, "mm-ms-N":1e-3}[name]; L = {"SI":1, "mm-t-s":1e-3, "mm-ms-N":1e-3}[name]
    lo = max(om.min(), base[0].min()); hi = min(om.max(), base[0].max())
    grid = np.linspace(lo + 1e-3*(hi-lo), hi - 1e-3*(hi-lo), 400)
    for d in (1, 2, 3, 4):
        a0 = base[2].amplitude_at(grid, dof=d)[:, 0]
        a1 = b.amplitude_at(grid * T, dof=d)[:, 0] * L
        print(name, "dof", d, "max rel diff dense", np.nanmax(np.abs(a1 - a0) / np.nanmax(a0)))
