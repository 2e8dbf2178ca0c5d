"""One visual language for the figures over the (y2'', y3'') plane and for the cases of Table 1.

Figs. 8, 10, 11 and 17 share: the colour of each case (:data:`CASE_COLORS`, case 0 being the
non-physical profile), a colour bar that names the cases, the orientation of the maps (y2''
horizontal, y3'' vertical, as the paper writes f "as a function of y2'' and y3''"), cells
centred on the grid points (:func:`cell_edges`), one hatch for cells that show no value and
one way of writing a setting in a title (:func:`setting_title`).  White is left to "no data"
(in Fig. 17: the mass never reaches the zone), so no case is drawn white.
"""

from __future__ import annotations

import numpy as np
from matplotlib.colors import BoundaryNorm, ListedColormap
from matplotlib.patches import Patch, PathPatch
from matplotlib.path import Path

from ..analysis.classification import CASE_LABELS

#: One colour per case of Table 1 (case 0: non-physical profile).
CASE_COLORS = {0: "0.82", 1: "tab:green", 2: "tab:red", 3: "tab:blue", 4: "tab:orange", 5: "tab:purple"}
#: Hatch of map cells that show no value of their panel; each legend says why.
HATCH = "////"
Y2_LABEL, Y3_LABEL = "$y_2''$", "$y_3''$"
#: Mathtext of the setting parameters, in the order titles list them.
SETTING_SYMBOLS = {"y2": "$y_2''$", "y3": "$y_3''$", "dy": r"$\Delta y$", "dt": r"$\Delta t$", "w": "$w$",
                   "c_mu": r"$c_\mu$"}


def setting_title(**values) -> str:
    """The setting in a title, in the order given: dy=0.064, dt=1.38 gives
    "$\\Delta y$ = 0.064, $\\Delta t$ = 1.38"."""
    return ", ".join(f"{SETTING_SYMBOLS[name]} = {value:g}" for name, value in values.items())


def case_label(case: int) -> str:
    """The tick of ``case`` on a case colour bar, e.g. "1 stick-slip, x' >= 0"."""
    return f"{case} {CASE_LABELS[case]}"


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
    """The case of Table 1 over the plane, with a colour bar naming every case."""
    cmap = ListedColormap([CASE_COLORS[c] for c in sorted(CASE_COLORS)])
    mesh = map_mesh(ax, y2, y3, case, cmap=cmap, norm=BoundaryNorm(np.arange(-0.5, len(CASE_COLORS)), cmap.N))
    bar = ax.figure.colorbar(mesh, ax=ax, ticks=sorted(CASE_COLORS))
    bar.ax.set_yticklabels([case_label(c) for c in sorted(CASE_COLORS)], fontsize="small")
    bar.set_label("case (Table 1)")
    return mesh


def hatch_cells(ax, y2, y3, mask, label: str) -> Patch:
    """Hatch the cells where ``mask[i_y2, i_y3]`` holds (drawn as one path of row runs, so
    the hatch is continuous and aligned with the cells of :func:`map_mesh`); returns the
    legend handle with ``label``."""
    x, y = cell_edges(y2), cell_edges(y3)
    vertices = []
    for j, row in enumerate(np.asarray(mask, dtype=bool).T):
        # Runs of consecutive hatched cells along y2'' become one rectangle each.
        steps = np.diff(np.concatenate([[0], row.astype(np.int8), [0]]))
        for start, stop in zip(np.flatnonzero(steps == 1), np.flatnonzero(steps == -1)):
            vertices.append([(x[start], y[j]), (x[stop], y[j]), (x[stop], y[j + 1]), (x[start], y[j + 1]),
                             (x[start], y[j])])
    style = {"facecolor": "none", "edgecolor": "k", "hatch": HATCH, "linewidth": 0.0}
    if vertices:
        codes = [Path.MOVETO] + [Path.LINETO] * 3 + [Path.CLOSEPOLY]
        ax.add_patch(PathPatch(Path(np.concatenate(vertices), codes * len(vertices)), label=label, **style))
    return Patch(label=label, **{**style, "linewidth": 0.5})
