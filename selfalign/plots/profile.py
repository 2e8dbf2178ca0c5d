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


def profile_sketch(fig, t, y, yd, ydd, marks: dict[str, float], title: str = ""):
    """Fig. 7: table position, velocity and acceleration in three panels sharing the time axis.

    The shaded lobes are the periodicity conditions of Sect. 4.4.3: in the
    y' panel the areas above and below zero are equal (item 5, the position
    returns), in the y'' panel likewise (item 6, the velocity returns).
    ``marks`` maps labels to times drawn as dotted lines in every panel
    (t0..t3 of Fig. 7).  ``ydd`` is drawn as a step function: each sample's
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
    ax_a.set_xlim(t[0], t[-1])
    return fig


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
    marks = {"$t_0$": 0.0, "$t_1$": a["t1"], "$t_2$": a["t2"], "$t_3$": a["t3"]}
    title = (rf"$\Delta t$ = {a['dt']:g}, $\Delta y$ = {a['dy']:g}, "
             rf"$y_2''$ = {a['y2']:g}, $y_3''$ = {a['y3']:g}")
    fig = Figure(figsize=(6.4, 6.4), layout="constrained")
    return profile_sketch(fig, d["t"], d["y"], d["yd"], d["ydd"], marks, title=title)
