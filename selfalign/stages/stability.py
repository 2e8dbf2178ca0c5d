"""Result files of the workflow stage "stability" (Sect. 6.1, docs/explanation/stability.md): every Floquet
method of :func:`selfalign.analysis.floquet.floquet` on one scene's steady state, and over a
(y2'', y3'') grid of three-phase profiles.  Each builder returns the (datasets, attributes) that
:func:`selfalign.io.hdf5.write_h5` writes.
"""

from __future__ import annotations

import numpy as np

from ..analysis.floquet import EXACT_EPS, analytic_applies, eigen, floquet, moreau_monodromies
from ..model.friction import StopZone, Uniform
from ..model.profiles import ThreePhaseProfile
from ..model.scene import Scene


def _method_runs(analytic: bool):
    """(label, method, options) of the methods compared for one system; the first is the reference."""
    runs = [("analytic", "analytic", {})] if analytic else []
    return runs + [("saltation", "saltation", {}), ("numeric_exact", "numeric", {"solver": "exact"}),
                   ("numeric_moreau", "numeric", {"solver": "moreau"})]


def stability_result(scene: Scene, moreau_steps=(100, 1000, 10000), moreau_eps=(1e-4, 1e-3, 1e-2)):
    """Datasets and attributes of ``results/stability/<scene>.h5`` (docs/reference/results.md).

    Every method of :func:`floquet` on the scene's steady state: ``methods`` (labels;
    the first is the reference: analytic where it applies, else saltation),
    ``monodromy`` (methods, 2, 2), ``multipliers`` (methods, 2; complex),
    ``monodromy_error`` and ``multiplier_error`` (max abs difference from the
    reference).  The Moreau estimate for every pair of ``moreau_steps`` (steps per
    period N, h = dt / N) and ``moreau_eps``: ``moreau_monodromy`` (N, eps, 2, 2),
    ``moreau_multipliers`` (N, eps, 2), ``moreau_multiplier_error`` (N, eps).
    """
    import yaml

    profile, surface = scene.profile, scene.surface
    runs = _method_runs(analytic_applies(scene))
    results = [floquet(scene, method, **opts) for _, method, opts in runs]
    ref, by = results[0], {label: r for (label, _, _), r in zip(runs, results)}
    mono = np.array([r.monodromy for r in results])
    mult = np.array([r.multipliers for r in results], dtype=complex)
    steps = np.asarray(moreau_steps, dtype=int)
    eps = np.asarray(moreau_eps, dtype=float)
    scan = [[floquet(scene, "numeric", solver="moreau", h=profile.dt / n, eps=float(e)) for e in eps]
            for n in steps]
    scan_mult = np.array([[r.multipliers for r in row] for row in scan], dtype=complex)
    motion = ref.motion
    datasets = {
        "methods": np.array([label for label, _, _ in runs]),
        "monodromy": mono,
        "multipliers": mult,
        "monodromy_error": np.abs(mono - ref.monodromy).max(axis=(1, 2)),
        "multiplier_error": np.abs(mult - ref.multipliers).max(axis=1),
        "moreau_steps": steps,
        "moreau_eps": eps,
        "moreau_monodromy": np.array([[r.monodromy for r in row] for row in scan]),
        "moreau_multipliers": scan_mult,
        "moreau_multiplier_error": np.abs(scan_mult - ref.multipliers).max(axis=2),
    }
    attrs = dict(profile.params())
    attrs.update(surface=surface.params() if isinstance(surface, StopZone) else {"kind": "uniform"},
                 reference=runs[0][0], x0=motion.x0, v0=motion.v0, phase=motion.phase,
                 orbit_periods=motion.periods, advance=motion.advance, orbit_source=motion.source,
                 exact_eps=by["numeric_exact"].info["eps"], moreau_h=by["numeric_moreau"].info["h"],
                 moreau_default_eps=by["numeric_moreau"].info["eps"],
                 saltation_events=by["saltation"].info["events"],
                 grazing_events=by["saltation"].info["grazing_events"], scene_name=scene.name,
                 scene=yaml.safe_dump(scene.to_dict(), sort_keys=False))
    if isinstance(profile, ThreePhaseProfile) and isinstance(surface, Uniform):
        from ..analysis.steady_state import steady_state

        attrs["case"] = steady_state(profile).case
    return datasets, attrs


def stability_grid(dt: float, dy: float, y2, y3, moreau_steps: int = 1000):
    """Datasets and attributes of ``results/stability/grid_<name>.h5``: every method over the
    (y2'', y3'') grid of three-phase profiles with the given dt, dy (uniform surface).

    ``y2`` (n,), ``y3`` (m,), ``case`` (n, m), ``methods``, ``monodromy`` (methods, n, m, 2, 2),
    ``multipliers`` (methods, n, m, 2; all real here: the monodromy is upper triangular),
    ``monodromy_error``, ``multiplier_error`` (methods, n, m) against the analytic method;
    NaN where the profile is infeasible (case 0).  Moreau: ``moreau_steps`` steps per
    period and eps = sqrt(h).
    """
    from ..analysis.steady_state import monodromy_grid, steady_state_grid

    y2, y3 = np.asarray(y2, dtype=float), np.asarray(y3, dtype=float)
    g2, g3 = np.meshgrid(y2, y3, indexing="ij")
    ss = steady_state_grid(dt, dy, g2, g3)
    labels = ["analytic", "saltation", "numeric_exact", "numeric_moreau"]
    mono = np.full((len(labels),) + g2.shape + (2, 2), np.nan)
    mono[0] = monodromy_grid(dt, dy, g2, g3)
    feasible = np.argwhere(ss.case > 0)
    profiles = [ThreePhaseProfile(dt, dy, g2[i, j], g3[i, j]) for i, j in feasible]
    for (i, j), p in zip(feasible, profiles):
        mono[1, i, j] = floquet(p, "saltation").monodromy
        mono[2, i, j] = floquet(p, "numeric").monodromy
    if profiles:
        mono[3][tuple(feasible.T)] = moreau_monodromies(profiles, ss.v0[tuple(feasible.T)], int(moreau_steps))
    mult = np.full(mono.shape[:-1], np.nan)
    for k, label in enumerate(labels):
        for i, j in feasible:
            w, _ = eigen(mono[k, i, j])
            if np.iscomplexobj(w):
                raise ValueError(f"{label} monodromy at y2 = {y2[i]!r}, y3 = {y3[j]!r} has complex "
                                 f"multipliers {w.tolist()}: expected an upper triangular matrix")
            mult[k, i, j] = w
    datasets = {
        "y2": y2, "y3": y3, "case": ss.case, "methods": np.array(labels), "monodromy": mono,
        "multipliers": mult,
        "monodromy_error": np.abs(mono - mono[0]).max(axis=(-2, -1)),
        "multiplier_error": np.abs(mult - mult[0]).max(axis=-1),
    }
    with np.errstate(invalid="ignore"):
        worst = {label: float(np.nanmax(datasets["monodromy_error"][k])) if profiles else float("nan")
                 for k, label in enumerate(labels)}
    attrs = {"dt": float(dt), "dy": float(dy), "moreau_steps": int(moreau_steps),
             "exact_eps": EXACT_EPS, "max_monodromy_error": worst}
    return datasets, attrs
