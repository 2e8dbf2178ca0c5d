"""Result file of the workflow stage "finite_jerk" (docs/explanation/model.md): the paper's maps
against the ramp time of y'' (:mod:`selfalign.analysis.finite_jerk`) into
``results/finite_jerk/finite_jerk.h5``, one group per plane: ``steady_<plane>`` (vbar and the
case of Table 1, exact solver) and ``stopping`` (steady-state entries into the stop zone).
The workflow runs it on coarse grids, ``benchmarks/finite_jerk_study.py`` on the full ones.
"""

from __future__ import annotations

from collections.abc import Mapping

import numpy as np

from ..analysis.finite_jerk import SteadyGrid, StoppingGrid, steady_grid, stopping_grid
from .common import range_values

#: Prefix of the group of each steady plane.
STEADY_PREFIX = "steady_"


def finite_jerk_results(ramp_fractions, steady: Mapping[str, Mapping], stopping: Mapping, zone: Mapping,
                        progress: str = "auto"):
    """(datasets, attrs, groups) of results/finite_jerk/finite_jerk.h5.

    ``steady``: plane name -> {dt, dy, y2, y3} (config ranges); ``stopping``: {dt, dy, y2, y3,
    n_entries, max_periods}; ``zone``: {w, c_mu}.  Every grid has the axes
    (ramp fractions, y2'', y3'').
    """
    fractions = np.asarray(ramp_fractions, dtype=float)
    groups = {}
    for name, plane in steady.items():
        grid = steady_grid(plane["dt"], plane["dy"], range_values(plane["y2"]), range_values(plane["y3"]),
                           fractions, progress=progress)
        groups[STEADY_PREFIX + name] = {"datasets": {"y2": grid.y2, "y3": grid.y3, "vbar": grid.vbar,
                                                     "case": grid.case},
                                        "attrs": {"dt": plane["dt"], "dy": plane["dy"]}}
    grid = stopping_grid(stopping["dt"], stopping["dy"], range_values(stopping["y2"]), range_values(stopping["y3"]),
                         fractions, w=zone["w"], c_mu=zone["c_mu"], n_entries=stopping["n_entries"],
                         max_periods=stopping["max_periods"],
                         progress=progress)
    groups["stopping"] = {"datasets": {"y2": grid.y2, "y3": grid.y3, "frac_accumulate": grid.frac_accumulate,
                                       "frac_rest": grid.frac_rest, "dx_d": grid.dx_d},
                          "attrs": {"dt": stopping["dt"], "dy": stopping["dy"], "w": zone["w"],
                                    "c_mu": zone["c_mu"], "n_entries": stopping["n_entries"]}}
    return {"ramp_fractions": fractions}, {}, groups


def grids_from_result(result: dict) -> tuple[dict[str, SteadyGrid], StoppingGrid]:
    """(plane name -> SteadyGrid, StoppingGrid) of a result of :func:`finite_jerk_results` (read_h5 layout)."""
    fractions = result["datasets"]["ramp_fractions"]
    steady = {name[len(STEADY_PREFIX):]: SteadyGrid(fractions, **group["datasets"])
              for name, group in result["groups"].items() if name.startswith(STEADY_PREFIX)}
    return steady, StoppingGrid(fractions, **result["groups"]["stopping"]["datasets"])
