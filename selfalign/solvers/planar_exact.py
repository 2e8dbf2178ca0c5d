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

from .engine import codes as C
from .jit import call, kernel
from .outcomes import STALL_EVENTS, Reason

#: Default event budget (the ``max_events`` option of the exact method).
MAX_EVENTS = 10_000_000


def stepper_arrays(starts, accels, dt: float, tau0: float, x0, v0, ratio: float) -> tuple:
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
    """Run the compiled stepper on the pieces of one period (``starts`` (m,) from 0, ``accels`` (m, 2)) and
    return its raw outcome: ``reason``, ``period_end``, ``tau_end``, ``x_end``, ``v_end`` (arrays (2,)),
    ``mode``, the counts (``sticks``, ``slips``, ``reversals``, ``breaks``, ``arcs``, ``events``), ``samples``
    (array (K, 5): x, y, vx, vy, mode at tau0 + k dt / samples_per_period; None without samples) and ``log``
    (array (E, 7): period, phase, kind, x, y, vx, vy; None without the log)."""
    x0 = np.asarray(x0, dtype=float)
    f, c, starts, accels = stepper_arrays(starts, accels, dt, tau0, x0, v0, ratio)
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
    return {"reason": Reason(int(reason)), "period_end": int(counters[C.PC_N_END]),
            "tau_end": float(state[C.PL_TAU_END]), "x_end": state[[C.PL_X, C.PL_Y]] + x0,
            "v_end": state[[C.PL_VX, C.PL_VY]].copy(), "mode": int(counters[C.PC_MODE]),
            "sticks": int(counters[C.PC_STICKS]), "slips": int(counters[C.PC_SLIPS]),
            "reversals": int(counters[C.PC_REVERSALS]), "breaks": int(counters[C.PC_BREAKS]),
            "arcs": int(counters[C.PC_ARCS]), "events": int(counters[C.PC_EVENTS]),
            "samples": _shifted(samples[:counters[C.PC_SAMPLES]], x0) if spp else None,
            "log": _shifted(entries[:counters[C.PC_LOG]], x0, column=3) if log else None,
            "message": _message(Reason(int(reason)), max_events, counters, state, dt)}


def _shifted(rows: np.ndarray, x0: np.ndarray, column: int = 0) -> np.ndarray:
    """``rows`` with the positions (columns ``column``, ``column + 1``) made absolute."""
    rows = rows.copy()
    rows[:, column:column + 2] += x0
    return rows


def _message(reason: Reason, max_events: int, counters, state, dt: float) -> str:
    t = counters[C.PC_N_END] * dt + state[C.PL_TAU_END]
    if reason is Reason.MAX_EVENTS:
        return f"max_events = {max_events} reached at t = {t!r}; raise max_events"
    if reason is Reason.STALL:
        return f"more than {STALL_EVENTS} events of zero length in a row at t = {t!r}"
    if reason is Reason.NONFINITE:
        return (f"non-finite state in the period from t = {t!r} (the arithmetic overflows at these scales); the "
                f"state at its start is kept")
    if reason is Reason.REST:
        return (f"at rest for good: stuck where r mu_bar = {state[C.PL_RATIO] * state[C.PL_MU]!r} >= max|Y''| = "
                f"{state[C.PL_REST]!r}")
    return ""
