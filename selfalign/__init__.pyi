"""Types of selfalign's top-level names (PEP 561): the package loads each one on first use
(``selfalign.__getattr__``), so a type checker reads them here.  The names are ``selfalign.__all__``
(tests/test_vocabulary.py compares them)."""

from .analysis.classification import classify as classify
from .analysis.design import Design as Design
from .analysis.design import design as design
from .analysis.floquet import FloquetResult as FloquetResult
from .analysis.floquet import floquet as floquet
from .analysis.lyapunov import LyapunovTrace as LyapunovTrace
from .analysis.lyapunov import lyapunov_trace as lyapunov_trace
from .analysis.optimal_motion import OptimalProfile as OptimalProfile
from .analysis.optimal_motion import optimal_profile as optimal_profile
from .analysis.optimal_motion import optimal_vbar as optimal_vbar
from .analysis.planar_alignment import CornerAlignment as CornerAlignment
from .analysis.planar_alignment import LineAlignment as LineAlignment
from .analysis.planar_alignment import corner_alignment as corner_alignment
from .analysis.planar_alignment import line_alignment as line_alignment
from .analysis.planar_drift import DriftMap as DriftMap
from .analysis.planar_drift import SteadyDrift as SteadyDrift
from .analysis.planar_drift import drift_map as drift_map
from .analysis.planar_drift import high_acceleration_drift as high_acceleration_drift
from .analysis.planar_drift import steady_drift as steady_drift
from .analysis.positioning import Positioning as Positioning
from .analysis.positioning import positioning as positioning
from .analysis.steady_state import SteadyState as SteadyState
from .analysis.steady_state import steady_state as steady_state
from .analysis.stick_map import stick_map as stick_map
from .io.design_spec import DesignSpecError as DesignSpecError
from .io.design_spec import load_design_spec as load_design_spec
from .io.scene_files import load_scene as load_scene
from .io.scene_files import scene_from_dict as scene_from_dict
from .model.design_spec import DesignSpec as DesignSpec
from .model.errors import NonPhysicalProfile as NonPhysicalProfile
from .model.errors import SceneError as SceneError
from .model.errors import SelfalignError as SelfalignError
from .model.friction import FrictionLaw as FrictionLaw
from .model.friction import StopZone as StopZone
from .model.friction import Uniform as Uniform
from .model.parts import Part as Part
from .model.planar import PlanarProfile as PlanarProfile
from .model.planar import Strip as Strip
from .model.profiles import FiniteJerkProfile as FiniteJerkProfile
from .model.profiles import FourierProfile as FourierProfile
from .model.profiles import PiecewiseConstantProfile as PiecewiseConstantProfile
from .model.profiles import PolynomialProfile as PolynomialProfile
from .model.profiles import Profile as Profile
from .model.profiles import ThreePhaseProfile as ThreePhaseProfile
from .model.scene import Record as Record
from .model.scene import Scene as Scene
from .model.units import SIScale as SIScale
from .solvers.driver import simulate as simulate
from .solvers.driver import simulate_batch as simulate_batch
from .solvers.jit import KernelError as KernelError
from .solvers.outcomes import EventKind as EventKind
from .solvers.outcomes import Reason as Reason
from .solvers.outcomes import Status as Status
from .solvers.results import BatchResult as BatchResult
from .solvers.results import Trajectory as Trajectory

__version__: str
