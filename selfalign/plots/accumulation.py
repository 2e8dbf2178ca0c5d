"""Plot functions and figure builders for the stopping figures (Figs. 14-18, Sect. 7).

As in :mod:`selfalign.plots.profile`, plot functions draw the data they are given onto
matplotlib Axes (or a Figure for multi-panel plots) and return the figure;
the builders ``figure_*`` take results in :func:`selfalign.io.hdf5.read_h5`
layout (written by :mod:`selfalign.analysis.positioning`'s ``fig*_content``), pick what is
shown and call them.  Nothing here computes physics or writes files; only the
object-oriented matplotlib API is used (headless).
"""

from __future__ import annotations

import numpy as np
from matplotlib.colors import BoundaryNorm, ListedColormap
from matplotlib.figure import Figure
from matplotlib.lines import Line2D
from matplotlib.patches import Patch, Rectangle
from matplotlib.ticker import MaxNLocator

from .classification import mean_velocity_zero_line, objective_panel
from .style import case_map, hatch_cells, map_mesh, setting_title

#: Shading of the table: low-friction and high-friction regions.
LOW_COLOR, HIGH_COLOR = "0.95", "0.7"
#: Colours and line styles of the two entries of a phase portrait (their starts differ by
#: less than a line width in Fig. 16, so the second is dashed).
ENTRY_COLORS = ("tab:blue", "tab:red")
ENTRY_STYLES = ("-", "--")
#: Fig. 17 C for settings where every entry ends at rest: how many accumulate.  One hue
#: (teal, light to dark) that no case of Table 1 uses, since panel B beside it shows the cases.
ACCUMULATION_CLASSES = ("none accumulates, all come to rest", "some accumulate, the rest come to rest",
                        "all accumulate")
ACCUMULATION_COLORS = ("#c7eae5", "#5ab4ac", "#01665e")
#: Legend texts of the cells of Fig. 17 C and D that show no class or no Delta x_d.
UNSETTLED_LABEL = "some entries never stop or stay undecided"
NOT_REACHED_LABEL = "blank: the mass never reaches the zone"
#: The two stick sequences of Fig. 18 (accumulating, resting).
COBWEB_COLORS = ("tab:green", "tab:red")


def _mark(ax, x, label, style=":"):
    ax.axvline(x, color="k", linestyle=style, linewidth=1.0)
    ax.text(x, 1.01, label, transform=ax.get_xaxis_transform(), ha="center", va="bottom", fontsize="small")


def situation_sketch(ax, x0, x_end, x_mu, w, x_stick_min, title=""):
    """Fig. 14: the table (low friction, transition, high friction), the body of width w
    at its start x0 and where it stopped, x_end = x_mu + overshoot."""
    lo, hi = x0 - 1.3 * w, max(x_end, x_mu + w) + 0.8 * w
    ax.set_xlim(lo, hi)
    ax.add_patch(Rectangle((lo, -1.0), hi - lo, 1.0, color=LOW_COLOR, linewidth=0))
    ax.add_patch(Rectangle((x_mu, -1.0), hi - x_mu, 1.0, color=HIGH_COLOR, linewidth=0, label=r"$\mu_2$ region"))
    for x, style, label in ((x0, "--", "start $x_{0s}$"), (x_end, "-", "end position")):
        # The body's reference point x is its front edge: its overlap with the zone is x - x_mu (eq. 8).
        ax.add_patch(Rectangle((x - w, 0.0), w, 0.6, fill=False, linestyle=style, linewidth=1.5, label=label))
    ax.annotate("", xy=(x_end, 0.8), xytext=(x_mu, 0.8), arrowprops={"arrowstyle": "<->"})
    ax.text(0.5 * (x_mu + x_end), 0.85, r"$\Delta x_{\mathrm{overshoot}}$", ha="center", va="bottom")
    _mark(ax, x_mu, r"$x_\mu$")
    _mark(ax, x_stick_min, r"$x_{\mathrm{stick,min}}$")
    ax.set_ylim(-1.0, 1.3)
    ax.set_yticks([])
    ax.set_xlabel("$x$")
    ax.legend(loc="upper left", fontsize="small", frameon=False)
    if title:
        ax.set_title(title, pad=16)
    return ax.figure


def end_position_region(ax, s, overshoot, x_mu, x_stick_min, dx_d, x_d, title=""):
    """Fig. 15: the end positions x_mu + overshoot of all steady-state entries (against
    their offset s), the range [x_d - Delta x_d, x_d + Delta x_d] and x_d (eq. 39)."""
    ax.plot(x_mu + overshoot, s, "k.", markersize=3, label="end positions of the entries")
    ax.axvspan(x_d - dx_d, x_d + dx_d, color="tab:blue", alpha=0.2, linewidth=0,
               label=r"$[x_d - \Delta x_d,\ x_d + \Delta x_d]$")
    _mark(ax, x_mu, r"$x_\mu$")
    _mark(ax, x_stick_min, r"$x_{\mathrm{stick,min}}$", style="--")
    _mark(ax, x_d, "$x_d$", style="-")
    ax.set_xlabel("end position $x$")
    ax.set_ylabel(r"entry offset $s$ ($x_{0s} = -s$)")
    ax.legend(loc="upper left", fontsize="small", frameon=True, framealpha=0.9)
    if title:
        ax.set_title(title, pad=16)
    return ax.figure


def stick_distances(ax, sequences, x_stick_min):
    """|x_n - x_stick_min| of stick sequences against the stick number n, on a log scale, so
    that accumulation (distances shrinking geometrically, a straight line) is visible on every
    scale.  ``sequences``: (label, positions, colour, line style).  Downward triangles: sticks
    short of x_stick_min, where the mass slips on; upward: past it, where it sticks for good.
    x_stick_min itself (distance 0, reached as t -> oo) lies below every scale."""
    for label, x, color, style in sequences:
        d = np.asarray(x, dtype=float) - x_stick_min
        n = np.arange(d.size)
        ax.plot(n, np.where(d != 0, np.abs(d), np.nan), color=color, linestyle=style, linewidth=0.8, label=label)
        ax.plot(n[d < 0], -d[d < 0], "v", color=color, markersize=4)
        ax.plot(n[d > 0], d[d > 0], "^", color=color, markersize=6)
    ax.set_yscale("log")
    ax.xaxis.set_major_locator(MaxNLocator(integer=True))
    ax.set_xlabel("stick $n$")
    ax.set_ylabel(r"$|x_n - x_{\mathrm{stick,min}}|$")
    ax.grid(True, which="major", linewidth=0.4, alpha=0.5)
    return [Line2D([], [], color="k", marker="v", linestyle="none", markersize=4,
                   label=r"$x_n < x_{\mathrm{stick,min}}$: slips on"),
            Line2D([], [], color="k", marker="^", linestyle="none", markersize=6,
                   label=r"$x_n > x_{\mathrm{stick,min}}$: sticks for good")]


def phase_portraits(fig, panels):
    """Fig. 16: per setting, the phase portrait (x, x') of two entries with x_mu and
    x_stick_min (left, as in the paper) and the distances of their sticks in the zone to
    x_stick_min (right, :func:`stick_distances`).  ``panels``: dicts with ``title``,
    ``x_mu``, ``x_stick_min`` and ``entries``, a list of (x, v, label, zone stick positions)."""
    axes = np.atleast_2d(fig.subplots(len(panels), 2, width_ratios=[1.6, 1]))
    # One distance scale for all settings, so that a single jump and a long accumulation compare.
    for ax_d in axes[1:, 1]:
        ax_d.sharey(axes[0, 1])
    for (ax, ax_d), panel in zip(axes, panels):
        sequences = []
        for (x, v, label, sticks), color, style in zip(panel["entries"], ENTRY_COLORS, ENTRY_STYLES):
            ax.plot(x, v, color=color, linestyle=style, linewidth=0.8, label=label)
            sequences.append((label, sticks, color, style))
        ax.axhline(0.0, color="0.5", linewidth=0.6)
        _mark(ax, panel["x_mu"], r"$x_\mu$", style="--")
        _mark(ax, panel["x_stick_min"], r"$x_{\mathrm{stick,min}}$", style="--")
        ax.set_ylabel("$x'$")
        ax.set_title(panel["title"], fontsize="medium", loc="left", pad=16)
        ax.legend(loc="upper left", fontsize="small", framealpha=0.9)
        handles = stick_distances(ax_d, sequences, panel["x_stick_min"])
        ax_d.set_title(r"stick positions $x_n \geq x_\mu$ in the zone", fontsize="small", pad=16)
        ax_d.legend(handles=handles, loc="lower left", fontsize="x-small", framealpha=0.9)
    axes[-1, 0].set_xlabel("$x$")
    return fig


def accumulation_classes(frac_accumulate):
    """Codes of Fig. 17 C (index into ACCUMULATION_CLASSES) from the fraction of entries that
    accumulate; NaN where the mass never reaches the zone (fraction NaN)."""
    code = np.where(frac_accumulate == 1, 2.0, np.where(frac_accumulate > 0, 1.0, 0.0))
    return np.where(np.isnan(frac_accumulate), np.nan, code)


def fig17_panels(fig, y2, y3, f, vbar, case, frac_accumulate, unsettled, dx_d, f_max=0.8, mark=None):
    """Fig. 17: A objective f (:func:`objective_panel`), B case (Table 1), C accumulation
    identification (none/some/all of the entries accumulate), D positioning error Delta x_d
    (eq. 39).  C and D show a value only where every entry ends at rest (stops or
    accumulates): ``unsettled`` cells (some entry never stops or stays undecided) are hatched,
    since Delta x_d there spans only the entries that stopped.  Blank: the mass never reaches
    the zone.  ``mark``: (y2'', y3'', label) of a setting marked on every panel."""
    axes = fig.subplots(2, 2, sharex=True, sharey=True).ravel()
    handles = objective_panel(axes[0], y2, y3, f, vbar, f_max)
    case_map(axes[1], y2, y3, case)
    mean_velocity_zero_line(axes[1], y2, y3, vbar)
    cmap = ListedColormap(ACCUMULATION_COLORS)
    map_mesh(axes[2], y2, y3, np.where(unsettled, np.nan, accumulation_classes(frac_accumulate)), cmap=cmap,
             norm=BoundaryNorm(np.arange(-0.5, len(ACCUMULATION_COLORS)), cmap.N))
    classes = [Patch(facecolor=c, edgecolor="k", linewidth=0.5, label=label)
               for c, label in zip(ACCUMULATION_COLORS, ACCUMULATION_CLASSES)]
    not_reached = Patch(facecolor="white", edgecolor="k", linewidth=0.5, label=NOT_REACHED_LABEL)
    axes[2].legend(handles=classes + [hatch_cells(axes[2], y2, y3, unsettled, UNSETTLED_LABEL), not_reached],
                   loc="lower left", fontsize="x-small", framealpha=0.9)
    mesh = map_mesh(axes[3], y2, y3, np.where(unsettled, np.nan, dx_d), cmap="magma")
    fig.colorbar(mesh, ax=axes[3], label=r"$\Delta x_d$ where every entry ends at rest")
    unsettled_d = hatch_cells(axes[3], y2, y3, unsettled,
                              f"{UNSETTLED_LABEL}:\n" + r"$\Delta x_d$ would span only the entries that stop")
    axes[3].legend(handles=[unsettled_d, not_reached], loc="lower left", fontsize="x-small", framealpha=0.9)
    if mark is not None:
        y2_mark, y3_mark, label = mark
        for ax in axes:
            ax.plot(y2_mark, y3_mark, marker="X", markersize=9, markerfacecolor="white", markeredgecolor="k",
                    linestyle="none", label=label)
        handles.append(axes[0].lines[-1])
    axes[0].legend(handles=handles, loc="lower left", fontsize="x-small", framealpha=0.9)
    for ax, label in zip(axes, "ABCD"):
        ax.set_title(label, loc="left", fontweight="bold")
        ax.label_outer()
    return fig


def _stick_map_lines(ax, x_n, formula, simulated, valid, x_stick_min, cobwebs):
    """The content of a Fig. 18 panel: eq. (59), the exact solver's map, the diagonal, the
    fixed point and the cobwebs of the stick sequences ``cobwebs`` (label, positions)."""
    ax.plot(x_n, np.where(valid, formula, np.nan), color="k", label="eq. (59)")
    ax.plot(x_n, np.where(valid, np.nan, formula), color="k", linestyle="--", linewidth=0.8,
            label="eq. (59) outside its assumptions")
    ax.plot(x_n, simulated, "o", markersize=3, markerfacecolor="none", color="tab:blue", label="exact solver")
    ax.plot(x_n, x_n, color="0.5", linewidth=0.8, label="$x_{n+1} = x_n$")
    for (label, seq), color in zip(cobwebs, COBWEB_COLORS):
        # (x0, x0) -> (x0, x1) -> (x1, x1) -> (x1, x2) -> ...
        ax.plot(np.repeat(seq, 2)[:-1], np.concatenate([seq[:1], np.repeat(seq[1:], 2)]), color=color,
                linewidth=0.9, label=label)
    ax.plot(x_stick_min, x_stick_min, marker="*", markersize=11, markerfacecolor="white", markeredgecolor="k",
            linestyle="none", label=r"fixed point $x_{\mathrm{stick,min}}$")
    ax.set_xlabel("$x_n$")
    ax.set_ylabel("$x_{n+1}$")


def stick_map_plot(fig, x_n, formula, simulated, valid, x_mu, x_stick_min, x_threshold, contraction, zoom,
                   cobwebs=(), title=""):
    """Fig. 18: A x_{n+1}(x_n) of eq. (59) (solid where its assumptions hold, ``valid``), the
    simulated map, the diagonal, x_mu, the threshold x_c and x_stick_min, and cobwebs of stick
    sequences (label, positions), as in the paper; B the same within ``zoom`` (x0, x1, y0, y1),
    the band the map lies in; C the distances of the sticks to x_stick_min on a log scale
    (:func:`stick_distances`), with what x_c means."""
    axes = fig.subplot_mosaic([["map", "zoom"], ["sticks", "sticks"]], height_ratios=[1.25, 1])
    for ax in (axes["map"], axes["zoom"]):
        _stick_map_lines(ax, x_n, formula, simulated, valid, x_stick_min, cobwebs)
        for x, label, style in ((x_mu, r"$x_\mu$", "--"), (x_threshold, "$x_c$", ":"),
                                (x_stick_min, r"$x_{\mathrm{stick,min}}$", "--")):
            _mark(ax, x, label, style=style)
    x0, x1, y0, y1 = zoom
    axes["zoom"].set_xlim(x0, x1)
    axes["zoom"].set_ylim(y0, y1)
    axes["map"].indicate_inset((x0, y0, x1 - x0, y1 - y0), edgecolor="0.3")
    axes["map"].legend(loc="lower right", fontsize="x-small", framealpha=0.9)
    axes["map"].set_title("A", loc="left", fontweight="bold", pad=16)
    axes["zoom"].set_title("B", loc="left", fontweight="bold", pad=16)
    axes["zoom"].set_title("zoom on the band of $x_{n+1}$ (grey box in A)", fontsize="small", pad=16)
    handles = stick_distances(axes["sticks"], [(label, seq, color, "-")
                                               for (label, seq), color in zip(cobwebs, COBWEB_COLORS)],
                              x_stick_min)
    axes["sticks"].legend(handles=axes["sticks"].get_legend_handles_labels()[0] + handles, loc="lower left",
                          fontsize="x-small", framealpha=0.9)
    axes["sticks"].set_title("C", loc="left", fontweight="bold")
    axes["sticks"].text(
        0.99, 0.97,
        "\n".join([
            r"$x_c$: the stick position whose next stick is $x_{\mathrm{stick,min}}$, "
            r"$x_{n+1}(x_c) = x_{\mathrm{stick,min}}$ (eq. 59).",
            r"First stick in $(x_c, x_{\mathrm{stick,min}})$: every later stick stays short of "
            r"$x_{\mathrm{stick,min}}$, the distance",
            rf"shrinking by $\cos(\omega(t_2 - t_1))$ = {contraction:.3g} per stick: accumulation, reached as "
            r"$t \to \infty$ (green).",
            r"First stick below $x_c$: the next stick lands past $x_{\mathrm{stick,min}}$, where the mass "
            "sticks for good (red).",
            r"Here $x_c > x_\mu$, so which happens depends on the initial conditions (Sect. 7.3)."
            if x_threshold > x_mu else
            r"Here $x_c \leq x_\mu$: every stick in the zone accumulates (Sect. 7.3)."]),
        transform=axes["sticks"].transAxes, ha="right", va="top", multialignment="left", fontsize="x-small",
        bbox={"boxstyle": "round,pad=0.4", "facecolor": "white", "edgecolor": "0.6"})
    if title:
        fig.suptitle(title, fontsize="medium")
    return fig


# ---------------------------------------------------------------------------------------
# Builders from result files
# ---------------------------------------------------------------------------------------

def _setting(result, key):
    groups = result["groups"]
    if key not in groups:
        raise ValueError(f"setting {key!r} not in the result; it holds {sorted(groups)}")
    return groups[key]


def _setting_title(attrs, result_attrs):
    return (f"{setting_title(y2=attrs['y2'], y3=attrs['y3'])} ("
            f"{setting_title(**{k: result_attrs[k] for k in ('dt', 'dy', 'w', 'c_mu')})})")


def figure_14(result, key):
    """Fig. 14 from ``fig16.h5``: the entry of setting ``key`` that stops farthest."""
    g = _setting(result, key)
    d, a = g["datasets"], g["attrs"]
    i = int(np.nanargmax(d["overshoot"]))
    fig = Figure(figsize=(7.0, 3.2), layout="constrained")
    return situation_sketch(fig.subplots(), d["x0"][i], d["x_end"][i], a["x_mu"], result["attrs"]["w"],
                            a["x_stick_min"], title=_setting_title(a, result["attrs"]))


def figure_15(result, key):
    """Fig. 15 from ``fig16.h5``: the end positions of all entries of setting ``key``."""
    g = _setting(result, key)
    d, a = g["datasets"], g["attrs"]
    fig = Figure(figsize=(7.0, 4.0), layout="constrained")
    return end_position_region(fig.subplots(), d["s"], d["overshoot"], a["x_mu"], a["x_stick_min"], a["dx_d"],
                               a["x_d"], title=_setting_title(a, result["attrs"]))


def figure_16(result, keys):
    """Fig. 16 from ``fig16.h5``: phase portraits of the settings ``keys``, two entries each,
    and their sticks in the zone (x >= x_mu)."""
    panels = []
    for key in keys:
        g = _setting(result, key)
        a = g["attrs"]
        entries = []
        for e in (g["groups"]["entry_0"], g["groups"]["entry_1"]):
            d = e["datasets"]
            label = (f"$x_{{0s}}$ = {g['datasets']['x0'][e['attrs']['index']]:.4f}: {e['attrs']['status']}, "
                     f"end {e['attrs']['x_end']:.5f}")
            entries.append((d["x"], d["v"], label, d["stick_x"][d["stick_x"] >= a["x_mu"]]))
        panels.append({"title": _setting_title(a, result["attrs"]), "x_mu": a["x_mu"],
                       "x_stick_min": a["x_stick_min"], "entries": entries})
    return phase_portraits(Figure(figsize=(11.0, 7.0), layout="constrained"), panels)


def figure_17(result, stick_map=None):
    """Fig. 17 from ``fig17.h5``; the setting of ``stick_map`` (``fig18.h5``, Fig. 18) is
    marked, with its Delta t when it differs from the grid's."""
    d, a = result["datasets"], result["attrs"]
    mark = None
    if stick_map is not None:
        s = stick_map["attrs"]
        label = "Fig. 18 setting" + (rf" (at $\Delta t$ = {s['dt']:g})" if s["dt"] != a["dt"] else "")
        mark = (s["y2"], s["y3"], label)
    # Delta x_d spans only the entries that stopped: shown where every entry ends at rest.
    unsettled = (d["frac_never_stop"] > 0) | (d["frac_undecided"] > 0)
    fig = Figure(figsize=(11.0, 8.5), layout="constrained")
    fig17_panels(fig, d["y2"], d["y3"], d["f"], d["vbar"], d["case"], d["frac_accumulate"], unsettled, d["dx_d"],
                 mark=mark)
    fig.suptitle(setting_title(**{k: a[k] for k in ("dt", "dy", "w", "c_mu")}), fontsize="medium")
    return fig


def figure_18(result):
    """Fig. 18 from ``fig18.h5``; panel B zooms on the band of x_{n+1} the map and the stick
    sequences lie in."""
    d, a = result["datasets"], result["attrs"]
    cobwebs = (("stick positions from above $x_c$", d["cobweb_accumulate"]),
               ("stick positions from below $x_c$", d["cobweb_rest"]))
    band = np.concatenate([d["x_next_formula"][d["valid"]], d["cobweb_accumulate"][1:], d["cobweb_rest"][1:]])
    margin = 0.15 * (band.max() - band.min())
    zoom = (a["x_mu"], a["x_mu"] + a["w"], band.min() - margin, band.max() + margin)
    fig = Figure(figsize=(11.0, 8.5), layout="constrained")
    return stick_map_plot(fig, d["x_n"], d["x_next_formula"], d["x_next_simulated"], d["valid"], a["x_mu"],
                          a["x_stick_min"], a["x_threshold"], a["contraction"], zoom, cobwebs,
                          title=setting_title(**{k: a[k] for k in ("y2", "y3", "dt", "dy")}))
