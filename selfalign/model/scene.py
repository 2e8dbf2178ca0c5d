"""Declarative scenes: what to simulate, and nothing more.

A scene names the table motion, the surface, the start state, the horizon,
the solver and what to record.  Scene files (YAML) are read and validated by
:mod:`selfalign.io.scene_files`.
"""

from __future__ import annotations

from dataclasses import dataclass, field

from .errors import SceneError, check_finite
from .friction import StopZone, Uniform
from .profiles import Profile
from .units import SIScale

#: Series a scene may ask to record; "t" comes with any of them.
SERIES = ("x", "v", "y", "yd", "ydd", "friction", "mode")
METHODS = ("exact", "moreau", "ivp")


@dataclass(frozen=True)
class Record:
    """What a run stores besides the end state.

    ``series`` are sampled ``samples_per_period`` times per period (plus
    every event) — empty means no dense output at all; ``events`` keeps the
    event log; ``rerun`` writes a rerun recording of the series.
    """

    series: tuple[str, ...] = ()
    samples_per_period: int = 200
    events: bool = False
    rerun: bool = False

    def __post_init__(self):
        unknown = [s for s in self.series if s not in SERIES]
        if unknown:
            raise SceneError(f"record.series: unknown series {unknown}; allowed: {list(SERIES)}")
        if int(self.samples_per_period) < 2:
            raise SceneError(f"record.samples_per_period must be >= 2, got {self.samples_per_period!r}")
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
    """

    profile: Profile
    surface: Uniform | StopZone = field(default_factory=Uniform)
    x0: float = 0.0
    v0: float = 0.0
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

    def __post_init__(self):
        if not isinstance(self.profile, Profile):
            raise SceneError(f"profile must be a selfalign profile, got {type(self.profile).__name__}")
        if not isinstance(self.surface, (Uniform, StopZone)):
            raise SceneError(f"surface must be Uniform() or StopZone(...), got {type(self.surface).__name__}")
        for key in ("x0", "v0", "phase"):
            try:
                object.__setattr__(self, key, check_finite(key, getattr(self, key)))
            except ValueError as exc:
                raise SceneError(str(exc)) from None
        if not 0.0 <= self.phase < 1.0:
            raise SceneError(f"phase must lie in [0, 1) (fraction of the period), got {self.phase!r}")
        until = self.until or ("periods" if self.periods is not None else None)
        if until not in ("periods", "rest"):
            raise SceneError(f"horizon: give periods=N or until='rest', got until={self.until!r}")
        if until == "periods" and (self.periods is None or int(self.periods) < 1 or self.periods != int(self.periods)):
            raise SceneError(f"horizon.periods must be an integer >= 1, got {self.periods!r}")
        if until == "rest" and self.periods is not None:
            raise SceneError("horizon: periods and until='rest' exclude each other; use max_periods")
        if int(self.max_periods) < 1:
            raise SceneError(f"horizon.max_periods must be >= 1, got {self.max_periods!r}")
        object.__setattr__(self, "until", until)
        if self.method not in METHODS:
            raise SceneError(f"solver.method must be one of {list(METHODS)}, got {self.method!r}")

    @property
    def horizon_periods(self) -> int:
        """Number of periods to simulate at most."""
        return int(self.periods) if self.until == "periods" else int(self.max_periods)

    def to_dict(self) -> dict:
        """The scene as a plain dict in the YAML layout (dimensionless units)."""
        profile = {k: v for k, v in self.profile.params().items()
                   if k in ("kind", "dt", "dy", "y2", "y3", "forward_fraction", "cos_coeffs", "sin_coeffs")}
        out = {"name": self.name, "profile": profile}
        if self.description:
            out["description"] = self.description
        if isinstance(self.surface, StopZone):
            out["surface"] = {"kind": "stop_zone", "x_mu": self.surface.x_mu, "c_mu": self.surface.c_mu}
            out["body"] = {"width": self.surface.w}
        else:
            out["surface"] = {"kind": "uniform"}
        out["start"] = {"x0": self.x0, "v0": self.v0, "phase": self.phase}
        out["horizon"] = ({"periods": int(self.periods)} if self.until == "periods"
                          else {"until": "rest", "max_periods": int(self.max_periods)})
        out["solver"] = {"method": self.method, "options": dict(self.solver_options)}
        out["record"] = {"series": list(self.record.series),
                         "samples_per_period": int(self.record.samples_per_period),
                         "events": bool(self.record.events), "rerun": bool(self.record.rerun)}
        if self.si is not None:
            out["si"] = {"mu": self.si.mu, "g": self.si.g, "L": self.si.L}
        return out

    def replace(self, **changes) -> "Scene":
        """A copy with some fields changed (validated again)."""
        from dataclasses import replace

        return replace(self, **changes)
