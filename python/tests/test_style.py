"""One visual language: report/style.toml declares every colour; no other
source that draws may name one (a chart names a role), and nsmodal.style
reads the same declaration as the gnuplot charts."""
import glob
import os
import re

import nsmodal
from nsmodal import style

SRC = os.environ.get("NSMODAL_SOURCE_DIR", os.path.join(os.path.dirname(__file__), "..", ".."))

# A colour literal: '#RRGGBB' or '#AARRGGBB', or a named colour where a
# chart would set one (gnuplot's rgb 'black', matplotlib's color='k').
HEX = re.compile(r"#[0-9A-Fa-f]{6}(?:[0-9A-Fa-f]{2})?\b")
NAMED = re.compile(r"""(?:rgb\s+['"][a-z]+|colou?rs?\s*=\s*['"](?!none)[a-z]+['"]|['"][rgbcmyk][.o^sx+-]['"])""")

# The sources that draw: the report library, the command line, the Python
# package and its examples, the scripts. Not the tests of the chart check
# (test_figure_colours.py), whose inputs are colours the check must refuse.
DRAWING = ["report/src/*.cc", "report/include/nsmodal/*.h", "cli/*.cc", "python/nsmodal/*.py",
           "python/nsmodal_module.cc", "examples/*.py", "scripts/*.py", "scripts/*.sh"]


def test_no_source_but_the_style_names_a_colour():
    offenders = []
    files = [f for pattern in DRAWING for f in glob.glob(os.path.join(SRC, pattern))]
    assert len(files) > 20, files  # the globs find the sources
    for path in files:
        with open(path, encoding="utf-8") as f:
            for number, line in enumerate(f, 1):
                if HEX.search(line) or NAMED.search(line):
                    offenders.append(f"{os.path.relpath(path, SRC)}:{number}: {line.strip()}")
    assert not offenders, "colours outside report/style.toml:\n" + "\n".join(offenders)


def test_the_check_finds_a_colour_where_a_chart_would_set_one():
    assert HEX.search("lc rgb '#0072B2'") and NAMED.search("lc rgb 'black'")
    assert NAMED.search('ax.plot(t, x, color="black")') and NAMED.search('ax.plot(t, x, "k.")')
    assert not NAMED.search('markerfacecolor="none"') and not HEX.search("issue #24")


def test_the_python_style_is_the_declaration():
    # The same text as report/style.toml (compiled into the module).
    tomllib = __import__("tomllib")
    with open(os.path.join(SRC, "report", "style.toml"), "rb") as f:
        declared = tomllib.load(f)
    assert style._STYLE == declared
    one = style.series("one_stable")
    assert one["color"] == declared["colours"][declared["series"]["one_stable"]["colour"]]
    assert style.series("two_unstable")["markerfacecolor"] == "none"  # open points: unstable
    assert style.series("obstacle")["linestyle"] == "--"


def test_an_unknown_role_is_named():
    try:
        style.series("no_such_role")
    except KeyError as e:
        assert "no_such_role" in str(e)
    else:
        raise AssertionError("an unknown role was accepted")
    for call, bad in ((style.colormap, "no_such_map"), (style.cycle, "no_such_cycle")):
        try:
            call(bad)
        except KeyError as e:
            assert bad in str(e)
        else:
            raise AssertionError(f"{bad} was accepted")
    assert nsmodal.__name__ == "nsmodal"


def test_save_writes_the_formats_asked_and_names_a_bad_one(tmp_path):
    import matplotlib
    matplotlib.use("Agg")
    import matplotlib.pyplot as plt
    style.use("column.pdf")
    fig, ax = plt.subplots(figsize=style.figsize("column.pdf"))
    ax.plot([0, 1], [0, 1], **style.series("one_stable"))
    style.save(fig, str(tmp_path / "c"), ["column.pdf", "png"])
    assert (tmp_path / "c.column.pdf").stat().st_size > 0 and (tmp_path / "c.png").stat().st_size > 0
    try:
        style.save(fig, str(tmp_path / "c"), ["jpg"])
    except ValueError as e:
        assert "formats" in str(e) and "jpg" in str(e)
    else:
        raise AssertionError("an unknown format was accepted")
    plt.close(fig)
