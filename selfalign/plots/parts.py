"""Figures of the queue study (docs/explanation/queue.md): a queue of parts at the stop zone.

Data in (the groups of results/parts/queue.h5, read_h5 layout), Figure out; no physics, no files.  Each
panel function draws on the Axes it is given and returns its Figure; the figure builders draw at print size
under the figure standard (:mod:`selfalign.plots.style`).
"""

from __future__ import annotations

import numpy as np
from matplotlib.figure import Figure
from matplotlib.lines import Line2D
from matplotlib.patches import Patch

from .style import LINE_COLORS, SPECIAL, new_figure, panel_letters, special_handle, styled

#: Colour of the zone's transition x_mu .. x_mu + w and of the high-friction side beyond.
TRANSITION_COLOR, HIGH_COLOR = "0.85", "0.93"
#: Status of a queue (dataset ``status``) that ran out of periods before every part stopped for good.
HORIZON = 2
#: Legend label of such a queue (the encoding "unsettled" of :data:`selfalign.plots.style.SPECIAL`).
UNSETTLED_LABEL = "not every part stops"


def _part_color(i: int) -> str:
    """The colour of the i-th part (0: the front part)."""
    return LINE_COLORS[i % len(LINE_COLORS)]


def _strip(ax, x_mu: float, w: float, *, vertical: bool) -> None:
    """The stop zone: its transition shaded darker than the high-friction side."""
    span = ax.axhspan if vertical else ax.axvspan
    span(x_mu, x_mu + w, color=TRANSITION_COLOR, zorder=0, label="transition (eqs. 7–9)")
    span(x_mu + w, x_mu + 1e3 * w, color=HIGH_COLOR, zorder=0, label=r"$c_\mu$ side")


def _mark_unsettled(ax, n, status) -> None:
    """The queues of ``n`` parts whose ``status`` is :data:`HORIZON` as hatched columns (the encoding
    "unsettled"), behind the parts."""
    encoding = SPECIAL["unsettled"]
    for k in np.asarray(n)[np.asarray(status) == HORIZON]:
        ax.axvspan(k - 0.4, k + 0.4, facecolor=encoding["facecolor"], edgecolor="k", hatch=encoding["hatch"],
                   linewidth=0.0, zorder=0.5, label=UNSETTLED_LABEL)


def _end_positions(ax, n, x_end) -> None:
    """Each part's end position against N, one colour per place in the queue (front part first)."""
    for i in range(n.size):
        ax.plot(n, x_end[:, i], "o", color=_part_color(i), markersize=3.5, label="front part" if i == 0 else None)


def end_positions_panel(ax, queue: dict, *, spacing: int = 0, restitution: int = 0, spread: int = 0):
    """End positions (x - x_mu) / w of every part against N at one grid point, the strip shaded, the single
    part's rest and the pooled rest marked, queues that never stop for good hatched.

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
    ...                       "status": np.array([[[[0, 1]]]]), "spacing": [0.05], "restitution": [0.0],
    ...                       "spread": [0.0]},
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
    _mark_unsettled(ax, n, np.asarray(d["status"])[spacing, restitution, spread])
    _end_positions(ax, n, x_end)
    ax.plot(n, pooled[:, 0], "k_", markersize=9, label="pooled rest (front part)")
    ax.axhline((float(d["x_single"]) - x_mu) / w, color="k", linestyle="--", linewidth=0.8, label="single part")
    ax.set_ylim(min(-1.0, np.nanmin(x_end) - 0.3), np.nanmax(x_end) + 0.5)
    ax.set_xticks(n)
    ax.set_xlabel("number of parts $N$")
    ax.set_ylabel(r"end position $(x_i - x_\mu)/w$")
    return ax.figure


def front_error_panel(ax, queue: dict, *, spread: int = -1):
    """The front part's error (x_front - x_single) / w against N, one line per spacing (line style) and e
    (colour) at one spread, and in grey the first grid point (gap, e and spread of index 0); the legend, in the
    upper left corner, names the styles and colours once each.

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
    reference = ax.plot(n, error[0, 0, 0], color="k", linewidth=3, alpha=0.3,
                        label=f"spread {float(d['spread'][0]):g}, gap {float(d['spacing'][0]) / w:g} $w$, "
                              f"$e = {float(d['restitution'][0]):g}$")[0]
    gaps, restitutions = np.asarray(d["spacing"]), np.asarray(d["restitution"])
    for i, gap in enumerate(gaps):
        for j, e in enumerate(restitutions):
            ax.plot(n, error[i, j, spread], marker="o", markersize=2.5, color=LINE_COLORS[j],
                    linestyle=styles[i % len(styles)], label=f"gap {gap / w:g} $w$, $e = {e:g}$")
    handles = [reference]
    handles += [Line2D([], [], color="k", linestyle=styles[i % len(styles)], label=f"gap {gap / w:g} $w$")
                for i, gap in enumerate(gaps)]
    handles += [Line2D([], [], color=LINE_COLORS[j], marker="o", markersize=2.5, label=f"$e = {e:g}$")
                for j, e in enumerate(restitutions)]
    ax.set_xticks(n)
    ax.set_xlabel("number of parts $N$")
    ax.set_ylabel(r"front part's error $(x_{N-1} - x_\mathrm{single})/w$")
    ax.legend(handles=handles, loc="upper left")
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
        ax.plot(t, x[:, i], color=_part_color(x.shape[1] - 1 - i), linewidth=1.0,
                label="front part" if i == x.shape[1] - 1 else None)
    ax.set_ylim(np.min(x) - 0.3, np.max(x) + 0.5)
    ax.set_xlabel("time $t$ (period ends)")
    ax.set_ylabel(r"$(x_i - x_\mu)/w$")
    ax.legend(loc="lower right")
    return ax.figure


def design_panel(ax, design: dict):
    """The SI queue on a design: each part's end position past the strip's edge [mm] against N, with the
    single part's, the parts aligned per second, and the queues that never stop for good hatched.

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
    ...                        "x_single": 7.25e-4, "throughput": np.array([0.96]), "status": np.array([0])},
    ...           "attrs": {"spec": "smd_steel_table"}}
    >>> ax = Figure().subplots()
    >>> fig = design_panel(ax, design)
    >>> ax.texts[0].get_text()
    '0.96/s'
    """
    d = design["datasets"]
    n, x_end = np.asarray(d["n"]), 1e3 * np.asarray(d["x_end"])
    width = 1e3 * float(d["width"])
    _strip(ax, 0.0, width, vertical=True)
    _mark_unsettled(ax, n, d["status"])
    _end_positions(ax, n, x_end)
    ax.axhline(1e3 * float(d["x_single"]), color="k", linestyle="--", linewidth=0.8, label="single part")
    for k, rate in zip(n, np.asarray(d["throughput"])):
        ax.annotate(f"{rate:.2g}/s", (k, np.nanmax(x_end[k - 1]) + 0.3 * width), ha="center", va="bottom",
                    bbox=dict(facecolor="white", edgecolor="none", pad=0.8))
    ax.set_ylim(-width, np.nanmax(x_end) + 1.5 * width)
    ax.set_xticks(n)
    ax.set_xlabel("number of parts $N$")
    ax.set_ylabel("end position past the strip's edge [mm]")
    return ax.figure


def _zone_legend_handles(status) -> list:
    """The legend entries of the end-position panels: the zone, the parts, the references and, where a queue
    never stops for good, the hatch of "unsettled"."""
    handles = [Patch(color=TRANSITION_COLOR, label="transition (eqs. 7–9)"),
               Patch(color=HIGH_COLOR, label=r"$c_\mu$ side"),
               Line2D([], [], color=_part_color(0), marker="o", markersize=3.5, linestyle="none", label="front part"),
               Line2D([], [], color="k", marker="_", markersize=9, linestyle="none", label="pooled rest (front part)"),
               Line2D([], [], color="k", linestyle="--", linewidth=0.8, label="single part")]
    if any(np.any(np.asarray(s) == HORIZON) for s in status):
        handles.append(special_handle("unsettled", UNSETTLED_LABEL))
    return handles


@styled
def queue_figure(result: dict) -> Figure:
    """The queue figure (two columns): (a), (b) end positions against N at the first grid point and at the
    last spacing and spread, (c) the front part's error against N for every spacing and e, (d) the SI queue of
    the design; one legend below the panels names the zone, the parts and the references.

    Parameters
    ----------
    result : dict
        results/parts/queue.h5 (read_h5 layout).

    Returns
    -------
    matplotlib.figure.Figure
        Four panels, 174 mm wide.

    Examples
    --------
    >>> import numpy as np
    >>> from selfalign.plots.parts import queue_figure
    >>> x_end = np.array([[[[[0.54, np.nan], [0.58, 0.53]]]]])
    >>> queue = {"datasets": {"n": np.array([1, 2]), "x_end": x_end, "pooled": x_end, "error": x_end - 0.54,
    ...                       "x_single": 0.54, "status": np.array([[[[0, 1]]]]), "spacing": np.array([0.0]),
    ...                       "restitution": np.array([0.0]), "spread": np.array([0.0])},
    ...          "attrs": {"x_mu": 0.5, "w": 0.05}}
    >>> design = {"datasets": {"n": np.array([1, 2]), "x_end": np.array([[7.3e-4, np.nan], [2.7e-3, 7e-4]]),
    ...                        "width": 2e-3, "x_single": 7.3e-4, "throughput": np.array([0.96, 0.21]),
    ...                        "status": np.array([0, 2])}, "attrs": {"spec": "smd_steel_table"}}
    >>> fig = queue_figure({"groups": {"queue": queue, "design_queue": design}})
    >>> [ax.get_title(loc="left") for ax in fig.axes], round(fig.get_figwidth() * 25.4)
    (['a', 'b', 'c', 'd'], 174)
    """
    groups = result["groups"]
    queue, design = groups["queue"], groups["design_queue"]
    fig = new_figure("double", 128)
    axes = fig.subplots(2, 2)
    last = len(queue["datasets"]["spacing"]) - 1
    end_positions_panel(axes[0, 0], queue, spacing=0)
    end_positions_panel(axes[0, 1], queue, spacing=last, spread=len(queue["datasets"]["spread"]) - 1)
    front_error_panel(axes[1, 0], queue)
    design_panel(axes[1, 1], design)
    panel_letters(axes.ravel())
    handles = _zone_legend_handles([queue["datasets"]["status"], design["datasets"]["status"]])
    fig.legend(handles=handles, loc="outside lower center", ncol=4)
    return fig


@styled
def motion_figure(result: dict) -> Figure:
    """The queue's trajectories (:func:`motion_panel`) on their own, one column wide.

    Parameters
    ----------
    result : dict
        results/parts/queue.h5 (read_h5 layout).

    Returns
    -------
    matplotlib.figure.Figure
        One panel, 84 mm wide.

    Examples
    --------
    >>> import numpy as np
    >>> from selfalign.plots.parts import motion_figure
    >>> motion = {"datasets": {"t": np.arange(3.0), "x": np.array([[0.0, 0.1], [0.1, 0.15], [0.12, 0.17]])},
    ...           "attrs": {"x_mu": 0.1, "w": 0.05, "spacing": 0.05, "restitution": 0.0}}
    >>> fig = motion_figure({"groups": {"queue_motion": motion}})
    >>> [round(x * 25.4) for x in fig.get_size_inches()]
    [84, 62]
    """
    fig = new_figure("single", 62)
    return motion_panel(fig.subplots(), result["groups"]["queue_motion"])
