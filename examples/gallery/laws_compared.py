"""Masing macroslip (Jenkins) against Menq microslip at the same stiffness
and gross-slip force: microslip softens the response before gross slip."""

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt

import hbmfric as hf

laws = {
    "Jenkins": hf.Jenkins(stiffness=3.0, slip_force=1.0),
    "Menq (microslip from 50 %)": hf.Menq.from_stiffness(
        stiffness=3.0, slip_force=1.0, microslip_onset=0.5
    ),
    "Iwan (3 elements)": hf.Iwan(
        stiffnesses=(1.0, 1.0, 1.0), slip_forces=(0.2, 0.3, 0.5)
    ),
}
fig, ax = plt.subplots(figsize=(6, 4))
for name, law in laws.items():
    osc = hf.Oscillator(1.0, 0.02, 1.0, law)
    branch = hf.frf(osc, 0.3, (0.5, 3.0))
    print(f"{name}: peak {branch.amplitude().max():.4g} m, {len(branch)} points")
    branch.plot(ax=ax, label=name)
ax.legend()
fig.savefig("laws_compared.png", dpi=110)
