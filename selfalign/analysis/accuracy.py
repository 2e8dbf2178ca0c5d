"""Work-precision study: Moreau time-stepping and solve_ivp against the exact solver.

For one scene (a fixed horizon of N >= 2 periods) every method is run through
:func:`selfalign.simulate` and compared with the exact event-driven solver, the
reference:

* Moreau time-stepping over a geometric range of steps per period (h = dt / n);
* ``solve_ivp`` (DOP853) over a geometric range of relative tolerances, with
  ``atol = atol_factor * rtol`` (positions are O(0.01-1), so atol only matters
  near x = 0);
* the exact solver once.

A scene with several parts (docs/explanation/several-parts.md) is studied the same way, with
the solvers of several parts: Moreau's time-stepping against the exact event-driven solver.
A planar scene (docs/explanation/planar-model.md) is studied with the planar solvers, all three; its
errors are the largest over the two coordinates, max(|x_1(N) - x_1,ref(N)|, |x_2(N) - x_2,ref(N)|).
``solve_ivp`` cannot simulate several parts, so it is not run: the result has no group ``ivp``
and its attribute ``ivp_not_run`` gives the reason.  An error is then the largest over the
parts, max_i |x_i(N) - x_i,ref(N)| (the maximum norm of the end positions), and likewise for vbar.

The reference is the exact solver.  A scene the exact solver refuses (Stribeck friction:
no closed-form arcs) names its reference in its own solver block instead, e.g. ``ivp``
with tolerances far below the study's (:func:`reference_solver`); the group ``exact`` of
the result then holds that reference run, and the attribute ``reference`` says which.

Measured per run: the **end-position error** |x(N) - x_ref(N)| and the **error of
the average velocity** vbar = (x(N) - x(N - 1)) / dt over the last period (eq. 10
taken over one period; in steady state this is the paper's vbar), against the
**CPU time** (``time.process_time`` around one ``simulate`` call over the N
periods).  Every method runs under the same driver, which fast-forwards a repeating
period-boundary state: the CPU time is that of the periods each run actually simulated
(``fast_forward_periods`` says how many it skipped; in a steady state nearly all).
x(N - 1) comes from a second, untimed call over N - 1 periods: the
solvers are deterministic, so it is the state the timed run passes at that time
(up to rounding).  Runs shorter than ``min_timing`` are repeated and the fastest
is kept (like ``timeit``), after one untimed warm-up per method so that no import
is timed.

Derived numbers:

* **Moreau order**: Theil-Sen slope of log(error) against log(h) over the runs with
  n >= ``fit_min_steps_per_period`` (the pre-asymptotic coarse steps are left out)
  and errors above 100 times the rounding level.  Theil-Sen (the median of pairwise
  slopes) because the error constant of a first-order scheme at a discontinuity
  depends on where the switch and stick times fall within a step, which scatters
  single points by up to a factor of ~30; a least-squares fit is pulled by the
  lucky cancellations.
* **CPU time at the target error** (1e-6): the step h* at which the fitted error
  line reaches the target, and the CPU time at h* interpolated linearly on the
  log-log curve of CPU time against h (extrapolated from the end segment, and
  flagged, when h* is outside the measured range).  The **speed ratio** is that
  time over the exact solver's.
* **ivp agreement**: the largest ratio err_end / rtol over the tolerances.
* **Exact events per second**: the exact solver once more with the event log on,
  which switches its steady-state fast-forward off (every event is computed).
"""

from __future__ import annotations

import math
import time
from dataclasses import asdict, dataclass

import numpy as np

from ..model.scene import Record, Scene
from ..progress import Progress, resolve_mode
from ..solvers.driver import simulate
from ..solvers.methods import scene_refused

#: Double-precision unit roundoff scale used for the rounding levels.
_EPS = np.finfo(float).eps
#: Repeats of one timed run at most (short runs are repeated until min_timing).
MAX_REPEATS = 1000


@dataclass(frozen=True)
class StudySettings:
    """What :func:`study` runs.  Ranges are ``(from, to, count)``, geometric, both ends included."""

    moreau_steps_per_period: tuple[float, float, int] = (10, 1_000_000, 21)
    ivp_rtol: tuple[float, float, int] = (1e-3, 1e-11, 5)
    ivp_atol_factor: float = 1e-2
    fit_min_steps_per_period: float = 100
    target_error: float = 1e-6
    min_timing: float = 0.05

    def __post_init__(self):
        for name in ("moreau_steps_per_period", "ivp_rtol"):
            lo, hi, count = getattr(self, name)
            if not (lo > 0 and hi > 0 and int(count) == count and count >= 2):
                raise ValueError(f"{name} must be (from > 0, to > 0, count >= 2 integer), got {(lo, hi, count)}")
        if min(self.moreau_steps_per_period[:2]) < 1:
            raise ValueError(f"moreau_steps_per_period must be >= 1, got {self.moreau_steps_per_period}")
        if max(self.ivp_rtol[:2]) >= 1:
            raise ValueError(f"ivp_rtol must be < 1, got {self.ivp_rtol}")
        for name in ("ivp_atol_factor", "fit_min_steps_per_period", "target_error", "min_timing"):
            value = getattr(self, name)
            if not (isinstance(value, (int, float)) and math.isfinite(value) and value > 0):
                raise ValueError(f"{name} must be a finite number > 0, got {value!r}")

    @classmethod
    def from_config(cls, config: dict) -> "StudySettings":
        """Settings from the workflow config block (ranges as ``{from, to, count}``)."""
        def rng(block):
            return (block["from"], block["to"], block["count"])

        values = dict(config)
        for name in ("moreau_steps_per_period", "ivp_rtol"):
            if name in values:
                values[name] = rng(values[name])
        unknown = sorted(set(values) - set(cls.__dataclass_fields__))
        if unknown:
            raise ValueError(f"unknown accuracy setting(s) {unknown}; allowed: {sorted(cls.__dataclass_fields__)}")
        return cls(**values)

    def steps_per_period(self) -> np.ndarray:
        """Distinct integer steps per period n (h = dt / n), ascending."""
        lo, hi, count = self.moreau_steps_per_period
        return np.unique(np.round(np.geomspace(lo, hi, int(count))).astype(np.int64))

    def rtols(self) -> np.ndarray:
        """Relative tolerances of solve_ivp, descending (coarse first)."""
        lo, hi, count = self.ivp_rtol
        return np.sort(np.geomspace(lo, hi, int(count)))[::-1]


@dataclass(frozen=True)
class Run:
    """One timed run: end state of the last two periods, cost and outcome (positions and vbar: one per part
    for a scene with several parts)."""

    x_prev: float | np.ndarray
    x_end: float | np.ndarray
    vbar: float | np.ndarray
    cpu_time: float
    steps: int
    events: int
    status: str
    fast_forward_periods: int


def _check_scene(scene: Scene) -> None:
    if scene.until != "periods" or scene.horizon_periods < 2:
        raise ValueError(f"scene {scene.name!r}: the accuracy study needs horizon.periods >= 2 "
                         f"(the average velocity is taken over the last period), got "
                         f"{'until: rest' if scene.until == 'rest' else scene.periods}")


def reference_solver(scene: Scene) -> tuple[str, dict]:
    """(method, options) of the study's reference: the exact solver, or the scene's solver block
    where the exact solver cannot simulate the scene; ValueError if that block names exact."""
    refused = scene_refused("exact", scene, {})
    if refused is None:
        return "exact", {}
    if scene.method == "exact":
        raise ValueError(f"scene {scene.name!r}: the accuracy study has no reference, {refused}; name the "
                         f"reference in the scene's solver block (method moreau or ivp, with tight tolerances)")
    return scene.method, dict(scene.solver_options)


def reference_text(method: str, options: dict) -> str:
    """The reference in words, e.g. ``exact`` or ``ivp rtol=1e-13 atol=1e-15``."""
    return " ".join([method, *(f"{k}={v:g}" if isinstance(v, float) else f"{k}={v}" for k, v in options.items())])


def best_time(call, min_timing: float):
    """(result of ``call()``, its smallest CPU time); repeated until the times add up to ``min_timing``."""
    best, total, repeats = math.inf, 0.0, 0
    while repeats == 0 or (total < min_timing and repeats < MAX_REPEATS):
        start = time.process_time()
        result = call()
        elapsed = time.process_time() - start
        best, total, repeats = min(best, elapsed), total + elapsed, repeats + 1
    return result, best


def timed_run(scene: Scene, method: str, options: dict, min_timing: float) -> Run:
    """Run ``scene`` with ``method``: x(N - 1) untimed, then x(N) timed as described above.

    With several parts the positions are arrays (one per part) and ``fast_forward_periods`` is 0: the
    solvers of several parts simulate every period."""
    _check_scene(scene)
    scene = scene.replace(record=Record())
    head = simulate(scene.replace(periods=scene.horizon_periods - 1), method, **options)
    full, best = best_time(lambda: simulate(scene, method, **options), min_timing)
    x_prev, x_end = (np.array(x, dtype=float) if scene.parts is not None or scene.planar else float(x)
                     for x in (head.x_end, full.x_end))
    return Run(x_prev=x_prev, x_end=x_end, vbar=(x_end - x_prev) / scene.profile.dt, cpu_time=best,
               steps=int(full.stats.get("steps", 0)), events=int(full.stats.get("events", 0)),
               status=full.status.value,
               fast_forward_periods=int(full.info.get("fast_forward_periods", 0)))


def fit_loglog(x, y) -> tuple[float, float, float, float]:
    """Theil-Sen fit of log y = intercept + slope log x: (slope, intercept, low, high), 95 % interval."""
    from scipy.stats import theilslopes

    x, y = np.asarray(x, dtype=float), np.asarray(y, dtype=float)
    if x.size < 3:
        raise ValueError(f"a log-log fit needs at least 3 points, got {x.size}")
    res = theilslopes(np.log(y), np.log(x))
    return float(res.slope), float(res.intercept), float(res.low_slope), float(res.high_slope)


def loglog_interpolate(x0: float, x, y) -> tuple[float, bool]:
    """y at x0 by linear interpolation of log y over log x; (value, inside the range of x).

    Outside the range the end segment is extended.
    """
    order = np.argsort(x)
    lx, ly = np.log(np.asarray(x, dtype=float)[order]), np.log(np.asarray(y, dtype=float)[order])
    l0 = math.log(x0)
    inside = bool(lx[0] <= l0 <= lx[-1])
    i = int(np.clip(np.searchsorted(lx, l0) - 1, 0, lx.size - 2))
    slope = (ly[i + 1] - ly[i]) / (lx[i + 1] - lx[i])
    return float(math.exp(ly[i] + slope * (l0 - lx[i]))), inside


def _warm_up(scene: Scene) -> None:
    """One untimed short call per method that can simulate the scene, so that imports are not timed."""
    short = scene.replace(periods=1, record=Record())
    for method in ("exact", "moreau", "ivp"):
        if scene_refused(method, scene, {}) is None:
            simulate(short, method)


def _table(runs: list[Run], ref: Run) -> dict[str, np.ndarray]:
    return {
        "cpu_time": np.array([r.cpu_time for r in runs]),
        "err_end_position": np.array([np.max(np.abs(r.x_end - ref.x_end)) for r in runs]),
        "err_vbar": np.array([np.max(np.abs(r.vbar - ref.vbar)) for r in runs]),
        "x_end": np.array([r.x_end for r in runs]),
        "vbar": np.array([r.vbar for r in runs]),
        "steps": np.array([r.steps for r in runs], dtype=np.int64),
        "events": np.array([r.events for r in runs], dtype=np.int64),
        "status": np.array([r.status for r in runs], dtype=str),
        "fast_forward_periods": np.array([r.fast_forward_periods for r in runs], dtype=np.int64),
    }


def study(scene: Scene, settings: StudySettings = StudySettings(), *, progress: str = "auto"
          ) -> tuple[dict, dict, dict]:
    """Run the work-precision study of ``scene``: (datasets, attrs, groups) for :func:`write_h5`.

    Layout: root attributes with the derived numbers (``moreau_order`` with its
    95 % interval ``moreau_order_low/high``, the order of the vbar error
    ``moreau_order_vbar`` and the number of fitted runs ``moreau_fit_points``;
    ``moreau_h_at_target``, ``target_interpolated``; ``ivp_max_err_over_rtol``;
    ``rounding_level_position`` = 4 eps max|x| and
    ``rounding_level_vbar`` = 2 rounding_level_position / dt; ``x_ref_end``,
    ``vbar_ref``; ``target_error``; ``settings``; ``scene_name``, ``scene``; ``reference``,
    :func:`reference_text` of the reference, ``exact`` unless the scene names another); root
    datasets ``moreau_cpu_at_target``, ``speed_ratio_at_target`` and
    ``exact_events_per_second``; group ``moreau`` with datasets ``h``, ``steps_per_period``
    and the :func:`_table` columns; group ``ivp`` with ``rtol``, ``atol`` and the same
    columns (a scene with several parts has none, and the attribute ``ivp_not_run`` instead of
    ``ivp_max_err_over_rtol``; its ``x_end``, ``vbar`` have one column per part, ``x_ref_end``,
    ``vbar_ref`` one entry per part, and the attribute ``parts`` counts them, 1 for the paper's
    scene; a planar scene's have two columns, the coordinates, and the attribute ``planar`` is True);
    group ``exact`` with attributes ``x_end``, ``vbar``, ``steps``, ``events``, ``status``,
    ``fast_forward_periods``, ``events_run_events`` and datasets ``cpu_time``,
    ``events_run_cpu_time``.  Every CPU time and what is computed from one is a dataset
    marked as a measurement (:mod:`selfalign.io.quantities`), never an attribute, so that two
    studies of one scene are byte-identical apart from those datasets.  ``progress`` reports
    the runs (:mod:`selfalign.progress`); it is called between the timed calls, never inside one.
    """
    import yaml

    _check_scene(scene)
    reference, reference_options = reference_solver(scene)
    resolve_mode(progress)
    dt = float(scene.profile.dt)
    steps_per_period = settings.steps_per_period()
    ivp_refused = scene_refused("ivp", scene, {})
    rtols = settings.rtols() if ivp_refused is None else np.empty(0)
    atols = settings.ivp_atol_factor * rtols
    with Progress(2 + steps_per_period.size + rtols.size, f"accuracy study of {scene.name}", unit="runs",
                  mode=progress) as bar:
        _warm_up(scene)

        def run(method: str, options: dict, note: str) -> Run:
            result = timed_run(scene, method, options, settings.min_timing)
            bar.advance(note=note)
            return result

        ref = run(reference, reference_options, reference)
        moreau = [run("moreau", {"h": dt / int(n)}, f"Moreau h = dt/{int(n)}") for n in steps_per_period]
        ivp = [run("ivp", {"rtol": float(r), "atol": float(a)}, f"ivp rtol = {r:.0e}") for r, a in zip(rtols, atols)]

        if scene.parts is None and not scene.planar:
            # Events per second of the reference computing every event (the event log switches
            # its steady-state fast-forward off); best of repeats like every other timing.
            logged = scene.replace(record=Record(events=True))
            traj, best = best_time(lambda: simulate(logged, reference, **reference_options), settings.min_timing)
            events_run = int(traj.stats["events"])
        else:
            # The exact solvers of several parts and of planar motion compute every event (no fast-forward):
            # the reference run is the run with every event.
            events_run, best = ref.events, ref.cpu_time
        bar.advance(note=f"{reference} with every event")

    starts = [p.x0 for p in scene.parts] if scene.parts is not None else list(np.ravel(scene.x0))
    level_x = 4.0 * _EPS * float(np.max(np.abs(np.concatenate([starts, np.ravel(ref.x_end), np.ravel(ref.x_prev)]))))
    level_v = 2.0 * level_x / dt
    m_table = _table(moreau, ref)
    h = dt / steps_per_period.astype(float)
    fit = (steps_per_period >= settings.fit_min_steps_per_period)
    use = fit & (m_table["err_end_position"] > 100 * level_x)
    order, intercept, low, high = fit_loglog(h[use], m_table["err_end_position"][use])
    use_v = fit & (m_table["err_vbar"] > 100 * level_v)
    order_v = fit_loglog(h[use_v], m_table["err_vbar"][use_v])[0]
    h_target = math.exp((math.log(settings.target_error) - intercept) / order)
    cpu_target, inside = loglog_interpolate(h_target, h, m_table["cpu_time"])

    attrs = {
        "scene_name": scene.name,
        "scene": yaml.safe_dump(scene.to_dict(), sort_keys=False),
        "settings": asdict(settings),
        "target_error": settings.target_error,
        "reference": reference_text(reference, reference_options),
        "parts": 1 if scene.parts is None else len(scene.parts),
        "planar": scene.planar,
        "x_ref_end": ref.x_end,
        "vbar_ref": ref.vbar,
        "rounding_level_position": level_x,
        "rounding_level_vbar": level_v,
        "moreau_order": order,
        "moreau_order_low": low,
        "moreau_order_high": high,
        "moreau_order_vbar": order_v,
        "moreau_fit_points": int(use.sum()),
        "moreau_h_at_target": h_target,
        "target_interpolated": inside,
    }
    groups = {"moreau": {"datasets": {"h": h, "steps_per_period": steps_per_period, **m_table}}}
    if ivp_refused is None:
        i_table = _table(ivp, ref)
        attrs["ivp_max_err_over_rtol"] = float(np.max(i_table["err_end_position"] / rtols))
        groups["ivp"] = {"datasets": {"rtol": rtols, "atol": atols, **i_table}}
    else:
        attrs["ivp_not_run"] = f"solve_ivp is not run: {ivp_refused}"
    measured = {
        "moreau_cpu_at_target": np.float64(cpu_target),
        "speed_ratio_at_target": np.float64(cpu_target / ref.cpu_time),
        "exact_events_per_second": np.float64(events_run / best),
    }
    groups["exact"] = {"attrs": {"x_end": ref.x_end, "vbar": ref.vbar,
                                 "steps": ref.steps, "events": ref.events, "status": ref.status,
                                 "fast_forward_periods": ref.fast_forward_periods,
                                 "events_run_events": events_run},
                       "datasets": {"cpu_time": np.float64(ref.cpu_time), "events_run_cpu_time": np.float64(best)}}
    return measured, attrs, groups
