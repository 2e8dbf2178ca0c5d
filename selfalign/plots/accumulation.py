"""Plot functions and figure builders for the stopping region (Fig. 2, Sect. 3.3) and the
stopping figures (Figs. 14-18, Sect. 7).

As in :mod:`selfalign.plots.profile`, plot functions draw the data they are given onto
matplotlib Axes (or a Figure for multi-panel plots) and return the figure; the builders
``figure_*`` take results in :func:`selfalign.io.hdf5.read_h5` layout (written by
:mod:`selfalign.stages.accumulation`'s ``fig*_content``), pick what is shown and call them;
:func:`figure_02` takes the stop zone itself and draws its friction coefficient with the
zone's own :meth:`~selfalign.StopZone.coefficient`.  Nothing here computes physics or writes
files; only the object-oriented matplotlib API is used (headless).  Every figure follows the
figure standard of :mod:`selfalign.plots.style`.
"""

from __future__ import annotations

import numpy as np
from matplotlib import rc_context
from matplotlib.colors import BoundaryNorm, LinearSegmentedColormap, ListedColormap, LogNorm
from matplotlib.lines import Line2D
from matplotlib.patches import Patch, Rectangle
from matplotlib.ticker import MaxNLocator

from .annotate import dimension
from .classification import mean_velocity_zero_line, objective_panel
from .style import (
    FRACTION_COLORS,
    LINE_COLORS,
    OKABE_ITO,
    QUANTITY_CMAPS,
    SMALL_FONT_SIZE,
    case_map,
    map_mesh,
    mark_cells,
    new_figure,
    panel_letters,
    styled,
)

#: Shading of the table: low-friction and high-friction regions (the transition between them,
#: eq. 9, is a gradient from one to the other).
LOW_COLOR, HIGH_COLOR = "0.93", "0.68"
#: Colours and line styles of the two entries of a phase portrait (their starts differ by
#: less than a line width in Fig. 16, so the second is dashed).
ENTRY_COLORS = LINE_COLORS[:2]
ENTRY_STYLES = ("-", "--")
#: Fig. 17 c for settings where every entry ends at rest: how many entries accumulate, in the
#: three fraction classes of the figure standard (style.FRACTION_COLORS: none, some, all).
ACCUMULATION_CLASSES = ("none accumulate", "some accumulate", "all accumulate")
#: Legend texts of the cells of Fig. 17 c and d that show no class or no Delta x_d.
UNSETTLED_LABEL = r"not every entry stops: no $\Delta x_d$"
NOT_REACHED_LABEL = "white: the mass never reaches the zone"
#: The two stick sequences of Fig. 18 (accumulating, resting) and the exact solver's map.
COBWEB_COLORS = (OKABE_ITO["blue"], OKABE_ITO["vermillion"])
SOLVER_COLOR = OKABE_ITO["bluish green"]
#: Padding (points) of the panel letters above axes whose marks (:func:`_mark`) are labelled above them.
MARKED_TITLE_PAD = 11.0
#: Fig. 2: the share of the body's width w on the high-friction region, z / w, in the sketch.
SKETCH_OVERLAP = 0.6


def _mark(ax, x, label, style=":"):
    """A vertical line at x with ``label`` above the axes."""
    ax.axvline(x, color="k", linestyle=style, linewidth=0.8)
    ax.text(x, 1.01, label, transform=ax.get_xaxis_transform(), ha="center", va="bottom",
            fontsize=SMALL_FONT_SIZE)


def _table(ax, lo, hi, x_mu, w, top=0.0, bottom=-1.0):
    """The table between x = ``lo`` and ``hi`` as a strip from ``bottom`` to ``top``: low friction
    before x_mu, high friction after it and, when ``w`` is given, the transition of eq. (9) from
    x_mu to x_mu + w as a gradient between the two."""
    ax.add_patch(Rectangle((lo, bottom), x_mu - lo, top - bottom, facecolor=LOW_COLOR, linewidth=0))
    start = x_mu if w is None else x_mu + w
    ax.add_patch(Rectangle((start, bottom), hi - start, top - bottom, facecolor=HIGH_COLOR, linewidth=0))
    if w is not None:
        ramp = LinearSegmentedColormap.from_list("transition", [LOW_COLOR, HIGH_COLOR])
        ax.imshow(np.linspace(0.0, 1.0, 64)[None, :], cmap=ramp, extent=(x_mu, x_mu + w, bottom, top),
                  aspect="auto", interpolation="bilinear")


def situation_sketch(ax, x0, x_end, x_mu, w, x_stick_min):
    """Fig. 14: the table (low friction, transition zone from x_mu to x_mu + w (eqs. 7-9), high
    friction), the body of width w at its start x0 and where it stopped, x_end = x_mu +
    overshoot, with the overshoot and x_stick_min.

    Parameters
    ----------
    ax : matplotlib.axes.Axes
    x0, x_end : float
        Front edge of the body (its position x, eq. 8) at the start and at rest.
    x_mu : float
        Start of the high-friction region.
    w : float
        Width of the body and of the transition zone.
    x_stick_min : float
        Where permanent stick becomes possible (eq. 41).

    Returns
    -------
    matplotlib.figure.Figure
        The figure of ``ax``.

    Examples
    --------
    >>> fig = new_figure("double", 50)
    >>> _ = situation_sketch(fig.subplots(), -0.05, 0.1, 0.065, 0.05, 0.09)
    >>> fig.axes[0].get_xlabel()
    '$x$'
    """
    lo, hi = x0 - 1.3 * w, max(x_end, x_mu + w) + 0.8 * w
    ax.set_xlim(lo, hi)
    _table(ax, lo, hi, x_mu, w)
    ax.text(0.5 * (lo + x_mu), -0.5, r"$\mu_1 = \mu$", ha="center", va="center")
    ax.text(0.5 * (x_mu + w + hi), -0.5, r"$\mu_2 = c_\mu \mu$", ha="center", va="center")
    backdrop = {"facecolor": "white", "edgecolor": "none", "alpha": 0.85, "pad": 0.8}
    dimension(ax, x_mu, x_mu + w, -0.35, r"transition $w$", color="k").set_bbox(backdrop)
    for x, style, label in ((x0, "--", "start: $x = x_{0s}$"), (x_end, "-", "at rest")):
        # The body's reference point x is its front edge: its overlap with the zone is x - x_mu (eq. 8).
        ax.add_patch(Rectangle((x - w, 0.0), w, 0.6, fill=False, linestyle=style, linewidth=1.2))
        ax.plot([x], [0.0], "o", color="k", markersize=3)
        ax.text(x - 0.5 * w, 0.3, label, ha="center", va="center", fontsize=SMALL_FONT_SIZE)
    dimension(ax, x_mu, x_end, 0.8, r"$\Delta x_{\mathrm{overshoot}}$", color="k").set_bbox(backdrop)
    _mark(ax, x_mu, r"$x_\mu$")
    _mark(ax, x_mu + w, r"$x_\mu + w$")
    _mark(ax, x_stick_min, r"$x_{\mathrm{stick,min}}$", style="--")
    ax.set_ylim(-1.0, 1.3)
    ax.set_yticks([])
    ax.set_xlabel("$x$")
    return ax.figure


def end_position_region(ax, s, overshoot, x_mu, x_stick_min, dx_d, x_d):
    """Fig. 15: the end positions x_mu + overshoot of all steady-state entries (against their
    offset s), the range [x_d - Delta x_d, x_d + Delta x_d] and x_d (eq. 39), legended below
    the axes.

    Parameters
    ----------
    ax : matplotlib.axes.Axes
    s, overshoot : array_like
        Offset of each entry (it starts at x0s = -s) and where it ends beyond x_mu.
    x_mu, x_stick_min, dx_d, x_d : float
        Start of the zone, eq. (41), eq. (39) and the desired end position.

    Returns
    -------
    matplotlib.figure.Figure
        The figure of ``ax``.

    Examples
    --------
    >>> fig = new_figure("single", 70)
    >>> _ = end_position_region(fig.subplots(), [0.0, 0.01], [0.03, 0.04], 0.06, 0.09, 0.005, 0.095)
    >>> len(fig.legends)
    1
    """
    ax.plot(x_mu + np.asarray(overshoot, dtype=float), s, "k.", markersize=3, label="end positions of the entries")
    ax.axvspan(x_d - dx_d, x_d + dx_d, color=OKABE_ITO["blue"], alpha=0.15, linewidth=0,
               label=r"$[x_d - \Delta x_d,\ x_d + \Delta x_d]$")
    _mark(ax, x_mu, r"$x_\mu$")
    _mark(ax, x_stick_min, r"$x_{\mathrm{stick,min}}$", style="--")
    _mark(ax, x_d, "$x_d$", style="-")
    ax.xaxis.set_major_locator(MaxNLocator(5))
    ax.set_xlabel("end position $x$")
    ax.set_ylabel(r"entry offset $s$ ($x_{0s} = -s$)")
    ax.figure.legend(*ax.get_legend_handles_labels(), loc="outside lower center", ncols=2)
    return ax.figure


def stick_distances(ax, sequences, x_stick_min):
    """|x_n - x_stick_min| of stick sequences against the stick number n, on a log scale, so
    that accumulation (distances shrinking geometrically, a straight line) is visible on every
    scale.

    Downward triangles: sticks short of x_stick_min, where the mass slips on; upward: past it,
    where it sticks for good.  x_stick_min itself (distance 0, reached as t -> oo) lies below
    every scale.

    Parameters
    ----------
    ax : matplotlib.axes.Axes
    sequences : iterable of (str, array_like, str, str)
        (label, stick positions, colour, line style) of each sequence.
    x_stick_min : float
        Where permanent stick becomes possible (eq. 41).

    Returns
    -------
    list of matplotlib.lines.Line2D
        Legend handles of the two triangles.

    Examples
    --------
    >>> ax = new_figure("single", 50).subplots()
    >>> handles = stick_distances(ax, [("run", [0.03, 0.039, 0.0399], "k", "-")], 0.04)
    >>> ax.get_yscale(), len(handles)
    ('log', 2)
    """
    for label, x, color, style in sequences:
        d = np.asarray(x, dtype=float) - x_stick_min
        n = np.arange(d.size)
        ax.plot(n, np.where(d != 0, np.abs(d), np.nan), color=color, linestyle=style, linewidth=0.8, label=label)
        ax.plot(n[d < 0], -d[d < 0], "v", color=color, markersize=4)
        ax.plot(n[d > 0], d[d > 0], "^", color=color, markersize=6)
    ax.set_yscale("log")
    ax.xaxis.set_major_locator(MaxNLocator(integer=True))
    ax.set_xlabel("stick $n$ in the zone")
    ax.set_ylabel(r"$|x_n - x_{\mathrm{stick,min}}|$")
    ax.grid(True, which="major", linewidth=0.4, alpha=0.5)
    return [Line2D([], [], color="k", marker="v", linestyle="none", markersize=4,
                   label=r"$x_n < x_{\mathrm{stick,min}}$: slips on"),
            Line2D([], [], color="k", marker="^", linestyle="none", markersize=6,
                   label=r"$x_n > x_{\mathrm{stick,min}}$: sticks for good")]


def phase_portraits(fig, panels):
    """Fig. 16: per setting (one row each), the phase portrait (x, x') of two entries with x_mu
    and x_stick_min (left, as in the paper) and the distances of their sticks in the zone to
    x_stick_min (right, :func:`stick_distances`), with the row's legend below it.

    Parameters
    ----------
    fig : matplotlib.figure.Figure
    panels : list of dict
        Per setting: ``x_mu``, ``x_stick_min`` and ``entries``, a list of two (x, v, label,
        zone stick positions).

    Returns
    -------
    matplotlib.figure.Figure
        ``fig``, panels lettered a, b, ... row by row.

    Examples
    --------
    >>> fig = new_figure("double", 80)
    >>> entry = ([0.0, 0.1], [0.1, 0.0], "entry", [0.09, 0.0999])
    >>> _ = phase_portraits(fig, [{"x_mu": 0.05, "x_stick_min": 0.1, "entries": [entry, entry]}])
    >>> [ax.get_title(loc="left") for ax in fig.axes]
    ['a', 'b']
    """
    rows = np.atleast_1d(fig.subfigures(len(panels), 1))
    axes = []
    for row, panel in zip(rows, panels):
        ax, ax_d = row.subplots(1, 2, width_ratios=[1.6, 1])
        if axes:
            # One distance scale for all settings, so that a single jump and a long accumulation compare.
            ax_d.sharey(axes[1])
        sequences = []
        for (x, v, label, sticks), color, style in zip(panel["entries"], ENTRY_COLORS, ENTRY_STYLES):
            ax.plot(x, v, color=color, linestyle=style, linewidth=0.8, label=label)
            sequences.append((label, sticks, color, style))
        ax.axhline(0.0, color="0.5", linewidth=0.6)
        _mark(ax, panel["x_mu"], r"$x_\mu$", style="--")
        _mark(ax, panel["x_stick_min"], r"$x_{\mathrm{stick,min}}$", style="--")
        ax.set_xlabel("$x$")
        ax.set_ylabel("$x'$")
        triangles = stick_distances(ax_d, sequences, panel["x_stick_min"])
        row.legend(handles=ax.get_legend_handles_labels()[0] + triangles, loc="outside lower center", ncols=2)
        axes += [ax, ax_d]
    panel_letters(axes)
    return fig


def accumulation_classes(frac_accumulate):
    """Codes of Fig. 17 c (index into ACCUMULATION_CLASSES: 0 none, 1 some, 2 all) from the
    fraction of entries that accumulate.

    Parameters
    ----------
    frac_accumulate : numpy.ndarray
        Fraction of the entries that accumulate; NaN where the mass never reaches the zone.

    Returns
    -------
    numpy.ndarray
        0.0, 1.0 or 2.0; NaN where ``frac_accumulate`` is NaN.

    Examples
    --------
    >>> accumulation_classes(np.array([0.0, 0.25, 1.0, np.nan])).tolist()
    [0.0, 1.0, 2.0, nan]
    """
    code = np.where(frac_accumulate == 1, 2.0, np.where(frac_accumulate > 0, 1.0, 0.0))
    return np.where(np.isnan(frac_accumulate), np.nan, code)


def accumulation_mesh(ax, y2, y3, frac_accumulate, unsettled):
    """How many entries accumulate (:func:`accumulation_classes`) over (y2'', y3'') in the three
    fraction classes of the figure standard, where every entry ends at rest; blank in the
    ``unsettled`` cells (some entry never stops or stays undecided) and where the mass never
    reaches the zone.  Returns the QuadMesh (for a colour bar of the classes)."""
    cmap = ListedColormap(FRACTION_COLORS)
    return map_mesh(ax, y2, y3, np.where(unsettled, np.nan, accumulation_classes(frac_accumulate)), cmap=cmap,
                    norm=BoundaryNorm(np.arange(-0.5, len(FRACTION_COLORS)), cmap.N))


def not_reached_handle() -> Patch:
    """The legend entry of the white cells of a stop-zone map: the mass never reaches the zone."""
    return Patch(facecolor="white", edgecolor="k", linewidth=0.5, label=NOT_REACHED_LABEL)


def positioning_error_panel(ax, y2, y3, dx_d, unsettled):
    """Fig. 17 d: the positioning error Delta x_d (eq. 39) over (y2'', y3'').

    Exact zeros (every entry accumulates at x_stick_min) are drawn in the encoding
    ``style.SPECIAL["dx_zero"]``, positive values in the map of Delta x_d
    (``style.QUANTITY_CMAPS["dx_d"]``) on a log scale, so that the two can be told apart;
    ``unsettled`` cells (some entry never stops or stays undecided) show no value and are
    marked ``"unsettled"``, since Delta x_d there would span only the entries that stopped.

    Parameters
    ----------
    ax : matplotlib.axes.Axes
    y2, y3 : array_like
        The grid axes.
    dx_d : array_like
        Delta x_d[i_y2, i_y3]; NaN where the mass never reaches the zone.
    unsettled : array_like of bool
        Settings where not every entry ends at rest.

    Returns
    -------
    list of matplotlib.patches.Patch
        Legend handles of the exact zeros and of the unsettled cells.

    Examples
    --------
    >>> fig = new_figure("single", 60)
    >>> ax = fig.subplots()
    >>> handles = positioning_error_panel(ax, [1.0, 2.0], [1.0, 2.0], np.array([[0.0, 1e-3], [2e-4, 0.0]]),
    ...                                   np.zeros((2, 2), dtype=bool))
    >>> [h.get_label() for h in handles]
    ['$\\\\Delta x_d = 0$ exactly: every entry accumulates', 'not every entry stops: no $\\\\Delta x_d$']
    """
    dx_d = np.asarray(dx_d, dtype=float)
    unsettled = np.asarray(unsettled, dtype=bool)
    zero = (dx_d == 0.0) & ~unsettled
    positive = (dx_d > 0.0) & ~unsettled
    shown = np.where(positive, dx_d, np.nan)
    norm = LogNorm(*(np.nanmin(shown), np.nanmax(shown))) if positive.any() else LogNorm(1e-6, 1e-2)
    mesh = map_mesh(ax, y2, y3, shown, cmap=QUANTITY_CMAPS["dx_d"], norm=norm)
    ax.figure.colorbar(mesh, ax=ax, label=r"$\Delta x_d > 0$ (eq. 39)")
    return [mark_cells(ax, y2, y3, zero, "dx_zero"), mark_cells(ax, y2, y3, unsettled, "unsettled", UNSETTLED_LABEL)]


def fig17_panels(fig, y2, y3, f, vbar, case, frac_accumulate, unsettled, dx_d, f_max=0.8, mark=None):
    """Fig. 17: a objective f (:func:`objective_panel`), b case (Table 1), c accumulation
    identification (none/some/all of the entries accumulate), d positioning error Delta x_d
    (:func:`positioning_error_panel`).

    c and d show a value only where every entry ends at rest (stops or accumulates):
    ``unsettled`` cells (some entry never stops or stays undecided) are marked "unsettled".
    White: the mass never reaches the zone.  The encodings are legended below the maps.

    Parameters
    ----------
    fig : matplotlib.figure.Figure
    y2, y3 : array_like
        The grid axes.
    f, vbar, case, frac_accumulate, dx_d : array_like
        The maps, indexed [i_y2, i_y3].
    unsettled : array_like of bool
        Settings where not every entry ends at rest.
    f_max : float
        Passed to :func:`objective_panel`.
    mark : tuple or None
        (y2'', y3'', label) of a setting of this plane to mark on every panel.

    Returns
    -------
    matplotlib.figure.Figure
        ``fig``.

    Examples
    --------
    >>> fig = new_figure("double", 150)
    >>> grid = np.array([[0.5, 0.0], [1.0, 1.0]])
    >>> _ = fig17_panels(fig, [1.0, 2.0], [1.0, 2.0], grid, grid, np.array([[1, 1], [3, 3]]), grid,
    ...                  np.zeros((2, 2), dtype=bool), np.array([[1e-3, 2e-3], [0.0, 0.0]]))
    >>> [ax.get_title(loc="left") for ax in fig.axes[:4]]
    ['a', 'b', 'c', 'd']
    """
    axes = fig.subplots(2, 2, sharex=True, sharey=True).ravel()
    handles = objective_panel(axes[0], y2, y3, f, vbar, f_max)
    case_map(axes[1], y2, y3, case)
    mean_velocity_zero_line(axes[1], y2, y3, vbar)
    classes = accumulation_mesh(axes[2], y2, y3, frac_accumulate, unsettled)
    bar = fig.colorbar(classes, ax=axes[2], ticks=range(len(ACCUMULATION_CLASSES)))
    bar.ax.set_yticklabels(ACCUMULATION_CLASSES)
    unsettled_handle = mark_cells(axes[2], y2, y3, unsettled, "unsettled", UNSETTLED_LABEL)
    zero_handle, _ = positioning_error_panel(axes[3], y2, y3, dx_d, unsettled)
    not_reached = not_reached_handle()
    if mark is not None:
        y2_mark, y3_mark, label = mark
        for ax in axes:
            ax.plot(y2_mark, y3_mark, marker="X", markersize=7, markerfacecolor="white", markeredgecolor="k",
                    linestyle="none", label=label)
        handles.append(axes[0].lines[-1])
    fig.legend(handles=handles + [unsettled_handle, zero_handle, not_reached], loc="outside lower center", ncols=2)
    axes[0].xaxis.set_major_locator(MaxNLocator(nbins=5, steps=[1, 2, 5, 10]))
    axes[0].yaxis.set_major_locator(MaxNLocator(nbins=5, steps=[1, 2, 5, 10]))
    for ax in axes:
        ax.label_outer()
    panel_letters(axes)
    return fig


def _stick_map_lines(ax, x_n, formula, simulated, valid, x_stick_min, cobwebs):
    """The content of a Fig. 18 map panel: eq. (59), the exact solver's map, the diagonal, the
    fixed point and the cobwebs of the stick sequences ``cobwebs`` (label, positions)."""
    ax.plot(x_n, np.where(valid, formula, np.nan), color="k", label="eq. (59)")
    ax.plot(x_n, np.where(valid, np.nan, formula), color="k", linestyle="--", linewidth=0.8,
            label="eq. (59) outside its assumptions")
    ax.plot(x_n, simulated, "o", markersize=3, markerfacecolor="none", color=SOLVER_COLOR, label="exact solver")
    ax.plot(x_n, x_n, color="0.5", linewidth=0.8, label="$x_{n+1} = x_n$")
    for (label, seq), color in zip(cobwebs, COBWEB_COLORS):
        # (x0, x0) -> (x0, x1) -> (x1, x1) -> (x1, x2) -> ...
        ax.plot(np.repeat(seq, 2)[:-1], np.concatenate([seq[:1], np.repeat(seq[1:], 2)]), color=color,
                linewidth=0.9, label=label)
    ax.plot(x_stick_min, x_stick_min, marker="*", markersize=9, markerfacecolor="white", markeredgecolor="k",
            linestyle="none", label=r"fixed point $x_{\mathrm{stick,min}}$")
    ax.set_xlabel("$x_n$")
    ax.set_ylabel("$x_{n+1}$")


def stick_map_plot(fig, x_n, formula, simulated, valid, x_mu, x_stick_min, x_threshold, contraction, zoom,
                   cobwebs=()):
    """Fig. 18: a x_{n+1}(x_n) of eq. (59) (solid where its assumptions hold, ``valid``), the
    simulated map, the diagonal, x_mu, the threshold x_c and x_stick_min, and cobwebs of stick
    sequences (label, positions), as in the paper; b the same within ``zoom`` (x0, x1, y0, y1),
    the band the map lies in; c the distances of the sticks to x_stick_min on a log scale
    (:func:`stick_distances`), with the contraction per stick.  One legend below the panels.

    Parameters
    ----------
    fig : matplotlib.figure.Figure
    x_n, formula, simulated, valid : array_like
        Stick positions, eq. (59), the exact solver's next stick, where eq. (59) holds.
    x_mu, x_stick_min, x_threshold, contraction : float
        Zone start, fixed point, threshold x_c and the slope cos(omega (t2 - t1)) at the fixed point.
    zoom : tuple of float
        (x0, x1, y0, y1) of panel b.
    cobwebs : sequence of (str, array_like)
        Stick sequences (at most two: accumulating, resting).

    Returns
    -------
    matplotlib.figure.Figure
        ``fig``.

    Examples
    --------
    >>> fig = new_figure("double", 140)
    >>> x = np.linspace(0.0, 0.05, 5)
    >>> _ = stick_map_plot(fig, x, 0.04 + 0 * x, 0.04 + 0 * x, x < 0.045, 0.0, 0.04, 0.008, 0.15,
    ...                    (0.0, 0.05, 0.038, 0.042), [("run", np.array([0.01, 0.039, 0.04]))])
    >>> [ax.get_title(loc="left") for ax in fig.axes]
    ['a', 'b', 'c']
    """
    axes = fig.subplot_mosaic([["map", "zoom"], ["sticks", "sticks"]], height_ratios=[1.25, 1])
    for ax in (axes["map"], axes["zoom"]):
        _stick_map_lines(ax, x_n, formula, simulated, valid, x_stick_min, cobwebs)
        for x, label, style in ((x_mu, r"$x_\mu$", "--"), (x_threshold, "$x_c$", ":"),
                                (x_stick_min, r"$x_{\mathrm{stick,min}}$", "--")):
            _mark(ax, x, label, style=style)
    x0, x1, y0, y1 = zoom
    axes["zoom"].set_xlim(x0, x1)
    axes["zoom"].set_ylim(y0, y1)
    axes["map"].indicate_inset((x0, y0, x1 - x0, y1 - y0), edgecolor="0.3")
    triangles = stick_distances(axes["sticks"], [(label, seq, color, "-")
                                                 for (label, seq), color in zip(cobwebs, COBWEB_COLORS)],
                                x_stick_min)
    axes["sticks"].text(0.98, 0.95, rf"factor per stick: $\cos(\omega(t_2 - t_1))$ = {contraction:.3g}",
                        transform=axes["sticks"].transAxes, ha="right", va="top")
    fig.legend(handles=axes["map"].get_legend_handles_labels()[0] + triangles, loc="outside lower center",
               ncols=3)
    with rc_context({"axes.titlepad": MARKED_TITLE_PAD}):  # the letters above the marks' labels
        panel_letters([axes["map"], axes["zoom"], axes["sticks"]])
    return fig


def friction_field(ax_sketch, ax_mu, zone, overlap=SKETCH_OVERLAP):
    """Fig. 2: the table with its two friction regions and a body of width w across x_mu
    (``ax_sketch``), and the friction coefficient the body sees against its position,
    mu_bar(x) / mu of eqs. (7)-(9), drawn from ``zone.coefficient`` (``ax_mu``).

    The body's position x is its front edge, so its overlap with the high-friction region is
    z = min(max(x - x_mu, 0), w) (eq. 8); the sketch puts it at z = ``overlap`` w and marks the
    same x on the curve.

    Parameters
    ----------
    ax_sketch, ax_mu : matplotlib.axes.Axes
        The sketch (above) and the coefficient (below), sharing x.
    zone : selfalign.StopZone
        The stop zone: x_mu, w, c_mu and its ``coefficient``.
    overlap : float
        z / w of the body in the sketch, in (0, 1).

    Returns
    -------
    matplotlib.figure.Figure
        The figure of the axes.

    Raises
    ------
    ValueError
        If ``overlap`` is not in (0, 1).

    Examples
    --------
    >>> from selfalign import StopZone
    >>> fig = new_figure("single", 80)
    >>> ax_sketch, ax_mu = fig.subplots(2, 1, sharex=True)
    >>> _ = friction_field(ax_sketch, ax_mu, StopZone(x_mu=0.0, w=0.05, c_mu=2.5))
    >>> float(ax_mu.lines[0].get_ydata().max())
    2.5
    """
    if not 0.0 < overlap < 1.0:
        raise ValueError(f"overlap must be in (0, 1) (the share z / w of the body on the zone), got {overlap!r}")
    x_mu, w, c_mu = zone.x_mu, zone.w, zone.c_mu
    lo, hi = x_mu - 1.6 * w, x_mu + 2.4 * w
    x_body = x_mu + overlap * w
    # The curve: the model's coefficient, sampled densely and at the two ends of the transition.
    x = np.union1d(np.linspace(lo, hi, 401), [x_mu, x_mu + w])
    ax_mu.plot(x, zone.coefficient(x), color="k", label=r"$\bar\mu(x)$, eqs. (7)-(9)")
    ax_mu.axvspan(x_mu, x_mu + w, color=HIGH_COLOR, alpha=0.35, linewidth=0)
    ax_mu.plot([x_body], zone.coefficient([x_body]), "o", color=OKABE_ITO["vermillion"], markersize=4)
    ax_mu.text(lo + 0.1 * w, 1.0, r"$\mu_1 = \mu$", ha="left", va="bottom")
    ax_mu.text(hi - 0.1 * w, c_mu, r"$\mu_2 = c_\mu \mu$", ha="right", va="top")
    ax_mu.text(x_mu + 0.06 * w, c_mu, "eq. (9)", ha="left", va="top")
    ax_mu.set_ylim(1.0 - 0.25 * (c_mu - 1.0) - 0.05, c_mu + 0.25 * (c_mu - 1.0) + 0.05)
    ax_mu.set_yticks([1.0, c_mu], ["1", r"$c_\mu$"])
    ax_mu.set_ylabel(r"$\bar\mu / \mu$")
    ax_mu.set_xlabel("position $x$ of the body (its front edge)")
    ax_mu.set_xticks([x_mu - w, x_mu, x_mu + w, x_mu + 2 * w],
                     [r"$x_\mu - w$", r"$x_\mu$", r"$x_\mu + w$", r"$x_\mu + 2w$"])
    ax_mu.set_xlim(lo, hi)
    # The sketch: the table has a step at x_mu; the body of width w overlaps it by z.
    _table(ax_sketch, lo, hi, x_mu, None)
    ax_sketch.text(0.5 * (lo + x_mu), -0.5, r"$\mu_1 = \mu$", ha="center", va="center")
    ax_sketch.text(0.5 * (x_mu + hi), -0.5, r"$\mu_2 = c_\mu \mu$", ha="center", va="center")
    ax_sketch.add_patch(Rectangle((x_body - w, 0.0), w, 0.7, facecolor="white", edgecolor="k", linewidth=1.0))
    ax_sketch.plot([x_body], [0.0], "o", color=OKABE_ITO["vermillion"], markersize=4, clip_on=False, zorder=3)
    dimension(ax_sketch, x_body - w, x_body, 1.0, "$w$", color="k")
    dimension(ax_sketch, x_mu, x_body, 0.35, "$z$", color="k")
    ax_sketch.plot([x_mu, x_mu], [-1.0, 0.75], color="k", linestyle=":", linewidth=0.8)
    ax_sketch.axvline(x_body, color=OKABE_ITO["vermillion"], linestyle=":", linewidth=0.8)
    ax_sketch.text(x_body, 1.01, "$x$", transform=ax_sketch.get_xaxis_transform(), ha="center", va="bottom",
                   fontsize=SMALL_FONT_SIZE, color=OKABE_ITO["vermillion"])
    ax_sketch.set_ylim(-1.0, 1.45)
    ax_sketch.set_yticks([])
    ax_sketch.tick_params(labelbottom=False)
    ax_mu.plot([x_body, x_body], [ax_mu.get_ylim()[0], zone.coefficient(x_body)], color=OKABE_ITO["vermillion"],
               linestyle=":", linewidth=0.8)
    return ax_mu.figure


# ---------------------------------------------------------------------------------------
# Builders from result files (Fig. 2: from the stop zone itself)
# ---------------------------------------------------------------------------------------

def _setting(result, key):
    groups = result["groups"]
    if key not in groups:
        raise ValueError(f"setting {key!r} not in the result; it holds {sorted(groups)}")
    return groups[key]


@styled
def figure_02(zone):
    """Fig. 2 (Sect. 3.3): the two friction regions, the body of width w with its overlap z
    across x_mu, and the coefficient mu_bar(x) of eqs. (7)-(9) from ``zone.coefficient``
    (:func:`friction_field`); one column wide.

    Parameters
    ----------
    zone : selfalign.StopZone
        The stop zone drawn (x_mu, w, c_mu).

    Returns
    -------
    matplotlib.figure.Figure

    Examples
    --------
    >>> from selfalign import StopZone
    >>> from selfalign.plots.style import print_check
    >>> fig = figure_02(StopZone(x_mu=0.0, w=0.05, c_mu=2.5))
    >>> [ax.get_title(loc="left") for ax in fig.axes], print_check(fig)
    (['a', 'b'], [])
    """
    fig = new_figure("single", 80)
    ax_sketch, ax_mu = fig.subplots(2, 1, sharex=True, height_ratios=[1, 1.3])
    friction_field(ax_sketch, ax_mu, zone)
    panel_letters([ax_sketch, ax_mu])
    return fig


@styled
def figure_14(result, key):
    """Fig. 14 from ``fig16.h5``: the entry of setting ``key`` that stops farthest
    (:func:`situation_sketch`); two columns wide.

    Parameters
    ----------
    result : dict
        ``fig16.h5`` in :func:`selfalign.io.hdf5.read_h5` layout.
    key : str
        The setting's group (:func:`selfalign.stages.accumulation.setting_group`).

    Returns
    -------
    matplotlib.figure.Figure

    Raises
    ------
    ValueError
        If the result holds no setting ``key``.
    """
    g = _setting(result, key)
    d, a = g["datasets"], g["attrs"]
    i = int(np.nanargmax(d["overshoot"]))
    fig = new_figure("double", 55)
    return situation_sketch(fig.subplots(), d["x0"][i], d["x_end"][i], a["x_mu"], result["attrs"]["w"],
                            a["x_stick_min"])


@styled
def figure_15(result, key):
    """Fig. 15 from ``fig16.h5``: the end positions of all entries of setting ``key``
    (:func:`end_position_region`); one column wide.

    Parameters
    ----------
    result : dict
        ``fig16.h5`` in :func:`selfalign.io.hdf5.read_h5` layout.
    key : str
        The setting's group.

    Returns
    -------
    matplotlib.figure.Figure

    Raises
    ------
    ValueError
        If the result holds no setting ``key``.
    """
    g = _setting(result, key)
    d, a = g["datasets"], g["attrs"]
    fig = new_figure("single", 85)
    return end_position_region(fig.subplots(), d["s"], d["overshoot"], a["x_mu"], a["x_stick_min"], a["dx_d"],
                               a["x_d"])


@styled
def figure_16(result, keys):
    """Fig. 16 from ``fig16.h5``: phase portraits of the settings ``keys``, two entries each,
    and their sticks in the zone (x >= x_mu) (:func:`phase_portraits`); two columns wide.

    Parameters
    ----------
    result : dict
        ``fig16.h5`` in :func:`selfalign.io.hdf5.read_h5` layout.
    keys : list of str
        The settings' groups, one row each.

    Returns
    -------
    matplotlib.figure.Figure

    Raises
    ------
    ValueError
        If the result holds no setting of ``keys``.
    """
    panels = []
    for key in keys:
        g = _setting(result, key)
        a = g["attrs"]
        entries = []
        for e in (g["groups"]["entry_0"], g["groups"]["entry_1"]):
            d = e["datasets"]
            label = (f"$x_{{0s}} = {g['datasets']['x0'][e['attrs']['index']]:.4f}$: {e['attrs']['status']}, "
                     f"end {e['attrs']['x_end']:.5f}")
            entries.append((d["x"], d["v"], label, d["stick_x"][d["stick_x"] >= a["x_mu"]]))
        panels.append({"x_mu": a["x_mu"], "x_stick_min": a["x_stick_min"], "entries": entries})
    return phase_portraits(new_figure("double", 75 * len(keys)), panels)


@styled
def figure_17(result, stick_map=None):
    """Fig. 17 from ``fig17.h5`` (:func:`fig17_panels`); two columns wide.

    The setting of ``stick_map`` (``fig18.h5``, Fig. 18) is marked only when it is a point of
    this plane (the grid's Delta t and Delta y): at another Delta t the same (y2'', y3'') is
    another profile (Fig. 18's setting at Delta t = 1.05 is case 0 at Delta t = 1), so the
    caption tells where it lies instead.

    Parameters
    ----------
    result : dict
        ``fig17.h5`` in :func:`selfalign.io.hdf5.read_h5` layout.
    stick_map : dict or None
        ``fig18.h5``, whose setting is marked if it lies in this plane.

    Returns
    -------
    matplotlib.figure.Figure
    """
    d, a = result["datasets"], result["attrs"]
    mark = None
    if stick_map is not None:
        s = stick_map["attrs"]
        if s["dt"] == a["dt"] and s["dy"] == a["dy"]:
            mark = (s["y2"], s["y3"], "Fig. 18 setting")
    # Delta x_d spans only the entries that stopped: shown where every entry ends at rest.
    unsettled = (d["frac_never_stop"] > 0) | (d["frac_undecided"] > 0)
    fig = new_figure("double", 145)
    return fig17_panels(fig, d["y2"], d["y3"], d["f"], d["vbar"], d["case"], d["frac_accumulate"], unsettled,
                        d["dx_d"], mark=mark)


@styled
def figure_18(result):
    """Fig. 18 from ``fig18.h5`` (:func:`stick_map_plot`); panel b zooms on the band of x_{n+1}
    the map and the stick sequences lie in; two columns wide.

    Parameters
    ----------
    result : dict
        ``fig18.h5`` in :func:`selfalign.io.hdf5.read_h5` layout.

    Returns
    -------
    matplotlib.figure.Figure
    """
    d, a = result["datasets"], result["attrs"]
    cobwebs = (("stick positions from above $x_c$", d["cobweb_accumulate"]),
               ("stick positions from below $x_c$", d["cobweb_rest"]))
    band = np.concatenate([d["x_next_formula"][d["valid"]], d["cobweb_accumulate"][1:], d["cobweb_rest"][1:]])
    margin = 0.15 * (band.max() - band.min())
    zoom = (a["x_mu"], a["x_mu"] + a["w"], band.min() - margin, band.max() + margin)
    fig = new_figure("double", 150)
    return stick_map_plot(fig, d["x_n"], d["x_next_formula"], d["x_next_simulated"], d["valid"], a["x_mu"],
                          a["x_stick_min"], a["x_threshold"], a["contraction"], zoom, cobwebs)
