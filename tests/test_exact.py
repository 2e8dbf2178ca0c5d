"""The exact event-driven solver (method="exact") against the paper's closed forms."""

import math
import os
import subprocess
import sys

import numpy as np
import pytest
from scipy.integrate import solve_ivp

import selfalign as sa
from selfalign.model import arcs

# Sect. 5.1 / 7.3 settings: y2'' = 2.2, y3'' = 0.9, dt = 1.05, dy = 0.084; zone w = 0.05, c_mu = 2.5.
CASE1 = sa.ThreePhaseProfile(1.05, 0.084, 2.2, 0.9)
X_MU = 0.03125          # exactly representable, also after adding 1e6
W, C_MU = 0.05, 2.5


def run(profile, surface=None, method="exact", **kw):
    options = kw.pop("options", {})
    scene = sa.Scene(profile, surface=surface or sa.Uniform(), **kw)
    return sa.simulate(scene, method=method, **options)


def events_of(traj, kind):
    return traj.events[traj.events["kind"] == int(kind)]


# ------------------------------------------------------------------------------------------
# Sect. 5.1, case 1 (eqs. 12-24)
# ------------------------------------------------------------------------------------------

def test_case1_steady_state_matches_closed_form():
    """Sect. 5.1, eqs. (12)-(24): from x0' = 0 at t0 = 0 with y2'' > 1, y3'' < 1 the mass sticks
    on [t0, t1], slips with x'' = y2'' - 1 on [t1, t2] (x'(t2) = (y2''-1)(t2-t1), x(t2) =
    (y2''-1)(t2-t1)^2/2), decelerates with x'' = -1 - y3'' and sticks at t_{x'=0} = t2 +
    x'(t2)/(1 + y3'') (eq. 21) until t3; after one period x' = 0 again (steady state at once)
    and x advanced by x(t_{x'=0}).  Tolerance 1e-12."""
    p = CASE1
    traj = run(p, periods=1, record=sa.Record(events=True))
    v2 = (p.y2 - 1.0) * (p.t2 - p.t1)
    x2 = 0.5 * (p.y2 - 1.0) * (p.t2 - p.t1) ** 2
    t_stop = p.t2 + v2 / (1.0 + p.y3)
    x_stop = x2 + v2 * v2 / (2.0 * (1.0 + p.y3))
    kinds = [sa.EventKind(k).name for k in traj.events["kind"]]
    assert kinds == ["SWITCH", "SLIP", "SWITCH", "STICK"]
    slip, at_t2, stick = traj.events[1], traj.events[2], traj.events[3]
    assert slip["tau"] == p.t1 and slip["x"] == 0.0 and slip["mode"] == sa.solvers.outcomes.FORWARD_SLIP
    assert at_t2["tau"] == p.t2
    assert abs(at_t2["x"] - x2) <= 1e-12 and abs(at_t2["v"] - v2) <= 1e-12
    assert abs(stick["tau"] - t_stop) <= 1e-12 and abs(stick["x"] - x_stop) <= 1e-12
    assert traj.v_end == 0.0 and abs(traj.x_end - x_stop) <= 1e-12
    assert (traj.period_end, traj.tau_end) == (1, 0.0)


def recorded(profile, surface=None, periods=1, **start):
    """A run of ``periods`` periods with its arcs and event log."""
    return sa.simulate(sa.Scene(profile, surface or sa.Uniform(), periods=periods,
                                record=sa.Record(events=True, arcs=True), **start))


def test_case1_one_period_returns_start_velocity_for_any_start_velocity():
    """Sect. 6.1, eqs. (26)-(27): in case 1 a start velocity 0 <= x0' < t1 is lost in the y'' = 0
    piece (x'' = -1), so x'(t3) = 0 and x(t3) = x0 + x0'^2/2 + c1; tolerance 1e-12."""
    p = CASE1
    base = recorded(p)
    for v0 in (0.0, 0.05, 0.9 * p.t1):
        step = recorded(p, v0=v0)
        assert step.v_end == 0.0 and step.arcs["mode"][-1] == 0
        assert abs(step.x_end - (v0 * v0 / 2.0 + base.x_end)) <= 1e-12


# ------------------------------------------------------------------------------------------
# Friction law and stick condition (eqs. 5, 6, 38)
# ------------------------------------------------------------------------------------------

@pytest.mark.parametrize("y2, y3", [(2.2, 0.9), (2.3, 1.3), (3.0, 2.5)])
def test_friction_never_does_positive_work(y2, y3):
    """Eq. (5): F = -(x'' + y'') in mu Sign(x'), so the friction force on the mass, -F, never does
    positive work on the relative motion: F * x' >= 0 (exactly), |F| <= mu_bar = 1, and
    |F| = 1 in slip.  Cases 1, 3 and 4 (with backward slip) on the uniform surface."""
    traj = run(sa.ThreePhaseProfile(1.0, 0.02, y2, y3), periods=4,
               record=sa.Record(series=("v", "friction", "mode"), samples_per_period=400))
    f, v, mode = traj.friction, traj.v, traj.mode
    assert np.all(f * v >= 0.0)
    assert np.all(np.abs(f) <= 1.0 + 1e-15)
    assert np.allclose(np.abs(f[mode != 0]), 1.0, rtol=0, atol=1e-15)
    assert np.all(v[mode == 1] >= 0.0) and np.all(v[mode == -1] <= 0.0) and np.all(v[mode == 0] == 0.0)
    if y3 > 1.0:
        assert np.any(v < 0.0)        # backward slip is exercised


def test_stick_only_where_table_acceleration_within_friction():
    """Sect. 3.2 and eq. (38): the mass sticks only where |y''| <= mu_bar(x) (dense samples and
    STICK events), on the uniform surface and through the stop zone (eq. 9)."""
    p = sa.ThreePhaseProfile(1.0, 0.084, 2.3, 1.3)
    for surface in (sa.Uniform(), sa.StopZone(X_MU, W, C_MU)):
        traj = run(p, surface, periods=12, record=sa.Record(series=("x", "ydd", "mode"), events=True))
        stuck = traj.mode == 0
        mu = surface.coefficient(traj.x[stuck])
        assert stuck.any() and np.all(np.abs(traj.ydd[stuck]) <= mu + 1e-12)
        sticks = events_of(traj, sa.EventKind.STICK)
        assert sticks.size and np.all(np.abs(p.acceleration(sticks["tau"])) <= surface.coefficient(sticks["x"]))


@pytest.mark.parametrize("phase", [0.0, 0.37])
def test_dense_output_hits_events_and_grid(phase):
    """DESIGN dense output: samples at t = phase dt + j dt / spp plus every event time (the state
    after the event); x and v are continuous (dense x, v at event times equal the event log)."""
    p, spp = CASE1, 50
    traj = run(p, sa.StopZone(X_MU, W, C_MU), periods=6, phase=phase,
               record=sa.Record(series=("x", "v"), samples_per_period=spp, events=True))
    t = traj.t
    assert np.all(np.diff(t) >= 0.0)
    grid = phase * p.dt + np.arange(6 * spp + 1) * (p.dt / spp)
    assert np.all(np.min(np.abs(t[:, None] - grid[None, :]), axis=0) <= 1e-12)
    for e in traj.events:
        te = e["period"] * p.dt + e["tau"]
        i = np.argmin(np.abs(t - te))
        assert abs(t[i] - te) <= 1e-12
        assert abs(traj.x[i] - e["x"]) <= 1e-12 and abs(traj.v[i] - e["v"]) <= 1e-12


# ------------------------------------------------------------------------------------------
# Arcs in the transition zone (Sect. 7.3)
# ------------------------------------------------------------------------------------------

def _paper_harmonic(x_star, v_star, ydd, s, x_mu=X_MU, w=W, c_mu=C_MU):
    """Eqs. (42)-(46) in absolute coordinates."""
    b1 = (c_mu - 1.0) / w
    b3 = b1 * x_mu - 1.0 - ydd
    d1, d2, om = x_star - b3 / b1, v_star / math.sqrt(b1), math.sqrt(b1)
    x = b3 / b1 + d1 * math.cos(om * s) + d2 * math.sin(om * s)
    v = -d1 * om * math.sin(om * s) + d2 * om * math.cos(om * s)
    return x, v, d1, d2


def test_harmonic_arc_matches_eqs_43_to_47():
    """Eqs. (43)-(47): forward slip in the transition zone is x = b3/b1 + d1 cos(sqrt(b1) s) +
    d2 sin(sqrt(b1) s); x' = 0 first at s = arcsin(d2 / sqrt(d1^2 + d2^2)) / sqrt(b1) when d1 >= 0
    (eq. 47) and at (pi - arcsin(...)) / sqrt(b1) when d1 < 0 (the atan2 generalisation).  The
    closed-form arc agrees to 1e-12 for random states and table accelerations."""
    rng = np.random.default_rng(7)
    b1 = (C_MU - 1.0) / W
    om = math.sqrt(b1)
    seen = set()
    for _ in range(200):
        xi, v0, ydd = rng.uniform(0, W), rng.uniform(0, 0.5), rng.uniform(-3.0, 2.0)
        acc0 = -ydd - (1.0 + b1 * xi)
        s = rng.uniform(0, 1.0)
        dx, v = arcs.step(arcs.HARMONIC, om, v0, acc0, s)
        x_ref, v_ref, d1, d2 = _paper_harmonic(X_MU + xi, v0, ydd, s)
        assert abs(X_MU + xi + dx - x_ref) <= 1e-12 and abs(v - v_ref) <= 1e-12
        s_zero = arcs.zero_velocity_time(arcs.HARMONIC, om, 1, v0, acc0)
        base = math.asin(d2 / math.hypot(d1, d2)) / om
        assert abs(s_zero - (base if d1 >= 0 else math.pi / om - base)) <= 1e-12
        seen.add(d1 >= 0)
    assert seen == {True, False}


def test_solver_zone_arcs_follow_eqs_43_44_and_47():
    """Sect. 7.3: in the accumulation scene every harmonic arc of the solver ends in the state
    given by eqs. (43)-(44) from its start, and arcs ending in stick last as long as eq. (47)
    (d1 >= 0 there) says; tolerance 1e-12."""
    traj = recorded(CASE1, sa.StopZone(X_MU, W, C_MU), periods=12)
    ends = {(int(e["period"]), float(e["tau"])): e for e in traj.events}
    checked = 0
    for arc in traj.arcs[traj.arcs["kind"] == arcs.HARMONIC]:
        x_ref, v_ref, d1, d2 = _paper_harmonic(arc["x"], arc["v"], arc["table_acc"], arc["duration"])
        end = ends.get((int(arc["period"]), float(arc["tau"] + arc["duration"])))
        if end is not None and end["kind"] == sa.EventKind.STICK:
            assert d1 >= 0.0
            assert abs(arc["duration"] - math.asin(d2 / math.hypot(d1, d2)) / arc["omega"]) <= 1e-12
            assert abs(end["x"] - x_ref) <= 1e-12 and abs(v_ref) <= 1e-12
            checked += 1
    assert checked >= 10


def _ivp_arc(acc0, kappa, v0, s_end, events=None):
    """x'' = acc0 + kappa x (x measured from the arc start), DOP853 at rtol 1e-12."""
    return solve_ivp(lambda t, y: [y[1], acc0 + kappa * y[0]], (0.0, s_end), [0.0, v0], method="DOP853",
                     rtol=1e-12, atol=1e-15, events=events)


def test_hyperbolic_arc_matches_high_accuracy_ivp():
    """Backward slip in the zone: x'' - b1 (x - x_mu) = 1 - y'' (eq. 38 with Sign = -1).  The
    closed form (cosh/sinh), its zero-velocity time (exponential form) and its crossing time of
    a boundary agree with DOP853 at rtol 1e-12 to 1e-10."""
    b1 = (C_MU - 1.0) / W
    om = math.sqrt(b1)
    for v0, acc0 in ((-0.2, 0.5), (-0.05, -0.3), (-0.3, 2.0), (0.0, -1.0)):
        sol = _ivp_arc(acc0, b1, v0, 0.4)
        dx, v = arcs.step(arcs.HYPERBOLIC, om, v0, acc0, 0.4)
        assert abs(dx - sol.y[0, -1]) <= 1e-10 and abs(v - sol.y[1, -1]) <= 1e-10 * max(1.0, abs(v))
        s_zero = arcs.zero_velocity_time(arcs.HYPERBOLIC, om, -1, v0, acc0)
        def zero(t, y):
            return y[1]

        zero.terminal, zero.direction = True, 1
        ref = _ivp_arc(acc0, b1, v0, 5.0, events=[zero]).t_events[0]
        if v0 < 0.0 and ref.size:
            assert abs(s_zero - ref[0]) <= 1e-10
        else:
            assert s_zero == math.inf and (ref.size == 0 or ref[0] == 0.0)
        delta = 0.01                                   # boundary 0.01 below the start
        def cross(t, y):
            return y[0] + delta

        cross.terminal = True
        ref = _ivp_arc(acc0, b1, v0, 5.0, events=[cross, zero]).t_events
        s_cross = arcs.crossing_time(arcs.HYPERBOLIC, om, v0, acc0, delta)
        if ref[0].size:
            assert abs(s_cross - ref[0][0]) <= 1e-10
        else:
            assert s_cross > s_zero


def test_solver_hyperbolic_arcs_match_ivp_of_the_model():
    """Eq. (38) with backward slip inside the zone (y3'' = 1.3 > mu_bar near x_mu): each
    hyperbolic arc of the solver, integrated from its start with DOP853 (rtol 1e-12) on the
    model's own mu_bar(x), ends where the next arc starts (1e-10); the ZONE event lies exactly
    on x_mu."""
    p, zone = sa.ThreePhaseProfile(1.0, 0.084, 2.3, 1.3), sa.StopZone(X_MU, W, C_MU)
    step = recorded(p, zone, x0=X_MU + 0.002, phase=p.t2 / p.dt)
    hyper = np.flatnonzero(step.arcs["kind"] == arcs.HYPERBOLIC)
    assert hyper.size
    for i in hyper:
        arc, nxt = step.arcs[i], step.arcs[i + 1]
        sol = solve_ivp(lambda t, y: [y[1], -arc["table_acc"] + zone.coefficient(y[0])], (0.0, arc["duration"]),
                        [arc["x"], arc["v"]], method="DOP853", rtol=1e-12, atol=1e-15)
        assert abs(sol.y[0, -1] - nxt["x"]) <= 1e-10 and abs(sol.y[1, -1] - nxt["v"]) <= 1e-10
    zone_events = step.events[step.events["kind"] == sa.EventKind.ZONE]
    assert zone_events.size and zone_events[0]["x"] == X_MU


def test_crossing_and_zero_velocity_times_keep_relative_accuracy():
    """Event times from quadratics use the citardauq form: a crossing 1e-20 after the arc start
    is found with full relative accuracy (the textbook formula would return 0)."""
    for kind, om in ((arcs.QUADRATIC, 0.0), (arcs.HARMONIC, 5.0), (arcs.HYPERBOLIC, 5.0)):
        s = arcs.crossing_time(kind, om, 1.0, -1.0, -1e-20)
        assert abs(s - 1e-20) <= 1e-35
    assert arcs.first_positive_root(1.0, -1e9, 1.0) == pytest.approx(1e-9, rel=1e-15)
    assert arcs.first_positive_root(1.0, 0.0, 1.0) == math.inf


# ------------------------------------------------------------------------------------------
# Outcomes
# ------------------------------------------------------------------------------------------

def test_rest_closed_form():
    """Case 5 / REST: with max|y''| < 1 (= mu_bar) the mass sliding with x0' = 0.3 during the
    y'' = 0 piece decelerates at x'' = -1 and sticks at x0 + x0'^2 / 2 = 0.045 (eq. 21), where it is
    at rest for good (mu_bar >= max|y''|).  Exact to 1e-15."""
    p = sa.ThreePhaseProfile(1.0, 0.01, 0.9, 0.8)
    assert p.t1 > 0.3
    traj = run(p, x0=0.5, v0=0.3, until="rest")
    assert traj.status is sa.Status.REST and traj.v_end == 0.0
    assert abs(traj.x_end - 0.545) <= 1e-15 and abs(traj.tau_end - 0.3) <= 1e-15 and traj.period_end == 0


def test_rest_in_high_friction_region_at_start():
    """Eq. (41): a mass starting at rest beyond x_stick_min (mu_bar >= max|y''|) is at rest for good."""
    traj = run(CASE1, sa.StopZone(X_MU, W, C_MU), x0=X_MU + 0.045, until="rest")
    assert traj.status is sa.Status.REST and traj.x_end == X_MU + 0.045 and traj.stats["events"] == 0


def test_accumulation_to_x_stick_min_follows_eq_59():
    """Sect. 7.3, eqs. (59)-(60), Fig. 18 settings (y2'' = 2.2, y3'' = 0.9, dt = 1.05, dy = 0.084,
    w = 0.05, c_mu = 2.5): successive stick positions in the zone follow the map (59) to 1e-14,
    increase geometrically (contraction in (0, 1)) to its fixed point x_stick_min (eq. 41);
    the run ends with ACCUMULATION once the remaining distance is <= accumulation_tol = 1e-12,
    with x_end = x_stick_min and an Aitken extrapolation of the last sticks within 1e-12 of it."""
    zone = sa.StopZone(X_MU, W, C_MU)
    traj = run(CASE1, zone, until="rest", record=sa.Record(events=True))
    assert traj.status is sa.Status.ACCUMULATION, traj.message
    limit = zone.x_stick_min(2.2)
    assert traj.x_end == limit and traj.info["limit"] == limit and traj.v_end == 0.0
    assert 0.0 < limit - traj.info["last_stick"] <= 1e-12
    assert 0.0 < traj.info["contraction"] < 1.0 and traj.info["stick_events"] >= 3
    sticks = events_of(traj, sa.EventKind.STICK)["x"]
    sticks = sticks[sticks >= X_MU]
    b1, y2, y3, T = zone.b1, CASE1.y2, CASE1.y3, CASE1.t2 - CASE1.t1
    b2 = b1 * X_MU - 1.0
    d = sticks[:-1] - (b2 + y2) / b1
    pred = (b2 - y3) / b1 + np.sqrt(((y2 + y3) / b1 + d * np.cos(np.sqrt(b1) * T)) ** 2
                                    + (d * np.sin(np.sqrt(b1) * T)) ** 2)
    assert np.max(np.abs(sticks[1:] - pred)) <= 1e-14
    assert np.all(np.diff(sticks) > 0.0)
    x0, x1, x2 = sticks[-3:]
    aitken = x2 - (x2 - x1) ** 2 / ((x2 - x1) - (x1 - x0))
    assert abs(aitken - limit) <= 1e-12


def test_large_offset_loses_nothing():
    """DESIGN: positions are relative to x_mu, so shifting the scene by 1e6 changes nothing: the
    relative end positions are bit-identical and x_end - x_mu agrees to 1e-9 (the absolute float
    x_end cannot hold more), for an accumulation, a rest and a horizon run."""
    shift, statuses = 1e6, set()
    for kw in ({"until": "rest"}, {"until": "rest", "x0": -0.09375}, {"periods": 3}):
        ends = []
        for off in (0.0, shift):
            x0 = kw.get("x0", 0.0) + off
            traj = run(CASE1, sa.StopZone(X_MU + off, W, C_MU), **{**kw, "x0": x0})
            ends.append((traj.status, traj.info["x_rel_end"], traj.x_end - (X_MU + off), traj.period_end,
                         traj.tau_end))
        (s0, r0, d0, n0, t0), (s1, r1, d1, n1, t1) = ends
        assert (s0, r0, n0, t0) == (s1, r1, n1, t1)
        statuses.add(s0)
        assert abs(d1 - d0) <= 1e-9
    assert statuses == {sa.Status.ACCUMULATION, sa.Status.REST, sa.Status.HORIZON}


def test_never_stops_walking_through_high_friction():
    """DESIGN NEVER_STOPS: with c_mu = 2 < max|y''| = 2.2 no stick is permanent (eq. 41 gives
    x_stick_min = inf); the mass passes the zone and repeats a period in the high-friction region
    with positive net advance, so it walks on for ever."""
    traj = run(CASE1, sa.StopZone(X_MU, W, 2.0), until="rest")
    assert traj.status is sa.Status.NEVER_STOPS, traj.message
    assert traj.info["net_advance"] > 0.0 and traj.x_end >= X_MU + W
    assert traj.info["x_stick_min"] == math.inf


def test_never_stops_periodic_motion_without_progress():
    """DESIGN NEVER_STOPS: with c_mu = 2.25 < max|y''| = 3.5 and a profile that walks forward on
    low friction but backward on high friction, the mass settles into a 2-period orbit across
    x_mu (stick in the zone, stick on low friction) with no net progress.  The reported end state
    is on the orbit: two more periods return to it within 1e-12."""
    p, zone = sa.ThreePhaseProfile(2.0, 0.25, 2.5, 3.5), sa.StopZone(0.0, 0.0625, 2.25)
    traj = run(p, zone, until="rest")
    assert traj.status is sa.Status.NEVER_STOPS, traj.message
    assert traj.info["cycle_periods"] == 2 and traj.info["net_advance"] == 0.0
    again = run(p, zone, x0=traj.x_end, v0=traj.v_end, periods=2)
    assert abs(again.x_end - traj.x_end) <= 1e-12 and abs(again.v_end - traj.v_end) <= 1e-12


def test_never_stops_on_uniform_surface_reports_advance():
    """Eqs. (10), (37): on a uniform surface a stick-slip steady state repeats every period with
    net advance vbar dt = x(t_{x'=0}) (case 1, eq. 20), never coming to rest."""
    traj = run(CASE1, until="rest")
    assert traj.status is sa.Status.NEVER_STOPS
    assert traj.info["net_advance"] == recorded(CASE1).x_end > 0.0


def test_max_events_gives_error_not_nan():
    """DESIGN: a run needing more than max_events events ends with ERROR, a message naming
    max_events, finite end state and exactly max_events events counted."""
    traj = run(CASE1, sa.StopZone(X_MU, W, C_MU), until="rest", options={"max_events": 10})
    assert traj.status is sa.Status.ERROR and "max_events" in traj.message
    assert traj.stats["events"] == 10 and math.isfinite(traj.x_end) and math.isfinite(traj.v_end)


def test_stalled_event_loop_is_an_error():
    """DESIGN "never hang": should zero-duration events ever repeat without changing the mode (a
    broken tie rule, injected here as a zero-velocity time of 0 for every arc), the run ends
    with ERROR after 100 such events instead of spinning until max_events.  The tie rules make
    this impossible, so the breakage is injected into the kernel run uncompiled
    (NUMBA_DISABLE_JIT=1: the same source as plain Python, where a model formula can be
    replaced), in a separate process."""
    code = ("import selfalign as sa\n"
            "from selfalign.model import arcs\n"
            "arcs.zero_velocity_time = lambda *args: 0.0\n"
            f"traj = sa.simulate(sa.Scene(sa.ThreePhaseProfile(1.05, 0.084, 2.2, 0.9), sa.StopZone({X_MU}, {W}, "
            f"{C_MU}), x0={X_MU + 0.001}, periods=10))\n"
            "print(traj.status.value, traj.stats['events'], traj.message)\n")
    out = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True, check=True,
                         env={**os.environ, "NUMBA_DISABLE_JIT": "1"}).stdout.split(maxsplit=2)
    assert out[0] == "error" and int(out[1]) < 200 and "stalled" in out[2], out


def test_bad_options_and_fourier_stop_zone_rejected():
    """DESIGN: bad input raises a one-line ValueError before any work."""
    with pytest.raises(ValueError, match="accumulation_tol"):
        run(CASE1, periods=1, options={"accumulation_tol": -1.0})
    with pytest.raises(ValueError, match="max_events"):
        run(CASE1, periods=1, options={"max_events": 0})
    fourier = sa.FourierProfile(1.0, [0.02, 0.0], [0.0, 0.006])
    with pytest.raises(ValueError, match="cannot simulate a Fourier profile on a stop zone"):
        run(fourier, sa.StopZone(1.0, W, C_MU), periods=1)


# ------------------------------------------------------------------------------------------
# Long horizons, ties, determinism
# ------------------------------------------------------------------------------------------

@pytest.mark.parametrize("y2, y3", [(2.2, 0.9), (3.0, 2.5)])
def test_long_horizon_fast_forward(y2, y3):
    """Eq. (10): in steady state every period advances x by vbar dt, so after 1e6 periods
    x_end = x(n) + (1e6 - n) (x(n+1) - x(n)) to 1e-12 relative, found by fast-forward (stick-slip
    case 1 and slip-slip case 4, whose boundary velocity converges by the contraction c4 < 1 of
    Sect. 6.1 until it repeats bit for bit)."""
    p = sa.ThreePhaseProfile(1.0, 0.02, y2, y3)
    n = 200
    x_n, x_n1 = run(p, periods=n).x_end, run(p, periods=n + 1).x_end
    traj = run(p, periods=1_000_000)
    expected = x_n + (1_000_000 - n) * (x_n1 - x_n)
    assert abs(traj.x_end - expected) <= 1e-12 * abs(expected)
    assert traj.info["fast_forward_periods"] > 999_000 and traj.stats["events"] < 10_000


@pytest.mark.parametrize("x_mu", [10.0, 10.46875])
def test_fast_forward_toward_the_zone_matches_stepping(x_mu):
    """DESIGN fast-forward: on the low-friction surface the steady period is translation invariant,
    so whole periods are skipped up to one cycle before the stop zone; the run then ends exactly
    as the period-by-period run (recording disables the fast-forward): same outcome (REST here),
    same end period, end time and position within 1e-12 (the skip adds c * (advance per period)
    instead of c rounded additions)."""
    zone = sa.StopZone(x_mu, W, C_MU)
    fast = run(CASE1, zone, until="rest")
    slow = run(CASE1, zone, until="rest", record=sa.Record(events=True))
    assert fast.status is slow.status is sa.Status.REST
    assert fast.period_end == slow.period_end and abs(fast.tau_end - slow.tau_end) <= 1e-12
    assert abs(fast.info["x_rel_end"] - slow.info["x_rel_end"]) <= 1e-12
    assert fast.info["fast_forward_periods"] > 100 and slow.info["fast_forward_periods"] == 0


def test_grazing_zero_velocity_at_switch_time():
    """Tie rules: v reaches 0 exactly at a switch time and |y''| = mu_bar = 1.  y'' = 1 on [0, 1/2),
    -3/2 on [1/2, 3/4), -1/2 on [3/4, 1); from x0' = 1 the mass decelerates at x'' = -2 and reaches
    v = 0 exactly at t = 1/2 (sticks: |y''| = 1 is a tie), slips forward with x'' = 1/2 after the
    switch and returns to v = 0 exactly at the period end.  Every binary-exact value is reproduced
    exactly (x = 1/4 + n/32), each period has a bounded number of events (no Zeno), and v0 = 1 +- 1e-12
    changes x_end by O(1e-12)."""
    p = sa.PiecewiseConstantProfile([0.0, 0.5, 0.75, 1.0], [1.0, -1.5, -0.5], 0.0, 0.0)
    traj = run(p, v0=1.0, periods=3, record=sa.Record(events=True))
    assert traj.x_end == 0.25 + 3 / 32 and traj.v_end == 0.0
    assert len(traj.events) <= 3 * 6
    sticks = events_of(traj, sa.EventKind.STICK)
    assert sticks["tau"][0] == 0.5 and sticks["x"][0] == 0.25
    for dv in (-1e-12, 1e-12):
        assert abs(run(p, v0=1.0 + dv, periods=3).x_end - traj.x_end) <= 1e-11


def test_tie_acceleration_equal_to_friction_sticks():
    """Tie rule |y''| = mu_bar counts as stick (DESIGN): with y3'' = 1 exactly the mass sticks in
    the y3 phase at v = 0 and stays stuck until the next switch (no slip event in between)."""
    p = sa.ThreePhaseProfile(1.0, 0.02, 2.2, 1.0)
    traj = run(p, periods=2, record=sa.Record(events=True))
    kinds = [sa.EventKind(k).name for k in traj.events["kind"]]
    # period 1 starts stuck (no event); period 2 starts with the wrap t = dt == 0 (y'' 1 -> 0).
    assert kinds == ["SWITCH", "SLIP", "SWITCH", "STICK"] + ["SWITCH", "SWITCH", "SLIP", "SWITCH", "STICK"]
    stick = traj.events[3]
    assert p.t2 < stick["tau"] < p.dt and p.acceleration(stick["tau"]) == 1.0


def test_deterministic():
    """Two runs of the same scene give bit-identical results (series and events)."""
    scene = sa.Scene(sa.ThreePhaseProfile(1.0, 0.084, 2.3, 1.3), surface=sa.StopZone(X_MU, W, C_MU),
                     periods=20, record=sa.Record(series=("x", "v", "friction"), events=True))
    a, b = sa.simulate(scene), sa.simulate(scene)
    assert a.x_end == b.x_end and a.v_end == b.v_end and a.tau_end == b.tau_end
    for name in ("t", "x", "v", "friction"):
        assert np.array_equal(a.series[name], b.series[name])
    assert np.array_equal(a.events, b.events)


# ------------------------------------------------------------------------------------------
# Smooth (Fourier) profiles on the uniform surface
# ------------------------------------------------------------------------------------------

FOURIER = sa.FourierProfile(1.0, [0.02, 0.0], [0.0, 0.006])


def test_fourier_arcs_and_events_match_ivp():
    """Sect. 4.4.2 profiles, uniform friction: each slip arc x' = v0 - s (t - t0) - (y'(t) - y'(t0))
    ends where DOP853 (rtol 1e-12) integration of x'' = -y'' - Sign(x') from its start ends
    (1e-10); slip starts where |y''| = 1 (1e-12); stick events have |y''| <= 1."""
    step = recorded(FOURIER, periods=3)
    for arc, nxt in zip(step.arcs, step.arcs[1:]):
        if arc["kind"] != arcs.SMOOTH:
            continue
        t0 = arc["period"] * FOURIER.dt + arc["tau"]
        sol = solve_ivp(lambda t, y: [y[1], -FOURIER.acceleration(t) - arc["mode"]], (t0, t0 + arc["duration"]),
                        [arc["x"], arc["v"]], method="DOP853", rtol=1e-12, atol=1e-15)
        assert abs(sol.y[0, -1] - nxt["x"]) <= 1e-10 and abs(sol.y[1, -1] - nxt["v"]) <= 1e-10
    for e in step.events:
        ydd = float(FOURIER.acceleration(e["tau"]))
        if e["kind"] == sa.EventKind.SLIP:
            assert abs(abs(ydd) - 1.0) <= 1e-12 and e["mode"] == -np.sign(ydd)
        elif e["kind"] == sa.EventKind.STICK:
            assert abs(ydd) <= 1.0 and e["v"] == 0.0


def test_fourier_long_run_fast_forwards_to_steady_advance():
    """Eq. (10) for a Fourier profile: after the transient every period advances by the same
    vbar dt, so 1e5 periods cost a few events and match x(n) + (N - n) (x(n+1) - x(n)) to 1e-12."""
    x_n, x_n1 = run(FOURIER, periods=50).x_end, run(FOURIER, periods=51).x_end
    traj = run(FOURIER, periods=100_000)
    expected = x_n + (100_000 - 50) * (x_n1 - x_n)
    assert abs(traj.x_end - expected) <= 1e-12 * abs(expected) and traj.stats["events"] < 1000
