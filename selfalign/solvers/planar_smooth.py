"""The general exact planar solver (``method="exact"`` on every planar scene the closed form does not cover):
strips, piecewise-linear y'' (finite jerk), Fourier components, static/kinetic friction.

Model (docs/explanation/planar-model.md): x'' = -Y''(t) + f, f in -mu_bar(x) Sign2(x'), with
mu_bar(x) the max over the strips of eqs. 7-9 along each normal (1 with none).  There is no closed form
in the plane, so the slip is integrated by an explicit Runge-Kutta method of order 8 with step-size control,
every step ending at an event located on the step's own local solution (the compiled stepper
:mod:`selfalign.solvers.engine.planar_smooth`, whose docstring gives the method and the tie rules).  This module
turns a planar scene into the stepper's arrays and its output into a :class:`~selfalign.solvers.planar.PlanarResult`.

Measured accuracy (docs/explanation/planar-model.md, tests/test_planar_smooth.py): the 1-D reduction agrees with
the 1-D exact solver to 6e-16 (tested to 1e-12); a stop under a constant Y'' matches the closed form to 3e-16 in
time and 6e-17 in position; a slip matches mpmath's Taylor integrator of the same equation at 30 digits to 4e-16
over half a period; a turned scene turns the trajectory to 4e-16.
"""

from __future__ import annotations

import math

import numpy as np

from ..model.planar import strip_rows
from ..model.profiles import PiecewiseConstantProfile
from . import exact
from . import records as R
from .engine import codes as C
from .jit import call, kernel
from .methods import ACCUMULATION_TOL
from .outcomes import STALL_EVENTS, STALL_ULPS, Reason, message
from .planar import PLANAR_EVENT_DTYPE, PLANAR_SAMPLE_DTYPE, PlanarResult

#: Grid intervals per period and harmonic of a Fourier component, on which the end of a stick is bracketed
#: (that of the 1-D smooth stepper, :func:`selfalign.solvers.engine.smooth.smooth_grid`).
GRID_PER_HARMONIC = 64
#: Log entries room is made for before the first run (a longer log runs again with room for all of it).
FIRST_LOG_ROOM = 1024
#: The first slip step of a run, as a fraction of the period (the step-size control adapts it).
FIRST_STEP = 1.0 / 64.0
#: Switches of the two components closer than this many ulp of the period are one switch.
SWITCH_MERGE_ULPS = 8.0


def component_row(profile, dt: float) -> np.ndarray:
    """The kernel row of one component of a planar profile: a Fourier row, or a piecewise-linear-y'' row (a
    piecewise-constant profile is one with zero jerks; ``None``, the missing y component, is y'' = 0)."""
    if profile is None:
        return R.linear_row(R.profile_header(dt, 0.0, 0.0, 0.0), [0.0, dt], [0.0], [0.0], [0.0], [0.0], [0.0])
    if isinstance(profile, PiecewiseConstantProfile):
        amax = profile.max_abs_acceleration
        head = R.profile_header(profile.dt, amax, profile.velocity_swing, amax)
        zeros = np.zeros(len(profile.accels))
        return R.linear_row(head, profile.breaks, profile.accels, zeros, zeros, zeros, profile.accels)
    return exact.profile_row(profile)[1]


def _breaks(row) -> np.ndarray:
    """The breaks of a piecewise-linear row (none for a Fourier row)."""
    k = R.data_size(row)
    if k > 0:
        return np.zeros(0)
    return row[R.col_break(0):R.col_break(-k + 1)]


def merged_pieces(rows: np.ndarray, dt: float, shift: float) -> np.ndarray:
    """The pieces of one period [0, dt) on which both components are smooth (columns of
    :mod:`selfalign.solvers.engine.codes`: PIECE_START, PIECE_END, the piece of each component, the y component's
    time offset): the breaks of x, and those of y moved by its lag ``shift``, merged."""
    bx, by = _breaks(rows[0]), _breaks(rows[1])
    points = np.unique(np.concatenate([[0.0, dt], bx, np.mod(by + shift, dt)]))
    points = points[points <= dt]
    keep = [points[0]]
    for p in points[1:]:
        if p - keep[-1] > SWITCH_MERGE_ULPS * np.spacing(dt):
            keep.append(p)
    keep[-1] = dt
    pieces = np.zeros((len(keep) - 1, C.GENERAL_PIECE_COLUMNS))
    for i, (a, b) in enumerate(zip(keep[:-1], keep[1:])):
        mid = 0.5 * (a + b)
        ty, offset = (mid - shift, shift) if mid >= shift else (mid - shift + dt, shift - dt)
        ix = max(np.searchsorted(bx, mid, side="right") - 1, 0) if bx.size else 0
        iy = max(np.searchsorted(by, ty, side="right") - 1, 0) if by.size else 0
        pieces[i] = (a, b, min(ix, max(bx.size - 2, 0)), min(iy, max(by.size - 2, 0)), offset)
    return pieces


def _piece_at(pieces: np.ndarray, tau: float) -> int:
    """The merged piece holding phase tau (right-continuous)."""
    return int(np.searchsorted(pieces[:, C.PIECE_START], tau, side="right") - 1)


def run(scene, options: dict) -> PlanarResult:
    """Simulate a planar scene with the general exact stepper.

    Parameters
    ----------
    scene : Scene
        A planar scene (``scene.planar``): a :class:`~selfalign.model.planar.PlanarProfile`, a uniform surface or
        strips, Coulomb or static/kinetic friction.
    options : dict
        The options of the exact method, checked and filled (``max_events``; ``accumulation_tol`` if given).

    Returns
    -------
    PlanarResult
        The end state and time, why the run ended, the event counts, and the samples and log the scene's record
        asks for.

    Raises
    ------
    ValueError
        If ``scene`` is not planar, or its friction law is neither Coulomb's nor static/kinetic.
    KernelError
        If the compiled stepper cannot be compiled on this machine.

    Examples
    --------
    A finite-jerk profile along the diagonal, from rest, for two periods:

    >>> import math
    >>> import selfalign as sa
    >>> from selfalign.solvers import planar_smooth
    >>> jerk = sa.FiniteJerkProfile(dt=1.05, dy=0.084, y2=2.2, y3=0.9, ramp=0.02)
    >>> profile = sa.PlanarProfile(jerk, angle=math.pi / 4)
    >>> result = planar_smooth.run(sa.Scene(profile, periods=2), {"max_events": 1000})
    >>> result.reason.name, result.sticks, result.slips
    ('PERIODS', 2, 2)
    >>> bool(abs(result.x_end[0] - result.x_end[1]) < 1e-15)
    True
    """
    if not getattr(scene, "planar", False):
        raise ValueError("scene must be a planar scene (a PlanarProfile): the general exact planar solver simulates "
                         "planar motion only")
    if scene.friction.kind not in ("coulomb", "static_kinetic"):
        raise ValueError(f"scene.friction.kind must be coulomb or static_kinetic for planar motion, got "
                         f"{scene.friction.kind!r}")
    profile = scene.profile
    dt = float(profile.dt)
    shift = float(profile.offset) * dt
    rows = R.pack_profiles([component_row(profile.x, dt), component_row(profile.y, dt)])
    pieces = merged_pieces(rows, dt, shift)
    strips = np.ascontiguousarray(strip_rows(scene.strips), dtype=float).reshape(-1, 5)
    harmonics = max((R.data_size(row) for row in rows), default=0)
    tau0 = float(scene.phase) * dt
    spp = scene.record.samples_per_period
    q = np.zeros(C.GENERAL_SETTINGS)
    q[C.GS_DT], q[C.GS_SHIFT], q[C.GS_COS], q[C.GS_SIN] = dt, shift, math.cos(profile.angle), math.sin(profile.angle)
    q[C.GS_RATIO], q[C.GS_AMAX] = scene.friction.ratio, profile.max_abs_acceleration
    q[C.GS_TAU0], q[C.GS_SAMPLE] = tau0, dt / spp
    q[C.GS_ACC_TOL] = options.get("accumulation_tol", ACCUMULATION_TOL)
    q[C.GS_GRID] = dt / (GRID_PER_HARMONIC * (harmonics + 1)) if harmonics > 0 else 0.0
    n_samples = scene.horizon_periods * spp + 1 if scene.record.dense else 0
    log_room = FIRST_LOG_ROOM if scene.record.events else 0
    while True:
        f = np.zeros(C.GENERAL_FLOATS)
        c = np.zeros(C.GENERAL_INTS, dtype=np.int64)
        f[C.GF_X], f[C.GF_Y] = scene.x0
        f[C.GF_VX], f[C.GF_VY] = scene.v0
        f[C.GF_TAU], f[C.GF_H] = tau0, FIRST_STEP * dt
        f[C.GF_D1] = f[C.GF_D2] = math.inf
        c[C.GI_PERIODS], c[C.GI_UNTIL_REST], c[C.GI_MAX_EVENTS] = scene.horizon_periods, scene.until == "rest", \
            options["max_events"]
        c[C.GI_RECORD_SAMPLES], c[C.GI_RECORD_LOG] = n_samples > 0, log_room > 0
        c[C.GI_MODE] = 0 if f[C.GF_VX] == 0.0 and f[C.GF_VY] == 0.0 else 1
        c[C.GI_PIECE] = _piece_at(pieces, tau0)
        samples = np.zeros((n_samples, C.GENERAL_RECORD_COLUMNS))
        log = np.zeros((log_room, C.GENERAL_RECORD_COLUMNS))
        code = call(kernel().planar_smooth_run, rows, pieces, strips, q, f, c, samples, log)
        if c[C.GI_LOG] <= log_room:
            break
        log_room = int(c[C.GI_LOG])
    log = log[:c[C.GI_LOG]] if log_room else None
    return _result(scene, options, Reason(code), f, c, samples[:c[C.GI_SAMPLES]], log)


def _result(scene, options, reason, f, c, samples, log) -> PlanarResult:
    """The :class:`PlanarResult` of one run of the stepper (its end arrays)."""
    dt = float(scene.profile.dt)
    n, tau = int(c[C.GI_PERIOD]), float(f[C.GF_TAU])
    x_end = np.array([f[C.GF_X], f[C.GF_Y]])
    v_end = np.array([f[C.GF_VX], f[C.GF_VY]])
    if reason is Reason.ACCUMULATION:
        x_end = np.array([f[C.GF_LIMX], f[C.GF_LIMY]])
    text = ""
    if reason is Reason.MAX_EVENTS:
        text = message(reason, max_events=options["max_events"], period=n, tau=tau)
    elif reason is Reason.STALL:
        text = message(reason, stall=STALL_EVENTS, stall_ulps=STALL_ULPS, x=tuple(x_end.tolist()), period=n, tau=tau)
    elif reason is Reason.NONFINITE:
        text = message(reason, period=n, x=tuple(x_end.tolist()), v=tuple(v_end.tolist()))
    out_samples = out_log = None
    if scene.record.dense:
        out_samples = np.zeros(samples.shape[0], dtype=PLANAR_SAMPLE_DTYPE)
        out_samples["t"] = samples[:, 0]
        out_samples["x"] = samples[:, 1:3]
        out_samples["v"] = samples[:, 3:5]
        out_samples["mode"] = samples[:, 5]
    if log is not None:
        out_log = np.zeros(log.shape[0], dtype=PLANAR_EVENT_DTYPE)
        out_log["t"] = log[:, 0]
        out_log["kind"] = log[:, 1]
        out_log["x"] = log[:, 2:4]
        out_log["v"] = log[:, 4:6]
    return PlanarResult(t_end=n * dt + tau, x_end=x_end, v_end=v_end, reason=reason, message=text,
                        sticks=int(c[C.GI_STICKS]), slips=int(c[C.GI_SLIPS]), crossings=int(c[C.GI_CROSSINGS]),
                        breaks=int(c[C.GI_BREAKS]), steps=int(c[C.GI_STEPS]), samples=out_samples, log=out_log)

