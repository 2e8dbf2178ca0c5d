"""selfalign: vibrational self-alignment of a rigid object exploiting friction.

Reference implementation of Hunnekens, Fey, Shukla & Nijmeijer, Nonlinear
Dynamics 65:109-129 (2011).  The public names below load their module on first
use, so ``import selfalign`` loads nothing but this file; numba, scipy, h5py,
matplotlib and rerun load where they are used.
"""

from __future__ import annotations

from importlib import import_module

#: Public name -> module that defines it.
_EXPORTS = {
    "SelfalignError": "model.errors", "NonPhysicalProfile": "model.errors", "SceneError": "model.errors",
    "DesignSpecError": "io.design_spec", "KernelError": "solvers.jit",
    "FrictionLaw": "model.friction", "StopZone": "model.friction", "Uniform": "model.friction",
    "FiniteJerkProfile": "model.profiles", "FourierProfile": "model.profiles",
    "PiecewiseConstantProfile": "model.profiles", "PolynomialProfile": "model.profiles",
    "Profile": "model.profiles",
    "ThreePhaseProfile": "model.profiles",
    "Record": "model.scene", "Scene": "model.scene", "SIScale": "model.units", "Part": "model.parts",
    "PlanarProfile": "model.planar", "Strip": "model.planar",
    "load_scene": "io.scene_files", "scene_from_dict": "io.scene_files",
    "simulate": "solvers.driver", "simulate_batch": "solvers.driver",
    "EventKind": "solvers.outcomes", "Reason": "solvers.outcomes", "Status": "solvers.outcomes",
    "BatchResult": "solvers.results", "Trajectory": "solvers.results",
    "classify": "analysis.classification", "FloquetResult": "analysis.floquet", "floquet": "analysis.floquet",
    "LyapunovTrace": "analysis.lyapunov", "lyapunov_trace": "analysis.lyapunov",
    "SteadyState": "analysis.steady_state", "steady_state": "analysis.steady_state",
    "stick_map": "analysis.stick_map",
    **{name: "analysis.planar_drift" for name in ("steady_drift", "SteadyDrift", "drift_map", "DriftMap",
                                                  "high_acceleration_drift")},
    **{name: "analysis.planar_alignment" for name in ("line_alignment", "LineAlignment", "corner_alignment",
                                                      "CornerAlignment")},
    "Positioning": "analysis.positioning", "positioning": "analysis.positioning",
    "Design": "analysis.design", "design": "analysis.design", "DesignSpec": "model.design_spec",
    "load_design_spec": "io.design_spec",
    "OptimalProfile": "analysis.optimal_motion", "optimal_profile": "analysis.optimal_motion",
    "optimal_vbar": "analysis.optimal_motion",
}

__all__ = sorted(_EXPORTS) + ["__version__"]


def __getattr__(name):
    if name in _EXPORTS:
        value = getattr(import_module(f".{_EXPORTS[name]}", __name__), name)
        globals()[name] = value
        return value
    if name == "__version__":
        # importlib.metadata costs a third of the import time; look the version up on first use.
        from importlib.metadata import PackageNotFoundError, version

        try:
            return version("selfalign")
        except PackageNotFoundError:  # running from a source tree that is not installed
            return "0.0.0+unknown"
    raise AttributeError(f"module 'selfalign' has no attribute {name!r}")


def __dir__():
    return __all__
