"""Result files of the workflow stage "effects": what the friction laws beyond the paper
(docs/explanation/stopping.md) do to vbar, stopping and accumulation (Sect. 7): static
friction (``static_friction.h5``) and the Stribeck law (``stribeck.h5``).  Each builder
returns the (datasets, attributes, groups) that :func:`selfalign.io.hdf5.write_h5` writes.
"""

from __future__ import annotations

import numpy as np

from ..analysis.finite_jerk import stopping
from ..analysis.positioning import MAX_PERIODS, positioning, positioning_grid
from ..analysis.steady_simulation import simulated_steady_state, three_phase_simulated_steady_state
from ..model.friction import FrictionLaw
from ..model.profiles import ThreePhaseProfile

#: Per-setting fractions of the maps, [r, i_y2, i_y3] (as in Fig. 17's fig17.h5).
MAP_FIELDS = ("frac_accumulate", "frac_never_stop", "frac_undecided", "dx_d")


def friction_law(ratio: float) -> FrictionLaw:
    """The paper's Coulomb law at r = 1, static/kinetic with mu_s/mu_k = ``ratio`` above."""
    return FrictionLaw() if ratio == 1.0 else FrictionLaw("static_kinetic", ratio)


def _pairs(settings) -> np.ndarray:
    """The (y2'', y3'') settings as an array [setting, 2]."""
    return np.asarray(settings, dtype=float).reshape(-1, 2)


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
    settings = _pairs(settings)
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


def stribeck_law(ratio: float, v_s: float, delta: float) -> FrictionLaw:
    """The Stribeck law mu(v) = mu_k (1 + (r - 1) exp(-(|v|/v_s)^delta)), r = ``ratio``."""
    return FrictionLaw("stribeck", ratio, v_s=v_s, delta=delta)


def stribeck_steady(v_s_fractions, settings, *, dt: float, dy: float, ratio: float, delta: float,
                    steps_per_period: int) -> dict:
    """Group ``stribeck_steady`` of ``stribeck.h5``: vbar (eq. 10, uniform surface) of each
    (y2'', y3'') of ``settings`` against v_s = each of ``v_s_fractions`` x the profile's velocity
    swing, by Moreau (dt / ``steps_per_period``), with the exact static/kinetic (v_s -> 0) and
    Coulomb (r = 1) values of each setting."""
    settings = _pairs(settings)
    fractions = np.asarray(v_s_fractions, dtype=float)
    profiles = [ThreePhaseProfile(dt, dy, y2, y3) for y2, y3 in settings]
    vbar = np.array([[simulated_steady_state([p], "moreau", steps_per_period=steps_per_period, progress="quiet",
                                             friction=stribeck_law(ratio, f * p.velocity_swing, delta)).vbar[0]
                      for f in fractions] for p in profiles])
    limits = {name: three_phase_simulated_steady_state(dt, dy, settings[:, 0], settings[:, 1], progress="quiet",
                                                       friction=law).vbar
              for name, law in (("vbar_static_kinetic", friction_law(ratio)), ("vbar_coulomb", FrictionLaw()))}
    return {"datasets": {"y2": settings[:, 0], "y3": settings[:, 1],
                         "velocity_swing": np.array([p.velocity_swing for p in profiles]), "vbar": vbar, **limits},
            "attrs": {"dt": float(dt), "dy": float(dy)}}


def stribeck_stopping(v_s_fractions, settings, *, dt: float, dy: float, w: float, c_mu: float, ratio: float,
                      delta: float, n_entries: int, steps_per_period: int, max_periods: int) -> dict:
    """Group ``stribeck_stopping`` of ``stribeck.h5``: the fraction of ``n_entries`` steady-state
    entries into the stop zone that accumulate, and Delta x_d (eq. 39), of each (y2'', y3'') of
    ``settings`` against v_s (as in :func:`stribeck_steady`), Moreau
    (:func:`~selfalign.analysis.finite_jerk.stopping`), with the exact static/kinetic and Coulomb
    values (:func:`~selfalign.analysis.positioning.positioning`, same entries)."""
    settings = _pairs(settings)
    fractions = np.asarray(v_s_fractions, dtype=float)
    profiles = [ThreePhaseProfile(dt, dy, y2, y3) for y2, y3 in settings]
    runs = [[stopping(p, w=w, c_mu=c_mu, n_entries=n_entries, steps_per_period=steps_per_period,
                      max_periods=max_periods, friction=stribeck_law(ratio, f * p.velocity_swing, delta))
             for f in fractions] for p in profiles]
    limits = {}
    for name, law in (("static_kinetic", friction_law(ratio)), ("coulomb", FrictionLaw())):
        exact = [positioning(p, w=w, c_mu=c_mu, n_entries=n_entries, max_periods=max_periods, friction=law)
                 for p in profiles]
        limits.update({f"{field}_{name}": np.array([getattr(e, field) for e in exact])
                       for field in ("frac_accumulate", "dx_d")})
    return {"datasets": {"y2": settings[:, 0], "y3": settings[:, 1],
                         "velocity_swing": np.array([p.velocity_swing for p in profiles]),
                         **{field: np.array([[getattr(r, field) for r in row] for row in runs])
                            for field in ("frac_accumulate", "frac_rest", "dx_d")}, **limits},
            "attrs": {"dt": float(dt), "dy": float(dy), "w": float(w), "c_mu": float(c_mu),
                      "n_entries": int(n_entries), "max_periods": int(max_periods)}}


def stribeck_content(v_s_fractions, *, ratio: float, delta: float, steps_per_period: int, steady: dict,
                     entries: dict):
    """Contents of ``results/effects/stribeck.h5``: vbar, accumulation and Delta x_d under the
    Stribeck law (docs/explanation/stopping.md) against v_s / velocity swing
    (``v_s_fraction``, the root's axis).  ``steady``: keyword arguments of
    :func:`stribeck_steady` (dt, dy, settings); ``entries``: those of
    :func:`stribeck_stopping` (dt, dy, w, c_mu, settings, n_entries, max_periods)."""
    fractions = np.asarray(v_s_fractions, dtype=float)
    if fractions.ndim != 1 or fractions.size == 0 or not np.all(np.isfinite(fractions) & (fractions > 0.0)):
        raise ValueError(f"v_s_fractions must be a non-empty 1-D list of finite values > 0, got {v_s_fractions!r}")
    stribeck_law(ratio, 1.0, delta)     # refuses r < 1 or delta <= 0 before any simulation
    law = {"ratio": float(ratio), "delta": float(delta), "steps_per_period": int(steps_per_period)}
    groups = {"stribeck_steady": stribeck_steady(fractions, **steady, **law),
              "stribeck_stopping": stribeck_stopping(fractions, **entries, **law)}
    return {"v_s_fraction": fractions}, law, groups
