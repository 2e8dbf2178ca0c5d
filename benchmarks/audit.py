"""Random-scene audit: the solvers cross-checked on random scenes, every scene reproducible.

Run:  python benchmarks/audit.py --n 50000 --seed 1 --jobs 1 --out results/audit
      python benchmarks/audit.py --seed 1 --index 1234 --verbose     (one scene, every detail)

Scenes (:func:`scene_spec`, scene i of seed S from ``numpy.random.default_rng([S, i])``):
finite-jerk three-phase profiles (ramps log-uniform from 1e-9 to 0.2 of the period), the paper's
three-phase profile, briefly the polynomial and Fourier profiles; a uniform surface or a stop zone
(x_mu, w, c_mu random; the entry before, inside or after the zone, or exactly on x_mu or x_mu + w);
Coulomb, static/kinetic (r in (1, 3]) or Stribeck friction (v_s from 1e-2 to 1 table velocity
swings); a random start phase (0, the scene default, in 10 %), mostly from rest; 1 to 3 periods (``until: periods``).

Methods: ``exact`` (the event-driven solver, the reference; Coulomb scenes through
``simulate_batch``, the others through ``simulate``), ``ivp`` (DOP853 at :data:`IVP_OPTIONS`) on
every ``--ivp-every``-th scene, Moreau at h = dt / :data:`MOREAU_STEPS`, and on every
``--referee-every``-th scene the 60-digit referee (benchmarks/referee.py, written from the model
equations).  Every Coulomb scene whose index is a multiple of :data:`SCALAR_EVERY` is also run
through ``simulate`` and must equal its batch member bit for bit.

Tolerances (both for the end position x and velocity v after the horizon):

* exact, ivp, referee: |dx| <= 1e-9 max(1, |x_end - x0|), |dv| <= 1e-9 V, V = A dt with
  A = max|y''| + r c_mu the largest relative acceleration.  ivp's error per step is kept below
  rtol = 1e-12 of the state (atol 1e-14), and its events are located to ~1e-14 of the period; the
  exact solver's arcs are closed form with events to 2 eps dt; so three orders of margin.
* Moreau (first order, Sect. 4.1): the scheme integrates the table's impulse exactly, and its only
  error is that a mode (stick, forward or backward slip) is decided per step of length h.  A slip
  that starts up to one step late or early runs with an acceleration off by at most A for at most h:
  its velocity is off by <= A h until it stops (a stop resets v to 0; its time is off by <= h, which
  moves x by O(A h^2)), so its displacement is off by <= A h T for a slip of duration T.  The slips
  of a period last at most dt in all, so the position error grows by <= A h dt per period:
  |dx| <= C A h dt P and |dv| <= C A h after P periods, with C = :data:`MOREAU_C` = 2 for the
  reversals (a stop and a start in one step).  Zone crossings change mu continuously (eq. 9), which
  costs O(h^2) in a step, but a position error dx at a crossing shifts the time the part spends on
  each side of the zone by dx / |v|, while its friction differs by up to r |c_mu - 1|: its
  velocity is off by r |c_mu - 1| dx / |v| more after each crossing (a zone 0.03 wide with c_mu
  4.3 crossed at |v| ~ 0.6 turns Moreau's dx = 1e-4 into dv = 1.2e-3, seed 7, scene 89).  Where
  the positions agree and the velocities do not, the velocity tolerance therefore adds this share,
  with dx the position tolerance and |v| the velocity of each crossing in the reference method's
  event log; a stick resets it (the next slip starts at a time set by the table, not the part), a
  reversal scales it by |x'' after / x'' before| (a velocity error dv moves the reversal by
  dv / |x'' before|).  Errors grow beyond this only where the solution itself depends on the state more
  than linearly (a graze, a stick at the friction limit, the zone's hyperbolic arcs): the tie test
  below.  The summary reports the largest |dx| / (A h dt P) measured (``moreau_ratio_max``): 0.77
  on 12,000 scenes (seeds 1 and 2; 99th percentile 0.08), on a narrow steep zone (w = 0.003,
  c_mu = 15.6) where Moreau's error is not monotone in h (1.0e-4, 8.4e-5, 1.2e-4, 2.5e-5 at 1e4,
  2e4, 1e5, 5e5 steps per period; the referee agrees with exact to 3e-15).

Outcome of each method pair per scene: ``agree``, ``disagree`` (beyond the tolerance), ``nan``
(a non-finite end state), ``error`` (status ERROR or an exception; the message is kept), ``hang``
(the scene did not finish within ``--timeout`` seconds of wall time: its worker process is killed
and restarted, the audit goes on).  Each non-agreeing pair is then classified (:func:`classify`):

* ``tie``: the exact solution is discontinuous at this scene: re-running exact from x0 +- 1e-12
  (ivp and referee pairs) or x0 +- A h dt and phase +- h / dt (Moreau pairs) moves its end position
  by more than the tolerance, and the other method's answer lies within the span so obtained.  Both
  answers are legitimate (a grazing stop, a stick exactly at the friction limit).
* ``known-ivp-chattering``: ivp reports "mode chattering" on a scene that starts at rest exactly on
  a zone edge (where the friction coefficient is not differentiable).
* ``known-ivp-edge-missed``: the referee agrees with exact, and ivp's event log has fewer zone-edge
  crossings than exact's: ivp misses an edge that a slip crosses shortly before it stops or
  reverses within one solver step.
* ``known-ivp-stepped-over``: the referee agrees with exact, and ivp's event log has fewer stick,
  slip or reversal events than exact's: a stop and a slip within one solver step (on a smooth
  profile, |y''| rising just past the stick limit and back, or x' dipping through 0 and back) show
  solve_ivp no sign change at the step's ends, the limitation of event location by sign changes
  that ``selfalign/solvers/ivp.py`` documents.  The exact solver locates such dips (it brackets
  every extremum of the slip velocity).
* ``unexplained``: anything else.  A scene may have no referee (Stribeck, Fourier); then only the
  tie test can explain it.

Output in ``--out``: ``summary.json`` (configuration, counts per pair and outcome, per class,
time per method) and ``cases.csv`` (every non-agreeing pair with its seed and index; reproduce one
with ``--seed S --index I --verbose``).  Progress (scenes done, rate, ETA) goes to stderr.
"""

from __future__ import annotations

import argparse
import csv
import json
import math
import multiprocessing as mp_
import os
import sys
import time
import traceback
from collections import Counter
from multiprocessing.connection import wait
from pathlib import Path

import numpy as np
import referee

#: ivp options: DOP853 at a tight relative tolerance.
IVP_OPTIONS = {"rtol": 1e-12, "atol": 1e-14}
#: Moreau steps per period (h = dt / MOREAU_STEPS).
MOREAU_STEPS = 100_000
#: Constant of Moreau's error bound |dx| <= MOREAU_C A h dt P (module docstring).
MOREAU_C = 2.0
#: Relative tolerance of the high-accuracy pairs (exact, ivp, referee).
TIGHT = 1e-9
#: Perturbation of x0 for the tie test of the high-accuracy pairs.
TIE_EPS = 1e-12
#: Coulomb scenes with an index multiple of this are also run through simulate and compared
#: with their simulate_batch member bit for bit.
SCALAR_EVERY = 10
#: Scenes per task sent to a worker.
CHUNK = 64
PAIRS = ("exact-ivp", "exact-moreau", "ivp-moreau", "exact-referee", "batch-scalar")


# --------------------------------------------------------------------------------------------
# scenes

def _loguniform(rng, lo, hi):
    return float(math.exp(rng.uniform(math.log(lo), math.log(hi))))


def scene_spec(seed: int, index: int) -> dict:
    """Scene ``index`` of ``seed``: a dict of plain numbers (see the module docstring)."""

    rng = np.random.default_rng([seed, index])
    while True:
        kind = str(rng.choice(["finite_jerk", "three_phase", "polynomial", "fourier"], p=[0.76, 0.16, 0.04, 0.04]))
        dt = float(rng.uniform(0.3, 2.5))
        if kind in ("finite_jerk", "three_phase"):
            y2, y3 = _loguniform(rng, 0.3, 8.0), _loguniform(rng, 0.3, 8.0)
            dy = dt * dt / (8 * (1 / y2 + 1 / y3)) * float(rng.uniform(0.05, 0.999))
            profile = {"kind": kind, "dt": dt, "dy": dy, "y2": y2, "y3": y3}
            if kind == "finite_jerk":
                profile["ramp"] = dt * _loguniform(rng, 1e-9, 0.2)
        elif kind == "polynomial":
            profile = {"kind": kind, "dt": dt, "dy": float(rng.uniform(0.01, 0.3)) * dt * dt,
                       "forward_fraction": float(rng.uniform(0.55, 0.9))}
        else:
            order = int(rng.integers(1, 4))
            scale = dt * dt / (4 * math.pi**2) * float(rng.uniform(0.5, 4.0))
            profile = {"kind": kind, "dt": dt, "cos": (scale * rng.uniform(-1, 1, order) / np.arange(1, order + 1)
                                                       ** 2).tolist(),
                       "sin": (scale * rng.uniform(-1, 1, order) / np.arange(1, order + 1) ** 2).tolist()}
        try:
            prof = build_profile(profile)
        except ValueError:            # a ramp that does not fit, a non-physical profile: draw again
            continue
        break
    amax = float(prof.max_abs_acceleration)
    swing = float(prof.velocity_swing)
    law = rng.choice(["coulomb", "static_kinetic", "stribeck"], p=[0.45, 0.35, 0.20])
    friction = {"kind": str(law)}
    if law != "coulomb":
        friction["r"] = float(3.0 - 2.0 * rng.uniform(0.0, 1.0))          # (1, 3]
    if law == "stribeck":
        friction["v_s"] = swing * _loguniform(rng, 1e-2, 1.0)
        friction["delta"] = float(rng.choice([1.0, 2.0]))
    spec = {"seed": seed, "index": index, "profile": profile, "friction": friction,
            "phase": 0.0 if rng.random() < 0.1 else float(rng.uniform(0.0, 1.0)), "periods": int(rng.integers(1, 4)),
            "v0": 0.0 if rng.random() < 0.85 else float(rng.uniform(-0.5, 0.5)) * swing}
    reach = 0.1 * swing * dt
    if kind == "fourier" or rng.random() < 0.15:
        spec["zone"] = None
        spec["x0"] = float(rng.uniform(-1, 1))
    else:
        x_mu = float(rng.uniform(-0.5, 0.5))
        w = _loguniform(rng, 1e-3, 0.3)
        c_mu = max(1.02, amax * float(rng.uniform(0.4, 2.0)) / friction.get("r", 1.0) * float(rng.uniform(0.8, 1.5)))
        spec["zone"] = {"x_mu": x_mu, "w": w, "c_mu": c_mu}
        where = rng.choice(["before", "inside", "after", "on_x_mu", "on_end"], p=[0.45, 0.25, 0.2, 0.06, 0.04])
        spec["entry"] = str(where)
        spec["x0"] = {"before": x_mu - float(rng.uniform(0, 2)) * reach, "inside": x_mu + float(rng.uniform()) * w,
                      "after": x_mu + w + float(rng.uniform(0, 1)) * reach, "on_x_mu": x_mu,
                      "on_end": x_mu + w}[str(where)]
    return spec


def build_profile(p: dict):
    import selfalign as sa
    from selfalign.model.profiles import FiniteJerkProfile

    if p["kind"] == "finite_jerk":
        return FiniteJerkProfile(p["dt"], p["dy"], p["y2"], p["y3"], ramp=p["ramp"])
    if p["kind"] == "three_phase":
        return sa.ThreePhaseProfile(p["dt"], p["dy"], p["y2"], p["y3"])
    if p["kind"] == "polynomial":
        return sa.PolynomialProfile(p["dt"], p["dy"], p["forward_fraction"])
    return sa.FourierProfile(p["dt"], p["cos"], p["sin"])


def build_friction(f: dict):
    from selfalign.model.friction import FrictionLaw

    if f["kind"] == "coulomb":
        return FrictionLaw()
    if f["kind"] == "static_kinetic":
        return FrictionLaw("static_kinetic", f["r"])
    return FrictionLaw("stribeck", f["r"], v_s=f["v_s"], delta=f["delta"])


def build_scene(spec: dict, x0=None, phase=None):
    import selfalign as sa

    z = spec["zone"]
    surface = sa.Uniform() if z is None else sa.StopZone(z["x_mu"], z["w"], z["c_mu"])
    return sa.Scene(build_profile(spec["profile"]), surface, build_friction(spec["friction"]),
                    spec["x0"] if x0 is None else x0, spec["v0"], spec["phase"] if phase is None else phase,
                    periods=spec["periods"])


def scales(spec: dict) -> dict:
    """A (largest relative acceleration), dt, Moreau's h and the tolerances of the scene."""
    prof = build_profile(spec["profile"])
    dt = float(prof.dt)
    r = spec["friction"].get("r", 1.0)
    c = 1.0 if spec["zone"] is None else spec["zone"]["c_mu"]
    A = float(prof.max_abs_acceleration) + r * c
    h = dt / MOREAU_STEPS
    P = spec["periods"]
    return {"A": A, "dt": dt, "h": h, "tight_v": TIGHT * A * dt, "moreau_x": MOREAU_C * A * h * dt * P,
            "moreau_v": MOREAU_C * A * h}


def tight_x(x0, x_end):
    return TIGHT * max(1.0, abs(x_end - x0))


# --------------------------------------------------------------------------------------------
# running the methods (inside a worker process)

def _result(x=math.nan, v=math.nan, status="", message="", seconds=0.0):
    return {"x": float(x), "v": float(v), "status": status, "message": message, "seconds": seconds}


def run_method(spec, method, x0=None, phase=None):
    """End state of one method on a scene: a dict with x, v, status, message, seconds."""
    import selfalign as sa

    t0 = time.perf_counter()
    try:
        scene = build_scene(spec, x0, phase)
        if method == "referee":
            return run_referee(spec, x0, phase)
        opts = IVP_OPTIONS if method == "ivp" else {"steps_per_period": MOREAU_STEPS} if method == "moreau" else {}
        tr = sa.simulate(scene, method=method, **opts)
        return _result(tr.x_end, tr.v_end, tr.status.value, str(tr.message) if tr.status.value == "error" else "",
                       time.perf_counter() - t0)
    except Exception as exc:        # every failure is a finding: recorded, never fatal
        return _result(status="exception", message=f"{type(exc).__name__}: {exc}"[:300],
                       seconds=time.perf_counter() - t0)


def referee_supported(spec) -> bool:
    """The referee has closed-form arcs for every profile here, but not for Stribeck friction."""
    return spec["friction"]["kind"] != "stribeck"


def run_referee(spec, x0=None, phase=None, keep_log=False):
    t0 = time.perf_counter()
    p = spec["profile"]
    x0 = spec["x0"] if x0 is None else x0
    phase = spec["phase"] if phase is None else phase
    if p["kind"] == "fourier":          # uniform surface only, as for the exact solver
        res = referee.simulate_fourier(referee.Fourier(p["dt"], p["cos"], p["sin"]), x0, spec["v0"], phase,
                                       spec["periods"], spec["friction"].get("r", 1.0), keep_log=keep_log)
        out = _result(float(res.xi), float(res.v), "horizon", "", time.perf_counter() - t0)
        if keep_log:
            out["log"] = res.log
        return out
    if p["kind"] == "polynomial":
        table = referee.polynomial_table(p["dt"], p["dy"], p["forward_fraction"])
    else:
        table = referee.three_phase_table(p["dt"], p["dy"], p["y2"], p["y3"], ramp=p.get("ramp"))
    z = spec["zone"]
    model = referee.Model(None if z is None else (z["x_mu"], z["w"], z["c_mu"]), spec["friction"].get("r", 1.0))
    res = referee.simulate(table, model, x0, spec["v0"], phase, spec["periods"], keep_log=keep_log)
    out = _result(float(res.xi), float(res.v), "horizon", "", time.perf_counter() - t0)
    if keep_log:
        out["log"] = res.log
    return out


def exact_batch(specs):
    """Exact end states of the Coulomb scenes among ``specs`` in one simulate_batch call, by index."""
    import selfalign as sa

    members = [s for s in specs if s["friction"]["kind"] == "coulomb"]
    out = {}
    for periods in (1, 2, 3):
        group = [s for s in members if s["periods"] == periods]
        if not group:
            continue
        t0 = time.perf_counter()
        zones = [s["zone"] for s in group]
        x0 = np.array([s["x0"] for s in group])
        try:
            b = sa.simulate_batch([build_profile(s["profile"]) for s in group], x0, [s["v0"] for s in group],
                                  [s["phase"] for s in group],
                                  x_mu=[x if z is None else z["x_mu"] for x, z in zip(x0, zones)],
                                  w=[1.0 if z is None else z["w"] for z in zones],
                                  c_mu=[1.0 if z is None else z["c_mu"] for z in zones],
                                  until="periods", periods=periods)
        except Exception:          # one refused member (e.g. Fourier on a zone): fall back to simulate
            continue
        each = (time.perf_counter() - t0) / len(group)
        statuses = [list(sa.Status)[c].value for c in b.status]
        for s, x, v, st in zip(group, b.x_end, b.v_end, statuses):
            out[s["index"]] = _result(x, v, st, "", each)
    return out


def scene_results(spec, batch=None, ivp_every=1, referee_every=5):
    """Every method's end state of one scene (a dict per method)."""
    res = {}
    if batch is not None and spec["index"] in batch:
        res["exact"] = batch[spec["index"]]
        if spec["index"] % SCALAR_EVERY == 0:
            res["scalar"] = run_method(spec, "exact")
    elif spec["friction"]["kind"] != "stribeck":
        res["exact"] = run_method(spec, "exact")
    res["moreau"] = run_method(spec, "moreau")
    if spec["index"] % ivp_every == 0:
        res["ivp"] = run_method(spec, "ivp")
    # the Fourier referee searches its events by halving (about 1 s a scene): a tenth as often
    every = referee_every * (10 if spec["profile"]["kind"] == "fourier" else 1)
    if spec["index"] % every == 0 and referee_supported(spec):
        try:
            res["referee"] = run_referee(spec)
        except Exception as exc:
            res["referee"] = _result(status="exception", message=f"{type(exc).__name__}: {exc}"[:300])
    return res


# --------------------------------------------------------------------------------------------
# comparing and classifying

def _failed(r):
    if r["status"] in ("error", "exception"):
        return "error"
    if not (math.isfinite(r["x"]) and math.isfinite(r["v"])):
        return "nan"
    return None


def compare(spec, a, b, pair, sc):
    """'agree', 'disagree', 'nan' or 'error' for the method results a, b (hangs are the watchdog's)."""
    for r in (a, b):
        f = _failed(r)
        if f:
            return f
    if pair == "batch-scalar":
        same = (np.float64(a["x"]).tobytes() == np.float64(b["x"]).tobytes()
                and np.float64(a["v"]).tobytes() == np.float64(b["v"]).tobytes() and a["status"] == b["status"])
        return "agree" if same else "disagree"
    if "moreau" in pair:
        tx, tv = sc["moreau_x"], sc["moreau_v"]
    else:
        tx, tv = tight_x(spec["x0"], a["x"]), sc["tight_v"]
    ok = abs(a["x"] - b["x"]) <= tx and abs(a["v"] - b["v"]) <= tv and a["status"] == b["status"]
    if not ok and "moreau" in pair and abs(a["x"] - b["x"]) <= tx and a["status"] == b["status"]:
        ok = abs(a["v"] - b["v"]) <= moreau_v_tolerance(spec, pair.split("-")[0], sc)
    return "agree" if ok else "disagree"


def moreau_v_tolerance(spec, method, sc) -> float:
    """Moreau's velocity tolerance with the share of the zone crossings (module docstring), from the
    event log of ``method``'s run of the scene."""
    z = spec["zone"]
    if z is None:
        return sc["moreau_v"]
    import selfalign as sa

    scene = build_scene(spec).replace(record=sa.Record(events=True))
    events = sa.simulate(scene, method=method, **(IVP_OPTIONS if method == "ivp" else {})).events
    jump = spec["friction"].get("r", 1.0) * abs(z["c_mu"] - 1.0)
    share = 0.0
    for ev in events:
        if ev["kind"] == sa.EventKind.ZONE:
            share += jump * sc["moreau_x"] / abs(ev["v"]) if ev["v"] else math.inf
        elif ev["kind"] == sa.EventKind.REVERSAL:
            share *= abs(ev["acc_after"] / ev["acc_before"]) if ev["acc_before"] else math.inf
        elif ev["kind"] == sa.EventKind.STICK:
            share = 0.0
    return sc["moreau_v"] + share


def pair_results(spec, res):
    """(pair, outcome, a, b) for every pair both of whose methods ran."""
    out = []
    sc = scales(spec)
    pairs = [("exact-ivp", "exact", "ivp"), ("exact-moreau", "exact", "moreau"), ("exact-referee", "exact", "referee"),
             ("batch-scalar", "exact", "scalar")]
    if spec["friction"]["kind"] == "stribeck":
        pairs.append(("ivp-moreau", "ivp", "moreau"))
    for pair, m1, m2 in pairs:
        if m1 in res and m2 in res:
            out.append((pair, compare(spec, res[m1], res[m2], pair, sc), res[m1], res[m2]))
    return out


def _on_edge(spec):
    z = spec["zone"]
    return z is not None and spec["v0"] == 0.0 and spec["x0"] in (z["x_mu"], z["x_mu"] + z["w"])


def event_counts(spec, method) -> dict:
    """How many events of each kind (stick, slip, reversal, zone) one method's run of the scene has."""
    import selfalign as sa

    scene = build_scene(spec).replace(record=sa.Record(events=True))
    events = sa.simulate(scene, method=method, **(IVP_OPTIONS if method == "ivp" else {})).events
    return {k.name.lower(): int(np.count_nonzero(events["kind"] == int(k))) for k in sa.EventKind
            if k != sa.EventKind.SWITCH}


def zone_crossings(spec, method) -> int:
    """Zone-edge crossings (EventKind.ZONE events) of one method's run of the scene."""
    return event_counts(spec, method)["zone"]


def classify(spec, pair, outcome, a, b):
    """(class, detail) of a pair that does not agree (module docstring)."""
    sc = scales(spec)
    ref_name, other_name = pair.split("-")
    if outcome == "error" and "ivp" in pair:
        r_ivp = a if ref_name == "ivp" else b
        if "chattering" in r_ivp["message"] and _on_edge(spec):
            return "known-ivp-chattering", r_ivp["message"][:120]
    if outcome != "disagree":
        return "unexplained", (a["message"] or b["message"])[:160]
    # tie test: is the solution discontinuous here, within the resolution of the methods compared?  Asked
    # of the referee where it can run (the solvers under test could be discontinuous by a bug).
    base = "referee" if referee_supported(spec) else "ivp" if ref_name == "ivp" else "exact"
    if other_name == "moreau":
        eps_x, eps_p, tx = sc["A"] * sc["h"] * sc["dt"], sc["h"] / sc["dt"], sc["moreau_x"]
    else:
        eps_x, eps_p, tx = TIE_EPS * max(1.0, abs(spec["x0"])), 0.0, tight_x(spec["x0"], a["x"])
    probes = [(None, None)] + [(spec["x0"] + d, None) for d in (-eps_x, eps_x)]
    if eps_p:
        probes += [(None, (spec["phase"] + d) % 1.0) for d in (-eps_p, eps_p)]
    runs = [run_method(spec, base, x0=x0, phase=phase) for x0, phase in probes]
    xs = [r["x"] for r in runs if _failed(r) is None]
    if len(xs) >= 2:
        spread = max(xs) - min(xs)
        if spread > tx and all(min(xs) - tx <= r["x"] <= max(xs) + tx for r in (a, b)):
            return "tie", f"{base} from x0 +- {eps_x:.1e}" + (f", phase +- {eps_p:.1e}" if eps_p else "") + \
                f" spans {spread:.3g} and covers both"
    if base != "referee" or _failed(runs[0]):
        return "unexplained", f"|dx| = {abs(a['x'] - b['x']):.3g} (tol {tx:.3g}), |dv| = {abs(a['v'] - b['v']):.3g}"
    # the referee decides which method is off
    ref = runs[0]
    tight = tight_x(spec["x0"], ref["x"])
    off = {name: abs(ref["x"] - r["x"]) for name, r in ((ref_name, a), (other_name, b)) if name != "referee"}
    if "exact" in off and off["exact"] > tight:
        return "unexplained", f"EXACT wrong: off the referee by {off['exact']:.1e} " + \
            ", ".join(f"({n} {d:.1e})" for n, d in off.items() if n != "exact")
    if pair == "exact-ivp":
        d_ivp = off["ivp"]
        n_exact, n_ivp = zone_crossings(spec, "exact"), zone_crossings(spec, "ivp")
        if n_ivp < n_exact:
            return "known-ivp-edge-missed", (f"referee agrees with exact ({off['exact']:.1e}), ivp off by {d_ivp:.1e} "
                                             f"and crosses a zone edge {n_ivp} times, exact {n_exact}")
        counts = {m: event_counts(spec, m) for m in ("exact", "ivp")}
        mode_changes = {m: sum(c[k] for k in ("stick", "slip", "reversal")) for m, c in counts.items()}
        if mode_changes["ivp"] < mode_changes["exact"]:
            return "known-ivp-stepped-over", (f"referee agrees with exact ({off['exact']:.1e}), ivp off by {d_ivp:.1e} "
                                              f"with {mode_changes['ivp']} stick/slip/reversal events, exact "
                                              f"{mode_changes['exact']}")
        return "unexplained", (f"ivp wrong: referee agrees with exact ({off['exact']:.1e}), ivp off by {d_ivp:.1e}; "
                               f"events exact {counts['exact']}, ivp {counts['ivp']}")
    return "unexplained", f"{other_name} wrong: referee agrees with exact ({off.get('exact', 0.0):.1e}), " \
        f"{other_name} off by {off.get(other_name, math.nan):.1e} (tol {tx:.1e})"


# --------------------------------------------------------------------------------------------
# workers with a watchdog

def _worker(conn, seed, ivp_every, referee_every):
    """Runs tasks (lists of indices) sent by the parent: one message per scene, ('batch', None) first."""
    import selfalign  # noqa: F401  (import once, before the first deadline)

    while True:
        task = conn.recv()
        if task is None:
            return
        indices, use_batch = task
        specs = [scene_spec(seed, i) for i in indices]
        batch = exact_batch(specs) if use_batch else None
        conn.send(("batch", None))
        for spec in specs:
            try:
                res = scene_results(spec, batch, ivp_every, referee_every)
                rows = evaluate(spec, res)        # classification reruns methods: inside the watchdog too
            except Exception:
                res = {"audit": _result(status="exception", message=traceback.format_exc()[-300:])}
                rows = [{"pair": "scene", "outcome": "error", "class": "unexplained",
                         "detail": res["audit"]["message"]}]
            conn.send(("scene", (spec["index"], res, rows)))


class Pool:
    """``jobs`` worker processes; each task's scenes must each finish within ``timeout`` seconds."""

    def __init__(self, jobs, seed, ivp_every, referee_every, timeout):
        self.args = (seed, ivp_every, referee_every)
        self.timeout = timeout
        self.ctx = mp_.get_context("fork" if sys.platform != "win32" else "spawn")
        self.workers = [self._start() for _ in range(jobs)]
        self.batch_hangs = 0

    def _start(self):
        parent, child = self.ctx.Pipe()
        proc = self.ctx.Process(target=_worker, args=(child, *self.args), daemon=True)
        proc.start()
        child.close()
        return {"proc": proc, "conn": parent, "task": None, "pending": [], "deadline": None, "batch_done": False}

    def _kill(self, w):
        w["proc"].kill()
        w["proc"].join()
        w["conn"].close()

    def run(self, indices, on_result):
        queue = [(indices[k:k + CHUNK], True) for k in range(0, len(indices), CHUNK)]
        while queue or any(w["task"] is not None for w in self.workers):
            for w in self.workers:
                if w["task"] is None and queue:
                    w["task"] = queue.pop(0)
                    w["pending"] = list(w["task"][0])
                    w["batch_done"] = False
                    w["deadline"] = time.monotonic() + self.timeout * (len(w["pending"]) if w["task"][1] else 1) \
                        + 60.0
                    w["conn"].send(w["task"])
            busy = [w for w in self.workers if w["task"] is not None]
            ready = wait([w["conn"] for w in busy], timeout=max(0.0, min(w["deadline"] for w in busy) -
                                                                time.monotonic()))
            for w in busy:
                if w["conn"] in ready:
                    try:
                        kind, payload = w["conn"].recv()
                    except EOFError:          # the worker died (a crash in compiled code): like a hang
                        kind, payload = "died", None
                    if kind == "batch":
                        w["batch_done"] = True
                        w["deadline"] = time.monotonic() + self.timeout
                        continue
                    if kind == "scene":
                        index, res, rows = payload
                        w["pending"].remove(index)
                        on_result(index, res, rows)
                        w["deadline"] = time.monotonic() + self.timeout
                        if not w["pending"]:
                            w["task"] = None
                        continue
                if w["conn"] in ready or time.monotonic() >= w["deadline"]:
                    # a hang (or a dead worker): kill it, start a fresh one, go on
                    self._kill(w)
                    pending, batch_done = w["pending"], w["batch_done"] or not w["task"][1]
                    w.update(self._start())
                    if not batch_done:      # the batch step itself: retry these scenes one by one
                        self.batch_hangs += 1
                        queue.insert(0, (pending, False))
                        continue
                    message = f"no result within {self.timeout:g} s (worker killed)"
                    on_result(pending[0], {"hang": _result(status="hang", message=message, seconds=self.timeout)},
                              [{"pair": "scene", "outcome": "hang", "class": "unexplained", "detail": message}])
                    if pending[1:]:
                        queue.insert(0, (pending[1:], True))

    def close(self):
        for w in self.workers:
            try:
                w["conn"].send(None)
            except (BrokenPipeError, OSError):
                pass
            w["proc"].join(timeout=5)
            if w["proc"].is_alive():
                self._kill(w)


# --------------------------------------------------------------------------------------------
# the audit

def evaluate(spec, res):
    """Rows (dicts) of one scene: one per pair, classified where they do not agree."""
    rows = []
    for pair, outcome, a, b in pair_results(spec, res):
        row = {"pair": pair, "outcome": outcome, "class": "", "detail": "",
               "x_a": a["x"], "x_b": b["x"], "v_a": a["v"], "v_b": b["v"], "status_a": a["status"],
               "status_b": b["status"]}
        if outcome != "agree":
            row["class"], row["detail"] = classify(spec, pair, outcome, a, b)
        rows.append(row)
    return rows


def describe(spec) -> dict:
    z = spec["zone"]
    return {"profile": spec["profile"]["kind"], "surface": "uniform" if z is None else "stop_zone",
            "entry": spec.get("entry", ""), "friction": spec["friction"]["kind"]}


def audit(n, seed, jobs, out, ivp_every=1, referee_every=5, timeout=30.0, start=0, progress=True):
    """Run scenes start .. start + n - 1; write summary.json and cases.csv into ``out``; return the summary."""
    out = Path(out)
    out.mkdir(parents=True, exist_ok=True)
    counts = {p: Counter() for p in PAIRS + ("scene",)}
    classes = Counter()
    cells = Counter()
    seconds = Counter()
    runs = Counter()
    moreau_ratio = []
    cases = []
    t0 = time.monotonic()
    done = [0, t0]

    def on_result(index, res, rows):
        spec = scene_spec(seed, index)
        for m, r in res.items():
            seconds[m] += r.get("seconds", 0.0)
            runs[m] += 1
        if "exact" in res and "moreau" in res and _failed(res["exact"]) is None and _failed(res["moreau"]) is None:
            sc = scales(spec)
            moreau_ratio.append((abs(res["exact"]["x"] - res["moreau"]["x"]) / (sc["A"] * sc["h"] * sc["dt"] *
                                                                                spec["periods"]), index))
        d = describe(spec)
        cells[(d["profile"], d["surface"], d["friction"])] += 1
        for row in rows:
            counts[row["pair"]][row["outcome"]] += 1
            if row["outcome"] != "agree":
                classes[(row["pair"], row["outcome"], row["class"])] += 1
                cases.append({"seed": seed, "index": index, **d, **row})
        done[0] += 1
        now = time.monotonic()
        if progress and (now - done[1] > 5.0 or done[0] == n):
            done[1] = now
            rate = done[0] / (now - t0)
            print(f"audit: {done[0]}/{n} scenes, {rate:.1f}/s, ETA {(n - done[0]) / rate:.0f} s, "
                  f"{len(cases)} non-agreeing", file=sys.stderr, flush=True)

    pool = Pool(jobs, seed, ivp_every, referee_every, timeout)
    try:
        pool.run(list(range(start, start + n)), on_result)
    finally:
        pool.close()
    wall = time.monotonic() - t0
    unexplained = sum(v for (p, o, c), v in classes.items() if c == "unexplained")
    ratio = np.array([r for r, _ in moreau_ratio] or [0.0])
    worst = max(moreau_ratio)[1] if moreau_ratio else None
    summary = {
        "seed": seed, "first_index": start, "scenes": n, "jobs": jobs, "wall_seconds": round(wall, 1),
        "scenes_per_second": round(n / wall, 2),
        "settings": {"ivp": IVP_OPTIONS, "ivp_every": ivp_every, "moreau_steps_per_period": MOREAU_STEPS,
                     "moreau_C": MOREAU_C, "tight_tolerance": TIGHT, "referee_every": referee_every,
                     "referee_digits": referee.DPS, "scalar_every": SCALAR_EVERY, "timeout_seconds": timeout},
        "runs_per_method": dict(runs),
        "seconds_per_run": {m: seconds[m] / runs[m] for m in runs},
        "outcomes": {p: dict(c) for p, c in counts.items() if c},
        "classes": [{"pair": p, "outcome": o, "class": c, "count": v} for (p, o, c), v in sorted(classes.items())],
        "hangs": counts["scene"]["hang"], "batch_steps_retried_after_timeout": pool.batch_hangs,
        "nan": sum(c["nan"] for c in counts.values()),
        "unexplained": unexplained,
        "moreau_ratio_max": float(ratio.max()), "moreau_ratio_max_index": worst,
        "moreau_ratio_p99": float(np.quantile(ratio, 0.99)),
        "scenes_per_cell": {"/".join(k): v for k, v in sorted(cells.items())},
    }
    (out / "summary.json").write_text(json.dumps(summary, indent=1) + "\n")
    fields = ["seed", "index", "profile", "surface", "entry", "friction", "pair", "outcome", "class", "detail",
              "x_a", "x_b", "v_a", "v_b", "status_a", "status_b"]
    with open(out / "cases.csv", "w", newline="") as fh:
        writer = csv.DictWriter(fh, fieldnames=fields, extrasaction="ignore")
        writer.writeheader()
        for case in sorted(cases, key=lambda c: (c["index"], c["pair"])):
            writer.writerow(case)
    return summary


def verbose(seed, index, ivp_every=1, referee_every=1):
    """Print one scene, every method's end state and the pairs' outcomes and classes."""
    spec = scene_spec(seed, index)
    print(json.dumps(spec, indent=1))
    print("scene:", build_scene(spec).to_dict())
    specs = [spec]
    batch = exact_batch(specs)
    res = scene_results(spec, batch, 1, 1)
    for m, r in res.items():
        print(f"{m:8s} x = {r['x']!r:24} v = {r['v']!r:24} {r['status']} {r['message']} ({r['seconds'] * 1e3:.2f} ms)")
    if referee_supported(spec):
        for event in run_referee(spec, keep_log=True)["log"]:
            print("referee event:", event[0], event[1], referee.mp.nstr(event[2], 17), referee.mp.nstr(event[3], 17))
    for row in evaluate(spec, res):
        print(f"{row['pair']:14s} {row['outcome']:9s} {row['class']} {row['detail']}")


def main(argv=None):
    ap = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    ap.add_argument("--n", type=int, default=2000, help="number of scenes (default 2000)")
    ap.add_argument("--seed", type=int, default=1)
    ap.add_argument("--start", type=int, default=0, help="first scene index")
    ap.add_argument("--jobs", type=int, default=1, help="worker processes (default 1)")
    ap.add_argument("--out", default="results/audit", help="directory for summary.json and cases.csv")
    ap.add_argument("--ivp-every", type=int, default=1, help="run ivp on every k-th scene (default 1: all)")
    ap.add_argument("--referee-every", type=int, default=10, help="run the referee on every k-th scene")
    ap.add_argument("--timeout", type=float, default=30.0, help="wall seconds per scene before it counts as a hang")
    ap.add_argument("--index", type=int, help="with --verbose: the one scene to show")
    ap.add_argument("--verbose", action="store_true")
    args = ap.parse_args(argv)
    if args.verbose:
        if args.index is None:
            ap.error("--verbose needs --index")
        verbose(args.seed, args.index)
        return 0
    summary = audit(args.n, args.seed, args.jobs, args.out, args.ivp_every, args.referee_every, args.timeout,
                    args.start)
    print(json.dumps({k: summary[k] for k in ("scenes", "wall_seconds", "outcomes", "hangs", "nan", "unexplained")},
                     indent=1))
    return 1 if summary["hangs"] or summary["nan"] or summary["unexplained"] else 0


if __name__ == "__main__":
    os.environ.setdefault("SELFALIGN_PROGRESS", "quiet")
    sys.exit(main())
