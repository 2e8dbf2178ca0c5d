"""The fastest table motion: the largest steady mean velocity of the part under an acceleration limit,
proven, and under speed and stroke limits too (beyond the paper, which optimises within the three-phase
family of Sect. 4.4.3; derivation, proof and search on the page docs/explanation/optimal-motion.md).

Acceleration limit |y''| <= a alone (proven): :func:`optimal_vbar` is the bound
v* = (a^2 - 1) r^2 dt / (4 a (1 + r)^2) (:func:`selfalign.model.optimal_motion.optimal_mean_velocity`) and
:func:`optimal_profile` returns the motion that attains it, y'' = -a, +a, +r
(:func:`selfalign.model.optimal_motion.optimal_phase_times`).  On it the part comes to rest exactly where
y'' jumps from +a to +r; under static friction (r > 1) a part that arrived a rounding error late, moving
backward, would slide backward for good (kinetic friction 1 cannot stop it against y'' = r > 1).  Every
returned motion therefore ends its slides with the part still moving forward at x' = m =
:data:`ARRIVAL_MARGIN` a dt (:func:`fastest_pieces`): it comes to rest just after y'' has switched to
its stick level and sticks.  This costs a relative ~1e-12 of v*.

Speed limit |y'| <= velocity_max (y' of zero mean, as a periodic y needs) and stroke limit
max y - min y <= stroke_max (y's offset is free) (numerical): k copies of the fastest motion of period
dt / k attain v* / k, the most any motion of period dt / k can, and meet the limits from k_fit on (speed
and stroke shrink as 1 / k and 1 / k^2); k_fit = 1 returns the fastest motion.  Otherwise the search runs
over motions made of sub-cycles, each a forward slide from rest that opens with y'' = -a followed by a
stick, all at period 1 (t -> t / dt):

* k < k_fit equal sub-cycles (:func:`search`): for a fixed slide time D a linear programme in y'' on a
  grid of cells (:func:`slide_programme`), solved globally by HiGHS; the best D per k by a scan and a
  bounded scalar search (:func:`best_slide`), the best k by doubling and a golden-section search on the
  integers (the value taken unimodal in k); the two best grid solutions polished by SLSQP over their arcs
  of constant y'' (:func:`polish`);
* sub-cycles of unequal lengths (:func:`unequal`): k_fit and k_fit + 1 copies of the fastest motion and
  the equal motions found, for at most :data:`JOINT_SUB_CYCLES` sub-cycles, stretched apart and polished
  as one motion.

The fastest of these and of the k_fit copies is chosen by the exact solver (:func:`steady_mean_velocity`),
which must agree with the closed form of each candidate's slides.

A period range (min, max): the longest period under the acceleration limit alone (v* is proportional to
dt), else up to the longest period the fastest motion fits, and a scan with a bounded search beyond it
(:func:`_best_period`).  A jerk limit |y'''| <= j: the ramped bang-bang-stick family, y'' held at a stick,
a pull-back, a coast and a catch-up level and ramped between them at the full jerk, by SLSQP on the exact
solver's mean velocity (:func:`jerk_limited`); not the optimum (a general search beats it).
"""

from __future__ import annotations

import math
from dataclasses import dataclass, replace

import numpy as np

from ..model.errors import check_finite, check_positive
from ..model.friction import FrictionLaw
from ..model.optimal_motion import optimal_mean_velocity, optimal_phase_times
from ..model.profiles import PiecewiseConstantProfile, check_scale
from ..solvers.driver import simulate_batch
from ..solvers.outcomes import Reason, Status
from ..solvers.records import DT
from ..solvers.tables import ProfileTable, profile_table

#: x' the returned motions leave the part at the end of a slide, relative to the table's speed scale
#: a dt: it arrives at rest just after y'' has switched to its stick level, not a rounding error before.
ARRIVAL_MARGIN = 2.0**-40
#: Longest cycle of period-boundary states :func:`steady_mean_velocity` recognises, in periods.
MAX_CYCLE = 64
#: Period budget of :func:`steady_mean_velocity`: a motion that has not settled by then gets NaN.
MAX_PERIODS = 100_000
#: Cells of the slide and of the stick in the linear programme that picks k and D, and in the one whose
#: solution is polished.
SCAN_CELLS, FINE_CELLS = 24, 96
#: Slide times D per k tried before the scalar search refines the best.
D_SCAN = 8
#: Fraction of a limit the polish keeps free: SLSQP ends up to ~1e-9 beyond its constraints, and k copies
#: of a sub-cycle place their breaks with a rounding that moves y' by up to ~k^2 eps of its scale (the
#: polish keeps LIMIT_SLACK + 64 eps k^2 free); the returned motion meets the limits exactly.
LIMIT_SLACK = 1e-8
#: Multiples of the slack the polish retries with when SLSQP ends outside a limit (it can end up to ~1e-5
#: beyond one, and a retry from there with too small a slack may not move): at most 1e-3 of a limit, a
#: relative loss of v-bar of the same order.
RETRY_SLACK = (1.0, 10.0, 100.0, 1e3, 1e4, 1e5)
#: Most sub-cycles per period the search builds: limits that need more are refused (a shorter period
#: is the same motion with fewer pieces).
MAX_SUB_CYCLES = 1024
#: Most sub-cycles a motion may have for its sub-cycles to be stretched to unequal lengths and polished
#: together (:func:`unequal`), and the stretches tried.
JOINT_SUB_CYCLES = 4
STRETCH = (0.3, 0.6)
#: A limit is reported binding when the motion uses all but this fraction of it.
BINDING = 1e-6
#: Agreement required between the exact solver's mean velocity and the closed form of the motion.
CLOSED_FORM_RTOL = 1e-9
#: Candidate motions whose mean velocities lie within this fraction of the fastest are taken as equally fast,
#: and the simplest of them is returned (fewest different sub-cycles, then fewest arcs).  Under a speed and a
#: stroke limit the optimum can be degenerate: at Fig. 6's limits three motions of three sub-cycles lie within
#: 4e-9 of each other, and which one the polish ranks first depends on the BLAS kernel and its threads.  The
#: polish itself moves v-bar by ~1e-9 between kernels; ties are decided well above that and well below the
#: 1e-6 to which the general searches confirm the optimum.
TIE_RTOL = 1e-8
#: A level of y'' within this fraction of +-a or +-r of a bound or of 0 is named as there in ``family``: the
#: polish places a coast at 0 only to ~1e-8 a (at Fig. 6's limits -8e-9 a on one BLAS kernel, 0 on another).
LEVEL_RTOL = 1e-6
#: A period range beyond the longest period the fastest motion fits: periods scanned per octave, at most in
#: all, and the bounded scalar search around the best (relative tolerance, evaluations).
PERIOD_SCAN, PERIOD_POINTS = 4, 16
PERIOD_XTOL, PERIOD_REFINE, PERIOD_PEAKS = 1e-3, 8, 3


@dataclass(frozen=True)
class OptimalProfile:
    """The fastest table motion found by :func:`~selfalign.optimal_profile`, and how fast the part moves on it.

    Built by :func:`~selfalign.optimal_profile`, which documents how; the fields are stored as given.

    Parameters
    ----------
    profile : PiecewiseConstantProfile
        The table motion: y'' piecewise constant, y' of zero mean, y's range centred on 0.
    vbar : float
        The part's steady mean velocity on it (eq. 10), from the exact solver.
    vbar_bound : float
        The proven bound v* under the acceleration limit alone (:func:`~selfalign.optimal_vbar`).
    binding : tuple of str
        The limits the motion uses to the full.
    family : str
        The structure of one sub-cycle of the motion.
    sub_cycles : int
        Slides per period.
    peak_velocity : float
        The largest table speed.
    stroke : float
        The table's stroke.
    period : float, optional
        The table's period, given or chosen within a range.  Default None.

    Attributes
    ----------
    profile : PiecewiseConstantProfile or PiecewiseLinearProfile
        The table motion: y'' piecewise constant (piecewise linear and continuous under a jerk limit),
        y' of zero mean (so y is periodic), y's range centred on 0; :func:`~selfalign.simulate`,
        :func:`~selfalign.simulate_batch` and a
        :class:`~selfalign.Scene` take it.
    vbar : float
        The steady mean velocity of the part relative to the table (eq. 10) on a uniform surface, from
        the exact solver, starting from rest at t = 0.
    vbar_bound : float
        The proven bound v* = (a^2 - 1) r^2 dt / (4 a (1 + r)^2) of the acceleration limit alone: no
        table motion of the period beats it, and ``vbar`` equals it (up to ``ARRIVAL_MARGIN``) when no
        other limit binds.
    binding : tuple of str
        The limits the motion uses to the full, among "accel_max", "velocity_max", "stroke_max",
        "jerk_max" (always, under a jerk limit: its ramps run at the full jerk) and, for a period range,
        "period" (the period chosen is an end of the range).
    family : str
        The structure of each sub-cycle (a slide and the stick after it), its constant-y'' pieces in order:
        "bang" (y'' = -+a, the part slides), "coast" (y'' = 0 while it slides), "ramp" (another level while
        it slides), "stick" (y'' = +-r, the static limit, while it sticks), "dwell" (y'' = 0 while it
        sticks) or "hold" (another level while it sticks).  k > 1 sub-cycles of one structure read
        "structure x k" (their lengths may differ), of several structures the structures joined by " | ".
        Under a jerk limit "ramped " and the names of the levels y'' holds or peaks at between its ramps.
    sub_cycles : int
        k, the slides per period.
    peak_velocity : float
        max ``|y'|``.
    stroke : float
        max y - min y.
    period : float or None
        The table's period dt: the one given, or the one chosen within a range (None only when built
        without it).

    See Also
    --------
    optimal_profile : Builds it.
    optimal_vbar : The bound alone.

    Examples
    --------
    >>> import selfalign as sa
    >>> best = sa.optimal_profile(1.0, 3.0)
    >>> print(best.family, best.binding, round(best.vbar, 9), round(best.vbar_bound, 9))
    bang-bang-stick ('accel_max',) 0.166666667 0.166666667
    """

    profile: PiecewiseConstantProfile
    vbar: float
    vbar_bound: float
    binding: tuple
    family: str
    sub_cycles: int
    peak_velocity: float
    stroke: float
    period: float | None = None


def check_ratio(ratio) -> float:
    """r = mu_s / mu_k as a float: a finite real number >= 1."""
    ratio = check_finite("ratio", ratio)
    if ratio < 1.0:
        raise ValueError(f"ratio = mu_s / mu_k must be >= 1 (static friction is at least kinetic), got {ratio!r}")
    return ratio


def check_moving(accel_max: float, ratio: float) -> None:
    """ValueError unless accel_max > ratio: below it the part never leaves the table's motion."""
    if not accel_max > ratio:
        raise ValueError(f"accel_max must exceed the static friction limit r = mu_s / mu_k = {ratio!r} (a stuck "
                         f"part stays stuck while |y''| <= r, so nothing moves), got {accel_max!r}")


def optimal_vbar(period, accel_max, ratio=1.0) -> float:
    """The largest steady mean velocity of the part under a table acceleration limit (proven bound).

    On a uniform surface (mu_bar = 1, Sect. 3.2) no periodic table motion of period dt with
    ``|y''| <= a`` moves the part faster on average than v* = (a^2 - 1) r^2 dt / (4 a (1 + r)^2), r the
    static/kinetic friction ratio (1: the paper's Coulomb friction, v* = (a^2 - 1) dt / (16 a)), and one
    motion attains it (:func:`~selfalign.optimal_profile`).  The proof is on the page
    docs/explanation/optimal-motion.md.

    Parameters
    ----------
    period : float
        The table's period dt, dimensionless (Sect. 3.2); in [1e-30, 1e30].
    accel_max : float
        a, the largest ``|y''|``; in [1e-30, 1e30] and above ``ratio``.
    ratio : float
        r = mu_s / mu_k, at least 1.  Default 1.0 (Coulomb).

    Returns
    -------
    float
        v*, dimensionless like x' (Sect. 3.2).

    Raises
    ------
    TypeError
        If a parameter is not a real number.
    ValueError
        If a parameter is not finite, ``period`` or ``accel_max`` lies outside [1e-30, 1e30],
        ``ratio`` < 1, or ``accel_max`` <= ``ratio`` (the part never moves: the mean velocity is 0).

    See Also
    --------
    optimal_profile : The motion that attains it, and the search under velocity and stroke limits.

    Examples
    --------
    The paper's Coulomb friction, T = 1: a = 3 gives 1/6, a = 5 gives 0.3; the best three-phase
    profile of Sect. 4.4.3 reaches 0.125 and 0.2:

    >>> import selfalign as sa
    >>> print(round(sa.optimal_vbar(1.0, 3.0), 12), round(sa.optimal_vbar(1.0, 5.0), 12))
    0.166666666667 0.3
    >>> print(round(sa.optimal_vbar(1.0, 3.0, ratio=1.5), 12))
    0.24
    """
    period, accel_max = check_scale("period", period), check_scale("accel_max", accel_max)
    ratio = check_ratio(ratio)
    check_moving(accel_max, ratio)
    return float(optimal_mean_velocity(period, accel_max, ratio))


def centred_motion(breaks, accels) -> tuple[float, float, float, float]:
    """(y_start, yd_start, peak_velocity, stroke) of the table motion with y'' = ``accels`` on the pieces
    between ``breaks``: y' of zero mean (y periodic), y's range centred on 0; peak velocity max ``|y'|``,
    stroke max y - min y (y' is linear in a piece, so y's extremes lie at the breaks or where y' = 0)."""
    breaks, accels = np.asarray(breaks, dtype=float), np.asarray(accels, dtype=float)
    lengths = np.diff(breaks)
    gained = np.concatenate([[0.0], np.cumsum(accels * lengths)])
    moved = np.concatenate([[0.0], np.cumsum(gained[:-1] * lengths + 0.5 * accels * lengths**2)])
    yd_start = -moved[-1] / breaks[-1]
    velocity = yd_start + gained
    position = moved + yd_start * breaks
    with np.errstate(divide="ignore", invalid="ignore"):
        turn = np.where(accels != 0.0, -velocity[:-1] / accels, -1.0)
    inside = (turn > 0.0) & (turn < lengths)
    turning = (position[:-1] + velocity[:-1] * turn + 0.5 * accels * turn**2)[inside]
    low, high = float(np.min(np.concatenate([position, turning]))), float(np.max(np.concatenate([position, turning])))
    return -(low + high) / 2.0, float(yd_start), float(np.max(np.abs(velocity))), high - low


def steady_mean_velocity(profiles, friction: FrictionLaw | None = None) -> np.ndarray:
    """The part's steady mean velocity (eq. 10) on each piecewise-constant profile, on a uniform surface.

    ``profiles``: a sequence of profiles or a ``selfalign.solvers.tables.ProfileTable`` of them.  The
    exact solver runs them in one batch from rest at t = 0 until the period-boundary state repeats (a
    cycle of up to :data:`MAX_CYCLE` periods, within :data:`MAX_PERIODS`); the mean velocity is the advance
    per period of that cycle over dt, 0 for a part at rest for good, NaN for one that has not settled.  The
    steady state reached from rest is the one meant: under static friction (r > 1) a profile can have
    several.
    """
    table = profiles if isinstance(profiles, ProfileTable) else profile_table(list(profiles), "exact", 0.0, {})
    res = simulate_batch(table, 0.0, 0.0, until="rest", max_periods=MAX_PERIODS, max_cycle=MAX_CYCLE,
                         friction=friction)
    reason = res.reason
    moving = np.isin(reason, [int(c) for c in Reason if c.status is Status.NEVER_STOPS])
    out = np.where(reason == int(Reason.REST), 0.0, np.nan)
    return np.where(moving, res.records["advance"] / table.rows[:, DT], out)


def _friction_ratio(friction) -> tuple[FrictionLaw | None, float]:
    """(the law for the solver, r) of ``friction`` (None: Coulomb)."""
    if friction is None:
        return None, 1.0
    if not isinstance(friction, FrictionLaw):
        raise TypeError(f"friction must be a FrictionLaw (or None for Coulomb friction), got {friction!r} "
                        f"({type(friction).__name__})")
    if friction.stribeck:
        raise ValueError(f"friction must be Coulomb or static_kinetic, got {friction!r}: the bound and the exact "
                         f"solver need a constant kinetic friction")
    return (None if friction.ratio == 1.0 else friction), friction.ratio


def _limit(name: str, value) -> float | None:
    return None if value is None else check_positive(name, value)


def fastest_pieces(period: float, accel_max: float, ratio: float, margin: float) -> tuple[np.ndarray, np.ndarray]:
    """(breaks, accels) of the fastest motion y'' = -a, +a, +r with the catch-up ending when the part still
    has x' = ``margin`` (:data:`ARRIVAL_MARGIN`, module docstring).

    The durations solve t1 + t2 + t3 = dt, -a t1 + a t2 + r t3 = 0 and (a - 1) t1 - (a + 1) t2 = m:
    t1 = t_back - (a - r) m / (2 a (1 + r)), t2 = t_catch - (a + r) m / (2 a (1 + r)) and the stick the
    rest (:func:`~selfalign.model.optimal_motion.optimal_phase_times` at m = 0).  The part slides with x'
    rising at a - 1 to (a - 1) t1, then falling at a + 1 to m, and comes to rest at 1 + r once y'' = r."""
    a, r = accel_max, ratio
    t_back, t_catch, _ = (float(t) for t in optimal_phase_times(period, a, r))
    t1 = t_back - (a - r) * margin / (2.0 * a * (1.0 + r))
    t2 = t_catch - (a + r) * margin / (2.0 * a * (1.0 + r))
    return np.array([0.0, t1, t1 + t2, period]), np.array([-a, a, r])


def _family(arcs: Arcs, a: float, r: float) -> str:
    """The ``family`` name of OptimalProfile: the names of the arcs of each sub-cycle (a slide and the stick
    after it), joined by "-"; "name x k" when all k sub-cycles have one name, else the names joined by
    " | "."""
    cycles = _cycle_names(arcs, a, r)
    return cycles[0] + (f" x {len(cycles)}" if len(cycles) > 1 else "") if len(set(cycles)) == 1 else " | ".join(cycles)


def _cycle_names(arcs: Arcs, a: float, r: float) -> list[str]:
    """The name of each sub-cycle of ``arcs``: the names of its arcs joined by "-" (a sliding arc at +-a is
    a bang, at 0 a coast, else a ramp; a stick arc at +-r a stick, at 0 a dwell, else a hold; "at" to
    :data:`LEVEL_RTOL` of +-a or +-r)."""
    words = []
    for level, slide in zip(arcs.levels.tolist(), arcs.sliding.tolist()):
        top, names = (a, ("bang", "coast", "ramp")) if slide else (r, ("stick", "dwell", "hold"))
        near = LEVEL_RTOL * top
        words.append(names[0] if abs(abs(level) - top) <= near else names[1] if abs(level) <= near else names[2])
    starts = [first for first, _ in arcs.slides()] + [arcs.levels.size]
    return ["-".join(words[i:j]) for i, j in zip(starts, starts[1:])]


@dataclass(frozen=True)
class Arcs:
    """A motion as arcs of constant y'': their ``levels``, ``durations`` (summing to its period) and whether
    the part slides forward on each (``sliding``).  Each run of sliding arcs is one slide from rest, the
    first arc opens a slide and every slide is followed by stick arcs: a sub-cycle is a slide and the stick
    after it."""

    levels: np.ndarray
    durations: np.ndarray
    sliding: np.ndarray

    def slides(self) -> list[tuple[int, int]]:
        """(first, last + 1) arc indices of every slide."""
        edges = np.flatnonzero(np.diff(np.concatenate([[0], self.sliding.astype(int), [0]])))
        return list(zip(edges[::2].tolist(), edges[1::2].tolist()))

    def quantities(self) -> tuple[np.ndarray, np.ndarray, np.ndarray, np.ndarray, float]:
        """(u, y, y_turn, x_end, area): y' at the arc starts and the end (zero mean), y there (y(0) = 0),
        y at each arc's point nearest to where y' = 0 (its extreme within the arc), x' at the end of each
        arc (0 on stick arcs; x' = -int (y'' + 1) dt from the start of its slide) and int x' dt over the
        slides."""
        d, level = self.durations, self.levels
        gained = np.concatenate([[0.0], np.cumsum(level * d)])
        moved = np.concatenate([[0.0], np.cumsum(gained[:-1] * d + 0.5 * level * d * d)])
        start = -moved[-1] / np.sum(d)
        u = start + gained
        y = moved + start * np.concatenate([[0.0], np.cumsum(d)])
        with np.errstate(divide="ignore", invalid="ignore"):
            turn = np.clip(np.where(level != 0.0, -u[:-1] / level, 0.0), 0.0, d)
        y_turn = y[:-1] + u[:-1] * turn + 0.5 * level * turn * turn
        x_end, area = np.zeros(d.size), 0.0
        for first, last in self.slides():
            ends = -np.cumsum((level[first:last] + 1.0) * d[first:last])
            x_end[first:last] = ends
            area += float(np.sum((np.concatenate([[0.0], ends[:-1]]) + ends) * d[first:last]) / 2.0)
        return u, y, y_turn, x_end, area

    def merged(self) -> Arcs:
        """Zero-length arcs dropped and neighbours of one level and mode joined."""
        levels, durations, sliding = [], [], []
        for level, duration, slide in zip(self.levels.tolist(), self.durations.tolist(), self.sliding.tolist()):
            if duration <= 0.0:
                continue
            if levels and sliding[-1] == slide and levels[-1] == level:
                durations[-1] += duration
            else:
                levels.append(level), durations.append(duration), sliding.append(slide)
        return Arcs(np.array(levels), np.array(durations), np.array(sliding, dtype=bool))

    def repeated(self, factors) -> Arcs:
        """Copies of this motion one after the other, the i-th with its durations times ``factors[i]`` (y''
        unchanged: the copy is the motion on the time scale factors[i], still ending its slide at rest)."""
        factors = np.asarray(factors, dtype=float)
        return Arcs(np.tile(self.levels, factors.size), np.outer(factors, self.durations).ravel(),
                    np.tile(self.sliding, factors.size))


def slide_programme(slide: float, a: float, r: float, velocity_max: float | None, stroke_max: float | None,
                    cells: int) -> tuple[float, Arcs | None]:
    """(vbar, arcs) of the best sub-cycle of period 1 that slides forward from rest for ``slide`` and then
    sticks, with y'' constant on each of ``cells`` cells of the slide and of the stick: a linear programme
    (HiGHS), (0, None) where none exists.

    Variables: y'' per cell, y'(0), the lowest and highest y, and one bound per cell on ``|Delta y''|``.
    x' = -int (y'' + 1) dt while sliding must stay >= 0 and be 0 at the end of the slide; the first cell
    pulls back at -a (the part breaks away); stuck cells keep ``|y''| <= r``; y'' and y' have zero mean
    (y periodic); ``|y'| <= velocity_max`` and y within [lowest, highest], highest - lowest <= stroke_max at
    the cell boundaries.  Objective: int x' dt over the slide (exact: x' is linear in a cell) less 1e-8
    times the total variation of y'', which picks among equally fast motions the one with the fewest and
    smallest jumps (the stick phase is otherwise free wherever the limits are slack)."""
    from scipy.optimize import linprog

    n = 2 * cells
    h = np.concatenate([np.full(cells, slide / cells), np.full(cells, (1.0 - slide) / cells)])
    t = np.concatenate([[0.0], np.cumsum(h)])
    before = np.tril(np.ones((n + 1, n)), -1)
    gain = before * h                                   # y' - y'(0) at the nodes, per unit y''
    pos = gain @ gain[:n] + before * (h * h / 2.0)     # y - y(0) - y'(0) t at the nodes, per unit y''
    nv, start, low, high = 2 * n + 3, n, n + 1, n + 2
    var = slice(n + 3, nv)
    x_slide = -gain[:cells + 1]                         # x' at the slide's nodes, per unit y'' (plus -t)
    weight = np.zeros(cells + 1)
    weight[:-1] += h[:cells] / 2.0
    weight[1:] += h[:cells] / 2.0
    cost = np.zeros(nv)
    cost[:n] = -(weight @ x_slide)
    cost[var] = 1e-8
    rows, bounds_ub, eq, bounds_eq = [], [], [], []

    def block(count):
        return np.zeros((count, nv))
    inside = block(cells - 1)
    inside[:, :n] = -x_slide[1:cells]
    rows.append(inside), bounds_ub.append(-t[1:cells])
    end, mean_acc, mean_vel = block(1), block(1), block(1)
    end[0, :n], mean_acc[0, :n] = x_slide[cells], h
    mean_vel[0, :n], mean_vel[0, start] = pos[n], t[n]
    eq += [end, mean_acc, mean_vel]
    bounds_eq += [t[cells], 0.0, 0.0]
    if velocity_max is not None:
        speed = block(n + 1)
        speed[:, :n], speed[:, start] = gain, 1.0
        rows += [speed, -speed]
        bounds_ub += [np.full(n + 1, velocity_max)] * 2
    if stroke_max is not None:
        above, below, span = block(n + 1), block(n + 1), block(1)
        above[:, :n], above[:, start], above[:, high] = pos, t, -1.0
        below[:, :n], below[:, start], below[:, low] = -pos, -t, 1.0
        span[0, high], span[0, low] = 1.0, -1.0
        rows += [above, below, span]
        bounds_ub += [np.zeros(n + 1), np.zeros(n + 1), [stroke_max]]
    step = np.roll(np.eye(n), 1, axis=1) - np.eye(n)
    for sign in (1.0, -1.0):
        jump = block(n)
        jump[:, :n], jump[:, var] = sign * step, -np.eye(n)
        rows.append(jump), bounds_ub.append(np.zeros(n))
    bounds = [(-a, -a)] + [(-a, a)] * (cells - 1) + [(-r, r)] * cells + [(None, None)] * 3 + [(0.0, None)] * n
    res = linprog(cost, A_ub=np.vstack(rows), b_ub=np.concatenate([np.atleast_1d(b) for b in bounds_ub]),
                  A_eq=np.vstack(eq), b_eq=np.array(bounds_eq), bounds=bounds, method="highs")
    if res.status != 0:
        return 0.0, None
    levels = res.x[:n]
    area = float(weight @ (x_slide @ levels - t[:cells + 1]))
    return area, _cells_to_arcs(levels, h, np.arange(n) < cells, 1e-7 * a)


def _cells_to_arcs(levels, durations, sliding, tol: float) -> Arcs:
    """Arcs of the cells: neighbouring cells of one mode whose levels differ by at most ``tol`` joined
    (their duration-weighted mean level)."""
    groups = []
    for level, duration, slide in zip(levels.tolist(), durations.tolist(), sliding.tolist()):
        if groups and groups[-1][2] == slide and abs(groups[-1][3] - level) <= tol:
            groups[-1][0] += level * duration
            groups[-1][1] += duration
        else:
            groups.append([level * duration, duration, slide, level])
    return Arcs(np.array([g[0] / g[1] for g in groups]), np.array([g[1] for g in groups]),
                np.array([g[2] for g in groups], dtype=bool))


def _solved_durations(arcs: Arcs, solve, period: float, margin: float) -> np.ndarray:
    """The durations of ``arcs`` with the entries ``solve`` (:func:`_dependent`) solved so that they sum to
    ``period``, y'' has zero mean and every slide ends at x' = ``margin``: linear equations in the
    durations, exact up to rounding (NaN where they are singular)."""
    d, level = arcs.durations.copy(), arcs.levels
    rows = [np.ones(d.size), level]
    for first, last in arcs.slides():
        row = np.zeros(d.size)
        row[first:last] = -(level[first:last] + 1.0)
        rows.append(row)
    matrix = np.array(rows)
    rest = np.ones(d.size, dtype=bool)
    rest[list(solve)] = False
    rhs = np.array([period, 0.0] + [margin] * (len(rows) - 2)) - matrix[:, rest] @ d[rest]
    try:
        d[list(solve)] = np.linalg.solve(matrix[:, list(solve)], rhs)
    except np.linalg.LinAlgError:
        d[list(solve)] = np.nan
    return d


def _dependent(arcs: Arcs) -> list[int]:
    """The arcs whose durations :func:`_solved_durations` solves: the last arc of every slide, the first arc
    and the longest stick arc."""
    stuck = np.flatnonzero(~arcs.sliding)
    return [last - 1 for _, last in arcs.slides()] + [0, int(stuck[np.argmax(arcs.durations[stuck])])]


def _tidy_stick(arcs: Arcs, r: float, velocity_max: float | None, stroke_max: float | None) -> Arcs:
    """``arcs`` with every stick that regains speed rewritten as ramp at +r, dwell, ramp at +r, the dwell
    level L keeping int y' dt over the stick (so the slides and y's centring do not change; an L within 1e-9
    of the speed gain of one of the stick's end speeds is set to it, dropping a vanishing ramp), where L lies
    between those speeds and the limits still hold; else ``arcs``."""
    u = arcs.quantities()[0]
    levels, durations, sliding = [], [], []
    edges = [first for first, _ in arcs.slides()] + [arcs.levels.size]
    for (first, last), following in zip(arcs.slides(), edges[1:]):
        levels += arcs.levels[first:last].tolist()
        durations += arcs.durations[first:last].tolist()
        sliding += [True] * (last - first)
        d, level = arcs.durations[last:following], arcs.levels[last:following]
        low, high = float(u[last]), float(u[following])
        area = float(np.sum(u[last:following] * d + 0.5 * level * d * d))
        total = float(np.sum(d))
        dwell = total - (high - low) / r
        height = (area - (high * high - low * low) / (2.0 * r)) / dwell if dwell > 1e-12 * total else np.nan
        near = 1e-9 * (high - low)
        height = high if abs(height - high) <= near else low if abs(height - low) <= near else height
        if low <= height <= high:
            up, down = (height - low) / r, (high - height) / r
            levels += [r, 0.0, r]
            durations += [up, total - up - down, down]
            sliding += [False] * 3
        else:
            levels += level.tolist()
            durations += d.tolist()
            sliding += [False] * (following - last)
    tidy = Arcs(np.array(levels), np.array(durations), np.array(sliding, dtype=bool)).merged()
    return tidy if _meets(tidy, velocity_max, stroke_max) else arcs


def _meets(arcs: Arcs, velocity_max: float | None, stroke_max: float | None) -> bool:
    u, y, y_turn, _, _ = arcs.quantities()
    every = np.concatenate([y, y_turn])
    return ((velocity_max is None or float(np.max(np.abs(u))) <= velocity_max)
            and (stroke_max is None or float(np.max(every) - np.min(every)) <= stroke_max))


def _batch(arcs: Arcs, levels: np.ndarray, durations: np.ndarray, solve, period: float, margin: float):
    """:meth:`Arcs.quantities` for rows of ``levels`` and ``durations`` (the pattern of slides of ``arcs``),
    the durations ``solve`` first solved as :func:`_solved_durations` does: (durations, u, y, y_turn, x_end,
    area), one row each."""
    rows = levels.shape[0]
    slides = arcs.slides()
    matrix = np.zeros((rows, 2 + len(slides), levels.shape[1]))
    matrix[:, 0, :], matrix[:, 1, :] = 1.0, levels
    for j, (first, last) in enumerate(slides):
        matrix[:, 2 + j, first:last] = -(levels[:, first:last] + 1.0)
    rest = np.ones(levels.shape[1], dtype=bool)
    rest[list(solve)] = False
    target = np.array([period, 0.0] + [margin] * len(slides))
    rhs = target - np.einsum("rqm,rm->rq", matrix[:, :, rest], durations[:, rest])
    durations = durations.copy()
    with np.errstate(all="ignore"):
        try:
            durations[:, list(solve)] = np.linalg.solve(matrix[:, :, list(solve)], rhs[:, :, None])[:, :, 0]
        except np.linalg.LinAlgError:
            durations[:, list(solve)] = np.nan
        zero = np.zeros((rows, 1))
        gained = np.concatenate([zero, np.cumsum(levels * durations, axis=1)], axis=1)
        moved = np.concatenate([zero, np.cumsum(gained[:, :-1] * durations + 0.5 * levels * durations**2, axis=1)],
                               axis=1)
        start = -moved[:, -1:] / period
        u = start + gained
        y = moved + start * np.concatenate([zero, np.cumsum(durations, axis=1)], axis=1)
        turn = np.clip(np.where(levels != 0.0, -u[:, :-1] / levels, 0.0), 0.0, durations)
        y_turn = y[:, :-1] + u[:, :-1] * turn + 0.5 * levels * turn * turn
        x_end, area = np.zeros(levels.shape), np.zeros(rows)
        for first, last in slides:
            ends = -np.cumsum((levels[:, first:last] + 1.0) * durations[:, first:last], axis=1)
            x_end[:, first:last] = ends
            begins = np.concatenate([zero, ends[:, :-1]], axis=1)
            area += np.sum((begins + ends) * durations[:, first:last], axis=1) / 2.0
    return durations, u, y, y_turn, x_end, area


def _slsqp(arcs: Arcs, a: float, r: float, velocity_max: float | None, stroke_max: float | None,
           margin: float, slack: float) -> Arcs:
    """SLSQP over the levels and durations of ``arcs`` (:func:`polish`); the durations of
    :func:`_dependent` are solved from the others, so that the equalities hold at every iterate.  The
    objective, the constraints and their forward differences are evaluated in one batch per point."""
    from scipy.optimize import minimize

    m, period = arcs.levels.size, float(np.sum(arcs.durations))
    speed, length = a * period, a * period * period
    v_lim = None if velocity_max is None else velocity_max * (1.0 - slack)
    s_lim = None if stroke_max is None else stroke_max * (1.0 - slack)
    solve = _dependent(arcs)
    free = np.setdiff1d(np.arange(m), solve)
    f = free.size
    inner = np.array([i for first, last in arcs.slides() for i in range(first, last - 1)], dtype=int)

    def evaluate(z_rows):
        durations = np.tile(arcs.durations, (z_rows.shape[0], 1))
        durations[:, free] = z_rows[:, :f] * period
        durations, u, y, y_turn, x_end, area = _batch(arcs, z_rows[:, f:f + m] * a, durations, solve, period, margin)
        out = [durations[:, solve] / period, (x_end[:, inner] - margin) / speed]
        if v_lim is not None:
            out += [1.0 - u / v_lim, 1.0 + u / v_lim]
        if s_lim is not None:
            every = np.concatenate([y, y_turn], axis=1) / s_lim
            low, high = z_rows[:, f + m:f + m + 1], z_rows[:, f + m + 1:f + m + 2]
            out += [high - every, every - low, 1.0 - (high - low)]
        return (np.nan_to_num(-area / length, nan=0.0), np.nan_to_num(np.concatenate(out, axis=1), nan=-1.0),
                durations)

    _, y, y_turn, _, _ = arcs.quantities()
    every = np.concatenate([y, y_turn]) / (length if s_lim is None else s_lim)
    z0 = np.concatenate([arcs.durations[free] / period, arcs.levels / a, [every.min(), every.max()]])
    lower = np.concatenate([np.zeros(f), np.where(arcs.sliding, -1.0, -r / a), [-np.inf] * 2])
    upper = np.concatenate([np.ones(f), np.where(arcs.sliding, 1.0, r / a), [np.inf] * 2])
    for first, last in arcs.slides():
        lower[f + first] = upper[f + first] = -1.0          # the slide opens at -a: the part breaks away
        if last < m:
            lower[f + last] = 0.0                          # it comes to rest on a stick arc of y'' in [0, r]
    memo = {}

    def at(z):
        key = z.tobytes()
        if key not in memo:
            step = 1.49e-8 * np.maximum(np.abs(z), 1.0)
            step = np.where(z + step > upper, -step, step)    # stay within the bounds
            objective, constraints, _ = evaluate(np.vstack([z, z + np.diag(step)]))
            memo.clear()
            memo[key] = (objective[0], constraints[0], (objective[1:] - objective[0]) / step,
                         ((constraints[1:] - constraints[0]) / step[:, None]).T)
        return memo[key]
    res = minimize(lambda z: at(z)[0], np.clip(z0, lower, upper), jac=lambda z: at(z)[2], method="SLSQP",
                   bounds=list(zip(lower, upper)),
                   constraints=[{"type": "ineq", "fun": lambda z: at(z)[1], "jac": lambda z: at(z)[3]}],
                   options={"maxiter": 200, "ftol": 1e-13})
    z = np.clip(res.x, lower, upper)
    return Arcs(z[f:f + m] * a, evaluate(z[None, :])[2][0], arcs.sliding)


def _clean(arcs: Arcs, a: float, r: float, drop: float, snap: float) -> Arcs | None:
    """``arcs`` without those shorter than ``drop`` times the period, levels within ``snap`` (relative) of
    0, +-a (sliding) or +-r (stuck) set to it; None unless the first arc opens a slide, every slide opens at
    -a with at least two arcs and a stick follows the last."""
    period = float(np.sum(arcs.durations))
    keep = arcs.durations > drop * period
    levels = arcs.levels[keep].copy()
    sliding = arcs.sliding[keep]
    for i, slide in enumerate(sliding):
        top = a if slide else r
        for target in (-top, 0.0, top):
            if abs(levels[i] - target) <= snap * top:
                levels[i] = target
    out = Arcs(levels, arcs.durations[keep], sliding).merged()
    slides = out.slides()
    if not slides or slides[0][0] != 0 or slides[-1][1] == out.levels.size:
        return None
    if any(last - first < 2 or out.levels[first] != -a for first, last in slides):
        return None
    return out


def polish(arcs: Arcs, a: float, r: float, velocity_max: float | None, stroke_max: float | None, margin: float,
           slack: float) -> Arcs | None:
    """A motion of one or more slides (a grid solution of :func:`slide_programme`, or copies of one) made
    exact: SLSQP over its arcs' levels and durations maximises int x' dt over the slides with the limits held
    within a fraction ``slack`` of them, and the period, zero-mean y'' and every slide's end at x' =
    ``margin`` (never touched before) exact by :func:`_solved_durations`; every slide opens at -a and comes
    to rest on a stick arc between 0 and r.  The grid leaves short arcs at intermediate levels where y''
    switches within a cell: arcs shorter than 1e-6 of the period are dropped and levels within 1e-6 of 0,
    +-a or +-r set to it, and SLSQP runs again (with the multiples :data:`RETRY_SLACK` of the slack while it
    ends outside a limit).
    Then :func:`_tidy_stick` writes the sticks in their canonical form.  None if SLSQP ends elsewhere than at
    a point meeting the limits."""
    period = float(np.sum(arcs.durations))

    def cleaned(start, times):
        return _clean(_slsqp(start, a, r, velocity_max, stroke_max, margin, times * slack), a, r, 1e-6, 1e-6)
    first = cleaned(arcs, 1.0)
    if first is None:
        return None
    for times in RETRY_SLACK:                     # SLSQP may end a little outside a constraint
        # and stay there when restarted from that point: then a restart from the grid solution moves
        for start in (first, cleaned(arcs, times) if times > 1.0 else None):
            second = None if start is None else _clean(
                _slsqp(start, a, r, velocity_max, stroke_max, margin, times * slack), a, r, 1e-12, 0.0)
            if second is None:
                continue
            exact = Arcs(second.levels, _solved_durations(second, _dependent(second), period, margin), second.sliding)
            if (np.all(exact.durations >= 0.0) and _meets(exact, velocity_max, stroke_max)
                    and np.all(exact.quantities()[3][exact.sliding] > 0.0)):
                return _tidy_stick(exact, r, velocity_max, stroke_max).merged()
    return None


def best_slide(a: float, r: float, velocity_max: float | None, stroke_max: float | None) -> tuple[float, float]:
    """(vbar, D) of the best grid solution (:func:`slide_programme`, :data:`SCAN_CELLS` cells) of period 1
    over the slide time D in (0, r / (1 + r)] (the longest slide, |F| <= r dt / (1 + r)): :data:`D_SCAN`
    equally spaced D, then a bounded scalar search between the neighbours of the best; (0, nan) if none."""
    from scipy.optimize import minimize_scalar

    longest = r / (1.0 + r)
    trial = longest * np.arange(1, D_SCAN + 1) / D_SCAN

    def value(slide):
        return slide_programme(slide, a, r, velocity_max, stroke_max, SCAN_CELLS)[0]
    values = [value(slide) for slide in trial]
    j = int(np.argmax(values))
    if values[j] <= 0.0:
        return 0.0, float("nan")
    res = minimize_scalar(lambda slide: -value(slide), bounds=(trial[max(j - 1, 0)], trial[min(j + 1, D_SCAN - 1)]),
                          method="bounded", options={"xatol": 1e-3 * longest})
    return (-float(res.fun), float(res.x)) if -res.fun > values[j] else (values[j], float(trial[j]))


def search(a: float, r: float, velocity_max: float | None, stroke_max: float | None, k_fit: int,
           polished: int = 2) -> list[Arcs]:
    """Polished motions of period 1 of k < ``k_fit`` equal sub-cycles, for the ``polished`` best k, the
    limits those of a period 1 (module docstring).

    Each sub-cycle is solved at period 1 (t -> k t, x, y -> k^2 x: the limits become k velocity_max and
    k^2 stroke_max, the mean velocity k vbar), so that every linear programme has the same scale.  k = 1,
    2, 4, ... below ``k_fit`` brackets the best (taken unimodal in k) and a golden-section search on the
    integers narrows the bracket."""
    values, slides = {}, {}

    def scaled(k):
        return (None if velocity_max is None else velocity_max * k, None if stroke_max is None else stroke_max * k * k)

    def value(k):
        if k not in values:
            vbar, slides[k] = best_slide(a, r, *scaled(k))
            values[k] = vbar / k
        return values[k]
    k = 1
    while k < k_fit:
        value(k)
        k *= 2
    if not values:
        return []
    best = max(values, key=values.get)
    low, high = max(1, best // 2), min(k_fit - 1, 2 * best)
    while high - low > 3:
        step = round(0.381966 * (high - low))
        left, right = low + step, high - step
        if value(left) < value(right):
            low = left
        else:
            high = right
    for k in range(low, high + 1):
        value(k)
    out = []
    for k in sorted((k for k in values if values[k] > 0.0), key=values.get, reverse=True):
        _, arcs = slide_programme(slides[k], a, r, *scaled(k), FINE_CELLS)
        exact = None if arcs is None else polish(arcs, a, r, *scaled(k), ARRIVAL_MARGIN * a * k, _slack(k))
        if exact is not None:
            out.append(exact.repeated(np.full(k, 1.0 / k)))
        if len(out) == polished:
            break
    return out


def unequal(motion: Arcs, a: float, r: float, velocity_max: float | None, stroke_max: float | None) -> list[Arcs]:
    """``motion`` (period 1, k equal sub-cycles, 2 <= k <= :data:`JOINT_SUB_CYCLES`) with its sub-cycles
    stretched by 1 + s (2 i / (k - 1) - 1), i = 0 .. k - 1, for each s of :data:`STRETCH`, each polished as
    one motion of period 1: sub-cycles of unequal length beat equal ones where a limit binds on the whole
    period (a stroke limit lets a long slide pair with a short one, Sect. "The searched family" of the page),
    and equal lengths are a stationary point of the polish, so it needs the push."""
    k = len(motion.slides())
    if not 2 <= k <= JOINT_SUB_CYCLES:
        return []
    first, last = 0, motion.levels.size // k
    one = Arcs(motion.levels[first:last], motion.durations[first:last] * k, motion.sliding[first:last])
    out = []
    for stretch in STRETCH:
        factors = (1.0 + stretch * (2.0 * np.arange(k) / (k - 1) - 1.0)) / k
        exact = polish(one.repeated(factors), a, r, velocity_max, stroke_max, ARRIVAL_MARGIN * a, _slack(k))
        if exact is not None:
            out.append(exact)
    return out


def _slack(k: int) -> float:
    """The fraction of the limits the polish of a motion of k sub-cycles keeps free (:data:`LIMIT_SLACK`)."""
    return LIMIT_SLACK + 64.0 * np.finfo(float).eps * k * k


def optimal_profile(period, accel_max, *, stroke_max=None, velocity_max=None, friction=None,
                    jerk_max=None) -> OptimalProfile:
    """The fastest periodic table motion under an acceleration limit, and under speed and stroke limits.

    Proven for the acceleration limit alone, numerical under the other limits.  On a uniform surface
    (mu_bar = 1, Sect. 3.2) the part's steady mean velocity (eq. 10) under ``|y''| <= a`` is at most v*
    (:func:`~selfalign.optimal_vbar`), and y'' = -a, +a, +r attains it: the table pulls back at -a while the part
    slides forward, catches up at +a as the part comes to rest, then regains its speed at the static limit
    r with the part stuck.  That motion is returned whenever it meets the other limits.  Otherwise the
    search of the module ``selfalign.analysis.optimal_motion`` runs (sub-cycles, each a slide from rest and
    a stick: equal ones by a linear programme per sub-cycle count and slide time, unequal ones from them,
    all polished): its result is the best it finds, not proven optimal.  The derivation, the proof and the
    search are on the page docs/explanation/optimal-motion.md.

    The limits bear on the table motion only through y'': y' is taken with zero mean (y periodic) and y's
    range centred on 0.  Under static friction (r > 1) the returned motion leaves the part a speed of
    ``ARRIVAL_MARGIN`` (2^-40) of a dt at the end of each slide, so that it comes to rest just after y''
    has jumped to its stick level rather than a rounding error before (from which it would slide backward
    for good); its mean velocity is below v* by a relative ~1e-12.

    Parameters
    ----------
    period : float or (float, float)
        The table's period dt, dimensionless (Sect. 3.2); in [1e-30, 1e30].  A pair (min, max),
        0 < min <= max, lets the period be anything in that range: the fastest motion over the range is
        returned, its period in ``.period``, and "period" is in ``.binding`` when it lies at an end.  Under
        the acceleration limit alone the longest period wins (v* is proportional to dt); under speed and
        stroke limits the period is searched (page, "A period range").
    accel_max : float
        a, the largest ``|y''|``; in [1e-30, 1e30] and above the friction ratio r.
    stroke_max : float, optional
        The largest stroke max y - min y; > 0.  Default None (no limit).
    velocity_max : float, optional
        The largest table speed ``|y'|``; > 0.  Default None (no limit).
    friction : FrictionLaw, optional
        Coulomb (the default, r = 1) or static_kinetic with r = mu_s / mu_k
        (``selfalign.model.friction.FrictionLaw``).
    jerk_max : float, optional
        j, the largest ``|y'''|``; in [1e-30, 1e30].  Default None (y'' may jump).  With it y'' is
        continuous and piecewise linear (a ``PiecewiseLinearProfile``, run on the exact solver's smooth
        stepper): the best motion of the ramped bang-bang-stick family found by SLSQP, below v* by about
        3 a / (j dt).  Numerical and not optimal: a general search finds faster motions that creep
        backward in place of the stick (page, "Finite jerk").

    Returns
    -------
    OptimalProfile
        The motion, the part's steady mean velocity on it from the exact solver, the bound v*, the limits
        it uses to the full and its structure.

    Raises
    ------
    TypeError
        If a number is not a real number, ``period`` is a sequence other than a pair, or ``friction`` is
        not a FrictionLaw.
    ValueError
        If ``period`` (or an end of its range) or ``accel_max`` is not finite or lies outside
        [1e-30, 1e30], a period range has min > max, a limit is not finite and > 0, ``friction`` is a
        Stribeck law, ``accel_max`` <= r (nothing moves), ``jerk_max`` is not finite and > 0, or it is
        too small for any motion of the family to move the part within the period.

    See Also
    --------
    optimal_vbar : The bound v* alone.
    ThreePhaseProfile : The paper's family (Sect. 4.4.3), which reaches 3/4 of v* at a = 3.

    Examples
    --------
    The paper's Coulomb friction at T = 1, a = 3: 1/6, against 0.125 for the best three-phase profile:

    >>> import selfalign as sa
    >>> best = sa.optimal_profile(1.0, 3.0)
    >>> print(best.family, round(best.vbar, 9), best.profile.accels.tolist())
    bang-bang-stick 0.166666667 [-3.0, 3.0, 1.0]
    >>> print(best.profile.breaks.round(6).tolist(), round(best.peak_velocity, 6), round(best.stroke, 6))
    [0.0, 0.333333, 0.5, 1.0] 0.583333 0.115741

    A speed limit below its 0.583: the search finds a motion that coasts at the limit while the part
    slides, and two sub-cycles per period at a tighter limit:

    >>> capped = sa.optimal_profile(1.0, 3.0, velocity_max=0.4)
    >>> print(capped.family, capped.binding, round(capped.vbar, 4), capped.peak_velocity <= 0.4)
    bang-coast-bang-stick-dwell ('accel_max', 'velocity_max') 0.1524 True
    >>> tighter = sa.optimal_profile(1.0, 3.0, velocity_max=0.2)
    >>> print(tighter.family, tighter.sub_cycles, round(tighter.vbar, 5))
    bang-coast-bang-stick-dwell x 2 2 0.07619

    A period range: under the acceleration limit alone the longest period wins (under a stroke limit, the
    period at which the fastest motion just fits it, found by a scan: docs/explanation/optimal-motion.md):

    >>> longest = sa.optimal_profile((0.5, 2.0), 3.0)
    >>> print(longest.period, longest.binding, round(longest.vbar, 9))
    2.0 ('accel_max', 'period') 0.333333333

    A jerk limit: y'' ramps between its levels, and the part loses about 3 a / (j dt) of v*:

    >>> ramped = sa.optimal_profile(1.0, 3.0, jerk_max=100.0)
    >>> print(ramped.family, ramped.binding, round(ramped.vbar, 5), round(ramped.vbar / ramped.vbar_bound, 4))
    ramped bang-bang-stick ('accel_max', 'jerk_max') 0.1511 0.9066
    """
    low, high = _period_range(period)
    accel_max = check_scale("accel_max", accel_max)
    stroke_max, velocity_max = _limit("stroke_max", stroke_max), _limit("velocity_max", velocity_max)
    jerk = None if jerk_max is None else check_scale("jerk_max", jerk_max)
    law, r = _friction_ratio(friction)
    check_moving(accel_max, r)
    a = accel_max
    # The fastest motion's speed and stroke grow as dt and dt^2 (t -> l t, x, y -> l^2 x leaves the model
    # alone, Sect. 3.2), so its k-fold repetition at period dt / k fits the limits from k_fit on.
    _, _, speed, stroke = centred_motion(*fastest_pieces(1.0, a, r, 0.0))
    k_fit = _sub_cycles_needed(low, speed, stroke, velocity_max, stroke_max)
    if k_fit > MAX_SUB_CYCLES:
        raise ValueError(f"velocity_max = {velocity_max!r}, stroke_max = {stroke_max!r} are too small for period = "
                         f"{low!r} and accel_max = {a!r}: the fastest motion's speed {speed * low:.6g} and stroke "
                         f"{stroke * low * low:.6g} would have to shrink {k_fit} times (more than {MAX_SUB_CYCLES} "
                         f"sub-cycles per period); choose a shorter period (speed and stroke shrink with it and its "
                         f"square)")
    if not isinstance(period, (tuple, list)):
        return _optimal_at(high, a, r, law, velocity_max, stroke_max, jerk)
    return _best_period(low, high, a, r, law, velocity_max, stroke_max, speed, stroke, jerk)


def _sub_cycles_needed(period, speed, stroke, velocity_max, stroke_max) -> int:
    """k_fit at ``period`` for the fastest motion of speed ``speed`` dt and stroke ``stroke`` dt^2."""
    return max(1, math.ceil(speed * period / velocity_max) if velocity_max is not None else 1,
               math.ceil(math.sqrt(stroke * period * period / stroke_max)) if stroke_max is not None else 1)


def _optimal_at(period: float, a: float, r: float, law, velocity_max, stroke_max, jerk=None) -> OptimalProfile:
    """The fastest motion of one period (:func:`optimal_profile` for a number ``period``)."""
    _, _, speed, stroke = centred_motion(*fastest_pieces(1.0, a, r, 0.0))
    k_fit = _sub_cycles_needed(period, speed, stroke, velocity_max, stroke_max)
    if jerk is not None:
        return _jerk_choice(period, a, r, law, jerk, velocity_max, stroke_max, k_fit)
    while not _fits(_built(_fastest_arcs(k_fit, a, r), period), velocity_max, stroke_max):
        k_fit += 1
    candidates = [_fastest_arcs(k_fit, a, r)]
    if k_fit > 1:
        unit_v = None if velocity_max is None else velocity_max / period
        unit_s = None if stroke_max is None else stroke_max / (period * period)
        equal = search(a, r, unit_v, unit_s, k_fit)
        candidates += equal
        for motion in [candidates[0], _fastest_arcs(k_fit + 1, a, r)] + equal:
            candidates += unequal(motion, a, r, unit_v, unit_s)
    return _choose(candidates, period, a, r, law, velocity_max, stroke_max)


def _period_range(period) -> tuple[float, float]:
    """(min, max) of ``period``: a number (both the same) or a pair (min, max), 0 < min <= max."""
    if not isinstance(period, (tuple, list)) or len(period) != 2:
        if isinstance(period, (tuple, list, np.ndarray)):
            raise TypeError(f"period must be a real number or a pair (min, max) of them, got {period!r}")
        value = check_scale("period", period)
        return value, value
    low, high = check_scale("period min", period[0]), check_scale("period max", period[1])
    if low > high:
        raise ValueError(f"period must be a number or a pair (min, max) with min <= max, both finite and > 0, got "
                         f"{tuple(period)!r}")
    return low, high


def _best_period(low: float, high: float, a: float, r: float, law, velocity_max, stroke_max, speed: float,
                 stroke: float, jerk: float | None) -> OptimalProfile:
    """The fastest motion over the periods in [``low``, ``high``] (page, "A period range").

    Up to the longest period t_fit at which the fastest motion meets the limits (its speed ``speed`` dt and
    stroke ``stroke`` dt^2), v* grows with dt and is attained (proven): the answer is min(high, t_fit) unless
    a longer period does better.  Beyond t_fit (numerical): :data:`PERIOD_SCAN` periods per octave of
    [max(low, t_fit), high], geometrically spaced (at most :data:`PERIOD_POINTS`), and a bounded scalar
    search between the neighbours of each of the :data:`PERIOD_PEAKS` best local maxima of the scan; the
    chosen period is the fastest of those evaluated (the
    shortest among those within :data:`CLOSED_FORM_RTOL` of it: k copies of a motion tie with it at k
    times its period)."""
    from scipy.optimize import minimize_scalar

    fit = math.inf if jerk is None else low     # under a jerk limit v* is a bound, not attained
    high = min(high, max(low, high / _sub_cycles_needed(high, speed, stroke, velocity_max, stroke_max)
                         * MAX_SUB_CYCLES))
    if velocity_max is not None:
        fit = min(fit, velocity_max / speed)
    if stroke_max is not None:
        fit = min(fit, math.sqrt(stroke_max / stroke))
    start = min(max(low, fit), high)
    found = {start: _optimal_at(start, a, r, law, velocity_max, stroke_max, jerk)}
    if start < high:
        count = min(PERIOD_POINTS, max(2, 1 + math.ceil(PERIOD_SCAN * math.log2(high / start))))
        grid = start * (high / start) ** np.linspace(0.0, 1.0, count)
        grid[-1] = high
        for period in grid[1:].tolist():
            found[period] = _optimal_at(period, a, r, law, velocity_max, stroke_max, jerk)
        values = [found[period].vbar for period in grid.tolist()]
        peaks = [i for i in range(count) if values[i] >= max(values[max(i - 1, 0)], values[min(i + 1, count - 1)])]

        def slower(period):
            period = float(period)
            if period not in found:
                found[period] = _optimal_at(period, a, r, law, velocity_max, stroke_max, jerk)
            return -found[period].vbar
        for i in sorted(peaks, key=lambda i: values[i], reverse=True)[:PERIOD_PEAKS]:
            left, right = grid[max(i - 1, 0)], grid[min(i + 1, count - 1)]
            minimize_scalar(slower, bounds=(left, right), method="bounded",
                            options={"xatol": PERIOD_XTOL * right, "maxiter": PERIOD_REFINE})
    fastest = max(result.vbar for result in found.values())
    period = min(p for p in found if found[p].vbar >= fastest * (1.0 - CLOSED_FORM_RTOL))   # ties: the shortest
    best = found[period]
    ends = ("period",) if period in (low, high) else ()
    return replace(best, binding=best.binding + ends)


def _fastest_arcs(k: int, a: float, r: float) -> Arcs:
    """k copies of the fastest motion (:func:`fastest_pieces`) of period 1 / k, the arrival margin that of
    the whole period 1."""
    breaks, accels = fastest_pieces(1.0, a, r, ARRIVAL_MARGIN * a * k)
    return Arcs(accels, np.diff(breaks), np.array([True, True, False])).repeated(np.full(k, 1.0 / k))


def _built(arcs: Arcs, period: float) -> tuple[np.ndarray, np.ndarray, float, float, float, float]:
    """(breaks, accels, y_start, yd_start, peak_velocity, stroke) of the motion ``arcs`` (period 1) scaled to
    ``period``: durations times period, y'' unchanged."""
    breaks = np.concatenate([[0.0], np.cumsum(arcs.durations) * period])
    breaks[-1] = period
    breaks = np.minimum(breaks, period)
    return (breaks, arcs.levels, *centred_motion(breaks, arcs.levels))


def _fits(built, velocity_max: float | None, stroke_max: float | None) -> bool:
    return (velocity_max is None or built[4] <= velocity_max) and (stroke_max is None or built[5] <= stroke_max)


def _choose(candidates, period, a, r, law, velocity_max, stroke_max) -> OptimalProfile:
    """The fastest of the candidate motions (arcs of period 1) scaled to ``period``, by the exact solver:
    each must meet the limits exactly and move the part as the closed form of its slides says
    (int x' dt, to :data:`CLOSED_FORM_RTOL`); the fastest motion's copies always do.  Of the motions within
    :data:`TIE_RTOL` of the fastest, the simplest is returned."""
    built = [(arcs, _built(arcs, period)) for arcs in candidates]
    built = [b for b in built if _fits(b[1], velocity_max, stroke_max)]
    profiles = [PiecewiseConstantProfile(*b[1][:4]) for b in built]
    closed = [arcs.quantities()[4] * period for arcs, _ in built]
    vbars = steady_mean_velocity(profiles, law)
    agree = [i for i, v in enumerate(vbars) if abs(v - closed[i]) <= CLOSED_FORM_RTOL * closed[i]]
    if not agree:
        raise RuntimeError(f"the exact solver's mean velocities {vbars.tolist()} disagree with the closed forms "
                           f"{closed} of the motions found for period = {period!r}, accel_max = {a!r}, r = {r!r}")
    fastest = max(vbars[i] for i in agree)
    tied = [i for i in agree if vbars[i] >= fastest * (1.0 - TIE_RTOL)]
    i = min(tied, key=lambda i: (len(set(_cycle_names(built[i][0], a, r))), built[i][0].levels.size, -vbars[i]))
    arcs, (_, _, _, _, speed, stroke) = built[i]
    used = {"accel_max": True, "velocity_max": velocity_max is not None and speed >= velocity_max * (1.0 - BINDING),
            "stroke_max": stroke_max is not None and stroke >= stroke_max * (1.0 - BINDING)}
    return OptimalProfile(profile=profiles[i], vbar=float(vbars[i]),
                          vbar_bound=float(optimal_mean_velocity(period, a, r)),
                          binding=tuple(name for name, full in used.items() if full), family=_family(arcs, a, r),
                          sub_cycles=len(arcs.slides()), peak_velocity=speed, stroke=stroke, period=period)


# ------------------------------------------------------------------------------------------
# A jerk limit |y'''| <= j: y'' piecewise linear (page, "Finite jerk")
# ------------------------------------------------------------------------------------------

#: The jerk-limited sub-cycle's levels of y'': stick s, pull-back -p, coast c, catch-up q (cyclic, in this
#: order), each held for a time and joined to the next by a ramp at the full jerk.
JERK_LEVELS = 4
#: Pull-back and catch-up levels the jerk-limited search starts from, as fractions of the way from r to a.
JERK_STARTS = (1.0, 0.6, 0.3)
#: Fraction of a speed or stroke limit the jerk-limited search keeps free (SLSQP ends up to ~1e-9 beyond its
#: constraints, and the motion returned must meet them exactly); a hold shorter than JERK_HOLD of the
#: sub-cycle's period does not name a level in ``family``.
JERK_SLACK, JERK_HOLD = 1e-7, 1e-6


def ramped_motion(levels, holds, jerk: float) -> tuple[np.ndarray, np.ndarray, np.ndarray, np.ndarray]:
    """(breaks, accels, jerks, ends) of y'' holding ``levels[i]`` for ``holds[i]`` and then ramping to
    ``levels[i + 1]`` (cyclic) at the full ``jerk``: the pieces of a :class:`PiecewiseLinearProfile`."""
    levels, holds = np.asarray(levels, dtype=float), np.asarray(holds, dtype=float)
    following = np.roll(levels, -1)
    ramps = np.abs(following - levels) / jerk
    durations = np.column_stack([holds, ramps]).ravel()
    accels = np.column_stack([levels, levels]).ravel()
    jerks = np.column_stack([np.zeros_like(levels), np.sign(following - levels) * jerk]).ravel()
    ends = np.column_stack([levels, following]).ravel()
    keep = durations > 0.0
    breaks = np.concatenate([[0.0], np.cumsum(durations[keep])])
    return breaks, accels[keep], jerks[keep], ends[keep]


def _held(levels: np.ndarray, coast: float, catch: float, jerk: float, period: float) -> np.ndarray | None:
    """The holds of ``levels`` (s, -p, c, q) with the coast and catch-up held for ``coast`` and ``catch``
    and the stick and pull-back holds solved so that the ramps and holds fill ``period`` and y'' has zero
    mean (two linear equations); None where they are singular."""
    following = np.roll(levels, -1)
    ramps = np.abs(following - levels) / jerk
    ramp_impulse = float(np.sum((levels + following) / 2.0 * ramps))
    rest = period - float(np.sum(ramps)) - coast - catch
    impulse = ramp_impulse + levels[2] * coast + levels[3] * catch
    det = levels[1] - levels[0]
    if det == 0.0:
        return None
    pull = (-impulse - levels[0] * rest) / det
    return np.array([rest - pull, pull, coast, catch])


def _linear_extremes(breaks, accels, jerks) -> tuple[float, float, float, float]:
    """(y_start, yd_start, peak_velocity, stroke) of y'' = accels + jerks s on the pieces between ``breaks``:
    y' of zero mean, y's range centred on 0 (y' is quadratic in a piece, y cubic: their extremes lie at the
    breaks or where y'' or y' vanishes inside a piece)."""
    lengths = np.diff(breaks)
    gained = np.concatenate([[0.0], np.cumsum(accels * lengths + jerks * lengths**2 / 2.0)])
    moved = np.concatenate([[0.0], np.cumsum(gained[:-1] * lengths + accels * lengths**2 / 2.0
                                             + jerks * lengths**3 / 6.0)])
    yd_start = -moved[-1] / breaks[-1]
    u = yd_start + gained
    y = moved + yd_start * breaks

    def inside(s):
        return np.where((s > 0.0) & (s < lengths[:, None]), s, 0.0)
    with np.errstate(divide="ignore", invalid="ignore"):
        turn = inside(np.where(jerks != 0.0, -accels / jerks, 0.0)[:, None])
        disc = np.sqrt(np.maximum(accels**2 - 2.0 * jerks * u[:-1], 0.0))
        roots = np.where(jerks[:, None] != 0.0, (-accels[:, None] + np.array([-1.0, 1.0]) * disc[:, None])
                         / jerks[:, None], np.where(accels != 0.0, -u[:-1] / accels, 0.0)[:, None])
        roots = inside(np.nan_to_num(roots))
    speed = u[:-1, None] + accels[:, None] * turn + jerks[:, None] * turn**2 / 2.0
    height = (y[:-1, None] + u[:-1, None] * roots + accels[:, None] * roots**2 / 2.0
              + jerks[:, None] * roots**3 / 6.0)
    every = np.concatenate([y, height.ravel()])
    low, high = float(np.min(every)), float(np.max(every))
    return -(low + high) / 2.0, float(yd_start), float(np.max(np.abs(np.concatenate([u, speed.ravel()])))), high - low


def _ramped_profile(levels, holds, jerk: float, copies: int = 1, period: float | None = None):
    """(profile, peak_velocity, stroke) of ``copies`` copies of :func:`ramped_motion`: a
    :class:`PiecewiseLinearProfile`, y' of zero mean, y's range centred on 0, its last break set to
    ``period`` (the sum of the pieces up to rounding) when given."""
    from ..model.profiles import PiecewiseLinearProfile

    breaks, accels, jerks, ends = ramped_motion(np.tile(levels, copies), np.tile(holds, copies), jerk)
    if period is not None:
        breaks[-1] = period
    y_start, yd_start, speed, stroke = _linear_extremes(breaks, accels, jerks)
    return PiecewiseLinearProfile(breaks, accels, jerks, y_start, yd_start, ends=ends), speed, stroke


def jerk_limited(period: float, a: float, r: float, law, jerk: float, velocity_max: float | None,
                 stroke_max: float | None, copies: int = 1) -> tuple[float, np.ndarray, np.ndarray] | None:
    """(vbar, levels, holds) of the fastest jerk-limited sub-cycle of period ``period`` / ``copies`` found by
    SLSQP: levels s (stick), -p (pull-back), c (coast) and q (catch-up) of y'', each held and joined to the
    next by a ramp at the full ``jerk`` (:func:`ramped_motion`); |s| <= r, r <= p <= a, |c|, |q| <= a; the
    stick and pull-back holds solved for the period and zero-mean y'' (:func:`_held`); speed and stroke
    within the limits (copies share them).  The objective is the exact solver's mean velocity, its forward
    differences in one batch.  Starts: the fastest motion's levels and times with the ramps cut from its
    holds, and pull-back and catch-up levels part of the way from r to a (:data:`JERK_STARTS`).  None if
    no start gives a moving part."""
    from scipy.optimize import minimize

    sub = period / copies
    slide = r * sub / (1.0 + r)
    v_lim = None if velocity_max is None else velocity_max * (1.0 - JERK_SLACK)
    s_lim = None if stroke_max is None else stroke_max * (1.0 - JERK_SLACK)
    lower = np.array([-r / a, r / a, -1.0, -1.0, 0.0, 0.0])
    upper = np.array([r / a, 1.0, 1.0, 1.0, 1.0, 1.0])

    def unpack(z):
        levels = np.array([z[0], -z[1], z[2], z[3]]) * a
        return levels, _held(levels, z[4] * sub, z[5] * sub, jerk, sub)

    def evaluate(rows):
        profiles, margins = [], []
        for z in rows:
            levels, holds = unpack(z)
            if holds is None or np.any(holds < 0.0):
                margins.append([-1.0] * 4 if holds is None else [holds[0] / sub, holds[1] / sub, 0.0, 0.0])
                profiles.append(None)
                continue
            profile, speed, stroke = _ramped_profile(levels, np.maximum(holds, 0.0), jerk)
            margins.append([holds[0] / sub, holds[1] / sub, 1.0 if v_lim is None else 1.0 - speed / v_lim,
                            1.0 if s_lim is None else 1.0 - stroke / s_lim])
            profiles.append(profile)
        good = [p for p in profiles if p is not None]
        found = iter(np.nan_to_num(steady_mean_velocity(good, law), nan=-1.0) if good else [])
        return (np.array([next(found) if p is not None else -1.0 for p in profiles]) / (a * sub),
                np.array(margins))

    memo = {}

    def at(z):
        key = z.tobytes()
        if key not in memo:
            step = 1e-7 * np.maximum(np.abs(z), 1.0)
            step = np.where(z + step > upper, -step, step)
            value, margins = evaluate(np.vstack([z, z + np.diag(step)]))
            memo.clear()
            memo[key] = (-value[0], -(value[1:] - value[0]) / step, margins[0],
                         ((margins[1:] - margins[0]) / step[:, None]).T)
        return memo[key]
    best = None
    for fraction in JERK_STARTS:
        level = (r + fraction * (a - r)) / a
        catch = max(slide * (a - 1.0) / (2.0 * a) - 2.0 * a / jerk, 0.0) / sub if fraction == 1.0 else 0.0
        z0 = np.array([r / a, level, 0.0, level, 0.0, catch])
        res = minimize(lambda z: at(z)[0], z0, jac=lambda z: at(z)[1], method="SLSQP",
                       bounds=list(zip(lower, upper)),
                       constraints=[{"type": "ineq", "fun": lambda z: at(z)[2], "jac": lambda z: at(z)[3]}],
                       options={"maxiter": 200, "ftol": 1e-14})
        z = np.clip(res.x, lower, upper)
        levels, holds = unpack(z)
        if holds is None or np.any(holds < 0.0):
            continue
        profile, speed, stroke = _ramped_profile(levels, holds, jerk)
        if (velocity_max is not None and speed > velocity_max) or (stroke_max is not None and stroke > stroke_max):
            continue
        vbar = float(steady_mean_velocity([profile], law)[0])
        if vbar > 0.0 and (best is None or vbar > best[0]):
            best = (vbar, levels, holds)
    return best


#: Most sub-cycles per period the jerk-limited search tries beyond the count the fastest motion's copies need.
JERK_SUB_CYCLES = 8


def _jerk_choice(period: float, a: float, r: float, law, jerk: float, velocity_max, stroke_max,
                 k_fit: int) -> OptimalProfile:
    """The fastest jerk-limited motion of ``period``: k equal sub-cycles (:func:`jerk_limited`), k = 1 without
    speed and stroke limits, else k = 1 .. min(k_fit + 1, :data:`JERK_SUB_CYCLES`); the whole motion run by
    the exact solver, which must agree with its sub-cycle's mean velocity to :data:`CLOSED_FORM_RTOL`."""
    unlimited = velocity_max is None and stroke_max is None
    counts = [1] if unlimited else range(1, min(k_fit + 1, JERK_SUB_CYCLES) + 1)
    found = [(k, jerk_limited(period, a, r, law, jerk, velocity_max, stroke_max, k)) for k in counts]
    found = [(k, best) for k, best in found if best is not None]
    if not found:
        raise ValueError(f"jerk_max = {jerk!r} is too small for period = {period!r} and accel_max = {a!r}: no "
                         f"jerk-limited motion found moves the part (y'' must ramp past the static limit "
                         f"r = {r!r} and back within the period); choose a longer period or a larger jerk_max")
    k, (sub_vbar, levels, holds) = max(found, key=lambda item: item[1][0])
    profile, speed, stroke = _ramped_profile(levels, holds, jerk, k, period)
    vbar = float(steady_mean_velocity([profile], law)[0])
    if not abs(vbar - sub_vbar) <= CLOSED_FORM_RTOL * sub_vbar:
        raise RuntimeError(f"the exact solver's mean velocity {vbar!r} of {k} jerk-limited sub-cycles disagrees "
                           f"with that of one, {sub_vbar!r} (period = {period!r}, accel_max = {a!r}, r = {r!r})")
    used = {"accel_max": float(np.max(np.abs(levels))) >= a * (1.0 - BINDING),
            "velocity_max": velocity_max is not None and speed >= velocity_max * (1.0 - BINDING),
            "stroke_max": stroke_max is not None and stroke >= stroke_max * (1.0 - BINDING), "jerk_max": True}
    return OptimalProfile(profile=profile, vbar=vbar, vbar_bound=float(optimal_mean_velocity(period, a, r)),
                          binding=tuple(name for name, full in used.items() if full),
                          family=_jerk_family(levels, holds, a, r, k), sub_cycles=k, peak_velocity=speed,
                          stroke=stroke, period=period)


def _jerk_family(levels: np.ndarray, holds: np.ndarray, a: float, r: float, k: int) -> str:
    """The ``family`` of a jerk-limited motion: "ramped " and the names of its sub-cycle's levels as
    :func:`_family` gives them (the stick level; the pull-back and catch-up levels, held or not; the coast
    level only where it is held), "x k" for k sub-cycles."""
    kept = [0, 1] + ([2] if holds[2] > JERK_HOLD * float(np.sum(holds)) else []) + [3]
    sliding = np.array([i != 0 for i in kept])
    order = np.roll(np.arange(len(kept)), -1)            # the sub-cycle opens with the slide
    name = _family(Arcs(levels[kept][order], np.ones(len(kept)), sliding[order]), a, r)
    return "ramped " + name + (f" x {k}" if k > 1 else "")
