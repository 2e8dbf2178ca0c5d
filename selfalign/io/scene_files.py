"""Scene files: YAML read, checked against the JSON schema, turned into a Scene.

:func:`load_scene` validates a YAML file against ``schemas/scene.schema.yaml``
(shared with the Snakemake config) and then checks the physics (feasible
profile, finite numbers), raising :class:`SceneError` with a one-line message
naming the file and the key.
"""

from __future__ import annotations

import functools
import math
from functools import lru_cache
from importlib import resources
from pathlib import Path

from ..model.errors import NonPhysicalProfile, SceneError
from ..model.friction import FrictionLaw, StopZone, Uniform
from ..model.parts import Part
from ..model.planar import PlanarProfile, Strip
from ..model.profiles import FiniteJerkProfile, FourierProfile, PolynomialProfile, ThreePhaseProfile
from ..model.scene import Record, Scene
from ..model.units import SIScale
from ..solvers.methods import check_scene


@lru_cache(maxsize=1)
def scene_schema() -> dict:
    """The JSON schema of a scene file (also used by the Snakemake config)."""
    import yaml

    text = resources.files("selfalign.io").joinpath("schemas/scene.schema.yaml").read_text()
    return yaml.safe_load(text)


def _key(path) -> str:
    return ".".join(str(p) for p in path) or "<top level>"


def first_non_finite(data, path=()):
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
        found = first_non_finite(value, path + (key,))
        if found:
            return found
    return None


def _yaml12_hint(value) -> str:
    """Why a value a YAML 1.1 reader would take for a number or boolean is text here (YAML 1.2)."""
    if not isinstance(value, str):
        return ""
    import re

    if value.lower() in ("yes", "no", "on", "off", "y", "n"):
        return " (YAML 1.2: the booleans are true and false)"
    if re.fullmatch(r"[-+]?[0-9][0-9_:]*(\.[0-9_]*)?([eE][-+]?[0-9]+)?", value) and ("_" in value or ":" in value):
        return " (YAML 1.2 reads it as text: write the number without '_' or ':')"
    return ""


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
        return (f"{key}: expected {error.validator_value}, got {type(error.instance).__name__} {error.instance!r}"
                f"{_yaml12_hint(error.instance)}")
    if kind == "enum":
        return f"{key}: {error.instance!r} is not allowed; allowed: {', '.join(map(str, error.validator_value))}"
    if kind == "not" and "required" in error.validator_value:
        return f"{key}: keys {', '.join(error.validator_value['required'])} exclude each other; give at most one"
    if kind in ("minimum", "exclusiveMinimum", "maximum", "exclusiveMaximum"):
        op = {"minimum": ">=", "exclusiveMinimum": ">", "maximum": "<=", "exclusiveMaximum": "<"}[kind]
        return f"{key}: must be {op} {error.validator_value}, got {error.instance!r}"
    return f"{key}: {error.message}"


def validate_scene_dict(data, source: str = "<scene>") -> None:
    """Check ``data`` against the scene schema; raise SceneError naming ``source`` and key."""
    import jsonschema

    if not isinstance(data, dict):
        raise SceneError(f"{source}: a scene must be a mapping of keys, got {type(data).__name__}")
    bad = first_non_finite(data)
    if bad:
        raise SceneError(f"{source}: {_key(bad[0])}: must be a finite number, got {bad[1]!r}")
    validator = jsonschema.Draft202012Validator(scene_schema())
    errors = sorted(validator.iter_errors(data), key=lambda e: (len(e.absolute_path), str(e.absolute_path)))
    if errors:
        # The deepest error names the offending key most precisely.
        # An unknown key says more than the required key it may be a typo of.
        error = max(errors, key=lambda e: (len(e.absolute_path), e.validator == "additionalProperties"))
        raise SceneError(f"{source}: {schema_error_message(error)}")


def _refuse_idle_keys(data: dict, source: str) -> None:
    """SceneError for a key that would do nothing in this scene (it would be ignored silently)."""
    surface = data.get("surface", {"kind": "uniform"})["kind"]
    method = data.get("solver", {}).get("method", "exact")
    record, horizon = data.get("record", {}), data["horizon"]
    widthless = surface == "strips" and any("w" not in s for s in data["surface"]["strips"])
    if "body" in data and surface != "stop_zone" and not widthless:
        raise SceneError(f"{source}: body: does nothing on a {surface} surface (the body width is the transition "
                         f"width of a stop zone, eq. 7); remove it, or give surface kind stop_zone or strips without "
                         f"their own w")
    if record.get("arcs") and method != "exact":
        raise SceneError(f"{source}: record.arcs: does nothing with method {method!r} (closed-form arcs are the exact "
                         f"solver's); remove it or use method exact")
    if record.get("events") and method == "moreau":
        raise SceneError(f"{source}: record.events: does nothing with method 'moreau' (time-stepping locates no "
                         f"events); remove it or use method exact or ivp")
    if "restitution" in data and "parts" not in data:
        raise SceneError(f"{source}: restitution: does nothing without parts (it acts between parts); remove it or "
                         f"give parts")
    if "parts" in data and ({"x0", "v0"} & set(data.get("start", {}))):
        raise SceneError(f"{source}: start.x0, start.v0: do nothing with parts (each part gives its own x0, v0); "
                         f"remove them")
    if "max_periods" in horizon and "periods" in horizon:
        raise SceneError(f"{source}: horizon.max_periods: does nothing with periods: N (it is the budget of until: "
                         f"rest); remove one of them")


def scene_from_dict(data: dict, source: str = "<scene>", name: str | None = None) -> Scene:
    """Build a :class:`~selfalign.Scene` from a dict in the YAML layout, validating it first.

    ``data`` is checked against the JSON schema of scene files (``schemas/scene.schema.yaml``,
    shared with the Snakemake config), then for the physics (a feasible profile, finite
    numbers) and for keys that would do nothing (``body`` without a stop zone, ``record.arcs``
    without the exact solver, ...), and finally the solver and its options are checked
    against the scene (``selfalign.solvers.methods.check_scene``), so that a scene its
    method cannot simulate is refused when it is loaded, not first inside the job that
    simulates it.  With ``units: si`` and an ``si`` block (mu, g, L) the lengths, times,
    velocities, accelerations and jerks are converted to the dimensionless model of
    Sect. 3.2 (:class:`~selfalign.SIScale`).  A three-phase profile with a
    ``ramp`` or ``jerk`` > 0 is the finite-jerk version of the paper's profile.

    Parameters
    ----------
    data : dict
        The scene in the YAML layout: ``profile`` and ``horizon``, optionally ``name``,
        ``description``, ``units``, ``si``, ``surface``, ``body``, ``friction``, ``start``,
        ``solver``, ``record``, ``parts`` and ``restitution``.
    source : str, optional
        Where the data came from; every error message starts with it.  Default "<scene>".
    name : str, optional
        The scene's name when ``data`` gives none (default "scene").

    Returns
    -------
    Scene
        The validated scene.

    Raises
    ------
    SceneError
        If ``data`` is not a mapping, holds a NaN or infinity, breaks the schema, describes
        no physical profile or surface, has a key that would do nothing, has no valid
        horizon, or names a solver that cannot simulate the scene; one line naming
        ``source`` and the key.

    See Also
    --------
    load_scene : Reads the same layout from a YAML file.
    Scene : The result.

    Examples
    --------
    A scene in SI units (a 2 mm part, mu = 0.2; 10 Hz, 1 mm stroke, 4 m/s^2):

    >>> import selfalign as sa
    >>> layout = {"units": "si", "si": {"mu": 0.2, "g": 9.81, "L": 0.002},
    ...           "profile": {"kind": "three_phase", "dt": 0.1, "dy": 0.001, "y2": 4.0, "y3": 4.0},
    ...           "horizon": {"periods": 10}}
    >>> scene = sa.scene_from_dict(layout, name="table")
    >>> scene.name, scene.method, scene.periods
    ('table', 'exact', 10)
    >>> print(round(scene.profile.dt, 6), round(scene.profile.dy, 6), round(scene.profile.y2, 6))
    3.132092 0.5 2.038736
    >>> layout["solver"] = {"method": "exact", "options": {"h": 0.01}}
    >>> try:
    ...     sa.scene_from_dict(layout, source="table.yaml")
    ... except sa.SceneError as exc:
    ...     print(exc)
    table.yaml: solver: unknown option(s) ['h'] for method 'exact'; allowed: ['accumulation_tol', 'max_events']
    """
    validate_scene_dict(data, source)
    try:
        si = SIScale(**data["si"]) if "si" in data else None
    except ValueError as exc:
        raise SceneError(f"{source}: {exc}") from None
    if data.get("units") == "si" and si is None:
        raise SceneError(f"{source}: units: 'si' needs an si block with mu, g, L")

    def value(block: dict, key: str, kind: str, default=None):
        raw = block.get(key, default)
        if raw is None or data.get("units") != "si" or kind == "dimensionless":
            return raw
        return si.to_dimensionless(raw, kind)

    def line_profile(p: dict):
        dt = value(p, "dt", "time")
        if p["kind"] == "three_phase" and (p.get("ramp") or p.get("jerk")):
            return FiniteJerkProfile(dt, value(p, "dy", "length"), value(p, "y2", "acceleration"),
                                     value(p, "y3", "acceleration"), ramp=value(p, "ramp", "time"),
                                     jerk=value(p, "jerk", "jerk"))
        if p["kind"] == "three_phase":         # ramp absent or 0: the paper's profile (Sect. 4.4.3)
            return ThreePhaseProfile(dt, value(p, "dy", "length"), value(p, "y2", "acceleration"),
                                     value(p, "y3", "acceleration"))
        if p["kind"] == "polynomial":
            return PolynomialProfile(dt, value(p, "dy", "length"), p.get("forward_fraction", 0.8))
        if len(p["cos_coeffs"]) != len(p["sin_coeffs"]):
            raise ValueError("cos_coeffs and sin_coeffs must have the same length")
        scale = si.L if data.get("units") == "si" else 1.0
        return FourierProfile(dt, [c / scale for c in p["cos_coeffs"]], [c / scale for c in p["sin_coeffs"]])

    def pair(block: dict, key: str, kind: str):
        """A start value: a number, or a pair in a planar scene (each entry in the scene's units)."""
        raw = block.get(key, 0.0)
        return [value({key: v}, key, kind) for v in raw] if isinstance(raw, list) else value(block, key, kind, 0.0)

    p = data["profile"]
    try:
        if p["kind"] == "planar":
            profile = PlanarProfile(line_profile(p["x"]), line_profile(p["y"]) if "y" in p else None,
                                    offset=p.get("offset", 0.0), angle=p.get("angle", 0.0))
        else:
            profile = line_profile(p)
    except NonPhysicalProfile as exc:
        raise SceneError(f"{source}: profile: {exc}") from None
    except ValueError as exc:
        raise SceneError(f"{source}: profile: {exc}") from None

    _refuse_idle_keys(data, source)
    s = data.get("surface", {"kind": "uniform"})
    if s["kind"] == "stop_zone":
        if "body" not in data:
            raise SceneError(f"{source}: body.width is required with a stop_zone surface "
                             "(the transition width of eq. 7 is the body width)")
        try:
            surface = StopZone(value(s, "x_mu", "length"), value(data["body"], "width", "length"), s["c_mu"])
        except ValueError as exc:
            raise SceneError(f"{source}: surface: {exc}") from None
    elif s["kind"] == "strips":
        width = value(data["body"], "width", "length") if "body" in data else None
        surface = []
        for i, strip in enumerate(s["strips"]):
            if "w" not in strip and width is None:
                raise SceneError(f"{source}: surface.strips[{i}].w is required without body.width (the transition "
                                 f"width of eq. 7 is the body width)")
            try:
                surface.append(Strip(strip["normal"], value(strip, "x_mu", "length"),
                                     value(strip, "w", "length") if "w" in strip else width, strip["c_mu"]))
            except ValueError as exc:
                raise SceneError(f"{source}: surface.strips[{i}]: {exc}") from None
    else:
        surface = Uniform()
    f = data.get("friction", {"kind": "coulomb"})
    try:
        friction = FrictionLaw(f["kind"], f.get("mu_s_over_mu_k", 1.0), value(f, "v_s", "velocity"),
                               f.get("delta", 2.0))
    except ValueError as exc:
        raise SceneError(f"{source}: {exc}") from None

    start = data.get("start", {})
    horizon = data["horizon"]
    if "periods" in horizon and horizon.get("until") == "rest":
        raise SceneError(f"{source}: horizon: periods and until: rest exclude each other; use max_periods")
    if "periods" not in horizon and horizon.get("until", "periods") == "periods":
        raise SceneError(f"{source}: horizon: give periods: N, or until: rest (with max_periods)")
    solver = data.get("solver", {})
    record = data.get("record", {})
    parts = None
    if "parts" in data:
        width = surface.w if isinstance(surface, StopZone) else None
        parts = []
        for i, p in enumerate(data["parts"]):
            if "width" not in p and width is None:
                raise SceneError(f"{source}: parts[{i}].width is required on a {s['kind']} surface (a part's extent "
                                 f"decides its contacts); on a stop zone it defaults to body.width")
            try:
                parts.append(Part(value(p, "x0", "length"), value(p, "v0", "velocity", 0.0),
                                  width=value(p, "width", "length") if "width" in p else width,
                                  mass=p.get("mass", 1.0), friction_factor=p.get("friction_factor", 1.0)))
            except ValueError as exc:
                raise SceneError(f"{source}: parts[{i}]: {exc}") from None
    try:
        scene = Scene(
            profile=profile, surface=surface, friction=friction,
            x0=pair(start, "x0", "length"), v0=pair(start, "v0", "velocity"),
            phase=start.get("phase", 0.0),
            periods=horizon.get("periods"), until=horizon.get("until"),
            max_periods=horizon.get("max_periods", 10_000),
            method=solver.get("method", "exact"), solver_options=dict(solver.get("options", {})),
            record=Record(series=tuple(record.get("series", ())),
                          samples_per_period=record.get("samples_per_period", 200),
                          events=record.get("events", False), arcs=record.get("arcs", False),
                          rerun=record.get("rerun", False)),
            name=data.get("name", name or "scene"), si=si, description=data.get("description", ""),
            parts=parts, restitution=data.get("restitution", 0.0),
        )
    except (ValueError, TypeError) as exc:
        raise SceneError(f"{source}: {exc}") from None
    # The solver and its options are checked here, when the scene is loaded (and so at
    # `snakemake -n`), not first inside the job that simulates it.
    try:
        check_scene(scene)
    except (ValueError, TypeError) as exc:
        raise SceneError(f"{source}: solver: {exc}") from None
    return scene


#: YAML 1.2 (core schema) plain scalars that are not strings; everything else is a string.
#: PyYAML resolves YAML 1.1, where ``1e-3`` is a string (no dot), ``1_05`` is 105, ``010`` is 8,
#: ``1:30`` is 90 and ``yes``/``on`` are true.
_YAML12 = {
    "tag:yaml.org,2002:null": (r"^(?:~|null|Null|NULL|)$", "~nN"),
    "tag:yaml.org,2002:bool": (r"^(?:true|True|TRUE|false|False|FALSE)$", "tTfF"),
    "tag:yaml.org,2002:int": (r"^(?:[-+]?[0-9]+|0o[0-7]+|0x[0-9a-fA-F]+)$", "-+0123456789"),
    "tag:yaml.org,2002:float": (r"^(?:[-+]?(?:\.[0-9]+|[0-9]+(?:\.[0-9]*)?)(?:[eE][-+]?[0-9]+)?"
                                r"|[-+]?\.(?:inf|Inf|INF)|\.(?:nan|NaN|NAN))$", "-+.0123456789"),
}


class DuplicateKey(Exception):
    """A key given twice in one YAML mapping (its line and the first one's)."""


@functools.cache
def _strict_loader():
    """A PyYAML SafeLoader that reads plain scalars as YAML 1.2 does (:data:`_YAML12`) and
    refuses a key given twice in a mapping (PyYAML keeps the last one silently)."""
    import re

    import yaml

    class StrictLoader(yaml.SafeLoader):
        def construct_mapping(self, node, deep=False):
            if isinstance(node, yaml.MappingNode):
                seen = {}
                for key_node, _ in node.value:
                    if key_node.tag == "tag:yaml.org,2002:merge":
                        continue
                    key = self.construct_object(key_node, deep=True)
                    if not isinstance(key, (str, int, float)):
                        continue                # an unhashable key: construct_mapping names it
                    line = key_node.start_mark.line + 1
                    if key in seen:
                        raise DuplicateKey(f"key {key!r} at line {line} is given already at line {seen[key]} (a "
                                           f"key may appear once in a mapping)")
                    seen[key] = line
            return super().construct_mapping(node, deep=deep)

        def construct_yaml_int(self, node):
            text = self.construct_scalar(node)
            base = 8 if text.startswith("0o") else 16 if text.startswith("0x") else 10
            return int(text[2:] if base != 10 else text, base)

        def construct_yaml_float(self, node):
            text = self.construct_scalar(node).lower().lstrip("+")
            special = {".inf": math.inf, "-.inf": -math.inf, ".nan": math.nan}
            return special[text] if text in special else float(text)

    keep = {tag for tag, _ in _YAML12.values()} | set(_YAML12)
    StrictLoader.yaml_implicit_resolvers = {
        first: [(tag, regexp) for tag, regexp in resolvers if tag not in keep and tag != "tag:yaml.org,2002:timestamp"]
        for first, resolvers in yaml.SafeLoader.yaml_implicit_resolvers.items()}
    for tag, (pattern, first) in _YAML12.items():
        StrictLoader.add_implicit_resolver(tag, re.compile(pattern), list(first) + ([""] if tag.endswith("null")
                                                                                     else []))
    StrictLoader.add_constructor("tag:yaml.org,2002:int", StrictLoader.construct_yaml_int)
    StrictLoader.add_constructor("tag:yaml.org,2002:float", StrictLoader.construct_yaml_float)
    return StrictLoader


def parse_yaml(text: str):
    """``text`` read as YAML 1.2 with every key once (:func:`_strict_loader`): the one YAML reader of
    scene files and design specs.  Raises yaml.YAMLError or :class:`DuplicateKey`."""
    import yaml

    return yaml.load(text, Loader=_strict_loader())


def read_yaml(path, error: type[ValueError], what: str):
    """The YAML content of ``path`` (:func:`parse_yaml`); ``error`` with one line naming the file if
    it cannot be read, is not UTF-8 text, or cannot be parsed (``what``: "scene file", "design spec", ...)."""
    import yaml

    path = Path(path)
    try:
        text = path.read_text(encoding="utf-8")
    except OSError as exc:
        raise error(f"{path}: cannot read {what} ({exc.strerror})") from None
    except UnicodeDecodeError as exc:
        raise error(f"{path}: not a {what}: not UTF-8 text (byte {exc.object[exc.start]:#04x} at offset "
                    f"{exc.start})") from None
    try:
        return parse_yaml(text)
    except DuplicateKey as exc:
        raise error(f"{path}: {exc}") from None
    except yaml.YAMLError as exc:
        mark = getattr(exc, "problem_mark", None)
        where = f" at line {mark.line + 1}" if mark else ""
        problem = getattr(exc, "problem", None) or getattr(exc, "reason", None)
        raise error(f"{path}: not valid YAML{where}" + (f" ({problem})" if problem else "")) from None


def load_scene(path) -> Scene:
    """Read, validate and build the scene in a YAML file.

    The file is read as YAML 1.2 with every key at most once per mapping, validated against
    ``schemas/scene.schema.yaml`` (shared with the Snakemake config) and then checked for
    the physics (feasible profile, finite numbers) and the solver, as
    :func:`scene_from_dict` does; the scene's name defaults to the file's stem.  Every
    problem raises :class:`~selfalign.SceneError` with a one-line message
    naming the file and the key.

    Parameters
    ----------
    path : str or os.PathLike
        The scene file (UTF-8 YAML).

    Returns
    -------
    Scene
        The validated scene.

    Raises
    ------
    TypeError
        If ``path`` is not a str or path-like object.
    SceneError
        If the file cannot be read, is not UTF-8 text or valid YAML, repeats a key, or
        fails the checks of :func:`scene_from_dict`.

    See Also
    --------
    scene_from_dict : Builds a scene from a mapping in the same layout.
    simulate : Simulates the scene.

    Examples
    --------
    >>> import pathlib, tempfile
    >>> import selfalign as sa
    >>> folder = tempfile.TemporaryDirectory()
    >>> path = pathlib.Path(folder.name) / "fig18_stop.yaml"
    >>> _ = path.write_text('''
    ... profile: {kind: three_phase, dt: 1.05, dy: 0.084, y2: 2.2, y3: 0.9}
    ... surface: {kind: stop_zone, x_mu: 0.5, c_mu: 2.5}
    ... body: {width: 0.05}
    ... horizon: {until: rest, max_periods: 1000}
    ... ''')
    >>> scene = sa.load_scene(path)
    >>> scene.name, scene.surface
    ('fig18_stop', StopZone(x_mu=0.5, w=0.05, c_mu=2.5))
    >>> sa.simulate(scene).status.value
    'accumulation'
    >>> try:
    ...     sa.load_scene(pathlib.Path(folder.name) / "missing.yaml")
    ... except sa.SceneError as exc:
    ...     print(str(exc).replace(folder.name, "<folder>"))
    <folder>/missing.yaml: cannot read scene file (No such file or directory)
    >>> folder.cleanup()
    """
    path = Path(path)
    return scene_from_dict(read_yaml(path, SceneError, "scene file"), source=str(path), name=path.stem)


def validate_config(config: dict, schema_path, source: str, overrides: dict | None = None) -> None:
    """Check a workflow config against its schema (which may $ref the scene schema).

    Raises SceneError with one line naming ``source`` and the key, the same
    form as a bad scene file.  ``overrides``: the values given on the command line
    (``--config``/``--configfile``), merged into ``config``; an error inside one of
    them names that override instead of ``source``.
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
        raise SceneError(f"{_origin(list(error.absolute_path), source, overrides or {})}: "
                         f"{schema_error_message(error)}")


def _origin(path: list, source: str, overrides: dict) -> str:
    """Where the config value at ``path`` came from: the deepest override on that path, or ``source``."""
    keys, node = [], overrides
    for key in path:
        if not isinstance(node, dict) or key not in node:
            break
        keys.append(str(key))
        node = node[key]
    return f"the command-line override --config {'.'.join(keys)}=..." if keys else source
