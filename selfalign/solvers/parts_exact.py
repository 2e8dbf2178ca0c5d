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
  arcs; otherwise conservative advancement on the two arcs
  (:func:`~selfalign.solvers.engine.parts.closing_search`): with the gap's first three derivatives exact
  and its fourth bounded, the first root of the lower bound is a step that cannot pass a closing, and the
  steps shrink as Newton's would near one.

At an event the clusters are decided again (:func:`~selfalign.solvers.engine.parts.settle`; every one at a
break and on a stop zone, else those the event touched): the contacts that touch (a closed contact, a gap
that closed at this event, or a gap within :data:`CONTACT_ULPS` ulp of the positions) and approach take
the simultaneous impact law (:func:`~selfalign.model.parts.impact_velocities`); runs of touching parts with one velocity
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

The implementation
------------------
:func:`simulate_parts` checks its input here, in Python, and runs the event loop compiled
(:mod:`selfalign.solvers.engine.parts`, through :func:`selfalign.solvers.jit.kernel`): loops over
preallocated arrays, calling the model's own formulas compiled (:func:`~selfalign.model.parts.chain_minimiser`,
:func:`~selfalign.model.parts.impact_velocities`, :mod:`selfalign.model.arcs`,
:func:`~selfalign.model.friction.coefficient`).  Mass-weighted means are sums in part order, without BLAS.
"""

from __future__ import annotations

import math
import numbers
from dataclasses import dataclass

import numpy as np

from ..model.errors import check_integer, check_real
from ..model.friction import StopZone, Uniform, transition_slope
from ..model.parts import check_parts, check_restitution, parts_friction_ratio
from ..model.profiles import PiecewiseConstantProfile
from .engine import codes as C
from .engine.codes import ACCELERATION_ULPS, CONTACT_ULPS, SEARCH_STEPS, VELOCITY_ULPS  # noqa: F401 (tie rules)
from .jit import call, kernel
from .outcomes import STALL_EVENTS, Reason, Status
from .tables import kernel_row

#: Default event budget of :func:`simulate_parts`.
MAX_EVENTS = 10_000_000
#: The event kinds a :class:`PartsResult` counts in total (attributes of these names; ``events`` is their sum).
PART_EVENTS = ("sticks", "slips", "impacts", "openings", "breaks")
#: What it holds per part (attributes ``part_<name>``, arrays of shape (N,)): the events per kind and the rest flag.
PER_PART = ("sticks", "slips", "impacts", "openings", "crossings", "held")

_EPS = np.finfo(float).eps


@dataclass(frozen=True)
class PartsResult:
    """The end state and event counts of a run of several parts (:func:`simulate_parts`).

    The solver builds it; its constructor checks nothing.  The events are counted by kind, each at the
    event time it happens (one event time may count several: a break and the slip it starts), in total and
    per part: an event counts for every part it involves (a cluster's stick for each of its parts, a contact
    closing or opening for the two parts of the contact), so the counts per part do not add up to the totals.

    Parameters
    ----------
    t_end : float
        The end time (Attributes).
    x_end, v_end : numpy.ndarray
        The end state (Attributes).
    sticks, slips, impacts, openings, breaks : int
        The events per kind (Attributes).
    part_sticks, part_slips, part_impacts, part_openings, part_crossings : numpy.ndarray
        The events per part (Attributes).
    part_held : numpy.ndarray
        Which parts stick for good at the end (Attributes).
    reason : Reason
        Why the run ended (Attributes).
    message : str
        Why it ended with an error (Attributes).

    Attributes
    ----------
    t_end : float
        The time the run ended (the start phase times dt plus periods times dt at the horizon; earlier at rest
        or on an error).
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
    part_sticks : numpy.ndarray
        Per part, shape (N,): the sticks of the clusters it was part of.
    part_slips : numpy.ndarray
        Per part: the slip starts of the clusters it was part of.
    part_impacts : numpy.ndarray
        Per part: the contact closings it took part in (with the part behind it or in front of it).
    part_openings : numpy.ndarray
        Per part: the openings of its contacts.
    part_crossings : numpy.ndarray
        Per part: its zone crossings, where it reached a boundary of its transition (x_mu or x_mu + w_i), to
        enter it or leave it (0 on a uniform surface); they are not counted in ``events``.
    part_held : numpy.ndarray
        Per part, bool: it sticks for good at ``t_end``: its cluster (the run of touching parts it belongs to)
        is at rest and no table acceleration of the profile moves it (the rest decision, cluster by cluster).
        All True where ``reason`` is ``REST``.
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
    >>> result.part_sticks.tolist() == [result.sticks], result.part_crossings.tolist(), result.part_held.tolist()
    (True, [0], [False])
    """

    t_end: float
    x_end: np.ndarray
    v_end: np.ndarray
    sticks: int
    slips: int
    impacts: int
    openings: int
    breaks: int
    part_sticks: np.ndarray
    part_slips: np.ndarray
    part_impacts: np.ndarray
    part_openings: np.ndarray
    part_crossings: np.ndarray
    part_held: np.ndarray
    reason: Reason
    message: str = ""

    @property
    def status(self) -> Status:
        """The status of ``reason``."""
        return self.reason.status

    @property
    def events(self) -> int:
        """All events counted, of every kind."""
        return sum(getattr(self, kind) for kind in PART_EVENTS)


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


def simulate_parts(profile, parts, *, surface=None, restitution=0.0, periods, phase=0.0, friction=None,
                   max_events=MAX_EVENTS) -> PartsResult:
    """Simulate several parts on one table exactly, event by event, over whole periods from a start phase.

    The model of :mod:`selfalign.model.parts` (eq. 6 per part, Coulomb friction, unilateral contacts and
    Newton's simultaneous impact law); the method, its events and tie rules are those of
    :mod:`selfalign.solvers.parts_exact` (docs/explanation/several-parts.md).

    Parameters
    ----------
    profile : PiecewiseConstantProfile
        The table motion, y'' constant on each piece (e.g. a :class:`~selfalign.ThreePhaseProfile`).
    parts : sequence of Part
        The parts (:class:`~selfalign.model.parts.Part`), the rear-most first, not overlapping; their x0,
        v0 hold at time ``phase`` times dt.
    surface : Uniform, StopZone or None, optional
        The friction field: uniform (mu_bar = 1, the default) or the paper's stop zone, whose ``x_mu`` and
        ``c_mu`` it uses (each part's transition spans its own width, eqs. 7-9; the zone's ``w`` is not
        used).
    restitution : float, optional
        Newton's coefficient of restitution e in [0, 1] of the contacts between parts.  Default 0
        (plastic).
    periods : int
        Simulate this many periods, an integer >= 1.  Keyword only, required.
    phase : float, optional
        The start time as a fraction of the period, in [0, 1) (as ``Scene.phase``): the run starts at
        tau0 = phase dt, and its periods end at tau0 + n dt.  Default 0.
    friction : FrictionLaw or None, optional
        Coulomb's law (None, the default) or static/kinetic friction: a cluster at rest sticks while the
        static bounds r k_i mu_bar_i hold it and slips with the kinetic k_i mu_bar_i
        (:func:`~selfalign.model.parts.static_kinetic_minimiser`).
    max_events : int, optional
        The event budget, an integer >= 1: the run ends with status ``"error"`` when it is used up.

    Returns
    -------
    PartsResult
        The end time, positions, velocities, the events per kind (in total and per part) and the status.

    Raises
    ------
    TypeError
        If ``profile`` is not a PiecewiseConstantProfile, ``surface`` not Uniform, StopZone or None, ``parts``
        not a sequence of Part, ``restitution`` or ``phase`` not a real number, ``friction`` not a FrictionLaw
        or None, or ``periods`` or ``max_events`` not an integer.
    ValueError
        If ``parts`` is empty or two parts overlap (naming them), ``restitution`` lies outside [0, 1],
        ``phase`` outside [0, 1), ``friction`` is Stribeck's law, or ``periods`` or ``max_events`` is < 1.

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
    phase = check_real("phase", phase)
    if not 0.0 <= phase < 1.0:
        raise ValueError(f"phase must lie in [0, 1) (fraction of the period), got {phase!r}")
    ratio = parts_friction_ratio(friction)
    return _Chain(profile, parts, e, surface, phase, ratio).run(periods, max_events)


class _Chain:
    """The state of a run of several parts in the arrays of the compiled stepper
    (:mod:`selfalign.solvers.engine.parts`, rows named in :mod:`selfalign.solvers.engine.codes`)."""

    def __init__(self, profile: PiecewiseConstantProfile, parts, e: float, surface, phase: float = 0.0,
                 ratio: float = 1.0):
        n = len(parts)
        self.n, self.profile = n, profile
        zone = isinstance(surface, StopZone)
        self.origin = surface.x_mu if zone else 0.0             # positions are kept relative to x_mu
        c_mu = surface.c_mu if zone else 1.0
        f = np.zeros((C.PARTS_FLOAT_ROWS, n))
        f[C.PX] = np.array([p.x0 for p in parts], dtype=float) - self.origin
        f[C.PV] = [p.v0 for p in parts]
        f[C.PW] = [p.width for p in parts]
        f[C.PM] = [p.mass for p in parts]
        f[C.PK] = [p.friction_factor for p in parts]
        f[C.PSLOPE] = [transition_slope(c_mu, p.width) for p in parts]
        g = np.zeros((C.PARTS_INT_ROWS, n), dtype=np.int64)
        g[C.PKIND] = C.ARC_QUADRATIC
        g[C.PDIRTY] = 1
        g[C.PALL_JOINED] = 1
        speed = profile.velocity_swing + float(np.max(np.abs(f[C.PV])))
        q = np.zeros(C.PARTS_SCALARS)
        q[C.QE], q[C.QC_MU] = e, c_mu
        q[C.QLENGTH] = float(np.max(f[C.PW])) + speed * profile.dt
        q[C.QV_FLOOR] = VELOCITY_ULPS * _EPS * speed
        q[C.QA_TOL] = ACCELERATION_ULPS * _EPS * (profile.max_abs_acceleration
                                                  + ratio * float(np.max(f[C.PK])) * c_mu)
        q[C.QHIGHEST], q[C.QLOWEST] = float(np.max(profile.accels)), float(np.min(profile.accels))
        q[C.QTAU0], q[C.QRATIO] = phase * profile.dt, ratio
        q[C.QMIN_GAP] = math.inf
        c = np.zeros(C.PARTS_COUNTERS, dtype=np.int64)
        c[C.CZONE] = zone
        self.f, self.g, self.q, self.c = f, g, q, c
        self.row = kernel_row("exact", profile, 0.0, {})[1]

    @property
    def x(self) -> np.ndarray:
        """Front positions (relative to the origin, x_mu on a stop zone)."""
        return self.f[C.PX]

    @property
    def v(self) -> np.ndarray:
        """Velocities relative to the table."""
        return self.f[C.PV]

    @property
    def a(self) -> np.ndarray:
        """Accelerations relative to the table at the start of the current arcs."""
        return self.f[C.PA]

    @property
    def min_gap(self) -> float:
        """The smallest gap between neighbours after any event, relative to the positions' scale (inf for
        one part)."""
        return float(self.q[C.QMIN_GAP])

    def run(self, periods: int, max_events: int) -> PartsResult:
        """Run the compiled stepper from the start state over ``periods`` periods (or to rest, the event budget,
        a stall) and return the result."""
        code = call(kernel().parts_run, self.f, self.g, self.q, self.c, self.row, periods, max_events)
        reason, t = Reason(int(code)), float(self.q[C.QT_END])
        message = ""
        if reason is Reason.MAX_EVENTS:
            message = f"max_events = {max_events} reached; raise max_events"
        elif reason is Reason.STALL:
            message = f"more than {STALL_EVENTS} events of zero length in a row at t = {t!r}"
        x, v = self.f[C.PX] + self.origin, self.f[C.PV].copy()
        if not (np.all(np.isfinite(x)) and np.all(np.isfinite(v))):
            reason, message = Reason.NONFINITE, message or f"the state stopped being finite before t = {t!r}"
        c = self.c
        return PartsResult(t_end=t, x_end=x, v_end=v, sticks=int(c[C.CSTICKS]), slips=int(c[C.CSLIPS]),
                           impacts=int(c[C.CIMPACTS]), openings=int(c[C.COPENINGS]), breaks=int(c[C.CBREAKS]),
                           part_sticks=self.g[C.PSTICKS].copy(), part_slips=self.g[C.PSLIPS].copy(),
                           part_impacts=self.g[C.PIMPACTS].copy(), part_openings=self.g[C.POPENINGS].copy(),
                           part_crossings=self.g[C.PCROSSINGS].copy(), part_held=self.g[C.PHELD] == 1,
                           reason=reason, message=message)
