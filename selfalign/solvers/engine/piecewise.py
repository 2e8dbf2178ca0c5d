"""The exact stepper on a piecewise-constant profile (the paper's three-phase profile, Sect.
4.4.3): closed-form arcs and event times of :mod:`selfalign.model.arcs` (quadratic on a uniform
surface, eq. 11; harmonic and hyperbolic in the transition zone, eqs. 12-15).
"""

from __future__ import annotations

import math

from ...model import arcs as A
from ...model import friction as F
from .. import records as R
from ..outcomes import HIGH, LOW, STALL_EVENTS, ZONE
from .codes import (
    ARC_HARMONIC,
    ARC_HYPERBOLIC,
    ARC_QUADRATIC,
    ARC_STICK,
    DONE,
    END_EDGE,
    END_PIECE,
    END_STOP,
    EV_REVERSAL,
    EV_SLIP,
    EV_STICK,
    EV_SWITCH,
    EV_ZONE,
    INF,
    STOP_BUDGET,
    STOP_STALL,
)
from .compiled import inlined, jit
from .field import (
    friction_at,
    holds_for_good,
    load_period,
    next_boundary,
    on_stick,
    record_crossings,
    region_of,
    save_period,
    stop_in_period,
    stop_nonfinite,
)
from .recording import record_arc, record_event


@jit
def piece_at(row, tau):
    """Index of the piece holding phase ``tau`` (right-continuous) of a piecewise-constant or
    piecewise-linear-y'' row (m or -m pieces in its first data column)."""
    m = abs(R.data_size(row))
    i = 0
    while i + 1 < m and row[R.col_break(i + 1)] <= tau:
        i += 1
    return i


@inlined
def period_segment(row, m, i0, tau0, tail, j):
    """(piece, start phase, length, period offset, starts at a break) of segment j of the period
    from tau0 (``tail``: tau0 is inside piece i0): the rest of piece i0, the following pieces,
    then (next period) the pieces before i0 and the head of piece i0.  The breaks of a
    profile row are read through :func:`~selfalign.solvers.records.col_break`."""
    if j == 0:
        return i0, tau0, row[R.col_break(i0 + 1)] - tau0, 0, not tail
    if j < m:
        p = i0 + j
        dn = 0
        if p >= m:
            p -= m
            dn = 1
        return p, row[R.col_break(p)], row[R.col_break(p + 1)] - row[R.col_break(p)], dn, True
    return i0, row[R.col_break(i0)], tau0 - row[R.col_break(i0)], 1, True


@jit
def arc_parameters(s, zone, xi, mode, a):
    """(kind, region, mu_bar, x'') of the arc starting at xi in ``mode`` under y'' = a (``zone``:
    :func:`~.field.friction_at`)."""
    r = region_of(s, zone, xi, mode)
    if r == LOW:
        mu = 1.0
    elif r == HIGH:
        mu = s.c_mu
    else:
        mu = F.coefficient(xi, s.w, s.c_mu)
    if mode == 0:
        return ARC_STICK, r, mu, 0.0
    kind = ARC_QUADRATIC if r != ZONE else (ARC_HARMONIC if mode > 0 else ARC_HYPERBOLIC)
    return kind, r, mu, -a - mode * mu


@jit
def _harmonic_reaches(xi, v, acc0, b1, om, xb):
    """False only if a harmonic arc from (xi, v) provably stays below xb: its largest x is
    the centre xi + acc0 / b1 plus the amplitude (a margin of 1e-9 covers rounding)."""
    centre = xi + acc0 / b1
    amplitude = math.sqrt((acc0 / b1) ** 2 + (v / om) ** 2)
    return centre + amplitude >= xb - 1e-9 * (abs(centre) + amplitude + abs(xb))


@inlined
def period_piecewise(s, row, run, bnd, cross, record, buffers, scratch, periods, uniform):
    """Advance member ``s`` from the period boundary (n, tau0) by ``periods`` periods, the state
    kept in registers from one period to the next (the driver asks for more than one only where
    it decides nothing at the boundaries between them)."""
    until, max_events = run.until, run.max_events
    arcs, events = buffers[0], buffers[1]
    dt = row[R.DT]
    m = R.data_size(row)
    tau0 = s.tau0
    i0 = s.piece0
    tail = tau0 > row[R.col_break(i0)]
    nseg = m + 1 if tail else m
    zone = False if uniform else s.zone     # uniform: compiled for members on a uniform surface only
    w, om, b1 = s.w, s.omega, s.b1
    r_static = s.static_ratio               # stick while |y''| <= r mu_bar; slip arcs use mu_bar
    lowest = next_boundary(bnd, cross)
    xi, v, mode, n, count, path, xi_max, dxp, lo, hi, regions, stalled = load_period(s)
    fresh = s.fresh
    s.fresh = False
    for _ in range(periods):
        dxp, lo, hi, regions, stalled = 0.0, 0.0, 0.0, 0, 0
        start = (xi, v, mode, n)            # the state to go back to if x or v stops being finite
        for j in range(nseg):
            p, ts, seg, dn, at_break = period_segment(row, m, i0, tau0, tail, j)
            a = row[R.col_level(m, p)]
            nn = n + dn
            s0 = 0.0
            if at_break and not fresh:
                count += 1
                if v * mode < 0.0:
                    v = 0.0
                if record:
                    before = p - 1 if p > 0 else m - 1
                    acc_b = arc_parameters(s, zone, xi, mode, row[R.col_level(m, before)])[3]
                    acc_a = arc_parameters(s, zone, xi, mode, a)[3]
                    record_event(events, s, dt, EV_SWITCH, nn, ts, xi, v, mode, mode, acc_b, acc_a)
                if mode == 0 or v == 0.0:            # tie rule 3: re-decide at v = 0
                    mu = friction_at(s, zone, xi)
                    new = F.decide_mode(a, r_static * mu)
                    if new != mode:
                        count += 1
                        if record:
                            kind_e = EV_SLIP if mode == 0 else (EV_STICK if new == 0 else EV_REVERSAL)
                            record_event(events, s, dt, kind_e, nn, ts, xi, 0.0, mode, new,
                                         arc_parameters(s, zone, xi, mode, a)[3],
                                         arc_parameters(s, zone, xi, new, a)[3])
                        mode = new
                        if new == 0:
                            code = on_stick(s, xi, mu, nn, ts, until, holds_for_good(s, mu))
                            if code != DONE:
                                save_period(s, count, path, xi_max, dxp, lo, hi, regions)
                                return stop_in_period(s, start, code, xi, 0.0, 0, nn, ts, dt)
                    v = 0.0
                if count >= max_events:
                    save_period(s, count, path, xi_max, dxp, lo, hi, regions)
                    return stop_in_period(s, start, STOP_BUDGET, xi, v, mode, nn, ts, dt)
            fresh = False
            while mode != 0:
                if v * mode < 0.0:                  # tie rule 4
                    v = 0.0
                kind, r, mu, acc0 = arc_parameters(s, zone, xi, mode, a)
                regions |= 1 << r
                rem = seg - s0
                s_b = INF
                xb = 0.0
                om_arc = 0.0
                if kind == ARC_QUADRATIC:
                    s_v = -v / acc0 if acc0 * mode < 0.0 else INF
                    if zone and (r == LOW) == (mode > 0):
                        xb = 0.0 if r == LOW else w
                        s_b = A.crossing_time(ARC_QUADRATIC, 0.0, v, acc0, xi - xb)
                else:
                    om_arc = om
                    s_v = A.zero_velocity_time(kind, om, mode, v, acc0)
                    xb = w if mode > 0 else 0.0
                    if kind == ARC_HYPERBOLIC or _harmonic_reaches(xi, v, acc0, b1, om, xb):
                        s_b = A.crossing_time(kind, om, v, acc0, xi - xb)
                if s_v <= s_b and s_v <= rem:       # tie rules 2, 3
                    dur, ev = s_v, END_STOP
                elif s_b <= rem:
                    dur, ev = s_b, END_EDGE
                else:
                    dur, ev = rem, END_PIECE
                dx, v1 = A.step(kind, om_arc, v, acc0, dur)
                if record:
                    record_arc(arcs, s, dt, kind, nn, ts + s0, dur, xi, v, acc0, a, om_arc, mode, r)
                xi_new = xb if ev == END_EDGE else xi + dx
                path += abs(xi_new - xi)
                if xi_new > xi_max:
                    xi_max = xi_new
                if xi_new >= lowest:
                    lowest = record_crossings(s, bnd, cross, kind, om_arc, xi, v, acc0, xi_new,
                                              0.0 if ev == END_STOP else v1, nn, ts + s0, dur)
                if ev == END_PIECE:
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
                    save_period(s, count, path, xi_max, dxp, lo, hi, regions)
                    return stop_in_period(s, start, STOP_STALL, xi, v, mode, nn, ts + s0, dt)
                if ev == END_EDGE:                         # zone crossing: land exactly on the boundary
                    dxp += xb - xi
                    xi = xb
                    v = v1
                    if record:
                        record_event(events, s, dt, EV_ZONE, nn, ts + s0, xi, v, mode, mode,
                                     A.acceleration(kind, b1, acc0, dx), arc_parameters(s, zone, xi, mode, a)[3])
                else:                               # v = 0: stick or reverse (tie rule 1)
                    dxp += dx
                    xi = xi_new
                    v = 0.0
                    mu = friction_at(s, zone, xi)
                    new = F.decide_mode(a, r_static * mu)
                    if record:
                        record_event(events, s, dt, EV_STICK if new == 0 else EV_REVERSAL, nn, ts + s0, xi,
                                     0.0, mode, new, A.acceleration(kind, b1, acc0, dx),
                                     arc_parameters(s, zone, xi, new, a)[3])
                    mode = new
                    if new == 0:
                        code = on_stick(s, xi, mu, nn, ts + s0, until, holds_for_good(s, mu))
                        if code != DONE:
                            save_period(s, count, path, xi_max, dxp, lo, hi, regions)
                            return stop_in_period(s, start, code, xi, 0.0, 0, nn, ts + s0, dt)
                if dxp > hi:
                    hi = dxp
                elif dxp < lo:
                    lo = dxp
                if count >= max_events:
                    save_period(s, count, path, xi_max, dxp, lo, hi, regions)
                    return stop_in_period(s, start, STOP_BUDGET, xi, v, mode, nn, ts + s0, dt)
            if mode == 0:
                r = region_of(s, zone, xi, 0)
                regions |= 1 << r
                if record:
                    record_arc(arcs, s, dt, ARC_STICK, nn, ts + s0, seg - s0, xi, 0.0, 0.0, a, 0.0, 0, r)
        n += 1
        if not (math.isfinite(xi) and math.isfinite(v)):
            save_period(s, count, path, xi_max, dxp, lo, hi, regions)
            return stop_nonfinite(s, start[0], start[1], start[2], start[3])
    s.xi, s.v, s.mode, s.n = xi, v, mode, n
    save_period(s, count, path, xi_max, dxp, lo, hi, regions)
    return DONE


#: :func:`period_piecewise` called rather than inlined: a recorded run (one trajectory, its speed set
#: by the recording) compiles in half the time, while batches keep the inlined stepper.
period_piecewise_called = jit(getattr(period_piecewise, "py_func", period_piecewise))
