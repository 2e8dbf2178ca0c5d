"""Plots of the stability and convergence stages (Sect. 6): Fig. 13.

Like :mod:`selfalign.plots.profile`, the functions draw given data with the
object-oriented matplotlib API and compute no physics; :func:`figure_13`
builds the figure from a convergence result (:func:`selfalign.io.hdf5.read_h5`
layout) and :func:`selfalign.stages.common.save_figure` writes it.
"""

from __future__ import annotations

import numpy as np

#: Shading of the intervals where the selected signs differ (V' < 0).
DIFFERENT = "tab:green"
DIFFERENT_ALPHA = 0.15


def convergence_panels(fig, t, v1, v2, V, starts, ends, equal, labels=("$v_1$", "$v_2$"), title=""):
    """Fig. 13: two velocity transients (top) and V = (v1 - v2)^2 / 2 (bottom).

    Intervals where the selected elements of Sign(v1), Sign(v2) agree are
    marked "=" above the V curve, those where they differ "≠" and shaded in
    both panels (Sect. 6.2).
    """
    t, v1, v2, V = (np.asarray(a, dtype=float) for a in (t, v1, v2, V))
    ax_v, ax_V = fig.subplots(2, 1, sharex=True)
    if title:
        fig.suptitle(title)
    ax_v.plot(t, v1, color="tab:blue", label=labels[0])
    ax_v.plot(t, v2, color="tab:red", linestyle="--", label=labels[1])
    ax_v.axhline(0.0, color="0.4", linewidth=0.8)
    ax_v.set_ylabel("$v = x'$")
    ax_v.legend(loc="upper right", frameon=False)

    ax_V.plot(t, V, color="k", label="$V$")
    ax_V.set_ylabel(r"$V = (v_1 - v_2)^2 / 2$")
    ax_V.set_xlabel("$t$")
    ax_V.set_xlim(t[0], t[-1])
    top = float(np.max(V)) if V.size else 1.0
    ax_V.set_ylim(-0.05 * top, 1.2 * top if top > 0 else 1.0)
    for a, b, same in zip(starts, ends, equal):
        if not same:
            for ax in (ax_v, ax_V):
                ax.axvspan(a, b, color=DIFFERENT, alpha=DIFFERENT_ALPHA, linewidth=0)
        ax_V.text(0.5 * (a + b), 1.1 * top, "=" if same else "≠", ha="center", va="center")
    return fig


def figure_13(result: dict):
    """Fig. 13 from a convergence result (:func:`selfalign.analysis.lyapunov.convergence_result`)."""
    from matplotlib.figure import Figure

    d, a = result["datasets"], result["attrs"]
    title = (rf"$\Delta t$ = {a['dt']:g}, $\Delta y$ = {a['dy']:g}, $y_2''$ = {a['y2']:g}, "
             rf"$y_3''$ = {a['y3']:g} (case {a['case']})") if a.get("kind") == "three_phase" else ""
    labels = (rf"$v_1$, $v_{{10}}$ = {a['v10']:g}", rf"$v_2$, $v_{{20}}$ = {a['v20']:g}")
    fig = Figure(figsize=(6.4, 5.6), layout="constrained")
    return convergence_panels(fig, d["t"], d["v1"], d["v2"], d["V"], d["interval_start"], d["interval_end"],
                              d["interval_equal"], labels=labels, title=title)
