"""The finite-jerk figures (docs/explanation/model.md): the paper's maps against the ramp time of y''.

:func:`finite_jerk_figure` draws vbar and the case of Table 1 over every steady plane,
:func:`finite_jerk_stopping_figure` the stopping over the plane of Fig. 17, one column per ramp
fraction.  Data in (the grids of :mod:`selfalign.analysis.finite_jerk`), Figure out; no physics,
no files.
"""

from __future__ import annotations

import numpy as np
from matplotlib import colormaps
from matplotlib.figure import Figure
from matplotlib.patches import Patch

from ..model.profiles import RAMPS_TOO_LONG
from .effects import accumulation_panel
from .style import (
    CASE_COLORS,
    QUANTITY_CMAPS,
    case_label,
    case_map,
    map_mesh,
    mark_cells,
    new_figure,
    panel_letters,
    special_handle,
    styled,
)

#: Height of one row of maps [mm], and of the legend below them.
ROW_MM, LEGEND_MM = 42.0, 30.0
#: Legend label of the cells without a profile: case 0, or ramps longer than their phases.
NO_PROFILE_LABEL = "no profile: case 0, or ramps longer than their phases"


def _map_grid(fig, rows: int, columns: int):
    """``rows`` x ``columns`` map panels over a legend row; returns (panels, legend axes)."""
    grid = fig.add_gridspec(rows + 1, columns, height_ratios=[ROW_MM] * rows + [LEGEND_MM])
    axes = np.array([[fig.add_subplot(grid[r, k]) for k in range(columns)] for r in range(rows)])
    key = fig.add_subplot(grid[rows, :])
    key.axis("off")
    return axes, key


def _share_block(axes):
    """Share the axes of a block of panels over one plane; tick labels only at its left and bottom."""
    for ax in axes.ravel()[1:]:
        ax.sharex(axes.ravel()[0])
        ax.sharey(axes.ravel()[0])
    for (r, k), ax in np.ndenumerate(axes):
        if k:
            ax.set_ylabel("")
            ax.tick_params(labelleft=False)
        if r < axes.shape[0] - 1:
            ax.set_xlabel("")
            ax.tick_params(labelbottom=False)


@styled
def finite_jerk_figure(steady: dict) -> Figure:
    """vbar (eq. 10) and the case of Table 1 over every steady plane, one column per ramp fraction.

    Per plane of ``steady`` (plane name -> SteadyGrid, in order) two rows: vbar in the map of speeds
    (one colour bar per plane), cells with vbar < 0 in the encoding "v_negative"; the cases (numbers
    on the regions).  Cells without a profile (case 0, or ramps longer than their phases) are drawn
    as case 0 ("non_physical") in both rows.

    Parameters
    ----------
    steady : dict
        Plane name -> :class:`selfalign.analysis.finite_jerk.SteadyGrid`, all of the same ramp fractions.

    Returns
    -------
    matplotlib.figure.Figure
        174 mm wide, panels lettered row by row.

    Raises
    ------
    ValueError
        If the planes do not fit one page (more than four planes).
    """
    grids = list(steady.values())
    columns = grids[0].ramp_fractions.size
    rows = 2 * len(grids)
    if rows > 8:
        raise ValueError(f"steady holds {len(grids)} planes; a page takes at most 4")
    fig = new_figure("double", ROW_MM * rows + LEGEND_MM)
    axes, key = _map_grid(fig, rows, columns)
    cmap = colormaps[QUANTITY_CMAPS["speed"]]
    negative = False
    for row, grid in zip(range(0, rows, 2), grids):
        vmax = np.nanmax(grid.vbar) if np.any(grid.vbar > 0) else 1.0
        for k in range(columns):
            no_profile = (grid.case[k] == 0) | (grid.case[k] == RAMPS_TOO_LONG)
            with np.errstate(invalid="ignore"):
                backward = grid.vbar[k] < 0.0
            negative |= bool(backward.any())
            ax_v, ax_c = axes[row, k], axes[row + 1, k]
            mesh = map_mesh(ax_v, grid.y2, grid.y3, np.where(backward, np.nan, grid.vbar[k]), cmap=cmap, vmin=0.0,
                            vmax=vmax)
            mark_cells(ax_v, grid.y2, grid.y3, backward, "v_negative")
            cases = case_map(ax_c, grid.y2, grid.y3, np.where(grid.case[k] == RAMPS_TOO_LONG, np.nan, grid.case[k]))
            cases.colorbar.remove()
            for ax in (ax_v, ax_c):
                mark_cells(ax, grid.y2, grid.y3, no_profile, "non_physical")
        fig.colorbar(mesh, ax=list(axes[row]), label=r"$\bar v$", fraction=0.04, pad=0.01)
        _share_block(axes[row:row + 2])
    handles = [Patch(facecolor=CASE_COLORS[c], edgecolor="k", linewidth=0.5, label=case_label(c))
               for c in sorted(CASE_COLORS) if c]
    handles.append(special_handle("non_physical", NO_PROFILE_LABEL))
    if negative:
        handles.append(special_handle("v_negative"))
    key.legend(handles=handles, loc="center", ncols=2, title="case (Table 1; numbers on the regions)",
               borderaxespad=0.0)
    panel_letters(axes.ravel())
    return fig


@styled
def finite_jerk_stopping_figure(stopping, no_profile=None) -> Figure:
    """The stopping over the plane of Fig. 17, one column per ramp fraction: the fraction of entries that
    accumulate as the three classes (top) and Delta x_d (eq. 39, bottom), both only where every entry ends
    at rest (elsewhere the encoding "unsettled"); Delta x_d = 0 exactly in the encoding "dx_zero".  White:
    the mass does not reach the zone; ``no_profile`` [ramp, y2, y3] cells (no profile of the family) as case 0.

    Parameters
    ----------
    stopping : selfalign.analysis.finite_jerk.StoppingGrid
        Shape (ramps, y2, y3).
    no_profile : array_like of bool, optional
        Where no profile exists (case 0, or ramps longer than their phases); None: not marked.

    Returns
    -------
    matplotlib.figure.Figure
        174 mm wide.
    """
    columns = stopping.ramp_fractions.size
    fig = new_figure("double", 2 * ROW_MM + LEGEND_MM)
    axes, key = _map_grid(fig, 2, columns)
    settled = stopping.frac_accumulate + stopping.frac_rest == 1.0
    unsettled = np.isfinite(stopping.frac_accumulate) & ~settled
    shown = np.where(settled, stopping.dx_d, np.nan)
    dmax = np.nanmax(shown) if np.any(shown > 0) else 1.0
    y2, y3 = stopping.y2, stopping.y3
    diagonal = [max(y2[0], y3[0]), min(y2[-1], y3[-1])]
    for k in range(columns):
        ax_acc, ax_dx = axes[0, k], axes[1, k]
        classes = accumulation_panel(ax_acc, y2, y3, stopping.frac_accumulate[k], unsettled[k])
        mesh = map_mesh(ax_dx, y2, y3, shown[k], cmap=QUANTITY_CMAPS["dx_d"], vmin=0.0, vmax=dmax)
        zero = mark_cells(ax_dx, y2, y3, shown[k] == 0.0, "dx_zero")
        mark_cells(ax_dx, y2, y3, unsettled[k], "unsettled")
        for ax in (ax_acc, ax_dx):
            if no_profile is not None:
                mark_cells(ax, y2, y3, np.asarray(no_profile, dtype=bool)[k], "non_physical")
            ax.plot(diagonal, diagonal, color="k", linewidth=0.6, linestyle="--", label="$y_2'' = y_3''$")
    fig.colorbar(mesh, ax=list(axes[1]), label=r"$\Delta x_d$ (every entry at rest)", fraction=0.04, pad=0.01)
    _share_block(axes)
    handles = classes[:3] + [zero, classes[3], classes[4]] + (
        [special_handle("non_physical", NO_PROFILE_LABEL)] if no_profile is not None else [])
    handles.append(axes[0, 0].get_lines()[-1])
    key.legend(handles=handles, loc="center", ncols=2, borderaxespad=0.0)
    panel_letters(axes.ravel())
    return fig
