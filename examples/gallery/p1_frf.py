"""P1: the FRF of a single-DOF oscillator with a Jenkins contact.

Traces the whole branch with the defaults (harmonics chosen along the
branch), checks one point against time integration, and draws the curve.
"""

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt

import hbmfric as hf

law = hf.Jenkins(stiffness=3.0, slip_force=1.0)  # kt = 3 N/m, f_s = 1 N
osc = hf.Oscillator(mass=1.0, damping=0.02, stiffness=1.0, contact=law)
branch = hf.frf(osc, force=0.5, omega=(0.5, 3.0))
print(f"{len(branch)} points, complete: {branch.complete}, {branch.elapsed:.3f} s")
print(f"largest estimated truncation error: {branch.truncation_error.max():.1e}")

# one point against the time-integration reference
sol = hf.periodic_solution(osc, force=0.5, omega=1.2)
ref = hf.validation.steady_state(osc, force=0.5, omega=1.2)
rel = abs(sol.amplitude(harmonic=1) / ref.amplitude(harmonic=1) - 1)
print(f"HBM vs time integration at 1.2 rad/s: {rel:.1e}")

fig, ax = plt.subplots(figsize=(6, 4))
branch.plot(ax=ax)
ax.set_title("P1: Jenkins oscillator, F = 0.5 N")
fig.savefig("p1_frf.png", dpi=110)
