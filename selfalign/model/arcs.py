"""Closed-form arcs of the inclusion x'' + y'' in -mu_bar(x) Sign(x') (eqs. 6, 38).

Between two events the table acceleration a = y'' is constant (piecewise-constant
profiles), the mode is fixed and mu_bar(x) is constant (uniform friction, and the
regions x <= x_mu, x >= x_mu + w of a stop zone) or affine, mu_bar = 1 + b1 (x - x_mu)
(the transition zone, eq. 9).  Every slip arc then solves a linear equation

    x'' = acc0 + kappa (x - x0),      acc0 = -a - sigma mu_bar(x0),

with sigma = +1 (forward slip) or -1 (backward slip) and kappa = 0 (uniform friction),
-b1 (forward slip in the zone: the harmonic oscillator of eq. 42) or +b1 (backward slip
in the zone: its hyperbolic counterpart).  With omega = sqrt(|kappa|) every arc is

    x(s) = x0 + v0 S1(s) + acc0 S2(s),      v(s) = v0 C(s) + acc0 S1(s),

    QUADRATIC:  C = 1,           S1 = s,                S2 = s^2 / 2                 (eqs. 15-20)
    HARMONIC:   C = cos(w s),    S1 = sin(w s) / w,     S2 = 2 sin^2(w s / 2) / w^2  (eqs. 43-44)
    HYPERBOLIC: C = cosh(w s),   S1 = sinh(w s) / w,    S2 = 2 sinh^2(w s / 2) / w^2

where s is the time since the arc start.  This is eq. (43) rewritten about the start
state (x_eq = x0 + acc0 / b1 = b3 / b1, d1 = -acc0 / b1, d2 = v0 / omega); written this
way no term is the difference of two large ones, so positions keep full relative
accuracy even for a tiny b1 or a short arc.  A STICK arc has v = 0 and x constant
(eqs. 22-24).  SMOOTH arcs (a Fourier profile on a uniform surface) are closed form
too, but in the profile (:func:`smooth_step`): x'' = -y''(t) - sigma does not depend on the
state, so x' and x are the profile's y', y integrated once and twice.

Every function here is a scalar function of floats written with :mod:`math` only, so
that the compiled event kernel (:mod:`selfalign.solvers.engine`) runs these very
functions compiled, and Python code (tests, analyses) can call them as they are.
"""

from __future__ import annotations

import math

from .registry import formula

#: Arc kinds (the ``kind`` field of an arc record).
STICK, QUADRATIC, HARMONIC, HYPERBOLIC, SMOOTH = 0, 1, 2, 3, 4
#: Printable names of the arc kinds.
ARC_NAMES = {STICK: "stick", QUADRATIC: "quadratic", HARMONIC: "harmonic",
             HYPERBOLIC: "hyperbolic", SMOOTH: "smooth"}


@formula(unnumbered="which closed form a slip arc takes: a case distinction, no equation")
def slip_kind(in_zone: bool, sigma: int) -> int:
    """Arc kind of a slip in direction ``sigma`` inside (``in_zone``) or outside the zone."""
    if not in_zone:
        return QUADRATIC
    return HARMONIC if sigma > 0 else HYPERBOLIC


@formula(unnumbered="kappa = -b1, +b1 or 0: the coefficient b1 of eq. (42) (forward slip), its sign flipped for "
                    "backward slip")
def stiffness(kind: int, b1: float) -> float:
    """kappa of x'' = acc0 + kappa (x - x0) for an arc of ``kind`` (0 for stick/quadratic)."""
    if kind == HARMONIC:
        return -b1
    if kind == HYPERBOLIC:
        return b1
    return 0.0


@formula(unnumbered="the basis functions from which step builds eqs. (13)-(20) and (43)-(44)")
def basis(kind: int, omega: float, s: float):
    """(C, S1, S2) of the arc (module docstring) after time ``s``.

    The harmonic and hyperbolic functions are built from the half angle, h = sin(w s / 2)
    (sinh), c = cos(w s / 2) (cosh): C = 1 -+ 2 h^2, S1 = 2 h c / w, S2 = 2 h^2 / w^2, so
    that C - 1 and S2 keep full relative accuracy for short arcs.  For STICK all three
    are 0, so that :func:`step` gives no displacement and v = 0.
    """
    if kind == QUADRATIC:
        return 1.0, s, 0.5 * s * s
    if kind == HARMONIC:
        half = 0.5 * omega * s
        h, c = math.sin(half), math.cos(half)
        return 1.0 - 2.0 * h * h, 2.0 * h * c / omega, 2.0 * (h / omega) * (h / omega)
    if kind == HYPERBOLIC:
        half = 0.5 * omega * s
        h, c = math.sinh(half), math.cosh(half)
        return 1.0 + 2.0 * h * h, 2.0 * h * c / omega, 2.0 * (h / omega) * (h / omega)
    return 0.0, 0.0, 0.0


@formula(eqs=("13", "14", "16", "17", "19", "20", "23", "24", "43", "44"))
def step(kind: int, omega: float, v0: float, acc0: float, s: float):
    """Displacement x(s) - x0 and velocity v(s) of an arc started with (v0, acc0).

    The displacement does not depend on x0, so a uniform-friction period advanced
    from the same velocity gives bit-identical displacements wherever it starts
    (used by the steady-state fast-forward).
    """
    c, s1, s2 = basis(kind, omega, s)
    return v0 * s1 + acc0 * s2, v0 * c + acc0 * s1


#: Terms of the series of S3 (below) for |w s| <= 1: the first one left out is < 1e-19 S3.
_S3_TERMS = 10


@formula(unnumbered="finite jerk is beyond the paper (its recommendation (2), Sect. 8)")
def jerk_basis(kind: int, omega: float, s: float) -> float:
    """S3(s), the integral of S2 from 0 to s: the response of an arc to a forcing ``jerk s``.

    QUADRATIC s^3 / 6; HARMONIC (w s - sin w s) / w^3; HYPERBOLIC (sinh w s - w s) / w^3.
    For |w s| <= 1 the difference would cancel, so it is summed as its Taylor series
    s^3 sum_n (-+ (w s)^2)^n / (2n + 3)! instead.
    """
    if kind == QUADRATIC or omega * s == 0.0:
        return s * s * s / 6.0
    x = omega * s
    if abs(x) <= 1.0:
        sign = -1.0 if kind == HARMONIC else 1.0
        term = 1.0 / 6.0
        total = term
        for n in range(1, _S3_TERMS):
            term *= sign * x * x / ((2 * n + 2) * (2 * n + 3))
            total += term
        return s * s * s * total
    if kind == HARMONIC:
        return (x - math.sin(x)) / (omega * omega * omega)
    return (math.sinh(x) - x) / (omega * omega * omega)


@formula(unnumbered="finite jerk is beyond the paper (its recommendation (2), Sect. 8)")
def jerk_step(kind: int, omega: float, v0: float, acc0: float, jerk: float, s: float):
    """Displacement, velocity and acceleration after time ``s`` of an arc of
    x'' = acc0 + kappa (x - x0) + jerk s (a table acceleration linear in time, y'' = a - jerk s):
    x - x0 = v0 S1 + acc0 S2 + jerk S3, v = v0 C + acc0 S1 + jerk S2 (the forcing enters the
    same linear equation, so its response adds to :func:`step`'s).

    The event solver relies on one property of these arcs: x''' = kappa x' + jerk, so the
    acceleration A = x'' solves A'' = kappa A.  A is linear (QUADRATIC), c cos(w s + phi)
    (HARMONIC: zeros pi / w apart) or c1 e^{ws} + c2 e^{-ws} (HYPERBOLIC: at most one zero), so
    in a time shorter than pi / w the velocity has at most one extremum and x' = 0 at most twice
    (see kernel._jerk_arc_end)."""
    c, s1, s2 = basis(kind, omega, s)
    dx = v0 * s1 + acc0 * s2 + jerk * jerk_basis(kind, omega, s)
    return dx, v0 * c + acc0 * s1 + jerk * s2, acc0 + stiffness(kind, omega * omega) * dx + jerk * s


@formula(eqs=("12", "15", "18", "22", "42"))
def acceleration(kind: int, b1: float, acc0: float, dx: float) -> float:
    """Relative acceleration x'' after a displacement ``dx`` from the arc start."""
    if kind == STICK:
        return 0.0
    return acc0 + stiffness(kind, b1) * dx


@formula(unnumbered="the fundamental solution matrix of an arc, the smooth part of the monodromy matrix of "
                    "Sect. 6.1 (method 2)")
def fundamental_matrix(kind: int, omega: float, s: float):
    """d(x(s), v(s)) / d(x0, v0) of an arc of duration ``s``, as (m11, m12, m21, m22).

    Slip arcs: ((C, S1), (kappa S1, C)), with kappa = -omega^2 (harmonic), +omega^2
    (hyperbolic), 0 (quadratic), because acc0 depends on x0 through mu_bar (eq. 38).
    SMOOTH arcs (x'' = -y''(t) - sigma does not depend on the state) are quadratic here.
    STICK: ((1, 0), (0, 0)): while |y''| < mu_bar a velocity perturbation is absorbed
    by the stick at once, a position perturbation is kept.  Event saltation matrices
    (built from the pre/post-event accelerations of the event log) are separate.
    """
    if kind == STICK:
        return 1.0, 0.0, 0.0, 0.0
    if kind == SMOOTH:
        kind = QUADRATIC
    c, s1, _ = basis(kind, omega, s)
    return c, s1, stiffness(kind, omega * omega) * s1, c


@formula(unnumbered="numerics: the smallest positive root of a quadratic, for the event times")
def first_positive_root(a: float, b: float, c: float) -> float:
    """Smallest root t > 0 of a t^2 + b t + c = 0, or inf.

    Uses q = -(b + sign(b) sqrt(b^2 - 4ac)) / 2 and the roots q / a, c / q
    ("citardauq"), so both roots keep full relative accuracy: a small root
    (an event just after the arc start) does not come from cancellation.
    """
    if a == 0.0:
        if b == 0.0:
            return math.inf
        t = -c / b
        return t if t > 0.0 else math.inf
    disc = b * b - 4.0 * a * c
    if disc < 0.0:
        return math.inf
    q = -0.5 * (b + math.copysign(math.sqrt(disc), b))
    if q == 0.0:  # b = 0 and c = 0: the only root is t = 0
        return math.inf
    r1, r2 = q / a, c / q
    if r1 > r2:
        r1, r2 = r2, r1
    if r1 > 0.0:
        return r1
    return r2 if r2 > 0.0 else math.inf


@formula(eqs=("21", "47"))
def zero_velocity_time(kind: int, omega: float, sigma: int, v0: float, acc0: float) -> float:
    """First s >= 0 at which a slip arc in direction ``sigma`` reaches v = 0, or inf.

    ``v0`` must be zero or have the sign of ``sigma``.

    QUADRATIC: s = -v0 / acc0 if the arc decelerates (acc0 sigma < 0), eq. (21).
    HARMONIC (forward): v(s) = v0 cos(w s) + (acc0 / w) sin(w s) = 0 first at
        s = atan2(v0 w, -acc0) / w, in [0, pi / w]: eq. (47) generalised to every sign
        of d1 = -acc0 / b1 (eq. 47's arcsin is the case d1 >= 0).
    HYPERBOLIC (backward): tanh(w s) = -v0 w / acc0 needs acc0 > 0 and
        acc0 + v0 w > 0 (else the mass runs away backwards); then
        s = log1p(-2 v0 w / (acc0 + v0 w)) / (2 w) (the exponential form of atanh,
        accurate for small and for large s).
    """
    if kind == QUADRATIC:
        return -v0 / acc0 if acc0 * sigma < 0.0 else math.inf
    if kind == HARMONIC:
        # + 0.0 turns v0 = -0.0 into +0.0, so that atan2 does not return -pi.
        return math.atan2(v0 * omega + 0.0, -acc0) / omega
    if acc0 > 0.0:   # HYPERBOLIC
        den = acc0 + v0 * omega
        if den > 0.0:
            return math.log1p(-2.0 * v0 * omega / den) / (2.0 * omega)
    return math.inf


@formula(unnumbered="the time t* an arc reaches a zone boundary (where eqs. 45-46 start), from eqs. (20) and (43)")
def crossing_time(kind: int, omega: float, v0: float, acc0: float, delta: float) -> float:
    """First s > 0 at which the arc reaches x = x_b, with ``delta = x0 - x_b``, or inf.

    The position equation is reduced to a quadratic solved by
    :func:`first_positive_root` (its constant term is delta itself, computed
    directly, so crossings just after the start are accurate):

    QUADRATIC:  (acc0 / 2) s^2 + v0 s + delta = 0;
    HARMONIC:   with t = tan(w s / 2):  (delta + 2 acc0 / w^2) t^2 + 2 (v0 / w) t + delta = 0,
                s = 2 atan(t) / w  (a forward-slip arc lasts at most pi / w);
    HYPERBOLIC: with t = tanh(w s / 2): (2 acc0 / w^2 - delta) t^2 + 2 (v0 / w) t + delta = 0,
                t in (0, 1), s = log1p(2 t / (1 - t)) / w.
    """
    if kind == QUADRATIC:
        return first_positive_root(0.5 * acc0, v0, delta)
    if kind == HARMONIC:
        t = first_positive_root(delta + 2.0 * acc0 / (omega * omega), 2.0 * v0 / omega, delta)
        return 2.0 * math.atan(t) / omega if t < math.inf else math.inf
    t = first_positive_root(2.0 * acc0 / (omega * omega) - delta, 2.0 * v0 / omega, delta)
    return math.log1p(2.0 * t / (1.0 - t)) / omega if t < 1.0 else math.inf


@formula(unnumbered="eq. (6) in slip integrated for any table motion y(t) on a uniform surface (mu_bar = 1): "
                    "the paper integrates it only for piecewise-constant y''")
def smooth_velocity(sigma: float, v0: float, s: float, yd0: float, yd1: float) -> float:
    """Relative velocity x'(s) = v0 - sigma s - (y'1 - y'0) of a slip in direction ``sigma`` on a
    uniform surface, a time ``s`` after its start, for any table motion (a SMOOTH arc).

    The arc solves x'' = -y''(t) - sigma, so x' is v0 minus sigma s minus the change of the table
    velocity, y'0 = y'(t0) and y'1 = y'(t0 + s).  The change y'1 - y'0 is taken first, so that a
    short arc keeps the relative accuracy of the profile's velocities."""
    return v0 - sigma * s - (yd1 - yd0)


@formula(unnumbered="eq. (6) in slip integrated for any table motion y(t) on a uniform surface (mu_bar = 1): "
                    "the paper integrates it only for piecewise-constant y''")
def smooth_step(sigma: float, v0: float, s: float, y0: float, yd0: float, y1: float, yd1: float):
    """Displacement x(s) - x0 and velocity x'(s) of a SMOOTH arc (:func:`smooth_velocity`): with the
    table's y0, y'0 at the arc start and y1, y'1 a time ``s`` later,

        x(s) - x0 = v0 s - sigma s^2 / 2 - (y1 - y0 - y'0 s),

    the table's displacement relative to its tangent at the start taken as one term."""
    return v0 * s - 0.5 * sigma * s * s - (y1 - y0 - yd0 * s), smooth_velocity(sigma, v0, s, yd0, yd1)
