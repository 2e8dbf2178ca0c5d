"""The general exact planar stepper: an accurate local solution with bracketed event location, for every planar
scene the closed form does not cover (strips, piecewise-linear y'' (finite jerk), Fourier components, and their
combinations; docs/explanation/planar-model.md, "General stepper: accurate local solution").

Slip (|v| > 0): x' = v, v' = -Y''(t) - mu_bar(x) v/|v| is integrated by the explicit Runge-Kutta method of order
8 of Dormand and Prince (DOP853, the coefficients of scipy.integrate's DOP853) with step-size control at
:data:`RTOL`, :data:`ATOL`.  The right-hand side is smooth between the events, and the steps are cut at them:

* a profile switch (a piece of the merged pieces table ends: y'' jumps or kinks) and the horizon's end, known in
  advance, are step ends;
* a strip boundary n.x = x_mu or x_mu + w (a kink of that strip's mu) and the equality of the two largest strip
  coefficients (a kink of their max) are located inside an accepted step by Brent's method on the event function
  of the step's own local solution: one DOP853 step of length s from the step's start is smooth in s, so the
  event time s is a root of g(step(s)), refined to 2 eps dt + 4 eps s;
* the stick event.  v/|v| is singular at v = 0, and in the plane the slip direction turns towards -Y'' as the
  speed vanishes (its angle to -Y'' decays as a power of the time left), so v is not smooth at the stop.  The
  speed itself falls linearly there, at the rate D = mu_bar + Y''.v/|v| > 0: a step is kept below
  :data:`APPROACH` times the time to stop |v| / D and every stage of an accepted step must keep moving along the
  step's start direction, so the steps approach the stop geometrically; once |v| / D <= :data:`STOP_FLOOR` dt the
  stop is placed at the linear extrapolation (time t + |v| / D, position x + v |v| / (2 D)), whose error is of
  second order in that floor.

Stick (v = 0) holds while |Y''(t)| <= r mu_bar(x) (tie: stick).  It ends at the first time |Y''|^2 > (r mu_bar)^2,
located by Brent's method: on a piece whose components are piecewise linear |Y''|^2 is a convex quadratic (the
end value decides, exactly one root); with a Fourier component on a grid of 64 (K + 1) intervals per period with
its interior maxima (zeros of Y''.Y''' between a + and a - at the grid points) tested.  The slip then starts from
rest along -Y''; a stop where |Y''| > r mu_bar is a reversal (the slip passes through zero speed and slips on
along -Y'', logged as REVERSAL and counted in the event budget, not among the slips).

Outcomes (:mod:`selfalign.solvers.planar_smooth`): REST at a stick where r mu_bar(x) >= max|Y''|; ACCUMULATION
(until='rest') at a stick in a strip's transition band nearer the strip's rest line (where its mu reaches
max|Y''| / r) than the previous band stick and within accumulation_tol of it, reported at its projection on that
line (the planar x_stick_min, eq. 41); PERIODS or MAX_PERIODS at the horizon; MAX_EVENTS, STALL (more than
STALL_EVENTS events in a row without time advancing, or a step rejected :data:`MAX_REJECTS` times in a row) and
NONFINITE (the last finite state is kept).
"""

from __future__ import annotations

import math

import numpy as np
from scipy.integrate._ivp import dop853_coefficients as _dop

from ...model import friction as F
from ...model.planar import STRIP_CMU, STRIP_NX, STRIP_NY, STRIP_W, STRIP_XMU, planar_coefficient
from .. import records as R
from ..outcomes import STALL_EVENTS
from .codes import (
    EPS,
    EV_REVERSAL,
    EV_SLIP,
    EV_STICK,
    EV_SWITCH,
    EV_ZONE,
    GF_CONTRACTION,
    GF_D1,
    GF_D2,
    GF_H,
    GF_LIMX,
    GF_LIMY,
    GF_TAU,
    GF_UX,
    GF_UY,
    GF_VX,
    GF_VY,
    GF_X,
    GF_Y,
    GI_BREAKS,
    GI_CROSSINGS,
    GI_EVENTS,
    GI_LOG,
    GI_MAX_EVENTS,
    GI_MODE,
    GI_NH,
    GI_PERIOD,
    GI_PERIODS,
    GI_PIECE,
    GI_RECORD_LOG,
    GI_RECORD_SAMPLES,
    GI_SAMPLES,
    GI_SLIPS,
    GI_STALLED,
    GI_STEPS,
    GI_STICKS,
    GI_UNTIL_REST,
    GS_ACC_TOL,
    GS_AMAX,
    GS_COS,
    GS_DT,
    GS_GRID,
    GS_RATIO,
    GS_SAMPLE,
    GS_SIN,
    GS_TAU0,
    NAN,
    PIECE_END,
    PIECE_OFFSET,
    PIECE_START,
    PIECE_X,
    PIECE_Y,
    REASON_ACCUMULATION,
    REASON_MAX_EVENTS,
    REASON_MAX_PERIODS,
    REASON_NONFINITE,
    REASON_PERIODS,
    REASON_REST,
    REASON_STALL,
)
from .compiled import jit
from .smooth import BRENT_MAX_ITER, _fourier_jerk, ramp_level, table_motion

#: Stages of DOP853 (the twelfth-stage method; its thirteenth evaluation, at the step's end, serves the error
#: estimate) and its coefficients, as scipy.integrate uses them.
STAGES = _dop.N_STAGES
RK_A = np.ascontiguousarray(_dop.A[:STAGES, :STAGES])
RK_B = np.ascontiguousarray(_dop.B)
RK_C = np.ascontiguousarray(_dop.C[:STAGES])
RK_E3 = np.ascontiguousarray(_dop.E3)
RK_E5 = np.ascontiguousarray(_dop.E5)
#: Tolerances of the step-size control (relative to max(|x|, |v|) component-wise, absolute): the local error of
#: an accepted step is below ATOL + RTOL |y| in DOP853's error norm.
RTOL, ATOL = 2.0e-15, 1.0e-17
#: Step-size control: safety factor and the bounds of the factor of one step change (scipy's DOP853).
SAFETY, MIN_FACTOR, MAX_FACTOR = 0.9, 0.2, 10.0
#: A slip step takes at most this fraction of the linear time to stop |v| / D ...
APPROACH = 0.75
#: ... until that time is below STOP_FLOOR dt: then the stop is placed by linear extrapolation.
STOP_FLOOR = 2.0**-40
#: A slip from rest starts with its direction slaved to -Y''/|Y''| (:func:`_field`): the true direction lags it
#: by about |v| |(Y''/|Y''|)'| / |Y''| radians, which relaxes at the rate |Y''| / |v|, a stiff mode an explicit
#: method could follow only with steps below ~|v| / |Y''|.  The slip leaves the slaved form for the full equation
#: once that lag would exceed SLAVED_LAG (a velocity error of at most SLAVED_LAG |v| there), where |Y''| falls
#: below mu_bar / 2 or turns away from -v (the cosine of their angle below SLAVED_ALIGNED), and at a switch where
#: v is no longer along the new -Y'' to SLAVED_LAG (the sine of their angle: Y'' jumps there, and the slip goes on
#: from the velocity it has).  While slaved, a step starts with v put back on that direction (it drifts off by
#: the step's integration error only).
SLAVED_LAG, SLAVED_ALIGNED = 1.0e-9, 0.5
#: Rejected tries of one step after which the run ends with STALL (a step that shrinks without end).
MAX_REJECTS = 200
#: Event functions (:func:`_event_value`): a strip boundary, the equality of two strips' coefficients, |Y''|^2
#: against the stick limit, Y''.Y''' (the extrema of |Y''|).
_BOUNDARY, _KINK, _STICK, _PEAK = 0, 1, 2, 3
#: What ended a slip step (:func:`_slip_step`).
_PLAIN, _STOPPED, _CROSSED, _FAILED = 0, 1, 2, 3


@jit
def _component(row, i, tau):
    """(y'', y''') of one component row (piecewise linear, -m pieces, or Fourier) on its piece i at its time tau."""
    k = R.data_size(row)
    if k > 0:
        return table_motion(row, tau)[2], _fourier_jerk(row, tau)
    m = -k
    jerk = row[R.col_jerk(m, i)]
    return ramp_level(row, i, row[R.col_level(m, i)] + jerk * (tau - row[R.col_break(i)])), jerk


@jit
def table_acceleration(rows, piece, q, tau):
    """(Y''_x, Y''_y, Y'''_x, Y'''_y) at phase tau, on the merged piece ``piece`` (a row of the pieces table: the
    piece of each component and the y component's time offset): Y'' = R(angle) (Px''(tau), Py''(tau - offset))."""
    ax, jx = _component(rows[0], int(piece[PIECE_X]), tau)
    ay, jy = _component(rows[1], int(piece[PIECE_Y]), tau - piece[PIECE_OFFSET])
    c, s = q[GS_COS], q[GS_SIN]
    return c * ax - s * ay, s * ax + c * ay, c * jx - s * jy, s * jx + c * jy


@jit
def _strip_coefficient(strips, i, px, py):
    """mu of strip i at (px, py): eqs. 7-9 along its normal."""
    r = strips[i]
    return F.coefficient(r[STRIP_NX] * px + r[STRIP_NY] * py - r[STRIP_XMU], r[STRIP_W], r[STRIP_CMU])


@jit
def _boundary_value(strips, j, px, py):
    """n.x - x_mu (j even) or n.x - x_mu - w (j odd) of strip j // 2."""
    r = strips[j // 2]
    g = r[STRIP_NX] * px + r[STRIP_NY] * py - r[STRIP_XMU]
    return g - r[STRIP_W] if j % 2 == 1 else g


@jit
def _field(rows, piece, strips, q, tau, y, u, slaved, out):
    """The slip's right-hand side (x', v') at phase tau and state y = (x, v) into ``out``.

    The friction direction is v/|v| where v moves along ``u`` (the step's start direction), else u: a stage that
    moves against u belongs to a step past the stop, which :func:`_rk_step` reports.  ``slaved``: the start of a
    slip from rest, where the direction is taken as -Y''/|Y''| itself (the velocity v = s (-Y''/|Y''|), s = -v.Y''/
    |Y''|, keeps that direction: v' = -Y'' + mu_bar Y''/|Y''| - s (Y''/|Y''|)'; :data:`SLAVED_LAG`)."""
    ax, ay, jx, jy = table_acceleration(rows, piece, q, tau)
    mu = planar_coefficient(y[0], y[1], strips)
    out[0] = y[2]
    out[1] = y[3]
    if slaved:
        size = math.hypot(ax, ay)
        ex, ey = ax / size, ay / size
        speed = -(y[2] * ex + y[3] * ey)
        turn = (jx * ey - jy * ex) / size              # (Y''/|Y''|)' = turn (-ey, ex)
        out[2] = -(size - mu) * ex + speed * turn * ey       # -Y'' + mu_bar Y''/|Y''| without cancellation
        out[3] = -(size - mu) * ey - speed * turn * ex
        return
    rho = math.hypot(y[2], y[3])
    if rho > 0.0 and y[2] * u[0] + y[3] * u[1] > 0.0:
        dx, dy = y[2] / rho, y[3] / rho
    else:
        dx, dy = u[0], u[1]
    out[2] = -ax - mu * dx
    out[3] = -ay - mu * dy


@jit
def _rk_step(rows, piece, strips, q, tau, y, u, slaved, h, k, out):
    """One DOP853 step of length h from state y at phase tau into ``out`` (``k``: the stage derivatives).  Returns
    (the error norm, whether every stage (of a step from motion; of a slip from rest, its end) kept moving along
    ``u``: a step that passes the stop is not a smooth local solution)."""
    moving = True
    from_motion = y[2] * u[0] + y[3] * u[1] > 0.0
    for s in range(STAGES):
        for i in range(4):
            acc = 0.0
            for j in range(s):
                acc += RK_A[s, j] * k[j, i]
            out[i] = y[i] + h * acc
        if s > 0 and from_motion and not out[2] * u[0] + out[3] * u[1] > 0.0:
            moving = False
        _field(rows, piece, strips, q, tau + RK_C[s] * h, out, u, slaved, k[s])
    for i in range(4):
        acc = 0.0
        for j in range(STAGES):
            acc += RK_B[j] * k[j, i]
        out[i] = y[i] + h * acc
    if h > 0.0 and not out[2] * u[0] + out[3] * u[1] > 0.0:
        moving = False
    _field(rows, piece, strips, q, tau + h, out, u, slaved, k[STAGES])
    e5 = 0.0
    e3 = 0.0
    for i in range(4):
        scale = ATOL + RTOL * max(abs(y[i]), abs(out[i]))
        a5 = 0.0
        a3 = 0.0
        for j in range(STAGES + 1):
            a5 += RK_E5[j] * k[j, i]
            a3 += RK_E3[j] * k[j, i]
        e5 += (a5 / scale) ** 2
        e3 += (a3 / scale) ** 2
    if e5 == 0.0 and e3 == 0.0:
        return 0.0, moving
    return abs(h) * e5 / math.sqrt((e5 + 0.01 * e3) * 4.0), moving


@jit
def _event_value(kind, a, b, rows, piece, strips, q, tau, y, u, slaved, s, k, out):
    """Event functions: _STICK |Y''|^2 - a^2 and _PEAK Y''.Y''' at phase tau + s; _BOUNDARY (strip boundary a) and
    _KINK (mu of strip a minus mu of strip b) at the state after one DOP853 step of length s from (tau, y)."""
    if kind == _STICK or kind == _PEAK:
        ax, ay, jx, jy = table_acceleration(rows, piece, q, tau + s)
        return ax * ax + ay * ay - a * a if kind == _STICK else ax * jx + ay * jy
    _rk_step(rows, piece, strips, q, tau, y, u, slaved, s, k, out)
    if kind == _BOUNDARY:
        return _boundary_value(strips, int(a), out[0], out[1])
    return _strip_coefficient(strips, int(a), out[0], out[1]) - _strip_coefficient(strips, int(b), out[0], out[1])


@jit
def _locate(kind, a, b, rows, piece, strips, q, tau, y, u, slaved, lo, hi, k, out):
    """The sign change of :func:`_event_value` in [lo, hi] (g(hi) = 0 or of the other sign than g(lo)) by Brent's
    method (the steps of scipy.optimize.brentq) to 2 eps dt + 4 eps s; returns the end of the last bracket on hi's
    side, so that the event has happened there."""
    xtol = 2.0 * EPS * q[GS_DT]
    rtol = 4.0 * EPS
    xpre, xcur = lo, hi
    fpre = _event_value(kind, a, b, rows, piece, strips, q, tau, y, u, slaved, xpre, k, out)
    fcur = _event_value(kind, a, b, rows, piece, strips, q, tau, y, u, slaved, xcur, k, out)
    if fcur == 0.0 or fpre == 0.0 or (fpre < 0.0) == (fcur < 0.0):
        return hi
    after = fcur > 0.0
    xblk = 0.0
    fblk = 0.0
    spre = 0.0
    scur = 0.0
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
            break
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
        fcur = _event_value(kind, a, b, rows, piece, strips, q, tau, y, u, slaved, xcur, k, out)
    if fcur == 0.0 or (fcur > 0.0) == after:
        return xcur
    return xblk


@jit
def _stick_end(rows, piece, strips, q, start, end, limit, k, out):
    """The first phase in [start, end] where |Y''| exceeds ``limit`` on the merged piece ``piece``, or -1."""
    y = out[:4]
    u = out[:2]
    if _event_value(_STICK, limit, 0.0, rows, piece, strips, q, 0.0, y, u, False, start, k, out) > 0.0:
        return start
    grid = q[GS_GRID]
    p = start
    while p < end:
        nxt = min(p + grid, end) if grid > 0.0 else end
        if _event_value(_STICK, limit, 0.0, rows, piece, strips, q, 0.0, y, u, False, nxt, k, out) > 0.0:
            return _locate(_STICK, limit, 0.0, rows, piece, strips, q, 0.0, y, u, False, p, nxt, k, out)
        if grid > 0.0 and _event_value(_PEAK, 0.0, 0.0, rows, piece, strips, q, 0.0, y, u, False, p, k, out) > 0.0 \
                and _event_value(_PEAK, 0.0, 0.0, rows, piece, strips, q, 0.0, y, u, False, nxt, k, out) < 0.0:
            peak = _locate(_PEAK, 0.0, 0.0, rows, piece, strips, q, 0.0, y, u, False, p, nxt, k, out)
            if _event_value(_STICK, limit, 0.0, rows, piece, strips, q, 0.0, y, u, False, peak, k, out) > 0.0:
                return _locate(_STICK, limit, 0.0, rows, piece, strips, q, 0.0, y, u, False, p, peak, k, out)
        p = nxt
    return -1.0


@jit
def _side(g, rate):
    """The side (+1, -1) of a boundary function g at a step's start; on the boundary (g = 0) the side the motion
    enters (``rate``: the rate of g); 0 if that is undecided too."""
    if g > 0.0 or (g == 0.0 and rate > 0.0):
        return 1
    if g < 0.0 or (g == 0.0 and rate < 0.0):
        return -1
    return 0


@jit
def _largest_strip(strips, px, py, dx, dy):
    """The strip with the largest mu > 1 at (px, py), -1 if none; a tie goes to the strip whose mu grows fastest
    along (dx, dy), then to the first."""
    best = -1
    top = 1.0
    rate = 0.0
    for i in range(strips.shape[0]):
        mu = _strip_coefficient(strips, i, px, py)
        r = strips[i]
        g = r[STRIP_NX] * px + r[STRIP_NY] * py - r[STRIP_XMU]
        grow = (r[STRIP_CMU] - 1.0) / r[STRIP_W] * (r[STRIP_NX] * dx + r[STRIP_NY] * dy) if 0.0 <= g < r[STRIP_W] \
            else 0.0
        if mu > 1.0 and (mu > top or (mu == top and grow > rate)):
            best, top, rate = i, mu, grow
    return best


@jit
def _record(buffer, c, counter, a0, a1, a2, a3, a4, a5):
    """Append a row (t, ...) to ``buffer`` (samples or the log) if there is room; always count it in c[counter]."""
    n = c[counter]
    if n < buffer.shape[0]:
        buffer[n, 0], buffer[n, 1], buffer[n, 2], buffer[n, 3], buffer[n, 4], buffer[n, 5] = a0, a1, a2, a3, a4, a5
    c[counter] = n + 1


@jit
def _slip_step(rows, piece, strips, q, tau, end, y, u, slaved, h, y1, tmp, k, sides):
    """One accepted slip step from (tau, y) of at most ``end`` - tau, its end state into ``y1``.  Returns (what ended
    it: _PLAIN, _STOPPED, _CROSSED or _FAILED, its length, the boundary crossed (j of :func:`_boundary_value`), the
    next step size, whether the slip from rest is still ``slaved`` (:data:`SLAVED_LAG`))."""
    dt = q[GS_DT]
    rho = math.hypot(y[2], y[3])
    if rho > 0.0:
        u[0], u[1] = y[2] / rho, y[3] / rho
    ax, ay, jx, jy = table_acceleration(rows, piece, q, tau)
    mu = planar_coefficient(y[0], y[1], strips)
    size = math.hypot(ax, ay)
    if slaved and (rho * abs(jx * ay - jy * ax) > SLAVED_LAG * size ** 3 or not size > 0.5 * mu
                   or not -(y[2] * ax + y[3] * ay) >= SLAVED_ALIGNED * rho * size):
        slaved = False
    elif slaved and rho > 0.0:              # on the slaved direction (it drifts off by the integration error only)
        y[2], y[3] = -rho * ax / size, -rho * ay / size
        u[0], u[1] = -ax / size, -ay / size
    rate = mu + ax * u[0] + ay * u[1]
    h = min(h, end - tau)
    if rho > 0.0 and rate > 0.0:
        left = rho / rate
        if left <= STOP_FLOOR * dt and left <= end - tau:
            y1[0] = y[0] + 0.5 * y[2] * left
            y1[1] = y[1] + 0.5 * y[3] * left
            y1[2] = 0.0
            y1[3] = 0.0
            return _STOPPED, left, -1, h, slaved
        h = min(h, APPROACH * left)
    rejects = 0
    while True:
        err, moving = _rk_step(rows, piece, strips, q, tau, y, u, slaved, h, k, y1)
        if moving and err <= 1.0:
            break
        rejects += 1
        if rejects > MAX_REJECTS or not h > 0.0:
            return _FAILED, 0.0, -1, h, slaved
        h *= 0.25 if not moving or not err < math.inf else max(MIN_FACTOR, SAFETY * err ** -0.125)
    grow = MAX_FACTOR if err == 0.0 else min(MAX_FACTOR, SAFETY * err ** -0.125)
    h_next = h * grow if rejects == 0 else h
    # Strip boundaries: the first one whose side has changed at the step's end, located on the local solution.
    length = h
    crossed = -1
    nb = 2 * strips.shape[0]
    for j in range(nb):
        g0 = _boundary_value(strips, j, y[0], y[1])
        r = strips[j // 2]
        vn = r[STRIP_NX] * y[2] + r[STRIP_NY] * y[3]
        an = r[STRIP_NX] * k[0, 2] + r[STRIP_NY] * k[0, 3]
        sides[j] = _side(g0, vn if vn != 0.0 else an)
    for j in range(nb):
        side = sides[j]
        if side == 0 or side * _boundary_value(strips, j, y1[0], y1[1]) > 0.0:
            continue
        lo = 0.0
        if _boundary_value(strips, j, y[0], y[1]) == 0.0:    # starts on it: from a point on its side
            lo = h
            for _ in range(60):
                lo *= 0.5
                if side * _event_value(_BOUNDARY, j, 0.0, rows, piece, strips, q, tau, y, u, slaved, lo, k,
                                       tmp) > 0.0:
                    break
            if not side * _event_value(_BOUNDARY, j, 0.0, rows, piece, strips, q, tau, y, u, slaved, lo, k, tmp) > 0:
                continue
        s = _locate(_BOUNDARY, j, 0.0, rows, piece, strips, q, tau, y, u, slaved, lo, h, k, tmp)
        if s < length or crossed < 0:
            length, crossed = s, j
    if crossed >= 0:
        _rk_step(rows, piece, strips, q, tau, y, u, slaved, length, k, y1)
    # The largest of two strips' coefficients changes: a kink of mu_bar (no event of the log).
    if strips.shape[0] > 1:
        first = _largest_strip(strips, y[0], y[1], y[2] if rho > 0.0 else u[0], y[3] if rho > 0.0 else u[1])
        last = _largest_strip(strips, y1[0], y1[1], 0.0, 0.0)
        if first >= 0 and last >= 0 and first != last \
                and _strip_coefficient(strips, first, y[0], y[1]) > _strip_coefficient(strips, last, y[0], y[1]) \
                and _strip_coefficient(strips, first, y1[0], y1[1]) < _strip_coefficient(strips, last, y1[0], y1[1]):
            length = _locate(_KINK, first, last, rows, piece, strips, q, tau, y, u, slaved, 0.0, length, k, tmp)
            crossed = -1
            _rk_step(rows, piece, strips, q, tau, y, u, slaved, length, k, y1)
    return (_CROSSED if crossed >= 0 else _PLAIN), length, crossed, h_next, slaved


@jit
def _samples_until(samples, c, q, t0, span, y, u, slaved, rows, piece, strips, tau, mode, k, tmp):
    """Record the samples at times in (t0, t0 + span] (the first one at t0 too, if it is still due): stuck or at
    the linear stop (``mode`` 0, 2: x + v s (1 - s / (2 span)), v (1 - s / span)) or on the slip's local solution
    (``mode`` 1: one DOP853 step of length s from (tau, y))."""
    while c[GI_SAMPLES] < samples.shape[0]:
        t = q[GS_TAU0] + c[GI_SAMPLES] * q[GS_SAMPLE]
        s = t - t0
        if s > span:
            return
        s = max(s, 0.0)
        if mode == 1:
            _rk_step(rows, piece, strips, q, tau, y, u, slaved, s, k, tmp)
            _record(samples, c, GI_SAMPLES, t, tmp[0], tmp[1], tmp[2], tmp[3], 1.0)
        elif mode == 2:
            f = 1.0 - s / span if span > 0.0 else 0.0
            g = s * (1.0 - 0.5 * s / span) if span > 0.0 else 0.0
            _record(samples, c, GI_SAMPLES, t, y[0] + y[2] * g, y[1] + y[3] * g, y[2] * f, y[3] * f, 1.0)
        else:
            _record(samples, c, GI_SAMPLES, t, y[0], y[1], 0.0, 0.0, 0.0)


@jit
def _held(q, f, c, strips, px, py, mu):
    """The stick outcomes at (px, py) (friction ``mu``): REST where r mu >= max|Y''|, ACCUMULATION (until='rest')
    at a band stick nearer its strip's rest line than the previous one and within accumulation_tol of it, else 0."""
    r = q[GS_RATIO]
    amax = q[GS_AMAX]
    if r * mu >= amax:
        return REASON_REST
    if c[GI_UNTIL_REST] == 0 or strips.shape[0] == 0:
        return 0
    i = _largest_strip(strips, px, py, 0.0, 0.0)
    if i < 0:
        return 0
    s = strips[i]
    g = s[STRIP_NX] * px + s[STRIP_NY] * py - s[STRIP_XMU]
    if not (0.0 <= g <= s[STRIP_W] and amax / r <= s[STRIP_CMU]):
        return 0
    d = (amax / r - mu) * s[STRIP_W] / (s[STRIP_CMU] - 1.0)
    if c[GI_NH] >= 1 and d < f[GF_D1] and d <= q[GS_ACC_TOL]:
        f[GF_LIMX], f[GF_LIMY] = px + d * s[STRIP_NX], py + d * s[STRIP_NY]
        f[GF_CONTRACTION] = (f[GF_D1] - d) / (f[GF_D2] - f[GF_D1]) if c[GI_NH] >= 2 and f[GF_D2] > f[GF_D1] else NAN
        return REASON_ACCUMULATION
    f[GF_D2] = f[GF_D1]
    f[GF_D1] = d
    c[GI_NH] = min(c[GI_NH] + 1, 2)
    return 0


@jit
def run_planar_smooth(rows, pieces, strips, q, f, c, samples, log):
    """Run one planar scene: the start state in ``f``, ``c`` (columns of :mod:`.codes`: G*, I*), the profile as two
    component rows and the merged pieces table, the strips (K, 5), the settings ``q``; writes the end state, the
    counts, the samples and the log (counted past their ends, written while they fit).  Returns the reason code."""
    dt = q[GS_DT]
    tau0 = q[GS_TAU0]
    periods = c[GI_PERIODS]
    record_samples = c[GI_RECORD_SAMPLES] != 0
    record_log = c[GI_RECORD_LOG] != 0
    y = np.empty(4)
    y1 = np.empty(4)
    tmp = np.empty(4)
    u = np.empty(2)
    k = np.empty((STAGES + 1, 4))
    sides = np.zeros(2 * strips.shape[0], np.int64)
    y[0], y[1], y[2], y[3] = f[GF_X], f[GF_Y], f[GF_VX], f[GF_VY]
    u[0], u[1] = f[GF_UX], f[GF_UY]
    tau = f[GF_TAU]
    n = c[GI_PERIOD]
    p = c[GI_PIECE]
    mode = c[GI_MODE]
    h = f[GF_H]
    slaved = False
    last_event = -1.0
    stalled = 0
    reason = -1
    if record_samples:
        _samples_until(samples, c, q, n * dt + tau, 0.0, y, u, slaved, rows, pieces[p], strips, tau,
                       0 if mode == 0 else 1, k, tmp)
    if mode == 0:
        held = _held(q, f, c, strips, y[0], y[1], planar_coefficient(y[0], y[1], strips))
        if held == REASON_REST and c[GI_UNTIL_REST] != 0:
            reason = held
    while reason < 0:
        if n >= periods and tau >= tau0:
            reason = REASON_PERIODS if c[GI_UNTIL_REST] == 0 else REASON_MAX_PERIODS
            break
        piece = pieces[p]
        end = piece[PIECE_END]
        if n >= periods and tau0 < end:
            end = tau0
        t0 = n * dt + tau
        event = -1
        if mode == 0:
            mu = planar_coefficient(y[0], y[1], strips)
            root = _stick_end(rows, piece, strips, q, tau, end, q[GS_RATIO] * mu, k, tmp)
            span = (root if root >= 0.0 else end) - tau
            if record_samples:
                _samples_until(samples, c, q, t0, span, y, u, slaved, rows, piece, strips, tau, 0, k, tmp)
            tau = root if root >= 0.0 else end
            if root >= 0.0:
                ax, ay, _, _ = table_acceleration(rows, piece, q, tau)
                size = math.hypot(ax, ay)
                u[0], u[1] = -ax / size, -ay / size
                mode = 1
                slaved = True
                event = EV_SLIP
                c[GI_SLIPS] += 1
        else:
            outcome, length, crossed, h_next, slaved = _slip_step(rows, piece, strips, q, tau, end, y, u, slaved, h,
                                                                  y1, tmp, k, sides)
            if outcome == _FAILED:
                reason = REASON_STALL
                break
            if not (math.isfinite(y1[0]) and math.isfinite(y1[1]) and math.isfinite(y1[2]) and math.isfinite(y1[3])):
                reason = REASON_NONFINITE
                break
            if record_samples:
                _samples_until(samples, c, q, t0, length, y, u, slaved, rows, piece, strips, tau,
                               2 if outcome == _STOPPED else 1, k, tmp)
            h = h_next
            c[GI_STEPS] += 1
            before = tau
            tau = end if length == end - tau else tau + length
            if tau == before and outcome == _PLAIN:       # a step that does not advance: a stalled loop
                stalled += 1
                if stalled > STALL_EVENTS:
                    reason = REASON_STALL
                    break
            y[0], y[1], y[2], y[3] = y1[0], y1[1], y1[2], y1[3]
            if outcome == _CROSSED:
                event = EV_ZONE
                c[GI_CROSSINGS] += 1
            elif outcome == _STOPPED:
                ax, ay, _, _ = table_acceleration(rows, piece, q, tau)
                mu = planar_coefficient(y[0], y[1], strips)
                limit = q[GS_RATIO] * mu
                if ax * ax + ay * ay <= limit * limit:
                    mode = 0
                    event = EV_STICK
                    c[GI_STICKS] += 1
                else:                           # passes through zero speed: slips on along -Y'' (a reversal)
                    size = math.hypot(ax, ay)
                    u[0], u[1] = -ax / size, -ay / size
                    slaved = True
                    event = EV_REVERSAL
        if event >= 0:
            c[GI_EVENTS] += 1
            t = n * dt + tau
            if record_log:
                _record(log, c, GI_LOG, t, float(event), y[0], y[1], y[2], y[3])
            stalled = stalled + 1 if t == last_event else 0
            last_event = t
            if event == EV_STICK:
                reason = _held(q, f, c, strips, y[0], y[1], planar_coefficient(y[0], y[1], strips))
                if reason == REASON_REST and c[GI_UNTIL_REST] == 0:
                    reason = -1
                if reason == 0:
                    reason = -1
                if reason >= 0:
                    break
            if stalled > STALL_EVENTS:
                reason = REASON_STALL
                break
            if c[GI_EVENTS] >= c[GI_MAX_EVENTS]:
                reason = REASON_MAX_EVENTS
                break
        if tau >= piece[PIECE_END]:                # the next merged piece: a switch of a component, or a period
            nxt = p + 1
            if nxt == pieces.shape[0]:
                nxt = 0
                n += 1
                tau = 0.0
            else:
                tau = pieces[nxt, PIECE_START]
            if slaved and mode == 1:               # Y'' may jump here: slaved on only if v is along the new -Y''
                ax, ay, _, _ = table_acceleration(rows, pieces[nxt], q, tau)
                slaved = abs(y[2] * ay - y[3] * ax) <= SLAVED_LAG * math.hypot(y[2], y[3]) * math.hypot(ax, ay)
            if pieces[nxt, PIECE_X] != piece[PIECE_X] or pieces[nxt, PIECE_Y] != piece[PIECE_Y]:
                c[GI_BREAKS] += 1
                if record_log:
                    _record(log, c, GI_LOG, n * dt + tau, float(EV_SWITCH), y[0], y[1], y[2], y[3])
            p = nxt
    if reason == REASON_PERIODS or reason == REASON_MAX_PERIODS:
        while record_samples and c[GI_SAMPLES] < samples.shape[0]:
            _record(samples, c, GI_SAMPLES, tau0 + c[GI_SAMPLES] * q[GS_SAMPLE], y[0], y[1], y[2], y[3],
                    0.0 if mode == 0 else 1.0)
    f[GF_X], f[GF_Y], f[GF_VX], f[GF_VY] = y[0], y[1], y[2], y[3]
    f[GF_TAU], f[GF_UX], f[GF_UY], f[GF_H] = tau, u[0], u[1], h
    c[GI_PERIOD], c[GI_PIECE], c[GI_MODE], c[GI_STALLED] = n, p, mode, stalled
    return reason
