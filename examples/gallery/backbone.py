"""The nonlinear mode of a Jenkins oscillator (EPMC): frequency and damping
ratio against amplitude, and the forced responses whose peaks lie on the
backbone (light viscous damping, ζ = 0.1 %)."""

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt
import numpy as np

import hbmfric as hf

osc = hf.Oscillator(1.0, 0.2, 1e4, hf.Jenkins(stiffness=3e4, slip_force=1.0))
mode = hf.nonlinear_mode(osc, amplitude=(1e-6, 1e-1), points=121, harmonics=15)
fig, (ax_frf, ax_d) = plt.subplots(1, 2, figsize=(10, 4))
ax_frf.plot(mode.omega, mode.dof_amplitude(0), "k-", lw=2, label="backbone")
for force in (0.02, 0.2, 0.5, 1.0):
    branch = hf.frf(osc, force, (80.0, 230.0))  # harmonics="auto"
    branch.plot(ax=ax_frf, harmonic=1, label=f"F = {force} N")
    omega, amp = mode.resonances(force)
    ax_frf.plot(omega, amp, "ko", mfc="none")
    print(f"F = {force} N: peak predicted at {omega.round(3)} rad/s, {amp} m")
ax_frf.set_yscale("log")
ax_frf.legend()
ax_d.semilogx(mode.amplitude, mode.damping_ratio)
ax_d.set_xlabel("modal amplitude a (m)")
ax_d.set_ylabel("damping ratio D")
print(
    f"D peaks at {mode.damping_ratio.max():.3f} (a = "
    f"{mode.amplitude[np.argmax(mode.damping_ratio)]:.3g} m)"
)
fig.tight_layout()
fig.savefig("backbone.png", dpi=110)
