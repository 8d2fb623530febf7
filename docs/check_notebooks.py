"""Checks of the tutorials (docs/source/tutorials/*.ipynb), run by scripts/docs.sh.

    python3 docs/check_notebooks.py stored               # before the build
    python3 docs/check_notebooks.py figures HTML_DIR     # after an executed build

stored: every notebook is stored without outputs (no outputs, no execution
counts): the build executes them, and git keeps only what a person wrote.

figures: every executed notebook's page holds its figures. For each code cell
that draws (calls plt.show()), the page HTML_DIR/tutorials/NAME.html must show
an image nbsphinx wrote from that cell's output
(_images/tutorials_NAME_CELL_OUTPUT.png); each image must be a PNG file of at
least 200 x 150 pixels that is not blank (more than one colour). A notebook
that ran but drew nothing, an image that was not copied, or a cell whose
figure went missing (e.g. a backend that does not display) fails the check.

Exit status 0 when every check holds, 1 with one line per failure otherwise.
"""
import glob
import json
import os
import re
import struct
import sys

HERE = os.path.dirname(os.path.abspath(__file__))
NOTEBOOKS = sorted(glob.glob(os.path.join(HERE, "source", "tutorials", "*.ipynb")))
MIN_WIDTH, MIN_HEIGHT = 200, 150


def load(path):
    with open(path, encoding="utf-8") as f:
        return json.load(f)


def check_stored():
    failures = []
    if not NOTEBOOKS:
        failures.append("no notebook in docs/source/tutorials")
    for path in NOTEBOOKS:
        name = os.path.relpath(path, os.path.dirname(HERE))
        for index, cell in enumerate(load(path)["cells"]):
            if cell["cell_type"] != "code":
                continue
            if cell.get("outputs") or cell.get("execution_count") is not None:
                failures.append(f"{name}: cell {index} is stored with its outputs; clear them before committing "
                                "(Jupyter: Edit > Clear All Outputs, or python3 -m nbconvert --clear-output --inplace FILE)")
    return failures


def png_size_and_colours(path):
    """(width, height, distinct colours > 1) of a PNG file; raises ValueError if it is not one."""
    with open(path, "rb") as f:
        head = f.read(24)
    if len(head) < 24 or head[:8] != b"\x89PNG\r\n\x1a\n" or head[12:16] != b"IHDR":
        raise ValueError("not a PNG file")
    width, height = struct.unpack(">II", head[16:24])
    import matplotlib.image  # Debian's python3-matplotlib, already needed by the notebooks

    pixels = matplotlib.image.imread(path)
    varied = bool((pixels != pixels[0, 0]).any())
    return width, height, varied


def check_figures(html_dir):
    failures = []
    for path in NOTEBOOKS:
        name = os.path.splitext(os.path.basename(path))[0]
        before = len(failures)
        page = os.path.join(html_dir, "tutorials", name + ".html")
        if not os.path.isfile(page):
            failures.append(f"tutorials/{name}: no page {page}")
            continue
        with open(page, encoding="utf-8") as f:
            html = f.read()
        shown = set(re.findall(r'<img[^>]*\ssrc="\.\./_images/(tutorials_%s_(\d+)_\d+\.png)"' % re.escape(name), html))
        cells_with_images = {int(cell) for _, cell in shown}
        drawing = [i for i, cell in enumerate(load(path)["cells"])
                   if cell["cell_type"] == "code" and "plt.show()" in "".join(cell["source"])]
        if not drawing:
            failures.append(f"tutorials/{name}: no cell draws a figure (plt.show())")
        for index in drawing:
            if index not in cells_with_images:
                failures.append(f"tutorials/{name}: cell {index} draws a figure, but its page shows no image "
                                "from that cell (was the notebook executed?)")
        for image, _ in sorted(shown):
            file = os.path.join(html_dir, "_images", image)
            if not os.path.isfile(file):
                failures.append(f"tutorials/{name}: {image} is on the page but not in _images/")
                continue
            try:
                width, height, varied = png_size_and_colours(file)
            except ValueError as error:
                failures.append(f"tutorials/{name}: {image}: {error}")
                continue
            if width < MIN_WIDTH or height < MIN_HEIGHT:
                failures.append(f"tutorials/{name}: {image} is {width} x {height} pixels (at least "
                                f"{MIN_WIDTH} x {MIN_HEIGHT} expected)")
            if not varied:
                failures.append(f"tutorials/{name}: {image} is blank (one colour)")
        if len(failures) == before:
            print(f"docs: tutorials/{name}: {len(shown)} figures, from cells {sorted(cells_with_images)}")
    return failures


def main():
    if len(sys.argv) == 2 and sys.argv[1] == "stored":
        failures = check_stored()
    elif len(sys.argv) == 3 and sys.argv[1] == "figures":
        failures = check_figures(sys.argv[2])
    else:
        sys.exit(__doc__)
    for line in failures:
        print(f"docs: {line}", file=sys.stderr)
    return 1 if failures else 0


if __name__ == "__main__":
    sys.exit(main())
