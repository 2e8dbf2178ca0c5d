"""Batched exact event-driven solver: many trajectories advanced together with numpy.

Solves x'' + y''(t) in -mu_bar(x) Sign(x') (eqs. 6, 38) for a batch of members,
each with its own piecewise-constant table acceleration (breaks, accels), its
own surface (uniform, or a stop zone x_mu, w, c_mu of eqs. 7-9) and its own
start state.  Every loop iteration advances every active member by exactly one
event with closed-form arcs:

* mu_bar constant (uniform surface, x <= x_mu, x >= x_mu + w): quadratic arcs;
* forward slip in the transition zone: harmonic arc of eq. (42), omega = sqrt(b1),
  centre -(y'' + 1) / b1 (relative to x_mu);
* backward slip in the transition zone: hyperbolic arc x'' = b1 (x - x_mu) + 1 - y''.

Events are the ends of the acceleration pieces, the zeros of the relative
velocity (stick or reversal) and the crossings of the boundaries x_mu,
x_mu + w and of optional user "levels" (whose first crossing times are
recorded).  Positions between events come from :func:`selfalign.model.arcs.step`
(with ``xp=numpy``); the event times and event states are array versions
written here, without cancellation: stop positions x + (R - A) with
R - A = B^2 / (R + A) when needed, crossing velocities from the conserved
energy of the arc, crossing times from angle (atan2) or logarithm
differences.  Positions are relative to x_mu (the start position on a uniform
surface), time is (period index n, tau); period boundaries are at tau = 0.

Outcomes (the same decisions as the single-trajectory exact solver; DESIGN,
"Solver contract"), decided exactly, never by a timeout where a decision exists:

* REST: a stick at x with mu_bar(x) >= max|y''|.
* ACCUMULATION: a stick in the transition zone at x > the previous zone stick
  with x_stick_min - x <= max(accumulation_tol, 64 eps w) (eq. 41); x_end is
  the limit x_stick_min, ``contraction`` the ratio of the last two increments.
* NEVER_STOPS with a reason: PERIODIC (x and v at a period boundary equal
  those of p <= HISTORY periods before up to ``periodic_tol`` -- relative to
  |x - x_mu| + w and to |v| + dt max|y''| -- while the mass travelled more
  than 1000 times that position tolerance in between: the motion repeats
  forever; an accumulation, whose increments shrink to nothing, never
  matches), WALK_FORWARD / WALK_BACKWARD (a whole period in a region of
  constant mu_bar -- a uniform surface, beyond x_mu + w or before x_mu -- and
  v at the boundary repeats to ``periodic_tol``: the motion repeats with a
  net advance away from the zone, or through the high-friction region).
  A tolerance rather than bit-for-bit equality: a converged periodic orbit
  with slip across the period boundary can drift by a few ulp per period
  forever instead of repeating exactly (seen at (y2'', y3'') = (1.719, 2.421)).
* HORIZON: ``until="periods"`` reached, ``until="stick"`` at the first stick,
  or max_periods reached without an outcome: reason BOUNDED if the mass had
  entered the zone (bounded motion that is not periodic with period
  <= HISTORY -- e.g. the chaotic stick-slip found for y3'' > y2'' -- which may
  still come to rest later), else MAX_PERIODS.
* ERROR: more than max_events events for a member.

These are the decisions of :mod:`selfalign.solvers.exact` (period-boundary
cycles of up to HISTORY = 8 periods, the same accumulation rule), so both
solvers classify a run alike; a periodic motion may be detected some periods
apart (the exact solver compares states bit for bit at the start phase, this
solver to periodic_tol at tau = 0).

Memory is O(batch size): only end states and a few per-member counters are kept.
"""

from __future__ import annotations

from dataclasses import dataclass
from enum import IntEnum

import numpy as np

from ..model.profiles import PiecewiseConstantProfile, three_phase_times
from .outcomes import Status
from ..model import arcs

#: Number of earlier period-boundary states compared in the periodicity test.
HISTORY = 8
#: Accumulation tolerances below this many ulp of the zone width are raised to it.
TOL_ULPS = 64.0
#: A periodic match needs the mass to have moved this many position tolerances in
#: between (an accumulation's boundary states differ by less and less, but so does its path).
MOTION_FACTOR = 1.0e3


class Outcome(IntEnum):
    """Status codes of :class:`BatchResult` (``Outcome(code).status`` gives the Status)."""

    HORIZON = 0
    REST = 1
    ACCUMULATION = 2
    NEVER_STOPS = 3
    ERROR = 4

    @property
    def status(self) -> Status:
        return Status[self.name]


class Reason(IntEnum):
    """Detail codes of :class:`BatchResult` (``reason``)."""

    NONE = 0
    PERIODIC = 1       #: NEVER_STOPS: the period-boundary state repeats
    WALK_FORWARD = 2   #: NEVER_STOPS: steady walk beyond the zone (c_mu < max|y''|) or on a uniform surface
    WALK_BACKWARD = 3  #: NEVER_STOPS: steady walk away from the zone, backwards
    BOUNDED = 4        #: HORIZON: max_periods reached after entering the zone, no outcome, no cycle
    MAX_PERIODS = 5    #: HORIZON: max_periods reached before the zone was entered
    PERIODS = 6        #: HORIZON: until="periods" done
    STICK = 7          #: HORIZON or REST: until="stick", the first stick event
    MAX_EVENTS = 8     #: ERROR


@dataclass(frozen=True)
class BatchResult:
    """Per-member outcome of :func:`solve_batch` (all arrays of shape (B,) unless noted).

    ``x_end``, ``v_end``: final state (absolute x; the limit for an accumulation);
    end time ``period_end * dt + tau_end``.  ``status``: :class:`Outcome` codes,
    ``reason``: :class:`Reason` codes.  ``events``: events processed;
    ``stick_events``: stick events; ``zone_sticks``: stick events at x >= x_mu;
    ``first_stick_x``, ``first_stick_period``, ``first_stick_tau``: the first
    stick at x >= x_mu (NaN / -1 if none).  ``contraction``: ratio of the last
    two stick increments for an accumulation (NaN otherwise).  ``advance``:
    net advance per period of a walk (NaN otherwise); ``cycle``: period of a
    periodic never-stop (0 otherwise).  ``x_max``: largest x reached.
    ``boundaries`` (B, nb): absolute positions x_mu, x_mu + w, then the levels
    (NaN for a uniform surface's first two); ``cross_period``, ``cross_tau``,
    ``cross_v`` (B, nb): the first time and velocity at which x reached each
    (-1 / NaN if never), ``cross_sticks`` (B, nb): stick events at x >= x_mu
    before that time.  Column 0 is the first entry into the zone.
    """

    x_end: np.ndarray
    v_end: np.ndarray
    status: np.ndarray
    reason: np.ndarray
    period_end: np.ndarray
    tau_end: np.ndarray
    events: np.ndarray
    stick_events: np.ndarray
    zone_sticks: np.ndarray
    first_stick_x: np.ndarray
    first_stick_period: np.ndarray
    first_stick_tau: np.ndarray
    contraction: np.ndarray
    advance: np.ndarray
    cycle: np.ndarray
    x_max: np.ndarray
    boundaries: np.ndarray
    cross_period: np.ndarray
    cross_tau: np.ndarray
    cross_v: np.ndarray
    cross_sticks: np.ndarray

    def statuses(self) -> list[Status]:
        """The status of every member as :class:`selfalign.Status`."""
        return [Outcome(int(c)).status for c in self.status]

    def count(self) -> dict[str, int]:
        """Number of members per status name."""
        return {o.status.value: int(np.count_nonzero(self.status == o)) for o in Outcome}


def three_phase_pieces(dt, dy, y2, y3) -> tuple[np.ndarray, np.ndarray]:
    """(breaks (..., 4), accels (..., 3)) of three-phase profiles, vectorised (Sect. 4.4.3).

    Zero-length pieces (t1 = 0 on the case-0 boundary) are kept; the solver
    passes them in zero time.  ValueError if any profile is non-physical (case 0).
    """
    times = three_phase_times(dt, dy, y2, y3)
    if not np.all(times.feasible):
        raise ValueError("three-phase profiles: every (dt, dy, y2, y3) must be physical (q <= 1); "
                         f"{int(np.size(times.feasible) - np.count_nonzero(times.feasible))} are case 0")
    zero = np.zeros_like(times.t1)
    breaks = np.stack([zero, times.t1, times.t2, times.t3], axis=-1)
    y2b, y3b = np.broadcast_arrays(np.asarray(y2, dtype=float), np.asarray(y3, dtype=float))
    y2b = np.broadcast_to(y2b, zero.shape)
    y3b = np.broadcast_to(y3b, zero.shape)
    accels = np.stack([zero, -y2b, y3b], axis=-1)
    return breaks, accels


def profile_pieces(profile: PiecewiseConstantProfile) -> tuple[np.ndarray, np.ndarray]:
    """(breaks, accels) of one piecewise-constant profile."""
    if not isinstance(profile, PiecewiseConstantProfile):
        raise ValueError(f"the batched solver needs a piecewise-constant profile, got {type(profile).__name__}")
    return profile.breaks.copy(), profile.accels.copy()


def _as_member_array(name, value, size, dtype=float):
    arr = np.asarray(value, dtype=dtype)
    try:
        arr = np.broadcast_to(arr, (size,))
    except ValueError:
        raise ValueError(f"{name} must be a scalar or have one entry per member ({size}), "
                         f"got shape {arr.shape}") from None
    return np.array(arr)


def solve_batch(breaks, accels, x0, v0=0.0, tau0=0.0, *, x_mu=None, w=None, c_mu=None, levels=None,
                until: str = "rest", periods: int | None = None, max_periods: int = 10_000,
                accumulation_tol: float = 1e-12, periodic_tol: float = 1e-12,
                max_events: int = 1_000_000) -> BatchResult:
    """Advance a batch of trajectories to their outcome (see the module docstring).

    ``breaks`` (B, m+1) / ``accels`` (B, m) — or (m+1,) / (m,) shared by all —
    give each member's piecewise-constant y'' (breaks from 0 to the period dt;
    zero-length pieces allowed).  ``x0``, ``v0`` hold at phase time ``tau0``
    in [0, dt).  ``x_mu``, ``w``, ``c_mu``: the stop zone (scalars or per
    member); ``x_mu=None`` means a uniform surface for all members, and
    ``c_mu == 1`` a uniform surface for that member.  ``levels`` (B, L) or
    (L,): absolute positions whose first crossing is recorded.
    ``until``: "rest" (run to an outcome, at most ``max_periods`` periods),
    "periods" (stop at t = tau0 + periods dt, as the exact solver's horizon; a mass
    at rest for good is reported HORIZON there, no accumulation shortcut) or
    "stick" (stop at the first stick event).
    """
    breaks = np.asarray(breaks, dtype=float)
    accels = np.asarray(accels, dtype=float)
    member_shapes = [breaks.shape[:-1], accels.shape[:-1]] + [np.shape(a) for a in (x0, v0, tau0, x_mu, w, c_mu)
                                                              if a is not None]
    if breaks.ndim == 1:
        breaks = breaks[None, :]
    if accels.ndim == 1:
        accels = accels[None, :]
    if breaks.ndim != 2 or accels.ndim != 2 or breaks.shape[1] != accels.shape[1] + 1 or accels.shape[1] < 1:
        raise ValueError("breaks must be (B, m+1) and accels (B, m) with m >= 1 (or 1-D, shared)")
    try:
        shape = np.broadcast_shapes(*member_shapes)
    except ValueError:
        raise ValueError(f"per-member inputs must be scalars or 1-D of one common length; got shapes "
                         f"{member_shapes}") from None
    if len(shape) > 1:
        raise ValueError(f"per-member inputs must be scalars or 1-D, got shape {shape}")
    size = shape[0] if shape else 1
    breaks = np.array(np.broadcast_to(breaks, (size, breaks.shape[1])))
    accels = np.array(np.broadcast_to(accels, (size, accels.shape[1])))
    if not (np.all(np.isfinite(breaks)) and np.all(np.isfinite(accels))):
        raise ValueError("breaks and accels must be finite")
    if np.any(breaks[:, 0] != 0.0) or np.any(np.diff(breaks, axis=1) < 0) or np.any(breaks[:, -1] <= 0):
        raise ValueError("breaks must start at 0, be non-decreasing and end at the period dt > 0")
    x0 = _as_member_array("x0", x0, size)
    v0 = _as_member_array("v0", v0, size)
    tau0 = _as_member_array("tau0", tau0, size)
    for name, arr in (("x0", x0), ("v0", v0), ("tau0", tau0)):
        if not np.all(np.isfinite(arr)):
            raise ValueError(f"{name} must be finite")
    if np.any((tau0 < 0) | (tau0 >= breaks[:, -1])):
        raise ValueError("tau0 must lie in [0, dt) (time within the period)")
    if until not in ("rest", "periods", "stick"):
        raise ValueError(f"until must be 'rest', 'periods' or 'stick', got {until!r}")
    if until == "periods" and (periods is None or int(periods) < 1):
        raise ValueError(f"until='periods' needs periods >= 1, got {periods!r}")
    if int(max_periods) < 1 or int(max_events) < 1:
        raise ValueError("max_periods and max_events must be >= 1")
    for name, tol in (("accumulation_tol", accumulation_tol), ("periodic_tol", periodic_tol)):
        if not (np.isfinite(tol) and tol > 0):
            raise ValueError(f"{name} must be finite and > 0, got {tol!r}")
    if x_mu is None:
        if w is not None or c_mu is not None:
            raise ValueError("w and c_mu need x_mu (a stop zone); leave all three None for a uniform surface")
        uniform = np.ones(size, dtype=bool)
        x_ref, w_arr, c_arr = x0.copy(), np.ones(size), np.ones(size)
    else:
        x_ref = _as_member_array("x_mu", x_mu, size)
        w_arr = _as_member_array("w", w, size)
        c_arr = _as_member_array("c_mu", c_mu, size)
        if not (np.all(np.isfinite(x_ref)) and np.all(np.isfinite(w_arr) & (w_arr > 0))
                and np.all(np.isfinite(c_arr) & (c_arr >= 1.0))):
            raise ValueError("stop zone: x_mu must be finite, w finite and > 0, c_mu finite and >= 1")
        uniform = c_arr == 1.0
    if levels is None:
        lev = np.empty((size, 0))
    else:
        lev = np.asarray(levels, dtype=float)
        lev = np.array(np.broadcast_to(lev if lev.ndim == 2 else lev[None, :], (size, lev.shape[-1])))
        if np.any(np.isnan(lev)):
            raise ValueError("levels must not be NaN (+inf: never reached)")
    solver = _Batch(breaks, accels, x0, v0, tau0, x_ref, w_arr, c_arr, uniform, lev, until,
                    int(periods) if periods is not None else 0, int(max_periods), float(accumulation_tol),
                    float(periodic_tol), int(max_events))
    return solver.run()


class _Batch:
    """State and event loop of :func:`solve_batch` (arrays over all members)."""

    def __init__(self, breaks, accels, x0, v0, tau0, x_ref, w, c_mu, uniform, levels, until, periods,
                 max_periods, acc_tol, per_tol, max_events):
        size, m = accels.shape
        self.size, self.m = size, m
        self.brk, self.acc = breaks, accels
        self.absacc = np.abs(accels)
        self.amax = self.absacc.max(axis=1)
        self.dt = breaks[:, -1]
        self.x_ref, self.w, self.c_mu, self.uniform = x_ref, w, c_mu, uniform
        self.b1 = np.where(uniform, 0.0, (c_mu - 1.0) / w)
        self.omega = np.sqrt(self.b1)
        with np.errstate(divide="ignore", invalid="ignore"):
            # x_stick_min - x_mu, eq. (41); +inf where permanent stick is impossible in the zone.
            xs = np.where(self.amax > c_mu, np.inf, w * (self.amax - 1.0) / (c_mu - 1.0))
        self.xs = np.where(uniform, np.inf, xs)
        nanz = np.where(uniform, np.nan, 0.0)
        self.bnd = np.column_stack([nanz, nanz + w, levels - x_ref[:, None]])
        self.until, self.periods, self.max_periods = until, periods, max_periods
        self.acc_tol = np.maximum(acc_tol, TOL_ULPS * np.finfo(float).eps * w)
        self.max_events = max_events
        self.per_tol = per_tol
        self.v_scale = self.dt * self.amax

        self.t_stop = tau0.copy()  # until="periods" ends at (periods, tau0): N whole periods
        self.xr = x0 - x_ref
        self.v = v0.copy()
        self.k = np.clip(np.sum(breaks[:, 1:] <= tau0[:, None], axis=1), 0, m - 1)
        self.tau = tau0.copy()
        self.n = np.zeros(size, dtype=np.int64)
        self.mode = np.sign(v0).astype(np.int8)
        self.alive = np.ones(size, dtype=bool)
        self.status = np.zeros(size, dtype=np.int8)
        self.reason = np.zeros(size, dtype=np.int8)
        self.x_end = np.full(size, np.nan)
        self.v_end = np.full(size, np.nan)
        self.period_end = np.zeros(size, dtype=np.int64)
        self.tau_end = np.full(size, np.nan)
        self.events = np.zeros(size, dtype=np.int64)
        self.sticks = np.zeros(size, dtype=np.int64)
        self.zsticks = np.zeros(size, dtype=np.int64)
        self.h1 = np.full(size, np.nan)  # last stick position in the transition zone
        self.h2 = np.full(size, np.nan)  # the one before
        self.first_x = np.full(size, np.nan)
        self.first_n = np.full(size, -1, dtype=np.int64)
        self.first_tau = np.full(size, np.nan)
        self.contraction = np.full(size, np.nan)
        self.advance = np.full(size, np.nan)
        self.cycle = np.zeros(size, dtype=np.int16)
        self.x_max = self.xr.copy()
        self.hist_x = np.zeros((size, HISTORY))
        self.hist_v = np.zeros((size, HISTORY))
        self.path = np.zeros(size)  # distance travelled
        self.hist_path = np.zeros((size, HISTORY))
        self.hist_count = np.zeros(size, dtype=np.int64)
        self.moved_region = np.zeros(size, dtype=bool)  # crossed x_mu or x_mu + w this period
        nb = self.bnd.shape[1]
        self.reached = self.xr[:, None] >= self.bnd
        self.cross_n = np.where(self.reached, 0, -1).astype(np.int64)
        self.cross_tau = np.where(self.reached, tau0[:, None], np.nan)
        self.cross_v = np.where(self.reached, v0[:, None], np.nan) + np.zeros((size, nb))
        self.cross_sticks = np.where(self.reached, 0, -1).astype(np.int64)

        # Start at v = 0: stick (a possible REST) or slip in the direction -sign(y'').
        still = np.flatnonzero(self.mode == 0)
        if still.size:
            self._decide_at_rest(still, start=True)

    # ---------------------------------------------------------------- helpers
    def _mu(self, ids, xr):
        """mu_bar(x) of eqs. (7)-(9) for members ``ids`` at relative positions ``xr``."""
        w = self.w[ids]
        mu = np.where(xr <= 0.0, 1.0, np.where(xr >= w, self.c_mu[ids], 1.0 + self.b1[ids] * xr))
        return np.where(self.uniform[ids], 1.0, mu)

    def _finish(self, ids, outcome, reason, x_rel, v, tau):
        self.alive[ids] = False
        self.status[ids] = outcome
        self.reason[ids] = reason
        self.x_end[ids] = x_rel
        self.v_end[ids] = v
        self.period_end[ids] = self.n[ids]
        self.tau_end[ids] = tau

    def _finish_horizon(self, ids, v):
        """until="periods": the state at t = (periods, tau0) is x, v."""
        self._finish(ids, Outcome.HORIZON, Reason.PERIODS, self.xr[ids], v, self.t_stop[ids])
        self.period_end[ids] = self.periods

    def _decide_at_rest(self, ids, start=False):
        """v = 0 at the current piece: slip (direction -sign(y'')) or stick (eq. 6)."""
        xr = self.xr[ids]
        a = self.acc[ids, self.k[ids]]
        mu = self._mu(ids, xr)
        fwd = -a - mu > 0.0
        bwd = -a + mu < 0.0
        self.v[ids] = 0.0
        self.mode[ids] = np.where(fwd, 1, np.where(bwd, -1, 0))
        stuck = ids[~fwd & ~bwd]
        if stuck.size:
            self._on_stick(stuck, mu[~fwd & ~bwd], start)

    def _on_stick(self, ids, mu, start):
        xr = self.xr[ids]
        tau = self.tau[ids]
        rest = mu >= self.amax[ids]
        zone = (xr >= 0.0) & ~self.uniform[ids]
        if not start:
            self.sticks[ids] += 1
            self.zsticks[ids] += zone
            first = zone & (self.first_n[ids] < 0)
            fi = ids[first]
            self.first_x[fi] = xr[first]
            self.first_n[fi] = self.n[fi]
            self.first_tau[fi] = tau[first]
        if self.until == "periods":  # a mass at rest for good keeps its state up to the horizon
            if rest.any():
                self._finish_horizon(ids[rest], 0.0)
            return
        done = rest.copy()
        if rest.any():
            reason = Reason.STICK if self.until == "stick" and not start else Reason.NONE
            self._finish(ids[rest], Outcome.REST, reason, xr[rest], 0.0, tau[rest])
        if start:
            return
        h1, h2 = self.h1[ids], self.h2[ids]
        acc = ~rest & zone & (xr <= self.w[ids]) & (self.xs[ids] - xr <= self.acc_tol[ids]) & (xr > h1)
        if acc.any():
            ai = ids[acc]
            self.contraction[ai] = (xr[acc] - h1[acc]) / (h1[acc] - h2[acc])
            self._finish(ai, Outcome.ACCUMULATION, Reason.NONE, self.xs[ai], 0.0, tau[acc])
            done |= acc
        if self.until == "stick" and (~done).any():
            rest_ids = ids[~done]
            self._finish(rest_ids, Outcome.HORIZON, Reason.STICK, xr[~done], 0.0, tau[~done])
        zi = ids[zone & (xr <= self.w[ids])]
        self.h2[zi] = self.h1[zi]
        self.h1[zi] = self.xr[zi]

    def _period_boundary(self, ids):
        """Checks at t = n dt (state xr, v at tau = 0): horizon, periodicity, walking, budget."""
        if self.until == "periods":  # the state at the horizon is wanted: no early never-stop verdicts
            done = (self.n[ids] >= self.periods) & (self.t_stop[ids] == 0.0)
            if done.any():
                self._finish_horizon(ids[done], self.v[ids[done]])
            return
        xr, v = self.xr[ids], self.v[ids]
        count = self.hist_count[ids]
        # Slot j of the ring buffer holds the boundary state lag periods ago.
        lag = (count[:, None] - 1 - np.arange(HISTORY)[None, :]) % HISTORY + 1
        tol_x = self.per_tol * (np.abs(xr) + np.where(self.uniform[ids], 0.0, self.w[ids]))
        tol_v = self.per_tol * (np.abs(v) + self.v_scale[ids])
        match = ((lag <= count[:, None]) & (np.abs(self.hist_x[ids] - xr[:, None]) <= tol_x[:, None])
                 & (np.abs(self.hist_v[ids] - v[:, None]) <= tol_v[:, None])
                 & (self.path[ids, None] - self.hist_path[ids] > MOTION_FACTOR * tol_x[:, None]))
        periodic = match.any(axis=1)
        cycle = np.where(match, lag, HISTORY + 1).min(axis=1)  # the shortest period
        if periodic.any():
            pi = ids[periodic]
            self.cycle[pi] = cycle[periodic]
            self._finish(pi, Outcome.NEVER_STOPS, Reason.PERIODIC, xr[periodic], v[periodic], 0.0)
        j = (count - 1) % HISTORY
        prev_x, prev_v = self.hist_x[ids, j], self.hist_v[ids, j]
        steady = ~periodic & (count >= 1) & ~self.moved_region[ids] & (np.abs(v - prev_v) <= tol_v)
        uni = self.uniform[ids]
        beyond = ~uni & (xr > self.w[ids])
        before = uni | (xr < 0.0)
        adv = xr - prev_x
        walk_f = steady & (beyond | uni) & (adv > 0.0)
        walk_b = steady & before & (adv < 0.0)
        for mask, reason in ((walk_f, Reason.WALK_FORWARD), (walk_b, Reason.WALK_BACKWARD)):
            if mask.any():
                wi = ids[mask]
                self.advance[wi] = adv[mask]
                self._finish(wi, Outcome.NEVER_STOPS, reason, xr[mask], v[mask], 0.0)
        left = ~periodic & ~walk_f & ~walk_b
        budget = left & (self.n[ids] >= self.max_periods)
        if budget.any():
            bi = ids[budget]
            entered = self.reached[bi, 0] if self.bnd.shape[1] else np.zeros(bi.size, dtype=bool)
            for mask, reason in ((entered, Reason.BOUNDED), (~entered, Reason.MAX_PERIODS)):
                if mask.any():
                    self._finish(bi[mask], Outcome.HORIZON, reason, self.xr[bi[mask]], self.v[bi[mask]], 0.0)
        self._push_history(ids)

    def _push_history(self, ids):
        slot = self.hist_count[ids] % HISTORY
        self.hist_x[ids, slot] = self.xr[ids]
        self.hist_v[ids, slot] = self.v[ids]
        self.hist_path[ids, slot] = self.path[ids]
        self.hist_count[ids] += 1
        self.moved_region[ids] = False

    def _record_crossings(self, ids):
        if self.bnd.shape[1] == 0:
            return
        new = (self.xr[ids, None] >= self.bnd[ids]) & ~self.reached[ids]
        if not new.any():
            return
        rows, cols = np.nonzero(new)
        g = ids[rows]
        self.reached[g, cols] = True
        self.cross_n[g, cols] = self.n[g]
        self.cross_tau[g, cols] = self.tau[g]
        self.cross_v[g, cols] = self.v[g]
        self.cross_sticks[g, cols] = self.zsticks[g]

    # ---------------------------------------------------------------- steps
    def _unstick(self, ids):
        """Stuck members: jump to the next piece with |y''| > mu_bar(x), where slip starts."""
        m = self.m
        xr = self.xr[ids]
        mu = self._mu(ids, xr)
        k = self.k[ids]
        slips = self.absacc[ids] > mu[:, None]
        order = (np.arange(m)[None, :] - k[:, None] - 1) % m
        first = np.where(slips, order, m).min(axis=1)
        bad = first >= m  # cannot happen: a stick with mu >= max|y''| is REST
        if bad.any():
            self._finish(ids[bad], Outcome.ERROR, Reason.NONE, xr[bad], 0.0, self.tau[ids[bad]])
            ids, k, first = ids[~bad], k[~bad], first[~bad]
        j = k + 1 + first
        wrap = j >= m
        j = j % m
        self.events[ids] += 1
        if self.until == "periods":  # the horizon comes before the next slip
            n_next = self.n[ids] + wrap
            over = (n_next > self.periods) | (n_next == self.periods) & (self.brk[ids, j] >= self.t_stop[ids])
            if over.any():
                self._finish_horizon(ids[over], 0.0)
                ids, j, wrap = ids[~over], j[~over], wrap[~over]
        wi = ids[wrap]
        if wi.size:
            self.n[wi] += 1
            self.tau[wi] = 0.0
            self.k[wi] = 0
            self._period_boundary(wi)
            keep = self.alive[ids]
            ids, j = ids[keep], j[keep]
        self.k[ids] = j
        self.tau[ids] = self.brk[ids, j]
        a = self.acc[ids, j]
        self.mode[ids] = np.where(a < 0.0, 1, -1)
        self.v[ids] = 0.0

    def _slip(self, ids):
        """Slipping members: advance to the next event along the closed-form arc."""
        xr, v, k, tau = self.xr[ids], self.v[ids], self.k[ids], self.tau[ids]
        sg = self.mode[ids].astype(float)
        a = self.acc[ids, k]
        hp = self.brk[ids, k + 1] - tau
        if self.until == "periods":  # the horizon (periods, tau0) ends the last arc like a piece end
            rem = np.where(self.n[ids] == self.periods, self.t_stop[ids] - tau, np.inf)
            horizon = rem <= hp
            hp = np.minimum(hp, rem)
        else:
            horizon = np.zeros(ids.size, dtype=bool)
        w = self.w[ids]
        fwd = sg > 0.0
        uni = self.uniform[ids]
        zone = ~uni & np.where(fwd, (xr >= 0.0) & (xr < w), (xr > 0.0) & (xr <= w))
        accel = -a - sg * self._mu(ids, xr)  # x'' at the start of the arc
        bnd = self.bnd[ids]
        with np.errstate(invalid="ignore"):
            xb = np.where(fwd, np.where(bnd > xr[:, None], bnd, np.inf).min(axis=1),
                          np.where(bnd < xr[:, None], bnd, -np.inf).max(axis=1))
        n = ids.size
        hv = np.full(n, np.inf)
        hx = np.full(n, np.inf)
        x_stop = xr.copy()
        v_cross = np.zeros(n)
        x_new = np.empty(n)
        v_new = np.empty(n)

        with np.errstate(divide="ignore", invalid="ignore", over="ignore"):
            # Quadratic arcs (mu_bar constant).
            c = np.flatnonzero(~zone)
            if c.size:
                xc, vc, ac, sc = xr[c], v[c], accel[c], sg[c]
                hv[c] = np.where(vc * ac < 0.0, -vc / ac, np.inf)
                x_stop[c] = xc - vc * vc / (2.0 * ac)
                dx = xb[c] - xc
                v1sq = vc * vc + 2.0 * ac * dx
                ok = (v1sq >= 0.0) & np.isfinite(dx)
                v1 = sc * np.sqrt(np.where(ok, v1sq, 0.0))
                hx[c] = np.where(ok, 2.0 * dx / (vc + v1), np.inf)
                v_cross[c] = v1
                s = np.minimum(np.minimum(hv[c], hx[c]), hp[c])
                dxs, v_new[c] = arcs.step(arcs.QUADRATIC, 0.0, vc, ac, s, xp=np)
                x_new[c] = xc + dxs
            # Harmonic arcs: forward slip in the transition zone (eq. 42-44).
            hz = np.flatnonzero(zone & fwd)
            if hz.size:
                g = ids[hz]
                om, b1 = self.omega[g], self.b1[g]
                xh, vh, ah = xr[hz], v[hz], accel[hz]
                A = -ah / b1               # x - centre of the oscillation (d_1 of eq. 45)
                B = vh / om                # d_2 of eq. 46, >= 0
                R = np.hypot(A, B)
                th0 = np.arctan2(-B, A)    # phase in [-pi, 0]; -pi for a slip from rest
                hv[hz] = -th0 / om         # eq. (47) with atan2: valid for both signs of A
                x_stop[hz] = xh + np.where(A <= 0.0, R - A, B * B / (R + A))
                d = (xb[hz] - xh) + A
                ok = d < R
                e = np.sqrt(np.where(ok, (R - d) * (R + d), 0.0))  # |v| / omega at x_b (energy)
                hx[hz] = np.where(ok, (-np.arctan2(e, d) - th0) / om, np.inf)
                v_cross[hz] = om * e
                s = np.minimum(np.minimum(hv[hz], hx[hz]), hp[hz])
                dxs, v_new[hz] = arcs.step(arcs.HARMONIC, om, vh, ah, s, xp=np)
                x_new[hz] = xh + dxs
            # Hyperbolic arcs: backward slip in the transition zone.
            yz = np.flatnonzero(zone & ~fwd)
            if yz.size:
                g = ids[yz]
                om, b1 = self.omega[g], self.b1[g]
                xy, vy, ay = xr[yz], v[yz], accel[yz]
                A = ay / b1                # x - centre
                B = vy / om                # <= 0
                stops = (A > 0.0) & (A + B > 0.0)
                hv[yz] = np.where(stops, np.arctanh(-B / A) / om, np.inf)
                x_stop[yz] = xy - B * B / (A + np.sqrt(np.where(stops, (A + B) * (A - B), 0.0)))
                dxb = xb[yz] - xy
                d = dxb + A
                e1sq = B * B + dxb * (d + A)
                ok = (e1sq >= 0.0) & np.isfinite(dxb)
                e1 = -np.sqrt(np.where(ok, e1sq, 0.0))
                p, P, Q, q = d + e1, A + B, A - B, d - e1
                ratio = np.where(np.abs(p) + np.abs(P) >= np.abs(Q) + np.abs(q), p / P, Q / q)
                ok &= (ratio >= 1.0) & np.isfinite(ratio)
                hx[yz] = np.where(ok, np.log(np.where(ok, ratio, 1.0)) / om, np.inf)
                v_cross[yz] = om * e1
                s = np.minimum(np.minimum(hv[yz], hx[yz]), hp[yz])
                dxs, v_new[yz] = arcs.step(arcs.HYPERBOLIC, om, vy, ay, s, xp=np)
                x_new[yz] = xy + dxs

        stop = (hv <= hx) & (hv <= hp)
        cross = (hx < hv) & (hx <= hp)
        piece = hp <= np.minimum(hv, hx)
        x_new = np.where(stop, x_stop, np.where(cross, xb, x_new))
        v_new = np.where(stop, 0.0, np.where(cross, v_cross, v_new))
        h = np.where(piece, hp, np.minimum(hv, hx))

        self.path[ids] += np.abs(x_new - xr)
        self.xr[ids] = x_new
        self.v[ids] = v_new
        self.x_max[ids] = np.maximum(self.x_max[ids], x_new)
        end = piece & horizon
        piece &= ~horizon
        self.tau[ids] = np.where(end, self.t_stop[ids], np.where(piece, self.brk[ids, k + 1], tau + h))
        self.events[ids] += 1
        crossed_zone = cross & ((xb == 0.0) | (xb == w))
        self.moved_region[ids[crossed_zone]] = True
        self._record_crossings(ids)

        k_new = k + piece
        wrap = k_new >= self.m
        self.k[ids] = np.where(wrap, 0, k_new)
        stop_ids = ids[stop]
        if stop_ids.size:
            self._decide_at_rest(stop_ids)
        ended = ids[end & self.alive[ids]]
        if ended.size:
            self._finish_horizon(ended, self.v[ended])
        wi = ids[wrap & self.alive[ids]]
        if wi.size:
            self.n[wi] += 1
            self.tau[wi] = 0.0
            self._period_boundary(wi)
        over = ids[self.alive[ids] & (self.events[ids] >= self.max_events)]
        if over.size:
            self._finish(over, Outcome.ERROR, Reason.MAX_EVENTS, self.xr[over], self.v[over], self.tau[over])

    def run(self) -> BatchResult:
        while True:
            live = np.flatnonzero(self.alive)
            if live.size == 0:
                break
            mode = self.mode[live]
            stuck = live[mode == 0]
            if stuck.size:
                self._unstick(stuck)
            slipping = live[mode != 0]
            slipping = slipping[self.alive[slipping]]
            if slipping.size:
                self._slip(slipping)
        ref = self.x_ref
        return BatchResult(
            x_end=ref + self.x_end, v_end=self.v_end, status=self.status, reason=self.reason,
            period_end=self.period_end, tau_end=self.tau_end, events=self.events,
            stick_events=self.sticks, zone_sticks=self.zsticks,
            first_stick_x=ref + self.first_x, first_stick_period=self.first_n, first_stick_tau=self.first_tau,
            contraction=self.contraction, advance=self.advance, cycle=self.cycle, x_max=ref + self.x_max,
            boundaries=ref[:, None] + self.bnd, cross_period=self.cross_n, cross_tau=self.cross_tau,
            cross_v=self.cross_v, cross_sticks=self.cross_sticks)

