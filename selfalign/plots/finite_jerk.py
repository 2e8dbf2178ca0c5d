"""The finite-jerk figure (README "Finite jerk"): the paper's maps against the ramp time of y''.

Data in (the grids of :mod:`selfalign.analysis.finite_jerk`), Figure out; no physics, no files.
"""

from __future__ import annotations

import numpy as np

from .style import case_map, hatch_cells, map_mesh


def finite_jerk_figure(fig, steady, stopping):
    """One column per ramp fraction: vbar and the case of Table 1 (Fig. 11 settings), the fraction
    of entries that accumulate and Delta x_d (Fig. 17 settings).  Cells whose ramps do not fit
    their phases are hatched."""
    columns = steady.ramp_fractions.size
    axes = fig.subplots(4, columns, squeeze=False)
    vmax = np.nanmax(steady.vbar)
    dmax = np.nanmax(stopping.dx_d) if np.any(np.isfinite(stopping.dx_d)) else 1.0
    for k, fraction in enumerate(steady.ramp_fractions.tolist()):
        title = f"ramp {100 * fraction:g} % of $\\Delta t$"
        too_long = steady.case[k] < 0
        mesh = map_mesh(axes[0, k], steady.y2, steady.y3, steady.vbar[k], vmin=0.0, vmax=vmax, cmap="viridis")
        fig.colorbar(mesh, ax=axes[0, k], label=r"$\bar v$")
        case_map(axes[1, k], steady.y2, steady.y3, np.where(too_long, 0, steady.case[k]))
        for ax in axes[:2, k]:
            if np.any(too_long):
                hatch_cells(ax, steady.y2, steady.y3, too_long, "ramps do not fit")
        mesh = map_mesh(axes[2, k], stopping.y2, stopping.y3, stopping.frac_accumulate[k], vmin=0.0, vmax=1.0,
                        cmap="magma")
        fig.colorbar(mesh, ax=axes[2, k], label="fraction accumulating")
        mesh = map_mesh(axes[3, k], stopping.y2, stopping.y3, stopping.dx_d[k], vmin=0.0, vmax=dmax, cmap="cividis")
        fig.colorbar(mesh, ax=axes[3, k], label=r"$\Delta x_d$")
        axes[0, k].set_title(title, fontsize="medium")
        for ax in axes[2:, k]:
            ax.plot([stopping.y2[0], stopping.y2[-1]], [stopping.y2[0], stopping.y2[-1]], color="w", linewidth=0.8,
                    linestyle="--")
    return fig
