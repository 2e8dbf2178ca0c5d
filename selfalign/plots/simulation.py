"""Plot functions and figure builders for the simulation figures (Figs. 3, 9, 12) and the
work-precision study (``accuracy_cost``, ``accuracy_effects``, ``accuracy_parts`` and
``accuracy_planar``: one figure per family of scenes).

As in :mod:`selfalign.plots.profile`, the plot functions draw data they are given onto
matplotlib Axes (or a Figure for multi-panel plots) and return the figure; the
builders ``figure_*`` take results in :func:`selfalign.io.hdf5.read_h5` layout,
pick what is shown and call them, at print size under the figure standard
(:mod:`selfalign.plots.style`): panels are lettered, and what each shows, with its
parameters, is in the caption.  Nothing here computes physics or writes
files; only the object-oriented matplotlib API is used (headless).
"""

from __future__ import annotations

import math

import numpy as np

from ..analysis.accuracy import reference_solver
from ..io.simulation_result import scene_from_result, trajectory_from_result
from ..solvers.outcomes import EventKind
from .profile import ZERO_COLOR, mark_times
from .style import CASE_COLORS, OKABE_ITO, case_label, new_figure, panel_letters, styled

#: Colour of the object's quantities (x, x', F_f) and of the table's (y, y'', -y'').
OBJECT_COLOR = OKABE_ITO["black"]
TABLE_COLOR = OKABE_ITO["bluish green"]
#: The friction bounds +-1 (Figs. 9, 12), in a colour no case of Table 1 has (Fig. 9 shows the case colours),
#: under the lines that run along them (F_f = +-1 in slip).
FRICTION_BOUND_STYLE = {"color": OKABE_ITO["reddish purple"], "linestyle": "--", "linewidth": 0.9, "zorder": 1.5}


def _zero_line(ax):
    return ax.axhline(0.0, color=ZERO_COLOR, linewidth=0.6)


# ---------------------------------------------------------------------------------------
# Fig. 3: object and table
# ---------------------------------------------------------------------------------------

def object_and_table(fig, t, x, y, v):
    """Fig. 3: x (object, relative to the table) and y (table) against t in panel a, x' in b.

    Stick shows as flat stretches of x and x' = 0.
    """
    t, x, y, v = (np.asarray(a, dtype=float) for a in (t, x, y, v))
    ax_x, ax_v = fig.subplots(2, 1, sharex=True, height_ratios=[2, 1])
    ax_x.plot(t, y, color=TABLE_COLOR, label="$y$ (table)")
    ax_x.plot(t, x, color=OBJECT_COLOR, label="$x$ (object)")
    ax_x.set_ylabel("position")
    fig.legend(handles=ax_x.lines, loc="outside lower center", ncols=2)
    ax_v.plot(t, v, color=OBJECT_COLOR, label="$x'$")
    _zero_line(ax_v)
    ax_v.set_ylabel("$x'$")
    ax_v.set_xlabel("$t$")
    ax_v.set_xlim(t[0], t[-1])
    panel_letters((ax_x, ax_v))
    return fig


@styled
def figure_03(result: dict):
    """Fig. 3 from a simulation result recording x, y and v (the paper uses Moreau time-stepping),
    one column wide; the caption gives the profile and the method."""
    traj = trajectory_from_result(result)
    return object_and_table(new_figure("single", 80), traj.t, traj.x, traj.y, traj.v)


# ---------------------------------------------------------------------------------------
# Fig. 9: the five cases of Table 1
# ---------------------------------------------------------------------------------------

def case_histories(fig, panels: list[dict]):
    """Fig. 9: one pair of axes per case sharing the time axis, x' above (black) and the
    table's y'' below (steps, with the friction bounds y'' = +-1 dashed: the mass can
    stick only while |y''| <= 1).

    Separate axes keep the stick segments (x' = 0) and the phases of y'' apart.  Each entry
    of ``panels`` holds ``t``, ``v``, ``ydd`` and ``case`` (of Table 1), which a swatch of its
    colour (:data:`selfalign.plots.style.CASE_COLORS`) and label (:func:`selfalign.plots.style.case_label`)
    names above the pair; ``ydd`` is
    drawn as a step function, so the samples must include the switch times.
    """
    from matplotlib.lines import Line2D
    from matplotlib.patches import Patch

    outer = fig.add_gridspec(len(panels), 1)
    velocity_axes = []
    for i, panel in enumerate(panels):
        t, v, ydd = (np.asarray(panel[k], dtype=float) for k in ("t", "v", "ydd"))
        inner = outer[i].subgridspec(2, 1, height_ratios=[3, 2], hspace=0.0)
        ax_v = fig.add_subplot(inner[0])
        ax_a = fig.add_subplot(inner[1], sharex=ax_v)
        ax_v.plot(t, v, color=OBJECT_COLOR, label="$x'$")
        _zero_line(ax_v)
        ax_v.set_ylabel("$x'$")
        ax_v.tick_params(labelbottom=False)
        swatch = Patch(facecolor=CASE_COLORS[panel["case"]], edgecolor="k", linewidth=0.5,
                       label=f"case {case_label(panel['case'])}")
        ax_v.legend(handles=[swatch], loc="lower left", bbox_to_anchor=(0.03, 1.0), borderaxespad=0.2,
                    borderpad=0.0, handlelength=1.2, handleheight=0.8)
        ax_a.plot(t, ydd, color=TABLE_COLOR, drawstyle="steps-post", label="$y''$")
        friction_bounds(ax_a)
        ax_a.set_ylabel("$y''$")
        ax_v.set_xlim(t[0], t[-1])
        if i == len(panels) - 1:
            ax_a.set_xlabel("$t$")
        velocity_axes.append(ax_v)
    panel_letters(velocity_axes)
    handles = [Line2D([], [], color=OBJECT_COLOR, label="$x'$: velocity of the mass relative to the table"),
               Line2D([], [], color=TABLE_COLOR, label="$y''$: table acceleration"),
               Line2D([], [], **FRICTION_BOUND_STYLE, label=r"$y'' = \pm 1$: the mass can stick only between")]
    fig.legend(handles=handles, loc="outside lower center", ncols=3)
    return fig


def friction_bounds(ax):
    """The friction bounds +-1 (eq. 5: |F_f| <= 1 in units of the maximum friction force) as
    dashed lines; returns them."""
    return [ax.axhline(bound, **FRICTION_BOUND_STYLE) for bound in (-1.0, 1.0)]


def last_periods(traj, dt: float, periods: int) -> np.ndarray:
    """Mask of the samples in the last ``periods`` periods of a recorded run."""
    t = np.asarray(traj.t)
    return t >= t[-1] - periods * dt * (1.0 + 1e-12)


@styled
def figure_09(results: list[dict], cases: list[int], periods: int):
    """Fig. 9: the last ``periods`` periods of each result, named by its case of Table 1
    (``cases`` gives the case of each result), two columns wide; the caption gives the
    profiles."""
    if len(results) != len(cases):
        raise ValueError(f"figure 9 needs one case per result, got {len(cases)} for {len(results)}")
    panels = []
    for result, case in zip(results, cases):
        traj, scene = trajectory_from_result(result), scene_from_result(result)
        keep = last_periods(traj, scene.profile.dt, periods)
        panels.append({"t": traj.t[keep], "v": traj.v[keep], "ydd": traj.ydd[keep], "case": case})
    return case_histories(new_figure("double", 36 * len(panels) + 12), panels)


# ---------------------------------------------------------------------------------------
# Fig. 12: one period of a case 1 trajectory
# ---------------------------------------------------------------------------------------

def case1_period(fig, t, ydd, friction, v, x, marks: dict[str, float]):
    """Fig. 12: the forces on the mass, x' and x over one period, with the times of ``marks``.

    Dimensionless, forces are in units of the maximum friction force mu m g.  Panel a draws
    -y'', the table's inertial force on the mass (in the frame of the table), and the friction
    force F_f = -(x'' + y'') (eq. 5), which lies in Sign(x'): +1 in forward slip, -1 in
    backward slip, and F_f = -y'' while the mass sticks, within the dashed friction bounds
    +-1; so the two coincide wherever the mass sticks.
    """
    t, ydd, friction, v, x = (np.asarray(a, dtype=float) for a in (t, ydd, friction, v, x))
    ax_f, ax_v, ax_x = fig.subplots(3, 1, sharex=True)
    inertial = ax_f.plot(t, -ydd, color=TABLE_COLOR, drawstyle="steps-post", linewidth=1.6,
                         label="$-y''$: inertial force")[0]
    friction_force = ax_f.plot(t, friction, color=OBJECT_COLOR, drawstyle="steps-post", label="$F_f$: friction")[0]
    bound = friction_bounds(ax_f)[0]
    bound.set_label(r"friction bounds $\pm 1$")
    ax_f.set_ylabel(r"force / $\mu m g$")
    fig.legend(handles=[inertial, friction_force, bound], loc="outside lower center", ncols=3, columnspacing=1.0,
               handlelength=1.4)
    ax_v.plot(t, v, color=OBJECT_COLOR, label="$x'$")
    _zero_line(ax_v)
    ax_v.set_ylabel("$x'$")
    ax_x.plot(t, x, color=OBJECT_COLOR, label="$x$")
    ax_x.set_ylabel("$x$")
    ax_x.set_xlabel("$t$")
    mark_times((ax_f, ax_v, ax_x), marks)
    ax_x.set_xlim(t[0], t[-1])
    panel_letters((ax_f, ax_v, ax_x))
    return fig


@styled
def figure_12(result: dict):
    """Fig. 12 from a three-phase simulation result recording ydd, friction, v, x and the event
    log, one column wide; the caption gives the profile.

    Marks: t0 (start), t1, t2 (profile switches), the stick time t_{x'=0} (the
    first STICK event of the log, eq. 21) and t3 = t0 + dt.
    """
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
    return case1_period(new_figure("single", 115), traj.t, traj.ydd, traj.friction, traj.v, traj.x, marks)


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
#: Line colour, marker and legend label of each method's runs.
METHOD_STYLE = {
    "moreau": {"color": OKABE_ITO["blue"], "marker": "o", "label": "Moreau time-stepping (step $h$)"},
    "ivp": {"color": OKABE_ITO["vermillion"], "marker": "s", "label": "solve_ivp DOP853 (rtol)"},
}
#: The vertical line at the reference's CPU time, by the reference's method (its colour is the
#: method's where the method is also studied).
REFERENCE_STYLE = {"exact": {"color": OKABE_ITO["black"], "linestyle": "--", "linewidth": 1.0},
                   "ivp": {"color": OKABE_ITO["vermillion"], "linestyle": "--", "linewidth": 1.0},
                   "moreau": {"color": OKABE_ITO["blue"], "linestyle": "--", "linewidth": 1.0}}
TARGET_STYLE = {"color": OKABE_ITO["reddish purple"], "linestyle": "-.", "linewidth": 0.9}
FLOOR_STYLE = {"color": "0.5", "linestyle": ":", "linewidth": 1.0}
SLOPE_STYLE = {"color": "0.6", "linewidth": 0.8}
#: Radius of the run markers (size s = 12 pt^2), in points.
MARKER_RADIUS = 0.5 * math.sqrt(12.0)
#: Where a panel's note goes, tried in this order: (x, y) in axes fraction and its alignment; the
#: low places keep clear of the rounding level, drawn near the bottom.
NOTE_PLACES = tuple((x, y, ha, va) for y, va in ((0.97, "top"), (0.08, "bottom"), (0.5, "center"))
                    for x, ha in ((0.97, "right"), (0.03, "left"), (0.5, "center")))


def _power(value: float) -> str:
    """``value`` in mathtext, as a power of ten where it is one (1e-06 -> $10^{-6}$)."""
    exponent = math.log10(value)
    return f"$10^{{{exponent:.0f}}}$" if abs(exponent - round(exponent)) < 1e-9 else f"{value:g}"


def reference_label(method: str, options: dict) -> str:
    """The legend label of a study's reference, named by what it is: the exact solver, or the
    method and options a scene names instead (e.g. solve_ivp at rtol 1e-13)."""
    if method == "exact":
        return "exact event-driven solver (reference): its CPU time"
    if method == "ivp":
        tolerances = ", ".join(f"{name} {_power(options[name])}" for name in ("rtol", "atol") if name in options)
        return f"solve_ivp {options.get('integrator', 'DOP853')}, {tolerances} (reference): its CPU time"
    return f"Moreau time-stepping, $h$ = {options['h']:g} (reference): its CPU time"


def slope_guide(ax, cpu_time, error, label: str):
    """A line of slope -1 in log-log (error proportional to 1 / CPU time: first order,
    since the cost grows as 1/h) through the middle of the given runs, over their CPU times."""
    cpu_time, error = np.asarray(cpu_time, dtype=float), np.asarray(error, dtype=float)
    mid = cpu_time.size // 2
    span = np.array([cpu_time.min(), cpu_time.max()])
    return ax.plot(span, error[mid] * cpu_time[mid] / span, label=label, **SLOPE_STYLE)[0]


def covers_data(ax, bbox) -> bool:
    """Whether the display box ``bbox`` covers any line or marker drawn in ``ax``."""
    for line in ax.lines:
        if line.get_visible() and line.get_transform().transform_path(line.get_path()).intersects_bbox(
                bbox, filled=False):
            return True
    markers = bbox.padded(MARKER_RADIUS * ax.figure.dpi / 72.0)  # display units are pixels
    return any(markers.count_contains(c.get_offset_transform().transform(c.get_offsets())) for c in ax.collections)


def place_note(ax, text: str):
    """Write ``text`` in the first place of :data:`NOTE_PLACES` in ``ax`` where it covers no line
    or marker (:func:`covers_data`), else above the panel's right corner; the figure must be
    laid out (drawn) first.  Returns the Text."""
    note = ax.text(0, 0, text, transform=ax.transAxes)
    for x, y, ha, va in NOTE_PLACES:
        note.set(x=x, y=y, ha=ha, va=va)
        if not covers_data(ax, note.get_window_extent()):
            return note
    note.set(x=1.0, y=1.02, ha="right", va="bottom")
    return note


def work_precision(fig, studies: list[dict]):
    """Error against CPU time, log-log: one column per scene, one row per error kind; panels
    lettered a, b, ... along the rows.

    Each study holds ``target_error``, ``moreau_order``, ``note`` (text under the order, may be
    empty), ``reference`` (the method and options of the reference) and per method (``moreau``,
    and ``ivp`` where it was run: the same methods in every study) the arrays ``cpu_time``,
    ``err_end_position``, ``err_vbar`` and the setting of each run (``steps_per_period``,
    ``rtol``), drawn as the colour of its marker, plus ``reference_cpu_time`` (drawn as a
    vertical line, labelled by what the reference is) and the rounding levels of both errors:
    errors below them are drawn at them (an exact zero has no logarithm), marked by a dotted
    line.  A slope -1 guide (first order) runs through the Moreau points.  The notes go where
    they cover no data (:func:`place_note`).
    """
    axes = fig.subplots(len(ERROR_KINDS), len(studies), squeeze=False, sharex="col", sharey="row")
    methods = {method: spec for method, spec in RUN_SETTING.items() if method in studies[0]}
    scales = {}
    for col, study in enumerate(studies):
        for row, (kind, (label, floor_key)) in enumerate(ERROR_KINDS.items()):
            ax = axes[row, col]
            floor = study[floor_key]
            for method, (setting, cmap, _) in methods.items():
                data, style = study[method], METHOD_STYLE[method]
                shown = np.maximum(data[kind], floor)
                ax.plot(data["cpu_time"], shown, color=style["color"], linewidth=0.8, label=style["label"])
                norm, colors = _setting_scale(setting, cmap, data[setting])
                scales[method] = ax.scatter(data["cpu_time"], shown, c=data[setting], cmap=colors, norm=norm,
                                            marker=style["marker"], s=(2 * MARKER_RADIUS) ** 2,
                                            edgecolors=style["color"],
                                            linewidths=0.5, zorder=3)
            slope_guide(ax, study["moreau"]["cpu_time"], study["moreau"][kind], "slope $-1$ (first order)")
            method, options = study["reference"]
            ax.axvline(study["reference_cpu_time"], label=reference_label(method, options),
                       **REFERENCE_STYLE[method])
            ax.axhline(floor, label="rounding level: smaller errors are drawn on it", **FLOOR_STYLE)
            if kind == "err_end_position":
                ax.axhline(study["target_error"], label=f"target error {_power(study['target_error'])}",
                           **TARGET_STYLE)
            ax.set_xscale("log")
            ax.set_yscale("log")
            if col == 0:
                ax.set_ylabel(label)
            else:
                ax.tick_params(labelleft=False)
            if row == len(ERROR_KINDS) - 1:
                ax.set_xlabel("CPU time [s]")
    legend = {}
    for ax in axes.flat:
        for handle, name in zip(*ax.get_legend_handles_labels()):
            legend.setdefault(name, handle)
    fig.legend(legend.values(), legend.keys(), loc="outside lower center", ncols=2)
    for row, (method, (_, _, label)) in enumerate(methods.items()):
        fig.colorbar(scales[method], ax=axes[row, :], location="right", aspect=20, pad=0.01, label=label)
    panel_letters(axes.flat)
    fig.draw_without_rendering()  # lays the panels out, so that the notes find free room
    for ax, study in zip(axes[0], studies):
        place_note(ax, "\n".join(filter(None, (f"Moreau order {study['moreau_order']:.2f}", study["note"]))))
    return fig


def _setting_scale(setting: str, cmap: str, values):
    """Log colour norm over a method's settings and the colour map without its palest third
    (the palest third of a sequential map is hard to see on white)."""
    from matplotlib import colormaps
    from matplotlib.colors import ListedColormap, LogNorm

    part = (0.0, 0.7) if cmap.endswith("_r") else (0.3, 1.0)
    colors = ListedColormap(colormaps[cmap](np.linspace(*part, 256)), name=f"{setting}_{cmap}")
    return LogNorm(float(np.min(values)), float(np.max(values))), colors


def _study(result: dict) -> dict:
    """What :func:`work_precision` draws of one accuracy result."""
    a, g = result["attrs"], result["groups"]
    return {
        "target_error": a["target_error"], "moreau_order": a["moreau_order"],
        "note": ("errors: largest of 2 coordinates" if a.get("planar") else
                 "" if a["parts"] == 1 else f"errors: largest of {a['parts']} parts\nsolve_ivp: not run"),
        "rounding_level_position": a["rounding_level_position"],
        "rounding_level_vbar": a["rounding_level_vbar"],
        **{method: g[method]["datasets"] for method in RUN_SETTING if method in g},
        # The group "exact" holds the reference run, which is the exact solver's unless the scene
        # names another reference (Stribeck friction: solve_ivp at tight tolerances).
        "reference": reference_solver(scene_from_result(result)),
        "reference_cpu_time": float(g["exact"]["datasets"]["cpu_time"]),
    }


@styled
def figure_accuracy_cost(results: list[dict]):
    """The work-precision figure from accuracy results (:mod:`selfalign.analysis.accuracy` layout):
    two columns wide, at most three scenes (a column each); the caption names the scenes.

    The results are all of one part or all of several parts (figure ``accuracy_parts``): solve_ivp
    cannot simulate several parts, so their studies have no ivp runs (the panel says so) and their
    errors are the largest over the parts (the panel says over how many).  Planar studies (figure
    ``accuracy_planar``) have ivp runs and their errors are the largest over the two coordinates.

    Raises
    ------
    ValueError
        If no result, more than three, or results of one part and of several parts are given.
    """
    if not 1 <= len(results) <= 3:
        raise ValueError(f"figure_accuracy_cost draws 1 to 3 studies (a column each at print width), "
                         f"got {len(results)}: split them by family of scenes into several figures")
    studies = [_study(result) for result in results]
    if len({"ivp" in study for study in studies}) > 1:
        raise ValueError("figure_accuracy_cost draws studies of one part or studies of several parts, not both: "
                         "solve_ivp runs in the first only (give the others to the figure accuracy_parts)")
    return work_precision(new_figure("double", 135), studies)
