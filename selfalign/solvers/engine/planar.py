"""The exact planar stepper on a piecewise-constant table acceleration and a uniform surface: the closed-form
slips of :mod:`selfalign.model.planar_slip` between events (docs/explanation/planar-model.md).

A point part on a table whose acceleration Y'' is a constant vector on each piece of the period (the merged
pieces of both components, :meth:`PlanarProfile.pieces`).  Its own state arrays and run loop, as the stepper
of several parts (:mod:`selfalign.solvers.engine`), called through the entry point
:func:`selfalign.solvers.engine.entries.planar_run`:

    ``planar_run(f, c, starts, accels, periods, until_rest, max_events, spp, samples, log) -> reason``

* ``f`` (float, :data:`~.codes.PLANAR_FLOATS`): the start state (position relative to the origin, velocity)
  and the settings (``PL_DT``, ``PL_TAU0``, ``PL_MU``, ``PL_RATIO``, ``PL_REST``); on return the end state and
  the end phase ``PL_TAU_END``;
* ``c`` (int, :data:`~.codes.PLANAR_COUNTERS`): on return the end period, the end mode and the counts;
* ``starts`` (m,), ``accels`` (m, 2): the pieces of one period, from 0 (the last one ends at dt);
* ``periods``: the horizon; ``until_rest``: end at a stick that holds for good (REST) rather than run on;
* ``spp`` and ``samples`` (K, 5): the state (x, y, vx, vy, mode) at the times tau0 + k dt / spp, k < K
  (spp = 0: none); ``log`` (E, 7): the events (period, phase, kind, x, y, vx, vy), the first E of them
  (the count is ``c[PC_LOG]``: the caller runs again with a larger log if it did not fit).

It returns the reason code (:class:`~selfalign.solvers.outcomes.Reason`): PERIODS, MAX_PERIODS, REST,
MAX_EVENTS, STALL or NONFINITE (the state at the start of the period that failed is kept).

The events: a piece switch (the acceleration jumps; the part at zero velocity is decided again), a stop
(the speed reaches 0: explicit in closed form, mu > |Y''|), and what follows a stop or a switch at zero
velocity: stick while |Y''| <= r mu (:func:`~selfalign.model.friction.decide_mode` of |Y''| against r mu),
else a slip from rest along -Y'' with kinetic friction (after a stop in slip, a reversal: only a collinear
slip can reach zero speed with |Y''| > mu).

Tie rules (every zero-length step changes the mode, so there is no Zeno loop):

1. |Y''| = r mu sticks (the stick disc grazed from inside or on its rim).
2. A stop exactly at a piece end is taken first, under the ending piece's acceleration; the switch then
   decides the part at rest again under the new one.
3. A slip is collinear (a quadratic arc on the line of v) exactly where v x Y'' = 0 in floating point, or
   from rest; every other slip takes the curved closed form (:func:`~selfalign.model.planar_slip.slip_shape`).
"""

from __future__ import annotations

import math

from ...model import friction as F
from ...model import planar_slip as S
from ..outcomes import STALL_EVENTS
from .codes import (
    EV_REVERSAL,
    EV_SLIP,
    EV_STICK,
    EV_SWITCH,
    INF,
    PC_ARCS,
    PC_BREAKS,
    PC_EVENTS,
    PC_LOG,
    PC_MODE,
    PC_N_END,
    PC_REVERSALS,
    PC_SAMPLES,
    PC_SLIPS,
    PC_STICKS,
    PL_DT,
    PL_MU,
    PL_RATIO,
    PL_REST,
    PL_TAU0,
    PL_TAU_END,
    PL_VX,
    PL_VY,
    PL_X,
    PL_Y,
    REASON_MAX_EVENTS,
    REASON_MAX_PERIODS,
    REASON_NONFINITE,
    REASON_PERIODS,
    REASON_REST,
    REASON_STALL,
)
from .compiled import jit
from .recording import normalised_time


@jit
def planar_segment(starts, dt, i0, tau0, tail, j):
    """(piece, start phase, length, period offset, starts at a switch) of segment j of the period from tau0
    (``tail``: tau0 is inside piece i0): the rest of piece i0, the following pieces, then (next period) the
    pieces before i0 and the head of piece i0."""
    m = starts.shape[0]
    if j == 0:
        end = starts[i0 + 1] if i0 + 1 < m else dt
        return i0, tau0, end - tau0, 0, not tail
    if j < m:
        p = i0 + j
        dn = 0
        if p >= m:
            p -= m
            dn = 1
        end = starts[p + 1] if p + 1 < m else dt
        return p, starts[p], end - starts[p], dn, True
    return i0, starts[i0], tau0 - starts[i0], 1, True


@jit
def planar_arc(vx, vy, ax, ay, mu):
    """The closed form of a slip from (vx, vy) under (ax, ay): (curved, its stop time, and its parameters:
    (ex, ey, cx, cy) of a collinear slip, its direction and acceleration, or (G, gx, gy, nx, ny, a, b, h) of a
    curved one).  From rest it is collinear along -Y''."""
    if vx == 0.0 and vy == 0.0:
        g = math.hypot(ax, ay)
        ex, ey = -ax / g, -ay / g
        cx, cy = S.collinear_acceleration(ex, ey, ax, ay, mu)
        return False, S.collinear_stop_time(vx, vy, cx, cy, ex, ey), (ex, ey, cx, cy, 0.0, 0.0, 0.0, 0.0)
    if S.slip_shape(vx, vy, ax, ay, mu) == S.COLLINEAR:
        speed = math.hypot(vx, vy)
        ex, ey = vx / speed, vy / speed
        cx, cy = S.collinear_acceleration(ex, ey, ax, ay, mu)
        return False, S.collinear_stop_time(vx, vy, cx, cy, ex, ey), (ex, ey, cx, cy, 0.0, 0.0, 0.0, 0.0)
    g, gx, gy, nx, ny, a, b, h = S.slip_frame(vx, vy, ax, ay)
    return True, S.stop_time(g, mu, a, b), (g, gx, gy, nx, ny, a, b, h)


@jit
def planar_state(curved, w, vx, vy, mu, s, stop):
    """(dx, dy, vx, vy) of the slip ``planar_arc`` described, a time s after its start (at its stop: v = 0)."""
    if not curved:
        dx, dy, wx, wy = S.collinear_step(vx, vy, w[2], w[3], s)
        if stop:
            return dx, dy, 0.0, 0.0
        return dx, dy, wx, wy
    g, gx, gy, nx, ny, a, b, h = w
    y = INF if stop else S.slip_parameter(g, mu, a, b, s)
    if y == 0.0:                      # s below the resolution of y: v s is the displacement to rounding
        return vx * s, vy * s, vx, vy
    disp_g, disp_n, p, q = S.slip_state(g, mu, a, b, h, y)
    return disp_g * gx + disp_n * nx, disp_g * gy + disp_n * ny, p * gx + q * nx, p * gy + q * ny


@jit
def planar_log(log, c, n, tau, dt, kind, x, y, vx, vy):
    """Write an event to the log (if it fits) and count it."""
    k = c[PC_LOG]
    if k < log.shape[0]:
        period, phase = normalised_time(n, tau, dt)
        log[k, 0], log[k, 1], log[k, 2] = period, phase, kind
        log[k, 3], log[k, 4], log[k, 5], log[k, 6] = x, y, vx, vy
    c[PC_LOG] = k + 1


@jit
def planar_samples(samples, c, spp, n, dt, local, dur, curved, w, x, y, vx, vy, mu, mode, last):
    """Write the samples of period n whose time lies in the arc [local, local + dur) of the period's own time
    (from its start at tau0), evaluated in closed form (``last``: the end of the run, up to the arc end)."""
    if spp == 0:
        return
    h = dt / spp
    end = local + dur
    while c[PC_SAMPLES] < samples.shape[0]:
        k = c[PC_SAMPLES]
        j = k - n * spp
        at = j * h
        if not (at < end or (last and at <= end)):
            return
        off = min(max(at - local, 0.0), dur)
        if mode == 0 or off == 0.0:
            dx, dy, wx, wy = 0.0, 0.0, vx, vy
        else:
            dx, dy, wx, wy = planar_state(curved, w, vx, vy, mu, off, False)
        samples[k, 0], samples[k, 1], samples[k, 2], samples[k, 3], samples[k, 4] = x + dx, y + dy, wx, wy, mode
        c[PC_SAMPLES] = k + 1


@jit
def planar_stop(f, c, code, x, y, vx, vy, mode, n, tau, dt):
    """End the run inside a period at state (x, y, vx, vy, mode) and time (n, tau): returns ``code``."""
    f[PL_X], f[PL_Y], f[PL_VX], f[PL_VY] = x, y, vx, vy
    period, phase = normalised_time(n, tau, dt)
    c[PC_N_END], f[PL_TAU_END], c[PC_MODE] = period, phase, mode
    return code


@jit
def run_planar(f, c, starts, accels, periods, until_rest, max_events, spp, samples, log):
    """The run loop (module docstring); returns the reason code."""
    dt, tau0, mu, ratio, rest = f[PL_DT], f[PL_TAU0], f[PL_MU], f[PL_RATIO], f[PL_REST]
    m = starts.shape[0]
    i0 = 0
    while i0 + 1 < m and starts[i0 + 1] <= tau0:
        i0 += 1
    tail = tau0 > starts[i0]
    nseg = m + 1 if tail else m
    x, y, vx, vy = f[PL_X], f[PL_Y], f[PL_VX], f[PL_VY]
    holds = ratio * mu >= rest                      # stuck anywhere, the part is at rest for good
    mode = 1
    if vx == 0.0 and vy == 0.0:
        mode = 0 if F.decide_mode(math.hypot(accels[i0, 0], accels[i0, 1]), ratio * mu) == 0 else 1
        if mode == 0 and holds and until_rest:
            return planar_stop(f, c, REASON_REST, x, y, vx, vy, 0, 0, tau0, dt)
    w = (0.0, 0.0, 0.0, 0.0, 0.0, 0.0, 0.0, 0.0)
    fresh = True
    stalled = 0
    for n in range(periods):
        start = (x, y, vx, vy, mode)
        for j in range(nseg):
            p, ts, seg, dn, at_break = planar_segment(starts, dt, i0, tau0, tail, j)
            ax, ay = accels[p, 0], accels[p, 1]
            nn = n + dn
            local = ts - tau0 + dn * dt             # the segment start in the period's own time
            s0 = 0.0
            if at_break and not fresh:
                c[PC_EVENTS] += 1
                c[PC_BREAKS] += 1
                planar_log(log, c, nn, ts, dt, EV_SWITCH, x, y, vx, vy)
                if vx == 0.0 and vy == 0.0:         # tie rule 2: at zero velocity, decided again
                    new = 0 if F.decide_mode(math.hypot(ax, ay), ratio * mu) == 0 else 1
                    if new != mode:
                        c[PC_EVENTS] += 1
                        if new == 1:
                            c[PC_SLIPS] += 1
                            planar_log(log, c, nn, ts, dt, EV_SLIP, x, y, 0.0, 0.0)
                        else:
                            c[PC_STICKS] += 1
                            planar_log(log, c, nn, ts, dt, EV_STICK, x, y, 0.0, 0.0)
                        mode = new
                        if new == 0 and holds and until_rest:
                            planar_samples(samples, c, spp, n, dt, local, 0.0, False, w, x, y, 0.0, 0.0, mu, 0, True)
                            return planar_stop(f, c, REASON_REST, x, y, 0.0, 0.0, 0, nn, ts, dt)
                if c[PC_EVENTS] >= max_events:
                    return planar_stop(f, c, REASON_MAX_EVENTS, x, y, vx, vy, mode, nn, ts, dt)
            fresh = False
            while mode == 1:
                curved, stop_at, w = planar_arc(vx, vy, ax, ay, mu)
                rem = seg - s0
                stops = stop_at <= rem                # tie rule 2: a stop at the piece end first
                dur = stop_at if stops else rem
                planar_samples(samples, c, spp, n, dt, local + s0, dur, curved, w, x, y, vx, vy, mu, 1, False)
                dx, dy, vx1, vy1 = planar_state(curved, w, vx, vy, mu, dur, stops)
                c[PC_ARCS] += 1
                x, y, vx, vy = x + dx, y + dy, vx1, vy1
                if not stops:
                    break
                s0 += dur
                c[PC_EVENTS] += 1
                stalled = stalled + 1 if dur == 0.0 else 0
                if stalled > STALL_EVENTS:
                    return planar_stop(f, c, REASON_STALL, x, y, vx, vy, mode, nn, ts + s0, dt)
                if F.decide_mode(math.hypot(ax, ay), ratio * mu) == 0:      # tie rule 1
                    mode = 0
                    c[PC_STICKS] += 1
                    planar_log(log, c, nn, ts + s0, dt, EV_STICK, x, y, 0.0, 0.0)
                    if holds and until_rest:
                        planar_samples(samples, c, spp, n, dt, local + s0, 0.0, False, w, x, y, 0.0, 0.0, mu, 0, True)
                        return planar_stop(f, c, REASON_REST, x, y, 0.0, 0.0, 0, nn, ts + s0, dt)
                else:                               # a collinear slip through zero speed: slips on along -Y''
                    c[PC_REVERSALS] += 1
                    planar_log(log, c, nn, ts + s0, dt, EV_REVERSAL, x, y, 0.0, 0.0)
                if c[PC_EVENTS] >= max_events:
                    return planar_stop(f, c, REASON_MAX_EVENTS, x, y, vx, vy, mode, nn, ts + s0, dt)
            if mode == 0:
                c[PC_ARCS] += 1
                planar_samples(samples, c, spp, n, dt, local + s0, seg - s0, False, w, x, y, 0.0, 0.0, mu, 0, False)
        if not (math.isfinite(x) and math.isfinite(y) and math.isfinite(vx) and math.isfinite(vy)):
            x, y, vx, vy, mode = start
            return planar_stop(f, c, REASON_NONFINITE, x, y, vx, vy, mode, n, tau0, dt)
    planar_samples(samples, c, spp, periods, dt, 0.0, 0.0, False, w, x, y, vx, vy, mu, mode, True)
    planar_stop(f, c, 0, x, y, vx, vy, mode, periods, tau0, dt)
    return REASON_MAX_PERIODS if until_rest else REASON_PERIODS
