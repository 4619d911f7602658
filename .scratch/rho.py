import numpy as np, hbmfric as hf, warnings
warnings.simplefilter("ignore")
from hbmfric.condensation import selection_matrix, coordinate_rows, _stuck_stiffnesses
from hbmfric.systems.contacts import check_contacts
from hbmfric.laws import Contact2D
def rho(s):
    M, C, K = (np.asarray(a, float) for a in s.matrices())
    cs = check_contacts(s, s.n_dof)
    B = selection_matrix(cs, s.n_dof)
    ks = []
    for c, d, _, _ in coordinate_rows(cs):
        law = cs[c][0]
        ks.append((law.normal_stiffness if d else law.tangential_stiffness) if isinstance(law, Contact2D) else float(getattr(law, "stuck_stiffness", 0.0)))
    ks = np.array(ks)
    try:
        G0 = B @ np.linalg.solve(K, B.T)
    except np.linalg.LinAlgError:
        return "singular"
    sv = np.linalg.svd(K, compute_uv=False)
    return f"rho={np.max(np.abs(np.linalg.eigvalsh(G0)))*ks.max():.2e} kappaK={sv[0]/sv[-1]:.1e} n_dof={s.n_dof} n_c={len(ks)}"
import inspect
print("lap10", rho(hf.lap_joint(10)))
print("lap40", rho(hf.lap_joint(40)))
print("lap10 full", rho(hf.lap_joint(10, n_modes=None)))
for name in dir(hf):
    if "lap" in name.lower() or "2d" in name.lower(): print(name)
