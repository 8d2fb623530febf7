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

here = os.path.dirname(os.path.abspath(__file__))
scene = sys.argv[1] if len(sys.argv) > 1 else os.path.join(here, "..", "configs", "paper.toml")
out = sys.argv[2] if len(sys.argv) > 2 else os.path.join("out", "examples")
os.makedirs(out, exist_ok=True)

model = nsmodal.load_scene(scene)
T1, T2 = model.linear_periods
atlas = nsmodal.atlas(model, period=(0.02, float(np.ceil(4 * T2)), 0.02))

# Fig. 8: admissible 1- and 2-ipp orbits, coloured by stability, and the bridges.
fig, ax = plt.subplots(figsize=(9, 6))
for family, colours, label in ((atlas["two"], ("#d95f02", "#fdbf6f"), "2-ipp"),
                               (atlas["one"], ("#1f5fb4", "#8ec1ee"), "1-ipp")):
    adm = family["admissible"]
    for stable, colour, word in ((True, colours[0], "stable"), (False, colours[1], "unstable")):
        sel = adm & (family["stable"] == stable)
        ax.scatter(family["T"][sel], family["energy"][sel], s=2, color=colour, label=f"{label}, {word}")
br = atlas["bridges"]
ax.vlines(br["T"], br["energy_min"], br["energy_max"], color="black", lw=2.5, label="bridges")
for t in atlas["transitions"]["T"][[k == "singular" for k in atlas["transitions"]["kind"]]]:
    ax.axvline(t, color="#7b3294", ls="--", lw=0.8)
ax.set_yscale("log")
energies = atlas["one"]["energy"][atlas["one"]["admissible"]]
ax.set_ylim(0.5 * energies.min(), 100 * np.median(energies))
ax.set_xlabel("period T (s)")
ax.set_ylabel("energy E (J)")
ax.set_title("Frequency-energy plot: admissible 1- and 2-impact orbits (paper Fig. 8)")
ax.legend(loc="upper right", markerscale=4, fontsize=8)
fig.tight_layout()
fep = os.path.join(out, "fig08_fep.png")
fig.savefig(fep, dpi=120)

# A non-periodic start simulated by the exact integrator.
s = nsmodal.simulate(model, x0=[0.5, 0.0], v0=[0.5, 1.2], t_end=60.0, integrator="exact", sample_dt=0.01)
tr = s["trajectory"]
c = model.contact_dof
fig, ax = plt.subplots(figsize=(9, 4))
for i in range(1, model.dofs + 1):
    ax.plot(tr["t"], tr[f"x{i}"], lw=1, label=f"x{i}")
ax.axhline(model.gap, color="black", ls="--", lw=0.8, label="obstacle d")
ax.plot(s["impact_log"]["t"], s["impact_log"][f"x{c}_before"], "k.", ms=4, label="impacts")
ax.set_xlabel("time t (s)")
ax.set_ylabel("displacement (m)")
ax.set_title(f"Simulated trajectory: {s['impacts']} impacts, energy drift {s['energy_drift']:.1e}")
ax.legend(loc="lower right", fontsize=8)
fig.tight_layout()
trajectory = os.path.join(out, "trajectory.png")
fig.savefig(trajectory, dpi=120)

print(f"T1 = {T1:.4f}, T2 = {T2:.4f}; {len(br['T'])} bridges; wrote {fep} and {trajectory}")
