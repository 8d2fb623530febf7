#!/usr/bin/env python3
"""Checks that the keyed series of every figure stay apart in colour, in
greyscale and for a deuteranope.

Usage: check_figure_colours.py DIR [--simulate OUT]
  DIR: the output of `nsmodal figures`; with --simulate, OUT receives each
  figNN_*.png as a deuteranope sees it (NAME.deutan.png) and printed in
  greyscale (NAME.grey.png), to look at (needs NumPy and matplotlib).

For each chart DIR/figNN_*.png.gp (the gnuplot script the figures command
wrote and ran), every plot element with a key entry is read: its kind
(lines, points, ...), dash type, point type and colour. Two series whose kind,
dash type and point type are the same can only be told apart by colour; such a
pair must differ by at least MIN_DELTA_E in CIELAB (CIE76) as printed in
colour and as a deuteranope sees it (Machado, Oliveira and Fernandes 2009,
severity 1), and by MIN_DELTA_L in CIE lightness when printed in greyscale.
Series coloured by a palette (viridis, perceptually uniform and readable
in greyscale and by colour-blind readers by design) are not compared.
Prints one line per pair that fails, then a table per figure, and exits 1 when
a pair fails.
"""
import glob
import os
import re
import sys

# CIE76 difference above which two colours read as different categories, not
# shades of one (about ten times the just-noticeable difference of 2.3).
MIN_DELTA_E = 20.0
# Lightness difference that keeps two series apart on a greyscale print
# (a tenth of the L* range; a laser printer's halftone resolves about 5).
MIN_DELTA_L = 10.0

NAMED = {"black": "#000000", "white": "#FFFFFF", "gray40": "#666666", "gray50": "#7F7F7F", "grey": "#BEBEBE"}

# Deuteranopia, severity 1 (Machado et al. 2009), on linear RGB.
DEUTAN = ((0.367322, 0.860646, -0.227968), (0.280085, 0.672501, 0.047413), (-0.011820, 0.042940, 0.968881))


def linear(hex_colour):
    h = hex_colour.lstrip("#")
    h = h[-6:]  # '#AARRGGBB': the alpha byte comes first in gnuplot
    out = []
    for k in range(3):
        c = int(h[2 * k:2 * k + 2], 16) / 255.0
        out.append(c / 12.92 if c <= 0.04045 else ((c + 0.055) / 1.055) ** 2.4)
    return out


def lab(rgb):
    r, g, b = rgb
    x = (0.4124 * r + 0.3576 * g + 0.1805 * b) / 0.95047
    y = 0.2126 * r + 0.7152 * g + 0.0722 * b
    z = (0.0193 * r + 0.1192 * g + 0.9505 * b) / 1.08883

    def f(t):
        return t ** (1.0 / 3.0) if t > 216.0 / 24389.0 else (24389.0 / 27.0 * t + 16.0) / 116.0

    return (116.0 * f(y) - 16.0, 500.0 * (f(x) - f(y)), 200.0 * (f(y) - f(z)))


def deutan(rgb):
    return [min(1.0, max(0.0, sum(m * c for m, c in zip(row, rgb)))) for row in DEUTAN]


def delta_e(a, b):
    return sum((p - q) ** 2 for p, q in zip(a, b)) ** 0.5


def split_top(text):
    """Splits a plot command at commas outside quotes and brackets."""
    parts, depth, quote, cur = [], 0, None, ""
    for ch in text:
        if quote:
            quote = None if ch == quote else quote
        elif ch in "'\"":
            quote = ch
        elif ch in "([{":
            depth += 1
        elif ch in ")]}":
            depth -= 1
        elif ch == "," and depth == 0:
            parts.append(cur)
            cur = ""
            continue
        cur += ch
    parts.append(cur)
    return parts


def series(script):
    """(title, kind, dash, point, colour) of each keyed element of each plot."""
    text = script.replace("\\\n", " ")
    plots = []
    for line in text.splitlines():
        m = re.match(r"\s*s?plot\s+(.*)", line)
        if not m:
            continue
        items = []
        for part in split_top(m.group(1)):
            if re.search(r"\bnotitle\b", part) or "palette" in part:
                continue
            title = re.search(r"\btitle\s+'([^']*)'", part)
            colour = re.search(r"\b(?:lc|fillcolor|fc)\s+rgb\s+'([^']+)'", part)
            kind = re.search(r"\bwith\s+(\w+)", part)
            if not (title and colour and kind) or not title.group(1):
                continue
            dash = re.search(r"\bdt\s+(\d+)", part)
            point = re.search(r"\bpt\s+(\d+)", part)
            c = colour.group(1)
            items.append((title.group(1), kind.group(1), dash.group(1) if dash else "1",
                          point.group(1) if point else "-", NAMED.get(c, c)))
        plots.append(items)
    return plots


def check(directory):
    failures, rows = [], []
    scripts = sorted(glob.glob(os.path.join(directory, "fig*.png.gp")))
    if not scripts:
        sys.exit(f"check_figure_colours: no fig*.png.gp in {directory}")
    for path in scripts:
        name = os.path.basename(path)[:-len(".png.gp")]
        with open(path) as f:
            plots = series(f.read())
        worst = None
        for items in plots:
            for i in range(len(items)):
                for j in range(i + 1, len(items)):
                    a, b = items[i], items[j]
                    if a[1:4] != b[1:4] or a[4].lower() == b[4].lower():
                        continue  # told apart by style, or one meaning drawn twice
                    la, lb = linear(a[4]), linear(b[4])
                    e_col = delta_e(lab(la), lab(lb))
                    e_deu = delta_e(lab(deutan(la)), lab(deutan(lb)))
                    d_l = abs(lab(la)[0] - lab(lb)[0])
                    if worst is None or min(e_col, e_deu) < worst[0]:
                        worst = (min(e_col, e_deu), d_l, a[0], b[0])
                    if e_col < MIN_DELTA_E or e_deu < MIN_DELTA_E or d_l < MIN_DELTA_L:
                        failures.append(f"{name}: '{a[0]}' {a[4]} and '{b[0]}' {b[4]} differ only in colour: "
                                        f"dE {e_col:.1f} (colour), {e_deu:.1f} (deuteranopia), dL {d_l:.1f} (greyscale)")
        rows.append((name, sum(len(p) for p in plots), worst))
    for f in failures:
        print("FAIL", f)
    print(f"{'figure':<28} keyed series  closest pair told apart by colour only (min dE, dL)")
    for name, n, worst in rows:
        desc = "none" if worst is None else f"{worst[0]:.1f}, {worst[1]:.1f}: '{worst[2]}' / '{worst[3]}'"
        print(f"{name:<28} {n:>5}         {desc}")
    return 1 if failures else 0


def simulate(directory, out):
    import matplotlib.image
    import numpy as np
    os.makedirs(out, exist_ok=True)
    for path in sorted(glob.glob(os.path.join(directory, "fig*.png"))):
        rgb = matplotlib.image.imread(path)[..., :3].astype(float)
        lin = np.where(rgb <= 0.04045, rgb / 12.92, ((rgb + 0.055) / 1.055) ** 2.4)
        name = os.path.basename(path)[:-4]
        for suffix, img in (("deutan", np.clip(lin @ np.array(DEUTAN).T, 0, 1)),
                            ("grey", np.repeat((lin @ np.array([0.2126, 0.7152, 0.0722]))[..., None], 3, axis=2))):
            srgb = np.where(img <= 0.0031308, 12.92 * img, 1.055 * img ** (1 / 2.4) - 0.055)
            matplotlib.image.imsave(os.path.join(out, f"{name}.{suffix}.png"), np.clip(srgb, 0, 1))


if __name__ == "__main__":
    if len(sys.argv) == 4 and sys.argv[2] == "--simulate":
        simulate(sys.argv[1], sys.argv[3])
    elif len(sys.argv) != 2:
        sys.exit(__doc__)
    sys.exit(check(sys.argv[1]))
