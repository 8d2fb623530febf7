"""The 1-ipp nonsmooth mode of a clamped steel bar hitting a wall at its free
end, as the finite-element mesh is refined (issue 12).

    python3 examples/bar_convergence.py [OUT_DIR] [MAX_ELEMENTS]

For n = 10 ... MAX_ELEMENTS (default 1000) linear elements with consistent
mass: the first linear period against the continuous bar's 4 L / c, and the
1-ipp orbit of period T = f * 4 L / c for f = 0.6, 0.75, 0.9 (energy,
admissibility, largest Floquet multiplier). Writes bar_convergence.csv and
bar_convergence.png to OUT_DIR (default out/examples).
"""
import csv
import os

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402
import numpy as np  # noqa: E402

import nsmodal  # noqa: E402
from nsmodal import style  # noqa: E402
from mesh_args import out_and_max_elements  # noqa: E402

out, max_elements = out_and_max_elements(1000)

L, E, RHO, A, GAP = 1.0, 210e9, 7800.0, 3.14e-4, 1e-4
C = np.sqrt(E / RHO)
T1_EXACT = 4.0 * L / C
FRACTIONS = (0.6, 0.75, 0.9)
meshes = [n for n in (10, 20, 50, 100, 200, 500, 1000) if n <= max_elements]

rows = []
for n in meshes:
    model = nsmodal.bar(length=L, youngs_modulus=E, density=RHO, area=A, elements=n, gap=GAP, restitution=1.0)
    t1 = max(model.linear_periods)
    for frac in FRACTIONS:
        (o,) = nsmodal.orbit(model, frac * T1_EXACT)
        rows.append({"elements": n, "T_over_4L_c": frac, "T1_error": t1 / T1_EXACT - 1.0,
                     "energy": o["energy"], "admissible": o["admissible"],
                     "max_multiplier": o.get("max_multiplier", float("nan"))})

with open(os.path.join(out, "bar_convergence.csv"), "w", newline="") as f:
    w = csv.DictWriter(f, fieldnames=list(rows[0].keys()))
    w.writeheader()
    w.writerows(rows)

style.use("pdf")
fig, (ax1, ax2) = plt.subplots(1, 2, figsize=style.figsize("pdf", 0.42), constrained_layout=True)
first = [r for r in rows if r["T_over_4L_c"] == FRACTIONS[0]]
ax1.loglog([r["elements"] for r in first], [-r["T1_error"] for r in first], **style.series("exact"))
ax1.set_xlabel("elements n")
ax1.set_ylabel(r"$1 - T_1^h / (4L/c)$")
finest = {r["T_over_4L_c"]: r["energy"] for r in rows if r["elements"] == meshes[-1]}
for frac, colour, marker in zip(FRACTIONS, style.cycle("sequences"), ("o", "s", "^")):
    sel = [r for r in rows if r["T_over_4L_c"] == frac and r["elements"] != meshes[-1]]
    ax2.loglog([r["elements"] for r in sel], [abs(r["energy"] / finest[frac] - 1.0) for r in sel],
               marker=marker, color=colour, label=f"T = {frac} (4L/c)")
ax2.set_xlabel("elements n")
ax2.set_ylabel(f"|E(n) / E({meshes[-1]}) - 1|")
ax2.legend(fontsize=7)
fig.savefig(os.path.join(out, "bar_convergence.png"), dpi=200)
for r in rows:
    print(",".join(f"{v:.6g}" if isinstance(v, float) else str(v) for v in r.values()))
