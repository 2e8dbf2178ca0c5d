"""From a machine's limits to a guaranteed self-aligning design (Sects. 2, 4.4.3, 5, 7).

The two objectives of Sect. 2: bring the part to x_d in the least process time T_p and stop
it there with the smallest positioning error Delta_x_d.  :func:`design` searches the
three-phase profiles (Sect. 4.4.3) inside an actuator's limits, in SI units
(:class:`~selfalign.model.design_spec.DesignSpec`), and certifies the one it returns.

Scaling (Sect. 3.2).  The length scale is the part's width, L = w~ (so w = 1), and
T = sqrt(L / (mu g)).  A fixed SI profile (period P, stroke S, accelerations A2, A3) is,
at friction coefficient mu', the dimensionless profile dt = P / T(mu'), dy = S / L,
y2 = A2 / (mu' g), y3 = A3 / (mu' g): a change of mu changes the profile the model sees.

Search.  A grid over (P, S, A2, A3, c_mu) inside the limits (:class:`DesignGrid`), screened
with closed forms at every mu of a dense sample of [mu (1 - delta), mu (1 + delta)]
(:data:`DENSE_MU`): a physical profile (q <= 1, Sect. 5.1), forward motion (case > 0 and
vbar > 0, :func:`~selfalign.analysis.steady_state.steady_state_grid`), a strip that can hold
the part (max(A2, A3) <= c_mu mu' g, eq. 41) and, where accumulation is asked for, y2'' > y3''
(README "Where the paper is wrong or imprecise (Sect. 7)": no setting with y3'' > y2''
accumulates) and an end position x_stick_min (eq. 41) that moves with mu by at most the
tolerance.  Survivors are ranked by a closed-form process time (distance to travel over the
slowest vbar, :class:`Screen`) and verified
with the engine, best first.

Effects.  The spec may declare static/kinetic or Stribeck friction and y'' ramps
(finite jerk; candidates whose ramps do not fit are dropped and counted).  The closed forms
above are the paper's model, so they then only rank the candidates (a heuristic); the
guarantee and the process time are simulated with the effect (:func:`friction_at`,
:func:`ramp_at`), by the most exact method that can
(:func:`~selfalign.solvers.methods.most_exact_method`; ``Verification.method``).

Guarantee (per candidate, :func:`verify`).  At ``mu_samples`` values of mu (both extremes
and the middle included), every one of ``entries`` steady-state entries into the strip
(Sect. 7.1, :func:`~selfalign.analysis.positioning.positioning_grid`) must end at rest or
accumulate, and with ``accumulation`` every one must accumulate; the sufficient condition
of Sect. 7.3 (x_{n+1}(x_mu) < x_stick_min, eq. 59) is reported where eq. 59 applies.  The
end positions are bounded over the whole mu interval and every entry phase, not only at the
samples (:func:`end_bounds`): no part rests below x_stick_min at mu_max (eq. 41, a proof; for
a design whose entries all accumulate the bound is the range of eq. 41 over the interval), and
the largest end is the largest sample plus the allowance the sampling gives for what lies
between samples (:func:`phase_sup`, :func:`mu_sup`).  The middle of the bound is x_d, its
half-width the robust error Delta_x_d,mu, which must not exceed the tolerance.  The process time
is simulated: the part at rest on the table (x' = 0) a distance D before the strip at the
start of the dwell (t = 0), until its first arrival within the tolerance of x_d
(``t_arrive``; an accumulation reaches x_d only as t -> infinity, so the band is needed)
and until the solver decides rest or accumulation (``t_rest``), at every mu sample; its bound
over the interval (:func:`worst_process_time`) must not exceed ``max_process_time``.

The guarantee is as strong as the model (:data:`ASSUMPTIONS`, with the spec's effects:
``Design.assumptions``).
"""

from __future__ import annotations

import math
import time
from dataclasses import dataclass

import numpy as np

from ..model.design_spec import FRONT_SIMULATED, DesignSpec
from ..model.errors import check_integer
from ..model.friction import FrictionLaw, StopZone, stick_limit, stick_limits, transition_slope
from ..model.profiles import (
    CASE_LABELS,
    ThreePhaseProfile,
    finite_jerk_times,
    three_phase_feasibility,
    three_phase_times,
)
from ..model.units import SIScale
from ..progress import Progress
from ..solvers.driver import simulate_batch
from ..solvers.outcomes import STATUS_CODES, Status
from ..solvers.tables import setting_method, setting_table
from .positioning import MAX_ENTRY_PERIODS, MAX_PERIODS, MEMORY_LIMIT, positioning_bytes, positioning_grid
from .steady_state import steady_state_grid
from .stick_map import stick_map, stick_map_validity

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
#: Values of mu at which the closed-form conditions are checked.
DENSE_MU = 65
#: Relative mu deviations at which the robustness margin is evaluated (closed forms).
MARGIN_STEPS = np.linspace(0.0, 0.96, 49)
#: Candidates verified per call of the engine.
BATCH = 8
#: Why a verified candidate is not guaranteed (the start of its ``failure`` text).
FAILURES = ("entries that do not stop", "entries that do not accumulate", "end positions spread beyond the tolerance",
            "the process run does not end at rest", "process time beyond max_process_time")
#: A change of the end position between adjacent entry phases above this many times the median
#: change is a jump (an entry sticking once more or once less), not a slope (:func:`phase_sup`).
JUMP_RATIO = 10.0
#: Status codes of entries that end.
_STOP = (STATUS_CODES[Status.REST], STATUS_CODES[Status.ACCUMULATION])


@dataclass(frozen=True)
class Candidates:
    """Designs in SI as flat arrays: period [s], stroke [m], y2, y3 [m/s^2], c_mu."""

    period: np.ndarray
    stroke: np.ndarray
    y2: np.ndarray
    y3: np.ndarray
    c_mu: np.ndarray

    def take(self, index) -> Candidates:
        return Candidates(*(getattr(self, k)[index] for k in ("period", "stroke", "y2", "y3", "c_mu")))

    def __len__(self) -> int:
        return self.period.size


def search_grid(spec: DesignSpec) -> Candidates:
    """Every design of the search grid (:class:`~selfalign.model.design_spec.DesignGrid`)."""
    g = spec.grid
    lo, hi = spec.period
    periods = np.geomspace(lo, hi, g.periods) if lo < hi else np.array([lo])
    if spec.min_stroke is None:
        strokes = spec.max_stroke * np.arange(1, g.strokes + 1) / g.strokes
    else:
        strokes = np.unique(np.linspace(spec.min_stroke, spec.max_stroke, g.strokes))
    accels = spec.max_acceleration * np.arange(1, g.accelerations + 1) / g.accelerations
    c_values = np.array([spec.c_mu[0]]) if spec.c_mu_fixed else np.linspace(*spec.c_mu, g.c_mu)
    mesh = np.meshgrid(periods, strokes, accels, accels, c_values, indexing="ij")
    return Candidates(*(a.ravel() for a in mesh))


def scale(spec: DesignSpec, mu: float) -> SIScale:
    """The SI scale of the model at friction coefficient ``mu`` (L = the part's width)."""
    return SIScale(mu=float(mu), g=spec.g, L=spec.width)


def dimensionless(spec: DesignSpec, cand: Candidates, mu: float):
    """(dt, dy, y2, y3) of the SI designs as the model sees them at ``mu``."""
    s = scale(spec, mu)
    return (cand.period / s.T, cand.stroke / s.L, cand.y2 / s.unit("acceleration"),
            cand.y3 / s.unit("acceleration"))


def mu_values(spec: DesignSpec, n: int) -> np.ndarray:
    lo, hi = spec.mu_range
    return np.linspace(lo, hi, n) if hi > lo else np.full(n, lo)


def friction_at(spec: DesignSpec, mu: float) -> FrictionLaw:
    """The spec's friction law as the model sees it at ``mu``: its Stribeck velocity (m/s in the
    spec) in the velocity unit sqrt(mu g L)."""
    law = spec.friction
    if not law.stribeck:
        return law
    return FrictionLaw("stribeck", law.ratio, v_s=law.v_s / scale(spec, mu).unit("velocity"), delta=law.delta)


def ramp_at(spec: DesignSpec, mu: float) -> float:
    """The spec's y'' ramp time in the time unit T(mu) (0 for the paper's jumps)."""
    return 0.0 if spec.ramp is None else spec.ramp / scale(spec, mu).T


def stick_offset(spec: DesignSpec, cand: Candidates, mu: float) -> np.ndarray:
    """x_stick_min - x_mu (eq. 41, :data:`~selfalign.model.friction.stick_limits`) at ``mu``, in m."""
    rest_acceleration = scale(spec, mu).to_dimensionless(np.maximum(cand.y2, cand.y3), "acceleration")
    return stick_limits(rest_acceleration, spec.width, cand.c_mu)


def end_spread(spec: DesignSpec, cand: Candidates) -> np.ndarray:
    """Half the range of x_stick_min (eq. 41) over the mu range, in m: the robust positioning
    error of a design whose entries all accumulate (inf where the strip cannot hold the part)."""
    lo, hi = spec.mu_range
    with np.errstate(invalid="ignore"):
        spread = 0.5 * (stick_offset(spec, cand, lo) - stick_offset(spec, cand, hi))
    return np.where(np.isnan(spread), np.inf, spread)


@dataclass(frozen=True)
class Screen:
    """Closed-form conditions per candidate over the dense mu sample (see the module docstring).

    ``physical``, ``holds`` (the strip can hold the part at every mu), ``moves`` (forward at
    every mu; evaluated only where it holds, False elsewhere), ``shape`` (y2'' > y3'' where
    accumulation is asked for, else True), ``within`` (x_stick_min moves by at most the
    tolerance, accumulation only, else True); ``ok``: all
    of these; ``short_slip``: omega (t2 - t1) < pi / 2 at mu_max, omega = sqrt((c_mu - 1) mu g / w),
    necessary for the sufficient condition of Sect. 7.3 (cos(omega (t2 - t1)) > (y2'' - mu g) /
    (2 (y2'' + y3'')) > 0, eq. 59) and used to order the candidates, not to exclude any;
    ``vbar_min`` [m/s] the slowest steady state over mu; ``t_estimate`` [s] = (D + x_stick_min(mu_max)
    - tolerance) / vbar_min, the closed-form process time.
    """

    physical: np.ndarray
    moves: np.ndarray
    holds: np.ndarray
    shape: np.ndarray
    within: np.ndarray
    short_slip: np.ndarray
    vbar_min: np.ndarray
    t_estimate: np.ndarray

    @property
    def ok(self) -> np.ndarray:
        return self.physical & self.moves & self.holds & self.shape & self.within


def _moves_and_holds(spec: DesignSpec, cand: Candidates, mus) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """(moves at every mu, holds at every mu, slowest vbar [m/s]; -inf where it does not move or
    hold) of the physical candidates.  The extremes of ``mus`` come first and each mu evaluates
    only the candidates still alive, so most are dropped after one or two."""
    holds = stick_offset(spec, cand, float(np.min(mus))) < np.inf  # mu_bar >= max |y''| somewhere
    moves = holds.copy()
    vbar_min = np.where(holds, np.inf, -np.inf)
    mus = np.asarray(mus, dtype=float)
    ordered = np.concatenate([[mus.max(), mus.min()], mus[(mus != mus.max()) & (mus != mus.min())]])
    for mu in ordered:
        alive = np.flatnonzero(moves)
        if alive.size == 0:
            break
        ss = steady_state_grid(*dimensionless(spec, cand.take(alive), mu))
        v = ss.vbar * scale(spec, mu).unit("velocity")
        ok = (ss.case > 0) & (v > 0)
        moves[alive] = ok
        vbar_min[alive] = np.where(ok, np.minimum(vbar_min[alive], v), -np.inf)
    return moves, holds, vbar_min


def screen(spec: DesignSpec, cand: Candidates) -> Screen:
    """The closed-form conditions of every candidate (:class:`Screen`)."""
    physical = three_phase_feasibility(cand.period, cand.stroke, cand.y2, cand.y3) <= 1.0  # mu-free (q)
    n = len(cand)
    moves, holds, vbar_min = np.zeros(n, bool), np.zeros(n, bool), np.full(n, np.nan)
    idx = np.flatnonzero(physical)
    m, h, v = _moves_and_holds(spec, cand.take(idx), mu_values(spec, DENSE_MU))
    moves[idx], holds[idx], vbar_min[idx] = m, h, v
    shape = cand.y2 > cand.y3 if spec.accumulation else np.ones(n, bool)
    within = end_spread(spec, cand) <= spec.tolerance if spec.accumulation else np.ones(n, bool)
    # A lower bound of the process time: the part covers the distance and, in the strip, at least
    # x_stick_min (eq. 41) at mu_max less the tolerance, at no more than the slowest steady speed.
    inside = np.zeros(n)
    inside[moves] = stick_offset(spec, cand.take(moves), spec.mu_range[1])
    with np.errstate(divide="ignore", invalid="ignore"):
        t_est = np.where(moves, (spec.distance + np.maximum(inside - spec.tolerance, 0.0)) / vbar_min, np.inf)
    return Screen(physical, moves, holds, shape, within, slip_phase(spec, cand) < 0.5 * math.pi, vbar_min, t_est)


def slip_frequency(spec: DesignSpec, c_mu):
    """omega = sqrt(b1) / T = sqrt((c_mu - 1) mu g / w) in rad/s at mu_max: the frequency of the
    harmonic slip of Sect. 7.3 (eq. 42) in the strip (b1 with the part's width as the unit of length)."""
    return np.sqrt(transition_slope(np.asarray(c_mu, dtype=float), 1.0)) / scale(spec, spec.mu_range[1]).T


def slip_phase(spec: DesignSpec, cand: Candidates) -> np.ndarray:
    """omega (t2 - t1) at mu_max (:func:`slip_frequency`): the phase of the harmonic slip over the
    y2'' window (the Appendix's times are scale-free)."""
    times = three_phase_times(cand.period, cand.stroke, cand.y2, cand.y3)
    return slip_frequency(spec, cand.c_mu) * (times.t2 - times.t1)


def robustness_margin(spec: DesignSpec, cand: Candidates) -> np.ndarray:
    """Largest relative deviation d (on :data:`MARGIN_STEPS`) such that the closed-form
    conditions (forward motion, a strip that holds, y2'' > y3'' with accumulation) hold at
    every mu in [mu (1 - d), mu (1 + d)] (``mu`` the spec's nominal value)."""
    margin = np.full(len(cand), -1.0)
    alive = np.ones(len(cand), bool)
    if spec.accumulation:
        alive &= cand.y2 > cand.y3
    for d in MARGIN_STEPS:
        idx = np.flatnonzero(alive)
        if idx.size == 0:
            break
        m, h, _ = _moves_and_holds(spec, cand.take(idx), np.array([spec.mu * (1 - d), spec.mu * (1 + d)]))
        alive[idx] = m & h
        margin[alive] = d
    return margin


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
    out = {key: np.full(shape, np.nan) for key in ("vbar", "frac_accumulate", "frac_stop", "frac_never_stop",
                                                  "frac_undecided", "dx_d", "x_stick_min", "end_min", "end_max",
                                                  "t_arrive", "t_rest")}
    ends = np.full(shape + (n_entries,), np.nan)
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
    # under static friction nothing accumulates (README "Static and kinetic friction"); with
    # another effect it is left at -1 (does not apply).
    paper_model = spec.friction.kind == "coulomb" and spec.ramp is None
    for i in range(k):
        for j, mu in enumerate(mus):
            if paper_model and case[i, j] > 0:
                profile = ThreePhaseProfile(*(float(a[i]) for a in dims[j]))
                sufficient[i, j] = sufficient_condition(profile, float(cand.c_mu[i]))
    stops = np.all((out["frac_accumulate"] + out["frac_stop"]) == 1.0, axis=1)
    accumulates = np.all(out["frac_accumulate"] == 1.0, axis=1)
    lo, hi = end_bounds(ends, out["x_stick_min"], stops)
    x_d, error = 0.5 * (lo + hi), 0.5 * (hi - lo)
    with np.errstate(invalid="ignore"):
        sampled_error = np.where(stops, 0.5 * (np.max(out["end_max"], axis=1) - np.min(out["end_min"], axis=1)),
                                 np.nan)
    process_stops = _process_runs(spec, cand, mus, dims, x_d, stops, out, methods)
    t_worst = worst_process_time(out["t_arrive"], cand.period)
    within = error <= spec.tolerance
    in_time = np.ones(k, bool) if spec.max_process_time is None else t_worst <= spec.max_process_time
    wanted = accumulates if spec.accumulation else stops
    guaranteed = wanted & within & process_stops.all(axis=1) & in_time
    failure = tuple(_failure(spec, i, out, stops, accumulates, within, process_stops, in_time, sufficient)
                    for i in range(k))
    return Verification(mu=mus, case=case, sufficient=sufficient, process_stops=process_stops, x_d=x_d, error=error,
                        sampled_error=sampled_error, t_worst=t_worst, stops=stops, accumulates=accumulates,
                        guaranteed=guaranteed, failure=failure,
                        method="; ".join(sorted(methods - {""})), **out)


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
        out["t_rest"][rows, j] = res.t_end * period
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


@dataclass(frozen=True)
class Design:
    """The answer of :func:`design`: the chosen profile in SI, its performance and its guarantee.

    ``found``: a guaranteed design exists on the grid; otherwise ``explanation`` says which
    constraint binds and what would have to change, and the profile fields hold the best
    candidate the engine checked (if any).  Profile: ``period`` [s], ``frequency`` [Hz],
    ``stroke`` [m], ``y2``, ``y3`` [m/s^2] (magnitudes of the two acceleration phases),
    ``c_mu``, the phase times ``t1``, ``t2``, ``t3`` [s] (zero acceleration on [0, t1),
    -y2'' on [t1, t2), +y3'' on [t2, t3)), ``y_ini`` [m], ``yd_ini`` [m/s].  ``case``:
    Table 1 at the nominal mu; ``vbar`` [m/s] at the nominal mu and ``vbar_min`` over the
    range; ``margin``: robustness margin (relative mu deviation, closed forms).
    ``verification``: the engine's results (one row); ``t_arrive``, ``t_rest`` [s]: worst
    over the mu samples; ``x_d``, ``error`` [m] from the strip's edge; ``front_*``: the
    trade-offs (module :func:`design`); ``search``: counts and the time taken.
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

    @property
    def frequency(self) -> float:
        return 1.0 / self.period

    @property
    def times(self):
        """Phase times etc. of the SI profile (the Appendix's closed form is scale-free)."""
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
        return CASE_LABELS[self.case]

    @property
    def assumptions(self) -> tuple[str, ...]:
        """:data:`ASSUMPTIONS`, with the spec's friction law and profile in place of the paper's."""
        law, ramp = self.spec.friction, self.spec.ramp
        friction = ASSUMPTIONS[1] if law.kind == "coulomb" else (
            f"{self.spec.effects().split('; ')[0]}, kinetic coefficient mu on the base and c_mu mu on the strip")
        profile = ASSUMPTIONS[3] if ramp is None else (
            f"the three-phase profile with y'' ramps of {1e3 * ramp:g} ms at each switch (finite jerk), no actuator "
            f"dynamics")
        return (ASSUMPTIONS[0], friction, ASSUMPTIONS[2], profile, *ASSUMPTIONS[4:])

    def profile_at(self, mu: float) -> ThreePhaseProfile:
        """The dimensionless profile the model sees at friction coefficient ``mu`` (L = width)."""
        cand = Candidates(*(np.array([v]) for v in (self.period, self.stroke, self.y2, self.y3, self.c_mu)))
        return ThreePhaseProfile(*(float(a[0]) for a in dimensionless(self.spec, cand, mu)))

    def report(self, *, timed: bool = True) -> str:
        """The design as text: inputs, profile, performance, guarantee, assumptions; ``timed``:
        end with the search's wall-clock time (a measurement, left out of result files)."""
        lines = [f"design {self.spec.name}: {self.spec.describe()}"]
        if not self.found:
            lines.append(f"NO GUARANTEED DESIGN: {self.explanation}")
        if self.verification is None:
            return "\n".join(lines)
        v, t = self.verification, self.times
        lines += [
            ("" if self.found else "the fastest candidate checked, NOT guaranteed: ") +
            f"profile: period {1e3 * self.period:.4g} ms ({self.frequency:.4g} Hz), stroke {1e3 * self.stroke:.4g} mm, "
            f"y2'' = {self.y2:.4g} m/s^2, y3'' = {self.y3:.4g} m/s^2, c_mu = {self.c_mu:.4g}",
            f"phases: y'' = 0 on [0, {1e3 * float(t.t1):.4g}) ms, -y2'' on [.., {1e3 * float(t.t2):.4g}) ms, "
            f"+y3'' on [.., {1e3 * self.period:.4g}) ms; y_ini = {1e3 * float(t.y_ini):.4g} mm, "
            f"y'_ini = {float(t.yd_ini):.4g} m/s",
            f"case {self.case} ({self.case_label}) at mu = {self.spec.mu:g}; vbar = {1e3 * self.vbar:.4g} mm/s "
            f"(slowest over the mu range {1e3 * self.vbar_min:.4g} mm/s)",
            f"process time from rest {1e3 * self.spec.distance:g} mm before the strip at t = 0: first within "
            f"{1e6 * self.spec.tolerance:g} um of x_d after {self.t_arrive:.4g} s, at rest after {self.t_rest:.4g} s "
            f"(worst over {v.mu.size} mu samples, simulated); at most {self.t_worst:.4g} s over the mu interval "
            f"(bound)",
            f"end position x_d = {1e6 * self.x_d:.4g} um past the strip's edge, error +-{1e6 * self.error:.4g} um "
            f"over every entry phase and mu in the interval (bound; +-{1e6 * float(v.sampled_error[0]):.4g} um over "
            f"the simulated entries); x_stick_min = "
            + ", ".join(f"{1e6 * x:.4g}" for x in v.x_stick_min[0]) + " um at mu = "
            + ", ".join(f"{m:.4g}" for m in v.mu),
            "Delta_x_d (eq. 39) per mu: " + ", ".join(f"{1e6 * x:.3g}" for x in v.dx_d[0]) + " um; accumulating "
            "entries: " + ", ".join(f"{100 * a:.0f} %" for a in v.frac_accumulate[0]),
            "sufficient condition of Sect. 7.3 per mu: "
            + ", ".join({1: "holds", 0: "fails", -1: "n/a"}[int(s)] for s in v.sufficient[0]),
            ("guarantee: yes, every criterion holds" if v.guaranteed[0] else f"guarantee: NO, found: {v.failure[0]}")
            + f". Criterion: every one of {self.search['entries']} steady-state entries at each of {v.mu.size} mu "
            f"in [{v.mu[0]:.4g}, {v.mu[-1]:.4g}] ends at rest" + (" by accumulation" if self.spec.accumulation else "")
            + f", within +-{1e6 * self.spec.tolerance:g} um, and the process run ends"
            + ("" if self.spec.max_process_time is None else f" within {self.spec.max_process_time:g} s")
            + "; bounds over the mu interval and every entry phase: no end below x_stick_min(mu_max) (eq. 41), "
            "the largest end and the process time with the sampling's allowance (analysis.design.end_bounds)"
            + f"; closed forms at {DENSE_MU} mu; robustness margin +-{100 * self.margin:.0f} % of mu",
            f"effects: {self.spec.effects()}; simulated with {v.method}",
            "assumes: " + "; ".join(self.assumptions),
            f"search: {self.search['designs']} designs"
            + (f", {self.search['ramps_do_not_fit']} physical ones dropped (the ramps do not fit)" if self.spec.ramp
               else "")
            + f", {self.search['screened']} pass the closed forms (the paper's model: a heuristic ranking where "
            f"effects are declared), {self.search['verified']} simulated"
            + (f", {self.search['seconds']:.2g} s" if timed else ""),
        ]
        return "\n".join(lines)


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


def _explain(spec: DesignSpec, cand: Candidates, scr: Screen, checked: Verification | None) -> str:
    """Which constraint empties the set of designs, and what would have to change."""
    lo, hi = spec.mu_range
    amax = spec.max_acceleration
    if not scr.physical.any():
        p = spec.period[1]
        largest = p * p * amax / 16  # q <= 1 with y2'' = y3'' = amax
        return (f"no physical profile in the limits (Sect. 5.1: 8 dy (1/y2'' + 1/y3'') <= dt^2): at the longest "
                f"period {1e3 * p:.4g} ms and |y''| = {amax:g} m/s^2 the stroke must be <= {1e3 * largest:.4g} mm, "
                f"the grid's smallest is {1e3 * float(cand.stroke.min()):.4g} mm")
    c_max = spec.c_mu[1]
    if not (scr.physical & scr.moves & scr.holds).any():
        if amax <= hi * spec.g:
            return (f"the part moves forward at every mu only if y2'' > mu (1 + delta) g = {hi * spec.g:.4g} m/s^2; "
                    f"the actuator allows at most {amax:g} m/s^2")
        if c_max * lo <= hi:
            return (f"stopping needs max(y2'', y3'') <= c_mu mu (1 - delta) g = {c_max * lo * spec.g:.4g} m/s^2 and "
                    f"moving needs y2'' > mu (1 + delta) g = {hi * spec.g:.4g} m/s^2: c_mu must exceed (1 + delta)/"
                    f"(1 - delta) = {hi / lo:.4g} (or delta be below (c_mu - 1)/(c_mu + 1) = "
                    f"{(c_max - 1) / (c_max + 1):.3g})")
        return (f"no profile in the limits both moves the part forward at every mu (closed-form steady state) and "
                f"keeps max(y2'', y3'') <= c_mu mu (1 - delta) g = {c_max * lo * spec.g:.4g} m/s^2")
    base = scr.physical & scr.moves & scr.holds
    if spec.accumulation and not (base & scr.shape).any():
        return (f"accumulation needs y2'' > y3'' with y2'' > mu (1 + delta) g = {hi * spec.g:.4g} m/s^2, and no such "
                f"profile in the limits moves the part at every mu")
    if spec.accumulation and not (base & scr.shape & scr.within).any():
        need = hi * spec.g
        allowed = 2 * spec.tolerance * spec.g * (c_max - 1) / (spec.width * (1 / lo - 1 / hi))
        return (f"with accumulation the end x_stick_min (eq. 41) moves with mu by w y2''/(g (c_mu - 1)) "
                f"(1/mu_min - 1/mu_max); keeping it within +-{1e6 * spec.tolerance:g} um needs y2'' <= "
                f"{allowed:.4g} m/s^2, but moving at mu_max needs y2'' > {need:.4g} m/s^2: widen the tolerance to "
                f"{1e6 * float(end_spread(spec, cand.take(np.flatnonzero(base & scr.shape))).min()):.3g} um, narrow "
                f"the mu uncertainty or raise c_mu")
    if spec.max_process_time is not None and not (scr.ok & (scr.t_estimate <= spec.max_process_time)).any():
        return (f"the fastest design that passes the closed forms needs {float(scr.t_estimate[scr.ok].min()):.4g} s "
                f"(steady state), more than max_process_time = {spec.max_process_time:g} s")
    if checked is None:
        return "no candidate was simulated"
    counts = {why: sum(text.startswith(why) for text in checked.failure) for why in FAILURES}
    summary = "; ".join(f"{n} with {why}" for why, n in counts.items() if n)
    text = f"none of the {len(checked.failure)} best candidates passes the simulated guarantee ({summary})"
    if spec.accumulation and not checked.accumulates.any():
        suff = checked.sufficient
        phase = slip_phase(spec, cand.take(np.flatnonzero(scr.ok)))
        omega = float(slip_frequency(spec, spec.c_mu[0]))
        text += (f". Accumulation needs y2'' > y3'' and, for the sufficient condition of Sect. 7.3 "
                 f"(x_(n+1)(x_mu) < x_stick_min, eq. 59), cos(omega (t2 - t1)) > (y2'' - mu g) / (2 (y2'' + y3'')) > 0 "
                 f"with omega = sqrt((c_mu - 1) mu g / w) = {omega:.4g} rad/s at mu_max: omega (t2 - t1) < pi/2; "
                 f"{int((phase < 0.5 * math.pi).sum())} of the {phase.size} designs that move and stop have it "
                 f"(smallest omega (t2 - t1) = {float(phase.min()):.3g} rad) and the condition held at "
                 f"{int((suff == 1).sum())} of {suff.size} simulated (candidate, mu) pairs: a shorter slip window "
                 f"(a smaller stroke or a higher frequency), a lower c_mu, or no accumulation requirement")
    return text


def design(spec: DesignSpec, *, progress: str = "auto") -> Design:
    """The guaranteed three-phase design of ``spec`` (module docstring); the trade-offs:
    ``front_time_error`` (the designs not dominated in closed-form process time and end
    spread over mu, the first :data:`FRONT_SIMULATED` of them simulated: ``t_arrive``,
    ``error``, ``guaranteed``) and ``front_time_margin`` (closed-form process time against
    the robustness margin)."""
    if not isinstance(spec, DesignSpec):
        raise ValueError(f"design needs a DesignSpec (selfalign.io.design_spec.load_design_spec reads one), "
                         f"got {type(spec).__name__}")
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
