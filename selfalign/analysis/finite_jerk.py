"""What finite jerk does to the paper's results (docs/explanation/model.md).

The three-phase profile with y'' ramps of time tau at each switch
(:class:`~selfalign.model.profiles.FiniteJerkProfile`) against the paper's (tau = 0):

* :func:`steady_grid`: the steady-state average velocity vbar (eq. 10) and the case of
  Table 1 over a (y2'', y3'') grid for each ramp, by simulation with the exact solver
  (uniform surface; the closed forms of Sect. 5.1 exist only for tau = 0).  The case is read
  off one steady period: the modes its arcs take (:func:`steady_case`).
* :func:`stopping`: the outcome of n_entries steady-state entries into a stop zone
  (Sect. 7.1, placed as :mod:`selfalign.analysis.positioning` places them) and the
  positioning error Delta x_d (eq. 39), with the exact solver (its jerk arcs on the zone,
  docs/explanation/model.md), or Moreau time-stepping under Stribeck friction.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from ..model.errors import check_integer, check_positive
from ..model.friction import FrictionLaw, StopZone
from ..model.profiles import RAMPS_TOO_LONG, FiniteJerkProfile, ThreePhaseProfile
from ..model.scene import Record, Scene
from ..progress import Progress, resolve_mode
from ..solvers.driver import simulate, simulate_batch
from ..solvers.methods import most_exact_method
from ..solvers.outcomes import STATUS_CODES, Status
from ..solvers.tables import setting_profile
from .steady_simulation import exact_steady_state, simulated_steady_state


def jerk_profile(dt: float, dy: float, y2: float, y3: float, ramp_fraction: float):
    """The paper's ThreePhaseProfile for ramp_fraction 0, else the FiniteJerkProfile with ramp =
    ramp_fraction dt; None where no profile exists (case 0) and RAMPS_TOO_LONG where the ramps
    do not fit."""
    try:
        return setting_profile(dt, dy, y2, y3, ramp_fraction * dt)
    except ValueError as exc:
        return None if "no physical" in str(exc) else RAMPS_TOO_LONG


def steady_case(profile) -> tuple[float, int]:
    """(vbar, case of Table 1) of the profile's steady state on a uniform surface, exact solver.

    The steady motion from its period-boundary velocity is recorded over one cycle; its arcs
    of positive duration say the case: no slip, 5 (pure stick); no stick, 4 (slip-slip);
    stick and slip in one direction only, 1 (forward) or 2 (backward); both, 3.
    """
    state = exact_steady_state(profile, aperiodic="average")
    periods = max(int(state.cycle[0]), 1)
    traj = simulate(Scene(profile, v0=float(state.v0[0]), periods=periods, record=Record(arcs=True)))
    modes = set(traj.arcs["mode"][traj.arcs["duration"] > 0.0].tolist())
    forward, backward = 1 in modes, -1 in modes
    if not (forward or backward):
        case = 5
    elif 0 not in modes:
        case = 4
    elif forward and backward:
        case = 3
    else:
        case = 1 if forward else 2
    return float(state.vbar[0]), case


@dataclass(frozen=True)
class SteadyGrid:
    """vbar and case, shape (ramps, y2, y3); case 0: no profile, RAMPS_TOO_LONG: ramps do not fit."""

    ramp_fractions: np.ndarray
    y2: np.ndarray
    y3: np.ndarray
    vbar: np.ndarray
    case: np.ndarray


def steady_grid(dt: float, dy: float, y2, y3, ramp_fractions, progress: str = "auto") -> SteadyGrid:
    """:func:`steady_case` over the grid y2 x y3 (1-D axes) for every ramp fraction of the period."""
    y2, y3, fractions = (np.asarray(a, dtype=float) for a in (y2, y3, ramp_fractions))
    if y2.ndim != 1 or y3.ndim != 1 or fractions.ndim != 1:
        raise ValueError("y2, y3 and ramp_fractions must be 1-D")
    if np.any(fractions < 0.0) or np.any(fractions >= 0.5):
        raise ValueError(f"ramp_fractions must lie in [0, 0.5), got {fractions.tolist()}")
    resolve_mode(progress)
    vbar = np.full((fractions.size, y2.size, y3.size), np.nan)
    case = np.zeros(vbar.shape, dtype=np.int64)
    with Progress(vbar.size, "finite-jerk steady states", unit="settings", mode=progress) as bar:
        for index in np.ndindex(vbar.shape):
            k, i, j = index
            profile = jerk_profile(dt, dy, float(y2[i]), float(y3[j]), float(fractions[k]))
            if profile is RAMPS_TOO_LONG:
                case[index] = RAMPS_TOO_LONG
            elif profile is not None:
                vbar[index], case[index] = steady_case(profile)
            bar.advance()
    return SteadyGrid(fractions, y2, y3, vbar, case)


@dataclass(frozen=True)
class Stopping:
    """Outcome of the entries of one setting: fractions that accumulate, come to rest, never stop
    (or stay undecided), and Delta x_d = (max - min) / 2 of the end positions of those that stop."""

    frac_accumulate: float
    frac_rest: float
    frac_other: float
    dx_d: float


def stopping(profile, *, w: float, c_mu: float, n_entries: int = 16, steps_per_period: int = 10_000,
             max_periods: int = 1000, offset: float = 0.5, method: str = "batch",
             friction: FrictionLaw | None = None) -> Stopping:
    """Steady-state entries into a stop zone (module docstring), batched with the most exact
    method that takes the scene (:func:`~selfalign.solvers.methods.most_exact_method`: the exact
    solver, or Moreau with ``steps_per_period`` under Stribeck friction), or ``method="ivp"``
    (solve_ivp at its default tolerances, one run per entry: slow, the cross-check), under the
    :class:`~selfalign.model.friction.FrictionLaw` ``friction`` (default: the paper's Coulomb law).

    The steady state (uniform surface: exact solver under Coulomb friction, else Moreau with
    ``steps_per_period``, since the exact solver has no Stribeck arcs) gives vbar and the
    period-boundary velocity v0; the zone starts at x_mu = the largest advance within a
    steady period, and entry j starts at x = -vbar dt (j + offset) / n_entries, x' = v0,
    phase 0.  ValueError if the steady state does not move forward.
    """
    if not isinstance(profile, (ThreePhaseProfile, FiniteJerkProfile)):
        raise ValueError(f"profile must be a ThreePhaseProfile or FiniteJerkProfile, got {profile!r}")
    check_positive("w", w)
    check_positive("c_mu", c_mu)
    n_entries = check_integer("n_entries", n_entries)
    if method not in ("batch", "ivp"):
        raise ValueError(f"method must be 'batch' or 'ivp', got {method!r}")
    friction = FrictionLaw() if friction is None else friction
    if friction.kind == "coulomb":
        state = exact_steady_state(profile, aperiodic="average")
        steady_method, steady_options = "exact", {}
    else:
        state = simulated_steady_state([profile], "moreau", steps_per_period=steps_per_period, progress="quiet",
                                       friction=friction)
        steady_method, steady_options = "moreau", {"h": profile.dt / steps_per_period}
    vbar, v0 = float(state.vbar[0]), float(state.v0[0])
    if not vbar > 0.0:
        raise ValueError(f"the steady state of {profile!r} does not move forward (vbar = {vbar!r})")
    period = simulate(Scene(profile, v0=v0, periods=1, friction=friction,
                            record=Record(series=("x",), samples_per_period=2000)),
                      method=steady_method, **steady_options)
    x_mu = float(np.max(period.series["x"]))        # the largest x is at a v = 0 event, which is sampled
    x0 = -vbar * profile.dt * (np.arange(n_entries) + offset) / n_entries
    zone = StopZone(x_mu, w, c_mu)
    if method == "batch":
        choice = most_exact_method(profile, zone, friction)
        options = {"steps_per_period": steps_per_period, "iteration": "exact"} if choice.method == "moreau" else {}
        res = simulate_batch(profile, x0, v0, surface=zone, until="rest", max_periods=max_periods,
                             method=choice.method, friction=friction, **options)
        codes, x_end = np.asarray(res.status), res.x_end
    else:
        runs = [simulate(Scene(profile, surface=zone, x0=float(x), v0=v0, until="rest", max_periods=max_periods,
                               friction=friction), method="ivp") for x in x0]
        codes, x_end = np.array([STATUS_CODES[run.status] for run in runs]), np.array([run.x_end for run in runs])
    # Status codes, the batch result's own form (STATUS_CODES), for both methods.
    accumulate, rest = codes == STATUS_CODES[Status.ACCUMULATION], codes == STATUS_CODES[Status.REST]
    stops = accumulate | rest
    ends = x_end[stops]
    return Stopping(float(np.mean(accumulate)), float(np.mean(rest)), float(np.mean(~stops)),
                    float((ends.max() - ends.min()) / 2.0) if ends.size else float("nan"))


@dataclass(frozen=True)
class StoppingGrid:
    """:func:`stopping` over a grid, shape (ramps, y2, y3); NaN where the mass does not move forward,
    no profile exists or the ramps do not fit."""

    ramp_fractions: np.ndarray
    y2: np.ndarray
    y3: np.ndarray
    frac_accumulate: np.ndarray
    frac_rest: np.ndarray
    dx_d: np.ndarray


def stopping_grid(dt: float, dy: float, y2, y3, ramp_fractions, *, w: float, c_mu: float, n_entries: int = 16,
                  max_periods: int = 1000, progress: str = "auto") -> StoppingGrid:
    """:func:`stopping` over the grid y2 x y3 (1-D axes) for every ramp fraction of the period."""
    y2, y3, fractions = (np.asarray(a, dtype=float) for a in (y2, y3, ramp_fractions))
    if y2.ndim != 1 or y3.ndim != 1 or fractions.ndim != 1:
        raise ValueError("y2, y3 and ramp_fractions must be 1-D")
    resolve_mode(progress)
    out = {key: np.full((fractions.size, y2.size, y3.size), np.nan) for key in ("frac_accumulate", "frac_rest", "dx_d")}
    with Progress(out["dx_d"].size, "finite-jerk stopping", unit="settings", mode=progress) as bar:
        for index in np.ndindex(out["dx_d"].shape):
            k, i, j = index
            profile = jerk_profile(dt, dy, float(y2[i]), float(y3[j]), float(fractions[k]))
            if profile is not None and profile is not RAMPS_TOO_LONG:
                vbar, case = steady_case(profile)
                if vbar > 0.0:
                    result = stopping(profile, w=w, c_mu=c_mu, n_entries=n_entries, max_periods=max_periods)
                    out["frac_accumulate"][index] = result.frac_accumulate
                    out["frac_rest"][index] = result.frac_rest
                    out["dx_d"][index] = result.dx_d
            bar.advance()
    return StoppingGrid(fractions, y2, y3, **out)
