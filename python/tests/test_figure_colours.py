"""The chart check (scripts/check_figure_colours.py) must be able to fail:
pairs told apart by colour alone that merge for a deuteranope or in
greyscale, markers that differ only in shape, colours that are not the
style's, and keys that name a series that draws nothing are reported."""
import importlib.util
import os
import shutil

import pytest

SRC = os.environ.get("NSMODAL_SOURCE_DIR", os.path.join(os.path.dirname(__file__), "..", ".."))
spec = importlib.util.spec_from_file_location("check_figure_colours",
                                              os.path.join(SRC, "scripts", "check_figure_colours.py"))
colours = importlib.util.module_from_spec(spec)
spec.loader.exec_module(colours)


def run(tmp_path, plot, keys=False, allowed=None):
    (tmp_path / "fig99_test.png.gp").write_text("set grid\n" + plot + "\n")
    return colours.check(str(tmp_path), keys=keys, allowed=allowed)


def test_red_and_green_lines_merge_for_a_deuteranope(tmp_path):
    # matplotlib's default red and green: 120 apart in CIELAB, 7 once simulated.
    plot = "plot 'a.csv' using 1:2 with lines lc rgb '#D62728' title 'a', '' using 1:3 with lines lc rgb '#2CA02C' title 'b'"
    assert run(tmp_path, plot) == 1


def test_blue_and_vermillion_points_merge_in_greyscale(tmp_path):
    # Okabe-Ito blue and vermillion: far apart in hue, 8 apart in lightness.
    plot = "plot 'a.csv' using 1:2 with points pt 7 lc rgb '#0072B2' title 'a', '' using 1:3 with points pt 7 lc rgb '#D55E00' title 'b'"
    assert run(tmp_path, plot) == 1


def test_a_marker_shape_alone_does_not_keep_them_apart(tmp_path):
    # Filled and open circles of Okabe-Ito's vermillion and orange (the 2-ipp
    # pair of earlier versions): 18 apart for a deuteranope, and a marker's
    # shape is not read at the PNG's point size.
    plot = "plot 'a.csv' using 1:2 with points pt 7 lc rgb '#D55E00' title 'a', '' using 1:3 with points pt 6 lc rgb '#E69F00' title 'b'"
    assert run(tmp_path, plot) == 1


def test_a_different_dash_keeps_them_apart(tmp_path):
    plot = "plot 'a.csv' using 1:2 with lines lc rgb '#E41A1C' title 'a', '' using 1:3 with lines dt 2 lc rgb '#4DAF4A' title 'b'"
    assert run(tmp_path, plot) == 0


def test_a_colour_not_in_the_style_fails(tmp_path):
    style = colours.style_colours()
    assert "#0072B2" in style  # the style's 1-ipp blue
    plot = "plot 'a.csv' using 1:2 with lines lc rgb '#0072B3' title 'a'"
    assert run(tmp_path, plot, allowed=style) == 1
    assert run(tmp_path, plot.replace("#0072B3", "#0072B2"), allowed=style) == 0


@pytest.mark.skipif(shutil.which("gnuplot") is None, reason="the key check runs gnuplot")
def test_a_key_that_names_nothing_drawn_fails(tmp_path):
    (tmp_path / "a.csv").write_text("1,2,0\n2,3,0\n3,4,0\n")
    drawn = "plot 'a.csv' using 1:2 with lines lc rgb '#0072B2' title 'drawn'"
    assert run(tmp_path, "set datafile separator ','\n" + drawn, keys=True) == 0
    # The third column is 0 everywhere: the layer selects no point.
    empty = drawn + ", '' using 1:($3 == 1 ? $2 : 1/0) with lines dt 2 lc rgb '#56B4E9' title 'empty'"
    assert run(tmp_path, "set datafile separator ','\n" + empty, keys=True) == 1


@pytest.mark.skipif(shutil.which("gnuplot") is None, reason="the key check runs gnuplot")
def test_a_shared_key_names_only_what_a_panel_draws(tmp_path):
    # A multi-panel chart's one key (legend-only NaN layers, Plot::Legend):
    # an entry passes when a panel draws its style, fails when none does.
    (tmp_path / "a.csv").write_text("1,2\n2,3\n3,4\n")
    panel = "set datafile separator ','\nset multiplot\nplot 'a.csv' using 1:2 with lines lc rgb '#0072B2' notitle\n"
    drawn = "set xrange [0:1]\nset yrange [0:1]\nplot NaN with lines lc rgb '#0072B2' title 'drawn'"
    assert run(tmp_path, panel + drawn + "\nunset multiplot", keys=True) == 0
    absent = drawn + ", NaN with lines dt 2 lc rgb '#56B4E9' title 'absent'"
    assert run(tmp_path, panel + absent + "\nunset multiplot", keys=True) == 1


@pytest.mark.skipif(shutil.which("gnuplot") is None, reason="the key check runs gnuplot")
def test_a_black_key_stands_for_a_layer_coloured_by_a_map_with_its_marker(tmp_path):
    # A layer coloured by a map (lc palette) is keyed by a legend-only entry
    # in black: it passes when a mapped layer of that kind and marker is
    # drawn, fails for another marker (the key would show a shape nothing has).
    (tmp_path / "a.csv").write_text("1,2,0.5\n2,3,0.5\n3,4,0.5\n")
    mapped = "set datafile separator ','\nplot 'a.csv' using 1:2:3 with points pt 7 lc palette notitle"
    key = ", NaN with points pt 7 ps 1 lw 1 lc rgb '#000000' title 'orbits'"
    assert run(tmp_path, mapped + key, keys=True) == 0
    assert run(tmp_path, mapped + key.replace("pt 7", "pt 6"), keys=True) == 1
    # A line's dash counts: a dashed black key for solid mapped lines fails.
    lines = "set datafile separator ','\nplot 'a.csv' using 1:2 with lines lw 1 lc palette frac 0.3 notitle"
    assert run(tmp_path, lines + ", NaN with lines lw 1 lc rgb '#000000' title 'orbit'", keys=True) == 0
    assert run(tmp_path, lines + ", NaN with lines lw 1 dt 2 lc rgb '#000000' title 'orbit'", keys=True) == 1


@pytest.mark.skipif(shutil.which("gnuplot") is None or colours.style_grey() is None,
                    reason="the key check runs gnuplot and reads the style")
def test_a_grey_key_stands_for_a_line_style_drawn_in_several_colours(tmp_path):
    # A key by colour (the levels) beside one by line style (stable solid,
    # unstable dashed) in the style's grey: a grey style entry passes when
    # lines of its dash are drawn in two colours or more, fails when in one
    # only (then it is that layer's key, in the wrong colour) or in none.
    grey = "#" + colours.style_grey()
    (tmp_path / "a.csv").write_text("1,2\n2,3\n3,4\n")
    two = ("set datafile separator ','\nplot 'a.csv' using 1:2 with lines dt 2 lc rgb '#0072B2' notitle, "
           "'' using 1:($2 + 1) with lines dt 2 lc rgb '#E69F00' notitle")
    key = f", NaN with lines dt 2 lc rgb '{grey}' title 'unstable'"
    assert run(tmp_path, two + key, keys=True) == 0
    one = "set datafile separator ','\nplot 'a.csv' using 1:2 with lines dt 2 lc rgb '#0072B2' notitle"
    assert run(tmp_path, one + key, keys=True) == 1
    assert run(tmp_path, two + key.replace("dt 2", "dt 3"), keys=True) == 1


@pytest.mark.skipif(shutil.which("gnuplot") is None, reason="the key check runs gnuplot")
def test_a_swatch_stands_for_a_surface_of_its_colour(tmp_path):
    # A surface (pm3d) has no key sample: a legend-only filled box of its
    # colour keys it, and fails where no surface of that colour is plotted.
    (tmp_path / "a.csv").write_text("0,1,0\n0,1,1\n\n1,1,0\n1,1,1\n")
    plane = ("set datafile separator ','\nsplot 'a.csv' using 1:2:3 with pm3d fillcolor rgb '#BBBBBB' notitle, "
             "'' using 1:2:3 with lines lc rgb '#0072B2' title 'edge'")
    key = ", keyentry with boxes fs solid 1.0 noborder lc rgb '#BBBBBB' title 'the plane'"
    assert run(tmp_path, plane + key, keys=True) == 0
    assert run(tmp_path, plane + key.replace("#BBBBBB", "#999999"), keys=True) == 1


def test_the_style_pairs_that_only_colour_tells_apart():
    # The style's stability pairs (report/style.toml), stable dark, unstable
    # light: 1-ipp blue and sky blue, 2-ipp vermillion (darkened) and orange,
    # apart for a deuteranope and in greyscale; Okabe-Ito's own vermillion
    # #D55E00 is not (18 < 20), which is why the style darkens it.
    def apart(x, y):
        a, b = colours.linear(x), colours.linear(y)
        return (abs(colours.lab(a)[0] - colours.lab(b)[0]) >= colours.MIN_DELTA_L and
                colours.delta_e(colours.lab(colours.deutan(a)), colours.lab(colours.deutan(b))) >= colours.MIN_DELTA_E)
    assert apart("#0072B2", "#56B4E9")
    assert apart("#B85000", "#E69F00")
    assert not apart("#D55E00", "#E69F00")
