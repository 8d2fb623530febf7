"""Modal truncation (issue 12: "model no more than a scene needs").

    python3 examples/modal_truncation.py [OUT_DIR] [ELEMENTS]

1. The dropped bar of dropped_bar.py (free-free steel bar, 0.1 m/s onto the
   ground at its end node, e = 0) with ELEMENTS (default 1000) linear
   elements, simulated by the exact integrator on its first k linear modes
   (nsmodal.truncate) and on all of them: the contact duration over 2 L / c,
   the rebound velocity over v0, the wall time, and the truncation's bound on
   what the neglected modes can add to x_c at the drop's energy.
2. A chain of 100 unit masses and springs (contact on the last mass, d = 1):
   the 1-ipp orbit of period T = 30 on k modes against the full one (its
   energy and x_c), with the bound at that orbit's energy.
Writes modal_truncation.csv and modal_truncation.png to OUT_DIR (default
out/examples).
"""
import csv
import os

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402
import numpy as np  # noqa: E402

import nsmodal  # noqa: E402
from nsmodal import style  # noqa: E402
from dropped_bar_scene import CONTACT, GAP, T_END, V0, model, rebound_over_v0  # noqa: E402
from mesh_args import out_and_max_elements  # noqa: E402

out, elements = out_and_max_elements(1000)

bar = model(elements)
N = bar.dofs
energy = 0.5 * V0 ** 2 * bar.mass_matrix.sum()
rows = []
for k in sorted({m for m in (5, 10, 20, 50, 100, 200, 500) if m < N} | {N}):
    t = nsmodal.truncate(bar, modes=k)
    x0 = t.from_physical @ np.zeros(N)
    v0 = t.from_physical @ np.full(N, V0)
    s = nsmodal.simulate(t.model, x0=list(x0), v0=list(v0), t_end=T_END, sample_dt=0.0)
    if s["status"] != "finished":
        raise SystemExit(f"{k} modes: {s['status']}: {s['message']}")
    v = t.to_physical @ np.asarray(s["final_state"])[k:]
    rows.append({"study": "dropped_bar", "modes": k, "dofs": N,
                 "contact_over_2L_c": s["sticking_time"] / CONTACT,
                 "rebound_over_v0": rebound_over_v0(bar, v),
                 "bound_m": t.contact_bound(energy), "bound_over_gap": t.contact_bound(energy) / GAP,
                 "wall_time_s": s["wall_time_s"]})

chain = nsmodal.Model(masses=[1.0] * 100, springs=[1.0] * 100, gap=1.0, restitution=1.0, contact_dof=100)
PERIOD = 30.0
full = nsmodal.orbit(chain, PERIOD, 1)[0]
for k in (5, 10, 20, 50, 100):
    t = nsmodal.truncate(chain, modes=k)
    o = nsmodal.orbit(t.model, PERIOD, 1)[0]
    rows.append({"study": "chain_1ipp", "modes": k, "dofs": 100,
                 "energy_rel_error": abs(o["energy"] - full["energy"]) / full["energy"],
                 "bound_m": t.contact_bound(full["energy"]), "bound_over_gap": t.contact_bound(full["energy"]) / 1.0})

fields = []
for r in rows:
    fields += [key for key in r if key not in fields]
with open(os.path.join(out, "modal_truncation.csv"), "w", newline="") as f:
    w = csv.DictWriter(f, fieldnames=fields)
    w.writeheader()
    w.writerows(rows)

bar_rows = [r for r in rows if r["study"] == "dropped_bar"]
ref = bar_rows[-1]
style.use("pdf")
fig, axes = plt.subplots(1, 3, figsize=style.figsize("png", 0.31), constrained_layout=True)
k = [r["modes"] for r in bar_rows[:-1]]
look = style.series("exact")  # the exact integrator, as in every chart
axes[0].loglog(k, [abs(r["contact_over_2L_c"] - ref["contact_over_2L_c"]) + 1e-16 for r in bar_rows[:-1]], **look)
axes[0].set_ylabel("|contact - all modes'| / (2L/c)")
axes[1].loglog(k, [r["bound_over_gap"] for r in bar_rows[:-1]], **look)
axes[1].set_ylabel("bound on neglected x_c / d")
axes[2].loglog([r["modes"] for r in bar_rows], [max(r["wall_time_s"], 1e-5) for r in bar_rows], **look)
axes[2].set_ylabel("wall time (s)")
for ax in axes:
    ax.set_xlabel(f"modes kept (of {N})")
fig.savefig(os.path.join(out, "modal_truncation.png"), dpi=200)
print(",".join(fields))
for r in rows:
    print(",".join(f"{r[key]:.6g}" if isinstance(r.get(key), float) else str(r.get(key, "")) for key in fields))
