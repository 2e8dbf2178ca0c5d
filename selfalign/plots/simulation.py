"""Plot functions and figure builders for the simulation figures (Figs. 3, 9, 12) and the
work-precision study (``accuracy_cost``, and ``accuracy_parts`` for scenes with several parts).

As in :mod:`selfalign.plots.profile`, the plot functions draw data they are given onto
matplotlib Axes (or a Figure for multi-panel plots) and return the figure; the
builders ``figure_*`` take results in :func:`selfalign.io.hdf5.read_h5` layout,
pick what is shown and call them.  Nothing here computes physics or writes
files; only the object-oriented matplotlib API is used (headless).
"""

from __future__ import annotations

import math

import numpy as np

from ..io.simulation_result import scene_from_result, trajectory_from_result
from ..model.planar import PlanarProfile
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
#: The friction bounds +-1 (Figs. 9, 12).
FRICTION_BOUND_STYLE = {"color": "tab:red", "linestyle": "--", "linewidth": 0.8}


def _profile_text(scene: Scene) -> str:
    return _motion_text(scene.profile)


def _motion_text(profile) -> str:
    """The parameters of a table motion in a figure's words (a planar one: its components, lag and angle)."""
    if isinstance(profile, PlanarProfile):
        parts = [f"x: {_motion_text(profile.x)}"]
        if profile.y is not None:
            same = profile.y.params() == profile.x.params()
            later = f", {profile.offset:g} period later"
            parts.append(("y: the same" if same else f"y: {_motion_text(profile.y)}") + later)
        return "; ".join(parts) + (f"; turned {math.degrees(profile.angle):.3g} deg" if profile.angle else "")
    p = profile.params()
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
    """Fig. 9: one pair of axes per case sharing the time axis, x' above (black) and the
    table's y'' below (grey steps, with the friction bounds y'' = +-1 dashed: the mass can
    stick only while |y''| <= 1).

    Separate axes keep the stick segments (x' = 0) and the phases of y'' apart.  Each entry
    of ``panels`` holds ``t``, ``v``, ``ydd`` and ``title``; ``ydd`` is drawn as a step
    function, so the samples must include the switch times.
    """
    from matplotlib.lines import Line2D

    outer = fig.add_gridspec(len(panels), 1)
    for i, panel in enumerate(panels):
        t, v, ydd = (np.asarray(panel[k], dtype=float) for k in ("t", "v", "ydd"))
        inner = outer[i].subgridspec(2, 1, height_ratios=[3, 2], hspace=0.0)
        ax_v = fig.add_subplot(inner[0])
        ax_a = fig.add_subplot(inner[1], sharex=ax_v)
        ax_v.plot(t, v, color="k", label="$x'$")
        ax_v.axhline(0.0, color="0.4", linewidth=0.8)
        ax_v.set_ylabel("$x'$")
        ax_v.set_title(panel["title"], fontsize="medium", loc="left")
        ax_v.tick_params(labelbottom=False)
        ax_a.plot(t, ydd, color=TABLE_COLOR, drawstyle="steps-post", label="$y''$")
        friction_bounds(ax_a)
        ax_a.set_ylabel("$y''$")
        ax_v.set_xlim(t[0], t[-1])
        if i == len(panels) - 1:
            ax_a.set_xlabel("$t$")
    handles = [Line2D([], [], color="k", label="$x'$: velocity of the mass relative to the table"),
               Line2D([], [], color=TABLE_COLOR, label="$y''$: table acceleration"),
               Line2D([], [], **FRICTION_BOUND_STYLE, label=r"$y'' = \pm 1$: stick possible only between")]
    fig.legend(handles=handles, loc="outside lower center", ncols=2, frameon=False, fontsize="small")
    return fig


def friction_bounds(ax):
    """The friction bounds +-1 (eq. 5: |F_f| <= 1 in units of the maximum friction force) as
    dashed lines; returns them."""
    return [ax.axhline(bound, **FRICTION_BOUND_STYLE) for bound in (-1.0, 1.0)]


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
    fig = Figure(figsize=(7.2, 2.4 * len(panels) + 0.8), layout="constrained")
    return case_histories(fig, panels)


# ---------------------------------------------------------------------------------------
# Fig. 12: one period of a case 1 trajectory
# ---------------------------------------------------------------------------------------

def case1_period(fig, t, ydd, friction, v, x, marks: dict[str, float], title: str = ""):
    """Fig. 12: y'' and the friction force, x' and x over one period, with the times of ``marks``.

    Dimensionless, y'' is the table's inertial force on the mass and F_f = -(x'' + y'') the
    friction force, both in units of the maximum friction force mu m g; F_f lies in
    Sign(x') (eq. 5): +1 in forward slip, -1 in backward slip, |F_f| <= 1 while the mass
    sticks (the dashed friction bounds).
    """
    t, ydd, friction, v, x = (np.asarray(a, dtype=float) for a in (t, ydd, friction, v, x))
    ax_f, ax_v, ax_x = fig.subplots(3, 1, sharex=True)
    if title:
        fig.suptitle(title)
    ax_f.plot(t, ydd, color=TABLE_COLOR, drawstyle="steps-post", label="$y''$ (table)")
    ax_f.plot(t, friction, color="k", drawstyle="steps-post", label="$F_f$ (friction force)")
    friction_bounds(ax_f)[0].set_label(r"friction bounds $F_f = \pm 1$")
    ax_f.set_ylabel(r"force / $\mu m g$")
    ax_f.legend(loc="lower right", fontsize="small", frameon=False)
    ax_v.plot(t, v, color="k", label="$x'$")
    ax_v.axhline(0.0, color="0.4", linewidth=0.8)
    ax_v.set_ylabel("$x'$")
    ax_x.plot(t, x, color="k", label="$x$")
    ax_x.set_ylabel("$x$")
    ax_x.set_xlabel("$t$")
    mark_times((ax_f, ax_v, ax_x), marks)
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
#: Per method: the dataset that sets each run's accuracy, the colour map of its markers (darker
#: = finer: more steps, smaller rtol) and the label of its colour bar.
RUN_SETTING = {
    "moreau": ("steps_per_period", "Blues", r"Moreau: steps per period $n = \Delta t / h$"),
    "ivp": ("rtol", "Oranges_r", "solve_ivp: rtol"),
}


def _setting_scale(setting: str, cmap: str, values):
    """Log colour norm over a method's settings and the colour map without its palest third
    (the palest third of a sequential map is hard to see on white)."""
    from matplotlib import colormaps
    from matplotlib.colors import ListedColormap, LogNorm

    part = (0.0, 0.7) if cmap.endswith("_r") else (0.3, 1.0)
    colors = ListedColormap(colormaps[cmap](np.linspace(*part, 256)), name=f"{setting}_{cmap}")
    return LogNorm(float(np.min(values)), float(np.max(values))), colors


def slope_guide(ax, cpu_time, error, label: str):
    """A dotted line of slope -1 in log-log (error proportional to 1 / CPU time: first order,
    since the cost grows as 1/h) through the middle of the given runs, over their CPU times."""
    cpu_time, error = np.asarray(cpu_time, dtype=float), np.asarray(error, dtype=float)
    mid = cpu_time.size // 2
    span = np.array([cpu_time.min(), cpu_time.max()])
    return ax.plot(span, error[mid] * cpu_time[mid] / span, color="0.6", linewidth=0.8, label=label)[0]


def work_precision(fig, studies: list[dict]):
    """Error against CPU time, log-log: one column per scene, one row per error kind.

    Each study holds ``title``, ``target_error``, ``moreau_order``, ``note`` (text under the
    order, may be empty) and per method (``moreau``, and ``ivp`` where it was run: the same
    method in every study) the arrays ``cpu_time``, ``err_end_position``, ``err_vbar`` and
    the setting of each run (``steps_per_period``, ``rtol``), drawn as the colour of its
    marker, plus ``exact_cpu_time`` (drawn as a vertical line: it is the reference) and
    the rounding levels of both errors: errors below them are drawn at them
    (an exact zero has no logarithm), marked by a dotted line.  A slope -1 guide
    (first order) runs through the Moreau points.
    """
    axes = fig.subplots(len(ERROR_KINDS), len(studies), squeeze=False, sharex="col")
    methods = {method: spec for method, spec in RUN_SETTING.items() if method in studies[0]}
    scales = {}
    for col, study in enumerate(studies):
        for row, (kind, (label, floor_key)) in enumerate(ERROR_KINDS.items()):
            ax = axes[row, col]
            floor = study[floor_key]
            for method, (setting, cmap, _) in methods.items():
                data = study[method]
                style = METHOD_STYLE[method]
                shown = np.maximum(data[kind], floor)
                ax.plot(data["cpu_time"], shown, color=style["color"], linewidth=1.0, label=style["label"])
                norm, colors = _setting_scale(setting, cmap, data[setting])
                scales[method] = ax.scatter(data["cpu_time"], shown, c=data[setting], cmap=colors, norm=norm,
                                            marker=style["marker"], s=22, edgecolors=style["color"],
                                            linewidths=0.6, zorder=3)
            slope_guide(ax, study["moreau"]["cpu_time"], study["moreau"][kind], "slope $-1$ (first order)")
            ax.axvline(study["exact_cpu_time"], linestyle="--", **METHOD_STYLE["exact"])
            ax.axhline(floor, color="0.6", linestyle=":", linewidth=1.0,
                       label="rounding level: smaller errors are drawn on it")
            if kind == "err_end_position":
                ax.axhline(study["target_error"], color="tab:red", linestyle="-.", linewidth=0.8,
                           label=f"target error {study['target_error']:g}")
                ax.set_title(study["title"], fontsize="small")
                ax.text(0.97, 0.97, "\n".join(filter(None, (f"Moreau order {study['moreau_order']:.2f}",
                                                             study["note"]))),
                        transform=ax.transAxes, ha="right", va="top", fontsize="small")
            ax.set_xscale("log")
            ax.set_yscale("log")
            if col == 0:
                ax.set_ylabel(label)
            if row == len(ERROR_KINDS) - 1:
                ax.set_xlabel("CPU time [s]")
    handles, names = axes[0, 0].get_legend_handles_labels()
    fig.legend(handles, names, loc="outside lower center", ncols=3, frameon=False, fontsize="small")
    for row, (method, (_, _, label)) in enumerate(methods.items()):
        fig.colorbar(scales[method], ax=axes[row, :], location="right", aspect=25, pad=0.01, label=label)
    return fig


def _study_title(scene: Scene) -> str:
    """What a work-precision study simulates, in physical terms (two lines): the parts (several, with
    their restitution), the surface, each effect beyond the paper's model (friction law, finite jerk)
    with its size, the horizon, the profile."""
    if scene.planar:
        where = "planar motion, " + (", ".join(
            rf"strip $n$ = ({s.normal[0]:.3g}, {s.normal[1]:.3g}) at $x_\mu$ = {s.x_mu:g}, $c_\mu$ = {s.c_mu:g}"
            for s in scene.strips) or "uniform friction")
    else:
        surface = scene.surface.params()
        where = ("uniform friction" if surface["kind"] == "uniform" else
                 rf"stop zone at $x_\mu$ = {surface['x_mu']:g}, $c_\mu$ = {surface['c_mu']:g}")
    if scene.parts is not None:
        where = f"{len(scene.parts)} parts, e = {scene.restitution:g}, {where}"
    law = scene.friction.params()
    if law["kind"] != "coulomb":
        where += rf", {law['kind'].replace('_', '/')} $\mu_s/\mu_k$ = {law['mu_s_over_mu_k']:g}"
        where += rf", $v_s$ = {law['v_s']:g}" if "v_s" in law else ""
    profile = scene.profile.params()
    if "ramp" in profile:
        where += rf", $y''$ ramps {100 * profile['ramp'] / profile['dt']:.3g} % of $\Delta t$"
    elif "jerk" in profile:
        where += rf", jerk {profile['jerk']:g}"
    return f"{where}, {scene.horizon_periods} periods from rest\n{_profile_text(scene)}"


def figure_accuracy_cost(results: list[dict]):
    """The work-precision figure from accuracy results (:mod:`selfalign.analysis.accuracy` layout).

    The results are all of one part or all of several parts (figure ``accuracy_parts``): solve_ivp
    cannot simulate several parts, so their studies have no ivp runs (the panel says so) and their
    errors are the largest over the parts (the panel says over how many).  Planar studies (figure
    ``accuracy_planar``) have ivp runs and their errors are the largest over the two coordinates."""
    from matplotlib.figure import Figure

    studies = []
    for result in results:
        a, g = result["attrs"], result["groups"]
        studies.append({
            # The exact solver is the reference unless the scene names another (Stribeck).
            "title": _study_title(scene_from_result(result))
                     + ("" if a["reference"] == "exact" else f"\nreference: {a['reference']}"),
            "target_error": a["target_error"], "moreau_order": a["moreau_order"],
            "note": ("errors: largest of 2 coordinates" if a.get("planar") else
                     "" if a["parts"] == 1 else f"errors: largest of {a['parts']} parts\nsolve_ivp: not run"),
            "rounding_level_position": a["rounding_level_position"],
            "rounding_level_vbar": a["rounding_level_vbar"],
            **{method: g[method]["datasets"] for method in RUN_SETTING if method in g},
            "exact_cpu_time": float(g["exact"]["datasets"]["cpu_time"]),
        })
    if len({"ivp" in study for study in studies}) > 1:
        raise ValueError("figure_accuracy_cost draws studies of one part or studies of several parts, not both: "
                         "solve_ivp runs in the first only (give the others to the figure accuracy_parts)")
    fig = Figure(figsize=(4.4 * len(studies) + 0.8, 7.6), layout="constrained")
    return work_precision(fig, studies)
