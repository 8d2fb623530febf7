"""The paper's conjecture, in numbers: "it is highly possible yet not proved
that the associated forced solutions reach high amplitudes when they approach
a nonsmooth mode" (Thorin, Legrand, Junca 2015, conclusion).

For the scene's system with modal damping zeta (both modes) decreasing from
0.05 to 0.001, a restitution e and a harmonic force of amplitude a on the
scene's direction, the (1,1) forced response is followed through w in
[0.4, 1.0]; at each admissible peak (a local maximum of the mean energy on
an admissible stretch of a branch) the frequency of the undamped, elastic
system's 1-ipp nonsmooth mode at the same mean energy is found on the
backbone. Prints the markdown table of the README.

usage: resonance_vs_backbone.py SCENE [--amplitude A] [--restitution E] [--out OUT.md]
       (SCENE: configs/forced.toml)
"""
import argparse
import os

import numpy as np

import nsmodal


def main():
    ap = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    ap.add_argument("scene")
    ap.add_argument("--amplitude", type=float, default=0.1)
    ap.add_argument("--restitution", type=float, default=None, help="default: the scene's")
    ap.add_argument("--out")
    args = ap.parse_args()
    scene = nsmodal.load_scene(args.scene)
    e = scene.restitution if args.restitution is None else args.restitution
    lines = ["| zeta | a | peak w | peak energy | mode w at that energy | w_peak - w_mode | stable at the peak |",
             "|---|---|---|---|---|---|---|"]
    for zeta in (0.05, 0.02, 0.01, 0.005, 0.002, 0.001):
        m = nsmodal.Model(mass_matrix=scene.mass_matrix, stiffness_matrix=scene.stiffness_matrix,
                          gap=scene.gap, restitution=e, contact_dof=scene.contact_dof,
                          damping_ratios=[zeta, zeta], forcing_amplitude=scene.forcing_amplitude,
                          forcing_frequency=scene.forcing_frequency)
        a = args.amplitude
        r = nsmodal.response(m, impacts=1, frequency=(0.4, 1.0, 0.005), amplitude=a)
        p = r["points"]
        peaks = [i for i, k in enumerate(p["kind"]) if k == "peak"]
        assert peaks, f"no admissible peak at zeta = {zeta}"
        for i in peaks:
            mode = p["mode_w"][i]
            assert np.isfinite(p["w"][i]) and np.isfinite(p["energy"][i])
            lines.append(f"| {zeta:g} | {a:g} | {p['w'][i]:.9f} | {p['energy'][i]:.6f} | "
                         + (f"{mode:.9f} | {p['w'][i] - mode:+.3e}" if np.isfinite(mode) else "none | -")
                         + f" | {'yes' if p['stable'][i] else 'no'} |")
    table = "\n".join(lines) + "\n"
    print(table)
    if args.out:
        os.makedirs(os.path.dirname(os.path.abspath(args.out)), exist_ok=True)
        with open(args.out, "w") as f:
            f.write(table)


if __name__ == "__main__":
    main()
