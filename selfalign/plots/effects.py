"""Plot functions and figure builders for the effects beyond the paper on stopping
and accumulation (Sect. 7): static and Stribeck friction.

As in :mod:`selfalign.plots.accumulation`, the plot functions draw the data they are given onto
matplotlib Axes and the builders ``figure_*`` take a result in
:func:`selfalign.io.hdf5.read_h5` layout (written by :mod:`selfalign.stages.effects`).  The
maps show the fraction of entries that accumulate as the three classes of the figure standard
(:data:`selfalign.plots.style.FRACTION_CLASSES`), as Fig. 17 c does, so the figures read alike.
"""

from __future__ import annotations

import numpy as np
from matplotlib.figure import Figure
from matplotlib.patches import Patch
from matplotlib.ticker import LogLocator

from .accumulation import ACCUMULATION_CLASSES, accumulation_mesh, not_reached_handle
from .style import (
    FRACTION_COLORS,
    LINE_COLORS,
    SMALL_FONT_SIZE,
    mark_cells,
    new_figure,
    panel_letters,
    setting_title,
    styled,
)

#: Colours of the swept settings of the line panels.
SETTING_COLORS = LINE_COLORS


def accumulation_panel(ax, y2, y3, frac_accumulate, unsettled, no_profile=None) -> list:
    """The fraction of entries that accumulate over (y2'', y3'') as the three classes, where every
    entry ends at rest; ``unsettled`` cells (some entry never stops or stays undecided) and
    ``no_profile`` cells (case 0; None: not marked) in their encodings; white where the mass never
    reaches the zone.  Returns the legend handles."""
    unsettled = np.asarray(unsettled, dtype=bool)
    accumulation_mesh(ax, y2, y3, frac_accumulate, unsettled)
    classes = [Patch(facecolor=c, edgecolor="k", linewidth=0.5, label=label)
               for c, label in zip(FRACTION_COLORS, ACCUMULATION_CLASSES)]
    handles = classes + [mark_cells(ax, y2, y3, unsettled, "unsettled"), not_reached_handle()]
    if no_profile is not None:
        handles.append(mark_cells(ax, y2, y3, no_profile, "non_physical"))
    return handles


def dx_d_against_ratio(ax, ratio, settings, dx_d, frac_accumulate, grid_ratio=(), grid_median=()):
    """Delta x_d of each (y2'', y3'') of ``settings`` against r - 1 (log-log), [setting, r] arrays
    over ``ratio`` (whose r = 1, Coulomb, is drawn as a dotted level where it is positive; the
    label says how many entries accumulate there).  ``grid_ratio``, ``grid_median``: the median
    Delta x_d of the maps."""
    ratio = np.asarray(ratio, dtype=float)
    excess = ratio - 1.0
    above = excess > 0
    for (y2, y3), d, acc, color in zip(settings, dx_d, frac_accumulate, SETTING_COLORS):
        coulomb = [f"{100 * acc[i]:.0f} % accumulate" for i in np.flatnonzero(~above) if acc[i] > 0]
        label = setting_title(y2=y2, y3=y3) + "".join(f" ($r = 1$: {text})" for text in coulomb)
        ax.plot(excess[above], d[above], "o-", color=color, label=label)
        for r_index in np.flatnonzero(~above & (d > 0)):
            ax.axhline(d[r_index], color=color, linestyle=":", linewidth=1.0)
    grid_excess = np.asarray(grid_ratio, dtype=float) - 1.0
    shown = grid_excess > 0
    if np.any(shown):
        ax.plot(grid_excess[shown], np.asarray(grid_median)[shown], "s", color="k", markerfacecolor="none",
                markersize=4, label=r"median $\Delta x_d$ of the maps")
    ax.plot([], [], color="0.4", linestyle=":", linewidth=1.0, label=r"Coulomb ($r = 1$) where $\Delta x_d > 0$")
    ax.set_xscale("log")
    ax.set_yscale("log")
    ax.set_xlabel(r"$r - 1 = \mu_s/\mu_k - 1$")
    ax.set_ylabel(r"$\Delta x_d$")
    ax.grid(True, which="major", linewidth=0.4, alpha=0.5)
    ax.legend(loc="upper left", bbox_to_anchor=(1.02, 1.0), borderaxespad=0.0)
    return ax


@styled
def figure_static_friction(result, no_profile=None) -> Figure:
    """The static-friction figure from ``static_friction.h5``: one Fig. 17 c map per r of the
    maps (a, b, ..., top row, the count of settings where some entry accumulates written in each)
    and Delta x_d of the swept settings against r - 1 (last panel).

    Parameters
    ----------
    result : dict
        ``results/effects/static_friction.h5`` read with :func:`selfalign.io.hdf5.read_h5`.
    no_profile : array_like of bool, optional
        [y2, y3]: the settings without a physical profile (case 0), drawn in its encoding; None: not marked.

    Returns
    -------
    matplotlib.figure.Figure
        174 mm wide.
    """
    d = result["datasets"]
    maps, sweep = result["groups"]["maps"]["datasets"], result["groups"]["sweep"]["datasets"]
    n = maps["ratio"].size
    fig = new_figure("double", 160.0)
    top, bottom = fig.subfigures(2, 1, height_ratios=(1.25, 1.0))
    grid = top.add_gridspec(2, n, height_ratios=(1.0, 0.22))
    maps_axes = [top.add_subplot(grid[0, k]) for k in range(n)]
    key = top.add_subplot(grid[1, :])
    medians = []
    for k, ax in enumerate(maps_axes):
        unsettled = (maps["frac_never_stop"][k] > 0) | (maps["frac_undecided"][k] > 0)
        handles = accumulation_panel(ax, d["y2"], d["y3"], maps["frac_accumulate"][k], unsettled, no_profile)
        some = np.count_nonzero(np.nan_to_num(maps["frac_accumulate"][k]) > 0)
        reached = np.count_nonzero(np.isfinite(maps["frac_accumulate"][k]))
        ax.text(0.04, 0.03, f"some accumulate:\n{some} of {reached}", transform=ax.transAxes, ha="left",
                va="bottom", fontsize=SMALL_FONT_SIZE)
        # Delta x_d over the settings where every entry ends at rest, as Fig. 17 d shows it.
        medians.append(np.nanmedian(np.where(unsettled, np.nan, maps["dx_d"][k])))
        if k:
            ax.sharey(maps_axes[0])
            ax.set_ylabel("")
            ax.tick_params(labelleft=False)
    key.axis("off")
    key.legend(handles=handles, loc="center", ncols=2, borderaxespad=0.0)
    sweep_ax = bottom.subplots()
    settings = np.column_stack([sweep["y2"], sweep["y3"]])
    dx_d_against_ratio(sweep_ax, sweep["ratio"], settings, sweep["dx_d"], sweep["frac_accumulate"],
                       maps["ratio"], medians)
    panel_letters(maps_axes + [sweep_ax])
    return fig


def against_v_s(ax, v_s_fraction, settings, values, limits, ylabel: str):
    """``values`` [setting, v_s] of each (y2'', y3'') of ``settings`` against v_s / velocity swing
    (log axis), with each setting's ``limits`` (label -> [setting] values: the first dashed, the
    second dotted, e.g. the static/kinetic limit v_s -> 0 and Coulomb) as horizontal lines in its
    colour.  Returns the legend handles: the settings, then the line styles in grey."""
    styles = ("--", ":")
    for k, ((y2, y3), row, color) in enumerate(zip(settings, values, SETTING_COLORS)):
        ax.plot(v_s_fraction, row, "o-", color=color, label=setting_title(y2=y2, y3=y3))
        for level, style in zip(limits.values(), styles):
            ax.axhline(level[k], color=color, linestyle=style, linewidth=1.0)
    handles = [line for line in ax.get_lines() if line.get_marker() == "o"]
    for label, style in zip(limits, styles):
        handles.append(ax.plot([], [], color="0.4", linestyle=style, linewidth=1.0, label=label)[0])
    ax.set_xscale("log")
    ax.xaxis.set_major_locator(LogLocator(numticks=12))
    ax.set_xlabel(r"$v_s\,/\,(\max y' - \min y')$")
    ax.set_ylabel(ylabel)
    ax.grid(True, which="major", linewidth=0.4, alpha=0.5)
    return handles


@styled
def figure_stribeck_friction(result) -> Figure:
    """The Stribeck-friction figure from ``stribeck.h5``: vbar of the steady settings (a), the
    fraction of entries that accumulate (b) and Delta x_d (c) of the stopping settings, against v_s,
    each with its static/kinetic (v_s -> 0, dashed) and Coulomb (dotted) values; the legends below.

    Parameters
    ----------
    result : dict
        ``results/effects/stribeck.h5`` read with :func:`selfalign.io.hdf5.read_h5`.

    Returns
    -------
    matplotlib.figure.Figure
        174 mm wide.
    """
    v_s = result["datasets"]["v_s_fraction"]
    d = result["groups"]["stribeck_steady"]["datasets"]
    e = result["groups"]["stribeck_stopping"]["datasets"]
    fig = new_figure("double", 92.0)
    top, bottom = fig.subfigures(2, 1, height_ratios=(1.0, 0.3))
    axes = {**top.subplot_mosaic([["vbar", "acc", "dx"]]),
            **bottom.subplot_mosaic([["key_steady", "key_stop"]], width_ratios=(1.0, 1.0))}
    static, coulomb = r"static/kinetic ($v_s \to 0$)", r"Coulomb ($r = 1$)"
    steady = against_v_s(axes["vbar"], v_s, np.column_stack([d["y2"], d["y3"]]), d["vbar"],
                         {static: d["vbar_static_kinetic"], coulomb: d["vbar_coulomb"]}, r"$\bar v$ (eq. 10)")
    settings = np.column_stack([e["y2"], e["y3"]])
    for ax, field, label in ((axes["acc"], "frac_accumulate", "fraction of entries that accumulate"),
                             (axes["dx"], "dx_d", r"$\Delta x_d$ (eq. 39)")):
        stopping = against_v_s(ax, v_s, settings, e[field], {static: e[f"{field}_static_kinetic"],
                                                            coulomb: e[f"{field}_coulomb"]}, label)
    for key, handles, title in (("key_steady", steady, r"$\bar v$: settings of Fig. 11's plane"),
                                ("key_stop", stopping, "stopping: settings of Fig. 17's plane")):
        axes[key].axis("off")
        axes[key].legend(handles=handles, loc="upper center", title=title, ncols=2, borderaxespad=0.0)
    panel_letters([axes["vbar"], axes["acc"], axes["dx"]])
    return fig
