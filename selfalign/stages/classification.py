"""Result files of the workflow stage "classification" (Sects. 4.3-5.2,
docs/explanation/stability.md): the (y2'', y3'') maps of Figs. 10 and 11 computed in shards and
gathered, their verification against simulation, and Fig. 6's Fourier optimisation.  Each builder returns the
(datasets, attributes) that :func:`selfalign.io.hdf5.write_h5` writes.
"""

from __future__ import annotations

import math

import numpy as np

from ..analysis.classification import decision_quantities
from ..analysis.fourier_design import (
    OPTIMISER_PERIODS,
    PAPER_FIG6_F,
    FourierOptimum,
    align_to,
    best_three_phase,
    optimise_fourier,
    steady_motion,
)
from ..analysis.steady_simulation import (
    RTOL,
    exact_steady_state,
    simulated_steady_state,
    three_phase_simulated_steady_state,
)
from ..analysis.steady_state import OBJECTIVE_SCALE, steady_state_grid
from ..model.profiles import PolynomialProfile

#: Target of :func:`map_verification`: closed-form and simulated vbar agree to this, relative.
VERIFY_RTOL = 1e-10


#: ... except within |vbar| < VERIFY_BAND * (velocity swing) of vbar = 0 (see map_verification).
VERIFY_BAND = 1e-3


#: 2-D datasets of a map, indexed [i_y2, i_y3].
MAP_FIELDS = ("case", "vbar", "f", "vbar_simulated")


def map_shard(dt: float, dy: float, y2, y3, rows: slice, *, simulate: bool = True, rtol: float = RTOL,
              progress: str = "auto") -> dict:
    """The map rows ``y2[rows]`` x all of ``y3``: closed-form ``case``, ``vbar``, ``f``
    (Sect. 5.1, eq. 11) and, with ``simulate``, ``vbar_simulated`` (batched exact solver,
    module docstring; ``progress``: :mod:`selfalign.progress` mode of its bisection).  Every
    entry depends only on its own (y2, y3), so shards concatenate to the whole map bit for bit."""
    y2 = np.asarray(y2, dtype=float)[rows]
    g2, g3 = np.meshgrid(y2, np.asarray(y3, dtype=float), indexing="ij")
    ss = steady_state_grid(dt, dy, g2, g3)
    out = {"case": ss.case.astype(np.int8), "vbar": ss.vbar, "f": ss.f}
    if simulate:
        out["vbar_simulated"] = three_phase_simulated_steady_state(dt, dy, g2, g3, rtol=rtol,
                                                                   progress=progress).vbar
    return out


def gather_map(dt: float, dy: float, y2, y3, shards: list[dict]) -> tuple[dict, dict]:
    """Datasets and attributes of ``results/classification/fig10.h5`` / ``fig11.h5`` from the
    shards in row order (docs/explanation/stability.md)."""
    y2, y3 = np.asarray(y2, dtype=float), np.asarray(y3, dtype=float)
    data = {"y2": y2, "y3": y3}
    for name in (n for n in MAP_FIELDS if n in shards[0]):
        data[name] = np.concatenate([s[name] for s in shards], axis=0)
        if data[name].shape != (y2.size, y3.size):
            raise ValueError(f"gathered {name!r} has shape {data[name].shape}, expected {(y2.size, y3.size)}")
    return data, {"dt": float(dt), "dy": float(dy)}


def map_verification(data: dict, attrs: dict) -> dict:
    """Agreement of the closed-form vbar with the simulated one over a map (:func:`gather_map` output).

    The target is |vbar_sim - vbar| <= VERIFY_RTOL |vbar|.  Next to the vbar = 0 line
    (inside case 4 or 3) vbar is a small difference of the forward and backward
    areas, and x'(0) of the steady state is itself determined only to ~ulp / (1 - c4)
    (eq. 33) by either computation, so the check is made against
    VERIFY_RTOL max(|vbar|, VERIFY_BAND u), u the table velocity swing (eq. 63).
    Returns ``max_rel_error`` (plain |dv| / |vbar|, 0 where both are 0),
    ``max_scaled_error`` (the checked quantity), ``max_abs_error``,
    ``max_error_over_swing``, ``points`` (feasible points verified),
    ``band_points`` (points with |vbar| < VERIFY_BAND u) and ``passed``.
    """
    ok = data["case"] > 0
    va, vs = data["vbar"][ok], data["vbar_simulated"][ok]
    if np.isnan(vs).any() or np.isnan(va).any():
        raise ValueError("map_verification: a feasible point has no vbar")
    g2, g3 = np.meshgrid(data["y2"], data["y3"], indexing="ij")
    swing = decision_quantities(attrs["dt"], attrs["dy"], g2, g3)["swing"][ok]
    diff = np.abs(vs - va)
    with np.errstate(divide="ignore", invalid="ignore"):
        rel = np.where(diff == 0.0, 0.0, diff / np.abs(va))
    scaled = diff / np.maximum(np.abs(va), VERIFY_BAND * swing)
    return {"max_rel_error": float(rel.max()), "max_scaled_error": float(scaled.max()),
            "max_abs_error": float(diff.max()), "max_error_over_swing": float((diff / swing).max()),
            "points": int(ok.sum()), "band_points": int(np.count_nonzero(np.abs(va) < VERIFY_BAND * swing)),
            "target": VERIFY_RTOL, "band": VERIFY_BAND, "passed": bool(scaled.max() <= VERIFY_RTOL)}


def fig06_results(dt: float, dy: float, yd_max: float, ydd_max: float, *, order: int = 12,
                  max_iter: int = 130, samples_per_period: int = 1000,
                  motion_periods: int = 3, progress: str = "auto") -> tuple[dict, dict, FourierOptimum]:
    """Datasets and attributes of ``results/classification/fig06.h5`` (docs/reference/results.md), and the
    optimisation result itself.

    The optimised profile is time-shifted to match the best three-phase profile
    (:func:`align_to`; the steady state does not depend on the phase).  Profile
    samples cover one period, with y shifted to zero mean (the three-phase y has
    min y = 0); the mass motion covers ``motion_periods`` steady periods.  ``progress``: the
    optimiser's iterations (:mod:`selfalign.progress` mode).
    """
    opt = optimise_fourier(dt, dy, yd_max, ydd_max, order=order, max_iter=max_iter, progress=progress)
    three = best_three_phase(dt, dy, ydd_max, yd_max)
    ss3 = steady_state_grid(dt, dy, three.y2, three.y3)
    best = align_to(opt.profile, three)
    t = np.arange(samples_per_period + 1) * dt / samples_per_period
    data = {"t": t, "history_f": opt.history_f, "cos_coeffs": best.cos_coeffs, "sin_coeffs": best.sin_coeffs,
            "start_cos_coeffs": opt.start.cos_coeffs, "start_sin_coeffs": opt.start.sin_coeffs}
    for name, profile in (("fourier", best), ("start", opt.start), ("three_phase", three)):
        y = profile.position(t)
        data.update({f"{name}_y": y - y[:-1].mean(), f"{name}_yd": profile.velocity(t),
                     f"{name}_ydd": profile.acceleration(t)})
    steady_best = exact_steady_state(best, max_periods=4 * OPTIMISER_PERIODS, aperiodic="average")
    for name, profile, v0 in zip(FIG06_MOTIONS, (best, three), (float(steady_best.v0[0]), float(ss3.v0))):
        for key, values in steady_motion(profile, v0, motion_periods, samples_per_period // 4).items():
            data[f"{name}_motion_{key}"] = values
    attrs = {f"fourier_{k}": v for k, v in opt.settings.items() if k not in ("dt", "dy", "yd_max", "ydd_max")}
    attrs.update(dt=float(dt), dy=float(dy), yd_max=float(yd_max), ydd_max=float(ydd_max),
                 fourier_vbar=opt.vbar, fourier_f=opt.f, start_f=float(opt.history_f[0]),
                 iterations=opt.iterations, evaluations=opt.evaluations, success=opt.success,
                 message=opt.message, three_phase_y2=three.y2, three_phase_y3=three.y3,
                 three_phase_case=int(ss3.case), three_phase_vbar=float(ss3.vbar), three_phase_f=float(ss3.f),
                 three_phase_peak_velocity=float(np.max(np.abs(three.piece_velocity))),
                 paper_f=PAPER_FIG6_F, paper_vbar=float(1.0 / math.sqrt(OBJECTIVE_SCALE * PAPER_FIG6_F)))
    return data, attrs, opt


#: The profiles whose steady motion of the mass ``fig06.h5`` holds.
FIG06_MOTIONS = ("fourier", "three_phase")


def fig06_mass_displacement(result: dict) -> dict:
    """x of the mass relative to the table (the paper's x, which falls where the mass slides
    back) over the steady motions of ``fig06.h5`` (:func:`fig06_results` layout): the
    recorded absolute displacement minus the table's, ``<name>_motion_x_abs - <name>_motion_y``."""
    d = result["datasets"]
    return {name: d[f"{name}_motion_x_abs"] - d[f"{name}_motion_y"] for name in FIG06_MOTIONS}


def polynomial_sweep(dt, dy, *, forward_fraction: float = 0.8, steps_per_period: int = 1000,
                     iteration: str = "exact", rtol: float = RTOL, progress: str = "auto") -> tuple[dict, dict]:
    """Figs. 4 and 5: steady state of the polynomial profile (Sect. 4.2) along a sweep.


    ``dt`` and ``dy`` broadcast to one dimension (one of them is the swept
    array).  Returns datasets ``dt``, ``dy``, and for ``exact`` and ``moreau``:
    ``vbar_*``, ``f_*`` (eq. 11), ``residual_*`` (|x'(dt) - x'(0)| over the
    steady period), ``periods_*`` (periods simulated); and attributes with
    the settings.  ``progress``: :mod:`selfalign.progress` mode of each method's loop.
    """
    dt, dy = (np.atleast_1d(a).astype(float) for a in np.broadcast_arrays(dt, dy))
    if dt.ndim != 1:
        raise ValueError(f"dt and dy must broadcast to one dimension, got shape {dt.shape}")
    profiles = [PolynomialProfile(t, s, forward_fraction) for t, s in zip(dt.tolist(), dy.tolist())]
    data = {"dt": dt, "dy": dy}
    for method in ("exact", "moreau"):
        res = simulated_steady_state(profiles, method, steps_per_period=steps_per_period,
                                     iteration=iteration, rtol=rtol, progress=progress)
        data.update({f"vbar_{method}": res.vbar, f"f_{method}": res.f, f"residual_{method}": res.residual,
                     f"periods_{method}": res.periods})
    attrs = {"forward_fraction": float(forward_fraction), "moreau_steps_per_period": int(steps_per_period),
             "moreau_iteration": iteration, "rtol": float(rtol), "objective_scale": OBJECTIVE_SCALE}
    return data, attrs
