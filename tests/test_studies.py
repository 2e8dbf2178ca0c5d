"""Parameter studies of Sects. 4.3-5.2 (selfalign.analysis.steady_simulation and .fourier_design,
selfalign.stages.classification): steady states by simulation, the
polynomial-profile sweeps of Figs. 4-5, the Fourier shape optimisation of Fig. 6 and the
verification of the closed-form maps of Figs. 10-11 against simulation."""

import numpy as np
import pytest

from selfalign import FourierProfile, PolynomialProfile, ThreePhaseProfile
from selfalign.analysis.classification import decision_quantities
from selfalign.analysis.fourier_design import (
    align_to,
    best_three_phase,
    fourier_start,
    optimise_fourier,
    steady_vbar_gradient,
    time_shift,
)
from selfalign.analysis.steady_simulation import (
    RTOL,
    exact_steady_state,
    iterate_to_steady_state,
    objective,
    run_periods,
    simulated_steady_state,
    three_phase_simulated_steady_state,
)
from selfalign.analysis.steady_state import OBJECTIVE_SCALE, steady_state, steady_state_grid
from selfalign.model.profiles import three_phase_times
from selfalign.model.scene import Scene
from selfalign.solvers.driver import simulate
from selfalign.stages.classification import (
    VERIFY_BAND,
    VERIFY_RTOL,
    gather_map,
    map_shard,
    map_verification,
    polynomial_sweep,
)

#: Fig. 6 settings (Sect. 4.4.2): dt, dy, y'max, y''max.
FIG6 = (0.072, 0.021, 3.2, 1275.0)


def affine_map(c, b, a=0.5):
    """Period map v -> c v + b with displacement a v + 1 (vectorised over members)."""
    def period_map(index, v):
        return c[index] * v + b[index], a * v + 1.0
    return period_map


def test_bisection_finds_the_fixed_point_of_a_contraction():
    """Steady state = fixed point v* of the period map (Sect. 5.1, eq. 10): for affine maps
    with slopes 0 ... 0.999 (c4 of eq. 33 near 1 needs thousands of plain iterations) the
    bisection returns v* to RTOL * s and vbar = D(v*) / dt, within ~60 periods."""
    c = np.array([0.0, 0.5, 0.9968, 0.999, 0.3])
    b = np.array([0.2, -0.3, 0.004, -1e-4, 0.0])
    res = iterate_to_steady_state(affine_map(c, b), np.full(5, 5.0), 0.1)
    v_star = b / (1.0 - c)
    assert np.all(np.abs(res.v0 - v_star) <= 2 * RTOL * 5.0 / (1.0 - c))
    np.testing.assert_allclose(res.vbar, (0.5 * res.v0 + 1.0) / 0.1, rtol=1e-14)
    assert res.periods.max() <= 60 and res.periods[-1] == 1       # v* = 0 is found at once


def test_bisection_returns_the_limit_of_iteration_from_rest_for_a_plateau():
    """Moreau's period map is a translation while the mass slips all period, so a whole
    interval of x'(0) is fixed (module docstring): the result is the end nearest to 0, the
    limit of time-stepping from rest, for both signs; a map without fixed point in [-s, s]
    is reported."""
    def plateau(index, v):
        # fixed on [1, 2] (and on [-2, -1] mirrored): P(v) - v = clip(1 - |v|, 0) - clip(|v| - 2, 0)
        g = np.clip(1.0 - np.abs(v), 0.0, None) - np.clip(np.abs(v) - 2.0, 0.0, None)
        return v + np.sign(index - 0.5) * g, v
    res = iterate_to_steady_state(plateau, np.array([5.0, 5.0]), 1.0, floor=1e-15)
    np.testing.assert_allclose(res.v0, [-1.0, 1.0], atol=1e-12)
    with pytest.raises(RuntimeError, match="does not contain the fixed point"):
        iterate_to_steady_state(affine_map(np.array([0.5]), np.array([10.0])), np.array([1.0]), 1.0)


def test_exact_steady_state_of_a_grazing_fourier_profile_is_the_independent_one():
    """A Fourier profile met during the Fig. 6 optimisation (Sect. 4.4.2) whose backward slip
    grazes x' = 0: the smooth stepper once missed a slip shorter than its grid spacing there and
    reported a 20-period cycle.  Its steady motion repeats every period: vbar from the exact
    steady state equals the average of ten simulated periods from it to 1e-9, and Moreau's
    (Sect. 4.1, h = dt / 2e6, first order) to 1e-7 -- an independent method, since solve_ivp
    steps over this grazing (test_ivp_follows_the_grazing_until_it_steps_over_it)."""
    dt = FIG6[0]
    profile = FourierProfile(dt, CYCLE_COS, CYCLE_SIN)
    ss = exact_steady_state(profile)
    assert ss.cycle[0] == 1
    _, disp = run_periods(profile, float(ss.v0[0]), 10)
    assert disp / (10 * dt) == pytest.approx(float(ss.vbar[0]), rel=1e-9)
    scene = Scene(profile, x0=0.0, v0=float(ss.v0[0]), periods=12, method="moreau",
                  solver_options={"steps_per_period": 2_000_000})
    moreau_vbar = (simulate(scene).x_end - simulate(scene.replace(periods=2)).x_end) / (10 * dt)
    assert moreau_vbar == pytest.approx(float(ss.vbar[0]), abs=1e-7)


def test_ivp_follows_the_grazing_until_it_steps_over_it():
    """The grazing of the profile above, with solve_ivp (rtol 1e-12): the backward slip reverses into
    a forward slip of 5.5e-5 from x' = 0, which solve_ivp took in one step ending past its end; it
    found the start root again and the event loop stalled (ERROR) in period 0.  Now the slip's own
    end is found: the first three periods agree with the exact solver to 1e-10.  In period 3 the
    backward slip's v = 0 crossing and its return lie in one step and are not seen (an honest limit
    of event location by sign changes at step ends, ivp module docstring; measured: 8e-6 off after
    12 periods at rtol 1e-12, 3.5e-4 at rtol 1e-8)."""
    profile = FourierProfile(FIG6[0], CYCLE_COS, CYCLE_SIN)
    scene = Scene(profile, x0=0.0, v0=float(exact_steady_state(profile).v0[0]), periods=3)
    ivp = simulate(scene, method="ivp", rtol=1e-12, atol=1e-14)
    assert ivp.status.value == "horizon", ivp.message
    assert ivp.x_end == pytest.approx(simulate(scene, method="exact").x_end, abs=1e-10)


#: Fourier coefficients (order 12) met during the Fig. 6 optimisation: a backward slip grazes
#: x' = 0 where |y''| < 1.
CYCLE_COS = [-0.005596183, -0.003128288, -0.001002368, -0.0002944828, -2.314545e-05, 0.0001869348,
             9.94112e-05, 4.168979e-05, -1.311337e-05, -9.190617e-06, 1.939271e-05, -1.798678e-05]
CYCLE_SIN = [-0.00724713, -0.000894182, 0.0002797218, 0.0004696737, 0.000333545, 0.0002550297,
             5.165404e-07, 1.700737e-05, 2.699701e-05, -4.86091e-05, 2.685831e-05, 3.973787e-06]


@pytest.mark.parametrize("method", ["exact", "moreau"])
def test_fast_table_limit_of_the_polynomial_profile(method):
    """Sect. 4.4.1 / Figs. 4-5 in the limit of large accelerations: the mass slips all the
    time, its absolute velocity w barely changes, and zero mean friction impulse makes w the
    median of y'; for the polynomial profile (forward stroke 0.8 dt, y' a triangle of height
    2.5 dy / dt) that is w = 0.375 * 2.5 dy / dt, so x advances by 15/16 dy per period and
    f = dt^2 / (c (15/16 dy)^2).  Exact solver to 1e-9, Moreau (h = dt / 1000) to 1e-2."""
    dt = np.array([0.01, 0.03, 0.1])
    profiles = [PolynomialProfile(t, 0.02) for t in dt]
    res = simulated_steady_state(profiles, method)
    tol = 1e-9 if method == "exact" else 1e-2
    np.testing.assert_allclose(res.vbar * dt / 0.02, 15 / 16, rtol=tol)
    np.testing.assert_allclose(res.f, dt**2 / (OBJECTIVE_SCALE * (15 / 16 * 0.02) ** 2), rtol=2 * tol)


def test_polynomial_sweeps_follow_the_design_rules():
    """Sect. 4.4.1 (Figs. 4, 5): a higher frequency (smaller dt) and a larger stroke dy give a
    smaller f, strictly along both sweeps and for both solvers; time-stepping agrees with the
    exact solver to 5 % (h = dt / 1000) except next to pure stick (the largest dt, where vbar -> 0)."""
    d4, _ = polynomial_sweep(np.geomspace(0.02, 1.2, 12), 0.02)
    d5, attrs = polynomial_sweep(0.05, np.geomspace(1e-4, 0.1, 12))
    for m in ("exact", "moreau"):
        assert np.all(np.diff(d4[f"f_{m}"]) > 0) and np.all(np.diff(d5[f"f_{m}"]) < 0)
    for d in (d4, d5):
        assert np.all(np.abs(d["f_moreau"][:-1] / d["f_exact"][:-1] - 1) < 5e-2)
    assert attrs["moreau_steps_per_period"] == 1000 and attrs["moreau_iteration"] == "exact"


def test_moreau_fixed_point_iteration_gives_the_exact_step_result():
    """Sect. 4.1: the paper solves the implicit Moreau step by a fixed-point iteration; its
    steady state equals that of the exact soft-threshold solution to 1e-10 (fp_tol 1e-14)."""
    profiles = [PolynomialProfile(t, 0.02) for t in (0.05, 0.5)]
    a = simulated_steady_state(profiles, "moreau", steps_per_period=200, iteration="exact")
    b = simulated_steady_state(profiles, "moreau", steps_per_period=200, iteration="fixed_point")
    np.testing.assert_allclose(b.vbar, a.vbar, rtol=1e-10)


@pytest.mark.parametrize("name, dt, dy, y2, y3", [
    ("fig10", 0.072, 0.021, np.linspace(20.0, 1500.0, 13), np.linspace(20.0, 300.0, 15)),
    ("fig11", 1.38, 0.064, np.linspace(0.1, 3.0, 14), np.linspace(0.1, 3.0, 13)),
])
def test_closed_form_vbar_equals_simulated_vbar_on_subsampled_maps(name, dt, dy, y2, y3):
    """Sect. 5.2: the analytic steady state (Sect. 5.1) equals the simulated one (batched exact
    solver, from x'(0) = 0) to 1e-10 relative at every point of a subsample of the Fig. 10 /
    Fig. 11 axes — outside the band |vbar| < 1e-3 u around vbar = 0, where the comparison is
    1e-13 u absolute (u the table velocity swing; map_verification)."""
    data, attrs = gather_map(dt, dy, y2, y3, [map_shard(dt, dy, y2, y3, slice(0, y2.size))])
    check = map_verification(data, attrs)
    assert check["passed"] and check["max_scaled_error"] <= VERIFY_RTOL
    assert check["points"] == np.count_nonzero(data["case"] > 0) > 100
    assert (VERIFY_RTOL, VERIFY_BAND) == (1e-10, 1e-3)


def test_map_verification_can_fail():
    """The verification reports a 1e-8 relative error at one point as a failure."""
    dt, dy, y2, y3 = 1.38, 0.064, np.linspace(0.1, 3.0, 8), np.linspace(0.1, 3.0, 8)
    data, attrs = gather_map(dt, dy, y2, y3, [map_shard(dt, dy, y2, y3, slice(0, 8))])
    i, j = np.argwhere(np.abs(data["vbar"]) > 1e-2)[0]
    data["vbar_simulated"][i, j] *= 1 + 1e-8
    check = map_verification(data, attrs)
    assert not check["passed"] and check["max_rel_error"] == pytest.approx(1e-8, rel=1e-3)


def test_simulated_steady_state_of_the_fig18_profile():
    """Sect. 5.1 case 1 (y2'' > 1 > y3''): x'(0) = 0 and vbar of the closed form, from a
    simulation that does not know them (to 1e-12)."""
    p = ThreePhaseProfile(1.05, 0.084, 2.2, 0.9)
    sim = three_phase_simulated_steady_state(p.dt, p.dy, p.y2, p.y3)
    ss = steady_state(p)
    assert ss.case == 1 and sim.v0 == 0.0
    assert sim.vbar == pytest.approx(ss.vbar, rel=1e-12)
    assert np.isnan(three_phase_simulated_steady_state(0.072, 0.021, 30.0, 30.0).vbar)   # case 0


def test_objective_is_eq11():
    """Eq. 11: f = 1 / (c vbar^2), c = 10,000; inf for vbar = 0, NaN for NaN."""
    np.testing.assert_array_equal(objective([0.5, -0.1, 0.0, np.nan]), [4e-4, 1e-2, np.inf, np.nan])


def test_steady_state_gradient_matches_differences_of_steady_states():
    """Fig. 6 optimiser: the implicit-function gradient of vbar over the Fourier coefficients
    (one-period runs from the fixed point) equals central differences of full steady states
    to 1e-5 relative (of the gradient's norm)."""
    dt, dy = FIG6[:2]
    start = fourier_start(dt, dy, 12)
    z = np.concatenate([start.cos_coeffs, start.sin_coeffs]) / dy

    def profile_of(zz):
        return FourierProfile(dt, dy * zz[:12], dy * zz[12:24])

    grad = steady_vbar_gradient(profile_of, z, exact_steady_state(profile_of(z)), 24, 1e-9)
    for i in (0, 5, 13, 23):
        step = np.zeros_like(z)
        step[i] = 1e-5
        fd = (exact_steady_state(profile_of(z + step)).vbar[0]
              - exact_steady_state(profile_of(z - step)).vbar[0]) / 2e-5
        assert grad[i] == pytest.approx(fd, abs=1e-5 * np.linalg.norm(grad))


def test_fourier_optimisation_improves_f_within_the_constraints():
    """Sect. 4.4.2: the SQP (analysis.sqp) lowers f of the 12th-order Fourier profile from its start (the
    polynomial profile truncated, f = 1.40e-3) while keeping the stroke <= dy, |y'| <= 3.2 and
    |y''| <= 1275 (true extremes, 0.5 % above at most, between the constraint samples)."""
    dt, dy, yd_max, ydd_max = FIG6
    opt = optimise_fourier(dt, dy, yd_max, ydd_max, max_iter=15)
    assert opt.history_f[0] == pytest.approx(1.404e-3, rel=1e-3)
    assert opt.f < 0.6 * opt.history_f[0]
    assert opt.iterations == 15 and opt.history_f.size == 16
    s = opt.settings
    assert 0.99 * dy <= s["stroke"] <= 1.005 * dy
    assert s["peak_velocity"] <= 1.005 * yd_max and s["peak_acceleration"] <= 1.005 * ydd_max


def test_time_shift_keeps_the_steady_state():
    """A Fourier profile shifted in time has the same steady state (vbar to 1e-12), and
    align_to recovers a known shift of the table velocity (to one sample)."""
    dt, dy = FIG6[:2]
    start = fourier_start(dt, dy, 12)
    shifted = time_shift(start, 0.3 * dt)
    t = np.linspace(0.0, dt, 50)
    np.testing.assert_allclose(shifted.position(t), start.position(t + 0.3 * dt), atol=1e-15)
    assert exact_steady_state(shifted).vbar[0] == pytest.approx(exact_steady_state(start).vbar[0], rel=1e-12)
    back = align_to(shifted, start)
    np.testing.assert_allclose(back.velocity(t), start.velocity(t), atol=2 * np.pi / 4096 * 3.0 * 12)


def test_best_three_phase_lies_next_to_slip_slip():
    """Sect. 5.2 design rule with the Fig. 6 constraints: the best three-phase profile is a
    general stick-slip (case 3) on the boundary to slip-slip (stick time ~0), with f no larger
    than anywhere on a 200 x 200 grid of y2'', y3'' <= 1275 and |y'| <= 3.2."""
    dt, dy, yd_max, ydd_max = FIG6
    best = best_three_phase(dt, dy, ydd_max, yd_max)
    ss = steady_state(best)
    assert ss.case == 3 and ss.stick_time < 1e-6 * dt
    axis = np.linspace(ydd_max / 200, ydd_max, 200)
    y2, y3 = np.meshgrid(axis, axis, indexing="ij")
    grid = steady_state_grid(dt, dy, y2, y3)
    qty = decision_quantities(dt, dy, y2, y3)
    yd_ini = three_phase_times(dt, dy, y2, y3).yd_ini
    allowed = (grid.case > 0) & (np.maximum(yd_ini, qty["swing"] - yd_ini) <= yd_max)
    assert ss.f <= np.min(grid.f[allowed])
    assert ss.f == pytest.approx(3.901e-4, rel=1e-3)
