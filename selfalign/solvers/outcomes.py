"""One vocabulary for how every run ends, scalar and batch, for every method.

A run ends for one :class:`Reason`; each reason belongs to one :class:`Status` and has
one message template (:data:`MESSAGES`).  The compiled driver writes reason codes, the
Python results (:class:`~selfalign.solvers.results.Trajectory`,
:class:`~selfalign.solvers.results.BatchResult`) turn them into a status and a message
with :func:`message`.  Nothing here imports numba.
"""

from __future__ import annotations

from enum import IntEnum, StrEnum


class Status(StrEnum):
    """How a run ended.

    One vocabulary for how every run ends, scalar and batch, for every method: a run ends
    for one :class:`Reason`, and each reason belongs to one status.  Status is a
    ``StrEnum``: each member equals its value and reads as it (``str()``, f-strings, a numpy
    array of statuses).  :class:`~selfalign.BatchResult` stores status codes, the index of a
    status in ``list(Status)``.

    Attributes
    ----------
    HORIZON : str
        "horizon": the requested horizon was simulated, or no final outcome within
        max_periods.
    REST : str
        "rest": stuck where mu_bar(x) >= max ``|y''|``: at rest for good.
    ACCUMULATION : str
        "accumulation": stick positions converge geometrically to a limit (Sect. 7.3).
    NEVER_STOPS : str
        "never_stops": keeps moving without coming to rest (periodic or walking).
    ERROR : str
        "error": the solver could not continue; see the message.

    See Also
    --------
    Reason : The detail behind a status.
    Trajectory : Carries the status of one run.
    BatchResult : Carries the status codes of a batch.

    Examples
    --------
    >>> import selfalign as sa
    >>> [status.value for status in sa.Status]
    ['horizon', 'rest', 'accumulation', 'never_stops', 'error']
    >>> sa.Status("rest") is sa.Status.REST, sa.Status.REST == "rest", str(sa.Status.REST)
    (True, True, 'rest')
    >>> list(sa.Status).index(sa.Status.ACCUMULATION)  # its status code in a BatchResult
    2
    """

    HORIZON = "horizon"            #: the requested horizon was simulated, or no final outcome within max_periods
    REST = "rest"                  #: at rest for good, stuck where mu_bar(x) >= max|y''|
    ACCUMULATION = "accumulation"  #: stick positions converge geometrically to a limit
    NEVER_STOPS = "never_stops"    #: keeps moving without coming to rest (periodic or walking)
    ERROR = "error"                #: the solver could not continue; see message


class Reason(IntEnum):
    """Why a run ended: the detail behind its :class:`~selfalign.Status` (codes stored in results).

    Each reason belongs to one status (its ``status`` property) and has one message template
    (``selfalign.solvers.outcomes.MESSAGES``).  The compiled driver writes reason codes,
    and the Python results turn them into a status and a message.

    Attributes
    ----------
    PERIODS : int
        0, HORIZON: until='periods', the requested periods were simulated.
    MAX_PERIODS : int
        1, HORIZON: until='rest', max_periods reached outside the stop zone (or on a uniform
        surface).
    BOUNDED : int
        2, HORIZON: until='rest', max_periods reached after entering the zone, no outcome,
        no cycle.
    FIRST_STICK : int
        3, HORIZON: until='stick', the first stick event.
    REST : int
        4, REST: a stick where mu_bar(x) >= max ``|y''|``.
    ACCUMULATION : int
        5, ACCUMULATION: zone stick positions converge to x_stick_min (eq. 41).
    PERIODIC : int
        6, NEVER_STOPS: the period-boundary state repeats with no net progress.
    WALK_FORWARD : int
        7, NEVER_STOPS: steady forward walk on uniform friction or through the high-friction
        region.
    WALK_BACKWARD : int
        8, NEVER_STOPS: steady backward walk (away from the zone).
    MAX_EVENTS : int
        9, ERROR: the event budget max_events was used up.
    STALL : int
        10, ERROR: events without time advancing (a broken invariant, never a hang).
    NONFINITE : int
        11, ERROR: the arithmetic overflowed (extreme scales); the last finite state is kept.
    SOLVER_FAILED : int
        12, ERROR: the underlying integrator failed (ivp).
    status : Status
        The status the reason belongs to.

    See Also
    --------
    Status : The outcome a reason details.

    Examples
    --------
    >>> import selfalign as sa
    >>> sa.Reason.ACCUMULATION.status
    <Status.ACCUMULATION: 'accumulation'>
    >>> int(sa.Reason.ACCUMULATION), sa.Reason(11).name
    (5, 'NONFINITE')
    >>> [reason.name for reason in sa.Reason if reason.status is sa.Status.ERROR]
    ['MAX_EVENTS', 'STALL', 'NONFINITE', 'SOLVER_FAILED']
    """

    PERIODS = 0        #: HORIZON: until='periods', the requested periods were simulated
    MAX_PERIODS = 1    #: HORIZON: until='rest', max_periods reached outside the stop zone (or on a uniform surface)
    BOUNDED = 2        #: HORIZON: until='rest', max_periods reached after entering the zone, no outcome, no cycle
    FIRST_STICK = 3    #: HORIZON: until='stick', the first stick event
    REST = 4           #: REST: a stick where mu_bar(x) >= max|y''|
    ACCUMULATION = 5   #: ACCUMULATION: zone stick positions converge to x_stick_min (eq. 41)
    PERIODIC = 6       #: NEVER_STOPS: the period-boundary state repeats with no net progress
    WALK_FORWARD = 7   #: NEVER_STOPS: steady forward walk on uniform friction or through the high-friction region
    WALK_BACKWARD = 8  #: NEVER_STOPS: steady backward walk (away from the zone)
    MAX_EVENTS = 9     #: ERROR: the event budget max_events was used up
    STALL = 10         #: ERROR: events without time advancing (a broken invariant, never a hang)
    NONFINITE = 11     #: ERROR: the arithmetic overflowed (extreme scales); the last finite state is kept
    SOLVER_FAILED = 12  #: ERROR: the underlying integrator failed (ivp)

    @property
    def status(self) -> Status:
        return REASON_STATUS[self]


REASON_STATUS = {
    Reason.PERIODS: Status.HORIZON, Reason.MAX_PERIODS: Status.HORIZON, Reason.BOUNDED: Status.HORIZON,
    Reason.FIRST_STICK: Status.HORIZON, Reason.REST: Status.REST, Reason.ACCUMULATION: Status.ACCUMULATION,
    Reason.PERIODIC: Status.NEVER_STOPS, Reason.WALK_FORWARD: Status.NEVER_STOPS,
    Reason.WALK_BACKWARD: Status.NEVER_STOPS, Reason.MAX_EVENTS: Status.ERROR, Reason.STALL: Status.ERROR,
    Reason.NONFINITE: Status.ERROR, Reason.SOLVER_FAILED: Status.ERROR,
}
#: Status codes (int) in the order of :class:`Status`, for arrays of results.
STATUS_CODES = {status: code for code, status in enumerate(Status)}

#: The driver's decision constants (docs/explanation/solvers.md), one set for every method.
#: Longest cycle of period-boundary states the driver looks for, in periods (default).
MAX_CYCLE = 8
#: A near repeat of the period-boundary state: within NEAR_ULPS ulp of the position scale
#: (|x - origin| + w) and of the velocity scale (|v| + the table velocity swing) ...
NEAR_ULPS = 64.0
#: ... while the mass moved more than MOTION_FACTOR times that position tolerance in between
#: (an accumulation's boundary states differ by less and less, but so does its path).
MOTION_FACTOR = 1.0e3
#: Accumulation tolerances below this many ulp of the zone width are raised to it.
ACC_TOL_ULPS = 64.0
#: Successive zero-duration arcs that count as a stalled (Zeno) event loop.  The tie rules
#: make this impossible; the guard turns a broken invariant into ERROR instead of a hang.
STALL_EVENTS = 100
#: ivp: events closer than this many ulp of dt to the one before count as without time advancing
#: (its event times are located to rounding and moved up to 64 ulp on); the compiled steppers
#: count arcs of zero duration.
STALL_ULPS = 128.0

#: Regions of constant or affine friction (a walk's region; bit masks use 1 << region).
LOW, ZONE, HIGH = 0, 1, 2
_WHERE = {-1: "on a uniform surface", LOW: "on the low-friction surface",
          HIGH: "in the high-friction region (c_mu < max|y''|: it walks through)"}

#: One message template per reason; fields are filled by :func:`message`.
MESSAGES = {
    Reason.PERIODS: "simulated {periods} periods ({fast_forward} by steady-state fast-forward)",
    Reason.MAX_PERIODS: "no final outcome within max_periods = {max_periods} periods{away}",
    Reason.BOUNDED: ("no final outcome within max_periods = {max_periods} periods: bounded motion in the stop "
                     "zone that is neither at rest nor periodic with a period <= {max_cycle}; it may still "
                     "come to rest later"),
    Reason.FIRST_STICK: "stopped at the first stick event (until='stick') at x = {x!r}",
    Reason.REST: "at rest for good: stuck at x = {x!r} where {holding} = {mu!r} >= max|y''| = {rest_acc!r}",
    Reason.ACCUMULATION: ("accumulation: stick positions in the transition zone converge to x_stick_min = "
                          "{limit!r} (eq. 41); the last one is {remaining!r} before it (<= accumulation_tol), "
                          "contraction {contraction!r}"),
    Reason.PERIODIC: ("never stops: the state at the period boundary repeats every {cycle} period(s) with no "
                      "net progress (periodic motion at x = {x!r})"),
    Reason.WALK_FORWARD: "never stops: steady motion {where} with net advance {advance!r} per period",
    Reason.WALK_BACKWARD: ("never stops: steady motion {where} with net advance {advance!r} per period"
                           "{never_reaches}"),
    Reason.MAX_EVENTS: "max_events = {max_events} reached at period {period}, tau = {tau!r}; raise max_events",
    Reason.STALL: ("event loop stalled (mode chattering): more than {stall} successive events without time "
                   "advancing by more than {stall_ulps:g} ulp of the period, at x = {x!r}, period {period}, "
                   "tau = {tau!r}"),
    Reason.NONFINITE: ("non-finite state in period {period} (the arithmetic overflows at these scales); the "
                       "state at its start, x = {x!r}, v = {v!r}, is kept"),
    Reason.SOLVER_FAILED: "{detail}",
}


def message(reason: Reason, **fields) -> str:
    """The message of ``reason`` filled with ``fields`` (see :data:`MESSAGES`).

    ``region`` (of a walk: LOW, HIGH, or -1 for a uniform surface) becomes the text
    ``where``; ``zone`` (bool) adds "(never reaches the stop zone)" to a backward walk
    on the low-friction surface and to max_periods without entering.
    """
    reason = Reason(reason)
    region = fields.get("region", -1)
    fields.setdefault("where", _WHERE.get(region, "in one region of constant friction"))
    zone = fields.get("zone", False)
    fields.setdefault("never_reaches", " (never reaches the stop zone)" if zone and region == LOW else "")
    fields.setdefault("away", " (the stop zone was never entered)" if zone else "")
    fields.setdefault("holding", "mu_bar")
    return MESSAGES[reason].format(**fields)


class EventKind(IntEnum):
    """Kinds of events in the event log (the code stored in ``events['kind']``).

    The exact solver and ivp log the events of a run when the scene's
    :class:`~selfalign.Record` asks for them (``events=True``); Moreau
    time-stepping locates no events.

    Attributes
    ----------
    SWITCH : int
        0: the table acceleration jumps (a profile switch time).
    STICK : int
        1: slip ends in stick (relative velocity reaches zero and ``|y''|`` <= mu_bar).
    SLIP : int
        2: stick ends: ``|y''|`` exceeds mu_bar.
    REVERSAL : int
        3: the relative velocity passes through zero and the slip changes direction.
    ZONE : int
        4: the body crosses x_mu or x_mu + w.

    See Also
    --------
    Trajectory : Holds the event log in ``events``.

    Examples
    --------
    One period of the Fig. 18 profile from rest on a uniform surface: the mass sticks
    through the dwell, slips forward from t1 and sticks again after t2.

    >>> import selfalign as sa
    >>> profile = sa.ThreePhaseProfile(dt=1.05, dy=0.084, y2=2.2, y3=0.9)
    >>> traj = sa.simulate(sa.Scene(profile, periods=1, record=sa.Record(events=True)))
    >>> [sa.EventKind(kind).name for kind in traj.events["kind"]]
    ['SWITCH', 'SLIP', 'SWITCH', 'STICK']
    >>> traj.events["tau"].round(6).tolist()
    [0.159637, 0.159637, 0.418129, 0.581388]
    """

    SWITCH = 0    #: the table acceleration jumps (a profile switch time)
    STICK = 1     #: slip ends in stick (relative velocity reaches zero and ``|y''| <= mu_bar``)
    SLIP = 2      #: the stick ends, ``|y''|`` exceeds mu_bar
    REVERSAL = 3  #: the relative velocity passes through zero and the slip changes direction
    ZONE = 4      #: the body crosses x_mu or x_mu + w


#: Mode codes in ``mode`` series and the event log.
BACKWARD_SLIP, STICK, FORWARD_SLIP = -1, 0, 1
#: How each mode code reads.
MODE_NAMES = {BACKWARD_SLIP: "backward slip", STICK: "stick", FORWARD_SLIP: "forward slip"}
