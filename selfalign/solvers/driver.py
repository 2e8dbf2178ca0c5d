"""One entry point for the three solvers of the inclusion (6) / (38)."""

from __future__ import annotations

from importlib import import_module

from ..model.scene import Scene
from .outcomes import Trajectory

#: Options each method accepts, with their defaults.
DEFAULT_OPTIONS = {
    "exact": {"accumulation_tol": 1e-12, "max_events": 50_000_000},
    "moreau": {"h": None, "iteration": "exact", "fp_tol": 1e-14, "fp_max_iter": 200,
               "accumulation_tol": 1e-12},
    "ivp": {"rtol": 1e-8, "atol": 1e-10, "integrator": "DOP853", "max_events": 1_000_000},
}


def resolve_options(method: str, options: dict, defaults: dict = DEFAULT_OPTIONS) -> dict:
    """Merge ``options`` into ``defaults[method]``; reject unknown methods and option names."""
    if method not in defaults:
        raise ValueError(f"unknown method {method!r}; allowed: {', '.join(defaults)}")
    allowed = defaults[method]
    unknown = sorted(set(options) - set(allowed))
    if unknown:
        raise ValueError(f"unknown option(s) {unknown} for method {method!r}; allowed: {sorted(allowed)}")
    return {**allowed, **options}


def simulate(scene: Scene, method: str | None = None, **options) -> Trajectory:
    """Simulate ``scene`` with ``method`` ("exact", "moreau" or "ivp").

    ``method`` and ``options`` default to the scene's solver block; options
    given here override the scene's.  Bad input raises ``ValueError`` before
    any work starts; a run that cannot finish reports it in
    ``Trajectory.status`` and ``message``.
    """
    if not isinstance(scene, Scene):
        raise TypeError(f"simulate expects a selfalign.Scene, got {type(scene).__name__}")
    if method is None:
        method, options = scene.method, {**scene.solver_options, **options}
    elif method == scene.method:
        options = {**scene.solver_options, **options}
    options = resolve_options(method, options)
    solver = import_module(f"selfalign.solvers.{method}")
    return solver.solve(scene, options)
