"""The figure standard of :mod:`selfalign.plots`: print sizes, fonts, colours and the encodings
of special values, in one place.

Print size.  Every figure is drawn at the size it prints in a journal page: one column
(:data:`SINGLE_COLUMN`, 84 mm) or two columns (:data:`DOUBLE_COLUMN`, 174 mm) wide and at
most :data:`MAX_HEIGHT` (234 mm) high, so a font size in points is the size it prints at.
Labels are :data:`FONT_SIZE` (8 pt); ticks, legends and annotations :data:`SMALL_FONT_SIZE`
(7 pt), the smallest text of any figure.  A figure builder draws inside :func:`styled` (the
rc settings :data:`RC`) on a figure made by :func:`new_figure`; panels are named by
:func:`panel_letters` (bold lowercase a, b, ...), and parameters go to the caption, not into
the artwork.

Colour.  The cases of Table 1 have one colour each (:data:`CASE_COLORS`, case 0 being the
non-physical profile), chosen from the Okabe-Ito and Tol palettes so that every two of them
stay at least 15 apart (CIE76 Delta E) under simulated protanopia, deuteranopia and
tritanopia (:mod:`selfalign.plots.colour_vision`).  Each quantity has one sequential map
(:data:`QUANTITY_CMAPS`), and each special value its own encoding (:data:`SPECIAL`), drawn
over the map cells by :func:`mark_cells` and named in the legend by :func:`special_handle`.
White is left to "no data" (in Fig. 17: the mass never reaches the zone), so no case and no
special value is drawn white.

Maps.  Figs. 8, 10, 11 and 17 and the design and effect maps share the orientation of the
maps (y2'' horizontal, y3'' vertical, as the paper writes f "as a function of y2'' and
y3''") and cells centred on the grid points (:func:`cell_edges`).
"""

from __future__ import annotations

import functools
import string

import numpy as np
from matplotlib import rc_context
from matplotlib.colors import BoundaryNorm, ListedColormap
from matplotlib.figure import Figure
from matplotlib.patches import Patch, PathPatch
from matplotlib.path import Path

from ..analysis.classification import CASE_LABELS

#: Millimetres in an inch (matplotlib sizes figures in inches).
MM = 1.0 / 25.4
#: Width of a one-column figure (84 mm) and of a two-column figure (174 mm), in inches.
SINGLE_COLUMN = 84.0 * MM
DOUBLE_COLUMN = 174.0 * MM
#: The print widths a figure may have, by name.
WIDTHS = {"single": SINGLE_COLUMN, "double": DOUBLE_COLUMN}
#: The tallest figure a page holds (234 mm), in inches.
MAX_HEIGHT = 234.0 * MM
#: Size of labels, in points at print size.
FONT_SIZE = 8.0
#: Size of tick labels, legends, colour-bar ticks and annotations: the smallest text drawn.
SMALL_FONT_SIZE = 7.0
#: Resolution of the PNG files (the report and the documentation show them).
DPI = 300

#: The Okabe-Ito palette (Okabe and Ito 2002), colour-blind safe, by name.
OKABE_ITO = {"black": "#000000", "orange": "#E69F00", "sky blue": "#56B4E9", "bluish green": "#009E73",
             "yellow": "#F0E442", "blue": "#0072B2", "vermillion": "#D55E00", "reddish purple": "#CC79A7"}
#: Lines and markers cycle through these, in this order.
LINE_COLORS = ("#0072B2", "#D55E00", "#009E73", "#CC79A7", "#E69F00", "#56B4E9", "#000000")

#: The matplotlib settings of every figure.
RC = {
    "font.size": FONT_SIZE,
    "axes.titlesize": FONT_SIZE,
    "axes.labelsize": FONT_SIZE,
    "figure.titlesize": FONT_SIZE,
    "xtick.labelsize": SMALL_FONT_SIZE,
    "ytick.labelsize": SMALL_FONT_SIZE,
    "legend.fontsize": SMALL_FONT_SIZE,
    "legend.title_fontsize": SMALL_FONT_SIZE,
    "axes.linewidth": 0.6,
    "lines.linewidth": 1.0,
    "lines.markersize": 3.0,
    "patch.linewidth": 0.6,
    "hatch.linewidth": 0.5,
    "xtick.major.width": 0.6,
    "ytick.major.width": 0.6,
    "xtick.minor.width": 0.4,
    "ytick.minor.width": 0.4,
    "xtick.major.size": 3.0,
    "ytick.major.size": 3.0,
    "xtick.minor.size": 1.8,
    "ytick.minor.size": 1.8,
    "legend.frameon": False,
    "legend.handlelength": 1.6,
    "axes.prop_cycle": __import__("cycler").cycler(color=LINE_COLORS),
    "mathtext.fontset": "dejavusans",
    "figure.constrained_layout.h_pad": 2.0 / 72,
    "figure.constrained_layout.w_pad": 2.0 / 72,
}


def styled(builder):
    """Decorate a figure builder so that it draws under :data:`RC` (fonts, line widths,
    colours); text sizes are fixed when text is made, so the settings must hold while drawing.

    Parameters
    ----------
    builder : callable
        A function that makes and returns a matplotlib Figure.

    Returns
    -------
    callable
        ``builder`` drawing under the figure standard.

    Examples
    --------
    >>> @styled
    ... def empty():
    ...     return new_figure("single", 40)
    >>> round(empty().get_figwidth() * 25.4)
    84
    """

    @functools.wraps(builder)
    def draw_styled(*args, **kwargs):
        with rc_context(RC):
            return builder(*args, **kwargs)

    return draw_styled


def new_figure(width: str = "double", height_mm: float = 80.0) -> Figure:
    """A figure of one print width, with constrained layout.

    Parameters
    ----------
    width : {"single", "double"}
        One column (84 mm) or two columns (174 mm) of a journal page.
    height_mm : float
        Height in millimetres, at most 234.

    Returns
    -------
    matplotlib.figure.Figure

    Raises
    ------
    ValueError
        If ``width`` is not one of the print widths or the height is not in (0, 234] mm.

    Examples
    --------
    >>> fig = new_figure("single", 60)
    >>> [round(x * 25.4) for x in fig.get_size_inches()]
    [84, 60]
    """
    if width not in WIDTHS:
        raise ValueError(f"figure width {width!r} is not one of {', '.join(WIDTHS)}")
    if not 0 < height_mm <= MAX_HEIGHT / MM:
        raise ValueError(f"figure height {height_mm!r} mm is not in (0, {MAX_HEIGHT / MM:g}] mm")
    with rc_context(RC):
        return Figure(figsize=(WIDTHS[width], height_mm * MM), layout="constrained")


def panel_letters(axes, start: int = 0):
    """Name the panels ``axes`` a, b, c, ... (bold lowercase, at the top left of each, as the
    left-hand title), starting from the ``start``-th letter.

    Parameters
    ----------
    axes : iterable of matplotlib.axes.Axes
        The panels, in reading order.
    start : int
        Index of the first letter (0: a).

    Returns
    -------
    list of str
        The letters given.

    Examples
    --------
    >>> fig = new_figure("double", 50)
    >>> panel_letters(fig.subplots(1, 2))
    ['a', 'b']
    """
    letters = []
    for ax, letter in zip(axes, string.ascii_lowercase[start:]):
        ax.set_title(letter, loc="left", fontweight="bold", fontsize=FONT_SIZE)
        letters.append(letter)
    return letters


#: One colour per case of Table 1 (case 0: non-physical profile): blue for the desirable
#: case 1 and vermillion for the undesirable case 2 (Sect. 5.2).
CASE_COLORS = {0: "0.6", 1: "#0072B2", 2: "#D55E00", 3: "#F0E442", 4: "#66CCEE", 5: "#882255"}
#: One sequential colour map per quantity, in every figure that shows it.
QUANTITY_CMAPS = {"f": "viridis", "dx_d": "cividis", "speed": "viridis", "count": "Blues", "lambda2": "YlOrBr",
                  "lambda2_difference": "magma"}
#: Fractions of entries (how many accumulate, how many stop): three classes, light to dark,
#: in a hue no case uses.
FRACTION_CLASSES = ("none", "some", "all")
FRACTION_COLORS = ("#c7eae5", "#5ab4ac", "#01665e")


#: The special values, each drawn one way in every figure: ``facecolor`` ("none": the map shows
#: through), ``hatch`` ("": none) and the legend ``label``.
SPECIAL = {
    "non_physical": dict(facecolor=CASE_COLORS[0], hatch="", label="case 0: no physical profile"),
    "f_infinite": dict(facecolor="#000000", hatch="", label=r"$f = \infty$: $\bar v = 0$"),
    "v_negative": dict(facecolor="none", hatch="////", label=r"$\bar v < 0$: walks backward"),
    "dx_zero": dict(facecolor=OKABE_ITO["sky blue"], hatch="",
                        label=r"$\Delta x_d = 0$ exactly: every entry accumulates"),
    "unsettled": dict(facecolor="none", hatch="\\\\\\\\", label="not every entry stops"),
}
Y2_LABEL, Y3_LABEL = "$y_2''$", "$y_3''$"
#: Mathtext of the setting parameters, in the order titles list them.
SETTING_SYMBOLS = {"y2": "$y_2''$", "y3": "$y_3''$", "dy": r"$\Delta y$", "dt": r"$\Delta t$", "w": "$w$",
                   "c_mu": r"$c_\mu$"}


def setting_title(**values) -> str:
    """The setting in a title, in the order given: dy=0.064, dt=1.38 gives
    "$\\Delta y$ = 0.064, $\\Delta t$ = 1.38"."""
    return ", ".join(f"{SETTING_SYMBOLS[name]} = {value:g}" for name, value in values.items())


#: The cases of Table 1 in mathtext: the labels of selfalign.analysis.classification.CASE_LABELS
#: with their relations typeset ("x' >= 0" -> "$x' \\geq 0$").
CASE_TEXT = {case: label.replace("x' >= 0", r"$x' \geq 0$").replace("x' <= 0", r"$x' \leq 0$")
             for case, label in CASE_LABELS.items()}


def case_label(case: int) -> str:
    """The tick of ``case`` on a case colour bar: its number and :data:`CASE_TEXT`, e.g.
    "1 stick-slip, $x' \\geq 0$"."""
    return f"{case} {CASE_TEXT[case]}"


def cell_edges(centres) -> np.ndarray:
    """The n + 1 edges of the cells centred on the n increasing grid points ``centres``:
    midpoints between neighbours, and half a step beyond the first and the last point."""
    c = np.asarray(centres, dtype=float)
    if c.ndim != 1 or c.size < 2 or np.any(np.diff(c) <= 0):
        raise ValueError("map axes must be 1-D, increasing and have at least two points")
    mid = 0.5 * (c[1:] + c[:-1])
    return np.concatenate([[c[0] - (mid[0] - c[0])], mid, [c[-1] + (c[-1] - mid[-1])]])


def map_mesh(ax, y2, y3, values, **kwargs):
    """``values[i_y2, i_y3]`` as cells centred on (y2[i], y3[j]), y2'' horizontal; NaN cells
    are left blank.  ``kwargs`` go to ``pcolormesh``; returns its QuadMesh."""
    shown = np.ma.masked_invalid(np.asarray(values, dtype=float).T)
    mesh = ax.pcolormesh(cell_edges(y2), cell_edges(y3), shown, **kwargs)
    ax.set_xlabel(Y2_LABEL)
    ax.set_ylabel(Y3_LABEL)
    return mesh


def case_map(ax, y2, y3, case):
    """The case of Table 1 over the plane, with a colour bar naming every case and the case
    number written on each region (:func:`label_regions`)."""
    cmap = ListedColormap([CASE_COLORS[c] for c in sorted(CASE_COLORS)])
    mesh = map_mesh(ax, y2, y3, case, cmap=cmap, norm=BoundaryNorm(np.arange(-0.5, len(CASE_COLORS)), cmap.N))
    bar = ax.figure.colorbar(mesh, ax=ax, ticks=sorted(CASE_COLORS))
    bar.ax.set_yticklabels([case_label(c) for c in sorted(CASE_COLORS)], fontsize=SMALL_FONT_SIZE)
    bar.set_label("case (Table 1)")
    label_regions(ax, y2, y3, case, {c: str(c) for c in CASE_COLORS}, {c: CASE_COLORS[c] for c in CASE_COLORS})
    return mesh


def ink(colour) -> str:
    """Black or white, whichever reads better on ``colour`` (by its luma).

    Parameters
    ----------
    colour : matplotlib colour

    Returns
    -------
    str
        ``"k"`` or ``"w"``.

    Examples
    --------
    >>> ink(CASE_COLORS[3]), ink(CASE_COLORS[5])
    ('k', 'w')
    """
    from matplotlib.colors import to_rgb

    r, g, b = to_rgb(colour)
    return "k" if 0.299 * r + 0.587 * g + 0.114 * b > 0.5 else "w"


def label_regions(ax, y2, y3, codes, labels: dict, colors: dict, min_cells: int = 6):
    """Write ``labels[code]`` on the map, once per code, at the cell deepest inside the code's
    cells (the last to go when they are eroded one cell at a time, the one nearest their middle),
    in black or white for contrast with ``colors[code]``; codes with fewer than ``min_cells``
    cells are left to the colour bar.

    Returns the Text artists drawn."""
    codes = np.asarray(codes, dtype=float)
    texts = []
    for code, label in labels.items():
        inside = codes == code
        if np.count_nonzero(inside) < min_cells:
            continue
        while True:
            # Erode by one cell (four neighbours; the edge of the map erodes too, keeping labels off it).
            padded = np.pad(inside, 1)
            core = inside & padded[:-2, 1:-1] & padded[2:, 1:-1] & padded[1:-1, :-2] & padded[1:-1, 2:]
            if not core.any():
                break
            inside = core
        cells = np.argwhere(inside)
        i, j = cells[np.argmin(np.sum((cells - cells.mean(axis=0)) ** 2, axis=1))]
        texts.append(ax.text(y2[i], y3[j], label, ha="center", va="center", color=ink(colors[code]),
                             fontsize=SMALL_FONT_SIZE, fontweight="bold"))
    return texts


def mark_cells(ax, y2, y3, mask, kind: str, label: str | None = None) -> Patch:
    """Draw the special value ``kind`` (a key of :data:`SPECIAL`) on the cells where
    ``mask[i_y2, i_y3]`` holds, as one path of row runs, so a hatch is continuous and aligned
    with the cells of :func:`map_mesh`; returns the legend handle (:func:`special_handle`),
    labelled ``label`` or the encoding's own label."""
    encoding = SPECIAL[kind]
    x, y = cell_edges(y2), cell_edges(y3)
    vertices = []
    for j, row in enumerate(np.asarray(mask, dtype=bool).T):
        # Runs of consecutive cells along y2'' become one rectangle each.
        steps = np.diff(np.concatenate([[0], row.astype(np.int8), [0]]))
        for start, stop in zip(np.flatnonzero(steps == 1), np.flatnonzero(steps == -1)):
            vertices.append([(x[start], y[j]), (x[stop], y[j]), (x[stop], y[j + 1]), (x[start], y[j + 1]),
                             (x[start], y[j])])
    handle = special_handle(kind, label)
    if vertices:
        codes = [Path.MOVETO] + [Path.LINETO] * 3 + [Path.CLOSEPOLY]
        ax.add_patch(PathPatch(Path(np.concatenate(vertices), codes * len(vertices)), label=handle.get_label(),
                               facecolor=encoding["facecolor"], edgecolor="k", hatch=encoding["hatch"],
                               linewidth=0.0))
    return handle


def special_handle(kind: str, label: str | None = None) -> Patch:
    """The legend entry of the special value ``kind`` (a key of :data:`SPECIAL`), labelled
    ``label`` or the encoding's own label."""
    encoding = SPECIAL[kind]
    facecolor = "white" if encoding["facecolor"] == "none" else encoding["facecolor"]
    return Patch(facecolor=facecolor, edgecolor="k", hatch=encoding["hatch"], linewidth=0.5,
                 label=encoding["label"] if label is None else label)


#: ASCII spellings of mathematics that figures write in mathtext instead.
ASCII_MATH = (">=", "<=", "!=", "+-")


def print_check(fig) -> list[str]:
    """What keeps ``fig`` from the figure standard, one line per problem; empty if it meets it.

    The figure is drawn (without rendering) first, so tick labels count.  Checked: the width
    is one of the print widths (84 or 174 mm) and the height at most 234 mm; every visible text
    is at least :data:`SMALL_FONT_SIZE` (mathtext sub- and superscripts are drawn smaller, as
    in print); no suptitle, and no axes title but a panel letter (the caption carries the
    parameters); no ASCII mathematics (:data:`ASCII_MATH`).

    Parameters
    ----------
    fig : matplotlib.figure.Figure

    Returns
    -------
    list of str

    Examples
    --------
    >>> fig = new_figure("single", 50)
    >>> ax = fig.subplots()
    >>> print_check(fig)
    []
    >>> _ = ax.set_xlabel("x >= 0", fontsize=6)
    >>> print_check(fig)
    ["text 'x >= 0' is 6 pt, below 7 pt", "text 'x >= 0' writes '>=' in ASCII"]
    """
    from matplotlib.text import Text

    problems = []
    width, height = fig.get_size_inches()
    if not any(abs(width - w) < 0.01 for w in WIDTHS.values()):
        problems.append(f"width {width / MM:.1f} mm is not a print width (84 or 174 mm)")
    if height > MAX_HEIGHT + 0.01:
        problems.append(f"height {height / MM:.1f} mm exceeds {MAX_HEIGHT / MM:g} mm")
    if fig.get_suptitle():
        problems.append(f"suptitle {fig.get_suptitle()!r}: parameters belong in the caption")
    for k, ax in enumerate(fig.axes):
        for loc in ("center", "right"):
            if ax.get_title(loc):
                problems.append(f"axes {k} has the title {ax.get_title(loc)!r}: parameters belong in the caption")
        left = ax.get_title("left")
        if left and not (len(left) == 1 and left in string.ascii_lowercase):
            problems.append(f"axes {k} has the left title {left!r}, not a panel letter")
    fig.draw_without_rendering()
    seen = set()
    for text in fig.findobj(Text):
        content = text.get_text()
        if not text.get_visible() or not content.strip() or (content, text.get_fontsize()) in seen:
            continue
        seen.add((content, text.get_fontsize()))
        if text.get_fontsize() < SMALL_FONT_SIZE - 1e-9:
            problems.append(f"text {content!r} is {text.get_fontsize():g} pt, below {SMALL_FONT_SIZE:g} pt")
        problems.extend(f"text {content!r} writes {ascii!r} in ASCII" for ascii in ASCII_MATH if ascii in content)
    return problems
