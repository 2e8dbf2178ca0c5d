"""Figures of the planar study (docs/explanation/planar-alignment.md): the drift of a part under a planar table
motion and where it stops at a strip and at a corner of two strips.

Data in (the groups of results/planar/planar.h5, read_h5 layout), Figure out; no physics, no files.  Each
panel function draws on the Axes it is given and returns its Figure.
"""

from __future__ import annotations

import numpy as np
from matplotlib.figure import Figure
from matplotlib.patches import Polygon

from .parts import HIGH_COLOR, PANEL, TRANSITION_COLOR
from .style import cell_edges

#: Half length of the drawn strips, in units of the plotted extent (they reach past every axis limit).
STRIP_REACH = 10.0


def _strip_patches(ax, normal, x_mu: float, w: float, reach: float, *, label: bool) -> None:
    """One strip in the plane: its transition x_mu <= n.x <= x_mu + w dark, the c_mu side beyond light."""
    n = np.asarray(normal, float)
    t = np.array([-n[1], n[0]])
    for low, high, color, name in ((x_mu, x_mu + w, TRANSITION_COLOR, "transition (eqs. 7-9)"),
                                   (x_mu + w, x_mu + w + reach, HIGH_COLOR, r"$c_\mu$ side")):
        corners = [low * n - reach * t, low * n + reach * t, high * n + reach * t, high * n - reach * t]
        ax.add_patch(Polygon(corners, closed=True, color=color, zorder=0, linewidth=0,
                             label=name if label else None))


def drift_map_panel(ax, drift: dict, *, title: str):
    """|v_bar| over the phase offset (horizontal) and the amplitude ratio (vertical) as colours, its direction
    as unit arrows.

    Parameters
    ----------
    ax : matplotlib.axes.Axes
        Where to draw.
    drift : dict
        A ``drift_*`` group (read_h5 layout).
    title : str
        The panel's title.

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
    >>> fig = drift_map_panel(ax, group, title="demo")
    >>> ax.collections[0].get_array().ravel().round(6).tolist()
    [0.1, 0.141421, 0.2, 0.1]
    """
    d = drift["datasets"]
    offset, amplitude, v = (np.asarray(d[k], float) for k in ("offset", "amplitude", "v_bar"))
    speed = np.hypot(v[..., 0], v[..., 1])
    mesh = ax.pcolormesh(cell_edges(offset) if offset.size > 1 else [offset[0] - 0.5, offset[0] + 0.5],
                         cell_edges(amplitude) if amplitude.size > 1 else [amplitude[0] - 0.5, amplitude[0] + 0.5],
                         speed.T, cmap="viridis", shading="flat")
    ax.figure.colorbar(mesh, ax=ax, label=r"$|\bar v|$")
    with np.errstate(invalid="ignore", divide="ignore"):
        unit = np.where(speed[..., None] > 0, v / speed[..., None], 0.0)
    p, a = np.meshgrid(offset, amplitude, indexing="ij")
    ax.quiver(p, a, unit[..., 0], unit[..., 1], color="w", pivot="middle", scale=1.0 / 0.28,
              scale_units="inches", width=0.008)
    ax.set_xlabel("phase offset of the y motion [periods]")
    ax.set_ylabel("amplitude ratio y / x")
    ax.set_title(title, fontsize="medium")
    return ax.figure


def limit_panel(ax, limits: dict):
    """The relative error of the high-acceleration limit against max|Y''|, log-log, one line per family, with
    the slope -1 of the asymptotic order.

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
    for i, (label, group) in enumerate(limits.items()):
        d = group["datasets"]
        a, e = np.asarray(d["max_acceleration"], float), np.asarray(d["error"], float)
        ax.loglog(a, e, "o-", color=f"C{i}", label=f"{label} (fit slope {float(d['slope']):.2f})")
        ax.loglog(a, e[-1] * a[-1] / a, ":", color=f"C{i}", linewidth=0.8)
    ax.set_xlabel(r"$\max|Y''|$")
    ax.set_ylabel(r"$|\bar v - c| \,/\, \max|Y'|$")
    ax.set_title("error of the limit c (dotted: slope -1)", fontsize="medium")
    ax.legend(fontsize="x-small")
    return ax.figure


def strip_cloud_panel(ax, line: dict):
    """End positions of the entries onto a strip in the strip's frame: along the strip from where each entry's
    drift line crosses the edge (``along``) against the depth (n.x_end - x_mu), both over w, one colour per
    angle, x_stick_min (eq. 41) dashed.

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
    for i, angle in enumerate(angles):
        ax.plot(along[i], depth[i], "o", color=f"C{i % 10}", markersize=3.5, alpha=0.8, label=f"{angle:g} deg")
    ax.axhspan(0.0, 1.0, color=TRANSITION_COLOR, zorder=0)
    ax.axhline(float(d["stick_depth"]) / w, color="k", linestyle="--", linewidth=0.8,
               label=r"$x_{stick,min}$ (eq. 41)")
    ax.set_xlabel("along the strip from the drift line's crossing of the edge, / w")
    ax.set_ylabel(r"depth $(n \cdot x_{end} - x_\mu)/w$")
    ax.set_title("ends at a strip; angle between drift and normal", fontsize="medium")
    ax.legend(fontsize="x-small", ncol=2)
    return ax.figure


def spread_panel(ax, lines: dict):
    """Delta x_d (eq. 39) along the normal and along the strip against the angle, one colour per motion.

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
    ...                       "dx_d_slide": np.array([0.0, 0.002])}, "attrs": {"w": 0.05}}
    >>> ax = Figure().subplots()
    >>> fig = spread_panel(ax, {"demo": group})
    >>> ax.lines[0].get_ydata().round(6).tolist()
    [0.02, 0.0]
    """
    for i, (label, group) in enumerate(lines.items()):
        d, w = group["datasets"], float(group["attrs"]["w"])
        angles = np.degrees(np.asarray(d["angle"], float))
        ax.plot(angles, np.asarray(d["dx_d_normal"], float) / w, "o-", color=f"C{i}", label=f"{label}: along n")
        ax.plot(angles, np.asarray(d["dx_d_slide"], float) / w, "s--", color=f"C{i}",
                label=f"{label}: along the strip (one entry line)")
    ax.set_xlabel("angle between drift and strip normal [deg]")
    ax.set_ylabel(r"$\Delta x_d / w$")
    ax.set_title(r"positioning error $\Delta x_d$ (eq. 39)", fontsize="medium")
    ax.legend(fontsize="x-small")
    return ax.figure


def plane_panel(ax, group: dict, *, title: str, paths=(), starts=None, ends=None, corner=None):
    """Strips in the plane with paths, start and end positions drawn on them.

    Parameters
    ----------
    ax : matplotlib.axes.Axes
        Where to draw.
    group : dict
        A group with the strips: datasets ``normal`` (k, 2) and, optionally, ``x_mu`` (k,) (0 without),
        attribute ``w``.
    title : str
        The panel's title.
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
    >>> fig = plane_panel(ax, group, title="demo", paths=[np.array([[-0.1, 0.0], [0.04, 0.0]])])
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
        ax.plot(path[:, 0], path[:, 1], "-", color=f"C{i % 10}", linewidth=0.8)
    if starts is not None:
        s = np.asarray(starts, float)
        ax.plot(s[:, 0], s[:, 1], "o", mfc="none", color="0.4", markersize=3, label="starts")
    if ends is not None:
        e = np.asarray(ends, float)
        ax.plot(e[:, 0], e[:, 1], "o", color="C3", markersize=3.5, label="ends")
    if corner is not None:
        ax.plot(*np.asarray(corner, float), "kx", markersize=8, label="corner point")
    ax.set_xlim(-extent, extent)
    ax.set_ylim(-extent, extent)
    ax.set_aspect("equal")
    ax.set_xlabel("x")
    ax.set_ylabel("y")
    ax.set_title(title, fontsize="medium")
    ax.legend(fontsize="x-small", loc="lower left")
    return ax.figure


def drift_figure(result: dict) -> Figure:
    """figures/planar_drift: the drift maps of the two families and the high-acceleration limit.

    Parameters
    ----------
    result : dict
        results/planar/planar.h5 (read_h5 layout).

    Returns
    -------
    matplotlib.figure.Figure
        Panels (a) three-phase profiles, (b) two-harmonic orbit, (c) the limit's error.

    Examples
    --------
    >>> import numpy as np
    >>> from selfalign.plots.planar import drift_figure
    >>> m = {"datasets": {"offset": np.array([0.0, 0.5]), "amplitude": np.array([0.0, 1.0]),
    ...                   "v_bar": np.ones((2, 2, 2))}}
    >>> lim = {"datasets": {"max_acceleration": np.array([10.0, 100.0]), "error": np.array([0.05, 0.005]),
    ...                     "slope": -1.0}}
    >>> groups = {"drift_three_phase": m, "drift_harmonic": m, "limit_three_phase": lim, "limit_harmonic": lim}
    >>> len(drift_figure({"groups": groups}).axes)
    5
    """
    g = result["groups"]
    fig = Figure(figsize=(3 * PANEL[0], PANEL[1]), layout="constrained")
    axes = fig.subplots(1, 3)
    drift_map_panel(axes[0], g["drift_three_phase"], title="(a) two three-phase profiles (Sect. 4.4.3)")
    drift_map_panel(axes[1], g["drift_harmonic"], title="(b) orbit sin + second harmonic, y = b sin")
    limit_panel(axes[2], {"three-phase pair": g["limit_three_phase"], "two-harmonic orbit": g["limit_harmonic"]})
    axes[2].set_title("(c) " + axes[2].get_title(), fontsize="medium")
    return fig


def alignment_figure(result: dict) -> Figure:
    """figures/planar_alignment: ends at a strip, Delta x_d against the angle, the corner's end cloud and two
    example paths.

    Parameters
    ----------
    result : dict
        results/planar/planar.h5 (read_h5 layout).

    Returns
    -------
    matplotlib.figure.Figure
        Panels (a) ends at a strip in its frame, (b) Delta x_d, (c) the corner, (d) example paths.

    Examples
    --------
    >>> import numpy as np
    >>> from selfalign.plots.planar import alignment_figure
    >>> line = {"datasets": {"angle": np.array([0.0]), "depth": np.array([[0.04]]), "along": np.zeros((1, 1)),
    ...                      "lateral": np.zeros((1, 1)), "stick_depth": 0.04, "dx_d_normal": np.zeros(1),
    ...                      "dx_d_slide": np.zeros(1)}, "attrs": {"w": 0.05}}
    >>> corner = {"datasets": {"normal": np.array([[0.7, 0.7], [0.7, -0.7]]), "start": np.zeros((1, 2)),
    ...                        "x_end": np.zeros((1, 2)), "corner": np.zeros(2)}, "attrs": {"w": 0.05}}
    >>> example = {"datasets": {"normal": np.array([[1.0, 0.0]]), "x_mu": np.zeros(1), "x": np.zeros((2, 2))},
    ...            "attrs": {"w": 0.05}}
    >>> groups = {"line_along": line, "line_planar": line, "corner": corner, "example_line": example,
    ...           "example_corner": example}
    >>> len(alignment_figure({"groups": groups}).axes)
    4
    """
    g = result["groups"]
    fig = Figure(figsize=(2 * PANEL[0], 2 * PANEL[1]), layout="constrained")
    (a, b), (c, d) = fig.subplots(2, 2)
    strip_cloud_panel(a, g["line_planar"])
    a.set_title("(a) " + a.get_title() + " (planar motion)", fontsize="medium")
    spread_panel(b, {"motion along the drift": g["line_along"], "planar motion": g["line_planar"]})
    b.set_title("(b) " + b.get_title(), fontsize="medium")
    corner = g["corner"]["datasets"]
    plane_panel(c, g["corner"], title="(c) corner of two strips: entries, ends, one path", starts=corner["start"],
                ends=corner["x_end"], corner=corner["corner"], paths=[g["example_corner"]["datasets"]["x"]])
    plane_panel(d, g["example_line"], title="(d) one entry onto a strip (planar motion)",
                paths=[g["example_line"]["datasets"]["x"]])
    return fig
