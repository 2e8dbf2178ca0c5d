"""Annotations drawn onto figures that other modules build, e.g. the lengths the paper defines
on Fig. 15 (Sect. 7.1), added to :func:`selfalign.plots.accumulation.figure_15`'s figure.

As everywhere in :mod:`selfalign.plots`: given data only, no physics, no files, the
object-oriented matplotlib API only, and the figure standard of :mod:`selfalign.plots.style`.
"""

from __future__ import annotations

from .style import OKABE_ITO, SMALL_FONT_SIZE

#: Colour of the dimension arrows of Fig. 15 (Okabe-Ito blue).
DIMENSION_COLOR = OKABE_ITO["blue"]


def dimension(ax, start: float, end: float, level: float, label: str, color: str = DIMENSION_COLOR):
    """A double arrow from x = ``start`` to ``end`` at height ``level`` (data coordinates)
    with ``label`` centred above it, like a dimension in a technical drawing.

    Parameters
    ----------
    ax : matplotlib.axes.Axes
    start, end, level : float
        Ends and height of the arrow, in data coordinates.
    label : str
        Text above the arrow.
    color : str
        Colour of arrow and text.

    Returns
    -------
    matplotlib.text.Text
        The label.

    Examples
    --------
    >>> from selfalign.plots.style import new_figure
    >>> ax = new_figure("single", 40).subplots()
    >>> dimension(ax, 0.0, 1.0, 0.5, "$w$").get_position()
    (0.5, 0.5)
    """
    ax.annotate("", xy=(end, level), xytext=(start, level),
                arrowprops={"arrowstyle": "<|-|>", "color": color, "linewidth": 0.8,
                            "shrinkA": 0, "shrinkB": 0, "mutation_scale": 6})
    return ax.text(0.5 * (start + end), level, label, ha="center", va="bottom", fontsize=SMALL_FONT_SIZE,
                   color=color)


def overshoot_dimensions(ax, x_mu: float, overshoot_min: float, overshoot_max: float, dx_d: float):
    """Fig. 15: Delta x_overshoot,min and Delta x_overshoot,max (from x_mu to the nearest and
    the farthest end position) and Delta x_d on both sides of x_d = x_mu +
    Delta x_overshoot,min + Delta x_d (eq. 39), as dimensions in a band added below the data.

    Parameters
    ----------
    ax : matplotlib.axes.Axes
        The axes of Fig. 15.
    x_mu, overshoot_min, overshoot_max, dx_d : float
        Start of the zone, the nearest and farthest overshoot and Delta x_d (eq. 39).

    Returns
    -------
    matplotlib.figure.Figure
        The figure of ``ax``.

    Examples
    --------
    >>> from selfalign.plots.style import new_figure
    >>> ax = new_figure("single", 60).subplots()
    >>> _ = ax.set_ylim(0.0, 1.0)
    >>> _ = overshoot_dimensions(ax, 0.0, 0.02, 0.03, 0.005)
    >>> len([t for t in ax.texts if t.get_text()]), [round(float(v), 2) for v in ax.get_ylim()]
    (4, [-0.38, 1.0])
    """
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
