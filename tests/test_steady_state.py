"""Closed-form steady state of the three-phase profile (Sect. 5.1, 5.2, Table 1) and its
analytic Floquet multipliers (Sect. 6.1, eqs. 25-33), checked against an independent
brute-force simulation written here."""

from dataclasses import astuple

import numpy as np
import pytest

from selfalign import Scene, ThreePhaseProfile, simulate
from selfalign.analysis.classification import classify, classify_grid
from selfalign.analysis.steady_state import (
    OBJECTIVE_SCALE,
    SteadyState,
    floquet_multipliers_analytic,
    monodromy_analytic,
    monodromy_grid,
    one_period_map,
    steady_state,
    steady_state_grid,
)
from selfalign.model.profiles import three_phase_times

EPS = np.finfo(float).eps

#: (dy, dt, y2'' = y3'' axis) of the paper's maps.  The axes reach every case boundary of the
#: setting: Fig. 10 shows cases 0, 3, 4; Fig. 11 cases 0, 1, 2, 3, 5 (no slip-slip exists
#: there); Fig. 17 cases 0, 1, 2, 3, 4 (no pure stick exists there).
SETTINGS = {
    "fig10": (0.021, 0.072, np.geomspace(20.0, 2000.0, 150)),
    "fig11": (0.064, 1.38, np.linspace(0.1, 3.0, 150)),
    "fig17": (0.084, 1.0, np.linspace(0.3, 6.0, 150)),
}
EXPECTED_CASES = {"fig10": {0, 3, 4}, "fig11": {0, 1, 2, 3, 5}, "fig17": {0, 1, 2, 3, 4}}


def swing(dt, dy, y2, y3):
    """Table velocity swing u = y2'' (t2 - t1) (eq. 63), the natural velocity scale."""
    times = three_phase_times(dt, dy, y2, y3)
    return y2 * (times.t2 - times.t1)


def rounding(dt, y2, y3):
    """Rounding bound of a velocity built from phases: 4 eps (1 + y2'' + y3'') dt."""
    return 4 * EPS * (1.0 + y2 + y3) * dt


MODES = {"forward": 1.0, "backward": -1.0, "stick": 0.0}


def simulate_reference(dt, dy, y2, y3, v_start, max_periods=20_000):
    """Brute-force steady state, independent of the closed forms.

    Event-driven integration in the absolute frame: the mass velocity w = x' + y' moves at
    rate -1 while faster than the table (x' > 0), +1 while slower, and follows y' when at
    rest relative to it if |y''| <= 1 (else it leaves in the direction -sign(y'')).  Each
    piece of constant y'' holds at most one meeting of w and y', so two sub-steps per piece
    are exact.  Periods are iterated from x'(0) = v_start until x'(0) repeats to 8 ulp of
    the velocity scale (at least two periods, so that mode changes across t = 0 are seen);
    the last period gives the mean velocity, the mean speed, and per mode the time spent in
    it and the phase at which it last began ("<mode>_start", 0 if it never changes).
    Returns a dict of flat arrays, NaN for infeasible entries.
    """
    dt, dy, y2, y3, v_start = (a.ravel() for a in np.broadcast_arrays(dt, dy, y2, y3, v_start))
    times = three_phase_times(dt, dy, y2, y3)
    pieces = [(np.zeros_like(y2), times.t1), (-y2, times.t2 - times.t1), (y3, dt - times.t2)]
    yd0 = times.yd_ini
    scale = y2 * (times.t2 - times.t1) + np.abs(v_start)
    keys = ["v0", "vbar", "speed", "periods", *MODES, *(f"{m}_start" for m in MODES)]
    result = {key: np.full(dt.size, np.nan) for key in keys}
    active = np.flatnonzero(times.feasible)
    v = v_start.copy()
    last_mode = np.full(dt.size, np.nan)
    for period in range(1, max_periods + 1):
        idx = active
        table_v = yd0[idx].copy()
        wa = table_v + v[idx]
        prev = last_mode[idx]
        clock = np.zeros(idx.size)
        disp = np.zeros(idx.size)
        speed = np.zeros(idx.size)
        spent = {m: np.zeros(idx.size) for m in MODES}
        began = {m: np.zeros(idx.size) for m in MODES}
        for accel, length in pieces:
            a, remaining = accel[idx], length[idx].copy()
            for _ in range(2):
                rel = wa - table_v
                mode = np.sign(rel)
                mode = np.where(rel == 0, np.where(np.abs(a) <= 1, 0.0, np.where(a < -1, 1.0, -1.0)),
                                mode)
                w_acc = np.where(mode == 0, a, -mode)
                rel_acc = w_acc - a
                with np.errstate(divide="ignore", invalid="ignore"):
                    t_meet = np.where(rel * rel_acc < 0, -rel / rel_acc, np.inf)
                met = t_meet <= remaining
                h = np.where(met, t_meet, remaining)
                disp += rel * h + 0.5 * rel_acc * h * h
                # |x'| integrates to the same triangles/trapezoids: x' keeps its sign on h.
                speed += np.abs(rel * h + 0.5 * rel_acc * h * h)
                moving = h > 0
                for m, code in MODES.items():
                    sel = moving & (mode == code)
                    spent[m] += np.where(sel, h, 0.0)
                    began[m] = np.where(sel & (prev != code), clock, began[m])
                prev = np.where(moving, mode, prev)
                clock += h
                table_v = table_v + a * h
                wa = np.where(met, table_v, wa + w_acc * h)
                remaining = remaining - h
            assert np.all(remaining == 0.0)
        last_mode[idx] = prev
        v_after = wa - table_v
        done = (np.abs(v_after - v[idx]) <= 8 * EPS * scale[idx]) & (period > 1)
        v[idx] = v_after
        fin = idx[done]
        result["v0"][fin] = v_after[done]
        result["vbar"][fin] = disp[done] / dt[fin]
        result["speed"][fin] = speed[done] / dt[fin]
        result["periods"][fin] = period
        for m in MODES:
            result[m][fin] = spent[m][done]
            result[f"{m}_start"][fin] = began[m][done]
        active = idx[~done]
        if active.size == 0:
            break
    assert active.size == 0, f"{active.size} points did not converge in {max_periods} periods"
    return result


def simulated_case(ref):
    """Table 1 from the sign pattern of x' over the steady period and whether it sticks."""
    fwd, bwd, stick = ref["forward"] > 0, ref["backward"] > 0, ref["stick"] > 0
    case = np.full(fwd.shape, -1)
    case[~fwd & ~bwd & stick] = 5
    case[fwd & ~bwd & stick] = 1
    case[~fwd & bwd & stick] = 2
    case[fwd & bwd & stick] = 3
    case[fwd & bwd & ~stick] = 4
    case[np.isnan(ref["v0"])] = 0
    return case


@pytest.fixture(scope="module", params=sorted(SETTINGS))
def setting(request):
    """Analytic and simulated steady state on the (y2'', y3'') grid of one paper setting.

    Simulations start from x'(0) drawn uniformly in [-4u, 4u] (u the table velocity swing)
    so the reference goes through genuine transients."""
    dy, dt, axis = SETTINGS[request.param]
    y2, y3 = (a.ravel() for a in np.meshgrid(axis, axis, indexing="ij"))
    v_start = np.random.default_rng(5).uniform(-4.0, 4.0, y2.size) * np.nan_to_num(swing(dt, dy, y2, y3))
    ref = simulate_reference(dt, dy, y2, y3, v_start)
    return request.param, dt, dy, y2, y3, steady_state_grid(dt, dy, y2, y3), ref


def test_grid_shows_every_case_boundary_of_the_setting(setting):
    """Sect. 5.2 / Figs. 10, 11, 17: the chosen axes contain the cases of the paper's maps
    (Fig. 10: general stick-slip next to slip-slip; Fig. 11: cases 1 and 2), and case 0."""
    name, *_, ss, _ = setting
    assert set(np.unique(ss.case)) == EXPECTED_CASES[name]


def test_vbar_matches_brute_force_simulation(setting):
    """Eq. 10: the closed-form vbar equals the brute-force steady-state mean velocity.
    vbar is a difference of forward and backward areas, so the error is measured against
    the mean speed mean|x'|: |dv| <= 1e-10 mean|x'| (1e-10 relative to vbar where it is not
    small), and vbar = 0 exactly in pure stick."""
    *_, ss, ref = setting
    ok = ss.case > 0
    assert np.array_equal(ok, ~np.isnan(ref["vbar"]))
    err = np.abs(ss.vbar[ok] - ref["vbar"][ok])
    assert np.all(err <= 1e-10 * ref["speed"][ok])
    assert np.all(ss.vbar[ss.case == 5] == 0.0)


def test_v0_and_mode_intervals_match_brute_force_simulation(setting):
    """Sect. 5.1: x'(0) of the steady state, and when each of stick, forward and backward
    slip begins and how long it lasts per period, agree with the simulation to 1e-10 of the
    velocity swing / the period (a mode filling the whole period begins at 0)."""
    _, dt, dy, y2, y3, ss, ref = setting
    ok = ss.case > 0
    u = swing(dt, dy, y2, y3)[ok]
    assert np.all(np.abs(ss.v0[ok] - ref["v0"][ok]) <= 1e-10 * u)
    for m in MODES:
        assert np.all(np.abs(getattr(ss, f"{m}_time")[ok] - ref[m][ok]) <= 1e-10 * dt)
        occurs = ok & (ref[m] > 0)
        assert np.array_equal(occurs, ok & ~np.isnan(getattr(ss, f"{m}_start")))
        assert np.all(np.abs(getattr(ss, f"{m}_start")[occurs] - ref[f"{m}_start"][occurs]) <= 1e-10 * dt)


def test_a_priori_case_agrees_with_simulated_sign_pattern(setting):
    """Table 1 / Fig. 8: the decision tree's case equals the case read off the simulated
    steady period (signs of x' that occur, and whether the mass sticks), on every point of a
    150 x 150 grid, including case 0 (no profile)."""
    _, dt, dy, y2, y3, ss, ref = setting
    assert np.array_equal(classify_grid(dt, dy, y2, y3), simulated_case(ref))
    assert np.array_equal(ss.case, simulated_case(ref))


def test_v0_reproduces_itself_after_one_period(setting):
    """Sect. 5.1: started at x'(0) = v0 the mass is in steady state immediately (subscript
    's'); one period of the case-free exact map returns v0 to rounding, 4 eps (1 + y2'' +
    y3'') dt (slopes up to 1 + y'' times phase lengths), and advances x by vbar dt (to 1e-12
    of the mean speed times dt)."""
    _, dt, dy, y2, y3, ss, ref = setting
    ok = ss.case > 0
    v_end, dx = one_period_map(dt, dy, y2[ok], y3[ok], ss.v0[ok])
    assert np.all(np.abs(v_end - ss.v0[ok]) <= rounding(dt, y2, y3)[ok])
    assert np.all(np.abs(dx - ss.vbar[ok] * dt) <= 1e-12 * ref["speed"][ok] * dt)


def test_vbar_matches_exact_solver_on_coarse_grids():
    """Eq. 10 against the library's exact event-driven solver (sa.simulate, method="exact"):
    from rest, vbar = (x(4000 dt) - x(3000 dt)) / (1000 dt) and x'(4000 dt) = v0, on every
    8th grid line of each paper setting (19 x 19, all its cases).  Tolerance 1e-10
    relative to vbar plus 1e-13 of max|x'| (for vbar near 0), and 1e-12 of the swing for
    v0."""
    for name, (dy, dt, axis) in SETTINGS.items():
        y2, y3 = (a.ravel() for a in np.meshgrid(axis[::8], axis[::8], indexing="ij"))
        ss = steady_state_grid(dt, dy, y2, y3)
        assert set(np.unique(ss.case)) == EXPECTED_CASES[name]
        for i in np.flatnonzero(ss.case > 0):
            profile = ThreePhaseProfile(dt, dy, y2[i], y3[i])
            early, late = (simulate(Scene(profile, periods=n), method="exact") for n in (3000, 4000))
            vbar = (late.x_end - early.x_end) / (1000 * dt)
            peak = max(ss.v_max[i], -ss.v0[i])
            assert abs(vbar - ss.vbar[i]) <= 1e-10 * abs(ss.vbar[i]) + 1e-13 * peak
            assert abs(late.v_end - ss.v0[i]) <= 1e-12 * swing(dt, dy, y2[i], y3[i])


def test_case1_stick_time_is_eq21():
    """Eq. 21: in case 1 the mass sticks at t_{x'=0} = t2 + x'(t2) / (1 + y3'') with
    x'(t2) = (y2'' - 1)(t2 - t1) (eq. 16); exact to 4 ulp of dt."""
    profile = ThreePhaseProfile(1.38, 0.064, 2.0, 0.6)
    ss = steady_state(profile)
    assert ss.case == 1 and ss.v0 == 0.0 and ss.forward_start == profile.t1
    v2 = (profile.y2 - 1) * (profile.t2 - profile.t1)
    assert ss.v_max == pytest.approx(v2, rel=4 * EPS)
    assert ss.stick_start == pytest.approx(profile.t2 + v2 / (1 + profile.y3), abs=4 * EPS * profile.dt)


def test_objective_function_definition():
    """Eq. 11: f = 1 / (c vbar^2) with c = 10,000; f = inf in pure stick (vbar = 0); case 0
    has no steady state (all fields NaN)."""
    ss = steady_state((1.38, 0.064, 2.0, 0.6))
    assert ss.f == 1.0 / (OBJECTIVE_SCALE * ss.vbar**2) and OBJECTIVE_SCALE == 1e4
    stick = steady_state((1.38, 0.064, 0.8, 0.9))
    assert stick.case == 5 and stick.vbar == 0.0 and stick.f == np.inf
    none = steady_state((0.072, 0.021, 30.0, 30.0))
    assert none.case == 0 and np.isnan(none.vbar) and np.isnan(none.f) and np.isnan(none.v0)


def test_steady_state_of_profile_equals_grid_entry():
    """steady_state(profile) is the scalar view of steady_state_grid: same numbers, floats
    and an int case; tuple and mapping inputs give the same result."""
    profile = ThreePhaseProfile(1.0, 0.084, 1.1, 3.0)
    one = steady_state(profile)
    grid = steady_state_grid([1.0, 1.0], 0.084, [1.1, 2.0], 3.0)
    assert isinstance(one, SteadyState) and isinstance(one.case, int) and isinstance(one.vbar, float)
    assert one.case == int(grid.case[0]) == classify(profile) == 4
    assert one.vbar == grid.vbar[0] and one.v0 == grid.v0[0]
    for other in (steady_state((1.0, 0.084, 1.1, 3.0)), steady_state(profile.params())):
        np.testing.assert_equal(astuple(other), astuple(one))


def test_bad_input_raises_before_work():
    """Non-finite or non-positive parameters are a ValueError naming the quantity; an
    infeasible profile is case 0, not an error."""
    with pytest.raises(ValueError, match="y3 must be finite and > 0"):
        steady_state_grid(1.0, 0.084, [1.0, 2.0], [3.0, -1.0])
    with pytest.raises(ValueError, match="dt"):
        steady_state((np.nan, 0.084, 1.0, 1.0))
    with pytest.raises(ValueError, match="v0"):
        one_period_map(1.0, 0.084, 2.0, 2.0, np.inf)
    assert steady_state_grid(0.072, 0.021, 30.0, 30.0).case == 0


def test_large_grid_is_evaluated_correctly():
    """Throughput target (benchmarks/bench_steady_state.py times it): a 1000 x 1000 grid in
    one call.  Correctness only: the cases are those of the tree, every feasible v0 is a
    fixed point of the exact period map (to 4 eps (1 + y2'' + y3'') dt), mode times sum to dt, and a
    row evaluated alone gives identical numbers."""
    dy, dt = 0.084, 1.0
    axis = np.linspace(0.3, 6.0, 1000)
    y2, y3 = np.meshgrid(axis, axis, indexing="ij")
    ss = steady_state_grid(dt, dy, y2, y3)
    assert np.array_equal(ss.case, classify_grid(dt, dy, y2, y3))
    ok = ss.case > 0
    v_end, _ = one_period_map(dt, dy, y2[ok], y3[ok], ss.v0[ok])
    assert np.all(np.abs(v_end - ss.v0[ok]) <= rounding(dt, y2, y3)[ok])
    total = ss.stick_time + ss.forward_time + ss.backward_time
    assert np.all(np.abs(total[ok] - dt) <= 8 * EPS * dt)
    row = steady_state_grid(dt, dy, y2[417], y3[417])
    assert np.array_equal(row.vbar, ss.vbar[417], equal_nan=True)


def _fixed_y_sweep(name, vary):
    """Steady states on the setting's (y2'', y3'') grid for a sweep of dy or dt (axis 0)."""
    dy, dt, axis = SETTINGS[name]
    axis = np.geomspace(axis[0], axis[-1], 60)
    y2, y3 = np.meshgrid(axis, axis, indexing="ij")
    factors = np.linspace(0.3, 3.0, 80)[:, None, None]
    if vary == "dy":
        return steady_state_grid(dt, dy * factors, y2, y3)
    return steady_state_grid(dt * factors, dy, y2, y3)


@pytest.mark.parametrize("name", sorted(SETTINGS))
@pytest.mark.parametrize("vary", ["dy", "dt"])
def test_design_rules_larger_stroke_and_frequency(name, vary):
    """Sect. 5.2 design rules, for fixed y2'', y3'': a larger stroke dy and a higher frequency
    (smaller dt) raise vbar - strictly, between neighbouring sweep points of the same case, in
    case 1 and in case 3 with vbar > 0 (a general stick-slip with vbar < 0 drifts backward
    faster instead).  In the slip-slip case 4 the rule is reversed: there vbar decreases
    with dy and with 1/dt (vbar(dt, dy) = dt G(q) by scaling and G falls with q in case 4)."""
    ss = _fixed_y_sweep(name, vary)
    gain = np.diff(ss.vbar, axis=0) * (1 if vary == "dy" else -1)
    both = lambda c: (ss.case[1:] == c) & (ss.case[:-1] == c)  # noqa: E731
    forward = (ss.vbar[1:] > 0) & (ss.vbar[:-1] > 0)
    rule = both(1) | (both(3) & forward)
    assert rule.sum() > 1000
    assert np.all(gain[rule] > 0)
    if both(4).any():
        assert np.all(gain[both(4)] < 0)


def test_slip_slip_has_much_larger_objective_than_general_stick_slip():
    """Sect. 5.2, Fig. 10 (dy = 0.021, dt = 0.072): vbar drops dramatically (f rises) from
    general stick-slip into slip-slip.  On the Fig. 10 grid case 3 has f < 1.6e-3 (the
    paper's colour cap), while f in case 4 exceeds it over a large part and reaches > 100x
    the largest case-3 value; the best f lies in case 3 next to the case-4 boundary."""
    dy, dt, axis = SETTINGS["fig10"]
    y2, y3 = np.meshgrid(axis, axis, indexing="ij")
    ss = steady_state_grid(dt, dy, y2, y3)
    f3, f4 = ss.f[ss.case == 3], ss.f[ss.case == 4]
    assert f3.max() < 1.6e-3
    assert np.mean(f4 > 1.6e-3) > 0.3
    assert f4.max() > 100 * f3.max()
    best = np.unravel_index(np.nanargmin(ss.f), ss.f.shape)
    i, j = best
    assert ss.case[best] == 3 and 4 in ss.case[max(i - 1, 0):i + 2, max(j - 1, 0):j + 2]


def _feasible_random(n, rng, cases):
    """n random feasible (dt, dy, y2, y3) of the given cases, q = 8 dy (1/y2 + 1/y3) / dt^2
    in (0.01, 0.99) so t1 > 0.1 dt, y'' over 0.3 ... 1000."""
    m = 40 * n
    dt = 10.0 ** rng.uniform(-2, 1, m)
    y2 = 10.0 ** rng.uniform(-0.5, 3, m)
    y3 = 10.0 ** rng.uniform(-0.5, 3, m)
    q = rng.uniform(0.01, 0.99, m)
    dy = (q * dt) ** 2 / (8.0 * (1.0 / y2 + 1.0 / y3))
    case = classify_grid(dt, dy, y2, y3)
    keep = np.flatnonzero(np.isin(case, cases))
    keep = np.concatenate([keep[case[keep] == c][:n // len(cases)] for c in cases])
    return dt[keep], dy[keep], y2[keep], y3[keep]


def test_case4_multiplier_is_eq33_and_matches_finite_differences():
    """Eq. 33: in slip-slip lambda2 = c4 = (y2''-1)(y3''-1) / ((y2''+1)(y3''+1)), in (0, 1);
    the monodromy (eq. 32) equals left and right differences of the exact one-period map of
    (x, x') at t = 0 (exact up to rounding: tolerance 1e-7)."""
    rng = np.random.default_rng(33)
    dt, dy, y2, y3 = _feasible_random(2000, rng, [4])
    assert dt.size == 2000
    mono = monodromy_grid(dt, dy, y2, y3)
    c4 = (y2 - 1) * (y3 - 1) / ((y2 + 1) * (y3 + 1))
    assert np.allclose(mono[:, 1, 1], c4, rtol=1e-14, atol=0)
    assert np.all((c4 > 0) & (c4 < 1))
    for side in (1, -1):
        fd_v, fd_x = _differences(dt, dy, y2, y3, side)
        assert np.allclose(mono[:, 1, 1], fd_v, rtol=0, atol=1e-7)
        assert np.allclose(mono[:, 0, 1], fd_x, rtol=1e-7, atol=1e-7 * dt)
    assert np.all(mono[:, 0, 0] == 1.0) and np.all(mono[:, 1, 0] == 0.0)


def _differences(dt, dy, y2, y3, side):
    """One-sided derivatives (side = +1: right, -1: left) of the exact one-period map
    P(x'(0)) = (x'(dt), x(dt)) at the steady v0: d x'(dt) / d x'(0) and d x(dt) / d x'(0).

    On each side of v0 the map is linear in x'(0) for x'(dt) and quadratic for x(dt), so
    2 D(h) - D(2h) with D(h) = (P(v0 + h) - P(v0)) / h is exact up to rounding; h is 1e-6
    of the velocity swing."""
    ss = steady_state_grid(dt, dy, y2, y3)
    h = side * 1e-6 * swing(dt, dy, y2, y3)
    v_0, x_0 = one_period_map(dt, dy, y2, y3, ss.v0)
    v_1, x_1 = one_period_map(dt, dy, y2, y3, ss.v0 + h)
    v_2, x_2 = one_period_map(dt, dy, y2, y3, ss.v0 + 2 * h)
    return ((4 * (v_1 - v_0) - (v_2 - v_0)) / (2 * h),
            (4 * (x_1 - x_0) - (x_2 - x_0)) / (2 * h))


def test_sticking_cases_have_multipliers_one_and_zero():
    """Sect. 6.1, eqs. 26-31: in cases 1, 2, 3 and 5 a perturbation of x'(0) dies out when
    the mass sticks, so the monodromy is [[1, m12], [0, 0]] with Floquet multipliers 1 and 0.
    m12 = d x(dt) / d x'(0) is 0 in cases 1 and 5 (at rest in the dwell) and the time to
    rest in cases 2 and 3 (the paper's [[1, 0], [0, 0]] holds only where x'(0) = 0); both
    entries equal left and right differences of the exact period map (tolerance 1e-7)."""
    rng = np.random.default_rng(31)
    dt, dy, y2, y3 = _feasible_random(4000, rng, [1, 2, 3, 5])
    case = classify_grid(dt, dy, y2, y3)
    assert all(np.sum(case == c) > 100 for c in (1, 2, 3, 5))
    mono = monodromy_grid(dt, dy, y2, y3)
    ss = steady_state_grid(dt, dy, y2, y3)
    assert np.all(mono[:, 1, 1] == 0.0)
    assert np.all(mono[np.isin(case, (1, 5)), 0, 1] == 0.0)
    assert np.array_equal(mono[np.isin(case, (2, 3)), 0, 1], ss.stick_start[np.isin(case, (2, 3))])
    for side in (1, -1):
        fd_v, fd_x = _differences(dt, dy, y2, y3, side)
        assert np.allclose(fd_v, 0.0, rtol=0, atol=1e-7)
        assert np.allclose(mono[:, 0, 1], fd_x, rtol=1e-7, atol=1e-7 * dt)


def test_kinks_return_the_right_derivative():
    """Sect. 6.1 at t1 = 0 (q = 1, the case-0 boundary): the period map has a kink at the
    steady x'(0) = 0; the analytic monodromy is its right derivative (one-sided differences
    exact up to rounding, tolerance 1e-7): in case 1 m12 = the forward-slip time F, in case 5 with y2'' = 1
    m12 = t2, in case 4 the smooth eq. 32."""
    for y2, y3, case in ((2.0, 0.5, 1), (1.0, 0.5, 5), (2.0, 3.0, 4)):
        dy = 0.05
        dt = float(np.sqrt(8.0 * dy * (1.0 / y2 + 1.0 / y3)))  # q == 1 exactly
        profile = ThreePhaseProfile(dt, dy, y2, y3)
        assert profile.t1 == 0.0 and classify(profile) == case
        mono = monodromy_analytic(profile)
        fd_v, fd_x = _differences(dt, dy, y2, y3, side=1)
        assert mono[1, 1] == pytest.approx(fd_v, abs=1e-7)
        assert mono[0, 1] == pytest.approx(fd_x, abs=1e-7 * dt)
        if case == 5:
            assert mono[0, 1] == pytest.approx(profile.t2, rel=1e-12)


def test_floquet_multipliers_are_eigenvalues_inside_unit_circle():
    """Sect. 6.1: lambda1 = 1 (freedom in position), |lambda2| < 1 in every case: all steady
    states are locally stable; lambda2 = c4 in slip-slip and 0 otherwise; case 0 is NaN."""
    for params, lam2 in (((1.0, 0.084, 1.1, 3.0), (0.1 / 2.1) * (2.0 / 4.0)),
                         ((1.38, 0.064, 2.0, 0.6), 0.0), ((1.38, 0.064, 0.6, 2.0), 0.0),
                         ((1.0, 0.084, 3.0, 3.0), 0.0), ((1.38, 0.064, 0.8, 0.9), 0.0)):
        lam = floquet_multipliers_analytic(params)
        assert lam[0] == 1.0 and lam[1] == pytest.approx(lam2, rel=1e-14, abs=0)
        assert np.allclose(np.sort(np.linalg.eigvals(monodromy_analytic(params))), np.sort(lam))
    assert np.all(np.isnan(floquet_multipliers_analytic((0.072, 0.021, 30.0, 30.0))))


@pytest.mark.parametrize("y2, y3, case", [(1.0, 0.5, 5), (1.0, 2.0, 2), (2.0, 1.0, 1), (1.0, 1.0, 5)])
def test_tie_accelerations_stick(y2, y3, case):
    """Sect. 3.2 with the tie rule of the model: |y''| = mu_bar = 1 allows stick, so
    y2'' = 1 or y3'' = 1 falls on the sticking side (Fig. 11 setting).  Closed form,
    simulation and the exact period map agree (1e-12 of the swing) and v0 is a fixed point."""
    dy, dt = 0.064, 1.38
    ss = steady_state((dt, dy, y2, y3))
    ref = simulate_reference(np.array(dt), dy, y2, y3, np.array(0.7 * swing(dt, dy, y2, y3)))
    assert ss.case == case == simulated_case(ref)[0]
    u = swing(dt, dy, y2, y3)
    assert abs(ss.v0 - ref["v0"][0]) <= 1e-12 * u and abs(ss.vbar - ref["vbar"][0]) <= 1e-12 * u
    assert one_period_map(dt, dy, y2, y3, ss.v0)[0] == pytest.approx(ss.v0, abs=1e-12 * u)


def test_time_scaling_law():
    """Sect. 3.2 scaling: t -> l t, x -> l^2 x leaves the inclusion (6) unchanged, so the case
    is kept and vbar(l dt, l^2 dy) = l vbar(dt, dy) (to 1e-12 of max|x'| = max(v_max, -v0):
    x' is largest at t2 and smallest at t = 0)."""
    dy, dt, axis = SETTINGS["fig17"]
    y2, y3 = np.meshgrid(axis[::5], axis[::5], indexing="ij")
    base = steady_state_grid(dt, dy, y2, y3)
    ok = base.case > 0
    for lam in (0.01, 3.0, 250.0):
        scaled = steady_state_grid(lam * dt, lam**2 * dy, y2, y3)
        assert np.array_equal(scaled.case, base.case)
        peak = np.maximum(base.v_max, -base.v0)[ok]
        assert np.all(np.abs(scaled.vbar[ok] - lam * base.vbar[ok]) <= 1e-12 * lam * peak)
