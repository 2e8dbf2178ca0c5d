"""The exact stepper of several parts on one table: the event loop of :mod:`selfalign.solvers.parts_exact`
(its module docstring gives the state, the events and the tie rules; docs/explanation/several-parts.md the
derivation).

The state is three arrays the caller allocates, one column per part (the rows are named in :mod:`.codes`):
``f`` (floats: positions, velocities, widths, masses, friction factors, transition slopes, accelerations,
arcs, and the scratch of :func:`~selfalign.model.parts.chain_minimiser`), ``g`` (ints: directions, arc
kinds, contact flags, the lists of the next event's parts and contacts, and the events per part), and
``q``, ``c`` (the run's scalars and counters).  A contact i (between parts i and i + 1) sits in column i of
its row; the last column of a contact row is unused.  Clusters are the maximal runs of parts joined by
``g[PJOINED]``; every part of a cluster holds the cluster's velocity, acceleration, direction and arc.
Loops only, nothing allocated: the event loop runs in the arrays it was given.
"""

from __future__ import annotations

import math

from ...model import arcs as A
from ...model.friction import coefficient
from ...model.parts import (
    CHAIN_WORK_ROWS,
    IMPACT_WORK_ROWS,
    STATIC_WORK_ROWS,
    chain_minimiser,
    impact_velocities,
    static_kinetic_minimiser,
)
from .. import records as R
from ..outcomes import HIGH, LOW, STALL_EVENTS, ZONE
from .codes import (
    ARC_HARMONIC,
    ARC_HYPERBOLIC,
    ARC_QUADRATIC,
    CBREAKS,
    CIMPACTS,
    CLISTS,
    CONTACT_ULPS,
    COPENINGS,
    CSLIPS,
    CSTICKS,
    CZONE,
    EPS,
    INF,
    PA,
    PALL_JOINED,
    PB,
    PCLOSED,
    PCROSSINGS,
    PDIRTY,
    PHELD,
    PIMPACTS,
    PIS_CLOSE,
    PIS_OPEN,
    PIS_STOP,
    PJOINED,
    PK,
    PKAPPA,
    PKIND,
    PLAND,
    PLANDS,
    PLIST_CROSSINGS,
    PLIST_STOPS,
    PLOWER,
    PM,
    POLD_SIGMA,
    POMEGA,
    POPENINGS,
    POUT,
    PS,
    PSIGMA,
    PSLIPS,
    PSLOPE,
    PSTICKS,
    PTOGETHER,
    PTOUCHING,
    PV,
    PW,
    PWAS_JOINED,
    PWORK,
    PX,
    QA_TOL,
    QC_MU,
    QE,
    QHIGHEST,
    QLENGTH,
    QLOWEST,
    QMIN_GAP,
    QRATIO,
    QT_END,
    QTAU0,
    QV_FLOOR,
    REASON_MAX_EVENTS,
    REASON_PERIODS,
    REASON_REST,
    REASON_STALL,
    SEARCH_STEPS,
)
from .compiled import jit
from .piecewise import period_segment, piece_at


# -- the clusters -----------------------------------------------------------------------------------------
@jit
def run_end(g, row, first, n):
    """The last part of the run that starts at part ``first`` of the parts linked by ``g[row]``."""
    last = first
    while last < n - 1 and g[row, last] != 0:
        last += 1
    return last


@jit
def gap(f, i):
    """The gap (x_{i+1} - w_{i+1}) - x_i of contact i."""
    return (f[PX, i + 1] - f[PW, i + 1]) - f[PX, i]


@jit
def contact_tolerance(f, q, i):
    """A gap within this of 0 counts as closed (tie rule 4); a position within it of a zone boundary lies on
    it (tie rule 7)."""
    return CONTACT_ULPS * EPS * (abs(f[PX, i]) + q[QLENGTH])


@jit
def friction(f, q, zone, j):
    """mu_bar of part j at its position (eqs. 7-9 over its own width; 1 on a uniform surface)."""
    return coefficient(f[PX, j], f[PW, j], q[QC_MU]) if zone else 1.0


@jit
def region(f, q, zone, j, sigma):
    """The region of part j moving in direction ``sigma``: a part within the contact tolerance of a zone
    boundary belongs to the region it moves into (tie rule 7)."""
    if not zone:
        return LOW
    x, tol = f[PX, j], contact_tolerance(f, q, j)
    if x < -tol or (abs(x) <= tol and sigma <= 0):
        return LOW
    if x > f[PW, j] + tol or (abs(x - f[PW, j]) <= tol and sigma >= 0):
        return HIGH
    return ZONE


@jit
def place(f, first, last, anchor):
    """Put the parts first..last of a cluster exactly adjacent to part ``anchor``."""
    for j in range(anchor + 1, last + 1):
        f[PX, j] = f[PX, j - 1] + f[PW, j]
    for j in range(anchor - 1, first - 1, -1):
        f[PX, j] = f[PX, j + 1] - f[PW, j + 1]


@jit
def mass_mean(f, row, first, last):
    """The mass-weighted mean of ``f[row]`` over the parts first..last."""
    total = 0.0
    mass = 0.0
    for j in range(first, last + 1):
        total += f[PM, j] * f[row, j]
        mass += f[PM, j]
    return total / mass


@jit
def force_step(f, q, zone, ay, j, sigma, acc, kap, force, rate):
    """(lam_j, d lam_j / d displacement) of contact j inside a sliding cluster on a stop zone, from those of
    contact j - 1: lam_j = sum_{i <= j} m_i (b_i - a), affine in the cluster's displacement while no part
    crosses a zone boundary."""
    b = -ay - sigma * f[PK, j] * friction(f, q, zone, j)
    slope = f[PK, j] * f[PSLOPE, j] if region(f, q, zone, j, sigma) == ZONE else 0.0
    return force + f[PM, j] * (b - acc), rate + f[PM, j] * (-sigma * slope - kap)


# -- between events ---------------------------------------------------------------------------------------
@jit
def take(g, c, best, t, which, item):
    """Keep ``item`` in list ``which`` (0 stops, 1 closes, 2 crossings, 3 opens) if its event time t is the
    earliest so far (emptying the lists when it is earlier than ``best``); returns the earliest time."""
    if t < best:
        best = t
        for k in range(4):
            c[CLISTS + k] = 0
    if t == best:
        g[PLIST_STOPS + which, c[CLISTS + which]] = item
        c[CLISTS + which] += 1
    return best


@jit
def arc_state(f, g, j, s):
    """(displacement, velocity, acceleration, jerk) of part j's cluster a time s into its arc."""
    if g[PSIGMA, j] == 0:
        return 0.0, 0.0, 0.0, 0.0
    acc, kap = f[PA, j], f[PKAPPA, j]
    dx, vel1 = A.step(g[PKIND, j], f[POMEGA, j], f[PV, j], acc, s)
    return dx, vel1, acc + kap * dx, kap * vel1


@jit
def acceleration_bound(f, g, j, vel, acc, window):
    """A bound on |x''''| = |kappa x''| of part j's cluster over a ``window`` of time from the point of its arc
    where its velocity and acceleration are ``vel``, ``acc``: on a harmonic arc x'' oscillates with the
    amplitude hypot(x'', omega x'), on a hyperbolic one it grows at most by cosh and sinh of omega times the
    window."""
    kind, om = g[PKIND, j], f[POMEGA, j]
    if g[PSIGMA, j] == 0 or kind == ARC_QUADRATIC:
        return 0.0
    if kind == ARC_HARMONIC:
        return om * om * math.hypot(acc, om * vel)
    return om * om * (abs(acc) * math.cosh(om * window) + om * abs(vel) * math.sinh(om * window))


@jit
def lower_bound(coef, p, quartic, s):
    """coef[p] - sum_{k > p} max(-coef[k], 0) s^(k - p) - quartic s^(4 - p)."""
    total = coef[p] - quartic * math.pow(s, 4.0 - p)
    for k in range(p + 1, 4):
        total -= max(-coef[k], 0.0) * math.pow(s, float(k - p))
    return total


@jit
def safe_step(coef, p, quartic, limit):
    """The first root of :func:`lower_bound` (decreasing from coef[p] > 0), by bisection to rounding; inf if
    it lies beyond ``limit``."""
    if lower_bound(coef, p, quartic, limit) > 0.0:
        return INF
    lo, hi = 0.0, limit
    while hi - lo > 4.0 * EPS * hi:
        mid = 0.5 * (lo + hi)
        if lower_bound(coef, p, quartic, mid) > 0.0:
            lo = mid
        else:
            hi = mid
    return lo


@jit
def closing_search(f, g, q, i, gp, tol, horizon):
    """Conservative advancement on the closed-form arcs of the two clusters at contact i: with the gap's first
    three derivatives exact and |g''''| <= b, the gap stays above g + g' s + g'' s^2 / 2 + g''' s^3 / 6 -
    b s^4 / 24 (its negative terms only), whose first root is a safe step; near a closing the steps shrink as
    Newton's would.  The search looks at most 1 / omega ahead at a time (the bound of a hyperbolic arc grows
    as exp(omega s)) and goes on to ``horizon``.  Returns (s, closes) as :func:`closing_time`."""
    omega = max(f[POMEGA, i], f[POMEGA, i + 1])
    reach = 1.0 / omega if omega > 0.0 else INF
    s = 0.0
    c0 = gp
    for _ in range(SEARCH_STEPS):
        r0, r1, r2, r3 = arc_state(f, g, i, s)
        f0, f1, f2, f3 = arc_state(f, g, i + 1, s)
        c1, c2, c3 = f1 - r1, (f2 - r2) / 2.0, (f3 - r3) / 6.0
        if s > 0.0:
            c0 = gp + (f0 - r0)
            if c0 <= tol:
                return s, True
        elif gp <= tol:                     # touching: the first derivative that is not zero decides
            c0 = 0.0
            if abs(c1) <= q[QV_FLOOR]:
                c1 = 0.0
                if abs(c2) <= q[QA_TOL]:
                    c2 = 0.0
                    if c3 == 0.0:
                        c3 = 0.0
            lead = c1 if c1 != 0.0 else (c2 if c2 != 0.0 else c3)
            if lead < 0.0:
                return 0.0, True
            if lead == 0.0:
                return INF, True
        p = 0 if c0 > 0.0 else (1 if c1 > 0.0 else (2 if c2 > 0.0 else 3))
        window = min(horizon - s, reach)
        bound = acceleration_bound(f, g, i, r1, r2, window) + acceleration_bound(f, g, i + 1, f1, f2, window)
        step = safe_step((c0, c1, c2, c3), p, bound / 24.0, window)
        if step == INF:
            if window >= horizon - s:
                return INF, True
            step = window
        s += step
    return s, False


@jit
def closing_time(f, g, q, i, horizon):
    """(s, closes) of the open contact i: the first s > 0 at which it closes (0 if it touches and approaches),
    or inf; closes False for a check point of the search that is no closing."""
    gp = gap(f, i)
    tol = contact_tolerance(f, q, i)
    if g[PKIND, i] == ARC_QUADRATIC and g[PKIND, i + 1] == ARC_QUADRATIC:
        dv = f[PV, i + 1] - f[PV, i]
        da = f[PA, i + 1] - f[PA, i]
        if gp <= tol:
            if dv < 0.0:
                return 0.0, True
            gp = 0.0
        return A.first_positive_root(0.5 * da, dv, gp), True
    return closing_search(f, g, q, i, gp, tol, horizon)


@jit
def next_event(f, g, q, c, zone, n, ay, rem):
    """The time s of the earliest event within ``rem`` (``rem`` if the piece ends first), with its lists (of
    ``g``, lengths in ``c``): the clusters reaching v = 0, the contacts closing, the zone crossings (part; its
    boundary in ``f[PLAND]``) and the contacts whose force falls to 0 (or a check point of a closing search),
    all at s."""
    best = rem
    for k in range(4):
        c[CLISTS + k] = 0
    first = 0
    while first < n:
        last = run_end(g, PJOINED, first, n)
        sigma = g[PSIGMA, first]
        if sigma != 0:
            vel, acc = f[PV, first], f[PA, first]
            kind, om = g[PKIND, first], f[POMEGA, first]
            best = take(g, c, best, A.zero_velocity_time(kind, om, sigma, vel, acc), 0, first)
            if zone:
                # The cluster moves as one, so its parts cross their boundaries in the order of the distances to
                # them: the nearest crossing, and every part within the contact tolerance of that distance (touching
                # parts of equal widths reach x_mu and x_mu + w together), are one event at one time.
                nearest, near = INF, -1
                for j in range(first, last + 1):
                    r = region(f, q, zone, j, sigma)
                    if sigma > 0 and r != HIGH:
                        f[PLAND, j] = 0.0 if r == LOW else f[PW, j]
                    elif sigma < 0 and r != LOW:
                        f[PLAND, j] = f[PW, j] if r == HIGH else 0.0
                    else:
                        f[PLAND, j] = INF
                        continue
                    if abs(f[PX, j] - f[PLAND, j]) < nearest:
                        nearest, near = abs(f[PX, j] - f[PLAND, j]), j
                if near >= 0:
                    t = A.crossing_time(kind, om, vel, acc, f[PX, near] - f[PLAND, near])
                    for j in range(first, last + 1):
                        if f[PLAND, j] != INF and abs(f[PX, j] - f[PLAND, j]) <= nearest + contact_tolerance(f, q, j):
                            best = take(g, c, best, t, 2, j)
                if kind != ARC_QUADRATIC:
                    force, rate, kap = 0.0, 0.0, f[PKAPPA, first]
                    for j in range(first, last):
                        force, rate = force_step(f, q, zone, ay, j, sigma, acc, kap, force, rate)
                        if force > 0.0 and rate != 0.0:
                            best = take(g, c, best, A.crossing_time(kind, om, vel, acc, force / rate), 3, j)
        first = last + 1
    for i in range(n - 1):
        if g[PJOINED, i] == 0:
            t, closes = closing_time(f, g, q, i, best)
            best = take(g, c, best, t, 1 if closes else 3, i)
    return best


@jit
def flag_lists(g, c, value):
    """Set (``value`` 1) or clear (0) the flags of the parts and contacts in the event lists."""
    for k in range(4):
        for item in range(c[CLISTS + k]):
            g[PIS_STOP + k if k < 2 else (PLANDS if k == 2 else PIS_OPEN), g[PLIST_STOPS + k, item]] = value


@jit
def advance(f, g, n, s):
    """Move every cluster on by a time s (the clusters whose first part is flagged in ``g[PIS_STOP]`` reach
    v = 0; the parts flagged in ``g[PLANDS]`` land on their zone boundary ``f[PLAND]``)."""
    first = 0
    while first < n:
        last = run_end(g, PJOINED, first, n)
        sigma = g[PSIGMA, first]
        if sigma != 0:
            vel, acc = f[PV, first], f[PA, first]
            dx, vel1 = A.step(g[PKIND, first], f[POMEGA, first], vel, acc, s)
            if g[PIS_STOP, first] != 0 or vel1 * sigma < 0.0:      # tie rules 2-3
                vel1 = 0.0
                for j in range(first, last + 1):
                    g[PDIRTY, j] = 1
            anchor = first
            for j in range(first, last + 1):
                if g[PLANDS, j] != 0:
                    anchor = j
                    break
            f[PX, anchor] = f[PLAND, anchor] if g[PLANDS, anchor] != 0 else f[PX, anchor] + dx
            place(f, first, last, anchor)
            acc1 = acc + f[PKAPPA, first] * dx
            for j in range(first, last + 1):
                f[PV, j] = vel1
                f[PA, j] = acc1
        first = last + 1


# -- at an event --------------------------------------------------------------------------------------------
@jit
def decide(f, g, q, zone, first, last, ay, out):
    """Accelerations of the parts first..last, touching at one velocity, under y'' = ay, written into row
    ``out`` of ``f``: :func:`~selfalign.model.parts.chain_minimiser` with kinetic friction at v != 0, and at
    v = 0 :func:`~selfalign.model.parts.static_kinetic_minimiser` (the static bound r k mu_bar until a part
    slips; with r = 1 the chain minimiser with the stick bound k mu_bar)."""
    vel = f[PV, first]
    for j in range(first, last + 1):
        f[PS, j] = f[PK, j] * friction(f, q, zone, j)
    end = last + 1
    if vel == 0.0:
        for j in range(first, last + 1):
            f[PB, j] = -ay
        # every part of the cluster is at rest and may stick (the row of ones of PALL_JOINED, N long)
        static_kinetic_minimiser(f[PB, first:end], f[PM, first:end], f[PS, first:end], q[QRATIO],
                                 g[PALL_JOINED, first:end], f[PLOWER, first:last], g[PALL_JOINED, first:last],
                                 f[out, first:end], f[PWORK:PWORK + STATIC_WORK_ROWS, first:end])
        return
    sign = math.copysign(1.0, vel)
    for j in range(first, last + 1):
        f[PB, j] = -ay - sign * f[PS, j]
        f[PS, j] = 0.0
    chain_minimiser(f[PB, first:end], f[PM, first:end], f[PS, first:end], f[PLOWER, first:last],
                    g[PALL_JOINED, first:last], f[out, first:end], f[PWORK:PWORK + CHAIN_WORK_ROWS, first:end])


@jit
def set_arc(f, g, q, zone, first, last):
    """The direction, acceleration and arc of the cluster first..last (tie rule 6: the mass-weighted mean of
    accelerations that differ by rounding)."""
    for j in range(first + 1, last + 1):
        if f[PA, j] != f[PA, first]:
            acc = mass_mean(f, PA, first, last)
            for i in range(first, last + 1):
                f[PA, i] = acc
            break
    vel, acc = f[PV, first], f[PA, first]
    sigma = (1 if vel > 0.0 else -1) if vel != 0.0 else (0 if acc == 0.0 else (1 if acc > 0.0 else -1))
    stiffness = 0.0
    if sigma != 0 and zone:
        mass = 0.0
        for j in range(first, last + 1):
            if region(f, q, zone, j, sigma) == ZONE:
                stiffness += f[PM, j] * f[PK, j] * f[PSLOPE, j]
            mass += f[PM, j]
        stiffness /= mass
    kind = ARC_QUADRATIC if stiffness == 0.0 else (ARC_HARMONIC if sigma > 0 else ARC_HYPERBOLIC)
    omega, kappa = math.sqrt(stiffness), A.stiffness(kind, stiffness)
    for j in range(first, last + 1):
        g[PSIGMA, j] = sigma
        g[PKIND, j] = kind
        f[POMEGA, j] = omega
        f[PKAPPA, j] = kappa


@jit
def split(f, g, q, zone, n, first, last, ay):
    """Open the contacts of a sliding cluster on a stop zone whose force is zero (to rounding, or because it fell
    to zero at this event: flagged in ``g[PIS_OPEN]``) and falls as the cluster moves on (tie rule 8); each
    side gets its own arc."""
    direction = f[PV, first] if f[PV, first] != 0.0 else f[PA, first]
    mass = 0.0
    for j in range(first, last + 1):
        mass += f[PM, j]
    sigma, acc, kap = g[PSIGMA, first], f[PA, first], f[PKAPPA, first]
    force, rate = 0.0, 0.0
    cut = False
    for i in range(first, last):
        force, rate = force_step(f, q, zone, ay, i, sigma, acc, kap, force, rate)
        if (g[PIS_OPEN, i] != 0 or force <= q[QA_TOL] * mass) and rate * direction < 0.0:
            g[PJOINED, i] = 0
            cut = True
    if not cut:
        return
    start = first
    while start <= last:
        end = run_end(g, PJOINED, start, n)
        for j in range(start, end + 1):
            f[PB, j] = -ay - sigma * f[PK, j] * friction(f, q, zone, j)
        acc = mass_mean(f, PB, start, end)
        for j in range(start, end + 1):
            f[PA, j] = acc
        set_arc(f, g, q, zone, start, end)
        start = end + 1


@jit
def settle(f, g, q, c, zone, n, ay, start, everything, instant):
    """Decide the contacts, impacts, clusters and accelerations at the current state under y'' = ay: every
    cluster (``everything``, at a break, and at every event on a stop zone, where the friction depends on the
    positions) or those an event touched, flagged in ``g[PDIRTY]`` (the others keep their accelerations,
    which a new decision would give again).  The contacts that closed at this event are flagged in
    ``g[PIS_CLOSE]``, those whose force fell to zero in ``g[PIS_OPEN]``; ``start``: the state at the run's
    start, whose stick and slip modes are no events (its impacts are); ``instant``: the event follows the one
    before it at the same time (tie rule 9)."""
    v_floor = q[QV_FLOOR]
    if everything or zone:
        for j in range(n):
            g[PDIRTY, j] = 1
    for i in range(n - 1):
        g[PTOUCHING, i] = g[PJOINED, i]
        if g[PTOUCHING, i] == 0 and (g[PIS_CLOSE, i] != 0 or gap(f, i) <= contact_tolerance(f, q, i)):
            g[PTOUCHING, i] = 1
            g[PDIRTY, i] = 1
            g[PDIRTY, i + 1] = 1
            if g[PIS_CLOSE, i] != 0 or f[PV, i] > f[PV, i + 1]:
                c[CIMPACTS] += 1
                g[PIMPACTS, i] += 1
                g[PIMPACTS, i + 1] += 1
    for i in range(n - 1):          # tie rule 9
        g[PCLOSED, i] = g[PTOUCHING, i] if instant else g[PTOUCHING, i] * (f[PV, i + 1] - f[PV, i] <= v_floor)
    first = 0
    while first < n:
        last = run_end(g, PCLOSED, first, n)
        for j in range(first, last):
            if f[PV, j] - f[PV, j + 1] > v_floor:
                end = last + 1
                impact_velocities(f[PV, first:end], f[PM, first:end], q[QE], g[PCLOSED, first:last],
                                  f[POUT, first:end], f[PWORK:PWORK + IMPACT_WORK_ROWS, first:end])
                for i in range(first, end):
                    f[PV, i] = f[POUT, i]
                    g[PDIRTY, i] = 1
                break
        first = last + 1
    for i in range(n - 1):
        g[PTOGETHER, i] = g[PTOUCHING, i] * (abs(f[PV, i + 1] - f[PV, i]) <= v_floor)
        g[PWAS_JOINED, i] = g[PJOINED, i]
    for j in range(n):
        g[POLD_SIGMA, j] = g[PSIGMA, j]
    first = 0
    while first < n:
        last = run_end(g, PTOGETHER, first, n)
        dirty = False
        for j in range(first, last + 1):
            dirty = dirty or g[PDIRTY, j] != 0
        if dirty:
            equal = True
            for j in range(first, last + 1):
                g[PDIRTY, j] = 1
                equal = equal and f[PV, j] == f[PV, first]
            if not equal:                                   # tie rule 5: one velocity, momentum kept
                vel = mass_mean(f, PV, first, last)
                for j in range(first, last + 1):
                    f[PV, j] = vel
            decide(f, g, q, zone, first, last, ay, PA)
        first = last + 1
    for i in range(n - 1):
        if g[PDIRTY, i] != 0 or g[PDIRTY, i + 1] != 0:
            g[PJOINED, i] = g[PTOGETHER, i] * (abs(f[PA, i + 1] - f[PA, i]) <= q[QA_TOL])
    first = 0
    while first < n:
        last = run_end(g, PJOINED, first, n)
        if g[PDIRTY, first] != 0:
            set_arc(f, g, q, zone, first, last)
            if zone and last > first and g[PSIGMA, first] != 0:
                split(f, g, q, zone, n, first, last, ay)
        first = last + 1
    for i in range(n - 1):
        if g[PWAS_JOINED, i] != 0 and g[PJOINED, i] == 0:
            c[COPENINGS] += 1
            g[POPENINGS, i] += 1
            g[POPENINGS, i + 1] += 1
    first = 0
    while first < n:
        last = run_end(g, PJOINED, first, n)
        if g[PDIRTY, first] != 0:
            place(f, first, last, first)                    # touching parts exactly adjacent
            sigma = g[PSIGMA, first]
            changed = False
            for j in range(first, last + 1):
                changed = changed or g[POLD_SIGMA, j] != sigma
            if f[PV, first] == 0.0 and changed and not start:
                c[CSTICKS if sigma == 0 else CSLIPS] += 1
                for j in range(first, last + 1):
                    g[PSTICKS if sigma == 0 else PSLIPS, j] += 1
        first = last + 1
    for j in range(n):
        g[PDIRTY, j] = 0
    for i in range(n - 1):
        q[QMIN_GAP] = min(q[QMIN_GAP], gap(f, i) / (abs(f[PX, i]) + q[QLENGTH]))


@jit
def held(f, g, q, zone, first, last):
    """The touching parts first..last stick for good: at rest, and the mode selection (:func:`decide`, b = -y'',
    the stick bounds) gives them zero accelerations under the largest and the smallest y'' of the profile, and so
    under every y'' between (its solution is monotone in b)."""
    for j in range(first, last + 1):
        if f[PV, j] != 0.0 or f[PA, j] != 0.0:
            return False
    for ay in (q[QHIGHEST], q[QLOWEST]):
        decide(f, g, q, zone, first, last, ay, POUT)
        for j in range(first, last + 1):
            if f[POUT, j] != 0.0:
                return False
    return True


@jit
def at_rest(f, g, q, zone, n):
    """Every part sticks for good (:func:`held`, cluster by cluster): no table acceleration of the profile moves
    any cluster."""
    for j in range(n):
        if f[PV, j] != 0.0 or f[PA, j] != 0.0:
            return False
    first = 0
    while first < n:
        last = run_end(g, PJOINED, first, n)
        if not held(f, g, q, zone, first, last):
            return False
        first = last + 1
    return True


@jit
def mark_held(f, g, q, zone, n):
    """Row PHELD: 1 for each part whose cluster sticks for good (:func:`held`), else 0."""
    first = 0
    while first < n:
        last = run_end(g, PJOINED, first, n)
        flag = 1 if held(f, g, q, zone, first, last) else 0
        for j in range(first, last + 1):
            g[PHELD, j] = flag
        first = last + 1


# -- the run --------------------------------------------------------------------------------------------------
@jit
def events(c):
    """All events counted, of every kind."""
    return c[CSTICKS] + c[CSLIPS] + c[CIMPACTS] + c[COPENINGS] + c[CBREAKS]


@jit
def run_parts(f, g, q, c, row, periods, max_events):
    """:func:`advance_parts`, then row PHELD of the end state (:func:`mark_held`).  Returns the reason code."""
    code = advance_parts(f, g, q, c, row, periods, max_events)
    mark_held(f, g, q, c[CZONE] != 0, f.shape[1])
    return code


@jit
def advance_parts(f, g, q, c, row, periods, max_events):
    """Run the parts from the start phase tau0 (``q[QTAU0]``, the period boundaries at tau0 + n dt) over
    ``periods`` periods of the piecewise-constant profile ``row``, or until every part is at rest for good, the
    event budget ``max_events`` is used up, or more than STALL_EVENTS events of zero length follow one another.
    Returns the reason code; the end time is ``q[QT_END]``, the end state and the counts are in the arrays."""
    n = f.shape[1]
    zone = c[CZONE] != 0
    dt = row[R.DT]
    m = R.data_size(row)
    tau0 = q[QTAU0]
    i0 = piece_at(row, tau0)
    tail = tau0 > row[R.col_break(i0)]
    nseg = m + 1 if tail else m
    stalled = 0
    settle(f, g, q, c, zone, n, row[R.col_level(m, i0)], True, True, False)
    fresh = True
    for period in range(periods):
        for k in range(nseg):
            p, ts, seg, dn, at_break = period_segment(row, m, i0, tau0, tail, k)
            ay = row[R.col_level(m, p)]
            if at_break and not fresh:
                c[CBREAKS] += 1
                settle(f, g, q, c, zone, n, ay, False, True, False)
            fresh = False
            t0 = (period + dn) * dt + ts
            s0 = 0.0
            while True:
                if at_rest(f, g, q, zone, n):
                    q[QT_END] = t0 + s0
                    return REASON_REST
                if events(c) >= max_events:
                    q[QT_END] = t0 + s0
                    return REASON_MAX_EVENTS
                s = next_event(f, g, q, c, zone, n, ay, seg - s0)
                if c[CLISTS] + c[CLISTS + 1] + c[CLISTS + 2] + c[CLISTS + 3] == 0:
                    advance(f, g, n, seg - s0)
                    break
                flag_lists(g, c, 1)
                advance(f, g, n, s)
                for item in range(c[CLISTS + 2]):
                    g[PCROSSINGS, g[PLIST_CROSSINGS, item]] += 1
                s0 += s
                stalled = stalled + 1 if s == 0.0 else 0
                if stalled > STALL_EVENTS:
                    flag_lists(g, c, 0)
                    q[QT_END] = t0 + s0
                    return REASON_STALL
                settle(f, g, q, c, zone, n, ay, False, False, s == 0.0)
                flag_lists(g, c, 0)
    q[QT_END] = periods * dt + tau0
    return REASON_PERIODS
