"""Plot functions and figure builders for the simulation figures (Figs. 3, 9, 12) and the
work-precision study (``accuracy_cost``).

As in :mod:`selfalign.plots.profile`, the plot functions draw data they are given onto
matplotlib Axes (or a Figure for multi-panel plots) and return the figure; the
builders ``figure_*`` take results in :func:`selfalign.io.hdf5.read_h5` layout,
pick what is shown and call them.  Nothing here computes physics or writes
files; only the object-oriented matplotlib API is used (headless).
"""

from __future__ import annotations

import numpy as np

from ..io.simulation_result import scene_from_result, trajectory_from_result
from ..model.scene import Scene
from ..solvers.outcomes import EventKind
from .profile import mark_times

#: Colours of the methods in the work-precision figure.
METHOD_STYLE = {
    "moreau": {"color": "tab:blue", "marker": "o", "label": "Moreau time-stepping (step h)"},
    "ivp": {"color": "tab:orange", "marker": "s", "label": "solve_ivp DOP853 (rtol)"},
    "exact": {"color": "k", "label": "exact event-driven (reference)"},
}
#: Colour of the table's quantities, drawn behind the object's.
TABLE_COLOR = "0.55"


def _profile_text(scene: Scene) -> str:
    p = scene.profile.params()
    if p["kind"] == "three_phase":
        return (rf"$\Delta t$ = {p['dt']:g}, $\Delta y$ = {p['dy']:g}, "
                rf"$y_2''$ = {p['y2']:g}, $y_3''$ = {p['y3']:g}")
    if p["kind"] == "polynomial":
        return rf"$\Delta t$ = {p['dt']:g}, $\Delta y$ = {p['dy']:g}, forward fraction {p['forward_fraction']:g}"
    return rf"$\Delta t$ = {p['dt']:g}"


# ---------------------------------------------------------------------------------------
# Fig. 3: object and table
# ---------------------------------------------------------------------------------------

def object_and_table(fig, t, x, y, v, title: str = ""):
    """Fig. 3: x (object, relative to the table) and y (table) against t, and x' below.

    Stick shows as flat stretches of x and x' = 0.
    """
    t, x, y, v = (np.asarray(a, dtype=float) for a in (t, x, y, v))
    ax_x, ax_v = fig.subplots(2, 1, sharex=True, height_ratios=[2, 1])
    if title:
        fig.suptitle(title)
    ax_x.plot(t, y, color=TABLE_COLOR, label="$y$ (table)")
    ax_x.plot(t, x, color="k", label="$x$ (object)")
    ax_x.set_ylabel("position")
    ax_x.legend(loc="upper left", frameon=False)
    ax_v.plot(t, v, color="k", label="$x'$")
    ax_v.axhline(0.0, color="0.4", linewidth=0.8)
    ax_v.set_ylabel("$x'$")
    ax_v.set_xlabel("$t$")
    ax_v.set_xlim(t[0], t[-1])
    return fig


def figure_03(result: dict):
    """Fig. 3 from a simulation result recording x, y and v (the paper uses Moreau time-stepping)."""
    from matplotlib.figure import Figure

    traj = trajectory_from_result(result)
    scene = scene_from_result(result)
    method = {"moreau": "Moreau time-stepping", "exact": "exact solution", "ivp": "solve_ivp"}[traj.method]
    if traj.method == "moreau":
        method += f" (h = {traj.options['h']:.3g}, {traj.options['iteration'].replace('_', '-')} iteration)"
    title = f"{method}\n{scene.profile.params()['kind'].replace('_', '-')} profile: {_profile_text(scene)}"
    fig = Figure(figsize=(6.4, 4.8), layout="constrained")
    return object_and_table(fig, traj.t, traj.x, traj.y, traj.v, title=title)


# ---------------------------------------------------------------------------------------
# Fig. 9: the five cases of Table 1
# ---------------------------------------------------------------------------------------

def case_histories(fig, panels: list[dict]):
    """Fig. 9: one panel per case, x' (black, left axis) and y'' (grey steps, right axis).

    Each entry of ``panels`` holds ``t``, ``v``, ``ydd`` and ``title``; ``ydd``
    is drawn as a step function, so the samples must include the switch times.
    """
    axes = fig.subplots(len(panels), 1)
    for ax, panel in zip(np.atleast_1d(axes), panels):
        t, v, ydd = (np.asarray(panel[k], dtype=float) for k in ("t", "v", "ydd"))
        acc = ax.twinx()
        acc.plot(t, ydd, color=TABLE_COLOR, linewidth=0.8, drawstyle="steps-post", label="$y''$")
        acc.set_ylabel("$y''$", color=TABLE_COLOR)
        acc.tick_params(axis="y", colors=TABLE_COLOR)
        ax.plot(t, v, color="k", label="$x'$")
        ax.axhline(0.0, color="0.4", linewidth=0.8)
        ax.set_zorder(acc.get_zorder() + 1)  # x' in front of the table's y''
        ax.patch.set_visible(False)
        ax.set_ylabel("$x'$")
        ax.set_title(panel["title"], fontsize="medium", loc="left")
        ax.set_xlim(t[0], t[-1])
    np.atleast_1d(axes)[-1].set_xlabel("$t$")
    return fig


def last_periods(traj, dt: float, periods: int) -> np.ndarray:
    """Mask of the samples in the last ``periods`` periods of a recorded run."""
    t = np.asarray(traj.t)
    return t >= t[-1] - periods * dt * (1.0 + 1e-12)


def figure_09(results: list[dict], cases: list[int], labels: dict[int, str], periods: int):
    """Fig. 9: the last ``periods`` periods of each result, titled with its case of Table 1.

    ``cases`` gives the case of each result and ``labels`` the case descriptions
    (:data:`selfalign.analysis.classification.CASE_LABELS`).
    """
    from matplotlib.figure import Figure

    if len(results) != len(cases):
        raise ValueError(f"figure 9 needs one case per result, got {len(cases)} for {len(results)}")
    panels = []
    for result, case in zip(results, cases):
        traj, scene = trajectory_from_result(result), scene_from_result(result)
        keep = last_periods(traj, scene.profile.dt, periods)
        panels.append({"t": traj.t[keep], "v": traj.v[keep], "ydd": traj.ydd[keep],
                       "title": f"Case {case}: {labels[case]}   ({_profile_text(scene)})"})
    fig = Figure(figsize=(7.2, 2.0 * len(panels) + 0.6), layout="constrained")
    return case_histories(fig, panels)


# ---------------------------------------------------------------------------------------
# Fig. 12: one period of a case 1 trajectory
# ---------------------------------------------------------------------------------------

def case1_period(fig, t, ydd, friction, v, x, marks: dict[str, float], title: str = ""):
    """Fig. 12: y'' and the friction force, x' and x over one period, with the times of ``marks``.

    The friction force F_f = -(x'' + y'') lies in Sign(x') (eq. 5): +-1 while the
    mass slips, |F_f| <= 1 while it sticks.
    """
    t, ydd, friction, v, x = (np.asarray(a, dtype=float) for a in (t, ydd, friction, v, x))
    ax_a, ax_v, ax_x = fig.subplots(3, 1, sharex=True)
    if title:
        fig.suptitle(title)
    ax_a.plot(t, ydd, color=TABLE_COLOR, drawstyle="steps-post", label="$y''$ (table)")
    ax_a.plot(t, friction, color="k", drawstyle="steps-post", label="$F_f$ (friction force)")
    for bound in (-1.0, 1.0):
        ax_a.axhline(bound, color="0.4", linestyle="--", linewidth=0.8)
    ax_a.set_ylabel("acceleration")
    ax_a.legend(loc="lower left", fontsize="small", frameon=False)
    ax_v.plot(t, v, color="k", label="$x'$")
    ax_v.axhline(0.0, color="0.4", linewidth=0.8)
    ax_v.set_ylabel("$x'$")
    ax_x.plot(t, x, color="k", label="$x$")
    ax_x.set_ylabel("$x$")
    ax_x.set_xlabel("$t$")
    mark_times((ax_a, ax_v, ax_x), marks)
    ax_x.set_xlim(t[0], t[-1])
    return fig


def figure_12(result: dict):
    """Fig. 12 from a three-phase simulation result recording ydd, friction, v, x and the event log.

    Marks: t0 (start), t1, t2 (profile switches), the stick time t_{x'=0} (the
    first STICK event of the log, eq. 21) and t3 = t0 + dt.
    """
    from matplotlib.figure import Figure

    traj, scene = trajectory_from_result(result), scene_from_result(result)
    p = scene.profile.params()
    if p["kind"] != "three_phase":
        raise ValueError(f"figure 12 needs a three_phase profile, got kind {p['kind']!r}")
    if traj.events is None:
        raise ValueError("figure 12 needs the event log: set record.events in the scene")
    t0 = float(traj.t[0])
    stick = traj.events[traj.events["kind"] == EventKind.STICK]
    marks = {"$t_0$": t0, "$t_1$": t0 + p["t1"], "$t_2$": t0 + p["t2"]}
    if stick.size:
        marks["$t_{x'=0}$"] = float(stick["period"][0] * p["dt"] + stick["tau"][0])
    marks["$t_3$"] = t0 + p["dt"]
    fig = Figure(figsize=(6.4, 6.4), layout="constrained")
    return case1_period(fig, traj.t, traj.ydd, traj.friction, traj.v, traj.x, marks,
                        title=f"Case 1 trajectory: {_profile_text(scene)}")


# ---------------------------------------------------------------------------------------
# Work-precision study
# ---------------------------------------------------------------------------------------

ERROR_KINDS = {
    "err_end_position": ("end-position error", "rounding_level_position"),
    "err_vbar": (r"error of $\bar v$ (last period)", "rounding_level_vbar"),
}


def work_precision(fig, studies: list[dict]):
    """Error against CPU time, log-log: one column per scene, one row per error kind.

    Each study holds ``title``, ``target_error``, ``moreau_order`` and per method
    (``moreau``, ``ivp``) the arrays ``cpu_time``, ``err_end_position``, ``err_vbar``,
    plus ``exact_cpu_time`` (drawn as a vertical line: it is the reference) and
    the rounding levels of both errors: errors below them are drawn at them
    (an exact zero has no logarithm), marked by a dotted line.
    """
    axes = fig.subplots(len(ERROR_KINDS), len(studies), squeeze=False, sharex="col")
    for col, study in enumerate(studies):
        for row, (kind, (label, floor_key)) in enumerate(ERROR_KINDS.items()):
            ax = axes[row, col]
            floor = study[floor_key]
            for method in ("moreau", "ivp"):
                data = study[method]
                ax.plot(data["cpu_time"], np.maximum(data[kind], floor), linestyle="-",
                        markersize=4, **METHOD_STYLE[method])
            ax.axvline(study["exact_cpu_time"], linestyle="--", **METHOD_STYLE["exact"])
            ax.axhline(floor, color="0.6", linestyle=":", linewidth=1.0, label="rounding level")
            if kind == "err_end_position":
                ax.axhline(study["target_error"], color="tab:red", linestyle="-.", linewidth=0.8,
                           label=f"target error {study['target_error']:g}")
                ax.set_title(study["title"], fontsize="medium")
                ax.text(0.97, 0.97, f"Moreau order {study['moreau_order']:.2f}", transform=ax.transAxes,
                        ha="right", va="top", fontsize="small")
            ax.set_xscale("log")
            ax.set_yscale("log")
            if col == 0:
                ax.set_ylabel(label)
            if row == len(ERROR_KINDS) - 1:
                ax.set_xlabel("CPU time [s]")
    handles, names = axes[0, 0].get_legend_handles_labels()
    fig.legend(handles, names, loc="outside lower center", ncols=3, frameon=False, fontsize="small")
    return fig


def figure_accuracy_cost(results: list[dict]):
    """The work-precision figure from accuracy results (:mod:`selfalign.analysis.accuracy` layout)."""
    from matplotlib.figure import Figure

    studies = []
    for result in results:
        a, g = result["attrs"], result["groups"]
        studies.append({
            "title": f"{a['scene_name']} ({scene_from_result(result).horizon_periods} periods)",
            "target_error": a["target_error"], "moreau_order": a["moreau_order"],
            "rounding_level_position": a["rounding_level_position"],
            "rounding_level_vbar": a["rounding_level_vbar"],
            "moreau": g["moreau"]["datasets"], "ivp": g["ivp"]["datasets"],
            "exact_cpu_time": g["exact"]["attrs"]["cpu_time"],
        })
    fig = Figure(figsize=(4.0 * len(studies) + 0.8, 6.4), layout="constrained")
    return work_precision(fig, studies)
