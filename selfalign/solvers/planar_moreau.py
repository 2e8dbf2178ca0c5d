"""Moreau's midpoint time-stepping in the plane (the paper's Sect. 4.1 method with the friction disc;
docs/explanation/planar-model.md).

One step of size h = dt / N from (x, v) at time t_k (x, v in R^2):

    x_M     = x + h/2 v                                   (midpoint)
    b       = v - (Y'(t_k + h) - Y'(t_k))                 (the free velocity: the table's exact impulse)
    v_new   = b - h mu_bar(x_M) s,   s in Sign2(v_new)    (implicit friction in the unit disc)
    x_new   = x_M + h/2 v_new

The implicit friction step has the exact solution v_new = b - h mu_bar b / |b| where |b| > h mu_bar and
v_new = 0 otherwise: the projection of b onto the disc of radius h mu_bar subtracted from it (the 2-D soft
threshold).  With b along one axis it is, operation for operation, the 1-D scheme's soft threshold, so a
table moving along the first axis gives the 1-D Moreau result (:mod:`selfalign.solvers.moreau`).  Under
static/kinetic friction (r = mu_s / mu_k > 1) a part that is stuck or comes to rest (b . v <= 0) sticks
while |b| <= r h mu_bar, as in 1-D.

The table impulses of one period are integrated exactly per axis (:func:`~selfalign.solvers.moreau.table_impulses`)
and turned by the profile's angle.  While v = 0 a step is the identity as long as |impulse| <= r h mu_bar(x),
so those steps are skipped, bit for bit the result of taking them.  The scheme is first order in h; it has
no event location, so its events are counted at step ends (a stick: v becomes 0; a slip start: v leaves 0),
and it has no event log.  REST: stuck where the scheme sticks for good, r h mu_bar >= the largest |impulse|
of the period.  Dense output is the state at the step nearest each sample time.
"""

from __future__ import annotations

import functools
import math

import numpy as np

from ..model.planar import planar_coefficient, strip_rows
from .engine.codes import REASON_MAX_PERIODS, REASON_NONFINITE, REASON_PERIODS, REASON_REST
from .moreau import check_swing_seen, moreau_step, table_impulses
from .outcomes import Reason
from .planar import PLANAR_SAMPLE_DTYPE, PlanarResult


def planar_impulses(profile, phase: float, n: int, h: float) -> np.ndarray:
    """The table's impulse Y'(t_k + h) - Y'(t_k) of each of the N steps of one period from ``phase`` dt, shape
    (N, 2): each component's 1-D impulses (the y component's phase shifted by its lag), turned by the angle."""
    first = table_impulses(profile.x, phase, n, h)
    second = np.zeros(n) if profile.y is None else table_impulses(profile.y, (phase - profile.offset) % 1.0, n, h)
    for component, impulse in ((profile.x, first), (profile.y, second)):
        if component is not None:
            check_swing_seen(component, n, impulse)
    r = profile.matrix
    return np.stack([first * r[0, 0] + second * r[0, 1], first * r[1, 0] + second * r[1, 1]], axis=1)


def run(scene, options: dict) -> PlanarResult:
    """Simulate the planar ``scene`` by Moreau time-stepping with the resolved ``options`` (``h`` or
    ``steps_per_period``); module docstring."""
    n, h = moreau_step(scene.profile.dt, options)
    impulse = planar_impulses(scene.profile, scene.phase, n, h)
    ratio = scene.friction.ratio if scene.friction.kind == "static_kinetic" else 1.0
    periods = scene.horizon_periods
    record = scene.record.dense
    spp = scene.record.samples_per_period
    sample_step = np.zeros(0, dtype=np.int64)
    if record:
        k = np.arange(periods * spp + 1)
        sample_step = np.minimum(np.round((k // spp) * n + (k % spp) * (n / spp)), periods * n).astype(np.int64)
    out = np.zeros((sample_step.size, 5))
    state = np.array([*scene.x0, *scene.v0])
    counts = np.zeros(4, dtype=np.int64)
    reason = _stepper()(state, impulse, h, ratio, strip_rows(scene.strips), periods, scene.until == "rest",
                        sample_step, out, counts)
    t0 = scene.phase * scene.profile.dt
    t_end = t0 + counts[3] * h
    samples = None
    if record:
        samples = np.zeros(sample_step.size, dtype=PLANAR_SAMPLE_DTYPE)
        samples["t"] = t0 + sample_step * h
        samples["x"], samples["v"] = out[:, 0:2], out[:, 2:4]
        samples["mode"] = out[:, 4]
        samples = samples[sample_step <= counts[3]]
    message = "" if reason != REASON_NONFINITE else (
        f"the state stopped being finite at t = {t_end:.6g}; the last finite state is kept")
    return PlanarResult(t_end=t_end, x_end=state[:2].copy(), v_end=state[2:].copy(), reason=Reason(reason),
                        message=message, sticks=int(counts[0]), slips=int(counts[1]), steps=int(counts[2]),
                        samples=samples)


def _advance(state, impulse, h, ratio, rows, periods, until_rest, sample_step, out, counts):
    """Moreau steps of the planar part in place (module docstring): ``state`` = (x, y, vx, vy), ``impulse`` the
    (N, 2) table impulses of one period, ``rows`` the strips; ``sample_step`` the steps whose states go into
    ``out`` (x, y, vx, vy, mode).  ``counts`` receives sticks, slips, steps taken and the step index reached.
    Returns the reason code."""
    n = impulse.shape[0]
    total = periods * n
    half = 0.5 * h
    largest = 0.0
    for k in range(n):
        largest = max(largest, math.hypot(impulse[k, 0], impulse[k, 1]))
    px, py, vx, vy = state[0], state[1], state[2], state[3]
    step = 0
    nxt = 0
    reason = REASON_PERIODS if not until_rest else REASON_MAX_PERIODS
    while True:
        while nxt < sample_step.size and sample_step[nxt] == step:
            out[nxt, 0], out[nxt, 1], out[nxt, 2], out[nxt, 3] = px, py, vx, vy
            out[nxt, 4] = 0.0 if vx == 0.0 and vy == 0.0 else 1.0
            nxt += 1
        if step == total:
            break
        if vx == 0.0 and vy == 0.0:
            hold = h * ratio * planar_coefficient(px, py, rows)
            if until_rest and hold >= largest:
                reason = REASON_REST
                break
            # Stuck: skip the steps whose impulse stays in the stick disc (each an identity).
            k = step % n
            while step < total and math.hypot(impulse[k, 0], impulse[k, 1]) <= hold:
                step += 1
                k += 1
                if k == n:
                    k = 0
                while nxt < sample_step.size and sample_step[nxt] == step:
                    out[nxt, 0], out[nxt, 1], out[nxt, 2], out[nxt, 3], out[nxt, 4] = px, py, 0.0, 0.0, 0.0
                    nxt += 1
            if step == total:
                break
        k = step % n
        mx, my = px + half * vx, py + half * vy
        bound = h * planar_coefficient(mx, my, rows)
        bx, by = vx - impulse[k, 0], vy - impulse[k, 1]
        size = math.hypot(bx, by)
        moving = vx != 0.0 or vy != 0.0
        if size <= bound or ratio > 1.0 and bx * vx + by * vy <= 0.0 and size <= ratio * bound:
            ux, uy = 0.0, 0.0
        else:
            ux, uy = bx - bound * (bx / size), by - bound * (by / size)
        if moving and ux == 0.0 and uy == 0.0:
            counts[0] += 1
        elif not moving and (ux != 0.0 or uy != 0.0):
            counts[1] += 1
        nx, ny = mx + half * ux, my + half * uy
        if not (math.isfinite(nx) and math.isfinite(ny) and math.isfinite(ux) and math.isfinite(uy)):
            reason = REASON_NONFINITE
            break
        px, py, vx, vy = nx, ny, ux, uy
        counts[2] += 1
        step += 1
    state[0], state[1], state[2], state[3] = px, py, vx, vy
    counts[3] = step
    return reason


@functools.cache
def _stepper():
    """:func:`_advance` compiled (:func:`selfalign.solvers.jit.compile_stepper`)."""
    from .jit import compile_stepper

    return compile_stepper(_advance, "the planar Moreau stepper")
