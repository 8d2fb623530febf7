#!/usr/bin/env python3
"""Checks charts against nsmodal's visual language (report/style.toml): every
colour comes from it, the series a reader must tell apart stay apart in
colour, in greyscale and for a deuteranope, and every key lists what is drawn.

Usage: check_figure_colours.py DIR [--simulate OUT]
  DIR: the output of `nsmodal figures` (or `response`, `bench`); with
  --simulate, OUT receives each NAME.png as a deuteranope sees it
  (NAME.deutan.png) and printed in greyscale (NAME.grey.png), to look at
  (needs NumPy and matplotlib).

For each chart DIR/NAME.png.gp (the gnuplot script nsmodal wrote and ran):
- every colour it names must be one of style.toml's [colours] or a stop of
  one of its [maps] (a chart that sets its own colour fails);
- every plot element with a key entry is read: its kind (lines, points, ...),
  dash type and colour. Two series of the same kind and dash can only be told
  apart by colour and marker; a marker's shape is not readable at the size of
  the PNG's points, so such a pair must differ by at least MIN_DELTA_E in
  CIELAB (CIE76) as printed in colour and as a deuteranope sees it (Machado,
  Oliveira and Fernandes 2009, severity 1), and by MIN_DELTA_L in CIE
  lightness when printed in greyscale. Series coloured by a palette (the
  colour maps, perceptually uniform) are not compared;
- gnuplot is run on the script with `set table`, which lists the points of
  every plotted curve: every keyed curve must have a point inside the axes
  (a key that names a series not drawn fails). Surfaces (pm3d), which gnuplot
  cannot tabulate, are not counted; one is keyed by a legend-only filled
  swatch (boxes) of its colour, which passes only if a surface of that
  colour is plotted.
Prints one line per failure, then a table per chart, and exits 1 on a failure.
"""
import glob
import os
import re
import subprocess
import sys
import tempfile

try:
    import tomllib
except ImportError:  # Python < 3.11
    tomllib = None

# CIE76 difference above which two colours read as different categories, not
# shades of one (about ten times the just-noticeable difference of 2.3).
MIN_DELTA_E = 20.0
# Lightness difference that keeps two series apart on a greyscale print
# (a tenth of the L* range; a laser printer's halftone resolves about 5).
MIN_DELTA_L = 10.0

STYLE = os.path.join(os.path.dirname(os.path.abspath(__file__)), "..", "report", "style.toml")


def style_colours(path=STYLE):
    """The colours a chart may name: [colours] and the maps' stops (upper case)."""
    if tomllib is None:
        return None
    with open(path, "rb") as f:
        style = tomllib.load(f)
    colours = {c.upper() for c in style["colours"].values()}
    for m in style["maps"].values():
        colours |= {c.upper() for _, c in m["stops"]}
    return colours

def style_grey(path=STYLE):
    """The style's grey (its [colours] grey, six hex digits, upper case), the
    colour of a key by line style; None without a TOML reader."""
    if tomllib is None:
        return None
    with open(path, "rb") as f:
        return tomllib.load(f)["colours"]["grey"].upper()[-6:]


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
    """Each plot command's layers: (title or None, kind, dash, colour or None,
    palette?, legend only?, point type or None) in order (a gnuplot plot's curves, as `set table`
    lists them). A legend-only layer plots NaN: a key entry for a multi-panel
    chart's one key, drawn by its panels; in black, it may stand for layers
    coloured by a map (lc palette) of its kind, dash and marker."""
    text = script.replace("\\\n", " ")
    plots = []
    inner = False  # between a script's own set table $BLOCK and unset table: tabulated, not drawn
    for line in text.splitlines():
        if re.match(r"\s*set table\b", line):
            inner = True
        elif re.match(r"\s*unset table\b", line):
            inner = False
        m = re.match(r"\s*s?plot\s+(.*)", line)
        if not m or inner:
            continue
        items = []
        for part in split_top(m.group(1)):
            title = re.search(r"\btitle\s+'([^']*)'", part)
            colour = re.search(r"\b(?:lc|fillcolor|fc)\s+rgb\s+'([^']+)'", part)
            kind = re.search(r"\bwith\s+(\w+)", part)
            dash = re.search(r"\bdt\s+(\d+)", part)
            point = re.search(r"\bpt\s+(\d+)", part)
            keyed = title is not None and title.group(1) and not re.search(r"\bnotitle\b", part)
            items.append((title.group(1) if keyed else None, kind.group(1) if kind else "lines",
                          dash.group(1) if dash else "1", colour.group(1) if colour else None, "palette" in part,
                          part.strip().startswith(("NaN ", "keyentry ")), point.group(1) if point else None))
        plots.append(items)
    return plots


def colours_named(script):
    """Every colour a script names (rgb '...', palette stops)."""
    return [c for c in re.findall(r"'(#[0-9A-Fa-f]{6,8}|[A-Za-z]+[0-9]*)'", " ".join(
        re.findall(r"(?:rgb\s+'[^']+'|defined\s*\([^)]*\))", script)))]


def tabulated(path):
    """gnuplot's table of each curve the script plots, in order: a list (one
    per plot command) of lists of (points inside the axes, tabulated?)."""
    with open(path) as f:
        lines = f.read().splitlines()
    # The script's own first lines pick the terminal and output: replaced.
    body = [l for l in lines if not l.startswith(("set terminal", "set output", "if (!exists('nsmodal_output'))"))]
    with tempfile.TemporaryDirectory() as tmp:
        table = os.path.join(tmp, "table.txt")
        script = os.path.join(tmp, "table.gp")
        # A script's own tables (contours into a datablock) end ours: it is
        # taken up again after each.
        body = [l + f"\nset table '{table}' append" if re.match(r"\s*unset table\b", l) else l for l in body]
        with open(script, "w") as f:
            f.write(f"set terminal unknown\nset table '{table}'\n" + "\n".join(body) + "\nunset table\n")
        run = subprocess.run(["gnuplot", script], cwd=os.path.dirname(os.path.abspath(path)),
                             capture_output=True, text=True, timeout=120)
        if run.returncode != 0:
            return None, run.stderr.strip().splitlines()[-1:] or ["gnuplot failed"]
        with open(table) as f:
            rows = f.read().splitlines()
    plots, current = [], None
    for row in rows:
        m = re.match(r"# (?:Curve|Surface) (\d+) of (\d+)", row)
        if m:
            if m.group(1) == "0":
                current = []
                plots.append(current)
            current.append([0, True])
        elif row.startswith("#") or not row.strip() or current is None:
            continue
        elif row.split()[-1] == "i":
            current[-1][0] += 1
    return plots, None


def check(directory, keys=True, allowed="style"):
    """Checks every DIR/*.png.gp; `keys`: also run gnuplot on each (the key
    check); `allowed`: the colours a chart may name (default: the style's;
    None: any). Returns 1 on a failure, else 0."""
    failures, rows = [], []
    scripts = sorted(glob.glob(os.path.join(directory, "*.png.gp")))
    if not scripts:
        sys.exit(f"check_figure_colours: no *.png.gp in {directory}")
    if allowed == "style":
        allowed = style_colours()
    GREY = style_grey()
    for path in scripts:
        name = os.path.basename(path)[:-len(".png.gp")]
        with open(path) as f:
            text = f.read()
        plots = series(text)
        if allowed is not None:
            for c in colours_named(text):
                if c.upper() not in allowed:
                    failures.append(f"{name}: the colour {c} is not one of report/style.toml's: "
                                    "a chart names a role, never a colour")
        worst = None
        for items in plots:
            keyed = [it for it in items if it[0] is not None and it[3] is not None and not it[4]]
            for i in range(len(keyed)):
                for j in range(i + 1, len(keyed)):
                    a, b = keyed[i], keyed[j]
                    # Points: a marker's shape is not told apart at the PNG's size.
                    same = a[1] == b[1] and (a[1] == "points" or a[2] == b[2])
                    if not same or a[3].upper()[-6:] == b[3].upper()[-6:]:
                        continue  # told apart by line or dash, or one colour meaning one thing
                    la, lb = linear(a[3]), linear(b[3])
                    e_col = delta_e(lab(la), lab(lb))
                    e_deu = delta_e(lab(deutan(la)), lab(deutan(lb)))
                    d_l = abs(lab(la)[0] - lab(lb)[0])
                    if worst is None or min(e_col, e_deu) < worst[0]:
                        worst = (min(e_col, e_deu), d_l, a[0], b[0])
                    if e_col < MIN_DELTA_E or e_deu < MIN_DELTA_E or d_l < MIN_DELTA_L:
                        failures.append(f"{name}: '{a[0]}' {a[3]} and '{b[0]}' {b[3]} differ only in colour: "
                                        f"dE {e_col:.1f} (colour), {e_deu:.1f} (deuteranopia), dL {d_l:.1f} (greyscale)")
        if keys:
            tables, error = tabulated(path)
            if error:
                failures.append(f"{name}: gnuplot could not tabulate the script: {error[0]}")
            elif len(tables) != len(plots):
                failures.append(f"{name}: {len(plots)} plot commands but gnuplot tabulated {len(tables)}")
            else:
                # The styles (kind, dash, colour) that draw a point somewhere.
                drawn = {item[1:4] for items, table in zip(plots, tables)
                         for item, (inside, _) in zip(items, table) if inside > 0}
                # Layers coloured by a map, by kind, dash and marker: keyed in black.
                mapped = {(item[1], item[2], item[6]) for items, table in zip(plots, tables)
                          for item, (inside, _) in zip(items, table) if inside > 0 and item[4]}
                for items, table in zip(plots, tables):
                    for item, (inside, _) in zip(items, table):
                        if item[0] is None or item[1] == "pm3d":
                            continue
                        # A line with markers keyed once, drawn as its line and its markers apart.
                        apart = item[1] == "linespoints" and ("lines",) + item[2:4] in drawn and any(
                            d[0] == "points" and d[2] == item[3] for d in drawn)
                        # A layer coloured by a map keyed in black, its marker's shape.
                        black = item[3] is not None and item[3].upper()[-6:] == "000000"
                        by_map = black and (item[1], item[2], item[6]) in mapped
                        # A line style keyed in grey for the layers drawn in it in
                        # several colours (a key by colour, one by style beside it).
                        grey = GREY is not None and item[3] is not None and item[3].upper()[-6:] == GREY
                        by_style = grey and item[1] == "lines" and sum(
                            1 for d in drawn if d[0] == "lines" and d[1] == item[2] and d[2] is not None
                            and d[2].upper()[-6:] != GREY) >= 2
                        # A filled swatch (legend-only boxes) for a surface of its
                        # colour (pm3d, which has no key sample of its own).
                        swatch = item[5] and item[1] == "boxes" and item[3] is not None and any(
                            it[1] == "pm3d" and it[3] is not None and it[3].upper()[-6:] == item[3].upper()[-6:]
                            for its in plots for it in its)
                        if (item[5] and item[1:4] not in drawn and not apart and not by_map and not by_style
                                and not swatch):
                            failures.append(f"{name}: the key names '{item[0]}', whose style no panel draws")
                        elif not item[5] and inside == 0:
                            failures.append(f"{name}: the key names '{item[0]}', which draws no point inside the axes")
        rows.append((name, sum(1 for p in plots for it in p if it[0] is not None), worst))
    for f in failures:
        print("FAIL", f)
    print(f"{'chart':<28} keyed series  closest pair told apart by colour only (min dE, dL)")
    for name, n, worst in rows:
        desc = "none" if worst is None else f"{worst[0]:.1f}, {worst[1]:.1f}: '{worst[2]}' / '{worst[3]}'"
        print(f"{name:<28} {n:>5}         {desc}")
    return 1 if failures else 0


def simulate(directory, out):
    import matplotlib.image
    import numpy as np
    os.makedirs(out, exist_ok=True)
    for path in sorted(glob.glob(os.path.join(directory, "*.png"))):
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
