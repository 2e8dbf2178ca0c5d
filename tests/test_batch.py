"""The batched exact solver (selfalign.solvers.batch) against the single-trajectory exact
solver and the closed-form steady state (Sects. 3.2, 3.3, 5.1, 7)."""

import numpy as np
import pytest

from selfalign import EventKind, Record, Scene, Status, StopZone, ThreePhaseProfile, Uniform, simulate
from selfalign.solvers.batch import Outcome, Reason, profile_pieces, solve_batch, three_phase_pieces
from selfalign.analysis.steady_state import steady_state, steady_state_grid

W, C_MU = 0.05, 2.5


def test_uniform_steady_state_is_a_walk_with_the_closed_form_advance():
    """Sect. 5.1: on a uniform surface every three-phase profile settles into the steady
    state of Table 1.  Started from x'(0) = 0, the batch reports NEVER_STOPS/WALK (the
    period-boundary velocity repeats to periodic_tol = 1e-12) with v(0) = v0 (1e-12) and
    a net advance vbar dt of the closed forms: rel. 1e-14 for the stick-slip cases, which
    repeat exactly, 1e-10 for slip-slip (case 4), which converges geometrically (eq. 33)
    and is declared steady once v repeats to the tolerance."""
    y2 = np.array([2.4, 2.3, 2.4, 1.2, 1.8])
    y3 = np.array([0.95, 1.3, 2.4, 2.4, 1.1])
    ss = steady_state_grid(1.0, 0.084, y2, y3)
    assert set(ss.case.tolist()) == {1, 3, 4}
    breaks, accels = three_phase_pieces(1.0, 0.084, y2, y3)
    res = solve_batch(breaks, accels, 0.0, 0.0, 0.0)
    assert res.count() == {"horizon": 0, "rest": 0, "accumulation": 0, "never_stops": 5, "error": 0}
    forward = ss.vbar > 0
    np.testing.assert_array_equal(res.reason[forward], Reason.WALK_FORWARD)
    np.testing.assert_array_equal(res.reason[~forward], Reason.WALK_BACKWARD)
    np.testing.assert_allclose(res.v_end, ss.v0, rtol=0, atol=1e-12)
    slip_slip = ss.case == 4
    np.testing.assert_allclose(res.advance[~slip_slip], ss.vbar[~slip_slip] * 1.0, rtol=1e-14)
    np.testing.assert_allclose(res.advance[slip_slip], ss.vbar[slip_slip] * 1.0, rtol=1e-10)


def test_pure_stick_is_rest():
    """Case 5 (Table 1): with y2'', y3'' <= 1 the mass sticks at once, at rest for good."""
    breaks, accels = three_phase_pieces(1.5, 0.05, 0.9, 0.95)
    res = solve_batch(breaks, accels, [0.0, 0.2], 0.0, 0.0)
    np.testing.assert_array_equal(res.status, Outcome.REST)
    np.testing.assert_array_equal(res.x_end, [0.0, 0.2])


def _entries(profile, n):
    """Steady-state entries of Sect. 7.1: x0 in (-vbar dt, 0], x_mu = Delta_x."""
    ss = steady_state(profile)
    breaks, accels = profile_pieces(profile)
    dx = solve_batch(breaks, accels, 0.0, ss.v0, 0.0, until="periods", periods=1).x_max[0]
    return -ss.vbar * profile.dt * (np.arange(n) + 0.5) / n, ss.v0, dx


@pytest.mark.parametrize("y2, y3, expected", [
    (2.3, 1.3, Status.ACCUMULATION), (1.8, 1.1, Status.REST), (2.4, 0.95, None), (2.0, 2.3, Status.NEVER_STOPS),
])
def test_batch_equals_exact_solver(y2, y3, expected):
    """Both exact solvers decide the same outcome for every steady-state entry (Sect. 7):
    same status, same end state (1e-12) for REST/ACCUMULATION, same end time; (2.4, 0.95)
    mixes REST and ACCUMULATION entries."""
    profile = ThreePhaseProfile(1.0, 0.084, y2, y3)
    x0, v0, dx = _entries(profile, 6)
    breaks, accels = profile_pieces(profile)
    res = solve_batch(breaks, accels, x0, v0, 0.0, x_mu=dx, w=W, c_mu=C_MU, max_periods=1000)
    statuses = res.statuses()
    if expected is None:
        assert {Status.REST, Status.ACCUMULATION} <= set(statuses)
    else:
        assert set(statuses) == {expected}
    for i, x in enumerate(x0):
        traj = simulate(Scene(profile, StopZone(dx, W, C_MU), x0=float(x), v0=v0, until="rest", max_periods=1000),
                        method="exact")
        assert traj.status is statuses[i]
        if traj.status in (Status.REST, Status.ACCUMULATION):
            assert res.x_end[i] == pytest.approx(traj.x_end, rel=0, abs=1e-12)
            assert res.period_end[i] == traj.period_end
            assert res.tau_end[i] == pytest.approx(traj.tau_end, abs=1e-12)
        if traj.status is Status.ACCUMULATION:
            assert res.contraction[i] == pytest.approx(traj.info["contraction"], rel=1e-3)


def test_horizon_runs_match_exact_solver_for_mixed_members():
    """One batch call with different profiles (and periods), surfaces (c_mu = 1 is a
    uniform surface) and start states (mid-period phases, forward/backward/zero velocity)
    advanced 7 periods, i.e. to t = phase dt + 7 dt, agrees with one exact run per member:
    x and v to 1e-12."""
    profiles = [ThreePhaseProfile(1.0, 0.084, 2.3, 1.3), ThreePhaseProfile(1.05, 0.084, 2.2, 0.9),
                ThreePhaseProfile(1.0, 0.084, 2.4, 2.4), ThreePhaseProfile(1.0, 0.084, 1.2, 2.4)]
    zones = [StopZone(0.0, W, C_MU), StopZone(0.02, W, C_MU), StopZone(-1.0, 0.02, 1.8), StopZone(0.0, W, 1.0)]
    x0, v0, phase = np.array([-0.03, 0.0, 0.01, 0.02]), np.array([0.1, 0.0, -0.2, 0.05]), np.array([0.4, 0, 0.7, 0.2])
    breaks, accels = (np.array(a) for a in zip(*(profile_pieces(p) for p in profiles)))
    res = solve_batch(breaks, accels, x0, v0, phase * breaks[:, -1], x_mu=[z.x_mu for z in zones],
                      w=[z.w for z in zones], c_mu=[z.c_mu for z in zones], until="periods", periods=7)
    np.testing.assert_array_equal(res.status, Outcome.HORIZON)
    for i, profile in enumerate(profiles):
        zone = zones[i] if zones[i].c_mu > 1 else Uniform()
        traj = simulate(Scene(profile, zone, x0=x0[i], v0=v0[i], phase=phase[i], periods=7), method="exact")
        assert (res.period_end[i], res.tau_end[i]) == (traj.period_end, pytest.approx(traj.tau_end, abs=1e-15))
        assert res.x_end[i] == pytest.approx(traj.x_end, rel=0, abs=1e-12)
        assert res.v_end[i] == pytest.approx(traj.v_end, rel=0, abs=1e-12)


def test_walking_through_the_zone():
    """c_mu < max|y''| (Sect. 7.2): the mass crosses the zone and walks on in the
    high-friction region with the steady state of friction c_mu, i.e. the uniform steady
    state of the profile (dt, dy/c_mu, y2''/c_mu, y3''/c_mu) scaled by c_mu (same switch
    times, eq. 6 divided by c_mu): NEVER_STOPS/WALK_FORWARD, advance rel. 1e-12."""
    c_mu = 1.2
    profile = ThreePhaseProfile(1.0, 0.084, 2.3, 1.3)
    breaks, accels = profile_pieces(profile)
    res = solve_batch(breaks, accels, 0.0, 0.0, 0.0, x_mu=0.05, w=W, c_mu=c_mu)
    assert res.status[0] == Outcome.NEVER_STOPS and res.reason[0] == Reason.WALK_FORWARD
    assert res.x_end[0] > 0.05 + W
    scaled = steady_state((1.0, 0.084 / c_mu, 2.3 / c_mu, 1.3 / c_mu))
    assert res.advance[0] == pytest.approx(c_mu * scaled.vbar, rel=1e-12)


def test_first_crossing_times_match_zone_events():
    """Recorded first arrival at x_mu and at x_mu + w equal the exact solver's ZONE events."""
    profile = ThreePhaseProfile(1.0, 0.084, 2.4, 0.95)
    breaks, accels = profile_pieces(profile)
    res = solve_batch(breaks, accels, -0.1, 0.0, 0.0, x_mu=0.0, w=0.02, c_mu=C_MU, until="periods", periods=4)
    traj = simulate(Scene(profile, StopZone(0.0, 0.02, C_MU), x0=-0.1, periods=4, record=Record(events=True)),
                    method="exact")
    zone_events = traj.events[traj.events["kind"] == EventKind.ZONE]
    for col, x_b in enumerate((0.0, 0.02)):
        first = zone_events[np.isclose(zone_events["x"], x_b, atol=1e-15)][0]
        assert res.cross_period[0, col] == first["period"]
        assert res.cross_tau[0, col] == pytest.approx(first["tau"], abs=1e-12)
        assert res.cross_v[0, col] == pytest.approx(first["v"], abs=1e-12)


def test_zero_length_dwell_on_the_case0_boundary():
    """q = 1 gives t1 = 0 (Appendix): the batch keeps the empty dwell piece and still
    matches the exact solver (which drops it) over 5 periods to 1e-12."""
    y2, y3 = 2.0, 2.0
    dy = 1.0 / (8 * (1 / y2 + 1 / y3))  # q = 1 with dt = 1
    breaks, accels = three_phase_pieces(1.0, dy, y2, y3)
    assert breaks[1] == 0.0
    res = solve_batch(breaks, accels, 0.0, 0.0, 0.0, until="periods", periods=5)
    traj = simulate(Scene(ThreePhaseProfile(1.0, dy, y2, y3), periods=5), method="exact")
    assert res.x_end[0] == pytest.approx(traj.x_end, abs=1e-12)
    assert res.v_end[0] == pytest.approx(traj.v_end, abs=1e-12)


def test_budget_is_reported_not_hung():
    """No outcome within max_periods is HORIZON (BOUNDED once inside the zone,
    MAX_PERIODS before it), never a hang; max_events gives ERROR."""
    profile = ThreePhaseProfile(1.0, 0.084, 2.3, 1.3)
    breaks, accels = profile_pieces(profile)
    far = solve_batch(breaks, accels, -10.0, 0.0, 0.0, x_mu=0.0, w=W, c_mu=C_MU, max_periods=3)
    assert far.status[0] == Outcome.HORIZON and far.reason[0] == Reason.MAX_PERIODS
    inside = solve_batch(breaks, accels, 0.001, 0.0, 0.0, x_mu=0.0, w=W, c_mu=C_MU, max_periods=2)
    assert inside.status[0] == Outcome.HORIZON and inside.reason[0] == Reason.BOUNDED
    short = solve_batch(breaks, accels, -10.0, 0.0, 0.0, x_mu=0.0, w=W, c_mu=C_MU, max_events=5)
    assert short.status[0] == Outcome.ERROR and short.reason[0] == Reason.MAX_EVENTS


@pytest.mark.parametrize("kwargs, match", [
    ({"tau0": 1.0}, "tau0"),
    ({"x0": np.nan}, "x0"),
    ({"until": "forever"}, "until"),
    ({"until": "periods"}, "periods"),
    ({"x_mu": 0.0, "w": -1.0, "c_mu": 2.0}, "stop zone"),
    ({"w": 0.1}, "x_mu"),
    ({"accumulation_tol": 0.0}, "accumulation_tol"),
    ({"periodic_tol": np.inf}, "periodic_tol"),
    ({"levels": [np.nan]}, "levels"),
])
def test_bad_input(kwargs, match):
    """A one-line ValueError naming the quantity, before any work."""
    breaks, accels = three_phase_pieces(1.0, 0.084, 2.3, 1.3)
    args = {"x0": 0.0, **kwargs}
    with pytest.raises(ValueError, match=match):
        solve_batch(breaks, accels, **args)
