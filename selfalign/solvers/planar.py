"""Planar motion (docs/explanation/planar-model.md): the result every planar solver returns, its records,
and the dispatch of a planar scene to its solver.

The solvers, one module each, take a checked scene and its resolved options and return a
:class:`PlanarResult`:

* ``exact``: :mod:`.planar_exact` (closed-form slip: piecewise-constant Y'' on a uniform surface) or
  :mod:`.planar_smooth` (every other scene: an accurate local solution with bracketed events);
* ``moreau``: :mod:`.planar_moreau` (Moreau's midpoint scheme with the disc projection);
* ``ivp``: :mod:`.planar_ivp` (scipy's solve_ivp mode by mode with event location).
"""

from __future__ import annotations

import importlib
from dataclasses import dataclass

import numpy as np

from .outcomes import Reason

#: Dense output of a planar run: the time, the position and velocity (relative to the table) and the mode
#: (0 stick, 1 slip), at the times tau0 + k dt / samples_per_period.
PLANAR_SAMPLE_DTYPE = np.dtype([("t", "f8"), ("x", "f8", (2,)), ("v", "f8", (2,)), ("mode", "i1")])
#: The event log of a planar run: time, kind (``selfalign.solvers.outcomes.EventKind``: STICK, SLIP, REVERSAL for a
#: straight slip through zero speed that slips on, ZONE for a strip boundary crossed, SWITCH for a profile switch
#: passed) and the state at the event.
PLANAR_EVENT_DTYPE = np.dtype([("t", "f8"), ("kind", "i1"), ("x", "f8", (2,)), ("v", "f8", (2,))])
#: Event counts of a planar run, in :attr:`PlanarResult` and a trajectory's ``info``.
PLANAR_EVENTS = ("sticks", "slips", "crossings", "breaks")


@dataclass(frozen=True)
class PlanarResult:
    """The end state, outcome and records of a planar run (what every planar solver returns).

    Parameters
    ----------
    t_end : float
        The time the run ended.
    x_end, v_end : numpy.ndarray
        Position and velocity relative to the table at ``t_end``, shape (2,).
    reason : Reason
        Why the run ended (PERIODS, MAX_PERIODS, REST, ACCUMULATION, or an error).
    message : str
        What went wrong, for an error reason ("" otherwise).
    sticks, slips, crossings, breaks : int
        Events: sticks (the speed reached 0 and the part sticks), slip starts, strip boundaries crossed,
        profile switches passed.
    steps : int
        Time steps taken (Moreau, and the integrators of the other solvers); 0 for closed-form arcs.
    samples : numpy.ndarray or None
        Dense output (:data:`PLANAR_SAMPLE_DTYPE`), when the scene's record asks for series.
    log : numpy.ndarray or None
        The event log (:data:`PLANAR_EVENT_DTYPE`), when the scene's record asks for events.

    Attributes
    ----------
    t_end, x_end, v_end, reason, message, sticks, slips, crossings, breaks, steps, samples, log
        As given.
    """

    t_end: float
    x_end: np.ndarray
    v_end: np.ndarray
    reason: Reason
    message: str = ""
    sticks: int = 0
    slips: int = 0
    crossings: int = 0
    breaks: int = 0
    steps: int = 0
    samples: np.ndarray | None = None
    log: np.ndarray | None = None


#: The solver module of each method for a planar scene (``run(scene, options) -> PlanarResult``); the exact
#: method has two (:func:`solver_module`).
SOLVERS = {"exact": "planar_exact", "exact_general": "planar_smooth", "moreau": "planar_moreau", "ivp": "planar_ivp"}


def closed_form(scene) -> bool:
    """Whether the exact solver integrates ``scene`` in closed form: piecewise-constant Y'' on a uniform surface."""
    return scene.profile.piecewise_constant and not scene.strips


def solver_module(method: str, scene):
    """The module that simulates the planar ``scene`` with ``method``."""
    key = "exact_general" if method == "exact" and not closed_form(scene) else method
    return importlib.import_module(f"{__package__}.{SOLVERS[key]}")


def run_planar(scene, method: str, options: dict) -> PlanarResult:
    """Simulate the planar ``scene`` with ``method`` and its resolved ``options``."""
    return solver_module(method, scene).run(scene, options)


def sample_times(scene) -> np.ndarray:
    """The dense-output times of a planar run: tau0 + k dt / samples_per_period for k = 0 ... periods x samples."""
    spp = scene.record.samples_per_period
    dt = scene.profile.dt
    k = np.arange(scene.horizon_periods * spp + 1)
    return scene.phase * dt + (k // spp) * dt + (k % spp) * (dt / spp)
