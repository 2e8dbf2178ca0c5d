"""From the engine's member record to the user's :class:`~selfalign.solvers.results.Trajectory`.

Every stepper of :func:`selfalign.simulate` (the compiled ones and ivp, which steps in
Python) starts from :func:`scene_member` and ends in :func:`trajectory`: one member record
in, one Trajectory out, with its dense series (:func:`dense_series`), event log, outcome
message and diagnostics built here once.
"""

from __future__ import annotations

import math

import numpy as np

from ..model.friction import FrictionLaw, StopZone, coefficient
from ..model.scene import Scene
from . import records as R
from .jit import call, kernel
from .outcomes import Reason, Status
from .results import Trajectory, outcome_message


def scene_member(scene: Scene) -> tuple[np.ndarray, float]:
    """The member record of a scene (inputs set) and its origin (x_mu, or x0)."""
    members = R.records(R.MEMBER_DTYPE, 1)
    m = members[0]
    surface = scene.surface
    if isinstance(surface, StopZone):
        origin = surface.x_mu
        # c_mu = 1 is friction 1 everywhere: a uniform surface with its origin at x_mu.
        m["zone"], m["w"], m["c_mu"] = surface.c_mu > 1.0, surface.w, surface.c_mu
    else:
        origin = scene.x0
        m["w"], m["c_mu"] = math.inf, 1.0
    m["xi"], m["v"], m["tau0"] = scene.x0 - origin, scene.v0, scene.phase * scene.profile.dt
    set_friction(members, scene.friction)
    return members, origin


def set_friction(members: np.ndarray, law: FrictionLaw) -> None:
    """The friction-law inputs of member records (the paper's Coulomb law: r = 1, no Stribeck)."""
    members["static_ratio"], members["v_s"], members["delta"] = law.ratio, law.v_s, law.delta


def trajectory(scene, method, options, code, row, record, origin, arcs, events, samples, cpu,
                detail: str = "") -> Trajectory:
    """The Trajectory of a finished member record (and its recordings); ``detail``: the
    message of a failed integrator (ivp)."""
    values = record.item()
    get = _INDEX.__getitem__
    reason = _REASONS[values[get("reason")]]
    surface = scene.surface
    zone = isinstance(surface, StopZone)
    xi = values[get("xi")]
    info = {"origin": origin, "x_rel_end": xi, "fast_forward_periods": values[get("fast_forward")],
            "at_rest": values[get("at_rest")]}
    if zone:
        info["x_stick_min"] = origin + values[get("xs")]
    if reason is Reason.ACCUMULATION:
        xs, last, contraction = values[get("xs")], values[get("last_stick")], values[get("contraction")]
        info.update(limit=origin + xs, contraction=None if contraction != contraction else contraction,
                    stick_events=values[get("zone_sticks")], periods=values[get("n_end")],
                    last_stick=origin + last, remaining=xs - last)
    elif reason.status is Status.NEVER_STOPS:
        info.update(net_advance=values[get("advance")], cycle_periods=values[get("cycle")])
    used = options
    if method == "moreau":
        used = {**options, "h": float(row[R.MOREAU_STEP])}
        info.update(steps_per_period=R.data_size(row), h_requested=options["h"])
        if options["iteration"] == "fixed_point":
            info.update(fp_iterations=values[get("fp_iterations")],
                        fp_unconverged_steps=values[get("fp_unconverged")])
    rec = None
    if scene.record.dense:
        rec = dict(zip(_FIELDS, values))
        series = _dense(scene, code, row, rec, origin, arcs, samples)
    else:
        series = {}
    log = None
    if scene.record.events and events is not None and code != R.MOREAU:
        log = events.copy()
        log["x"] += origin
    arc_log = None
    if scene.record.arcs and arcs is not None and code != R.MOREAU:
        arc_log = arcs.copy()
        arc_log["x"] += origin

    def compose():
        r = rec if rec is not None else dict(zip(_FIELDS, values))
        mu = coefficient(xi, surface.w, surface.c_mu) if zone else 1.0
        text = outcome_message(r, origin, options, scene.until, scene.horizon_periods, mu, detail,
                               scene.friction.ratio)
        if method == "moreau" and reason is Reason.ACCUMULATION:
            text += (f"; the limit is that of the time-stepping scheme (x_stick_min for its rest acceleration "
                     f"max|impulse| / h = {r['rest_acc']!r})")
        if method == "moreau" and options["iteration"] == "fixed_point" and r["fp_unconverged"]:
            text += (f"; WARNING: the fixed-point iteration missed fp_tol = {options['fp_tol']!r} within "
                     f"fp_max_iter = {options['fp_max_iter']} on {r['fp_unconverged']} steps (largest last "
                     f"change {r['fp_max_change']!r})")
        return text

    events_count = values[get("events")]
    return Trajectory(
        x_end=origin + xi, v_end=values[get("v")], period_end=values[get("n_end")], tau_end=values[get("tau_end")],
        status=reason.status, reason=reason, message=compose, method=method, options=used, series=series,
        events=log, arcs=arc_log,
        stats={"events": events_count, "steps": events_count if method == "exact" else values[get("steps")],
               "cpu_time": cpu},
        info=info,
    )


_REASONS = list(Reason)
_INDEX = {name: i for i, name in enumerate(R.MEMBER_DTYPE.names)}
_FIELDS = R.MEMBER_DTYPE.names


def _dense(scene, code, row, rec, origin, arcs, samples) -> dict:
    """Dense series of a recorded run: the exact solver's arcs evaluated on the grid plus
    every event, or the states a stepper sampled (Moreau: the steps nearest the grid; ivp:
    solve_ivp's dense output on the grid plus every event)."""
    if code not in (R.EXACT_PIECEWISE, R.EXACT_SMOOTH):         # Moreau, ivp: the states themselves
        s = samples
        return dense_series(scene, s["period"], s["tau"], origin + s["x"], s["v"], None)
    end = np.zeros(1, dtype=R.ARC_DTYPE)
    e = end[0]
    stuck = rec["mode"] == 0 or rec["reason"] == Reason.ACCUMULATION
    e["kind"], e["mode"] = (0, 0) if stuck else (1, rec["mode"])
    e["period"], e["tau"], e["x"], e["v"] = rec["n_end"], rec["tau_end"], rec["xi"], 0.0 if stuck else rec["v"]
    all_arcs = np.concatenate([arcs, end])
    period, tau, x, v, mode = call(kernel().sample_arcs, all_arcs, row, float(rec["tau0"]),
                                   int(scene.record.samples_per_period))
    return dense_series(scene, period, tau, origin + x, v, mode)


def dense_series(scene: Scene, period, tau, x, v, mode) -> dict:
    """``t`` and the recorded series of a scene at states (period, tau, x, v), x absolute.

    ``mode`` None: the mode of the model at each state (slip in the direction of v; at
    v = 0 stick iff |y''| <= r mu_bar, else slip -sign(y''), :func:`decide_mode`).  The
    friction force is F = mu_bar mu(v) mode in slip (mu(v) = 1 but for Stribeck friction)
    and -y'' in stick (eq. 5).
    """
    profile, surface, law = scene.profile, scene.surface, scene.friction
    period, tau = np.asarray(period), np.asarray(tau, dtype=float)
    x, v = np.asarray(x, dtype=float), np.asarray(v, dtype=float)
    ydd = np.asarray(profile.acceleration(tau), dtype=float) + 0.0 * tau
    mu = surface.coefficient(x) if isinstance(surface, StopZone) else np.ones_like(x)
    if mode is None:
        mode = call(kernel().modes, v, ydd, law.ratio * mu)
    mode = np.asarray(mode, dtype=np.int8)
    available = {
        "x": lambda: x,
        "v": lambda: v,
        "y": lambda: np.asarray(profile.position(tau), dtype=float),
        "yd": lambda: np.asarray(profile.velocity(tau), dtype=float),
        "ydd": lambda: ydd,
        "friction": lambda: np.where(mode == 0, -ydd, mode * mu * law.factor(v)),
        "mode": lambda: mode,
    }
    out = {"t": period * profile.dt + tau}
    out.update({name: available[name]() for name in scene.record.series})
    return out
