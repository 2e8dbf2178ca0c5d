"""Table-motion profiles: the Appendix constraints of the three-phase profile (Sect. 4.4.3),
the polynomial profile of Sect. 4.2 and the Fourier profile of Sect. 4.4.2."""

import numpy as np
import pytest

from selfalign import FourierProfile, NonPhysicalProfile, PolynomialProfile, ThreePhaseProfile
from selfalign.model.profiles import three_phase_feasibility, three_phase_times

rng = np.random.default_rng(20110101)


def random_feasible(n):
    """n feasible (dt, dy, y2, y3) spanning decades; q uniform in (0, 1) so dy is feasible."""
    dt = 10.0 ** rng.uniform(-3, 3, n)
    y2 = 10.0 ** rng.uniform(-2, 3, n)
    y3 = 10.0 ** rng.uniform(-2, 3, n)
    q = rng.uniform(1e-6, 1.0, n)
    dy = (q * dt) ** 2 / (8.0 * (1.0 / y2 + 1.0 / y3))
    return dt, dy, y2, y3


def integrate(sol, y2, y3):
    """Table velocity and position at t2, t_bottom, t_top and t3 by piecewise integration of
    y'' = 0, -y2, +y3 from (y_ini, y'_ini) at t0 = 0: independent of the closed form's algebra."""
    s1, s2, s3 = sol.t1, sol.t2 - sol.t1, sol.t3 - sol.t2
    v1, x1 = sol.yd_ini, sol.y_ini + sol.yd_ini * s1
    v2, x2 = v1 - y2 * s2, x1 + v1 * s2 - 0.5 * y2 * s2**2
    v3, x3 = v2 + y3 * s3, x2 + v2 * s3 + 0.5 * y3 * s3**2
    a = sol.t_top - sol.t1
    top = x1 + v1 * a - 0.5 * y2 * a**2
    b = sol.t_bottom - sol.t2
    bottom = x2 + v2 * b + 0.5 * y3 * b**2
    return {"v3": v3, "x3": x3, "v2": v2, "top": top, "bottom": bottom}


def test_appendix_constraints_hold_for_random_feasible_inputs():
    """Sect. 4.4.3 items 1-7 / Appendix eqs. 1-7 for 200,000 random feasible inputs:
    t0 = 0, t3 = dt exactly; y and y' periodic; min y = 0 and max y = dy (stroke);
    mean y'' = 0 (eq. 63).  Times are absolute floats, so a piece carries an error of order
    eps dt whatever its length: tolerance 16 eps relative to dt (y2 + y3) for velocities and
    dt^2 (y2 + y3) for positions; where every piece is longer than 1e-3 dt, positions also
    to 1e-12 relative to dy."""
    dt, dy, y2, y3 = random_feasible(200_000)
    sol = three_phase_times(dt, dy, y2, y3)
    assert sol.feasible.all()
    assert np.array_equal(sol.t3, dt)
    r = integrate(sol, y2, y3)
    tol = 16 * np.finfo(float).eps
    vscale = dt * (y2 + y3)
    xscale = dt * vscale
    shortest = np.minimum.reduce([sol.t1, sol.t2 - sol.t1, sol.t3 - sol.t2]) / dt
    well = shortest > 1e-3
    assert well.mean() > 0.5
    assert np.all(np.abs(r["v3"] - sol.yd_ini) <= tol * vscale)       # item 6: y' periodic
    mean_ydd = (-y2 * (sol.t2 - sol.t1) + y3 * (sol.t3 - sol.t2)) / dt  # eq. 63
    assert np.all(np.abs(mean_ydd) * dt <= tol * vscale)
    for err in (r["x3"] - sol.y_ini,             # item 5: y periodic
                r["bottom"],                      # item 1: min y = 0
                r["top"] - r["bottom"] - dy):     # item 4: stroke
        assert np.all(np.abs(err) <= tol * xscale)
        assert np.all(np.abs(err[well]) <= 1e-12 * dy[well])


def test_times_are_ordered_and_initial_velocity_is_positive():
    """0 <= t1 < t_top < t2 < t_bottom < t3 and y'_ini > 0: the table first moves forward, so the
    Appendix's "second case" y'_ini < 0 never arises (docs/explanation/model.md, derivation)."""
    dt, dy, y2, y3 = random_feasible(200_000)
    sol = three_phase_times(dt, dy, y2, y3)
    assert np.all(sol.yd_ini > 0)
    assert np.all((0 <= sol.t1) & (sol.t1 < sol.t_top) & (sol.t_top < sol.t2)
                  & (sol.t2 < sol.t_bottom) & (sol.t_bottom < sol.t3))


@pytest.mark.parametrize("seed", range(20))
def test_profile_object_matches_constraints_on_dense_samples(seed):
    """A ThreePhaseProfile sampled on 20,001 points plus its extremes: min y = 0, max y = dy,
    y(0) = y(dt), y'(0) = y'(dt), mean y'' = 0 (Sect. 4.4.3 items 1, 4, 5, 6), rtol 1e-12."""
    local = np.random.default_rng(seed)
    dt, y2, y3 = 10.0 ** local.uniform(-2, 2), 10.0 ** local.uniform(-1, 2), 10.0 ** local.uniform(-1, 2)
    dy = local.uniform(0.01, 1.0) ** 2 * dt**2 / (8 * (1 / y2 + 1 / y3))
    p = ThreePhaseProfile(dt, dy, y2, y3)
    t = np.concatenate([np.linspace(0.0, dt, 20_001), [p.t_top, p.t_bottom]])
    y = p.position(t)
    assert y.min() == pytest.approx(0.0, abs=1e-12 * dy)
    assert y.max() == pytest.approx(dy, rel=1e-12)
    assert p.piece_position[-1] == pytest.approx(p.piece_position[0], rel=1e-12)
    assert p.piece_velocity[-1] == pytest.approx(p.piece_velocity[0], rel=1e-12)
    assert abs(np.dot(p.accels, np.diff(p.breaks))) <= 1e-12 * p.y2 * (p.t2 - p.t1)
    assert p.t3 == dt and p.t0 == 0.0


@pytest.fixture
def boundary():
    """dt, y2, y3 and the largest feasible stroke dy_max = dt^2 / (8 (1/y2 + 1/y3)) (q = 1)."""
    dt, y2, y3 = 1.05, 2.2, 0.9
    return dt, y2, y3, dt**2 / (8 * (1 / y2 + 1 / y3))


def test_case0_boundary_feasible_side(boundary):
    """Just inside case 0's boundary (q = 1 - 1e-12) the profile exists with t1 ~ 0
    (t1 = dt sqrt(1 - q) = 1e-6 dt) and still meets the constraints (rtol 1e-9)."""
    dt, y2, y3, dy_max = boundary
    dy = dy_max * (1 - 1e-12) ** 2
    assert three_phase_feasibility(dt, dy, y2, y3) < 1.0
    p = ThreePhaseProfile(dt, dy, y2, y3)
    assert 0.0 < p.t1 <= 2e-6 * dt
    t = np.concatenate([np.linspace(0.0, dt, 10_001), [p.t_top, p.t_bottom]])
    y = p.position(t)
    assert y.max() - y.min() == pytest.approx(dy, rel=1e-9)
    assert p.piece_velocity[-1] == pytest.approx(p.piece_velocity[0], rel=1e-9)


def test_case0_boundary_infeasible_side(boundary):
    """Just outside (q = 1 + 1e-12) there is no physical profile (the paper's case 0): the
    constructor raises NonPhysicalProfile naming the condition, and the vectorised solver
    returns NaN with feasible = False."""
    dt, y2, y3, dy_max = boundary
    dy = dy_max * (1 + 1e-12) ** 2
    assert three_phase_feasibility(dt, dy, y2, y3) > 1.0
    with pytest.raises(NonPhysicalProfile, match=r"case 0.*8\*dy\*\(1/y2 \+ 1/y3\).*exceeds dt\^2"):
        ThreePhaseProfile(dt, dy, y2, y3)
    sol = three_phase_times(dt, dy, y2, y3)
    assert not sol.feasible and np.isnan(sol.t1) and np.isnan(sol.t3)


def test_case0_exact_boundary_drops_the_empty_first_piece():
    """At q = 1 exactly (dt = 4, dy = 4, y2 = y3 = 4) t1 = 0, and the zero-length first piece
    is dropped so solvers never see an empty interval."""
    p = ThreePhaseProfile(4.0, 4.0, 4.0, 4.0)
    assert p.t1 == 0.0
    np.testing.assert_array_equal(p.accels, [-4.0, 4.0])
    assert p.breaks[0] == 0.0 and p.breaks[-1] == 4.0


@pytest.mark.parametrize("dt, dy, y2, y3", [(0.0, 0.1, 1, 1), (1, -0.1, 1, 1), (1, 0.1, 0, 1),
                                            (1, 0.1, 1, float("nan"))])
def test_three_phase_rejects_non_positive_input(dt, dy, y2, y3):
    """Bad input raises a one-line ValueError naming the quantity, before any work."""
    with pytest.raises(ValueError, match=r"^(dt|dy|y2|y3) must be"):
        ThreePhaseProfile(dt, dy, y2, y3)


@pytest.mark.parametrize("f", [0.1, 0.5, 0.8, 0.95])
def test_polynomial_profile(f):
    """Sect. 4.2 profile (our definition, docs/explanation/model.md): periodic y and y', stroke dy, zero mean y,
    peak accelerations 4 dy / (f dt)^2 and 4 dy / ((1 - f) dt)^2 (rtol 1e-12, dense mean 1e-9)."""
    dt, dy = 0.05, 0.02
    p = PolynomialProfile(dt, dy, forward_fraction=f)
    assert p.piece_position[-1] == pytest.approx(p.piece_position[0], abs=1e-12 * dy)
    assert p.piece_velocity[-1] == pytest.approx(p.piece_velocity[0], abs=1e-12 * dy / dt)
    t = np.linspace(0.0, dt, 200_001)
    y = p.position(t)
    assert y.max() - y.min() == pytest.approx(dy, rel=1e-12)
    assert np.trapezoid(y, t) / dt == pytest.approx(0.0, abs=1e-9 * dy)
    assert abs(np.mean(p.acceleration(t[:-1]))) <= 1e-3 * p.max_abs_acceleration  # grid-limited
    assert np.dot(p.accels, np.diff(p.breaks)) == pytest.approx(0.0, abs=1e-12 * p.max_abs_acceleration * dt)
    assert p.max_abs_acceleration == pytest.approx(4 * dy / (min(f, 1 - f) * dt) ** 2, rel=1e-12)


def test_polynomial_rejects_bad_fraction():
    with pytest.raises(ValueError, match="forward_fraction"):
        PolynomialProfile(1.0, 0.1, forward_fraction=1.0)


@pytest.mark.parametrize("seed", range(10))
def test_fourier_peaks_match_dense_sampling(seed):
    """Sect. 4.4.2 constraint quantities (stroke, max |y'|, max |y''|) agree with 400,000-point
    sampling to rtol 1e-8 and are never below it (the Newton refinement finds the true peak)."""
    local = np.random.default_rng(seed)
    order = int(local.integers(1, 13))  # up to the paper's twelfth order
    dt = 0.072
    decay = 1.0 / np.arange(1, order + 1) ** 2
    p = FourierProfile(dt, local.normal(size=order) * decay * 0.01, local.normal(size=order) * decay * 0.01)
    t = np.linspace(0.0, dt, 400_000, endpoint=False)
    y, yd, ydd = p.position(t), p.velocity(t), p.acceleration(t)
    for prop, dense in ((p.stroke, y.max() - y.min()), (p.peak_velocity, np.abs(yd).max()),
                        (p.peak_acceleration, np.abs(ydd).max())):
        assert prop >= dense * (1 - 1e-14)
        assert prop == pytest.approx(dense, rel=1e-8)
    assert np.mean(y) == pytest.approx(0.0, abs=1e-12 * p.stroke)
    # derivatives are consistent: central differences of y and y' (h = 1e-6 dt), rtol 1e-6
    h = 1e-6 * dt
    np.testing.assert_allclose((p.position(t[:50] + h) - p.position(t[:50] - h)) / (2 * h), yd[:50],
                               atol=1e-6 * p.peak_velocity)
    np.testing.assert_allclose((p.velocity(t[:50] + h) - p.velocity(t[:50] - h)) / (2 * h), ydd[:50],
                               atol=1e-6 * p.peak_acceleration)
