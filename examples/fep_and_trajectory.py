"""Redraw the paper's frequency-energy plot (Fig. 8) and a simulated trajectory
with nsmodal and matplotlib.

    python3 examples/fep_and_trajectory.py [SCENE] [OUT_DIR]

SCENE defaults to configs/paper.toml, OUT_DIR to out/examples.
"""
import os
import sys

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402
import numpy as np  # noqa: E402

import nsmodal  # noqa: E402
from nsmodal import style  # noqa: E402

here = os.path.dirname(os.path.abspath(__file__))
scene = sys.argv[1] if len(sys.argv) > 1 else os.path.join(here, "..", "configs", "paper.toml")
out = sys.argv[2] if len(sys.argv) > 2 else os.path.join("out", "examples")
os.makedirs(out, exist_ok=True)

model = nsmodal.load_scene(scene)
T1, T2 = model.linear_periods
atlas = nsmodal.atlas(model, period=(0.02, float(np.ceil(4 * T2)), 0.02))

# Fig. 8: admissible 1- and 2-ipp orbits, coloured by stability, and the bridges.
# Every series is drawn by its role in nsmodal's visual language (nsmodal.style).
style.use("png")
fig, ax = plt.subplots(figsize=style.figsize("png"))
for family, name in ((atlas["two"], "two"), (atlas["one"], "one")):
    adm = family["admissible"]
    for stable, word in ((True, "stable"), (False, "unstable")):
        sel = adm & (family["stable"] == stable)
        look = style.series(f"{name}_{word}")
        look.update(linestyle="none", marker=look.get("marker", "o"), markersize=2)
        ax.plot(family["T"][sel], family["energy"][sel], **look, label=style.means(f"{name}_{word}"))
br = atlas["bridges"]
bridge = style.series("bridge")
ax.vlines(br["T"], br["energy_min"], br["energy_max"], colors=bridge["color"], linewidth=bridge["linewidth"],
          label="bridges")
singular = [t for t, k in zip(atlas["transitions"]["T"], atlas["transitions"]["kind"]) if k == "singular"]
for k, t in enumerate(singular):
    ax.axvline(t, **style.series("singular"), label=style.means("singular") if k == 0 else None)
ax.set_yscale("log")
energies = atlas["one"]["energy"][atlas["one"]["admissible"]]
ax.set_ylim(0.5 * energies.min(), 100 * np.median(energies))
ax.set_xlabel("period T (s)")
ax.set_ylabel("energy E (J)")
ax.legend(loc="upper right", markerscale=3)
fig.tight_layout()
fep = os.path.join(out, "fig08_fep.png")
fig.savefig(fep, dpi=100)

# A non-periodic start simulated by the exact integrator.
s = nsmodal.simulate(model, x0=[0.5, 0.0], v0=[0.5, 1.2], t_end=60.0, integrator="exact", sample_dt=0.01)
tr = s["trajectory"]
c = model.contact_dof
fig, ax = plt.subplots(figsize=style.figsize("png", 0.45))
for i in range(1, model.dofs + 1):
    ax.plot(tr["t"], tr[f"x{i}"], **style.series("dof_contact" if i == c else "dof_other"), label=f"x{i}")
ax.axhline(model.gap, **style.series("obstacle"), label="obstacle d")
ax.plot(s["impact_log"]["t"], s["impact_log"][f"x{c}_before"], **style.series("grazing") | {"markersize": 3},
        label="impacts")
ax.set_xlabel("time t (s)")
ax.set_ylabel("displacement (m)")
print(f"simulated trajectory: {s['impacts']} impacts, energy drift {s['energy_drift']:.1e}")
ax.legend(loc="lower right")
fig.tight_layout()
trajectory = os.path.join(out, "trajectory.png")
fig.savefig(trajectory, dpi=100)

print(f"T1 = {T1:.4f}, T2 = {T2:.4f}; {len(br['T'])} bridges; wrote {fep} and {trajectory}")
