"""Finite jerk: the three-phase profile with linear y'' ramps, its closed form,
the exact solver on it and the cross-checks against solve_ivp, Moreau and the paper's profile."""

from __future__ import annotations

import mpmath
import numpy as np
import pytest
from conftest import random_three_phase

import selfalign as sa
from selfalign.io.scene_files import scene_from_dict
from selfalign.model.errors import NonPhysicalProfile, SceneError
from selfalign.model.profiles import FiniteJerkProfile, finite_jerk_times
from selfalign.solvers.outcomes import EventKind

FIG18 = dict(dt=1.05, dy=0.084, y2=2.2, y3=0.9)       # case 1 (stick-slip, x' >= 0)
CASE3 = dict(dt=1.05, dy=0.084, y2=2.2, y3=1.8)       # case 3 (general stick-slip: reversals)


def random_profiles(count, seed):
    """Random feasible finite-jerk profiles: ramp or jerk given, ramps up to ~15 % of the period."""
    def ramped(rng, dt, dy, y2, y3):
        fraction = rng.uniform(1e-4, 0.15)
        kw = {"ramp": dt * fraction} if rng.random() < 0.5 else {"jerk": (y2 + y3) / (dt * fraction)}
        try:
            return FiniteJerkProfile(dt, dy, y2, y3, **kw)
        except ValueError:             # ramps too long for this profile, or infeasible
            return None
    return random_three_phase(count, seed, accelerations=(1.1, 8.0), strokes=(0.05, 0.9), complete=ramped)


def test_constraints_hold_for_random_profiles():
    """Closed form (finite_jerk_times): for random profiles y'' and y' average to zero (y' and y are
    periodic), y' = 0 at t_top and t_bottom, the stroke y(t_top) - y(t_bottom) is dy and min y = y(t_bottom)
    = 0, y'' is continuous (the ramps join the levels 0, -y2, +y3) and the largest |jerk| is the one
    asked for; all to 1e-12 relative (rounding is ~1e-15)."""
    for p in random_profiles(300, seed=1):
        scale_v, scale_y = p.velocity_swing, p.dy
        assert abs(p.piece_velocity[-1] - p.piece_velocity[0]) <= 1e-12 * scale_v
        assert abs(p.piece_position[-1] - p.piece_position[0]) <= 1e-12 * scale_y
        assert abs(p.velocity(p.t_top)) <= 1e-12 * scale_v and abs(p.velocity(p.t_bottom)) <= 1e-12 * scale_v
        assert abs(p.position(p.t_top) - p.position(p.t_bottom) - p.dy) <= 1e-12 * scale_y
        assert abs(p.position(p.t_bottom)) <= 1e-12 * scale_y
        grid = np.linspace(0.0, p.dt, 20001)
        assert p.position(grid).min() >= -1e-12 * scale_y
        assert p.position(grid).max() <= p.dy * (1 + 1e-12)
        ends = p.accels + p.jerks * np.diff(p.breaks)
        assert np.allclose(ends[:-1], p.accels[1:], rtol=0, atol=1e-12 * (p.y2 + p.y3))
        assert abs(ends[-1] - p.accels[0]) <= 1e-12 * (p.y2 + p.y3)
        assert sorted(set(np.round(p.accels[[1, 3, 5]] / (p.y2 + p.y3), 12))) == sorted(
            set(np.round(np.array([0.0, -p.y2, p.y3]) / (p.y2 + p.y3), 12)))
        if p.jerk is not None:
            assert abs(np.max(np.abs(p.jerks)) - p.jerk) <= 1e-12 * p.jerk


def test_constraints_hold_in_high_precision():
    """The derivation, not just its floating-point evaluation: the closed-form times, evaluated in
    50-digit arithmetic (mpmath) and the profile integrated piece by piece there, satisfy
    periodicity of y and y', the stroke and min y = 0 to 1e-40."""
    mpmath.mp.dps = 50
    dt, dy, y2, y3, tau = (mpmath.mpf(v) for v in ("1.05", "0.084", "2.2", "0.9", "0.05"))
    k = 1 / y2 + 1 / y3
    shift = (-y2 + (y2 + y3) - y3) * tau**2 / 24
    dip = (y2 + y3) * tau**2 / 24
    q = 2 * k * (mpmath.sqrt(2 * (dy + dip) / k) - shift / dt) / dt
    r = mpmath.sqrt(1 - q)
    u = dt * (1 - r) / k
    t1, t2 = dt * r, dt * r + u / y2
    yd_ini = (u**2 * k / 2 - shift) / dt
    h = tau / 2
    breaks = [0, h, t1 - h, t1 + h, t2 - h, t2 + h, dt - h, dt]
    accels = [y3 / 2, 0, 0, -y2, -y2, y3, y3]
    jerks = [-y3 / tau, 0, -y2 / tau, 0, (y2 + y3) / tau, 0, -y3 / tau]
    y, yd = yd_ini**2 / (2 * y3) - y3 * tau**2 / 48, yd_ini - y3 * tau / 8
    y0, yd0, values = y, yd, []
    for i in range(7):
        L = breaks[i + 1] - breaks[i]
        y, yd = y + yd * L + accels[i] * L**2 / 2 + jerks[i] * L**3 / 6, yd + accels[i] * L + jerks[i] * L**2 / 2
        values.append((y, yd))
    t_top, t_bottom = t1 + yd_ini / y2, dt - yd_ini / y3

    def y_at(t, i):                    # y on piece i (a plateau), from its start
        ys, yds = values[i - 1]
        s = t - breaks[i]
        return ys + yds * s + accels[i] * s**2 / 2
    assert abs(y - y0) < 1e-40 and abs(yd - yd0) < 1e-40
    assert abs(y_at(t_top, 3) - y_at(t_bottom, 5) - dy) < 1e-40
    assert abs(y_at(t_bottom, 5)) < 1e-40
    sol = finite_jerk_times(1.05, 0.084, 2.2, 0.9, 0.05, 0.05, 0.05)
    assert abs(float(sol.t1) - float(t1)) < 1e-15 and abs(float(sol.t2) - float(t2)) < 1e-15


def test_ramp_to_zero_gives_the_paper_profile():
    """tau -> 0: the ramp centres, y_ini' and y(t) tend to the paper's t1, t2, y'_ini and y(t), with an
    error C tau^2 (E and D are quadratic in tau): shrinking tau tenfold shrinks it ~100-fold, and at
    tau = 1e-7 dt every value agrees to 1e-12."""
    paper = sa.ThreePhaseProfile(**FIG18)
    grid = np.linspace(0.0, paper.dt, 4001)

    def error(tau):
        p = FiniteJerkProfile(**FIG18, ramp=tau * paper.dt)
        return max(abs(p.t1 - paper.t1), abs(p.t2 - paper.t2), abs(p.yd_ini - paper.yd_ini),
                   float(np.max(np.abs(p.position(grid) - paper.position(grid)))))
    e3, e4, e7 = error(1e-3), error(1e-4), error(1e-7)
    assert 80 < e3 / e4 < 120
    assert e7 < 1e-12


def test_bad_input_is_refused_with_one_line():
    """DESIGN: both or neither of ramp and jerk, a non-positive ramp, ramps longer than the phases
    and an unreachable stroke raise before any work, naming the problem."""
    with pytest.raises(ValueError, match="exactly one of ramp"):
        FiniteJerkProfile(**FIG18)
    with pytest.raises(ValueError, match="exactly one of ramp"):
        FiniteJerkProfile(**FIG18, ramp=0.01, jerk=100.0)
    with pytest.raises(ValueError, match="ramp must be > 0"):
        FiniteJerkProfile(**FIG18, ramp=0.0)
    with pytest.raises(ValueError, match="too long"):
        FiniteJerkProfile(1.05, 0.01, 2.2, 0.9, ramp=0.3)
    with pytest.raises(NonPhysicalProfile, match="q <= 1"):
        FiniteJerkProfile(**FIG18, ramp=0.5)


def test_scene_declares_ramp_and_jerk():
    """Scene schema: profile.ramp (>= 0) or profile.jerk (> 0) on a three_phase profile, not both;
    ramp 0 or absent loads the paper's ThreePhaseProfile (today's code path); the exact solver
    takes a finite-jerk profile on a stop zone, as Moreau and ivp do; the scene survives to_dict."""
    base = {"profile": {"kind": "three_phase", **FIG18}, "horizon": {"periods": 3}}
    assert type(scene_from_dict(base).profile) is sa.ThreePhaseProfile
    zero = scene_from_dict({**base, "profile": {**base["profile"], "ramp": 0}})
    assert type(zero.profile) is sa.ThreePhaseProfile
    ramped = scene_from_dict({**base, "profile": {**base["profile"], "ramp": 0.0105}})
    assert isinstance(ramped.profile, FiniteJerkProfile) and ramped.profile.ramps == (0.0105,) * 3
    assert scene_from_dict(ramped.to_dict()).profile.ramps == ramped.profile.ramps
    with pytest.raises(SceneError, match="ramp, jerk exclude each other"):
        scene_from_dict({**base, "profile": {**base["profile"], "ramp": 0.01, "jerk": 50.0}})
    with pytest.raises(SceneError, match="profile.ramp: must be >= 0"):
        scene_from_dict({**base, "profile": {**base["profile"], "ramp": -0.01}})
    zone = {**base, "profile": {**base["profile"], "jerk": 200.0},
            "surface": {"kind": "stop_zone", "x_mu": 0.5, "c_mu": 2.5}, "body": {"width": 0.05}}
    for method in ("exact", "moreau", "ivp"):
        assert scene_from_dict({**zone, "solver": {"method": method}}).method == method


def run(profile, method="exact", periods=10, surface=None, **options):
    scene = sa.Scene(profile, surface=surface or sa.Uniform(), periods=periods)
    return sa.simulate(scene, method=method, **options)


def test_exact_tends_to_the_paper_result_as_ramp_vanishes():
    """tau -> 0 on the simulation: the end position after 40 periods from rest converges to the
    paper profile's at first order in tau (the slip starts where the ramp crosses |y''| = 1, an
    O(tau) shift), and at tau = 1e-13 dt it agrees to 1e-12 (the accuracy asked of the finite-jerk
    solver, met at this tau)."""
    paper = run(sa.ThreePhaseProfile(**FIG18), periods=40).x_end

    def error(tau):
        return abs(run(FiniteJerkProfile(**FIG18, ramp=tau * FIG18["dt"]), periods=40).x_end - paper)
    e4, e5 = error(1e-4), error(1e-5)
    assert 8 < e4 / e5 < 12
    assert error(1e-13) <= 1e-12


@pytest.mark.parametrize("params", [FIG18, CASE3], ids=["case1", "case3"])
def test_exact_agrees_with_ivp(params):
    """Cross-check: with y'' linear in every piece the arcs are cubics, which solve_ivp (DOP853, order 8)
    integrates exactly between the breaks, so the two differ only by event location: at rtol = 1e-10
    the end positions after 10 periods agree to 1e-10 (measured ~1e-15), with ramp 5 % and 1 % of dt."""
    for tau in (0.05, 0.01):
        p = FiniteJerkProfile(**params, ramp=tau * params["dt"])
        exact = run(p, periods=10).x_end
        ivp = run(p, "ivp", periods=10, rtol=1e-10, atol=1e-12).x_end
        assert abs(exact - ivp) <= 1e-10


def test_a_slip_from_rest_shorter_than_the_grid_spacing_ends():
    """A start at rest on the ramp from +y3'' to 0 where y'' is just above 1 (y3'' = 2.0333, ramp
    1 % of dt: the backward slip lasts ~2e-4, under the grid's spacing dt / 1600) is a slip that
    ends, found between the grid point where x' is back through 0 and a point of the slip's sign
    before it: the exact end after 20 periods agrees with solve_ivp to 1e-10 (before, the slip went
    on with x' of the wrong sign: x_end = 383 against 0.178)."""
    p = FiniteJerkProfile(1.38, 0.064, 2.0, 0.1 + 10 * 2.9 / 15, ramp=0.01 * 1.38)
    exact = run(p, periods=20).x_end
    ivp = run(p, "ivp", periods=20, rtol=1e-10, atol=1e-12).x_end
    assert abs(exact - ivp) <= 1e-10


def test_moreau_converges_to_exact():
    """Cross-check: Moreau converges to the exact solver on the ramped profile at about first order:
    the least-squares slope of log error against log h over 1e3 ... 1e6 steps per period lies in
    [0.6, 1.4] (case 3, with reversals; single points scatter, docs/explanation/solvers.md; measured
    0.7 over 10 periods, 2e-6 at 1e6 steps)."""
    p = FiniteJerkProfile(**CASE3, ramp=0.05 * CASE3["dt"])
    exact = run(p, periods=10).x_end
    steps = np.array([1e3, 1e4, 1e5, 1e6])
    errs = [abs(run(p, "moreau", periods=10, steps_per_period=int(n)).x_end - exact) for n in steps]
    slope = np.polyfit(np.log(steps), np.log(errs), 1)[0]
    assert 0.6 <= -slope <= 1.4


def test_event_times_are_located_to_the_stated_accuracy():
    """Stated accuracy of the smooth stepper (Brent to 2 eps dt + 4 eps t): the slip of a stuck mass
    starts where the ramp's linear y'' crosses -1, t = (t1 - tau/2) + tau/y2 in closed form, and the
    stick time is the root of the cubic-arc velocity, found here with mpmath in 40 digits: the solver's
    times agree to 1e-14."""
    tau = 0.05 * FIG18["dt"]
    p = FiniteJerkProfile(**FIG18, ramp=tau)
    traj = sa.simulate(sa.Scene(p, surface=sa.Uniform(), periods=1, record=sa.Record(events=True)))
    slips = traj.events[traj.events["kind"] == int(EventKind.SLIP)]
    sticks = traj.events[traj.events["kind"] == int(EventKind.STICK)]
    t_slip = (p.t1 - tau / 2) + tau / p.y2
    assert slips.size == 1 and abs(slips["tau"][0] - t_slip) <= 1e-14
    mpmath.mp.dps = 40
    i = int(np.searchsorted(p.breaks, sticks["tau"][0]) - 1)
    b, a, j, v = (mpmath.mpf(float(c)) for c in (p.breaks[i], p.accels[i], p.jerks[i], p.piece_velocity[i]))
    ts, yds = mpmath.mpf(float(t_slip)), None
    for k in range(p.breaks.size - 1):        # y' at the slip time (the mass slips forward from there)
        if p.breaks[k] <= t_slip < p.breaks[k + 1]:
            s = ts - mpmath.mpf(float(p.breaks[k]))
            yds = mpmath.mpf(float(p.piece_velocity[k])) + mpmath.mpf(float(p.accels[k])) * s \
                + mpmath.mpf(float(p.jerks[k])) * s**2 / 2

    def rel_velocity(t):                      # x' = -(t - t_slip) - (y'(t) - y'(t_slip)), forward slip
        s = t - b
        return -(t - ts) - (v + a * s + j * s**2 / 2 - yds)
    root = mpmath.findroot(rel_velocity, mpmath.mpf(float(sticks["tau"][0])))
    assert sticks.size == 1 and abs(sticks["tau"][0] - float(root)) <= 1e-14


def test_simulated_case_and_vbar_reproduce_table1_at_zero_ramp():
    """analysis.finite_jerk.steady_case read off a simulated steady period: at ramp 0 it gives the case
    of Table 1 (sa.classify, closed form) and the closed-form vbar (to 1e-9 relative) on a 6 x 6 grid of
    the Fig. 11 plane (cases 0, 1, 2, 3, 5) and on the case 4 setting of Fig. 9; at ramp 1e-9 dt the grid
    is the same to 1e-7."""
    from selfalign.analysis.finite_jerk import steady_case, steady_grid

    axis = np.linspace(0.1, 3.0, 6)
    grid = steady_grid(1.38, 0.064, axis, axis, [0.0, 1e-9], progress="quiet")
    for i, y2 in enumerate(axis):
        for j, y3 in enumerate(axis):
            case = sa.classify((1.38, 0.064, y2, y3))
            assert grid.case[0, i, j] == case
            if case == 0:
                assert np.isnan(grid.vbar[0, i, j])
                continue
            profile = sa.ThreePhaseProfile(1.38, 0.064, y2, y3)
            assert abs(grid.vbar[0, i, j] - sa.steady_state(profile).vbar) <= 1e-9 * max(grid.vbar[0, i, j], 1e-3)
    assert set(np.unique(grid.case[0]).tolist()) >= {1, 2, 3, 5}
    slip_slip = sa.ThreePhaseProfile(1.0, 0.084, 1.4, 1.3)           # case 4 of Fig. 9
    assert steady_case(slip_slip)[1] == sa.classify(slip_slip) == 4
    assert np.array_equal(grid.case[1], grid.case[0])
    assert np.allclose(grid.vbar[1], grid.vbar[0], rtol=0, atol=1e-7, equal_nan=True)


@pytest.mark.parametrize("y2, y3", [(2.3, 1.3), (1.8, 1.1)])
def test_stopping_at_zero_ramp_is_the_paper_positioning(y2, y3):
    """analysis.finite_jerk.stopping (exact solver) against sa.positioning (exact, its own entry
    placement) on the paper's profile: the same fraction of entries accumulates and Delta x_d
    agrees to 1e-12 (one accumulating setting of Fig. 17, one that stops at rest)."""
    from selfalign.analysis.finite_jerk import stopping

    profile = sa.ThreePhaseProfile(1.0, 0.084, y2, y3)
    exact = sa.positioning(profile, w=0.05, c_mu=2.5, n_entries=16)
    ours = stopping(profile, w=0.05, c_mu=2.5, n_entries=16)
    assert ours.frac_accumulate == exact.frac_accumulate
    assert abs(ours.dx_d - exact.dx_d) <= 1e-12


def test_ramps_create_accumulation_where_the_paper_has_none_and_ivp_agrees():
    """The finding of docs/explanation/model.md at one cell of the Fig. 17 plane (y2'' = 1.8, y3'' = 1.5):
    with the paper's profile no entry accumulates (exact positioning), with ramps of 5 % of dt 3 of 16
    do, and solve_ivp, run entry by entry, gives the same outcomes as the exact solver."""
    from selfalign.analysis.finite_jerk import jerk_profile, stopping

    assert sa.positioning(sa.ThreePhaseProfile(1.0, 0.084, 1.8, 1.5), w=0.05, c_mu=2.5,
                          n_entries=16).frac_accumulate == 0.0
    ramped = jerk_profile(1.0, 0.084, 1.8, 1.5, 0.05)
    exact = stopping(ramped, w=0.05, c_mu=2.5)
    ivp = stopping(ramped, w=0.05, c_mu=2.5, method="ivp")
    assert exact.frac_accumulate == ivp.frac_accumulate == 3 / 16
    assert exact.frac_rest == ivp.frac_rest


def test_stage_result_reads_back_into_the_grids_and_the_figure(tmp_path):
    """The workflow stage's content (stages.finite_jerk), written with write_h5 and read back, gives
    the grids steady_grid and stopping_grid compute directly (bit for bit, every steady plane by name),
    and draw("finite_jerk") makes two rows per steady plane, draw("finite_jerk_stopping") two stopping
    rows, of one panel per ramp fraction, both at print size (print_check empty)."""
    from selfalign.analysis.finite_jerk import steady_grid, stopping_grid
    from selfalign.io.hdf5 import read_h5, write_h5
    from selfalign.plots.style import print_check
    from selfalign.stages.figures import draw
    from selfalign.stages.finite_jerk import finite_jerk_results, grids_from_result

    def axis(lo, hi):
        return {"from": lo, "to": hi, "count": 2, "scale": "linear"}

    fractions = [0.0, 0.05]
    steady = {"fig10": {"dt": 0.072, "dy": 0.021, "y2": axis(200.0, 1500.0), "y3": axis(50.0, 300.0)},
              "fig11": {"dt": 1.38, "dy": 0.064, "y2": axis(1.0, 3.0), "y3": axis(0.5, 3.0)}}
    stop = {"dt": 1.0, "dy": 0.084, "y2": axis(1.8, 2.3), "y3": axis(1.3, 1.5), "n_entries": 2,
            "max_periods": 300}
    zone = {"w": 0.05, "c_mu": 2.5}
    path = write_h5(tmp_path / "finite_jerk.h5", *finite_jerk_results(fractions, steady, stop, zone, progress="quiet"))
    result = read_h5(path)
    planes, stopping = grids_from_result(result)
    assert list(planes) == ["fig10", "fig11"]
    for name, plane in steady.items():
        direct = steady_grid(plane["dt"], plane["dy"], np.linspace(plane["y2"]["from"], plane["y2"]["to"], 2),
                             np.linspace(plane["y3"]["from"], plane["y3"]["to"], 2), fractions, progress="quiet")
        for field in ("ramp_fractions", "y2", "y3", "vbar", "case"):
            assert np.array_equal(getattr(planes[name], field), getattr(direct, field), equal_nan=True), field
    direct = stopping_grid(1.0, 0.084, [1.8, 2.3], [1.3, 1.5], fractions, w=0.05, c_mu=2.5, n_entries=2,
                           max_periods=300, progress="quiet")
    for field in ("y2", "y3", "frac_accumulate", "frac_rest", "dx_d"):
        assert np.array_equal(getattr(stopping, field), getattr(direct, field), equal_nan=True), field
    for name, rows in (("finite_jerk", 2 * len(steady)), ("finite_jerk_stopping", 2)):
        fig = draw(name, [result])
        assert print_check(fig) == []
        panels = [ax for ax in fig.axes if ax.get_label() != "<colorbar>" and ax.axison]
        assert len(panels) == rows * len(fractions)
