"""The compiled event kernel: steppers and the one driver, for one trajectory or many.

Load it through :func:`selfalign.solvers.jit.kernel` (which sets numba's cache
directory first); importing this module compiles nothing until a function is called.

Layout.  Every trajectory is one :data:`~selfalign.solvers.records.MEMBER_DTYPE`
record; :func:`run_members` drives each member of an array of them with
:func:`drive`, the same code for one trajectory (``selfalign.simulate``) and for a
batch, so scalar and batch results are bit-identical by construction.  :func:`drive`
owns the horizon, the outcome decisions and the steady-state fast-forward; a stepper
advances one member by one period:

* :func:`_period_piecewise`: the exact event-driven solver on a piecewise-constant
  profile, closed-form arcs and event times of :mod:`selfalign.model.arcs`;
* :func:`_period_smooth`: the exact solver on a Fourier or a piecewise-linear-y''
  (finite-jerk) profile, uniform surface: closed form in the profile, event times
  bracketed on a grid and refined by Brent's method (:func:`_brent`) to ~1 ulp;
* :func:`_period_moreau`: Moreau time-stepping with the table impulse of each step
  integrated exactly (:mod:`selfalign.solvers.moreau`).

The friction law and the arcs are the functions of :mod:`selfalign.model` themselves
(registered with numba when :mod:`selfalign.solvers.jit` loads this module).

Positions are relative to an origin (x_mu on a stop zone, else x0), so that x_mu = 1e6
costs no accuracy in the zone; time is (period n, tau in [0, dt)), period boundaries
at the start phase tau0.

Tie rules of the exact solver (they make every zero-length step change the mode, so
there is no Zeno loop):

1. |y''| = mu_bar counts as stick.
2. v = 0 and a zone crossing at the same time: the v = 0 event wins (mu_bar is
   continuous, so no crossing is needed to decide the mode).
3. v = 0 exactly at a break (grazing): the v = 0 event is handled first with the
   ending piece's y'', then the break re-decides the mode with the new piece's y''.
4. A slip velocity of the wrong sign (rounding, at most a few ulp) is set to 0 at
   the start of an arc; an arc that decelerates from v = 0 then ends at once with a
   v = 0 event, which always changes the mode.
5. A mass exactly on a zone boundary belongs to the region it moves into (stuck:
   x = x_mu counts as low friction, x = x_mu + w as high friction).

Outcome decisions (:func:`drive`, README "Solvers"): REST at a stick where
mu_bar(x) >= the stepper's rest acceleration (max|y''|; Moreau: max|impulse| / h);
ACCUMULATION at a stick in the transition zone above the previous zone stick and within
``acc_tol`` of x_stick_min (eq. 41); NEVER_STOPS when the period-boundary state repeats
(exactly, or to NEAR_ULPS ulp while the mass moved MOTION_FACTOR times that tolerance
in between) with no progress, or repeats in one region of constant friction while the
mass walks away from the zone or through it; HORIZON at the horizon; ERROR on the event
budget, a stall or an overflow.  A bit-exact repeat of the period-boundary state is
also fast-forwarded (skipped in whole cycles) unless a recording is asked for.
"""

from __future__ import annotations

import math

import numpy as np
from numba import literally, njit, types
from numba.extending import intrinsic, overload

from ..model import arcs as A
from ..model import friction as F
from . import records as R
from .outcomes import ACC_TOL_ULPS, HIGH, LOW, MOTION_FACTOR, NEAR_ULPS, STALL_EVENTS, ZONE, EventKind, Reason

jit = njit(cache=True, error_model="numpy", nogil=True)
inlined = njit(cache=True, error_model="numpy", nogil=True, inline="always")


def borrowed(array):
    """``array`` itself, for use inside the kernel without reference counting (below)."""
    return array


@intrinsic
def _without_refcount(typingctx, array):
    def codegen(context, builder, signature, args):
        view = context.make_array(signature.args[0])(context, builder, value=args[0])
        view.meminfo = context.get_constant_null(types.MemInfoPointer(types.voidptr))
        return view._getvalue()
    return array(array), codegen


@overload(borrowed)
def _borrowed(array):
    """Compiled, a view of ``array`` with no memory-info pointer: numba increments and
    decrements the reference count of every array argument at every call (an atomic
    operation each, ~10 per period), and skips both for a NULL memory-info.  Safe because
    the entry points' callers hold the arrays for the whole kernel call."""
    return lambda array: _without_refcount(array)


@jit
def _borrowed_all(table, bnd, cross, hist, arcs, events, samples, steps):
    """:func:`borrowed` of every array an entry point passes down to :func:`drive`."""
    return (borrowed(table), borrowed(bnd), borrowed(cross), borrowed(hist), borrowed(arcs), borrowed(events),
            borrowed(samples), borrowed(steps))


_INF = math.inf
_EPS = 2.0 ** -52
_NAN = math.nan

# Reason codes as plain ints (compile-time constants for numba).
_ACCUMULATION = int(Reason.ACCUMULATION)
_BOUNDED = int(Reason.BOUNDED)
_FIRST_STICK = int(Reason.FIRST_STICK)
_MAX_EVENTS = int(Reason.MAX_EVENTS)
_MAX_PERIODS = int(Reason.MAX_PERIODS)
_NONFINITE = int(Reason.NONFINITE)
_PERIODIC = int(Reason.PERIODIC)
_PERIODS = int(Reason.PERIODS)
_REST = int(Reason.REST)
_STALL = int(Reason.STALL)
_WALK_BACKWARD = int(Reason.WALK_BACKWARD)
_WALK_FORWARD = int(Reason.WALK_FORWARD)

# Stepper results (period functions).
DONE, STOP_REST, STOP_ACCUMULATION, STOP_FIRST_STICK, STOP_BUDGET, STOP_STALL = 0, 1, 2, 3, 4, 5

#: Evaluations of Brent's method at most per event time (it needs ~10 to 1 ulp).
BRENT_MAX_ITER = 200
#: Grid intervals per piece of a piecewise-linear-y'' profile, for the smooth stepper and the
#: stop-zone stepper's brackets (which add as many per harmonic period): between two grid points
#: the slip velocity has at most one extremum, which is tested where it can be a zero
#: (:func:`_slip_minimum`, :func:`_jerk_arc_end`).
GRID_PER_PIECE = 16

_SWITCH, _STICK, _SLIP, _REVERSAL, _ZONE = (int(EventKind.SWITCH), int(EventKind.STICK), int(EventKind.SLIP),
                                            int(EventKind.REVERSAL), int(EventKind.ZONE))
_QUADRATIC, _HARMONIC, _HYPERBOLIC, _STICK_ARC, _SMOOTH = A.QUADRATIC, A.HARMONIC, A.HYPERBOLIC, A.STICK, A.SMOOTH


# ----------------------------------------------------------------------------------------
# Recording (scalar runs only).  The buffers are sized by the caller and never reassigned
# here (a loop-carried array costs reference counting in every iteration); a record past
# the end is only counted, and the caller runs again with buffers of the counted size.
# ----------------------------------------------------------------------------------------

@jit
def _norm(n, tau, dt):
    """(period, tau) with tau in [0, dt): an event at the very end of a period starts the next."""
    if tau >= dt:
        return n + 1, tau - dt
    return n, tau


@jit
def _record_arc(arcs, s, dt, kind, n, tau, dur, xi, v, acc, a, om, mode, region):
    k = s.n_arcs
    if k < arcs.shape[0]:
        r = arcs[k]
        r.kind = kind
        r.period, r.tau = _norm(n, tau, dt)
        r.duration, r.x, r.v, r.acc, r.table_acc, r.omega, r.mode, r.region = dur, xi, v, acc, a, om, mode, region
    s.n_arcs = k + 1


@jit
def _record_event(events, s, dt, kind, n, tau, xi, v, mode_before, mode_after, acc_before, acc_after):
    k = s.n_events
    if k < events.shape[0]:
        r = events[k]
        r.kind = kind
        r.period, r.tau = _norm(n, tau, dt)
        r.x, r.v, r.mode_before, r.mode = xi, v, mode_before, mode_after
        r.acc_before, r.acc_after = acc_before, acc_after
    s.n_events = k + 1


@jit
def _record_sample(samples, s, n, tau, xi, v, mode):
    k = s.n_samples
    if k < samples.shape[0]:
        r = samples[k]
        r.period, r.tau, r.x, r.v, r.mode = n, tau, xi, v, mode
    s.n_samples = k + 1


# ----------------------------------------------------------------------------------------
# Friction field and stick outcomes (shared by every stepper)
# ----------------------------------------------------------------------------------------

@jit
def _mu(s, xi):
    """mu_bar at xi (eqs. 7-9; 1 on a uniform surface)."""
    if not s.zone:
        return 1.0
    return F.coefficient(xi, s.w, s.c_mu)


@jit
def _region(s, xi, mode):
    """Region of an arc starting at xi in ``mode`` (tie rule 5)."""
    if not s.zone:
        return LOW
    if xi < 0.0 or (xi == 0.0 and mode <= 0):
        return LOW
    if xi > s.w or (xi == s.w and mode >= 0):
        return HIGH
    return ZONE


@jit
def _holds(s, mu):
    """Whether friction mu_bar holds a stuck mass for good: r mu_bar >= max|y''| (exact
    solvers; r = mu_s / mu_k, 1 for the paper's Coulomb law).  Moreau passes its own test,
    the step's (:func:`_period_moreau`)."""
    return s.static_ratio * mu >= s.rest_acc


@jit
def _on_stick(s, xi, mu, n, tau, until, holds):
    """Bookkeeping at a stick event at xi (friction mu); a non-zero result ends the run.

    REST where ``holds`` (the friction holds the mass for good, :func:`_holds`);
    ACCUMULATION (until='rest') at a stick in the transition zone above the previous one
    and within acc_tol of x_stick_min; FIRST_STICK for until='stick'.
    """
    s.sticks += 1
    if s.zone and xi >= 0.0:
        s.zone_sticks += 1
        if s.first_stick_n < 0:
            s.first_stick_xi, s.first_stick_n, s.first_stick_tau = xi, n, tau
    if holds:
        s.at_rest = True
        if until != R.UNTIL_PERIODS:
            return STOP_REST
        return DONE
    if until == R.UNTIL_REST and s.zone and 0.0 <= xi <= s.w:
        if s.nh >= 1 and xi > s.h1 and s.xs - xi <= s.acc_tol:
            if s.nh >= 2 and s.h1 > s.h2:
                s.contraction = (xi - s.h1) / (s.h1 - s.h2)
            s.last_stick = xi
            return STOP_ACCUMULATION
        s.h2 = s.h1
        s.h1 = xi
        s.nh = min(s.nh + 1, 2)
    if until == R.UNTIL_STICK:
        return STOP_FIRST_STICK
    return DONE


@inlined
def _next_boundary(bnd, cross):
    """The lowest boundary not crossed yet (inf if none): an arc that ends below it crosses
    nothing, so the steppers call :func:`_crossed` only for an arc that reaches it."""
    lowest = _INF
    for j in range(bnd.shape[0]):
        if cross[j].period < 0 and bnd[j] < lowest:     # NaN: a boundary that does not exist
            lowest = bnd[j]
    return lowest


@jit
def _crossed(s, bnd, cross, kind, om, xi0, v0, acc0, xi1, v1, n, tau, dur):
    """First crossings of the boundaries ``bnd`` by an arc from (xi0, v0) to (xi1, v1) of
    duration ``dur`` starting at (n, tau): the time in closed form on exact arcs, at the
    step end on smooth arcs and Moreau steps.  Returns the next boundary (:func:`_next_boundary`)."""
    for j in range(bnd.shape[0]):
        c = cross[j]
        if c.period >= 0 or not xi1 >= bnd[j]:      # NaN: a boundary that does not exist
            continue
        if xi0 >= bnd[j]:
            sc, vc = 0.0, v0
        elif kind == _SMOOTH or kind == _STICK_ARC:
            sc, vc = dur, v1
        else:
            sc = min(A.crossing_time(kind, om, v0, acc0, xi0 - bnd[j]), dur)
            vc = v1 if sc == dur else A.step(kind, om, v0, acc0, sc)[1]
        c.period = n
        c.tau = tau + sc
        c.v = vc
        c.sticks = s.zone_sticks
    return _next_boundary(bnd, cross)


@jit
def _load(s):
    """(x, v, mode, period, events, path, xi_max) of the member record at a period start, and
    zeroed running totals of the period (dxp, lo, hi, regions, stalled): :func:`_save`'s inverse."""
    return s.xi, s.v, s.mode, s.n, s.events, s.path, s.xi_max, 0.0, 0.0, 0.0, 0, 0


@jit
def _save(s, events, path, xi_max, dxp, lo, hi, regions):
    """Write a period's running totals back to the member record."""
    s.events, s.path, s.xi_max = events, path, xi_max
    s.dxp, s.lo, s.hi, s.regions = dxp, lo, hi, regions


@jit
def _stop(s, code, xi, v, mode, n, tau, dt):
    s.xi, s.v, s.mode = xi, v, mode
    s.stop_n, s.stop_tau = _norm(n, tau, dt)
    return code


# ----------------------------------------------------------------------------------------
# Exact stepper, piecewise-constant profiles
# ----------------------------------------------------------------------------------------

@jit
def _pw_piece(row, tau):
    """Index of the piece holding phase ``tau`` (right-continuous) of a piecewise-constant or
    piecewise-linear-y'' row (m or -m pieces in its first data column)."""
    m = abs(int(row[R.DATA]))
    i = 0
    while i + 1 < m and row[R.DATA + 2 + i] <= tau:
        i += 1
    return i


@inlined
def _segment(row, m, i0, tau0, tail, j):
    """(piece, start phase, length, period offset, starts at a break) of segment j of the period
    from tau0 (``tail``: tau0 is inside piece i0): the rest of piece i0, the following pieces,
    then (next period) the pieces before i0 and the head of piece i0.  The breaks of a
    profile row with m pieces start at column DATA + 1 (piecewise-constant and -linear)."""
    b0 = R.DATA + 1
    if j == 0:
        return i0, tau0, row[b0 + i0 + 1] - tau0, 0, not tail
    if j < m:
        p = i0 + j
        dn = 0
        if p >= m:
            p -= m
            dn = 1
        return p, row[b0 + p], row[b0 + p + 1] - row[b0 + p], dn, True
    return i0, row[b0 + i0], tau0 - row[b0 + i0], 1, True


@jit
def _arc_params(s, xi, mode, a):
    """(kind, region, mu_bar, x'') of the arc starting at xi in ``mode`` under y'' = a."""
    r = _region(s, xi, mode)
    if r == LOW:
        mu = 1.0
    elif r == HIGH:
        mu = s.c_mu
    else:
        mu = F.coefficient(xi, s.w, s.c_mu)
    if mode == 0:
        return _STICK_ARC, r, mu, 0.0
    kind = _QUADRATIC if r != ZONE else (_HARMONIC if mode > 0 else _HYPERBOLIC)
    return kind, r, mu, -a - mode * mu


@jit
def _harmonic_reaches(xi, v, acc0, b1, om, xb):
    """False only if a harmonic arc from (xi, v) provably stays below xb: its largest x is
    the centre xi + acc0 / b1 plus the amplitude (a margin of 1e-9 covers rounding)."""
    centre = xi + acc0 / b1
    amplitude = math.sqrt((acc0 / b1) ** 2 + (v / om) ** 2)
    return centre + amplitude >= xb - 1e-9 * (abs(centre) + amplitude + abs(xb))


@inlined
def _period_piecewise(s, row, until, max_events, bnd, cross, record, arcs, events):
    """Advance member ``s`` from the period boundary (n, tau0) to (n + 1, tau0)."""
    dt = row[R.DT]
    m = int(row[R.DATA])
    b0 = R.DATA + 1
    a0 = R.DATA + 2 + m
    tau0 = s.tau0
    i0 = s.piece0
    tail = tau0 > row[b0 + i0]
    nseg = m + 1 if tail else m
    zone, w, om, b1 = s.zone, s.w, s.omega, s.b1
    r_static = s.static_ratio               # stick while |y''| <= r mu_bar; slip arcs use mu_bar
    lowest = _next_boundary(bnd, cross)
    xi, v, mode, n, count, path, xi_max, dxp, lo, hi, regions, stalled = _load(s)
    fresh = s.fresh
    s.fresh = False
    for j in range(nseg):
        p, ts, seg, dn, at_break = _segment(row, m, i0, tau0, tail, j)
        a = row[a0 + p]
        nn = n + dn
        s0 = 0.0
        if at_break and not fresh:
            count += 1
            if v * mode < 0.0:
                v = 0.0
            if record:
                acc_b = _arc_params(s, xi, mode, row[a0 + (p - 1 if p > 0 else m - 1)])[3]   # the piece before
                acc_a = _arc_params(s, xi, mode, a)[3]
                _record_event(events, s, dt, _SWITCH, nn, ts, xi, v, mode, mode, acc_b, acc_a)
            if mode == 0 or v == 0.0:            # tie rule 3: re-decide at v = 0
                mu = _mu(s, xi)
                new = F.decide_mode(a, r_static * mu)
                if new != mode:
                    count += 1
                    if record:
                        kind_e = _SLIP if mode == 0 else (_STICK if new == 0 else _REVERSAL)
                        _record_event(events, s, dt, kind_e, nn, ts, xi, 0.0, mode, new,
                                               _arc_params(s, xi, mode, a)[3], _arc_params(s, xi, new, a)[3])
                    mode = new
                    if new == 0:
                        code = _on_stick(s, xi, mu, nn, ts, until, _holds(s, mu))
                        if code != DONE:
                            _save(s, count, path, xi_max, dxp, lo, hi, regions)
                            return _stop(s, code, xi, 0.0, 0, nn, ts, dt)
                v = 0.0
            if count >= max_events:
                _save(s, count, path, xi_max, dxp, lo, hi, regions)
                return _stop(s, STOP_BUDGET, xi, v, mode, nn, ts, dt)
        fresh = False
        while mode != 0:
            if v * mode < 0.0:                  # tie rule 4
                v = 0.0
            kind, r, mu, acc0 = _arc_params(s, xi, mode, a)
            regions |= 1 << r
            rem = seg - s0
            s_b = _INF
            xb = 0.0
            om_arc = 0.0
            if kind == _QUADRATIC:
                s_v = -v / acc0 if acc0 * mode < 0.0 else _INF
                if zone and (r == LOW) == (mode > 0):
                    xb = 0.0 if r == LOW else w
                    s_b = A.crossing_time(_QUADRATIC, 0.0, v, acc0, xi - xb)
            else:
                om_arc = om
                s_v = A.zero_velocity_time(kind, om, mode, v, acc0)
                xb = w if mode > 0 else 0.0
                if kind == _HYPERBOLIC or _harmonic_reaches(xi, v, acc0, b1, om, xb):
                    s_b = A.crossing_time(kind, om, v, acc0, xi - xb)
            if s_v <= s_b and s_v <= rem:       # tie rules 2, 3
                dur, ev = s_v, 1
            elif s_b <= rem:
                dur, ev = s_b, 2
            else:
                dur, ev = rem, 0
            dx, v1 = A.step(kind, om_arc, v, acc0, dur)
            if record:
                _record_arc(arcs, s, dt, kind, nn, ts + s0, dur, xi, v, acc0, a, om_arc, mode, r)
            xi_new = xb if ev == 2 else xi + dx
            path += abs(xi_new - xi)
            if xi_new > xi_max:
                xi_max = xi_new
            if xi_new >= lowest:
                lowest = _crossed(s, bnd, cross, kind, om_arc, xi, v, acc0, xi_new, 0.0 if ev == 1 else v1, nn,
                                  ts + s0, dur)
            if ev == 0:
                dxp += dx
                xi = xi_new
                v = v1
                if dxp > hi:
                    hi = dxp
                elif dxp < lo:
                    lo = dxp
                break
            s0 += dur
            count += 1
            stalled = stalled + 1 if dur == 0.0 else 0
            if stalled > STALL_EVENTS:
                _save(s, count, path, xi_max, dxp, lo, hi, regions)
                return _stop(s, STOP_STALL, xi, v, mode, nn, ts + s0, dt)
            if ev == 2:                         # zone crossing: land exactly on the boundary
                dxp += xb - xi
                xi = xb
                v = v1
                if record:
                    _record_event(events, s, dt, _ZONE, nn, ts + s0, xi, v, mode, mode,
                                           A.acceleration(kind, b1, acc0, dx), _arc_params(s, xi, mode, a)[3])
            else:                               # v = 0: stick or reverse (tie rule 1)
                dxp += dx
                xi = xi_new
                v = 0.0
                mu = _mu(s, xi)
                new = F.decide_mode(a, r_static * mu)
                if record:
                    _record_event(events, s, dt, _STICK if new == 0 else _REVERSAL, nn, ts + s0, xi,
                                           0.0, mode, new, A.acceleration(kind, b1, acc0, dx),
                                           _arc_params(s, xi, new, a)[3])
                mode = new
                if new == 0:
                    code = _on_stick(s, xi, mu, nn, ts + s0, until, _holds(s, mu))
                    if code != DONE:
                        _save(s, count, path, xi_max, dxp, lo, hi, regions)
                        return _stop(s, code, xi, 0.0, 0, nn, ts + s0, dt)
            if dxp > hi:
                hi = dxp
            elif dxp < lo:
                lo = dxp
            if count >= max_events:
                _save(s, count, path, xi_max, dxp, lo, hi, regions)
                return _stop(s, STOP_BUDGET, xi, v, mode, nn, ts + s0, dt)
        if mode == 0:
            r = _region(s, xi, 0)
            regions |= 1 << r
            if record:
                _record_arc(arcs, s, dt, _STICK_ARC, nn, ts + s0, seg - s0, xi, 0.0, 0.0, a, 0.0, 0, r)
    s.xi, s.v, s.mode, s.n = xi, v, mode, n + 1
    _save(s, count, path, xi_max, dxp, lo, hi, regions)
    return DONE


# ----------------------------------------------------------------------------------------
# Exact stepper, smooth profiles: Fourier, or y'' piecewise linear (uniform surface)
# ----------------------------------------------------------------------------------------

@jit
def _fourier(row, t):
    """(y, y', y'') of the Fourier profile in ``row`` at time t."""
    k = int(row[R.DATA])
    y = 0.0
    yd = 0.0
    ydd = 0.0
    for i in range(k):
        a, b, om = row[R.DATA + 1 + i], row[R.DATA + 1 + k + i], row[R.DATA + 1 + 2 * k + i]
        c, sn = math.cos(om * t), math.sin(om * t)
        y += a * c + b * sn
        yd += om * (b * c - a * sn)
        ydd -= om * om * (a * c + b * sn)
    return y, yd, ydd


@jit
def _ramp(row, i, value):
    """``value``, a y'' of piece i of a piecewise-linear-y'' row, kept within the piece's range
    [min(a_i, e_i), max(a_i, e_i)] (start value a_i, end value e_i: the profile's ``ends``): a
    ramp's a + j s, its break times rounded, would otherwise pass the level it ends on."""
    m = -int(row[R.DATA])
    a, e = row[R.DATA + 2 + m + i], row[R.DATA + 2 + 5 * m + i]
    return min(max(value, min(a, e)), max(a, e))


@jit
def _piecewise_linear(row, t):
    """(y, y', y'') of the piecewise-linear-y'' profile in ``row`` at time t in [0, 2 dt)."""
    dt = row[R.DT]
    m = -int(row[R.DATA])
    b0 = R.DATA + 1
    tau = t - dt if t >= dt else t
    i = 0
    while i + 1 < m and row[b0 + i + 1] <= tau:
        i += 1
    s = tau - row[b0 + i]
    a, j = row[b0 + m + 1 + i], row[b0 + 2 * m + 1 + i]
    yd, y = row[b0 + 3 * m + 1 + i], row[b0 + 4 * m + 1 + i]
    return y + s * (yd + s * (a / 2.0 + s * j / 6.0)), yd + s * (a + s * j / 2.0), _ramp(row, i, a + j * s)


@jit
def _table_motion(row, t):
    """(y, y', y'') of the smooth stepper's profile ``row`` (a Fourier row has K > 0 in its
    first data column, a piecewise-linear one -m)."""
    if row[R.DATA] > 0.0:
        return _fourier(row, t)
    return _piecewise_linear(row, t)


@jit
def _event_function(kind, row, t0, s, sign, v, s0, yd0, limit):
    """Event functions of the smooth stepper: kind 0, |y''| crossing the stick limit
    ``limit`` = r mu_bar = r upwards while stuck (sign sgn(y'')); kind 1, the relative
    velocity of a slip in direction ``sign`` from (s0, v): x' = v - sign (s - s0) -
    (y'(t0 + s) - y'(t0 + s0)), signed."""
    y, yd, ydd = _table_motion(row, t0 + s)
    if kind == 0:
        return sign * ydd - limit
    return sign * (v - sign * (s - s0) - (yd - yd0))


@jit
def _brent(kind, row, t0, sign, v, s0, yd0, limit, xa, xb, xtol, rtol):
    """Root of :func:`_event_function` in [xa, xb] (a sign change) by Brent's method, as
    scipy.optimize.brentq (same steps), to |error| <= xtol + rtol |x|."""
    xpre, xcur = xa, xb
    xblk = 0.0
    fblk = 0.0
    spre = 0.0
    scur = 0.0
    fpre = _event_function(kind, row, t0, xpre, sign, v, s0, yd0, limit)
    fcur = _event_function(kind, row, t0, xcur, sign, v, s0, yd0, limit)
    if fpre == 0.0:
        return xpre
    if fcur == 0.0:
        return xcur
    for _ in range(BRENT_MAX_ITER):
        if fpre != 0.0 and fcur != 0.0 and (fpre < 0.0) != (fcur < 0.0):
            xblk, fblk = xpre, fpre
            spre = scur = xcur - xpre
        if abs(fblk) < abs(fcur):
            xpre, xcur, xblk = xcur, xblk, xcur
            fpre, fcur, fblk = fcur, fblk, fcur
        delta = 0.5 * (xtol + rtol * abs(xcur))
        sbis = 0.5 * (xblk - xcur)
        if fcur == 0.0 or abs(sbis) < delta:
            return xcur
        if abs(spre) > delta and abs(fcur) < abs(fpre):
            if xpre == xblk:
                stry = -fcur * (xcur - xpre) / (fcur - fpre)
            else:
                dpre = (fpre - fcur) / (xpre - xcur)
                dblk = (fblk - fcur) / (xblk - xcur)
                stry = -fcur * (fblk * dblk - fpre * dpre) / (dblk * dpre * (fblk - fpre))
            if 2.0 * abs(stry) < min(abs(spre), 3.0 * abs(sbis) - delta):
                spre, scur = scur, stry
            else:
                spre, scur = sbis, sbis
        else:
            spre, scur = sbis, sbis
        xpre, fpre = xcur, fcur
        if abs(scur) > delta:
            xcur += scur
        else:
            xcur += delta if sbis > 0.0 else -delta
        fcur = _event_function(kind, row, t0, xcur, sign, v, s0, yd0, limit)
    return xcur


@jit
def _slip_sign_point(row, t0, sign, v, s0, yd0, limit, right):
    """A point of (s0, right) where the slip from rest at s0 in direction ``sign`` has the
    slip's sign (found by halving from ``right``, the first tries nearest it); s0 if there is
    none above 2^-60 (right - s0).  Its velocity is 0 at s0 and x'' has the slip's sign there
    (|y''| > r mu_bar), so such a point exists unless the slip has no length."""
    p = right
    for _ in range(60):
        p = s0 + 0.5 * (p - s0)
        if _event_function(1, row, t0, p, sign, v, s0, yd0, limit) > 0.0:
            return p
    return s0


@jit
def _past_jump(row, t0, sign, limit, q, xtol):
    """Where a stuck mass starts to slip when y'' jumps past the limit at the break q of a
    piecewise-linear-y'' row (y'' is linear between grid points, and the limit is not reached
    before q from the left): q, or the first point a few ulps on where the profile evaluates to
    the new piece (q + t0 may round below the break).  Brent's method would converge to either
    side of the jump, and a slip started on its near side ends at once and sticks again there."""
    root = q
    for _ in range(8):
        if _event_function(0, row, t0, root, sign, 0.0, 0.0, 0.0, limit) >= 0.0:
            break
        root += 0.5 * xtol
    return root


@jit
def _slip_minimum(row, t0, sigma, p, q, g_p, slope_p, g_q, slope_q, xtol, rtol):
    """The interior minimum of the slip velocity G = sigma x' on the grid interval [p, q] of
    :func:`_period_smooth` (G(p), G(q) > 0 and G'(p) = ``slope_p`` < 0 given), or -1 if G has
    none there: only there can G vanish between two grid points of the slip's sign.

    Piecewise-linear y'': the interval lies in one piece (the grid holds the breaks), where
    G' = -1 - sigma y'' is linear, so G is the quadratic through G(p), G'(p) and G(q); its
    vertex p - G'(p) / c, c = 2 (G(q) - G(p) - G'(p) h) / h^2, is the minimum if c > 0 and it
    lies inside.  (G'(q) is not used: y'' may jump at q.)  So no sign change of x' is missed
    but a graze within the rounding of G.
    Fourier: the zero of G' (``slope_q`` > 0 needed), by Brent's method.  G' may have further
    zeros between two grid points, so a dip of G is missed where G'' = -sigma y^(3) also changes
    sign in the interval (at a peak of |y''|); with h = dt / (64 (K + 1)) such a dip is shorter
    than h and less deep than h^3 max|y^(4)| / 8 (1.5e-5 of the peak table velocity for K = 1)."""
    if row[R.DATA] < 0.0:
        h = q - p
        c = 2.0 * (g_q - g_p - slope_p * h) / (h * h)
        if c > 0.0:
            s = p - slope_p / c
            if p < s < q:
                return s
        return -1.0
    if slope_q > 0.0:
        return _brent(0, row, t0, -sigma, 0.0, 0.0, 0.0, 1.0, p, q, xtol, rtol)
    return -1.0


@jit
def _grid_intervals(row):
    """Intervals of the smooth stepper's grid on one period: 64 (order + 1) on a Fourier
    profile, :data:`GRID_PER_PIECE` per piece on a piecewise-linear one."""
    if row[R.DATA] > 0.0:
        return 64 * (int(row[R.DATA]) + 1)
    return GRID_PER_PIECE * -int(row[R.DATA])


@jit
def _grid_scratch(method, table):
    """Scratch space (3, points) for :func:`_smooth_grid`, enough for every profile of ``table``
    (none for the other steppers): allocated once per kernel call, not once per member."""
    points = 0
    if method == R.EXACT_SMOOTH:
        for p in range(table.shape[0]):
            points = max(points, _grid_intervals(table[p]) + 2)
    return np.empty((3, points))


@jit
def _smooth_grid(row, tau0, scratch):
    """(grid offsets from tau0, y', y'') on one period, views of ``scratch``: 64 (order + 1) + 1
    uniform points on a Fourier profile; on a piecewise-linear one the breaks and
    :data:`GRID_PER_PIECE` uniform points per piece, from tau0 round to tau0 + dt."""
    g = _grid_intervals(row)
    dt = row[R.DT]
    if row[R.DATA] > 0.0:
        points = g + 1
        for i in range(points):
            scratch[0, i] = dt * i / g
    else:
        m = -int(row[R.DATA])
        b0 = R.DATA + 1
        scratch[0, 0] = 0.0
        points = 1
        for after in (True, False):           # the pieces' points after tau0, then (next period) before it
            for i in range(m):
                for k in range(GRID_PER_PIECE):
                    p = row[b0 + i] + (row[b0 + i + 1] - row[b0 + i]) * k / GRID_PER_PIECE
                    offset = p - tau0 if after else dt - (tau0 - p)
                    if (p > tau0 if after else p < tau0) and scratch[0, points - 1] < offset < dt:
                        scratch[0, points] = offset
                        points += 1
        scratch[0, points] = dt
        points += 1
    grid = scratch[0, :points]
    yd = scratch[1, :points]
    ydd = scratch[2, :points]
    for i in range(points):
        _, yd[i], ydd[i] = _table_motion(row, tau0 + grid[i])
    return grid, yd, ydd


@jit
def _period_smooth(s, row, until, max_events, bnd, cross, record, arcs, events, grid, g_yd, g_ydd):
    """Advance member ``s`` one period on a smooth (Fourier or piecewise-linear-y'') profile, uniform surface."""
    dt = row[R.DT]
    tau0 = s.tau0
    xtol = 2.0 * _EPS * dt
    rtol = 4.0 * _EPS
    xi, v, mode, n = s.xi, s.v, s.mode, s.n
    dxp = 0.0
    lo = 0.0
    hi = 0.0
    s.fresh = False
    s0 = 0.0
    g = grid.shape[0]
    lowest = _next_boundary(bnd, cross)
    limit = s.static_ratio              # stick while |y''| <= r mu_bar (mu_bar = 1 here)
    while True:
        k0 = 0
        while k0 < g and grid[k0] <= s0:
            k0 += 1
        if mode == 0:
            k = k0
            while k < g and not abs(g_ydd[k]) > limit:
                k += 1
            if k >= g:
                if record:
                    _record_arc(arcs, s, dt, _STICK_ARC, n, tau0 + s0, dt - s0, xi, 0.0, 0.0, _NAN, 0.0,
                                       0, LOW)
                break
            sgn = 1.0 if g_ydd[k] > 0.0 else -1.0
            left = max(s0, grid[k - 1])
            f_left = _event_function(0, row, tau0, left, sgn, 0.0, 0.0, 0.0, limit)
            if f_left >= 0.0:
                root = left
            elif row[R.DATA] < 0.0 and not 2.0 * _event_function(0, row, tau0, 0.5 * (left + grid[k]), sgn, 0.0, 0.0,
                                                                     0.0, limit) - f_left > 0.0:
                root = _past_jump(row, tau0, sgn, limit, grid[k], xtol)
            else:
                root = _brent(0, row, tau0, sgn, 0.0, 0.0, 0.0, limit, left, grid[k], xtol, rtol)
            new = -int(sgn)
            if record:
                _record_arc(arcs, s, dt, _STICK_ARC, n, tau0 + s0, root - s0, xi, 0.0, 0.0, _NAN, 0.0, 0, LOW)
                ydd_r = _table_motion(row, tau0 + root)[2]
                _record_event(events, s, dt, _SLIP, n, tau0 + root, xi, 0.0, 0, new, 0.0, -ydd_r + sgn)
            s.events += 1
            mode, v, s0 = new, 0.0, root
        else:
            sigma = float(mode)
            y0, yd0, ydd0 = _table_motion(row, tau0 + s0)
            # First grid point where the velocity has the slip's sign (a slip from rest
            # first has to leave v = 0), then the first where it has lost it again.  A slip
            # from rest already back through v = 0 at a grid point (shorter than the grid's
            # spacing) is bracketed between that point and one of the slip's sign before it.
            k = k0
            short = False
            if not sigma * v > 0.0:
                while k < g:
                    moved = sigma * (v - sigma * (grid[k] - s0) - (g_yd[k] - yd0))
                    if moved != 0.0:
                        short = moved < 0.0
                        break
                    k += 1
            # Between grid points where it has the slip's sign, the velocity can vanish only at
            # an interior minimum (_slip_minimum): located and tested in every interval where
            # the velocity falls at the start.  A slip from v = 0 starts where the mode
            # decision found |y''| > r >= 1, so x'' has the slip's sign there (to rounding).
            dip = -1.0
            if not short:
                g_prev, p = sigma * v, s0
                slope = -1.0 - sigma * ydd0 if sigma * v > 0.0 else 0.0
                while k < g:
                    g_k = sigma * (v - sigma * (grid[k] - s0) - (g_yd[k] - yd0))
                    if not g_k > 0.0:
                        break
                    if slope < 0.0:
                        s_min = _slip_minimum(row, tau0, sigma, p, grid[k], g_prev, slope, g_k,
                                              -1.0 - sigma * g_ydd[k], xtol, rtol)
                        if s_min >= 0.0 and not _event_function(1, row, tau0, s_min, sigma, v, s0, yd0, limit) > 0.0:
                            dip = s_min
                            break
                    g_prev, p = g_k, grid[k]
                    slope = -1.0 - sigma * g_ydd[k]
                    k += 1
            if k >= g:
                root = dt
                found = False
            else:
                if short:
                    left = _slip_sign_point(row, tau0, sigma, v, s0, yd0, limit, grid[k])
                else:
                    left = grid[k - 1] if k > k0 else s0
                root = _brent(1, row, tau0, sigma, v, s0, yd0, limit, left, dip if dip >= 0.0 else grid[k], xtol,
                              rtol)
                found = True
            d = root - s0
            y1, yd1, ydd1 = _table_motion(row, tau0 + root)
            dx = v * d - 0.5 * sigma * d * d - (y1 - y0 - yd0 * d)
            if record:
                _record_arc(arcs, s, dt, _SMOOTH, n, tau0 + s0, d, xi, v, -ydd0 - sigma, _NAN, 0.0, mode, LOW)
            v_end = v - sigma * d - (yd1 - yd0)
            s.path += abs(dx)
            s.xi_max = max(s.xi_max, xi + dx)
            if xi + dx >= lowest:
                lowest = _crossed(s, bnd, cross, _SMOOTH, 0.0, xi, v, 0.0, xi + dx, v_end if not found else 0.0,
                                  n, tau0 + s0, d)
            xi += dx
            dxp += dx
            if dxp > hi:
                hi = dxp
            elif dxp < lo:
                lo = dxp
            if not found:
                v = v_end
                break
            s.events += 1
            v, s0 = 0.0, root
            new = F.decide_mode(ydd1, limit)
            if record:
                _record_event(events, s, dt, _STICK if new == 0 else _REVERSAL, n, tau0 + root, xi, 0.0,
                                       mode, new, -ydd1 - sigma, 0.0 if new == 0 else -ydd1 - new)
            mode = new
            if new == 0:
                code = _on_stick(s, xi, 1.0, n, tau0 + root, until, _holds(s, 1.0))
                if code != DONE:
                    s.dxp, s.lo, s.hi, s.regions = dxp, lo, hi, 1
                    return _stop(s, code, xi, 0.0, 0, n, tau0 + root, dt)
        if s.events >= max_events:
            s.dxp, s.lo, s.hi, s.regions = dxp, lo, hi, 1
            return _stop(s, STOP_BUDGET, xi, v, mode, n, tau0 + s0, dt)
    s.xi, s.v, s.mode, s.n = xi, v, mode, n + 1
    s.dxp, s.lo, s.hi, s.regions = dxp, lo, hi, 1
    return DONE


# ----------------------------------------------------------------------------------------
# Exact stepper, piecewise-linear y'' (finite jerk) on a stop zone
# ----------------------------------------------------------------------------------------

#: Event functions of a jerk arc (:func:`_jerk_event_function`).
_GAP, _VELOCITY, _SLOPE = 0, 1, 2


@jit
def _jerk_event_function(which, kind, om, sigma, v0, acc0, jerk, gap, s):
    """(g, g') of an arc of :func:`A.jerk_step` after time s, positive before its event:
    _VELOCITY g = sigma x' (v = 0 ahead); _GAP g = sigma (gap - (x - x0)) (the boundary at
    distance ``gap`` ahead); _SLOPE g = -sigma x'' (a minimum of sigma x' ahead), with
    g' = -sigma (kappa x' + jerk), the arc's third derivative."""
    dx, v, acc = A.jerk_step(kind, om, v0, acc0, jerk, s)
    if which == _VELOCITY:
        return sigma * v, sigma * acc
    if which == _SLOPE:
        kappa = -om * om if kind == _HARMONIC else (om * om if kind == _HYPERBOLIC else 0.0)
        return -sigma * acc, -sigma * (kappa * v + jerk)
    return sigma * (gap - dx), -sigma * v


@jit
def _jerk_event_time(which, kind, om, sigma, v0, acc0, jerk, gap, lo, hi, xtol, rtol):
    """The event of :func:`_jerk_event_function` in [lo, hi] (g(lo) > 0 >= g(hi)) by Newton's
    method kept inside the bracket, to a last step <= xtol + rtol s.  A step that would leave
    the bracket, or a second step after which the bracket has not halved, is a bisection, so
    the bracket halves at least every third evaluation: from <= dt to xtol = 2 eps dt takes
    <= 3 * 52 < BRENT_MAX_ITER of them (the cap is never reached).  A NaN g (overflow) bisects
    too; the NaN state then ends the run as NONFINITE.  The bracket keeps g(lo) > 0 >= g(hi),
    so where g changes sign once in [lo, hi] (:func:`_jerk_arc_end` brackets so) the result
    is that sign change."""
    s = 0.5 * (lo + hi)
    width = hi - lo
    for it in range(BRENT_MAX_ITER):
        g, dg = _jerk_event_function(which, kind, om, sigma, v0, acc0, jerk, gap, s)
        if g > 0.0:
            lo = s
        else:
            hi = s
        nxt = s - g / dg if dg != 0.0 else _NAN
        slow = it % 2 == 1 and hi - lo > 0.5 * width
        if slow or not lo < nxt < hi:
            nxt = 0.5 * (lo + hi)
        if it % 2 == 1:
            width = hi - lo
        if abs(nxt - s) <= xtol + rtol * abs(s) or hi - lo <= xtol + rtol * hi:
            return min(max(nxt, lo), hi)
        s = nxt
    return s


@jit
def _jerk_arc_end(kind, om, sigma, v, acc0, jerk, gap, bounded, rem, xtol, rtol):
    """(duration, event) of a slip arc of :func:`A.jerk_step` within time ``rem``: event 1
    v = 0, 2 the boundary at distance ``gap`` ahead (if ``bounded``), 0 none; v = 0 wins a
    tie (tie rule 2).  ``v`` is 0 or has the sign ``sigma`` of the slip.

    Why no event in a bracket is missed.  Let G = sigma x' and A = G' = sigma x''.  The arc
    solves x'' = acc0 + kappa (x - x0) + jerk s, so x''' = kappa x' + jerk and A'' = kappa A:
    the acceleration of a jerk arc solves the homogeneous equation.  So A is linear
    (QUADRATIC, kappa = 0), c cos(w s + phi) (HARMONIC, zeros pi / w apart) or
    c1 e^{ws} + c2 e^{-ws} (HYPERBOLIC, at most one zero), and unless A = 0 throughout its
    zeros are simple.  The bracketing grid has GRID_PER_PIECE points plus GRID_PER_PIECE per
    harmonic period 2 pi / w, so an interval [s_{k-1}, s_k] is shorter than pi / w and holds at
    most one zero of A: on it G is monotone or has one interior extremum, where A changes
    sign.  With G(s_{k-1}) > 0:

    * G(s_k) <= 0: G has exactly one sign change in (s_{k-1}, s_k], the first v = 0 (falling;
      rising to a maximum, then falling; or falling to a minimum, then rising to G(s_k) <= 0).
    * G(s_k) > 0: G can vanish inside only at an interior minimum, i.e. only if
      A(s_{k-1}) < 0 < A(s_k); then that minimum s* (the zero of A, bracketed by these signs) is
      located, and G has a zero in (s_{k-1}, s*] iff G(s*) <= 0, exactly one.
    * x is strictly monotone in the direction sigma from s_{k-1} to the first zero s_v of G
      (or to s_k if there is none), so the boundary ahead is crossed before the slip stops iff
      g_b = sigma (gap - (x - x0)) has reached 0 there, g_b(s_v) <= 0 (g_b(s_k) <= 0), and
      that crossing is g_b's only sign change on [s_{k-1}, s_v].  When G has a single zero and
      g_b(s_k) <= 0, g_b stays <= 0 after s_v (the mass moves back, away from the boundary), so
      [s_{k-1}, s_k] brackets the same crossing.
    * A slip from v = 0 (G(0) = 0) that decelerates, A(0) < 0 or A(0) = 0 with sigma jerk <= 0
      (G''(0) = sigma jerk), ends at once with v = 0 (tie rule 4).  Otherwise G > 0 just after
      0 and, by the first bullet, exactly on (0, s_v) within the first interval: a point of the
      slip's sign before s_v is found by halving s_1 (G > 0 at q iff q < s_v).

    Hence every event is located: rounding can hide only a zero of G (or g_b) within the
    rounding of G (g_b) itself, a graze of depth ~eps times the velocity (distance) scale, which
    rounding could not tell from a miss either.  Each time is refined by
    :func:`_jerk_event_time` to 2 eps dt + 4 eps t."""
    if not rem > 0.0:                       # at the segment's end: the next segment decides
        return 0.0, 0
    if v == 0.0 and (sigma * acc0 < 0.0 or (acc0 == 0.0 and sigma * jerk <= 0.0)):
        return 0.0, 1                       # tie rule 4: decelerates from v = 0
    points = GRID_PER_PIECE + int(GRID_PER_PIECE * om * rem / (2.0 * math.pi))
    prev = 0.0
    a_prev = sigma * acc0                   # A = sigma x'' at prev
    for k in range(1, points + 1):
        sk = rem * k / points
        gv, a_k = _jerk_event_function(_VELOCITY, kind, om, sigma, v, acc0, jerk, gap, sk)
        gb = _jerk_event_function(_GAP, kind, om, sigma, v, acc0, jerk, gap, sk)[0] if bounded else 1.0
        s_v = _INF
        if gv > 0.0 and a_prev < 0.0 < a_k:     # sigma x' has its minimum inside: is it <= 0?
            s_min = _jerk_event_time(_SLOPE, kind, om, sigma, v, acc0, jerk, gap, prev, sk, xtol, rtol)
            if not _jerk_event_function(_VELOCITY, kind, om, sigma, v, acc0, jerk, gap, s_min)[0] > 0.0:
                s_v = _jerk_event_time(_VELOCITY, kind, om, sigma, v, acc0, jerk, gap, prev, s_min, xtol, rtol)
        if gv > 0.0 and gb > 0.0 and s_v == _INF:
            prev = sk
            a_prev = a_k
            continue
        if not gv > 0.0:
            left = prev
            if left == 0.0 and v == 0.0:
                left = sk
                for _ in range(60):
                    left *= 0.5
                    if _jerk_event_function(_VELOCITY, kind, om, sigma, v, acc0, jerk, gap, left)[0] > 0.0:
                        break
                if not _jerk_event_function(_VELOCITY, kind, om, sigma, v, acc0, jerk, gap, left)[0] > 0.0:
                    return 0.0, 1
            s_v = _jerk_event_time(_VELOCITY, kind, om, sigma, v, acc0, jerk, gap, left, sk, xtol, rtol)
        s_b = _INF
        if bounded:
            end_b = -1.0                        # where the crossing is bracketed, if it comes first
            if not gb > 0.0 and (s_v == _INF or not gv > 0.0):
                end_b = sk
            elif s_v < _INF and not _jerk_event_function(_GAP, kind, om, sigma, v, acc0, jerk, gap, s_v)[0] > 0.0:
                end_b = s_v
            if end_b >= 0.0:
                s_b = _jerk_event_time(_GAP, kind, om, sigma, v, acc0, jerk, gap, prev, end_b, xtol, rtol)
        if s_v <= s_b:
            return s_v, 1
        return s_b, 2
    return rem, 0


@jit
def _period_jerk_zone(s, row, until, max_events, bnd, cross, record, arcs, events):
    """Advance member ``s`` one period on a piecewise-linear-y'' profile on a stop zone.

    Within a piece y'' = a + j t, so every slip arc is an arc of :mod:`selfalign.model.arcs`
    (quadratic outside the zone, harmonic or hyperbolic in it) plus the response to the
    forcing -j t (:func:`A.jerk_step`), and a stuck mass slips when the linear |y''|, kept
    within the piece's levels (:func:`_ramp`), exceeds r mu_bar (closed form).  The events of a
    slip (v = 0, a zone boundary) are bracketed and refined by :func:`_jerk_arc_end` to
    |error| <= 2 eps dt + 4 eps t.  Piece breaks are no events (y'' is continuous at a
    finite-jerk profile's breaks; a jump is decided at once).  Slip arcs are recorded with their
    kind and omega and a NaN table acceleration."""
    dt = row[R.DT]
    m = -int(row[R.DATA])
    b0 = R.DATA + 1
    a0 = b0 + m + 1
    j0 = b0 + 2 * m + 1
    tau0 = s.tau0
    i0 = _pw_piece(row, tau0)
    tail = tau0 > row[b0 + i0]
    xtol = 2.0 * _EPS * dt
    rtol = 4.0 * _EPS
    w = s.w
    r_static = s.static_ratio
    lowest = _next_boundary(bnd, cross)
    xi, v, mode, n, count, path, xi_max, dxp, lo, hi, regions, stalled = _load(s)
    s.fresh = False
    for seg_j in range(m + 1 if tail else m):
        p, ts, seg, dn, _ = _segment(row, m, i0, tau0, tail, seg_j)
        jerk = row[j0 + p]
        a_seg = row[a0 + p] + jerk * (ts - row[b0 + p])
        nn = n + dn
        s0 = 0.0
        a_slip = _NAN                           # y'' at a slip start from stick: exactly +-r mu_bar
        while True:
            a = _ramp(row, p, a_seg + jerk * s0) if math.isnan(a_slip) else a_slip
            a_slip = _NAN
            rem = seg - s0
            if mode == 0:
                mu = _mu(s, xi)
                limit = r_static * mu
                a_end = _ramp(row, p, a_seg + jerk * seg)
                root, new = _INF, 0
                if abs(a) > limit:
                    root, new = s0, F.decide_mode(a, limit)
                elif a_end > limit:
                    root, new = s0 + (limit - a) / jerk, -1
                elif a_end < -limit:
                    root, new = s0 + (-limit - a) / jerk, 1
                if not root < seg:              # stuck to the segment's end (the next one decides)
                    r = _region(s, xi, 0)
                    regions |= 1 << r
                    if record:
                        _record_arc(arcs, s, dt, _STICK_ARC, nn, ts + s0, rem, xi, 0.0, 0.0, _NAN, 0.0, 0, r)
                    break
                r = _region(s, xi, 0)
                regions |= 1 << r
                if root > s0:
                    a_slip = -new * limit
                if record:
                    _record_arc(arcs, s, dt, _STICK_ARC, nn, ts + s0, root - s0, xi, 0.0, 0.0, _NAN, 0.0, 0, r)
                    a_r = a if root == s0 else -new * limit
                    _record_event(events, s, dt, _SLIP, nn, ts + root, xi, 0.0, 0, new, 0.0,
                                  _arc_params(s, xi, new, a_r)[3])
                count += 1
                mode, v, s0 = new, 0.0, root
            else:
                if v * mode < 0.0:              # tie rule 4
                    v = 0.0
                sigma = float(mode)
                kind, r, mu, acc0 = _arc_params(s, xi, mode, a)
                regions |= 1 << r
                om_arc = 0.0 if kind == _QUADRATIC else s.omega
                if kind == _QUADRATIC:
                    bounded = s.zone and (r == LOW) == (mode > 0)
                    xb = 0.0 if r == LOW else w
                else:
                    bounded = True
                    xb = w if mode > 0 else 0.0
                dur, ev = _jerk_arc_end(kind, om_arc, sigma, v, acc0, -jerk, xb - xi, bounded, rem, xtol, rtol)
                dx, v1, acc1 = A.jerk_step(kind, om_arc, v, acc0, -jerk, dur)
                if record:
                    _record_arc(arcs, s, dt, kind, nn, ts + s0, dur, xi, v, acc0, _NAN, om_arc, mode, r)
                xi_new = xb if ev == 2 else xi + dx
                path += abs(xi_new - xi)
                xi_max = max(xi_max, xi_new)
                if xi_new >= lowest:
                    lowest = _crossed(s, bnd, cross, _SMOOTH, 0.0, xi, v, 0.0, xi_new, 0.0 if ev == 1 else v1, nn,
                                      ts + s0, dur)
                dxp += xi_new - xi
                hi = max(hi, dxp)
                lo = min(lo, dxp)
                xi = xi_new
                if ev == 0:
                    v = v1
                    break
                s0 += dur
                count += 1
                stalled = stalled + 1 if dur == 0.0 else 0
                if stalled > STALL_EVENTS:
                    _save(s, count, path, xi_max, dxp, lo, hi, regions)
                    return _stop(s, STOP_STALL, xi, v, mode, nn, ts + s0, dt)
                a_now = _ramp(row, p, a_seg + jerk * s0)
                if ev == 2:                     # zone crossing: on the boundary exactly
                    v = v1
                    if record:
                        _record_event(events, s, dt, _ZONE, nn, ts + s0, xi, v, mode, mode, acc1,
                                      _arc_params(s, xi, mode, a_now)[3])
                else:                           # v = 0: stick or reverse (tie rule 1)
                    v = 0.0
                    mu = _mu(s, xi)
                    new = F.decide_mode(a_now, r_static * mu)
                    if record:
                        _record_event(events, s, dt, _STICK if new == 0 else _REVERSAL, nn, ts + s0, xi, 0.0,
                                      mode, new, acc1, _arc_params(s, xi, new, a_now)[3])
                    mode = new
                    if new == 0:
                        code = _on_stick(s, xi, mu, nn, ts + s0, until, _holds(s, mu))
                        if code != DONE:
                            _save(s, count, path, xi_max, dxp, lo, hi, regions)
                            return _stop(s, code, xi, 0.0, 0, nn, ts + s0, dt)
            if count >= max_events:
                _save(s, count, path, xi_max, dxp, lo, hi, regions)
                return _stop(s, STOP_BUDGET, xi, v, mode, nn, ts + s0, dt)
    s.xi, s.v, s.mode, s.n = xi, v, mode, n + 1
    _save(s, count, path, xi_max, dxp, lo, hi, regions)
    return DONE


# ----------------------------------------------------------------------------------------
# Moreau time-stepping
# ----------------------------------------------------------------------------------------

#: Relaxation r of the paper's fixed-point iteration, in units of the friction bound h mu_bar:
#: s <- proj_[-1,1](s + r v_{k+1}(s)) with r = FP_RELAXATION / (h mu_bar), a contraction
#: with factor |1 - FP_RELAXATION| = 1/2 (1 would reach the soft threshold in one sweep).
FP_RELAXATION = 0.5


@jit
def _impulse(s, v_free, bound, fixed_point, fp_tol, fp_max_iter):
    """v_{k+1} = v* - bound s, s in Sign(v_{k+1}): exactly (the soft threshold of v* by
    bound) or by the paper's fixed-point iteration on the multiplier s."""
    if not fixed_point:
        if v_free > bound:
            return v_free - bound
        if v_free < -bound:
            return v_free + bound
        return 0.0
    m = 0.0
    r = FP_RELAXATION / bound
    change = 0.0
    converged = False
    for it in range(1, fp_max_iter + 1):
        m_new = min(1.0, max(-1.0, m + r * (v_free - bound * m)))
        change = abs(bound * (m_new - m))
        m = m_new
        s.fp_iterations += 1
        if change <= fp_tol:
            converged = True
            break
    if not converged:
        s.fp_unconverged += 1
        s.fp_max_change = max(s.fp_max_change, change)
    if abs(m) >= 1.0:
        return v_free - bound * m
    return 0.0


@jit
def _stribeck_speed(u, bound, ratio, v_s, delta):
    """The slip speed c > 0 of an implicit Moreau step under Stribeck friction: the root of
    c + bound f(c) = u, f = :func:`~selfalign.model.friction.stribeck_factor`, for a free
    speed u > bound r (else the step sticks).  f(0) = r and f >= 1 bracket it in
    (0, u - bound]; Newton's method kept inside the bracket (bisection where a Newton step
    leaves it) refines it to rounding.  The root is unique while h mu_bar max|f'| < 1."""
    lo = 0.0
    hi = u - bound
    c = hi
    for _ in range(200):
        e = math.exp(-((c / v_s) ** delta)) if c > 0.0 else 1.0
        g = c + bound * (1.0 + (ratio - 1.0) * e) - u
        if g == 0.0:
            return c
        if g > 0.0:
            hi = c
        else:
            lo = c
        slope = 1.0 - bound * (ratio - 1.0) * e * delta * (c / v_s) ** delta / c if c > 0.0 else 0.0
        c_new = c - g / slope if slope > 0.0 else 0.5 * (lo + hi)
        if not lo < c_new < hi:
            c_new = 0.5 * (lo + hi)
        if c_new == c or hi - lo <= 4.0 * _EPS * hi:
            return c_new
        c = c_new
    return c


@jit
def _step_region(s, x):
    if not s.zone or x <= 0.0:
        return LOW
    return HIGH if x >= s.w else ZONE


@jit
def _richer_friction_step(s, v, v_free, h_mu, fixed_point, fp_tol, fp_max_iter):
    """The implicit friction step of a Moreau step under static/kinetic or Stribeck friction
    (mu_s / mu_k = r > 1 or v_s > 0): stick while the free velocity ``v_free`` stays in the window
    r h mu_bar of a mass that is stuck or comes to rest; else slip against h mu_bar, times f(v) of
    :func:`~selfalign.model.friction.stribeck_factor` for Stribeck friction."""
    r_static = s.static_ratio
    if r_static > 1.0 and v_free * v <= 0.0 and abs(v_free) <= h_mu * r_static:
        return 0.0                      # static friction holds a mass that is stuck or comes to rest
    if s.v_s > 0.0:
        if abs(v_free) <= h_mu * r_static:
            return 0.0
        return math.copysign(_stribeck_speed(abs(v_free), h_mu, r_static, s.v_s, s.delta), v_free)
    return _impulse(s, v_free, h_mu, fixed_point, fp_tol, fp_max_iter)


@jit
def _period_moreau(s, row, until, bnd, cross, record, samples, sample_steps, fixed_point, fp_tol, fp_max_iter):
    """Advance member ``s`` one period with N Moreau steps (:mod:`selfalign.solvers.moreau`)."""
    dt = row[R.DT]
    nsteps = int(row[R.DATA])
    h = row[R.DATA + 1]
    largest = row[R.DATA + 2]
    d0 = R.DATA + 3
    half = 0.5 * h
    tau0 = s.tau0
    xi, v, n = s.xi, s.v, s.n
    r_static = s.static_ratio      # stick window r h mu_bar; slip against h mu_bar (Stribeck: h mu_bar f(v))
    # The paper's law takes the step of :func:`_impulse` alone; the richer laws are a separate
    # call so that they add nothing to the loop of the Coulomb step.
    coulomb = r_static == 1.0 and not s.v_s > 0.0
    dxp = 0.0
    lo = 0.0
    hi = 0.0
    regions = 0
    s.fresh = False
    nxt = 0            # next dense-output sample (index into sample_steps)
    lowest = _next_boundary(bnd, cross)
    k = 0
    while k < nsteps:
        if v == 0.0:
            # Stuck: a step is the identity while |impulse| <= h mu_bar (v* = -impulse lies in
            # the stick window), so jump to the first step that can start a slip.
            bound = h * _mu(s, xi) * r_static
            k_next = k
            while k_next < nsteps and abs(row[d0 + k_next]) <= bound:
                k_next += 1
            regions |= 1 << _step_region(s, xi)
            if record:
                while nxt < sample_steps.shape[0] and sample_steps[nxt] < k_next:
                    _record_sample(samples, s, n, tau0 + sample_steps[nxt] * h, xi, 0.0, 0)
                    nxt += 1
            k = k_next
            if k >= nsteps:
                break
        if record and nxt < sample_steps.shape[0] and sample_steps[nxt] == k:
            _record_sample(samples, s, n, tau0 + k * h, xi, v, (v > 0.0) - (v < 0.0))
            nxt += 1
        x_mid = xi + half * v
        mu = _mu(s, x_mid)
        regions |= 1 << _step_region(s, x_mid)
        v_free = v - row[d0 + k]
        if coulomb:
            v_new = _impulse(s, v_free, h * mu, fixed_point, fp_tol, fp_max_iter)
        else:
            v_new = _richer_friction_step(s, v, v_free, h * mu, fixed_point, fp_tol, fp_max_iter)
        x_new = x_mid + half * v_new
        s.steps += 1
        dx = x_new - xi
        dxp += dx
        if dxp > hi:
            hi = dxp
        elif dxp < lo:
            lo = dxp
        s.path += abs(dx)
        s.xi_max = max(s.xi_max, x_new)
        if x_new >= lowest:
            lowest = _crossed(s, bnd, cross, _SMOOTH, 0.0, xi, v, 0.0, x_new, v_new, n, tau0 + k * h, h)
        was_moving = v != 0.0
        xi, v = x_new, v_new
        k += 1
        if v == 0.0 and was_moving:
            mu_x = _mu(s, xi)
            code = _on_stick(s, xi, mu_x, n, tau0 + k * h, until, h * mu_x * r_static >= largest)
            if code != DONE:
                s.dxp, s.lo, s.hi, s.regions = dxp, lo, hi, regions
                return _stop(s, code, xi, 0.0, 0, n, tau0 + k * h, dt)
    s.xi, s.v, s.n = xi, v, n + 1
    s.mode = (v > 0.0) - (v < 0.0)
    s.dxp, s.lo, s.hi, s.regions = dxp, lo, hi, regions
    return DONE


# ----------------------------------------------------------------------------------------
# The driver: horizon, outcome decisions, fast-forward
# ----------------------------------------------------------------------------------------

@jit
def _prepare(s, row, method, acc_tol):
    """Derived constants of a member and its state at the run start (n = 0, time tau0)."""
    s.b1 = (s.c_mu - 1.0) / s.w if s.zone else 0.0
    s.omega = math.sqrt(s.b1)
    s.rest_acc = row[R.REST_ACC]
    # Permanent stick needs r mu_bar >= max|y''|: eq. (41) for max|y''| / r.
    s.xs = F.stick_limit(row[R.REST_ACC] / s.static_ratio, s.w, s.c_mu) if s.zone else _INF
    s.acc_tol = max(acc_tol, ACC_TOL_ULPS * _EPS * s.w) if s.zone else acc_tol
    s.n, s.fresh, s.events, s.steps = 0, True, 0, 0
    s.sticks, s.zone_sticks, s.nh = 0, 0, 0
    s.h1, s.h2 = _NAN, _NAN
    s.first_stick_xi, s.first_stick_n, s.first_stick_tau = _NAN, -1, _NAN
    s.at_rest = False
    s.xi_max, s.path, s.fast_forward = s.xi, 0.0, 0
    s.n_arcs, s.n_events, s.n_samples = 0, 0, 0
    s.fp_iterations, s.fp_unconverged, s.fp_max_change = 0, 0, 0.0
    s.contraction, s.advance, s.cycle, s.cycle_region, s.last_stick = _NAN, _NAN, 0, -1, _NAN
    s.stop_n, s.stop_tau = 0, s.tau0
    s.dxp, s.lo, s.hi, s.regions = 0.0, 0.0, 0.0, 0


@jit
def _start(s, a, until, moreau, holds_scale):
    """The mode at the start under table acceleration ``a``: the sign of v0, or at v0 = 0
    the stick/slip decision (Moreau: stuck until a step says otherwise); REST if stuck for
    good (Moreau: ``holds_scale`` = (h, largest |impulse|), the step's test).  No stick
    event is counted for the initial state."""
    if s.v != 0.0:
        s.mode = 1 if s.v > 0.0 else -1
        return DONE
    mu = _mu(s, s.xi)
    s.mode = 0 if moreau else F.decide_mode(a, s.static_ratio * mu)
    holds = holds_scale[0] * mu * s.static_ratio >= holds_scale[1] if moreau else _holds(s, mu)
    if s.mode == 0 and holds:
        s.at_rest = True
        if until != R.UNTIL_PERIODS:
            s.stop_n, s.stop_tau = 0, s.tau0
            return STOP_REST
    return DONE


@jit
def _region_of_mask(regions):
    if regions == 1 << LOW:
        return LOW
    if regions == 1 << HIGH:
        return HIGH
    return -1


@jit
def _cycles(s, hist, count, max_cycle, near, swing):
    """The shortest k-period cycles ending now, in one pass over the history:
    (k, region, k_near, region_near), k = 0 where there is none.

    k: a bit-exact repeat, of (v, mode) when all k periods stayed in one region of
    constant friction (translation invariance: region >= 0, the mass may have moved), else
    of (x, v, mode) (region -1).  k_near (only if ``near``, and only one shorter than k): a
    near repeat (see NEAR_ULPS, MOTION_FACTOR).  :func:`_cycle_span` gives a cycle's advance.
    ``hist`` is a ring of the last ``max_cycle`` periods, the newest at (count - 1) mod max_cycle.
    """
    tol_x = NEAR_ULPS * _EPS * (abs(s.xi) + (s.w if s.zone else 0.0))
    tol_v = NEAR_ULPS * _EPS * (abs(s.v) + swing)
    last = (count - 1) % max_cycle
    idx = last + 1
    region = -1
    k_near = 0
    region_near = -1
    for k in range(1, min(count, max_cycle) + 1):
        idx -= 1                      # the period that started k periods ago
        if idx < 0:
            idx += max_cycle
        h = hist[idx]
        # The region all of the last k periods stayed in (-1: none), kept up as k grows.
        if k == 1:
            region = _region_of_mask(h.regions)
        elif _region_of_mask(h.regions) != region:
            region = -1
        if h.mode != s.mode:
            continue
        dv = abs(h.v - s.v)
        dx = abs(h.xi - s.xi)
        if dv == 0.0 and (region >= 0 or dx == 0.0):
            return k, region, k_near, region_near
        if near and k_near == 0 and dv <= tol_v and (
                region >= 0 or dx <= tol_x and s.path - h.path > MOTION_FACTOR * tol_x):
            k_near, region_near = k, region
    return 0, -1, k_near, region_near


@jit
def _cycle_span(hist, count, max_cycle, k):
    """(advance, lo, hi) of the last k periods: the displacement over them and the extreme
    displacements within them."""
    j = (count - k) % max_cycle
    cum = 0.0
    lo = 0.0
    hi = 0.0
    for _ in range(k):
        p = hist[j]
        lo = min(lo, cum + p.lo)
        hi = max(hi, cum + p.hi)
        cum += p.dxp
        j += 1
        if j >= max_cycle:
            j -= max_cycle
    return cum, lo, hi


@jit
def _verdict(s, region, advance):
    """NEVER_STOPS reason for a cycle (until='rest'), or -1 (no verdict: it moves on)."""
    if region < 0:
        return _PERIODIC
    if not s.zone:
        return _PERIODIC if advance == 0.0 else (
            _WALK_FORWARD if advance > 0.0 else _WALK_BACKWARD)
    if region == LOW and advance <= 0.0:
        return _PERIODIC if advance == 0.0 else _WALK_BACKWARD
    if region == HIGH and advance >= 0.0:
        return _PERIODIC if advance == 0.0 else _WALK_FORWARD
    return -1


@jit
def _skippable(s, region, advance, lo, hi, cycles):
    """How many of ``cycles`` repeats keep the mass in its region of constant friction
    (one cycle of margin: the following cycle is simulated normally)."""
    if not s.zone or advance == 0.0:
        return cycles
    if region == LOW and advance > 0.0:
        room = -(s.xi + hi)
    elif region == HIGH and advance < 0.0:
        room = s.xi + lo - s.w
    else:
        return cycles
    return max(0, min(cycles, int(math.floor(room / abs(advance))) - 1))


@inlined
def _after_period(s, hist, count, max_cycle, swing, until, total, fast_forward, v0, mode0, xi0, path0):
    """After a completed period that started in state (v0, mode0, xi0): record it, then
    decide (until='rest', 'stick') or fast-forward on a repeating period-boundary state.
    Returns (reason or -1 to go on, history count, horizon reached)."""
    if s.n >= total:
        return -1, count, True
    if until == R.UNTIL_PERIODS and not fast_forward:
        return -1, count, False             # nothing to decide, nothing to skip: no history
    h = hist[count % max_cycle]
    h.v, h.xi, h.mode, h.path = v0, xi0, mode0, path0
    h.dxp, h.lo, h.hi, h.regions = s.dxp, s.lo, s.hi, s.regions
    count += 1
    k, region, k_near, region_near = _cycles(s, hist, count, max_cycle, until != R.UNTIL_PERIODS, swing)
    if until == R.UNTIL_CYCLE and k_near > 0 and (k == 0 or k_near < k):
        # The periodic motion itself: the shortest k at which the state repeats exactly or to
        # the near-repeat tolerance (an attracting orbit can settle into an ulp-level 2-cycle).
        k, region = k_near, region_near
    elif k == 0 and (until == R.UNTIL_REST or until == R.UNTIL_STICK):
        k, region = k_near, region_near
    elif k > 0 and until != R.UNTIL_CYCLE:
        advance, lo, hi = _cycle_span(hist, count, max_cycle, k)
        advance = advance if region >= 0 else 0.0
        if until != R.UNTIL_PERIODS:
            reason = _verdict(s, region, advance)
            if reason >= 0:
                s.advance, s.cycle, s.cycle_region = advance / k, k, region
                return reason, count, False
        if fast_forward:
            cycles = (total - s.n) // k
            if region >= 0:
                cycles = _skippable(s, region, advance, lo, hi, cycles)
                s.xi += cycles * advance
            if cycles > 0:
                s.n += cycles * k
                s.fast_forward += cycles * k
                count = 0
        return -1, count, False
    if k > 0:
        advance = _cycle_span(hist, count, max_cycle, k)[0] if region >= 0 else 0.0
        reason = _verdict(s, region, advance)
        if reason >= 0:
            s.advance, s.cycle, s.cycle_region = advance / k, k, region
            return reason, count, False
    return -1, count, False


@jit
def _finish(s, code, reason, until):
    """The reason a run ended (from the stepper's stop code if no verdict) and its end time."""
    if reason < 0:
        if code == STOP_REST:
            reason = _REST
        elif code == STOP_ACCUMULATION:
            reason = _ACCUMULATION
            s.xi, s.v = s.xs, 0.0
        elif code == STOP_FIRST_STICK:
            reason = _FIRST_STICK
        elif code == STOP_BUDGET:
            reason = _MAX_EVENTS
        elif code == STOP_STALL:
            reason = _STALL
        elif until == R.UNTIL_PERIODS:
            reason = _PERIODS
        elif s.zone and s.xi_max >= 0.0:
            reason = _BOUNDED
        else:
            reason = _MAX_PERIODS
    s.reason = reason
    if code != DONE or reason == _NONFINITE:
        s.n_end, s.tau_end = s.stop_n, s.stop_tau
    else:
        s.n_end, s.tau_end = s.n, s.tau0


@jit
def drive(s, method, row, until, total, max_events, max_cycle, acc_tol, bnd, cross, record, fast_forward, hist,
          scratch, arcs, events, samples, sample_steps, fixed_point, fp_tol, fp_max_iter):
    """Run member ``s`` to its outcome (module docstring), recording into the buffers if asked.

    ``hist`` is scratch space for ``max_cycle`` period records, ``scratch`` that of the
    smooth stepper's grid (:func:`_grid_scratch`); ``fast_forward`` allows
    skipping bit-exact repeating periods (off while recording).  ``record`` is a
    compile-time constant (two specialisations), so a run that records nothing carries no
    recording code in its loops.
    """
    literally(record)
    _prepare(s, row, method, acc_tol)
    swing = row[R.SWING]
    if method == R.EXACT_SMOOTH:
        grid, g_yd, g_ydd = _smooth_grid(row, s.tau0, scratch)
        a0 = g_ydd[0]
    else:
        grid, g_yd, g_ydd = scratch[0, :0], scratch[1, :0], scratch[2, :0]
        a0 = 0.0
        if method == R.EXACT_PIECEWISE:
            s.piece0 = _pw_piece(row, s.tau0)
            a0 = row[R.DATA + 2 + int(row[R.DATA]) + s.piece0]
    count = 0
    reason = -1
    moreau = method == R.MOREAU
    code = _start(s, a0, until, moreau, (row[R.DATA + 1], row[R.DATA + 2]) if moreau else (0.0, 0.0))
    _crossed(s, bnd, cross, _STICK_ARC, 0.0, s.xi, s.v, 0.0, s.xi, s.v, 0, s.tau0, 0.0)
    while code == DONE and s.n < total:
        v0, mode0, xi0, path0 = s.v, s.mode, s.xi, s.path
        if method == R.EXACT_PIECEWISE:
            code = _period_piecewise(s, row, until, max_events, bnd, cross, record, arcs, events)
        elif method == R.EXACT_SMOOTH and s.zone:
            code = _period_jerk_zone(s, row, until, max_events, bnd, cross, record, arcs, events)
        elif method == R.EXACT_SMOOTH:
            code = _period_smooth(s, row, until, max_events, bnd, cross, record, arcs, events,
                                                grid, g_yd, g_ydd)
        else:
            code = _period_moreau(s, row, until, bnd, cross, record, samples, sample_steps,
                                           fixed_point, fp_tol, fp_max_iter)
        if not (math.isfinite(s.xi) and math.isfinite(s.v)):
            s.xi, s.v, s.mode = xi0, v0, mode0
            if code == DONE:
                s.n -= 1
            s.stop_n, s.stop_tau = s.n, s.tau0
            reason = _NONFINITE
            break
        if code != DONE:
            break
        reason, count, horizon = _after_period(s, hist, count, max_cycle, swing, until, total,
                                               fast_forward and not record, v0, mode0, xi0, path0)
        if reason >= 0 or horizon:
            break
    _finish(s, code, reason, until)
    if record and method == R.MOREAU:
        _record_sample(samples, s, s.n_end, s.tau_end, s.xi, s.v, s.mode)


@jit
def run_members(members, method, table, until, total, max_events, max_cycle, acc_tol, bnd, cross, fast_forward,
                fixed_point, fp_tol, fp_max_iter, hist, arcs, events, samples, steps):
    """Drive every member (no recording): the batch, and one trajectory without series.
    ``hist`` is scratch space (HIST_DTYPE, max_cycle records); the recording buffers are
    passed (empty) only so that the same :func:`drive` serves both entry points.  Every
    record array is allocated by the caller (numpy record arrays, so that the kernel also
    runs uncompiled, NUMBA_DISABLE_JIT=1)."""
    scratch = _grid_scratch(method, table)
    table, bnd, cross, hist, arcs, events, samples, steps = _borrowed_all(table, bnd, cross, hist, arcs, events,
                                                                          samples, steps)
    for i in range(members.shape[0]):
        s = members[i]
        drive(s, method, table[s.profile], until, total, max_events, max_cycle, acc_tol, bnd[i], cross[i], False,
              fast_forward, hist, scratch, arcs, events, samples, steps, fixed_point, fp_tol, fp_max_iter)


@jit
def run_recorded(members, method, table, until, total, max_events, max_cycle, acc_tol, bnd, cross,
                 fixed_point, fp_tol, fp_max_iter, hist, arcs, events, samples, sample_steps):
    """Drive member 0 recording its arcs and events (exact) or samples (Moreau) into the
    buffers; the member's n_arcs, n_events, n_samples say how many there were (a buffer
    that was too small holds the first ones only: run again with larger buffers)."""
    table, bnd, cross, hist, arcs, events, samples, sample_steps = _borrowed_all(table, bnd, cross, hist, arcs, events,
                                                                                 samples, sample_steps)
    s = members[0]
    drive(s, method, table[s.profile], until, total, max_events, max_cycle, acc_tol, bnd[0], cross[0], True, False,
          hist, _grid_scratch(method, table), arcs, events, samples, sample_steps, fixed_point, fp_tol, fp_max_iter)


# ----------------------------------------------------------------------------------------
# Entry points for a stepper written in Python (ivp): the same decisions, on member 0
# ----------------------------------------------------------------------------------------

@jit
def begin_entry(members, row, method, acc_tol, a, until):
    """:func:`_prepare` and :func:`_start` on member 0; returns the start code."""
    s = members[0]
    _prepare(s, row, method, acc_tol)
    return _start(s, a, until, False, (0.0, 0.0))


@jit
def stick_entry(members, xi, mu, n, tau, until):
    """:func:`_on_stick` on member 0."""
    return _on_stick(members[0], xi, mu, n, tau, until, _holds(members[0], mu))


@jit
def moved_entry(members, xi0, xi1):
    """Path and largest x after a move of member 0 (no boundary crossings are tracked)."""
    s = members[0]
    s.path += abs(xi1 - xi0)
    if xi1 > s.xi_max:
        s.xi_max = xi1


@jit
def after_period_entry(members, hist, count, max_cycle, swing, until, total, fast_forward, v0, mode0, xi0,
                       path0):
    """:func:`_after_period` on member 0."""
    return _after_period(members[0], hist, count, max_cycle, swing, until, total, fast_forward, v0, mode0, xi0,
                         path0)


@jit
def modes(v, ydd, mu):
    """The model's mode at states (v, y'', mu_bar): the sign of v, at v = 0 :func:`decide_mode`."""
    out = np.empty(v.shape[0], dtype=np.int8)
    for i in range(v.shape[0]):
        out[i] = 1 if v[i] > 0.0 else (-1 if v[i] < 0.0 else F.decide_mode(ydd[i], mu[i]))
    return out


@jit
def finish_entry(members, code, reason, until):
    """:func:`_finish` on member 0."""
    _finish(members[0], code, reason, until)


# ----------------------------------------------------------------------------------------
# Dense output of the exact solver: evaluate the recorded arcs on the sample grid
# ----------------------------------------------------------------------------------------

@jit
def sample_arcs(arcs, row, tau0, spp):
    """Samples on the grid t = tau0 + j dt / spp plus every arc start (the state after each
    event): each arc with a positive duration contributes its start and the grid points
    strictly inside it; the last arc (the end state) contributes its start only.
    Returns (period, tau, x, v, mode) with tau measured from the arc's period start."""
    dt = row[R.DT]
    h = dt / spp
    na = arcs.shape[0]
    total = 0
    for pass_ in range(2):
        if pass_ == 1:
            period = np.empty(total, dtype=np.int64)
            tau = np.empty(total)
            x = np.empty(total)
            v = np.empty(total)
            mode = np.empty(total, dtype=np.int8)
        k = 0
        for i in range(na):
            arc = arcs[i]
            last = i == na - 1
            if arc.duration <= 0.0 and not last:
                continue
            off = arc.tau - tau0
            base = arc.period
            if off < 0.0:
                off += dt
                base -= 1
            j_lo = int(math.floor(off / h)) + 1
            j_hi = min(int(math.ceil((off + arc.duration) / h)) - 1, spp - 1)
            count = 1 if last else 1 + max(0, j_hi - j_lo + 1)
            if pass_ == 0:
                total += count
                continue
            for r in range(count):
                if r == 0:
                    sr = 0.0
                    pn, pt = arc.period, arc.tau
                else:
                    j = j_lo + r - 1
                    sr = min(max(j * h - off, 0.0), arc.duration)
                    pn, pt = _norm(base, tau0 + j * h, dt)
                if arc.kind == _SMOOTH:
                    sig = float(arc.mode)
                    y0, yd0, _ = _table_motion(row, arc.tau)
                    y1, yd1, _ = _table_motion(row, arc.tau + sr)
                    dx = arc.v * sr - 0.5 * sig * sr * sr - (y1 - y0 - yd0 * sr)
                    vv = arc.v - sig * sr - (yd1 - yd0)
                elif arc.kind != _STICK_ARC and row[R.DATA] < 0.0:      # a slip of _period_jerk_zone
                    m = -int(row[R.DATA])
                    jerk = row[R.DATA + 2 + 2 * m + _pw_piece(row, arc.tau)]
                    dx, vv, _ = A.jerk_step(arc.kind, arc.omega, arc.v, arc.acc, -jerk, sr)
                else:
                    dx, vv = A.step(arc.kind, arc.omega, arc.v, arc.acc, sr)
                period[k] = pn
                tau[k] = pt
                x[k] = arc.x + dx
                v[k] = vv
                mode[k] = arc.mode
                k += 1
    return period, tau, x, v, mode
