"""The search: screen, rank, verify best first, choose; the trade-off fronts (the package docstring)."""

from __future__ import annotations

import math
import time
from dataclasses import dataclass, replace

import numpy as np

from ...model.design_spec import FRONT_SIMULATED, DesignSpec
from ...model.profiles import (
    CASE_LABELS,
    PiecewiseConstantProfile,
    ThreePhaseProfile,
    finite_jerk_times,
    three_phase_feasibility,
    three_phase_times,
)
from ...progress import Progress, resolve_mode
from ..optimal_motion import steady_mean_velocity
from ..steady_state import steady_state_grid
from .candidates import Candidates, dimensionless, friction_at, scale, search_grid
from .explanation import _explain
from .optimal import FAMILY as OPTIMAL
from .optimal import Motion, motions, t_estimate, unavailable, verify_motions
from .screening import end_spread, robustness_margin, screen
from .verification import Verification, verify

#: What the guarantee assumes (printed with every design).
ASSUMPTIONS = (
    "rigid part that neither tips nor bounces (Sect. 3.3)",
    "Coulomb friction, one coefficient mu on the base and c_mu mu on the strip (eq. 1)",
    "the linear friction transition of eqs. 7-9 over the part's width",
    "the exact three-phase profile (Sect. 4.4.3): jumps in y'', no jerk limit, no actuator dynamics",
    "mu constant during a run; the mu range is checked by simulation at the mu samples, between them by the "
    "bounds of analysis.design.end_bounds (eq. 41 below, the sampling's allowance above and for the process "
    "time), and by the closed forms at 65 values",
)


#: Candidates verified per call of the engine.
BATCH = 8


@dataclass(frozen=True)
class Design:
    """The answer of design: the chosen profile in SI, its performance and its guarantee.

    ``found`` says whether a guaranteed design exists on the search grid; otherwise
    ``explanation`` says which constraint binds and what would have to change, and the profile
    fields hold the best candidate the engine checked (if any).  The profile has zero
    acceleration on [0, t1), -y2'' on [t1, t2) and +y3'' on [t2, t3) (``times``).  The
    performance is the worst over the mu samples of the spec, simulated by the engine
    (``verification``); the trade-off fronts are described at :func:`~selfalign.design`.

    Parameters
    ----------
    spec : DesignSpec
        The spec designed for (Attributes).
    found : bool
        Whether a guaranteed design exists (Attributes).
    explanation : str
        Why not, if not (Attributes).
    period, stroke, y2, y3, c_mu : float
        The profile and the strip (Attributes).
    case : int
        The case of Table 1 at the nominal mu (Attributes).
    vbar, vbar_min, margin : float
        The fields of the same names (Attributes).
    verification : ``Verification`` or None
        The engine's results (Attributes).
    front_time_error, front_time_margin, search : dict
        The fronts and the search counts (Attributes).
    family : str, optional
        The profile family (Attributes).  Default "three_phase".
    motion : ``Motion`` or None, optional
        The optimal family's motion (Attributes).  Default None.
    other : Design or None, optional
        The best design of the other family searched (Attributes).  Default None.

    Attributes
    ----------
    spec : DesignSpec
        The spec designed for.
    found : bool
        Whether a guaranteed design exists on the grid.
    explanation : str
        Which constraint binds and what would have to change ("" if found).
    period : float
        The period [s].
    stroke : float
        The stroke [m].
    y2 : float
        Magnitude of the deceleration phase [m/s^2].
    y3 : float
        Magnitude of the acceleration phase [m/s^2].
    c_mu : float
        The friction ratio of the strip.
    case : int
        The case of Table 1 at the nominal mu.
    vbar : float
        The steady average velocity at the nominal mu [m/s].
    vbar_min : float
        The least steady average velocity over the mu range [m/s].
    margin : float
        The robustness margin, a relative mu deviation (closed forms).
    verification : ``Verification`` or None
        The engine's results for the design (one row).
    front_time_error : dict
        The designs not dominated in closed-form process time and end spread over mu.
    front_time_margin : dict
        Closed-form process time against the robustness margin.
    search : dict
        Counts of the search (designs, screened, verified, entries) and its time [s].
    family : str
        The profile family of the design: "three_phase" (the paper's: y'' = 0, -y2'', +y3'') or
        "optimal" (the fastest table motion: y'' = -y2'', +y2'', then the stick level y3'' while the
        part sticks, ``motion``).
    motion : ``Motion`` or None
        The optimal family's motion in SI (its pieces), None for the three-phase family.
    other : Design or None
        The best design of the other family when both were searched (found or not), else None.
    gain : dict or None
        With ``other``: per family ("three_phase", "optimal") its found, vbar [m/s], t_arrive and
        t_rest [s] (simulated, worst over the mu samples) and why not (its explanation), and the
        ratios old/new of t_arrive and t_rest (NaN unless both were found).
    frequency : float
        1 / period [Hz].
    times : ``ThreePhaseTimes``
        The phase times t1, t2, t3 [s], y_ini [m] and yd_ini [m/s] of the SI profile.
    t_arrive : float
        The worst time to reach the strip [s].
    t_worst : float
        The worst process time [s].
    t_rest : float
        The worst time to come to rest [s].
    x_d : float
        The end position from the strip's edge [m].
    error : float
        The positioning error, half the range of end positions [m].
    case_label : str
        The name of the case.
    assumptions : tuple of str
        The model assumptions the guarantee rests on.

    See Also
    --------
    design : Computes it.

    Examples
    --------
    >>> import selfalign as sa
    >>> from selfalign.model.design_spec import DesignGrid
    >>> grid = DesignGrid(periods=2, strokes=1, accelerations=2, c_mu=1, mu_samples=3, max_verified=1)
    >>> spec = sa.DesignSpec(mu=0.2, mu_uncertainty=0.05, c_mu=(3.0, 3.0), width=2e-3, max_stroke=1e-3,
    ...                      max_acceleration=8.0, period=(0.01, 0.1), distance=4e-3, tolerance=250e-6, grid=grid)
    >>> result = sa.design(spec, progress="quiet")
    >>> result.found, result.frequency, result.case, result.margin
    (True, 10.0, 3, 0.32)
    >>> result.search["designs"], result.search["verified"]
    (8, 1)
    """

    spec: DesignSpec
    found: bool
    explanation: str
    period: float
    stroke: float
    y2: float
    y3: float
    c_mu: float
    case: int
    vbar: float
    vbar_min: float
    margin: float
    verification: Verification | None
    front_time_error: dict
    front_time_margin: dict
    search: dict
    family: str = "three_phase"
    motion: Motion | None = None
    other: Design | None = None

    @property
    def gain(self) -> dict | None:
        if self.other is None:
            return None
        by = {d.family: {"found": bool(d.found), "vbar": d.vbar,
                         "t_arrive": d.t_arrive if d.found else math.nan,
                         "t_rest": d.t_rest if d.found else math.nan, "why_not": d.explanation}
              for d in (self, self.other)}
        old, new = by["three_phase"], by[OPTIMAL]
        return {**by, "arrive_ratio": old["t_arrive"] / new["t_arrive"], "rest_ratio": old["t_rest"] / new["t_rest"]}

    @property
    def frequency(self) -> float:
        return 1.0 / self.period

    @property
    def times(self):
        """Phase times etc. of the SI three-phase profile (the Appendix's closed form is scale-free)."""
        if self.family == OPTIMAL:
            raise ValueError("times are the three-phase profile's; an optimal design's pieces are design.motion")
        return three_phase_times(self.period, self.stroke, self.y2, self.y3)

    @property
    def t_arrive(self) -> float:
        return float(np.max(self.verification.t_arrive[0]))

    @property
    def t_worst(self) -> float:
        return float(self.verification.t_worst[0])

    @property
    def t_rest(self) -> float:
        return float(np.max(self.verification.t_rest[0]))

    @property
    def x_d(self) -> float:
        return float(self.verification.x_d[0])

    @property
    def error(self) -> float:
        return float(self.verification.error[0])

    @property
    def case_label(self) -> str:
        return f"fastest table motion, {self.motion.family}" if self.family == OPTIMAL else CASE_LABELS[self.case]

    @property
    def assumptions(self) -> tuple[str, ...]:
        """``ASSUMPTIONS``, with the spec's friction law and profile in place of the paper's."""
        law, ramp = self.spec.friction, self.spec.ramp
        friction = ASSUMPTIONS[1] if law.kind == "coulomb" else (
            f"{self.spec.effects().split('; ')[0]}, kinetic coefficient mu on the base and c_mu mu on the strip")
        profile = ASSUMPTIONS[3] if ramp is None else (
            f"the three-phase profile with y'' ramps of {1e3 * ramp:g} ms at each switch (finite jerk), no actuator "
            f"dynamics")
        if self.family == OPTIMAL:
            profile = ("the exact pieces of the fastest table motion (docs/explanation/optimal-motion.md): jumps in "
                       "y'', no jerk limit, no actuator dynamics")
        return (ASSUMPTIONS[0], friction, ASSUMPTIONS[2], profile, *ASSUMPTIONS[4:])

    def profile_at(self, mu: float) -> ThreePhaseProfile | PiecewiseConstantProfile:
        """The dimensionless profile the model sees at friction coefficient ``mu`` (L = width)."""
        if self.family == OPTIMAL:
            return self.motion.profile_at(self.spec, mu)
        cand = Candidates(*(np.array([v]) for v in (self.period, self.stroke, self.y2, self.y3, self.c_mu)))
        return ThreePhaseProfile(*(float(a[0]) for a in dimensionless(self.spec, cand, mu)))



def _pareto(cost_a, cost_b) -> np.ndarray:
    """Indices of the points not dominated in (cost_a, cost_b), both minimised, by increasing cost_a."""
    order = np.lexsort((cost_b, cost_a))
    best = np.inf
    keep = []
    for i in order:
        if cost_b[i] < best:
            keep.append(i)
            best = cost_b[i]
    return np.array(keep, dtype=int)


def design(spec: DesignSpec, *, progress: str = "auto") -> Design:
    """The guaranteed design of ``spec`` (module docstring) and its trade-offs.

    The families searched are ``spec.families``: the paper's three-phase profiles (the default)
    and the fastest table motions (``selfalign.analysis.design.optimal``); with both, the faster
    guaranteed design wins (under the objective "robustness" a guaranteed three-phase design stays)
    and keeps the other family's best as ``other``, ``gain`` comparing them.

    The trade-offs: ``front_time_error`` (the designs not dominated in closed-form process
    time and end spread over mu, the first ``FRONT_SIMULATED`` of them simulated: ``t_arrive``,
    ``error``, ``guaranteed``) and ``front_time_margin`` (closed-form process time against
    the robustness margin).

    The two objectives of Sect. 2: bring the part to x_d in the least process time and stop
    it there with the smallest positioning error (module docstring of
    ``selfalign.analysis.design``).  A grid over (period, stroke, y2'', y3'', c_mu)
    inside the actuator's limits is screened with closed forms at 65 values of mu across
    [mu (1 - delta), mu (1 + delta)]: a physical profile (q <= 1), forward motion, a strip
    that can hold the part (eq. 41) and, where accumulation is asked for, y2'' > y3''.
    Survivors are ranked by a closed-form process time and verified with the engine, best
    first: at every mu sample each of ``grid.entries`` steady-state entries into the strip
    (Sect. 7.1) must come to rest or accumulate (with ``accumulation``: accumulate); the end
    positions are bounded over the whole mu interval and every entry phase, the middle of
    the bound is x_d and its half-width, the robust error Delta_x_d,mu, must not exceed the
    tolerance; and the bound of the simulated process time over the mu interval must not
    exceed ``max_process_time``.  Static/kinetic or Stribeck friction and y'' ramps of the spec
    are simulated (the closed forms then only rank).  The guarantee is as strong as the
    model (``Design.assumptions``).

    Parameters
    ----------
    spec : DesignSpec
        The machine, the part, the actuator's limits and the task, in SI units.
    progress : str, optional
        How the candidates verified are reported (``selfalign.progress``): "auto" (the
        default), "bar", "log" or "quiet".

    Returns
    -------
    Design
        ``found``: a guaranteed design exists on the grid; otherwise ``explanation`` says
        which constraint binds and what would have to change, and the profile fields hold
        the best candidate the engine checked (if any).  The profile in SI: ``period`` [s],
        ``frequency`` [Hz], ``stroke`` [m], ``y2``, ``y3`` [m/s^2], ``c_mu``, ``times`` (the
        phase times); ``case`` of Table 1 and ``vbar`` [m/s] at the nominal mu, ``vbar_min``
        over the range, ``margin`` (robustness margin); the simulated ``verification``,
        ``t_arrive``, ``t_rest`` [s] (worst over the mu samples), ``x_d`` and ``error`` [m]
        from the strip's edge; the fronts and ``search`` (counts and the time taken);
        ``family`` ("three_phase" or "optimal"), ``motion`` (an optimal design's pieces),
        ``other`` and ``gain`` (with both families searched).

    Raises
    ------
    TypeError
        If ``spec`` is not a DesignSpec.
    ValueError
        If ``progress`` (or, with "auto", the environment variable ``SELFALIGN_PROGRESS``) is
        not one of the modes.
    KernelError
        If numba is missing or cannot compile the kernel (a RuntimeError).

    See Also
    --------
    DesignSpec : The input.
    load_design_spec : Reads a spec from a YAML file.
    positioning : The steady-state entries of one dimensionless setting.

    Examples
    --------
    A 2 mm part on a steel table (mu = 0.2 +- 5 %, a strip of c_mu = 3), on a small grid:

    >>> import selfalign as sa
    >>> from selfalign.model.design_spec import DesignGrid
    >>> grid = DesignGrid(periods=2, strokes=1, accelerations=2, c_mu=1, mu_samples=3, max_verified=1)
    >>> spec = sa.DesignSpec(mu=0.2, mu_uncertainty=0.05, c_mu=(3.0, 3.0), width=2e-3, max_stroke=1e-3,
    ...                      max_acceleration=8.0, period=(0.01, 0.1), distance=4e-3, tolerance=250e-6, grid=grid)
    >>> result = sa.design(spec, progress="quiet")
    >>> result.found, result.case_label
    (True, 'general stick-slip')
    >>> print(f"{result.frequency:.4g} Hz, stroke {1e3 * result.stroke:g} mm, y2'' = y3'' = {result.y3:g} m/s^2")
    10 Hz, stroke 1 mm, y2'' = y3'' = 4 m/s^2
    >>> print(f"x_d = {1e6 * result.x_d:.4g} um +- {1e6 * result.error:.3g} um, arrival within {result.t_arrive:.3g} s")
    x_d = 1044 um +- 102 um, arrival within 3.18 s
    """
    if not isinstance(spec, DesignSpec):
        raise TypeError(f"design needs a DesignSpec (selfalign.io.design_spec.load_design_spec reads one), "
                         f"got {type(spec).__name__}")
    resolve_mode(progress)  # refuses a bad mode before any work
    paper = _three_phase(spec, progress) if "three_phase" in spec.families else None
    best = _optimal(spec, progress) if OPTIMAL in spec.families else None
    if best is None or paper is None:
        return paper if best is None else best
    if _beats(spec, best, paper):  # the trade-off fronts are the three-phase search's
        return replace(best, front_time_error=paper.front_time_error, front_time_margin=paper.front_time_margin,
                       other=paper)
    return replace(paper, other=best)


def _beats(spec: DesignSpec, new: Design, old: Design) -> bool:
    """Whether the optimal design ``new`` wins over the three-phase ``old``: guaranteed, and ``old`` is not
    or arrives later (with the objective "robustness" the margin, a closed form of the paper's profile,
    decides: a guaranteed three-phase design stays)."""
    if not new.found:
        return False
    if not old.found:
        return True
    return spec.objective == "process_time" and new.t_arrive < old.t_arrive


def _three_phase(spec: DesignSpec, progress: str) -> Design:
    """The guaranteed three-phase design (the package docstring)."""
    start = time.perf_counter()
    cand = search_grid(spec)
    designs = len(cand)
    ramps_do_not_fit = 0
    if spec.ramp is not None:  # the Appendix's constraints with ramps (scale-free, so in SI)
        ramp = spec.ramp
        fits = finite_jerk_times(cand.period, cand.stroke, cand.y2, cand.y3, ramp, ramp, ramp).valid
        ramps_do_not_fit = int(np.count_nonzero(~fits & (three_phase_feasibility(cand.period, cand.stroke, cand.y2,
                                                                                 cand.y3) <= 1.0)))
        cand = cand.take(np.flatnonzero(fits))
    scr = screen(spec, cand)
    ok = np.flatnonzero(scr.ok)
    margin = np.full(len(cand), np.nan)
    margin[ok] = robustness_margin(spec, cand.take(ok))
    if spec.objective == "robustness":
        fits = ok[scr.t_estimate[ok] <= spec.max_process_time]
        order = fits[np.lexsort((scr.t_estimate[fits], -margin[fits]))]
    else:
        order = ok[np.argsort(scr.t_estimate[ok], kind="stable")]
        if spec.accumulation:
            # Interleave the fastest candidates with the fastest whose slip window allows the
            # sufficient condition of Sect. 7.3: the fastest often jump across the transition.
            rank = np.arange(order.size, dtype=float)
            short = scr.short_slip[order]
            rank_short = np.full(order.size, np.inf)
            rank_short[short] = np.arange(int(short.sum()))
            order = order[np.argsort(np.minimum(rank, rank_short), kind="stable")]
    checked, verified, chosen = [], 0, None
    with Progress(min(order.size, spec.grid.max_verified), f"design {spec.name}", unit="candidates",
                  mode=progress) as bar:
        for begin in range(0, min(order.size, spec.grid.max_verified), BATCH):
            batch = order[begin:begin + BATCH]
            checked.append((batch, verify(spec, cand.take(batch))))
            verified += batch.size
            bar.advance(int(batch.size))
            chosen = _choose(spec, checked, margin)
            if chosen is not None and _settled(spec, chosen, order[begin + BATCH:], scr, margin):
                break
    front_te = _front_time_error(spec, cand, scr, ok)
    keep = _pareto(scr.t_estimate[ok], -margin[ok])
    front_tm = {"period": cand.period[ok][keep], "stroke": cand.stroke[ok][keep], "y2": cand.y2[ok][keep],
                "y3": cand.y3[ok][keep], "c_mu": cand.c_mu[ok][keep], "t_estimate": scr.t_estimate[ok][keep],
                "margin": margin[ok][keep]}
    search = {"designs": designs, "ramps_do_not_fit": ramps_do_not_fit, "screened": int(ok.size),
              "verified": verified, "entries": spec.grid.entries, "seconds": time.perf_counter() - start}
    if chosen is None:
        merged = _merge([ver for _, ver in checked]) if checked else None
        best = checked[0][0][:1] if checked else None
        explanation = _explain(spec, cand, scr, merged)
        if best is None:
            return Design(spec, False, explanation, *(math.nan,) * 5, 0, math.nan, math.nan, math.nan, None,
                          front_te, front_tm, search)
        index, ver = int(best[0]), _row(checked[0][1], 0)
    else:
        index, ver = chosen
        explanation = ""
    d = cand.take(np.array([index]))
    nominal = steady_state_grid(*dimensionless(spec, d, spec.mu))
    return Design(spec, chosen is not None, explanation, float(d.period[0]), float(d.stroke[0]), float(d.y2[0]),
                  float(d.y3[0]), float(d.c_mu[0]), int(nominal.case[0]),
                  float(nominal.vbar[0] * scale(spec, spec.mu).unit("velocity")), float(scr.vbar_min[index]),
                  float(margin[index]), ver, front_te, front_tm, search)


def _optimal(spec: DesignSpec, progress: str) -> Design:
    """The guaranteed design of the optimal family (:mod:`.optimal`): its candidates verified best first
    in batches until one is guaranteed and no later one can arrive sooner (by the ranking's time less one
    period), at most ``grid.max_verified``."""
    start = time.perf_counter()
    why = unavailable(spec)
    cands = [] if why else motions(spec)
    count = min(len(cands), spec.grid.max_verified)
    chosen, first, verified = None, None, 0
    with Progress(count, f"design {spec.name} ({OPTIMAL})", unit="candidates", mode=progress) as bar:
        for begin in range(0, count, BATCH):
            batch = cands[begin:begin + BATCH]
            ver = verify_motions(spec, batch)
            verified += len(batch)
            bar.advance(len(batch))
            first = first or (batch[0], _row(ver, 0))
            for i in np.flatnonzero(ver.guaranteed):
                t = float(np.max(ver.t_arrive[i]))
                if chosen is None or t < float(np.max(chosen[1].t_arrive[0])):
                    chosen = (batch[int(i)], _row(ver, int(i)))
            following = cands[begin + BATCH:count]
            if chosen is not None and (not following or min(t_estimate(spec, m) for m in following)
                                       - spec.period[1] > float(np.max(chosen[1].t_arrive[0]))):
                break
    search = {"designs": len(cands), "ramps_do_not_fit": 0, "screened": len(cands), "verified": verified,
              "entries": spec.grid.entries, "seconds": time.perf_counter() - start}
    if chosen is None:
        if not why:
            why = ("no motion of the optimal family moves the part at mu_max, is held by the strip at mu_min "
                   "(A <= r c_mu mu_min g, eq. 41) and meets the stroke limits" if first is None else
                   f"no candidate of the optimal family checked is guaranteed; the fastest: {first[1].failure[0]}")
            if first is not None and spec.accumulation and not first[1].accumulates[0]:
                step = float(np.nanmin(first[1].vbar[0])) * first[0].period
                why += (f"; its advance per period, {1e3 * step:.3g} mm, is {step / spec.width:.3g} widths of the "
                        f"friction transition: a part that slides across most of it at once ends past x_stick_min "
                        f"instead of approaching it in shrinking steps (Sect. 7)")
        if first is None:
            return Design(spec, False, why, *(math.nan,) * 5, 0, math.nan, math.nan, math.nan, None, {}, {},
                          search, family=OPTIMAL)
        chosen = first
    motion, ver = chosen
    nominal = steady_mean_velocity([motion.profile_at(spec, spec.mu)], friction_at(spec, spec.mu))
    return Design(spec, bool(ver.guaranteed[0]), "" if ver.guaranteed[0] else why, motion.period, motion.stroke,
                  motion.accel, float(motion.accels[-1]), motion.c_mu, 0,
                  float(nominal[0] * scale(spec, spec.mu).unit("velocity")), float(np.nanmin(ver.vbar[0])),
                  math.nan, ver, {}, {}, search, family=OPTIMAL, motion=motion)


def _settled(spec, chosen, following, scr, margin) -> bool:
    """True when none of the unverified candidates ``following`` can beat ``chosen``."""
    if following.size == 0:
        return True
    index, ver = chosen
    t_best = float(np.max(ver.t_arrive[0]))
    # A run may arrive up to one period before the closed-form time (the advance within a
    # period is not uniform), so only candidates slower by more than that are out of the race.
    faster = scr.t_estimate[following] - spec.period[1] <= t_best
    if spec.objective == "robustness":
        return not np.any((margin[following] > margin[index]) | ((margin[following] == margin[index]) & faster))
    return not faster.any()


def _row(ver: Verification, i: int) -> Verification:
    return Verification(**{k: (getattr(ver, k) if k in ("mu", "method") else
                               tuple(getattr(ver, k)[i:i + 1]) if k == "failure" else getattr(ver, k)[i:i + 1])
                           for k in Verification.__dataclass_fields__})


def _merge(vers: list[Verification]) -> Verification:
    return Verification(**{k: (vers[0].mu if k == "mu" else
                               "; ".join(sorted({v.method for v in vers})) if k == "method" else
                               sum((v.failure for v in vers), ()) if k == "failure" else
                               np.concatenate([getattr(v, k) for v in vers]))
                           for k in Verification.__dataclass_fields__})


def _choose(spec, checked, margin):
    """(grid index, one-row Verification) of the best guaranteed candidate verified, or None."""
    best, best_key = None, None
    for batch, ver in checked:
        for i in np.flatnonzero(ver.guaranteed):
            t = float(np.max(ver.t_arrive[i]))
            key = (-margin[batch[i]], t) if spec.objective == "robustness" else (t,)
            if best_key is None or key < best_key:
                best, best_key = (int(batch[i]), _row(ver, int(i))), key
    return best


def _front_time_error(spec, cand, scr, ok) -> dict:
    """Closed-form front of process time against the end spread over mu; its first members simulated."""
    spread = end_spread(spec, cand.take(ok))
    keep = _pareto(scr.t_estimate[ok], spread)
    members = ok[keep]
    simulated = members[np.unique(np.linspace(0, members.size - 1, min(FRONT_SIMULATED, members.size)).astype(int))] \
        if members.size else members
    ver = verify(spec, cand.take(simulated)) if simulated.size else None
    sim = {"t_arrive": np.full(members.size, np.nan), "error": np.full(members.size, np.nan),
           "guaranteed": np.zeros(members.size, bool)}
    if ver is not None:
        where = np.array([np.flatnonzero(members == s)[0] for s in simulated])
        sim["t_arrive"][where] = np.max(ver.t_arrive, axis=1)
        sim["error"][where] = ver.error
        sim["guaranteed"][where] = ver.guaranteed
    return {"period": cand.period[members], "stroke": cand.stroke[members], "y2": cand.y2[members],
            "y3": cand.y3[members], "c_mu": cand.c_mu[members], "t_estimate": scr.t_estimate[members],
            "spread": end_spread(spec, cand.take(members)), **sim}
