"""The figures of the workflow, each drawn from its result files.

:data:`FIGURES` maps a figure's name (the stem of ``figures/<name>.png``) to the
function that draws it from the results it is given, in
:func:`selfalign.io.hdf5.read_h5` layout and in the order the workflow lists them
(``workflow/rules/figures.smk``), plus the options the config gives it.  One
workflow rule per figure calls :func:`draw`; the plot functions in
:mod:`selfalign.plots` do the drawing, and what a figure needs computed on top of
its results (the case of each Fig. 9 run, the displacement of the mass relative to the
table for Fig. 6) is computed here, not in the plot; Fig. 15 gets the lengths of
Sect. 7.1 drawn onto it (:mod:`selfalign.plots.annotate`), and Fig. 2 the workflow's stop zone
(:class:`~selfalign.StopZone`), whose own coefficient it draws.
"""

from __future__ import annotations

import numpy as np

from ..analysis.classification import classify
from ..analysis.finite_jerk import RAMPS_TOO_LONG, jerk_profile
from ..analysis.steady_state import monodromy_grid
from ..io.simulation_result import scene_from_result
from ..model.friction import StopZone
from ..model.profiles import PiecewiseLinearProfile
from ..plots.accumulation import figure_02, figure_14, figure_15, figure_16, figure_17, figure_18
from ..plots.annotate import overshoot_dimensions
from ..plots.classification import figure_04, figure_05, figure_06, figure_08, figure_map
from ..plots.design import figure_design
from ..plots.effects import figure_static_friction, figure_stribeck_friction
from ..plots.finite_jerk import finite_jerk_figure, finite_jerk_stopping_figure
from ..plots.profile import figure_07
from ..plots.simulation import figure_03, figure_09, figure_12, figure_accuracy_cost
from ..plots.stability import figure_13, figure_floquet_map
from .accumulation import setting_group
from .classification import fig06_mass_displacement
from .finite_jerk import grids_from_result


def _fig09(results, periods):
    cases = [classify(scene_from_result(r).profile) for r in results]
    return figure_09(results, cases, periods=periods)


def accuracy_figure(scene) -> str:
    """The work-precision figure that draws the accuracy study of ``scene``, by family of scenes:
    ``accuracy_parts`` (several parts), ``accuracy_planar`` (planar motion), ``accuracy_effects``
    (one part under an effect beyond the paper's model: a friction law other than Coulomb's, or
    finite jerk, i.e. a piecewise-linear y'') or ``accuracy_cost`` (the paper's model).

    Parameters
    ----------
    scene : selfalign.Scene
        A scene of the accuracy stage.

    Returns
    -------
    str
        The figure's name.

    Examples
    --------
    >>> import selfalign as sa
    >>> scene = sa.Scene(profile=sa.ThreePhaseProfile(1.05, 0.084, 2.2, 0.9), periods=4)
    >>> accuracy_figure(scene), accuracy_figure(scene.replace(friction=sa.FrictionLaw("static_kinetic", 1.3)))
    ('accuracy_cost', 'accuracy_effects')
    """
    if scene.parts is not None:
        return "accuracy_parts"
    if scene.planar:
        return "accuracy_planar"
    if scene.friction.kind != "coulomb" or isinstance(scene.profile, PiecewiseLinearProfile):
        return "accuracy_effects"
    return "accuracy_cost"


def _fig15(results, setting):
    """Fig. 15 with the lengths of Sect. 7.1 (overshoots, Delta x_d) drawn on it."""
    (result,) = results
    key = setting_group(*setting)
    fig = figure_15(result, key)
    a = result["groups"][key]["attrs"]
    return overshoot_dimensions(fig.axes[0], a["x_mu"], a["overshoot_min"], a["overshoot_max"], a["dx_d"])


def _no_profile(dt: float, dy: float, y2, y3, fractions) -> np.ndarray:
    """[ramp, y2, y3]: where no profile of the family exists (case 0, or ramps longer than their phases),
    found by building the profiles (:func:`selfalign.analysis.finite_jerk.jerk_profile`)."""
    return np.array([[[jerk_profile(dt, dy, a, b, fraction) in (None, RAMPS_TOO_LONG) for b in np.asarray(y3).tolist()]
                      for a in np.asarray(y2).tolist()] for fraction in np.asarray(fractions).tolist()])


def _finite_jerk_stopping(results):
    """The stopping figure of the finite-jerk study, the cells without a profile marked."""
    (result,) = results
    _, stopping = grids_from_result(result)
    a = result["groups"]["stopping"]["attrs"]
    return finite_jerk_stopping_figure(stopping, _no_profile(a["dt"], a["dy"], stopping.y2, stopping.y3,
                                                             stopping.ramp_fractions))


def _static_friction(results):
    """The static-friction figure, the settings without a physical profile (case 0) marked."""
    (result,) = results
    d, a = result["datasets"], result["attrs"]
    return figure_static_friction(result, _no_profile(a["dt"], a["dy"], d["y2"], d["y3"], [0.0])[0])


def _floquet_map(results):
    """The second Floquet multiplier over a stability grid against eq. (33): lambda2 = c4 =
    (y2'' - 1)(y3'' - 1) / ((y2'' + 1)(y3'' + 1)) in case 4 (slip-slip), 0 in cases 1, 2, 3 and 5
    (Sect. 6.1), NaN in case 0: the entry m22 of the closed-form monodromy matrix
    (:func:`selfalign.analysis.steady_state.monodromy_grid`)."""
    (result,) = results
    d, a = result["datasets"], result["attrs"]
    y2, y3 = np.meshgrid(d["y2"], d["y3"], indexing="ij")
    return figure_floquet_map(result, monodromy_grid(a["dt"], a["dy"], y2, y3)[..., 1, 1])


#: name -> draw(results, **options): the results are the figure's inputs in the workflow's order.
FIGURES = {
    # Drawn from the stop zone of the workflow's accumulation stage (no result file): x_mu = 0.
    "fig02": lambda results, zone: figure_02(StopZone(x_mu=0.0, w=zone["w"], c_mu=zone["c_mu"])),
    "fig03": lambda results: figure_03(*results),
    "fig04": lambda results: figure_04(*results),
    "fig05": lambda results: figure_05(*results),
    "fig06": lambda results: figure_06(*results, fig06_mass_displacement(*results)),
    "fig07": lambda results: figure_07(*results),
    "fig08": lambda results: figure_08(),
    "fig09": _fig09,
    "fig10": lambda results, f_max: figure_map(*results, f_max),
    "fig11": lambda results, f_max: figure_map(*results, f_max),
    "fig12": lambda results: figure_12(*results),
    "fig13": lambda results: figure_13(*results),
    "floquet_fig17": _floquet_map,
    "fig14": lambda results, setting: figure_14(*results, setting_group(*setting)),
    "fig15": _fig15,
    "fig16": lambda results, settings: figure_16(*results, [setting_group(*s) for s in settings]),
    "fig17": lambda results: figure_17(*results),  # fig17.h5, fig18.h5 (its setting is marked)
    "fig18": lambda results: figure_18(*results),
    # One work-precision figure per family of scenes (accuracy_figure).
    "accuracy_cost": figure_accuracy_cost,
    "accuracy_effects": figure_accuracy_cost,
    "accuracy_parts": figure_accuracy_cost,
    "accuracy_planar": figure_accuracy_cost,
    "static_friction": _static_friction,
    "stribeck_friction": lambda results: figure_stribeck_friction(*results),
    "finite_jerk": lambda results: finite_jerk_figure(grids_from_result(*results)[0]),
    "finite_jerk_stopping": _finite_jerk_stopping,
}


#: Figures drawn once per item, by name prefix: ``design_<spec>`` from results/design/<spec>.h5.
FAMILIES = {"design_": lambda results: figure_design(*results)}


def draw(name: str, results: list[dict], **options):
    """The matplotlib Figure ``name`` drawn from ``results`` with ``options``."""
    family = [drawing for prefix, drawing in FAMILIES.items() if name.startswith(prefix)]
    if name not in FIGURES and not family:
        raise ValueError(f"unknown figure {name!r}; known: {', '.join(FIGURES)} and "
                         f"{', '.join(p + '<name>' for p in FAMILIES)}")
    return (FIGURES.get(name) or family[0])(results, **options)
