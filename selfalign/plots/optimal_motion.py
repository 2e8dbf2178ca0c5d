"""Fig. 6 revisited (docs/explanation/fig6-revisited.md): the part's mean velocity under the paper's Fourier
optimum, its three-phase family and the fastest table motion, against the limits and the Fourier order.

The plot functions draw the data they are given onto an Axes; :func:`figure_fig06_revisited` builds the
figure from ``results/optimal_motion/fig06_revisited.h5`` in :func:`selfalign.io.hdf5.read_h5` layout
(written by :mod:`selfalign.stages.optimal_motion`).  No physics here.
"""

from __future__ import annotations

import numpy as np
from matplotlib.figure import Figure
from matplotlib.ticker import NullLocator

from .style import OKABE_ITO, SMALL_FONT_SIZE, new_figure, panel_letters, styled

#: Colour of each answer; the Fourier orders in the order given (4, 8, 12 in the workflow).
OPTIMUM_COLOR, BOUND_COLOR, THREE_PHASE_COLOR = "k", "0.45", OKABE_ITO["vermillion"]
ORDER_COLORS = tuple(OKABE_ITO[name] for name in ("sky blue", "blue", "reddish purple", "bluish green", "orange"))
#: Ticks of a limit's axis are at least this factor apart, so their labels do not touch at print size.
TICK_RATIO = 1.8
#: vbar below this is not drawn (log axis; a truncation that hardly moves the part).
VBAR_FLOOR = 0.1


def _shown(values) -> np.ndarray:
    """``values`` with everything below :data:`VBAR_FLOOR` (and NaN) left out of a log axis."""
    values = np.asarray(values, dtype=float)
    return np.where(values >= VBAR_FLOOR, values, np.nan)


def vbar_against_limit(ax, x, optimal, bound, three_phase, orders, fourier, truncated, *, marked: float,
                       xlabel: str):
    """vbar against one limit ``x`` (log-log; ticks at ``marked`` and at the values of ``x`` at least
    :data:`TICK_RATIO` times from every other tick, smallest first):
    the fastest motion (black), the bound v* (grey, dashed), the best three-phase profile (red), and per Fourier
    order N of ``orders`` the SQP optimum (``fourier[i]``, circles where it ran) and the fastest motion
    truncated to N harmonics (``truncated[i]``, dotted), both in the order's colour; a vertical line at Fig.
    6's value ``marked``.  Returns ``ax``."""
    ax.plot(x, bound, "--", color=BOUND_COLOR, label=r"bound $v^*$ ($|y''|$ limit alone)")
    ax.plot(x, optimal, "-", color=OPTIMUM_COLOR, marker=".", label="fastest motion (optimal_profile)")
    ax.plot(x, _shown(three_phase), "-", color=THREE_PHASE_COLOR, marker=".", label="best three-phase (Sect. 4.4.3)")
    for i, order in enumerate(np.asarray(orders).tolist()):
        color = ORDER_COLORS[i % len(ORDER_COLORS)]
        ax.plot(x, _shown(truncated[i]), ":", color=color, linewidth=1.2,
                label=f"fastest motion, {order} harmonics, scaled")
        ax.plot(x, _shown(fourier[i]), "o", color=color, markersize=4, label=f"Fourier SQP, order {order}")
    ax.axvline(marked, color="0.7", linewidth=0.8, zorder=0, label="Fig. 6's limit")
    ax.set_xscale("log")
    ax.set_yscale("log")
    ticks = [float(marked)]
    for value in np.asarray(x, dtype=float).tolist():
        if all(max(value, tick) >= TICK_RATIO * min(value, tick) for tick in ticks):
            ticks.append(value)
    ticks.sort()
    ax.set_xticks(ticks, [f"{value:g}" for value in ticks])
    ax.xaxis.set_minor_locator(NullLocator())
    ax.set_xlabel(xlabel)
    ax.set_ylabel(r"$\bar v$ (eq. 10)")
    ax.grid(True, which="major", linewidth=0.4, alpha=0.5)
    return ax


def vbar_against_order(ax, orders, vbar, scale, sqp_orders, sqp_vbar, optimal: float, three_phase: float):
    """vbar at Fig. 6's limits against the Fourier order (log x): the fastest motion truncated to N harmonics
    and scaled into the limits (squares, each labelled with its scale), the SQP optimum of each order
    (circles), and the fastest motion and the best three-phase profile as levels.  Returns ``ax``."""
    ax.axhline(optimal, color=OPTIMUM_COLOR, label="fastest motion (optimal_profile)")
    ax.axhline(three_phase, color=THREE_PHASE_COLOR, label="best three-phase (Sect. 4.4.3)")
    ax.plot(orders, _shown(vbar), "s:", color="0.3", label="fastest motion, N harmonics, scaled")
    for n, v, s in zip(np.asarray(orders).tolist(), np.asarray(vbar).tolist(), np.asarray(scale).tolist()):
        if v >= VBAR_FLOOR:
            ax.annotate(rf"$\times${s:.2f}", (n, v), textcoords="offset points", xytext=(0, -10), ha="center",
                        fontsize=SMALL_FONT_SIZE)
    for i, (n, v) in enumerate(zip(np.asarray(sqp_orders).tolist(), np.asarray(sqp_vbar).tolist())):
        ax.plot([n], [v], "o", color=ORDER_COLORS[i % len(ORDER_COLORS)], markersize=4, label=f"Fourier SQP, order {n}")
    ax.set_xscale("log")
    ax.set_xticks(np.asarray(orders).tolist(), [str(n) for n in np.asarray(orders).tolist()])
    ax.minorticks_off()
    ax.set_ylim(0.0, 1.08 * optimal)
    ax.set_xlabel("Fourier order N (harmonics)")
    ax.set_ylabel(r"$\bar v$ (eq. 10)")
    ax.grid(True, which="major", linewidth=0.4, alpha=0.5)
    return ax


@styled
def figure_fig06_revisited(result: dict) -> Figure:
    """The figure from ``fig06_revisited.h5``: vbar against the acceleration limit (a) and the stroke
    limit (b), the other limits Fig. 6's, and against the Fourier order at Fig. 6's limits (c); the
    legends below the panels.

    Parameters
    ----------
    result : dict
        ``results/optimal_motion/fig06_revisited.h5`` read with :func:`selfalign.io.hdf5.read_h5`.

    Returns
    -------
    matplotlib.figure.Figure
        174 mm wide.
    """
    a = result["attrs"]
    groups = result["groups"]
    fig = new_figure("double", 100.0)
    top, bottom = fig.subfigures(2, 1, height_ratios=(1.0, 0.36))
    ax_a, ax_s, ax_n = top.subplots(1, 3)
    key_limits, key_order = bottom.subplots(1, 2, width_ratios=(1.9, 1.0))
    for ax, name in ((ax_a, "accel_max"), (ax_s, "stroke_max")):
        d = groups[name.split("_")[0] + "_sweep"]["datasets"]
        label = r"acceleration limit $a = \max|y''|$" if name == "accel_max" else r"stroke limit $S$"
        vbar_against_limit(ax, d[name], d["vbar_optimal"], d["vbar_bound"], d["vbar_three_phase"], d["orders"],
                           d["vbar_fourier"], d["vbar_truncated"], marked=a[name], xlabel=label)
    c, t = groups["comparison"]["datasets"], groups["truncation"]["datasets"]
    entries = c["entry"].tolist()
    sqp = [i for i, e in enumerate(entries) if e.startswith("fourier_")]
    vbar_against_order(ax_n, t["orders"], t["vbar"], t["scale"], [int(entries[i].split("_")[1]) for i in sqp],
                       c["vbar"][sqp], float(c["vbar"][entries.index("optimal")]),
                       float(c["vbar"][entries.index("three_phase")]))
    for key, ax, columns in ((key_limits, ax_a, 2), (key_order, ax_n, 1)):
        key.axis("off")
        key.legend(handles=[line for line in ax.get_lines() if not line.get_label().startswith("_")],
                   loc="upper center", ncols=columns, borderaxespad=0.0)
    panel_letters([ax_a, ax_s, ax_n])
    return fig
