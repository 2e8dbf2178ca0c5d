"""Several parts on one table: the exact event-driven solver (the paper's Sect. 8, recommendation 5).

N rigid parts on one line on the same table (:mod:`selfalign.model.parts`), the table acceleration y''
piecewise constant (a :class:`~selfalign.PiecewiseConstantProfile`, such as the three-phase profile of
Sect. 4.4.3), Coulomb friction (eq. 2 per part) on a uniform surface or the paper's stop zone (eqs. 7-9,
each part over its own width), unilateral contacts between neighbours with Newton's impact law.  The
derivation is docs/explanation/several-parts.md.

The state
---------
Positions x_i (fronts; relative to x_mu on a stop zone, as in the single-part solver), velocities v_i,
and which contacts are closed: a cluster is a maximal run of touching parts that move together (one
velocity, one acceleration).  Between two events every cluster follows a closed-form arc of
:mod:`selfalign.model.arcs` (:func:`~selfalign.model.arcs.step`): a quadratic where its friction is
constant; on a stop zone, while some of its parts lie in their transition, the harmonic (forward) or
hyperbolic (backward) arc of x'' = a + kappa (x - x_start) with kappa = -+ sum m_j k_j b1_j / sum m_j over
those parts (eq. 42 pooled; b1_j = (c_mu - 1) / w_j).  Inside a cluster the positions are kept exactly
adjacent: each part's front is the front of its neighbour plus or minus a width, so no overlap or gap
builds up from rounding.

The events
----------
The earliest of:

* a profile break (y'' jumps);
* a cluster's velocity reaching 0 (:func:`~selfalign.model.arcs.zero_velocity_time`);
* on a stop zone, a part crossing x_mu or x_mu + w_i (:func:`~selfalign.model.arcs.crossing_time`), and a
  contact force inside a sliding cluster falling to 0 (it is affine in the cluster's displacement, so this
  is a crossing too);
* the gap between two neighbouring clusters closing: the first positive root of a quadratic in the
  cancellation-free form (:func:`~selfalign.model.arcs.first_positive_root`) where both are on quadratic
  arcs; otherwise conservative advancement on the two arcs (:meth:`_Chain.closing_search`): with the
  gap's first three derivatives exact and its fourth bounded, the first root of the lower bound is a step
  that cannot pass a closing, and the steps shrink as Newton's would near one.

At an event the clusters are decided again (:meth:`_Chain.settle`; every one at a break and on a stop
zone, else those the event touched): the contacts that touch (a closed contact, a gap that closed at this
event, or a gap within :data:`CONTACT_ULPS` ulp of the positions) and approach take the simultaneous
impact law (:func:`~selfalign.model.parts.impact_velocities`); runs of touching parts with one velocity
(within :data:`VELOCITY_ULPS` ulp of the velocity scale) are pooled into one velocity; each such run gets
its accelerations from :func:`~selfalign.model.parts.chain_minimiser` (kinetic friction at v != 0, the
stick bound at v = 0), and splits where they differ (its contacts open).

Tie rules
---------
Those of the single-part exact solver (:mod:`selfalign.solvers.engine`), per cluster, and more for the
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
7. A part that crosses a zone boundary lands on it exactly; a part within the contact tolerance of a
   boundary belongs to the region it moves into (the single-part solver's rule 5).
8. A contact inside a sliding cluster whose force is zero (to rounding, or because it fell to zero at this
   event) and falls as the cluster moves on opens at once; each side gets its own arc.
9. The impact law acts on the touching contacts that do not separate (relative velocity at most the floor
   of rule 5): a touching pair already moving apart is open, and if the impact drives it together again it
   closes at once, as a new event (a zero-length step), so that impacts through parts that separate follow
   one another, as Moreau's rule (a contact is active where its gap at the step's midpoint is <= 0) has it.
   At that second impact, at the same time as the first, the law acts on every touching contact: the rest
   of the cascade is resolved at once, simultaneously (pairwise impacts one after the other could go on
   without end in a touching chain).

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
from ..model.friction import StopZone, Uniform, coefficient, transition_slope
from ..model.parts import (
    CHAIN_WORK_ROWS,
    IMPACT_WORK_ROWS,
    chain_minimiser,
    check_parts,
    check_restitution,
    impact_velocities,
)
from ..model.profiles import PiecewiseConstantProfile
from .outcomes import HIGH, LOW, STALL_EVENTS, ZONE, Reason, Status

#: A gap between clusters within this many ulp of the positions' scale counts as closed (tie rule 4).
CONTACT_ULPS = 16
#: A relative velocity at a closed contact within this many ulp of the velocity scale counts as zero
#: (tie rule 5, the Zeno floor).
VELOCITY_ULPS = 64
#: Accelerations of touching neighbours within this many ulp of the force scale count as equal (tie rule 6).
ACCELERATION_ULPS = 8
#: Largest number of steps of the search for a closing gap between clusters on a stop zone's arcs.
SEARCH_STEPS = 10_000
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
    reason : Reason
        Why the run ended (Attributes).
    message : str
        Why it ended with an error (Attributes).

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
    reason : Reason
        ``PERIODS`` (the periods asked for are done), ``REST`` (every part sticks for good: no table
        acceleration of the profile moves a part alone or a cluster of parts pushed together), or
        ``MAX_EVENTS``, ``STALL`` or ``NONFINITE`` (errors, see ``message``).
    status : Status
        The status of ``reason``: ``"horizon"``, ``"rest"`` or ``"error"``.
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
    >>> result.status.value, result.events == sum((result.sticks, result.slips, result.impacts, result.openings,
    ...                                             result.breaks))
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
    reason: Reason
    message: str = ""

    @property
    def status(self) -> Status:
        """The status of ``reason``."""
        return self.reason.status

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
    if not isinstance(surface, (Uniform, StopZone)):
        raise TypeError(f"surface must be Uniform(), StopZone(...) or None, got {type(surface).__name__}")
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
    surface : Uniform, StopZone or None, optional
        The friction field: uniform (mu_bar = 1, the default) or the paper's stop zone, whose ``x_mu`` and
        ``c_mu`` it uses (each part's transition spans its own width, eqs. 7-9; the zone's ``w`` is not
        used).
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
        If ``profile`` is not a PiecewiseConstantProfile, ``surface`` not Uniform, StopZone or None, ``parts``
        not a sequence of Part, ``restitution`` not a real number, or ``periods`` or ``max_events`` not an
        integer.
    ValueError
        If ``parts`` is empty or two parts overlap (naming them), ``restitution`` lies outside [0, 1], or
        ``periods`` or ``max_events`` is < 1.

    Examples
    --------
    Two equal parts touching, pushed forward together by the three-phase profile of Fig. 18: they move
    as one part, the front one a width ahead of the rear one.

    >>> import selfalign as sa
    >>> from selfalign.model.parts import Part
    >>> from selfalign.solvers.parts_exact import simulate_parts
    >>> profile = sa.ThreePhaseProfile(dt=1.05, dy=0.084, y2=2.2, y3=0.9)
    >>> result = simulate_parts(profile, [Part(0.0, width=0.05), Part(0.05, width=0.05)], periods=10)
    >>> result.status.value, round(float(result.x_end[1] - result.x_end[0]), 12)
    ('horizon', 0.05)
    >>> result.openings, result.impacts
    (0, 0)

    The same pair pushed into a stop zone comes to rest where the mean of their friction coefficients reaches
    max|y''| = 2.2: the front part on the high-friction side (2.5), the rear one at mu_bar = 1.9, 0.6 of its
    width into its transition.

    >>> zone = sa.StopZone(x_mu=0.15, w=0.05, c_mu=2.5)
    >>> pair = simulate_parts(profile, [Part(-0.05, width=0.05), Part(0.0, width=0.05)], surface=zone, periods=60)
    >>> [round(float(x), 12) for x in pair.x_end]
    [0.18, 0.23]
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
    return _Chain(profile, parts, e, surface).run(periods, max_events)


class _Chain:
    """The state of the parts and the event loop."""

    def __init__(self, profile: PiecewiseConstantProfile, parts, e: float, surface):
        n = len(parts)
        self.profile, self.e, self.n = profile, e, n
        self.zone = isinstance(surface, StopZone)
        self.origin = surface.x_mu if self.zone else 0.0        # positions are kept relative to x_mu
        self.c_mu = surface.c_mu if self.zone else 1.0
        self.x = np.array([p.x0 for p in parts], dtype=float) - self.origin
        self.v = np.array([p.v0 for p in parts], dtype=float)
        self.w = np.array([p.width for p in parts], dtype=float)
        self.m = np.array([p.mass for p in parts], dtype=float)
        self.k = np.array([p.friction_factor for p in parts], dtype=float)
        self.slope = np.array([transition_slope(self.c_mu, p.width) for p in parts])    # b1 of each part
        self.a = np.zeros(n)                        # accelerations relative to the table (at the arc start)
        self.sigma = np.zeros(n, dtype=np.int64)    # the direction of the kinetic friction: -1, 0 (stuck), +1
        self.kind = np.full(n, A.QUADRATIC, dtype=np.int64)     # each cluster's arc (model.arcs kinds)
        self.omega = np.zeros(n)                    # and its omega = sqrt(|kappa|)
        self.kappa = np.zeros(n)                    # x'' = a + kappa (x - x_start) along the arc
        self.joined = np.zeros(max(n - 1, 0), dtype=bool)   # parts i and i + 1 move together
        self.dirty = np.ones(n, dtype=bool)         # parts whose cluster the next settle decides again
        amax = profile.max_abs_acceleration
        speed = profile.velocity_swing + float(np.max(np.abs(self.v)))
        self.length_scale = float(np.max(self.w)) + speed * profile.dt
        self.v_floor = VELOCITY_ULPS * _EPS * speed
        self.force_scale = amax + float(np.max(self.k)) * self.c_mu
        self.a_tol = ACCELERATION_ULPS * _EPS * self.force_scale
        self.extremes = (float(np.max(profile.accels)), float(np.min(profile.accels)))
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

    def mu(self, j: int) -> float:
        """mu_bar of part j at its position (eqs. 7-9 over its own width; 1 on a uniform surface)."""
        return coefficient(self.x[j], self.w[j], self.c_mu) if self.zone else 1.0

    def region(self, j: int, sigma: int) -> int:
        """The region of part j moving in direction ``sigma``: a part within the contact tolerance of a zone
        boundary belongs to the region it moves into (the single-part solver's tie rule 5)."""
        if not self.zone:
            return LOW
        x, tol = self.x[j], self.contact_tolerance(j)
        if x < -tol or (abs(x) <= tol and sigma <= 0):
            return LOW
        if x > self.w[j] + tol or (abs(x - self.w[j]) <= tol and sigma >= 0):
            return HIGH
        return ZONE

    def place(self, first: int, last: int, anchor: int) -> None:
        """Put the parts first..last of a cluster exactly adjacent to part ``anchor``."""
        for j in range(anchor + 1, last + 1):
            self.x[j] = self.x[j - 1] + self.w[j]
        for j in range(anchor - 1, first - 1, -1):
            self.x[j] = self.x[j + 1] - self.w[j + 1]

    # -- between events -----------------------------------------------------------------------------------
    def next_event(self, rem: float):
        """(s, clusters reaching v = 0, contacts closing, zone crossings (part, boundary), contacts whose
        force falls to 0, all at s) of the earliest event within ``rem``; s = rem and nothing else if the
        piece ends first."""
        best = rem
        found = ([], [], [], [])        # stops, closes, crossings, opens

        def take(t, which, item):
            nonlocal best, found
            if t < best:
                best, found = t, ([], [], [], [])
            if t == best:
                found[which].append(item)

        for first, last in self.runs(self.joined):
            vel, acc, sigma = self.v[first], self.a[first], int(self.sigma[first])
            if sigma == 0:
                continue
            kind, om = int(self.kind[first]), self.omega[first]
            take(A.zero_velocity_time(kind, om, sigma, vel, acc), 0, first)
            if not self.zone:
                continue
            for j in range(first, last + 1):
                r = self.region(j, sigma)
                xb = (0.0 if r == LOW else self.w[j] if r == ZONE else None) if sigma > 0 else \
                     (self.w[j] if r == HIGH else 0.0 if r == ZONE else None)
                if xb is not None:
                    take(A.crossing_time(kind, om, vel, acc, self.x[j] - xb), 2, (j, xb))
            if kind != A.QUADRATIC:
                for i, force, rate in self.contact_forces(first, last):
                    if force > 0.0 and rate != 0.0:
                        take(A.crossing_time(kind, om, vel, acc, force / rate), 3, i)
        for i in range(self.n - 1):
            if not self.joined[i]:
                t, closes = self.closing_time(i, best)
                take(t, 1 if closes else 3, i)
        return (best,) + found

    def contact_forces(self, first: int, last: int):
        """(contact, force lam_i, d lam_i / d displacement) of the contacts inside a sliding cluster on a stop
        zone: lam_i = sum_{j <= i} m_j (b_j - a), affine in the cluster's displacement while no part crosses a
        zone boundary."""
        sigma, acc, kap = int(self.sigma[first]), self.a[first], self.kappa[first]
        force = rate = 0.0
        ay = self.ay
        for j in range(first, last):
            b = -ay - sigma * self.k[j] * self.mu(j)
            slope = self.k[j] * self.slope[j] if self.region(j, sigma) == ZONE else 0.0
            force += self.m[j] * (b - acc)
            rate += self.m[j] * (-sigma * slope - kap)
            yield j, force, rate

    def arc_state(self, j: int, s: float):
        """(displacement, velocity, acceleration, jerk) of part j's cluster a time s into its arc."""
        vel, acc = self.v[j], self.a[j]
        if self.sigma[j] == 0:
            return 0.0, 0.0, 0.0, 0.0
        kap = self.kappa[j]
        dx, vel1 = A.step(int(self.kind[j]), self.omega[j], vel, acc, s)
        return dx, vel1, acc + kap * dx, kap * vel1

    def acceleration_bound(self, j: int, state, window: float) -> float:
        """A bound on |x''''| = |kappa x''| of part j's cluster over a ``window`` of time from the point of its
        arc where (displacement, velocity, acceleration, jerk) is ``state`` (:meth:`arc_state`): on a harmonic
        arc x'' oscillates with the amplitude hypot(x'', omega x'), on a hyperbolic one it grows at most by
        cosh and sinh of omega times the window."""
        kind, om = int(self.kind[j]), self.omega[j]
        if self.sigma[j] == 0 or kind == A.QUADRATIC:
            return 0.0
        _, vel, acc, _ = state
        if kind == A.HARMONIC:
            return om * om * math.hypot(acc, om * vel)
        return om * om * (abs(acc) * math.cosh(om * window) + om * abs(vel) * math.sinh(om * window))

    def closing_time(self, i: int, horizon: float):
        """(s, closes) of the open contact i: the first s > 0 at which it closes (0 if it touches and
        approaches), or inf; closes False for a check point of the search that is no closing."""
        g = self.gap(i)
        tol = self.contact_tolerance(i)
        if self.kind[i] == A.QUADRATIC and self.kind[i + 1] == A.QUADRATIC:
            dv = self.v[i + 1] - self.v[i]
            da = self.a[i + 1] - self.a[i]
            if g <= tol:
                if dv < 0.0:
                    return 0.0, True
                g = 0.0
            return A.first_positive_root(0.5 * da, dv, g), True
        return self.closing_search(i, g, tol, horizon)

    def closing_search(self, i: int, g: float, tol: float, horizon: float):
        """Conservative advancement on the closed-form arcs of the two clusters: with the gap's first three
        derivatives exact and |g''''| <= q, the gap stays above g + g' s + g'' s^2 / 2 + g''' s^3 / 6 - q s^4 / 24
        (its negative terms only), whose first root is a safe step; near a closing the steps shrink as
        Newton's would.  The search looks at most 1 / omega ahead at a time (the bound of a hyperbolic arc
        grows as exp(omega s)) and goes on to ``horizon``."""
        omega = max(self.omega[i], self.omega[i + 1])
        reach = 1.0 / omega if omega > 0.0 else math.inf
        s = 0.0
        coef = [g, 0.0, 0.0, 0.0]
        for _ in range(SEARCH_STEPS):
            rear, front = self.arc_state(i, s), self.arc_state(i + 1, s)
            coef[1:] = [front[1] - rear[1], (front[2] - rear[2]) / 2.0, (front[3] - rear[3]) / 6.0]
            if s > 0.0:
                coef[0] = g + (front[0] - rear[0])
                if coef[0] <= tol:
                    return s, True
            else:
                if g <= tol:                        # touching: the first derivative that is not zero decides
                    coef[0] = 0.0
                    for p, floor in ((1, self.v_floor), (2, self.a_tol), (3, 0.0)):
                        if abs(coef[p]) > floor:
                            break
                        coef[p] = 0.0
                    lead = next((c for c in coef if c != 0.0), 0.0)
                    if lead < 0.0:
                        return 0.0, True
                    if lead == 0.0:
                        return math.inf, True
            p = next(p for p, c in enumerate(coef) if c > 0.0)
            window = min(horizon - s, reach)
            q = self.acceleration_bound(i, rear, window) + self.acceleration_bound(i + 1, front, window)
            step = _safe_step(coef, p, q / 24.0, window)
            if step == math.inf:
                if window >= horizon - s:
                    return math.inf, True
                step = window
            s += step
        return s, False

    def advance(self, s: float, stops, crossings) -> None:
        """Move every cluster on by a time s (the clusters whose first part is in ``stops`` reach v = 0; the
        parts in ``crossings`` land on their zone boundary)."""
        landing = dict(crossings)
        for first, last in self.runs(self.joined):
            vel, acc = self.v[first], self.a[first]
            if self.sigma[first] == 0:
                continue
            dx, vel1 = A.step(int(self.kind[first]), self.omega[first], vel, acc, s)
            if first in stops or vel1 * self.sigma[first] < 0.0:     # tie rules 2-3
                vel1 = 0.0
                self.dirty[first:last + 1] = True
            anchor = next((j for j in range(first, last + 1) if j in landing), first)
            self.x[anchor] = landing[anchor] if anchor in landing else self.x[anchor] + dx
            self.place(first, last, anchor)
            self.v[first:last + 1] = vel1
            self.a[first:last + 1] = acc + self.kappa[first] * dx

    # -- at an event --------------------------------------------------------------------------------------
    def settle(self, ay: float, closes=(), opens=(), start: bool = False, everything: bool = False,
               instant: bool = False) -> None:
        """Decide the contacts, impacts, clusters and accelerations at the current state under y'' = ay: every
        cluster (``everything``, at a break, and at every event on a stop zone, where the friction depends on
        the positions) or those an event touched (the others keep their accelerations, which a new decision
        would give again).  ``opens``: contacts whose force fell to zero at this event; ``start``: the state at
        time 0, whose stick and slip modes are no events (its impacts are); ``instant``: the event follows the
        one before it at the same time (tie rule 9)."""
        n, v, m, dirty = self.n, self.v, self.m, self.dirty
        self.ay = ay
        if everything or self.zone:
            dirty[:] = True
        touching = self.joined.copy()
        for i in range(n - 1):
            if not touching[i] and (i in closes or self.gap(i) <= self.contact_tolerance(i)):
                touching[i] = True
                dirty[i:i + 2] = True
                if i in closes or v[i] > v[i + 1]:
                    self.impacts += 1
        closed = touching if instant else touching & (v[1:] - v[:-1] <= self.v_floor)     # tie rule 9
        for first, last in self.runs(closed):
            if last > first and np.any(v[first:last] - v[first + 1:last + 1] > self.v_floor):
                out = self.out[first:last + 1]
                impact_velocities(v[first:last + 1], m[first:last + 1], self.e, closed[first:last], out,
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
        for first, last in list(self.runs(self.joined)):
            if dirty[first]:
                self.set_arc(first, last)
                if self.zone and last > first and self.sigma[first] != 0:
                    self.split(first, last, opens)
        for i in range(n - 1):
            if was_joined[i] and not self.joined[i]:
                self.openings += 1
        for first, last in self.runs(self.joined):
            if not dirty[first]:
                continue
            cluster = slice(first, last + 1)
            self.place(first, last, first)                          # touching parts exactly adjacent
            if v[first] == 0.0 and np.any(old_sigma[cluster] != self.sigma[first]) and not start:
                if self.sigma[first] == 0:
                    self.sticks += 1
                else:
                    self.slips += 1
        dirty[:] = False

    def set_arc(self, first: int, last: int) -> None:
        """The direction, acceleration and arc of the cluster first..last (tie rule 6: the mass-weighted
        mean of accelerations that differ by rounding)."""
        cluster, m = slice(first, last + 1), self.m
        if last > first and np.any(self.a[cluster] != self.a[first]):
            self.a[cluster] = np.dot(m[cluster], self.a[cluster]) / np.sum(m[cluster])
        vel, acc = self.v[first], self.a[first]
        sigma = (1 if vel > 0.0 else -1) if vel != 0.0 else (0 if acc == 0.0 else (1 if acc > 0.0 else -1))
        self.sigma[cluster] = sigma
        stiffness = 0.0
        if sigma != 0 and self.zone:
            for j in range(first, last + 1):
                if self.region(j, sigma) == ZONE:
                    stiffness += m[j] * self.k[j] * self.slope[j]
            stiffness /= float(np.sum(m[cluster]))
        kind = A.QUADRATIC if stiffness == 0.0 else (A.HARMONIC if sigma > 0 else A.HYPERBOLIC)
        self.kind[cluster] = kind
        self.omega[cluster] = math.sqrt(stiffness)
        self.kappa[cluster] = A.stiffness(kind, stiffness)

    def split(self, first: int, last: int, opens) -> None:
        """Open the contacts of a sliding cluster on a stop zone whose force is zero (to rounding, or because
        it fell to zero at this event) and falls as the cluster moves on; each part gets its own arc."""
        direction = self.v[first] if self.v[first] != 0.0 else self.a[first]
        cut = [i for i, force, rate in self.contact_forces(first, last)
               if (i in opens or force <= self.a_tol * self.m[first:last + 1].sum()) and rate * direction < 0.0]
        if not cut:
            return
        ay, sigma = self.ay, int(self.sigma[first])
        for i in cut:
            self.joined[i] = False
        for start, end in list(self.runs(self.joined)):
            if first <= start and end <= last:
                group = slice(start, end + 1)
                b = [-ay - sigma * self.k[j] * self.mu(j) for j in range(start, end + 1)]
                self.a[group] = np.dot(self.m[group], b) / np.sum(self.m[group])
                self.set_arc(start, end)

    def decide(self, first: int, last: int, ay: float, out=None) -> None:
        """Accelerations of the parts first..last, touching at one velocity, under y'' = ay
        (:func:`~selfalign.model.parts.chain_minimiser`: kinetic friction at v != 0, the stick bound at
        v = 0), written into their ``a`` or into ``out`` (an array of the group's length)."""
        group = slice(first, last + 1)
        vel = self.v[first]
        b, s = self.b[group], self.s[group]
        for j in range(first, last + 1):
            s[j - first] = self.k[j] * self.mu(j)
        if vel == 0.0:
            b[:] = -ay
        else:
            b[:] = -ay - math.copysign(1.0, vel) * s
            s[:] = 0.0
        chain_minimiser(b, self.m[group], s, self.lower[first:last], self.all_joined[first:last],
                        self.a[group] if out is None else out, self.work[:CHAIN_WORK_ROWS, first:last + 1])

    def at_rest(self) -> bool:
        """Every part sticks for good: at rest, no table acceleration of the profile moves any cluster.  The
        mode selection (:func:`~selfalign.model.parts.chain_minimiser`, b = -y'', the stick bounds) gives zero
        accelerations under the largest and the smallest y'' of the profile, and so under every y'' between
        (its solution is monotone in b); for a part alone this is k_i mu_bar_i >= max|y''|, for parts pushed
        together their pooled bound (a pair held in a stop zone where the mean of its coefficients reaches
        max|y''|)."""
        if not (np.all(self.v == 0.0) and np.all(self.a == 0.0)):
            return False
        for first, last in self.runs(self.joined):
            out = self.out[first:last + 1]
            for ay in self.extremes:
                self.decide(first, last, ay, out)
                if np.any(out != 0.0):
                    return False
        return True

    # -- the run ------------------------------------------------------------------------------------------
    def run(self, periods: int, max_events: int) -> PartsResult:
        profile = self.profile
        breaks, accels, dt = profile.breaks, profile.accels, profile.dt
        pieces = accels.size
        stalled = 0
        self.settle(float(accels[0]), start=True, everything=True)
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
                        return self.result(period * dt + breaks[p] + s0, Reason.REST)
                    if self.events() >= max_events:
                        return self.result(period * dt + breaks[p] + s0, Reason.MAX_EVENTS,
                                           f"max_events = {max_events} reached; raise max_events")
                    s, stops, closes, crossings, opens = self.next_event(seg - s0)
                    if not (stops or closes or crossings or opens):
                        self.advance(seg - s0, (), ())
                        break
                    self.advance(s, stops, crossings)
                    s0 += s
                    stalled = stalled + 1 if s == 0.0 else 0
                    if stalled > STALL_EVENTS:
                        return self.result(period * dt + breaks[p] + s0, Reason.STALL,
                                           f"more than {STALL_EVENTS} events of zero length in a row at t = "
                                           f"{period * dt + breaks[p] + s0!r}")
                    self.settle(ay, closes, opens, instant=s == 0.0)
        return self.result(periods * dt, Reason.PERIODS)

    def events(self) -> int:
        return self.sticks + self.slips + self.impacts + self.openings + self.breaks

    def result(self, t: float, reason: Reason, message: str = "") -> PartsResult:
        if not (np.all(np.isfinite(self.x)) and np.all(np.isfinite(self.v))):
            reason, message = Reason.NONFINITE, message or f"the state stopped being finite before t = {t!r}"
        return PartsResult(t_end=float(t), x_end=self.x + self.origin, v_end=self.v.copy(), sticks=self.sticks,
                           slips=self.slips, impacts=self.impacts, openings=self.openings, breaks=self.breaks,
                           reason=reason, message=message)


def _safe_step(coef, p: int, quartic: float, limit: float) -> float:
    """The first root of coef[p] - sum_{q > p} max(-coef[q], 0) s^(q - p) - quartic s^(4 - p) (decreasing from
    coef[p] > 0), by bisection to rounding; inf if it lies beyond ``limit``."""
    def lower(s):
        total = coef[p] - quartic * s ** (4 - p)
        for q in range(p + 1, 4):
            total -= max(-coef[q], 0.0) * s ** (q - p)
        return total

    if lower(limit) > 0.0:
        return math.inf
    lo, hi = 0.0, limit
    while hi - lo > 4.0 * _EPS * hi:
        mid = 0.5 * (lo + hi)
        if lower(mid) > 0.0:
            lo = mid
        else:
            hi = mid
    return lo
