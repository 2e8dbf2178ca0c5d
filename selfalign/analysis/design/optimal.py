"""The optimal family: the fastest table motion (docs/explanation/optimal-motion.md) as a design
candidate, and its simulated guarantee (the package docstring, "Guarantee").

The motion.  :func:`~selfalign.optimal_profile` at the period, a bang level A <= the actuator's
limit and a stroke limit, built at the smallest friction coefficient mu_min = mu (1 - delta) of
the spec: y'' = -A, +A, then the stick level r mu_min g (r = mu_s / mu_k) while the part sticks
(under a stroke limit, several such sub-cycles).  Its stick level is r mu' g or less at every mu'
of the interval, so the part stays stuck on the base through it; at mu' > mu_min the slide ends
early and the part may slide back under +A, which the simulation at the mu samples covers.

The stop zone.  A part at rest for good in the strip sticks through every piece, which needs
mu_s mu_bar(x) >= A (eq. 41 with max |y''| = A): the strip holds the part at every mu only if
A <= r c_mu mu_min g.  The optimum at the actuator's limit may break this, so A is searched
below the limit.  The lower bound of the end positions (eq. 41, :func:`.verification.end_bounds`)
holds for any profile.  Accumulation (Sect. 7) needs its slip structure: near x_stick_min, where
mu_bar = A - eps, a part at rest slips forward under -A for the whole piece t1 (x'' = eps), stops
early in +A and slips back for about t2 (x'' = -eps), then sticks under the stick level: a net
step eps (t1^2 - t2^2) / 2 forward, shrinking with eps as mu_bar rises, so the stick positions
converge to x_stick_min when t1 > t2, as the fastest motion has (t1 / t2 = (a + 1) / (a - 1)).
The sufficient condition of Sect. 7.3 (eq. 59) is derived for the dwell, -y2'', +y3'' sequence and
does not apply to these pieces (``sufficient`` is -1): whether every entry accumulates is decided
by the exact solver alone, and where it does not the family is reported with the solver's reason.
Under static friction nothing accumulates (docs/explanation/stopping.md), as for the paper's family.

The search.  Bang levels A over (r mu_max g, min(limit, r c_mu mu_min g)] (at most
:data:`ACCELERATIONS`: they move the part at mu_max and the strip holds it at mu_min), stroke
limits (the actuator's and its half, at least its smallest stroke) and periods: geometric over the
range (at most :data:`PERIODS`) and, per A and stroke, the period whose fastest motion has exactly
that stroke (its stroke grows as the period squared; the only periods of a fixed-stroke drive);
each with the strip's c_mu values that hold the part and, with accumulation, keep the range of
x_stick_min over mu within the tolerance (eq. 41).  A motion below the smallest stroke is dropped.
Candidates are ranked by the closed-form
process time (D + x_stick_min(mu_max) - tolerance) / vbar(mu_min) (a ranking, not a bound) and
verified best first with :func:`verify_motions`.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from ...model.design_spec import DesignSpec
from ...model.friction import static_stick_limits
from ...model.profiles import PiecewiseConstantProfile
from ...solvers.driver import simulate_batch
from ...solvers.outcomes import STATUS_CODES, Status
from ..optimal_motion import centred_motion, optimal_profile, steady_mean_velocity
from ..positioning import MAX_PERIODS
from .candidates import friction_at, mu_values, scale
from .verification import Verification, conclude, empty_results

#: The family's name in a spec and a design.
FAMILY = "optimal"
#: Most periods, bang levels and stroke limits the optimal family searches (each motion under a
#: binding stroke limit is a numerical search of about a second).
PERIODS, ACCELERATIONS, STROKES = 6, 8, 2
#: Steady periods the part runs before an entry starts, so that it enters in its steady state.
RUN_IN = 3


@dataclass(frozen=True)
class Motion:
    """One candidate of the optimal family in SI: ``period`` [s], ``accel`` (the bang level A)
    [m/s^2], ``stroke_limit`` and ``stroke`` (the limit searched under and the motion's own) [m],
    ``c_mu``, ``breaks`` [s] and ``accels`` [m/s^2] of the pieces, ``vbar`` [m/s] at mu_min (exact
    solver) and ``family`` (the structure, ``OptimalProfile.family``)."""

    period: float
    accel: float
    stroke_limit: float
    stroke: float
    c_mu: float
    breaks: np.ndarray
    accels: np.ndarray
    vbar: float
    family: str

    def profile_at(self, spec: DesignSpec, mu: float) -> PiecewiseConstantProfile:
        """The dimensionless motion the model sees at friction coefficient ``mu`` (L = width)."""
        s = scale(spec, mu)
        breaks, accels = self.breaks / s.T, self.accels / s.unit("acceleration")
        y_start, yd_start, _, _ = centred_motion(breaks, accels)
        return PiecewiseConstantProfile(breaks, accels, y_start=y_start, yd_start=yd_start)


def unavailable(spec: DesignSpec) -> str:
    """Why the optimal family cannot be searched for ``spec`` ("" if it can)."""
    if spec.ramp is not None:
        return "the optimal family has y'' jumps; the spec's actuator ramps them (finite jerk)"
    if spec.friction.stribeck:
        return "the optimal family needs a constant kinetic friction (Coulomb or static/kinetic), not Stribeck's"
    return ""


def motions(spec: DesignSpec) -> list[Motion]:
    """The candidates of the optimal family (module docstring, "The search"), fastest first."""
    g, r = spec.grid, spec.friction.ratio
    mu_lo, mu_hi = spec.mu_range
    s_lo = scale(spec, mu_lo)
    friction = spec.friction if spec.friction.kind != "coulomb" else None
    c_values = np.array([spec.c_mu[0]]) if spec.c_mu_fixed else np.linspace(*spec.c_mu, g.c_mu)
    a_lo, a_hi = r * mu_hi * spec.g, min(spec.max_acceleration, r * c_values.max() * mu_lo * spec.g)
    n_a = min(g.accelerations, ACCELERATIONS)
    accels = a_lo + (a_hi - a_lo) * np.arange(1, n_a + 1) / n_a if a_hi > a_lo else np.zeros(0)
    lo, hi = spec.period
    grid = np.geomspace(lo, hi, min(g.periods, PERIODS)) if lo < hi else np.array([lo])
    strokes = spec.max_stroke * np.array([1.0, 0.5])[:min(g.strokes, STROKES)]
    if spec.min_stroke is not None:
        strokes = strokes[strokes >= spec.min_stroke]
    found, seen = [], set()
    for accel in accels:
        a = accel / s_lo.unit("acceleration")
        unit_stroke = optimal_profile(1.0, a, friction=friction).stroke * s_lo.L  # at period T(mu_lo); grows as dt^2
        # The longest period whose fastest motion has each stroke exactly: the fastest motion that fits.
        fitting = np.sqrt(strokes / unit_stroke) * s_lo.T
        fitting = fitting[(fitting >= lo * (1 - 1e-12)) & (fitting <= hi * (1 + 1e-12))].clip(lo, hi)
        periods = fitting if spec.min_stroke is not None else np.concatenate([grid, fitting])
        held = stick_offset(spec, accel, c_values, mu_lo) < np.inf
        if spec.accumulation:  # every entry ends at x_stick_min: its range over mu must fit (eq. 41)
            with np.errstate(invalid="ignore"):  # inf - inf where the strip does not hold: dropped
                held &= 0.5 * (stick_offset(spec, accel, c_values, mu_lo)
                               - stick_offset(spec, accel, c_values, mu_hi)) <= spec.tolerance
        holding = c_values[held]
        for period in periods:
            for limit in strokes:
                best = optimal_profile(period / s_lo.T, a, stroke_max=limit / s_lo.L * (1 + 1e-9), friction=friction)
                stroke = best.stroke * s_lo.L
                key = (round(period, 15), accel, round(stroke / spec.max_stroke, 9))
                if key in seen or (spec.min_stroke is not None and stroke < spec.min_stroke * (1 - 1e-6)):
                    continue
                seen.add(key)
                for c in holding:
                    found.append(Motion(float(period), float(accel), float(limit), float(stroke), float(c),
                                        best.profile.breaks * s_lo.T,
                                        best.profile.accels * s_lo.unit("acceleration"),
                                        float(best.vbar * s_lo.unit("velocity")), best.family))
    return sorted(found, key=lambda m: t_estimate(spec, m))


def stick_offset(spec: DesignSpec, accel, c_mu, mu: float) -> np.ndarray:
    """x_stick_min - x_mu [m] (eq. 41 with the static coefficient) at ``mu`` for |y''| <= ``accel``."""
    s = scale(spec, mu)
    return static_stick_limits(np.asarray(accel, dtype=float) / s.unit("acceleration"), spec.friction.ratio, 1.0,
                               np.asarray(c_mu, dtype=float)) * spec.width


def t_estimate(spec: DesignSpec, motion: Motion) -> float:
    """The closed-form process time [s] that ranks the candidates (module docstring)."""
    inside = float(stick_offset(spec, motion.accel, motion.c_mu, spec.mu_range[1]))
    return (spec.distance + max(inside - spec.tolerance, 0.0)) / motion.vbar if motion.vbar > 0 else np.inf


def verify_motions(spec: DesignSpec, cands: list[Motion], n_entries: int | None = None) -> Verification:
    """Simulate the optimal-family candidates at the spec's mu samples, as :func:`.verification.verify`
    does the three-phase ones: ``n_entries`` entries into the strip at phases (k + 1/2) / n of a
    steady period after :data:`RUN_IN` steady periods, the bounds of the end positions and the
    process run from rest.  ``case`` is 0 and ``dx_d`` NaN (Table 1 and eq. 39 are the paper's
    profile's); ``sufficient`` is -1 (eq. 59 does not apply, the module docstring)."""
    n_entries = spec.grid.entries if n_entries is None else n_entries
    mus = mu_values(spec, spec.grid.mu_samples)
    shape = (len(cands), mus.size)
    out, ends = empty_results(shape, n_entries)
    c_mu = np.array([m.c_mu for m in cands])
    rest, accumulation = STATUS_CODES[Status.REST], STATUS_CODES[Status.ACCUMULATION]
    never = STATUS_CODES[Status.NEVER_STOPS]
    for j, mu in enumerate(mus):
        s = scale(spec, mu)
        profiles = [m.profile_at(spec, mu) for m in cands]
        friction = friction_at(spec, mu)
        vbar = steady_mean_velocity(profiles, friction)
        out["vbar"][:, j] = vbar * s.unit("velocity")
        out["x_stick_min"][:, j] = stick_offset(spec, [m.accel for m in cands], c_mu, mu)
        moving = np.flatnonzero(np.nan_to_num(vbar) > 0)
        if moving.size == 0:
            continue
        dt = np.array([profiles[i].dt for i in moving])
        frac = (RUN_IN + (np.arange(n_entries) + 0.5) / n_entries)
        x0 = -(vbar[moving] * dt)[:, None] * frac[None, :]
        rep = lambda a: np.repeat(a, n_entries)  # noqa: E731
        res = simulate_batch([profiles[i] for i in moving], x0.ravel(), 0.0,
                             profile_index=rep(np.arange(moving.size)), x_mu=np.zeros(x0.size), w=np.ones(x0.size),
                             c_mu=rep(c_mu[moving]), until="rest", max_periods=MAX_PERIODS + RUN_IN,
                             friction=friction)
        status = res.status.reshape(moving.size, n_entries)
        out["frac_accumulate"][moving, j] = np.mean(status == accumulation, axis=1)
        out["frac_stop"][moving, j] = np.mean(status == rest, axis=1)
        out["frac_never_stop"][moving, j] = np.mean(status == never, axis=1)
        out["frac_undecided"][moving, j] = np.mean(~np.isin(status, (rest, accumulation, never)), axis=1)
        end = np.where(np.isin(status, (rest, accumulation)), res.x_end.reshape(moving.size, n_entries), np.nan)
        ends[moving, j] = end * spec.width
        out["end_min"][moving, j] = np.min(end, axis=1) * spec.width  # NaN where an entry does not stop
        out["end_max"][moving, j] = np.max(end, axis=1) * spec.width
    return conclude(spec, mus, out, ends, np.array([m.period for m in cands]),
                    lambda x_d, stops: _process_runs(spec, cands, mus, x_d, stops, out),
                    case=np.zeros(shape, np.int8), sufficient=np.full(shape, -1, np.int8),
                    methods={"exact (piecewise-constant optimal motion)"})


def process_run(spec: DesignSpec, motion: Motion, mu: float, level: float):
    """The process run of ``motion`` at ``mu``: the part at rest ``spec.distance`` before the strip at
    t = 0, until it ends, recording the first crossing of ``level`` [m past the strip's edge]; the
    ``BatchResult`` of one member (positions in widths, times in periods)."""
    profile = motion.profile_at(spec, mu)
    vbar = float(steady_mean_velocity([profile], friction_at(spec, mu))[0])
    budget = int(np.ceil(2.0 * spec.distance / spec.width / (vbar * profile.dt))) + MAX_PERIODS
    return simulate_batch([profile], -spec.distance / spec.width, 0.0, x_mu=0.0, w=1.0, c_mu=motion.c_mu,
                          levels=np.array([[level / spec.width]]), until="rest", max_periods=budget,
                          friction=friction_at(spec, mu))


def _process_runs(spec, cands, mus, x_d, stops, out) -> np.ndarray:
    """The process run (:func:`process_run`) of every candidate whose entries all stop, at every mu:
    fills ``t_arrive`` and ``t_rest`` [s] of ``out``; returns where it ended at rest or accumulated."""
    ended = np.zeros((len(cands), mus.size), bool)
    for i in np.flatnonzero(stops):
        for j, mu in enumerate(mus):
            res = process_run(spec, cands[i], mu, x_d[i] - spec.tolerance)
            out["t_arrive"][i, j] = float(res.crossing_time(2)[0]) * cands[i].period
            out["t_rest"][i, j] = float(res.t_end_periods[0]) * cands[i].period
            ended[i, j] = int(res.status[0]) in (STATUS_CODES[Status.REST], STATUS_CODES[Status.ACCUMULATION])
    return ended
