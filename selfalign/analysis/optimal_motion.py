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
and stroke shrink as 1 / k and 1 / k^2); k_fit = 1 returns the fastest motion.  Otherwise :func:`search`
runs over motions of k < k_fit equal sub-cycles, each a forward slide from rest that opens with y'' = -a
followed by a stick, every sub-cycle solved at period 1 (t -> k t / dt):

* for a fixed slide time D a linear programme in y'' on a grid of cells (:func:`slide_programme`),
  solved globally by HiGHS;
* the best D per k by a scan and a bounded scalar search (:func:`best_slide`), the best k by doubling
  and a golden-section search on the integers (the value taken unimodal in k);
* the two best grid solutions polished by SLSQP over their arcs of constant y'' (:func:`polish`).

The fastest of these and of the k_fit copies is chosen by the exact solver (:func:`steady_mean_velocity`),
which must agree with the closed form of each candidate's slide.
"""

from __future__ import annotations

import math
from dataclasses import dataclass

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
#: Most sub-cycles per period the search builds: limits that need more are refused (a shorter period
#: is the same motion with fewer pieces).
MAX_SUB_CYCLES = 1024
#: A limit is reported binding when the motion uses all but this fraction of it.
BINDING = 1e-6
#: Agreement required between the exact solver's mean velocity and the closed form of the motion.
CLOSED_FORM_RTOL = 1e-9


@dataclass(frozen=True)
class OptimalProfile:
    """The fastest table motion found by :func:`optimal_profile`, and how fast the part moves on it.

    Built by :func:`optimal_profile`, which documents how; the fields are stored as given.

    Parameters
    ----------
    profile : PiecewiseConstantProfile
        The table motion: y'' piecewise constant, y' of zero mean, y's range centred on 0.
    vbar : float
        The part's steady mean velocity on it (eq. 10), from the exact solver.
    vbar_bound : float
        The proven bound v* under the acceleration limit alone (:func:`optimal_vbar`).
    binding : tuple of str
        The limits the motion uses to the full.
    family : str
        The structure of one sub-cycle of the motion.
    sub_cycles : int
        Equal sub-cycles per period.
    peak_velocity : float
        The largest table speed.
    stroke : float
        The table's stroke.

    Attributes
    ----------
    profile : PiecewiseConstantProfile
        The table motion: y'' piecewise constant, y' of zero mean (so y is periodic), y's range centred
        on 0; :func:`~selfalign.simulate`, :func:`~selfalign.simulate_batch` and a
        :class:`~selfalign.Scene` take it.
    vbar : float
        The steady mean velocity of the part relative to the table (eq. 10) on a uniform surface, from
        the exact solver, starting from rest at t = 0.
    vbar_bound : float
        The proven bound v* = (a^2 - 1) r^2 dt / (4 a (1 + r)^2) of the acceleration limit alone: no
        table motion of the period beats it, and ``vbar`` equals it (up to ``ARRIVAL_MARGIN``) when no
        other limit binds.
    binding : tuple of str
        The limits the motion uses to the full, among "accel_max", "velocity_max" and "stroke_max".
    family : str
        The structure of one sub-cycle, its constant-y'' pieces in order: "bang" (y'' = -+a, the
        part slides), "coast" (y'' = 0 while it slides), "ramp" (another level while it slides), "stick"
        (y'' = +-r, the static limit, while it sticks), "dwell" (y'' = 0 while it sticks) or "hold"
        (another level while it sticks); followed by " x k" for k > 1 sub-cycles.
    sub_cycles : int
        k, the equal sub-cycles per period.
    peak_velocity : float
        max ``|y'|``.
    stroke : float
        max y - min y.

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
    motion attains it (:func:`optimal_profile`).  The proof is on the page
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


def _repeat(breaks: np.ndarray, accels: np.ndarray, k: int, period: float) -> tuple[np.ndarray, np.ndarray]:
    """The pieces of ``k`` copies of a sub-cycle (breaks from 0 to period / k) filling [0, period]; a break
    that rounding would put an ulp before the previous one is moved onto it (a piece of length 0, which the
    profile drops)."""
    sub = period / k
    inner = np.concatenate([j * sub + breaks[:-1] for j in range(k)])
    return np.maximum.accumulate(np.concatenate([inner, [period]])), np.tile(accels, k)


def _family(levels, durations, sliding, a: float, r: float, k: int) -> str:
    """The ``family`` name of OptimalProfile for one sub-cycle's arcs (zero-length arcs left out)."""
    names = []
    for level, duration, slide in zip(levels, durations, sliding):
        if duration > 0.0:
            top, words = (a, ("bang", "coast", "ramp")) if slide else (r, ("stick", "dwell", "hold"))
            near = 1e-9 * top
            names.append(words[0] if abs(abs(level) - top) <= near else words[1] if abs(level) <= near else words[2])
    return "-".join(names) + (f" x {k}" if k > 1 else "")


@dataclass(frozen=True)
class Arcs:
    """One sub-cycle as arcs of constant y'': their ``levels``, ``durations`` and whether the part slides
    forward on each (``sliding``: the slide first, then the stick)."""

    levels: np.ndarray
    durations: np.ndarray
    sliding: np.ndarray

    @property
    def slide_arcs(self) -> int:
        return int(np.count_nonzero(self.sliding))

    def quantities(self) -> tuple[np.ndarray, np.ndarray, np.ndarray, np.ndarray, float]:
        """(u, y, y_turn, x_slide, area): y' at the arc starts and the end (zero mean), y there (y(0) = 0),
        y at each arc's point nearest to where y' = 0 (its extreme within the arc), x' at the boundaries of
        the slide arcs (from rest) and int x' dt over the slide."""
        d, level, s = self.durations, self.levels, self.slide_arcs
        gained = np.concatenate([[0.0], np.cumsum(level * d)])
        moved = np.concatenate([[0.0], np.cumsum(gained[:-1] * d + 0.5 * level * d * d)])
        start = -moved[-1] / np.sum(d)
        u = start + gained
        y = moved + start * np.concatenate([[0.0], np.cumsum(d)])
        with np.errstate(divide="ignore", invalid="ignore"):
            turn = np.clip(np.where(level != 0.0, -u[:-1] / level, 0.0), 0.0, d)
        y_turn = y[:-1] + u[:-1] * turn + 0.5 * level * turn * turn
        x_slide = np.concatenate([[0.0], -np.cumsum((level[:s] + 1.0) * d[:s])])
        area = float(np.sum((x_slide[:-1] + x_slide[1:]) * d[:s]) / 2.0)
        return u, y, y_turn, x_slide, area

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


def _solved_durations(levels, durations, slide_arcs: int, solve, period: float, margin: float) -> np.ndarray:
    """``durations`` with the entries ``solve`` (a first slide arc, a later slide arc, a stick arc) solved
    so that they sum to ``period``, y'' has zero mean and the slide ends at x' = ``margin``, exactly up to
    rounding (Cramer's rule on the three linear equations); NaN where the equations are singular."""
    d = np.array(durations, dtype=float)
    rest = np.ones(d.size, dtype=bool)
    rest[list(solve)] = False
    slide = np.arange(d.size) < slide_arcs
    rhs = [period - float(np.sum(d[rest])), -float(np.sum((levels * d)[rest])),
           -margin - float(np.sum(((levels + 1.0) * d)[rest & slide]))]
    matrix = [[1.0, 1.0, 1.0], [float(levels[i]) for i in solve],
              [float(levels[i]) + 1.0 if i < slide_arcs else 0.0 for i in solve]]

    def det(m):
        return (m[0][0] * (m[1][1] * m[2][2] - m[1][2] * m[2][1]) - m[0][1] * (m[1][0] * m[2][2] - m[1][2] * m[2][0])
                + m[0][2] * (m[1][0] * m[2][1] - m[1][1] * m[2][0]))
    whole = det(matrix)
    for column, index in enumerate(solve):
        swapped = [[rhs[i] if j == column else matrix[i][j] for j in range(3)] for i in range(3)]
        d[index] = det(swapped) / whole if whole != 0.0 else float("nan")
    return d


def _dependent(arcs: Arcs) -> list[int]:
    """The arcs whose durations :func:`_solved_durations` solves: the first and the last slide arc and the
    longest stick arc."""
    s = arcs.slide_arcs
    return [0, s - 1, s + int(np.argmax(arcs.durations[s:]))]


def _tidy_stick(arcs: Arcs, r: float, velocity_max: float | None, stroke_max: float | None) -> Arcs:
    """``arcs`` with the stick rewritten as ramp at +r, dwell, ramp at +r, the dwell level L keeping
    int y' dt over the stick (so the slide and y's centring do not change; an L within 1e-9 of the speed
    gain of one of the stick's end speeds is set to it, dropping a vanishing ramp), where L lies between
    those speeds and the limits still hold; else ``arcs``."""
    u, _, _, _, _ = arcs.quantities()
    s = arcs.slide_arcs
    d, level = arcs.durations[s:], arcs.levels[s:]
    first, last = float(u[s]), float(u[-1])
    area = float(np.sum(u[s:-1] * d + 0.5 * level * d * d))
    total = float(np.sum(d))
    dwell = total - (last - first) / r
    if dwell <= 1e-12 * total:
        return arcs
    height = (area - (last * last - first * first) / (2.0 * r)) / dwell
    near = 1e-9 * (last - first)
    height = last if abs(height - last) <= near else first if abs(height - first) <= near else height
    if not first <= height <= last:
        return arcs
    up, down = (height - first) / r, (last - height) / r
    tidy = Arcs(np.concatenate([arcs.levels[:s], [r, 0.0, r]]),
                np.concatenate([arcs.durations[:s], [up, total - up - down, down]]),
                np.concatenate([arcs.sliding[:s], [False] * 3])).merged()
    return tidy if _meets(tidy, velocity_max, stroke_max) else arcs


def _meets(arcs: Arcs, velocity_max: float | None, stroke_max: float | None) -> bool:
    u, y, y_turn, _, _ = arcs.quantities()
    every = np.concatenate([y, y_turn])
    return ((velocity_max is None or float(np.max(np.abs(u))) <= velocity_max)
            and (stroke_max is None or float(np.max(every) - np.min(every)) <= stroke_max))


def _slsqp(arcs: Arcs, a: float, r: float, velocity_max: float | None, stroke_max: float | None,
           margin: float, slack: float) -> Arcs:
    """SLSQP over the levels and durations of the arcs of a sub-cycle of period 1 (:func:`polish`); the
    durations of :func:`_dependent` are solved from the others, so that the equalities hold at every
    iterate."""
    from scipy.optimize import minimize

    m, s = arcs.levels.size, arcs.slide_arcs
    period, speed, length = 1.0, a, a
    v_lim = None if velocity_max is None else velocity_max * (1.0 - slack)
    s_lim = None if stroke_max is None else stroke_max * (1.0 - slack)
    solve = _dependent(arcs)
    free = np.setdiff1d(np.arange(m), solve)
    f = free.size

    def unpack(z) -> Arcs:
        levels = z[f:f + m] * a
        durations = np.zeros(m)
        durations[free] = z[:f] * period
        return Arcs(levels, _solved_durations(levels, durations, s, solve, period, margin), arcs.sliding)

    def inequalities(z):
        trial = unpack(z)
        u, y, y_turn, x_slide, _ = trial.quantities()
        out = [trial.durations[solve] / period, (x_slide[1:-1] - margin) / speed]
        if v_lim is not None:
            out += [(v_lim - u) / speed, (v_lim + u) / speed]
        if s_lim is not None:
            every = np.concatenate([y, y_turn]) / length
            low, high = z[f + m], z[f + m + 1]
            out += [high - every, every - low, [s_lim / length - (high - low)]]
        return np.nan_to_num(np.concatenate(out), nan=-1.0)

    _, y, y_turn, _, _ = arcs.quantities()
    every = np.concatenate([y, y_turn]) / length
    z0 = np.concatenate([arcs.durations[free] / period, arcs.levels / a, [every.min(), every.max()]])
    lower = np.concatenate([np.zeros(f), np.where(arcs.sliding, -1.0, -r / a), [-np.inf] * 2])
    upper = np.concatenate([np.ones(f), np.where(arcs.sliding, 1.0, r / a), [np.inf] * 2])
    lower[f] = upper[f] = -1.0
    lower[f + s] = 0.0
    res = minimize(lambda z: -np.nan_to_num(unpack(z).quantities()[4], nan=-np.inf) / length,
                   np.clip(z0, lower, upper), method="SLSQP", bounds=list(zip(lower, upper)),
                   constraints=[{"type": "ineq", "fun": inequalities}], options={"maxiter": 500, "ftol": 1e-15})
    return unpack(np.clip(res.x, lower, upper))


def _clean(arcs: Arcs, a: float, r: float, drop: float, snap: float) -> Arcs | None:
    """``arcs`` without those shorter than ``drop`` times the sub-cycle, levels within ``snap`` (relative)
    of 0, +-a (sliding) or +-r (stuck) set to it; None if the slide or the stick is left with too few arcs."""
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
    if out.slide_arcs < 2 or out.slide_arcs == out.levels.size or out.levels[0] != -a:
        return None
    return out


def polish(arcs: Arcs, a: float, r: float, velocity_max: float | None, stroke_max: float | None, margin: float,
           slack: float) -> Arcs | None:
    """The arcs of a grid solution of period 1 (:func:`slide_programme`) made exact: SLSQP over their levels
    and durations maximises int x' dt over the slide with the limits held within a fraction ``slack`` of
    them, the sub-cycle's length, zero-mean y'' and the slide's end at x' = ``margin`` (never touched
    before) exact by :func:`_solved_durations`; the first arc stays at -a and the first stick arc between 0
    and r (the part comes to rest on it).  The grid leaves short arcs at intermediate levels where y''
    switches within a cell: arcs shorter than 1e-6 of the sub-cycle are dropped and levels within 1e-6 of 0,
    +-a or +-r set to it, and SLSQP runs again.  Then :func:`_tidy_stick` writes the stick in its canonical
    form.  None if SLSQP ends elsewhere than at a point meeting the limits."""
    first = _clean(_slsqp(arcs, a, r, velocity_max, stroke_max, margin, slack), a, r, 1e-6, 1e-6)
    second = None if first is None else _clean(_slsqp(first, a, r, velocity_max, stroke_max, margin, slack), a, r,
                                               1e-12, 0.0)
    if second is None:
        return None
    exact = Arcs(second.levels, _solved_durations(second.levels, second.durations, second.slide_arcs,
                                                  _dependent(second), 1.0, margin), second.sliding)
    if not (np.all(exact.durations >= 0.0) and _meets(exact, velocity_max, stroke_max)
            and np.all(exact.quantities()[3][1:] > 0.0)):
        return None
    return _tidy_stick(exact, r, velocity_max, stroke_max).merged()


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
           polished: int = 2) -> list[tuple[int, Arcs]]:
    """Polished sub-cycles (k, arcs of period 1) for the ``polished`` best k < ``k_fit``, the limits those
    of a period 1 (module docstring).

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
    for k in sorted((k for k in values if values[k] > 0.0), key=values.get, reverse=True)[:polished]:
        _, arcs = slide_programme(slides[k], a, r, *scaled(k), FINE_CELLS)
        slack = LIMIT_SLACK + 64.0 * np.finfo(float).eps * k * k
        exact = None if arcs is None else polish(arcs, a, r, *scaled(k), ARRIVAL_MARGIN * a * k, slack)
        if exact is not None:
            out.append((k, exact))
    return out


def optimal_profile(period, accel_max, *, stroke_max=None, velocity_max=None, friction=None) -> OptimalProfile:
    """The fastest periodic table motion under an acceleration limit, and under speed and stroke limits.

    Proven for the acceleration limit alone, numerical under the other limits.  On a uniform surface
    (mu_bar = 1, Sect. 3.2) the part's steady mean velocity (eq. 10) under ``|y''| <= a`` is at most v*
    (:func:`optimal_vbar`), and y'' = -a, +a, +r attains it: the table pulls back at -a while the part
    slides forward, catches up at +a as the part comes to rest, then regains its speed at the static limit
    r with the part stuck.  That motion is returned whenever it meets the other limits.  Otherwise the
    search of the module ``selfalign.analysis.optimal_motion`` runs (equal sub-cycles, each a slide from
    rest and a stick; a linear programme per sub-cycle count and slide time, polished): its result is the
    best it finds, not proven optimal.  The derivation, the proof and the search are on the page
    docs/explanation/optimal-motion.md.

    The limits bear on the table motion only through y'': y' is taken with zero mean (y periodic) and y's
    range centred on 0.  Under static friction (r > 1) the returned motion leaves the part a speed of
    ``ARRIVAL_MARGIN`` (2^-40) of a dt at the end of each slide, so that it comes to rest just after y''
    has jumped to its stick level rather than a rounding error before (from which it would slide backward
    for good); its mean velocity is below v* by a relative ~1e-12.

    Parameters
    ----------
    period : float
        The table's period dt, dimensionless (Sect. 3.2); in [1e-30, 1e30].
    accel_max : float
        a, the largest ``|y''|``; in [1e-30, 1e30] and above the friction ratio r.
    stroke_max : float, optional
        The largest stroke max y - min y; > 0.  Default None (no limit).
    velocity_max : float, optional
        The largest table speed ``|y'|``; > 0.  Default None (no limit).
    friction : FrictionLaw, optional
        Coulomb (the default, r = 1) or static_kinetic with r = mu_s / mu_k
        (``selfalign.model.friction.FrictionLaw``).

    Returns
    -------
    OptimalProfile
        The motion, the part's steady mean velocity on it from the exact solver, the bound v*, the limits
        it uses to the full and its structure.

    Raises
    ------
    TypeError
        If a number is not a real number, or ``friction`` is not a FrictionLaw.
    ValueError
        If ``period`` or ``accel_max`` is not finite or lies outside [1e-30, 1e30], a limit is not finite
        and > 0, ``friction`` is a Stribeck law, or ``accel_max`` <= r (nothing moves).

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
    """
    period, accel_max = check_scale("period", period), check_scale("accel_max", accel_max)
    stroke_max, velocity_max = _limit("stroke_max", stroke_max), _limit("velocity_max", velocity_max)
    law, r = _friction_ratio(friction)
    check_moving(accel_max, r)
    a = accel_max
    # The fastest motion's speed and stroke grow as dt and dt^2 (t -> l t, x, y -> l^2 x leaves the model
    # alone, Sect. 3.2), so its k-fold repetition at period dt / k fits the limits from k_fit on.
    _, _, speed, stroke = centred_motion(*fastest_pieces(period, a, r, 0.0))
    k_fit = max(1, math.ceil(speed / velocity_max) if velocity_max is not None else 1,
                math.ceil(math.sqrt(stroke / stroke_max)) if stroke_max is not None else 1)
    if k_fit > MAX_SUB_CYCLES:
        raise ValueError(f"velocity_max = {velocity_max!r}, stroke_max = {stroke_max!r} are too small for period = "
                         f"{period!r} and accel_max = {a!r}: the fastest motion's speed {speed:.6g} and stroke "
                         f"{stroke:.6g} would have to shrink {k_fit} times (more than {MAX_SUB_CYCLES} sub-cycles per "
                         f"period); choose a shorter period (speed and stroke shrink with it and its square)")
    while not _fits(_built(_fastest_arcs(k_fit, a, r), k_fit, period), velocity_max, stroke_max):
        k_fit += 1
    candidates = [(k_fit, _fastest_arcs(k_fit, a, r))]
    if k_fit > 1:
        unit_v = None if velocity_max is None else velocity_max / period
        unit_s = None if stroke_max is None else stroke_max / (period * period)
        candidates += search(a, r, unit_v, unit_s, k_fit)
    return _choose(candidates, period, a, r, law, velocity_max, stroke_max)


def _fastest_arcs(k: int, a: float, r: float) -> Arcs:
    """The fastest motion (:func:`fastest_pieces`) as the arcs of a sub-cycle of period 1 of a motion with
    ``k`` sub-cycles per period, its arrival margin that of the whole period."""
    breaks, accels = fastest_pieces(1.0, a, r, ARRIVAL_MARGIN * a * k)
    return Arcs(accels, np.diff(breaks), np.array([True, True, False]))


def _built(arcs: Arcs, k: int, period: float) -> tuple[np.ndarray, np.ndarray, float, float, float, float]:
    """(breaks, accels, y_start, yd_start, peak_velocity, stroke) of ``k`` copies of the sub-cycle ``arcs``
    (period 1) scaled to fill ``period``: durations times period / k, y'' unchanged."""
    sub = np.concatenate([[0.0], np.cumsum(arcs.durations)]) * (period / k)
    breaks, accels = _repeat(sub, arcs.levels, k, period)
    return (breaks, accels, *centred_motion(breaks, accels))


def _fits(built, velocity_max: float | None, stroke_max: float | None) -> bool:
    return (velocity_max is None or built[4] <= velocity_max) and (stroke_max is None or built[5] <= stroke_max)


def _choose(candidates, period, a, r, law, velocity_max, stroke_max) -> OptimalProfile:
    """The fastest of the candidate sub-cycles (k, arcs of period 1) scaled to ``period``, by the exact
    solver: each must meet the limits exactly and move the part as the closed form of its slide says
    (int x' dt over the slide, to :data:`CLOSED_FORM_RTOL`); the fastest sub-cycle always does."""
    built = [(k, arcs, _built(arcs, k, period)) for k, arcs in candidates]
    built = [b for b in built if _fits(b[2], velocity_max, stroke_max)]
    profiles = [PiecewiseConstantProfile(*b[2][:4]) for b in built]
    closed = [arcs.quantities()[4] * period / k for k, arcs, _ in built]
    vbars = steady_mean_velocity(profiles, law)
    agree = [i for i, v in enumerate(vbars) if abs(v - closed[i]) <= CLOSED_FORM_RTOL * closed[i]]
    if not agree:
        raise RuntimeError(f"the exact solver's mean velocities {vbars.tolist()} disagree with the closed forms "
                           f"{closed} of the motions found for period = {period!r}, accel_max = {a!r}, r = {r!r}")
    i = max(agree, key=lambda i: vbars[i])
    k, arcs, (_, _, _, _, speed, stroke) = built[i]
    used = {"accel_max": True, "velocity_max": velocity_max is not None and speed >= velocity_max * (1.0 - BINDING),
            "stroke_max": stroke_max is not None and stroke >= stroke_max * (1.0 - BINDING)}
    return OptimalProfile(profile=profiles[i], vbar=float(vbars[i]),
                          vbar_bound=float(optimal_mean_velocity(period, a, r)),
                          binding=tuple(name for name, full in used.items() if full),
                          family=_family(arcs.levels, arcs.durations, arcs.sliding, a, r, k), sub_cycles=k,
                          peak_velocity=speed, stroke=stroke)
