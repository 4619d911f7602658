import time, warnings
import numpy as np
import hbmfric as hf
V = hf.validation
warnings.simplefilter("ignore")
n = 3
K = 1.0 * (2*np.eye(n) - np.eye(n, k=1) - np.eye(n, k=-1)); K[-1,-1] = 1.0
s3 = hf.LinearStructure(np.eye(n), K, modal_damping=0.01, load={0: 1.0}, contact=hf.Jenkins(100.0, 1.0), contact_dof=2)
osc = hf.Oscillator(1.0, 0.02, 1.0, contact=hf.Jenkins(3.0, 1.0))
for name, s, F, w in (("chain", s3, 3.0, 0.3), ("chain", s3, 1.0, 1.6), ("sdof", osc, 0.5, 1.2), ("sdof", osc, 2.0, 1.5)):
    V.steady_state(s, F, w); V.steady_state(s, F, w, check_halving=True)
    t = time.process_time(); r0 = V.steady_state(s, F, w); t0 = time.process_time() - t
    t = time.process_time(); r1 = V.steady_state(s, F, w, check_halving=True); t1 = time.process_time() - t
    print(name, F, w, f"{t0:.3f}s {r0.periods}p  halving {t1:.3f}s +{r1.halving_periods}p")
