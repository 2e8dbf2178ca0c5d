"""Results of the driver: one trajectory (:class:`Trajectory`) or a batch (:class:`BatchResult`).

Like scipy's ``OdeResult``: the end state, a :class:`~selfalign.solvers.outcomes.Status`
with its :class:`~selfalign.solvers.outcomes.Reason` and a message (the same table for
both, :mod:`selfalign.solvers.outcomes`); dense series, the event log and the arcs only
when they were asked for.
"""

from __future__ import annotations

from dataclasses import dataclass, field

import numpy as np

from .outcomes import MAX_CYCLE, STALL_EVENTS, STALL_ULPS, STATUS_CODES, Reason, Status, message

_REASON_TO_STATUS_CODE = np.array([STATUS_CODES[Reason(r).status] for r in range(len(Reason))], dtype=np.int8)
_STATUSES = list(Status)


@dataclass(eq=False)
class Trajectory:
    """Outcome of :func:`selfalign.simulate`.

    ``x_end``, ``v_end`` are the final state (for an accumulation, the limit); the end
    time is ``period_end * dt + tau_end``.  ``series`` maps the recorded names (``t``,
    ``x``, ``v``, ``y``, ``yd``, ``ydd``, ``friction``, ``mode``) to arrays; ``events`` is
    a record array of :data:`~selfalign.solvers.records.EVENT_DTYPE` (absolute x) or
    None; ``arcs`` the exact solver's arcs (:data:`~selfalign.solvers.records.ARC_DTYPE`,
    absolute x) when asked for; ``stats`` holds ``events``, ``steps``, ``cpu_time``;
    ``info`` outcome details (e.g. ``limit``, ``contraction`` of an accumulation,
    ``net_advance`` of a walk).
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

    ``records`` holds each member's :data:`~selfalign.solvers.records.MEMBER_DTYPE`
    record (positions relative to ``origin``); the properties read it in absolute
    positions.  ``boundaries`` (B, nb): x_mu, x_mu + w, then the levels, absolute (NaN
    on a uniform surface); ``crossings`` (B, nb) of
    :data:`~selfalign.solvers.records.CROSS_DTYPE`: the first time x reached each
    (period -1: never), the velocity there and the stick events at x >= x_mu before it.
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
        """Status codes (int8): the index of each member's status in ``list(Status)``."""
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
    def t_end(self) -> np.ndarray:
        """End times in periods, n_end + tau_end / dt."""
        return self.records["n_end"] + self.records["tau_end"] / self.dt

    @property
    def events(self) -> np.ndarray:
        return self.records["events"]

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
        """The message of member ``i`` (:data:`~selfalign.solvers.outcomes.MESSAGES`)."""
        return outcome_message(self.records[i], float(self.origin[i]), self.options, self.until, self.horizon)


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
