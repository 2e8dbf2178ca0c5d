"""Several parts on one table: the exact event-driven solver (the paper's Sect. 8, recommendation 5).

N rigid parts on one line on the same table (:mod:`selfalign.model.parts`), the table acceleration y''
piecewise constant (a :class:`~selfalign.PiecewiseConstantProfile`, such as the three-phase profile of
Sect. 4.4.3), Coulomb friction (eq. 2 per part) on a uniform surface, unilateral contacts between
neighbours with Newton's impact law.  The derivation is docs/explanation/several-parts.md.

The state
---------
Positions x_i (fronts), velocities v_i, and which contacts are closed: a cluster is a maximal run of
touching parts that move together (one velocity, one acceleration).  Between two events every cluster
moves with a constant acceleration (closed-form quadratics, :func:`selfalign.model.arcs.step`).  Inside a
cluster the positions are kept exactly adjacent: each part's front is the front of the part behind it
plus its own width, so no overlap or gap builds up from rounding.

The events
----------
Each found exactly as the first positive root of a quadratic in the cancellation-free form
(:func:`selfalign.model.arcs.first_positive_root`), the earliest one taken:

* a profile break (y'' jumps);
* a cluster's velocity reaching 0 (v + a s = 0, the cluster decelerating);
* the gap between two neighbouring clusters closing.

At an event every cluster is decided again (:meth:`_Chain.settle`): the contacts that touch (a closed
contact, a gap that closed at this event, or a gap within :data:`CONTACT_ULPS` ulp of the positions)
and approach take the simultaneous impact law (:func:`~selfalign.model.parts.impact_velocities`); runs
of touching parts with one velocity (within :data:`VELOCITY_ULPS` ulp of the velocity scale) are pooled
into one velocity; each such run gets its accelerations from
:func:`~selfalign.model.parts.chain_minimiser` (kinetic friction at v != 0, the stick bound at v = 0),
and splits where they differ (its contacts open).

Tie rules
---------
Those of the single-part exact solver (:mod:`selfalign.solvers.engine`), per cluster, and three for the
contacts, so that no zero-length loop can arise:

1. |y''| = k mu_bar counts as stick (:func:`~selfalign.model.parts.chain_minimiser`'s soft threshold).
2. v = 0 exactly at a break: the v = 0 event is taken first, then the break decides the cluster again
   under the new y''.
3. A slip velocity of the wrong sign (rounding, a few ulp) is set to 0 when the cluster moves on.
4. A gap that closes at an event counts as closed whatever its rounded value; a gap within
   :data:`CONTACT_ULPS` ulp of the positions counts as closed too.
5. A relative velocity at a closed contact below the floor (:data:`VELOCITY_ULPS` ulp of the velocity
   scale) counts as zero: the parts are pooled into one velocity, conserving momentum.  This resolves
   the Zeno accumulation of impacts with e > 0 (a part bouncing against another under a steady push:
   infinitely many impacts in a finite time, their relative velocities falling geometrically) as a
   plastic contact once the relative velocity reaches the floor.
6. Accelerations of neighbours in one velocity run that differ by at most :data:`ACCELERATION_ULPS`
   ulp of the force scale count as equal (the parts stay together, with the mass-weighted mean).

A run that makes more than :data:`~selfalign.solvers.outcomes.STALL_EVENTS` events of zero length in a
row, or uses up its event budget, ends with status ``"error"``.
"""

from __future__ import annotations

import math
import numbers
from dataclasses import dataclass

import numpy as np

from ..model import arcs as A
from ..model.errors import check_integer
from ..model.friction import StopZone, Uniform
from ..model.parts import (
    CHAIN_WORK_ROWS,
    IMPACT_WORK_ROWS,
    chain_minimiser,
    check_parts,
    check_restitution,
    impact_velocities,
)
from ..model.profiles import PiecewiseConstantProfile
from .outcomes import STALL_EVENTS

#: A gap between clusters within this many ulp of the positions' scale counts as closed (tie rule 4).
CONTACT_ULPS = 16
#: A relative velocity at a closed contact within this many ulp of the velocity scale counts as zero
#: (tie rule 5, the Zeno floor).
VELOCITY_ULPS = 64
#: Accelerations of touching neighbours within this many ulp of the force scale count as equal (tie rule 6).
ACCELERATION_ULPS = 8
#: Default event budget of :func:`simulate_parts`.
MAX_EVENTS = 10_000_000

_EPS = np.finfo(float).eps


@dataclass(frozen=True)
class PartsResult:
    """The end state and event counts of a run of several parts (:func:`simulate_parts`).

    The solver builds it; its constructor checks nothing.  The events are counted by kind, each at the
    event time it happens (one event time may count several: a break and the slip it starts).

    Parameters
    ----------
    t_end : float
        The end time (Attributes).
    x_end, v_end : numpy.ndarray
        The end state (Attributes).
    sticks, slips, impacts, openings, breaks : int
        The events per kind (Attributes).
    status, message : str
        How the run ended (Attributes).

    Attributes
    ----------
    t_end : float
        The time the run ended (periods times dt at the horizon; earlier at rest or on an error).
    x_end : numpy.ndarray
        Front positions of the parts at ``t_end``, shape (N,), rear-most first.
    v_end : numpy.ndarray
        Their velocities relative to the table at ``t_end``, shape (N,).
    sticks : int
        Stick events: a cluster's velocity reached 0 and it sticks.
    slips : int
        Slip starts: a cluster at zero velocity starts to slip (from stick, or a reversal).
    impacts : int
        Contact closings: a gap between neighbours closed (an impact, or a grazing contact).
    openings : int
        Contact openings: touching neighbours separate.
    breaks : int
        Profile breaks (y'' jumps) passed.
    status : str
        ``"horizon"`` (the periods asked for are done), ``"rest"`` (every part sticks where the friction
        holds it for good: k_i mu_bar_i >= max|y''| for every part i) or ``"error"`` (see ``message``).
    message : str
        Why the run ended with ``"error"``; empty otherwise.
    events : int
        All events counted, of every kind.

    Examples
    --------
    >>> import selfalign as sa
    >>> from selfalign.model.parts import Part
    >>> from selfalign.solvers.parts_exact import simulate_parts
    >>> profile = sa.ThreePhaseProfile(dt=1.05, dy=0.084, y2=2.2, y3=0.9)
    >>> result = simulate_parts(profile, [Part(0.0, width=0.05)], periods=2)
    >>> result.status, result.events == result.sticks + result.slips + result.impacts + result.openings + result.breaks
    ('horizon', True)
    """

    t_end: float
    x_end: np.ndarray
    v_end: np.ndarray
    sticks: int
    slips: int
    impacts: int
    openings: int
    breaks: int
    status: str
    message: str = ""

    @property
    def events(self) -> int:
        """All events counted, of every kind."""
        return self.sticks + self.slips + self.impacts + self.openings + self.breaks


def _check_profile(profile) -> PiecewiseConstantProfile:
    if not isinstance(profile, PiecewiseConstantProfile):
        raise TypeError("profile must be a PiecewiseConstantProfile (e.g. a ThreePhaseProfile): the exact solver of "
                        f"several parts integrates piecewise-constant y'' in closed form, got {type(profile).__name__}")
    return profile


def _check_surface(surface):
    if surface is None:
        return Uniform()
    if isinstance(surface, StopZone):
        raise ValueError("surface: the exact solver of several parts integrates a uniform surface only; a StopZone "
                         "is not supported yet (use Uniform() or None)")
    if not isinstance(surface, Uniform):
        raise TypeError(f"surface must be Uniform() or None, got {type(surface).__name__}")
    return surface


def simulate_parts(profile, parts, *, surface=None, restitution=0.0, periods, max_events=MAX_EVENTS) -> PartsResult:
    """Simulate several parts on one table exactly, event by event, from time 0 over whole periods.

    The model of :mod:`selfalign.model.parts` (eq. 6 per part, Coulomb friction, unilateral contacts and
    Newton's simultaneous impact law); the method, its events and tie rules are those of
    :mod:`selfalign.solvers.parts_exact` (docs/explanation/several-parts.md).

    Parameters
    ----------
    profile : PiecewiseConstantProfile
        The table motion, y'' constant on each piece (e.g. a :class:`~selfalign.ThreePhaseProfile`).
    parts : sequence of Part
        The parts (:class:`~selfalign.model.parts.Part`), the rear-most first, not overlapping; their x0,
        v0 hold at time 0.
    surface : Uniform or None, optional
        The friction field: uniform (mu_bar = 1), the default.  A StopZone is refused (not supported yet).
    restitution : float, optional
        Newton's coefficient of restitution e in [0, 1] of the contacts between parts.  Default 0
        (plastic).
    periods : int
        Simulate this many periods, an integer >= 1.  Keyword only, required.
    max_events : int, optional
        The event budget, an integer >= 1: the run ends with status ``"error"`` when it is used up.

    Returns
    -------
    PartsResult
        The end time, positions, velocities, the events per kind and the status.

    Raises
    ------
    TypeError
        If ``profile`` is not a PiecewiseConstantProfile, ``surface`` not Uniform or None, ``parts`` not a
        sequence of Part, ``restitution`` not a real number, or ``periods`` or ``max_events`` not an integer.
    ValueError
        If ``parts`` is empty or two parts overlap (naming them), ``restitution`` lies outside [0, 1],
        ``periods`` or ``max_events`` is < 1, or ``surface`` is a StopZone.

    Examples
    --------
    Two equal parts touching, pushed forward together by the three-phase profile of Fig. 18: they move
    as one part, the front one a width ahead of the rear one.

    >>> import selfalign as sa
    >>> from selfalign.model.parts import Part
    >>> from selfalign.solvers.parts_exact import simulate_parts
    >>> profile = sa.ThreePhaseProfile(dt=1.05, dy=0.084, y2=2.2, y3=0.9)
    >>> result = simulate_parts(profile, [Part(0.0, width=0.05), Part(0.05, width=0.05)], periods=10)
    >>> result.status, round(float(result.x_end[1] - result.x_end[0]), 12)
    ('horizon', 0.05)
    >>> result.openings, result.impacts
    (0, 0)
    """
    profile = _check_profile(profile)
    parts = check_parts(parts)
    surface = _check_surface(surface)
    e = check_restitution(restitution)
    if isinstance(periods, bool) or not isinstance(periods, numbers.Integral):
        raise TypeError(f"periods must be a positive integer, got {periods!r} ({type(periods).__name__})")
    periods = check_integer("periods", periods)
    if isinstance(max_events, bool) or not isinstance(max_events, numbers.Integral):
        raise TypeError(f"max_events must be a positive integer, got {max_events!r} ({type(max_events).__name__})")
    max_events = check_integer("max_events", max_events)
    return _Chain(profile, parts, e).run(periods, max_events)


class _Chain:
    """The state of the parts and the event loop (uniform surface, mu_bar = 1)."""

    def __init__(self, profile: PiecewiseConstantProfile, parts, e: float):
        n = len(parts)
        self.profile, self.e, self.n = profile, e, n
        self.x = np.array([p.x0 for p in parts], dtype=float)
        self.v = np.array([p.v0 for p in parts], dtype=float)
        self.w = np.array([p.width for p in parts], dtype=float)
        self.m = np.array([p.mass for p in parts], dtype=float)
        self.k = np.array([p.friction_factor for p in parts], dtype=float)
        self.a = np.zeros(n)                        # accelerations relative to the table
        self.sigma = np.zeros(n, dtype=np.int64)    # the direction of the kinetic friction: -1, 0 (stuck), +1
        self.joined = np.zeros(max(n - 1, 0), dtype=bool)   # parts i and i + 1 move together
        self.dirty = np.ones(n, dtype=bool)         # parts whose cluster the next settle decides again
        amax = profile.max_abs_acceleration
        speed = profile.velocity_swing + float(np.max(np.abs(self.v)))
        self.length_scale = float(np.max(self.w)) + speed * profile.dt
        self.v_floor = VELOCITY_ULPS * _EPS * speed
        self.a_tol = ACCELERATION_ULPS * _EPS * (amax + float(np.max(self.k)))
        self.rest_acc = amax
        self.sticks = self.slips = self.impacts = self.openings = self.breaks = 0
        self.b, self.s, self.out = np.empty(n), np.empty(n), np.empty(n)
        self.lower = np.zeros(max(n - 1, 0))
        self.all_joined = np.ones(max(n - 1, 0), dtype=bool)
        self.work = np.empty((max(CHAIN_WORK_ROWS, IMPACT_WORK_ROWS), n))

    # -- the clusters -------------------------------------------------------------------------------------
    def runs(self, linked):
        """(first, last) of the maximal runs of parts linked by ``linked`` (a bool per contact)."""
        first = 0
        for i in range(self.n - 1):
            if not linked[i]:
                yield first, i
                first = i + 1
        yield first, self.n - 1

    def gap(self, i: int) -> float:
        return (self.x[i + 1] - self.w[i + 1]) - self.x[i]

    def contact_tolerance(self, i: int) -> float:
        return CONTACT_ULPS * _EPS * (abs(self.x[i]) + self.length_scale)

    # -- between events -----------------------------------------------------------------------------------
    def next_event(self, rem: float):
        """(s, clusters reaching v = 0 at s, contacts closing at s) of the earliest event within ``rem``;
        s = rem and nothing else if the piece ends first."""
        best = rem
        stops, closes = [], []
        for first, _ in self.runs(self.joined):
            vel, acc = self.v[first], self.a[first]
            if vel != 0.0 and vel * acc < 0.0:
                t = -vel / acc
                if t < best:
                    best, stops, closes = t, [first], []
                elif t == best:
                    stops.append(first)
        for i in range(self.n - 1):
            if self.joined[i]:
                continue
            t = self.closing_time(i)
            if t < best:
                best, stops, closes = t, [], [i]
            elif t == best:
                closes.append(i)
        return best, stops, closes

    def closing_time(self, i: int) -> float:
        """First s > 0 at which the open contact i closes (0 if it touches and approaches), or inf."""
        g = self.gap(i)
        dv = self.v[i + 1] - self.v[i]
        da = self.a[i + 1] - self.a[i]
        if g <= self.contact_tolerance(i):
            if dv < 0.0:
                return 0.0
            g = 0.0
        return A.first_positive_root(0.5 * da, dv, g)

    def advance(self, s: float, stops) -> None:
        """Move every cluster on by a time s (the clusters whose first part is in ``stops`` reach v = 0)."""
        for first, last in self.runs(self.joined):
            vel, acc = self.v[first], self.a[first]
            if vel == 0.0 and acc == 0.0:
                continue
            dx, vel1 = A.step(A.QUADRATIC, 0.0, vel, acc, s)
            if first in stops or vel1 * self.sigma[first] < 0.0:     # tie rules 2-3
                vel1 = 0.0
                self.dirty[first:last + 1] = True
            self.x[first] += dx
            for j in range(first + 1, last + 1):
                self.x[j] = self.x[j - 1] + self.w[j]
            self.v[first:last + 1] = vel1

    # -- at an event --------------------------------------------------------------------------------------
    def settle(self, ay: float, closes=(), count: bool = True, everything: bool = False) -> None:
        """Decide the contacts, impacts, clusters and accelerations at the current state under y'' = ay: every
        cluster (``everything``, at a break) or those an event touched (the others keep their accelerations,
        which a new decision would give again)."""
        n, v, m, dirty = self.n, self.v, self.m, self.dirty
        if everything:
            dirty[:] = True
        touching = self.joined.copy()
        for i in range(n - 1):
            if not touching[i] and (i in closes or self.gap(i) <= self.contact_tolerance(i)):
                touching[i] = True
                dirty[i:i + 2] = True
                if count and (i in closes or v[i] > v[i + 1]):
                    self.impacts += 1
        for first, last in self.runs(touching):
            if last > first and np.any(v[first:last] - v[first + 1:last + 1] > self.v_floor):
                out = self.out[first:last + 1]
                impact_velocities(v[first:last + 1], m[first:last + 1], self.e, touching[first:last], out,
                                  self.work[:IMPACT_WORK_ROWS, first:last + 1])
                v[first:last + 1] = out
                dirty[first:last + 1] = True
        together = touching & (np.abs(v[1:] - v[:-1]) <= self.v_floor)
        was_joined, old_sigma = self.joined.copy(), self.sigma.copy()
        for first, last in self.runs(together):
            group = slice(first, last + 1)
            if not np.any(dirty[group]):
                continue
            dirty[group] = True
            if last > first and np.any(v[group] != v[first]):
                v[group] = np.dot(m[group], v[group]) / np.sum(m[group])    # tie rule 5: momentum kept
            self.decide(first, last, ay)
        for i in range(n - 1):
            if dirty[i] or dirty[i + 1]:
                self.joined[i] = together[i] and abs(self.a[i + 1] - self.a[i]) <= self.a_tol
                if was_joined[i] and not self.joined[i] and count:
                    self.openings += 1
        for first, last in self.runs(self.joined):
            if not dirty[first]:
                continue
            cluster = slice(first, last + 1)
            if last > first and np.any(self.a[cluster] != self.a[first]):
                self.a[cluster] = np.dot(m[cluster], self.a[cluster]) / np.sum(m[cluster])   # tie rule 6
            for j in range(first + 1, last + 1):                     # touching parts exactly adjacent
                self.x[j] = self.x[j - 1] + self.w[j]
            vel, acc = v[first], self.a[first]
            sigma = (1 if vel > 0.0 else -1) if vel != 0.0 else (0 if acc == 0.0 else (1 if acc > 0.0 else -1))
            changed = np.any(old_sigma[cluster] != sigma)
            self.sigma[cluster] = sigma
            if count and vel == 0.0 and changed:
                if sigma == 0:
                    self.sticks += 1
                else:
                    self.slips += 1
        dirty[:] = False

    def decide(self, first: int, last: int, ay: float) -> None:
        """Accelerations of the parts first..last, touching at one velocity, under y'' = ay
        (:func:`~selfalign.model.parts.chain_minimiser`: kinetic friction at v != 0, the stick bound at
        v = 0)."""
        group = slice(first, last + 1)
        vel = self.v[first]
        b, s = self.b[group], self.s[group]
        if vel == 0.0:
            b[:] = -ay
            s[:] = self.k[group]
        else:
            b[:] = -ay - math.copysign(1.0, vel) * self.k[group]
            s[:] = 0.0
        chain_minimiser(b, self.m[group], s, self.lower[first:last], self.all_joined[first:last], self.a[group],
                        self.work[:CHAIN_WORK_ROWS, first:last + 1])

    def at_rest(self) -> bool:
        """Every part sticks where its friction holds it for good (k_i mu_bar_i >= max|y''|)."""
        return bool(np.all(self.v == 0.0) and np.all(self.a == 0.0) and np.all(self.k >= self.rest_acc))

    # -- the run ------------------------------------------------------------------------------------------
    def run(self, periods: int, max_events: int) -> PartsResult:
        profile = self.profile
        breaks, accels, dt = profile.breaks, profile.accels, profile.dt
        pieces = accels.size
        stalled = 0
        self.settle(float(accels[0]), count=False, everything=True)
        for period in range(periods):
            for p in range(pieces):
                ay = float(accels[p])
                if period or p:
                    self.breaks += 1
                    self.settle(ay, everything=True)
                seg = breaks[p + 1] - breaks[p]
                s0 = 0.0
                while True:
                    if self.at_rest():
                        return self.result(period * dt + breaks[p] + s0, "rest")
                    if self.events() >= max_events:
                        return self.result(period * dt + breaks[p] + s0, "error",
                                           f"max_events = {max_events} reached; raise max_events")
                    s, stops, closes = self.next_event(seg - s0)
                    if not (stops or closes):
                        self.advance(seg - s0, ())
                        break
                    self.advance(s, stops)
                    s0 += s
                    stalled = stalled + 1 if s == 0.0 else 0
                    if stalled > STALL_EVENTS:
                        return self.result(period * dt + breaks[p] + s0, "error",
                                           f"more than {STALL_EVENTS} events of zero length in a row at t = "
                                           f"{period * dt + breaks[p] + s0!r}")
                    self.settle(ay, closes)
        return self.result(periods * dt, "horizon")

    def events(self) -> int:
        return self.sticks + self.slips + self.impacts + self.openings + self.breaks

    def result(self, t: float, status: str, message: str = "") -> PartsResult:
        if not (np.all(np.isfinite(self.x)) and np.all(np.isfinite(self.v))):
            status, message = "error", message or f"the state stopped being finite before t = {t!r}"
        return PartsResult(t_end=float(t), x_end=self.x.copy(), v_end=self.v.copy(), sticks=self.sticks,
                           slips=self.slips, impacts=self.impacts, openings=self.openings, breaks=self.breaks,
                           status=status, message=message)
