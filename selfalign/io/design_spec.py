"""Design spec files: YAML read, checked against ``schemas/design.schema.yaml``, turned into a
:class:`~selfalign.model.design_spec.DesignSpec` (docs/tutorials/design-station.md).

Every problem is one line naming the file and the key, e.g.
``workflow/designs/x.yaml: actuator.acceleration: must be > 0, got -3``.
"""

from __future__ import annotations

from functools import lru_cache
from importlib import resources
from pathlib import Path

from ..model.design_spec import DesignGrid, DesignSpec, period_from_frequency
from ..model.errors import SelfalignError
from ..model.friction import FrictionLaw
from .scene_files import first_non_finite, read_yaml, schema_error_message


class DesignSpecError(SelfalignError, ValueError):
    """A design spec file is invalid; the message names the file and the key.

    Raised by :func:`~selfalign.load_design_spec` before any work, with one line naming the file
    and the key, for a file that cannot be read, is not valid YAML, breaks the schema or gives
    values the :class:`~selfalign.DesignSpec` refuses.  It is a :class:`~selfalign.SelfalignError`
    and a ValueError, not a :class:`~selfalign.SceneError`: a spec is not a scene.

    See Also
    --------
    load_design_spec : Reads a design spec file.

    Examples
    --------
    >>> import pathlib, tempfile
    >>> import selfalign as sa
    >>> folder = tempfile.TemporaryDirectory()
    >>> path = pathlib.Path(folder.name) / "station.yaml"
    >>> _ = path.write_text("machine: [")
    >>> try:
    ...     sa.load_design_spec(path)
    ... except sa.DesignSpecError as exc:
    ...     print(str(exc).split(": ", 1)[1], isinstance(exc, sa.SceneError))
    not valid YAML at line 1 (expected the node content, but found '<stream end>') False
    >>> folder.cleanup()
    """


@lru_cache(maxsize=1)
def design_schema() -> dict:
    """The JSON schema of a design spec file."""
    import yaml

    return yaml.safe_load(resources.files("selfalign.io").joinpath("schemas/design.schema.yaml").read_text())


def _pair(value) -> tuple[float, float]:
    """(min, max) of a number (min = max) or a {min, max} range."""
    return (value["min"], value["max"]) if isinstance(value, dict) else (value, value)


def design_spec_from_dict(data, source: str = "<design>", name: str | None = None) -> DesignSpec:
    """Validate ``data`` (the YAML layout) and build the :class:`DesignSpec`."""
    import jsonschema

    if not isinstance(data, dict):
        raise DesignSpecError(f"{source}: a design spec must be a mapping of keys, got {type(data).__name__}")
    bad = first_non_finite(data)
    if bad:
        raise DesignSpecError(f"{source}: {'.'.join(map(str, bad[0]))}: must be a finite number, got {bad[1]!r}")
    errors = list(jsonschema.Draft202012Validator(design_schema()).iter_errors(data))
    if errors:
        error = max(errors, key=lambda e: (len(e.absolute_path), e.validator == "additionalProperties"))
        if error.validator == "oneOf" and list(error.absolute_path) == ["actuator"]:
            raise DesignSpecError(f"{source}: actuator: give exactly one of frequency and period (each {{min, max}})")
        raise DesignSpecError(f"{source}: {schema_error_message(error)}")
    machine, actuator, task = data["machine"], data["actuator"], data["task"]
    friction = data.get("friction", {})
    if friction.get("kind") in ("static_kinetic", "stribeck") and "mu_s_over_mu_k" not in friction:
        raise DesignSpecError(f"{source}: friction.mu_s_over_mu_k: required with kind {friction['kind']} (the ratio "
                              f"mu_s/mu_k >= 1 of static to kinetic friction)")
    stroke_min, stroke_max = _pair(actuator["stroke"])
    try:
        period = (period_from_frequency(*_pair(actuator["frequency"])) if "frequency" in actuator
                  else _pair(actuator["period"]))
        return DesignSpec(
            mu=machine["mu"], mu_uncertainty=machine.get("mu_uncertainty", 0.0), c_mu=_pair(machine["c_mu"]),
            g=machine.get("g", 9.81), width=data["part"]["width"], max_stroke=stroke_max,
            min_stroke=stroke_min if isinstance(actuator["stroke"], dict) else None,
            max_acceleration=actuator["acceleration"], period=period, distance=task["distance"],
            tolerance=task["tolerance"], accumulation=task.get("accumulation", False),
            objective=task.get("objective", "process_time"), max_process_time=task.get("max_process_time"),
            name=data.get("name", name or "design"), grid=DesignGrid(**data.get("search", {})),
            friction=FrictionLaw(**friction), ramp=actuator.get("ramp"),
            families=tuple(data.get("profile", {}).get("families", ("three_phase",))),
        )
    except ValueError as exc:
        raise DesignSpecError(f"{source}: {exc}") from None


def load_design_spec(path) -> DesignSpec:
    """Read, validate and build the design spec in a YAML file (its name defaults to the file stem).

    The file is read as YAML 1.2 with every key at most once per mapping, checked against
    ``schemas/design.schema.yaml`` and turned into a :class:`~selfalign.DesignSpec`
    (docs/tutorials/design-station.md).
    Sections: ``machine`` (mu, mu_uncertainty, c_mu as a number or
    {min, max}, g), ``part`` (width), ``actuator`` (stroke as a number or {min, max},
    acceleration, exactly one of frequency [Hz] and period [s] as {min, max}, ramp),
    ``task`` (distance, tolerance, accumulation, objective, max_process_time) and optionally
    ``friction``, ``profile`` (families: the profile families searched, three_phase and/or
    optimal), ``search`` (the ``selfalign.model.design_spec.DesignGrid``), ``name``
    and ``description``.  Every problem is one line naming the file and the key, e.g.
    ``workflow/designs/x.yaml: actuator.acceleration: must be > 0, got -3``.

    Parameters
    ----------
    path : str or os.PathLike
        The design spec file (UTF-8 YAML).

    Returns
    -------
    DesignSpec
        The validated spec, in SI units.

    Raises
    ------
    TypeError
        If ``path`` is not a str or path-like object.
    DesignSpecError
        If the file cannot be read, is not UTF-8 text or valid YAML, repeats a key, breaks the
        schema, holds a NaN or infinity, or gives values the :class:`~selfalign.DesignSpec`
        refuses.

    See Also
    --------
    design : Searches and certifies the design of the spec.
    DesignSpec : The result.

    Examples
    --------
    >>> import pathlib, tempfile
    >>> import selfalign as sa
    >>> folder = tempfile.TemporaryDirectory()
    >>> path = pathlib.Path(folder.name) / "station.yaml"
    >>> _ = path.write_text('''
    ... machine: {mu: 0.2, mu_uncertainty: 0.05, c_mu: 3.0}
    ... part: {width: 2.0e-3}
    ... actuator: {stroke: 1.0e-3, acceleration: 8.0, frequency: {min: 10.0, max: 100.0}}
    ... task: {distance: 10.0e-3, tolerance: 250.0e-6}
    ... ''')
    >>> spec = sa.load_design_spec(path)
    >>> spec.name, spec.period, spec.c_mu
    ('station', (0.01, 0.1), (3.0, 3.0))
    >>> _ = path.write_text(path.read_text().replace("acceleration: 8.0", "acceleration: -8.0"))
    >>> try:
    ...     sa.load_design_spec(path)
    ... except sa.DesignSpecError as exc:
    ...     print(type(exc).__name__, str(exc).split(": ", 1)[1])
    DesignSpecError actuator.acceleration: must be > 0, got -8.0
    >>> folder.cleanup()
    """
    path = Path(path)
    return design_spec_from_dict(read_yaml(path, DesignSpecError, "design spec"), source=str(path), name=path.stem)
