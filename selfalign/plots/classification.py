"""Plot functions for the steady-state studies: Figs. 4, 5, 6, 8, 10 and 11.

As in :mod:`selfalign.plots.profile`: each function draws data it is given onto a
matplotlib ``Figure`` and returns it; no physics, no file writes, only the
object-oriented API.  ``figure_NN(result)`` builds figure NN from a result file
read with :func:`selfalign.io.hdf5.read_h5` (the layouts are in docs/reference/results.md,
"Steady state and classification").  Fig. 8 is drawn by walking the decision
tree of :mod:`selfalign.analysis.classification` — the tree that classifies the maps —
so the flow chart cannot disagree with the code.
"""

from __future__ import annotations

import textwrap

import numpy as np
from matplotlib import colormaps
from matplotlib.lines import Line2D

from ..analysis.classification import CASE_LABELS, DECISION_TREE, Decision
from .style import CASE_COLORS, case_map, hatch_cells, map_mesh, setting_title

#: Mathtext of the quantities the decision tree tests, and what they mean.
QUANTITIES = {
    "q": ("q", r"$q = 8\,\Delta y\,(1/y_2'' + 1/y_3'')\,/\,\Delta t^2$: a physical profile needs $q \leq 1$"),
    "y2": ("y_2''", None),
    "y3": ("y_3''", None),
    "t1": ("t_1", None),
    "v_back": ("v_{back}", r"$v_{back} = -x'(t_3)$ of a mass at rest at $t_1$ (it sticks again in "
                           r"$[0, t_1]$ iff $v_{back} \leq t_1$)"),
}
_OPS = {"<=": r"\leq", "<": "<", ">": ">", ">=": r"\geq"}


# --------------------------------------------------------------------------------------
# Figs. 4 and 5
# --------------------------------------------------------------------------------------

def objective_sweep(fig, x, f_exact, f_moreau, xlabel: str, title: str = "", moreau_label: str = "time-stepping"):
    """f (eq. 11) along a parameter sweep: exact solver (line) and time-stepping (markers),
    log-log, and below it the relative difference of the time-stepping value."""
    x, f_exact, f_moreau = (np.asarray(a, dtype=float) for a in (x, f_exact, f_moreau))
    ax_f, ax_d = fig.subplots(2, 1, sharex=True, height_ratios=[3, 1])
    ax_f.loglog(x, f_exact, color="k", label="exact solver")
    ax_f.loglog(x, f_moreau, linestyle="none", marker="o", markersize=4, markerfacecolor="none",
                color="tab:blue", label=moreau_label)
    ax_f.set_ylabel(r"$f = 1 / (c\,\bar v^2)$")
    ax_f.legend(loc="best", fontsize="small")
    ax_f.grid(True, which="major", linewidth=0.4, alpha=0.5)
    with np.errstate(divide="ignore", invalid="ignore"):
        rel = np.abs(f_moreau / f_exact - 1.0)
    ax_d.loglog(x, rel, linestyle="none", marker="o", markersize=3, color="tab:blue")
    ax_d.set_title(rf"relative difference of $f$: {moreau_label} ($f_{{\mathrm{{ts}}}}$) against the exact solver "
                   rf"($f_{{\mathrm{{exact}}}}$)", fontsize="small")
    ax_d.set_ylabel(r"$|f_{\mathrm{ts}} / f_{\mathrm{exact}} - 1|$")
    ax_d.set_xlabel(xlabel)
    ax_d.grid(True, which="major", linewidth=0.4, alpha=0.5)
    if title:
        fig.suptitle(title, fontsize="medium")
    return fig


def _sweep_figure(result, swept: str, fixed: str, xlabel: str, fixed_label: str):
    from matplotlib.figure import Figure

    d, a = result["datasets"], result["attrs"]
    title = (rf"polynomial profile, {fixed_label} = {d[fixed][0]:g}; time-stepping: Moreau, "
             rf"$h = \Delta t / {a['moreau_steps_per_period']}$")
    fig = Figure(figsize=(6.4, 5.6), layout="constrained")
    return objective_sweep(fig, d[swept], d["f_exact"], d["f_moreau"], xlabel, title)


def figure_04(result):
    """Fig. 4: f against dt (results/classification/fig04.h5)."""
    return _sweep_figure(result, "dt", "dy", r"$\Delta t$", r"$\Delta y$")


def figure_05(result):
    """Fig. 5: f against dy (results/classification/fig05.h5)."""
    return _sweep_figure(result, "dy", "dt", r"$\Delta y$", r"$\Delta t$")


# --------------------------------------------------------------------------------------
# Fig. 6
# --------------------------------------------------------------------------------------

#: Shading of the intervals in which the mass slides back (x' < 0), Fig. 6.
SLIDING_BACK = {"color": "tab:red", "alpha": 0.15, "linewidth": 0}


def fourier_optimum(fig, d: dict, a: dict):
    """Fig. 6: optimised Fourier profile against its start and the best three-phase profile
    (y, y', y'' over one period, left; the actuator bounds dash-dotted), the steady
    displacement x of the mass relative to the table beside the table's y under both (right,
    top and middle: x flat where the mass sticks, falling where it slides back, x' < 0,
    shaded) and f per optimiser iteration (right, bottom).

    ``d`` holds the datasets of ``results/classification/fig06.h5`` plus ``<name>_motion_x``
    (x of the mass relative to the table, for ``fourier`` and ``three_phase``); ``a`` its
    attributes."""
    from matplotlib.lines import Line2D
    from matplotlib.patches import Patch

    axes = fig.subplots(3, 2, gridspec_kw={"width_ratios": [1.15, 1]})
    styles = (("fourier", "optimised Fourier", {"color": "k"}),
              ("start", "start (polynomial, 12 harmonics)", {"color": "0.55", "linestyle": ":"}),
              ("three_phase", "best three-phase", {"color": "tab:red", "linestyle": "--"}))
    labels = (("y", "$y$"), ("yd", "$y'$"), ("ydd", "$y''$"))
    for ax, (key, ylabel) in zip(axes[:, 0], labels):
        for name, label, style in styles:
            ax.plot(d["t"], d[f"{name}_{key}"], label=label, linewidth=1.0, **style)
        ax.set_ylabel(ylabel)
    bound_style = {"color": "0.3", "linewidth": 0.6, "linestyle": "-."}
    for ax, bound in ((axes[1, 0], a["yd_max"]), (axes[2, 0], a["ydd_max"])):
        for sign in (1, -1):
            ax.axhline(sign * bound, **bound_style)
    bounds = Line2D([], [], **bound_style, label=r"actuator bounds $\pm y'_{\max}$, $\pm y''_{\max}$")
    axes[0, 0].legend(handles=axes[0, 0].get_lines() + [bounds], loc="lower left", bbox_to_anchor=(0.0, 1.02),
                      ncols=2, fontsize="x-small", frameon=False, borderaxespad=0.0)
    axes[2, 0].set_xlabel("$t$")
    for ax, name, title in ((axes[0, 1], "fourier", "optimised Fourier"),
                            (axes[1, 1], "three_phase", "best three-phase")):
        t, v = d[f"{name}_motion_t"], d[f"{name}_motion_v"]
        ax.fill_between(t, 0.0, 1.0, where=v < 0.0, transform=ax.get_xaxis_transform(), **SLIDING_BACK)
        ax.plot(t, d[f"{name}_motion_y"], color="0.55", linewidth=1.0, label="$y$ (table)")
        ax.plot(t, d[f"{name}_motion_x"], color="k", linewidth=1.2, label="$x$ (mass, relative to the table)")
        ax.set_ylabel("displacement")
        ax.set_title(f"steady motion under the {title} profile", fontsize="small")
        ax.set_xlim(t[0], t[-1])
        ax.legend(handles=ax.get_lines() + [Patch(**SLIDING_BACK, label="mass slides back ($x' < 0$)")],
                  loc="upper left", fontsize="x-small", frameon=False)
    axes[1, 1].set_xlabel("$t$")
    hist = axes[2, 1]
    hist.semilogy(np.arange(d["history_f"].size), d["history_f"], color="k", marker=".", markersize=3,
                  linewidth=0.8, label="Fourier (SQP iterates)")
    hist.axhline(a["three_phase_f"], color="tab:red", linestyle="--", linewidth=1.0, label="best three-phase")
    hist.set_xlabel("iteration")
    hist.set_ylabel("$f$")
    hist.legend(loc="upper right", fontsize="x-small")
    fig.suptitle(rf"$\Delta t$ = {a['dt']:g}, $\Delta y$ = {a['dy']:g}, $|y'| \leq$ {a['yd_max']:g}, "
                 rf"$|y''| \leq$ {a['ydd_max']:g}: Fourier $f$ = {a['fourier_f']:.3g}, three-phase "
                 rf"($y_2''$ = {a['three_phase_y2']:.4g}, $y_3''$ = {a['three_phase_y3']:.4g}) $f$ = "
                 rf"{a['three_phase_f']:.3g}; paper $f$ = {a['paper_f']:g}", fontsize="small")
    return fig


def figure_06(result, mass_displacement: dict):
    """Fig. 6 from results/classification/fig06.h5 and ``mass_displacement``: profile name
    (``fourier``, ``three_phase``) -> x of the mass relative to the table at ``<name>_motion_t``."""
    from matplotlib.figure import Figure

    datasets = dict(result["datasets"])
    datasets.update({f"{name}_motion_x": x for name, x in mass_displacement.items()})
    fig = Figure(figsize=(11.0, 7.6), layout="constrained")
    return fourier_optimum(fig, datasets, result["attrs"])


# --------------------------------------------------------------------------------------
# Fig. 8
# --------------------------------------------------------------------------------------

def _condition_text(condition) -> str:
    def term(x):
        if isinstance(x, str):
            return QUANTITIES.get(x, (rf"\mathrm{{{x}}}", None))[0]
        return f"{x:g}"
    return f"${term(condition.lhs)} {_OPS[condition.op]} {term(condition.rhs)}$"


def tree_layout(tree) -> dict[str, tuple[float, int]]:
    """(x, depth) of every node: leaves at x = 0, 1, ... in depth-first order ("yes" first),
    decisions centred over their children."""
    children: dict[str, list[str]] = {}
    for parent, child, _ in tree.edges():
        children.setdefault(parent, []).append(child)
    pos: dict[str, tuple[float, int]] = {}
    next_leaf = [0]

    def place(node, depth):
        kids = children.get(node, [])
        for kid in kids:
            place(kid, depth + 1)
        if kids:
            x = float(np.mean([pos[k][0] for k in kids]))
        else:
            x, next_leaf[0] = float(next_leaf[0]), next_leaf[0] + 1
        pos[node] = (x, depth)

    place(tree.root, 0)
    return pos


def decision_tree(fig, tree=DECISION_TREE, width: int = 24):
    """Fig. 8: the flow chart of the a-priori case decision, drawn from ``tree``.

    Every node of ``tree.nodes()`` becomes a box (decisions: the question and its
    condition; leaves: the case of Table 1 in its map colour), every edge of
    ``tree.edges()`` an arrow labelled yes / no; the quantities the conditions
    use are explained below the chart.
    """
    ax = fig.add_subplot()
    ax.set_axis_off()
    pos = tree_layout(tree)
    boxes = {}
    for node_id, attrs in tree.nodes():
        x, depth = pos[node_id]
        node = tree[node_id]
        if isinstance(node, Decision):
            text = textwrap.fill(attrs["label"], width) + "\n" + _condition_text(node.condition)
            style = {"boxstyle": "round,pad=0.4", "facecolor": "white", "edgecolor": "k"}
        else:
            text = f"case {attrs['case']}\n" + textwrap.fill(CASE_LABELS[attrs["case"]], width // 2)
            # The map colour itself (no transparency), so a leaf matches its cells in Figs. 10, 11, 17.
            style = {"boxstyle": "round4,pad=0.4", "facecolor": CASE_COLORS[attrs["case"]], "edgecolor": "k"}
        boxes[node_id] = ax.text(x, -depth, text, ha="center", va="center", fontsize=8, bbox=style, zorder=3)
    for parent, child, label in tree.edges():
        (x0, d0), (x1, d1) = pos[parent], pos[child]
        ax.annotate("", xy=(x1, -d1), xytext=(x0, -d0),
                    arrowprops={"arrowstyle": "-|>", "color": "0.25", "linewidth": 1.0,
                                "patchA": boxes[parent].get_bbox_patch(),
                                "patchB": boxes[child].get_bbox_patch(), "shrinkA": 2, "shrinkB": 2})
        ax.text(0.5 * (x0 + x1), -0.5 * (d0 + d1), label, ha="center", va="center", fontsize=8,
                # Not green / red: those are the colours of cases 1 and 2.
                color="k" if label == "yes" else "0.4", fontweight="bold" if label == "yes" else "normal", zorder=4,
                bbox={"boxstyle": "round,pad=0.15", "facecolor": "white", "edgecolor": "none"})
    xs = [p[0] for p in pos.values()]
    depth = max(p[1] for p in pos.values())
    ax.set_xlim(min(xs) - 0.6, max(xs) + 0.6)
    ax.set_ylim(-depth - 0.6, 0.5)
    used = []
    for node_id, attrs in tree.nodes():
        if attrs["kind"] == "decision":
            cond = tree[node_id].condition
            used += [t for t in (cond.lhs, cond.rhs) if isinstance(t, str) and t not in used]
    notes = [QUANTITIES[q][1] for q in used if q in QUANTITIES and QUANTITIES[q][1]]
    fig.text(0.02, 0.02, "\n".join(notes), fontsize=8, va="bottom", ha="left")
    fig.suptitle("A-priori classification of the steady state (Table 1); ties $|y''| = 1$ stick",
                 fontsize="medium")
    return fig


def figure_08(tree=DECISION_TREE):
    """Fig. 8 from the decision tree itself (no result file: the tree is code)."""
    from matplotlib.figure import Figure

    return decision_tree(Figure(figsize=(9.5, 6.4), layout="constrained"), tree)


# --------------------------------------------------------------------------------------
# Figs. 10 and 11 (and panels A, B of Fig. 17)
# --------------------------------------------------------------------------------------

def mean_velocity_zero_line(ax, y2, y3, vbar) -> Line2D:
    """The line vbar = 0 (dashed) over a map; returns its legend handle."""
    ax.contour(y2, y3, np.ma.masked_invalid(np.asarray(vbar, dtype=float).T), levels=[0.0], colors="k",
               linestyles="--", linewidths=0.9)
    return Line2D([], [], color="k", linestyle="--", linewidth=0.9, label=r"$\bar v = 0$")


def objective_panel(ax, y2, y3, f, vbar, f_max: float):
    """f (eq. 11) over (y2'', y3''), values >= ``f_max`` shown as ``f_max`` (as the paper does
    for clarity), case 0 (no physical profile, f NaN) in its case colour.  f = 1/(c vbar^2) is
    blind to the direction of motion, so the cells with vbar < 0 are hatched and the line
    vbar = 0 is drawn.  Returns the legend handles of the line and the hatch."""
    f = np.asarray(f, dtype=float)
    with np.errstate(invalid="ignore"):
        shown = np.where(np.isnan(f), np.nan, np.minimum(f, f_max))
    cmap = colormaps["viridis"].with_extremes(bad=CASE_COLORS[0])
    mesh = map_mesh(ax, y2, y3, shown, cmap=cmap, vmin=0.0, vmax=f_max)
    ax.figure.colorbar(mesh, ax=ax, label=rf"$f$ (values $\geq$ {f_max:g} shown as {f_max:g})")
    handles = [mean_velocity_zero_line(ax, y2, y3, vbar)]
    with np.errstate(invalid="ignore"):
        backward = np.asarray(vbar, dtype=float) < 0.0
    if backward.any():
        handles.append(hatch_cells(ax, y2, y3, backward, r"$\bar v < 0$ ($f$ does not see the direction)"))
    return handles


def objective_map(fig, y2, y3, f, case, vbar, f_max: float, title: str = ""):
    """Figs. 10 and 11: f (eq. 11) over (y2'', y3'') (:func:`objective_panel`) beside the case
    of Table 1, with the line vbar = 0 on both.  Arrays are indexed [i_y2, i_y3]."""
    ax_f, ax_c = fig.subplots(1, 2, sharex=True, sharey=True)
    handles = objective_panel(ax_f, y2, y3, f, vbar, f_max)
    ax_f.set_title(r"objective $f = 1 / (c\,\bar v^2)$", fontsize="small")
    case_map(ax_c, y2, y3, case)
    mean_velocity_zero_line(ax_c, y2, y3, vbar)
    ax_c.set_title("case (Table 1)", fontsize="small")
    ax_c.label_outer()
    ax_f.legend(handles=handles, loc="upper right", fontsize="x-small", framealpha=0.9)
    if title:
        fig.suptitle(title, fontsize="medium")
    return fig


def figure_map(result, f_max: float):
    """Fig. 10 or 11 from results/classification/fig10.h5 or fig11.h5."""
    from matplotlib.figure import Figure

    d, a = result["datasets"], result["attrs"]
    fig = Figure(figsize=(11.0, 4.8), layout="constrained")
    return objective_map(fig, d["y2"], d["y3"], d["f"], d["case"], d["vbar"], f_max,
                         setting_title(dy=a["dy"], dt=a["dt"]))
