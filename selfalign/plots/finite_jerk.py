"""The finite-jerk figure (docs/explanation/model.md): the paper's maps against the ramp time of y''.

Data in (the grids of :mod:`selfalign.analysis.finite_jerk`), Figure out; no physics, no files.
"""

from __future__ import annotations

import numpy as np
from matplotlib.figure import Figure

from .style import case_map, hatch_cells, map_mesh

#: Width and height of one panel [in].
PANEL = (4.5, 3.6)


def finite_jerk_figure(steady: dict, stopping) -> Figure:
    """One column per ramp fraction: vbar and the case of Table 1 for every steady plane
    (``steady``: plane name -> SteadyGrid, in order), the fraction of entries that accumulate and
    Delta x_d (``stopping``: StoppingGrid).  Cells whose ramps do not fit their phases are hatched."""
    columns = stopping.ramp_fractions.size
    rows = 2 * len(steady) + 2
    fig = Figure(figsize=(PANEL[0] * columns, PANEL[1] * rows), layout="constrained")
    axes = fig.subplots(rows, columns, squeeze=False)
    for row, (plane, grid) in zip(range(0, rows, 2), steady.items()):
        vmax = np.nanmax(grid.vbar) if np.any(np.isfinite(grid.vbar)) else 1.0
        for k, fraction in enumerate(grid.ramp_fractions.tolist()):
            too_long = grid.case[k] < 0
            mesh = map_mesh(axes[row, k], grid.y2, grid.y3, grid.vbar[k], vmin=0.0, vmax=vmax, cmap="viridis")
            fig.colorbar(mesh, ax=axes[row, k], label=r"$\bar v$")
            case_map(axes[row + 1, k], grid.y2, grid.y3, np.where(too_long, 0, grid.case[k]))
            for ax in axes[row:row + 2, k]:
                ax.set_title(f"{plane} plane, ramp {100 * fraction:g} % of $\\Delta t$", fontsize="medium")
                if np.any(too_long):
                    hatch_cells(ax, grid.y2, grid.y3, too_long, "ramps do not fit")
    dmax = np.nanmax(stopping.dx_d) if np.any(np.isfinite(stopping.dx_d)) else 1.0
    for k, fraction in enumerate(stopping.ramp_fractions.tolist()):
        ax_acc, ax_dx = axes[-2, k], axes[-1, k]
        mesh = map_mesh(ax_acc, stopping.y2, stopping.y3, stopping.frac_accumulate[k], vmin=0.0, vmax=1.0,
                        cmap="magma")
        fig.colorbar(mesh, ax=ax_acc, label="fraction accumulating")
        mesh = map_mesh(ax_dx, stopping.y2, stopping.y3, stopping.dx_d[k], vmin=0.0, vmax=dmax, cmap="cividis")
        fig.colorbar(mesh, ax=ax_dx, label=r"$\Delta x_d$")
        for ax in (ax_acc, ax_dx):
            ax.set_title(f"stop zone, ramp {100 * fraction:g} % of $\\Delta t$", fontsize="medium")
            ax.plot([stopping.y2[0], stopping.y2[-1]], [stopping.y2[0], stopping.y2[-1]], color="w", linewidth=0.8,
                    linestyle="--")
    return fig
