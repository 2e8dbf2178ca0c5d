"""An independent high-precision integrator of the model (eqs. 6-9, Sect. 3), the audit's referee.

Written from the model equations alone, in mpmath at :data:`DPS` digits: it imports nothing of
``selfalign`` (tests/test_audit.py checks that) and builds the table acceleration y''(t) of one
period itself, from the profile parameters (the Appendix's closed form for the three-phase profile,
docs/explanation/model.md items 1-3 for its ramps, the table of "The polynomial profile").

Model (dimensionless, Sect. 3.2).  x is the position relative to the table, v = x', xi = x - x_mu.
mu(xi) = 1 for xi < 0, 1 + b1 xi on [0, w] with b1 = (c_mu - 1)/w, c_mu for xi > w (eqs. 7-9).
Slip with sigma = sign(v): x'' = -y''(t) - sigma mu(xi).  Stick (v = 0) holds while
|y''| <= r mu(xi) (r = mu_s/mu_k, 1 for Coulomb; a tie counts as stick); a slip then starts in
the direction sigma = -sign(y'').  A slip that reaches v = 0 sticks if |y''| <= r mu(xi) there, and
otherwise continues the other way.

Arcs.  y'' is piecewise linear in time (a + j s on each piece; j = 0 for the paper's jumps), so on
each piece and each friction region the arc is closed form:
- constant mu = m: x'' = -(a + sigma m) - j s, so v is quadratic and x cubic in s;
- transition zone: xi'' + sigma b1 xi = -(a + sigma) - j s: harmonic (forward, omega^2 = b1) or
  hyperbolic (backward) around the particular solution (-(a + sigma) - j s) / (sigma b1).

Events without sampling.  The acceleration A = x'' of an arc satisfies A'' = -sigma b1 A (zone) or
A'' = 0 (constant mu): on an interval shorter than pi / (2 omega) (the whole piece outside the
harmonic case) A is a line, a piece of a sinusoid shorter than a quarter period, or a sum of two
exponentials, and has at most one zero, which is simple unless A vanishes identically.  So a sign
change of A at the interval's ends finds its only zero, v is monotone on either side of it, and a
zero of v is bracketed by a sign change on a monotone part.  Before the first zero of v, x is
monotone, so a zone edge is crossed exactly when x passes it at that zero (or at the interval's
end).  Every root is refined in its bracket by the Illinois method (bisection whenever it stalls)
to 1e-45 of the period.  So no event is missed, and event times are exact to far below 1e-30.

Degenerate starts.  A slip from rest is followed for DELTA = 1e-24 before its first stop is
searched: with Coulomb friction on a ramp the relative acceleration starts at exactly 0, and its
rounding (1e-60) could otherwise fake a stop at once.  A slip that has not developed by then
(sigma v <= 0) is no slip: the mass stays stuck.  This ignores motions shorter than 1e-24
(displacements below 1e-48), far below any comparison made with the referee.

Stribeck friction (velocity-dependent) and Fourier profiles have no closed-form arcs here; the
referee refuses them.
"""

from __future__ import annotations

import mpmath as mp

#: Working digits; results are trusted to ~40 (the zone arcs' closed forms cancel up to
#: log10(|a| / (b1 w)) digits for wide, weak zones).
DPS = 60
#: Length of the "does the slip develop" probe after a slip from rest (dimensionless time).
DELTA = mp.mpf("1e-24")
#: Root tolerance in time, as a fraction of dt.
ROOT_TOL = mp.mpf("1e-45")


class Table:
    """y''(t) over one period: ``breaks`` t_0 = 0 < ... < t_m = dt, on piece k y'' = a_k + j_k (t - t_k)."""

    def __init__(self, dt, breaks, accels, jerks):
        self.dt, self.breaks, self.accels, self.jerks = dt, breaks, accels, jerks


def _mpf(value):
    return mp.mpf(float(value))


def three_phase_table(dt, dy, y2, y3, ramp=None, jerk=None) -> Table:
    """The three-phase profile (Sect. 4.4.3, Appendix), with linear ramps of time ``ramp`` (or
    |jump| / ``jerk``) centred on the switches (docs/explanation/model.md), or the paper's jumps."""
    with mp.workdps(DPS):
        dt, dy, y2, y3 = (_mpf(v) for v in (dt, dy, y2, y3))
        k = 1 / y2 + 1 / y3
        if ramp is None and jerk is None:
            q = mp.sqrt(8 * dy * k) / dt
            r = mp.sqrt(1 - q)
            t1 = dt * r
            t2 = t1 + dt * (1 - r) / k / y2
            return Table(dt, [mp.mpf(0), t1, t2, dt], [mp.mpf(0), -y2, y3], [mp.mpf(0)] * 3)
        if ramp is not None:
            ta = tb = tc = _mpf(ramp)
        else:
            jerk = _mpf(jerk)
            ta, tb, tc = y2 / jerk, (y2 + y3) / jerk, y3 / jerk
        shift = (-y2 * ta**2 + (y2 + y3) * tb**2 - y3 * tc**2) / 24
        dip = (y2 + y3) * tb**2 / 24
        depth = mp.sqrt(2 * (dy + dip) / k)
        q = 2 * k * (depth - shift / dt) / dt
        r = mp.sqrt(1 - q)
        t1 = dt * r
        t2 = t1 + dt * (1 - r) / k / y2
        ha, hb, hc = ta / 2, tb / 2, tc / 2
        breaks = [mp.mpf(0), hc, t1 - ha, t1 + ha, t2 - hb, t2 + hb, dt - hc, dt]
        accels = [y3 / 2, mp.mpf(0), mp.mpf(0), -y2, -y2, y3, y3]
        jerks = [-y3 / tc, mp.mpf(0), -y2 / ta, mp.mpf(0), (y2 + y3) / tb, mp.mpf(0), -y3 / tc]
        return Table(dt, breaks, accels, jerks)


def polynomial_table(dt, dy, forward_fraction=0.8) -> Table:
    """The polynomial profile (docs/explanation/model.md): four constant-acceleration pieces."""
    with mp.workdps(DPS):
        dt, dy, f = _mpf(dt), _mpf(dy), _mpf(forward_fraction)
        fwd, back = 4 * dy / (f * dt) ** 2, 4 * dy / ((1 - f) * dt) ** 2
        breaks = [mp.mpf(0), f * dt / 2, f * dt, f * dt + (1 - f) * dt / 2, dt]
        return Table(dt, breaks, [fwd, -fwd, -back, back], [mp.mpf(0)] * 4)


class Arc:
    """x(s), v(s), A(s) of one arc from (xi0, v0) at s = 0 under y'' = a + j s, in region ``region``
    (0: mu = 1, 1: transition, 2: mu = c_mu; uniform surface: always 0) slipping in direction sigma."""

    def __init__(self, model, region, sigma, a, j, xi0, v0):
        self.sigma, self.region, self.a, self.j = sigma, region, a, j
        self.xi0, self.v0 = xi0, v0
        if region == 1:
            b1 = model.b1
            self.kind = "harmonic" if sigma > 0 else "hyperbolic"
            self.k = mp.sqrt(b1)
            # particular solution p(s) = p0 + p1 s of xi'' + sigma b1 xi = -(a + sigma) - j s
            self.p0, self.p1 = -(a + sigma) / (sigma * b1), -j / (sigma * b1)
            self.C = xi0 - self.p0
            self.D = (v0 - self.p1) / self.k
        else:
            m = model.c_mu if region == 2 else mp.mpf(1)
            self.kind = "poly"
            self.c0, self.c1 = -(a + sigma * m), -j

    def xi(self, s):
        if self.kind == "poly":
            return self.xi0 + s * (self.v0 + s * (self.c0 / 2 + s * self.c1 / 6))
        trig = (mp.cos, mp.sin) if self.kind == "harmonic" else (mp.cosh, mp.sinh)
        ks = self.k * s
        return self.p0 + self.p1 * s + self.C * trig[0](ks) + self.D * trig[1](ks)

    def v(self, s):
        if self.kind == "poly":
            return self.v0 + s * (self.c0 + s * self.c1 / 2)
        ks = self.k * s
        if self.kind == "harmonic":
            return self.p1 + self.k * (-self.C * mp.sin(ks) + self.D * mp.cos(ks))
        return self.p1 + self.k * (self.C * mp.sinh(ks) + self.D * mp.cosh(ks))

    def acc(self, s):
        if self.kind == "poly":
            return self.c0 + self.c1 * s
        ks = self.k * s
        if self.kind == "harmonic":
            return -self.k**2 * (self.C * mp.cos(ks) + self.D * mp.sin(ks))
        return self.k**2 * (self.C * mp.cosh(ks) + self.D * mp.sinh(ks))


def _root(f, lo, hi, flo, fhi, tol):
    """The root of f in [lo, hi] where f(lo), f(hi) differ in sign (Illinois, bisection when stalled)."""
    side = 0
    for _ in range(2000):
        if hi - lo <= tol:
            break
        width = hi - lo
        mid = (lo * fhi - hi * flo) / (fhi - flo)
        if not lo < mid < hi:
            mid = (lo + hi) / 2
        fm = f(mid)
        if fm == 0:
            return mid
        if (fm > 0) == (fhi > 0):
            hi, fhi = mid, fm
            if side == 1:
                flo /= 2
            side = 1
        else:
            lo, flo = mid, fm
            if side == -1:
                fhi /= 2
            side = -1
        if hi - lo > width / 2:                        # stalled: bisect once
            mid = (lo + hi) / 2
            fm = f(mid)
            if fm == 0:
                return mid
            if (fm > 0) == (fhi > 0):
                hi, fhi = mid, fm
            else:
                lo, flo = mid, fm
    return (lo + hi) / 2


class Model:
    """Surface and friction law: ``zone`` None (uniform) or (x_mu, w, c_mu); ``ratio`` r = mu_s/mu_k."""

    def __init__(self, zone=None, ratio=1.0):
        self.uniform = zone is None
        if not self.uniform:
            self.x_mu, self.w, self.c_mu = (_mpf(v) for v in zone)
            self.b1 = (self.c_mu - 1) / self.w
        self.ratio = _mpf(ratio)

    def region(self, xi, sigma):
        """Friction region of xi; on an edge, the one the motion sigma enters (stick: the edge's value
        is the same from both sides)."""
        if self.uniform:
            return 0
        if xi < 0 or (xi == 0 and sigma < 0):
            return 0
        if xi > self.w or (xi == self.w and sigma > 0):
            return 2
        return 1

    def mu(self, xi):
        if self.uniform or xi <= 0:
            return mp.mpf(1)
        if xi >= self.w:
            return self.c_mu
        return 1 + self.b1 * xi


def _sign(x):
    return 1 if x > 0 else -1 if x < 0 else 0


class Result:
    def __init__(self, xi, v, events, log):
        self.xi, self.v, self.events, self.log = xi, v, events, log


def simulate(table: Table, model: Model, x0, v0, phase, periods, max_events=100_000, keep_log=False):
    """End state after ``periods`` periods from (x0, v0) at time phase * dt: a :class:`Result` with the
    absolute end position ``xi``, the velocity ``v``, the number of arcs and, with ``keep_log``, the
    events (kind, period, time in the period, position relative to x_mu)."""
    with mp.workdps(DPS):
        dt = table.dt
        tol = ROOT_TOL * dt
        origin = mp.mpf(0) if model.uniform else model.x_mu
        xi, v = _mpf(x0) - origin, _mpf(v0)
        t = _mpf(float(phase) * float(dt))              # the time the start state holds, as given
        t_end = t + int(periods) * dt
        n_per = 0
        tau = t
        sigma = _sign(v)
        events = 0
        log = []
        k = max(i for i in range(len(table.breaks) - 1) if table.breaks[i] <= tau)
        while True:
            events += 1
            if events > max_events:
                raise RuntimeError(f"referee: more than {max_events} events")
            # the current piece, from tau to its end (or the horizon)
            piece_end = table.breaks[k + 1]
            stop_at = min(piece_end, t_end - n_per * dt)
            a = table.accels[k] + table.jerks[k] * (tau - table.breaks[k])
            j = table.jerks[k]
            S = stop_at - tau
            if sigma == 0:
                s_ev, slip = _stick(model, xi, a, j, S)
                if slip is None or s_ev >= S:
                    tau = stop_at
                else:
                    tau = tau + s_ev
                    # try the slip: does it develop within DELTA?
                    arc = Arc(model, model.region(xi, slip), slip, a + j * s_ev, j, xi, mp.mpf(0))
                    probe = min(DELTA, stop_at - tau)
                    if probe > 0 and slip * arc.v(probe) > 0:
                        sigma = slip
                        if keep_log:
                            log.append(("slip", n_per, tau, xi, slip))
                    else:                                    # no slip develops: stays stuck
                        tau = tau + probe if probe > 0 else stop_at
            else:
                region = model.region(xi, sigma)
                arc = Arc(model, region, sigma, a, j, xi, v)
                s_ev, what = _slip_event(model, arc, region, sigma, S, tol)
                xi_new, v_new = arc.xi(s_ev), arc.v(s_ev)
                tau = tau + s_ev
                if what == "stop":
                    xi, v = xi_new, mp.mpf(0)
                    ydd = table.accels[k] + j * (tau - table.breaks[k])
                    if abs(ydd) <= model.ratio * model.mu(xi):
                        sigma = 0
                        if keep_log:
                            log.append(("stick", n_per, tau, xi))
                    else:
                        sigma = -_sign(ydd)
                        if keep_log:
                            log.append(("reverse", n_per, tau, xi))
                elif what == "edge":
                    xi, v = (mp.mpf(0) if region == 0 or (region == 1 and sigma < 0) else model.w), v_new
                    if keep_log:
                        log.append(("edge", n_per, tau, xi))
                else:
                    xi, v, tau = xi_new, v_new, stop_at
            if tau >= t_end - n_per * dt:
                break
            if tau >= piece_end:
                k += 1
                if k == len(table.breaks) - 1:
                    k, n_per, tau = 0, n_per + 1, tau - dt
                    if tau < 0:
                        tau = mp.mpf(0)
        return Result(xi + origin, v, events, log)


def _stick(model, xi, a, j, S):
    """(s, sigma) of the first time in [0, S] where |a + j s| > r mu(xi) (the slip's direction), or (S, None)."""
    limit = model.ratio * model.mu(xi)
    if abs(a) > limit:
        return mp.mpf(0), -_sign(a)
    if j == 0:
        return S, None
    end = a + j * S
    if abs(end) <= limit:
        return S, None
    target = limit if j > 0 else -limit
    s = (target - a) / j
    return min(max(s, mp.mpf(0)), S), -_sign(target)


def _slip_event(model, arc, region, sigma, S, tol):
    """(s, what) of the first event of a slip arc in [0, S]: 'stop' (v = 0), 'edge' (a zone edge
    crossed) or 'end'.  Sub-intervals short enough that A has at most one zero (module docstring)."""
    if arc.kind == "harmonic":
        n = int(mp.ceil(S * arc.k / (mp.pi / 2))) + 1
    else:
        n = 1
    edge = None
    if not model.uniform:
        if sigma > 0 and region < 2:
            edge = mp.mpf(0) if region == 0 else model.w
        elif sigma < 0 and region > 0:
            edge = model.w if region == 2 else mp.mpf(0)
    start = min(DELTA, S) if arc.v0 == 0 else mp.mpf(0)
    grid = [start + (S - start) * i / n for i in range(n + 1)]
    for lo, hi in zip(grid[:-1], grid[1:]):
        a_lo, a_hi = arc.acc(lo), arc.acc(hi)
        parts = [lo, hi]
        if a_lo * a_hi < 0:
            parts = [lo, _root(arc.acc, lo, hi, a_lo, a_hi, tol), hi]
        for p0, p1 in zip(parts[:-1], parts[1:]):
            s_end, what = p1, None
            if sigma * arc.v(p1) <= 0:               # v is monotone on [p0, p1] and of sign sigma at p0
                v0 = arc.v(p0)
                s_end = p0 if sigma * v0 <= 0 else _root(arc.v, p0, p1, v0, arc.v(p1), tol)
                what = "stop"
            if edge is not None and sigma * (arc.xi(s_end) - edge) >= 0:
                g0 = arc.xi(p0) - edge
                if sigma * g0 >= 0:
                    return p0, "edge"
                return _root(lambda s: arc.xi(s) - edge, p0, s_end, g0, arc.xi(s_end) - edge, tol), "edge"
            if what:
                return s_end, what
    return S, "end"


class Fourier:
    """y(t) = sum_k a_k cos(w_k t) + b_k sin(w_k t), w_k = 2 pi k / dt (Sect. 4.4.2), and its derivatives."""

    def __init__(self, dt, cos_coeffs, sin_coeffs):
        with mp.workdps(DPS):
            self.dt = _mpf(dt)
            self.terms = [(_mpf(a), _mpf(b), 2 * mp.pi * (k + 1) / self.dt)
                          for k, (a, b) in enumerate(zip(cos_coeffs, sin_coeffs))]
            #: a bound of |y'''|, the Lipschitz constant of y'' and of the relative acceleration
            self.m3 = sum(mp.sqrt(a * a + b * b) * w**3 for a, b, w in self.terms)

    def d(self, t, n):
        """d^n y / dt^n at t."""
        total = mp.mpf(0)
        for a, b, w in self.terms:
            c, s = mp.cos(w * t), mp.sin(w * t)
            even, odd = a * c + b * s, b * c - a * s
            total += w**n * (even, odd, -even, -odd)[n % 4]
        return total


def _first(lo, hi, test, tol):
    """Left-first search of [lo, hi] in halves: ``test(lo, hi)`` returns a time (found), None (nothing in
    this interval) or "split"; intervals shorter than ``tol`` are tested with split treated as nothing."""
    stack = [(lo, hi)]
    while stack:
        a, b = stack.pop()
        verdict = test(a, b)
        if verdict == "split":
            if b - a < tol:
                continue
            mid = (a + b) / 2
            stack.append((mid, b))
            stack.append((a, mid))
        elif verdict is not None:
            return verdict
    return None


def simulate_fourier(profile: Fourier, x0, v0, phase, periods, ratio=1.0, max_events=100_000, keep_log=False):
    """End state after ``periods`` periods on a uniform surface (mu = 1) under a Fourier profile.

    Slip sigma from (t0, x0, v0): v = v0 - (y'(t) - y'(t0)) - sigma (t - t0) and x in closed form.  Events
    without sampling: the relative acceleration A = -y'' - sigma has |A'| <= m3 (:attr:`Fourier.m3`), so
    an interval whose midpoint value exceeds m3 times its half-length has no zero of A and v is monotone
    on it; such intervals, taken left to right (others halved), bracket the first stop exactly.  A stick
    ends where |y''| first exceeds r, found the same way (|y''| at the midpoint plus m3 times the
    half-length bounds it on the interval).  Tangencies within 1e-45 of the period count as ties.
    """
    with mp.workdps(DPS):
        dt, r, m3 = profile.dt, _mpf(ratio), profile.m3
        tol = ROOT_TOL * dt
        t = _mpf(float(phase) * float(dt))
        t_end = t + int(periods) * dt
        x, v = _mpf(x0), _mpf(v0)
        sigma = _sign(v)
        log, events = [], 0
        while t < t_end:
            events += 1
            if events > max_events:
                raise RuntimeError(f"referee: more than {max_events} events")
            if sigma == 0:
                def test(a, b):
                    if abs(profile.d(a, 2)) > r:
                        return a
                    if abs(profile.d((a + b) / 2, 2)) + m3 * (b - a) / 2 <= r:
                        return None
                    return "split"
                ts = _first(t, t_end, test, tol)
                if ts is None:
                    t = t_end
                    break
                slip = -_sign(profile.d(ts, 2))
                probe = min(DELTA, t_end - ts)
                yd0 = profile.d(ts, 1)
                vp = -(profile.d(ts + probe, 1) - yd0) - slip * probe
                t = ts + probe
                if slip * vp > 0:                   # the slip develops (else: stays stuck, time moves on)
                    x += -(profile.d(t, 0) - profile.d(ts, 0) - yd0 * probe) - slip * probe**2 / 2
                    v, sigma = vp, slip
                    if keep_log:
                        log.append(("slip", 0, ts, x, slip))
                continue
            t0, x_0, v_0, y0, yd0 = t, x, v, profile.d(t, 0), profile.d(t, 1)

            def vel(s):
                return v_0 - (profile.d(s, 1) - yd0) - sigma * (s - t0)

            def test(a, b, sigma=sigma):
                if abs(-profile.d((a + b) / 2, 2) - sigma) <= m3 * (b - a) / 2:
                    return "split"
                vb = vel(b)
                if sigma * vb > 0:
                    return None
                va = vel(a)
                return a if sigma * va <= 0 else _root(vel, a, b, va, vb, tol)

            ts = _first(t0, t_end, test, tol)
            t = t_end if ts is None else ts
            s = t - t0
            x = x_0 + v_0 * s - (profile.d(t, 0) - y0 - yd0 * s) - sigma * s * s / 2
            v = vel(t)
            if ts is None:
                break
            v = mp.mpf(0)
            ydd = profile.d(t, 2)
            if abs(ydd) <= r:
                sigma = 0
                if keep_log:
                    log.append(("stick", 0, t, x))
            else:
                sigma = -_sign(ydd)
                if keep_log:
                    log.append(("reverse", 0, t, x))
                # the reversed slip starts from rest: let it develop for DELTA before searching its stop
                yd0 = profile.d(t, 1)
                x += -(profile.d(t + DELTA, 0) - profile.d(t, 0) - yd0 * DELTA) - sigma * DELTA**2 / 2
                v = -(profile.d(t + DELTA, 1) - yd0) - sigma * DELTA
                t = t + DELTA
        return Result(x, v, events, log)
