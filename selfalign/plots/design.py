"""The figure of a design (results/design/<spec>.h5, docs/tutorials/design-station.md).

A: process time against positioning error along the closed-form front (time D/vbar against
the spread of x_stick_min over mu) and its simulated members; B: closed-form process time
against the robustness margin; C: the design map over (y2'', y3'') at the chosen period,
stroke and c_mu (the colours and orientation of Figs. 10, 11 and 17), with the region that
passes every closed-form condition, where all simulated entries accumulate at the nominal mu,
where the sufficient condition of Sect. 7.3 holds, and the chosen design.  Everything in SI.
"""

from __future__ import annotations

import numpy as np
from matplotlib.figure import Figure
from matplotlib.lines import Line2D

from .style import case_map, hatch_cells

#: Line styles of the region outlines of panel C.
REGIONS = {"screened": ("k", "-", "passes every closed-form condition"),
           "accumulates": ("w", "--", "all entries accumulate (nominal mu)"),
           "sufficient": ("tab:cyan", ":", "sufficient condition of Sect. 7.3 (nominal mu)")}


def tradeoff_time_error(ax, front: dict, chosen: tuple[float, float] | None):
    """Panel A: closed-form front (line) and its simulated members (dots: guaranteed filled)."""
    ax.plot(1e6 * front["spread"], front["t_estimate"], "-", color="0.6", label="closed form: spread of "
            "$x_{stick,min}$ over $\\mu$, $D/\\bar v$")
    simulated = np.isfinite(front["t_arrive"])
    good = simulated & front["guaranteed"].astype(bool)
    ax.plot(1e6 * front["error"][good], front["t_arrive"][good], "o", color="tab:green", label="simulated, guaranteed")
    ax.plot(1e6 * front["error"][simulated & ~good], front["t_arrive"][simulated & ~good], "o", mfc="none",
            color="tab:red", label="simulated, not guaranteed")
    if chosen is not None:
        ax.plot(1e6 * chosen[0], chosen[1], "*", ms=14, color="k", label="chosen")
    ax.set_xlabel(r"positioning error over all entries and $\mu$ [$\mu$m]")
    ax.set_ylabel("process time [s]")
    ax.set_title("A  process time against positioning error", loc="left", fontsize="medium")
    ax.legend(fontsize="x-small")


def tradeoff_time_margin(ax, front: dict, chosen: tuple[float, float] | None):
    """Panel B: the closed-form front of process time against the mu margin."""
    ax.step(100 * front["margin"], front["t_estimate"], "-o", where="post", ms=3, color="tab:blue",
            label="closed form")
    if chosen is not None:
        ax.plot(100 * chosen[0], chosen[1], "*", ms=14, color="k", label="chosen")
    ax.set_xlabel(r"robustness margin: $\pm$ % of $\mu$")
    ax.set_ylabel(r"process time $D/\bar v$ [s]")
    ax.set_title("B  process time against robustness", loc="left", fontsize="medium")
    ax.legend(fontsize="x-small")


def design_map_panel(ax, m: dict, chosen: tuple[float, float] | None,
                     title: str = "C  design map at the chosen period, stroke and $c_\\mu$"):
    """Panel C: cases, non-physical cells hatched, region outlines, the chosen (y2'', y3'') if the chosen
    design is of the paper's family (the map's)."""
    y2, y3 = m["y2"], m["y3"]
    case_map(ax, y2, y3, m["case"])
    handles = [hatch_cells(ax, y2, y3, ~m["physical"].astype(bool), "no physical profile (case 0)")]
    regions = {"screened": m["screened"].astype(float), "accumulates": (m["frac_accumulate"] == 1).astype(float),
               "sufficient": (m["sufficient"] == 1).astype(float)}
    for key, values in regions.items():
        colour, style, label = REGIONS[key]
        if values.any() and not values.all():
            ax.contour(y2, y3, values.T, levels=[0.5], colors=colour, linestyles=style, linewidths=1.5)
        handles.append(Line2D([], [], color=colour if colour != "w" else "0.4", linestyle=style, label=label))
    if chosen is not None:
        ax.plot(*chosen, "*", ms=14, color="k", mec="w")
        handles.append(Line2D([], [], marker="*", ms=10, color="k", linestyle="none", label="chosen"))
    ax.set_xlabel("$y_2''$ [m/s$^2$]")
    ax.set_ylabel("$y_3''$ [m/s$^2$]")
    ax.set_title(title, loc="left", fontsize="medium")
    ax.legend(handles=handles, fontsize="x-small", loc="upper left", framealpha=0.9)


def figure_design(result: dict):
    """The three panels of a design result (read_h5 layout)."""
    g, a = result["groups"], result["attrs"]
    found = "profile" in g
    performance = g["performance"]["datasets"] if found else {}
    profile = g["profile"]["datasets"] if found else {}
    fig = Figure(figsize=(15.0, 5.0), layout="constrained")
    ax_a, ax_b, ax_c = fig.subplots(1, 3, width_ratios=(1.0, 1.0, 1.3))
    tradeoff_time_error(ax_a, g["front_time_error"]["datasets"],
                        (float(performance["error"]), float(performance["t_arrive"])) if a["found"] else None)
    margin_point = None
    if a["found"]:
        front = g["front_time_margin"]["datasets"]
        same = np.flatnonzero((front["y2"] == profile["y2"]) & (front["y3"] == profile["y3"])
                              & (front["period"] == profile["period"]) & (front["stroke"] == profile["stroke"]))
        if same.size:
            margin_point = (float(performance["margin"]), float(front["t_estimate"][same[0]]))
    tradeoff_time_margin(ax_b, g["front_time_margin"]["datasets"], margin_point)
    if "map" in g and a.get("family", "three_phase") == "three_phase":
        design_map_panel(ax_c, g["map"]["datasets"], (float(profile["y2"]), float(profile["y3"])) if found else None)
    elif "map" in g:  # the map is of the best three-phase design; the chosen motion is not on it
        design_map_panel(ax_c, g["map"]["datasets"], None,
                         "C  design map of the best three-phase design\n(the chosen design is of the optimal family)")
    spec = a["spec"]
    verdict = "guaranteed" if a["found"] else "no guaranteed design"
    fig.suptitle(f"{spec['name']}: {verdict}" + (f"; period {1e3 * float(profile['period']):.4g} ms, stroke "
                                                 f"{1e3 * float(profile['stroke']):.3g} mm, $c_\\mu$ = "
                                                 f"{float(profile['c_mu']):.3g}" if found else ""), fontsize="medium")
    return fig
