"""Declarative scenes: what to simulate, and nothing more.

A scene names the table motion, the surface, the start state, the horizon,
the solver and what to record.  :func:`load_scene` validates a YAML file
against ``schemas/scene.schema.yaml`` (shared with the Snakemake config) and
then checks the physics (feasible profile, finite numbers), raising
:class:`SceneError` with a one-line message naming the file and the key.
"""

from __future__ import annotations

import math
from dataclasses import dataclass, field
from functools import lru_cache
from importlib import resources
from pathlib import Path

from .errors import NonPhysicalProfile, SceneError, check_finite
from .friction import StopZone, Uniform
from .profiles import FourierProfile, PolynomialProfile, Profile, ThreePhaseProfile
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


@lru_cache(maxsize=1)
def scene_schema() -> dict:
    """The JSON schema of a scene file (also used by the Snakemake config)."""
    import yaml

    text = resources.files("selfalign").joinpath("schemas/scene.schema.yaml").read_text()
    return yaml.safe_load(text)


def _key(path) -> str:
    return ".".join(str(p) for p in path) or "<top level>"


def _non_finite(data, path=()):
    """First (path, value) holding a NaN or infinity, or None."""
    if isinstance(data, dict):
        items = data.items()
    elif isinstance(data, list):
        items = enumerate(data)
    else:
        if isinstance(data, float) and not math.isfinite(data):
            return path, data
        return None
    for key, value in items:
        found = _non_finite(value, path + (key,))
        if found:
            return found
    return None


def schema_error_message(error) -> str:
    """One line for a jsonschema error: key, problem and what is allowed."""
    key = _key(error.absolute_path)
    kind = error.validator
    if kind == "additionalProperties":
        allowed = sorted(error.schema.get("properties", {}))
        extra = sorted(set(error.instance) - set(allowed))
        return f"{key}: unknown key {', '.join(map(repr, extra))}; allowed: {', '.join(allowed)}"
    if kind == "required":
        return f"{key}: {error.message}"
    if kind == "type":
        return f"{key}: expected {error.validator_value}, got {type(error.instance).__name__} {error.instance!r}"
    if kind == "enum":
        return f"{key}: {error.instance!r} is not allowed; allowed: {', '.join(map(str, error.validator_value))}"
    if kind in ("minimum", "exclusiveMinimum", "maximum", "exclusiveMaximum"):
        op = {"minimum": ">=", "exclusiveMinimum": ">", "maximum": "<=", "exclusiveMaximum": "<"}[kind]
        return f"{key}: must be {op} {error.validator_value}, got {error.instance!r}"
    return f"{key}: {error.message}"


def validate_scene_dict(data, source: str = "<scene>") -> None:
    """Check ``data`` against the scene schema; raise SceneError naming ``source`` and key."""
    import jsonschema

    if not isinstance(data, dict):
        raise SceneError(f"{source}: a scene must be a mapping of keys, got {type(data).__name__}")
    bad = _non_finite(data)
    if bad:
        raise SceneError(f"{source}: {_key(bad[0])}: must be a finite number, got {bad[1]!r}")
    validator = jsonschema.Draft202012Validator(scene_schema())
    errors = sorted(validator.iter_errors(data), key=lambda e: (len(e.absolute_path), str(e.absolute_path)))
    if errors:
        # The deepest error names the offending key most precisely.
        # An unknown key says more than the required key it may be a typo of.
        error = max(errors, key=lambda e: (len(e.absolute_path), e.validator == "additionalProperties"))
        raise SceneError(f"{source}: {schema_error_message(error)}")


def scene_from_dict(data: dict, source: str = "<scene>", name: str | None = None) -> Scene:
    """Build a :class:`Scene` from a dict in the YAML layout, validating it first."""
    validate_scene_dict(data, source)
    si = SIScale(**data["si"]) if "si" in data else None
    if data.get("units") == "si" and si is None:
        raise SceneError(f"{source}: units: 'si' needs an si block with mu, g, L")

    def value(block: dict, key: str, kind: str, default=None):
        raw = block.get(key, default)
        if raw is None or data.get("units") != "si" or kind == "dimensionless":
            return raw
        return si.to_dimensionless(raw, kind)

    p = data["profile"]
    try:
        dt = value(p, "dt", "time")
        if p["kind"] == "three_phase":
            profile = ThreePhaseProfile(dt, value(p, "dy", "length"), value(p, "y2", "acceleration"),
                                        value(p, "y3", "acceleration"))
        elif p["kind"] == "polynomial":
            profile = PolynomialProfile(dt, value(p, "dy", "length"), p.get("forward_fraction", 0.8))
        else:
            if len(p["cos_coeffs"]) != len(p["sin_coeffs"]):
                raise ValueError("cos_coeffs and sin_coeffs must have the same length")
            scale = si.L if data.get("units") == "si" else 1.0
            profile = FourierProfile(dt, [c / scale for c in p["cos_coeffs"]],
                                     [c / scale for c in p["sin_coeffs"]])
    except NonPhysicalProfile as exc:
        raise SceneError(f"{source}: profile: {exc}") from None
    except ValueError as exc:
        raise SceneError(f"{source}: profile: {exc}") from None

    s = data.get("surface", {"kind": "uniform"})
    if s["kind"] == "stop_zone":
        if "body" not in data:
            raise SceneError(f"{source}: body.width is required with a stop_zone surface "
                             "(the transition width of eq. 7 is the body width)")
        surface = StopZone(value(s, "x_mu", "length"), value(data["body"], "width", "length"), s["c_mu"])
    else:
        surface = Uniform()

    start = data.get("start", {})
    horizon = data["horizon"]
    if "periods" in horizon and horizon.get("until") == "rest":
        raise SceneError(f"{source}: horizon: periods and until: rest exclude each other; use max_periods")
    if "periods" not in horizon and horizon.get("until", "periods") == "periods":
        raise SceneError(f"{source}: horizon: give periods: N, or until: rest (with max_periods)")
    solver = data.get("solver", {})
    record = data.get("record", {})
    try:
        return Scene(
            profile=profile, surface=surface,
            x0=value(start, "x0", "length", 0.0), v0=value(start, "v0", "velocity", 0.0),
            phase=start.get("phase", 0.0),
            periods=horizon.get("periods"), until=horizon.get("until"),
            max_periods=horizon.get("max_periods", 10_000),
            method=solver.get("method", "exact"), solver_options=dict(solver.get("options", {})),
            record=Record(series=tuple(record.get("series", ())),
                          samples_per_period=record.get("samples_per_period", 200),
                          events=record.get("events", False), rerun=record.get("rerun", False)),
            name=data.get("name", name or "scene"), si=si, description=data.get("description", ""),
        )
    except (SceneError, ValueError) as exc:
        raise SceneError(f"{source}: {exc}") from None


def load_scene(path) -> Scene:
    """Read, validate and build the scene in a YAML file."""
    import yaml

    path = Path(path)
    try:
        text = path.read_text()
    except OSError as exc:
        raise SceneError(f"{path}: cannot read scene file ({exc.strerror})") from None
    try:
        data = yaml.safe_load(text)
    except yaml.YAMLError as exc:
        mark = getattr(exc, "problem_mark", None)
        where = f" at line {mark.line + 1}" if mark else ""
        raise SceneError(f"{path}: not valid YAML{where}") from None
    return scene_from_dict(data, source=str(path), name=path.stem)


def validate_config(config: dict, schema_path, source: str) -> None:
    """Check a workflow config against its schema (which may $ref the scene schema).

    Raises SceneError with one line naming ``source`` and the key, the same
    form as a bad scene file.
    """
    import jsonschema
    import yaml
    from referencing import Registry, Resource

    schema = yaml.safe_load(Path(schema_path).read_text())
    registry = Registry().with_resource("scene.schema.yaml", Resource.from_contents(scene_schema()))
    validator = jsonschema.Draft202012Validator(schema, registry=registry)
    errors = list(validator.iter_errors(config))
    if errors:
        error = max(errors, key=lambda e: (len(e.absolute_path), e.validator == "additionalProperties"))
        raise SceneError(f"{source}: {schema_error_message(error)}")
