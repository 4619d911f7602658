import time, warnings, sys
sys.path.insert(0, "tests")
import test_hunt_probe_memory as T
import hbmfric as hf
warnings.simplefilter("ignore")
s = T._chain(3)
for w in (0.3, 0.6, 1.2):
  for F in (1.0, 0.3):
    t = time.process_time()
    a = hf.periodic_solution(s, F, w, harmonics=7, condense=False)
    print(w, F, a.method, a.converged, time.process_time()-t)
