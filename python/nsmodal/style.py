"""nsmodal's visual language for matplotlib.

The same declaration as the command line's gnuplot charts (report/style.toml,
compiled into the module): colours, line styles and markers by role, the
colour maps with their one meaning, the chart formats. A chart names a role,
never a colour::

    import matplotlib.pyplot as plt
    from nsmodal import style

    style.use("png")                        # fonts and size of the PNG charts
    fig, ax = plt.subplots(figsize=style.figsize("png"))
    ax.plot(T, E, **style.series("one_stable"), label="1-ipp, stable")
    style.save(fig, "out/fep")              # fep.png, .svg, .pdf (as drawn)
"""
import json as _json

from . import _nsmodal

_STYLE = _json.loads(_nsmodal._style_json())
FORMATS = ("png", "svg", "pdf", "column.pdf")


def colour(name):
    """'#RRGGBB' of a named colour of style.toml's [colours]."""
    try:
        value = _STYLE["colours"][name]
    except KeyError:
        raise KeyError(f"nsmodal.style: no colour {name!r} (one of {sorted(_STYLE['colours'])})") from None
    if len(value) == 9:  # gnuplot's '#AARRGGBB' (alpha first, 0 opaque) as matplotlib's '#RRGGBBAA'
        alpha = 255 - int(value[1:3], 16)
        return f"#{value[3:]}{alpha:02X}"
    return value


def series(role, colour_override=None):
    """matplotlib keyword arguments (color, linewidth, linestyle, marker,
    markersize, markerfacecolor) drawing a series of this role; a role drawn
    as points has no line, one drawn as lines no marker."""
    try:
        s = _STYLE["series"][role]
    except KeyError:
        raise KeyError(f"nsmodal.style: no series role {role!r}") from None
    c = colour_override or colour(s["colour"])
    marker = _STYLE["markers"][s["marker"]]
    kw = {"color": c, "linewidth": s["width"]}
    if s["kind"] in ("lines", "vectors", "linespoints"):
        dash = _STYLE["dashes"][s["dash"]]["matplotlib"]
        kw["linestyle"] = dash if isinstance(dash, str) else (dash[0], tuple(dash[1]))
    else:
        kw["linestyle"] = "none"
    if s["kind"] in ("points", "linespoints") and marker["matplotlib"]:
        kw["marker"] = marker["matplotlib"]
        kw["markersize"] = 6.0 * s["size"]
        kw["markerfacecolor"] = "none" if marker["open"] else c
    return kw


def means(role):
    """What a role means (for a key or a caption)."""
    return _STYLE["series"][role]["means"]


def cycle(name):
    """The colours of a cycle of style.toml's [cycles], in order."""
    if name not in _STYLE["cycles"]:
        raise KeyError(f"nsmodal.style: no cycle {name!r} (one of {sorted(_STYLE['cycles'])})")
    return [colour(n) for n in _STYLE["cycles"][name]]


def colormap(name):
    """A matplotlib colormap of style.toml's [maps] (with its meaning as
    `.means`)."""
    from matplotlib.colors import LinearSegmentedColormap
    if name not in _STYLE["maps"]:
        raise KeyError(f"nsmodal.style: no colour map {name!r} (one of {sorted(_STYLE['maps'])})")
    m = _STYLE["maps"][name]
    cmap = LinearSegmentedColormap.from_list(f"nsmodal.{name}", [(p, c) for p, c in m["stops"]])
    cmap.means = m["means"]
    return cmap


def figsize(fmt="png", aspect=650 / 900):
    """(width, height) in inches of a chart in one of FORMATS."""
    width = _STYLE["matplotlib"]["width"][fmt]
    return (width, width * aspect)


def use(fmt="png"):
    """Sets matplotlib's fonts, grid and default colours for one of FORMATS."""
    import matplotlib
    matplotlib.rcParams.update({
        "font.size": _STYLE["matplotlib"]["font"][fmt],
        "axes.grid": True,
        "grid.color": colour("grid"),
        "grid.linewidth": 0.5,
        "legend.frameon": False,
        "axes.prop_cycle": matplotlib.cycler(color=cycle("sequences")),
    })


def save(fig, stem, formats=("png", "svg", "pdf")):
    """Writes STEM.EXT for each of `formats` (of FORMATS), the figure as
    drawn: a chart for an 8.5 cm column is drawn at its size, with
    use("column.pdf") and figsize("column.pdf"), then saved as
    save(fig, stem, ["column.pdf"])."""
    for fmt in formats:
        if fmt not in FORMATS:
            raise ValueError(f"nsmodal.style.save: formats: {fmt!r} is not one of {FORMATS}")
        fig.savefig(f"{stem}.{fmt}", dpi=100 if fmt == "png" else None)
