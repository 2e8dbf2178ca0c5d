"""The exact planar solver on a piecewise-constant table acceleration and a uniform surface (``method="exact"``).

A point part on a table whose acceleration Y''(t) in R^2 is constant on each piece of the period
(:meth:`PlanarProfile.pieces`), uniform friction mu_bar = 1, Coulomb or static/kinetic friction: between events
every slip is the block sliding on an incline with friction, in closed form
(:mod:`selfalign.model.planar_slip`, derived in docs/explanation/planar-model.md), and the events (piece
switches, stops, slip starts from stick, reversals of collinear slips) are located exactly.  The stepping is
compiled (:mod:`selfalign.solvers.engine.planar`, its events and tie rules are documented there); this module
checks the scene, fills the stepper's arrays and builds the :class:`~selfalign.solvers.planar.PlanarResult`.
Scenes on strips and smooth profiles go to the general exact planar solver instead (the dispatch,
:func:`selfalign.solvers.planar.run_planar`).
"""

from __future__ import annotations

import numpy as np

from ..model.planar import PlanarProfile
from .engine import codes as C
from .jit import call, kernel
from .outcomes import STALL_EVENTS, Reason
from .planar import PLANAR_EVENT_DTYPE, PLANAR_SAMPLE_DTYPE, PlanarResult, sample_times

#: Default event budget (the ``max_events`` option of the exact method).
MAX_EVENTS = 10_000_000


def run(scene, options: dict) -> PlanarResult:
    """Simulate the planar ``scene`` exactly, in closed form between events, with the resolved ``options``
    (``max_events``; module docstring).

    Parameters
    ----------
    scene : Scene
        A planar scene (``scene.planar``) with a piecewise-constant :class:`~selfalign.PlanarProfile` on a
        uniform surface, under Coulomb or static/kinetic friction.
    options : dict
        The exact method's options, checked and filled (``selfalign.solvers.methods``): ``max_events``.

    Returns
    -------
    PlanarResult
        The end time and state, the reason, the event counts, the samples and the event log the scene's record
        asks for (``steps`` is 0: there are no time steps).

    Raises
    ------
    ValueError
        If the scene is not planar, its profile is not piecewise constant, its surface has strips or its friction
        law is Stribeck's (the dispatch, :func:`selfalign.solvers.planar.run_planar`, sends those elsewhere).

    Examples
    --------
    The three-phase profile of Fig. 18 along the first axis, from rest: the part walks along it, y stays 0.

    >>> import selfalign as sa
    >>> from selfalign.solvers import planar_exact
    >>> profile = sa.ThreePhaseProfile(dt=1.05, dy=0.084, y2=2.2, y3=0.9)
    >>> scene = sa.Scene(sa.PlanarProfile(x=profile), x0=(0.0, 0.0), periods=3)
    >>> result = planar_exact.run(scene, {"max_events": 1000})
    >>> result.reason.name, result.x_end.round(6).tolist(), result.sticks, result.breaks
    ('PERIODS', [0.196235, 0.0], 3, 8)
    """
    _check(scene)
    profile = scene.profile
    starts, accels = profile.pieces()
    ratio = scene.friction.ratio if scene.friction.kind == "static_kinetic" else 1.0
    record = scene.record
    raw = run_pieces(starts, accels, profile.dt, tau0=scene.phase * profile.dt, x0=scene.x0, v0=scene.v0,
                     ratio=ratio, periods=scene.horizon_periods, until_rest=scene.until == "rest",
                     max_events=int(options["max_events"]),
                     samples_per_period=record.samples_per_period if record.dense else 0, log=record.events)
    samples = log = None
    if raw["samples"] is not None:
        rows = raw["samples"]
        samples = np.zeros(len(rows), dtype=PLANAR_SAMPLE_DTYPE)
        samples["t"] = sample_times(scene)[:len(rows)]
        samples["x"], samples["v"], samples["mode"] = rows[:, 0:2], rows[:, 2:4], rows[:, 4]
    if raw["log"] is not None:
        rows = raw["log"]
        log = np.zeros(len(rows), dtype=PLANAR_EVENT_DTYPE)
        log["t"] = rows[:, 0] * profile.dt + rows[:, 1]
        log["kind"], log["x"], log["v"] = rows[:, 2], rows[:, 3:5], rows[:, 5:7]
    return PlanarResult(t_end=raw["period_end"] * profile.dt + raw["tau_end"], x_end=raw["x_end"],
                        v_end=raw["v_end"], reason=raw["reason"], message=raw["message"], sticks=raw["sticks"],
                        slips=raw["slips"], breaks=raw["breaks"], samples=samples, log=log)


def _check(scene) -> None:
    """ValueError unless this solver takes ``scene`` (:func:`run`)."""
    if not getattr(scene, "planar", False) or not isinstance(scene.profile, PlanarProfile):
        raise ValueError("scene must be a planar scene (a PlanarProfile): the exact planar solver simulates planar "
                         "motion only")
    if not scene.profile.piecewise_constant:
        raise ValueError("scene.profile must be piecewise constant in both components for the closed-form planar "
                         "solver; the general exact planar solver takes the others")
    if scene.strips:
        raise ValueError(f"scene.surface must be uniform for the closed-form planar solver, got {len(scene.strips)} "
                         "strip(s); the general exact planar solver takes strips")
    if scene.friction.kind not in ("coulomb", "static_kinetic"):
        raise ValueError(f"scene.friction.kind must be coulomb or static_kinetic for planar motion, got "
                         f"{scene.friction.kind!r}")


def _stepper_arrays(starts, accels, dt: float, tau0: float, x0, v0, ratio: float) -> tuple:
    """(f, c, starts, accels): the stepper's float state and counters (:mod:`selfalign.solvers.engine.codes`,
    ``PL_*`` and ``PC_*``) for a start at ``x0``, ``v0`` (positions relative to x0) at phase ``tau0``, and the
    pieces as contiguous float arrays."""
    starts = np.ascontiguousarray(starts, dtype=float)
    accels = np.ascontiguousarray(accels, dtype=float).reshape(-1, 2)
    f = np.zeros(C.PLANAR_FLOATS)
    f[C.PL_VX], f[C.PL_VY] = float(v0[0]), float(v0[1])
    f[C.PL_DT], f[C.PL_TAU0], f[C.PL_MU], f[C.PL_RATIO] = dt, tau0, 1.0, ratio
    f[C.PL_REST] = float(np.max(np.hypot(accels[:, 0], accels[:, 1])))
    return f, np.zeros(C.PLANAR_COUNTERS, dtype=np.int64), starts, accels


def run_pieces(starts, accels, dt: float, *, tau0: float = 0.0, x0=(0.0, 0.0), v0=(0.0, 0.0), ratio: float = 1.0,
               periods: int, until_rest: bool = False, max_events: int = MAX_EVENTS, samples_per_period: int = 0,
               log: bool = False) -> dict:
    """Run the compiled stepper on the pieces of one period and return its raw outcome (what :func:`run` turns
    into a :class:`~selfalign.solvers.planar.PlanarResult`; benchmarks call it directly).

    Parameters
    ----------
    starts : array_like
        Start times of the pieces of one period, shape (m,), from 0 and increasing (the last piece ends at dt).
    accels : array_like
        The constant table acceleration Y'' of each piece, shape (m, 2).
    dt : float
        The period.
    tau0 : float, optional
        The start phase, in [0, dt).  Default 0.
    x0, v0 : pair of float, optional
        The start position and velocity relative to the table.  Default (0, 0).
    ratio : float, optional
        r = mu_s / mu_k of static/kinetic friction (1: Coulomb).  Default 1.
    periods : int
        The horizon in periods.  Keyword only, required.
    until_rest : bool, optional
        End at a stick that holds for good (REST) instead of running on.  Default False.
    max_events : int, optional
        The event budget.
    samples_per_period : int, optional
        Samples per period (0: none).  Default 0.
    log : bool, optional
        Keep the event log.  Default False.

    Returns
    -------
    dict
        ``reason`` (:class:`~selfalign.solvers.outcomes.Reason`), ``period_end``, ``tau_end`` (the end time is
        period_end dt + tau_end), ``x_end``, ``v_end`` (arrays (2,)), ``mode`` (0 stick, 1 slip), the counts
        ``sticks``, ``slips``, ``reversals``, ``breaks``, ``arcs`` (closed-form arcs) and ``events`` (all of
        them, as the budget counts), ``samples`` (array (K, 5): x, y, vx, vy, mode at tau0 + k dt /
        samples_per_period, or None), ``log`` (array (E, 7): period, phase, kind, x, y, vx, vy, or None) and
        ``message``.

    Raises
    ------
    selfalign.KernelError
        If the compiled stepper cannot be compiled.

    Examples
    --------
    Y'' = (-2, 0) then (2, 0): from rest the part slips along +x accelerating at 1 for half a period, then
    decelerates at 3, reverses at t = 2/3 (2 > mu) and slips back accelerating at 1.

    >>> from selfalign.solvers.planar_exact import run_pieces
    >>> out = run_pieces([0.0, 0.5], [[-2.0, 0.0], [2.0, 0.0]], 1.0, periods=1)
    >>> out["reason"].name, round(float(out["x_end"][0]), 12), out["v_end"].round(12).tolist(), out["reversals"]
    ('PERIODS', 0.111111111111, [-0.333333333333, 0.0], 1)
    """
    x0 = np.asarray(x0, dtype=float)
    f, c, starts, accels = _stepper_arrays(starts, accels, dt, tau0, x0, v0, ratio)
    spp = int(samples_per_period)
    samples = np.zeros((periods * spp + 1 if spp else 0, C.PLANAR_SAMPLE_COLUMNS))
    size = min(max_events, 4 * (starts.size + 1) * min(periods, 1000) + 16) if log else 0
    while True:
        entries = np.zeros((size, C.PLANAR_LOG_COLUMNS))
        state, counters = f.copy(), c.copy()
        reason = call(kernel().planar_run, state, counters, starts, accels, int(periods), bool(until_rest),
                      int(max_events), spp, samples, entries)
        if counters[C.PC_LOG] <= size:
            break
        size = int(counters[C.PC_LOG])
    written = int(counters[C.PC_SAMPLES])
    if reason == C.REASON_NONFINITE:           # the samples up to the start of the period that failed
        written = min(written, int(counters[C.PC_N_END]) * spp + 1)
    return {"reason": Reason(int(reason)), "period_end": int(counters[C.PC_N_END]),
            "tau_end": float(state[C.PL_TAU_END]), "x_end": state[[C.PL_X, C.PL_Y]] + x0,
            "v_end": state[[C.PL_VX, C.PL_VY]].copy(), "mode": int(counters[C.PC_MODE]),
            "sticks": int(counters[C.PC_STICKS]), "slips": int(counters[C.PC_SLIPS]),
            "reversals": int(counters[C.PC_REVERSALS]), "breaks": int(counters[C.PC_BREAKS]),
            "arcs": int(counters[C.PC_ARCS]), "events": int(counters[C.PC_EVENTS]),
            "samples": _shifted(samples[:written], x0) if spp else None,
            "log": _shifted(entries[:counters[C.PC_LOG]], x0, column=3) if log else None,
            "message": _message(Reason(int(reason)), max_events, counters, state, dt)}


def _shifted(rows: np.ndarray, x0: np.ndarray, column: int = 0) -> np.ndarray:
    """``rows`` with the positions (columns ``column``, ``column + 1``) made absolute."""
    rows = rows.copy()
    rows[:, column:column + 2] += x0
    return rows


def _message(reason: Reason, max_events: int, counters, state, dt: float) -> str:
    t = float(counters[C.PC_N_END] * dt + state[C.PL_TAU_END])
    if reason is Reason.MAX_EVENTS:
        return f"max_events = {max_events} reached at t = {t!r}; raise max_events"
    if reason is Reason.STALL:
        return f"more than {STALL_EVENTS} events of zero length in a row at t = {t!r}"
    if reason is Reason.NONFINITE:
        return (f"non-finite state in the period from t = {t!r} (the arithmetic overflows at these scales); the "
                f"state at its start is kept")
    if reason is Reason.REST:
        return (f"at rest for good: stuck where r mu_bar = {float(state[C.PL_RATIO] * state[C.PL_MU])!r} >= "
                f"max|Y''| = {float(state[C.PL_REST])!r}")
    return ""
