"""Result files of the workflow stage "effects": what the friction laws beyond the paper (issue 16,
README "Static and kinetic friction") do to stopping and accumulation (Sect. 7).  Each builder
returns the (datasets, attributes, groups) that :func:`selfalign.io.hdf5.write_h5` writes.
"""

from __future__ import annotations

import numpy as np

from ..analysis.positioning import MAX_PERIODS, positioning_grid
from ..model.friction import FrictionLaw

#: Per-setting fractions of the maps, [r, i_y2, i_y3] (as in Fig. 17's fig17.h5).
MAP_FIELDS = ("frac_accumulate", "frac_never_stop", "frac_undecided", "dx_d")


def friction_law(ratio: float) -> FrictionLaw:
    """The paper's Coulomb law at r = 1, static/kinetic with mu_s/mu_k = ``ratio`` above."""
    return FrictionLaw() if ratio == 1.0 else FrictionLaw("static_kinetic", ratio)


def static_friction_content(y2, y3, ratios, settings, sweep_excess, *, dt: float, dy: float, w: float, c_mu: float,
                            n_entries: int, sweep_entries: int, max_periods: int = MAX_PERIODS):
    """Contents of ``results/effects/static_friction.h5``: accumulation under mu_s = r mu_k.

    Group ``maps``: for each r of ``ratios`` (``ratio``), the positioning of Fig. 17
    (Sect. 7.2) over the grid ``y2`` x ``y3`` with ``n_entries`` entries per setting:
    :data:`MAP_FIELDS`, each [r, i_y2, i_y3].  Group ``sweep``: Delta x_d and the fraction of
    accumulating entries ([setting, r] ``dx_d``, ``frac_accumulate``) of each (y2'', y3'') of
    ``settings`` ([setting] ``y2``, ``y3``) at r = 1 and at r = 1 + each of ``sweep_excess``
    (``ratio``), ``sweep_entries`` entries each.  The root holds the grid axes ``y2``, ``y3``;
    the attributes the common setting.
    """
    y2, y3 = np.asarray(y2, dtype=float), np.asarray(y3, dtype=float)
    settings = np.asarray(settings, dtype=float).reshape(-1, 2)
    sweep_ratios = np.concatenate([[1.0], 1.0 + np.asarray(sweep_excess, dtype=float)])
    common = {"w": w, "c_mu": c_mu, "max_periods": max_periods, "progress": "quiet"}
    g2, g3 = np.meshgrid(y2, y3, indexing="ij")
    maps = [positioning_grid(dt, dy, g2, g3, n_entries=n_entries, friction=friction_law(r), **common)
            for r in ratios]
    sweep = [positioning_grid(dt, dy, settings[:, 0], settings[:, 1], n_entries=sweep_entries,
                              friction=friction_law(r), **common) for r in sweep_ratios]
    groups = {
        "maps": {"datasets": {"ratio": np.asarray(ratios, dtype=float),
                              **{name: np.stack([getattr(m, name) for m in maps]) for name in MAP_FIELDS}}},
        "sweep": {"datasets": {"ratio": sweep_ratios, "y2": settings[:, 0], "y3": settings[:, 1],
                               **{name: np.stack([getattr(s, name) for s in sweep], axis=1)
                                  for name in ("dx_d", "frac_accumulate")}}},
    }
    attrs = {"dt": float(dt), "dy": float(dy), "w": float(w), "c_mu": float(c_mu), "n_entries": int(n_entries),
             "sweep_entries": int(sweep_entries), "max_periods": int(max_periods),
             "events": int(sum(m.events for m in maps + sweep))}
    return {"y2": y2, "y3": y3}, attrs, groups
