"""The exact event-driven solver (``method="exact"``).

Model (Sect. 3.2, eqs. 6 and 38; DESIGN): x'' + y''(t) in -mu_bar(x) Sign(x').

Piecewise-constant profiles (ThreePhaseProfile, PolynomialProfile, any
PiecewiseConstantProfile) are integrated in closed form between events
(:mod:`selfalign.model.arcs`): a quadratic where mu_bar is constant (eqs. 15-20),
a harmonic oscillator for forward slip in the transition zone (eqs. 42-44,
omega = sqrt(b1)), its hyperbolic counterpart for backward slip there, and stick
(x constant, eqs. 22-24).  Events, located in closed form:

* SWITCH: a profile break (y'' jumps).  A stuck mass starts to slip only here
  (y'' is constant between breaks and mu_bar is constant while stuck): it slips
  iff |y''| > mu_bar(x), in the direction -sign(y'') (SLIP event).
* STICK / REVERSAL: v reaches 0 (eq. 21; eq. 47 generalised with atan2; the
  exponential form for hyperbolic arcs).  Stick iff |y''| <= mu_bar(x), else the
  slip reverses.
* ZONE: the mass crosses x_mu or x_mu + w; the arc type changes there.

Crossing times come from quadratics solved in the cancellation-free "citardauq"
form; the earliest candidate within the current piece is taken, and no candidate
is ever sought beyond the piece end.

Tie rules (they make every zero-length step change the mode, so no Zeno loop):

1. |y''| = mu_bar counts as stick.
2. v = 0 and a zone crossing at the same time: the v = 0 event wins (mu_bar is
   continuous, so no crossing is needed to decide the mode).
3. v = 0 exactly at a break (grazing): the v = 0 event is handled first with the
   ending piece's y'', then the break re-decides the mode with the new piece's y''
   (a mass at v = 0 at a break is always re-decided, as if stuck).
4. A slip velocity of the wrong sign (rounding, at most a few ulp) is set to 0 at
   the start of an arc; an arc that decelerates from v = 0 then ends at once with
   a v = 0 event, which always changes the mode.
5. A mass exactly on a zone boundary belongs to the region it moves into
   (stuck: x = x_mu counts as low friction, x = x_mu + w as high friction).

Time is (period index n, tau in [0, dt)); positions are kept relative to an origin
(x_mu for a StopZone, else x0), so x_mu = 1e6 costs no accuracy inside the zone.

Smooth (Fourier) profiles, uniform friction only: during a slip in direction s,
x' = v0 - s (t - t0) - (y'(t) - y'(t0)) and x follows in closed form.  The events
(v = 0, and |y''| crossing 1 while stuck) are bracketed on a fixed grid of
64 (order + 1) points per period (sign changes closer than the grid spacing are
not resolved; a grazing |y''| = 1 within one grid cell is sub-grid) and refined
with brentq to ~1 ulp (event-located integration).

Outcomes (DESIGN "Solver contract"): HORIZON; REST (at a stick where
mu_bar(x) >= max|y''|); ACCUMULATION (stick positions inside the zone increase
toward x_stick_min, eq. 41, and are within ``accumulation_tol`` of it; tolerances
below 64 ulp of the zone width are raised to that); NEVER_STOPS (the period-boundary
state repeats with no net progress, or the mass repeats a period in the
high-friction region with net advance >= 0, i.e. walks through it, c_mu < max|y''|,
or on a uniform surface, or walks away from the zone); ERROR (``max_events``, a stalled
event loop, arithmetic failure; never NaN).

Steady-state fast-forward: the state at the start of each of the last k <= 8 periods is
compared with the current one.  If the k periods stayed in one region of constant
friction, bit-equal (v, mode) suffices (the motion is translation invariant there and
per-period displacements are computed independently of x, so they repeat bit for bit).
Otherwise (x, v, mode) must repeat to 16 ulp of the position scale (|x - origin| + w)
and velocity scale (|v| + max|y''| dt): a periodic orbit whose position is neutral
jitters at the ulp level instead of repeating bit for bit.  While stuck inside the zone
below x_stick_min a near-repeat may be a slow accumulation, so there only an exact
repeat counts.  Whole cycles are then added as c * (sum of the cycle's displacements),
c bounded so that the mass stays in its region.  Fast-forward is off while recording
series or events.

Low-level access for other modules: :class:`ExactSolver` (``step_period()`` with
events, pre/post-event accelerations and arcs) and :func:`iterate_events`.
"""

from __future__ import annotations

import math
import numbers
import time
from collections import deque
from typing import NamedTuple

import numpy as np

from ..model.friction import StopZone, Uniform
from ..model.profiles import FourierProfile
from .outcomes import EVENT_DTYPE, EventKind, Status, Trajectory
from ..model import arcs
from ..model.arcs import HARMONIC, HYPERBOLIC, QUADRATIC, SMOOTH, STICK, decide_mode

_INF = math.inf
_EPS = 2.0 ** -52
_SWITCH, _STICK_EVENT, _SLIP, _REVERSAL, _ZONE = (int(k) for k in (
    EventKind.SWITCH, EventKind.STICK, EventKind.SLIP, EventKind.REVERSAL, EventKind.ZONE))
#: run_period results.
_DONE, _REST, _ACCUMULATION, _BUDGET, _STALL = 0, 1, 2, 3, 4
#: Successive zero-duration arcs that count as a stalled (Zeno) event loop.  The tie rules make
#: this impossible; the guard turns a broken invariant into ERROR instead of a long hang.
_STALL_EVENTS = 100
#: Longest period-boundary cycle the fast-forward looks for.
_CYCLE_MAX = 8
#: Relative tolerance of a near-repeat of the period-boundary state (16 ulp).
_NEAR = 16.0 * _EPS
#: Regions (Arc.region): low friction (or the whole uniform surface), transition zone, high friction.
LOW, ZONE, HIGH = 0, 1, 2


class Event(NamedTuple):
    """One event.  ``acc_before`` / ``acc_after`` are x'' just before and after it, so the
    vector field f = (x', x'') jumps from (v, acc_before) to (v, acc_after) (saltation
    matrices).  A SWITCH is time-triggered; STICK/REVERSAL lie on v = 0; ZONE on x = x_mu
    or x_mu + w.  At a break where the mode also changes, a SWITCH event is followed by a
    SLIP/STICK/REVERSAL event at the same time."""

    kind: EventKind
    period: int
    tau: float
    x: float
    v: float
    mode_before: int
    mode_after: int
    acc_before: float
    acc_after: float


class Arc(NamedTuple):
    """One closed-form arc: ``kind`` (arcs.STICK/QUADRATIC/HARMONIC/HYPERBOLIC/SMOOTH),
    start time (period, tau), duration, start state (x, v), x'' at the start (``acc``),
    table acceleration y'' (NaN for SMOOTH), omega = sqrt(b1) (0 outside the zone),
    mode and region (LOW, ZONE, HIGH).  ``arcs.step(kind, omega, v, acc, s)`` gives the
    motion and ``arcs.fundamental_matrix(kind, omega, duration)`` its linearisation."""

    kind: int
    period: int
    tau: float
    duration: float
    x: float
    v: float
    acc: float
    table_acc: float
    omega: float
    mode: int
    region: int


class PeriodStep(NamedTuple):
    """Result of :meth:`ExactSolver.step_period`: the state at the next period boundary,
    the net advance over the period and (when recording) its events and arcs."""

    x: float
    v: float
    mode: int
    period: int
    tau: float
    advance: float
    events: tuple
    arcs: tuple


# --------------------------------------------------------------------------------------
# Steppers: one period at a time, state relative to the origin
# --------------------------------------------------------------------------------------

class _Stepper:
    """State (xi = x - origin, v, mode, period) and the stick-outcome bookkeeping.

    ``run_period(budget)`` advances from one period boundary (time phase * dt) to the
    next and returns _DONE, or stops early at the event that ends the run (_REST,
    _ACCUMULATION, _BUDGET; time in ``stop``).  It leaves per-period results in
    ``events`` (count), ``dxp`` (displacement), ``lo``/``hi`` (extreme displacements
    from the period start), ``regions`` (bit mask of the regions visited).
    """

    def __init__(self, dt, tau0, max_acc, zone, w):
        self.dt, self.tau0, self.max_acc = dt, tau0, max_acc
        self.zone, self.w = zone, w
        self.xi, self.v, self.mode, self.period = 0.0, 0.0, 0, 0
        self.fresh = True              # at the run start: no break event at the first boundary
        self.record = None             # (arcs, events) lists while recording
        self.stop_at_rest = False
        self.at_rest = False
        self.acc_tol = None            # set by watch_accumulation
        self.xs_rel = _INF             # x_stick_min - origin (eq. 41) on a stop zone
        self.zone_sticks = []          # last stick positions inside the zone
        self.zone_stick_count = 0
        self.stop = (0, tau0)
        self.events, self.dxp, self.lo, self.hi, self.regions = 0, 0.0, 0.0, 0.0, 0

    def watch_accumulation(self, tol: float) -> None:
        """Stop with _ACCUMULATION when zone stick positions increase to within tol of x_stick_min."""
        if math.isfinite(self.xs_rel):
            self.acc_tol = max(tol, 64.0 * _EPS * self.w)

    def may_accumulate(self) -> bool:
        """Stuck inside the zone below x_stick_min: a slow accumulation may be under way."""
        return self.zone and self.mode == 0 and 0.0 <= self.xi <= self.w and self.xi < self.xs_rel

    def _stick(self, xi, mu, n, tau) -> int:
        """Checks at the start of a stick at xi (friction mu); the run ends on a non-zero result."""
        if mu >= self.max_acc:
            self.at_rest = True
            if self.stop_at_rest:
                self.stop = (n, tau)
                return _REST
            return _DONE
        if self.acc_tol is not None and 0.0 <= xi <= self.w:
            sticks = self.zone_sticks
            self.zone_stick_count += 1
            sticks.append(xi)
            del sticks[:-3]
            if len(sticks) >= 2 and xi > sticks[-2] and self.xs_rel - xi <= self.acc_tol:
                self.stop = (n, tau)
                return _ACCUMULATION
        return _DONE

    def start(self, xi: float, v: float) -> int:
        """Set the state at the run start (time phase * dt of period 0); decide the mode if v = 0."""
        self.xi, self.v, self.period, self.fresh = float(xi), float(v), 0, True
        self.stop = (0, self.tau0)
        if v != 0.0:
            self.mode = 1 if v > 0.0 else -1
            return _DONE
        self.v = 0.0
        mu = self.mu(self.xi)
        self.mode = decide_mode(self.table_acc(self.tau0), mu)
        return self._stick(self.xi, mu, 0, self.tau0) if self.mode == 0 else _DONE

    def _halt(self, code, xi, v, mode, n, tau, events, dxp, lo, hi, regions):
        self.xi, self.v, self.mode = xi, v, mode
        self.events, self.dxp, self.lo, self.hi, self.regions = events, dxp, lo, hi, regions
        if code in (_BUDGET, _STALL):
            self.stop = (n, tau)
        return code


class _PiecewiseStepper(_Stepper):
    """Closed-form event stepping for piecewise-constant y'' (any surface)."""

    def __init__(self, profile, surface, phase):
        dt = float(profile.dt)
        tau0 = phase * dt
        zone = isinstance(surface, StopZone) and surface.b1 > 0.0
        super().__init__(dt, tau0, float(profile.max_abs_acceleration), zone, surface.w if zone else _INF)
        self.b1 = surface.b1 if zone else 0.0
        self.omega = math.sqrt(self.b1)
        self.c = surface.c_mu if zone else 1.0
        if zone and 1.0 < self.max_acc <= self.c:
            self.xs_rel = surface.w * (self.max_acc - 1.0) / (self.c - 1.0)   # as StopZone.x_stick_min
        breaks = [float(b) for b in profile.breaks]
        accs = [float(a) for a in profile.accels]
        self.breaks, self.accels = breaks, accs
        m = len(accs)
        i0 = int(profile.piece_index(tau0))
        # One period from tau0: (y'', tau at start, length, period offset, starts at a break).
        segs = [(accs[i0], tau0, breaks[i0 + 1] - tau0, 0, tau0 == breaks[i0])]
        segs += [(accs[i], breaks[i], breaks[i + 1] - breaks[i], 0, True) for i in range(i0 + 1, m)]
        segs += [(accs[i], breaks[i], breaks[i + 1] - breaks[i], 1, True) for i in range(i0)]
        if tau0 > breaks[i0]:
            segs.append((accs[i0], breaks[i0], tau0 - breaks[i0], 1, True))
        self.segs = tuple(segs)

    def table_acc(self, tau):
        i = max(0, min(len(self.accels) - 1, np.searchsorted(self.breaks, tau, side="right") - 1))
        return self.accels[int(i)]

    def mu(self, xi):
        """mu_bar at xi (eq. 9 in the zone)."""
        if not self.zone or xi <= 0.0:
            return 1.0
        return self.c if xi >= self.w else 1.0 + self.b1 * xi

    def arc_params(self, xi, mode, a):
        """(kind, region, mu_bar, x'') of the arc starting at xi in ``mode`` under y'' = a (tie rule 5)."""
        if self.zone:
            if xi < 0.0 or (xi == 0.0 and mode <= 0):
                r, mu = LOW, 1.0
            elif xi > self.w or (xi == self.w and mode >= 0):
                r, mu = HIGH, self.c
            else:
                r, mu = ZONE, 1.0 + self.b1 * xi
        else:
            r, mu = LOW, 1.0
        if mode == 0:
            return STICK, r, mu, 0.0
        kind = QUADRATIC if r != ZONE else (HARMONIC if mode > 0 else HYPERBOLIC)
        return kind, r, mu, -a - mode * mu

    def run_period(self, budget) -> int:
        zone, w, om = self.zone, self.w, self.omega
        arc_params, zvt, crt, step = self.arc_params, arcs.zero_velocity_time, arcs.crossing_time, arcs.step
        mu_of, stick = self.mu, self._stick
        rec = self.record
        xi, v, mode, n = self.xi, self.v, self.mode, self.period
        dxp = lo = hi = 0.0
        regions = events = stalled = 0
        fresh, self.fresh = self.fresh, False
        a_prev = self.segs[-1][0]
        for a, ts, seg_len, dn, at_break in self.segs:
            nn = n + dn
            s0 = 0.0
            if at_break and not fresh:
                events += 1
                if v * mode < 0.0:
                    v = 0.0
                if rec is not None:
                    acc_b, acc_a = self._acc(xi, mode, a_prev), self._acc(xi, mode, a)
                    rec[1].append((_SWITCH, nn, ts, xi, v, mode, mode, acc_b, acc_a))
                if mode == 0 or v == 0.0:          # tie rule 3: re-decide at v = 0
                    mu = mu_of(xi)
                    new = decide_mode(a, mu)
                    if new != mode:
                        events += 1
                        if rec is not None:
                            kind = _SLIP if mode == 0 else (_STICK_EVENT if new == 0 else _REVERSAL)
                            rec[1].append((kind, nn, ts, xi, 0.0, mode, new,
                                           self._acc(xi, mode, a), self._acc(xi, new, a)))
                        mode = new
                        if new == 0:
                            code = stick(xi, mu, nn, ts)
                            if code:
                                return self._halt(code, xi, 0.0, 0, nn, ts, events, dxp, lo, hi, regions)
                    v = 0.0
                if events >= budget:
                    return self._halt(_BUDGET, xi, v, mode, nn, ts, events, dxp, lo, hi, regions)
            fresh = False
            a_prev = a
            while mode != 0:
                if v * mode < 0.0:                  # tie rule 4
                    v = 0.0
                kind, r, mu, acc = arc_params(xi, mode, a)
                regions |= 1 << r
                rem = seg_len - s0
                s_b = _INF
                if kind == QUADRATIC:
                    s_v = -v / acc if acc * mode < 0.0 else _INF
                    if zone and (r == LOW) == (mode > 0):
                        xb = 0.0 if r == LOW else w
                        s_b = crt(QUADRATIC, 0.0, v, acc, xi - xb)
                else:
                    s_v = zvt(kind, om, mode, v, acc)
                    xb = w if mode > 0 else 0.0
                    s_b = crt(kind, om, v, acc, xi - xb)
                if s_v <= s_b and s_v <= rem:       # tie rules 2, 3
                    s, ev = s_v, 1
                elif s_b <= rem:
                    s, ev = s_b, 2
                else:
                    s, ev = rem, 0
                dx, v1 = step(kind, om, v, acc, s)
                if rec is not None:
                    rec[0].append((kind, nn, ts + s0, s, xi, v, acc, a, om if r == ZONE else 0.0, mode, r))
                if ev == 0:
                    xi += dx
                    dxp += dx
                    v = v1
                    if dxp > hi:
                        hi = dxp
                    elif dxp < lo:
                        lo = dxp
                    break
                s0 += s
                events += 1
                stalled = stalled + 1 if s == 0.0 else 0
                if stalled > _STALL_EVENTS:
                    return self._halt(_STALL, xi, v, mode, nn, ts + s0, events, dxp, lo, hi, regions)
                acc_end = arcs.acceleration(kind, self.b1, acc, dx) if rec is not None else 0.0
                if ev == 2:                         # zone crossing: land exactly on the boundary
                    dxp += xb - xi
                    xi = xb
                    v = v1
                    if rec is not None:
                        rec[1].append((_ZONE, nn, ts + s0, xi, v, mode, mode, acc_end, self._acc(xi, mode, a)))
                else:                               # v = 0: stick or reverse (tie rule 1)
                    xi += dx
                    dxp += dx
                    v = 0.0
                    mu = mu_of(xi)
                    new = decide_mode(a, mu)
                    if rec is not None:
                        rec[1].append((_STICK_EVENT if new == 0 else _REVERSAL, nn, ts + s0, xi, 0.0, mode, new,
                                       acc_end, self._acc(xi, new, a)))
                    mode = new
                    if new == 0:
                        code = stick(xi, mu, nn, ts + s0)
                        if code:
                            return self._halt(code, xi, 0.0, 0, nn, ts + s0, events, dxp, lo, hi, regions)
                if dxp > hi:
                    hi = dxp
                elif dxp < lo:
                    lo = dxp
                if events >= budget:
                    return self._halt(_BUDGET, xi, v, mode, nn, ts + s0, events, dxp, lo, hi, regions)
            if mode == 0:
                r = (LOW if xi <= 0.0 else (HIGH if xi >= w else ZONE)) if zone else LOW
                regions |= 1 << r
                if rec is not None:
                    rec[0].append((STICK, nn, ts + s0, seg_len - s0, xi, 0.0, 0.0, a, 0.0, 0, r))
        self.period = n + 1
        self.stop = (n + 1, self.tau0)
        self._halt(_DONE, xi, v, mode, n + 1, self.tau0, events, dxp, lo, hi, regions)
        return _DONE

    def _acc(self, xi, mode, a):
        """x'' of ``mode`` at xi under y'' = a (0 in stick)."""
        return self.arc_params(xi, mode, a)[3]

    def current_arc(self, n, tau):
        """The zero-length arc at the current state (for the last dense sample)."""
        a = self.table_acc(tau)
        kind, r, _, acc = self.arc_params(self.xi, self.mode, a)
        return (kind, n, tau, 0.0, self.xi, self.v, acc, a, self.omega if r == ZONE else 0.0, self.mode, r)


class _SmoothStepper(_Stepper):
    """Event-located closed-form stepping for a FourierProfile on a uniform surface."""

    def __init__(self, profile, phase):
        from scipy.optimize import brentq  # only smooth profiles need it (slow import)

        dt = float(profile.dt)
        super().__init__(dt, phase * dt, float(profile.max_abs_acceleration), False, _INF)
        self.brentq = brentq
        self.terms = [(float(w), float(a), float(b))
                      for w, a, b in zip(profile.omega, profile.cos_coeffs, profile.sin_coeffs)]
        grid = 64 * (profile.order + 1)
        self.grid = np.linspace(0.0, dt, grid + 1)
        # Grid values from the same scalar evaluator as the root finding (bit-identical).
        values = np.array([self.eval(self.tau0 + s) for s in self.grid.tolist()])
        self.g_yd, self.g_ydd = values[:, 1], values[:, 2]
        self.xtol = 2.0 * _EPS * dt

    def eval(self, t):
        """(y, y', y'') at time t, in pure Python."""
        y = yd = ydd = 0.0
        for w, a, b in self.terms:
            c, s = math.cos(w * t), math.sin(w * t)
            y += a * c + b * s
            yd += w * (b * c - a * s)
            ydd -= w * w * (a * c + b * s)
        return y, yd, ydd

    def table_acc(self, tau):
        return self.eval(tau)[2]

    def mu(self, xi):
        return 1.0

    def run_period(self, budget) -> int:
        tau0, dt, grid = self.tau0, self.dt, self.grid
        g_yd, g_ydd = self.g_yd, self.g_ydd
        ev, rec, brentq = self.eval, self.record, self.brentq
        xi, v, mode, n = self.xi, self.v, self.mode, self.period
        dxp = lo = hi = 0.0
        events = 0
        self.fresh = False
        s0 = 0.0
        while True:
            k0 = int(np.searchsorted(grid, s0, side="right"))
            if mode == 0:
                above = np.abs(g_ydd[k0:]) > 1.0
                j = int(np.argmax(above)) if above.size else 0
                if not above.size or not above[j]:
                    if rec is not None:
                        rec[0].append((STICK, n, tau0 + s0, dt - s0, xi, 0.0, 0.0, math.nan, 0.0, 0, LOW))
                    break
                k = k0 + j
                sgn = 1.0 if g_ydd[k] > 0.0 else -1.0
                left = max(s0, float(grid[k - 1]))

                def g(s, sgn=sgn):
                    return sgn * ev(tau0 + s)[2] - 1.0
                root = left if g(left) >= 0.0 else brentq(g, left, float(grid[k]), xtol=self.xtol, rtol=4 * _EPS)
                if rec is not None:
                    rec[0].append((STICK, n, tau0 + s0, root - s0, xi, 0.0, 0.0, math.nan, 0.0, 0, LOW))
                    rec[1].append((_SLIP, n, tau0 + root, xi, 0.0, 0, -int(sgn), 0.0, -ev(tau0 + root)[2] + sgn))
                events += 1
                mode, v, s0 = -int(sgn), 0.0, root
            else:
                sigma = float(mode)
                y0, yd0, ydd0 = ev(tau0 + s0)
                positive = sigma * (v - sigma * (grid[k0:] - s0) - (g_yd[k0:] - yd0)) > 0.0
                if sigma * v > 0.0:
                    first = 0
                else:
                    first = int(np.argmax(positive)) if positive.size else 0
                    if not positive.size or not positive[first]:
                        first = positive.size    # sub-grid grazing: no v = 0 resolved
                rest = ~positive[first:]
                j = first + int(np.argmax(rest)) if rest.size else positive.size
                if j >= positive.size or not rest[j - first]:
                    root, ev_kind = dt, None
                else:
                    k = k0 + j
                    left = float(grid[k - 1]) if j > 0 else s0

                    def f(s, v=v, sigma=sigma, s0=s0, yd0=yd0):
                        return sigma * (v - sigma * (s - s0) - (ev(tau0 + s)[1] - yd0))
                    root = brentq(f, left, float(grid[k]), xtol=self.xtol, rtol=4 * _EPS)
                    ev_kind = True
                d = root - s0
                y1, yd1, ydd1 = ev(tau0 + root)
                dx = v * d - 0.5 * sigma * d * d - (y1 - y0 - yd0 * d)
                if rec is not None:
                    rec[0].append((SMOOTH, n, tau0 + s0, d, xi, v, -ydd0 - sigma, math.nan, 0.0, mode, LOW))
                xi += dx
                dxp += dx
                if dxp > hi:
                    hi = dxp
                elif dxp < lo:
                    lo = dxp
                if ev_kind is None:
                    v = v - sigma * d - (yd1 - yd0)
                    break
                events += 1
                v, s0 = 0.0, root
                new = decide_mode(ydd1, 1.0)
                if rec is not None:
                    rec[1].append((_STICK_EVENT if new == 0 else _REVERSAL, n, tau0 + root, xi, 0.0, mode, new,
                                   -ydd1 - sigma, 0.0 if new == 0 else -ydd1 - new))
                mode = new
                if new == 0:
                    code = self._stick(xi, 1.0, n, tau0 + root)
                    if code:
                        return self._halt(code, xi, 0.0, 0, n, tau0 + root, events, dxp, lo, hi, 1)
            if events >= budget:
                return self._halt(_BUDGET, xi, v, mode, n, tau0 + s0, events, dxp, lo, hi, 1)
        self.period = n + 1
        self.stop = (n + 1, tau0)
        self._halt(_DONE, xi, v, mode, n + 1, tau0, events, dxp, lo, hi, 1)
        return _DONE

    def current_arc(self, n, tau):
        _, _, ydd = self.eval(tau)
        kind = STICK if self.mode == 0 else SMOOTH
        acc = 0.0 if self.mode == 0 else -ydd - self.mode
        return (kind, n, tau, 0.0, self.xi, self.v, acc, math.nan, 0.0, self.mode, LOW)


def _make_stepper(profile, surface, phase):
    if surface is None:
        surface = Uniform()
    if not isinstance(surface, (Uniform, StopZone)):
        raise ValueError(f"surface must be Uniform() or StopZone(...), got {type(surface).__name__}")
    if getattr(profile, "piecewise_constant", False):
        return _PiecewiseStepper(profile, surface, phase)
    if isinstance(profile, FourierProfile):
        if isinstance(surface, StopZone):
            raise ValueError("method='exact' supports a FourierProfile only on a Uniform surface "
                             "(the stop zone needs piecewise-constant y''); use method='moreau' or 'ivp'")
        return _SmoothStepper(profile, phase)
    raise ValueError(f"method='exact' needs a piecewise-constant or Fourier profile, got {type(profile).__name__}")


def _origin(surface, x0):
    return surface.x_mu if isinstance(surface, StopZone) else x0


def _norm_time(n, tau, dt):
    """(period, tau) with tau in [0, dt) (an event at the very end of a period is the next one's start)."""
    return (n + 1, tau - dt) if tau >= dt else (n, tau)


# --------------------------------------------------------------------------------------
# Low-level public access
# --------------------------------------------------------------------------------------

class ExactSolver:
    """One trajectory advanced period by period, for modules that need events and arcs
    (Floquet via saltation matrices, Lyapunov analysis, stopping studies).

    ``x0``, ``v0`` hold at time ``phase * dt`` of period 0; every period boundary is at
    that phase.  With ``record=True`` each :meth:`step_period` returns the period's
    :class:`Event` list (time, state, mode and x'' before/after) and :class:`Arc` list
    (kind, duration, start state, omega); the event logic is the solver's own.  No
    outcome detection (rest, accumulation) and no fast-forward happen here.
    """

    def __init__(self, profile, surface=None, x0: float = 0.0, v0: float = 0.0, phase: float = 0.0,
                 record: bool = True):
        for name, value in (("x0", x0), ("v0", v0), ("phase", phase)):
            if not isinstance(value, numbers.Real) or not math.isfinite(value):
                raise ValueError(f"{name} must be a finite number, got {value!r}")
        if not 0.0 <= phase < 1.0:
            raise ValueError(f"phase must lie in [0, 1) (fraction of the period), got {phase!r}")
        surface = Uniform() if surface is None else surface
        self._stepper = _make_stepper(profile, surface, float(phase))
        self.origin = float(_origin(surface, x0))
        self.record = bool(record)
        self._stepper.start(float(x0) - self.origin, float(v0))

    @property
    def x(self) -> float:
        return self.origin + self._stepper.xi

    @property
    def xi(self) -> float:
        """Position relative to ``origin`` (x_mu for a StopZone, else x0): full accuracy."""
        return self._stepper.xi

    @property
    def v(self) -> float:
        return self._stepper.v

    @property
    def mode(self) -> int:
        return self._stepper.mode

    @property
    def period(self) -> int:
        return self._stepper.period

    @property
    def tau(self) -> float:
        return self._stepper.tau0

    def step_period(self) -> PeriodStep:
        """Advance one period; events and arcs are filled when ``record`` is True."""
        st = self._stepper
        st.record = ([], []) if self.record else None
        st.run_period(_INF)
        ev, ar = (), ()
        if st.record is not None:
            o, dt = self.origin, st.dt
            ev = tuple(Event(EventKind(k), *_norm_time(p, t, dt), o + x, v, mb, ma, ab, aa)
                       for k, p, t, x, v, mb, ma, ab, aa in st.record[1])
            ar = tuple(Arc(k, *_norm_time(p, t, dt), d, o + x, v, acc, a, om, m, r)
                       for k, p, t, d, x, v, acc, a, om, m, r in st.record[0])
            st.record = None
        return PeriodStep(self.x, st.v, st.mode, st.period, st.tau0, st.dxp, ev, ar)

    def advance(self, periods: int) -> int:
        """Advance ``periods`` periods without recording; returns the number of events."""
        st = self._stepper
        st.record = None
        events = 0
        for _ in range(int(periods)):
            st.run_period(_INF)
            events += st.events
        return events


def iterate_events(profile, surface=None, x0: float = 0.0, v0: float = 0.0, phase: float = 0.0,
                   periods: int | None = None):
    """Yield the :class:`Event` records of a trajectory in time order, for ``periods``
    periods (or for ever), built on :class:`ExactSolver`."""
    solver = ExactSolver(profile, surface, x0, v0, phase, record=True)
    while periods is None or solver.period < periods:
        yield from solver.step_period().events


# --------------------------------------------------------------------------------------
# solve(): outcomes, fast-forward, output
# --------------------------------------------------------------------------------------

def _check_options(options):
    tol = options.get("accumulation_tol", 1e-12)
    if isinstance(tol, bool) or not isinstance(tol, numbers.Real) or not 0.0 < tol < _INF:
        raise ValueError(f"option accumulation_tol must be a finite number > 0, got {tol!r}")
    max_events = options.get("max_events", 50_000_000)
    integral = isinstance(max_events, numbers.Integral) or (
        isinstance(max_events, float) and max_events.is_integer())
    if isinstance(max_events, bool) or not integral or max_events < 1:
        raise ValueError(f"option max_events must be an integer >= 1, got {max_events!r}")
    return float(tol), int(max_events)


class _PeriodRecord(NamedTuple):
    v: float        # state at the period start
    mode: int
    xi: float
    dxp: float      # displacement over the period, and its extremes
    lo: float
    hi: float
    region: int     # LOW or HIGH if the whole period had constant friction there, else -1


def _find_cycle(history, v, mode, xi, tol_x=0.0, tol_v=0.0):
    """(k, advance, region, lo, hi) of the shortest k-period cycle ending now, or None.

    region >= 0: translation-invariant cycle (bit-equal v, mode; all k periods in one region of
    constant friction), advance = sum of displacements; region -1: repeat of (x, v, mode) to
    within tol_x, tol_v, advance 0.  lo/hi: extreme displacements within the cycle.
    """
    for k in range(1, len(history) + 1):
        start = history[-k]
        if start.mode != mode or abs(start.v - v) > tol_v:
            continue
        cycle = list(history)[-k:]
        region = cycle[0].region
        if region < 0 or start.v != v or any(p.region != region for p in cycle):
            if abs(start.xi - xi) > tol_x:
                continue
            region = -1
        cum, lo, hi = 0.0, 0.0, 0.0
        for p in cycle:
            lo, hi = min(lo, cum + p.lo), max(hi, cum + p.hi)
            cum += p.dxp
        return k, (cum if region >= 0 else 0.0), region, lo, hi
    return None


def _skippable_cycles(zone, w, region, xi, advance, lo, hi, cycles):
    """How many of ``cycles`` repeats keep the mass inside its region of constant friction
    (one cycle of margin: the following cycle is simulated normally)."""
    if not zone or advance == 0.0:
        return cycles
    if region == LOW and advance > 0.0:
        room = -(xi + hi)
    elif region == HIGH and advance < 0.0:
        room = xi + lo - w
    else:
        return cycles                     # moving away from the zone
    return max(0, min(cycles, math.floor(room / abs(advance)) - 1))


def _region_of_mask(regions):
    return {1 << LOW: LOW, 1 << HIGH: HIGH}.get(regions, -1)


def solve(scene, options: dict) -> Trajectory:
    """Simulate ``scene`` with the exact event-driven solver (module docstring)."""
    tol, max_events = _check_options(options)
    profile, surface = scene.profile, scene.surface
    stepper = _make_stepper(profile, surface, scene.phase)
    cpu0 = time.process_time()
    origin = float(_origin(surface, scene.x0))
    dt = stepper.dt
    recording = scene.record.dense or scene.record.events
    if recording:
        stepper.record = ([], [])
    until_rest = scene.until == "rest"
    stepper.stop_at_rest = until_rest
    max_acc = stepper.max_acc
    info = {"origin": origin}
    if isinstance(surface, StopZone):
        info["x_stick_min"] = surface.x_stick_min(max_acc)
        if until_rest:
            stepper.watch_accumulation(tol)
    # Near-repeat tolerances (module docstring); none while a slow accumulation may be under way.
    scale_x = _NEAR * (stepper.w if stepper.zone else 0.0)
    scale_v = _NEAR * max_acc * dt
    total = scene.horizon_periods
    history = deque(maxlen=_CYCLE_MAX)
    events = skipped = 0
    status, message = None, ""
    try:
        code = stepper.start(scene.x0 - origin, scene.v0)
        while code == _DONE and stepper.period < total:
            start = (stepper.v, stepper.mode, stepper.xi)
            code = stepper.run_period(max_events - events)
            events += stepper.events
            if code != _DONE:
                break
            history.append(_PeriodRecord(*start, stepper.dxp, stepper.lo, stepper.hi,
                                         _region_of_mask(stepper.regions)))
            if stepper.period >= total:
                break
            near = 0.0 if stepper.may_accumulate() else 1.0
            cycle = _find_cycle(history, stepper.v, stepper.mode, stepper.xi,
                                near * (scale_x + _NEAR * abs(stepper.xi)),
                                near * (scale_v + _NEAR * abs(stepper.v)))
            if cycle is None:
                continue
            k, advance, region, lo, hi = cycle
            if until_rest:
                if region < 0:
                    status = Status.NEVER_STOPS
                    message = (f"never stops: the state at the period boundary repeats every {k} period(s) "
                               f"with no net progress (periodic motion at x = {origin + stepper.xi!r})")
                elif not stepper.zone or (region == LOW and advance <= 0.0) or (region == HIGH and advance >= 0.0):
                    where = {LOW: "on the low-friction surface" if stepper.zone else "on a uniform surface",
                             HIGH: "in the high-friction region (c_mu < max|y''|: it walks through)"}[region]
                    status = Status.NEVER_STOPS
                    message = (f"never stops: steady motion {where} with net advance {advance / k!r} per "
                               f"period" + (" (never reaches the stop zone)" if region == LOW and stepper.zone
                                            else ""))
                if status is not None:
                    info.update(net_advance=advance / k, cycle_periods=k)
                    break
            if recording:
                continue
            cycles = (total - stepper.period) // k
            if region >= 0:
                cycles = _skippable_cycles(stepper.zone, stepper.w, region, stepper.xi, advance, lo, hi, cycles)
                stepper.xi += cycles * advance
            if cycles > 0:
                stepper.period += cycles * k
                skipped += cycles * k
                history.clear()
    except (ArithmeticError, ValueError) as exc:
        code, status = None, Status.ERROR
        message = f"arithmetic failure at period {stepper.period}: {exc}"

    n_end, tau_end = _norm_time(*stepper.stop, dt) if code != _DONE else (stepper.period, stepper.tau0)
    x_rel, v_end = stepper.xi, stepper.v
    if code == _REST:
        status = Status.REST
        message = (f"at rest for good: stuck at x = {origin + x_rel!r} where mu_bar = {stepper.mu(x_rel)!r} "
                   f">= max|y''| = {max_acc!r}")
    elif code == _ACCUMULATION:
        sticks = stepper.zone_sticks
        contraction = ((sticks[-1] - sticks[-2]) / (sticks[-2] - sticks[-3])
                       if len(sticks) >= 3 and sticks[-2] > sticks[-3] else None)
        status = Status.ACCUMULATION
        info.update(limit=origin + stepper.xs_rel, contraction=contraction,
                    stick_events=stepper.zone_stick_count, periods=n_end, last_stick=origin + sticks[-1],
                    remaining=stepper.xs_rel - sticks[-1])
        message = (f"accumulation: stick positions in the transition zone converge to x_stick_min = "
                   f"{info['limit']!r} (eq. 41); the last one is {info['remaining']!r} before it "
                   f"(<= accumulation_tol), contraction {contraction!r}")
        x_rel, v_end = stepper.xs_rel, 0.0
    elif code == _BUDGET:
        status = Status.ERROR
        message = f"max_events = {max_events} reached at period {n_end}, tau = {tau_end!r}; raise max_events"
    elif code == _STALL:
        status = Status.ERROR
        message = (f"event loop stalled: more than {_STALL_EVENTS} successive events without time advancing "
                   f"at period {n_end}, tau = {tau_end!r}")
    elif status is None:
        status = Status.HORIZON
        message = f"simulated {stepper.period} periods ({skipped} by steady-state fast-forward)"
        if until_rest:
            message = f"no final outcome within max_periods = {total} periods"
    if not (math.isfinite(x_rel) and math.isfinite(v_end)):
        status, message = Status.ERROR, f"non-finite state (x_rel = {x_rel!r}, v = {v_end!r}); {message}"
        x_rel, v_end = 0.0, 0.0
    info.update(x_rel_end=x_rel, fast_forward_periods=skipped, at_rest=stepper.at_rest)

    series, log = {}, None
    if recording and code is not None:          # None: arithmetic failure, the record is unusable
        arcs_list, events_list = stepper.record
        if scene.record.dense:
            end_arc = stepper.current_arc(n_end, tau_end)
            series = _dense_series(scene, stepper, arcs_list + [end_arc], origin)
        if scene.record.events:
            log = _event_log(events_list, origin, dt)
    return Trajectory(
        x_end=float(origin + x_rel), v_end=float(v_end), period_end=int(n_end), tau_end=float(tau_end),
        status=status, message=message, method="exact", options=dict(options), series=series, events=log,
        stats={"events": events, "steps": events, "cpu_time": time.process_time() - cpu0}, info=info,
    )


def _event_log(events_list, origin, dt):
    log = np.zeros(len(events_list), dtype=EVENT_DTYPE)
    for i, (kind, n, tau, xi, v, _, mode, _, _) in enumerate(events_list):
        n, tau = _norm_time(n, tau, dt)
        log[i] = (kind, n, tau, origin + xi, v, mode)
    return log


def _dense_series(scene, stepper, arc_list, origin):
    """Samples on the grid t = phase dt + j dt / spp plus every event (the state after it:
    each arc contributes its start and the grid points strictly inside it), then the end."""
    profile = scene.profile
    dt, tau0 = stepper.dt, stepper.tau0
    spp = int(scene.record.samples_per_period)
    h = dt / spp
    cols = list(zip(*arc_list))
    kind = np.array(cols[0], dtype=int)
    n = np.array(cols[1], dtype=float)
    tau, dur, xi0, v0, acc0, a, om = (np.array(c, dtype=float) for c in cols[2:9])
    mode = np.array(cols[9], dtype=np.int8)
    keep = dur > 0.0
    keep[-1] = True                                   # the end state
    idx0 = np.flatnonzero(keep)
    off = tau[idx0] - tau0                            # offset from the period boundary
    base = n[idx0] - (off < 0.0)
    off = np.where(off < 0.0, off + dt, off)
    j_lo = np.floor(off / h).astype(int) + 1
    j_hi = np.minimum(np.ceil((off + dur[idx0]) / h).astype(int) - 1, spp - 1)
    count = 1 + np.maximum(0, j_hi - j_lo + 1)
    count[-1] = 1
    which = np.repeat(np.arange(idx0.size), count)
    rank = np.arange(which.size) - np.repeat(np.cumsum(count) - count, count)
    j = j_lo[which] + rank - 1
    idx = idx0[which]
    s = np.where(rank == 0, 0.0, np.clip(j * h - off[which], 0.0, dur[idx]))
    t = np.where(rank == 0, n[idx] * dt + tau[idx], tau0 + (base[which] * spp + j) * h)
    tt = tau[idx] + s                                 # profile time (period-reduced by the profile)
    x = np.empty(idx.size)
    v = np.empty(idx.size)
    xdd = np.empty(idx.size)
    ydd = a[idx].copy()
    for k in np.unique(kind[idx]).tolist():
        m = kind[idx] == k
        i = idx[m]
        if k == SMOOTH:
            sig = mode[i].astype(float)
            ss = s[m]
            y0, yd0 = profile.position(tau[i]), profile.velocity(tau[i])
            dx = v0[i] * ss - 0.5 * sig * ss * ss - (profile.position(tt[m]) - y0 - yd0 * ss)
            v[m] = v0[i] - sig * ss - (profile.velocity(tt[m]) - yd0)
            ydd[m] = profile.acceleration(tt[m])
            xdd[m] = -ydd[m] - sig
        else:
            dx, vv = arcs.step(k, om[i], v0[i], acc0[i], s[m], xp=np)
            v[m] = vv
            xdd[m] = arcs.acceleration(k, getattr(stepper, "b1", 0.0), acc0[i], dx)
            if k == STICK:
                ydd[m] = np.where(np.isnan(a[i]), profile.acceleration(tt[m]), a[i])
        x[m] = xi0[i] + dx
    available = {
        "x": lambda: origin + x,
        "v": lambda: v,
        "y": lambda: np.asarray(profile.position(tt), dtype=float),
        "yd": lambda: np.asarray(profile.velocity(tt), dtype=float),
        "ydd": lambda: ydd,
        "friction": lambda: -(xdd + ydd),             # F = -(x'' + y''), eq. (5)
        "mode": lambda: mode[idx],
    }
    out = {"t": t}
    out.update({name: available[name]() for name in scene.record.series})
    return out
