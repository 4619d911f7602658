import warnings, numpy as np, hbmfric as hf
warnings.simplefilter("always")
for zeta in (1e-2, 1e-3):
    osc = hf.Oscillator(1.0, 4*zeta, 1.0, contact=hf.Jenkins(3.0, 1.0))
    for w in (2*(1-zeta), 2.0):
        F = 1e-3 * zeta / 1e-2
        exact = F / abs(4 - w**2 + 1j*4*zeta*w)
        with warnings.catch_warnings(record=True) as ws:
            warnings.simplefilter("always")
            r = hf.validation.steady_state(osc, F, w, initial_state="linear")
        print(zeta, w, r.amplitude(1)/exact-1, r.scheme_error, [str(x.message) for x in ws])
        r2 = hf.validation.steady_state(osc, F, w, initial_state="linear", steps_per_period=4096+2048)
        print("  finer", r2.amplitude(1)/exact-1, r2.scheme_error)
