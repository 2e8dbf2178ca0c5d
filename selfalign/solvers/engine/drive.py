"""The driver: one loop for every stepper and every member.  It owns the horizon, the outcome
decisions (REST, ACCUMULATION, NEVER_STOPS, HORIZON, ERROR) and the fast-forward of repeating
periods; a stepper advances one member by whole periods (the contract: :mod:`selfalign.solvers.engine`).
"""

from __future__ import annotations

import math

from numba import literally, types
from numba.core import errors
from numba.extending import overload

from ...model import friction as F
from .. import records as R
from ..outcomes import ACC_TOL_ULPS, HIGH, LOW, MOTION_FACTOR, NEAR_ULPS
from .codes import (
    ARC_STICK,
    DONE,
    EPS,
    INF,
    LARGEST,
    NAN,
    REASON_ACCUMULATION,
    REASON_BOUNDED,
    REASON_FIRST_STICK,
    REASON_MAX_EVENTS,
    REASON_MAX_PERIODS,
    REASON_NONFINITE,
    REASON_PERIODIC,
    REASON_PERIODS,
    REASON_REST,
    REASON_STALL,
    REASON_WALK_BACKWARD,
    REASON_WALK_FORWARD,
    STOP_ACCUMULATION,
    STOP_BUDGET,
    STOP_FIRST_STICK,
    STOP_NONFINITE,
    STOP_REST,
    STOP_STALL,
)
from .compiled import OPTIONS, borrowed_all, inlined, jit
from .field import friction_at, holds_for_good, record_crossings, stop_nonfinite
from .jerk_zone import period_jerk_zone
from .piecewise import period_piecewise, period_piecewise_called, piece_at
from .recording import record_sample
from .smooth import grid_scratch, period_smooth, smooth_grid
from .timestepping import period_moreau


@jit
def prepare_member(s, row, method, acc_tol):
    """Derived constants of a member and its state at the run start (n = 0, time tau0)."""
    s.b1 = F.transition_slope(s.c_mu, s.w) if s.zone else 0.0
    s.omega = math.sqrt(s.b1)
    s.rest_acc = row[R.REST_ACC]
    s.xs = F.static_stick_limit(row[R.REST_ACC], s.static_ratio, s.w, s.c_mu) if s.zone else INF
    s.acc_tol = max(acc_tol, ACC_TOL_ULPS * EPS * s.w) if s.zone else acc_tol
    s.n, s.fresh, s.events, s.steps = 0, True, 0, 0
    s.sticks, s.zone_sticks, s.nh = 0, 0, 0
    s.h1, s.h2 = NAN, NAN
    s.first_stick_xi, s.first_stick_n, s.first_stick_tau = NAN, -1, NAN
    s.at_rest = False
    s.xi_max, s.path, s.fast_forward = s.xi, 0.0, 0
    s.n_arcs, s.n_events, s.n_samples = 0, 0, 0
    s.fp_iterations, s.fp_unconverged, s.fp_max_change = 0, 0, 0.0
    s.contraction, s.advance, s.cycle, s.cycle_region, s.last_stick = NAN, NAN, 0, -1, NAN
    s.stop_n, s.stop_tau = 0, s.tau0
    s.dxp, s.lo, s.hi, s.regions = 0.0, 0.0, 0.0, 0


@jit
def start_mode(s, a, until, moreau, holds_scale):
    """The mode at the start under table acceleration ``a``: the sign of v0, or at v0 = 0
    the stick/slip decision (Moreau: stuck until a step says otherwise); REST if stuck for
    good (Moreau: ``holds_scale`` = (h, largest |impulse|), the step's test).  No stick
    event is counted for the initial state."""
    if s.v != 0.0:
        s.mode = 1 if s.v > 0.0 else -1
        return DONE
    mu = friction_at(s, s.zone, s.xi)
    s.mode = 0 if moreau else F.decide_mode(a, s.static_ratio * mu)
    holds = holds_scale[0] * mu * s.static_ratio >= holds_scale[1] if moreau else holds_for_good(s, mu)
    if s.mode == 0 and holds:
        s.at_rest = True
        if until != R.UNTIL_PERIODS:
            s.stop_n, s.stop_tau = 0, s.tau0
            return STOP_REST
    return DONE


@jit
def _region_of_mask(regions):
    if regions == 1 << LOW:
        return LOW
    if regions == 1 << HIGH:
        return HIGH
    return -1


@jit
def _cycles(s, hist, count, max_cycle, near, swing):
    """The shortest k-period cycles ending now, in one pass over the history:
    (k, region, k_near, region_near), k = 0 where there is none.

    k: a bit-exact repeat, of (v, mode) when all k periods stayed in one region of
    constant friction (translation invariance: region >= 0, the mass may have moved), else
    of (x, v, mode) (region -1).  k_near (only if ``near``, and only one shorter than k): a
    near repeat (see NEAR_ULPS, MOTION_FACTOR).  :func:`_cycle_span` gives a cycle's advance.
    ``hist`` is a ring of the last ``max_cycle`` periods, the newest at (count - 1) mod max_cycle.
    """
    tol_x = NEAR_ULPS * EPS * (abs(s.xi) + (s.w if s.zone else 0.0))
    tol_v = NEAR_ULPS * EPS * (abs(s.v) + swing)
    last = (count - 1) % max_cycle
    idx = last + 1
    region = -1
    k_near = 0
    region_near = -1
    for k in range(1, min(count, max_cycle) + 1):
        idx -= 1                      # the period that started k periods ago
        if idx < 0:
            idx += max_cycle
        h = hist[idx]
        # The region all of the last k periods stayed in (-1: none), kept up as k grows.
        if k == 1:
            region = _region_of_mask(h.regions)
        elif _region_of_mask(h.regions) != region:
            region = -1
        if h.mode != s.mode:
            continue
        dv = abs(h.v - s.v)
        dx = abs(h.xi - s.xi)
        if dv == 0.0 and (region >= 0 or dx == 0.0):
            return k, region, k_near, region_near
        if near and k_near == 0 and dv <= tol_v and (
                region >= 0 or dx <= tol_x and s.path - h.path > MOTION_FACTOR * tol_x):
            k_near, region_near = k, region
    return 0, -1, k_near, region_near


@jit
def _cycle_span(hist, count, max_cycle, k):
    """(advance, lo, hi) of the last k periods: the displacement over them and the extreme
    displacements within them."""
    j = (count - k) % max_cycle
    cum = 0.0
    lo = 0.0
    hi = 0.0
    for _ in range(k):
        p = hist[j]
        lo = min(lo, cum + p.lo)
        hi = max(hi, cum + p.hi)
        cum += p.dxp
        j += 1
        if j >= max_cycle:
            j -= max_cycle
    return cum, lo, hi


@jit
def _verdict(s, region, advance):
    """NEVER_STOPS reason for a cycle (until='rest'), or -1 (no verdict: it moves on)."""
    if region < 0:
        return REASON_PERIODIC
    if not s.zone:
        return REASON_PERIODIC if advance == 0.0 else (
            REASON_WALK_FORWARD if advance > 0.0 else REASON_WALK_BACKWARD)
    if region == LOW and advance <= 0.0:
        return REASON_PERIODIC if advance == 0.0 else REASON_WALK_BACKWARD
    if region == HIGH and advance >= 0.0:
        return REASON_PERIODIC if advance == 0.0 else REASON_WALK_FORWARD
    return -1


@jit
def _finite_cycles(xi, advance, cycles):
    """How many of ``cycles`` cycles of ``advance`` keep x finite (two cycles of margin: a walk
    that leaves the floats is simulated normally to its last finite state, reason NONFINITE)."""
    if math.isfinite(xi + cycles * advance):
        return cycles
    return max(0, int((LARGEST - abs(xi)) / abs(advance)) - 2)


@jit
def _skippable(s, region, advance, lo, hi, cycles):
    """How many of ``cycles`` repeats keep the mass in its region of constant friction and x
    finite (one cycle of margin: the following cycle is simulated normally)."""
    cycles = _finite_cycles(s.xi, advance, cycles)
    if not s.zone or advance == 0.0:
        return cycles
    if region == LOW and advance > 0.0:
        room = -(s.xi + hi)
    elif region == HIGH and advance < 0.0:
        room = s.xi + lo - s.w
    else:
        return cycles
    return max(0, min(cycles, int(math.floor(room / abs(advance))) - 1))


@inlined
def after_period(s, hist, count, max_cycle, swing, until, total, fast_forward, v0, mode0, xi0, path0):
    """After a completed period that started in state (v0, mode0, xi0): record it, then
    decide (until='rest', 'stick') or fast-forward on a repeating period-boundary state.
    Returns (reason or -1 to go on, history count, horizon reached)."""
    if s.n >= total:
        return -1, count, True
    if until == R.UNTIL_PERIODS and not fast_forward:
        return -1, count, False             # nothing to decide, nothing to skip: no history
    h = hist[count % max_cycle]
    h.v, h.xi, h.mode, h.path = v0, xi0, mode0, path0
    h.dxp, h.lo, h.hi, h.regions = s.dxp, s.lo, s.hi, s.regions
    count += 1
    k, region, k_near, region_near = _cycles(s, hist, count, max_cycle, until != R.UNTIL_PERIODS, swing)
    if until == R.UNTIL_CYCLE and k_near > 0 and (k == 0 or k_near < k):
        # The periodic motion itself: the shortest k at which the state repeats exactly or to
        # the near-repeat tolerance (an attracting orbit can settle into an ulp-level 2-cycle).
        k, region = k_near, region_near
    elif k == 0 and (until == R.UNTIL_REST or until == R.UNTIL_STICK):
        k, region = k_near, region_near
    elif k > 0 and until != R.UNTIL_CYCLE:
        advance, lo, hi = _cycle_span(hist, count, max_cycle, k)
        advance = advance if region >= 0 else 0.0
        if until != R.UNTIL_PERIODS:
            reason = _verdict(s, region, advance)
            if reason >= 0:
                s.advance, s.cycle, s.cycle_region = advance / k, k, region
                return reason, count, False
        if fast_forward:
            cycles = (total - s.n) // k
            if region >= 0:
                cycles = _skippable(s, region, advance, lo, hi, cycles)
                s.xi += cycles * advance
            if cycles > 0:
                s.n += cycles * k
                s.fast_forward += cycles * k
                count = 0
        return -1, count, False
    if k > 0:
        advance = _cycle_span(hist, count, max_cycle, k)[0] if region >= 0 else 0.0
        reason = _verdict(s, region, advance)
        if reason >= 0:
            s.advance, s.cycle, s.cycle_region = advance / k, k, region
            return reason, count, False
    return -1, count, False


@jit
def finish_run(s, code, reason, until):
    """The reason a run ended (from the stepper's stop code if no verdict) and its end time."""
    if reason < 0:
        if code == STOP_REST:
            reason = REASON_REST
        elif code == STOP_ACCUMULATION:
            reason = REASON_ACCUMULATION
            s.xi, s.v = s.xs, 0.0
        elif code == STOP_FIRST_STICK:
            reason = REASON_FIRST_STICK
        elif code == STOP_BUDGET:
            reason = REASON_MAX_EVENTS
        elif code == STOP_STALL:
            reason = REASON_STALL
        elif code == STOP_NONFINITE:
            reason = REASON_NONFINITE
        elif until == R.UNTIL_PERIODS:
            reason = REASON_PERIODS
        elif s.zone and s.xi_max >= 0.0:
            reason = REASON_BOUNDED
        else:
            reason = REASON_MAX_PERIODS
    s.reason = reason
    if code != DONE or reason == REASON_NONFINITE:
        s.n_end, s.tau_end = s.stop_n, s.stop_tau
    else:
        s.n_end, s.tau_end = s.n, s.tau0


def begin(method, s, row, scratch):
    """Set up member ``s`` for the stepper of ``method`` at its start phase: (the table's y'' at the
    start, the stepper's scratch tuple).  Compiled, specialised on the method (:func:`_begin`)."""
    if method == R.EXACT_SMOOTH:
        return _begin_smooth(s, row, scratch)
    if method == R.EXACT_PIECEWISE:
        return _begin_piecewise(s, row, scratch)
    return _begin_none(s, row, scratch)


@jit
def _begin_piecewise(s, row, scratch):
    s.piece0 = piece_at(row, s.tau0)
    return row[R.col_level(R.data_size(row), s.piece0)], (scratch[0, :0], scratch[1, :0], scratch[2, :0])


@jit
def _begin_smooth(s, row, scratch):
    grid, g_yd, g_ydd = smooth_grid(row, s.tau0, scratch)
    return g_ydd[0], (grid, g_yd, g_ydd)


@jit
def _begin_none(s, row, scratch):
    return 0.0, (scratch[0, :0], scratch[1, :0], scratch[2, :0])


def step(method, s, row, run, bnd, cross, record, buffers, scratch, periods, uniform):
    """Advance member ``s`` one period with the stepper of ``method`` (the dispatch of the stepper
    contract, :mod:`selfalign.solvers.engine`).  Compiled, specialised on the method (:func:`_step`),
    so that a run compiles only its own stepper; a recorded run calls the piecewise stepper rather
    than inlining it (half the compile time, where the recording sets the speed anyway)."""
    if method == R.EXACT_PIECEWISE:
        return period_piecewise(s, row, run, bnd, cross, record, buffers, scratch, periods, uniform)
    if method == R.EXACT_SMOOTH:
        if s.zone:
            return period_jerk_zone(s, row, run, bnd, cross, record, buffers, scratch, periods)
        return period_smooth(s, row, run, bnd, cross, record, buffers, scratch, periods)
    return period_moreau(s, row, run, bnd, cross, record, buffers, scratch, periods)


def _method_code(method) -> int:
    """The literal method code a specialisation is compiled for (the callers ask ``literally``)."""
    if not isinstance(method, types.IntegerLiteral):
        raise errors.TypingError("the engine's method code must be a compile-time constant (literally)")
    return method.literal_value


@overload(begin, inline="always", jit_options=OPTIONS)
def _begin(method, s, row, scratch):
    code = _method_code(method)
    if code == R.EXACT_SMOOTH:
        return lambda method, s, row, scratch: _begin_smooth(s, row, scratch)
    if code == R.EXACT_PIECEWISE:
        return lambda method, s, row, scratch: _begin_piecewise(s, row, scratch)
    return lambda method, s, row, scratch: _begin_none(s, row, scratch)


@overload(step, inline="always", jit_options=OPTIONS)
def _step(method, s, row, run, bnd, cross, record, buffers, scratch, periods, uniform):
    code = _method_code(method)
    if code == R.EXACT_PIECEWISE and isinstance(record, types.BooleanLiteral) and record.literal_value:
        def piecewise_recorded(method, s, row, run, bnd, cross, record, buffers, scratch, periods, uniform):
            return period_piecewise_called(s, row, run, bnd, cross, record, buffers, scratch, periods, uniform)
        return piecewise_recorded
    if code == R.EXACT_PIECEWISE:
        def piecewise(method, s, row, run, bnd, cross, record, buffers, scratch, periods, uniform):
            return period_piecewise(s, row, run, bnd, cross, record, buffers, scratch, periods, uniform)
        return piecewise
    if code == R.EXACT_SMOOTH:
        def smooth(method, s, row, run, bnd, cross, record, buffers, scratch, periods, uniform):
            if s.zone:
                return period_jerk_zone(s, row, run, bnd, cross, record, buffers, scratch, periods)
            return period_smooth(s, row, run, bnd, cross, record, buffers, scratch, periods)
        return smooth

    def moreau(method, s, row, run, bnd, cross, record, buffers, scratch, periods, uniform):
        return period_moreau(s, row, run, bnd, cross, record, buffers, scratch, periods)
    return moreau


@jit
def drive(s, method, uniform, row, run, bnd, cross, record, hist, buffers, scratch):
    """Run member ``s`` to its outcome (:mod:`selfalign.solvers.engine`), recording into ``buffers``
    (arcs, events, samples, sample steps) if asked.

    ``run``: the run settings (:data:`~selfalign.solvers.records.RUN_DTYPE`); ``hist``: scratch
    space for ``run.max_cycle`` period records; ``scratch``: that of the smooth stepper's grid
    (:func:`grid_scratch`).  Repeating periods are skipped only if ``run.fast_forward`` and
    nothing is recorded.  ``method`` and ``record`` are compile-time constants, so each run
    compiles and carries only its own stepper, and a run that records nothing carries no
    recording code in its loops.
    """
    literally(method)
    literally(uniform)
    literally(record)
    until, total, max_cycle = run.until, run.total, run.max_cycle
    prepare_member(s, row, method, run.acc_tol)
    swing = row[R.SWING]
    a0, work = begin(method, s, row, scratch)
    count = 0
    reason = -1
    moreau = method == R.MOREAU
    code = start_mode(s, a0, until, moreau, (row[R.MOREAU_STEP], row[R.MOREAU_LARGEST]) if moreau else
                      (0.0, 0.0))
    record_crossings(s, bnd, cross, ARC_STICK, 0.0, s.xi, s.v, 0.0, s.xi, s.v, 0, s.tau0, 0.0)
    fast_forward = run.fast_forward and not record
    # Nothing is decided at the period boundaries of a run to a fixed horizon that skips nothing:
    # the stepper may then advance to the horizon in one call.
    in_one_call = until == R.UNTIL_PERIODS and not fast_forward
    while code == DONE and s.n < total:
        v0, mode0, xi0, path0 = s.v, s.mode, s.xi, s.path
        code = step(method, s, row, run, bnd, cross, record, buffers, work, total - s.n if in_one_call else 1,
                    uniform)
        if not (math.isfinite(s.xi) and math.isfinite(s.v)):   # back to where the call started
            code = stop_nonfinite(s, xi0, v0, mode0, s.n - 1 if code == DONE else s.n)
        if code != DONE:
            break
        reason, count, horizon = after_period(s, hist, count, max_cycle, swing, until, total, fast_forward, v0, mode0,
                                              xi0, path0)
        if reason >= 0 or horizon:
            break
    finish_run(s, code, reason, until)
    if record and moreau:
        record_sample(buffers[2], s, s.n_end, s.tau_end, s.xi, s.v, s.mode)


@jit
def run_members(members, method, uniform, table, run, bnd, cross, hist, arcs, events, samples, steps):
    """Drive every member (no recording): the batch, and one trajectory without series.
    ``run``: the run settings (one :data:`~selfalign.solvers.records.RUN_DTYPE` record);
    ``hist`` is scratch space (HIST_DTYPE, max_cycle records); the recording buffers are
    passed (empty) only so that the same :func:`drive` serves both entry points.  Every
    record array is allocated by the caller (numpy record arrays, so that the kernel also
    runs uncompiled, NUMBA_DISABLE_JIT=1)."""
    literally(method)
    literally(uniform)
    scratch = grid_scratch(method, table)
    table, bnd, cross, hist, arcs, events, samples, steps = borrowed_all(table, bnd, cross, hist, arcs, events,
                                                                         samples, steps)
    settings = run[0]
    for i in range(members.shape[0]):
        s = members[i]
        drive(s, method, uniform, table[s.profile], settings, bnd[i], cross[i], False, hist,
              (arcs, events, samples, steps), scratch)


@jit
def run_recorded(members, method, table, run, bnd, cross, hist, arcs, events, samples, sample_steps):
    """Drive member 0 recording its arcs and events (exact) or samples (Moreau) into the
    buffers; the member's n_arcs, n_events, n_samples say how many there were (a buffer
    that was too small holds the first ones only: run again with larger buffers)."""
    literally(method)
    table, bnd, cross, hist, arcs, events, samples, sample_steps = borrowed_all(table, bnd, cross, hist, arcs, events,
                                                                                samples, sample_steps)
    s = members[0]
    drive(s, method, False, table[s.profile], run[0], bnd[0], cross[0], True, hist,
          (arcs, events, samples, sample_steps), grid_scratch(method, table))
