"""The exact stepper on a smooth profile on a uniform surface: a Fourier profile, or y'' piecewise
linear (finite jerk).  The arcs are closed form in the profile; event times are bracketed on a
grid and refined by Brent's method (:func:`brent`) to ~1 ulp.
"""

from __future__ import annotations

import math

import numpy as np

from ...model import arcs as A
from ...model import friction as F
from .. import records as R
from ..outcomes import LOW
from .codes import ARC_SMOOTH, ARC_STICK, DONE, EPS, EV_REVERSAL, EV_SLIP, EV_STICK, NAN, STOP_BUDGET
from .compiled import jit
from .field import holds_for_good, next_boundary, on_stick, record_crossings, stop_at
from .recording import record_arc, record_event

#: Evaluations of Brent's method at most per event time (it needs ~10 to 1 ulp).
BRENT_MAX_ITER = 200
#: Grid intervals per piece of a piecewise-linear-y'' profile, for the smooth stepper and the
#: stop-zone stepper's brackets (which add as many per harmonic period): between two grid points
#: the slip velocity has at most one extremum, which is tested where it can be a zero
#: (:func:`_slip_minimum`, :func:`_jerk_arc_end`).
GRID_PER_PIECE = 16
#: Event functions of this stepper (:func:`_event_function`).
STICK_LIMIT, SLIP_VELOCITY, JERK = 0, 1, 2



@jit
def _fourier(row, t):
    """(y, y', y'') of the Fourier profile in ``row`` at time t."""
    k = R.data_size(row)
    y = 0.0
    yd = 0.0
    ydd = 0.0
    for i in range(k):
        a, b, om = row[R.col_fourier(k, 0, i)], row[R.col_fourier(k, 1, i)], row[R.col_fourier(k, 2, i)]
        c, sn = math.cos(om * t), math.sin(om * t)
        y += a * c + b * sn
        yd += om * (b * c - a * sn)
        ydd -= om * om * (a * c + b * sn)
    return y, yd, ydd


@jit
def ramp_level(row, i, value):
    """``value``, a y'' of piece i of a piecewise-linear-y'' row, kept within the piece's range
    [min(a_i, e_i), max(a_i, e_i)] (start value a_i, end value e_i: the profile's ``ends``): a
    ramp's a + j s, its break times rounded, would otherwise pass the level it ends on."""
    m = -R.data_size(row)
    a, e = row[R.col_level(m, i)], row[R.col_end_level(m, i)]
    return min(max(value, min(a, e)), max(a, e))


@jit
def _piecewise_linear(row, t):
    """(y, y', y'') of the piecewise-linear-y'' profile in ``row`` at time t in [0, 2 dt)."""
    dt = row[R.DT]
    m = -R.data_size(row)
    tau = t - dt if t >= dt else t
    i = 0
    while i + 1 < m and row[R.col_break(i + 1)] <= tau:
        i += 1
    s = tau - row[R.col_break(i)]
    a, j = row[R.col_level(m, i)], row[R.col_jerk(m, i)]
    yd, y = row[R.col_start_velocity(m, i)], row[R.col_start_position(m, i)]
    return y + s * (yd + s * (a / 2.0 + s * j / 6.0)), yd + s * (a + s * j / 2.0), ramp_level(row, i, a + j * s)


@jit
def table_motion(row, t):
    """(y, y', y'') of the smooth stepper's profile ``row`` (a Fourier row has K > 0 in its
    first data column, a piecewise-linear one -m)."""
    if R.data_size(row) > 0:
        return _fourier(row, t)
    return _piecewise_linear(row, t)


@jit
def _event_function(kind, row, t0, s, sign, v, s0, yd0, limit):
    """Event functions of the smooth stepper: STICK_LIMIT, |y''| crossing the stick limit
    ``limit`` = r mu_bar = r upwards while stuck (sign sgn(y'')); SLIP_VELOCITY, the relative
    velocity of a slip in direction ``sign`` from (s0, v): x' = v - sign (s - s0) -
    (y'(t0 + s) - y'(t0 + s0)), signed; JERK, sign y''' of a Fourier profile (its zeros are the
    extrema of y'')."""
    if kind == JERK:
        return sign * _fourier_jerk(row, t0 + s)
    y, yd, ydd = table_motion(row, t0 + s)
    if kind == STICK_LIMIT:
        return sign * ydd - limit
    return sign * A.smooth_velocity(sign, v, s - s0, yd0, yd)


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
        if _event_function(SLIP_VELOCITY, row, t0, p, sign, v, s0, yd0, limit) > 0.0:
            return p
    return s0


@jit
def _fourier_jerk(row, t):
    """y''' of the Fourier profile in ``row`` at time t."""
    k = R.data_size(row)
    total = 0.0
    for i in range(k):
        a, b, om = row[R.col_fourier(k, 0, i)], row[R.col_fourier(k, 1, i)], row[R.col_fourier(k, 2, i)]
        total += om * om * om * (a * math.sin(om * t) - b * math.cos(om * t))
    return total


@jit
def _fourier_peak_bound(row):
    """A bound of max|y''''| of the Fourier profile in ``row``: the sum of |c_i| w_i^4."""
    k = R.data_size(row)
    total = 0.0
    for i in range(k):
        a, b, om = row[R.col_fourier(k, 0, i)], row[R.col_fourier(k, 1, i)], row[R.col_fourier(k, 2, i)]
        total += math.sqrt(a * a + b * b) * om**4
    return total


@jit
def _stick_peak(row, t0, p, q, ydd_p, ydd_q, limit, m4, xtol, rtol):
    """Where |y''| of a Fourier profile exceeds the stick limit inside the grid interval [p, q]
    although not at its ends, or -1.

    Only at an interior extremum t* of y'' (y'''(t*) = 0) can it: by Taylor about t*,
    |y''(t*)| <= |y''| at the nearer end + m4 (q - p)^2 / 8 (m4 >= max|y''''|), so an interval where
    that bound stays within the limit is skipped; otherwise the extremum between a sign change of
    y''' is located by Brent's method and returned if |y''| there exceeds the limit (a stuck mass
    then slips between the interval's start and it; the caller locates where)."""
    if not max(abs(ydd_p), abs(ydd_q)) + m4 * (q - p) * (q - p) / 8.0 > limit:
        return -1.0
    j_p, j_q = _fourier_jerk(row, t0 + p), _fourier_jerk(row, t0 + q)
    if j_p == 0.0 or j_q == 0.0 or (j_p > 0.0) == (j_q > 0.0):
        return -1.0
    peak = _brent(JERK, row, t0, 1.0, 0.0, 0.0, 0.0, 0.0, p, q, xtol, rtol)
    if abs(table_motion(row, t0 + peak)[2]) > limit:
        return peak
    return -1.0


@jit
def _past_jump(row, t0, sign, limit, q, xtol):
    """Where a stuck mass starts to slip when y'' jumps past the limit at the break q of a
    piecewise-linear-y'' row (y'' is linear between grid points, and the limit is not reached
    before q from the left): q, or the first point a few ulps on where the profile evaluates to
    the new piece (q + t0 may round below the break).  Brent's method would converge to either
    side of the jump, and a slip started on its near side ends at once and sticks again there."""
    root = q
    for _ in range(8):
        if _event_function(STICK_LIMIT, row, t0, root, sign, 0.0, 0.0, 0.0, limit) >= 0.0:
            break
        root += 0.5 * xtol
    return root


@jit
def _slip_minimum(row, t0, sigma, p, q, g_p, slope_p, g_q, slope_q, xtol, rtol):
    """The interior minimum of the slip velocity G = sigma x' on the grid interval [p, q] of
    :func:`period_smooth` (G(p), G(q) > 0 and G'(p) = ``slope_p`` < 0 given), or -1 if G has
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
    if R.data_size(row) < 0:
        h = q - p
        c = 2.0 * (g_q - g_p - slope_p * h) / (h * h)
        if c > 0.0:
            s = p - slope_p / c
            if p < s < q:
                return s
        return -1.0
    if slope_q > 0.0:
        return _brent(STICK_LIMIT, row, t0, -sigma, 0.0, 0.0, 0.0, 1.0, p, q, xtol, rtol)
    return -1.0


@jit
def _grid_intervals(row):
    """Intervals of the smooth stepper's grid on one period: 64 (order + 1) on a Fourier
    profile, :data:`GRID_PER_PIECE` per piece on a piecewise-linear one."""
    if R.data_size(row) > 0:
        return 64 * (R.data_size(row) + 1)
    return GRID_PER_PIECE * -R.data_size(row)


@jit
def grid_scratch(method, table):
    """Scratch space (3, points) for :func:`smooth_grid`, enough for every profile of ``table``
    (none for the other steppers): allocated once per kernel call, not once per member."""
    points = 0
    if method == R.EXACT_SMOOTH:
        for p in range(table.shape[0]):
            points = max(points, _grid_intervals(table[p]) + 2)
    return np.empty((3, points))


@jit
def smooth_grid(row, tau0, scratch):
    """(grid offsets from tau0, y', y'') on one period, views of ``scratch``: 64 (order + 1) + 1
    uniform points on a Fourier profile; on a piecewise-linear one the breaks and
    :data:`GRID_PER_PIECE` uniform points per piece, from tau0 round to tau0 + dt."""
    g = _grid_intervals(row)
    dt = row[R.DT]
    if R.data_size(row) > 0:
        points = g + 1
        for i in range(points):
            scratch[0, i] = dt * i / g
    else:
        m = -R.data_size(row)
        scratch[0, 0] = 0.0
        points = 1
        for after in (True, False):           # the pieces' points after tau0, then (next period) before it
            for i in range(m):
                for k in range(GRID_PER_PIECE):
                    p = row[R.col_break(i)] + (row[R.col_break(i + 1)] - row[R.col_break(i)]) * k / GRID_PER_PIECE
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
        _, yd[i], ydd[i] = table_motion(row, tau0 + grid[i])
    return grid, yd, ydd


@jit
def period_smooth(s, row, run, bnd, cross, record, buffers, scratch, periods):
    """Advance member ``s`` one period on a smooth (Fourier or piecewise-linear-y'') profile, uniform surface."""
    until, max_events = run.until, run.max_events
    arcs, events = buffers[0], buffers[1]
    grid, g_yd, g_ydd = scratch
    dt = row[R.DT]
    tau0 = s.tau0
    xtol = 2.0 * EPS * dt
    rtol = 4.0 * EPS
    xi, v, mode, n = s.xi, s.v, s.mode, s.n
    dxp = 0.0
    lo = 0.0
    hi = 0.0
    s.fresh = False
    s0 = 0.0
    g = grid.shape[0]
    lowest = next_boundary(bnd, cross)
    limit = s.static_ratio              # stick while |y''| <= r mu_bar (mu_bar = 1 here)
    fourier = R.data_size(row) > 0
    m4 = _fourier_peak_bound(row) if fourier else 0.0
    while True:
        k0 = 0
        while k0 < g and grid[k0] <= s0:
            k0 += 1
        if mode == 0:
            k = k0
            peak = -1.0
            while k < g and not abs(g_ydd[k]) > limit:
                if fourier and k > 0:
                    left = max(s0, grid[k - 1])
                    ydd_left = g_ydd[k - 1] if left == grid[k - 1] else table_motion(row, tau0 + left)[2]
                    peak = _stick_peak(row, tau0, left, grid[k], ydd_left, g_ydd[k], limit, m4, xtol, rtol)
                    if peak >= 0.0:
                        break
                k += 1
            if k >= g:
                if record:
                    record_arc(arcs, s, dt, ARC_STICK, n, tau0 + s0, dt - s0, xi, 0.0, 0.0, NAN, 0.0,
                                       0, LOW)
                break
            ydd_k = table_motion(row, tau0 + peak)[2] if peak >= 0.0 else g_ydd[k]
            sgn = 1.0 if ydd_k > 0.0 else -1.0
            left = max(s0, grid[k - 1])
            f_left = _event_function(STICK_LIMIT, row, tau0, left, sgn, 0.0, 0.0, 0.0, limit)
            if f_left >= 0.0:
                root = left
            elif peak >= 0.0:                   # |y''| passes the limit only inside the interval
                root = _brent(STICK_LIMIT, row, tau0, sgn, 0.0, 0.0, 0.0, limit, left, peak, xtol, rtol)
            elif R.data_size(row) < 0 and not 2.0 * _event_function(STICK_LIMIT, row, tau0, 0.5 * (left + grid[k]), sgn,
                                                                 0.0, 0.0, 0.0, limit) - f_left > 0.0:
                root = _past_jump(row, tau0, sgn, limit, grid[k], xtol)
            else:
                root = _brent(STICK_LIMIT, row, tau0, sgn, 0.0, 0.0, 0.0, limit, left, grid[k], xtol, rtol)
            new = -int(sgn)
            if record:
                record_arc(arcs, s, dt, ARC_STICK, n, tau0 + s0, root - s0, xi, 0.0, 0.0, NAN, 0.0, 0, LOW)
                ydd_r = table_motion(row, tau0 + root)[2]
                record_event(events, s, dt, EV_SLIP, n, tau0 + root, xi, 0.0, 0, new, 0.0, -ydd_r + sgn)
            s.events += 1
            mode, v, s0 = new, 0.0, root
        else:
            sigma = float(mode)
            y0, yd0, ydd0 = table_motion(row, tau0 + s0)
            # First grid point where the velocity has the slip's sign (a slip from rest
            # first has to leave v = 0), then the first where it has lost it again.  A slip
            # from rest already back through v = 0 at a grid point (shorter than the grid's
            # spacing) is bracketed between that point and one of the slip's sign before it.
            k = k0
            short = False
            if not sigma * v > 0.0:
                while k < g:
                    moved = sigma * A.smooth_velocity(sigma, v, grid[k] - s0, yd0, g_yd[k])
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
                    g_k = sigma * A.smooth_velocity(sigma, v, grid[k] - s0, yd0, g_yd[k])
                    if not g_k > 0.0:
                        break
                    if slope < 0.0:
                        s_min = _slip_minimum(row, tau0, sigma, p, grid[k], g_prev, slope, g_k,
                                              -1.0 - sigma * g_ydd[k], xtol, rtol)
                        if s_min >= 0.0 and not _event_function(SLIP_VELOCITY, row, tau0, s_min, sigma, v, s0, yd0,
                                                                limit) > 0.0:
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
                root = _brent(SLIP_VELOCITY, row, tau0, sigma, v, s0, yd0, limit, left,
                              dip if dip >= 0.0 else grid[k], xtol, rtol)
                found = True
            d = root - s0
            y1, yd1, ydd1 = table_motion(row, tau0 + root)
            dx, v_end = A.smooth_step(sigma, v, d, y0, yd0, y1, yd1)
            if record:
                record_arc(arcs, s, dt, ARC_SMOOTH, n, tau0 + s0, d, xi, v, -ydd0 - sigma, NAN, 0.0, mode, LOW)
            s.path += abs(dx)
            s.xi_max = max(s.xi_max, xi + dx)
            if xi + dx >= lowest:
                lowest = record_crossings(s, bnd, cross, ARC_SMOOTH, 0.0, xi, v, 0.0, xi + dx,
                                          v_end if not found else 0.0, n, tau0 + s0, d)
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
                record_event(events, s, dt, EV_STICK if new == 0 else EV_REVERSAL, n, tau0 + root, xi, 0.0,
                                       mode, new, -ydd1 - sigma, 0.0 if new == 0 else -ydd1 - new)
            mode = new
            if new == 0:
                code = on_stick(s, xi, 1.0, n, tau0 + root, until, holds_for_good(s, 1.0))
                if code != DONE:
                    s.dxp, s.lo, s.hi, s.regions = dxp, lo, hi, 1
                    return stop_at(s, code, xi, 0.0, 0, n, tau0 + root, dt)
        if s.events >= max_events:
            s.dxp, s.lo, s.hi, s.regions = dxp, lo, hi, 1
            return stop_at(s, STOP_BUDGET, xi, v, mode, n, tau0 + s0, dt)
    s.xi, s.v, s.mode, s.n = xi, v, mode, n + 1
    s.dxp, s.lo, s.hi, s.regions = dxp, lo, hi, 1
    return DONE
