import warnings, numpy as np, hbmfric as hf
warnings.simplefilter("ignore")
def spectral_v(x, omega):
    n = x.shape[-1]; X = np.fft.rfft(x, axis=-1); k = np.arange(X.shape[-1]); dX = 1j*k*omega*X
    if n % 2 == 0: dX[..., -1] = 0
    return np.fft.irfft(dX, n=n, axis=-1)
def balance(sys_, F, w, N=4096):
    r = hf.validation.steady_state(sys_, F, w, steps_per_period=N)
    M, C, K = sys_.matrices()
    p = np.real(sys_.load_vector(F))
    x = r.samples; v = spectral_v(x, w)
    t = 2*np.pi/w*np.arange(N)/N; dt = 2*np.pi/w/N
    win = np.sum((p[:, None]*np.cos(w*t)[None, :]) * v) * dt
    wd = np.sum(v * (C @ v)) * dt
    c = sys_.contact_dof
    fc = r.contact_force
    # friction work: ∮ f dx_c = ∮ f v_c dt
    wf = np.sum(fc * v[c]) * dt
    return win, wd, wf, r
osc = lambda kt: hf.Oscillator(1.0, 0.02, 1.0, contact=hf.Jenkins(kt, 1.0))
n = 3
K = (2*np.eye(n) - np.eye(n, k=1) - np.eye(n, k=-1)); K[-1,-1] = 1.0
for name, s, F, w in [("sdof kt3", osc(3.0), 2.0, 1.5), ("sdof kt1e3", osc(1e3), 3.0, 0.8), ("sdof kt1e3 hi", osc(1e3), 30.0, 1.0),
                      ("chain kt100", hf.LinearStructure(np.eye(n), K, modal_damping=0.01, load={0: 1.0}, contact=hf.Jenkins(100.0, 1.0), contact_dof=2), 3.0, 0.6),
                      ("chain kt100 w1.6", hf.LinearStructure(np.eye(n), K, modal_damping=0.01, load={0: 1.0}, contact=hf.Jenkins(100.0, 1.0), contact_dof=2), 1.0, 1.6)]:
    win, wd, wf, r = balance(s, F, w)
    print(f"{name} F {F} w {w}: Win {win:.6e} Wd {wd:.6e} Wf {wf:.6e} imbalance {(win-wd-wf)/win:+.1e} friction share {wf/win:.2f} conv {r.converged}")
# Den Hartog check: stiff Jenkins at high amplitude: friction work ≈ 4 fs a
win, wd, wf, r = balance(osc(1e4), 30.0, 1.0/np.sqrt(1)*0.7)
a = r.amplitude(None); print("kt1e4 F30: Wf", wf, "4 fs (a - fs/kt)", 4*1.0*(a - 1e-4))
