"""Plots of the stability and convergence stages (Sect. 6): Fig. 13 and the map of the second
Floquet multiplier over the plane of Fig. 17.

Like :mod:`selfalign.plots.profile`, the functions draw given data with the
object-oriented matplotlib API and compute no physics; :func:`figure_13` builds the figure
from a convergence result and :func:`figure_floquet_map` from a stability grid
(:func:`selfalign.io.hdf5.read_h5` layout) at print size (:mod:`selfalign.plots.style`), and
:func:`selfalign.stages.common.save_figure` writes them.
"""

from __future__ import annotations

import numpy as np
from matplotlib.collections import LineCollection
from matplotlib.colors import LogNorm, Normalize
from matplotlib.lines import Line2D
from matplotlib.patheffects import withStroke

from .style import (
    CASE_COLORS,
    LINE_COLORS,
    OKABE_ITO,
    QUANTITY_CMAPS,
    cell_edges,
    label_regions,
    map_mesh,
    mark_cells,
    new_figure,
    panel_letters,
    styled,
)

#: Shading of the intervals where the selected signs differ (V' < 0), Fig. 13.
DIFFERENT = OKABE_ITO["bluish green"]
DIFFERENT_ALPHA = 0.2


def convergence_panels(fig, t, v1, v2, V, starts, ends, equal, labels=("$v_1$", "$v_2$")):
    """Fig. 13: (a) two velocity transients and (b) V = (v1 - v2)^2 / 2.

    Intervals where the selected elements of Sign(v1), Sign(v2) agree are
    marked "=" above the V curve, those where they differ "≠" and shaded in
    both panels (Sect. 6.2).
    """
    t, v1, v2, V = (np.asarray(a, dtype=float) for a in (t, v1, v2, V))
    ax_v, ax_V = fig.subplots(2, 1, sharex=True)
    ax_v.plot(t, v1, color=LINE_COLORS[0], label=labels[0])
    ax_v.plot(t, v2, color=LINE_COLORS[1], linestyle="--", label=labels[1])
    ax_v.axhline(0.0, color="0.4", linewidth=0.6)
    ax_v.set_ylabel("$v = x'$")
    ax_v.legend(loc="upper right")

    ax_V.plot(t, V, color="k", label="$V$")
    ax_V.set_ylabel(r"$V = (v_1 - v_2)^2 / 2$")
    ax_V.set_xlabel("$t$")
    ax_V.set_xlim(t[0], t[-1])
    top = float(np.max(V)) if V.size else 1.0
    ax_V.set_ylim(-0.05 * top, 1.25 * top if top > 0 else 1.0)
    for a, b, same in zip(starts, ends, equal):
        if not same:
            for ax in (ax_v, ax_V):
                ax.axvspan(a, b, color=DIFFERENT, alpha=DIFFERENT_ALPHA, linewidth=0)
        ax_V.text(0.5 * (a + b), 1.12 * top, "=" if same else "≠", ha="center", va="center")
    panel_letters([ax_v, ax_V])
    return fig


@styled
def figure_13(result: dict):
    """Fig. 13 from a convergence result (:func:`selfalign.analysis.lyapunov.convergence_result`)."""
    d, a = result["datasets"], result["attrs"]
    labels = (rf"$v_1$, $v_{{10}}$ = {a['v10']:g}", rf"$v_2$, $v_{{20}}$ = {a['v20']:g}")
    return convergence_panels(new_figure("single", 80), d["t"], d["v1"], d["v2"], d["V"], d["interval_start"],
                              d["interval_end"], d["interval_equal"], labels=labels)


# --------------------------------------------------------------------------------------
# The second Floquet multiplier over the (y2'', y3'') plane (Sect. 6.1, eq. 33)
# --------------------------------------------------------------------------------------

#: Differences below this are rounding of the double-precision arithmetic; they (and exact
#: zeros) are drawn in the lowest colour of the difference scale.
DIFFERENCE_FLOOR = 1e-17
#: What each method of the stability grid is called in the figure.
METHOD_TEXT = {"analytic": "analytic linearisation", "saltation": "saltation matrices",
               "numeric_exact": "finite differences, exact solver",
               "numeric_moreau": "finite differences, time-stepping"}


def case_outlines(ax, y2, y3, case) -> Line2D:
    """The boundaries between the cases of Table 1 on a map, black on white.

    Parameters
    ----------
    ax : matplotlib.axes.Axes
        The map's panel.
    y2, y3 : array_like
        The increasing grid axes (n,) and (m,).
    case : array_like
        The case of Table 1, indexed [i_y2, i_y3] (n, m).

    Returns
    -------
    matplotlib.lines.Line2D
        The legend handle of the boundaries; the cell edges between cells of different case are
        drawn on ``ax``.

    Examples
    --------
    >>> import numpy as np
    >>> from selfalign.plots.style import new_figure
    >>> ax = new_figure("single", 60).subplots()
    >>> case_outlines(ax, [1.0, 2.0, 3.0], [1.0, 2.0], np.array([[1, 3], [3, 3], [3, 4]])).get_label()
    'boundary of the cases of Table 1'
    >>> len(ax.collections[-1].get_segments())
    4
    """
    case = np.asarray(case)
    x, y = cell_edges(y2), cell_edges(y3)
    segments = [[(x[i + 1], y[j]), (x[i + 1], y[j + 1])] for i, j in zip(*np.nonzero(case[1:] != case[:-1]))]
    segments += [[(x[i], y[j + 1]), (x[i + 1], y[j + 1])] for i, j in zip(*np.nonzero(case[:, 1:] != case[:, :-1]))]
    # Black on a white line, so that the boundary shows on dark and light cells alike.
    ax.add_collection(LineCollection(segments, colors="w", linewidths=2.0))
    ax.add_collection(LineCollection(segments, colors="k", linewidths=0.8))
    return Line2D([], [], color="k", linewidth=0.8, label="boundary of the cases of Table 1",
                  path_effects=[withStroke(linewidth=2.0, foreground="w")])


def floquet_map(fig, y2, y3, case, lambda2: dict, eq33):
    """The second Floquet multiplier over (y2'', y3'') against eq. (33) (Sect. 6.1).

    (a) lambda2 of the first method of ``lambda2``; (b, c, ...) |lambda2 - eq. (33)| of the
    others on one logarithmic scale, differences below :data:`DIFFERENCE_FLOOR` drawn at it;
    the largest difference of every method is in the legend title.  The case regions are
    outlined on every panel (:func:`case_outlines`; case numbers on (a)), case 0 is grey.

    Parameters
    ----------
    fig : matplotlib.figure.Figure
        The figure to draw on (empty).
    y2, y3 : array_like
        The increasing grid axes (n,) and (m,).
    case : array_like
        The case of Table 1, indexed [i_y2, i_y3] (n, m).
    lambda2 : dict
        Method name -> lambda2 of that method, (n, m), in the order of the panels.
    eq33 : array_like
        lambda2 of eq. (33), (n, m): c4 in case 4 and 0 in the other cases.

    Returns
    -------
    matplotlib.figure.Figure
        ``fig``.

    Raises
    ------
    ValueError
        If ``lambda2`` is empty or an array is not shaped (n, m).

    Examples
    --------
    >>> import numpy as np
    >>> from selfalign.plots.style import new_figure, print_check
    >>> case = np.array([[1, 3], [3, 4]])
    >>> c4 = np.where(case == 4, 0.25, 0.0)
    >>> fig = floquet_map(new_figure("double", 120), [1.0, 2.0], [1.0, 2.0], case,
    ...                   {"analytic": c4, "saltation": c4 + 1e-12}, c4)
    >>> print_check(fig), [ax.get_title(loc="left") for ax in fig.axes[:2]]
    ([], ['a', 'b'])
    """
    shape = (np.size(y2), np.size(y3))
    if not lambda2:
        raise ValueError("lambda2 must name at least one method")
    for name, values in {"case": case, "eq33": eq33, **{f"lambda2[{k!r}]": v for k, v in lambda2.items()}}.items():
        if np.shape(values) != shape:
            raise ValueError(f"{name} must be shaped (len(y2), len(y3)) = {shape}, got {np.shape(values)}")
    y2, y3, case, eq33 = (np.asarray(a, dtype=float) for a in (y2, y3, case, eq33))
    names = list(lambda2)
    axes = fig.subplots(2, (len(names) + 1) // 2, sharex=True, sharey=True).ravel()
    physical = case > 0
    first = np.where(physical, lambda2[names[0]], np.nan)
    mesh = map_mesh(axes[0], y2, y3, first, cmap=QUANTITY_CMAPS["lambda2"],
                    norm=Normalize(0.0, max(float(np.nanmax(first)) if physical.any() else 0.0, 1e-3)))
    fig.colorbar(mesh, ax=axes[0], label=rf"$\lambda_2$, {METHOD_TEXT.get(names[0], names[0])}")
    label_regions(axes[0], y2, y3, case, {c: str(c) for c in CASE_COLORS}, {c: "white" for c in CASE_COLORS},
                  min_cells=4)
    largest = {}
    with np.errstate(invalid="ignore"):
        differences = {name: np.where(physical, np.abs(lambda2[name] - eq33), np.nan) for name in names[1:]}
    top = max([float(np.nanmax(d)) for d in differences.values() if np.isfinite(d).any()] + [10 * DIFFERENCE_FLOOR])
    norm = LogNorm(DIFFERENCE_FLOOR, 10 ** np.ceil(np.log10(top)))
    for ax, name in zip(axes[1:], names[1:]):
        largest[name] = float(np.nanmax(differences[name])) if physical.any() else float("nan")
        mesh = map_mesh(ax, y2, y3, np.maximum(differences[name], DIFFERENCE_FLOOR),
                        cmap=QUANTITY_CMAPS["lambda2_difference"], norm=norm)
    if len(names) > 1:
        bar = fig.colorbar(mesh, ax=axes[1:].tolist(), extend="min")
        bar.set_label(r"$|\lambda_2 - \lambda_2^{(33)}|$" + "\n" + rf"(below $10^{{{np.log10(DIFFERENCE_FLOOR):.0f}}}$:"
                      " lowest colour)")
    for ax, name in zip(axes, names):
        handles = [case_outlines(ax, y2, y3, case), mark_cells(ax, y2, y3, ~physical, "non_physical")]
        ax.text(0.97, 0.97, METHOD_TEXT.get(name, name), transform=ax.transAxes, ha="right", va="top",
                bbox={"boxstyle": "round,pad=0.2", "facecolor": "white", "edgecolor": "none", "alpha": 0.85})
        ax.label_outer()
    for ax in axes[len(names):]:
        ax.set_axis_off()
    title = "largest $|\\lambda_2 - \\lambda_2^{(33)}|$: " + ", ".join(
        f"({letter}) {value:.1e}" for letter, value in zip("bcdefgh", largest.values()))
    fig.legend(handles=handles, loc="outside lower center", ncols=len(handles), title=title)
    panel_letters(axes[:len(names)])
    return fig


@styled
def figure_floquet_map(result: dict, eq33):
    """The second Floquet multiplier over a stability grid against eq. (33) (:func:`floquet_map`).

    Parameters
    ----------
    result : dict
        A stability grid (results/stability/grid_<name>.h5,
        :func:`selfalign.stages.stability.stability_grid`) in
        :func:`selfalign.io.hdf5.read_h5` layout; every method in it gets a panel, the first
        (analytic) showing lambda2 itself.
    eq33 : array_like
        lambda2 of eq. (33) on the same grid, [i_y2, i_y3].

    Returns
    -------
    matplotlib.figure.Figure
        Two columns (174 mm) wide.

    Raises
    ------
    ValueError
        If ``eq33`` is not shaped like the grid.

    Examples
    --------
    >>> import numpy as np
    >>> from selfalign.stages.stability import stability_grid
    >>> datasets, attrs = stability_grid(1.0, 0.084, [1.3, 3.0], [1.5, 3.0], moreau_steps=100)
    >>> datasets["case"].tolist()
    [[4, 3], [3, 3]]
    >>> eq33 = np.where(datasets["case"] == 4, (0.3 * 0.5) / (2.3 * 2.5), 0.0)
    >>> fig = figure_floquet_map({"datasets": datasets, "attrs": attrs}, eq33)
    >>> round(fig.get_figwidth() * 25.4), len(fig.axes)
    (174, 6)
    """
    d = result["datasets"]
    lambda2 = {str(name): d["multipliers"][k, ..., 1] for k, name in enumerate(d["methods"])}
    return floquet_map(new_figure("double", 150), d["y2"], d["y3"], d["case"], lambda2, eq33)
