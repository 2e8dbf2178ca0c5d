"""Results of the driver: one trajectory (:class:`Trajectory`) or a batch (:class:`BatchResult`).

Like scipy's ``OdeResult``: the end state, a :class:`~selfalign.solvers.outcomes.Status`
with its :class:`~selfalign.solvers.outcomes.Reason` and a message (the same table for
both, :mod:`selfalign.solvers.outcomes`); dense series, the event log and the arcs only
when they were asked for.
"""

from __future__ import annotations

import warnings
from dataclasses import dataclass, field

import numpy as np

from ..model.friction import coefficient
from .outcomes import MAX_CYCLE, STALL_EVENTS, STALL_ULPS, STATUS_CODES, Reason, Status, message

_REASON_TO_STATUS_CODE = np.array([STATUS_CODES[Reason(r).status] for r in range(len(Reason))], dtype=np.int8)
_STATUSES = list(Status)


@dataclass(eq=False)
class Trajectory:
    """Outcome of :func:`selfalign.simulate`.

    ``x_end``, ``v_end`` are the final state (for an accumulation, the limit); the end
    time is ``period_end * dt + tau_end``.  ``series`` maps the recorded names (``t``,
    ``x``, ``v``, ``y``, ``yd``, ``ydd``, ``friction``, ``mode``) to arrays; ``events`` is
    a record array of ``EVENT_DTYPE`` (absolute x) or
    None; ``arcs`` the exact solver's arcs (``ARC_DTYPE``,
    absolute x) when asked for; ``stats`` holds ``events``, ``steps``, ``cpu_time``;
    ``info`` outcome details (e.g. ``limit``, ``contraction`` of an accumulation,
    ``net_advance`` of a walk).  Like scipy's ``OdeResult``: the end state, a
    :class:`~selfalign.Status` with its :class:`~selfalign.Reason` and a message (the same
    vocabulary as :class:`~selfalign.BatchResult`, ``selfalign.solvers.outcomes``); dense
    series, the event log and the arcs only when the scene's :class:`~selfalign.Record`
    asked for them.  The recorded series also read as attributes (``traj.x``).

    Parameters
    ----------
    x_end, v_end : float
        The final state x, x' (for an accumulation, the limit).
    period_end : int
        Completed periods at the end.
    tau_end : float
        Time within the period at the end.
    status : Status
        How the run ended.
    reason : Reason
        Why it ended.
    message : str or callable
        The outcome message in words; a callable is formatted on first read.
    method : str
        The solver that ran: "exact", "moreau" or "ivp".
    options : dict
        The solver options used (defaults filled in; Moreau adds the step ``h`` used).
    series : dict
        Recorded name -> array (empty without dense output).
    events : numpy.ndarray or None
        The event log (:class:`~selfalign.EventKind` codes in ``kind``).
    arcs : numpy.ndarray or None
        The exact solver's arcs.
    stats : dict
        ``events``, ``steps`` and ``cpu_time`` [s] of the run.
    info : dict
        Outcome details, e.g. ``origin``, ``x_stick_min`` on a stop zone, ``limit``,
        ``contraction`` of an accumulation, ``net_advance`` and ``cycle_periods`` of a
        never-stopping motion.

    Attributes
    ----------
    success : bool
        False when the status is ERROR.
    t : numpy.ndarray
        Times of the samples, period * dt + tau (``series["t"]``; any recorded series brings
        it).
    x : numpy.ndarray
        Position x of the mass relative to the table (``series["x"]``; likewise below).
    v : numpy.ndarray
        Relative velocity x'.
    y : numpy.ndarray
        Table position.
    yd : numpy.ndarray
        Table velocity y'.
    ydd : numpy.ndarray
        Table acceleration y''.
    friction : numpy.ndarray
        Friction force: mu_bar mu(v) mode in slip (mu(v) = 1 but for Stribeck friction),
        -y'' in stick (eq. 5).
    mode : numpy.ndarray
        Mode codes: -1 backward slip, 0 stick, 1 forward slip.

    Raises
    ------
    AttributeError
        On reading a series (``t``, ``x``, ...) that was not recorded; the message says to
        add it to the scene's ``record.series``.

    See Also
    --------
    simulate : Returns a Trajectory.
    BatchResult : The outcome of many runs.

    Examples
    --------
    >>> import selfalign as sa
    >>> profile = sa.ThreePhaseProfile(dt=1.05, dy=0.084, y2=2.2, y3=0.9)
    >>> scene = sa.Scene(profile, periods=3, record=sa.Record(series=("x",), samples_per_period=4))
    >>> traj = sa.simulate(scene)
    >>> traj.status, traj.success, traj.period_end
    (<Status.HORIZON: 'horizon'>, True, 3)
    >>> print(traj.message)
    simulated 3 periods (0 by steady-state fast-forward)
    >>> traj.x[:8].round(4).tolist()
    [0.0, 0.0, 0.0063, 0.0401, 0.0624, 0.0654, 0.0654, 0.0654]
    >>> traj.v
    Traceback (most recent call last):
    ...
    AttributeError: series 'v' was not recorded; add it to the scene's record.series
    """

    x_end: float
    v_end: float
    period_end: int
    tau_end: float
    status: Status
    reason: Reason
    message: str
    method: str
    options: dict = field(default_factory=dict)
    series: dict = field(default_factory=dict)
    events: np.ndarray | None = None
    arcs: np.ndarray | None = None
    stats: dict = field(default_factory=dict)
    info: dict = field(default_factory=dict)

    def __post_init__(self):
        # ``message`` may be given as a callable: it is formatted on first read.
        if callable(self.message):
            self._compose = self.message
            del self.message

    @property
    def success(self) -> bool:
        return self.status is not Status.ERROR

    def __getattr__(self, name):
        if name == "message":
            value = self.__dict__.pop("_compose")()
            self.__dict__["message"] = value
            return value
        # t, x, v, ... read as attributes; missing series raise a clear error.
        series = self.__dict__.get("series", {})
        if name in ("t", "x", "v", "y", "yd", "ydd", "friction", "mode"):
            if name in series:
                return series[name]
            raise AttributeError(f"series {name!r} was not recorded; add it to the scene's record.series")
        raise AttributeError(name)


@dataclass(frozen=True)
class BatchResult:
    """Per-member outcome of :func:`selfalign.simulate_batch` (arrays of shape (B,) unless noted).

    ``records`` holds each member's ``MEMBER_DTYPE``
    record (positions relative to ``origin``); the properties read it in absolute
    positions.  ``boundaries`` (B, nb): x_mu, x_mu + w, then the levels, absolute (NaN
    on a uniform surface); ``crossings`` (B, nb) of
    ``CROSS_DTYPE``: the first time x reached each
    (period -1: never), the velocity there and the stick events at x >= x_mu before it.
    Each member ends with a :class:`~selfalign.Reason` and its :class:`~selfalign.Status`,
    the vocabulary of :class:`~selfalign.Trajectory`.
    ``len(result)`` is the number of members B.  ``t_end`` and ``events`` are deprecated names
    of ``t_end_periods`` and ``event_count``: they warn with a DeprecationWarning.

    Parameters
    ----------
    records : numpy.ndarray
        (B,) member records.
    origin : numpy.ndarray
        (B,) origin of each member's relative positions (x_mu, or x0 on a uniform surface).
    dt : numpy.ndarray
        (B,) period of each member's profile.
    boundaries : numpy.ndarray
        (B, nb) boundaries whose first crossing is recorded.
    crossings : numpy.ndarray
        (B, nb) first crossings of the boundaries.
    method : str
        The solver that ran: "exact" or "moreau".
    options : dict
        The solver options used (Moreau adds the step ``h`` used).
    until : str
        The horizon rule: "periods", "rest", "stick" or "cycle".
    horizon : int
        The horizon in periods (``periods`` or ``max_periods``).

    Attributes
    ----------
    reason : numpy.ndarray
        :class:`~selfalign.Reason` codes (int8).
    status : numpy.ndarray
        Status codes (int8): the index of each member's status in ``list(Status)``.
    x_end : numpy.ndarray
        The final position (for an accumulation, the limit), absolute.
    v_end : numpy.ndarray
        The final velocity x'.
    period_end : numpy.ndarray
        Completed periods at the end.
    tau_end : numpy.ndarray
        The time within the period at the end.
    t_end_periods : numpy.ndarray
        End times in periods, period_end + tau_end / dt (the end time t_end of a result file
        or of the CLI divided by the period dt).
    event_count : numpy.ndarray
        Number of events of each run.
    stick_events : numpy.ndarray
        Number of stick events of each run.
    zone_sticks : numpy.ndarray
        Stick events at x >= x_mu.
    first_stick_x : numpy.ndarray
        Position of the first stick at x >= x_mu (NaN if none).
    first_stick_time : numpy.ndarray
        Time of the first stick at x >= x_mu, in periods (NaN if none).
    contraction : numpy.ndarray
        Ratio of the last two zone-stick increments of an accumulation (NaN otherwise).
    advance : numpy.ndarray
        Net advance per period of a walk or periodic motion (NaN otherwise).
    cycle : numpy.ndarray
        Periods per repeat of a never-stopping motion (0 otherwise).
    x_max : numpy.ndarray
        The largest x reached.

    See Also
    --------
    simulate_batch : Returns a BatchResult.
    Trajectory : The outcome of one run.

    Examples
    --------
    Four entries of the Fig. 18 profile into a stop zone:

    >>> import numpy as np
    >>> import selfalign as sa
    >>> profile = sa.ThreePhaseProfile(dt=1.05, dy=0.084, y2=2.2, y3=0.9)
    >>> zone = sa.StopZone(x_mu=0.5, w=0.05, c_mu=2.5)
    >>> batch = sa.simulate_batch(profile, np.linspace(-0.06, 0.0, 4), surface=zone, max_periods=1000)
    >>> len(batch), batch.count()
    (4, {'horizon': 0, 'rest': 1, 'accumulation': 3, 'never_stops': 0, 'error': 0})
    >>> [status.value for status in batch.statuses()]
    ['accumulation', 'accumulation', 'rest', 'accumulation']
    >>> batch.x_end.round(6).tolist(), batch.zone_sticks.tolist()
    ([0.54, 0.54, 0.540866, 0.54], [14, 13, 2, 14])
    >>> batch.crossing_time(0).round(3).tolist()  # first arrival at x_mu, in periods
    [8.388, 8.311, 7.498, 7.405]
    >>> print(batch.message(0))
    accumulation: stick positions in the transition zone converge to x_stick_min = 0.54 (eq. 41); ...
    """

    records: np.ndarray
    origin: np.ndarray
    dt: np.ndarray
    boundaries: np.ndarray
    crossings: np.ndarray
    method: str
    options: dict
    until: str
    horizon: int

    def __len__(self) -> int:
        return self.records.shape[0]

    @property
    def reason(self) -> np.ndarray:
        """:class:`~selfalign.solvers.outcomes.Reason` codes (int8)."""
        return self.records["reason"]

    @property
    def status(self) -> np.ndarray:
        """The status code of each member (int8), the index of its status in ``list(Status)``."""
        return _REASON_TO_STATUS_CODE[self.records["reason"]]

    @property
    def x_end(self) -> np.ndarray:
        return self.origin + self.records["xi"]

    @property
    def v_end(self) -> np.ndarray:
        return self.records["v"]

    @property
    def period_end(self) -> np.ndarray:
        return self.records["n_end"]

    @property
    def tau_end(self) -> np.ndarray:
        return self.records["tau_end"]

    @property
    def t_end_periods(self) -> np.ndarray:
        """End times in periods, period_end + tau_end / dt (the end time t_end of a result file or
        of the CLI, period_end * dt + tau_end, divided by the period dt)."""
        return self.records["n_end"] + self.records["tau_end"] / self.dt

    @property
    def event_count(self) -> np.ndarray:
        """Number of events of each member (a count; ``Trajectory.events`` is the event log)."""
        return self.records["events"]

    @property
    def t_end(self) -> np.ndarray:
        """Deprecated name of ``t_end_periods`` (it is in periods, not time)."""
        _renamed("t_end", "t_end_periods")
        return self.t_end_periods

    @property
    def events(self) -> np.ndarray:
        """Deprecated name of ``event_count`` (a count, not an event log)."""
        _renamed("events", "event_count")
        return self.event_count

    @property
    def stick_events(self) -> np.ndarray:
        return self.records["sticks"]

    @property
    def zone_sticks(self) -> np.ndarray:
        """Stick events at x >= x_mu."""
        return self.records["zone_sticks"]

    @property
    def first_stick_x(self) -> np.ndarray:
        """Position of the first stick at x >= x_mu (NaN if none)."""
        return self.origin + self.records["first_stick_xi"]

    @property
    def first_stick_time(self) -> np.ndarray:
        """Time of the first stick at x >= x_mu, in periods (NaN if none)."""
        r = self.records
        return np.where(r["first_stick_n"] >= 0, r["first_stick_n"] + r["first_stick_tau"] / self.dt, np.nan)

    @property
    def contraction(self) -> np.ndarray:
        """Ratio of the last two zone-stick increments of an accumulation (NaN otherwise)."""
        return self.records["contraction"]

    @property
    def advance(self) -> np.ndarray:
        """Net advance per period of a walk or periodic motion (NaN otherwise)."""
        return self.records["advance"]

    @property
    def cycle(self) -> np.ndarray:
        """Periods per repeat of a never-stopping motion (0 otherwise)."""
        return self.records["cycle"]

    @property
    def x_max(self) -> np.ndarray:
        """The largest x reached."""
        return self.origin + self.records["xi_max"]

    def crossing_time(self, column: int) -> np.ndarray:
        """Time (in periods) of the first crossing of boundary ``column`` (NaN if never)."""
        c = self.crossings[:, column]
        return np.where(c["period"] >= 0, c["period"] + c["tau"] / self.dt, np.nan)

    def statuses(self) -> list[Status]:
        """The status of every member."""
        return [_STATUSES[code] for code in self.status.tolist()]

    def count(self) -> dict[str, int]:
        """Number of members per status value."""
        codes = self.status
        return {status.value: int(np.count_nonzero(codes == i)) for i, status in enumerate(_STATUSES)}

    def message(self, i: int) -> str:
        """The message of member ``i`` (``MESSAGES``); a rest names mu_bar at the end position (eqs. 7-9)."""
        rec = self.records[i]
        mu = coefficient(float(rec["xi"]), float(rec["w"]), float(rec["c_mu"])) if rec["zone"] else 1.0
        return outcome_message(rec, float(self.origin[i]), self.options, self.until, self.horizon, mu,
                               ratio=float(rec["static_ratio"]))


def _renamed(old: str, new: str) -> None:
    warnings.warn(f"BatchResult.{old} is deprecated; use BatchResult.{new}", DeprecationWarning, stacklevel=3)


def outcome_message(rec, origin: float, options: dict, until: str, horizon: int, mu: float | None = None,
                    detail: str = "", ratio: float = 1.0) -> str:
    """The message of one member record (a record or a dict of its fields; shared by
    :class:`Trajectory` and :class:`BatchResult`).  ``mu``: mu_bar at the end position; under
    static friction (``ratio`` r = mu_s/mu_k > 1) a rest is held by r mu_bar, which is reported."""
    reason = Reason(int(rec["reason"]))
    x = origin + float(rec["xi"])
    fields = {"x": x, "v": float(rec["v"]), "period": int(rec["n_end"]), "tau": float(rec["tau_end"]),
              "periods": int(rec["n_end"]), "fast_forward": int(rec["fast_forward"]),
              "max_periods": horizon, "max_cycle": MAX_CYCLE, "max_events": options.get("max_events"),
              "stall": STALL_EVENTS, "stall_ulps": STALL_ULPS, "rest_acc": float(rec["rest_acc"]),
              "mu": mu if mu is None or ratio == 1.0 else ratio * mu,
              "holding": "mu_bar" if ratio == 1.0 else f"mu_s = r mu_bar (r = mu_s/mu_k = {ratio!r})",
              "limit": origin + float(rec["xs"]), "remaining": float(rec["xs"] - rec["last_stick"]),
              "contraction": None if np.isnan(rec["contraction"]) else float(rec["contraction"]),
              "cycle": int(rec["cycle"]), "advance": float(rec["advance"]),
              "region": int(rec["cycle_region"]) if rec["zone"] else -1, "zone": bool(rec["zone"]), "detail": detail}
    return message(reason, **fields)
