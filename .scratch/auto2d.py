import numpy as np, hbmfric as hf, warnings
warnings.simplefilter("ignore")
M = np.diag([1.0, 1.1, 1.2, 1.3]); K = np.array([[2.,-1,0,0],[-1,2,-1,0],[0,-1,2,-1],[0,0,-1,1]])
el = hf.Contact2D(tangential_stiffness=1.0, normal_stiffness=2.0, friction_coefficient=0.3, preload=0.05)
s = hf.LinearStructure(M, K, rayleigh=(0.01, 0.02), contacts=[hf.Contact(el, 1, normal=2)], load={3: 1.0})
sol = hf.periodic_solution(s, 0.1, 0.8)
print("ok", sol.harmonic_numbers[-1], sol.info if hasattr(sol, "info") else "")
b = hf.frf(s, 0.1, (0.6, 1.0))
print("frf ok", len(b.omega), b.info.get("condensed"), b.complete)
