"""Plot functions for the paper's figures.

Each function draws data it is given onto a matplotlib ``Axes`` (or a
``Figure`` for multi-panel plots) and returns the figure.  They compute no
physics and write no files: the workflow's compute rules produce the data,
:func:`selfalign.stages.common.save_figure` writes the image, so restyling a
figure never reruns a simulation.  Only the object-oriented matplotlib API
is used (no pyplot state), so they run headless.
"""

from __future__ import annotations

import numpy as np

#: Shading of the positive and negative lobes of an equal-area condition.
POSITIVE = "tab:blue"
NEGATIVE = "tab:red"
LOBE_ALPHA = 0.3


def profile_sketch(fig, t, y, yd, ydd, marks: dict[str, float], values=(), title: str = ""):
    """Fig. 7: table position, velocity and acceleration in three panels sharing the time axis.

    The shaded lobes are the periodicity conditions of Sect. 4.4.3: in the
    y' panel the areas above and below zero are equal (item 5, the position
    returns), in the y'' panel likewise (item 6, the velocity returns).
    ``marks`` maps labels to times drawn as dotted lines in every panel
    (t0..t3 of Fig. 7).  ``values`` lists (panel, label, t, value) points to label,
    ``panel`` one of "y", "yd", "ydd" (the quantities the Appendix reads off Fig. 7:
    y_ini, y'_ini, the acceleration levels).  ``ydd`` is drawn as a step function: each sample's
    value holds until the next sample, so samples must include the switch
    times.
    """
    t, y, yd, ydd = (np.asarray(a, dtype=float) for a in (t, y, yd, ydd))
    ax_y, ax_v, ax_a = fig.subplots(3, 1, sharex=True)
    if title:
        fig.suptitle(title)

    ax_y.plot(t, y, color="k", label="$y$")
    ax_y.set_ylabel("$y$")

    ax_v.plot(t, yd, color="k", label="$y'$")
    ax_v.fill_between(t, yd, 0.0, where=yd >= 0.0, interpolate=True, color=POSITIVE,
                      alpha=LOBE_ALPHA, linewidth=0, label=r"$\int y'\,dt$ above 0")
    ax_v.fill_between(t, yd, 0.0, where=yd <= 0.0, interpolate=True, color=NEGATIVE,
                      alpha=LOBE_ALPHA, linewidth=0, label=r"$\int y'\,dt$ below 0")
    ax_v.set_ylabel("$y'$")

    ax_a.plot(t, ydd, color="k", drawstyle="steps-post", label="$y''$")
    ax_a.fill_between(t, ydd, 0.0, where=ydd >= 0.0, step="post", color=POSITIVE,
                      alpha=LOBE_ALPHA, linewidth=0, label=r"$\int y''\,dt$ above 0")
    ax_a.fill_between(t, ydd, 0.0, where=ydd <= 0.0, step="post", color=NEGATIVE,
                      alpha=LOBE_ALPHA, linewidth=0, label=r"$\int y''\,dt$ below 0")
    ax_a.set_ylabel("$y''$")
    ax_a.set_xlabel("$t$")

    # The legends go where the lobes leave room: below zero before the first
    # zero crossing of y', below zero after the last switch for y''.
    for ax, condition, where in ((ax_v, "equal areas: $y$ periodic (item 5)", "lower left"),
                                 (ax_a, "equal areas: $y'$ periodic (item 6)", "lower right")):
        ax.axhline(0.0, color="0.4", linewidth=0.8)
        ax.legend(handles=ax.collections[:2], loc=where, fontsize="small", title=condition,
                  title_fontsize="small", frameon=False)
    mark_times((ax_y, ax_v, ax_a), marks)
    panels = {"y": ax_y, "yd": ax_v, "ydd": ax_a}
    for panel, label, time, value in values:
        label_value(panels[panel], label, time, value)
    ax_a.set_xlim(t[0], t[-1])
    return fig


def label_value(ax, label: str, time: float, value: float):
    """A dot at (time, value) labelled on its side towards zero (below a positive value,
    above a negative one), to the right of it at the left edge of the data, else centred."""
    ax.plot([time], [value], "o", color="k", markersize=4, clip_on=False)
    at_start = time <= ax.dataLim.x0
    ax.annotate(label, (time, value), xytext=(6 if at_start else 0, -5 if value > 0 else 5),
                textcoords="offset points", ha="left" if at_start else "center",
                va="top" if value > 0 else "bottom")


def mark_times(axes, marks: dict[str, float]):
    """Dotted vertical lines at ``marks`` (label -> time) in every one of ``axes``, labelled
    above the first."""
    for label, time in marks.items():
        for ax in axes:
            ax.axvline(time, color="0.5", linestyle=":", linewidth=1.0)
        axes[0].text(time, 1.02, label, transform=axes[0].get_xaxis_transform(), ha="center", va="bottom")


def figure_07(result: dict):
    """Fig. 7, the three-phase profile sketch, from a trajectory result (:func:`read_h5` layout)."""
    from matplotlib.figure import Figure

    d, a = result["datasets"], result["attrs"]
    if a.get("kind") != "three_phase":
        raise ValueError(f"figure 7 needs a three_phase profile, got kind {a.get('kind')!r}")
    marks = {"$t_0$": 0.0, "$t_1$": a["t1"], "$t_{y'=0,1}$": a["t_top"], "$t_2$": a["t2"],
             "$t_{y'=0,2}$": a["t_bottom"], "$t_3$": a["t3"]}
    values = [("y", r"$y_{\mathrm{ini}}$", 0.0, a["y_ini"]), ("yd", r"$y'_{\mathrm{ini}}$", 0.0, a["yd_ini"]),
              ("ydd", "$-y_2''$", 0.5 * (a["t1"] + a["t2"]), -a["y2"]),
              ("ydd", "$y_3''$", 0.5 * (a["t2"] + a["t3"]), a["y3"])]
    title = (rf"$\Delta t$ = {a['dt']:g}, $\Delta y$ = {a['dy']:g}, "
             rf"$y_2''$ = {a['y2']:g}, $y_3''$ = {a['y3']:g}")
    fig = Figure(figsize=(6.4, 6.4), layout="constrained")
    return profile_sketch(fig, d["t"], d["y"], d["yd"], d["ydd"], marks, values, title=title)
