import time, warnings, sys
sys.path.insert(0, "tests")
import test_hunt_probe_memory as T
import numpy as np
t = time.process_time()
s = T._chain(3)
pts = T._points(s, (0.3, 0.6)); print("points", time.process_time()-t); t = time.process_time()
from hbmfric.hbm import HBMProblem
from hbmfric.continuation.accuracy import watched_truncation_errors
p = HBMProblem(s, 1.0, harmonics=7, symmetry=False)
print(watched_truncation_errors(p, pts, every=1), time.process_time()-t)
