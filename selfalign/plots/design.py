"""The figure of a design (results/design/<spec>.h5, docs/tutorials/design-station.md).

a: process time against positioning error along the closed-form front (time D/vbar against
the spread of x_stick_min over mu) and its simulated members; b: closed-form process time
against the robustness margin; c: the design map over (y2'', y3'') at the chosen period,
stroke and c_mu (the colours and orientation of Figs. 10, 11 and 17), with the region that
passes every closed-form condition, where all simulated entries accumulate at the nominal mu,
where the sufficient condition of Sect. 7.3 holds.  The chosen design is marked in every panel
that can show it, and the legend says which actuator limits it lies on.  Everything in SI.
"""

from __future__ import annotations

import numpy as np
from matplotlib import patheffects
from matplotlib.figure import Figure
from matplotlib.lines import Line2D
from matplotlib.ticker import FuncFormatter, LogLocator, NullFormatter

from ..analysis.optimal_motion import BINDING
from .style import OKABE_ITO, case_map, mark_cells, new_figure, panel_letters, styled

#: Outline colour, line style, halo colour and legend label of the regions of panel c.  Every
#: outline has a halo of the other shade, so it shows on every case colour.
REGIONS = {"screened": ("k", "-", "w", "passes every closed-form condition"),
           "accumulates": ("w", "--", "k", r"all entries accumulate (nominal $\mu$)"),
           "sufficient": ("k", ":", "w", r"sufficient condition of Sect. 7.3 (nominal $\mu$)")}
#: Simulated members of the front farther right than this many times the front's largest spread
#: are off the scale of panel a: drawn right of a break, on a scale of their own.
OFF_SCALE = 3.0
#: Markers of the simulated members (filled: guaranteed) and of the chosen design.
GUARANTEED = dict(marker="o", color=OKABE_ITO["bluish green"], linestyle="none")
NOT_GUARANTEED = dict(marker="o", color=OKABE_ITO["vermillion"], markerfacecolor="none", linestyle="none")
CHOSEN = dict(marker="*", markersize=11, color="k", markeredgecolor="w", markeredgewidth=0.6, linestyle="none",
              zorder=5)


def _halo(colour: str, halo: str, style: str) -> dict:
    return dict(color=colour, linestyle=style, linewidth=1.2,
                path_effects=[patheffects.withStroke(linewidth=2.4, foreground=halo)])


def actuator_limits(spec: dict, profile: dict) -> list[str]:
    """The actuator limits of ``spec`` (a design result's ``spec`` attribute) that the chosen design
    ``profile`` (its ``profile`` datasets, SI) lies on, using all but
    :data:`selfalign.analysis.optimal_motion.BINDING` of it: its peak acceleration at the acceleration
    limit, its stroke at the largest stroke (when the stroke is free), its period at an end of the
    period range, each as a phrase with the limit's value.

    Parameters
    ----------
    spec : dict
        ``max_acceleration`` [m/s^2], ``max_stroke`` and ``min_stroke`` [m] (``min_stroke`` None or
        equal to ``max_stroke`` for a fixed stroke), ``period`` [s] (range).
    profile : dict
        ``y2``, ``y3`` [m/s^2] (and ``accels`` for a motion of the optimal family), ``stroke`` [m],
        ``period`` [s].

    Returns
    -------
    list of str
        Empty when the design lies inside every limit.

    Examples
    --------
    >>> spec = {"max_acceleration": 4.0, "max_stroke": 0.01, "min_stroke": 0.01, "period": [0.1, 0.3]}
    >>> actuator_limits(spec, {"y2": 4.0, "y3": 2.0, "stroke": 0.01, "period": 0.25})
    ['acceleration limit 4 m/s$^2$']
    >>> actuator_limits({**spec, "min_stroke": None}, {"y2": 3.0, "y3": 2.0, "stroke": 0.01, "period": 0.1})
    ['stroke limit 10 mm', 'period limit 100 ms']
    """
    limits = []
    peak = float(np.max(np.abs(np.asarray(profile.get("accels", [profile["y2"], profile["y3"]]), dtype=float))))
    if peak >= (1.0 - BINDING) * spec["max_acceleration"]:
        limits.append(f"acceleration limit {spec['max_acceleration']:g} m/s$^2$")
    fixed = spec.get("min_stroke") is not None and spec["min_stroke"] == spec["max_stroke"]
    if not fixed and float(profile["stroke"]) >= (1.0 - BINDING) * spec["max_stroke"]:
        limits.append(f"stroke limit {1e3 * spec['max_stroke']:g} mm")
    shortest, longest = spec["period"]
    period = float(profile["period"])
    for end, reached in ((shortest, period <= (1.0 + BINDING) * shortest),
                         (longest, period >= (1.0 - BINDING) * longest)):
        if reached:
            limits.append(f"period limit {1e3 * end:g} ms")
    return limits


def tradeoff_time_error(ax, front: dict, chosen: tuple[float, float] | None) -> list:
    """Panel a: closed-form front (line) and its simulated members (dots: guaranteed filled), on a
    log time axis.  The error axis spans the front and the members within :data:`OFF_SCALE` times
    its largest spread; members (and ``chosen``, (error, time)) beyond it are drawn right of a break
    (dotted) on a scale of their own, whose ticks give their smallest and largest error.  Returns the
    legend handles."""
    spread, t_estimate = 1e6 * front["spread"], front["t_estimate"]
    ax.plot(spread, t_estimate, "-", color="0.45",
            label=r"closed form: spread of $x_{\mathrm{stick,min}}$ over $\mu$, $D/\bar v$")
    simulated = np.isfinite(front["t_arrive"])
    error = 1e6 * front["error"]
    good = simulated & front["guaranteed"].astype(bool)
    everything = np.concatenate([spread, error[simulated]] + ([] if chosen is None else [[1e6 * chosen[0]]]))
    everything = everything[np.isfinite(everything)]
    in_scale = everything[everything <= OFF_SCALE * np.nanmax(spread)]
    # One value (a front of one member) gets a margin of its own size.
    pad = 0.08 * ((in_scale.max() - in_scale.min()) or max(in_scale.max(), 1.0))
    left, right = max(0.0, in_scale.min() - pad), in_scale.max() + pad
    ax.set_xlim(left, right)
    off_scale = everything[everything > right]
    # Errors beyond the scale: drawn right of a break on a scale of their own, [lo, hi] -> [band].
    band = (right + 0.06 * (right - left), right + 0.20 * (right - left))
    lo, hi = (off_scale.min(), off_scale.max()) if off_scale.size else (right, right)

    def placed(x):
        x = np.asarray(x, dtype=float)
        beyond = band[0] + (band[1] - band[0]) * ((x - lo) / (hi - lo) if hi > lo else 0.5)
        return np.where(x > right, beyond, x)

    handles = ax.get_lines()[:]
    for mask, style, label in ((good, GUARANTEED, "simulated, guaranteed"),
                               (simulated & ~good, NOT_GUARANTEED, "simulated, not guaranteed")):
        ax.plot(placed(error[mask]), front["t_arrive"][mask], label=label, **style)
        handles.append(ax.get_lines()[-1])
    if chosen is not None:
        ax.plot(placed(1e6 * chosen[0]), chosen[1], **CHOSEN)
    if off_scale.size:
        ticks = [t for t in ax.get_xticks() if left <= t <= right]
        extra = sorted({round(lo), round(hi)})
        ax.set_xlim(left, right + 0.26 * (right - left))
        ax.axvline(right, color="0.3", linestyle=":", linewidth=0.8)
        ax.set_xticks(ticks + placed(np.array(extra, dtype=float)).tolist(), [f"{t:g}" for t in ticks + extra])
    ax.set_yscale("log")
    ax.yaxis.set_major_locator(LogLocator(subs=(1.0, 2.0, 5.0)))
    ax.yaxis.set_major_formatter(FuncFormatter(lambda value, _: f"{value:g}"))
    ax.yaxis.set_minor_formatter(NullFormatter())
    ax.set_xlabel(r"positioning error over all entries and $\mu$ [$\mu$m]")
    ax.set_ylabel("process time [s]")
    ax.grid(True, which="major", linewidth=0.4, alpha=0.5)
    return handles


def tradeoff_time_margin(ax, front: dict, chosen: tuple[float, float] | None) -> list:
    """Panel b: the closed-form front of process time against the mu margin, with ``chosen``
    (margin, time).  Returns the legend handles."""
    ax.step(100 * front["margin"], front["t_estimate"], "-o", where="post", ms=3, color=OKABE_ITO["blue"],
            label=r"closed form: process time $D/\bar v$ against margin")
    if chosen is not None:
        ax.plot(100 * chosen[0], chosen[1], **CHOSEN)
    ax.set_xlabel(r"robustness margin: $\pm$ % of $\mu$")
    ax.set_ylabel(r"process time $D/\bar v$ [s]")
    ax.grid(True, which="major", linewidth=0.4, alpha=0.5)
    return ax.get_lines()[:1]


def design_map_panel(ax, m: dict, chosen: tuple[float, float] | None) -> list:
    """Panel c: cases (colour bar with mathtext labels), non-physical cells (case 0) in their
    encoding, region outlines with halos, the chosen (y2'', y3'') if the chosen design is of the
    paper's family (the map's).  Returns the legend handles."""
    y2, y3 = m["y2"], m["y3"]
    case_map(ax, y2, y3, m["case"])
    handles = [mark_cells(ax, y2, y3, ~m["physical"].astype(bool), "non_physical")]
    regions = {"screened": m["screened"].astype(float), "accumulates": (m["frac_accumulate"] == 1).astype(float),
               "sufficient": (m["sufficient"] == 1).astype(float)}
    for key, values in regions.items():
        colour, style, halo, label = REGIONS[key]
        if values.any() and not values.all():
            contour = ax.contour(y2, y3, values.T, levels=[0.5], colors=colour, linestyles=style, linewidths=1.2)
            contour.set_path_effects([patheffects.withStroke(linewidth=2.4, foreground=halo)])
        elif not values.any():
            label += ": nowhere on the map"
        else:
            label += ": the whole map"
        handles.append(Line2D([], [], label=label, **_halo(colour, halo, style)))
    if chosen is not None:
        ax.plot(*chosen, clip_on=False, **CHOSEN)
    ax.set_xlabel("$y_2''$ [m/s$^2$]")
    ax.set_ylabel("$y_3''$ [m/s$^2$]")
    return handles


def chosen_label(attrs: dict, profile: dict, on_map: bool) -> str:
    """Legend label of the chosen design: chosen or (no design guaranteed) the fastest candidate checked,
    the actuator limits it lies on (:func:`actuator_limits`) and, for a design of the optimal family,
    that panels b and c show the best three-phase design's front and map."""
    label = "chosen design" if attrs["found"] else "fastest candidate checked (none guaranteed)"
    limits = actuator_limits(attrs["spec"], profile)
    if limits:
        label += ",\non the " + " and the ".join(limits) + " (edge of the search)"
    if not on_map:
        label += ":\nfastest table motion (optimal family), shown in a only;\nb and c: the best three-phase design"
    return label


@styled
def figure_design(result: dict) -> Figure:
    """The three panels of a design result (read_h5 layout) and their legend.

    Parameters
    ----------
    result : dict
        ``results/design/<spec>.h5`` read with :func:`selfalign.io.hdf5.read_h5`.

    Returns
    -------
    matplotlib.figure.Figure
        174 x 150 mm: a, b on top; c and the legend below.
    """
    g, a = result["groups"], result["attrs"]
    found = "profile" in g
    performance = g["performance"]["datasets"] if found else {}
    profile = g["profile"]["datasets"] if found else {}
    on_map = found and a.get("family", "three_phase") == "three_phase"
    fig = new_figure("double", 150.0)
    top, bottom = fig.subfigures(2, 1, height_ratios=(1.0, 1.15))
    ax_a, ax_b = top.subplots(1, 2)
    ax_c, ax_key = bottom.subplots(1, 2, width_ratios=(1.0, 0.62))
    handles = tradeoff_time_error(ax_a, g["front_time_error"]["datasets"],
                                  (float(performance["error"]), float(performance["t_arrive"])) if found else None)
    margin_point = None
    if on_map:
        front = g["front_time_margin"]["datasets"]
        same = np.flatnonzero((front["y2"] == profile["y2"]) & (front["y3"] == profile["y3"])
                              & (front["period"] == profile["period"]) & (front["stroke"] == profile["stroke"]))
        if same.size:
            margin_point = (float(performance["margin"]), float(front["t_estimate"][same[0]]))
    handles += tradeoff_time_margin(ax_b, g["front_time_margin"]["datasets"], margin_point)
    lettered = [ax_a, ax_b]
    if "map" in g:
        handles += design_map_panel(ax_c, g["map"]["datasets"], (float(profile["y2"]), float(profile["y3"]))
                                    if on_map else None)
        lettered.append(ax_c)
    else:
        ax_c.axis("off")
    if found:
        handles.append(Line2D([], [], label=chosen_label(a, profile, on_map), **CHOSEN))
    ax_key.axis("off")
    ax_key.legend(handles=handles, loc="center left", borderaxespad=0.0)
    panel_letters(lettered)
    return fig
