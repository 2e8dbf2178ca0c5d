"""One driver for every method: :func:`simulate` (one scene) and :func:`simulate_batch`.

Both hand their members to the compiled driver (:func:`selfalign.solvers.engine.drive.drive`),
which owns the horizon, the outcome decisions and the fast-forward of repeating
periods with one set of constants; the exact solver and Moreau time-stepping are its
steppers.  ``ivp`` (scipy's solve_ivp, :mod:`selfalign.solvers.ivp`) steps in Python and
calls the same compiled decisions.  Results carry one status vocabulary
(:mod:`selfalign.solvers.outcomes`).  Dense output is built here, once, from the states
the stepper provides (arcs, steps or solve_ivp's dense output).
"""

from __future__ import annotations

import functools
import time

import numpy as np

from ..model.errors import check_choice, check_integer, check_real_array
from ..model.friction import FrictionLaw, StopZone, check_zone_position
from ..model.scene import Scene
from . import moreau
from . import records as R
from .assembly import scene_member, set_friction, trajectory
from .jit import call, kernel
from .methods import PLANAR_OPTIONS, check_accumulation_tol, check_moreau_work, check_scene, friction_refused, resolve
from .outcomes import MAX_CYCLE, Reason, Status
from .results import BatchResult, Trajectory
from .tables import kernel_row, profile_table


def resolve_options(method: str, options: dict) -> dict:
    """The options of ``method`` with defaults filled in and checked (:func:`methods.resolve`)."""
    return resolve(method, options)


class _Prepared:
    """Everything a run of one scene with one method and options needs that does not
    change between runs (cached on the scene: a Scene is immutable)."""

    __slots__ = ("options", "code", "row", "table", "template", "origin", "run", "args", "steps")

    def members(self) -> np.ndarray:
        """A fresh member record (from bytes: numpy copies structured arrays field by field, 15x slower)."""
        members = np.frombuffer(bytearray(self.template), dtype=R.MEMBER_DTYPE)
        return members if _compiled() else members.view(np.recarray)

    def __init__(self, scene: Scene, method: str, options: dict):
        self.options = check_scene(scene, method, options)
        if method == "ivp":
            return
        self.code, self.row = kernel_row(method, scene.profile, scene.phase, self.options)
        self.table = self.row[None, :]
        members, self.origin = scene_member(scene)
        self.template = members.tobytes()
        o = self.options
        self.run = _run_settings(R.UNTIL_CODES[scene.until], scene.horizon_periods, o.get("max_events", 2**62),
                                 MAX_CYCLE, o["accumulation_tol"], True, o.get("iteration") == "fixed_point",
                                 o.get("fp_tol", 0.0), o.get("fp_max_iter", 1))
        self.args = (self.table, self.run, _NO_BOUNDARIES, _no_crossings())
        self.steps = (moreau.sample_steps(R.data_size(self.row), scene.record.samples_per_period)
                      if self.code == R.MOREAU and scene.record.dense else _NO_STEPS)


def _prepared(scene: Scene, method: str, options: dict) -> _Prepared:
    cache = scene.__dict__.setdefault("_prepared", {})
    try:
        key = (method, tuple(sorted(options.items())))
        hash(key)
    except TypeError:
        return _Prepared(scene, method, options)
    if key not in cache:
        cache[key] = _Prepared(scene, method, options)
    return cache[key]


def simulate(scene: Scene, method: str | None = None, **options) -> Trajectory:
    """Simulate ``scene`` with ``method`` ("exact", "moreau" or "ivp").

    ``method`` and ``options`` default to the scene's solver block; options given here
    override the scene's (with another method than the scene's, only the options given
    here apply).  Bad input raises ``ValueError`` before any work starts; a run
    that cannot finish reports it in ``Trajectory.status`` and ``message``.

    The exact solver (event-driven, closed-form arcs) and Moreau time-stepping are the
    steppers of one compiled driver, which owns the horizon, the outcome decisions and the
    fast-forward of repeating periods; ``ivp`` (scipy's solve_ivp) steps in Python and calls
    the same compiled decisions.  The first call of a process compiles the driver's entry
    point unless numba's on-disk cache holds it (``selfalign.solvers.jit``).

    Parameters
    ----------
    scene : Scene
        The scene: profile, surface, friction law, start state, horizon and record.
    method : str, optional
        The solver, "exact", "moreau" or "ivp"; None: the scene's ``method``.
    **options
        Options of the method (``selfalign.solvers.methods``): ``accumulation_tol`` (every
        method), ``max_events`` (exact, ivp), ``h``, ``steps_per_period``, ``iteration``,
        ``fp_tol``, ``fp_max_iter`` (moreau), ``rtol``, ``atol``, ``integrator`` (ivp).

    Returns
    -------
    Trajectory
        The end state, its status, reason and message, and the series, event log and arcs
        the scene's record asked for.

    Raises
    ------
    TypeError
        If ``scene`` is not a Scene, or an option that takes a number gets something else.
    ValueError
        If the method or an option is unknown, an option value is not allowed, or the method
        cannot simulate the scene (e.g. the exact solver with a Fourier profile on a stop
        zone or with Stribeck friction, a Moreau horizon of more than 1e10 steps, an
        ``accumulation_tol`` above 1e-6 of the zone width).
    KernelError
        If numba is missing or cannot compile the kernel (a RuntimeError).

    See Also
    --------
    simulate_batch : Many runs at once through the same compiled driver.
    load_scene : Reads a scene file.

    Examples
    --------
    The Fig. 18 profile entering a stop zone accumulates at x_stick_min (eq. 41):

    >>> import selfalign as sa
    >>> profile = sa.ThreePhaseProfile(dt=1.05, dy=0.084, y2=2.2, y3=0.9)
    >>> scene = sa.Scene(profile, sa.StopZone(x_mu=0.5, w=0.05, c_mu=2.5), until="rest", max_periods=1000)
    >>> traj = sa.simulate(scene)
    >>> print(traj.status.value, round(traj.x_end, 6), traj.period_end)
    accumulation 0.54 20
    >>> print(traj.message)
    accumulation: stick positions in the transition zone converge to x_stick_min = 0.54 (eq. 41); ...

    The same scene with Moreau time-stepping at 500 steps per period:

    >>> traj = sa.simulate(scene, "moreau", steps_per_period=500)
    >>> print(traj.status.value, round(traj.x_end, 6), round(traj.options["h"], 6))
    accumulation 0.54 0.0021
    """
    if not isinstance(scene, Scene):
        raise TypeError(f"simulate expects a selfalign.Scene, got {type(scene).__name__}")
    if method is None:
        method, options = scene.method, {**scene.solver_options, **options}
    elif method == scene.method:
        options = {**scene.solver_options, **options}
    if scene.parts is not None:
        return _simulate_parts(scene, method, options)
    if scene.planar:
        return _simulate_planar(scene, method, options)
    prep = _prepared(scene, method, options)
    cpu0 = time.process_time()
    if method == "ivp":
        from . import ivp

        return ivp.solve(scene, prep.options, cpu0)
    members = prep.members()
    K = kernel()
    record = scene.record
    arcs = events = samples = None
    if record.dense or record.events or record.arcs:
        arcs, events, samples = _recorded_run(K.RECORDED_RUNS[prep.code], members, (members,) + prep.args, prep.steps)
    else:
        # One trajectory runs the entry point for every surface, so that a first call compiles one
        # kernel for the paper's scenes, uniform or stop zone; batches pick K.member_run.
        call(K.MEMBER_RUNS[prep.code], members, *prep.args, _hist(), *_no_recording())
    return trajectory(scene, method, prep.options, prep.code, prep.row, members[0], prep.origin, arcs, events,
                       samples, time.process_time() - cpu0)


def _simulate_parts(scene: Scene, method: str, given: dict) -> Trajectory:
    """A scene with several parts through its solver (:mod:`.parts_exact` or :mod:`.parts_moreau`), as a
    Trajectory whose x_end, v_end have shape (N,); the exact solver's events and rest flags per part are in
    ``info`` (``part_sticks``, ..., ``part_held`` of :class:`~.parts_exact.PartsResult`, arrays of shape (N,))."""
    from .parts_exact import PART_EVENTS, PER_PART, simulate_parts
    from .parts_moreau import moreau_parts

    options = check_scene(scene, method, given)
    dt, n, tau0 = scene.profile.dt, len(scene.parts), scene.phase * scene.profile.dt
    cpu0 = time.process_time()
    if method == "exact":
        run = simulate_parts(scene.profile, scene.parts, surface=scene.surface, restitution=scene.restitution,
                             periods=scene.horizon_periods, phase=scene.phase, friction=scene.friction,
                             max_events=options["max_events"])
        stats, used = {"events": run.events, "steps": 0}, {"max_events": options["max_events"]}
        info = {name: getattr(run, name) for name in PART_EVENTS}
        info.update({"part_" + name: getattr(run, "part_" + name) for name in PER_PART})
        reason = run.reason
        if reason.status is not Status.ERROR and scene.until == "periods":
            reason = Reason.PERIODS         # at rest for good before the horizon: nothing moves after it
        elif reason is Reason.PERIODS:
            reason = Reason.MAX_PERIODS     # until='rest': the horizon is max_periods
    else:
        steps, h = moreau.moreau_step(dt, options)
        run = moreau_parts(scene.profile, scene.parts, surface=scene.surface, restitution=scene.restitution,
                           periods=scene.horizon_periods, phase=scene.phase, steps_per_period=steps,
                           friction=scene.friction)
        stats, used, info = {"events": 0, "steps": run.steps}, {"steps_per_period": steps, "h": h}, {
            "max_overlap": run.max_overlap}
        reason = Reason.PERIODS
    if reason in (Reason.PERIODS, Reason.MAX_PERIODS):
        period_end, tau_end = scene.horizon_periods, tau0
    else:
        period_end = int((run.t_end - tau0) // dt)          # whole periods from the start phase, as one part's
        tau_end = run.t_end - period_end * dt
    if reason.status is Status.ERROR:
        text = run.message
    elif reason is Reason.REST:
        text = (f"{n} parts at rest for good: no table acceleration of the profile moves a part alone or a cluster "
                f"pushed together")
    else:
        text = f"simulated {period_end} periods of {n} parts" + (
            f": {run.impacts} contact closings, {run.openings} openings, {run.sticks} sticks"
            if method == "exact" else f" (largest overlap {run.max_overlap:.3g})")
    return Trajectory(x_end=run.x_end, v_end=run.v_end, period_end=period_end, tau_end=tau_end, status=reason.status,
                      reason=reason, message=text, method=method, options=used,
                      stats={**stats, "cpu_time": time.process_time() - cpu0}, info=info)


def _simulate_planar(scene: Scene, method: str, given: dict) -> Trajectory:
    """A planar scene through its solver (:func:`.planar.run_planar`), as a Trajectory whose x_end, v_end have
    shape (2,), series ``x`` and ``v`` shape (n, 2), the events counted per kind in ``info`` (sticks, slips,
    crossings, breaks) and the event log in ``events`` (:data:`.planar.PLANAR_EVENT_DTYPE`)."""
    from .planar import PLANAR_EVENTS, run_planar

    options = check_scene(scene, method, given)
    dt, tau0 = scene.profile.dt, scene.phase * scene.profile.dt
    cpu0 = time.process_time()
    run = run_planar(scene, method, options)
    reason = run.reason
    if reason is Reason.REST and scene.until == "periods":
        reason = Reason.PERIODS          # at rest for good before the horizon: nothing moves after it
    if reason in (Reason.PERIODS, Reason.MAX_PERIODS):
        period_end, tau_end = scene.horizon_periods, tau0
    else:
        period_end = int((run.t_end - tau0) // dt)
        tau_end = run.t_end - period_end * dt
    info = {name: getattr(run, name) for name in PLANAR_EVENTS}
    events = sum(info.values())
    if reason.status is Status.ERROR:
        text = run.message
    elif reason is Reason.REST:
        text = (f"at rest for good at x = ({run.x_end[0]:.10g}, {run.x_end[1]:.10g}): stuck where r mu_bar(x) >= "
                f"max|Y''| = {scene.profile.max_abs_acceleration:.6g}")
    elif reason is Reason.ACCUMULATION:
        text = (f"accumulation: stick positions converge to x = ({run.x_end[0]:.10g}, {run.x_end[1]:.10g}), where "
                f"r mu_bar(x) = max|Y''| (eq. 41 along the strip's normal)")
    else:
        text = (f"simulated {period_end} periods in the plane: {run.sticks} sticks, {run.slips} slip starts, "
                f"{run.crossings} strip-boundary crossings")
    series = {}
    if run.samples is not None:
        series = {"t": run.samples["t"], **{name: run.samples[name] for name in scene.record.series}}
    used = {name: options[name] for name in PLANAR_OPTIONS[method] if name in options}
    if method == "moreau":
        used["steps_per_period"], used["h"] = moreau.moreau_step(dt, options)
    return Trajectory(x_end=run.x_end, v_end=run.v_end, period_end=period_end, tau_end=tau_end, status=reason.status,
                      reason=reason, message=text, method=method, options=used, series=series,
                      events=run.log if scene.record.events else None,
                      stats={"events": events, "steps": run.steps, "cpu_time": time.process_time() - cpu0},
                      info=info)


def _recorded_run(entry, members, args, steps):
    """Run with recording; if a buffer was too small, run again (deterministic) with the
    counted sizes.  Returns the arcs, events and samples recorded."""
    start = members.copy()
    sizes = (4096, 4096, 4096)
    while True:
        buffers = (_records(R.ARC_DTYPE, sizes[0]), _records(R.EVENT_DTYPE, sizes[1]),
                   _records(R.SAMPLE_DTYPE, sizes[2]))
        call(entry, *args, _hist(), *buffers, steps)
        rec = members[0]
        counts = (int(rec["n_arcs"]), int(rec["n_events"]), int(rec["n_samples"]))
        if all(c <= size for c, size in zip(counts, sizes)):
            return tuple(np.asarray(b[:c]) for b, c in zip(buffers, counts))
        sizes = counts
        members[:] = start


@functools.cache
def _compiled() -> bool:
    """Whether the kernel runs compiled (not uncompiled under NUMBA_DISABLE_JIT=1)."""
    kernel()
    from numba import config

    return not config.DISABLE_JIT


def _records(dtype, size: int | tuple = 0) -> np.ndarray:
    """Zeroed records for the kernel.  Compiled, a plain structured array: numba types a
    ``numpy.recarray`` argument in Python, ~2.5 us per argument and call, a plain one in C;
    uncompiled, a record array (:func:`~selfalign.solvers.records.records`), whose fields the
    kernel reads as attributes."""
    return np.zeros(size, dtype=dtype) if _compiled() else R.records(dtype, size)


def _run_settings(*args) -> np.ndarray:
    """:func:`~selfalign.solvers.records.run_settings`, as :func:`_records` hands records to the kernel."""
    run = R.run_settings(*args)
    return run if _compiled() else run.view(np.recarray)


def _hist(size: int = MAX_CYCLE) -> np.ndarray:
    """Scratch records of the driver's cycle search: the last ``size`` periods."""
    return _records(R.HIST_DTYPE, size)


@functools.cache
def _no_crossings() -> np.ndarray:
    return _records(R.CROSS_DTYPE, (1, 0))


@functools.cache
def _no_recording() -> tuple:
    return _records(R.ARC_DTYPE), _records(R.EVENT_DTYPE), _records(R.SAMPLE_DTYPE), _NO_STEPS


_NO_BOUNDARIES = np.zeros((1, 0))
_NO_STEPS = np.zeros(0, dtype=np.int64)


# ----------------------------------------------------------------------------------------
# Batches
# ----------------------------------------------------------------------------------------

def _member_array(name, value, size, dtype=float) -> np.ndarray:
    if np.asarray(value).dtype.kind not in "biuf" or np.asarray(value).dtype.kind == "b" and dtype is float:
        raise TypeError(f"{name} must be a real number or an array of them, got {np.asarray(value).dtype} "
                        f"{value!r:.60}")
    arr = np.asarray(value, dtype=dtype)
    try:
        arr = np.broadcast_to(arr, (size,))
    except ValueError:
        raise ValueError(f"{name} must be a scalar or have one entry per member ({size}), got shape "
                         f"{arr.shape}") from None
    if dtype is float and not np.all(np.isfinite(arr)):
        raise ValueError(f"{name} must be finite")
    return np.array(arr)


def _horizon(until, periods, max_periods) -> tuple[int, int, str]:
    """(until code, horizon in periods, the name of the option that gave it)."""
    check_choice("until", until, R.UNTIL_CODES)
    value, name = (periods, "periods") if until == "periods" else (max_periods, "max_periods")
    if value is None:
        raise ValueError(f"until = {until!r} needs {name}, an integer >= 1")
    return R.UNTIL_CODES[until], check_integer(name, value), name


#: Largest memory (bytes) of the records a :func:`simulate_batch` call allocates for its members,
#: estimated from the member count before any is allocated (:func:`batch_bytes`).
BATCH_MEMORY_LIMIT = 2 * 1024**3


def batch_bytes(members: int, boundaries: int) -> int:
    """Bytes :func:`simulate_batch` allocates for ``members`` members with ``boundaries`` recorded
    crossings each: the member record, a crossing record and three floats per boundary (the
    boundary, its relative position and its level), and eight per-member float arrays."""
    return members * (R.MEMBER_DTYPE.itemsize + boundaries * (R.CROSS_DTYPE.itemsize + 24) + 64)


def _profile_index(value, size: int, table_size: int) -> np.ndarray:
    """Each member's profile: integers (or integral floats) in [0, table_size)."""
    index = np.asarray(value)
    if index.dtype.kind not in "iuf":
        raise TypeError(f"profile_index must hold integers, got dtype {index.dtype}")
    if index.dtype.kind == "f" and not np.all(np.isfinite(index) & (index == np.round(index))):
        bad = index[~(np.isfinite(index) & (index == np.round(index)))].ravel()[0]
        raise ValueError(f"profile_index must hold integers (indices into the profiles), got {float(bad)!r}")
    if np.any((index < 0) | (index >= table_size)):
        raise ValueError(f"profile_index must lie in [0, {table_size})")
    return _member_array("profile_index", index.astype(np.int64), size, np.int64)


def simulate_batch(profiles, x0, v0=0.0, phase=0.0, *, profile_index=None, surface=None, x_mu=None, w=None,
                   c_mu=None, levels=None, until: str = "rest", periods: int | None = None,
                   max_periods: int = 10_000, method: str = "exact", max_cycle: int = MAX_CYCLE,
                   fast_forward: bool = True, friction: FrictionLaw | None = None, **options) -> BatchResult:
    """Many trajectories through the same compiled driver as :func:`~selfalign.simulate`.

    Every member is one run: its profile, start state and surface may differ, the method,
    its options, the horizon and the friction law are shared.  Per-member inputs are
    scalars or 1-D arrays of one common length B, the number of members; the records of a
    call may take at most 2 GiB (``BATCH_MEMORY_LIMIT``, estimated before any is allocated:
    simulate more members in parts).  ``ivp`` is not offered here (use
    :func:`simulate`).

    Parameters
    ----------
    profiles : Profile, list of Profile, or ProfileTable
        One profile, a sequence of profiles, or a
        ``ProfileTable`` (vectorised three-phase sweeps); a
        batch runs one kind of profile (all piecewise-constant, or all Fourier).
    x0 : float or array_like
        Start position at time ``phase * dt`` (scalar or one per member).
    v0 : float or array_like, optional
        Start velocity at time ``phase * dt`` (scalar or one per member).  Default 0.
    phase : float or array_like, optional
        Start time as a fraction of the period, in [0, 1) (scalar or one per member; Moreau
        needs one phase for all).  Default 0.
    profile_index : array_like of int, optional
        Picks each member's profile (default: all the one profile, or one profile per member).
    surface : Uniform or StopZone, optional
        The surface of every member: Uniform or one StopZone for all (a StopZone takes the
        place of ``x_mu``, ``w``, ``c_mu``; a surface together with any of them is refused).
    x_mu, w, c_mu : float or array_like, optional
        Per-member stop zones instead of ``surface`` (``c_mu == 1`` is a uniform surface);
        ``w`` > 0 and ``c_mu`` >= 1.  ``w`` and ``c_mu`` need ``x_mu``.
    levels : array_like, optional
        (L,) or (B, L): absolute positions whose first crossing is recorded (after x_mu and
        x_mu + w); not NaN (+inf: never reached).
    until : str, optional
        "periods" (``periods``), "rest" (the default; at most ``max_periods``), "stick" (the
        first stick event) or "cycle" (until the period-boundary state repeats, at most
        ``max_periods``).
    periods : int, optional
        The horizon of ``until="periods"``.
    max_periods : int, optional
        The horizon of the other rules.  Default 10000.
    method : str, optional
        The compiled solver, "exact" (the default) or "moreau".
    max_cycle : int, optional
        The longest period of a repeating motion that is recognised, in [1, 1024].  Default 8.
    fast_forward : bool, optional
        False simulates every period even when the period-boundary state repeats
        (benchmarks).  Default True.
    friction : FrictionLaw, optional
        The :class:`~selfalign.model.friction.FrictionLaw` of every member (default Coulomb).
    **options
        Those of ``method`` (``selfalign.solvers.methods``).

    Returns
    -------
    BatchResult
        Per-member end states, reasons and status codes, zone statistics and the first
        crossing of every boundary.

    Raises
    ------
    TypeError
        If ``profiles`` holds something other than profiles, ``friction`` is not a
        FrictionLaw, an option that takes a number gets something else, a per-member input
        or ``levels`` does not hold real numbers, ``profile_index`` does not hold integers,
        or ``periods``, ``max_periods`` or ``max_cycle`` is not a number.
    ValueError
        If the method or an option is unknown or not allowed (``ivp``; Stribeck friction
        with the exact solver; a Moreau horizon of more than 1e10 steps); ``until`` is
        unknown or its horizon is missing or not an integer >= 1; ``max_cycle`` is not an
        integer in [1, 1024]; ``profiles`` holds no profile or mixes
        kinds; per-member inputs are not scalars or 1-D of one length, or not finite;
        ``profile_index`` lies outside the profiles; ``phase`` lies outside [0, 1) (or
        differs between Moreau members); a Uniform ``surface`` comes with ``x_mu``, ``w``
        or ``c_mu``, or ``w``, ``c_mu`` come without ``x_mu``; a zone has ``w`` <= 0,
        ``c_mu`` < 1, ``|x_mu| > 2**32 w`` or an ``accumulation_tol`` above 1e-6 of w; the exact
        solver gets a Fourier profile on a stop zone; ``levels`` holds NaN; or the records
        would exceed 2 GiB.
    KernelError
        If numba is missing or cannot compile the kernel (a RuntimeError).

    See Also
    --------
    simulate : One scene, every method, with dense output and event logs.
    positioning : Steady-state entries into a stop zone, built on this function.

    Examples
    --------
    Four entries of the Fig. 18 profile into a stop zone (status codes index
    ``list(sa.Status)``):

    >>> import numpy as np
    >>> import selfalign as sa
    >>> profile = sa.ThreePhaseProfile(dt=1.05, dy=0.084, y2=2.2, y3=0.9)
    >>> zone = sa.StopZone(x_mu=0.5, w=0.05, c_mu=2.5)
    >>> batch = sa.simulate_batch(profile, np.linspace(-0.06, 0.0, 4), surface=zone, max_periods=1000)
    >>> [list(sa.Status)[code].value for code in batch.status]
    ['accumulation', 'accumulation', 'rest', 'accumulation']
    >>> batch.x_end.round(6).tolist()
    [0.54, 0.54, 0.540866, 0.54]

    Two profiles on a uniform surface, one member each: both walk forward for ever.

    >>> slip_slip = sa.ThreePhaseProfile(dt=1.0, dy=0.084, y2=1.4, y3=1.3)
    >>> batch = sa.simulate_batch([profile, slip_slip], 0.0, max_periods=100)
    >>> [status.value for status in batch.statuses()], batch.advance.round(6).tolist()
    (['never_stops', 'never_stops'], [0.065412, 0.009778])
    """
    options = resolve(method, options)
    friction = FrictionLaw() if friction is None else friction
    if not isinstance(friction, FrictionLaw):
        raise TypeError(f"friction must be a FrictionLaw, got {type(friction).__name__}")
    refused = friction_refused(method, friction, options)
    if refused:
        raise ValueError(refused)
    if method == "ivp":
        raise ValueError("simulate_batch runs the compiled methods 'exact' and 'moreau'; use simulate for 'ivp'")
    until_code, total, horizon_name = _horizon(until, periods, max_periods)
    max_cycle = check_integer("max_cycle", max_cycle, 1, 1024)
    table = profile_table(profiles, method, phase, options)
    shapes = [np.shape(a) for a in (x0, v0, phase, profile_index, x_mu, w, c_mu) if a is not None]
    try:
        shape = np.broadcast_shapes(*shapes, (table.size,) if profile_index is None and table.size > 1 else ())
    except ValueError:
        raise ValueError(f"per-member inputs must be scalars or 1-D of one common length, got shapes {shapes}") \
            from None
    if len(shape) > 1:
        raise ValueError(f"per-member inputs must be scalars or 1-D, got shape {shape}")
    size = shape[0] if shape else 1
    n_levels = 0 if levels is None else np.shape(levels)[-1] if np.ndim(levels) else 1
    need = batch_bytes(size, 2 * (x_mu is not None or isinstance(surface, StopZone)) + n_levels)
    if need > BATCH_MEMORY_LIMIT:
        raise ValueError(f"simulate_batch: {size:,} members need about {need / 1024**3:.3g} GiB of records, more "
                         f"than the {BATCH_MEMORY_LIMIT / 1024**3:g} GiB allowed per call; simulate them in parts")
    if method == "moreau":
        check_moreau_work(R.data_size(table.rows[0]), total, horizon_name)
    index = (np.arange(size) if table.size > 1 and profile_index is None
             else _profile_index(0 if profile_index is None else profile_index, size, table.size))
    dt = table.rows[index, R.DT]
    members = _records(R.MEMBER_DTYPE, size)
    x0 = _member_array("x0", x0, size)
    phase = _member_array("phase", phase, size)
    if np.any((phase < 0.0) | (phase >= 1.0)):
        raise ValueError("phase must lie in [0, 1) (fraction of the period)")
    if method == "moreau" and phase.size and np.ptp(phase) > 0.0:
        raise ValueError("method 'moreau' in a batch needs one phase for every member")
    if surface is not None and (x_mu is not None or w is not None or c_mu is not None):
        raise ValueError("give the surface either as surface= or as x_mu=, w=, c_mu=, not both")
    if isinstance(surface, StopZone):
        x_mu, w, c_mu = surface.x_mu, surface.w, surface.c_mu
    if x_mu is None:
        if w is not None or c_mu is not None:
            raise ValueError("w and c_mu need x_mu (a stop zone); leave all three None for a uniform surface")
        origin = x0
        members["w"], members["c_mu"] = np.inf, 1.0
    else:
        origin = _member_array("x_mu", x_mu, size)
        w_arr, c_arr = _member_array("w", w, size), _member_array("c_mu", c_mu, size)
        if np.any(w_arr <= 0.0) or np.any(c_arr < 1.0):
            raise ValueError("stop zone: w must be > 0 and c_mu >= 1")
        check_zone_position(origin, w_arr)
        members["zone"] = c_arr > 1.0
        if members["zone"].any():
            check_accumulation_tol(options["accumulation_tol"], float(w_arr[members["zone"]].min()))
        members["w"] = np.where(members["zone"], w_arr, np.inf)
        members["c_mu"] = c_arr
    members["profile"] = index
    set_friction(members, friction)
    members["xi"] = x0 - origin
    members["v"] = _member_array("v0", v0, size)
    members["tau0"] = phase * dt
    if method == "exact" and table.code == R.EXACT_SMOOTH and np.any(members["zone"] & (table.rows[index, R.DATA] > 0)):
        raise ValueError("method 'exact' cannot simulate a Fourier profile on a stop zone; use 'moreau'")
    boundaries = np.zeros((size, 0))
    if x_mu is not None or levels is not None:
        lev = np.zeros((size, 0)) if levels is None else check_real_array("levels", levels)
        lev = np.array(np.broadcast_to(lev if lev.ndim == 2 else lev[None, :], (size, lev.shape[-1])))
        if np.any(np.isnan(lev)):
            raise ValueError("levels must not be NaN (+inf: never reached)")
        zone_b = np.where(members["zone"][:, None], np.stack([origin, origin + members["w"]], axis=1), np.nan)
        boundaries = np.concatenate([zone_b, lev], axis=1)
    crossings = _records(R.CROSS_DTYPE, boundaries.shape)
    crossings["period"] = -1
    crossings["tau"] = crossings["v"] = np.nan
    relative = boundaries - origin[:, None]
    K = kernel()
    run = _run_settings(until_code, total, options.get("max_events", 2**62), int(max_cycle),
                        options["accumulation_tol"], bool(fast_forward), options.get("iteration") == "fixed_point",
                        options.get("fp_tol", 0.0), options.get("fp_max_iter", 1))
    call(K.member_run(table.code, members), members, table.rows, run, relative, crossings, _hist(int(max_cycle)),
         *_no_recording())
    if method == "moreau":
        options = {**options, "h": float(table.rows[0, R.MOREAU_STEP])}
    return BatchResult(records=members.view(np.recarray), origin=origin, dt=dt, boundaries=boundaries,
                       crossings=crossings.view(np.recarray), method=method, options=options, until=until,
                       horizon=total)
