"""A structure from FE matrices: a 30-DOF spring-mass chain written as
Matrix Market files (what Abaqus or ANSYS export), read back, reduced by
Craig-Bampton onto the contact and forced DOFs, and its FRF traced."""

import numpy as np
import scipy.io
import scipy.sparse

import hbmfric as hf

n, k, m = 30, 2.0e4, 0.05
K = scipy.sparse.diags(
    [-k * np.ones(n - 1), 2 * k * np.ones(n), -k * np.ones(n - 1)], [-1, 0, 1]
)
K = K.tolil()
K[n - 1, n - 1] = k  # free end
scipy.io.mmwrite("K.mtx", K.tocoo(), symmetry="symmetric")
scipy.io.mmwrite("M.mtx", scipy.sparse.identity(n) * m, symmetry="symmetric")

full = hf.LinearStructure.from_files(
    "M.mtx",
    "K.mtx",
    modal_damping=0.01,
    dof_names={"drive": 10, "tip": n - 1},
    load={"drive": 1.0},
    contact=hf.Jenkins(stiffness=5.0e3, slip_force=1.0),
    contact_dof="tip",
)
reduced = hf.craig_bampton(full, ["tip", "drive"], n_modes=8)
f_full = full.natural_frequencies(5)
f_red = reduced.with_contact(None).natural_frequencies(5)
print("first five frequencies, Hz:", np.round(f_full, 3))
print("Craig-Bampton error:", np.max(np.abs(f_red / f_full - 1)))

w1 = 2 * np.pi * f_full[0]
branch = hf.frf(reduced, 2.0, (0.5 * w1, 1.6 * w1))
print(f"{len(branch)} points, complete: {branch.complete}")
x_full = reduced.expand(branch.coefficients)  # every DOF of the full chain
print("coefficients of the full model:", x_full.shape)
