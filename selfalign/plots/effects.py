"""Plot functions and figure builders for the effects beyond the paper on stopping
and accumulation (Sect. 7).

As in :mod:`selfalign.plots.accumulation`, the plot functions draw the data they are given onto
matplotlib Axes and the builders ``figure_*`` take a result in
:func:`selfalign.io.hdf5.read_h5` layout (written by :mod:`selfalign.stages.effects`).  The
maps share Fig. 17 C's classes and colours, so the two figures read alike.
"""

from __future__ import annotations

import numpy as np
from matplotlib.colors import BoundaryNorm, ListedColormap
from matplotlib.figure import Figure
from matplotlib.patches import Patch

from .accumulation import (
    ACCUMULATION_CLASSES,
    ACCUMULATION_COLORS,
    NOT_REACHED_LABEL,
    UNSETTLED_LABEL,
    accumulation_classes,
)
from .style import hatch_cells, map_mesh, setting_title

#: Colours of the swept settings of the Delta x_d panel.
SETTING_COLORS = ("tab:blue", "tab:red", "tab:purple", "tab:brown", "tab:olive")


def accumulation_panel(ax, y2, y3, frac_accumulate, unsettled, title: str):
    """Fig. 17 C for one friction law: none/some/all entries accumulate where every entry ends
    at rest, ``unsettled`` cells hatched, blank where the mass never reaches the zone; the title
    counts the settings where some entry accumulates.  Returns the legend handles."""
    cmap = ListedColormap(ACCUMULATION_COLORS)
    map_mesh(ax, y2, y3, np.where(unsettled, np.nan, accumulation_classes(frac_accumulate)), cmap=cmap,
             norm=BoundaryNorm(np.arange(-0.5, len(ACCUMULATION_COLORS)), cmap.N))
    hatch = hatch_cells(ax, y2, y3, unsettled, UNSETTLED_LABEL)
    reached = np.isfinite(frac_accumulate)
    some = np.count_nonzero(np.nan_to_num(frac_accumulate) > 0)
    ax.set_title(f"{title}\nsome accumulate: {some} of {np.count_nonzero(reached)} settings", fontsize="medium")
    classes = [Patch(facecolor=c, edgecolor="k", linewidth=0.5, label=label)
               for c, label in zip(ACCUMULATION_COLORS, ACCUMULATION_CLASSES)]
    return classes + [hatch, Patch(facecolor="white", edgecolor="k", linewidth=0.5, label=NOT_REACHED_LABEL)]


def dx_d_against_ratio(ax, ratio, settings, dx_d, frac_accumulate, grid_ratio=(), grid_median=()):
    """Delta x_d of each (y2'', y3'') of ``settings`` against r - 1 (log-log), [setting, r] arrays
    over ``ratio`` (whose r = 1, Coulomb, is drawn as a dotted level where it is positive; the
    label says how many entries accumulate there).  ``grid_ratio``, ``grid_median``: the median
    Delta x_d of the maps."""
    ratio = np.asarray(ratio, dtype=float)
    excess = ratio - 1.0
    above = excess > 0
    for (y2, y3), d, acc, color in zip(settings, dx_d, frac_accumulate, SETTING_COLORS):
        coulomb = [f"{acc[i]:.0%} accumulate" for i in np.flatnonzero(~above) if acc[i] > 0]
        label = setting_title(y2=y2, y3=y3) + "".join(f" (r = 1: {text})" for text in coulomb)
        ax.plot(excess[above], d[above], "o-", color=color, markersize=4, label=label)
        for r_index in np.flatnonzero(~above & (d > 0)):
            ax.axhline(d[r_index], color=color, linestyle=":", linewidth=1.0)
    grid_excess = np.asarray(grid_ratio, dtype=float) - 1.0
    shown = grid_excess > 0
    if np.any(shown):
        ax.plot(grid_excess[shown], np.asarray(grid_median)[shown], "s", color="k", markerfacecolor="none",
                label=r"median $\Delta x_d$ of the maps")
    ax.set_xscale("log")
    ax.set_yscale("log")
    ax.set_xlabel(r"$r - 1 = \mu_s/\mu_k - 1$")
    ax.set_ylabel(r"$\Delta x_d$")
    ax.grid(True, which="major", linewidth=0.4, alpha=0.5)
    ax.legend(fontsize="x-small", loc="upper left", title=r"dotted: Coulomb (r = 1) where $\Delta x_d$ > 0",
              title_fontsize="x-small")
    return ax


def figure_static_friction(result):
    """The static-friction figure from ``static_friction.h5``: one Fig. 17 C map per r of the
    maps (top row) and Delta x_d of the swept settings against r - 1 (bottom)."""
    d, a = result["datasets"], result["attrs"]
    maps, sweep = result["groups"]["maps"]["datasets"], result["groups"]["sweep"]["datasets"]
    n = maps["ratio"].size
    fig = Figure(figsize=(3.2 * n + 1.0, 8.5), layout="constrained")
    axes = fig.subplot_mosaic([[f"map{k}" for k in range(n)], ["sweep"] * n], height_ratios=[1.0, 1.1])
    medians = []
    for k, r in enumerate(maps["ratio"]):
        ax = axes[f"map{k}"]
        unsettled = (maps["frac_never_stop"][k] > 0) | (maps["frac_undecided"][k] > 0)
        handles = accumulation_panel(ax, d["y2"], d["y3"], maps["frac_accumulate"][k], unsettled,
                                     r"$\mu_s/\mu_k$ = " + f"{r:g}")
        # Delta x_d over the settings where every entry ends at rest, as Fig. 17 D shows it.
        medians.append(np.nanmedian(np.where(unsettled, np.nan, maps["dx_d"][k])))
        if k:
            ax.set_ylabel("")
            ax.tick_params(labelleft=False)
    axes["map0"].legend(handles=handles, loc="lower left", fontsize="xx-small", framealpha=0.9)
    settings = np.column_stack([sweep["y2"], sweep["y3"]])
    dx_d_against_ratio(axes["sweep"], sweep["ratio"], settings, sweep["dx_d"], sweep["frac_accumulate"],
                       maps["ratio"], medians)
    fig.suptitle(setting_title(**{k: a[k] for k in ("dt", "dy", "w", "c_mu")}) + r", static friction $\mu_s$ = r "
                 r"$\mu_k$", fontsize="medium")
    return fig


def against_v_s(ax, v_s_fraction, settings, values, limits, ylabel: str):
    """``values`` [setting, v_s] of each (y2'', y3'') of ``settings`` against v_s / velocity swing
    (log axis), with each setting's ``limits`` (label -> [setting] values: the first dashed, the
    second dotted, e.g. the static/kinetic limit v_s -> 0 and Coulomb) as horizontal lines in its
    colour; the legend names the line styles in grey."""
    styles = ("--", ":")
    for k, ((y2, y3), row, color) in enumerate(zip(settings, values, SETTING_COLORS)):
        ax.plot(v_s_fraction, row, "o-", color=color, markersize=3, label=setting_title(y2=y2, y3=y3))
        for level, style in zip(limits.values(), styles):
            ax.axhline(level[k], color=color, linestyle=style, linewidth=1.0)
    for label, style in zip(limits, styles):
        ax.plot([], [], color="grey", linestyle=style, linewidth=1.0, label=label)
    ax.set_xscale("log")
    ax.set_xlabel(r"$v_s$ / velocity swing ($\max \dot y - \min \dot y$)")
    ax.set_ylabel(ylabel)
    ax.grid(True, which="major", linewidth=0.4, alpha=0.5)
    ax.legend(fontsize="x-small")
    return ax


def figure_stribeck_friction(result):
    """The Stribeck-friction figure from ``stribeck.h5``: vbar of the steady settings (left), the
    fraction of entries that accumulate (middle) and Delta x_d (right) of the stopping settings,
    against v_s, each with its static/kinetic (v_s -> 0, dashed) and Coulomb (dotted) values."""
    a, v_s = result["attrs"], result["datasets"]["v_s_fraction"]
    steady = result["groups"]["stribeck_steady"]
    entries = result["groups"]["stribeck_stopping"]
    d, e = steady["datasets"], entries["datasets"]
    fig = Figure(figsize=(14.0, 4.8), layout="constrained")
    ax_vbar, ax_acc, ax_dx = fig.subplots(1, 3)
    static, coulomb = r"static/kinetic ($v_s \to 0$)", "Coulomb (r = 1)"
    against_v_s(ax_vbar, v_s, np.column_stack([d["y2"], d["y3"]]), d["vbar"],
                {static: d["vbar_static_kinetic"], coulomb: d["vbar_coulomb"]}, r"$\bar v$ (eq. 10)")
    ax_vbar.set_title(setting_title(**{k: steady["attrs"][k] for k in ("dt", "dy")}) + ", uniform surface",
                      fontsize="medium")
    settings = np.column_stack([e["y2"], e["y3"]])
    for ax, field, label in ((ax_acc, "frac_accumulate", "fraction of entries that accumulate"),
                             (ax_dx, "dx_d", r"$\Delta x_d$ (eq. 39)")):
        against_v_s(ax, v_s, settings, e[field], {static: e[f"{field}_static_kinetic"],
                                                  coulomb: e[f"{field}_coulomb"]}, label)
        ax.set_title(setting_title(**{k: entries["attrs"][k] for k in ("dt", "dy", "w", "c_mu")})
                     + f", {entries['attrs']['n_entries']} entries", fontsize="medium")
    fig.suptitle(r"Stribeck friction $\mu(v) = \mu_k\,(1 + (r - 1)\,e^{-(|v|/v_s)^\delta})$, "
                 f"r = {a['ratio']:g}, " + r"$\delta$" + f" = {a['delta']:g} (Moreau, " + r"$\Delta t$"
                 + f"/{a['steps_per_period']})", fontsize="medium")
    return fig
