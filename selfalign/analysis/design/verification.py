"""The simulated guarantee of a candidate (the package docstring, "Guarantee") and the bounds of the
end positions and the process time over the mu interval and every entry phase."""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from ...model.design_spec import DesignSpec
from ...model.friction import StopZone, stick_limit
from ...model.profiles import (
    ThreePhaseProfile,
)
from ...solvers.driver import simulate_batch
from ...solvers.outcomes import STATUS_CODES, Status
from ...solvers.tables import setting_method, setting_table
from ..positioning import MAX_PERIODS, positioning_grid
from ..stick_map import stick_map, stick_map_validity
from .candidates import Candidates, dimensionless, friction_at, mu_values, ramp_at, scale

#: Why a verified candidate is not guaranteed (the start of its ``failure`` text).
FAILURES = ("entries that do not stop", "entries that do not accumulate", "end positions spread beyond the tolerance",
            "the process run does not end at rest", "process time beyond max_process_time")


#: A change of the end position between adjacent entry phases above this many times the median
#: change is a jump (an entry sticking once more or once less), not a slope (:func:`phase_sup`).
JUMP_RATIO = 10.0


#: Status codes of entries that end.
_STOP = (STATUS_CODES[Status.REST], STATUS_CODES[Status.ACCUMULATION])


@dataclass(frozen=True)
class Verification:
    """Engine results of candidates (rows) at the mu samples (columns, ``mu``).

    Per mu: ``case`` (Table 1), ``vbar`` [m/s], ``frac_accumulate``, ``frac_stop``
    (rest without accumulation), ``frac_never_stop``, ``frac_undecided``, ``dx_d`` [m]
    (eq. 39 at that mu), ``x_stick_min`` [m, from the strip's edge, eq. 41],
    ``end_min``/``end_max`` [m, from the strip's edge], ``sufficient`` (Sect. 7.3:
    1 holds, 0 fails, -1 eq. 59 does not apply), ``t_arrive``/``t_rest`` [s] of the
    process run, ``process_stops``.  Per candidate: ``x_d``, ``error`` [m] (the middle and
    half-width of the bound on the end positions over the mu interval and every entry phase,
    :func:`end_bounds`), ``sampled_error`` [m] (half the range of the simulated ends alone),
    ``t_worst`` [s] (bound on the process time over the mu interval, :func:`worst_process_time`),
    ``stops`` (every entry ends at every mu),
    ``accumulates`` (every entry accumulates at every mu), ``guaranteed``, ``failure``
    (why not, "" if guaranteed); ``method``: the solver of the simulations
    (:func:`~selfalign.solvers.methods.most_exact_method`).
    """

    mu: np.ndarray
    case: np.ndarray
    vbar: np.ndarray
    frac_accumulate: np.ndarray
    frac_stop: np.ndarray
    frac_never_stop: np.ndarray
    frac_undecided: np.ndarray
    dx_d: np.ndarray
    x_stick_min: np.ndarray
    end_min: np.ndarray
    end_max: np.ndarray
    sufficient: np.ndarray
    t_arrive: np.ndarray
    t_rest: np.ndarray
    process_stops: np.ndarray
    x_d: np.ndarray
    error: np.ndarray
    sampled_error: np.ndarray
    t_worst: np.ndarray
    stops: np.ndarray
    accumulates: np.ndarray
    guaranteed: np.ndarray
    failure: tuple[str, ...]
    method: str


def sufficient_condition(profile: ThreePhaseProfile, c_mu: float) -> int:
    """Sect. 7.3 for x_mu = 0, w = 1: 1 if x_{n+1}(x_mu) < x_stick_min (eq. 59 valid at x_mu,
    y2'' > y3''), 0 if eq. 59 applies and the condition fails, -1 if eq. 59 does not apply."""
    if profile.y2 <= profile.y3 or profile.y2 >= c_mu:
        return -1
    if not bool(stick_map_validity(0.0, profile, w=1.0, c_mu=c_mu, x_mu=0.0).valid):
        return -1
    x_stick_min = stick_limit(profile.y2, 1.0, c_mu)  # max(y2'', y3'') = y2'' here
    return int(float(stick_map(0.0, profile, w=1.0, c_mu=c_mu, x_mu=0.0)) < x_stick_min)


def verify(spec: DesignSpec, cand: Candidates, n_entries: int | None = None) -> Verification:
    """Simulate every candidate at the spec's mu samples (module docstring, "Guarantee")."""
    n_entries = spec.grid.entries if n_entries is None else n_entries
    mus = mu_values(spec, spec.grid.mu_samples)
    k, n_mu = len(cand), mus.size
    shape = (k, n_mu)
    out, ends = empty_results(shape, n_entries)
    case = np.zeros(shape, np.int8)
    sufficient = np.full(shape, -1, np.int8)
    dims = [dimensionless(spec, cand, mu) for mu in mus]
    methods = set()
    for c in np.unique(cand.c_mu):
        rows = np.flatnonzero(cand.c_mu == c)
        for j, mu in enumerate(mus):  # the effects' parameters are dimensionless per mu
            grid = positioning_grid(*(a[rows] for a in dims[j]), w=1.0, c_mu=float(c), n_entries=n_entries,
                                    progress="quiet", friction=friction_at(spec, mu), ramp=ramp_at(spec, mu))
            methods.add(grid.method)
            case[rows, j] = grid.case
            for key in ("frac_accumulate", "frac_stop", "frac_never_stop", "frac_undecided"):
                out[key][rows, j] = getattr(grid, key)
            for key, value in (("dx_d", grid.dx_d), ("x_stick_min", grid.x_stick_min),
                               ("end_min", grid.overshoot_min), ("end_max", grid.overshoot_max)):
                out[key][rows, j] = value * spec.width  # L
            ends[rows, j] = grid.overshoot * spec.width
            out["vbar"][rows, j] = grid.vbar * scale(spec, mu).unit("velocity")
    # The sufficient condition of eq. (59) is that of the paper's model (Coulomb friction, y'' jumps);
    # under static friction nothing accumulates (docs/explanation/stopping.md); with
    # another effect it is left at -1 (does not apply).
    paper_model = spec.friction.kind == "coulomb" and spec.ramp is None
    for i in range(k):
        for j, mu in enumerate(mus):
            if paper_model and case[i, j] > 0:
                profile = ThreePhaseProfile(*(float(a[i]) for a in dims[j]))
                sufficient[i, j] = sufficient_condition(profile, float(cand.c_mu[i]))
    return conclude(spec, mus, out, ends, cand.period,
                    lambda x_d, stops: _process_runs(spec, cand, mus, dims, x_d, stops, out, methods),
                    case=case, sufficient=sufficient, methods=methods)


#: The per-(candidate, mu sample) results of a verification, in ``Verification``'s fields.
RESULT_KEYS = ("vbar", "frac_accumulate", "frac_stop", "frac_never_stop", "frac_undecided", "dx_d", "x_stick_min",
               "end_min", "end_max", "t_arrive", "t_rest")


def empty_results(shape: tuple[int, int], n_entries: int) -> tuple[dict, np.ndarray]:
    """NaN arrays of :data:`RESULT_KEYS` of ``shape`` (candidates, mu samples) and of the entries' end
    positions (candidates, mu samples, entries), for a verification to fill."""
    return {key: np.full(shape, np.nan) for key in RESULT_KEYS}, np.full(shape + (n_entries,), np.nan)


def conclude(spec: DesignSpec, mus: np.ndarray, out: dict, ends: np.ndarray, periods: np.ndarray, process_runs,
             *, case: np.ndarray, sufficient: np.ndarray, methods: set) -> Verification:
    """The verdict on every candidate from its filled results ``out`` and entries' ``ends`` (module
    docstring, "Guarantee"): it stops (every entry at rest or accumulating at every mu), accumulates, the
    bounds x_d +- error of the end positions, the process runs from rest (``process_runs(x_d, stops)``, a
    boolean array (candidates, mu samples); it may add to ``out`` and ``methods``), the worst process time
    over ``periods`` and whether all of it meets the spec."""
    k = len(periods)
    stops = np.all((out["frac_accumulate"] + out["frac_stop"]) == 1.0, axis=1)
    accumulates = np.all(out["frac_accumulate"] == 1.0, axis=1)
    lo, hi = end_bounds(ends, out["x_stick_min"], stops)
    x_d, error = 0.5 * (lo + hi), 0.5 * (hi - lo)
    with np.errstate(invalid="ignore"):
        sampled_error = np.where(stops, 0.5 * (np.max(out["end_max"], axis=1) - np.min(out["end_min"], axis=1)),
                                 np.nan)
    process_stops = process_runs(x_d, stops)
    t_worst = worst_process_time(out["t_arrive"], periods)
    within = error <= spec.tolerance
    in_time = np.ones(k, bool) if spec.max_process_time is None else t_worst <= spec.max_process_time
    wanted = accumulates if spec.accumulation else stops
    guaranteed = wanted & within & process_stops.all(axis=1) & in_time
    failure = tuple(_failure(spec, i, out, stops, accumulates, within, process_stops, in_time, sufficient)
                    for i in range(k))
    return Verification(mu=mus, case=case, sufficient=sufficient, process_stops=process_stops, x_d=x_d, error=error,
                        sampled_error=sampled_error, t_worst=t_worst, stops=stops, accumulates=accumulates,
                        guaranteed=guaranteed, failure=failure, method="; ".join(sorted(methods - {""})), **out)


def mu_sup(values: np.ndarray) -> np.ndarray:
    """Upper bound over the mu interval of a quantity continuous in mu from its values at the
    equally spaced mu samples (last axis, both ends included): the largest sample, or the secant
    of two adjacent samples extended over the next cell, whichever is larger.

    Why.  A function concave or linear over three adjacent samples lies, on the outer cells,
    below the extension of the secant of the other two: on [mu_i, mu_(i+1)] below
    v_i + max(0, v_i - v_(i-1)) and below v_(i+1) + max(0, v_(i+1) - v_(i+2)).  This is exact for
    a linear trend (no allowance where the samples fall monotonically away from the largest) and
    covers a smooth maximum between samples (a parabola's secants overshoot its peak); a convex
    piece rising between samples faster than its secants is the assumption's limit, measured by
    the dense checks of tests/test_design_guarantee.py.  The edge cells are bounded from the
    inside.  NaN in a row gives NaN."""
    v = np.asarray(values, dtype=float)
    mid = v[..., 1:-1]
    left = mid + np.maximum(mid - v[..., :-2], 0.0)
    right = mid + np.maximum(mid - v[..., 2:], 0.0)
    return np.maximum(v.max(axis=-1), np.maximum(left.max(axis=-1), right.max(axis=-1)))


def phase_sup(values: np.ndarray) -> np.ndarray:
    """Upper bound over every entry phase of the end position from its values at equally spaced
    phases (last axis, periodic: an entry one steady period later is the same motion, Sect. 7.1).

    The end position against entry phase is a sawtooth: smooth pieces and jumps where an entry
    sticks once more or once less (near a jump a solver with a step error may put samples on
    either side).  On a cell [s_i, s_(i+1)] a smooth piece rises above the larger sample by at
    most the change per spacing of the cells around it (a parabola's peak between two samples:
    a quarter of its neighbours' change; the top of a tooth: one spacing's change).  So the
    bound of a cell is its larger sample plus the largest change of that cell and its two
    neighbours that is not a jump, a jump being a change above :data:`JUMP_RATIO` times the
    median change of the row (no change of the row: a cell among jumps).  A jump is not charged
    as a slope; a smooth piece that steepens beyond ten times the median change towards the
    largest end is the assumption's limit, measured by the dense checks of
    tests/test_design_guarantee.py.  NaN in a row gives NaN."""
    v = np.asarray(values, dtype=float)
    nxt = np.roll(v, -1, axis=-1)
    change = np.abs(nxt - v)  # cell i: [s_i, s_(i+1)]
    with np.errstate(invalid="ignore"):
        smooth = np.where(change > JUMP_RATIO * np.median(change, axis=-1, keepdims=True), np.nan, change)
    local = np.fmax(np.fmax(np.roll(smooth, 1, axis=-1), smooth), np.roll(smooth, -1, axis=-1))
    local = np.where(np.isnan(local), np.nanmax(np.where(np.isnan(v), 0.0, smooth), axis=-1, keepdims=True), local)
    return np.max(np.maximum(v, nxt) + local, axis=-1)


def end_bounds(ends: np.ndarray, x_stick_min: np.ndarray, stops: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """(lowest, highest) end position [m past the strip's edge] of each candidate over the whole
    mu interval and every entry phase, from ``ends`` (candidate, mu sample, entry in the order of
    its phase) and ``x_stick_min`` (candidate, mu sample; eq. 41 with the static coefficient);
    NaN where some entry does not stop (``stops`` False).

    Lower end, a proof.  A part at rest for good sticks through the whole period, so
    mu_s mu_bar(x) >= max |y''| (eq. 41): no end lies below x_stick_min, which falls with mu
    (max |y''| / (mu g) does), so its value at mu_max, a sample, bounds every end at every mu.
    An accumulating entry ends exactly there (eq. 60 = eq. 41 for y2'' >= y3''), so for a design
    whose entries all accumulate both ends are x_stick_min at mu_max and mu_min: the range of
    eq. 41 over the interval, no sampling involved (:func:`end_spread`).

    Upper end, a stated allowance.  The stick set x >= x_stick_min is unbounded above, and an
    energy bound on how far a part slides past it (its speed relative to the table is at most
    (y2'' - mu g) (t2 - t1), the deceleration beyond x_stick_min grows with mu_bar - max |y''|)
    reaches 6.9 mm past the strip's edge for smd_realistic and 10.2 mm for the cam drive, whose
    simulated ends lie below 1.5 and 3.7 mm: no use against a tolerance.  The
    upper end is therefore :func:`phase_sup` over the entry phases at each mu sample, then
    :func:`mu_sup` over the mu samples.
    """
    lo = np.minimum(np.min(ends, axis=(1, 2)), np.min(x_stick_min, axis=1))
    hi = mu_sup(phase_sup(ends))
    return np.where(stops, lo, np.nan), np.where(stops, hi, np.nan)


def worst_process_time(t_arrive: np.ndarray, period: np.ndarray) -> np.ndarray:
    """Bound [s] on the process time of each candidate (rows) over the mu interval from its
    values at the mu samples (columns): :func:`mu_sup`, plus one period.  The first
    arrival falls in the period in which the part crosses the level; as mu changes the crossing
    moves continuously within a period (covered by the secant's extension) and steps to the next
    period where the samples need not show it (one period)."""
    return mu_sup(t_arrive) + period


def _process_runs(spec, cand, mus, dims, x_d, stops, out, methods) -> np.ndarray:
    """The process run of every candidate whose entries all stop, at every mu: fills
    ``t_arrive``, ``t_rest`` [s] of ``out``; returns where it ended at rest or accumulated.
    Adds the description of the method it ran with to the set ``methods``."""
    ended = np.zeros((len(cand), mus.size), bool)
    rows = np.flatnonzero(stops)
    length = spec.width
    for j, mu in enumerate(mus):
        if rows.size == 0:
            break
        dt, dy, y2, y3 = (a[rows] for a in dims[j])
        vbar = out["vbar"][rows, j] / scale(spec, mu).unit("velocity")
        budget = int(np.max(np.ceil(2.0 * spec.distance / length / (vbar * dt)))) + MAX_PERIODS
        level = (x_d[rows] - spec.tolerance) / length
        friction, ramp = friction_at(spec, mu), ramp_at(spec, mu)
        choice = setting_method(dt, dy, y2, y3, ramp, StopZone(0.0, 1.0, float(cand.c_mu[rows[0]])), friction)
        methods.add(choice.describe())
        res = simulate_batch(setting_table(dt, dy, y2, y3, ramp, choice), -spec.distance / length, 0.0, 0.0,
                             profile_index=np.arange(rows.size), x_mu=np.zeros(rows.size), w=np.ones(rows.size),
                             c_mu=cand.c_mu[rows], levels=level[:, None], until="rest", max_periods=budget,
                             friction=friction, method=choice.method, **choice.options)
        period = cand.period[rows]
        out["t_arrive"][rows, j] = res.crossing_time(2) * period
        out["t_rest"][rows, j] = res.t_end_periods * period
        ended[rows, j] = np.isin(res.status, _STOP)
    return ended


def _failure(spec, i, out, stops, accumulates, within, process_stops, in_time, sufficient) -> str:
    """Why candidate ``i`` is not guaranteed ("" if it is)."""
    never = out["frac_never_stop"][i] + out["frac_undecided"][i]
    if not stops[i]:
        worst = int(np.nanargmax(np.nan_to_num(never, nan=1.0)))
        return f"{FAILURES[0]}: {100 * np.nan_to_num(never[worst], nan=1.0):.0f} % at mu sample {worst}"
    if spec.accumulation and not accumulates[i]:
        worst = int(np.nanargmin(out["frac_accumulate"][i]))
        why = {1: "although the sufficient condition of Sect. 7.3 holds", 0: "the sufficient condition of Sect. 7.3 "
               "fails", -1: "eq. 59 does not apply"}[int(sufficient[i, worst])]
        if spec.friction.kind == "static_kinetic":
            why = f"static friction mu_s/mu_k = {spec.friction.ratio:g} > 1 leaves no accumulation"
        share = 100 * out["frac_accumulate"][i, worst]
        return f"{FAILURES[1]}: only {share:.0f} % accumulate at mu sample {worst} ({why})"
    if not within[i]:
        return FAILURES[2]
    if not process_stops[i].all():
        return FAILURES[3]
    if not in_time[i]:
        return FAILURES[4]
    return ""
