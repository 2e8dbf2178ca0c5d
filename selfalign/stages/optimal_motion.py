"""Result file of the workflow stage "optimal_motion" (docs/explanation/fig6-revisited.md): Fig. 6 of the
paper (Sect. 4.4.2) revisited with the fastest table motion.

Under the actuator limits of Fig. 6 (period dt, |y''| <= a, |y'| <= V, stroke <= S) four answers are set
side by side: the paper's reported optimum (its caption's f), the project's Fourier optimum of each order
(:func:`selfalign.analysis.fourier_design.optimise_fourier`, a local SQP from the polynomial profile), the
best three-phase profile of Sect. 4.4.3 meeting the same limits (:func:`three_phase_under_limits`) and the
fastest motion found by :func:`selfalign.analysis.optimal_motion.optimal_profile`, with the bound v* of the
acceleration limit alone.  Two sweeps move a and S away from Fig. 6.  The optimum truncated to N harmonics
and scaled into the limits (:func:`fourier_truncation`) is a Fourier motion of order N that meets them: it
shows what a series of that order can reach, against what the SQP finds.

:func:`fig06_revisited_results` builds ``results/optimal_motion/fig06_revisited.h5``; every number in it
follows from the settings (no times are stored), so two runs write the same bytes.
"""

from __future__ import annotations

from collections.abc import Mapping

import numpy as np

from ..analysis.fourier_design import (
    OPTIMISER_PERIODS,
    PAPER_FIG6_F,
    best_three_phase,
    fourier_projection,
    optimise_fourier,
    steady_motion,
)
from ..analysis.optimal_motion import centred_motion, optimal_profile
from ..analysis.steady_simulation import exact_steady_state, objective
from ..analysis.steady_state import OBJECTIVE_SCALE, steady_state_grid
from ..model.profiles import FourierProfile, ThreePhaseProfile
from .common import range_values

#: The limits, in the order the results list them.
LIMITS = ("accel_max", "velocity_max", "stroke_max")
#: A limit is binding when a motion uses all but this fraction of it (or more: the Fourier SQP meets its
#: limits on sample times only, so its peaks may exceed them by ~1e-4).
BINDING = 1e-3
#: Strokes q S tried per pass of :func:`three_phase_under_limits`, passes after the first, and the grid
#: size of each (y2'', y3'') search (:func:`~selfalign.analysis.fourier_design.best_three_phase`).
STROKE_SCAN, STROKE_ZOOMS, THREE_PHASE_GRID = 8, 2, 101
#: Samples per period of the steady motion whose slides ``_slide_structure`` counts.
STRUCTURE_SAMPLES = 4000


def _steady_vbar(profile) -> tuple[float, float]:
    """(vbar, x'(0)) of the steady motion the exact solver reaches from rest at t = 0 on a uniform surface
    (eq. 10; the time average over the second half of :data:`OPTIMISER_PERIODS` periods if it never repeats,
    as in the Fourier optimisation)."""
    steady = exact_steady_state(profile, max_periods=OPTIMISER_PERIODS, aperiodic="average")
    return float(steady.vbar[0]), float(steady.v0[0])


def _limits_used(profile) -> tuple[float, float, float]:
    """(peak acceleration max |y''|, peak speed max |y'|, stroke max y - min y) of a Fourier or a
    piecewise-constant table motion (y' of zero mean, as a periodic y needs)."""
    if isinstance(profile, FourierProfile):
        return profile.peak_acceleration, profile.peak_velocity, profile.stroke
    _, _, speed, stroke = centred_motion(profile.breaks, profile.accels)
    return float(np.max(np.abs(profile.accels))), speed, stroke


def _binding(used, limits) -> str:
    """The names of :data:`LIMITS` that ``used`` (same order) reaches within :data:`BINDING`, joined by
    ", "."""
    return ", ".join(name for name, u, limit in zip(LIMITS, used, limits) if u >= (1.0 - BINDING) * limit)


def three_phase_under_limits(period: float, accel_max: float, stroke_max: float,
                             velocity_max: float) -> tuple[ThreePhaseProfile, float]:
    """The fastest three-phase profile (Sect. 4.4.3) with y2'', y3'' <= ``accel_max``, ``|y'|`` <=
    ``velocity_max`` and a stroke dy <= ``stroke_max``, and its vbar (closed form, Sect. 5.1).

    Parameters
    ----------
    period : float
        dt, dimensionless (Sect. 3.2).
    accel_max, stroke_max, velocity_max : float
        The limits a, S and V.

    Returns
    -------
    tuple of (ThreePhaseProfile, float)
        The profile and its vbar.

    Raises
    ------
    ValueError
        If no physical three-phase profile meets the limits at any stroke tried.

    Notes
    -----
    The stroke is a free parameter of the family, and under a speed limit the largest stroke need not be the
    best (at a = 1275, V = 3.2, S = 0.05 a stroke of 0.04 moves the part twice as fast as 0.05).  So the
    stroke q S is searched: :data:`STROKE_SCAN` values of q in (0, 1], then :data:`STROKE_ZOOMS` times as many
    around the best, each with the (y2'', y3'') grid search of ``best_three_phase``
    (:data:`THREE_PHASE_GRID` points a side, refined three times); at the best stroke that search runs once
    more on its default grid, as for Fig. 6.

    Examples
    --------
    >>> from selfalign.stages.optimal_motion import three_phase_under_limits
    >>> profile, vbar = three_phase_under_limits(0.072, 1275.0, 0.021, 3.2)
    >>> print(round(profile.dy, 4), round(vbar, 3))
    0.021 0.506
    """
    def fastest(q):
        """(vbar, profile) at the stroke q S; (-inf, None) where no physical profile meets the limits."""
        try:
            profile = best_three_phase(period, q * stroke_max, accel_max, velocity_max, num=THREE_PHASE_GRID)
        except ValueError:      # best_three_phase's "no feasible three-phase profile"
            return -np.inf, None
        return float(steady_state_grid(period, profile.dy, profile.y2, profile.y3).vbar), profile

    low, high, best = 0.0, 1.0, (-np.inf, None, None)
    for _ in range(STROKE_ZOOMS + 1):
        step = (high - low) / STROKE_SCAN
        for q in low + step * np.arange(1, STROKE_SCAN + 1):
            vbar, profile = fastest(float(q))
            if vbar > best[0]:
                best = (vbar, profile, float(q))
        if best[1] is None:
            raise ValueError(f"no physical three-phase profile with dt = {period!r}, a stroke <= {stroke_max!r}, "
                             f"y'' <= {accel_max!r} and |y'| <= {velocity_max!r}")
        low, high = max(best[2] - step, 0.0), min(best[2] + step, 1.0)
    profile = best_three_phase(period, best[2] * stroke_max, accel_max, velocity_max)
    return profile, float(steady_state_grid(period, profile.dy, profile.y2, profile.y3).vbar)


def fourier_truncation(profile, order: int, accel_max: float, stroke_max: float,
                       velocity_max: float) -> tuple[FourierProfile, float]:
    """The first ``order`` harmonics of a table motion, scaled down until they meet the limits.

    Parameters
    ----------
    profile : Profile
        A periodic table motion (here the fastest one).
    order : int
        N, the harmonics kept.
    accel_max, stroke_max, velocity_max : float
        The limits a, S and V.

    Returns
    -------
    tuple of (FourierProfile, float)
        The truncated, scaled motion (a Fourier motion of order N within the limits) and the scale factor
        (1 when the truncation already meets them).

    Raises
    ------
    ValueError
        If ``order`` is not an integer >= 1.

    Notes
    -----
    A truncated series overshoots the jumps of y'' (Gibbs) and rounds them off: the scale is the factor its
    peaks leave.  Its vbar bounds from below what the best Fourier motion of order N reaches.

    Examples
    --------
    >>> from selfalign.model.profiles import ThreePhaseProfile
    >>> from selfalign.stages.optimal_motion import fourier_truncation
    >>> motion, scale = fourier_truncation(ThreePhaseProfile(1.0, 0.05, 2.0, 1.0), 4, 2.0, 0.05, 1.0)
    >>> print(motion.order, round(scale, 3), motion.peak_acceleration <= 2.0, motion.stroke <= 0.05)
    4 0.844 True True
    """
    if isinstance(order, bool) or not isinstance(order, (int, np.integer)) or order < 1:
        raise ValueError(f"order must be an integer >= 1, got {order!r}")
    full = fourier_projection(profile, int(order))
    scale = min(1.0, *(limit / used for limit, used in zip((accel_max, velocity_max, stroke_max),
                                                           _limits_used(full))))
    return FourierProfile(full.dt, scale * full.cos_coeffs, scale * full.sin_coeffs), float(scale)


def _slide_structure(profile, v0: float) -> tuple[int, int, float]:
    """(forward slides, backward slides, backward loss) of one steady period of ``profile`` from x'(0) =
    ``v0`` (exact solver, :data:`STRUCTURE_SAMPLES` samples a period plus every event): the slides are the
    runs of x' > 0 and of x' < 0 around the period, the loss is int max(-x', 0) dt over int max(x', 0) dt,
    the share of the forward advance that backward slides take back (the proof of the bound has none,
    docs/explanation/optimal-motion.md)."""
    motion = steady_motion(profile, v0, periods=1, samples_per_period=STRUCTURE_SAMPLES)
    t, v = motion["t"], motion["v"]
    ahead, back = np.maximum(v, 0.0), np.maximum(-v, 0.0)
    forward = float(np.sum(np.diff(t) * (ahead[1:] + ahead[:-1]))) / 2.0
    backward = float(np.sum(np.diff(t) * (back[1:] + back[:-1]))) / 2.0
    sign = np.sign(v[:-1])
    runs = [int(np.count_nonzero((sign == s) & (np.roll(sign, 1) != s))) or int(np.all(sign == s)) for s in (1, -1)]
    return runs[0], runs[1], backward / forward if forward > 0.0 else float("nan")


class _Study:
    """The computations at each (a, S) of one study, each done once (the sweeps meet Fig. 6's limits)."""

    def __init__(self, period: float, velocity_max: float, max_iter: int, progress: str):
        self.period, self.velocity_max, self.max_iter, self.progress = period, velocity_max, max_iter, progress
        self.points: dict = {}
        self.fourier: dict = {}

    def point(self, a: float, s: float, truncations) -> dict:
        """The optimum, the three-phase profile and the optimum's truncations to ``truncations`` harmonics."""
        key = (a, s)
        if key not in self.points:
            best = optimal_profile(self.period, a, stroke_max=s, velocity_max=self.velocity_max)
            three, vbar = three_phase_under_limits(self.period, a, s, self.velocity_max)
            self.points[key] = {"optimal": best, "three_phase": three, "vbar_three_phase": vbar, "truncated": {}}
        known = self.points[key]["truncated"]
        for n in truncations:
            if n not in known:
                motion, scale = fourier_truncation(self.points[key]["optimal"].profile, n, a, s, self.velocity_max)
                known[n] = (scale, _steady_vbar(motion)[0])
        return self.points[key]

    def sqp(self, a: float, s: float, order: int):
        """The Fourier optimum of ``order`` (SQP from the polynomial profile, Fig. 6's method)."""
        key = (a, s, order)
        if key not in self.fourier:
            self.fourier[key] = optimise_fourier(self.period, s, self.velocity_max, a, order=order,
                                                 max_iter=self.max_iter, progress=self.progress)
        return self.fourier[key]

    def sweep(self, values, name: str, fixed: dict, orders, fourier_at) -> dict:
        """The group of one sweep of the limit ``name`` (``accel_max`` or ``stroke_max``) over ``values``
        joined with ``fourier_at``, the other limits ``fixed``: every curve, the Fourier SQP at the values
        of ``fourier_at`` only (NaN elsewhere)."""
        chosen = set(map(float, fourier_at))
        axis = sorted(set(map(float, values)) | chosen)
        pairs = [(x, fixed["stroke_max"]) if name == "accel_max" else (fixed["accel_max"], x) for x in axis]
        points = [self.point(a, s, orders) for a, s in pairs]
        sqp = [[self.sqp(a, s, n).vbar if x in chosen else np.nan for x, (a, s) in zip(axis, pairs)]
               for n in orders]
        return {"datasets": {name: np.array(axis), "orders": np.asarray(orders, dtype=np.int64),
                             "vbar_optimal": np.array([p["optimal"].vbar for p in points]),
                             "vbar_bound": np.array([p["optimal"].vbar_bound for p in points]),
                             "vbar_three_phase": np.array([p["vbar_three_phase"] for p in points]),
                             "three_phase_stroke": np.array([p["three_phase"].dy for p in points]),
                             "vbar_truncated": np.array([[p["truncated"][n][1] for p in points] for n in orders]),
                             "vbar_fourier": np.array(sqp, dtype=float)},
                "attrs": {k: float(x) for k, x in fixed.items() if k != name}}


def fig06_revisited_results(settings: Mapping, progress: str = "auto") -> tuple[dict, dict, dict]:
    """(datasets, attrs, groups) of ``results/optimal_motion/fig06_revisited.h5``.

    Parameters
    ----------
    settings : Mapping
        The stage's config block (``workflow/config/config.yaml``, ``stages.optimal_motion``): ``period``,
        ``accel_max``, ``stroke_max``, ``velocity_max`` (Fig. 6's limits), ``orders`` (Fourier orders of the
        SQP), ``max_iter`` (its iteration budget), ``truncation_orders`` (orders of the optimum's truncation at
        Fig. 6's limits), ``accel_sweep`` and ``stroke_sweep`` (config ranges of a and S, the other limits
        those of Fig. 6), ``fourier_accel_max`` and ``fourier_stroke_max`` (the values of each sweep at which
        the SQP runs; they join the sweep's axis).
    progress : str
        :mod:`selfalign.progress` mode of the SQP runs.

    Returns
    -------
    tuple of (dict, dict, dict)
        No root datasets; root attributes (the limits, c of eq. 11, the paper's f, the SQP's budget, stop
        reasons and iterations at Fig. 6's limits); the groups ``comparison`` (one entry per answer at Fig. 6's
        limits), ``truncation``, ``accel_sweep`` and ``stroke_sweep`` (docs/explanation/fig6-revisited.md;
        every dataset on the result-quantities page).

    Raises
    ------
    ValueError
        From the analyses, for limits they refuse (e.g. ``accel_max`` <= 1: nothing moves).

    Examples
    --------
    The workflow's settings take about a minute (the Fourier SQP of every order); a small study at a = 300,
    order 4 and three SQP iterations, at one point per sweep, takes a few seconds:

    >>> import yaml
    >>> from selfalign.stages.optimal_motion import fig06_revisited_results
    >>> settings = yaml.safe_load(open("workflow/config/config.yaml"))["stages"]["optimal_motion"]
    >>> one = {"from": 1.0, "to": 1.0, "count": 1, "scale": "linear"}
    >>> settings.update(accel_max=300.0, orders=[4], max_iter=3, truncation_orders=[4, 12],
    ...                 accel_sweep={**one, "from": 300.0, "to": 300.0}, fourier_accel_max=[300.0],
    ...                 stroke_sweep={**one, "from": 0.021, "to": 0.021}, fourier_stroke_max=[0.021])
    >>> _, _, groups = fig06_revisited_results(settings, progress="quiet")
    >>> c = groups["comparison"]["datasets"]
    >>> print(c["entry"].tolist(), [round(float(v), 4) for v in c["vbar"]])
    ['paper', 'three_phase', 'fourier_4', 'optimal', 'bound'] [0.0013, 0.5055, 0.3547, 0.6994, 1.35]
    """
    period, a, s, v = (float(settings[k]) for k in ("period", "accel_max", "stroke_max", "velocity_max"))
    limits = (a, v, s)
    orders, truncations = ([int(n) for n in settings[key]] for key in ("orders", "truncation_orders"))
    study = _Study(period, v, int(settings["max_iter"]), progress)
    here = study.point(a, s, truncations)
    best, three = here["optimal"], here["three_phase"]
    fourier = [study.sqp(a, s, n) for n in orders]
    entries = ["paper"] + ["three_phase"] + [f"fourier_{n}" for n in orders] + ["optimal", "bound"]
    paper_vbar = float(1.0 / np.sqrt(OBJECTIVE_SCALE * PAPER_FIG6_F))
    motions = [three] + [opt.profile for opt in fourier] + [best.profile]
    steady = [_steady_vbar(m) for m in motions]
    used = [_limits_used(m) for m in motions]
    structure = [_slide_structure(m, v0) for m, (_, v0) in zip(motions, steady)]
    nan3 = (np.nan, np.nan, np.nan)
    vbar = np.array([paper_vbar] + [vb for vb, _ in steady] + [best.vbar_bound])
    table = np.array([nan3] + used + [(a, np.nan, np.nan)])
    slides = np.array([nan3] + structure + [nan3])
    comparison = {"entry": np.array(entries), "vbar": vbar, "f": objective(vbar),
                  "peak_acceleration": table[:, 0], "peak_velocity": table[:, 1], "stroke": table[:, 2],
                  "binding": np.array([""] + [_binding(u, limits) for u in used] + ["accel_max"]),
                  "forward_slides": slides[:, 0], "backward_slides": slides[:, 1], "backward_loss": slides[:, 2],
                  "share_of_optimum": vbar / best.vbar}
    truncation = {"orders": np.array(truncations, dtype=np.int64),
                  "scale": np.array([here["truncated"][n][0] for n in truncations]),
                  "vbar": np.array([here["truncated"][n][1] for n in truncations])}
    fixed = {"period": period, "accel_max": a, "stroke_max": s, "velocity_max": v}
    groups = {"comparison": {"datasets": comparison},
              "truncation": {"datasets": truncation},
              "accel_sweep": study.sweep(range_values(settings["accel_sweep"]), "accel_max", fixed, orders,
                                         settings["fourier_accel_max"]),
              "stroke_sweep": study.sweep(range_values(settings["stroke_sweep"]), "stroke_max", fixed, orders,
                                          settings["fourier_stroke_max"])}
    attrs = {**fixed, "objective_scale": float(OBJECTIVE_SCALE), "paper_f": float(PAPER_FIG6_F),
             "max_iter": int(settings["max_iter"]), "optimal_family": best.family,
             "optimal_sub_cycles": int(best.sub_cycles), "three_phase_y2": float(three.y2),
             "three_phase_y3": float(three.y3), "three_phase_dy": float(three.dy),
             "fourier_iterations": [int(opt.iterations) for opt in fourier],
             "fourier_messages": [opt.message for opt in fourier]}
    return {}, attrs, groups
