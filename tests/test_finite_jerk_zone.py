"""Finite jerk on a stop zone (eqs. 7-9, Sect. 7.3): the exact event-driven
solver's closed-form arcs with a linear forcing (quadratic outside the zone, harmonic and
hyperbolic in it) against solve_ivp, Moreau, the paper's piecewise-constant profile, the batch
driver and its own dense series."""

from __future__ import annotations

import numpy as np
import pytest
from conftest import assert_batch_member_is
from test_finite_jerk import CASE3, FIG18, random_profiles

import selfalign as sa
from selfalign.model import arcs as sa_arcs
from selfalign.model.profiles import FiniteJerkProfile
from selfalign.solvers import ivp as ivp_module
from selfalign.solvers.driver import simulate_batch
from selfalign.solvers.outcomes import STALL_EVENTS, EventKind, Reason
from selfalign.solvers.outcomes import ZONE as ZONE_REGION

ZONE = sa.StopZone(0.05, 0.05, 2.5)    # Fig. 18's zone: x_stick_min = 0.09 for max|y''| = 2.2


@pytest.mark.parametrize("params", [FIG18, CASE3], ids=["case1", "case3"])
def test_exact_agrees_with_ivp_and_moreau_on_a_stop_zone(params):
    """Cross-check on a stop zone, ramps of 1 %, 5 % and 10 % of dt, entries before the zone,
    on its edge and inside it, 30 periods (most runs end parked at x_stick_min, where r mu_bar(x)
    equals the plateau's |y''| to rounding: the tie sticks).  The exact end position is the
    reference: solve_ivp at rtol 1e-12 is within 1e-12 of it (measured <= 7.7e-14) and at rtol
    1e-13 within 1e-13 (measured <= 4.7e-15): the difference shrinks with ivp's tolerance, so it
    is ivp's error.  Moreau (first order in h) is within 2e-7 at h = dt / 16000 (measured
    <= 1.1e-9) and its largest error there is below the one at h = dt / 1000.  The runs go
    through the zone's harmonic slip arcs, in case 3 (reversals) also through its hyperbolic ones."""
    kinds = set()
    moreau_errors = {1000: [], 16000: []}
    for fraction in (0.01, 0.05, 0.10):
        p = FiniteJerkProfile(**params, ramp=fraction * params["dt"])
        for x0 in (-0.01, ZONE.x_mu, 0.07):
            scene = sa.Scene(p, ZONE, x0=x0, periods=30, record=sa.Record(arcs=True))
            exact = sa.simulate(scene)
            assert exact.status is sa.Status.HORIZON, exact.message
            for rtol in (1e-12, 1e-13):
                ivp = sa.simulate(scene, method="ivp", rtol=rtol, atol=rtol * 1e-2)
                assert abs(ivp.x_end - exact.x_end) <= rtol, (fraction, x0, rtol)
            for n in moreau_errors:
                moreau_errors[n].append(abs(sa.simulate(scene, method="moreau", steps_per_period=n).x_end
                                            - exact.x_end))
            slips = (exact.arcs["region"] == ZONE_REGION) & (exact.arcs["kind"] != sa_arcs.STICK)
            kinds |= set(exact.arcs["kind"][slips].tolist())
    assert max(moreau_errors[16000]) <= 2e-7 and max(moreau_errors[16000]) < max(moreau_errors[1000])
    assert kinds == ({sa_arcs.HARMONIC} if params is FIG18 else {sa_arcs.HARMONIC, sa_arcs.HYPERBOLIC})


@pytest.mark.parametrize("params", [FIG18, CASE3], ids=["case1", "case3"])
def test_ivp_holds_the_tie_at_x_stick_min_as_the_exact_solver_does(params):
    """At x_stick_min r mu_bar(x) equals the plateau's |y''| to rounding, and the model's rule
    (decide_mode: stick while |y''| <= r mu_bar) keeps the mass stuck.  solve_ivp's stick exit
    events follow that rule, so ivp (rtol 1e-12) run until rest from before, on and inside the zone
    with ramps of 1 % and 5 % of dt ends with the exact solver's status (ACCUMULATION at
    x_stick_min, or REST just past it) and end position within 1e-12 (measured <= 8e-14), in well
    under max_events.  Before, it chattered stick-slip in ulp-long steps from period ~22 on."""
    for fraction in (0.01, 0.05):
        p = FiniteJerkProfile(**params, ramp=fraction * params["dt"])
        for x0 in (-0.01, ZONE.x_mu, 0.07):
            scene = sa.Scene(p, ZONE, x0=x0, until="rest", max_periods=300)
            exact = sa.simulate(scene)
            ivp = sa.simulate(scene, method="ivp", rtol=1e-12, atol=1e-14)
            assert exact.status in (sa.Status.ACCUMULATION, sa.Status.REST), exact.message
            assert ivp.status is exact.status, (fraction, x0, ivp.message)
            assert abs(ivp.x_end - exact.x_end) <= 1e-12, (fraction, x0)
            assert ivp.stats["events"] < 1000, (fraction, x0)


def test_ivp_chattering_ends_as_an_error_naming_where():
    """Bounded work should the tie rule break: stick exit events that take the tie |y''| = r mu_bar
    for a crossing (as solve_ivp sees a plain |y''| - r mu_bar, zero on the plateau at x_stick_min)
    make ivp switch stick <-> slip with time advancing by ulps.  The run (case 3, 1 % ramp, 40
    periods) then ends with ERROR, reason STALL, within 2 * STALL_EVENTS events (measured 152), its
    message naming the chattering and x, instead of hanging."""
    def tie_crossing_exit(run, mu, mode):
        return lambda t, y: -mode * run.acceleration(t) - mu

    scene = sa.Scene(FiniteJerkProfile(**CASE3, ramp=0.01 * CASE3["dt"]), ZONE, x0=0.07, periods=40)
    with pytest.MonkeyPatch.context() as patch:
        patch.setattr(ivp_module._Run, "stick_exit", tie_crossing_exit)
        traj = sa.simulate(scene, method="ivp", rtol=1e-12, atol=1e-14)
    assert traj.status is sa.Status.ERROR and traj.reason is Reason.STALL, traj.message
    assert "chattering" in traj.message and f"x = {traj.x_end!r}" in traj.message, traj.message
    assert abs(traj.x_end - ZONE.x_stick_min(CASE3["y2"])) <= 1e-12
    assert traj.stats["events"] <= 2 * STALL_EVENTS


@pytest.mark.parametrize("params, zone", [(FIG18, ZONE), (CASE3, sa.StopZone(0.05, 0.01, 2.5)),
                                          (FIG18, sa.StopZone(0.05, 0.005, 4.0))],
                         ids=["case1", "case3-narrow", "case1-steep"])
def test_ramp_to_zero_reproduces_the_paper_rest_position(params, zone):
    """tau -> 0 on a stop zone: entered from x0 = -0.01, the mass overshoots x_stick_min and comes
    to REST, with the paper's three-phase profile and with every ramp.  The rest position's error
    is first order in tau (the slips start and end shifted by O(tau)): the log-log slope fitted
    over tau = 1e-3 ... 1e-6 dt is 1 within 0.05 (measured 1.000), and at tau = 1e-12 dt the rest
    position equals the paper's to 1e-12 (measured 3e-14 ... 1.5e-13)."""
    def rest(profile):
        traj = sa.simulate(sa.Scene(profile, zone, x0=-0.01, until="rest", max_periods=500))
        assert traj.status is sa.Status.REST, traj.message
        return traj.x_end

    paper = rest(sa.ThreePhaseProfile(**params))
    fractions = np.array([1e-3, 1e-4, 1e-5, 1e-6])
    errors = np.array([abs(rest(FiniteJerkProfile(**params, ramp=f * params["dt"])) - paper) for f in fractions])
    slope = np.polyfit(np.log(fractions), np.log(errors), 1)[0]
    assert abs(slope - 1.0) <= 0.05, (slope, errors)
    assert abs(rest(FiniteJerkProfile(**params, ramp=1e-12 * params["dt"])) - paper) <= 1e-12


def test_stop_zone_tends_to_the_paper_accumulation_as_ramp_vanishes():
    """tau -> 0 on Fig. 18's stop zone (Sect. 7.3): the finite-jerk runs end, as the paper's
    three-phase profile does, with ACCUMULATION at x_stick_min (eq. 41) within 1e-12; their stick
    positions converge to the paper's at first order in tau (errors at tau = 1e-7 dt and 1e-9 dt in
    a ratio 80-120) and agree to 1e-9 at tau = 1e-9 dt (measured 1e-10)."""
    def sticks(profile):
        traj = sa.simulate(sa.Scene(profile, ZONE, until="rest", record=sa.Record(events=True)))
        assert traj.status is sa.Status.ACCUMULATION, traj.message
        assert abs(traj.x_end - ZONE.x_stick_min(FIG18["y2"])) <= 1e-12
        return traj.events["x"][traj.events["kind"] == int(EventKind.STICK)]

    paper = sticks(sa.ThreePhaseProfile(**FIG18))

    def error(fraction):
        s = sticks(FiniteJerkProfile(**FIG18, ramp=fraction * FIG18["dt"]))
        assert s.size == paper.size
        return np.max(np.abs(s - paper))
    e7, e9 = error(1e-7), error(1e-9)
    assert 80 < e7 / e9 < 120
    assert e9 <= 1e-9


def random_zone_scenes(count, seed):
    """test_finite_jerk's random feasible finite-jerk profiles (ramps up to ~15 % of dt) on random
    stop zones, with random start position, velocity and phase."""
    rng = np.random.default_rng(seed)
    out = []
    for p in random_profiles(count, seed):
        zone = sa.StopZone(rng.uniform(-0.2, 0.3), np.exp(rng.uniform(np.log(0.005), np.log(0.5))),
                           rng.uniform(1.05, 6.0))
        v0 = rng.uniform(-0.5, 0.5) if rng.random() < 0.5 else 0.0
        phase = rng.uniform(0.0, 1.0) if rng.random() < 0.5 else 0.0
        out.append((p, zone, rng.uniform(-0.3, 0.1), v0, phase))
    return out


@pytest.mark.parametrize("horizon", [{"until": "periods", "periods": 25}, {"until": "rest", "max_periods": 300}])
def test_batch_and_scalar_are_bit_identical_on_random_zone_scenes(horizon):
    """One engine: on 150 random finite-jerk stop-zone scenes one simulate_batch(method="exact")
    call and one scalar simulate per scene run the same compiled _period_jerk_zone, so statuses,
    reasons, end times, event counts and end states are equal bit for bit; until rest the scenes
    reach every outcome (horizon, rest, accumulation, never stops)."""
    scenes = random_zone_scenes(150, seed=16)
    profiles, zones, x0, v0, phase = (list(c) for c in zip(*scenes))
    res = simulate_batch(profiles, np.array(x0), np.array(v0), np.array(phase), x_mu=[z.x_mu for z in zones],
                         w=[z.w for z in zones], c_mu=[z.c_mu for z in zones], method="exact", **horizon)
    kw = {"periods": horizon["periods"]} if horizon["until"] == "periods" else horizon
    statuses = set()
    for i, (p, zone, x, v, ph) in enumerate(scenes):
        traj = sa.simulate(sa.Scene(p, zone, x0=x, v0=v, phase=ph, **kw))
        statuses.add(traj.status)
        assert_batch_member_is(res, i, traj)
    if horizon["until"] == "rest":
        assert statuses == {sa.Status.HORIZON, sa.Status.REST, sa.Status.ACCUMULATION, sa.Status.NEVER_STOPS}


def test_stop_zone_dense_series_follows_the_arcs():
    """The dense series of a recorded case-3 stop-zone run (5 % ramp, entry before the zone) is
    evaluated from its arc records (quadratic, harmonic and hyperbolic arcs with the forcing of
    the piece's jerk): x is continuous (between samples |dx| <= (max|v| + max|x''| h) h + 1e-15,
    h the sample spacing, |x''| <= y2'' + c_mu), the mode changes only at logged events, and at
    every period boundary (x, v) equal the end state of an unrecorded run of that many periods
    to 1e-14."""
    p = FiniteJerkProfile(**CASE3, ramp=0.05 * CASE3["dt"])
    record = sa.Record(series=("x", "v", "mode"), samples_per_period=64, events=True)
    traj = sa.simulate(sa.Scene(p, ZONE, x0=-0.01, periods=8, record=record))
    t, x, v, mode = (traj.series[k] for k in ("t", "x", "v", "mode"))
    step = np.diff(t)
    acc_bound = CASE3["y2"] + ZONE.c_mu         # |x''| <= |y''| + mu_bar
    assert np.all(np.abs(np.diff(x)) <= (np.max(np.abs(v)) + acc_bound * step) * step + 1e-15)
    event_times = traj.events["period"] * p.dt + traj.events["tau"]
    changes = t[1:][np.diff(mode) != 0]
    assert changes.size >= 8
    assert all(np.min(np.abs(event_times - c)) <= 1e-12 for c in changes)
    for k in range(1, 8):
        at = np.flatnonzero(np.isclose(t, k * p.dt, rtol=0.0, atol=1e-13))[-1]
        end = sa.simulate(sa.Scene(p, ZONE, x0=-0.01, periods=k))
        assert abs(x[at] - end.x_end) <= 1e-14 and abs(v[at] - end.v_end) <= 1e-14


def test_exact_takes_finite_jerk_but_not_fourier_on_a_stop_zone():
    """methods.py: exact simulates a finite-jerk profile on a stop zone (scalar and batch); a
    Fourier profile on a stop zone stays refused, before any work, with its one-line message."""
    p = FiniteJerkProfile(**FIG18, ramp=0.05 * FIG18["dt"])
    assert sa.simulate(sa.Scene(p, ZONE, periods=3)).status is sa.Status.HORIZON
    assert simulate_batch(p, 0.0, surface=ZONE, until="periods", periods=3).statuses() == [sa.Status.HORIZON]
    fourier = sa.FourierProfile(1.0, [0.02, 0.0], [0.0, 0.006])
    with pytest.raises(ValueError, match="cannot simulate a Fourier profile on a stop zone"):
        sa.simulate(sa.Scene(fourier, ZONE, periods=1))
    with pytest.raises(ValueError, match="cannot simulate a Fourier profile on a stop zone"):
        simulate_batch(fourier, 0.0, surface=ZONE, until="periods", periods=1)


def test_a_tiny_ramp_still_accumulates_at_x_stick_min():
    """Eq. (41) with max|y''| = max(y2, y3), the profile's levels: the ramp ends computed as
    a + j (t_end - t_start) miss the levels by the rounding of the break times (3e-11 relative
    for a ramp of 4e-7 dt), and when that overshoot was taken as max|y''| the mass parked 4e-11
    below the x_stick_min so computed and the run read as a periodic motion.  Here the entries of
    a profile from the design tool (case 3, y2'' = 2 y3'') accumulate at the paper's x_stick_min
    for ramps from 1e-8 to 1e-4 of dt, as they do without ramps."""
    dt, dy, y2, y3 = 2.4422284905389176, 0.5, 2.1460378775685394, 1.0730189387842697
    zone = sa.StopZone(0.0, 1.0, 2.5)
    paper = sa.simulate(sa.Scene(sa.ThreePhaseProfile(dt, dy, y2, y3), zone, x0=-0.3, until="rest",
                                 max_periods=2000))
    assert paper.status is sa.Status.ACCUMULATION
    for fraction in (1e-8, 4e-7, 1e-4):
        profile = FiniteJerkProfile(dt, dy, y2, y3, ramp=fraction * dt)
        assert profile.max_abs_acceleration == y2
        for x0 in (-0.3, -1.0):
            run = sa.simulate(sa.Scene(profile, zone, x0=x0, until="rest", max_periods=2000))
            assert run.status is sa.Status.ACCUMULATION, (fraction, x0, run.message)
            assert abs(run.x_end - paper.x_end) <= 1e-12, (fraction, x0)
