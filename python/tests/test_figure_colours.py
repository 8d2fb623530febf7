"""The colour check of the figures (scripts/check_figure_colours.py) must be
able to fail: pairs told apart by colour alone that merge for a deuteranope or
in greyscale are reported, pairs with different line or point styles are not."""
import importlib.util
import os

SRC = os.environ.get("NSMODAL_SOURCE_DIR", os.path.join(os.path.dirname(__file__), "..", ".."))
spec = importlib.util.spec_from_file_location("check_figure_colours",
                                              os.path.join(SRC, "scripts", "check_figure_colours.py"))
colours = importlib.util.module_from_spec(spec)
spec.loader.exec_module(colours)


def run(tmp_path, plot):
    (tmp_path / "fig99_test.png.gp").write_text("set grid\n" + plot + "\n")
    return colours.check(str(tmp_path))


def test_red_and_green_lines_merge_for_a_deuteranope(tmp_path):
    # matplotlib's default red and green: 120 apart in CIELAB, 7 once simulated.
    plot = "plot 'a.csv' using 1:2 with lines lc rgb '#D62728' title 'a', '' using 1:3 with lines lc rgb '#2CA02C' title 'b'"
    assert run(tmp_path, plot) == 1


def test_blue_and_vermillion_points_merge_in_greyscale(tmp_path):
    # Okabe-Ito blue and vermillion: far apart in hue, 8 apart in lightness.
    plot = "plot 'a.csv' using 1:2 with points pt 7 lc rgb '#0072B2' title 'a', '' using 1:3 with points pt 7 lc rgb '#D55E00' title 'b'"
    assert run(tmp_path, plot) == 1


def test_a_different_dash_or_point_keeps_them_apart(tmp_path):
    plot = ("plot 'a.csv' using 1:2 with lines lc rgb '#E41A1C' title 'a', '' using 1:3 with lines dt 2 lc rgb '#4DAF4A' title 'b', "
            "'' using 1:4 with points pt 7 lc rgb '#0072B2' title 'c', '' using 1:5 with points pt 6 lc rgb '#D55E00' title 'd'")
    assert run(tmp_path, plot) == 0


def test_why_the_two_impact_stability_pair_needs_a_style():
    # The project's pairs (report/src/figures.cc), stable dark, unstable light:
    # 1-ipp blue and sky blue stay apart by colour alone; 2-ipp vermillion and
    # orange do not for a deuteranope (18 < 20), so the figures also draw them
    # with different points or dashes.
    def apart(x, y):
        a, b = colours.linear(x), colours.linear(y)
        return (abs(colours.lab(a)[0] - colours.lab(b)[0]) >= colours.MIN_DELTA_L and
                colours.delta_e(colours.lab(colours.deutan(a)), colours.lab(colours.deutan(b))) >= colours.MIN_DELTA_E)
    assert apart("#0072B2", "#56B4E9")
    assert not apart("#D55E00", "#E69F00")
