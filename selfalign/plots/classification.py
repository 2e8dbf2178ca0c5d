"""Plot functions for the steady-state studies: Figs. 4, 5, 6, 8, 10 and 11.

As in :mod:`selfalign.plots.profile`: each function draws data it is given onto a
matplotlib ``Figure`` and returns it; no physics, no file writes, only the
object-oriented API.  ``figure_NN(result)`` builds figure NN from a result file
read with :func:`selfalign.io.hdf5.read_h5` (the layouts are in docs/reference/results.md,
"Steady state and classification") at print size (:mod:`selfalign.plots.style`); the
parameters of each figure are in its caption.  Fig. 8 is drawn by walking the decision
tree of :mod:`selfalign.analysis.classification` — the tree that classifies the maps —
so the flow chart cannot disagree with the code.
"""

from __future__ import annotations

import re
import textwrap

import numpy as np
from matplotlib.colors import LogNorm
from matplotlib.lines import Line2D
from matplotlib.patches import Patch, Rectangle
from matplotlib.ticker import NullFormatter

from ..analysis.classification import DECISION_TREE, Decision
from .style import (
    CASE_COLORS,
    CASE_TEXT,
    LINE_COLORS,
    OKABE_ITO,
    QUANTITY_CMAPS,
    SMALL_FONT_SIZE,
    case_map,
    cell_edges,
    ink,
    map_mesh,
    mark_cells,
    new_figure,
    panel_letters,
    styled,
)

#: Mathtext of the quantities the decision tree tests, and what they mean.
QUANTITIES = {
    "q": ("q", r"$q = 8\,\Delta y\,(1/y_2'' + 1/y_3'')\,/\,\Delta t^2$: a physical profile needs $q \leq 1$"),
    "y2": ("y_2''", None),
    "y3": ("y_3''", None),
    "t1": ("t_1", None),
    "v_back": ("v_{back}", r"$v_{back} = -x'(t_3)$ of a mass at rest at $t_1$ (it sticks again in "
                           r"$[0, t_1]$ iff $v_{back} \leq t_1$)"),
}
_OPS = {"<=": r"\leq", "<": "<", ">": ">", ">=": r"\geq"}


# --------------------------------------------------------------------------------------
# Figs. 4 and 5
# --------------------------------------------------------------------------------------

#: Relative differences below this are rounding: drawn on the lower edge of the panel, as
#: open triangles (the time-stepping steady motion coincides with the exact one there).
ROUNDING_FLOOR = 1e-6


def objective_sweep(fig, x, f_exact, f_moreau, xlabel: str, moreau_label: str = "time-stepping",
                    legend_loc: str = "best"):
    """f (eq. 11) along a parameter sweep: (a) exact solver (line) and time-stepping
    (circles), log-log, with the legend at ``legend_loc``; (b) the relative difference of the
    time-stepping value, with the differences below :data:`ROUNDING_FLOOR` drawn as triangles
    on the floor."""
    x, f_exact, f_moreau = (np.asarray(a, dtype=float) for a in (x, f_exact, f_moreau))
    ax_f, ax_d = fig.subplots(2, 1, sharex=True, height_ratios=[2.2, 1])
    ax_f.loglog(x, f_exact, color="k", label="exact solver")
    ax_f.loglog(x, f_moreau, linestyle="none", marker="o", markerfacecolor="none", color=LINE_COLORS[0],
                label=moreau_label)
    ax_f.set_ylabel(r"$f = 1 / (c\,\bar v^2)$")
    ax_f.grid(True, which="major", linewidth=0.4, alpha=0.5)
    with np.errstate(divide="ignore", invalid="ignore"):
        rel = np.abs(f_moreau / f_exact - 1.0)
    rounding = rel < ROUNDING_FLOOR
    ax_d.loglog(x[~rounding], rel[~rounding], linestyle="none", marker="o", color=LINE_COLORS[0])
    floor = ax_d.plot(x[rounding], np.full(np.count_nonzero(rounding), ROUNDING_FLOOR), linestyle="none",
                      marker="v", markerfacecolor="none", color=LINE_COLORS[0],
                      label=rf"(b) below $10^{{{np.log10(ROUNDING_FLOOR):.0f}}}$, drawn at the floor")
    ax_d.set_ylim(ROUNDING_FLOOR / 2, 2.0)
    ax_d.set_ylabel(r"$|f_{\mathrm{ts}} / f_{\mathrm{exact}} - 1|$")
    ax_d.set_xlabel(xlabel)
    ax_d.grid(True, which="major", linewidth=0.4, alpha=0.5)
    handles = ax_f.get_lines() + (floor if rounding.any() else [])
    ax_f.legend(handles=handles, loc=legend_loc)
    panel_letters([ax_f, ax_d])
    return fig


def _sweep_figure(result, swept: str, xlabel: str, legend_loc: str):
    d = result["datasets"]
    return objective_sweep(new_figure("single", 95), d[swept], d["f_exact"], d["f_moreau"], xlabel,
                           legend_loc=legend_loc)


@styled
def figure_04(result):
    """Fig. 4: f against dt (results/classification/fig04.h5)."""
    return _sweep_figure(result, "dt", r"$\Delta t$", "upper left")


@styled
def figure_05(result):
    """Fig. 5: f against dy (results/classification/fig05.h5)."""
    return _sweep_figure(result, "dy", r"$\Delta y$", "upper right")


# --------------------------------------------------------------------------------------
# Fig. 6
# --------------------------------------------------------------------------------------

#: Shading of the intervals in which the mass slides back (x' < 0), Fig. 6.
SLIDING_BACK = {"color": OKABE_ITO["orange"], "alpha": 0.3, "linewidth": 0}
#: The table's displacement beside the mass's, Fig. 6 (d, e).
TABLE_COLOR = "0.6"


def fourier_optimum(fig, d: dict, a: dict):
    """Fig. 6: optimised Fourier profile against its start and the best three-phase profile:
    (a-c) y, y', y'' over one period (the actuator bounds dash-dotted); (d, e) the steady
    displacement x of the mass relative to the table beside the table's y under both (x flat
    where the mass sticks, falling where it slides back, x' < 0, shaded); (f) f per optimiser
    iteration, the final values in the legend.

    ``d`` holds the datasets of ``results/classification/fig06.h5`` plus ``<name>_motion_x``
    (x of the mass relative to the table, for ``fourier`` and ``three_phase``); ``a`` its
    attributes."""
    axes = fig.subplots(3, 2, gridspec_kw={"width_ratios": [1.1, 1]})
    styles = (("fourier", "optimised Fourier", {"color": "k"}),
              ("start", "start (polynomial, 12 harmonics)", {"color": "0.5", "linestyle": ":"}),
              ("three_phase", "best three-phase", {"color": LINE_COLORS[1], "linestyle": "--"}))
    labels = (("y", "$y$"), ("yd", "$y'$"), ("ydd", "$y''$"))
    for ax, (key, ylabel) in zip(axes[:, 0], labels):
        for name, label, style in styles:
            ax.plot(d["t"], d[f"{name}_{key}"], label=label, linewidth=0.9, **style)
        ax.set_ylabel(ylabel)
        ax.set_xlim(d["t"][0], d["t"][-1])
    bound_style = {"color": "0.3", "linewidth": 0.6, "linestyle": "-."}
    for ax, bound in ((axes[1, 0], a["yd_max"]), (axes[2, 0], a["ydd_max"])):
        for sign in (1, -1):
            ax.axhline(sign * bound, **bound_style)
    bounds = Line2D([], [], **bound_style, label=r"actuator bounds $\pm y'_{\max}$, $\pm y''_{\max}$")
    axes[2, 0].set_xlabel("$t$")
    for ax, name in ((axes[0, 1], "fourier"), (axes[1, 1], "three_phase")):
        t, v = d[f"{name}_motion_t"], d[f"{name}_motion_v"]
        ax.fill_between(t, 0.0, 1.0, where=v < 0.0, transform=ax.get_xaxis_transform(), **SLIDING_BACK)
        ax.plot(t, d[f"{name}_motion_y"], color=TABLE_COLOR, linewidth=0.7)
        ax.plot(t, d[f"{name}_motion_x"], linewidth=0.9, **dict((s[0], s[2]) for s in styles)[name])
        ax.set_ylabel("$x$, $y$")
        ax.set_xlim(t[0], t[-1])
    table = Line2D([], [], color=TABLE_COLOR, linewidth=0.7, label="$y$ of the table (d, e)")
    fig.legend(handles=axes[0, 0].get_lines() + [bounds, table, Patch(**SLIDING_BACK, label="$x' < 0$ (d, e)")],
               loc="outside upper center", ncols=3)
    axes[1, 1].set_xlabel("$t$")
    hist = axes[2, 1]
    hist.semilogy(np.arange(d["history_f"].size), d["history_f"], color="k", marker=".", markersize=2,
                  linewidth=0.8, label=rf"Fourier (SQP iterates), final $f$ = {_sci(a['fourier_f'])}")
    hist.axhline(a["three_phase_f"], color=LINE_COLORS[1], linestyle="--",
                 label=rf"best three-phase, $f$ = {_sci(a['three_phase_f'])}")
    # Whole decades, with room above the iterates for the legend.
    low, high = np.log10(np.min(d["history_f"])), np.log10(np.max(d["history_f"]))
    hist.set_ylim(10.0 ** np.floor(low), 10.0 ** np.ceil(high + 0.5))
    hist.yaxis.set_minor_formatter(NullFormatter())
    hist.set_xlabel("iteration")
    hist.set_ylabel("$f$")
    hist.legend(loc="upper right")
    panel_letters(axes.T.ravel())
    return fig


def _sci(value: float) -> str:
    """``value`` to three digits in mathtext, 1.28e-04 as $1.28 \\cdot 10^{-4}$."""
    mantissa, exponent = f"{value:.2e}".split("e")
    return rf"${mantissa} \cdot 10^{{{int(exponent)}}}$" if int(exponent) else f"${mantissa}$"


@styled
def figure_06(result, mass_displacement: dict):
    """Fig. 6 from results/classification/fig06.h5 and ``mass_displacement``: profile name
    (``fourier``, ``three_phase``) -> x of the mass relative to the table at ``<name>_motion_t``."""
    datasets = dict(result["datasets"])
    datasets.update({f"{name}_motion_x": x for name, x in mass_displacement.items()})
    return fourier_optimum(new_figure("double", 150), datasets, result["attrs"])


# --------------------------------------------------------------------------------------
# Fig. 8
# --------------------------------------------------------------------------------------

#: Plain-text spellings in the questions of the decision tree and their mathtext.
#: (No blank inside the mathtext, so that wrapping the question cannot split it.)
_QUESTION_MATH = (("[t1, t2]", r"$[t_1,\,t_2]$"), ("[t2, t3]", r"$[t_2,\,t_3]$"), ("[0, t1]", r"$[0,\,t_1]$"),
                  ("t3", "$t_3$"))


def question_text(label: str) -> str:
    """A question of the decision tree as Fig. 8 prints it: intervals and times in mathtext, the
    parenthesised condition left out (the box prints it below the question, in mathtext).

    >>> print(question_text("Can the mass slip forward in [t1, t2] (y2'' > 1)?"))
    Can the mass slip forward in $[t_1,\\,t_2]$?
    """
    text = re.sub(r"\s*\([^)]*\)", "", label)
    for plain, math in _QUESTION_MATH:
        text = text.replace(plain, math)
    return text


def _condition_text(condition) -> str:
    def term(x):
        if isinstance(x, str):
            return QUANTITIES.get(x, (rf"\mathrm{{{x}}}", None))[0]
        return f"{x:g}"
    return f"${term(condition.lhs)} {_OPS[condition.op]} {term(condition.rhs)}$"


def tree_layout(tree) -> dict[str, tuple[float, int]]:
    """(x, depth) of every node: leaves at x = 0, 1, ... in depth-first order ("yes" first),
    decisions centred over their children."""
    children: dict[str, list[str]] = {}
    for parent, child, _ in tree.edges():
        children.setdefault(parent, []).append(child)
    pos: dict[str, tuple[float, int]] = {}
    next_leaf = [0]

    def place(node, depth):
        kids = children.get(node, [])
        for kid in kids:
            place(kid, depth + 1)
        if kids:
            x = float(np.mean([pos[k][0] for k in kids]))
        else:
            x, next_leaf[0] = float(next_leaf[0]), next_leaf[0] + 1
        pos[node] = (x, depth)

    place(tree.root, 0)
    return pos


def decision_tree(fig, tree=DECISION_TREE, width: int = 17):
    """Fig. 8: the flow chart of the a-priori case decision, drawn from ``tree``.

    Every node of ``tree.nodes()`` becomes a box (decisions: the question, wrapped at
    ``width`` characters, and its condition; leaves: the case of Table 1 in its map colour),
    every edge of ``tree.edges()`` an arrow labelled yes / no; the quantities the conditions
    use are explained below the chart.
    """
    ax = fig.add_subplot()
    ax.set_axis_off()
    pos = tree_layout(tree)
    boxes = {}
    for node_id, attrs in tree.nodes():
        x, depth = pos[node_id]
        node = tree[node_id]
        if isinstance(node, Decision):
            text = textwrap.fill(question_text(attrs["label"]), width) + "\n" + _condition_text(node.condition)
            style = {"boxstyle": "round,pad=0.3", "facecolor": "white", "edgecolor": "k", "linewidth": 0.6}
        else:
            text = f"case {attrs['case']}\n" + textwrap.fill(CASE_TEXT[attrs["case"]], 11, break_on_hyphens=False,
                                                                      break_long_words=False)
            # The map colour itself (no transparency), so a leaf matches its cells in Figs. 10, 11, 17.
            style = {"boxstyle": "round4,pad=0.3", "facecolor": CASE_COLORS[attrs["case"]], "edgecolor": "k",
                     "linewidth": 0.6}
        boxes[node_id] = ax.text(x, -depth, text, ha="center", va="center", fontsize=SMALL_FONT_SIZE, bbox=style,
                                 zorder=3, color=ink(style["facecolor"]))
    for parent, child, label in tree.edges():
        (x0, d0), (x1, d1) = pos[parent], pos[child]
        ax.annotate("", xy=(x1, -d1), xytext=(x0, -d0),
                    arrowprops={"arrowstyle": "-|>", "color": "0.25", "linewidth": 0.8,
                                "patchA": boxes[parent].get_bbox_patch(),
                                "patchB": boxes[child].get_bbox_patch(), "shrinkA": 1, "shrinkB": 1})
        ax.text(0.5 * (x0 + x1), -0.5 * (d0 + d1), label, ha="center", va="center", fontsize=SMALL_FONT_SIZE,
                # Not blue / vermillion: those are the colours of cases 1 and 2.
                color="k" if label == "yes" else "0.35", fontweight="bold" if label == "yes" else "normal",
                zorder=4, bbox={"boxstyle": "round,pad=0.1", "facecolor": "white", "edgecolor": "none"})
    xs = [p[0] for p in pos.values()]
    depth = max(p[1] for p in pos.values())
    ax.set_xlim(min(xs) - 0.55, max(xs) + 0.55)
    ax.set_ylim(-depth - 0.5, 0.45)
    used = []
    for node_id, attrs in tree.nodes():
        if attrs["kind"] == "decision":
            cond = tree[node_id].condition
            used += [t for t in (cond.lhs, cond.rhs) if isinstance(t, str) and t not in used]
    notes = [QUANTITIES[q][1] for q in used if q in QUANTITIES and QUANTITIES[q][1]]
    notes.append(r"ties $|y''| = 1$ stick")
    # The lowest leaves are at the left (yes first), so the notes go to the bottom right.
    ax.text(0.995, 0.0, "\n".join(notes), fontsize=SMALL_FONT_SIZE, va="bottom", ha="right", transform=ax.transAxes)
    return fig


@styled
def figure_08(tree=DECISION_TREE):
    """Fig. 8 from the decision tree itself (no result file: the tree is code)."""
    return decision_tree(new_figure("double", 120), tree)


# --------------------------------------------------------------------------------------
# Figs. 10 and 11 (and panels a, b of Fig. 17)
# --------------------------------------------------------------------------------------

def mean_velocity_zero_line(ax, y2, y3, vbar) -> Line2D:
    """The line vbar = 0 (dashed) over a map; returns its legend handle."""
    ax.contour(y2, y3, np.ma.masked_invalid(np.asarray(vbar, dtype=float).T), levels=[0.0], colors="k",
               linestyles="--", linewidths=0.9)
    return Line2D([], [], color="k", linestyle="--", linewidth=0.9, label=r"$\bar v = 0$")


def objective_norm(f, f_max: float) -> LogNorm:
    """The logarithmic colour scale of f on a map.

    Parameters
    ----------
    f : array_like
        The objective (eq. 11) over the map; NaN (case 0) and inf (pure stick) are ignored.
    f_max : float
        The top of the scale, > 0: larger values are clipped to it.

    Returns
    -------
    matplotlib.colors.LogNorm
        From the smallest finite f > 0 of the map (a decade below ``f_max`` if there is none
        below ``f_max``) to ``f_max``.

    Raises
    ------
    ValueError
        If ``f_max`` is not a finite number > 0.

    Examples
    --------
    >>> norm = objective_norm([0.08, 0.5, float("inf"), float("nan"), 3.0], 0.8)
    >>> norm.vmin, norm.vmax
    (0.08, 0.8)
    """
    if not (isinstance(f_max, (int, float, np.floating)) and np.isfinite(f_max) and f_max > 0):
        raise ValueError(f"f_max must be a finite number > 0, got {f_max!r}")
    f = np.asarray(f, dtype=float)
    shown = f[np.isfinite(f) & (f > 0)]
    low = float(shown.min()) if shown.size else f_max / 10.0
    return LogNorm(vmin=low if low < f_max else f_max / 10.0, vmax=f_max)


def _objective_cells(ax, y2, y3, f, vbar, norm):
    """The cells of f (eq. 11) on the colour scale ``norm`` (values above its top in the
    colour of the top) and the special values over them; returns (mesh, legend handles of
    the special values that occur)."""
    f = np.asarray(f, dtype=float)
    mesh = map_mesh(ax, y2, y3, np.where(np.isfinite(f), f, np.nan), cmap=QUANTITY_CMAPS["f"], norm=norm)
    with np.errstate(invalid="ignore"):
        backward = np.asarray(vbar, dtype=float) < 0.0
    handles = [mean_velocity_zero_line(ax, y2, y3, vbar)]
    for kind, mask in (("non_physical", np.isnan(f)), ("f_infinite", np.isposinf(f)), ("v_negative", backward)):
        handle = mark_cells(ax, y2, y3, mask, kind)
        if mask.any():
            handles.append(handle)
    return mesh, handles


def objective_panel(ax, y2, y3, f, vbar, f_max: float):
    """f (eq. 11) over (y2'', y3'') with its colour bar and its special values.

    f is drawn on a logarithmic colour scale (``QUANTITY_CMAPS["f"]``, :func:`objective_norm`)
    from the smallest f of the map to ``f_max``, so that the structure far below the clip
    shows; values >= ``f_max`` are drawn in the colour of ``f_max`` (the colour bar's
    "extend max" triangle), as the paper limits f "for clarity".  Special values
    (:data:`selfalign.plots.style.SPECIAL`, :func:`selfalign.plots.style.mark_cells`):
    f = inf (vbar = 0: pure stick, case 5, or a motion whose forward and backward slips
    cancel exactly) black, case 0 (no physical profile, f NaN) grey, and, since
    f = 1/(c vbar^2) is blind to the direction of motion, vbar < 0 hatched, with the line
    vbar = 0 dashed.

    Parameters
    ----------
    ax : matplotlib.axes.Axes
        The panel.
    y2, y3 : array_like
        The increasing grid axes (n,) and (m,).
    f, vbar : array_like
        The objective and the mean velocity, indexed [i_y2, i_y3] (n, m).
    f_max : float
        The top of the colour scale, > 0.

    Returns
    -------
    list of matplotlib.artist.Artist
        Legend handles: the line vbar = 0, then each special value that occurs on the map.

    Raises
    ------
    ValueError
        If ``f_max`` is not a finite number > 0.

    Examples
    --------
    >>> import numpy as np
    >>> from selfalign.plots.style import new_figure
    >>> ax = new_figure("single", 60).subplots()
    >>> f = np.array([[np.nan, np.inf], [0.1, 2.0]])
    >>> vbar = np.array([[np.nan, 0.0], [-0.03, 0.007]])
    >>> for handle in objective_panel(ax, [1.0, 2.0], [1.0, 2.0], f, vbar, 0.8):
    ...     print(handle.get_label())
    $\\bar v = 0$
    case 0: no physical profile
    $f = \\infty$: $\\bar v = 0$
    $\\bar v < 0$: walks backward
    """
    mesh, handles = _objective_cells(ax, y2, y3, f, vbar, objective_norm(f, f_max))
    bar = ax.figure.colorbar(mesh, ax=ax, extend="max")
    bar.set_label(rf"$f$ (values $\geq$ {f_max:g} drawn as {f_max:g})")
    return handles


def backward_window(y2, y3, vbar, share: float = 0.05):
    """The window of a map that holds its few cells with vbar < 0, to magnify them.

    Parameters
    ----------
    y2, y3 : array_like
        The increasing grid axes (n,) and (m,).
    vbar : array_like
        The mean velocity, indexed [i_y2, i_y3] (n, m).
    share : float
        The largest share of the map's area the window may cover.

    Returns
    -------
    tuple or None
        ((y2 low, y2 high), (y3 low, y3 high)): the cells with vbar < 0 and a margin of three
        cells, if that window covers less than ``share`` of the map's area (too few cells to
        see at print size); None if it is larger or there is no such cell.

    Examples
    --------
    >>> import numpy as np
    >>> vbar = np.ones((40, 40))
    >>> vbar[2, 30] = -1.0
    >>> backward_window(np.arange(40.0), np.arange(40.0), vbar)
    ((-0.5, 5.5), (26.5, 33.5))
    >>> backward_window(np.arange(40.0), np.arange(40.0), -vbar) is None
    True
    """
    with np.errstate(invalid="ignore"):
        i, j = np.nonzero(np.asarray(vbar, dtype=float) < 0.0)
    if i.size == 0:
        return None
    e2, e3 = cell_edges(y2), cell_edges(y3)
    lo2, hi2 = max(i.min() - 3, 0), min(i.max() + 4, y2.size)
    lo3, hi3 = max(j.min() - 3, 0), min(j.max() + 4, y3.size)
    window = ((float(e2[lo2]), float(e2[hi2])), (float(e3[lo3]), float(e3[hi3])))
    covered = (window[0][1] - window[0][0]) * (window[1][1] - window[1][0])
    return window if covered < share * (e2[-1] - e2[0]) * (e3[-1] - e3[0]) else None


def objective_map(fig, y2, y3, f, case, vbar, f_max: float):
    """Figs. 10 and 11: (a) f (eq. 11) over (y2'', y3'') (:func:`objective_panel`) beside (b)
    the case of Table 1, with the line vbar = 0 on both; where the cells with vbar < 0 are too
    few to see (:func:`backward_window`), (c) magnifies them, on the colour scale of (a), and
    (a) outlines the window.  Arrays are indexed [i_y2, i_y3]."""
    y2, y3 = np.asarray(y2, dtype=float), np.asarray(y3, dtype=float)
    window = backward_window(y2, y3, vbar)
    if window is None:
        ax_f, ax_c = fig.subplots(1, 2)
        axes = [ax_f, ax_c]
    else:
        grid = fig.add_gridspec(2, 2, height_ratios=[1.2, 1])
        ax_f, ax_c, ax_z = fig.add_subplot(grid[0, 0]), fig.add_subplot(grid[0, 1]), fig.add_subplot(grid[1, 0])
        axes = [ax_f, ax_c, ax_z]
        ax_legend = fig.add_subplot(grid[1, 1])
        ax_legend.set_axis_off()
    handles = objective_panel(ax_f, y2, y3, f, vbar, f_max)
    case_map(ax_c, y2, y3, case)
    mean_velocity_zero_line(ax_c, y2, y3, vbar)
    if window is not None:
        _objective_cells(ax_z, y2, y3, f, vbar, ax_f.collections[0].norm)
        ax_z.set_xlim(*window[0])
        ax_z.set_ylim(*window[1])
        (x0, x1), (z0, z1) = window
        handles.append(ax_f.add_patch(Rectangle((x0, z0), x1 - x0, z1 - z0, facecolor="none", linewidth=1.0,
                                                edgecolor=OKABE_ITO["vermillion"], label="window of (c)")))
        ax_legend.legend(handles=handles, loc="center left")
    else:
        fig.legend(handles=handles, loc="outside lower center", ncols=len(handles))
    panel_letters(axes)
    return fig


@styled
def figure_map(result, f_max: float):
    """Fig. 10 or 11 from results/classification/fig10.h5 or fig11.h5."""
    d = result["datasets"]
    height = 75 if backward_window(d["y2"], d["y3"], d["vbar"]) is None else 130
    return objective_map(new_figure("double", height), d["y2"], d["y3"], d["f"], d["case"], d["vbar"], f_max)
