"""The accumulation map x_n -> x_{n+1} of Sect. 7.3 (eqs. 42-60) against the solvers."""

import numpy as np
import pytest

from selfalign import Status, StopZone, ThreePhaseProfile, simulate, simulate_batch
from selfalign.analysis.stick_map import (
    stick_map,
    stick_map_constants,
    stick_map_contraction,
    stick_map_simulated,
    stick_map_slip_limit,
    stick_map_threshold,
    stick_map_validity,
    stick_sequence,
)
from selfalign.model.friction import FrictionLaw
from selfalign.model.scene import Record, Scene
from selfalign.solvers.outcomes import EventKind

#: Fig. 18: y2'' = 2.2, y3'' = 0.9, dt = 1.05, dy = 0.084; w = 0.05, c_mu = 2.5 (Sect. 7.2).
FIG18 = ThreePhaseProfile(1.05, 0.084, 2.2, 0.9)
#: Fig. 16 (upper): (2.3, 1.3) with dt = 1.
FIG16 = ThreePhaseProfile(1.0, 0.084, 2.3, 1.3)
ZONE = {"w": 0.05, "c_mu": 2.5, "x_mu": 0.3}


def fixed_point(profile, zone=ZONE):
    return stick_map_constants(profile, StopZone(**zone)).fixed_point


@pytest.mark.parametrize("profile", [FIG18, FIG16], ids=["fig18", "fig16"])
def test_closed_form_equals_simulated_map(profile):
    """Eq. (59) is the exact stick-to-stick map where its assumptions hold (Sect. 7.3).

    x_{n+1} = first stick after t = 0 of a mass stuck at x_n at t = 0, measured with the
    exact event-driven solver and with the batched solver; they agree with eq. (59) to
    1e-12 at every valid x_n in [x_mu, x_f)."""
    x_n = np.linspace(ZONE["x_mu"], fixed_point(profile), 41)[:-1]
    valid = stick_map_validity(x_n, profile, **ZONE).valid
    assert valid.sum() >= 10
    formula = stick_map(x_n, profile, **ZONE)
    exact = stick_map_simulated(x_n[valid], profile, **ZONE, method="exact")
    batch = stick_map_simulated(x_n[valid], profile, **ZONE)
    np.testing.assert_allclose(exact, formula[valid], rtol=0, atol=1e-12)
    np.testing.assert_allclose(batch, formula[valid], rtol=0, atol=1e-12)


def test_validity_flags_where_eq59_fails():
    """Where stick_map_validity says an assumption of eq. (59) fails, the real map differs.

    Three failures: x_n >= x_f (no slip at t1: the mass stays, x_{n+1} = x_n), x_n beyond
    the zone, and y3'' > mu_bar(x_{n+1}) (the mass reverses instead of sticking: setting
    (2.4, 2.3) from x_n near x_mu + 0.01).  Where all hold they agree to 1e-12; elsewhere (but at x_f
    itself) they differ by more than 1e-6."""
    reverses = ThreePhaseProfile(1.0, 0.084, 2.4, 2.3)
    x_n = np.linspace(0.3, 0.36, 25)
    for profile in (FIG18, FIG16, reverses):
        val = stick_map_validity(x_n, profile, **ZONE)
        formula = stick_map(x_n, profile, **ZONE)
        real = stick_map_simulated(x_n, profile, **ZONE)
        np.testing.assert_allclose(real[val.valid], formula[val.valid], rtol=0, atol=1e-12)
        differ = ~val.valid & (x_n != fixed_point(profile))  # at x_f both give x_f
        assert differ.any() and np.all(np.abs(real - formula)[differ] > 1e-6)
    assert not stick_map_validity(0.31, reverses, **ZONE).sticks
    assert not stick_map_validity(0.345, FIG18, **ZONE).slips_at_t1
    assert not stick_map_validity(0.36, FIG18, **ZONE).in_zone


def test_fixed_point_is_x_stick_min():
    """The fixed point of eq. (59) is (b2 + y2'')/b1 = x_stick_min of eq. (41) (eq. 60).

    Exact (1 ulp) for y2'' >= y3''; the simulated map leaves x_stick_min in place (the mass
    is at rest for good there).  For y3'' > y2'' the fixed point lies below x_stick_min:
    eq. (60)'s identification needs max(y2'', y3'') = y2''."""
    zone = StopZone(**ZONE)
    for profile in (FIG18, FIG16):
        xs = zone.x_stick_min(profile.max_abs_acceleration)
        assert fixed_point(profile) == pytest.approx(xs, rel=0, abs=1e-15)
        assert float(stick_map(xs, profile, **ZONE)) == pytest.approx(xs, rel=0, abs=1e-15)
        assert float(stick_map_simulated(xs, profile, **ZONE)) == xs
    high_y3 = ThreePhaseProfile(1.0, 0.084, 1.8, 2.2)
    assert fixed_point(high_y3) < zone.x_stick_min(high_y3.max_abs_acceleration) - 0.01


@pytest.mark.parametrize("profile", [FIG18, FIG16], ids=["fig18", "fig16"])
def test_contraction_is_cos_omega_slip_window(profile):
    """d x_{n+1}/d x_n at the fixed point = cos(sqrt(b1) (t2 - t1)) (from eq. 59).

    Central differences of eq. (59) (h = 1e-5, tol 1e-8) and a second-order one-sided
    difference of the simulated map from below (h = 1e-4, tol 1e-6)."""
    c = stick_map_contraction(profile, **ZONE)
    const = stick_map_constants(profile, StopZone(**ZONE))
    assert c == pytest.approx(np.cos(const.omega * const.slip_window), abs=1e-15)
    xf = fixed_point(profile)
    h = 1e-5
    central = (stick_map(xf + h, profile, **ZONE) - stick_map(xf - h, profile, **ZONE)) / (2 * h)
    assert central == pytest.approx(c, abs=1e-8)
    h = 1e-4
    f0, f1, f2 = stick_map_simulated(np.array([xf, xf - h, xf - 2 * h]), profile, **ZONE)
    one_sided = (3 * f0 - 4 * f1 + f2) / (2 * h)
    assert one_sided == pytest.approx(c, abs=1e-6)


def test_sufficient_condition_for_the_map():
    """Sect. 7.3: if x_{n+1}(x_mu) < x_stick_min, the stick positions accumulate at x_stick_min.

    For the map itself this holds: eq. (59) is convex in x_n (a hypot of affine terms), so
    on [x_mu, x_stick_min) it stays below max(f(x_mu), x_stick_min) = x_stick_min and above
    x_n; the batched solver started stuck at 30 positions in [x_mu, x_stick_min) at t = 0
    ends in ACCUMULATION at x_stick_min for Fig. 16 (upper), where the condition holds, and
    ends at rest beyond x_stick_min for some starts of Fig. 18, where it fails."""
    zone = StopZone(**ZONE)
    for profile, holds in ((FIG16, True), (FIG18, False)):
        xs = zone.x_stick_min(profile.max_abs_acceleration)
        assert (float(stick_map(zone.x_mu, profile, **ZONE)) < xs) is holds
        starts = np.linspace(zone.x_mu, xs, 31)[:-1]
        if holds:
            assert stick_map_validity(starts, profile, **ZONE).valid[1:].all()
        res = simulate_batch(profile, starts, surface=zone)
        acc = np.array([s is Status.ACCUMULATION for s in res.statuses()])
        assert all(s in (Status.ACCUMULATION, Status.REST) for s in res.statuses())
        assert bool(acc.all()) is holds
        np.testing.assert_array_equal(res.x_end[acc], xs)
        assert np.all(res.x_end[~acc] > xs)


def test_bad_input():
    """A one-line ValueError/TypeError before any work."""
    with pytest.raises(ValueError, match="method"):
        stick_map_simulated(0.3, FIG18, **ZONE, method="rk4")
    with pytest.raises(ValueError, match="c_mu"):
        stick_map(0.3, FIG18, w=0.05, c_mu=1.0, x_mu=0.3)
    with pytest.raises(TypeError, match="ThreePhaseProfile"):
        stick_map_simulated(0.3, object(), **ZONE)


def test_threshold_separates_rest_from_accumulation():
    """Fig. 18's middle line: x_c = x_f - 2 (y2'' + y3'')/b1 cos(omega (t2 - t1)) maps onto x_f
    (eq. 59, 1e-15); the simulated map sends starts just above x_c below x_stick_min and
    starts just below x_c beyond it (Fig. 18, Sect. 7.3)."""
    x_c = stick_map_threshold(FIG18, **ZONE)
    xf = fixed_point(FIG18)
    assert ZONE["x_mu"] < x_c < xf
    assert float(stick_map(x_c, FIG18, **ZONE)) == pytest.approx(xf, abs=1e-15)
    below, above = stick_map_simulated(np.array([x_c - 1e-6, x_c + 1e-6]), FIG18, **ZONE)
    assert below > xf > above


@pytest.mark.parametrize("ratio", [1.3, 1.01])
def test_static_friction_map_gives_the_exact_stick_sequences(ratio):
    """Under static friction mu_s = r mu_k the map is eq. (59) below x_s = x_mu + w (y2/r - 1)/(c_mu - 1)
    (a stuck mass slips only once y2'' > r mu_bar; the slip runs against mu_bar) and the identity
    above: from starts stuck across [x_mu, x_s) on the Fig. 18 profile, its stick sequence is the
    exact solver's stick for stick (1e-12), ends at or beyond x_s and is where the mass rests."""
    profile, kw = FIG18, {"w": 0.05, "c_mu": 2.5, "x_mu": 0.0}
    x_s = stick_map_slip_limit(profile, **kw, ratio=ratio)
    assert x_s < stick_map_constants(profile, StopZone(**kw)).fixed_point
    steps = []
    for x0 in np.linspace(kw["x_mu"], x_s, 6)[:-1]:
        seq = stick_sequence(x0, profile, **kw, ratio=ratio)
        assert seq.valid and seq.rests and seq.x[-1] >= x_s
        traj = simulate(Scene(profile, StopZone(**kw), x0=float(x0), periods=10, record=Record(events=True),
                              friction=FrictionLaw("static_kinetic", ratio)), method="exact")
        sticks = traj.events[traj.events["kind"] == EventKind.STICK]["x"]
        np.testing.assert_allclose(sticks, seq.x[1:], rtol=0, atol=1e-12)
        assert traj.x_end == pytest.approx(seq.x[-1], abs=1e-12)
        steps.append(seq.x.size - 1)
    assert max(steps) == 1 if ratio == 1.3 else max(steps) > 1  # r near 1: several sticks before rest


def test_coulomb_map_sequence_never_rests():
    """At r = 1, x_s is the fixed point x_f, and the sticks from above the threshold x_c approach it
    without reaching it (the accumulation; by 0.154 per stick, so within 5 sticks it stays above
    rounding): the sequence takes every allowed step and does not rest."""
    kw = {"w": 0.05, "c_mu": 2.5, "x_mu": 0.0}
    x_f = fixed_point(FIG18, kw)
    assert stick_map_slip_limit(FIG18, **kw) == x_f
    seq = stick_sequence(0.5 * (stick_map_threshold(FIG18, **kw) + x_f), FIG18, **kw, max_sticks=5)
    assert seq.valid and not seq.rests and seq.x.size == 6
    assert np.all(np.diff(seq.x[1:]) > 0) and seq.x[-1] < x_f
