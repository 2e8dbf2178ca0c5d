"""Moreau midpoint time-stepping (Sect. 4.1), ``simulate(scene, method="moreau")``, with the
table impulse of each step integrated exactly.

References are closed forms computed here: the case-1 steady state of Sect. 5.1
(eqs. 12-24) and the stick-position map (59) of Sect. 7.3 in the stop zone.
"""

import math

import numpy as np
import pytest

import selfalign as sa
from selfalign.analysis.stick_map import stick_map as closed_form_stick_map
from selfalign.solvers import records as R
from selfalign.solvers.driver import simulate_batch
from selfalign.solvers.jit import kernel
from selfalign.solvers.moreau import table_impulses

# Fig. 18 settings (Sect. 7.3): case 1 on the uniform surface (y2 > 1, y3 < 1).
PROFILE = sa.ThreePhaseProfile(1.05, 0.084, 2.2, 0.9)
ZONE = sa.StopZone(0.5, 0.05, 2.5)   # Sect. 7.2: w = 0.05, c_mu = 2.5


def case1_advance(p):
    """Net advance per period of the case-1 steady state from x = x' = 0 at t = 0 (eqs. 12-24)."""
    v2 = (p.y2 - 1.0) * (p.t2 - p.t1)                    # eq. (16) at t2
    x2 = (p.y2 - 1.0) * (p.t2 - p.t1) ** 2 / 2.0         # eq. (17) at t2
    t_stop = p.t2 + v2 / (1.0 + p.y3)                    # eq. (21)
    assert p.t2 < t_stop < p.t3                           # it is a case-1 motion
    return x2 + v2 * v2 / (2.0 * (1.0 + p.y3))           # eq. (20) at t_{x'=0}, held to t3 (eq. 24)


def stick_map(p, zone, x_n):
    """x_{n+1} from a stick at x_n in the transition region: the closed form of eq. (59)."""
    return float(closed_form_stick_map(x_n, p, w=zone.w, c_mu=zone.c_mu, x_mu=zone.x_mu))


def envelope_order(run, reference, base_steps):
    """Slope of log(error envelope) vs log(h): at each base h the largest error over six
    steps in [h, 1.83 h], because the O(h) error constant oscillates with where the
    profile's switch times fall inside a step."""
    envelope = [max(abs(run(h * (1 + j / 6)) - reference) for j in range(6)) for h in base_steps]
    return np.polyfit(np.log(base_steps), np.log(envelope), 1)[0], envelope


def test_case1_first_order_convergence():
    """Sect. 4.1 / 5.1: Moreau time-stepping converges with order 1 to the analytic case-1
    steady state (eqs. 12-24); fitted slope of the end-position error envelope over three
    decades of h (1e-2 ... 1e-5) must lie in [0.8, 1.2]."""
    scene = sa.Scene(PROFILE, periods=1)
    order, envelope = envelope_order(lambda h: sa.simulate(scene, method="moreau", h=h).x_end,
                                     case1_advance(PROFILE), np.logspace(-2, -5, 7))
    assert 0.8 <= order <= 1.2, (order, envelope)
    assert envelope[-1] < 1e-4


def test_stop_zone_first_order_convergence():
    """Sect. 7.3, eq. (59): from a stick at x_n = x_mu + 0.01 in the transition region, one
    period of forced harmonic-oscillator slip ends stuck at x_{n+1} of the closed-form map
    (reference: eq. 59, not a fine Moreau run).  Fitted order over h in [1e-5, 1e-2] must
    lie in [0.8, 1.2]."""
    x_n = ZONE.x_mu + 0.01
    scene = sa.Scene(PROFILE, ZONE, x0=x_n, periods=1)
    reference = stick_map(PROFILE, ZONE, x_n)
    assert x_n < reference < ZONE.x_stick_min(PROFILE.max_abs_acceleration)
    order, envelope = envelope_order(lambda h: sa.simulate(scene, method="moreau", h=h).x_end,
                                     reference, np.logspace(-2, -5, 7))
    assert 0.8 <= order <= 1.2, (order, envelope)


@pytest.mark.parametrize("surface, x0", [(sa.Uniform(), 0.0), (ZONE, 0.45)])
def test_fixed_point_agrees_with_exact_iteration(surface, x0):
    """Sect. 4.1: the paper's fixed-point iteration solves the same implicit step as the
    exact soft threshold; each step's velocity differs by <= fp_tol, so over S steps the
    positions differ by <= S h fp_tol (+ rounding 1e-14) and the velocities by <= fp_tol."""
    scene = sa.Scene(PROFILE, surface, x0=x0, periods=4)
    exact = sa.simulate(scene, method="moreau", h=1e-3)
    for fp_tol in (1e-14, 1e-9):
        fixed = sa.simulate(scene, method="moreau", h=1e-3, iteration="fixed_point", fp_tol=fp_tol)
        bound = exact.stats["steps"] * exact.options["h"] * fp_tol + 1e-14
        assert abs(fixed.x_end - exact.x_end) <= bound
        assert abs(fixed.v_end - exact.v_end) <= fp_tol
        assert fixed.info["fp_unconverged_steps"] == 0 and "WARNING" not in fixed.message


def test_implicit_step_fixed_point_equals_soft_threshold():
    """Sect. 4.1: the implicit friction step v = v* - bound s, s in Sign(v), solved by the
    paper's fixed-point iteration (r = 0.5 / bound, contraction 1/2) matches its exact solution,
    the soft threshold of v* by bound, to fp_tol = 1e-13 on 2000 random (v*, bound), and both
    detect a stick (v = 0 exactly) on the same ones."""
    rng = np.random.default_rng(1)
    member = R.records(R.MEMBER_DTYPE, 1)[0]
    kernel()                                # loads the engine: formulas registered, cache set
    from selfalign.solvers.engine.timestepping import _impulse as step

    for v_free, bound in zip(rng.uniform(-0.01, 0.01, 2000), rng.uniform(1e-4, 1e-2, 2000)):
        exact = step(member, v_free, bound, False, 1e-13, 200)
        fixed = step(member, v_free, bound, True, 1e-13, 200)
        assert exact == v_free - min(max(v_free, -bound), bound)
        assert abs(exact - fixed) <= 1e-13 and (exact == 0.0) == (fixed == 0.0)


def test_table_impulses_are_the_exact_integral_of_the_acceleration():
    """Each step's impulse is int y'' dt over [t_k, t_k + h] in closed form: equal
    to y'(t_k + h) - y'(t_k) (to 4 ulp of max |y'| + max |y''| t: the reference subtracts two
    velocities, each rounded and evaluated at a rounded time t), y'' h inside a piece exactly,
    and summing to 0 over a period (y' periodic) to 16 ulp of the velocity swing, for any phase."""
    for profile in (PROFILE, sa.PolynomialProfile(2.0, 0.1), sa.FourierProfile(1.0, [0.0, 0.002], [0.03, 0.01])):
        for phase in (0.0, 0.37):
            n = 1000
            h = profile.dt / n
            impulse = table_impulses(profile, phase, n, h)
            t = phase * profile.dt + np.arange(n + 1) * h
            yd = profile.velocity(t)
            swing = profile.velocity_swing
            scale = np.max(np.abs(yd)) + profile.max_abs_acceleration * t[-1]
            assert np.max(np.abs(impulse - np.diff(yd))) <= 4 * np.finfo(float).eps * scale
            assert abs(impulse.sum()) <= 16 * np.finfo(float).eps * swing
            if profile.piecewise_constant:
                inside = profile.piece_index(np.mod(t[:-1], profile.dt)) == profile.piece_index(
                    np.mod(t[1:] - 1e-12, profile.dt))
                accel = profile.accels[profile.piece_index(np.mod(t[:-1], profile.dt))]
                np.testing.assert_array_equal(impulse[inside], accel[inside] * h)


def test_a_phase_shorter_than_the_step_is_not_missed():
    """A case-1 profile whose y2'' phase lasts 0.13 h at h = dt / 1000 (uniform
    surface, from rest, until rest).  Sampling y'' at step midpoints never saw that phase and
    reported "never stops, no net progress" at x0; with the exact table impulse Moreau walks
    forward with the exact solver's net advance per period, to O(h): within h times the table
    velocity swing, at h = dt / 1000, dt / 4000, dt / 16000."""
    p = sa.ThreePhaseProfile(2.7712217769574714, 0.00851350873112948, 161.89767648968618, 0.17769817419527031)
    assert (p.t2 - p.t1) < 0.14 * p.dt / 1000 and sa.classify(p) == 1
    exact = sa.simulate(sa.Scene(p, until="rest"))
    assert exact.status is sa.Status.NEVER_STOPS and exact.info["net_advance"] == pytest.approx(1.443e-3, rel=1e-3)
    for n in (1000, 4000, 16000):
        h = p.dt / n
        tr = sa.simulate(sa.Scene(p, until="rest"), method="moreau", h=h)
        assert tr.status is sa.Status.NEVER_STOPS and tr.reason is sa.Reason.WALK_FORWARD, tr.message
        assert abs(tr.info["net_advance"] - exact.info["net_advance"]) <= h * p.velocity_swing, n


def test_error_at_fixed_step_grows_linearly_not_quadratically():
    """With y2'' = y3'' = 2000 (dt = 1, dy = 0.084) midpoint sampling left a net
    table impulse of up to h |jump| per period, so the mass drifted like N^2 h max|y''| (error
    1.3e3 after 50 periods at h = dt/1000).  With the exact impulse the table velocity is
    periodic and the error at fixed h grows at most linearly in N: from 50 to 500 periods by
    at most 11x (not 100x), and after 50 periods it is below 0.05 (measured 0.023)."""
    q = sa.ThreePhaseProfile(1.0, 0.084, 2000.0, 2000.0)
    errors = []
    for n in (50, 500):
        exact = sa.simulate(sa.Scene(q, periods=n))
        errors.append(abs(sa.simulate(sa.Scene(q, periods=n), method="moreau").x_end - exact.x_end))
    assert errors[0] <= 0.05 and errors[1] <= 11 * errors[0], errors


def test_fixed_point_non_convergence_is_reported():
    """Sect. 4.1: with fp_max_iter = 1 the iteration cannot reach fp_tol; the run finishes
    but says so in its message and info."""
    tr = sa.simulate(sa.Scene(PROFILE, periods=1), method="moreau", iteration="fixed_point", fp_max_iter=1)
    assert tr.status is sa.Status.HORIZON
    assert "WARNING" in tr.message and tr.info["fp_unconverged_steps"] > 0


@pytest.mark.parametrize("options, word", [
    ({"h": 0.0}, "h"), ({"h": -1e-3}, "h"), ({"h": float("nan")}, "h"), ({"h": float("inf")}, "h"),
    ({"h": 2.0}, "h"), ({"iteration": "newton"}, "iteration"), ({"fp_tol": 0.0}, "fp_tol"),
    ({"fp_max_iter": 0}, "fp_max_iter"), ({"fp_max_iter": 10**5}, "fp_max_iter"),
])
def test_bad_options_raise(options, word):
    """Bad input raises a one-line ValueError naming the option (DESIGN), before any work:
    h must be finite in (0, dt]."""
    with pytest.raises(ValueError, match=word):
        sa.simulate(sa.Scene(PROFILE, periods=1), method="moreau", **options)


@pytest.mark.parametrize("options, word", [({"h": "0.01"}, "h"), ({"h": True}, "h"),
                                           ({"steps_per_period": "10"}, "steps_per_period")])
def test_options_of_the_wrong_type_raise(options, word):
    """An option of the wrong type is a TypeError naming it (DESIGN), before any work."""
    with pytest.raises(TypeError, match=f"option {word} must be"):
        sa.simulate(sa.Scene(PROFILE, periods=1), method="moreau", **options)


def test_step_is_adjusted_to_whole_periods():
    """Sect. 4.1 (fixed steps): h is adjusted down to dt / ceil(dt / h) and reported."""
    tr = sa.simulate(sa.Scene(PROFILE, periods=1), method="moreau", h=0.004)
    n = math.ceil(PROFILE.dt / 0.004)
    assert tr.options["h"] == PROFILE.dt / n and tr.info["steps_per_period"] == n
    assert sa.simulate(sa.Scene(PROFILE, periods=1), method="moreau").options["h"] == PROFILE.dt / 1000


SCENES = [
    sa.Scene(PROFILE, periods=3, record=sa.Record(series=("x", "v", "y", "yd", "ydd", "friction", "mode"))),
    sa.Scene(PROFILE, ZONE, x0=0.3, v0=0.2, phase=0.4, periods=5, record=sa.Record(series=("x", "friction"))),
    sa.Scene(sa.PolynomialProfile(0.05, 0.02), periods=4, record=sa.Record(series=("x", "v"))),
    sa.Scene(sa.FourierProfile(1.0, [0.0, 0.002], [0.03, 0.01]), sa.StopZone(0.02, 0.02, 3.0), periods=4,
             record=sa.Record(series=("x", "v", "mode"), samples_per_period=64)),
]


@pytest.mark.parametrize("scene", SCENES)
def test_no_nan_and_consistent_dense_output(scene):
    """DESIGN solver contract: finite results for every profile kind and surface; dense
    output on the uniform grid (samples_per_period per period + the end), nondecreasing t,
    ending at the end state."""
    tr = sa.simulate(scene, method="moreau", h=scene.profile.dt / 2000)
    assert math.isfinite(tr.x_end) and math.isfinite(tr.v_end) and tr.events is None
    assert tr.stats["events"] == 0 and tr.stats["steps"] > 0
    assert len(tr.t) == scene.periods * scene.record.samples_per_period + 1
    assert np.all(np.diff(tr.t) > 0) and tr.t[-1] == pytest.approx(scene.periods * scene.profile.dt
                                                                    + scene.phase * scene.profile.dt)
    for name in scene.record.series:
        assert np.all(np.isfinite(tr.series[name]))
    assert tr.x[-1] == tr.x_end
    assert (tr.period_end, tr.tau_end) == (scene.periods, pytest.approx(scene.phase * scene.profile.dt))


def test_friction_series_follows_the_model():
    """Eq. (5): F = -(x'' + y''); on the case-1 steady state F = -y'' = 0 while stuck in
    [0, t1), F = +1 in forward slip, |F| <= 1 always (uniform surface, mu_bar = 1)."""
    tr = sa.simulate(SCENES[0], method="moreau", h=PROFILE.dt / 2000)
    assert np.all(np.abs(tr.friction) <= 1.0)
    assert np.all(tr.friction[tr.mode == 1] == 1.0)
    stick = tr.mode == 0
    assert np.array_equal(tr.friction[stick], -tr.ydd[stick])
    assert np.all(tr.mode >= 0)   # case 1: x' >= 0 throughout (Table 1)


def test_rest_on_uniform_surface():
    """Sect. 3.2: with max|y''| <= 1 the mass ends in pure stick (case 5); from v0 = 0.05 in
    [0, t1) (y'' = 0) it slips with x'' = -1 to rest at x = v0^2 / 2, t = v0, and stays
    there (REST, v = 0); tolerance h v0 (one step)."""
    gentle = sa.ThreePhaseProfile(2.0, 0.05, 0.9, 0.8)
    h, v0 = 1e-4, 0.05
    tr = sa.simulate(sa.Scene(gentle, v0=v0, until="rest"), method="moreau", h=h)
    assert tr.status is sa.Status.REST and tr.v_end == 0.0
    assert tr.x_end == pytest.approx(v0**2 / 2, abs=h * v0)
    assert tr.period_end == 0 and tr.tau_end == pytest.approx(v0, abs=h)


def test_accumulation_in_stop_zone():
    """Sect. 7.3, eq. (60): entering the stop zone with the Fig. 18 profile, stick positions
    accumulate at x_stick_min (eq. 41) = 0.54; the scheme's limit (reported with the
    caveat) equals it to 1e-12 for every h."""
    scene = sa.Scene(PROFILE, ZONE, until="rest", max_periods=200)
    for h in (1e-2, 1e-3):
        tr = sa.simulate(scene, method="moreau", h=h)
        assert tr.status is sa.Status.ACCUMULATION, tr.message
        assert tr.x_end == pytest.approx(ZONE.x_stick_min(2.2), abs=1e-12)
        assert 0.0 < tr.info["contraction"] < 1.0 and "time-stepping scheme" in tr.message


def test_never_stops_when_walking_away():
    """Sects. 5.1, 7: case 1 on a uniform surface advances for ever (NEVER_STOPS, net advance
    per period = the eq. 12-24 value to O(h)); the same when the zone is too weak
    (c_mu < max|y''|) and the mass has passed it."""
    tr = sa.simulate(sa.Scene(PROFILE, until="rest"), method="moreau", h=1e-4)
    assert tr.status is sa.Status.NEVER_STOPS
    assert tr.info["net_advance"] == pytest.approx(case1_advance(PROFILE), abs=1e-3)
    weak = sa.StopZone(0.1, 0.05, 1.5)
    tr = sa.simulate(sa.Scene(PROFILE, weak, until="rest"), method="moreau", h=1e-3)
    assert tr.status is sa.Status.NEVER_STOPS and tr.x_end > weak.x_end and tr.info["net_advance"] > 0


def test_fast_forward_equals_stepping():
    """Sect. 6.2: the velocity becomes periodic, so whole periods are added as n * advance;
    the end positions equal plain stepping (no fast-forward) to rounding."""
    scene = sa.Scene(PROFILE, ZONE, x0=-5.0, periods=100)
    tr = sa.simulate(scene, method="moreau", h=1e-3)
    stepped = simulate_batch(PROFILE, -5.0, surface=ZONE, until="periods", periods=100, method="moreau", h=1e-3,
                             fast_forward=False)
    assert tr.info["fast_forward_periods"] > 0 and stepped.records["fast_forward"][0] == 0
    assert tr.x_end == pytest.approx(stepped.x_end[0], abs=1e-12)


def test_batch_matches_scalar_path():
    """Sect. 4.1: the batch runs the same compiled driver; end states equal the scalar runs bit
    for bit (slip-slip polynomial profile of Sect. 4.2, and a list of profiles with N steps per
    period each, as in the Delta t sweep of Fig. 4)."""
    poly = sa.PolynomialProfile(0.05, 0.02)
    x0, v0 = np.array([0.0, 0.1, -0.2]), np.array([0.0, 0.5, -0.3])
    batch = simulate_batch(poly, x0, v0, until="periods", periods=3, method="moreau", h=1e-5)
    for i in range(3):
        tr = sa.simulate(sa.Scene(poly, x0=x0[i], v0=v0[i], periods=3), method="moreau", h=1e-5)
        assert (tr.x_end, tr.v_end) == (batch.x_end[i], batch.v_end[i])
    profiles = [sa.PolynomialProfile(dt, 0.02) for dt in (0.04, 0.05, 0.08)]
    sweep = simulate_batch(profiles, 0.0, until="periods", periods=3, method="moreau", steps_per_period=1000)
    for i, prof in enumerate(profiles):
        tr = sa.simulate(sa.Scene(prof, periods=3), method="moreau")
        assert tr.x_end == sweep.x_end[i]


def test_batch_fixed_point_and_bad_input():
    """Sect. 4.1: the batched fixed-point iteration agrees with the exact step to
    S h fp_tol; bad h raises before work."""
    x0 = np.linspace(0.3, 0.45, 4)
    kw = dict(surface=ZONE, until="periods", periods=5, method="moreau", h=1e-3)
    exact = simulate_batch(PROFILE, x0, **kw)
    fixed = simulate_batch(PROFILE, x0, iteration="fixed_point", fp_tol=1e-12, **kw)
    assert np.max(np.abs(exact.x_end - fixed.x_end)) <= 5 * 1050 * exact.options["h"] * 1e-12 + 1e-14
    with pytest.raises(ValueError, match="h"):
        simulate_batch(PROFILE, x0, **{**kw, "h": 0.0})
    with pytest.raises(ValueError, match="steps per period"):
        sa.simulate(sa.Scene(PROFILE, periods=1), method="moreau", h=1e-9)
