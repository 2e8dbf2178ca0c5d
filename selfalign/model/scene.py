"""Declarative scenes: what to simulate, and nothing more.

A scene names the table motion, the surface, the start state, the horizon,
the solver and what to record.  Scene files (YAML) are read and validated by
:mod:`selfalign.io.scene_files`.
"""

from __future__ import annotations

from dataclasses import dataclass, field

from .errors import SceneError, check_finite, check_integer
from .friction import FrictionLaw, StopZone, Uniform
from .parts import Part, check_parts, check_restitution, parts_friction_ratio
from .planar import PlanarProfile, Strip, check_planar_state, check_strips
from .profiles import Profile
from .units import SIScale

#: Series a scene may ask to record; "t" comes with any of them.
SERIES = ("x", "v", "y", "yd", "ydd", "friction", "mode")
#: Series a planar scene may ask to record (x and v of shape (n, 2)).
PLANAR_SERIES = ("x", "v", "mode")
#: Largest number of dense-output samples per period.
MAX_SAMPLES_PER_PERIOD = 10_000_000
#: A recording larger than this (bytes, estimated before the run) is refused.
RECORD_MEMORY_LIMIT = 2 * 1024**3
METHODS = ("exact", "moreau", "ivp")


@dataclass(frozen=True)
class Record:
    """What a run stores besides the end state.

    ``series`` are sampled ``samples_per_period`` times per period (plus
    every event) — empty means no dense output at all; ``events`` keeps the
    event log; ``arcs`` keeps the exact solver's arcs; ``rerun`` writes a rerun
    recording of the series.  The time ``t`` comes with any series.

    Parameters
    ----------
    series : tuple of str, optional
        Names of the series to record, from "x", "v", "y", "yd", "ydd", "friction" and
        "mode" (``selfalign.model.scene.SERIES``).  Default (): no dense output.
    samples_per_period : int, optional
        Dense-output samples per period; an integer in [2, 10,000,000] (an integral float
        is accepted).  Default 200.
    events : bool, optional
        Keep the event log (``Trajectory.events``).  Default False.
    arcs : bool, optional
        Keep the exact solver's arcs.  Default False.
    rerun : bool, optional
        Write a rerun recording of the series; needs at least one series.  Default False.

    Attributes
    ----------
    dense : bool
        True when ``series`` is not empty (the run has dense output).

    Raises
    ------
    TypeError
        If ``samples_per_period`` is not a real number.
    SceneError
        If a series is unknown, ``samples_per_period`` is not an integer in
        [2, 10,000,000], a flag is not a bool, or ``rerun`` is asked without a series.

    See Also
    --------
    Scene : Takes the record in ``record``.
    Trajectory : Holds what was recorded.

    Examples
    --------
    >>> import selfalign as sa
    >>> record = sa.Record(series=("x", "v"), samples_per_period=50, events=True)
    >>> record.dense, record.samples_per_period
    (True, 50)
    >>> sa.Record(series=("acceleration",))
    Traceback (most recent call last):
    ...
    selfalign.model.errors.SceneError: record.series: unknown series ['acceleration']; allowed: [...]
    """

    series: tuple[str, ...] = ()
    samples_per_period: int = 200
    events: bool = False
    arcs: bool = False
    rerun: bool = False

    def __post_init__(self):
        unknown = [s for s in self.series if s not in SERIES]
        if unknown:
            raise SceneError(f"record.series: unknown series {unknown}; allowed: {list(SERIES)}")
        try:
            spp = check_integer("record.samples_per_period", self.samples_per_period, 2, MAX_SAMPLES_PER_PERIOD)
        except ValueError as exc:
            raise SceneError(str(exc)) from None
        object.__setattr__(self, "samples_per_period", spp)
        for key in ("events", "arcs", "rerun"):
            if not isinstance(getattr(self, key), bool):
                raise SceneError(f"record.{key} must be true or false, got {getattr(self, key)!r}")
        if self.rerun and not self.series:
            raise SceneError("record.rerun needs at least one entry in record.series")

    @property
    def dense(self) -> bool:
        return bool(self.series)


@dataclass(frozen=True)
class Scene:
    """A validated simulation scene (dimensionless units of Sect. 3.2).

    ``x0``, ``v0`` are the relative position and velocity at time
    ``phase * dt`` (phase in [0, 1)); the horizon is ``periods`` periods or,
    with ``until="rest"``, until the run reaches a final outcome (at rest for
    good, accumulation, never stops) but at most ``max_periods`` periods.
    A scene names the table motion, the surface, the start state, the horizon,
    the solver and what to record, and nothing more; scene files (YAML) are read
    and validated by :func:`~selfalign.load_scene`.  A Scene is immutable; its
    ``replace`` method makes a validated copy.

    Parameters
    ----------
    profile : Profile or PlanarProfile
        The table motion y(t), e.g. a :class:`~selfalign.ThreePhaseProfile` (any profile of
        ``selfalign.model.profiles``), or a :class:`~selfalign.PlanarProfile` for motion in the plane
        (docs/explanation/planar-model.md).
    surface : Uniform, StopZone, Strip or list of Strip, optional
        The friction field mu_bar(x) of the table (Sect. 3.3).  Default ``Uniform()``.  A planar scene takes
        ``Uniform()``, a :class:`~selfalign.Strip` or a list of them (stored as a tuple; friction is the
        largest of the strips'); a 1-D scene ``Uniform()`` or a ``StopZone``.
    friction : FrictionLaw, optional
        The friction law (``selfalign.model.friction.FrictionLaw``): the paper's Coulomb
        friction by default, or static/kinetic or Stribeck friction.
    x0 : float or tuple of float, optional
        Relative position at time ``phase * dt``; finite; a pair (x, y) in a planar scene (stored as a
        tuple; 0 stands for (0, 0)).  Default 0.
    v0 : float or tuple of float, optional
        Relative velocity x' at time ``phase * dt``; finite; a pair in a planar scene.  Default 0.
    phase : float, optional
        Start time as a fraction of the period, in [0, 1).  Default 0.
    periods : int, optional
        Simulate this many periods (an integer in [1, 2**53]); excludes ``until="rest"``.
    until : str, optional
        "rest": run until a final outcome, at most ``max_periods`` periods; "periods" (the
        default when ``periods`` is given): ``periods`` periods.
    max_periods : int, optional
        The horizon of ``until="rest"``; an integer in [1, 2**53].  Default 10000.
    method : str, optional
        The solver :func:`~selfalign.simulate` uses by default: "exact" (the default),
        "moreau" or "ivp".
    solver_options : dict, optional
        Options of ``method`` (``selfalign.solvers.methods``), checked when the scene is
        simulated or loaded from a file.  Default: none.
    record : Record, optional
        What the run stores besides the end state.  Default ``Record()``: the end state only.
    name : str, optional
        The scene's name (a scene file's stem).  Default "scene".
    si : SIScale, optional
        The SI scale of a scene file given in SI units.
    description : str, optional
        Free text.
    parts : list or tuple of Part, optional
        Several parts on the table instead of the paper's one (:class:`~selfalign.Part`, the rear-most first,
        not overlapping; docs/explanation/several-parts.md): each carries its own start x0, v0, so the
        scene's ``x0`` and ``v0`` stay 0, and on a stop zone each part's width must be the zone's body width
        ``w``.  The friction law is Coulomb's or static/kinetic, and nothing is recorded besides the end
        state (and, with the exact solver, the events per part).  Stored as a tuple.  Default None: the
        paper's single part.
    restitution : float, optional
        Newton's coefficient of restitution e in [0, 1] of the contacts between ``parts`` (0 plastic, 1
        elastic).  Default 0.

    Attributes
    ----------
    horizon_periods : int
        Number of periods to simulate at most: ``periods``, or ``max_periods`` with
        ``until="rest"``.
    planar : bool
        True when the profile is a :class:`~selfalign.PlanarProfile`.
    strips : tuple of Strip
        The strips of a planar scene's surface (empty on a uniform surface, and in a 1-D scene).

    Raises
    ------
    TypeError
        If ``profile``, ``surface``, ``friction``, ``record``, ``si``, ``solver_options`` or
        ``parts`` has the wrong type, or ``x0``, ``v0``, ``phase``, ``periods``, ``max_periods`` or
        ``restitution`` is not a real number.
    SceneError
        If ``x0``, ``v0`` or ``phase`` is not finite or ``phase`` lies outside [0, 1); the
        horizon is missing, gives both ``periods`` and ``until="rest"``, or its counts are
        not integers in [1, 2**53]; ``method`` is unknown; the recording would need more
        than 2 GiB; ``parts`` is empty, overlapping, or comes with a start, friction law or record it
        cannot have; or ``restitution`` lies outside [0, 1] or comes without ``parts``; or a planar
        scene has a 1-D start, a stop zone, Stribeck friction, parts, or a record of series other than
        x, v and mode (arcs and rerun included), or a 1-D scene has a pair as start or strips.

    See Also
    --------
    simulate : Simulates a scene.
    load_scene : Reads a scene from a YAML file.
    scene_from_dict : Builds a scene from a mapping in the YAML layout.

    Examples
    --------
    The Fig. 18 profile entering a stop zone, run until a final outcome:

    >>> import selfalign as sa
    >>> profile = sa.ThreePhaseProfile(dt=1.05, dy=0.084, y2=2.2, y3=0.9)
    >>> scene = sa.Scene(profile, sa.StopZone(x_mu=0.5, w=0.05, c_mu=2.5), until="rest", max_periods=1000)
    >>> scene.until, scene.horizon_periods
    ('rest', 1000)
    >>> scene.to_dict()["horizon"]
    {'until': 'rest', 'max_periods': 1000}
    >>> scene.replace(x0=0.1).x0
    0.1
    """

    profile: Profile | PlanarProfile
    surface: Uniform | StopZone | Strip | tuple[Strip, ...] = field(default_factory=Uniform)
    friction: FrictionLaw = field(default_factory=FrictionLaw)
    x0: float | tuple[float, float] = 0.0
    v0: float | tuple[float, float] = 0.0
    phase: float = 0.0
    periods: int | None = None
    until: str | None = None
    max_periods: int = 10_000
    method: str = "exact"
    solver_options: dict = field(default_factory=dict)
    record: Record = field(default_factory=Record)
    name: str = "scene"
    si: SIScale | None = None
    description: str = ""
    parts: tuple[Part, ...] | None = None
    restitution: float = 0.0

    def __post_init__(self):
        for key, kind, allowed in (("profile", (Profile, PlanarProfile), "a selfalign profile or a PlanarProfile"),
                                   ("friction", FrictionLaw, "a FrictionLaw"), ("record", Record, "a Record"),
                                   ("si", (SIScale, type(None)), "an SIScale or None"),
                                   ("solver_options", dict, "a mapping of solver options")):
            if not isinstance(getattr(self, key), kind):
                raise TypeError(f"{key} must be {allowed}, got {type(getattr(self, key)).__name__}")
        keys = ("phase",) if self.planar else ("x0", "v0", "phase")
        if self.planar:
            self._check_planar()
        elif not isinstance(self.surface, (Uniform, StopZone)):
            raise TypeError(f"surface must be Uniform() or StopZone(...), got {self.surface!r:.80}"
                            + ("; strips need a PlanarProfile (use StopZone in 1-D)"
                               if isinstance(self.surface, (Strip, list, tuple)) else ""))
        for key in keys:
            try:
                object.__setattr__(self, key, check_finite(key, getattr(self, key)))
            except ValueError as exc:
                raise SceneError(str(exc)) from None
        if not 0.0 <= self.phase < 1.0:
            raise SceneError(f"phase must lie in [0, 1) (fraction of the period), got {self.phase!r}")
        until = self.until or ("periods" if self.periods is not None else None)
        if until not in ("periods", "rest"):
            raise SceneError(f"horizon: give periods=N or until='rest', got until={self.until!r}")
        if until == "rest" and self.periods is not None:
            raise SceneError("horizon: periods and until='rest' exclude each other; use max_periods")
        try:
            if until == "periods":
                object.__setattr__(self, "periods", check_integer("horizon.periods", self.periods))
            object.__setattr__(self, "max_periods", check_integer("horizon.max_periods", self.max_periods))
        except ValueError as exc:
            raise SceneError(str(exc)) from None
        object.__setattr__(self, "until", until)
        if self.method not in METHODS:
            raise SceneError(f"solver.method must be one of {list(METHODS)}, got {self.method!r}")
        self._check_parts()
        if self.record.dense:
            size = self.horizon_periods * self.record.samples_per_period * (1 + len(self.record.series)) * 8
            if size > RECORD_MEMORY_LIMIT:
                raise SceneError(f"record: {len(self.record.series)} series at {self.record.samples_per_period} "
                                 f"samples per period over {self.horizon_periods} periods need about "
                                 f"{size / 1024**3:.3g} GiB, more than the {RECORD_MEMORY_LIMIT / 1024**3:g} GiB "
                                 "allowed; record fewer periods or samples")

    def _check_planar(self) -> None:
        """Validate and store the start and surface of a planar scene; SceneError for what it cannot have."""
        if isinstance(self.surface, StopZone):
            raise SceneError("surface: a planar scene takes strips, not a StopZone: Strip(normal=(1, 0), x_mu, w, "
                             "c_mu) is the stop zone along the first axis")
        strips = check_strips(self.surface)
        if not isinstance(self.surface, (Uniform, Strip)):
            object.__setattr__(self, "surface", strips)
        for key in ("x0", "v0"):
            value = getattr(self, key)
            try:
                pair = (0.0, 0.0) if isinstance(value, (int, float)) and not isinstance(value, bool) and value == 0 \
                    else check_planar_state(key, value)
            except ValueError as exc:
                raise SceneError(str(exc)) from None
            object.__setattr__(self, key, pair)
        if self.friction.stribeck:
            raise SceneError("friction.kind: stribeck is not simulated in the plane; use coulomb or static_kinetic")
        if self.parts is not None:
            raise SceneError("parts: several parts move along one line; a planar scene has one part")
        if set(self.record.series) - set(PLANAR_SERIES) or self.record.arcs or self.record.rerun:
            raise SceneError(f"record: a planar scene records the series {list(PLANAR_SERIES)} and events (no arcs, "
                             f"no rerun recording of a run; the planar stage writes its own), got series "
                             f"{list(self.record.series)}, arcs {self.record.arcs}, rerun {self.record.rerun}")

    @property
    def planar(self) -> bool:
        """True when the table moves in the plane (a PlanarProfile)."""
        return isinstance(self.profile, PlanarProfile)

    @property
    def strips(self) -> tuple:
        """The strips of a planar scene's surface (empty on a uniform surface and in 1-D)."""
        return check_strips(self.surface) if self.planar else ()

    def _check_parts(self) -> None:
        """SceneError unless ``parts`` and ``restitution`` are consistent with the rest of the scene."""
        try:
            object.__setattr__(self, "restitution", check_restitution(self.restitution))
            if self.parts is not None:
                object.__setattr__(self, "parts", check_parts(self.parts))
        except ValueError as exc:
            raise SceneError(str(exc)) from None
        if self.parts is None:
            if self.restitution != 0.0:
                raise SceneError(f"restitution = {self.restitution!r} acts between parts: give parts=[Part(...), ...]")
            return
        if self.x0 != 0.0 or self.v0 != 0.0:
            raise SceneError("x0, v0: with parts each Part carries its own start (Part(x0, v0, ...)); leave the "
                             "scene's x0 and v0 at 0")
        try:
            parts_friction_ratio(self.friction)
        except ValueError as exc:
            raise SceneError(str(exc)) from None
        if self.record != Record():
            raise SceneError("record: a scene with parts keeps the end state only (Record())")
        if isinstance(self.surface, StopZone):
            for i, part in enumerate(self.parts):
                if part.width != self.surface.w:
                    raise SceneError(f"parts[{i}].width = {part.width!r}: on a stop zone every part's width is the "
                                     f"zone's body width w = {self.surface.w!r} (eq. 7: the transition width is "
                                     f"the body width)")

    @property
    def horizon_periods(self) -> int:
        """Number of periods to simulate at most."""
        return int(self.periods) if self.until == "periods" else int(self.max_periods)

    def to_dict(self) -> dict:
        """The scene as a plain dict in the YAML layout (dimensionless units)."""
        out = {"name": self.name, "profile": _profile_dict(self.profile)}
        if self.description:
            out["description"] = self.description
        if isinstance(self.surface, StopZone):
            out["surface"] = {"kind": "stop_zone", "x_mu": self.surface.x_mu, "c_mu": self.surface.c_mu}
            out["body"] = {"width": self.surface.w}
        elif self.strips:
            out["surface"] = {"kind": "strips", "strips": [{"normal": list(s.normal), "x_mu": s.x_mu, "w": s.w,
                                                            "c_mu": s.c_mu} for s in self.strips]}
        else:
            out["surface"] = {"kind": "uniform"}
        if self.friction.kind != "coulomb":
            out["friction"] = self.friction.params()
        out["start"] = {"x0": list(self.x0) if self.planar else self.x0,
                        "v0": list(self.v0) if self.planar else self.v0, "phase": self.phase}
        out["horizon"] = ({"periods": int(self.periods)} if self.until == "periods"
                          else {"until": "rest", "max_periods": int(self.max_periods)})
        out["solver"] = {"method": self.method, "options": dict(self.solver_options)}
        out["record"] = {"series": list(self.record.series),
                         "samples_per_period": int(self.record.samples_per_period),
                         "events": bool(self.record.events), "arcs": bool(self.record.arcs),
                         "rerun": bool(self.record.rerun)}
        if self.si is not None:
            out["si"] = {"mu": self.si.mu, "g": self.si.g, "L": self.si.L}
        if self.parts is not None:
            del out["start"]["x0"], out["start"]["v0"], out["record"]
            out["parts"] = [{"x0": p.x0, "v0": p.v0, "width": p.width, "mass": p.mass,
                             "friction_factor": p.friction_factor} for p in self.parts]
            out["restitution"] = self.restitution
        return out

    def replace(self, **changes) -> "Scene":
        """A copy with some fields changed (validated again)."""
        from dataclasses import replace

        return replace(self, **changes)


def _profile_dict(profile) -> dict:
    """A profile's block of a scene file: its defining parameters (a planar profile's components nested)."""
    if isinstance(profile, PlanarProfile):
        out = {"kind": "planar", "x": _profile_dict(profile.x)}
        if profile.y is not None:
            out["y"] = _profile_dict(profile.y)
        return {**out, "offset": profile.offset, "angle": profile.angle}
    return {k: v for k, v in profile.params().items()
            if k in ("kind", "dt", "dy", "y2", "y3", "ramp", "jerk", "forward_fraction", "cos_coeffs", "sin_coeffs")}
