"""What each method can simulate and which options it takes, declared once.

A scene file is checked against these declarations when it is loaded
(:func:`selfalign.io.scene_files.scene_from_dict` calls :func:`check_scene`), so a
scene a method cannot simulate, or an option it does not take or a value it cannot
use, is refused before any work starts, in one line naming the option and what is
allowed.  :func:`resolve` fills in the defaults.  Nothing here imports numba or scipy.
"""

from __future__ import annotations

import math
import numbers
from dataclasses import dataclass, field
from types import SimpleNamespace
from typing import Callable

from ..model.errors import check_choice
from ..model.friction import StopZone
from ..model.profiles import FourierProfile, PiecewiseLinearProfile
from . import records as R
from .moreau import MAX_STEPS_PER_PERIOD, moreau_step, profile_row

#: Most Moreau steps of one run (periods of the horizon x steps per period), checked before
#: the run: the scheme has no event budget, so its horizon is its work.  Measured on one core:
#: 2-4 ns per step (Coulomb friction, exact iteration), 11 ns (fixed-point iteration), 39 ns
#: (Stribeck friction), so 1e10 steps take 20 s to 7 min; the default (10,000 periods x 1000) is 1e7.
MAX_MOREAU_STEPS = 10**10
#: Largest ``max_events`` (exact and ivp): event budgets of one run beyond this are refused.
#: The exact solver needs 10 ns (piecewise-constant y'', uniform surface) to 0.5 us (finite jerk on
#: a stop zone) per event, so 1e10 events are minutes to hours; the default is 5e7 (ivp: 1e6).
MAX_EVENTS = 10**10
#: Largest ``fp_max_iter``: sweeps of the fixed-point iteration per Moreau step (default 200;
#: it converges linearly, and a step that needs more is reported, not hidden).
MAX_FP_ITERATIONS = 10_000
#: Largest ``accumulation_tol`` as a fraction of the zone width w.  An accumulation is
#: declared at a stick within the tolerance of x_stick_min (eq. 41) and reported at
#: x_stick_min, so a tolerance is an accepted position error: on 2,209 random three-phase
#: settings x 3 zones x 32 entries (positioning_grid), tolerances up to 1e-5 w left every x_d
#: unchanged, while 1e-4 w and 1e-3 w moved x_d by 2.4 and 4 times the tolerance (sticks
#: short of x_stick_min taken for converged although the mass slid on to rest beyond it).
#: Tolerances below 64 ulp of w are raised to that (outcomes.ACC_TOL_ULPS); the default,
#: :data:`ACCUMULATION_TOL`, is accepted for any w.
MAX_ACCUMULATION_TOL = 1e-6
#: Default ``accumulation_tol`` of every method (absolute, dimensionless length).
ACCUMULATION_TOL = 1e-12
#: Tolerances of solve_ivp the ivp method accepts.  rtol: from 100 eps (scipy raises smaller values
#: to it, with a warning) to 1e-3 (the method is the accuracy baseline: a looser one is a mistake).
#: atol: from 1e-15 (positions and velocities are dimensionless, of order 1e-3 to 1e2 in the
#: paper's scenes; a smaller atol asks more digits of a state crossing 0 than doubles carry, and
#: the step control then shrinks steps without end: workflow/scenes/stop_zone.yaml took 0.02 s at
#: 1e-15 and did not finish in 60 s at 1e-30) to 1e-3.
IVP_RTOL, IVP_ATOL = (100 * 2.0**-52, 1e-3), (1e-15, 1e-3)
#: Most solve_ivp steps per period a slip can need under Stribeck friction (:func:`ivp_slip_step`),
#: checked before the run: at ~20 us a step, 1e6 steps are 20 s per period.
MAX_IVP_STEPS_PER_PERIOD = 10**6
#: The integrators of scipy.integrate.solve_ivp the ivp method can use.
INTEGRATORS = ("RK23", "RK45", "DOP853", "Radau", "BDF", "LSODA")
#: Iterations of the implicit Moreau step.
ITERATIONS = ("exact", "fixed_point")


def _type(name, value, what):
    """TypeError unless ``value`` is a real number (not a bool): the option's ``what``."""
    if isinstance(value, bool) or not isinstance(value, numbers.Real):
        raise TypeError(f"option {name} must be {what}, got {value!r} ({type(value).__name__})")


def _real(name, value, low=0.0, high=math.inf, low_open=True, high_open=True):
    _type(name, value, "a real number (int, float or numpy scalar)")
    ok = math.isfinite(value)
    ok = ok and (value > low if low_open else value >= low) and (value < high if high_open else value <= high)
    if not ok:
        lo = f"{'>' if low_open else '>='} {low:g}"
        hi = "" if high == math.inf else f" and {'<' if high_open else '<='} {high:g}"
        raise ValueError(f"option {name} must be a finite number {lo}{hi}, got {value!r}")
    return float(value)


def _integer(name, value, high, low=1):
    """``value`` as an int: an integer (or integral float, ``1e6``) in [low, high]."""
    _type(name, value, "an integer")
    if not (isinstance(value, numbers.Integral) or math.isfinite(value) and float(value).is_integer()) \
            or not low <= value <= high:
        raise ValueError(f"option {name} must be an integer in [{low}, {high:,}], got {value!r}")
    return int(value)


def _choice(name, value, allowed):
    if value not in allowed:
        raise ValueError(f"option {name} must be one of {list(allowed)}, got {value!r}")
    return value


@dataclass(frozen=True)
class Option:
    """One option: its default and the check that returns the value to use (or raises)."""

    default: object
    check: Callable
    help: str


@dataclass(frozen=True)
class Method:
    """A method: its options and what it refuses (``refuses(scene)`` returns a reason or None)."""

    name: str
    summary: str
    options: dict = field(default_factory=dict)
    refuses: Callable = lambda scene: None


def friction_refused(method: str, friction, options: dict) -> str | None:
    """Why ``method`` with ``options`` cannot simulate the friction law ``friction``, or None.
    Static/kinetic friction every method simulates; Stribeck friction has no closed-form arcs."""
    if not friction.stribeck:
        return None
    if method == "exact":
        return ("method 'exact' cannot simulate Stribeck friction (friction.kind: stribeck): slip under "
                "mu(v) = mu_k + (mu_s - mu_k) exp(-(|v|/v_s)^delta) has no closed-form arcs; use method 'ivp' "
                "or 'moreau'")
    if method == "moreau" and options.get("iteration") == "fixed_point":
        return ("option iteration 'fixed_point' cannot solve the implicit step under Stribeck friction "
                "(friction.kind: stribeck); use iteration 'exact', which solves it for the smooth law")
    return None


def ivp_slip_step(profile, surface, law) -> float:
    """The longest solve_ivp step of a slip (``inf`` but under Stribeck friction).

    Stribeck friction rises from mu_k to mu_s within |v| ~ v_s of v = 0.  A step longer than that
    band takes to cross can sample the slip law only at speeds where it is mu_k: its error estimate
    is blind to the extra friction, and the step is accepted with an error far above rtol.  So v
    may change by at most v_s in one step, |x''| being at most max|y''| + r max mu_bar."""
    if not law.stribeck:
        return math.inf
    top_mu = surface.c_mu if isinstance(surface, StopZone) else 1.0
    return law.v_s / (profile.max_abs_acceleration + law.ratio * top_mu)


def check_ivp_work(scene) -> None:
    """ValueError if a slip of ``scene`` under Stribeck friction needs more than
    :data:`MAX_IVP_STEPS_PER_PERIOD` solve_ivp steps per period (:func:`ivp_slip_step`), naming v_s,
    the estimate and the limit."""
    steps = scene.profile.dt / ivp_slip_step(scene.profile, scene.surface, scene.friction)
    if steps > MAX_IVP_STEPS_PER_PERIOD:
        raise ValueError(f"friction v_s = {scene.friction.v_s!r} is too small for method 'ivp': a slip step may "
                         f"change v by at most v_s, so a period needs up to {steps:.3g} solve_ivp steps (at most "
                         f"{MAX_IVP_STEPS_PER_PERIOD:.0e} allowed, ~20 us each); use method 'moreau', whose implicit "
                         f"step solves the Stribeck law at any v_s")


def _exact_refuses(scene):
    smooth = (FourierProfile, PiecewiseLinearProfile)
    if isinstance(scene.profile, FourierProfile) and isinstance(scene.surface, StopZone):
        return ("method 'exact' cannot simulate a Fourier profile on a stop zone (it has closed-form arcs with "
                "position-dependent friction only for a piecewise-linear y''); use method 'moreau' or 'ivp'")
    if not (getattr(scene.profile, "piecewise_constant", False) or isinstance(scene.profile, smooth)):
        return (f"method 'exact' needs a piecewise-constant, piecewise-linear-y'' or Fourier profile, got "
                f"{type(scene.profile).__name__}")
    return None


def _moreau_h(name, value):
    return None if value is None else _real(name, value)


METHODS = {
    "exact": Method("exact", "event-driven, closed-form arcs and event times", {
        "accumulation_tol": Option(ACCUMULATION_TOL, lambda n, v: _real(n, v),
                                   "an accumulation ends within this distance of x_stick_min"),
        "max_events": Option(50_000_000, lambda n, v: _integer(n, v, MAX_EVENTS), "event budget of the run"),
    }, _exact_refuses),
    "moreau": Method("moreau", "Moreau midpoint time-stepping with the exact table impulse of each step", {
        "h": Option(None, _moreau_h, "time step (adjusted down to dt / N); None: dt / 1000"),
        "steps_per_period": Option(None, lambda n, v: None if v is None else _integer(n, v, MAX_STEPS_PER_PERIOD),
                                   "N steps per period instead of h (h = dt / N); not with h"),
        "iteration": Option("exact", lambda n, v: _choice(n, v, ITERATIONS),
                            "implicit friction step: exact soft threshold or the paper's fixed-point iteration"),
        "fp_tol": Option(1e-14, lambda n, v: _real(n, v), "fixed-point iteration: stop when v changes by <= this"),
        "fp_max_iter": Option(200, lambda n, v: _integer(n, v, MAX_FP_ITERATIONS),
                              "fixed-point iteration: most sweeps per step"),
        "accumulation_tol": Option(ACCUMULATION_TOL, lambda n, v: _real(n, v),
                                   "an accumulation ends within this distance of the scheme's x_stick_min"),
    }),
    "ivp": Method("ivp", "scipy.integrate.solve_ivp mode by mode with event location", {
        "rtol": Option(1e-8, lambda n, v: _real(n, v, *IVP_RTOL, False, False), "relative tolerance of solve_ivp"),
        "atol": Option(1e-10, lambda n, v: _real(n, v, *IVP_ATOL, False, False), "absolute tolerance of solve_ivp"),
        "integrator": Option("DOP853", lambda n, v: _choice(n, v, INTEGRATORS), "solve_ivp method"),
        "max_events": Option(1_000_000, lambda n, v: _integer(n, v, MAX_EVENTS), "event budget of the run"),
        "accumulation_tol": Option(ACCUMULATION_TOL, lambda n, v: _real(n, v),
                                   "an accumulation ends within this distance of x_stick_min"),
    }),
}


def resolve(method: str, options: dict) -> dict:
    """The options of ``method`` with defaults filled in and every value checked.

    TypeError for a method that is not a string; ValueError naming an unknown method, an
    unknown option, or a value that is not allowed (and what is).
    """
    check_choice("method", method, METHODS)
    spec = METHODS[method].options
    unknown = sorted(set(options) - set(spec))
    if unknown:
        raise ValueError(f"unknown option(s) {unknown} for method {method!r}; allowed: {sorted(spec)}")
    return {name: opt.check(name, options[name]) if name in options else opt.default
            for name, opt in spec.items()}


#: The options each method takes for a scene with several parts (the others do nothing there).
PARTS_OPTIONS = {"exact": ("max_events",), "moreau": ("h", "steps_per_period")}


def parts_refused(method: str, scene, given: dict) -> str | None:
    """Why ``method`` with the options ``given`` cannot simulate the several parts of ``scene``, or None:
    the exact solver of several parts (:mod:`selfalign.solvers.parts_exact`) takes piecewise-constant
    profiles, Moreau's (:mod:`selfalign.solvers.parts_moreau`) any profile and surface
    for a number of periods, ivp none; options the solver of several parts does not use are refused."""
    if method not in PARTS_OPTIONS:
        return f"method {method!r} cannot simulate several parts; use 'exact' or 'moreau'"
    idle = sorted(set(given) - set(PARTS_OPTIONS[method]))
    if idle:
        return (f"option(s) {idle} do nothing for a scene with parts; method {method!r} takes "
                f"{list(PARTS_OPTIONS[method])} there")
    if method == "exact" and not getattr(scene.profile, "piecewise_constant", False):
        return (f"method 'exact' simulates several parts under a piecewise-constant profile (closed-form arcs), got "
                f"{type(scene.profile).__name__}; use method 'moreau'")
    if method == "moreau" and scene.until != "periods":
        return ("method 'moreau' simulates several parts for a number of periods (it has no rest decision for "
                "them); use horizon periods=N, or method 'exact'")
    return None


#: The options each method takes for a planar scene (docs/explanation/planar-model.md).
PLANAR_OPTIONS = {"exact": ("max_events",), "moreau": ("h", "steps_per_period"),
                  "ivp": ("rtol", "atol", "integrator", "max_events")}


def planar_refused(method: str, scene, given: dict) -> str | None:
    """Why ``method`` with the options ``given`` cannot simulate the planar ``scene``, or None: every method
    simulates every planar scene (the exact one in closed form for piecewise-constant Y'' on a uniform surface,
    else on an accurate local solution); options a planar solver does not use are refused."""
    idle = sorted(set(given) - set(PLANAR_OPTIONS[method]))
    if idle:
        return (f"option(s) {idle} do nothing for a planar scene; method {method!r} takes "
                f"{list(PLANAR_OPTIONS[method])} there")
    return None


def scene_refused(method: str, scene, given: dict) -> str | None:
    """Why ``method`` with the options ``given`` cannot simulate ``scene``, or None: for several parts
    :func:`parts_refused`, for planar motion :func:`planar_refused`, else the method's own refusal of the scene
    (its profile and surface) or of the friction law (:func:`friction_refused`; an option it reads that is not
    given has its default, which it accepts)."""
    if scene.parts is not None:
        return parts_refused(method, scene, given)
    if scene.planar:
        return planar_refused(method, scene, given)
    return METHODS[method].refuses(scene) or friction_refused(method, scene.friction, given)


def check_scene(scene, method: str | None = None, options: dict | None = None) -> dict:
    """Check that ``method`` (default: the scene's) can simulate ``scene`` with ``options``
    (default: the scene's solver options); return the resolved options.  ValueError with
    the reason otherwise."""
    method = scene.method if method is None else method
    given = scene.solver_options if options is None else options
    options = resolve(method, given)
    reason = scene_refused(method, scene, given)
    if reason:
        raise ValueError(reason)
    if scene.parts is not None or scene.planar:
        if method == "moreau":
            check_moreau_work(moreau_step(scene.profile.dt, options)[0], scene.horizon_periods,
                              "horizon.periods" if scene.until == "periods" else "horizon.max_periods")
        return options
    if method == "moreau":
        n = R.data_size(profile_row(scene.profile, scene.phase, options))
        check_moreau_work(n, scene.horizon_periods, "horizon.periods" if scene.until == "periods"
                          else "horizon.max_periods")
    if method == "ivp":
        check_ivp_work(scene)
    if isinstance(scene.surface, StopZone):
        check_accumulation_tol(options["accumulation_tol"], scene.surface.w)
    return options


def check_accumulation_tol(tol: float, w: float) -> None:
    """ValueError if the option ``accumulation_tol`` exceeds :data:`MAX_ACCUMULATION_TOL` of
    the zone width ``w`` (the narrowest zone of a batch) and the default :data:`ACCUMULATION_TOL`."""
    limit = max(MAX_ACCUMULATION_TOL * w, ACCUMULATION_TOL)
    if tol > limit:
        raise ValueError(f"option accumulation_tol = {tol!r} is more than {MAX_ACCUMULATION_TOL:g} of the zone "
                         f"width w = {w!r} (at most {limit:.6g}): an accumulation ends at a stick "
                         f"within accumulation_tol of x_stick_min (eq. 41) and reports x_stick_min, so a coarser "
                         f"tolerance takes sticks short of it for converged where the mass may still slide on")


def check_moreau_work(n: int, periods: int, name: str) -> None:
    """ValueError if ``periods`` periods (the horizon option ``name``) of ``n`` Moreau steps
    exceed :data:`MAX_MOREAU_STEPS`, naming the option, the estimate and the limit."""
    if n * periods > MAX_MOREAU_STEPS:
        raise ValueError(f"method moreau: {name} = {periods:,} periods at {n:,} steps per period is up to "
                         f"{n * periods:.3g} steps, more than the {MAX_MOREAU_STEPS:.0e} allowed per run (Moreau has "
                         f"no event budget: its horizon is its work, 4-40 ns per step); shorten the horizon to at "
                         f"most {MAX_MOREAU_STEPS // n:,} periods or take fewer steps per period")


#: Moreau steps per period when the exact solver cannot simulate a scene (:func:`most_exact_method`):
#: h = dt / 2000, first order, so end positions carry an error of order h^2 (tests/test_design_effects.py
#: checks a design's guarantee against Moreau at a 4x finer step).
FALLBACK_STEPS_PER_PERIOD = 2000


@dataclass(frozen=True)
class MethodChoice:
    """The method an analysis runs (``method``, ``options`` for it) and, when it is not the exact
    solver, why (``refusal``: the exact solver's own message)."""

    method: str
    options: dict
    refusal: str = ""

    def describe(self) -> str:
        """One line: "exact" or "moreau (h = dt / N, iteration exact)"."""
        if self.method == "exact":
            return "exact (event-driven, closed-form arcs)"
        return (f"moreau (h = dt / {self.options['steps_per_period']}, iteration {self.options['iteration']}): "
                f"the exact solver refuses the scene")


def most_exact_method(profile, surface, friction) -> MethodChoice:
    """The exact solver if it can simulate ``profile`` on ``surface`` under the
    :class:`~selfalign.model.friction.FrictionLaw` ``friction``, otherwise Moreau time-stepping
    with :data:`FALLBACK_STEPS_PER_PERIOD` steps per period and the implicit step solved exactly
    (the only iteration that handles Stribeck friction).  The refusals are the methods' own
    (:data:`METHODS`, :func:`friction_refused`), so this follows them as they change."""
    scene = SimpleNamespace(profile=profile, surface=surface, friction=friction)
    refusal = METHODS["exact"].refuses(scene) or friction_refused("exact", friction, {})
    if refusal is None:
        return MethodChoice("exact", {})
    return MethodChoice("moreau", {"steps_per_period": FALLBACK_STEPS_PER_PERIOD, "iteration": "exact"}, refusal)
