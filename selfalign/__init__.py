"""selfalign: vibrational self-alignment of a rigid object exploiting friction.

Reference implementation of Hunnekens, Fey, Shukla & Nijmeijer, Nonlinear
Dynamics 65:109-129 (2011).  Only light modules are imported here; solvers,
plotting and recording load on first use.
"""

from importlib.metadata import PackageNotFoundError, version as _version

from .errors import NonPhysicalProfile, SceneError
from .friction import StopZone, Uniform
from .profiles import FourierProfile, PiecewiseConstantProfile, PolynomialProfile, ThreePhaseProfile
from .scene import Record, Scene, load_scene, scene_from_dict
from .simulate import simulate
from .classification import classify
from .steady_state import SteadyState, steady_state
from .trajectory import EventKind, Status, Trajectory
from .units import SIScale

try:
    __version__ = _version("selfalign")
except PackageNotFoundError:  # running from a source tree that is not installed
    __version__ = "0.0.0+unknown"

__all__ = [
    "FourierProfile", "NonPhysicalProfile", "PiecewiseConstantProfile", "PolynomialProfile",
    "Record", "SIScale", "Scene", "SceneError", "SteadyState", "classify", "steady_state", "Status", "StopZone", "EventKind", "ThreePhaseProfile",
    "Trajectory", "Uniform", "load_scene", "scene_from_dict", "simulate", "__version__",
]
