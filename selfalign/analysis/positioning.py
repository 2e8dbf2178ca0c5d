"""Stopping in the high-friction zone: positioning accuracy and accumulation (Sect. 7).

Entries (Sect. 7.1).  On the uniform surface the steady state of a three-phase
profile is x_s(t) with x_s(0) = 0 and x_s'(0) = v0 (:mod:`selfalign.analysis.steady_state`),
and x_s(t + dt) = x_s(t) + vbar dt.  Every steady-state approach to the zone is
x(t) = x_s(t) - s for some offset s; offsets differing by vbar dt give the same
motion one period later, so the entries form a one-parameter family
s in [0, vbar dt) modulo translation.  We sample

    s_j = vbar dt (j + offset) / n_entries,   j = 0 .. n_entries - 1,

start every entry at t = 0 (phase 0, the start of the dwell, t0 of Fig. 7) at
x0s = -s_j with x' = v0, and put the zone at

    x_mu = Delta_x = max_{0 <= t <= dt} (x_s(t) - x_s(0)),

the maximum displacement within one steady period.  Then x(t) <= x0s +
Delta_x <= x_mu during the whole first period, so no entry touches the zone
before its first period ends (only s = 0 can touch x_mu, at rest or while
turning, which is harmless since mu_bar(x_mu) = 1), and x0s in (-vbar dt, 0]
is the paper's range -vbar dt <= x0s <= 0.  Results are periodic in s with
period vbar dt and independent of where the sample starts (``offset``) up to
the sampling resolution.  The entry phase of an entry is the phase of its
first arrival at x_mu (``entry_tau``).

Positioning (eqs. 39-41).  overshoot = x_end - x_mu of the entries that stop
(REST or ACCUMULATION, whose end is the limit x_stick_min);
Delta_x_d = (max - min) / 2 over them, x_d = x_mu + overshoot_min + Delta_x_d.
Entries that never stop (or stay undecided) have no end position: they are
counted separately and left out of the range (NaN when no entry stops).

Accumulation speed (Sect. 7.3).  The level x_mu + p (x_stick_min - x_mu) is
"reached" at the first time x >= level.  Times are reported in periods, from
the start of the run, from the entry (first arrival at x_mu) and from the
first stick in the zone, and as the number of zone sticks before the level
(map iterations of eq. 59 after the first stick x_1).
"""

from __future__ import annotations

from concurrent.futures import ProcessPoolExecutor
from contextlib import nullcontext
from dataclasses import dataclass, replace

import numpy as np

from ..model.errors import check_finite, check_integer, check_positive
from ..model.friction import FrictionLaw, StopZone, level_position, static_stick_limits
from ..model.profiles import ThreePhaseProfile
from ..model.registry import formula
from ..progress import Progress, resolve_mode
from ..solvers.driver import simulate_batch
from ..solvers.methods import MethodChoice, check_accumulation_tol, resolve
from ..solvers.outcomes import STATUS_CODES, Status
from ..solvers.tables import setting_method, setting_profile, setting_table
from .classification import check_parameters
from .steady_simulation import three_phase_simulated_steady_state
from .steady_state import steady_state_grid
from .stick_map import stick_map, stick_map_validity

#: Members per call of the batched solver: bounds the memory of a grid run and sets how often it
#: reports progress (~0.3 s of work per call at 64 entries; members are independent, so the size
#: does not change a bit of the results).
CHUNK_MEMBERS = 16_384
#: Default period budget: runs without an outcome by then are reported undecided.
MAX_PERIODS = 1000
#: Largest memory (bytes) a positioning call may need for its entries, estimated before any
#: work from the number of entries (:func:`positioning_bytes`).
MEMORY_LIMIT = 2 * 1024**3
#: Largest budget of a positioning call in entry-periods (settings x n_entries x max_periods): an
#: entry without an outcome runs the whole budget, at 50 ns (the paper's profile) to a few us
#: (finite jerk on the zone) per entry-period.  Fig. 17's grid is 6.5e8 (10,201 x 64 x 1000).
MAX_ENTRY_PERIODS = 10**10


def positioning_bytes(entries: int, levels: int) -> int:
    """Bytes a positioning call needs for ``entries`` entries (settings x n_entries) and
    ``levels`` accumulation levels: the peak measured with tracemalloc (643 bytes per entry and
    56 per entry and level, from one setting x 131,072 entries to 400 x 256), rounded up."""
    return entries * (660 + 60 * levels)


def _check_zone(w, c_mu, n_entries, offset, max_periods, ramp, accumulation_tol, settings=1, levels=0):
    """Check the zone and sampling options of ``settings`` settings before any work."""
    w = check_positive("w", w)
    if not 0.0 <= check_finite("ramp", ramp):
        raise ValueError(f"ramp must be >= 0 (the y'' ramp time of a finite-jerk profile; 0: the paper's), "
                         f"got {ramp!r}")
    check_finite("c_mu", c_mu)
    if c_mu <= 1.0:
        raise ValueError(f"c_mu must be > 1 (a high-friction zone), got {c_mu!r}")
    n_entries = check_integer("n_entries", n_entries)
    need = positioning_bytes(settings * n_entries, levels)
    if need > MEMORY_LIMIT:
        raise ValueError(f"n_entries = {n_entries:,} entries for each of {settings:,} setting(s) need about "
                         f"{need / 1024**3:.3g} GiB, more than the {MEMORY_LIMIT / 1024**3:g} GiB allowed (about "
                         f"{positioning_bytes(1, levels)} bytes per entry); at most "
                         f"{MEMORY_LIMIT // positioning_bytes(settings, levels):,} entries per setting")
    check_finite("offset", offset)
    if not 0.0 <= offset < 1.0:
        raise ValueError(f"offset must lie in [0, 1) (fraction of the sample spacing), got {offset!r}")
    max_periods = check_integer("max_periods", max_periods)
    budget = settings * n_entries * max_periods
    if budget > MAX_ENTRY_PERIODS:
        raise ValueError(f"max_periods = {max_periods:,} for {settings:,} setting(s) x {n_entries:,} entries is a "
                         f"budget of {budget:.3g} entry-periods, more than the {MAX_ENTRY_PERIODS:.0e} allowed (an "
                         f"entry without an outcome runs all of it, 50 ns to a few us per entry-period); at most "
                         f"{MAX_ENTRY_PERIODS // (settings * n_entries):,} periods here")
    check_accumulation_tol(resolve("exact", {"accumulation_tol": accumulation_tol})["accumulation_tol"], w)


def _check_levels(levels):
    levels = np.atleast_1d(np.asarray(levels, dtype=float))
    if levels.ndim != 1 or np.any(~np.isfinite(levels)) or np.any((levels <= 0) | (levels >= 1)):
        raise ValueError(f"levels p must be numbers in (0, 1), got {levels.tolist()!r}")
    return levels


#: Status codes of the per-entry ``status`` arrays (``list(selfalign.Status).index``).
ACCUMULATE, REST, NEVER_STOPS = (STATUS_CODES[s] for s in (Status.ACCUMULATION, Status.REST, Status.NEVER_STOPS))


def _run_chunk(args):
    """Simulate the entries of settings (flat arrays) with the method ``choice``; per-entry arrays shaped (M, N)."""
    dt, dy, y2, y3, v0, vbar, w, c_mu, n_entries, offset, max_periods, tol, levels, friction, ramp, choice = args
    m = dt.size
    table = setting_table(dt, dy, y2, y3, ramp, choice)
    run = {"friction": friction, "method": choice.method, **choice.options}
    # Delta_x: the largest x over one steady period from x_s(0) = 0 (local maxima are v = 0 events).
    dx = simulate_batch(table, 0.0, v0, profile_index=np.arange(m), until="periods", periods=1,
                        fast_forward=False, **run).x_max if m else np.zeros(0)
    frac = (np.arange(n_entries) + offset) / n_entries
    s = (vbar * dt)[:, None] * frac[None, :]
    xs_rel = static_stick_limits(np.maximum(y2, y3), friction.ratio, w, c_mu)
    lev = dx[:, None] + levels[None, :] * xs_rel[:, None]
    rep = lambda a: np.repeat(a, n_entries, axis=0)  # noqa: E731
    res = simulate_batch(table, -s.ravel(), rep(v0), profile_index=rep(np.arange(m)), x_mu=rep(dx), w=w,
                         c_mu=c_mu, levels=rep(lev), until="rest", max_periods=max_periods, accumulation_tol=tol,
                         **run)
    per = lambda a: a.reshape((m, n_entries) + a.shape[1:])  # noqa: E731
    crossing = np.stack([res.crossing_time(j) for j in range(res.boundaries.shape[1])], axis=1)
    t_cross = per(crossing)
    return {
        "dx_period": dx, "x_stick_min_rel": xs_rel, "s": s,
        "status": per(res.status), "reason": per(res.reason), "overshoot": per(res.x_end) - dx[:, None],
        "periods": per(res.t_end_periods),
        "zone_sticks": per(res.zone_sticks), "contraction": per(res.contraction), "cycle": per(res.cycle),
        "entry_time": t_cross[:, :, 0], "entry_tau": per(res.crossings["tau"][:, 0]),
        "entry_v": per(res.crossings["v"][:, 0]),
        "first_stick_time": per(res.first_stick_time), "first_stick_x": per(res.first_stick_x) - dx[:, None],
        "level_time": t_cross[:, :, 2:], "level_sticks": per(res.crossings["sticks"][:, 2:]),
        "events": per(res.event_count),
    }


def _simulate_settings(dt, dy, y2, y3, w, c_mu, n_entries, offset, max_periods, tol, levels, processes, progress,
                       friction, ramp):
    """Steady state, entry runs and the method used (its description; "" if nothing moves) for flat
    setting arrays; entry results for the moving ones, reporting progress
    (:class:`selfalign.progress.Progress` mode ``progress``) per chunk.  Under static/kinetic or
    Stribeck friction or with y'' ramps the steady state (vbar, v0, f) is simulated (no closed form);
    ``case`` stays that of the paper's Coulomb friction and profile (Table 1).  Entries run with the
    most exact method that can simulate them (``setting_method``)."""
    ss = steady_state_grid(dt, dy, y2, y3)
    if friction.kind != "coulomb" or ramp > 0.0:
        sim = three_phase_simulated_steady_state(dt, dy, y2, y3, progress="quiet", friction=friction, ramp=ramp)
        ss = replace(ss, vbar=sim.vbar, v0=sim.v0, f=sim.f)
    moving = (ss.case > 0) & (ss.vbar > 0)
    idx = np.flatnonzero(moving)
    choice = setting_method(dt[idx], dy[idx], y2[idx], y3[idx], ramp, StopZone(0.0, w, c_mu), friction) \
        if idx.size else None
    per_chunk = max(1, CHUNK_MEMBERS // n_entries)
    parts = [idx[i:i + per_chunk] for i in range(0, idx.size, per_chunk)]
    if processes > 1 and len(parts) < processes and idx.size >= processes:
        parts = np.array_split(idx, processes)
    jobs = [(dt[p], dy[p], y2[p], y3[p], ss.v0[p], ss.vbar[p], w, c_mu, n_entries, offset, max_periods, tol,
             levels, friction, ramp, choice) for p in parts]
    parallel = processes > 1 and len(jobs) > 1
    outs = []
    with (ProcessPoolExecutor(max_workers=processes) if parallel else nullcontext()) as pool, \
            Progress(int(idx.size), "positioning grid", unit="settings", mode=progress) as bar:
        for part, out in zip(parts, (pool.map if parallel else map)(_run_chunk, jobs)):
            outs.append(out)
            bar.advance(int(part.size))
    if outs:
        runs = {key: np.concatenate([o[key] for o in outs]) for key in outs[0]}
    else:  # no setting moves: the empty arrays' shapes, from a run of no members with the paper's model
        runs = _run_chunk((dt[:0], dy[:0], y2[:0], y3[:0], ss.v0[:0], ss.vbar[:0], w, c_mu, n_entries,
                           offset, max_periods, tol, levels, FrictionLaw(), 0.0, MethodChoice("exact", {})))
    return ss, idx, runs, "" if choice is None else choice.describe()


@dataclass(frozen=True)
class Positioning:
    """Positioning accuracy of one three-phase profile (Sect. 7.1-7.2), the result of positioning.

    The profile's steady state enters a stop zone at ``n_entries`` evenly spaced phases; each
    entry runs until it stops, accumulates or is found never to stop.  The zone starts at
    ``x_mu`` = Delta_x, the distance the steady motion covers in one period, so that each
    entry starts at x = -s (s the offset) and reaches the zone within a period.  Status codes
    are the index of a status in ``list(selfalign.Status)``.

    Parameters
    ----------
    profile : ThreePhaseProfile
        The profile (Attributes).
    w, c_mu : float
        The zone (Attributes).
    case : int
        The case of Table 1 (Attributes).
    vbar, v0, dx_period, x_mu, x_stick_min, overshoot_min, overshoot_max, dx_d, x_d : float
        The fields of the same names (Attributes).
    frac_accumulate, frac_stop, frac_never_stop, frac_undecided : float
        The outcome fractions (Attributes).
    accumulation : str
        "all", "some" or "none" (Attributes).
    s, x0, status, reason, x_end, overshoot, periods, zone_sticks : numpy.ndarray
        Per entry (Attributes).
    first_stick_x, contraction, entry_time, entry_tau, entry_v : numpy.ndarray
        Per entry (Attributes).
    method : str
        The solver the entries ran with (Attributes).

    Attributes
    ----------
    profile : ThreePhaseProfile
        The profile.
    w : float
        The zone width.
    c_mu : float
        The friction ratio of the zone.
    case : int
        The case of Table 1 of the steady state.
    vbar : float
        The steady average velocity (eq. 10).
    v0 : float
        The steady x' at the profile's t = 0.
    dx_period : float
        Delta_x, the largest x over one steady period from x = 0.
    x_mu : float
        Start of the zone, Delta_x.
    x_stick_min : float
        The lowest position a stick holds in the zone (eq. 41), absolute.
    overshoot_min : float
        The smallest end position beyond x_mu over the entries that stop.
    overshoot_max : float
        The largest end position beyond x_mu over the entries that stop.
    dx_d : float
        The positioning error (eq. 39), half the range of the end positions.
    x_d : float
        The middle of the range of end positions of the entries that stop, absolute.
    frac_accumulate : float
        Fraction of the entries that accumulate.
    frac_stop : float
        Fraction at rest for good without accumulation.
    frac_never_stop : float
        Fraction that never stop (periodic or walking).
    frac_undecided : float
        Fraction without an outcome within ``max_periods`` (bounded non-periodic motion).
    accumulation : str
        "all", "some" or "none" of the entries accumulate.
    s : numpy.ndarray
        The offset of each entry.
    x0 : numpy.ndarray
        The start position of each entry, -s.
    status : numpy.ndarray
        Status codes (int8).
    reason : numpy.ndarray
        :class:`~selfalign.Reason` codes (int8).
    x_end : numpy.ndarray
        The end position, or the state where a never-stopping or undecided run was stopped.
    overshoot : numpy.ndarray
        x_end - x_mu (NaN unless the entry stops).
    periods : numpy.ndarray
        The end time of each entry, in periods.
    zone_sticks : numpy.ndarray
        Stick events at x >= x_mu.
    first_stick_x : numpy.ndarray
        Position of the first stick at x >= x_mu (NaN if none).
    contraction : numpy.ndarray
        Ratio of the last two zone-stick increments of an accumulation (NaN otherwise).
    entry_time : numpy.ndarray
        Time of the first arrival at x_mu, in periods.
    entry_tau : numpy.ndarray
        The phase of the first arrival at x_mu.
    entry_v : numpy.ndarray
        The velocity x' at the first arrival at x_mu.
    method : str
        The solver the entries ran with.
    zone : StopZone
        The stop zone (x_mu, w, c_mu).

    See Also
    --------
    positioning : Computes it.

    Examples
    --------
    >>> import selfalign as sa
    >>> profile = sa.ThreePhaseProfile(dt=1.05, dy=0.084, y2=2.2, y3=0.9)
    >>> result = sa.positioning(profile, w=0.05, c_mu=2.5, n_entries=8)
    >>> result.case, result.accumulation, [str(s) for s in (list(sa.Status)[c] for c in result.status[:3])]
    (1, 'some', ['rest', 'accumulation', 'accumulation'])
    >>> result.zone
    StopZone(x_mu=0.0654116..., w=0.05, c_mu=2.5)
    """

    profile: ThreePhaseProfile
    w: float
    c_mu: float
    case: int
    vbar: float
    v0: float
    dx_period: float
    x_mu: float
    x_stick_min: float
    overshoot_min: float
    overshoot_max: float
    dx_d: float
    x_d: float
    frac_accumulate: float
    frac_stop: float
    frac_never_stop: float
    frac_undecided: float
    accumulation: str
    s: np.ndarray
    x0: np.ndarray
    status: np.ndarray
    reason: np.ndarray
    x_end: np.ndarray
    overshoot: np.ndarray
    periods: np.ndarray
    zone_sticks: np.ndarray
    first_stick_x: np.ndarray
    contraction: np.ndarray
    entry_time: np.ndarray
    entry_tau: np.ndarray
    entry_v: np.ndarray
    method: str = ""

    @property
    def zone(self) -> StopZone:
        return StopZone(x_mu=self.x_mu, w=self.w, c_mu=self.c_mu)


@formula(eqs=("39",), kernel=False)
def _summary(status, overshoot):
    """Outcome fractions, overshoot range and Delta_x_d (eq. 39) over the last axis (the entries)."""
    n = status.shape[-1]
    acc = np.count_nonzero(status == ACCUMULATE, axis=-1) / n
    rest = np.count_nonzero(status == REST, axis=-1) / n
    never = np.count_nonzero(status == NEVER_STOPS, axis=-1) / n
    stops = (status == ACCUMULATE) | (status == REST)
    with np.errstate(invalid="ignore"):
        lo = np.where(stops.any(axis=-1), np.where(stops, overshoot, np.inf).min(axis=-1), np.nan)
        hi = np.where(stops.any(axis=-1), np.where(stops, overshoot, -np.inf).max(axis=-1), np.nan)
    return {"frac_accumulate": acc, "frac_stop": rest, "frac_never_stop": never,
            "frac_undecided": 1.0 - acc - rest - never, "overshoot_min": lo, "overshoot_max": hi,
            "dx_d": 0.5 * (hi - lo)}  # eq. (39)


def positioning(profile: ThreePhaseProfile, *, w: float, c_mu: float, n_entries: int = 64, offset: float = 0.5,
                max_periods: int = MAX_PERIODS, accumulation_tol: float = 1e-12,
                friction: FrictionLaw | None = None, ramp: float = 0.0) -> Positioning:
    """Overshoot range, positioning error and outcome of every steady-state entry (Sect. 7.1).

    ``friction``: a :class:`~selfalign.model.friction.FrictionLaw` (default: the paper's Coulomb
    friction); ``ramp``: y'' ramp time of the finite-jerk version of ``profile`` (0: the paper's).
    The entries run with the exact solver where it can simulate them, otherwise with Moreau
    (``setting_method``; ``method`` of the result says which).  ValueError if the profile's
    steady state does not move forward (vbar <= 0): then the mass never reaches the zone.

    Entries (Sect. 7.1, module docstring of ``selfalign.analysis.positioning``): on the
    uniform surface the steady state is x_s(t) with x_s(0) = 0 and x_s'(0) = v0, and every
    steady-state approach to the zone is x_s(t) - s for an offset s in [0, vbar dt).  The
    entries sample s_j = vbar dt (j + offset) / n_entries and start at t = 0 at
    x0s = -s_j with x' = v0, with the zone at x_mu = Delta_x, the largest displacement within
    one steady period: no entry touches the zone before its first period ends, and
    x0s in (-vbar dt, 0] is the paper's range.  Each entry runs until it comes to rest,
    accumulates or never stops, at most ``max_periods`` periods.  Positioning (eqs. 39-41):
    overshoot = x_end - x_mu of the entries that stop (REST, or ACCUMULATION, whose end is
    the limit x_stick_min); Delta_x_d = (max - min) / 2 over them and
    x_d = x_mu + overshoot_min + Delta_x_d.  Entries that never stop (or stay undecided) are
    counted separately and left out of the range (NaN when no entry stops).  Under
    static/kinetic or Stribeck friction or with y'' ramps the steady state has no closed
    form and is simulated.

    Parameters
    ----------
    profile : ThreePhaseProfile
        The table motion.
    w : float
        Width of the body, the transition width (eqs. 7-9); > 0.
    c_mu : float
        Coefficient of the high-friction zone; > 1.
    n_entries : int, optional
        Number of entries (offsets s_j); the entries may need at most 2 GiB.  Default 64.
    offset : float, optional
        Where the sample starts, as a fraction of the sample spacing; in [0, 1).  Results are
        independent of it up to the sampling resolution.  Default 0.5.
    max_periods : int, optional
        Period budget of an entry: entries without an outcome by then are undecided.  At
        most 1e10 entry-periods (n_entries x max_periods).  Default 1000.
    accumulation_tol : float, optional
        An accumulation ends at a stick within this distance of x_stick_min; at most 1e-6 w.
        Default 1e-12.
    friction : FrictionLaw, optional
        The friction law (``selfalign.model.friction.FrictionLaw``; default: the paper's
        Coulomb friction).
    ramp : float, optional
        y'' ramp time of the finite-jerk version of ``profile``; >= 0.  Default 0: the
        paper's profile.

    Returns
    -------
    Positioning
        Scalars: ``case``, ``vbar``, ``v0`` of the steady state; ``dx_period`` = Delta_x =
        ``x_mu``; ``x_stick_min`` (eq. 41, absolute); ``overshoot_min``, ``overshoot_max``
        over the entries that stop; ``dx_d`` (eq. 39), ``x_d``; the fractions
        ``frac_accumulate``, ``frac_stop`` (at rest for good without accumulation),
        ``frac_never_stop`` (periodic or walking), ``frac_undecided`` (no outcome within
        ``max_periods``); ``accumulation``: "all", "some" or "none" of the entries;
        ``method``: the solver the entries ran with.  Per entry (arrays of n_entries):
        ``s``, ``x0``, ``status`` (status codes: the index in ``list(selfalign.Status)``),
        ``reason``, ``x_end``, ``overshoot`` (NaN unless it stops), ``periods``,
        ``zone_sticks``, ``first_stick_x``, ``contraction``, ``entry_time``, ``entry_tau``
        (phase of the first arrival at x_mu) and ``entry_v``.

    Raises
    ------
    TypeError
        If ``profile`` is not a ThreePhaseProfile, ``friction`` is not a FrictionLaw, or
        ``w``, ``c_mu``, ``n_entries``, ``offset``, ``max_periods``, ``accumulation_tol`` or
        ``ramp`` is not a real number.
    ValueError
        If a number is outside its range above or not finite; the entries would need more
        than 2 GiB or 1e10 entry-periods; the ramps do not fit the profile's phases; or the
        steady state does not move forward.

    See Also
    --------
    simulate_batch : Runs the entries.
    stick_map : The closed-form map of the zone sticks (eq. 59).

    Examples
    --------
    The Fig. 18 profile into a zone of width 0.05 at c_mu = 2.5, eight entries:

    >>> import selfalign as sa
    >>> profile = sa.ThreePhaseProfile(dt=1.05, dy=0.084, y2=2.2, y3=0.9)
    >>> result = sa.positioning(profile, w=0.05, c_mu=2.5, n_entries=8)
    >>> print(f"{result.dx_d:.3g}", result.frac_accumulate, result.frac_stop, result.accumulation)
    0.000675 0.75 0.25 some
    >>> print(round(result.x_mu, 6), round(result.x_stick_min, 6), round(result.x_d, 6))
    0.065412 0.105412 0.106086
    >>> result.method
    'exact (event-driven, closed-form arcs)'
    """
    return _positioning(profile, w, c_mu, n_entries, offset, max_periods, accumulation_tol, np.empty(0),
                        friction, ramp)[1]


def _friction(friction) -> FrictionLaw:
    friction = FrictionLaw() if friction is None else friction
    if not isinstance(friction, FrictionLaw):
        raise TypeError(f"friction must be a FrictionLaw, got {friction!r}")
    return friction


def _positioning(profile, w, c_mu, n_entries, offset, max_periods, accumulation_tol, levels, friction=None,
                 ramp=0.0):
    """(per-entry runs of the one setting, Positioning) with the level crossings of ``levels``."""
    if not isinstance(profile, ThreePhaseProfile):
        raise TypeError(f"positioning needs a ThreePhaseProfile, got {type(profile).__name__}")
    _check_zone(w, c_mu, n_entries, offset, max_periods, ramp, accumulation_tol, 1, levels.size)
    arrays = [np.array([v]) for v in (profile.dt, profile.dy, profile.y2, profile.y3)]
    if ramp > 0.0:
        setting_profile(*(float(a[0]) for a in arrays), float(ramp))  # raises if the ramps do not fit
    ss, idx, runs, method = _simulate_settings(*arrays, float(w), float(c_mu), int(n_entries), float(offset),
                                               int(max_periods), float(accumulation_tol), levels, 1, "quiet",
                                               _friction(friction), float(ramp))
    if idx.size == 0:
        raise ValueError(f"the steady state of {profile!r} does not move forward (vbar = {float(ss.vbar[0])!r}, "
                         f"case {int(ss.case[0])}): the mass never reaches the zone")
    r = {key: val[0] for key, val in runs.items()}
    summ = {key: float(val[0]) for key, val in _summary(runs["status"], runs["overshoot"]).items()}
    x_mu = float(r["dx_period"])
    stops = (r["status"] == ACCUMULATE) | (r["status"] == REST)
    frac = summ["frac_accumulate"]
    return r, Positioning(
        profile=profile, w=float(w), c_mu=float(c_mu), case=int(ss.case[0]), vbar=float(ss.vbar[0]),
        v0=float(ss.v0[0]), dx_period=x_mu, x_mu=x_mu, x_stick_min=x_mu + float(r["x_stick_min_rel"]),
        x_d=x_mu + summ["overshoot_min"] + summ["dx_d"],
        accumulation="all" if frac == 1 else "some" if frac else "none",
        s=r["s"], x0=-r["s"], status=r["status"], reason=r["reason"], x_end=x_mu + r["overshoot"],
        overshoot=np.where(stops, r["overshoot"], np.nan), periods=r["periods"], zone_sticks=r["zone_sticks"],
        first_stick_x=x_mu + r["first_stick_x"],
        contraction=r["contraction"], entry_time=r["entry_time"], entry_tau=r["entry_tau"], entry_v=r["entry_v"],
        method=method,
        **{key: summ[key] for key in ("overshoot_min", "overshoot_max", "dx_d", "frac_accumulate", "frac_stop",
                                      "frac_never_stop", "frac_undecided")},
    )


@dataclass(frozen=True)
class PositioningGrid:
    """Positioning over a grid of three-phase settings (Fig. 17); arrays shaped like the inputs.

    Steady state: ``case``, ``vbar``, ``f``.  Where the mass moves forward
    (``moving``: case > 0 and vbar > 0), relative to x_mu = Delta_x
    (``dx_period``): ``x_stick_min`` (eq. 41, minus x_mu), ``overshoot_min``,
    ``overshoot_max``, ``overshoot`` (shape (..., n_entries): each entry's end minus x_mu in the
    order of its offset s, NaN where it does not stop), ``dx_d`` (eq. 39), ``x_d`` (minus x_mu), the outcome
    fractions, ``contraction`` (median over accumulating entries) and, for each
    level p of ``levels``, the worst case over accumulating entries of the
    time to reach x_mu + p (x_stick_min - x_mu) in periods from the start
    (``level_from_start``), from the entry (``level_from_entry``), from the
    first zone stick (``level_from_first_stick``) and the number of zone
    sticks before it (``level_sticks``), shape (..., L).  NaN elsewhere.
    ``events``: total solver events; ``method``: the solver the entries ran with.
    """

    case: np.ndarray
    vbar: np.ndarray
    f: np.ndarray
    moving: np.ndarray
    dx_period: np.ndarray
    x_stick_min: np.ndarray
    overshoot_min: np.ndarray
    overshoot_max: np.ndarray
    overshoot: np.ndarray
    dx_d: np.ndarray
    x_d: np.ndarray
    frac_accumulate: np.ndarray
    frac_stop: np.ndarray
    frac_never_stop: np.ndarray
    frac_undecided: np.ndarray
    contraction: np.ndarray
    levels: np.ndarray
    level_from_start: np.ndarray
    level_from_entry: np.ndarray
    level_from_first_stick: np.ndarray
    level_sticks: np.ndarray
    n_entries: int
    events: int
    method: str = ""


def positioning_grid(dt, dy, y2, y3, *, w: float, c_mu: float, n_entries: int = 64, offset: float = 0.5,
                     max_periods: int = MAX_PERIODS, accumulation_tol: float = 1e-12, levels=(),
                     processes: int = 1, progress: str = "auto", friction: FrictionLaw | None = None,
                     ramp: float = 0.0) -> PositioningGrid:
    """:func:`positioning` for broadcast arrays of (dt, dy, y2, y3) with the batched solver
    (``friction``, ``ramp`` and the method as in :func:`positioning`; settings whose ramps do not
    fit count as not moving).

    ``levels``: fractions p in (0, 1) for the accumulation speed; ``processes``
    > 1 splits the settings over that many worker processes.  ``progress``: how the
    settings done are reported (:mod:`selfalign.progress`: "auto", "bar", "log", "quiet").
    """
    levels = _check_levels(levels) if np.size(levels) else np.empty(0)
    processes = check_integer("processes", processes, 1, 1024)
    resolve_mode(progress)
    arrays = check_parameters(dt, dy, y2, y3)
    _check_zone(w, c_mu, n_entries, offset, max_periods, ramp, accumulation_tol, arrays[0].size, levels.size)
    shape = arrays[0].shape
    flat = [a.ravel() for a in arrays]
    ss, idx, runs, method = _simulate_settings(*flat, float(w), float(c_mu), int(n_entries), float(offset),
                                               int(max_periods), float(accumulation_tol), levels, int(processes),
                                               progress, _friction(friction), float(ramp))
    size, nl = flat[0].size, levels.size

    def scatter(values, extra=()):
        out = np.full((size,) + extra, np.nan)
        out[idx] = values
        return out.reshape(shape + extra)

    summ = _summary(runs["status"], runs["overshoot"])
    acc = runs["status"] == ACCUMULATE
    any_acc = acc.any(axis=1)
    # Median over the accumulating entries (a sorted masked row: NaNs sort last).
    k = np.count_nonzero(acc, axis=1)
    ordered = np.sort(np.where(acc, runs["contraction"], np.nan), axis=1)
    rows = np.arange(k.size)
    lo_mid, hi_mid = np.maximum((k - 1) // 2, 0), np.maximum(k // 2, 0)
    contraction = np.where(any_acc, 0.5 * (ordered[rows, lo_mid] + ordered[rows, hi_mid]), np.nan)

    def worst(values):
        v = np.where(acc[:, :, None], values, -np.inf).max(axis=1)
        return np.where(any_acc[:, None], v, np.nan)

    lt = runs["level_time"]
    return PositioningGrid(
        case=ss.case.reshape(shape), vbar=ss.vbar.reshape(shape), f=ss.f.reshape(shape),
        moving=np.isin(np.arange(size), idx).reshape(shape), dx_period=scatter(runs["dx_period"]),
        x_stick_min=scatter(runs["x_stick_min_rel"]), x_d=scatter(summ["overshoot_min"] + summ["dx_d"]),
        overshoot=scatter(np.where(np.isin(runs["status"], (ACCUMULATE, REST)), runs["overshoot"], np.nan),
                          (int(n_entries),)),
        contraction=scatter(contraction), levels=levels,
        level_from_start=scatter(worst(lt), (nl,)),
        level_from_entry=scatter(worst(lt - runs["entry_time"][:, :, None]), (nl,)),
        level_from_first_stick=scatter(worst(lt - runs["first_stick_time"][:, :, None]), (nl,)),
        level_sticks=scatter(worst(runs["level_sticks"].astype(float)), (nl,)),
        n_entries=int(n_entries), events=int(runs["events"].sum()), method=method,
        **{key: scatter(summ[key]) for key in ("overshoot_min", "overshoot_max", "dx_d", "frac_accumulate",
                                               "frac_stop", "frac_never_stop", "frac_undecided")},
    )


@dataclass(frozen=True)
class AccumulationSpeed:
    """How fast accumulating entries approach x_stick_min (Sect. 7.3, the p-claim).

    ``p`` (L,): the levels; per entry (n_entries, L), NaN for entries that do
    not accumulate: ``from_start`` (periods from t = 0, the run start with
    x0s in (-vbar dt, 0] and x_mu = Delta_x), ``from_entry`` (periods from the
    first arrival at x_mu), ``from_first_stick`` (periods from the first stick
    in the zone, x_1), ``sticks`` (zone sticks before the level: iterations of
    the map after x_1).  ``worst_*`` (L,): their maxima over the accumulating
    entries.  ``map_iterations`` (L,): iterations of eq. (59) from x_0 = x_mu
    until x_k >= level (NaN if eq. 59 is not valid along the way);
    ``positioning``: the underlying :class:`Positioning`.
    """

    p: np.ndarray
    from_start: np.ndarray
    from_entry: np.ndarray
    from_first_stick: np.ndarray
    sticks: np.ndarray
    map_iterations: np.ndarray
    positioning: Positioning

    def _worst(self, values):
        acc = self.positioning.status == ACCUMULATE
        return np.where(acc.any(), np.where(acc[:, None], values, -np.inf).max(axis=0), np.nan)

    @property
    def worst_from_start(self):
        return self._worst(self.from_start)

    @property
    def worst_from_entry(self):
        return self._worst(self.from_entry)

    @property
    def worst_from_first_stick(self):
        return self._worst(self.from_first_stick)

    @property
    def worst_sticks(self):
        return self._worst(self.sticks)


def map_iterations(profile: ThreePhaseProfile, *, w: float, c_mu: float, x_mu: float, p, max_iter: int = 1000):
    """Iterations of eq. (59) from x_0 = x_mu until x_k >= x_mu + p (x_f - x_mu), per level p.

    x_f is the fixed point (eq. 60).  NaN where eq. (59) is invalid at an
    iterate before the level is reached (``stick_map_validity``) or the
    level is not reached within ``max_iter`` iterations.
    """
    p = _check_levels(p)
    fixed = x_mu + level_position(profile.y2, w, c_mu)
    target = x_mu + p * (fixed - x_mu)
    out = np.full(p.size, np.nan)
    x = x_mu
    for k in range(max_iter + 1):
        newly = np.isnan(out) & (x >= target)
        out[newly] = k
        if not np.isnan(out).any():
            break
        if not stick_map_validity(x, profile, w=w, c_mu=c_mu, x_mu=x_mu).valid:
            break
        x = float(stick_map(x, profile, w=w, c_mu=c_mu, x_mu=x_mu))
    return out


def accumulation_speed(profile: ThreePhaseProfile, *, w: float, c_mu: float, p=(0.99, 0.999),
                       n_entries: int = 64, offset: float = 0.5, max_periods: int = MAX_PERIODS,
                       accumulation_tol: float = 1e-12) -> AccumulationSpeed:
    """Times at which the steady-state entries reach x_mu + p (x_stick_min - x_mu) (Sect. 7.3)."""
    levels = _check_levels(p)
    r, pos = _positioning(profile, w, c_mu, n_entries, offset, max_periods, accumulation_tol, levels)
    acc = (r["status"] == ACCUMULATE)[:, None]
    lt = r["level_time"]
    keep = lambda a: np.where(acc, a, np.nan)  # noqa: E731
    return AccumulationSpeed(
        p=levels, from_start=keep(lt), from_entry=keep(lt - r["entry_time"][:, None]),
        from_first_stick=keep(lt - r["first_stick_time"][:, None]), sticks=keep(r["level_sticks"].astype(float)),
        map_iterations=map_iterations(profile, w=w, c_mu=c_mu, x_mu=pos.x_mu, p=levels), positioning=pos,
    )
