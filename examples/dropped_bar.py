"""The dropped bar (issue 12): a free-free steel bar falls at 0.1 m/s onto a
rigid ground at its end node, e = 0 at the node.

    python3 examples/dropped_bar.py [OUT_DIR] [MAX_ELEMENTS]

The continuous bar (length L, wave speed c) stays in contact exactly 2 L / c
and leaves with its velocity reversed. For n = 10 ... MAX_ELEMENTS (default
1000) linear elements with consistent mass, each integrator (exact, CVODE at
rtol 1e-10 up to 200 elements, where it already takes 25 to 30 s, Moreau-Jean at a
tenth of an element's wave transit h / c) gives
the contact duration (the time the node is held: e = 0, so it arrives and
stays until the contact force falls through 0), the rebound velocity (the
bar's momentum over its mass after it left) and its wall time. Writes
dropped_bar.csv and dropped_bar.png to OUT_DIR (default out/examples).
"""
import csv
import os
import sys

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402

import nsmodal  # noqa: E402
from nsmodal import style  # noqa: E402
from dropped_bar_scene import C, CONTACT, L, T_END, V0, model, rebound_over_v0  # noqa: E402
from mesh_args import out_and_max_elements  # noqa: E402

out, max_elements = out_and_max_elements(1000)
meshes = [n for n in (10, 20, 50, 100, 200, 500, 1000, 2000) if n <= max_elements]
INTEGRATORS = ("exact", "cvode", "moreau-jean")
MAX_ELEMENTS = {"exact": 2000, "cvode": 200, "moreau-jean": 2000}  # CVODE's dense Newton: ~n^3 per run

rows = []
for n in meshes:
    bar = model(n)
    dofs = bar.dofs
    for integrator in (i for i in INTEGRATORS if n <= MAX_ELEMENTS[i]):
        s = nsmodal.simulate(bar, x0=[0.0] * dofs, v0=[V0] * dofs, t_end=T_END, integrator=integrator,
                             rtol=1e-10, atol=1e-14, step=0.1 * (L / n) / C, sample_dt=0.0)
        if s["status"] != "finished":
            sys.exit(f"{integrator}, {n} elements: {s['status']}: {s['message']}")
        rows.append({"elements": n, "integrator": integrator,
                     "contact_over_2L_c": s["sticking_time"] / CONTACT,
                     "rebound_over_v0": rebound_over_v0(bar, s["final_state"][dofs:]),
                     "impacts": s["impacts"], "sticking_phases": s["sticking_phases"],
                     "wall_time_s": s["wall_time_s"]})

with open(os.path.join(out, "dropped_bar.csv"), "w", newline="") as f:
    w = csv.DictWriter(f, fieldnames=list(rows[0].keys()))
    w.writeheader()
    w.writerows(rows)

style.use("pdf")
fig, axes = plt.subplots(1, 3, figsize=style.figsize("png", 0.31), constrained_layout=True)
for integrator in INTEGRATORS:
    sel = [r for r in rows if r["integrator"] == integrator]
    n = [r["elements"] for r in sel]
    look = style.series(integrator) | {"label": integrator}  # each integrator as in every chart
    axes[0].loglog(n, [abs(r["contact_over_2L_c"] - 1.0) for r in sel], **look)
    axes[1].loglog(n, [abs(r["rebound_over_v0"] + 1.0) for r in sel], **look)
    axes[2].loglog(n, [max(r["wall_time_s"], 1e-5) for r in sel], **look)
axes[0].set_ylabel("|contact / (2L/c) - 1|")
axes[1].set_ylabel("|v_rebound / v_0 + 1|")
axes[2].set_ylabel("wall time (s)")
for ax in axes:
    ax.set_xlabel("elements n")
axes[0].legend(fontsize=7)
fig.savefig(os.path.join(out, "dropped_bar.png"), dpi=200)
print(",".join(rows[0].keys()))
for r in rows:
    print(",".join(f"{v:.6g}" if isinstance(v, float) else str(v) for v in r.values()))
