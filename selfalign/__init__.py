"""selfalign: vibrational self-alignment of a rigid object exploiting friction.

Reference implementation of Hunnekens, Fey, Shukla & Nijmeijer, Nonlinear
Dynamics 65:109-129 (2011).  Importing it loads numpy and the package's own
modules only; scipy, h5py, matplotlib and rerun load where they are used.
"""

from .model.errors import NonPhysicalProfile, SceneError
from .model.friction import StopZone, Uniform
from .model.profiles import FourierProfile, PiecewiseConstantProfile, PolynomialProfile, ThreePhaseProfile
from .model.scene import Record, Scene
from .io.scene_files import load_scene, scene_from_dict
from .solvers.driver import simulate
from .analysis.classification import classify
from .analysis.floquet import floquet
from .analysis.lyapunov import lyapunov_trace
from .analysis.steady_state import SteadyState, steady_state
from .analysis.stick_map import stick_map
from .analysis.positioning import positioning
from .solvers.outcomes import EventKind, Status, Trajectory
from .model.units import SIScale


def __getattr__(name):
    # importlib.metadata costs a third of the import time; look the version up on first use.
    if name == "__version__":
        from importlib.metadata import PackageNotFoundError, version

        try:
            return version("selfalign")
        except PackageNotFoundError:  # running from a source tree that is not installed
            return "0.0.0+unknown"
    raise AttributeError(f"module 'selfalign' has no attribute {name!r}")

__all__ = [
    "FourierProfile", "NonPhysicalProfile", "PiecewiseConstantProfile", "PolynomialProfile",
    "Record", "SIScale", "floquet", "lyapunov_trace", "positioning", "stick_map", "Scene", "SceneError", "SteadyState", "classify", "steady_state", "Status", "StopZone", "EventKind", "ThreePhaseProfile",
    "Trajectory", "Uniform", "load_scene", "scene_from_dict", "simulate", "__version__",
]
