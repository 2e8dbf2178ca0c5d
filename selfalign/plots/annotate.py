"""Annotations drawn onto figures that other modules build, e.g. the lengths the paper defines
on Fig. 15 (Sect. 7.1), added to :func:`selfalign.plots.accumulation.figure_15`'s figure.

As everywhere in :mod:`selfalign.plots`: given data only, no physics, no files, the
object-oriented matplotlib API only.
"""

from __future__ import annotations

#: Colour of the dimension arrows.
DIMENSION_COLOR = "tab:blue"


def dimension(ax, start: float, end: float, level: float, label: str):
    """A double arrow from x = ``start`` to ``end`` at height ``level`` (data coordinates)
    with ``label`` centred above it, like a dimension in a technical drawing."""
    ax.annotate("", xy=(end, level), xytext=(start, level),
                arrowprops={"arrowstyle": "<|-|>", "color": DIMENSION_COLOR, "linewidth": 1.0,
                            "shrinkA": 0, "shrinkB": 0, "mutation_scale": 8})
    ax.text(0.5 * (start + end), level, label, ha="center", va="bottom", fontsize="small", color=DIMENSION_COLOR)


def overshoot_dimensions(ax, x_mu: float, overshoot_min: float, overshoot_max: float, dx_d: float):
    """Fig. 15: Delta x_overshoot,min and Delta x_overshoot,max (from x_mu to the nearest and
    the farthest end position) and Delta x_d on both sides of x_d = x_mu +
    Delta x_overshoot,min + Delta x_d (eq. 39), as dimensions in a band added below the data."""
    low, high = ax.get_ylim()
    step = 0.12 * (high - low)
    ax.set_yticks([tick for tick in ax.get_yticks() if low <= tick <= high])  # no ticks in the band
    ax.set_ylim(low - 3.2 * step, high)
    x_d = x_mu + overshoot_min + dx_d
    dimension(ax, x_mu, x_mu + overshoot_max, low - 3 * step, r"$\Delta x_{\mathrm{overshoot,max}}$")
    dimension(ax, x_mu, x_mu + overshoot_min, low - 2 * step, r"$\Delta x_{\mathrm{overshoot,min}}$")
    for start in (x_d - dx_d, x_d):
        dimension(ax, start, start + dx_d, low - step, r"$\Delta x_d$")
    return ax.figure
