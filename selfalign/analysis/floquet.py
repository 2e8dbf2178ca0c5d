"""Floquet multipliers of the steady state, three ways (Sect. 6.1).

The monodromy matrix M = Phi(t0 + k dt, t0) maps a perturbation (dx, dx') of the
periodic motion at the period start t0 = phase * dt to the perturbation k periods
later (eq. 25; k = 1 except for a k-periodic motion); its eigenvalues are the
Floquet multipliers.  :func:`floquet` computes it by

``method="analytic"``
    the linearisation of the closed-form one-period map, eqs. (25)-(33), for every
    case of Table 1 including pure stick (case 5, which the paper leaves out); the
    closed forms are in :mod:`selfalign.analysis.steady_state`.  Three-phase profile on a
    uniform surface at t0 = 0 only.

``method="saltation"``
    fundamental matrices of the smooth arcs of the exact solver, joined by
    saltation matrices at its events (Leine & Nijmeijer, ref. [11] of the paper):

        M = Phi_n S_n ... S_2 Phi_2 S_1 Phi_1.

    Works for everything the exact solver handles (piecewise-constant and Fourier
    profiles, uniform surface or stop zone), e.g. a periodic motion inside the
    transition zone, where no position freedom exists and both multipliers are
    below 1.  See :func:`saltation_matrix` for the matrix of each event kind.

``method="numeric"``
    central finite differences of the k-period map (the paper's method 3), with
    the exact solver (``solver="exact"``) or with Moreau time stepping
    (``solver="moreau"``, step ``h``).  The time-stepping map is a staircase in
    x' at the scale of one step (a step whose velocity lands in the stick window
    |v| <= h mu_bar of the implicit friction impulse erases a perturbation, any
    other step passes it on unchanged), so its local derivative is 0 or 1; only
    a secant with h << eps averages it, with an error ~ lambda2 h / eps
    (docs/explanation/stability.md).  Hence the default eps = sqrt(h) for Moreau.

The periodic motion is started from the closed-form steady state
(:func:`selfalign.analysis.steady_state.steady_state`: x'(0) = v0) for a three-phase
profile on a uniform surface at phase 0, and is otherwise found by the driver with
``until="cycle"`` (:func:`selfalign.simulate_batch`): the exact solver runs until the
state at the period boundary repeats bit for bit ((x', mode) where all periods of the
cycle lie in one region of constant friction, where the motion is invariant under
shifts in x; (x, x', mode) otherwise) with the shortest period k <= 8.
"""

from __future__ import annotations

import math
import numbers
from dataclasses import dataclass, field

import numpy as np

from ..model import arcs as _arcs
from ..model.errors import check_choice, check_real
from ..model.friction import StopZone, Uniform
from ..model.profiles import Profile, ThreePhaseProfile
from ..model.scene import Record, Scene
from ..solvers.driver import simulate, simulate_batch
from ..solvers.methods import resolve
from ..solvers.outcomes import MAX_CYCLE, EventKind, Reason, Status

NUMERIC_SOLVERS = ("exact", "moreau")
#: Options of each method, with their defaults.  ``max_periods`` bounds the search for
#: the periodic motion; ``eps`` is the finite-difference step in x and x' (None:
#: :data:`EXACT_EPS` with the exact solver, sqrt(h) with Moreau, see :func:`floquet`);
#: ``h`` the Moreau time step (None: dt / 1000).
DEFAULT_OPTIONS = {
    "analytic": {},
    "saltation": {"max_periods": 10_000},
    "numeric": {"solver": "exact", "eps": None, "h": None, "max_periods": 10_000},
}
#: Default finite-difference step with the exact solver: the period map is piecewise
#: smooth, so central differences are exact to O(eps^2) on smooth pieces and to O(eps)
#: where a stick makes the map kink (x(dt) gains +-dv^2/2 for either sign of dv).
EXACT_EPS = 1e-7


@dataclass(frozen=True)
class PeriodicMotion:
    """A periodic motion: state (x0, v0) at time phase * dt repeats after ``periods``
    periods (on a uniform surface up to a shift of x by ``advance``).  ``source`` says
    how it was found: "closed form" or "simulated N periods"."""

    profile: Profile
    surface: Uniform | StopZone
    x0: float
    v0: float
    phase: float
    periods: int
    advance: float
    source: str


@dataclass(frozen=True)
class FloquetResult:
    """Floquet multipliers and monodromy matrix of a periodic motion, the result of floquet.

    The monodromy matrix is the 2x2 derivative of the state (x, x') after ``motion.periods``
    periods with respect to the state at the period start phase * dt.  Its eigenvalues, the
    Floquet multipliers, are sorted by decreasing modulus (a real array when both are real),
    with unit eigenvectors as columns in the same order.  On a uniform surface one multiplier
    is 1 (the freedom in position, Sect. 6.1).

    Parameters
    ----------
    method : str
        The method that computed it: "analytic", "saltation" or "numeric".
    monodromy, multipliers, eigenvectors : numpy.ndarray
        The fields of the same names (Attributes).
    motion : ``PeriodicMotion``
        The periodic motion (Attributes).
    info : dict
        Method details (Attributes).

    Attributes
    ----------
    method : str
        The method that computed it.
    monodromy : numpy.ndarray
        The 2x2 monodromy matrix.
    multipliers : numpy.ndarray
        Its two eigenvalues, by decreasing modulus.
    eigenvectors : numpy.ndarray
        Unit eigenvectors as columns, in the order of ``multipliers``.
    motion : ``PeriodicMotion``
        The periodic motion: state (x0, v0) at time phase * dt that repeats after ``periods``
        periods (on a uniform surface up to a shift of x by ``advance``), and ``source``, how
        it was found ("closed form" or "simulated N periods").
    info : dict
        Method details (events used, eps, h, ...).

    See Also
    --------
    floquet : Computes it.

    Examples
    --------
    Case 4 of Fig. 9 (slip-slip), whose second multiplier is c4 of eq. (33):

    >>> import selfalign as sa
    >>> result = sa.floquet(sa.ThreePhaseProfile(dt=1.0, dy=0.084, y2=1.4, y3=1.3))
    >>> result.method, result.multipliers.round(6).tolist(), result.motion.periods
    ('analytic', [1.0, 0.021739], 1)
    >>> result.eigenvectors.round(6).tolist()
    [[1.0, -0.1697], [0.0, 0.985496]]
    """

    method: str
    monodromy: np.ndarray
    multipliers: np.ndarray
    eigenvectors: np.ndarray
    motion: PeriodicMotion
    info: dict = field(default_factory=dict)


def _system(profile_or_scene):
    """(profile, surface, x0, v0, phase) of a Scene, or of a profile on a uniform surface."""
    if isinstance(profile_or_scene, Scene):
        s = profile_or_scene
        return s.profile, s.surface, s.x0, s.v0, s.phase
    if isinstance(profile_or_scene, Profile):
        return profile_or_scene, Uniform(), 0.0, 0.0, 0.0
    raise TypeError(f"floquet needs a selfalign profile or Scene, got {type(profile_or_scene).__name__}")


def _check_options(method, options):
    check_choice("method", method, DEFAULT_OPTIONS)
    allowed = DEFAULT_OPTIONS[method]
    unknown = sorted(set(options) - set(allowed))
    if unknown:
        raise ValueError(f"unknown option(s) {unknown} for method {method!r}; allowed: {sorted(allowed)}")
    opts = {**allowed, **options}
    if "max_periods" in opts:
        mp = opts["max_periods"]
        if isinstance(mp, bool) or not isinstance(mp, numbers.Real):
            raise TypeError(f"option max_periods must be an integer, got {mp!r} ({type(mp).__name__})")
        if not isinstance(mp, numbers.Integral) or mp < 1:
            raise ValueError(f"option max_periods must be an integer >= 1, got {mp!r}")
    if method == "numeric":
        if opts["solver"] not in NUMERIC_SOLVERS:
            raise ValueError(f"option solver must be one of {list(NUMERIC_SOLVERS)}, got {opts['solver']!r}")
        eps = opts["eps"]
        if eps is not None and not 0.0 < check_real("option eps", eps) < 1.0:
            raise ValueError(f"option eps (finite-difference step) must be a number in (0, 1), got {eps!r}")
        h = opts["h"]
        if opts["solver"] == "exact" and h is not None:
            raise ValueError("option h (time step) applies to solver='moreau' only")
        if h is not None:
            resolve("moreau", {"h": h})
    return opts


def _closed_form_applies(profile, surface, phase):
    return isinstance(profile, ThreePhaseProfile) and isinstance(surface, Uniform) and phase == 0.0


def analytic_applies(profile_or_scene) -> bool:
    """Whether method ``analytic`` (closed form, Sect. 6.1) covers this system: a three-phase
    profile on a uniform surface, started at phase 0."""
    profile, surface, _, _, phase = _system(profile_or_scene)
    return _closed_form_applies(profile, surface, phase)


def periodic_motion(profile_or_scene, max_periods: int = 10_000) -> PeriodicMotion:
    """The steady periodic motion the monodromy is taken about (module docstring).

    Raises ValueError when no period-boundary state repeats within ``max_periods``
    periods (e.g. an accumulation, Sect. 7.3, or a chaotic motion).
    """
    profile, surface, x0, v0, phase = _system(profile_or_scene)
    if _closed_form_applies(profile, surface, phase):
        from .steady_state import steady_state

        ss = steady_state(profile)
        return PeriodicMotion(profile, surface, x0, ss.v0, phase, 1, ss.vbar * profile.dt, "closed form")
    res = simulate_batch(profile, x0, v0, phase, surface=None if isinstance(surface, Uniform) else surface,
                         until="cycle", max_periods=max_periods, max_cycle=MAX_CYCLE)
    reason = Reason(int(res.reason[0]))
    if reason is Reason.REST:       # stuck for good: the state repeats every period
        return PeriodicMotion(profile, surface, float(res.x_end[0]), 0.0, phase, 1, 0.0,
                              f"at rest from period {int(res.period_end[0])}")
    if reason.status is not Status.NEVER_STOPS:
        raise ValueError(f"no periodic motion found: the state at the period boundary did not repeat with a "
                         f"period <= {MAX_CYCLE} within max_periods = {max_periods} periods ({res.message(0)})")
    k = int(res.cycle[0])
    advance = float(res.advance[0]) * k if isinstance(surface, Uniform) else 0.0
    return PeriodicMotion(profile, surface, float(res.x_end[0]), float(res.v_end[0]), phase, k, advance,
                          f"simulated {int(res.period_end[0])} periods")


def saltation_matrix(kind, v: float, acc_before: float, acc_after: float) -> np.ndarray:
    """Saltation matrix of one event of the exact solver's log, state z = (x, x').

    The vector field f = (x', x'') jumps from f- = (v, acc_before) to
    f+ = (v, acc_after) on an event surface h(z, t) = 0.  To first order a
    perturbation dz- just before the event becomes (Leine & Nijmeijer, ref. [11])

        dz+ = S dz-,   S = I + (f+ - f-) n^T / (n^T f- + dh/dt),   n = grad_z h.

    * SWITCH (y'' jumps at a profile break) and SLIP (stick ends: |y''| exceeds
      mu_bar, which for a piecewise-constant profile happens only at a break, and
      for a Fourier profile when |y''(t)| crosses 1 -- both times independent of
      the state, as the mass is stuck at a fixed x): h = t - t_s, n = 0, S = I.
    * REVERSAL (x' passes through 0 and the slip changes direction): h = x',
      n = (0, 1), n^T f- = acc_before:  S = [[1, 0], [0, acc_after / acc_before]].
      A velocity perturbation is scaled by the ratio of the slopes after and
      before the crossing (the origin of lambda2 = c4 in case 4, eq. 33).
    * STICK (x' reaches 0 and |y''| <= mu_bar): the motion enters the sliding mode
      x' = 0 whose vector field is f+ = (0, 0) (acc_after = 0):
      S = [[1, 0], [0, 0]].  A velocity perturbation only shifts the stick
      time, by -dv / acc_before, during which x moves by O(dv^2): it is removed,
      a position perturbation is kept.
    * ZONE (x crosses x_mu or x_mu + w): h = x - x_b, n = (1, 0), n^T f- = v:
      S = [[1, 0], [(acc_after - acc_before) / v, 1]].  mu_bar is continuous
      (eq. 9), so x'' is too and S = I up to rounding; only the Jacobian of the
      vector field jumps, which the fundamental matrices of the two arcs carry.
    """
    kind = EventKind(kind)
    if kind in (EventKind.SWITCH, EventKind.SLIP):
        return np.eye(2)
    if kind in (EventKind.STICK, EventKind.REVERSAL):
        if acc_before == 0.0:
            raise ValueError(f"{kind.name} event with x'' = 0 before it: the velocity grazes zero and the "
                             "monodromy matrix does not exist")
        return np.array([[1.0, 0.0], [0.0, acc_after / acc_before]])
    if v == 0.0:
        raise ValueError("ZONE event at x' = 0: the orbit grazes the zone boundary and the monodromy "
                         "matrix does not exist")
    return np.array([[1.0, 0.0], [(acc_after - acc_before) / v, 1.0]])


def arc_matrix(arc) -> np.ndarray:
    """Fundamental matrix of one arc record of the exact solver (:func:`arcs.fundamental_matrix`).

    SMOOTH arcs (Fourier profile, uniform surface) have x'' = -y''(t) - sigma,
    independent of the state, so their matrix is that of a quadratic arc,
    [[1, s], [0, 1]].
    """
    m11, m12, m21, m22 = _arcs.fundamental_matrix(int(arc["kind"]), float(arc["omega"]), float(arc["duration"]))
    return np.array([[m11, m12], [m21, m22]])


def monodromy_from_record(arcs, events) -> tuple[np.ndarray, dict]:
    """Product of arc and saltation matrices in time order (module docstring).

    Arcs and events are the exact solver's records of consecutive periods.  At
    equal times an event comes after the arc that ends there and before the arc
    that starts there; events at one time keep their logged order.  A STICK or
    REVERSAL at the time of a SWITCH (x' = 0 exactly at a break) makes the period
    map non-smooth; the product is then the derivative for perturbations that
    move that event earlier, and ``info["grazing_events"]`` counts them.
    """
    items = [((int(a["period"]), float(a["tau"]), 1, i), a) for i, a in enumerate(arcs)]
    items += [((int(e["period"]), float(e["tau"]), 0, i), e) for i, e in enumerate(events)]
    items.sort(key=lambda item: item[0])
    switch_times = {(int(e["period"]), float(e["tau"])) for e in events if e["kind"] == EventKind.SWITCH}
    grazing = sum(1 for e in events if e["kind"] in (EventKind.STICK, EventKind.REVERSAL)
                  and (int(e["period"]), float(e["tau"])) in switch_times)
    m = np.eye(2)
    for (_, _, is_arc, _), item in items:
        if is_arc:
            m = _matmul(arc_matrix(item), m)
        else:
            m = _matmul(saltation_matrix(item["kind"], float(item["v"]), float(item["acc_before"]),
                                         float(item["acc_after"])), m)
    counts = {k.name.lower(): int(np.count_nonzero(events["kind"] == k)) for k in EventKind}
    return m, {"arcs": len(arcs), "events": counts, "grazing_events": grazing}


def _analytic(motion, opts):
    from .steady_state import monodromy_analytic

    return np.asarray(monodromy_analytic(motion.profile), dtype=float), {}


def _matmul(a, b) -> np.ndarray:
    """2 x 2 matrix product written out: no BLAS, the same bits on every CPU."""
    return np.array([[a[0, 0] * b[0, 0] + a[0, 1] * b[1, 0], a[0, 0] * b[0, 1] + a[0, 1] * b[1, 1]],
                     [a[1, 0] * b[0, 0] + a[1, 1] * b[1, 0], a[1, 0] * b[0, 1] + a[1, 1] * b[1, 1]]])


def _saltation(motion, opts):
    scene = Scene(motion.profile, motion.surface, x0=motion.x0, v0=motion.v0, phase=motion.phase,
                  periods=motion.periods, record=Record(events=True, arcs=True))
    traj = simulate(scene, "exact")
    return monodromy_from_record(traj.arcs, traj.events)


def _period_map(motion, x0, v0, method, options):
    """(x - x0_motion, x') after ``motion.periods`` periods from each (x0, v0), one batch.
    Positions are read relative to each member's origin (x0 on a uniform surface, x_mu on
    a stop zone), so no large x enters the differences."""
    uniform = isinstance(motion.surface, Uniform)
    res = simulate_batch(motion.profile, np.asarray(x0), np.asarray(v0), motion.phase,
                         surface=None if uniform else motion.surface, until="periods", periods=motion.periods,
                         method=method, fast_forward=False, **options)
    xi = res.records["xi"]
    shift = (np.asarray(x0) - motion.x0) + xi if uniform else xi - (motion.x0 - motion.surface.x_mu)
    return np.stack([shift, res.v_end], axis=1)


def moreau_step(dt: float, h) -> float:
    """The Moreau step actually used for a requested ``h`` (dt / ceil(dt / h); None: dt / 1000)."""
    from ..solvers.moreau import steps_per_period

    return steps_per_period(float(dt), h)[1]


def _fd_points(x0, v0, eps):
    """Central-difference points: x0 +- eps at v0, v0 +- eps at x0."""
    return np.array([x0 + eps, x0 - eps, x0, x0]), np.array([v0, v0, v0 + eps, v0 - eps])


def _fd_matrix(p, xs, vs, x0, v0):
    """Difference quotients of the map values ``p`` (4, 2) at :func:`_fd_points`, divided
    by the perturbations actually applied, (x0 + eps) - x0 etc., rather than by 2 eps, so
    that the rounding of x0 + eps does not enter."""
    dx, dv = (xs[0] - x0) - (xs[1] - x0), (vs[2] - v0) - (vs[3] - v0)
    return np.column_stack([(p[0] - p[1]) / dx, (p[2] - p[3]) / dv])


def _numeric(motion, opts):
    x0, v0 = motion.x0, motion.v0
    if opts["solver"] == "exact":
        eps = EXACT_EPS if opts["eps"] is None else opts["eps"]
        xs, vs = _fd_points(x0, v0, eps)
        return (_fd_matrix(_period_map(motion, xs, vs, "exact", {}), xs, vs, x0, v0),
                {"solver": "exact", "eps": eps})
    h = moreau_step(motion.profile.dt, opts["h"])
    eps = math.sqrt(h) if opts["eps"] is None else opts["eps"]
    xs, vs = _fd_points(x0, v0, eps)
    return (_fd_matrix(_period_map(motion, xs, vs, "moreau", {"h": h}), xs, vs, x0, v0),
            {"solver": "moreau", "eps": eps, "h": h})


def eigen(monodromy) -> tuple[np.ndarray, np.ndarray]:
    """Eigenvalues sorted by decreasing modulus (ties: larger real part first) and unit
    eigenvectors as columns; real arrays when the eigenvalues are real.

    Closed form for the 2 x 2 case (no LAPACK, so the same bits on every CPU): with
    m = (a + d) / 2 and disc = ((a - d) / 2)^2 + b c, the larger root is m + sign(m) sqrt(disc)
    and the other det / that (no cancellation); an eigenvector of lambda is (b, lambda - a) or
    (lambda - d, c), whichever is larger, scaled to unit length with its larger component
    positive.
    """
    (a, b), (c, d) = np.asarray(monodromy, dtype=float)
    m, half = 0.5 * (a + d), 0.5 * (a - d)
    disc = half * half + b * c
    if disc >= 0.0:
        root = math.sqrt(disc)
        big = m + math.copysign(root, m) if m != 0.0 else root
        small = (a * d - b * c) / big if big != 0.0 else m - root
        w = np.array([big, small])
    else:
        root = math.sqrt(-disc)
        w = np.array([complex(m, root), complex(m, -root)])
    order = np.lexsort((-w.real, -np.abs(w)))
    w = w[order]
    vec = np.zeros((2, 2), dtype=w.dtype)
    for j, lam in enumerate(w):
        u, v = (b, lam - a), (lam - d, c)
        cand = u if abs(u[0]) + abs(u[1]) >= abs(v[0]) + abs(v[1]) else v
        if cand[0] == 0 and cand[1] == 0:        # a multiple of the identity: any vector
            cand = (1.0, 0.0) if j == 0 else (0.0, 1.0)
        norm = math.sqrt(abs(cand[0]) ** 2 + abs(cand[1]) ** 2)
        sign = 1.0 if (cand[0] if abs(cand[0]) >= abs(cand[1]) else cand[1]).real >= 0.0 else -1.0
        vec[:, j] = (sign * cand[0] / norm, sign * cand[1] / norm)
    return w, vec


def floquet(profile_or_scene, method: str = "analytic", **options) -> FloquetResult:
    """Floquet multipliers and monodromy matrix of the steady state (module docstring).

    ``profile_or_scene``: a profile (uniform surface, start at t = 0) or a Scene (its
    surface, start state and phase).  Options (``DEFAULT_OPTIONS``): saltation
    and numeric ``max_periods``; numeric ``solver`` ("exact" | "moreau"), ``eps``,
    ``h`` (Moreau only).

    The monodromy matrix M = Phi(t0 + k dt, t0) maps a perturbation (dx, dx') of the
    periodic motion at the period start t0 = phase * dt to the perturbation k periods later
    (eq. 25; k = 1 except for a k-periodic motion); its eigenvalues are the Floquet
    multipliers (Sect. 6.1).  The three methods (module docstring of
    ``selfalign.analysis.floquet``):

    * "analytic": the linearisation of the closed-form one-period map, eqs. (25)-(33), for
      every case of Table 1 including pure stick (case 5, which the paper leaves out);
      three-phase profile on a uniform surface at t0 = 0 only.
    * "saltation": fundamental matrices of the exact solver's smooth arcs joined by
      saltation matrices at its events (Leine & Nijmeijer, ref. [11] of the paper), for
      everything the exact solver handles, e.g. a periodic motion inside the transition
      zone, where both multipliers are below 1.
    * "numeric": central finite differences of the k-period map (the paper's method 3) with
      the exact solver or Moreau time-stepping; the time-stepping map is a staircase at the
      scale of one step, so its default step is eps = sqrt(h).

    The periodic motion is the closed-form steady state for a three-phase profile on a
    uniform surface at phase 0; otherwise the driver finds it with ``until="cycle"``, running
    until the period-boundary state repeats with a period k <= 8.

    Parameters
    ----------
    profile_or_scene : Profile or Scene
        A profile (uniform surface, start at t = 0) or a Scene (its surface, start state and
        phase).
    method : str, optional
        How the monodromy matrix is computed: "analytic" (the default), "saltation" or
        "numeric".
    **options
        ``max_periods`` (saltation, numeric; default 10000): the budget of the search for
        the periodic motion.  Numeric only: ``solver`` ("exact" or "moreau", default
        "exact"), ``eps`` (the finite-difference step in x and x', in (0, 1); default
        ``EXACT_EPS`` = 1e-7 with the exact solver, sqrt(h) with Moreau) and ``h`` (the
        Moreau time step; default dt / 1000).

    Returns
    -------
    FloquetResult
        ``monodromy`` (2x2, of (x, x') over ``motion.periods`` periods), its eigenvalues
        ``multipliers`` sorted by decreasing modulus (real dtype when both are real), unit
        ``eigenvectors`` as columns in the same order, the periodic ``motion`` (its start
        state, ``periods``, ``advance`` per cycle and ``source``: "closed form" or
        "simulated N periods") and ``info`` (method details: events used, eps, h, ...).

    Raises
    ------
    TypeError
        If ``profile_or_scene`` is neither a profile nor a Scene, or the option
        ``max_periods``, ``eps`` or ``h`` is not a number.
    ValueError
        If the method or an option is unknown or an option value is not allowed; "analytic"
        is asked outside
        its domain; no period-boundary state repeats within ``max_periods`` periods (e.g. an
        accumulation, Sect. 7.3, or a chaotic motion); the orbit grazes (a stick or reversal
        with x'' = 0 before it, a zone boundary crossed at x' = 0), so that the monodromy
        matrix does not exist; or the matrix is not finite.
    KernelError
        If numba is missing or cannot compile the kernel ("saltation", "numeric", or a
        periodic motion that is simulated); a RuntimeError.

    See Also
    --------
    steady_state : The steady state whose stability this is.
    lyapunov_trace : Convergence of the velocity in the time domain (Sect. 6.2).

    Examples
    --------
    A slip-slip profile of Fig. 9 (case 4): lambda2 = c4 (eq. 33), three ways.

    >>> import selfalign as sa
    >>> profile = sa.ThreePhaseProfile(dt=1.0, dy=0.084, y2=1.4, y3=1.3)
    >>> analytic = sa.floquet(profile)
    >>> analytic.multipliers.round(6).tolist(), analytic.motion.source
    ([1.0, 0.021739], 'closed form')
    >>> analytic.monodromy.round(6).tolist()
    [[1.0, 0.168454], [0.0, 0.021739]]
    >>> sa.floquet(profile, method="saltation").multipliers.round(6).tolist()
    [1.0, 0.021739]
    >>> sa.floquet(profile, method="numeric", solver="moreau", h=1e-3).multipliers.round(6).tolist()
    [1.0, 0.023717]
    """
    opts = _check_options(method, options)
    profile, surface, _, _, phase = _system(profile_or_scene)
    if method == "analytic" and not _closed_form_applies(profile, surface, phase):
        raise ValueError("method='analytic' needs a ThreePhaseProfile on a uniform surface at phase 0 "
                         "(Sect. 6.1); use method='saltation' or 'numeric'")
    motion = periodic_motion(profile_or_scene, opts.get("max_periods", 10_000))
    m, info = {"analytic": _analytic, "saltation": _saltation, "numeric": _numeric}[method](motion, opts)
    if not np.all(np.isfinite(m)):
        raise ValueError(f"method={method!r}: non-finite monodromy matrix {m.tolist()} "
                         "(infeasible profile or a failed simulation)")
    w, vec = eigen(m)
    return FloquetResult(method, m, w, vec, motion, info)


def multiplier_distance(a, b) -> float:
    """max |a_i - b_i| of two multiplier vectors sorted as :func:`eigen` sorts them."""
    return float(np.max(np.abs(np.asarray(a) - np.asarray(b))))


def moreau_monodromies(profiles, v0s, steps: int):
    """Numeric (Moreau) monodromies of many three-phase steady states (uniform surface,
    start at t = 0) in one batched run, eps = sqrt(h) as in :func:`floquet`."""
    h = np.array([p.dt / steps for p in profiles])
    eps = np.sqrt(h)
    xs = np.stack([eps, -eps, 0 * eps, 0 * eps], axis=1)                 # x0 = 0
    vs = np.stack([v0s, v0s, v0s + eps, v0s - eps], axis=1)
    res = simulate_batch(profiles, xs.ravel(), vs.ravel(), profile_index=np.repeat(np.arange(len(profiles)), 4),
                         until="periods", periods=1, method="moreau", steps_per_period=int(steps),
                         fast_forward=False)
    p = np.stack([res.x_end, res.v_end], axis=1).reshape(len(profiles), 4, 2)
    dx = xs[:, 0] - xs[:, 1]
    dv = (vs[:, 2] - v0s) - (vs[:, 3] - v0s)
    return np.stack([(p[:, 0] - p[:, 1]) / dx[:, None], (p[:, 2] - p[:, 3]) / dv[:, None]], axis=2)
