import time, numpy as np, hbmfric as hf
n = 3
K = (2*np.eye(n) - np.eye(n, k=1) - np.eye(n, k=-1)); K[-1,-1] = 1.0
s3 = hf.LinearStructure(np.eye(n), K, modal_damping=0.01, load={0: 1.0}, contact=hf.Jenkins(100.0, 1.0), contact_dof=2)
for w in (0.3, 0.3):
    t = time.process_time(); ex = hf.validation.exact_periodic_solution(s3, 3.0, w); print("exact cpu", time.process_time()-t)
t = time.process_time(); r = hf.validation.steady_state(s3, 3.0, 0.3, check_halving=True); print("ss cpu", time.process_time()-t, r.error_estimate, r.amplitude(1)/ex.amplitude(1)-1)
