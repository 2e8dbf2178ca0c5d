"""The design map over (y2'', y3'') at a design's period, stroke and c_mu."""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from ...model.errors import check_integer
from ...model.profiles import (
    ThreePhaseProfile,
)
from ..positioning import MAX_ENTRY_PERIODS, MAX_PERIODS, MEMORY_LIMIT, positioning_bytes, positioning_grid
from .candidates import Candidates, dimensionless, friction_at, ramp_at
from .screening import screen
from .search import Design
from .verification import sufficient_condition


@dataclass(frozen=True)
class DesignMap:
    """The design map over (y2'', y3'') at the chosen period, stroke and c_mu.

    ``y2``, ``y3`` (n,) [m/s^2]: the axes (y2'' along the first index); (n, n) arrays:
    ``case`` (Table 1 at the nominal mu), ``physical``, ``moves`` (forward at every mu),
    ``holds`` (the strip holds at every mu), ``screened`` (every closed-form condition of
    :class:`Screen`), ``sufficient`` (Sect. 7.3 at the nominal mu: 1 holds, 0 fails, -1 n/a),
    ``frac_accumulate``, ``frac_stop`` (simulated at the nominal mu with ``entries`` entries;
    NaN where the part does not move forward).
    """

    y2: np.ndarray
    y3: np.ndarray
    case: np.ndarray
    physical: np.ndarray
    moves: np.ndarray
    holds: np.ndarray
    screened: np.ndarray
    sufficient: np.ndarray
    frac_accumulate: np.ndarray
    frac_stop: np.ndarray


def design_map(result: Design, *, refine: int = 1, entries: int = 32, progress: str = "auto") -> DesignMap:
    """:class:`DesignMap` of ``result`` on the search grid's accelerations, each step divided into
    ``refine`` (so the chosen design is a grid point), up to the actuator's |y''| limit."""
    if result.verification is None:
        raise ValueError("design_map needs a design with a chosen period and stroke (no candidate was checked)")
    if int(refine) != refine or refine < 1:
        raise ValueError(f"refine must be an integer >= 1, got {refine!r}")
    spec = result.spec
    n = spec.grid.accelerations * int(refine)
    check_integer("entries", entries, 1)
    need, budget = positioning_bytes(n * n * entries, 0), n * n * entries * MAX_PERIODS
    if need > MEMORY_LIMIT or budget > MAX_ENTRY_PERIODS:
        raise ValueError(f"a design map of (search.accelerations x refine)^2 = {n * n:,} settings x {entries:,} "
                         f"entries "
                         f"needs about {need / 1024**3:.3g} GiB and up to {budget:.3g} entry-periods, more than the "
                         f"{MEMORY_LIMIT / 1024**3:g} GiB and {MAX_ENTRY_PERIODS:.0e} allowed: fewer accelerations, a "
                         f"smaller refine or fewer entries")
    axis = spec.max_acceleration * np.arange(1, n + 1) / n
    y2, y3 = np.meshgrid(axis, axis, indexing="ij")
    cand = Candidates(np.full(y2.size, result.period), np.full(y2.size, result.stroke), y2.ravel(), y3.ravel(),
                      np.full(y2.size, result.c_mu))
    scr = screen(spec, cand)
    dims = dimensionless(spec, cand, spec.mu)
    physical = scr.physical
    case = np.zeros(y2.size, np.int8)
    grid = positioning_grid(*(d[physical] for d in dims), w=1.0, c_mu=result.c_mu, n_entries=entries,
                            progress=progress, friction=friction_at(spec, spec.mu), ramp=ramp_at(spec, spec.mu))
    case[physical] = grid.case
    frac = {key: np.full(y2.size, np.nan) for key in ("frac_accumulate", "frac_stop")}
    for key in frac:
        frac[key][physical] = getattr(grid, key)
    sufficient = np.full(y2.size, -1, np.int8)
    for i in np.flatnonzero(case > 0) if spec.friction.kind == "coulomb" and spec.ramp is None else ():  # as verify
        sufficient[i] = sufficient_condition(ThreePhaseProfile(*(float(d[i]) for d in dims)), result.c_mu)
    square = lambda a: a.reshape(n, n)  # noqa: E731
    return DesignMap(axis, axis, square(case), square(physical), square(scr.moves), square(scr.holds),
                     square(scr.ok), square(sufficient), square(frac["frac_accumulate"]), square(frac["frac_stop"]))
