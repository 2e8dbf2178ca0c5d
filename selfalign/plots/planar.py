"""Figures of the planar study (docs/explanation/planar-alignment.md): the drift of a part under a planar table
motion and where it stops at a strip and at a corner of two strips.

Data in (the groups of results/planar/planar.h5, read_h5 layout), Figure out; no physics, no files.  Each
panel function draws on the Axes it is given and returns its Figure; the figure builders draw at print size
under the figure standard (:mod:`selfalign.plots.style`).
"""

from __future__ import annotations

import numpy as np
from matplotlib.figure import Figure
from matplotlib.lines import Line2D
from matplotlib.patches import Polygon
from matplotlib.transforms import offset_copy

from .parts import HIGH_COLOR, TRANSITION_COLOR, _strip
from .style import LINE_COLORS, QUANTITY_CMAPS, SPECIAL, cell_edges, new_figure, panel_letters, special_handle, styled

#: Half length of the drawn strips, in units of the plotted extent (they reach past every axis limit).
STRIP_REACH = 10.0
#: Length of a direction arrow of the drift maps [in] (a unit vector).
ARROW_LENGTH = 0.14
#: Gap between the bottom of a panel and a legend below it [pt], room for the tick labels and the axis label.
BELOW_AXES = 30.0
#: Legend label of the angles at which every entry accumulates at x_stick_min along n (the encoding "dx_zero"
#: of :data:`selfalign.plots.style.SPECIAL`; Delta x_d along n is then zero to rounding).
ACCUMULATES_LABEL = r"$\Delta x_d = 0$: all accumulate"


def _legend_below(ax, handles, **kwargs):
    """A legend of ``handles`` centred below ``ax``, under its axis label (off the data)."""
    below = offset_copy(ax.transAxes, fig=ax.figure, y=-BELOW_AXES, units="points")
    return ax.legend(handles=handles, loc="upper center", bbox_to_anchor=(0.5, 0.0), bbox_transform=below,
                     **kwargs)


def _strip_patches(ax, normal, x_mu: float, w: float, reach: float, *, label: bool) -> None:
    """One strip in the plane: its transition x_mu <= n.x <= x_mu + w dark, the c_mu side beyond light."""
    n = np.asarray(normal, float)
    t = np.array([-n[1], n[0]])
    for low, high, color, name in ((x_mu, x_mu + w, TRANSITION_COLOR, "transition (eqs. 7–9)"),
                                   (x_mu + w, x_mu + w + reach, HIGH_COLOR, r"$c_\mu$ side")):
        corners = [low * n - reach * t, low * n + reach * t, high * n + reach * t, high * n - reach * t]
        ax.add_patch(Polygon(corners, closed=True, color=color, zorder=0, linewidth=0,
                             label=name if label else None))


def drift_map_panel(ax, drift: dict):
    """|v_bar| over the phase offset (horizontal) and the amplitude ratio (vertical) as colours (the map of the
    speed, :data:`selfalign.plots.style.QUANTITY_CMAPS`), its direction as unit arrows.

    Parameters
    ----------
    ax : matplotlib.axes.Axes
        Where to draw.
    drift : dict
        A ``drift_*`` group (read_h5 layout).

    Returns
    -------
    matplotlib.figure.Figure
        The figure of ``ax``.

    Examples
    --------
    >>> import numpy as np
    >>> from matplotlib.figure import Figure
    >>> from selfalign.plots.planar import drift_map_panel
    >>> v = np.array([[[0.1, 0.0], [0.0, 0.2]], [[0.1, 0.1], [0.0, -0.1]]])
    >>> group = {"datasets": {"offset": np.array([0.0, 0.5]), "amplitude": np.array([0.0, 1.0]), "v_bar": v}}
    >>> ax = Figure().subplots()
    >>> fig = drift_map_panel(ax, group)
    >>> ax.collections[0].get_array().ravel().round(6).tolist()
    [0.1, 0.141421, 0.2, 0.1]
    """
    d = drift["datasets"]
    offset, amplitude, v = (np.asarray(d[k], float) for k in ("offset", "amplitude", "v_bar"))
    speed = np.hypot(v[..., 0], v[..., 1])
    mesh = ax.pcolormesh(cell_edges(offset) if offset.size > 1 else [offset[0] - 0.5, offset[0] + 0.5],
                         cell_edges(amplitude) if amplitude.size > 1 else [amplitude[0] - 0.5, amplitude[0] + 0.5],
                         speed.T, cmap=QUANTITY_CMAPS["speed"], shading="flat")
    ax.figure.colorbar(mesh, ax=ax, label=r"drift speed $|\bar v|$")
    with np.errstate(invalid="ignore", divide="ignore"):
        unit = np.where(speed[..., None] > 0, v / speed[..., None], 0.0)
    p, a = np.meshgrid(offset, amplitude, indexing="ij")
    ax.quiver(p, a, unit[..., 0], unit[..., 1], color="w", edgecolor="k", linewidth=0.3, pivot="middle",
              units="inches", scale=1.0 / ARROW_LENGTH, scale_units="inches", width=0.012, headwidth=3.5,
              headlength=4.0, headaxislength=3.5)
    ax.set_xlabel(r"phase offset $\phi$ [periods]")
    ax.set_ylabel(r"amplitude ratio $r$")
    return ax.figure


def limit_panel(ax, limits: dict):
    """The relative error of the high-acceleration limit against max|Y''|, log-log, one line per family, with
    the slope -1 of the asymptotic order dotted; the legend, in the upper right corner (the errors fall to the
    right), gives each fitted slope.

    Parameters
    ----------
    ax : matplotlib.axes.Axes
        Where to draw.
    limits : dict
        Label -> a ``limit_*`` group (read_h5 layout).

    Returns
    -------
    matplotlib.figure.Figure
        The figure of ``ax``.

    Examples
    --------
    >>> import numpy as np
    >>> from matplotlib.figure import Figure
    >>> from selfalign.plots.planar import limit_panel
    >>> group = {"datasets": {"max_acceleration": np.array([10.0, 100.0]), "error": np.array([0.05, 0.005]),
    ...                       "slope": -1.0}}
    >>> ax = Figure().subplots()
    >>> fig = limit_panel(ax, {"demo": group})
    >>> ax.lines[0].get_ydata().tolist()
    [0.05, 0.005]
    """
    handles = []
    for i, (label, group) in enumerate(limits.items()):
        d = group["datasets"]
        a, e = np.asarray(d["max_acceleration"], float), np.asarray(d["error"], float)
        color = LINE_COLORS[i % len(LINE_COLORS)]
        handles += ax.loglog(a, e, "o-", color=color, label=f"{label}, fit slope ${float(d['slope']):.2f}$")
        ax.loglog(a, e[-1] * a[-1] / a, ":", color=color, linewidth=0.8)
    handles.append(Line2D([], [], color="k", linestyle=":", linewidth=0.8, label="slope $-1$"))
    ax.set_xlabel(r"$\max|Y''|$")
    ax.set_ylabel(r"$|\bar v - c| \,/\, \max|Y'|$")
    ax.legend(handles=handles, loc="upper right")
    return ax.figure


def strip_cloud_panel(ax, line: dict):
    """End positions of the entries onto a strip in the strip's frame: along the strip from where each entry's
    drift line crosses the edge (``along``) against the depth (n.x_end - x_mu), both over w, one colour per
    angle, x_stick_min (eq. 41) dashed, the zone shaded; the legend below the panel.

    Parameters
    ----------
    ax : matplotlib.axes.Axes
        Where to draw.
    line : dict
        A ``line_*`` group (read_h5 layout).

    Returns
    -------
    matplotlib.figure.Figure
        The figure of ``ax``.

    Examples
    --------
    >>> import numpy as np
    >>> from matplotlib.figure import Figure
    >>> from selfalign.plots.planar import strip_cloud_panel
    >>> group = {"datasets": {"angle": np.array([0.0]), "depth": np.array([[0.04, 0.04]]),
    ...                       "along": np.array([[0.0, 0.0]]), "lateral": np.array([[-0.05, 0.05]]),
    ...                       "stick_depth": 0.04}, "attrs": {"w": 0.05}}
    >>> ax = Figure().subplots()
    >>> fig = strip_cloud_panel(ax, group)
    >>> ax.lines[0].get_ydata().round(12).tolist()
    [0.8, 0.8]
    """
    d, w = line["datasets"], float(line["attrs"]["w"])
    angles = np.degrees(np.asarray(d["angle"], float))
    depth, along = np.asarray(d["depth"], float) / w, np.asarray(d["along"], float) / w
    handles = [ax.plot(along[i], depth[i], "o", color=LINE_COLORS[i % len(LINE_COLORS)], markersize=3, alpha=0.8,
                       label=f"{angle:g}°")[0] for i, angle in enumerate(angles)]
    _strip(ax, 0.0, 1.0, vertical=True)
    handles.append(ax.axhline(float(d["stick_depth"]) / w, color="k", linestyle="--", linewidth=0.8,
                              label=r"$x_\mathrm{stick,min}$ (eq. 41)"))
    ax.set_ylim(min(-0.2, np.nanmin(depth) - 0.1), max(1.2, np.nanmax(depth) + 0.1))
    ax.set_xlabel(r"along the strip $s/w$")
    ax.set_ylabel(r"depth $(n \cdot x_\mathrm{end} - x_\mu)/w$")
    _legend_below(ax, handles, title=r"angle $\theta$ between drift and $n$", ncol=3)
    return ax.figure


def spread_panel(ax, lines: dict):
    """Delta x_d (eq. 39) along the normal (solid, circles) and along the strip (dashed, squares) against the
    angle, one colour per motion; the angles at which every entry accumulates at x_stick_min along n (dataset
    ``at_limit`` 1) in the encoding "dx_zero" of :data:`selfalign.plots.style.SPECIAL`; the legend below the
    panel.

    Parameters
    ----------
    ax : matplotlib.axes.Axes
        Where to draw.
    lines : dict
        Label -> a ``line_*`` group (read_h5 layout).

    Returns
    -------
    matplotlib.figure.Figure
        The figure of ``ax``.

    Examples
    --------
    >>> import numpy as np
    >>> from matplotlib.figure import Figure
    >>> from selfalign.plots.planar import spread_panel
    >>> group = {"datasets": {"angle": np.array([0.0, 0.5]), "dx_d_normal": np.array([0.001, 0.0]),
    ...                       "dx_d_slide": np.array([0.0, 0.002]), "at_limit": np.array([0.8, 1.0])},
    ...          "attrs": {"w": 0.05}}
    >>> ax = Figure().subplots()
    >>> fig = spread_panel(ax, {"demo": group})
    >>> ax.lines[0].get_ydata().round(6).tolist(), ax.lines[1].get_xdata().round(2).tolist()
    ([0.02, 0.0], [28.65])
    """
    encoding = SPECIAL["dx_zero"]
    handles = []
    for i, (label, group) in enumerate(lines.items()):
        d, w = group["datasets"], float(group["attrs"]["w"])
        angles = np.degrees(np.asarray(d["angle"], float))
        color = LINE_COLORS[i % len(LINE_COLORS)]
        normal = np.asarray(d["dx_d_normal"], float) / w
        ax.plot(angles, normal, "o-", color=color, label=f"{label}: along $n$")
        every = np.asarray(d["at_limit"], float) == 1.0
        ax.plot(angles[every], normal[every], "o", markersize=4.5, mfc=encoding["facecolor"], mec=color,
                label=ACCUMULATES_LABEL)
        ax.plot(angles, np.asarray(d["dx_d_slide"], float) / w, "s--", color=color, markersize=2.5,
                label=f"{label}: along the strip (one entry line)")
        handles.append(Line2D([], [], color=color, label=label))
    handles += [Line2D([], [], color="k", marker="o", label="along $n$"),
                Line2D([], [], color="k", marker="s", markersize=2.5, linestyle="--", label="along the strip"),
                special_handle("dx_zero", ACCUMULATES_LABEL)]
    ax.set_xlabel(r"angle $\theta$ between drift and $n$ [°]")
    ax.set_ylabel(r"$\Delta x_d / w$")
    _legend_below(ax, handles, ncol=2)
    return ax.figure


def plane_panel(ax, group: dict, *, paths=(), starts=None, ends=None, corner=None):
    """Strips in the plane with paths, start and end positions drawn on them, each labelled for a legend (the
    panel draws none: the figure names the strips, paths and points once).

    Parameters
    ----------
    ax : matplotlib.axes.Axes
        Where to draw.
    group : dict
        A group with the strips: datasets ``normal`` (k, 2) and, optionally, ``x_mu`` (k,) (0 without),
        attribute ``w``.
    paths : sequence of array_like, optional
        Paths (n, 2) drawn as lines.
    starts, ends : array_like, optional
        Points (m, 2) drawn as open and filled markers.
    corner : array_like, optional
        A point (2,) drawn as a cross (the corner point of two strips).

    Returns
    -------
    matplotlib.figure.Figure
        The figure of ``ax``.

    Examples
    --------
    >>> import numpy as np
    >>> from matplotlib.figure import Figure
    >>> from selfalign.plots.planar import plane_panel
    >>> group = {"datasets": {"normal": np.array([[1.0, 0.0]])}, "attrs": {"w": 0.05}}
    >>> ax = Figure().subplots()
    >>> fig = plane_panel(ax, group, paths=[np.array([[-0.1, 0.0], [0.04, 0.0]])])
    >>> len(ax.patches), ax.lines[0].get_xdata().tolist()
    (2, [-0.1, 0.04])
    """
    d, w = group["datasets"], float(group["attrs"]["w"])
    normals = np.asarray(d["normal"], float)
    x_mu = np.asarray(d.get("x_mu", np.zeros(len(normals))), float)
    points = [np.asarray(p, float) for p in paths] + [np.asarray(p, float).reshape(-1, 2)
                                                      for p in (starts, ends, corner) if p is not None]
    extent = float(np.max(np.abs(np.concatenate(points)))) + 2.0 * w if points else 1.0
    for k, (n, edge) in enumerate(zip(normals, x_mu)):
        _strip_patches(ax, n, float(edge), w, STRIP_REACH * extent, label=k == 0)
    for i, path in enumerate(paths):
        path = np.asarray(path, float)
        ax.plot(path[:, 0], path[:, 1], "-", color=LINE_COLORS[i % len(LINE_COLORS)], linewidth=0.8,
                label="path" if i == 0 else None)
    if starts is not None:
        s = np.asarray(starts, float)
        ax.plot(s[:, 0], s[:, 1], "o", mfc="none", color="0.4", markersize=3, label="starts")
    if ends is not None:
        e = np.asarray(ends, float)
        ax.plot(e[:, 0], e[:, 1], "o", color=LINE_COLORS[1], markersize=3, label="ends")
    if corner is not None:
        ax.plot(*np.asarray(corner, float), "kx", markersize=6, label="corner point")
    ax.set_xlim(-extent, extent)
    ax.set_ylim(-extent, extent)
    ax.set_aspect("equal")
    ax.set_xlabel("$x$")
    ax.set_ylabel("$y$")
    return ax.figure


@styled
def drift_figure(result: dict) -> Figure:
    """figures/planar_drift (two columns): the drift maps of the two families side by side and, below them, the
    high-acceleration limit.

    Parameters
    ----------
    result : dict
        results/planar/planar.h5 (read_h5 layout).

    Returns
    -------
    matplotlib.figure.Figure
        Panels (a) three-phase profiles, (b) two-harmonic orbit, (c) the limit's error, 174 mm wide.

    Examples
    --------
    >>> import numpy as np
    >>> from selfalign.plots.planar import drift_figure
    >>> m = {"datasets": {"offset": np.array([0.0, 0.5]), "amplitude": np.array([0.0, 1.0]),
    ...                   "v_bar": np.ones((2, 2, 2))}}
    >>> lim = {"datasets": {"max_acceleration": np.array([10.0, 100.0]), "error": np.array([0.05, 0.005]),
    ...                     "slope": -1.0}}
    >>> groups = {"drift_three_phase": m, "drift_harmonic": m, "limit_three_phase": lim, "limit_harmonic": lim}
    >>> fig = drift_figure({"groups": groups})
    >>> len(fig.axes), [ax.get_title(loc="left") for ax in fig.axes[:3]]
    (5, ['a', 'b', 'c'])
    """
    g = result["groups"]
    fig = new_figure("double", 112)
    grid = fig.add_gridspec(2, 2, height_ratios=[1.5, 1.0])
    axes = [fig.add_subplot(grid[0, 0]), fig.add_subplot(grid[0, 1]), fig.add_subplot(grid[1, :])]
    drift_map_panel(axes[0], g["drift_three_phase"])
    drift_map_panel(axes[1], g["drift_harmonic"])
    limit_panel(axes[2], {"three-phase pair": g["limit_three_phase"], "two-harmonic orbit": g["limit_harmonic"]})
    panel_letters(axes)
    return fig


@styled
def alignment_figure(result: dict) -> Figure:
    """figures/planar_alignment (two columns): ends at a strip, Delta x_d against the angle, the corner's end
    cloud and an example path; one legend below the panels names the strips, paths and points of (c) and (d).

    Parameters
    ----------
    result : dict
        results/planar/planar.h5 (read_h5 layout).

    Returns
    -------
    matplotlib.figure.Figure
        Panels (a) ends at a strip in its frame, (b) Delta x_d, (c) the corner, (d) example path, 174 mm wide.

    Examples
    --------
    >>> import numpy as np
    >>> from selfalign.plots.planar import alignment_figure
    >>> line = {"datasets": {"angle": np.array([0.0]), "depth": np.array([[0.04]]), "along": np.zeros((1, 1)),
    ...                      "lateral": np.zeros((1, 1)), "stick_depth": 0.04, "dx_d_normal": np.zeros(1),
    ...                      "dx_d_slide": np.zeros(1), "at_limit": np.ones(1)}, "attrs": {"w": 0.05}}
    >>> corner = {"datasets": {"normal": np.array([[0.7, 0.7], [0.7, -0.7]]), "start": np.zeros((1, 2)),
    ...                        "x_end": np.zeros((1, 2)), "corner": np.zeros(2)}, "attrs": {"w": 0.05}}
    >>> example = {"datasets": {"normal": np.array([[1.0, 0.0]]), "x_mu": np.zeros(1), "x": np.zeros((2, 2))},
    ...            "attrs": {"w": 0.05}}
    >>> groups = {"line_along": line, "line_planar": line, "corner": corner, "example_line": example,
    ...           "example_corner": example}
    >>> fig = alignment_figure({"groups": groups})
    >>> [ax.get_title(loc="left") for ax in fig.axes], [t.get_text() for t in fig.legends[0].texts][2:]
    (['a', 'b', 'c', 'd'], ['path', 'starts', 'ends', 'corner point'])
    """
    g = result["groups"]
    fig = new_figure("double", 165)
    (a, b), (c, d) = fig.subplots(2, 2, height_ratios=[1.0, 1.35])
    strip_cloud_panel(a, g["line_planar"])
    spread_panel(b, {"motion along the drift": g["line_along"], "planar motion": g["line_planar"]})
    corner = g["corner"]["datasets"]
    plane_panel(c, g["corner"], starts=corner["start"], ends=corner["x_end"], corner=corner["corner"],
                paths=[g["example_corner"]["datasets"]["x"]])
    plane_panel(d, g["example_line"], paths=[g["example_line"]["datasets"]["x"]])
    panel_letters([a, b, c, d])
    handles = {}
    for ax in (c, d):
        for handle, label in zip(*ax.get_legend_handles_labels()):
            handles.setdefault(label, handle)
    fig.legend(handles.values(), handles.keys(), loc="outside lower center", ncol=len(handles))
    return fig
