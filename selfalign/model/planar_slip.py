"""The closed-form slip of a point part on a table with a constant acceleration A and friction mu (planar motion).

In slip the relative velocity v of the part obeys v' = -A - mu v / |v| (the planar model of Sect. 3.2 with
the paper's recommendation (4), Sect. 8: general planar motion).  With G = |A| > 0 and the driving direction
g = -A / G this is the classical block sliding on an incline with friction.  In the frame (g, n), n the
unit normal to g on the side of v, the velocity is v = p g + q n with q > 0.  Its state is carried by

    a = (|v| + p) / 2,   b = (|v| - p) / 2,   h = q / 2        (a b = h^2),

and one parameter y >= 0 (y = -ln(u / u0), u = tan(theta / 2), theta the angle from g to v), which
grows from 0 as the slip goes on.  With the exponents E_c(y) = (1 - exp(-c y)) / c:

    speed   s = a e^{-(k-1) y} + b e^{-(k+1) y},      k = mu / G,
    p       = a e^{-(k-1) y} - b e^{-(k+1) y},        q = 2 h e^{-k y},
    time    t = (a E_{k-1}(y) + b E_{k+1}(y)) / G,
    along g P = (a^2 E_{2k-2}(y) - b^2 E_{2k+2}(y)) / G,
    along n Q = 2 h (a E_{2k-1}(y) + b E_{2k+1}(y)) / G.

For k > 1 (mu > G) the part stops at y = inf, at the time T = a / (mu - G) + b / (mu + G).  The
derivation is docs/explanation/planar-model.md, "Closed-form slip".  Exponents near zero (k near 1 or
1/2) are no special case: E_c(y) = y phi1(-c y) with phi1(z) = expm1(z) / z, so no term cancels.  The
exponents c are formed from mu and G directly ((mu - G) / G, not k - 1), so that k near 1 keeps its
accuracy.

The collinear slips (v parallel to A, or A = 0: the direction of v never turns) are the one-dimensional
quadratic arcs of :mod:`selfalign.model.arcs` along the line of v; :func:`slip_shape` says which closed form
a slip takes.

Every function here is a scalar function of floats written with :mod:`math` only, so that the compiled
stepper (:mod:`selfalign.solvers.engine.planar`) runs these very functions compiled.
"""

from __future__ import annotations

import math

from . import arcs as A
from .registry import formula

_PAGE = "planar motion, beyond the paper (its recommendation (4), Sect. 8); derived in docs/explanation/planar-model.md"

#: Slip shapes (:func:`slip_shape`): along a line (a quadratic arc of :mod:`selfalign.model.arcs`) or curved.
COLLINEAR, CURVED = 0, 1
#: A curved slip needs k = mu / G below this (beyond it A turns v by less than 2^-1000 of a radian before it
#: stops, far below rounding, and the exponents of the closed form would overflow): otherwise it is collinear.
MAX_K = 2.0 ** 1000
#: A velocity within this many ulp of the line of A (transverse speed |q| <= 2 COLLINEAR_ULPS eps |v|) slips on
#: that line (:func:`slip_shape`): the rounding of a velocity along a turned line is a few ulp.
COLLINEAR_ULPS = 16.0
#: Safeguarded Newton iterations of :func:`slip_parameter` at most (it converges in fewer than 10 in practice).
NEWTON_STEPS = 200
#: A parameter y beyond which every exponential of a stopping slip underflows (e^{-745} = 0 in doubles), over
#: the smallest exponent: there its state is the stop state to rounding.
UNDERFLOW = 800.0

_EPS = 2.0 ** -52
_LOG_LARGEST = 709.78                    # expm1 overflows beyond (the log of the largest double, 709.7827...)


@formula(unnumbered="numerics of the closed-form slip: expm1(z) / z without cancellation (" + _PAGE + ")")
def phi1(z: float) -> float:
    """expm1(z) / z, continued by its limit 1 at z = 0 (accurate for every z: expm1 keeps the relative
    accuracy that exp(z) - 1 loses for small z)."""
    if z == 0.0:
        return 1.0
    if z > _LOG_LARGEST:
        return math.inf
    return math.expm1(z) / z


@formula(unnumbered="the integral of the powers of u in the closed-form slip (" + _PAGE + ")")
def exponent_integral(c: float, y: float) -> float:
    """E_c(y) = (1 - e^{-c y}) / c = y phi1(-c y): the integral of e^{-c x} over x in [0, y].

    y at c = 0 (the logarithms of the derivation), 1 / c at y = inf for c > 0."""
    if y == math.inf:
        return 1.0 / c if c > 0.0 else math.inf
    return y * phi1(-c * y)


@formula(unnumbered="the state of a curved slip in the frame of the driving direction (" + _PAGE + ")")
def slip_invariants(p: float, q: float):
    """(a, b, h) of a velocity with components p along g and q > 0 across it: a = (|v| + p) / 2,
    b = (|v| - p) / 2, h = q / 2.

    The smaller of a and b is taken as h^2 over the larger one (a b = h^2), not as a difference that
    cancels when v lies close to the line of g."""
    s = math.hypot(p, q)
    h = 0.5 * q
    if p >= 0.0:
        a = 0.5 * (s + p)
        return a, (h / a) * h, h
    b = 0.5 * (s - p)
    return (h / b) * h, b, h


@formula(unnumbered="which closed form a slip takes: a case distinction (" + _PAGE + ")")
def slip_shape(vx: float, vy: float, ax: float, ay: float, mu: float) -> int:
    """:data:`CURVED` where the table acceleration (ax, ay) turns the velocity (vx, vy), else :data:`COLLINEAR`:
    the slip then stays on the line of v, a quadratic arc.

    Collinear are: v x A = 0 in floating point, A = 0, mu / G >= :data:`MAX_K`, an invariant a or b that
    underflows, and a velocity within :data:`COLLINEAR_ULPS` ulp of the line of A (|q| / |v| below
    2 COLLINEAR_ULPS eps): the transverse velocity left out is the rounding of v, so that a table motion along
    a line at any angle is the 1-D model on that line (its stops, sticks and reversals included)."""
    if vx * ay - vy * ax == 0.0 or not mu < MAX_K * math.hypot(ax, ay):
        return COLLINEAR
    _, _, _, _, _, a, b, h = slip_frame(vx, vy, ax, ay)
    if a > 0.0 and b > 0.0 and math.isfinite(a) and h > COLLINEAR_ULPS * _EPS * (a + b):
        return CURVED
    return COLLINEAR


@formula(unnumbered="a power of u in the closed-form slip, scaled without overflow (" + _PAGE + ")")
def decayed(w: float, c: float, y: float) -> float:
    """w e^{-c y} for w > 0 (0 at y = inf for c > 0); where the product under- or overflows although the result
    does not (a tiny w and a large growth), it is taken as exp(ln w - c y)."""
    if y == math.inf:
        return 0.0 if c > 0.0 else math.inf
    out = w * math.exp(-c * y)
    if (out == 0.0 or not out < math.inf) and w > 0.0:
        return math.exp(math.log(w) - c * y)
    return out


@formula(unnumbered="the integrals of the closed-form slip, from the weights at both ends (" + _PAGE + ")")
def weighted_integral(w0: float, w1: float, c: float, y: float) -> float:
    """w0 E_c(y), the integral of w0 e^{-c x} over [0, y], given w1 = w0 e^{-c y}: (w0 - w1) / c once
    |c y| > 1 (e^{-c y} is then far from 1, nothing cancels, and no factor overflows before the result does),
    else w0 y phi1(-c y) (:func:`exponent_integral`)."""
    if abs(c * y) > 1.0:
        return (w0 - w1) / c
    return w0 * exponent_integral(c, y)


@formula(unnumbered="the time, speed and velocity of a curved slip at its parameter y (" + _PAGE + ")")
def slip_time(g: float, mu: float, a: float, b: float, y: float) -> float:
    """Time t(y) = (a E_{k-1}(y) + b E_{k+1}(y)) / G a curved slip takes to reach the parameter y."""
    em, ep = (mu - g) / g, (mu + g) / g
    return (weighted_integral(a, decayed(a, em, y), em, y) + weighted_integral(b, decayed(b, ep, y), ep, y)) / g


@formula(unnumbered="the speed of a curved slip at its parameter y, dt / dy times G (" + _PAGE + ")")
def slip_speed(g: float, mu: float, a: float, b: float, y: float) -> float:
    """Speed s(y) = a e^{-(k-1) y} + b e^{-(k+1) y} of a curved slip (and G dt / dy)."""
    return decayed(a, (mu - g) / g, y) + decayed(b, (mu + g) / g, y)


@formula(unnumbered="the closed-form curved slip (" + _PAGE + ")")
def slip_state(g: float, mu: float, a: float, b: float, h: float, y: float):
    """(P, Q, p, q): displacement along g and n and velocity along g and n of a curved slip at the
    parameter y (module docstring); at y = inf (mu > G only) the stop: P, Q of the whole slip, p = q = 0.

    Every term is an integral of a product of the decaying weights a e^{-(k-1) x}, b e^{-(k+1) x} and
    h e^{-k x} (:func:`weighted_integral` from its values at both ends), so that a tiny start speed followed
    by a long acceleration neither under- nor overflows on the way."""
    em, ep, kk = (mu - g) / g, (mu + g) / g, mu / g
    fall_a, fall_b, fall_h = decayed(a, em, y), decayed(b, ep, y), decayed(h, kk, y)
    disp_g = (weighted_integral(a * a, fall_a * fall_a, 2.0 * em, y)
              - weighted_integral(b * b, fall_b * fall_b, 2.0 * ep, y)) / g
    disp_n = 2.0 * (weighted_integral(h * a, fall_h * fall_a, (2.0 * mu - g) / g, y)
                    + weighted_integral(h * b, fall_h * fall_b, (2.0 * mu + g) / g, y)) / g
    return disp_g, disp_n, fall_a - fall_b, 2.0 * fall_h


@formula(unnumbered="the stop time of a curved slip, its time at y = inf (" + _PAGE + ")")
def stop_time(g: float, mu: float, a: float, b: float) -> float:
    """T = a / (mu - G) + b / (mu + G): when a curved slip stops (the speed reaches 0 as y -> inf);
    inf unless mu > G (then the speed tends to a (mu = G) or grows without bound)."""
    if mu > g:
        return a / (mu - g) + b / (mu + g)
    return math.inf


@formula(unnumbered="numerics: the inverse of the monotone time t(y) of a curved slip (" + _PAGE + ")")
def slip_parameter(g: float, mu: float, a: float, b: float, duration: float) -> float:
    """The parameter y >= 0 at which a curved slip has lasted ``duration`` (< :func:`stop_time`).

    t(y) increases with y and dt / dy = s(y) / G > 0, so a safeguarded Newton iteration on
    [0, y_hi] converges; y_hi is explicit: for mu > G, 1 - e^{-(k-1) y} >= t / T bounds it
    (y_hi = -log1p(-duration / T) / (k - 1)); for mu <= G the term a E_{k-1} alone reaches the duration
    by y_hi = log1p(z) / (1 - k) with z = (G - mu) duration / a.  Newton starts at min(G duration / |v|,
    y_hi) and steps that leave the bracket are bisections; it ends when a step is below 4 ulp of y."""
    if duration <= 0.0:
        return 0.0
    em = (mu - g) / g
    if mu > g:
        hi = min(-math.log1p(-duration / stop_time(g, mu, a, b)) / em, UNDERFLOW / em)
    else:
        z = (g - mu) * duration / a
        hi = (g * duration / a) * (math.log1p(z) / z if z > 0.0 else 1.0)
    if not hi < 1e300:
        hi = 1e300
    lo = 0.0
    y = min(g * duration / (a + b), hi)
    for _ in range(NEWTON_STEPS):
        f = slip_time(g, mu, a, b, y) - duration
        if f == 0.0:
            return y
        if f < 0.0:
            lo = y
        else:
            hi = y
        new = y - f * g / slip_speed(g, mu, a, b, y)
        if not (lo < new < hi):
            new = lo + 0.5 * (hi - lo)
        if abs(new - y) <= 4.0 * _EPS * y or hi - lo <= 4.0 * _EPS * hi:
            return new
        y = new
    return y


@formula(unnumbered="the constant relative acceleration of a collinear slip, -A - mu v / |v| (" + _PAGE + ")")
def collinear_acceleration(ex: float, ey: float, ax: float, ay: float, mu: float):
    """Relative acceleration -A - mu e of a slip along the unit vector e = (ex, ey) (the direction of v,
    or of -A for a slip from rest): constant while the slip stays on the line of e."""
    return -ax - mu * ex, -ay - mu * ey


@formula(unnumbered="the stop time of a collinear slip: eq. (21) along the line of the slip (" + _PAGE + ")")
def collinear_stop_time(vx: float, vy: float, cx: float, cy: float, ex: float, ey: float) -> float:
    """When a collinear slip with velocity v and acceleration c along e reaches v = 0, or inf: s = -(v.e) / (c.e)
    if it decelerates (c.e < 0), eq. (21) on the line of e."""
    ce = cx * ex + cy * ey
    if ce < 0.0:
        return -(vx * ex + vy * ey) / ce
    return math.inf


@formula(unnumbered="the collinear slip: eqs. (15)-(20) per component (" + _PAGE + ")")
def collinear_step(vx: float, vy: float, cx: float, cy: float, s: float):
    """(dx, dy, vx, vy) of a collinear slip (constant acceleration (cx, cy)) after time s: the quadratic arc
    of :func:`selfalign.model.arcs.step` per component."""
    dx, wx = A.step(A.QUADRATIC, 0.0, vx, cx, s)
    dy, wy = A.step(A.QUADRATIC, 0.0, vy, cy, s)
    return dx, dy, wx, wy


@formula(unnumbered="the frame (g, n) of a curved slip and its invariants (" + _PAGE + ")")
def slip_frame(vx: float, vy: float, ax: float, ay: float):
    """(G, gx, gy, nx, ny, a, b, h) of a curved slip: G = |A|, the driving direction g = -A / G, the
    unit normal n on the side of v and the invariants of :func:`slip_invariants`."""
    g = math.hypot(ax, ay)
    gx, gy = -ax / g, -ay / g
    cross = gx * vy - gy * vx
    nx, ny = (-gy, gx) if cross >= 0.0 else (gy, -gx)
    p = vx * gx + vy * gy
    q = abs(cross)
    a, b, h = slip_invariants(p, q)
    return g, gx, gy, nx, ny, a, b, h


@formula(unnumbered="a slip under constant A and mu in closed form, up to its stop (" + _PAGE + ")")
def slip_step(vx: float, vy: float, ax: float, ay: float, mu: float, s: float):
    """(dx, dy, vx, vy) of a slip from velocity (vx, vy) != 0 under the table acceleration (ax, ay) and
    friction mu after time s, or at its stop if it stops earlier (then v = (0, 0)).

    Curved (:func:`slip_shape`): the closed form of :func:`slip_state` at :func:`slip_parameter`; collinear:
    the quadratic arc along the line of v, :func:`collinear_step`, up to :func:`collinear_stop_time`."""
    if slip_shape(vx, vy, ax, ay, mu) == COLLINEAR:
        speed = math.hypot(vx, vy)
        ex, ey = vx / speed, vy / speed
        cx, cy = collinear_acceleration(ex, ey, ax, ay, mu)
        stop = collinear_stop_time(vx, vy, cx, cy, ex, ey)
        if stop <= s:
            dx, dy, _, _ = collinear_step(vx, vy, cx, cy, stop)
            return dx, dy, 0.0, 0.0
        return collinear_step(vx, vy, cx, cy, s)
    g, gx, gy, nx, ny, a, b, h = slip_frame(vx, vy, ax, ay)
    y = math.inf if s >= stop_time(g, mu, a, b) else slip_parameter(g, mu, a, b, s)
    disp_g, disp_n, p, q = slip_state(g, mu, a, b, h, y)
    return (disp_g * gx + disp_n * nx, disp_g * gy + disp_n * ny, p * gx + q * nx, p * gy + q * ny)
