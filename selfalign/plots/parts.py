"""Figures of the queue study (docs/explanation/queue.md): a queue of parts at the stop zone.

Data in (the groups of results/parts/queue.h5, read_h5 layout), Figure out; no physics, no files.  Each
panel function draws on the Axes it is given and returns its Figure.
"""

from __future__ import annotations

import numpy as np
from matplotlib.figure import Figure

#: Width and height of one panel [in].
PANEL = (4.6, 3.4)
#: Colour of the zone's transition x_mu .. x_mu + w and of the high-friction side beyond.
TRANSITION_COLOR, HIGH_COLOR = "0.85", "0.93"


def _strip(ax, x_mu: float, w: float, *, vertical: bool) -> None:
    """The stop zone: its transition shaded darker than the high-friction side."""
    span = ax.axhspan if vertical else ax.axvspan
    span(x_mu, x_mu + w, color=TRANSITION_COLOR, zorder=0, label="transition (eqs. 7-9)")
    span(x_mu + w, x_mu + 1e3 * w, color=HIGH_COLOR, zorder=0, label=r"$c_\mu$ side")


def end_positions_panel(ax, queue: dict, *, spacing: int = 0, restitution: int = 0, spread: int = 0):
    """End positions (x - x_mu) / w of every part against N at one grid point, the strip shaded, the single
    part's rest and the pooled rest marked.

    Parameters
    ----------
    ax : matplotlib.axes.Axes
        Where to draw.
    queue : dict
        The ``queue`` group (read_h5 layout).
    spacing, restitution, spread : int
        Indices of the grid point.

    Returns
    -------
    matplotlib.figure.Figure
        The figure of ``ax``.

    Examples
    --------
    One part at x_stick_min and two at the pooled rest of the Fig. 18 setting (x_mu = 0.5, w = 0.05):

    >>> import numpy as np
    >>> from matplotlib.figure import Figure
    >>> from selfalign.plots.parts import end_positions_panel
    >>> x_end = np.array([[[[[0.54, np.nan], [0.58, 0.53]]]]])
    >>> queue = {"datasets": {"n": np.array([1, 2]), "x_end": x_end, "pooled": x_end, "x_single": 0.54,
    ...                       "spacing": [0.05], "restitution": [0.0], "spread": [0.0]},
    ...          "attrs": {"x_mu": 0.5, "w": 0.05}}
    >>> ax = Figure().subplots()
    >>> fig = end_positions_panel(ax, queue)
    >>> ax.lines[0].get_ydata().round(6).tolist()
    [0.8, 1.6]
    """
    d, a = queue["datasets"], queue["attrs"]
    x_mu, w = float(a["x_mu"]), float(a["w"])
    n = np.asarray(d["n"])
    x_end = (np.asarray(d["x_end"])[spacing, restitution, spread] - x_mu) / w
    pooled = (np.asarray(d["pooled"])[spacing, restitution, spread] - x_mu) / w
    _strip(ax, 0.0, 1.0, vertical=True)
    for i in range(n.size):
        ax.plot(n, x_end[:, i], "o", color=f"C{i % 10}", markersize=4, label="front part" if i == 0 else None)
    ax.plot(n, pooled[:, 0], "k_", markersize=12, label="pooled rest (front part)")
    ax.axhline((float(d["x_single"]) - x_mu) / w, color="k", linestyle="--", linewidth=0.8, label="single part")
    ax.set_ylim(min(-1.0, np.nanmin(x_end) - 0.3), np.nanmax(x_end) + 0.5)
    ax.set_xticks(n)
    ax.set_xlabel("number of parts $N$")
    ax.set_ylabel(r"end position $(x_i - x_\mu)/w$")
    ax.set_title(f"gap {float(d['spacing'][spacing]) / w:g} w, e = {float(d['restitution'][restitution]):g}, "
                 f"spread {float(d['spread'][spread]):g}", fontsize="medium")
    ax.legend(fontsize="x-small", loc="upper left")
    return ax.figure


def front_error_panel(ax, queue: dict, *, spread: int = -1):
    """The front part's error (x_front - x_single) / w against N, one line per spacing and e at one spread, and
    in black the first grid point (gap, e and spread of index 0).

    Parameters
    ----------
    ax : matplotlib.axes.Axes
        Where to draw.
    queue : dict
        The ``queue`` group (read_h5 layout).
    spread : int
        Index of the friction-factor spread.  Default the last.

    Returns
    -------
    matplotlib.figure.Figure
        The figure of ``ax``.

    Examples
    --------
    >>> import numpy as np
    >>> from matplotlib.figure import Figure
    >>> from selfalign.plots.parts import front_error_panel
    >>> queue = {"datasets": {"n": np.array([1, 2]), "error": np.array([[[[[0.0, np.nan], [0.04, -0.01]]]]]),
    ...                       "spacing": [0.05], "restitution": [0.0], "spread": [0.0]}, "attrs": {"w": 0.05}}
    >>> ax = Figure().subplots()
    >>> fig = front_error_panel(ax, queue)
    >>> ax.lines[-1].get_ydata().round(6).tolist()
    [0.0, 0.8]
    """
    d, w = queue["datasets"], float(queue["attrs"]["w"])
    n, error = np.asarray(d["n"]), np.asarray(d["error"])[..., 0] / w
    styles = ("-", "--", ":", "-.")
    ax.plot(n, error[0, 0, 0], color="k", linewidth=3, alpha=0.3,
            label=f"gap {float(d['spacing'][0]) / w:g} w, e = {float(d['restitution'][0]):g}, "
                  f"spread {float(d['spread'][0]):g}")
    for i, gap in enumerate(np.asarray(d["spacing"])):
        for j, e in enumerate(np.asarray(d["restitution"])):
            ax.plot(n, error[i, j, spread], marker="o", markersize=3, color=f"C{j}", linestyle=styles[i % 4],
                    label=f"gap {gap / w:g} w, e = {e:g}")
    ax.set_xticks(n)
    ax.set_xlabel("number of parts $N$")
    ax.set_ylabel(r"front part's error $(x_{N-1} - x_\mathrm{single})/w$")
    ax.set_title(f"friction-factor spread {float(d['spread'][spread]):g}", fontsize="medium")
    ax.legend(fontsize="x-small", ncol=2)
    return ax.figure


def motion_panel(ax, motion: dict):
    """A queue's fronts (x_i - x_mu) / w against time (period ends), the strip shaded.

    Parameters
    ----------
    ax : matplotlib.axes.Axes
        Where to draw.
    motion : dict
        The ``queue_motion`` group (read_h5 layout).

    Returns
    -------
    matplotlib.figure.Figure
        The figure of ``ax``.

    Examples
    --------
    >>> import numpy as np
    >>> from matplotlib.figure import Figure
    >>> from selfalign.plots.parts import motion_panel
    >>> motion = {"datasets": {"t": np.arange(3.0), "x": np.array([[0.0, 0.1], [0.1, 0.15], [0.12, 0.17]])},
    ...           "attrs": {"x_mu": 0.1, "w": 0.05, "spacing": 0.05, "restitution": 0.0}}
    >>> ax = Figure().subplots()
    >>> motion_panel(ax, motion) is ax.figure, len(ax.lines)
    (True, 2)
    """
    d, a = motion["datasets"], motion["attrs"]
    x_mu, w = float(a["x_mu"]), float(a["w"])
    t, x = np.asarray(d["t"]), (np.asarray(d["x"]) - x_mu) / w
    _strip(ax, 0.0, 1.0, vertical=True)
    for i in range(x.shape[1]):
        ax.plot(t, x[:, i], color=f"C{(x.shape[1] - 1 - i) % 10}", linewidth=1.0,
                label="front part" if i == x.shape[1] - 1 else None)
    ax.set_ylim(np.min(x) - 0.3, np.max(x) + 0.5)
    ax.set_xlabel("time $t$ (period ends)")
    ax.set_ylabel(r"$(x_i - x_\mu)/w$")
    ax.set_title(f"{x.shape[1]} parts, gap {float(a['spacing']) / w:g} w, e = {float(a['restitution']):g}",
                 fontsize="medium")
    ax.legend(fontsize="x-small", loc="lower right")
    return ax.figure


def design_panel(ax, design: dict):
    """The SI queue on a design: each part's end position past the strip's edge [mm] against N, with the
    single part's and the parts aligned per second.

    Parameters
    ----------
    ax : matplotlib.axes.Axes
        Where to draw.
    design : dict
        The ``design_queue`` group (read_h5 layout).

    Returns
    -------
    matplotlib.figure.Figure
        The figure of ``ax``.

    Examples
    --------
    >>> import numpy as np
    >>> from matplotlib.figure import Figure
    >>> from selfalign.plots.parts import design_panel
    >>> design = {"datasets": {"n": np.array([1]), "x_end": np.array([[7.25e-4]]), "width": 2e-3,
    ...                        "x_single": 7.25e-4, "throughput": np.array([0.96])},
    ...           "attrs": {"spec": "smd_steel_table"}}
    >>> ax = Figure().subplots()
    >>> fig = design_panel(ax, design)
    >>> ax.texts[0].get_text()
    '0.96/s'
    """
    d, a = design["datasets"], design["attrs"]
    n, x_end = np.asarray(d["n"]), 1e3 * np.asarray(d["x_end"])
    width = 1e3 * float(d["width"])
    _strip(ax, 0.0, width, vertical=True)
    for i in range(n.size):
        ax.plot(n, x_end[:, i], "o", color=f"C{i % 10}", markersize=4, label="front part" if i == 0 else None)
    ax.axhline(1e3 * float(d["x_single"]), color="k", linestyle="--", linewidth=0.8, label="single part")
    for k, rate in zip(n, np.asarray(d["throughput"])):
        ax.annotate(f"{rate:.2g}/s", (k, np.nanmax(x_end[k - 1]) + 0.3 * width), ha="center", fontsize="x-small")
    ax.set_ylim(-width, np.nanmax(x_end) + width)
    ax.set_xticks(n)
    ax.set_xlabel("number of parts $N$")
    ax.set_ylabel("end position past the strip's edge [mm]")
    ax.set_title(f"design {a['spec']}: parts aligned per second", fontsize="medium")
    ax.legend(fontsize="x-small", loc="upper left")
    return ax.figure


def queue_figure(result: dict) -> Figure:
    """The queue figure: (a) end positions against N at the first and the last spacing, (b) the front part's
    error against N for every spacing and e, (c) the SI queue of the design.

    Parameters
    ----------
    result : dict
        results/parts/queue.h5 (read_h5 layout).

    Returns
    -------
    matplotlib.figure.Figure
        Four panels.

    Examples
    --------
    >>> from selfalign.plots.parts import queue_figure
    >>> queue_figure.__name__
    'queue_figure'
    """
    groups = result["groups"]
    queue = groups["queue"]
    fig = Figure(figsize=(2 * PANEL[0], 2 * PANEL[1]), layout="constrained")
    axes = fig.subplots(2, 2)
    last = len(queue["datasets"]["spacing"]) - 1
    end_positions_panel(axes[0, 0], queue, spacing=0)
    end_positions_panel(axes[0, 1], queue, spacing=last, spread=len(queue["datasets"]["spread"]) - 1)
    front_error_panel(axes[1, 0], queue)
    design_panel(axes[1, 1], groups["design_queue"])
    for ax, letter in zip(axes.ravel(), "abcd"):
        ax.set_title(f"({letter}) {ax.get_title()}", fontsize="medium")
    return fig


def motion_figure(result: dict) -> Figure:
    """The queue's trajectories (:func:`motion_panel`) on their own.

    Parameters
    ----------
    result : dict
        results/parts/queue.h5 (read_h5 layout).

    Returns
    -------
    matplotlib.figure.Figure
        One panel.

    Examples
    --------
    >>> from selfalign.plots.parts import motion_figure
    >>> motion_figure.__name__
    'motion_figure'
    """
    fig = Figure(figsize=(1.5 * PANEL[0], PANEL[1]), layout="constrained")
    return motion_panel(fig.subplots(), result["groups"]["queue_motion"])
