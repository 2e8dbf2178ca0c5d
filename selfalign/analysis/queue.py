"""A queue of parts at the stop zone: where several parts that arrive one after another come to rest
(the paper's Sect. 8, recommendation 5, on the stop zone of Sect. 7).

N equal-width parts (the zone's body width w, eq. 7) walk forward on the uniform surface, the front-most
part ``distance`` before x_mu and each of the others ``spacing`` behind its neighbour at t = 0 (a stagger
in time tau is the spacing vbar tau).  They meet, push and hit each other (Newton's law with restitution
e, docs/explanation/several-parts.md) and queue in the zone.  A queue is simulated with the exact solver
of several parts (:func:`~selfalign.solvers.parts_exact.simulate_parts`) one period at a time, each period
starting from the end state of the last (every period starts at phase 0 of the profile, so this is the
same motion), which records the positions at every period's end, until every part sticks for good
(``rest``), the positions repeat from period to period within ``settle`` (``settled``: a part that keeps
tapping against its stuck neighbour in a small cycle, which the model does not call rest), or
``max_periods`` (``horizon``).

The references a queue is compared with:

* the single-part rest position: one part from the front part's start, simulated (:func:`single_rest`);
  on the Fig. 18 setting it ends past x_stick_min (eq. 41), where its entry phase takes it;
* the pooled rest (:func:`pooled_rest`): the smallest front position at which N touching parts can rest,
  where the mass-weighted mean of k_i mu_bar_i over the cluster reaches max|y''| (the rest condition of a
  pushed cluster, docs/explanation/several-parts.md).  For N equal parts (k = 1) in the zone its front
  lies at x_mu + N (x_stick_min - x_mu): N w (max|y''| - 1) / (c_mu - 1), since exactly one part is in
  its transition at a time and the coefficients over the cluster add up to N + (c_mu - 1)(x - x_mu) / w.

:func:`queue_study` runs a grid of spacing x e x friction-factor spread x N.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from ..model.errors import check_finite, check_integer, check_positive, check_real
from ..model.friction import StopZone, coefficient
from ..model.parts import Part, check_restitution
from ..model.profiles import PiecewiseConstantProfile
from ..solvers.parts_exact import simulate_parts

#: Queue statuses and their codes in result files.
STATUSES = ("rest", "settled", "horizon", "error")
#: The front part counts as at the single-part position within this many widths: 1e-9 w, a thousand
#: times the 1e-12 to which one part of a queue reproduces the single part (tests/test_queue.py) and far
#: below any positioning tolerance of a feeder.
AT_SINGLE_WIDTHS = 1e-9
#: Bisection steps of :func:`pooled_rest` (the bracket of N + 1 widths halves to rounding).
POOLED_STEPS = 200


#: The events per part a queue run keeps for every period (:attr:`QueueRun.part_events`), in this order.
QUEUE_EVENTS = ("sticks", "slips", "impacts", "openings", "crossings")


def _check_setting(profile, zone):
    if not isinstance(profile, PiecewiseConstantProfile):
        raise TypeError(f"profile must be a PiecewiseConstantProfile (e.g. a ThreePhaseProfile), got "
                        f"{type(profile).__name__}")
    if not isinstance(zone, StopZone):
        raise TypeError(f"zone must be a StopZone, got {type(zone).__name__}")
    peak = profile.max_abs_acceleration
    if not 1.0 < peak <= zone.c_mu:
        raise ValueError(f"a queue needs 1 < max|y''| <= c_mu (a part walks on the uniform surface and can rest "
                         f"in the zone, eq. 41), got max|y''| = {peak!r} and c_mu = {zone.c_mu!r}")
    return peak


def _factors(name, values, n) -> np.ndarray:
    if values is None:
        return np.ones(n)
    out = np.asarray(values, dtype=float)
    if out.shape != (n,) or not np.all(np.isfinite(out)) or np.any(out <= 0):
        raise ValueError(f"{name} must be {n} finite numbers > 0 (one per part, rear-most first), got {values!r}")
    return out


def queue_parts(n: int, zone: StopZone, *, distance: float, spacing: float, friction_factors=None,
                masses=None) -> tuple[Part, ...]:
    """The parts of a queue at t = 0, at rest, rear-most first.

    Parameters
    ----------
    n : int
        The number of parts N >= 1.
    zone : StopZone
        The stop zone; every part is ``zone.w`` wide (eq. 7).
    distance : float
        x_mu minus the front part's front at t = 0, > 0.
    spacing : float
        The gap between neighbours at t = 0, >= 0 (0: touching).
    friction_factors, masses : sequence of float, optional
        k_i and m_i per part, rear-most first; default 1 each.

    Returns
    -------
    tuple of Part
        N parts, the front-most last.

    Raises
    ------
    TypeError
        If ``zone`` is not a StopZone or a number is not real.
    ValueError
        If ``n`` < 1, ``distance`` <= 0, ``spacing`` < 0, or a factor or mass list is not N positive numbers.

    Examples
    --------
    >>> import selfalign as sa
    >>> from selfalign.analysis.queue import queue_parts
    >>> parts = queue_parts(3, sa.StopZone(x_mu=0.5, w=0.05, c_mu=2.5), distance=0.25, spacing=0.1)
    >>> [round(p.x0, 6) for p in parts], parts[0].width
    ([-0.05, 0.1, 0.25], 0.05)
    """
    if not isinstance(zone, StopZone):
        raise TypeError(f"zone must be a StopZone, got {type(zone).__name__}")
    n = check_integer("n", n)
    distance = check_positive("distance", distance)
    if check_finite("spacing", spacing) < 0.0:
        raise ValueError(f"spacing must be >= 0 (the gap between neighbours), got {spacing!r}")
    k, m = _factors("friction_factors", friction_factors, n), _factors("masses", masses, n)
    front = zone.x_mu - distance
    return tuple(Part(front - (n - 1 - i) * (zone.w + spacing), width=zone.w, mass=float(m[i]),
                      friction_factor=float(k[i])) for i in range(n))


def pooled_rest(profile: PiecewiseConstantProfile, zone: StopZone, friction_factors, masses=None) -> np.ndarray:
    """Where N touching parts pushed into the zone can first rest: the smallest front position at which the
    mass-weighted mean of k_i mu_bar_i over the cluster reaches max|y''|.

    The cluster's parts are ``zone.w`` wide and touch, so part i's front is the front part's minus
    (N - 1 - i) w.  The mean is nondecreasing in the front position; it is found by bisection to rounding.

    Parameters
    ----------
    profile : PiecewiseConstantProfile
        The table motion (its max|y''|).
    zone : StopZone
        The stop zone.
    friction_factors : sequence of float
        k_i, rear-most first.
    masses : sequence of float, optional
        m_i, rear-most first; default 1 each.

    Returns
    -------
    numpy.ndarray
        The fronts of the parts at the pooled rest, shape (N,), rear-most first.

    Raises
    ------
    TypeError
        If ``profile`` is not a PiecewiseConstantProfile or ``zone`` not a StopZone.
    ValueError
        If max|y''| is not in (1, c_mu], a factor or mass is not positive, or no position holds the cluster
        (the mean of k_i c_mu stays below max|y''|).

    Examples
    --------
    Two equal parts on the Fig. 18 setting: the front one 2 (x_stick_min - x_mu) = 0.08 into the zone.

    >>> import selfalign as sa
    >>> from selfalign.analysis.queue import pooled_rest
    >>> profile = sa.ThreePhaseProfile(dt=1.05, dy=0.084, y2=2.2, y3=0.9)
    >>> pooled_rest(profile, sa.StopZone(x_mu=0.5, w=0.05, c_mu=2.5), [1.0, 1.0]).round(12).tolist()
    [0.53, 0.58]
    """
    peak = _check_setting(profile, zone)
    k = np.asarray(friction_factors, dtype=float)
    n = k.size
    k, m = _factors("friction_factors", k, n), _factors("masses", masses, n)
    offsets = (n - 1 - np.arange(n)) * zone.w

    def deficit(front):
        mu = np.array([coefficient(front - o - zone.x_mu, zone.w, zone.c_mu) for o in offsets])
        return float(np.sum(m * k * mu) / np.sum(m)) - peak

    low, high = zone.x_mu, zone.x_mu + n * zone.w   # the rear part is on the high side at `high`
    if deficit(high) < 0.0:
        raise ValueError(f"no position holds the cluster: the mean of k_i c_mu, {deficit(high) + peak!r}, stays "
                         f"below max|y''| = {peak!r}")
    if deficit(low) >= 0.0:
        high = low
    for _ in range(POOLED_STEPS):
        mid = 0.5 * (low + high)
        if not low < mid < high:
            break
        low, high = (low, mid) if deficit(mid) >= 0.0 else (mid, high)
    return high - offsets


@dataclass(frozen=True)
class QueueRun:
    """A queue simulated until rest, settled or the horizon (:func:`run_queue`).

    Parameters
    ----------
    status, t_end, x_end, v_end, periods, events, t, x, part_events : see Attributes
        As in Attributes.

    Attributes
    ----------
    status : str
        ``"rest"`` (every part sticks for good), ``"settled"`` (the period-end positions repeated within the
        settle tolerance: nothing moves on, though some part keeps a small cycle), ``"horizon"`` or
        ``"error"`` (the solver's message is lost; rerun :func:`simulate_parts` to see it).
    t_end : float
        The time of rest (the last part's last stick), of settling (the end of the first of the periods
        that repeat), or the horizon.
    x_end, v_end : numpy.ndarray
        The fronts and velocities at ``t_end``, shape (N,), rear-most first.
    periods : int
        Whole periods simulated.
    events : int
        The solver's events over all periods.
    t : numpy.ndarray
        The period ends 0, dt, 2 dt, ... simulated, shape (periods + 1,); at rest the last one is ``t_end``.
    x : numpy.ndarray
        The fronts at those times, shape (periods + 1, N).
    part_events : numpy.ndarray
        The events of each part in each period, shape (periods, N, len(:data:`QUEUE_EVENTS`)): the exact
        solver's counts per part (``part_sticks``, ... of :class:`~selfalign.solvers.parts_exact.PartsResult`).

    Examples
    --------
    >>> import selfalign as sa
    >>> from selfalign.analysis.queue import queue_parts, run_queue
    >>> zone = sa.StopZone(x_mu=0.5, w=0.05, c_mu=2.5)
    >>> profile = sa.ThreePhaseProfile(dt=1.05, dy=0.084, y2=2.2, y3=0.9)
    >>> run = run_queue(profile, zone, queue_parts(1, zone, distance=0.25, spacing=0.0), max_periods=100)
    >>> run.status, run.x.shape == (run.periods + 1, 1)
    ('rest', True)
    """

    status: str
    t_end: float
    x_end: np.ndarray
    v_end: np.ndarray
    periods: int
    events: int
    t: np.ndarray
    x: np.ndarray
    part_events: np.ndarray


def run_queue(profile: PiecewiseConstantProfile, zone: StopZone, parts, *, restitution: float = 0.0,
              max_periods: int = 1000, settle: float = 1e-9, settle_periods: int = 10) -> QueueRun:
    """Simulate a queue one period at a time until rest, settled or ``max_periods``.

    Parameters
    ----------
    profile : PiecewiseConstantProfile
        The table motion.
    zone : StopZone
        The stop zone.
    parts : sequence of Part
        The queue at t = 0 (:func:`queue_parts`).
    restitution : float, optional
        Newton's e in [0, 1] between parts.  Default 0.
    max_periods : int, optional
        The horizon in periods.  Default 1000.
    settle : float, optional
        Settled: over ``settle_periods`` periods in a row, no period-end front moves more than ``settle``
        widths.  Default 1e-9.
    settle_periods : int, optional
        See ``settle``.  Default 10.

    Returns
    -------
    QueueRun
        The end state, the period-end samples and the status.

    Raises
    ------
    TypeError
        If ``profile`` or ``zone`` has the wrong type, or the parts are not Parts.
    ValueError
        If max|y''| is not in (1, c_mu], ``restitution`` lies outside [0, 1], ``settle`` <= 0, or a count is < 1.

    Examples
    --------
    Two equal parts a width apart: the rear one pushes the front one on until the pair's mean coefficient
    reaches max|y''| = 2.2 (:func:`pooled_rest`).

    >>> import selfalign as sa
    >>> from selfalign.analysis.queue import queue_parts, run_queue
    >>> zone = sa.StopZone(x_mu=0.5, w=0.05, c_mu=2.5)
    >>> profile = sa.ThreePhaseProfile(dt=1.05, dy=0.084, y2=2.2, y3=0.9)
    >>> run = run_queue(profile, zone, queue_parts(2, zone, distance=0.25, spacing=0.05))
    >>> run.status, run.x_end.round(9).tolist()
    ('settled', [0.53, 0.58])
    """
    _check_setting(profile, zone)
    e = check_restitution(restitution)
    max_periods = check_integer("max_periods", max_periods)
    settle_periods = check_integer("settle_periods", settle_periods)
    settle = check_positive("settle", settle)
    current = tuple(parts)
    xs, events, still, counts = [np.array([p.x0 for p in current])], 0, 0, []
    for period in range(1, max_periods + 1):
        result = simulate_parts(profile, current, surface=zone, restitution=e, periods=1)
        events += result.events
        counts.append(np.stack([getattr(result, "part_" + kind) for kind in QUEUE_EVENTS], axis=1))
        status = result.status.value
        if status != "horizon":
            xs.append(result.x_end.copy())
            t_end = (period - 1) * profile.dt + result.t_end
            return QueueRun("error" if status == "error" else "rest", t_end, result.x_end.copy(),
                            result.v_end.copy(), period, events, np.append(np.arange(period) * profile.dt, t_end),
                            np.array(xs), np.array(counts))
        xs.append(result.x_end.copy())
        still = still + 1 if np.max(np.abs(xs[-1] - xs[-2])) <= settle * zone.w else 0
        if still >= settle_periods:
            return QueueRun("settled", (period - settle_periods) * profile.dt, result.x_end.copy(),
                            result.v_end.copy(), period, events, np.arange(period + 1) * profile.dt, np.array(xs),
                            np.array(counts))
        current = tuple(Part(float(x), float(v), width=p.width, mass=p.mass, friction_factor=p.friction_factor)
                        for x, v, p in zip(result.x_end, result.v_end, current))
    return QueueRun("horizon", max_periods * profile.dt, xs[-1], np.array([p.v0 for p in current]), max_periods,
                    events, np.arange(max_periods + 1) * profile.dt, np.array(xs), np.array(counts))


def single_rest(profile: PiecewiseConstantProfile, zone: StopZone, *, distance: float,
                max_periods: int = 1000, settle: float = 1e-9) -> float:
    """Where one part, at rest ``distance`` before x_mu at t = 0, comes to rest (simulated, as the front part
    of a queue starts).

    Parameters
    ----------
    profile : PiecewiseConstantProfile
        The table motion.
    zone : StopZone
        The stop zone (the part is ``zone.w`` wide).
    distance : float
        x_mu minus the part's front at t = 0.
    max_periods : int, optional
        The horizon.  Default 1000.
    settle : float, optional
        As :func:`run_queue` (a part that accumulates at x_stick_min settles).  Default 1e-9.

    Returns
    -------
    float
        The part's front at rest.

    Raises
    ------
    TypeError, ValueError
        As :func:`run_queue`; ValueError also if the part does not come to rest within ``max_periods``.

    Examples
    --------
    >>> import selfalign as sa
    >>> from selfalign.analysis.queue import single_rest
    >>> profile = sa.ThreePhaseProfile(dt=1.05, dy=0.084, y2=2.2, y3=0.9)
    >>> round(single_rest(profile, sa.StopZone(x_mu=0.5, w=0.05, c_mu=2.5), distance=0.25), 9)
    0.54
    """
    run = run_queue(profile, zone, queue_parts(1, zone, distance=distance, spacing=0.0), max_periods=max_periods,
                    settle=settle)
    if run.status not in ("rest", "settled"):
        raise ValueError(f"one part {distance!r} before the zone does not come to rest within {max_periods} "
                         f"periods (status {run.status!r}): raise max_periods")
    return float(run.x_end[0])


def spread_factors(n: int, spread: float) -> np.ndarray:
    """Friction factors of a queue with a spread: k_i = 1 + spread sin(2.4 i), i = 0 the front-most part,
    a fixed, irregular pattern in [1 - spread, 1 + spread] (1 for the front part, so that the front part is
    the single part of factor 1).

    Parameters
    ----------
    n : int
        The number of parts.
    spread : float
        The half range, in [0, 1).

    Returns
    -------
    numpy.ndarray
        k_i, rear-most first, shape (n,).

    Raises
    ------
    TypeError
        If ``spread`` is not a real number or ``n`` not an integer.
    ValueError
        If ``spread`` is not in [0, 1) or ``n`` < 1.

    Examples
    --------
    >>> from selfalign.analysis.queue import spread_factors
    >>> spread_factors(3, 0.2).round(4).tolist()
    [0.8008, 1.1351, 1.0]
    """
    n = check_integer("n", n)
    if not 0.0 <= check_real("spread", spread) < 1.0:
        raise ValueError(f"spread must be a number in [0, 1) (the half range of the friction factors), got {spread!r}")
    return (1.0 + spread * np.sin(2.4 * np.arange(n)))[::-1]


def queue_study(profile: PiecewiseConstantProfile, zone: StopZone, *, n_max: int, spacings, restitutions,
                spreads, distance: float, max_periods: int = 1000, settle: float = 1e-9,
                settle_periods: int = 10) -> dict:
    """Queues of N = 1..``n_max`` equal-width parts over a grid of spacing x e x friction-factor spread.

    Parameters
    ----------
    profile : PiecewiseConstantProfile
        The table motion.
    zone : StopZone
        The stop zone.
    n_max : int
        The largest queue.
    spacings, restitutions, spreads : sequence of float
        The grid: gaps at t = 0 (>= 0), e in [0, 1], spreads of the friction factors (:func:`spread_factors`).
    distance : float
        x_mu minus the front part's front at t = 0.
    max_periods, settle, settle_periods
        As :func:`run_queue`.

    Returns
    -------
    dict
        ``x_single`` (the single part's rest, :func:`single_rest`), ``tolerance`` (:data:`AT_SINGLE_WIDTHS`
        widths), the axes ``spacing``, ``restitution``, ``spread``, ``n``, and per point (axes in that order,
        the part axis last, NaN beyond N, part 0 the front-most): ``x_end``, ``error`` (x_end - x_single),
        ``pooled`` (:func:`pooled_rest`), ``friction_factor``; per queue: ``status`` (code of
        :data:`STATUSES`), ``t_end``, ``periods``, ``events``, ``front_at_single``, ``in_zone`` (parts
        whose front ends past x_mu), ``front_through`` (the front part ends past x_mu + w, or does not come
        to rest).

    Raises
    ------
    TypeError, ValueError
        As :func:`run_queue` and :func:`queue_parts`; ValueError also if an axis is empty.

    Examples
    --------
    >>> import selfalign as sa
    >>> from selfalign.analysis.queue import queue_study
    >>> profile = sa.ThreePhaseProfile(dt=1.05, dy=0.084, y2=2.2, y3=0.9)
    >>> study = queue_study(profile, sa.StopZone(x_mu=0.5, w=0.05, c_mu=2.5), n_max=2, spacings=[0.05],
    ...                     restitutions=[0.0], spreads=[0.0], distance=0.25)
    >>> study["front_at_single"].ravel().tolist(), study["x_end"][0, 0, 0, 1].round(9).tolist()
    ([True, False], [0.58, 0.53])
    """
    _check_setting(profile, zone)
    n_max = check_integer("n_max", n_max)
    axes = {}
    for name, values in (("spacing", spacings), ("restitution", restitutions), ("spread", spreads)):
        values = np.asarray(values, dtype=float)
        if values.ndim != 1 or values.size == 0:
            raise ValueError(f"{name}s must be a non-empty list of numbers, got {values.tolist()!r}")
        axes[name] = values
    for e in axes["restitution"]:
        check_restitution(float(e))
    x_single = single_rest(profile, zone, distance=distance, max_periods=max_periods, settle=settle)
    shape = (*(a.size for a in axes.values()), n_max)
    per_part = {k: np.full((*shape, n_max), np.nan) for k in ("x_end", "error", "pooled", "friction_factor")}
    per_queue = {"status": np.zeros(shape, np.int64), "t_end": np.zeros(shape), "periods": np.zeros(shape, np.int64),
                 "events": np.zeros(shape, np.int64), "front_at_single": np.zeros(shape, bool),
                 "in_zone": np.zeros(shape, np.int64), "front_through": np.zeros(shape, bool)}
    tolerance = AT_SINGLE_WIDTHS * zone.w
    for (a, spacing), (b, e), (c, spread) in ((ia, ib, ic) for ia in enumerate(axes["spacing"])
                                              for ib in enumerate(axes["restitution"])
                                              for ic in enumerate(axes["spread"])):
        for n in range(1, n_max + 1):
            k = spread_factors(n, float(spread))
            run = run_queue(profile, zone, queue_parts(n, zone, distance=distance, spacing=float(spacing),
                                                       friction_factors=k),
                            restitution=float(e), max_periods=max_periods, settle=settle,
                            settle_periods=settle_periods)
            at = (a, b, c, n - 1)
            front_first = slice(None, None, -1)
            per_part["x_end"][at][:n] = run.x_end[front_first]
            per_part["error"][at][:n] = run.x_end[front_first] - x_single
            per_part["pooled"][at][:n] = pooled_rest(profile, zone, k)[front_first]
            per_part["friction_factor"][at][:n] = k[front_first]
            per_queue["status"][at] = STATUSES.index(run.status)
            per_queue["t_end"][at] = run.t_end
            per_queue["periods"][at] = run.periods
            per_queue["events"][at] = run.events
            per_queue["front_at_single"][at] = abs(run.x_end[-1] - x_single) <= tolerance
            per_queue["in_zone"][at] = int(np.sum(run.x_end > zone.x_mu))
            per_queue["front_through"][at] = run.x_end[-1] > zone.x_mu + zone.w or run.status in ("horizon", "error")
    return {"x_single": x_single, "tolerance": tolerance, **axes, "n": np.arange(1, n_max + 1),
            **per_part, **per_queue}


def aligned_times(run: QueueRun, tolerance: float) -> np.ndarray:
    """For each part, the first period end after which it stays within ``tolerance`` of its end position.

    Parameters
    ----------
    run : QueueRun
        A simulated queue (:func:`run_queue`).
    tolerance : float
        The positioning tolerance, > 0, in the units of the positions.

    Returns
    -------
    numpy.ndarray
        The times, shape (N,), rear-most first: a feeder can take the part from then on.

    Raises
    ------
    TypeError
        If ``run`` is not a QueueRun.
    ValueError
        If ``tolerance`` is not a finite number > 0.

    Examples
    --------
    >>> import selfalign as sa
    >>> from selfalign.analysis.queue import aligned_times, queue_parts, run_queue
    >>> zone = sa.StopZone(x_mu=0.5, w=0.05, c_mu=2.5)
    >>> profile = sa.ThreePhaseProfile(dt=1.05, dy=0.084, y2=2.2, y3=0.9)
    >>> run = run_queue(profile, zone, queue_parts(1, zone, distance=0.25, spacing=0.0))
    >>> aligned_times(run, 0.005).round(2).tolist()
    [5.25]
    """
    if not isinstance(run, QueueRun):
        raise TypeError(f"run must be a QueueRun, got {type(run).__name__}")
    tolerance = check_positive("tolerance", tolerance)
    outside = np.abs(run.x - run.x_end) > tolerance                # (samples, N)
    last_out = np.where(outside.any(axis=0), outside.shape[0] - 1 - np.argmax(outside[::-1], axis=0), -1)
    return run.t[np.minimum(last_out + 1, run.t.size - 1)]
