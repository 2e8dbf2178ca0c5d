"""Moreau's midpoint time-stepping for several parts on one table (the paper's Sect. 4.1 method, extended to
its Sect. 8 recommendation 5): unilateral contacts between neighbours, impacts with Newton's restitution e
and Coulomb friction (eqs. 2, 6, 7-9 per part), in one exact convex solve per step.

The model (``selfalign.model.parts``): part i (0 the rear-most) has its front at x_i, width w_i, mass m_i
and friction factor k_i; the gap to the part in front is g_i = (x_{i+1} - w_{i+1}) - x_i.

One step of size h = dt / N from (x, v) at time t_k = k h (all parts at once):

    x_M,i   = x_i + h/2 v_i                                     (midpoint positions)
    mu_i    = k_i mu_bar(x_M,i - x_mu; w_i, c_mu)               (eqs. 7-9 over the part's OWN width; 1 off a zone)
    g_M,i   = g_i + h/2 (v_{i+1} - v_i)                          (midpoint gaps)
    active  = { i : g_M,i <= 0 }                                 (Moreau's contact rule)
    u       = argmin  sum_i m_i ((u_i - b_i)^2 / 2 + s_i |u_i|)
              subject to  u_{i+1} - u_i >= e max(v_i - v_{i+1}, 0)  for i in active,
              b_i = v_i - (y'(t_k + h) - y'(t_k)),   s_i = h mu_i
    x_i     <- x_M,i + h/2 u_i,     v_i <- u_i,     g_i <- g_M,i + h/2 (u_{i+1} - u_i)

The gaps are integrated along with the positions (the same formula, (x_{i+1} - w_{i+1}) - x_i, up to
rounding) rather than recomputed from them: touching parts at one velocity then keep a gap of exactly 0
and their contact stays active, where a difference of positions would open it by a rounding error now
and then (and the parts would part for a step).  A start gap within rounding of 0 (16 eps times the
positions involved) counts as touching.

The minimisation is one call of :func:`~selfalign.model.parts.chain_minimiser` (exact: pooling of
adjacent violators, no iteration, no tolerance).  Its optimality conditions are the implicit
(backward Euler) impulse balance of every part over the step,

    m_i (u_i - v_i) = -m_i (y'(t_k + h) - y'(t_k)) - h m_i mu_i xi_i + P_{i-1} - P_i,   xi_i in Sign(u_i),

with contact impulses P_i >= 0 only on active contacts and complementary to
u_{i+1} - u_i - e max(v_i - v_{i+1}, 0) >= 0: Moreau's impact law (Newton's at the velocity level,
simultaneous over all active contacts: the generalised law of
:func:`~selfalign.model.parts.impact_velocities`), which with e = 0 makes touching parts share one
velocity and with the friction term gives sticking, sliding and pushing clusters.  No friction impulse
acts at an impact beyond the step's own h mu_i (friction is bounded by the weight).  Under static/kinetic
friction the step's mode selection is :func:`~selfalign.model.parts.static_kinetic_minimiser` instead.

The table's impulse over a step, y'(t_k + h) - y'(t_k), is integrated exactly, in closed form, as in the
one-part scheme (:func:`selfalign.solvers.moreau.table_impulses`), rather than as h y''(t_k + h/2): no short
phase of the profile is missed, and the table velocity the parts see is periodic.  With
one part the step is exactly that of ``simulate(scene, method="moreau")`` (the soft threshold).

Penetration.  Contacts are decided at the midpoint and enforced at the velocity level, so a contact that
closes during a step can overlap: the overlap -g_i (end of step) stays below h times the approach speed
|v_{i+1} - v_i| just before the contact closed (the second half of the step that closes it and the
first half of the next), and it is kept, not pushed back, while the parts stay together (e = 0) - an
O(h) position error of the kind the scheme makes anyway (first order).  The result reports the largest
overlap, :attr:`PartsMoreauResult.max_overlap`.  Measured on two parts of tests/test_parts_moreau.py that
collide at about 0.12 in every period of the Fig. 18 profile, over h = dt/250 ... dt/64000: largest
overlap / h = 0.05-0.12 with e = 0, 0.06-0.08 with e = 0.5, 0.03-0.05 with e = 1.

Two position-level alternatives were not chosen.  The bound u_{i+1} - u_i >= -2 g_i / h - (v_{i+1} - v_i),
which keeps every end gap >= 0 with midpoint positions, forces the second half-step to undo the first: a
contact that closes at the start of a step rebounds at the approach speed whatever e is (every impact
elastic).  The bound u_{i+1} - u_i >= -g_i / h keeps the gaps >= 0 only with the end-velocity position
update x <- x + h u, which is not the paper's midpoint scheme (and not the one-part solver's).

While every part is at rest (v = 0) a step is the identity as long as every part alone would stick,
|y'(t_k + h) - y'(t_k)| <= h mu_i for all i (u = 0 is then the minimiser, and no contact needs a force), so
the stepper skips those steps, bit for bit the result of taking them (as the one-part solver does).

The step h must be small compared with the gaps and widths over the approach speeds (h |v_rel| << w):
a part may not pass through its neighbour within one step.
"""

from __future__ import annotations

import functools
from dataclasses import dataclass

import numpy as np

from ..model.errors import check_integer, check_real
from ..model.friction import StopZone, Uniform, coefficient
from ..model.parts import (
    CHAIN_WORK_ROWS,
    STATIC_WORK_ROWS,
    chain_minimiser,
    check_parts,
    check_restitution,
    parts_friction_ratio,
    static_kinetic_minimiser,
)
from ..model.profiles import Profile
from . import moreau as M
from .methods import check_moreau_work

#: Most bytes of the sampled positions and velocities of one run (checked before the run).
MAX_SAMPLE_BYTES = 2 * 1024**3


@dataclass(frozen=True)
class PartsMoreauResult:
    """The end state of a Moreau run of several parts (:func:`moreau_parts`) and its samples.

    Built by :func:`moreau_parts`; arrays are read-only.  Part i of the arrays is part i of the input,
    the rear-most first.

    Parameters
    ----------
    t_end : float
        The end time (Attributes).
    x_end, v_end : numpy.ndarray
        The end state (Attributes).
    steps : int
        The step count (Attributes).
    h, max_overlap : float
        The step and the largest overlap (Attributes).
    t, x, v : numpy.ndarray or None
        The samples (Attributes).

    Attributes
    ----------
    t_end : float
        The end time, (phase + periods) times the period dt (the run starts at t = phase dt).
    x_end : numpy.ndarray
        Front positions x_i at ``t_end``, shape (N,), rear-most part first.
    v_end : numpy.ndarray
        Velocities relative to the table at ``t_end``, shape (N,).
    steps : int
        Number of Moreau steps taken.
    h : float
        The step, dt / ``steps_per_period``.
    max_overlap : float
        The largest overlap -g_i = x_i - (x_{i+1} - w_{i+1}) of neighbours at the end of any step (0 if
        none ever overlapped): the scheme's penetration, O(h) (module docstring).
    t : numpy.ndarray or None
        Sample times (every ``sample_every`` steps from the start), or None without samples.
    x : numpy.ndarray or None
        Positions at the sample times, shape (samples, N), or None.
    v : numpy.ndarray or None
        Velocities at the sample times, shape (samples, N), or None.

    Examples
    --------
    >>> import selfalign as sa
    >>> from selfalign.model.parts import Part
    >>> from selfalign.solvers.parts_moreau import moreau_parts
    >>> profile = sa.ThreePhaseProfile(1.05, 0.084, 2.2, 0.9)
    >>> result = moreau_parts(profile, [Part(0.0, width=0.05)], periods=2, sample_every=500)
    >>> result.steps, result.x.shape, result.t.round(3).tolist()
    (2000, (5, 1), [0.0, 0.525, 1.05, 1.575, 2.1])
    >>> bool(result.x[-1, 0] == result.x_end[0]), result.x_end.flags.writeable
    (True, False)
    """

    t_end: float
    x_end: np.ndarray
    v_end: np.ndarray
    steps: int
    h: float
    max_overlap: float
    t: np.ndarray | None = None
    x: np.ndarray | None = None
    v: np.ndarray | None = None


def moreau_parts(profile, parts, *, surface=None, restitution=0.0, periods, phase=0.0, steps_per_period=1000,
                 sample_every=None, friction=None) -> PartsMoreauResult:
    """Simulate N parts on one vibrating table with Moreau's midpoint time-stepping.

    Every step solves the parts' contacts, impacts (Newton's law with restitution e) and Coulomb friction
    together in one exact convex problem (``selfalign.model.parts.chain_minimiser``); the module docstring
    of ``selfalign.solvers.parts_moreau`` writes the scheme down.  With one part it is the one-part Moreau
    scheme of ``simulate(scene, method="moreau")``.

    Parameters
    ----------
    profile : Profile
        The table motion y(t) (any profile: piecewise-constant y'' such as the paper's
        :class:`~selfalign.ThreePhaseProfile` is integrated piece by piece, smooth ones through y').
    parts : sequence of Part
        The parts (``selfalign.model.parts.Part``), rear-most first, not overlapping; their ``x0``, ``v0``
        are the state at t = 0.
    surface : Uniform or StopZone, optional
        The table surface; default ``Uniform()``.  Of a StopZone only ``x_mu`` and ``c_mu`` are used:
        each part sees eqs. 7-9 over its own width.
    restitution : float, optional
        Newton's coefficient e in [0, 1] of the contacts between parts.  Default 0 (plastic).
    periods : int
        Number of periods to simulate, >= 1.
    phase : float, optional
        The start time as a fraction of the period, in [0, 1) (as ``Scene.phase``): the parts' ``x0``, ``v0``
        hold at t = phase dt and the run ends at (phase + periods) dt.  Default 0.
    steps_per_period : int, optional
        Moreau steps per period N (the step is h = dt / N); in [1, 10,000,000].  Default 1000.
    sample_every : int, optional
        Record the state every this many steps (from the start); default None: the end state only.
    friction : FrictionLaw, optional
        Coulomb's law (the default) or static/kinetic friction: a part whose velocity would reach or cross zero
        within a step gets the static bound h r mu_i, and slips with the kinetic one if that does not hold it
        (:func:`~selfalign.model.parts.static_kinetic_minimiser`; the one-part scheme's rule).  Stribeck's law
        is refused.

    Returns
    -------
    PartsMoreauResult
        End state, step count, step size, largest overlap and the samples.

    Raises
    ------
    TypeError
        If ``profile`` is not a Profile, ``surface`` not a Uniform or StopZone, ``friction`` not a
        FrictionLaw, ``parts`` not a sequence of Part, or a count or ``restitution`` not a number.
    ValueError
        If the parts overlap or are not listed rear to front, ``restitution`` lies outside [0, 1], a count
        is out of range, the friction law is Stribeck's, N steps per period cannot resolve the table
        motion (``selfalign.solvers.moreau.check_swing_seen``), the run exceeds 1e10 steps, or the samples
        would take more than 2 GiB.
    KernelError
        If numba is missing or cannot compile the stepper.

    Examples
    --------
    Two parts 0.05 wide on the Fig. 18 profile; the rear one has less friction (k = 0.7).  Alone, in 10
    periods, it would walk to x = 0.7801 and the front one to 0.654; together the rear one catches the
    front one in every forward slip and pushes it on, then slides back alone while y'' = 0.9 > 0.7:

    >>> import selfalign as sa
    >>> from selfalign.model.parts import Part
    >>> from selfalign.solvers.parts_moreau import moreau_parts
    >>> profile = sa.ThreePhaseProfile(dt=1.05, dy=0.084, y2=2.2, y3=0.9)
    >>> parts = [Part(0.0, width=0.05, friction_factor=0.7), Part(0.06, width=0.05)]
    >>> result = moreau_parts(profile, parts, periods=10)
    >>> print(result.steps, result.x_end.round(4), result.v_end.round(4))
    10000 [0.6775 0.746 ] [-0.0863  0.    ]
    >>> print(f"{result.max_overlap:.2e}", result.max_overlap < result.h * profile.velocity_swing)
    4.85e-05 True
    """
    if not isinstance(profile, Profile):
        raise TypeError(f"profile must be a selfalign Profile, got {type(profile).__name__}")
    parts = check_parts(parts)
    surface = Uniform() if surface is None else surface
    if not isinstance(surface, (Uniform, StopZone)):
        raise TypeError(f"surface must be a Uniform or a StopZone, got {type(surface).__name__}")
    ratio = parts_friction_ratio(friction)
    e = check_restitution(restitution)
    periods = check_integer("periods", periods)
    phase = check_real("phase", phase)
    if not 0.0 <= phase < 1.0:
        raise ValueError(f"phase must lie in [0, 1) (fraction of the period), got {phase!r}")
    n_steps = check_integer("steps_per_period", steps_per_period, 1, M.MAX_STEPS_PER_PERIOD)
    every = None if sample_every is None else check_integer("sample_every", sample_every)
    check_moreau_work(n_steps, periods, "periods")
    total = n_steps * periods
    samples = 0 if every is None else total // every + 1
    n = len(parts)
    if 2 * 8 * samples * (n + 1) > MAX_SAMPLE_BYTES:
        raise ValueError(f"sample_every = {every}: {samples:,} samples of {n} parts would take more than "
                         f"{MAX_SAMPLE_BYTES / 1024**3:g} GiB; sample less often or shorten the run")
    n_steps, h = M.steps_per_period(profile.dt, profile.dt / n_steps)
    impulse = M.table_impulses(profile, phase, n_steps, h)
    M.check_swing_seen(profile, n_steps, impulse)

    x = np.array([p.x0 for p in parts])
    v = np.array([p.v0 for p in parts])
    width = np.array([p.width for p in parts])
    mass = np.array([p.mass for p in parts])
    factor = np.array([p.friction_factor for p in parts])
    zone = isinstance(surface, StopZone) and surface.c_mu > 1.0
    x_mu, c_mu = (surface.x_mu, surface.c_mu) if zone else (0.0, 1.0)
    xs = np.empty((samples, n))
    vs = np.empty((samples, n))
    gap = (x[1:] - width[1:]) - x[:-1]
    gap[gap <= 16 * np.finfo(float).eps * (np.abs(x[1:]) + width[1:] + np.abs(x[:-1]))] = 0.0
    advance = _stepper()
    overlap = advance(x, v, gap, width, mass, factor, zone, x_mu, c_mu, e, ratio, impulse, h, total, every or 0, xs,
                      vs, np.empty((4, n)), np.empty(max(n - 1, 0), dtype=np.bool_), np.empty(max(n - 1, 0)),
                      np.empty(n, dtype=np.bool_), np.empty((STATIC_WORK_ROWS, n)))
    t = None
    if every is not None:
        t = phase * profile.dt + np.arange(samples) * (every * h)
        for a in (t, xs, vs):
            a.flags.writeable = False
    for a in (x, v):
        a.flags.writeable = False
    return PartsMoreauResult(t_end=(phase + periods) * profile.dt, x_end=x, v_end=v, steps=total, h=h,
                             max_overlap=float(overlap), t=t, x=None if every is None else xs,
                             v=None if every is None else vs)


def _advance(x, v, gap, width, mass, factor, zone, x_mu, c_mu, e, ratio, impulse, h, total, every, xs, vs, rows,
             joined, lower, may_stick, work):
    """``total`` Moreau steps of the parts in place (module docstring): x, v, ``gap`` are the state,
    ``impulse`` the table impulses of one period's steps, ``ratio`` r = mu_s / mu_k, ``every`` the sampling
    interval (samples into xs, vs; 0: none); ``rows``, ``joined``, ``lower``, ``may_stick`` and ``work`` are
    scratch.  Returns the largest overlap of neighbours."""
    x, v, gap, width, mass, factor = _borrowed(x), _borrowed(v), _borrowed(gap), _borrowed(width), \
        _borrowed(mass), _borrowed(factor)
    rows, joined, lower, work = _borrowed(rows), _borrowed(joined), _borrowed(lower), _borrowed(work)
    may_stick = _borrowed(may_stick)
    n = x.size
    half = 0.5 * h
    period = impulse.size
    mid, b, s, u = rows[0], rows[1], rows[2], rows[3]
    overlap = 0.0
    sample = 0
    k = 0
    step = 0
    at_rest = False      # every part at v = 0: a step is the identity while |dv| <= the least h mu_i
    hold = 0.0
    while True:
        if every > 0 and step % every == 0:
            for i in range(n):
                xs[sample, i] = x[i]
                vs[sample, i] = v[i]
            sample += 1
        if step == total:
            break
        dv = impulse[k]
        if not (at_rest and abs(dv) <= hold):
            for i in range(n):
                mid[i] = x[i] + half * v[i]
                mu = factor[i] * coefficient(mid[i] - x_mu, width[i], c_mu) if zone else factor[i]
                s[i] = h * mu
                b[i] = v[i] - dv
            for i in range(n - 1):
                gap[i] += half * (v[i + 1] - v[i])                # the midpoint gap
                joined[i] = gap[i] <= 0.0
                lower[i] = e * max(v[i] - v[i + 1], 0.0)
            if ratio == 1.0:
                chain_minimiser(b, mass, s, lower, joined, u, work[:CHAIN_WORK_ROWS])
            else:
                # the static bound for a part whose velocity would reach or cross 0 within the step
                for i in range(n):
                    may_stick[i] = v[i] * b[i] <= 0.0
                static_kinetic_minimiser(b, mass, s, ratio, may_stick, lower, joined, u, work)
            at_rest = True
            for i in range(n):
                x[i] = mid[i] + half * u[i]
                v[i] = u[i]
                at_rest = at_rest and u[i] == 0.0
            for i in range(n - 1):
                gap[i] += half * (u[i + 1] - u[i])
                overlap = max(overlap, -gap[i])
            if at_rest:
                # At rest the next midpoints are the positions, every part alone sticks while |dv| <= h r mu_i
                # (u = 0 then solves the step, and its contacts need no force): skip those steps.
                hold = np.inf
                for i in range(n):
                    mu = factor[i] * coefficient(x[i] - x_mu, width[i], c_mu) if zone else factor[i]
                    hold = min(hold, h * ratio * mu)
        step += 1
        k += 1
        if k == period:
            k = 0
    return overlap


def _borrowed(array):
    """``array`` itself; compiled (:func:`_stepper`), a view without reference counting
    (``selfalign.solvers.engine.compiled.borrowed``), so that the calls of the chain minimiser in every
    step count no references to their arrays."""
    return array


@functools.cache
def _stepper():
    """:func:`_advance` compiled by numba, calling the model functions compiled
    (:func:`selfalign.solvers.jit.kernel` registers them: the friction formulas, the chain minimiser and its
    helper), and kept in the kernel's cache directory (:func:`selfalign.solvers.jit.cache_dir`, keyed by the
    content of the model's sources; numba itself checks this file's time stamp), so that a later process
    loads it."""
    from .engine.compiled import borrowed
    from .jit import compile_stepper, kernel

    kernel()
    from numba.extending import overload

    overload(_borrowed)(lambda array: lambda array: borrowed(array))
    return compile_stepper(_advance, "the Moreau stepper of several parts")
