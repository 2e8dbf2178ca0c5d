"""Result files of the workflow stage "accumulation" (Sect. 7, docs/explanation/stopping.md):
the Fig. 17 sweep computed in shards and gathered, the accumulation map of Fig. 18 and the phase
portraits of Figs. 14-16.  Each builder returns the (datasets, attributes[, groups]) that
:func:`selfalign.io.hdf5.write_h5` writes.
"""

from __future__ import annotations

import numpy as np

from ..analysis.positioning import MAX_PERIODS, positioning, positioning_grid
from ..analysis.stick_map import (
    stick_map,
    stick_map_contraction,
    stick_map_simulated,
    stick_map_threshold,
    stick_map_validity,
)
from ..model.friction import StopZone
from ..model.profiles import ThreePhaseProfile
from ..model.scene import Record, Scene
from ..solvers.driver import simulate
from ..solvers.outcomes import EventKind

#: Root attributes of fig17.h5 that every shard carries alike (besides ``events``, summed).
FIG17_SETTING = ("dt", "dy", "w", "c_mu", "n_entries", "max_periods", "offset", "positions")


#: 2-D [i_y2, i_y3] and 3-D [i_y2, i_y3, level] datasets of fig17.h5, split by rows across shards.
FIG17_FIELDS = ("case", "vbar", "f", "dx_d", "frac_accumulate", "frac_stop", "frac_never_stop", "frac_undecided",
                "x_stick_min", "overshoot_min", "overshoot_max", "contraction", "level_from_first_stick",
                "level_from_entry", "level_sticks")


def fig17_shard(y2, y3, rows: slice, *, dt: float, dy: float, w: float, c_mu: float, n_entries: int,
                max_periods: int = MAX_PERIODS, levels=(0.99, 0.999), processes: int = 1, progress: str = "auto"):
    """Datasets and attributes of one shard of the Fig. 17 sweep: the rows ``y2[rows]`` x all of ``y3``
    (``progress``: :mod:`selfalign.progress` mode of the settings done).

    Datasets: :data:`FIG17_FIELDS` for those rows and ``levels``; attributes: those of
    :func:`fig17_content` (``events`` counted over the shard) plus ``row_start``,
    ``row_stop``, ``row_step`` (the slice ``rows``).  Every setting is simulated on its own
    (batched, no coupling between members), so shards that cover the rows once
    (:func:`selfalign.stages.common.shard_rows`, contiguous or interleaved) gather
    (:func:`gather_fig17`) to the whole sweep bit for bit, for any number of shards.
    """
    y2, y3 = np.asarray(y2, dtype=float), np.asarray(y3, dtype=float)
    if y2.ndim != 1 or y3.ndim != 1:
        raise ValueError("y2 and y3 must be 1-D axes of the grid")
    g2, g3 = np.meshgrid(y2[rows], y3, indexing="ij")
    grid = positioning_grid(dt, dy, g2, g3, w=w, c_mu=c_mu, n_entries=n_entries, max_periods=max_periods,
                            levels=levels, processes=processes, progress=progress)
    datasets = {name: getattr(grid, name) for name in FIG17_FIELDS + ("levels",)}
    start, stop, step = rows.indices(y2.size)
    attrs = {"dt": float(dt), "dy": float(dy), "w": float(w), "c_mu": float(c_mu), "n_entries": int(n_entries),
             "max_periods": int(max_periods), "offset": 0.5, "events": grid.events,
             "positions": "x_stick_min, overshoot_min, overshoot_max are relative to x_mu = Delta_x",
             "row_start": start, "row_stop": stop, "row_step": step}
    return datasets, attrs


def gather_fig17(y2, y3, shards: list[dict]):
    """Datasets and attributes of ``results/accumulation/fig17.h5`` from the shards of
    :func:`fig17_shard`, each a dict with ``datasets`` and ``attrs`` (as
    :func:`selfalign.io.hdf5.read_h5` returns it).  Together the shards must cover every row
    of ``y2`` exactly once, with the same setting; each row is put back in its place, and
    ``events`` is their sum."""
    y2, y3 = np.asarray(y2, dtype=float), np.asarray(y3, dtype=float)
    if not shards:
        raise ValueError("gather_fig17: no shards given")
    setting = {k: shards[0]["attrs"][k] for k in FIG17_SETTING}
    for i, shard in enumerate(shards):
        same_levels = np.array_equal(shard["datasets"]["levels"], shards[0]["datasets"]["levels"])
        if {k: shard["attrs"][k] for k in FIG17_SETTING} != setting or not same_levels:
            raise ValueError(f"gather_fig17: shard {i} was computed with another setting than shard 0")
    # order[k]: the row of y2 that the k-th concatenated shard row belongs to.
    order = np.concatenate([np.arange(y2.size)[slice(int(a["row_start"]), int(a["row_stop"]), int(a["row_step"]))]
                            for a in (s["attrs"] for s in shards)])
    if not np.array_equal(np.sort(order), np.arange(y2.size)):
        raise ValueError(f"gather_fig17: the shards do not cover each of the {y2.size} rows of y2 exactly once")
    place = np.argsort(order)
    datasets = {"y2": y2, "y3": y3}
    for name in FIG17_FIELDS:
        datasets[name] = np.concatenate([s["datasets"][name] for s in shards], axis=0)[place]
        if datasets[name].shape[:2] != (y2.size, y3.size):
            raise ValueError(f"gather_fig17: {name!r} has shape {datasets[name].shape}, expected "
                             f"{(y2.size, y3.size)} in its first two axes")
    datasets["levels"] = shards[0]["datasets"]["levels"]
    return datasets, {**setting, "events": int(sum(int(s["attrs"]["events"]) for s in shards))}


def fig17_content(y2, y3, *, dt: float, dy: float, w: float, c_mu: float, n_entries: int,
                  max_periods: int = MAX_PERIODS, levels=(0.99, 0.999), processes: int = 1,
                  progress: str = "auto"):
    """Datasets and attributes of ``results/accumulation/fig17.h5`` (Fig. 17, Sect. 7.2), in one piece.

    1-D ``y2``, ``y3``; 2-D [i_y2, i_y3]: ``case``, ``vbar``, ``f`` (steady state),
    ``dx_d`` (eq. 39, NaN where no entry stops or the mass never reaches the zone),
    ``frac_accumulate``, ``frac_stop``, ``frac_never_stop``, ``frac_undecided``,
    ``x_stick_min``, ``overshoot_min``, ``overshoot_max`` (all three relative to x_mu),
    ``contraction``; 3-D [i_y2, i_y3, level]: ``level_from_first_stick``,
    ``level_from_entry``, ``level_sticks`` (worst case over accumulating entries);
    1-D ``levels``.  The workflow computes the same in shards (:func:`fig17_shard`,
    :func:`gather_fig17`).
    """
    y2 = np.asarray(y2, dtype=float)
    datasets, attrs = fig17_shard(y2, y3, slice(0, y2.size), dt=dt, dy=dy, w=w, c_mu=c_mu, n_entries=n_entries,
                                  max_periods=max_periods, levels=levels, processes=processes,
                                  progress=progress)
    return gather_fig17(y2, y3, [{"datasets": datasets, "attrs": attrs}])


def stick_positions(traj) -> np.ndarray:
    """Positions of the STICK events in the event log of ``traj``, in order."""
    return traj.events[traj.events["kind"] == EventKind.STICK]["x"]


def fig18_content(profile: ThreePhaseProfile, *, w: float, c_mu: float, x_mu: float = 0.0, points: int = 61,
                  cobweb_periods: int = 30):
    """Datasets and attributes of ``results/accumulation/fig18.h5`` (Fig. 18, Sect. 7.3).

    ``x_n`` (``points`` positions on [x_mu, x_mu + w]), ``x_next_formula`` (eq. 59),
    ``x_next_simulated`` (exact solver, :func:`stick_map_simulated`), ``valid``;
    ``cobweb_accumulate`` / ``cobweb_rest``: the stick positions of exact runs started
    stuck at t = 0 just above / below the threshold x_c (:func:`stick_map_threshold`).
    Attributes: the profile, w, c_mu, x_mu, x_stick_min, x_threshold, contraction.
    """
    zone = StopZone(x_mu=x_mu, w=w, c_mu=c_mu)
    kw = {"w": w, "c_mu": c_mu, "x_mu": x_mu}
    x_n = np.linspace(x_mu, zone.x_end, points)
    x_stick = zone.x_stick_min(profile.max_abs_acceleration)
    x_c = float(stick_map_threshold(profile, **kw))

    def cobweb(x0):
        traj = simulate(Scene(profile, zone, x0=x0, periods=cobweb_periods, record=Record(events=True)),
                        method="exact")
        return np.concatenate([[x0], stick_positions(traj)])

    gap = 0.25 * min(x_c - x_mu, x_stick - x_c)
    datasets = {
        "x_n": x_n, "x_next_formula": stick_map(x_n, profile, **kw),
        "x_next_simulated": stick_map_simulated(x_n, profile, **kw, method="exact"),
        "valid": stick_map_validity(x_n, profile, **kw).valid,
        "cobweb_accumulate": cobweb(x_c + gap), "cobweb_rest": cobweb(x_c - gap),
    }
    attrs = {**profile.params(), "w": float(w), "c_mu": float(c_mu), "x_mu": float(x_mu), "x_stick_min": x_stick,
             "x_threshold": x_c, "contraction": stick_map_contraction(profile, **kw)}
    return datasets, attrs


def setting_group(y2: float, y3: float) -> str:
    """Name of the group of the (y2'', y3'') setting in ``fig16.h5``."""
    return f"y2_{y2:g}_y3_{y3:g}"


def fig16_content(settings, *, dt: float, dy: float, w: float, c_mu: float, n_entries: int = 64,
                  samples_per_period: int = 400):
    """Contents of ``results/accumulation/fig16.h5`` (Figs. 14-16, Sects. 7.1-7.2) for write_h5.

    One group per setting (y2'', y3'') named ``y2_<y2>_y3_<y3>``: the per-entry
    results of :func:`positioning` (``s``, ``x0``, ``status``, ``x_end``, ``overshoot``,
    ``first_stick_x``) and its scalars as attributes, plus subgroups ``entry_0`` and
    ``entry_1`` with the exact solver's dense ``t``, ``x``, ``v`` and the positions of all
    its sticks ``stick_x`` (from the event log, exact) of the two entries with the lowest and
    the highest first stick in the zone (attribute ``index``).
    """
    groups = {}
    for y2, y3 in settings:
        profile = ThreePhaseProfile(dt, dy, y2, y3)
        pos = positioning(profile, w=w, c_mu=c_mu, n_entries=n_entries)
        entries = {}
        for k, i in enumerate((int(np.nanargmin(pos.first_stick_x)), int(np.nanargmax(pos.first_stick_x)))):
            traj = simulate(Scene(profile, pos.zone, x0=float(pos.x0[i]), v0=pos.v0, until="rest",
                                  max_periods=MAX_PERIODS,
                                  record=Record(series=("x", "v"), samples_per_period=samples_per_period,
                                                events=True)),
                            method="exact")
            entries[f"entry_{k}"] = {"datasets": {"t": traj.t, "x": traj.x, "v": traj.v,
                                                  "stick_x": stick_positions(traj)},
                                     "attrs": {"index": i, "status": traj.status.value, "x_end": traj.x_end}}
        scalars = ("x_mu", "x_stick_min", "overshoot_min", "overshoot_max", "dx_d", "x_d", "vbar", "v0",
                   "frac_accumulate", "frac_stop", "frac_never_stop", "frac_undecided", "accumulation", "case")
        groups[setting_group(y2, y3)] = {
            "datasets": {name: getattr(pos, name) for name in ("s", "x0", "status", "x_end", "overshoot",
                                                                "first_stick_x")},
            "attrs": {"y2": float(y2), "y3": float(y3), **{name: getattr(pos, name) for name in scalars}},
            "groups": entries,
        }
    attrs = {"dt": float(dt), "dy": float(dy), "w": float(w), "c_mu": float(c_mu), "n_entries": int(n_entries)}
    return {}, attrs, groups
