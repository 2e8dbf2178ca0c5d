"""Plot functions for the paper's figures.

Each function draws data it is given onto a matplotlib ``Axes`` (or a
``Figure`` for multi-panel plots) and returns the figure.  They compute no
physics and write no files: the workflow's compute rules produce the data,
:func:`selfalign.stages.common.save_figure` writes the image, so restyling a
figure never reruns a simulation.  Only the object-oriented matplotlib API
is used (no pyplot state), so they run headless.  Figure builders draw at print
size under the figure standard (:mod:`selfalign.plots.style`).
"""

from __future__ import annotations

import numpy as np

from .style import OKABE_ITO, new_figure, panel_letters, styled

#: Shading of the positive and negative lobes of an equal-area condition.
POSITIVE = OKABE_ITO["blue"]
NEGATIVE = OKABE_ITO["vermillion"]
LOBE_ALPHA = 0.3
#: Colour of the zero lines and of the dotted time marks.
ZERO_COLOR = "0.4"
MARK_COLOR = "0.5"


def profile_sketch(fig, t, y, yd, ydd, marks: dict[str, float], values=()):
    """Fig. 7: table position, velocity and acceleration in three panels sharing the time axis.

    The shaded lobes are the periodicity conditions of Sect. 4.4.3: in the
    y' panel the areas above and below zero are equal (item 5, the position
    returns), in the y'' panel likewise (item 6, the velocity returns); one legend
    under the panels names them.  ``marks`` maps labels to times drawn as dotted
    lines in every panel and named on the top axis (t0..t3 of Fig. 7).  ``values``
    lists (panel, label, t, value) points to label, ``panel`` one of "y", "yd", "ydd"
    (the quantities the Appendix reads off Fig. 7: y_ini, y'_ini, the acceleration
    levels).  ``ydd`` is drawn as a step function: each sample's value holds until the
    next sample, so samples must include the switch times.
    """
    t, y, yd, ydd = (np.asarray(a, dtype=float) for a in (t, y, yd, ydd))
    ax_y, ax_v, ax_a = fig.subplots(3, 1, sharex=True)

    ax_y.plot(t, y, color="k", label="$y$")
    ax_y.set_ylabel("$y$")

    ax_v.plot(t, yd, color="k", label="$y'$")
    ax_v.set_ylabel("$y'$")
    ax_a.plot(t, ydd, color="k", drawstyle="steps-post", label="$y''$")
    ax_a.set_ylabel("$y''$")
    ax_a.set_xlabel("$t$")
    for ax, values_, step in ((ax_v, yd, None), (ax_a, ydd, "post")):
        lobes = dict(interpolate=step is None, step=step, alpha=LOBE_ALPHA, linewidth=0)
        ax.fill_between(t, values_, 0.0, where=values_ >= 0.0, color=POSITIVE, label="area above 0", **lobes)
        ax.fill_between(t, values_, 0.0, where=values_ <= 0.0, color=NEGATIVE, label="area below 0", **lobes)
        ax.axhline(0.0, color=ZERO_COLOR, linewidth=0.6)
    fig.legend(handles=ax_v.collections[:2], loc="outside lower center", ncols=2,
               title="equal areas: b, $y$ periodic (item 5); c, $y'$ periodic (item 6)")
    mark_times((ax_y, ax_v, ax_a), marks)
    panels = {"y": ax_y, "yd": ax_v, "ydd": ax_a}
    for panel, label, time, value in values:
        label_value(panels[panel], label, time, value)
    ax_a.set_xlim(t[0], t[-1])
    panel_letters((ax_y, ax_v, ax_a))
    return fig


def label_value(ax, label: str, time: float, value: float):
    """A dot at (time, value) labelled on its side towards zero (below a positive value,
    above a negative one), to the right of it at the left edge of the data, else centred."""
    ax.plot([time], [value], "o", color="k", markersize=3.5, clip_on=False)
    at_start = time <= ax.dataLim.x0 + 1e-9 * ax.dataLim.width  # rounding of the first sample
    ax.annotate(label, (time, value), xytext=(5 if at_start else 0, -4 if value > 0 else 4),
                textcoords="offset points", ha="left" if at_start else "center",
                va="top" if value > 0 else "bottom")


def mark_times(axes, marks: dict[str, float]):
    """Dotted vertical lines at ``marks`` (label -> time) in every one of ``axes``, named by the
    ticks of a secondary time axis on top of the first (so a panel letter stays clear of them);
    returns that axis."""
    for time in marks.values():
        for ax in axes:
            ax.axvline(time, color=MARK_COLOR, linestyle=":", linewidth=0.8)
    top = axes[0].secondary_xaxis("top")
    top.set_xticks(list(marks.values()), list(marks))
    top.tick_params(length=0, pad=2)
    return top


@styled
def figure_07(result: dict):
    """Fig. 7, the three-phase profile sketch, from a trajectory result (:func:`read_h5` layout),
    one column wide; the caption gives the profile's parameters."""
    d, a = result["datasets"], result["attrs"]
    if a.get("kind") != "three_phase":
        raise ValueError(f"figure 7 needs a three_phase profile, got kind {a.get('kind')!r}")
    marks = {"$t_0$": 0.0, "$t_1$": a["t1"], "$t_{y'=0,1}$": a["t_top"], "$t_2$": a["t2"],
             "$t_{y'=0,2}$": a["t_bottom"], "$t_3$": a["t3"]}
    values = [("y", r"$y_{\mathrm{ini}}$", 0.0, a["y_ini"]), ("yd", r"$y'_{\mathrm{ini}}$", 0.0, a["yd_ini"]),
              ("ydd", "$-y_2''$", 0.5 * (a["t1"] + a["t2"]), -a["y2"]),
              ("ydd", "$y_3''$", 0.5 * (a["t2"] + a["t3"]), a["y3"])]
    fig = new_figure("single", 120)
    return profile_sketch(fig, d["t"], d["y"], d["yd"], d["ydd"], marks, values)
