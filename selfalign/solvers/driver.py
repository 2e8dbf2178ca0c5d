"""One driver for every method: :func:`simulate` (one scene) and :func:`simulate_batch`.

Both hand their members to the compiled driver (:func:`selfalign.solvers.kernel.drive`),
which owns the horizon, the outcome decisions and the fast-forward of repeating
periods with one set of constants; the exact solver and Moreau time-stepping are its
steppers.  ``ivp`` (scipy's solve_ivp, :mod:`selfalign.solvers.ivp`) steps in Python and
calls the same compiled decisions.  Results carry one status vocabulary
(:mod:`selfalign.solvers.outcomes`).  Dense output is built here, once, from the states
the stepper provides (arcs, steps or solve_ivp's dense output).
"""

from __future__ import annotations

import functools
import math
import numbers
import time

import numpy as np

from ..model.errors import check_integer
from ..model.friction import FrictionLaw, StopZone, check_zone_position, coefficient
from ..model.profiles import Profile
from ..model.scene import Scene
from . import exact, moreau
from . import records as R
from .jit import call, kernel
from .methods import check_accumulation_tol, check_moreau_work, check_scene, friction_refused, resolve
from .outcomes import MAX_CYCLE, Reason, Status
from .results import BatchResult, Trajectory, outcome_message


def resolve_options(method: str, options: dict) -> dict:
    """The options of ``method`` with defaults filled in and checked (:func:`methods.resolve`)."""
    return resolve(method, options)


def _row(method: str, profile: Profile, phase: float, options: dict) -> tuple[int, np.ndarray]:
    """(kernel method code, profile row), cached on the profile object."""
    key = (method, phase, options.get("h"), options.get("steps_per_period")) if method == "moreau" else (method,)
    cache = profile.__dict__.setdefault("_kernel_rows", {})
    if key not in cache:
        if method == "moreau":
            cache[key] = (R.MOREAU, moreau.profile_row(profile, phase, options))
        else:
            cache[key] = exact.profile_row(profile)
    return cache[key]


def _scene_member(scene: Scene) -> tuple[np.ndarray, float]:
    """The member record of a scene (inputs set) and its origin (x_mu, or x0)."""
    members = R.records(R.MEMBER_DTYPE, 1)
    m = members[0]
    surface = scene.surface
    if isinstance(surface, StopZone):
        origin = surface.x_mu
        # c_mu = 1 is friction 1 everywhere: a uniform surface with its origin at x_mu.
        m["zone"], m["w"], m["c_mu"] = surface.c_mu > 1.0, surface.w, surface.c_mu
    else:
        origin = scene.x0
        m["w"], m["c_mu"] = math.inf, 1.0
    m["xi"], m["v"], m["tau0"] = scene.x0 - origin, scene.v0, scene.phase * scene.profile.dt
    _set_friction(members, scene.friction)
    return members, origin


def _set_friction(members: np.ndarray, law: FrictionLaw) -> None:
    """The friction-law inputs of member records (the paper's Coulomb law: r = 1, no Stribeck)."""
    members["static_ratio"], members["v_s"], members["delta"] = law.ratio, law.v_s, law.delta


class _Prepared:
    """Everything a run of one scene with one method and options needs that does not
    change between runs (cached on the scene: a Scene is immutable)."""

    __slots__ = ("options", "code", "row", "table", "template", "origin", "args", "tail", "steps")

    def members(self) -> np.ndarray:
        """A fresh member record (from bytes: numpy copies structured arrays field by field, 15x slower)."""
        members = np.frombuffer(bytearray(self.template), dtype=R.MEMBER_DTYPE)
        return members if _compiled() else members.view(np.recarray)

    def __init__(self, scene: Scene, method: str, options: dict):
        self.options = check_scene(scene, method, options)
        if method == "ivp":
            return
        self.code, self.row = _row(method, scene.profile, scene.phase, self.options)
        self.table = self.row[None, :]
        members, self.origin = _scene_member(scene)
        self.template = members.tobytes()
        o = self.options
        self.args = (self.code, self.table, R.UNTIL_CODES[scene.until], scene.horizon_periods,
                     o.get("max_events", 2**62), MAX_CYCLE, o["accumulation_tol"], _NO_BOUNDARIES, _no_crossings())
        self.tail = (o.get("iteration") == "fixed_point", o.get("fp_tol", 0.0), o.get("fp_max_iter", 1))
        self.steps = (moreau.sample_steps(int(self.row[R.DATA]), scene.record.samples_per_period)
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
    override the scene's.  Bad input raises ``ValueError`` before any work starts; a run
    that cannot finish reports it in ``Trajectory.status`` and ``message``.
    """
    if not isinstance(scene, Scene):
        raise TypeError(f"simulate expects a selfalign.Scene, got {type(scene).__name__}")
    if method is None:
        method, options = scene.method, {**scene.solver_options, **options}
    elif method == scene.method:
        options = {**scene.solver_options, **options}
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
        arcs, events, samples = _recorded_run(K, members, (members,) + prep.args, prep.tail, prep.steps)
    else:
        call(K.run_members, members, *prep.args, True, *prep.tail, _hist(), *_no_recording())
    return _trajectory(scene, method, prep.options, prep.code, prep.row, members[0], prep.origin, arcs, events,
                       samples, time.process_time() - cpu0)


def _recorded_run(K, members, args, tail, steps):
    """Run with recording; if a buffer was too small, run again (deterministic) with the
    counted sizes.  Returns the arcs, events and samples recorded."""
    start = members.copy()
    sizes = (4096, 4096, 4096)
    while True:
        buffers = (_records(R.ARC_DTYPE, sizes[0]), _records(R.EVENT_DTYPE, sizes[1]),
                   _records(R.SAMPLE_DTYPE, sizes[2]))
        call(K.run_recorded, *args, *tail, _hist(), *buffers, steps)
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


def _trajectory(scene, method, options, code, row, record, origin, arcs, events, samples, cpu,
                detail: str = "") -> Trajectory:
    """The Trajectory of a finished member record (and its recordings); ``detail``: the
    message of a failed integrator (ivp)."""
    values = record.item()
    get = _INDEX.__getitem__
    reason = _REASONS[values[get("reason")]]
    surface = scene.surface
    zone = isinstance(surface, StopZone)
    xi = values[get("xi")]
    info = {"origin": origin, "x_rel_end": xi, "fast_forward_periods": values[get("fast_forward")],
            "at_rest": values[get("at_rest")]}
    if zone:
        info["x_stick_min"] = origin + values[get("xs")]
    if reason is Reason.ACCUMULATION:
        xs, last, contraction = values[get("xs")], values[get("last_stick")], values[get("contraction")]
        info.update(limit=origin + xs, contraction=None if contraction != contraction else contraction,
                    stick_events=values[get("zone_sticks")], periods=values[get("n_end")],
                    last_stick=origin + last, remaining=xs - last)
    elif reason.status is Status.NEVER_STOPS:
        info.update(net_advance=values[get("advance")], cycle_periods=values[get("cycle")])
    used = options
    if method == "moreau":
        used = {**options, "h": float(row[R.DATA + 1])}
        info.update(steps_per_period=int(row[R.DATA]), h_requested=options["h"])
        if options["iteration"] == "fixed_point":
            info.update(fp_iterations=values[get("fp_iterations")],
                        fp_unconverged_steps=values[get("fp_unconverged")])
    rec = None
    if scene.record.dense:
        rec = dict(zip(_FIELDS, values))
        series = _dense(scene, code, row, rec, origin, arcs, samples)
    else:
        series = {}
    log = None
    if scene.record.events and events is not None and code != R.MOREAU:
        log = events.copy()
        log["x"] += origin
    arc_log = None
    if scene.record.arcs and arcs is not None and code != R.MOREAU:
        arc_log = arcs.copy()
        arc_log["x"] += origin

    def compose():
        r = rec if rec is not None else dict(zip(_FIELDS, values))
        mu = coefficient(xi, surface.w, surface.c_mu) if zone else 1.0
        text = outcome_message(r, origin, options, scene.until, scene.horizon_periods, mu, detail,
                               scene.friction.ratio)
        if method == "moreau" and reason is Reason.ACCUMULATION:
            text += (f"; the limit is that of the time-stepping scheme (x_stick_min for its rest acceleration "
                     f"max|impulse| / h = {r['rest_acc']!r})")
        if method == "moreau" and options["iteration"] == "fixed_point" and r["fp_unconverged"]:
            text += (f"; WARNING: the fixed-point iteration missed fp_tol = {options['fp_tol']!r} within "
                     f"fp_max_iter = {options['fp_max_iter']} on {r['fp_unconverged']} steps (largest last "
                     f"change {r['fp_max_change']!r})")
        return text

    events_count = values[get("events")]
    return Trajectory(
        x_end=origin + xi, v_end=values[get("v")], period_end=values[get("n_end")], tau_end=values[get("tau_end")],
        status=reason.status, reason=reason, message=compose, method=method, options=used, series=series,
        events=log, arcs=arc_log,
        stats={"events": events_count, "steps": events_count if method == "exact" else values[get("steps")],
               "cpu_time": cpu},
        info=info,
    )


_REASONS = list(Reason)
_INDEX = {name: i for i, name in enumerate(R.MEMBER_DTYPE.names)}
_FIELDS = R.MEMBER_DTYPE.names


def _dense(scene, code, row, rec, origin, arcs, samples) -> dict:
    """Dense series of a recorded run: the exact solver's arcs evaluated on the grid plus
    every event, or the states a stepper sampled (Moreau: the steps nearest the grid; ivp:
    solve_ivp's dense output on the grid plus every event)."""
    if code not in (R.EXACT_PIECEWISE, R.EXACT_SMOOTH):         # Moreau, ivp: the states themselves
        s = samples
        return dense_series(scene, s["period"], s["tau"], origin + s["x"], s["v"], None)
    end = np.zeros(1, dtype=R.ARC_DTYPE)
    e = end[0]
    stuck = rec["mode"] == 0 or rec["reason"] == Reason.ACCUMULATION
    e["kind"], e["mode"] = (0, 0) if stuck else (1, rec["mode"])
    e["period"], e["tau"], e["x"], e["v"] = rec["n_end"], rec["tau_end"], rec["xi"], 0.0 if stuck else rec["v"]
    all_arcs = np.concatenate([arcs, end])
    period, tau, x, v, mode = call(kernel().sample_arcs, all_arcs, row, float(rec["tau0"]),
                                   int(scene.record.samples_per_period))
    return dense_series(scene, period, tau, origin + x, v, mode)


def dense_series(scene: Scene, period, tau, x, v, mode) -> dict:
    """``t`` and the recorded series of a scene at states (period, tau, x, v), x absolute.

    ``mode`` None: the mode of the model at each state (slip in the direction of v; at
    v = 0 stick iff |y''| <= r mu_bar, else slip -sign(y''), :func:`decide_mode`).  The
    friction force is F = mu_bar mu(v) mode in slip (mu(v) = 1 but for Stribeck friction)
    and -y'' in stick (eq. 5).
    """
    profile, surface, law = scene.profile, scene.surface, scene.friction
    period, tau = np.asarray(period), np.asarray(tau, dtype=float)
    x, v = np.asarray(x, dtype=float), np.asarray(v, dtype=float)
    ydd = np.asarray(profile.acceleration(tau), dtype=float) + 0.0 * tau
    mu = surface.coefficient(x) if isinstance(surface, StopZone) else np.ones_like(x)
    if mode is None:
        mode = call(kernel().modes, v, ydd, law.ratio * mu)
    mode = np.asarray(mode, dtype=np.int8)
    available = {
        "x": lambda: x,
        "v": lambda: v,
        "y": lambda: np.asarray(profile.position(tau), dtype=float),
        "yd": lambda: np.asarray(profile.velocity(tau), dtype=float),
        "ydd": lambda: ydd,
        "friction": lambda: np.where(mode == 0, -ydd, mode * mu * law.factor(v)),
        "mode": lambda: mode,
    }
    out = {"t": period * profile.dt + tau}
    out.update({name: available[name]() for name in scene.record.series})
    return out


# ----------------------------------------------------------------------------------------
# Batches
# ----------------------------------------------------------------------------------------

class ProfileTable:
    """Profile rows for a batch: ``rows`` (P, width) of the kernel's profile table, all of
    one kernel method ``code``.  Build it from profiles (:func:`profile_table`) or, for a
    vectorised sweep, from arrays (:func:`selfalign.solvers.exact.piecewise_rows`)."""

    def __init__(self, rows: np.ndarray, code: int):
        self.rows = np.ascontiguousarray(rows, dtype=float)
        self.code = int(code)

    @property
    def size(self) -> int:
        return self.rows.shape[0]


def profile_table(profiles, method: str, phase, options: dict) -> ProfileTable:
    """The :class:`ProfileTable` of ``profiles`` (one, a sequence, or a table already) for ``method``."""
    if isinstance(profiles, ProfileTable):
        if method == "moreau" and profiles.code != R.MOREAU or method == "exact" and profiles.code == R.MOREAU:
            raise ValueError(f"the profile table was built for another method than {method!r}")
        return profiles
    profiles = [profiles] if isinstance(profiles, Profile) else list(profiles)
    if not profiles or not all(isinstance(p, Profile) for p in profiles):
        raise ValueError("profiles: give a selfalign profile, a non-empty sequence of them, or a ProfileTable")
    phase0 = float(np.ravel(phase)[0]) if np.size(phase) else 0.0
    rows = [_row(method, p, phase0, options) for p in profiles]
    codes = {code for code, _ in rows}
    if len(codes) > 1:
        raise ValueError("a batch runs one kind of profile: all piecewise-constant, or all Fourier")
    return ProfileTable(R.pack_profiles([row for _, row in rows]), codes.pop())

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
    if until not in R.UNTIL_CODES:
        raise ValueError(f"until must be one of {list(R.UNTIL_CODES)}, got {until!r}")
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
    """Many trajectories through the same compiled driver as :func:`simulate`.

    ``profiles``: one profile, a sequence of profiles, or a
    :class:`~selfalign.solvers.exact.ProfileTable` (vectorised three-phase sweeps);
    ``profile_index`` picks each member's profile (default: all the one profile, or one
    profile per member).  ``x0``, ``v0`` hold at time ``phase * dt`` (scalars or one per
    member; Moreau needs one phase for all).  The surface: ``surface`` (Uniform or one
    StopZone for all) or per-member arrays ``x_mu``, ``w``, ``c_mu`` (``c_mu == 1`` is a
    uniform surface).  ``levels`` (L,) or (B, L): absolute positions whose first crossing
    is recorded (after x_mu and x_mu + w).  ``until``: "periods" (``periods``), "rest"
    (at most ``max_periods``) or "stick" (the first stick event).  ``options``: those of
    ``method`` (:mod:`selfalign.solvers.methods`).  ``max_cycle``: the longest period of
    a repeating motion that is recognised; ``fast_forward=False`` simulates every period
    even when the period-boundary state repeats (benchmarks).  ``friction``: the
    :class:`~selfalign.model.friction.FrictionLaw` of every member (default Coulomb).
    """
    options = resolve(method, options)
    friction = FrictionLaw() if friction is None else friction
    if not isinstance(friction, FrictionLaw):
        raise ValueError(f"friction must be a FrictionLaw, got {type(friction).__name__}")
    refused = friction_refused(method, friction, options)
    if refused:
        raise ValueError(refused)
    if method == "ivp":
        raise ValueError("simulate_batch runs the compiled methods 'exact' and 'moreau'; use simulate for 'ivp'")
    until_code, total, horizon_name = _horizon(until, periods, max_periods)
    if isinstance(max_cycle, bool) or not isinstance(max_cycle, numbers.Integral) or not 1 <= max_cycle <= 1024:
        raise ValueError(f"max_cycle must be an integer in [1, 1024], got {max_cycle!r}")
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
        check_moreau_work(int(table.rows[0, R.DATA]), total, horizon_name)
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
    if isinstance(surface, StopZone):
        x_mu, w, c_mu = surface.x_mu, surface.w, surface.c_mu
    elif surface is not None and (x_mu is not None or w is not None or c_mu is not None):
        raise ValueError("give the surface either as surface= or as x_mu=, w=, c_mu=, not both")
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
    _set_friction(members, friction)
    members["xi"] = x0 - origin
    members["v"] = _member_array("v0", v0, size)
    members["tau0"] = phase * dt
    if method == "exact" and table.code == R.EXACT_SMOOTH and np.any(members["zone"] & (table.rows[index, R.DATA] > 0)):
        raise ValueError("method 'exact' cannot simulate a Fourier profile on a stop zone; use 'moreau'")
    boundaries = np.zeros((size, 0))
    if x_mu is not None or levels is not None:
        lev = np.zeros((size, 0)) if levels is None else np.asarray(levels, dtype=float)
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
    call(K.run_members, members, table.code, table.rows, until_code, total, options.get("max_events", 2**62),
         int(max_cycle), options["accumulation_tol"], relative, crossings, bool(fast_forward),
         options.get("iteration") == "fixed_point", options.get("fp_tol", 0.0), options.get("fp_max_iter", 1),
         _hist(int(max_cycle)), *_no_recording())
    if method == "moreau":
        options = {**options, "h": float(table.rows[0, R.DATA + 1])}
    return BatchResult(records=members.view(np.recarray), origin=origin, dt=dt, boundaries=boundaries,
                       crossings=crossings.view(np.recarray), method=method, options=options, until=until,
                       horizon=total)
