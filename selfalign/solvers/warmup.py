"""Compiling the solvers ahead of a run: one tiny run of each compiled entry point.

Every entry point of the compiled engine compiles on its first call in a fresh numba cache (seconds
each, see docs/explanation/performance.md) and is loaded from the cache afterwards
(:mod:`selfalign.solvers.jit`).  Jobs that start together on an empty cache (the first ``snakemake
-c2``, a sweep's array jobs on a cluster) would each compile the same entry points; compiling them once
first (``selfalign compile``, :func:`warm_up`) lets every later process load them.

Each warm-up in :data:`WARMUPS` is a run of a few periods through the public solvers that reaches one
group of entry points: the exact solver on piecewise-constant and on smooth profiles, Moreau, each with
and without recording, batches on a uniform surface, solve_ivp's compiled decisions, the two solvers
of several parts, and the solvers of planar motion.  They are independent of one another
(:func:`warm_up` takes any of them).
"""

from __future__ import annotations

import time
from collections.abc import Callable, Iterable

from ..model.friction import StopZone, Uniform
from ..model.parts import Part
from ..model.planar import PlanarProfile, Strip
from ..model.profiles import FourierProfile, ThreePhaseProfile
from ..model.scene import Record, Scene
from .driver import simulate, simulate_batch


def _three_phase() -> ThreePhaseProfile:
    return ThreePhaseProfile(dt=1.05, dy=0.084, y2=2.2, y3=0.9)      # Fig. 18's profile


def _fourier() -> FourierProfile:
    return FourierProfile(dt=1.0, cos_coeffs=(0.0, 0.0), sin_coeffs=(0.1, 0.02))


def _scene(profile, **kwargs) -> Scene:
    """Three periods of ``profile``, on the stop zone of Fig. 18 if it is piecewise constant (the exact solver
    has closed-form zone arcs for it only), else on a uniform surface."""
    zone = StopZone(x_mu=0.15, w=0.05, c_mu=2.5) if isinstance(profile, ThreePhaseProfile) else Uniform()
    return Scene(profile=profile, surface=zone, periods=3, **kwargs)


def _recorded() -> Record:
    return Record(series=("x", "v"), samples_per_period=8, events=True, arcs=True)


def _planar(profile=None) -> Scene:
    """Three periods of a planar motion (``profile`` on both axes, a quarter period apart; default Fig. 18's)
    over a strip."""
    profile = _three_phase() if profile is None else profile
    return Scene(PlanarProfile(profile, profile, offset=0.25), Strip((0.6, 0.8), 0.15, 0.05, 2.5), x0=(0.0, 0.0),
                 periods=3)


#: Warm-up name -> (what it compiles, a run that reaches it).
WARMUPS: dict[str, tuple[str, Callable[[], object]]] = {
    "exact": ("the exact solver, piecewise-constant profiles",
              lambda: simulate(_scene(_three_phase()), method="exact")),
    "exact_smooth": ("the exact solver, smooth profiles",
                     lambda: simulate(_scene(_fourier()), method="exact")),
    "moreau": ("Moreau time-stepping", lambda: simulate(_scene(_three_phase()), method="moreau", steps_per_period=20)),
    "recorded_exact": ("the exact solver with dense output, piecewise-constant profiles",
                       lambda: simulate(_scene(_three_phase(), record=_recorded()), method="exact")),
    "recorded_smooth": ("the exact solver with dense output, smooth profiles",
                        lambda: simulate(_scene(_fourier(), record=_recorded()), method="exact")),
    "recorded_moreau": ("Moreau time-stepping with dense output",
                        lambda: simulate(_scene(_three_phase(), record=Record(series=("x",), samples_per_period=8)),
                                         method="moreau", steps_per_period=20)),
    "batch_uniform": ("batches on a uniform surface",
                      lambda: simulate_batch(_three_phase(), [0.0, 0.1], until="periods", periods=2)),
    "ivp": ("solve_ivp's compiled decisions", lambda: simulate(_scene(_three_phase()), method="ivp")),
    "parts_exact": ("the exact solver of several parts",
                    lambda: simulate(_scene(_three_phase(), parts=[Part(-0.1, width=0.05), Part(0.0, width=0.05)]),
                                     method="exact")),
    "parts_moreau": ("Moreau time-stepping of several parts",
                     lambda: simulate(_scene(_three_phase(), parts=[Part(-0.1, width=0.05), Part(0.0, width=0.05)]),
                                      method="moreau", steps_per_period=20)),
    "planar_moreau": ("Moreau time-stepping in the plane",
                      lambda: simulate(_planar(), method="moreau", steps_per_period=20)),
    "planar_exact": ("the exact planar solver, piecewise-constant motions on a uniform surface",
                     lambda: simulate(_planar().replace(surface=Uniform()), method="exact")),
    "planar_general": ("the exact planar solver's general stepper (strips, smooth motions)",
                       lambda: simulate(_planar(), method="exact")),
}


def warm_up(names: Iterable[str] | None = None) -> list[tuple[str, float]]:
    """Compile the solvers' entry points now (or load them from numba's cache), by tiny runs.

    Parameters
    ----------
    names : iterable of str, optional
        Keys of :data:`WARMUPS`; default all of them.

    Returns
    -------
    list of (str, float)
        Each warm-up's name and its wall time in seconds (compiling on an empty cache; loading from it
        afterwards).

    Raises
    ------
    ValueError
        If a name is not a key of :data:`WARMUPS` (before any run).
    KernelError
        If the compiled kernel cannot be built on this machine.

    Examples
    --------
    >>> from selfalign.solvers.warmup import warm_up
    >>> [name for name, seconds in warm_up(["exact", "moreau"])]
    ['exact', 'moreau']
    """
    names = list(WARMUPS) if names is None else list(names)
    unknown = [name for name in names if name not in WARMUPS]
    if unknown:
        raise ValueError(f"unknown warm-up {unknown[0]!r}; allowed: {', '.join(WARMUPS)}")
    times = []
    for name in names:
        start = time.perf_counter()
        WARMUPS[name][1]()
        times.append((name, time.perf_counter() - start))
    return times
