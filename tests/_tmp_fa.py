import sys, warnings
sys.path.insert(0, "tests")
import numpy as np
import hbmfric as hf
from hbmfric.api import _problem
from hbmfric.continuation.accuracy import truncation_errors, normal_outputs
from test_contact2d import _integrate, _first_harmonic, OSC, OSC_ELEMENT
exec(open("/tmp/h31/common2d.py").read())
warnings.simplefilter("ignore")
s = structure(12.0, fx=0.0)
p = OSC_ELEMENT.params
for om in (128.2, 129.5):
    osc = np.array([OSC[k] for k in ("m", "k", "c", "my", "ky", "cy")] + [0.0, OSC["py"]])
    n_periods = int(np.ceil(15.0 * om / (2 * np.pi)))
    rec = _integrate(p, osc, om, 16384, n_periods)
    ti = np.hypot(*_first_harmonic(rec[1, 16384:]))
    for H in (21, 31, 45, 63):
        sol = hf.periodic_solution(s, 1.0, om, harmonics=H)
        pr = _problem(s, 1.0, H, None, None, "auto", None)
        y = np.r_[sol.coefficients.ravel(), om]
        est = truncation_errors(pr, y[None], 1e-4, amplitude_scale=pr.amplitude_scale((om, om)), output=normal_outputs(pr)[0])[0]
        print(om, H, "n_time", pr.n_time, "est_y %.2e" % est, "err vs TI %.2e" % abs(sol.amplitude(harmonic=1, dof="y")/ti-1))
