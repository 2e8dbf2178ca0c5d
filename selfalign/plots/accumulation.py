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
from matplotlib.patches import Rectangle

#: Shading of the table: low-friction and high-friction regions.
LOW_COLOR, HIGH_COLOR = "0.95", "0.7"
#: Colours of the two entries of a phase portrait.
ENTRY_COLORS = ("tab:blue", "tab:red")
#: Accumulation identification classes of Fig. 17 C, in the order of their codes 0..4.
ACCUMULATION_CLASSES = ("no entry accumulates, all stop", "some entries accumulate", "all entries accumulate",
                        "some entries never stop or stay undecided", "mass never reaches the zone")
ACCUMULATION_COLORS = ("tab:orange", "tab:olive", "tab:green", "tab:purple", "white")
#: Case colours of Fig. 17 B (Table 1, case 0 non-physical).
CASE_COLORS = ("white", "tab:green", "tab:red", "tab:blue", "tab:orange", "0.6")


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


def phase_portraits(fig, panels):
    """Fig. 16: one phase portrait (x, x') per panel, two entries each, with x_mu and
    x_stick_min.  ``panels``: dicts with ``title``, ``x_mu``, ``x_stick_min``, ``w``
    and ``entries``, a list of (x, v, label)."""
    axes = fig.subplots(len(panels), 1)
    for ax, panel in zip(np.atleast_1d(axes), panels):
        for (x, v, label), color in zip(panel["entries"], ENTRY_COLORS):
            ax.plot(x, v, color=color, linewidth=0.8, label=label)
        ax.axhline(0.0, color="0.5", linewidth=0.6)
        _mark(ax, panel["x_mu"], r"$x_\mu$", style="--")
        _mark(ax, panel["x_stick_min"], r"$x_{\mathrm{stick,min}}$", style="--")
        ax.set_ylabel("$x'$")
        ax.set_title(panel["title"], fontsize="medium", pad=16)
        ax.legend(loc="upper left", fontsize="small", frameon=False)
    np.atleast_1d(axes)[-1].set_xlabel("$x$")
    return fig


def accumulation_classes(frac_accumulate, frac_never_stop):
    """Codes of Fig. 17 C (index into ACCUMULATION_CLASSES) from the outcome fractions."""
    code = np.where(frac_accumulate == 1, 2, np.where(frac_accumulate > 0, 1, 0))
    code = np.where(frac_never_stop > 0, 3, code)
    return np.where(np.isnan(frac_accumulate), 4, code)


def fig17_panels(fig, y2, y3, f, vbar, case, frac_accumulate, frac_never_stop, dx_d, f_max=0.8):
    """Fig. 17: A objective f (eq. 11, clipped at f_max; blank where vbar <= 0, since f
    = 1/(c vbar^2) does not see the direction), B case (Table 1), C accumulation
    identification (all/some/none of the entries accumulate; some never stop or stay
    undecided), D positioning error Delta x_d (eq. 39; blank where undefined)."""
    axes = fig.subplots(2, 2, sharex=True, sharey=True).ravel()
    extent = (y3[0], y3[-1], y2[0], y2[-1])
    grid = {"origin": "lower", "extent": extent, "aspect": "auto", "interpolation": "nearest"}
    im = axes[0].imshow(np.where(vbar > 0, np.minimum(f, f_max), np.nan), cmap="viridis", **grid)
    fig.colorbar(im, ax=axes[0], label=rf"$f$ where $\bar v > 0$ (clipped at {f_max:g})")
    cmap = ListedColormap(CASE_COLORS)
    im = axes[1].imshow(case, cmap=cmap, norm=BoundaryNorm(np.arange(-0.5, 6), cmap.N), **grid)
    fig.colorbar(im, ax=axes[1], ticks=range(6), label="case")
    cmap = ListedColormap(ACCUMULATION_COLORS)
    codes = accumulation_classes(frac_accumulate, frac_never_stop)
    axes[2].imshow(codes, cmap=cmap, norm=BoundaryNorm(np.arange(-0.5, 5), cmap.N), **grid)
    handles = [Rectangle((0, 0), 1, 1, facecolor=c, edgecolor="k", linewidth=0.5) for c in ACCUMULATION_COLORS]
    axes[2].legend(handles, ACCUMULATION_CLASSES, loc="lower left", fontsize="x-small", framealpha=0.8)
    im = axes[3].imshow(dx_d, cmap="magma", **grid)
    fig.colorbar(im, ax=axes[3], label=r"$\Delta x_d$")
    for ax, label in zip(axes, "ABCD"):
        ax.set_title(label, loc="left", fontweight="bold")
    for ax in axes[2:]:
        ax.set_xlabel("$y_3''$")
    for ax in axes[::2]:
        ax.set_ylabel("$y_2''$")
    return fig


def stick_map_plot(ax, x_n, formula, simulated, valid, x_mu, x_stick_min, x_threshold, cobwebs=(), title=""):
    """Fig. 18: x_{n+1}(x_n) of eq. (59) (solid where its assumptions hold, ``valid``),
    the simulated map, the diagonal, x_mu, the threshold x_c and x_stick_min, and cobwebs
    of stick sequences (label, positions)."""
    ax.plot(x_n, np.where(valid, formula, np.nan), color="k", label="eq. (59)")
    ax.plot(x_n, np.where(valid, np.nan, formula), color="k", linestyle="--", linewidth=0.8,
            label="eq. (59) outside its assumptions")
    ax.plot(x_n, simulated, "o", markersize=3, markerfacecolor="none", color="tab:blue",
            label="exact solver")
    ax.plot(x_n, x_n, color="0.5", linewidth=0.8, label="$x_{n+1} = x_n$")
    for (label, seq), color in zip(cobwebs, ("tab:green", "tab:red")):
        # (x0, x0) -> (x0, x1) -> (x1, x1) -> (x1, x2) -> ...
        ax.plot(np.repeat(seq, 2)[:-1], np.concatenate([seq[:1], np.repeat(seq[1:], 2)]), color=color,
                linewidth=0.9, label=label)
    for x, label, style in ((x_mu, r"$x_\mu$", "--"), (x_threshold, "$x_c$", ":"),
                            (x_stick_min, r"$x_{\mathrm{stick,min}}$", "--")):
        _mark(ax, x, label, style=style)
    ax.set_xlabel("$x_n$")
    ax.set_ylabel("$x_{n+1}$")
    ax.legend(loc="lower right", fontsize="small", frameon=False)
    if title:
        ax.set_title(title, pad=16)
    return ax.figure


# ---------------------------------------------------------------------------------------
# Builders from result files
# ---------------------------------------------------------------------------------------

def _setting(result, key):
    groups = result["groups"]
    if key not in groups:
        raise ValueError(f"setting {key!r} not in the result; it holds {sorted(groups)}")
    return groups[key]


def _setting_title(attrs, result_attrs):
    return (rf"$y_2''$ = {attrs['y2']:g}, $y_3''$ = {attrs['y3']:g} ($\Delta t$ = {result_attrs['dt']:g}, "
            rf"$\Delta y$ = {result_attrs['dy']:g}, $w$ = {result_attrs['w']:g}, $c_\mu$ = {result_attrs['c_mu']:g})")


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
    """Fig. 16 from ``fig16.h5``: phase portraits of the settings ``keys``, two entries each."""
    panels = []
    for key in keys:
        g = _setting(result, key)
        a = g["attrs"]
        entries = [(e["datasets"]["x"], e["datasets"]["v"],
                    f"$x_{{0s}}$ = {g['datasets']['x0'][e['attrs']['index']]:.4f}: {e['attrs']['status']}, "
                    f"end {e['attrs']['x_end']:.5f}")
                   for e in (g["groups"]["entry_0"], g["groups"]["entry_1"])]
        panels.append({"title": _setting_title(a, result["attrs"]), "x_mu": a["x_mu"],
                       "x_stick_min": a["x_stick_min"], "entries": entries})
    return phase_portraits(Figure(figsize=(7.0, 6.5), layout="constrained"), panels)


def figure_17(result):
    """Fig. 17 from ``fig17.h5``."""
    d = result["datasets"]
    fig = Figure(figsize=(9.0, 7.5), layout="constrained")
    never = d["frac_never_stop"] + d["frac_undecided"]
    return fig17_panels(fig, d["y2"], d["y3"], d["f"], d["vbar"], d["case"], d["frac_accumulate"], never,
                        d["dx_d"])


def figure_18(result):
    """Fig. 18 from ``fig18.h5``."""
    d, a = result["datasets"], result["attrs"]
    title = (rf"$y_2''$ = {a['y2']:g}, $y_3''$ = {a['y3']:g}, $\Delta t$ = {a['dt']:g}, "
             rf"$\Delta y$ = {a['dy']:g}")
    cobwebs = (("stick positions from above $x_c$", d["cobweb_accumulate"]),
               ("stick positions from below $x_c$", d["cobweb_rest"]))
    fig = Figure(figsize=(6.4, 5.2), layout="constrained")
    return stick_map_plot(fig.subplots(), d["x_n"], d["x_next_formula"], d["x_next_simulated"], d["valid"],
                          a["x_mu"], a["x_stick_min"], a["x_threshold"], cobwebs, title=title)
