"""The exact stepper on a piecewise-linear-y'' (finite-jerk) profile on a stop zone: polynomial
arcs on the uniform parts, harmonic/hyperbolic arcs forced by a linear y'' in the transition
zone (:func:`selfalign.model.arcs.jerk_step`); every event in a bracket is located in order.
"""

from __future__ import annotations

import math

from ...model import arcs as A
from ...model import friction as F
from .. import records as R
from ..outcomes import LOW, STALL_EVENTS
from .codes import (
    ARC_HARMONIC,
    ARC_HYPERBOLIC,
    ARC_QUADRATIC,
    ARC_SMOOTH,
    ARC_STICK,
    DONE,
    END_EDGE,
    END_PIECE,
    END_STOP,
    EPS,
    EV_REVERSAL,
    EV_SLIP,
    EV_STICK,
    EV_ZONE,
    INF,
    NAN,
    STOP_BUDGET,
    STOP_STALL,
)
from .compiled import jit
from .field import (
    friction_at,
    holds_for_good,
    load_period,
    next_boundary,
    on_stick,
    record_crossings,
    region_of,
    save_period,
    stop_at,
)
from .piecewise import arc_parameters, period_segment, piece_at
from .recording import record_arc, record_event
from .smooth import BRENT_MAX_ITER, GRID_PER_PIECE, ramp_level

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
        kappa = -om * om if kind == ARC_HARMONIC else (om * om if kind == ARC_HYPERBOLIC else 0.0)
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
        nxt = s - g / dg if dg != 0.0 else NAN
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
    """(duration, end) of a slip arc of :func:`A.jerk_step` within time ``rem``: END_STOP
    v = 0, END_EDGE the boundary at distance ``gap`` ahead (if ``bounded``), END_PIECE none; v = 0 wins a
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
        return 0.0, END_PIECE
    if v == 0.0 and (sigma * acc0 < 0.0 or (acc0 == 0.0 and sigma * jerk <= 0.0)):
        return 0.0, END_STOP                       # tie rule 4: decelerates from v = 0
    points = GRID_PER_PIECE + int(GRID_PER_PIECE * om * rem / (2.0 * math.pi))
    prev = 0.0
    a_prev = sigma * acc0                   # A = sigma x'' at prev
    for k in range(1, points + 1):
        sk = rem * k / points
        gv, a_k = _jerk_event_function(_VELOCITY, kind, om, sigma, v, acc0, jerk, gap, sk)
        gb = _jerk_event_function(_GAP, kind, om, sigma, v, acc0, jerk, gap, sk)[0] if bounded else 1.0
        s_v = INF
        if gv > 0.0 and a_prev < 0.0 < a_k:     # sigma x' has its minimum inside: is it <= 0?
            s_min = _jerk_event_time(_SLOPE, kind, om, sigma, v, acc0, jerk, gap, prev, sk, xtol, rtol)
            if not _jerk_event_function(_VELOCITY, kind, om, sigma, v, acc0, jerk, gap, s_min)[0] > 0.0:
                s_v = _jerk_event_time(_VELOCITY, kind, om, sigma, v, acc0, jerk, gap, prev, s_min, xtol, rtol)
        if gv > 0.0 and gb > 0.0 and s_v == INF:
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
                    return 0.0, END_STOP
            s_v = _jerk_event_time(_VELOCITY, kind, om, sigma, v, acc0, jerk, gap, left, sk, xtol, rtol)
        s_b = INF
        if bounded:
            end_b = -1.0                        # where the crossing is bracketed, if it comes first
            if not gb > 0.0 and (s_v == INF or not gv > 0.0):
                end_b = sk
            elif s_v < INF and not _jerk_event_function(_GAP, kind, om, sigma, v, acc0, jerk, gap, s_v)[0] > 0.0:
                end_b = s_v
            if end_b >= 0.0:
                s_b = _jerk_event_time(_GAP, kind, om, sigma, v, acc0, jerk, gap, prev, end_b, xtol, rtol)
        if s_v <= s_b:
            return s_v, END_STOP
        return s_b, END_EDGE
    return rem, END_PIECE


@jit
def period_jerk_zone(s, row, run, bnd, cross, record, buffers, scratch, periods):
    """Advance member ``s`` one period on a piecewise-linear-y'' profile on a stop zone.

    Within a piece y'' = a + j t, so every slip arc is an arc of :mod:`selfalign.model.arcs`
    (quadratic outside the zone, harmonic or hyperbolic in it) plus the response to the
    forcing -j t (:func:`A.jerk_step`), and a stuck mass slips when the linear |y''|, kept
    within the piece's levels (:func:`ramp_level`), exceeds r mu_bar (closed form).  The events of a
    slip (v = 0, a zone boundary) are bracketed and refined by :func:`_jerk_arc_end` to
    |error| <= 2 eps dt + 4 eps t.  Piece breaks are no events (y'' is continuous at a
    finite-jerk profile's breaks; a jump is decided at once).  Slip arcs are recorded with their
    kind and omega and a NaN table acceleration."""
    until, max_events = run.until, run.max_events
    arcs, events = buffers[0], buffers[1]
    dt = row[R.DT]
    m = -R.data_size(row)
    tau0 = s.tau0
    i0 = piece_at(row, tau0)
    tail = tau0 > row[R.col_break(i0)]
    xtol = 2.0 * EPS * dt
    rtol = 4.0 * EPS
    w = s.w
    r_static = s.static_ratio
    lowest = next_boundary(bnd, cross)
    xi, v, mode, n, count, path, xi_max, dxp, lo, hi, regions, stalled = load_period(s)
    s.fresh = False
    for seg_j in range(m + 1 if tail else m):
        p, ts, seg, dn, _ = period_segment(row, m, i0, tau0, tail, seg_j)
        jerk = row[R.col_jerk(m, p)]
        a_seg = row[R.col_level(m, p)] + jerk * (ts - row[R.col_break(p)])
        nn = n + dn
        s0 = 0.0
        a_slip = NAN                           # y'' at a slip start from stick: exactly +-r mu_bar
        while True:
            a = ramp_level(row, p, a_seg + jerk * s0) if math.isnan(a_slip) else a_slip
            a_slip = NAN
            rem = seg - s0
            if mode == 0:
                mu = friction_at(s, s.zone, xi)
                limit = r_static * mu
                a_end = ramp_level(row, p, a_seg + jerk * seg)
                root, new = INF, 0
                if abs(a) > limit:
                    root, new = s0, F.decide_mode(a, limit)
                elif a_end > limit:
                    root, new = s0 + (limit - a) / jerk, -1
                elif a_end < -limit:
                    root, new = s0 + (-limit - a) / jerk, 1
                if not root < seg:              # stuck to the segment's end (the next one decides)
                    r = region_of(s, s.zone, xi, 0)
                    regions |= 1 << r
                    if record:
                        record_arc(arcs, s, dt, ARC_STICK, nn, ts + s0, rem, xi, 0.0, 0.0, NAN, 0.0, 0, r)
                    break
                r = region_of(s, s.zone, xi, 0)
                regions |= 1 << r
                if root > s0:
                    a_slip = -new * limit
                if record:
                    record_arc(arcs, s, dt, ARC_STICK, nn, ts + s0, root - s0, xi, 0.0, 0.0, NAN, 0.0, 0, r)
                    a_r = a if root == s0 else -new * limit
                    record_event(events, s, dt, EV_SLIP, nn, ts + root, xi, 0.0, 0, new, 0.0,
                                  arc_parameters(s, s.zone, xi, new, a_r)[3])
                count += 1
                mode, v, s0 = new, 0.0, root
            else:
                if v * mode < 0.0:              # tie rule 4
                    v = 0.0
                sigma = float(mode)
                kind, r, mu, acc0 = arc_parameters(s, s.zone, xi, mode, a)
                regions |= 1 << r
                om_arc = 0.0 if kind == ARC_QUADRATIC else s.omega
                if kind == ARC_QUADRATIC:
                    bounded = s.zone and (r == LOW) == (mode > 0)
                    xb = 0.0 if r == LOW else w
                else:
                    bounded = True
                    xb = w if mode > 0 else 0.0
                dur, ev = _jerk_arc_end(kind, om_arc, sigma, v, acc0, -jerk, xb - xi, bounded, rem, xtol, rtol)
                dx, v1, acc1 = A.jerk_step(kind, om_arc, v, acc0, -jerk, dur)
                if record:
                    record_arc(arcs, s, dt, kind, nn, ts + s0, dur, xi, v, acc0, NAN, om_arc, mode, r)
                xi_new = xb if ev == END_EDGE else xi + dx
                path += abs(xi_new - xi)
                xi_max = max(xi_max, xi_new)
                if xi_new >= lowest:
                    lowest = record_crossings(s, bnd, cross, ARC_SMOOTH, 0.0, xi, v, 0.0, xi_new,
                                              0.0 if ev == END_STOP else v1, nn, ts + s0, dur)
                dxp += xi_new - xi
                hi = max(hi, dxp)
                lo = min(lo, dxp)
                xi = xi_new
                if ev == END_PIECE:
                    v = v1
                    break
                s0 += dur
                count += 1
                stalled = stalled + 1 if dur == 0.0 else 0
                if stalled > STALL_EVENTS:
                    save_period(s, count, path, xi_max, dxp, lo, hi, regions)
                    return stop_at(s, STOP_STALL, xi, v, mode, nn, ts + s0, dt)
                a_now = ramp_level(row, p, a_seg + jerk * s0)
                if ev == END_EDGE:                     # zone crossing: on the boundary exactly
                    v = v1
                    if record:
                        record_event(events, s, dt, EV_ZONE, nn, ts + s0, xi, v, mode, mode, acc1,
                                      arc_parameters(s, s.zone, xi, mode, a_now)[3])
                else:                           # v = 0: stick or reverse (tie rule 1)
                    v = 0.0
                    mu = friction_at(s, s.zone, xi)
                    new = F.decide_mode(a_now, r_static * mu)
                    if record:
                        record_event(events, s, dt, EV_STICK if new == 0 else EV_REVERSAL, nn, ts + s0, xi, 0.0,
                                      mode, new, acc1, arc_parameters(s, s.zone, xi, new, a_now)[3])
                    mode = new
                    if new == 0:
                        code = on_stick(s, xi, mu, nn, ts + s0, until, holds_for_good(s, mu))
                        if code != DONE:
                            save_period(s, count, path, xi_max, dxp, lo, hi, regions)
                            return stop_at(s, code, xi, 0.0, 0, nn, ts + s0, dt)
            if count >= max_events:
                save_period(s, count, path, xi_max, dxp, lo, hi, regions)
                return stop_at(s, STOP_BUDGET, xi, v, mode, nn, ts + s0, dt)
    s.xi, s.v, s.mode, s.n = xi, v, mode, n + 1
    save_period(s, count, path, xi_max, dxp, lo, hi, regions)
    return DONE
