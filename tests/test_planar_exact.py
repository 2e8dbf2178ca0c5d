"""The exact planar solver on piecewise-constant table accelerations (selfalign.model.planar_slip,
selfalign.solvers.engine.planar, selfalign.solvers.planar_exact): the closed-form slip against an independent
integration, the reduction to the paper's 1-D model, isotropy, the hard cases and the steady drift
(docs/explanation/planar-model.md, "Closed-form slip")."""

import math

import numpy as np
import pytest
from scipy.integrate import solve_ivp

import selfalign as sa
from selfalign.model import planar_slip as S
from selfalign.solvers import planar_exact
from selfalign.solvers.outcomes import EventKind, Reason

OPTIONS = {"max_events": 1_000_000}
FIG18 = sa.ThreePhaseProfile(dt=1.05, dy=0.084, y2=2.2, y3=0.9)


def referee(v0, acc, mu, duration):
    """x'' = -A - mu v / |v| integrated by DOP853 at rtol 1e-13: (dx, dy, vx, vy) after ``duration``."""
    def rhs(_, z):
        speed = math.hypot(z[2], z[3])
        return [z[2], z[3], -acc[0] - mu * z[2] / speed, -acc[1] - mu * z[3] / speed]
    sol = solve_ivp(rhs, (0.0, duration), [0.0, 0.0, *v0], method="DOP853", rtol=1e-13, atol=1e-15)
    assert sol.success
    return sol.y[:, -1]


def _slip(k, seed):
    """A random slip with friction ratio k = mu / |A|: (v0, A, mu)."""
    rng = np.random.default_rng(seed)
    angle, g = rng.uniform(0.0, 2.0 * np.pi), rng.uniform(0.5, 3.0)
    return rng.normal(size=2), -g * np.array([np.cos(angle), np.sin(angle)]), k * g


@pytest.mark.parametrize("k", [1e-6, 0.3, 0.5, 1.0 - 1e-6, 1.0, 1.0 + 1e-6, 1.7, 5.0, 1e6])
def test_closed_form_slip_matches_a_high_precision_integration(k):
    """The closed form (planar-model.md, "Closed-form slip") solves v' = -A - mu v/|v|: for random A, mu and v0,
    its displacement and velocity agree with DOP853 at rtol 1e-13 to 1e-12, for k < 1, at k = 1 and the special
    exponent k = 1/2, near 1 on both sides, for k > 1 up to 0.9 of the stop time, and at the extremes k = 1e-6
    (friction negligible) and k = 1e6 (the drive negligible)."""
    for seed in range(4):
        v0, acc, mu = _slip(k, seed)
        g, _, _, _, _, a, b, _ = S.slip_frame(*v0, *acc)
        duration = min(0.9 * S.stop_time(g, mu, a, b), 3.0)
        got = np.array(S.slip_step(*v0, *acc, mu, duration))
        assert np.max(np.abs(got - referee(v0, acc, mu, duration))) <= 1e-12 * (1.0 + np.max(np.abs(got)))


def test_the_stop_is_explicit_and_is_the_limit_of_the_slip():
    """For mu > |A| the slip stops at T = a/(mu - G) + b/(mu + G) (planar-model.md): the integration to 0.999 T
    is within 1e-3 T of the stop displacement and slows to under 1e-2 of the start speed, and slip_step at T
    and beyond returns the stop with v = 0."""
    v0, acc, mu = _slip(2.0, 7)
    g, _, _, _, _, a, b, _ = S.slip_frame(*v0, *acc)
    stop = S.stop_time(g, mu, a, b)
    end = S.slip_step(*v0, *acc, mu, stop)
    assert end[2:] == (0.0, 0.0) and S.slip_step(*v0, *acc, mu, 2.0 * stop) == end
    near = referee(v0, acc, mu, 0.999 * stop)
    assert np.hypot(near[2], near[3]) < 1e-2 * np.hypot(*v0)
    assert np.max(np.abs(near[:2] - np.array(end[:2]))) < 1e-3 * stop * np.hypot(*v0)


def test_slip_parameter_inverts_the_time_to_rounding_at_the_numerical_edges():
    """t(y) is inverted to ~1 ulp (planar-model.md, "Stop, and the time to a given time"): for tiny durations,
    k near 1, large k, a velocity nearly against the drive (u0 huge) and long slips, t(slip_parameter(tau)) is
    tau to 8 ulp, and the state is finite."""
    cases = [(1e-12, 0.7), (0.3, 1.0 + 1e-12), (0.3, 1.0 - 1e-12), (1e-7, 1e6), (0.4, 0.2), (50.0, 0.5)]
    for duration, k in cases:
        for v0 in ([1.0, 0.2], [-1.0, 1e-9], [1e-3, -2.0]):
            acc = np.array([-1.5, 0.5])
            mu = k * np.hypot(*acc)
            g, _, _, _, _, a, b, h = S.slip_frame(*v0, *acc)
            if duration >= S.stop_time(g, mu, a, b):
                continue
            y = S.slip_parameter(g, mu, a, b, duration)
            assert S.slip_time(g, mu, a, b, y) == pytest.approx(duration, rel=8 * 2.0**-52, abs=0)
            assert all(math.isfinite(value) for value in S.slip_state(g, mu, a, b, h, y))


def test_nearly_collinear_slip_against_the_drive_turns_like_the_1d_reversal():
    """A slip against the drive with a transverse velocity of 1e-12 (u0 ~ 1e12) decelerates, turns at nearly zero
    speed and accelerates along g: within 1e-11 of the 1-D reversal (stop at s0/(G + mu), then slip from rest)."""
    acc, mu = np.array([-3.0, 0.0]), 1.0
    got = S.slip_step(-1.0, 1e-12, *acc, mu, 0.75)
    # 1-D: back to rest at 0.25 (displacement -1/8), then 0.5 at acceleration 2 forward (+1/4), v = 1.
    assert got == pytest.approx((0.125, 0.0, 1.0, 0.0), abs=1e-11)


def _planar(profile, **scene):
    return sa.Scene(sa.PlanarProfile(x=profile), **scene)


PROFILES = [FIG18, sa.PolynomialProfile(dt=0.05, dy=0.02),
            sa.PiecewiseConstantProfile([0.0, 0.25, 0.5, 0.75, 1.0], [1.6, -3.0, 2.5, -1.1], 0.0, 0.1)]


@pytest.mark.parametrize("friction", [sa.FrictionLaw(), sa.FrictionLaw("static_kinetic", 1.2)])
@pytest.mark.parametrize("profile", PROFILES, ids=["three_phase", "polynomial", "piecewise"])
def test_a_table_moving_along_one_axis_is_the_1d_exact_solver(profile, friction):
    """1-D reduction (planar-model.md, "Collinear slips"): PlanarProfile(x=p) with the start on the axis gives the
    1-D exact solver's end state, end time and outcome to 1e-12, with y and vy exactly 0, for Coulomb and
    static/kinetic friction, from rest and moving, from a start phase."""
    for x0, v0, phase in ((0.3, 0.0, 0.0), (-0.2, -0.7, 0.4), (0.0, 0.9, 0.85)):
        one = sa.simulate(sa.Scene(profile, friction=friction, x0=x0, v0=v0, phase=phase, periods=7))
        two = sa.simulate(_planar(profile, friction=friction, x0=(x0, 0.0), v0=(v0, 0.0), phase=phase, periods=7))
        assert two.x_end[1] == 0.0 and two.v_end[1] == 0.0
        assert two.x_end[0] == pytest.approx(one.x_end, abs=1e-12)
        assert two.v_end[0] == pytest.approx(one.v_end, abs=1e-12)
        assert two.period_end * profile.dt + two.tau_end == one.period_end * profile.dt + one.tau_end
        assert two.reason is one.reason


def test_rest_for_good_ends_the_run_where_the_1d_solver_does():
    """REST (planar-model.md, "Events and tie rules"): under static/kinetic friction with r mu >= max|Y''| the
    part stops for good at its first stick, at the 1-D solver's time and place (1e-12)."""
    law = sa.FrictionLaw("static_kinetic", 2.5)
    one = sa.simulate(sa.Scene(FIG18, friction=law, v0=0.8, until="rest", max_periods=5))
    two = sa.simulate(_planar(FIG18, friction=law, x0=(0.0, 0.0), v0=(0.8, 0.0), until="rest", max_periods=5))
    assert one.reason is Reason.REST and two.reason is Reason.REST
    assert two.x_end[0] == pytest.approx(one.x_end, abs=1e-12) and two.x_end[1] == 0.0
    assert two.period_end * FIG18.dt + two.tau_end == pytest.approx(one.period_end * FIG18.dt + one.tau_end, abs=1e-12)


def _diagonal(offset=0.25, angle=0.0):
    second = sa.ThreePhaseProfile(dt=1.05, dy=0.05, y2=1.8, y3=1.1)
    return sa.PlanarProfile(x=FIG18, y=second, offset=offset, angle=angle)


def test_rotating_the_table_motion_rotates_the_trajectory():
    """Isotropy (planar-model.md, "The model"): turning the table motion and the start state by theta turns x(t)
    and v(t) by theta, at the end and at every sample, to 1e-12."""
    record = sa.Record(series=("x", "v", "mode"), samples_per_period=16)
    base = sa.Scene(_diagonal(), x0=(0.1, -0.2), v0=(0.3, 0.1), periods=12, record=record)
    ref = planar_exact.run(base, OPTIONS)
    for theta in (0.7, 2.0, -2.9):
        rot = sa.model.planar.rotation(theta)
        turned = base.replace(profile=base.profile.rotated(theta), x0=tuple(rot @ base.x0), v0=tuple(rot @ base.v0))
        got = planar_exact.run(turned, OPTIONS)
        assert got.reason is ref.reason and got.sticks == ref.sticks
        assert np.max(np.abs(got.x_end - rot @ ref.x_end)) <= 1e-12
        assert np.max(np.abs(got.v_end - rot @ ref.v_end)) <= 1e-12
        assert np.max(np.abs(got.samples["x"] - ref.samples["x"] @ rot.T)) <= 1e-12
        assert np.max(np.abs(got.samples["v"] - ref.samples["v"] @ rot.T)) <= 1e-12
        assert np.array_equal(got.samples["mode"], ref.samples["mode"])


def _square(ax, ay, ratio=1.0, **scene):
    """A table whose Y'' is (ax, ay) for half the period and its opposite for the other half."""
    x = sa.PiecewiseConstantProfile([0.0, 0.5, 1.0], [ax, -ax], 0.0, -0.5 * ax)
    y = sa.PiecewiseConstantProfile([0.0, 0.5, 1.0], [ay, -ay], 0.0, -0.5 * ay)
    law = sa.FrictionLaw("static_kinetic", ratio) if ratio != 1.0 else sa.FrictionLaw()
    return sa.Scene(sa.PlanarProfile(x=x, y=y), friction=law, **scene)


def test_a_slip_against_the_drive_reverses_through_zero_speed():
    """A 1-D reversal embedded in 2-D (planar-model.md, "Collinear slips"): v0 = (-1, 0) against Y'' = (-3, 0)
    decelerates at G + mu = 4, reaches zero speed at t = 1/4 (a REVERSAL, since G > mu) and slips on along +x;
    with a transverse velocity of 1e-12 the curved closed form turns at nearly zero speed and ends within 1e-11
    of it."""
    scene = _square(-3.0, 0.0, x0=(0.0, 0.0), v0=(-1.0, 0.0), periods=1, record=sa.Record(events=True))
    exact = planar_exact.run(scene, OPTIONS)
    reversals = exact.log[exact.log["kind"] == EventKind.REVERSAL]
    assert reversals["t"][0] == 0.25 and np.all(reversals["v"] == 0.0)
    assert exact.x_end[1] == 0.0 and np.isfinite(exact.x_end).all()
    near = planar_exact.run(scene.replace(v0=(-1.0, 1e-12)), OPTIONS)
    assert np.max(np.abs(near.x_end - exact.x_end)) <= 1e-11
    assert np.max(np.abs(near.v_end - exact.v_end)) <= 1e-11


def test_grazing_the_stick_disc_sticks_and_just_beyond_it_slips():
    """Tie rule 1 (planar-model.md, "Events and tie rules"): with |Y''| = r mu exactly ((0.75, 1), r = 1.25) a part
    at rest sticks through every switch and stays exactly where it is (to rest: REST at once); with 2^-40 more it
    slips from the start (G > r mu >= mu: it never sticks again)."""
    on = planar_exact.run(_square(0.75, 1.0, ratio=1.25, x0=(0.5, 0.5), periods=20), OPTIONS)
    assert on.x_end.tolist() == [0.5, 0.5] and on.v_end.tolist() == [0.0, 0.0] and on.slips == 0
    assert planar_exact.run(_square(0.75, 1.0, ratio=1.25, until="rest"), OPTIONS).reason is Reason.REST
    beyond = planar_exact.run(_square(0.75, 1.0 + 2.0**-40, ratio=1.25, periods=3), OPTIONS)
    assert beyond.sticks == 0 and np.all(beyond.x_end != 0.0) and np.all(beyond.v_end != 0.0)


def test_a_long_run_ends_finite_without_hanging():
    """1e5 periods of a planar motion with stick-slip every period end with PERIODS, a finite state and the
    event count of the steady state (no NaN, no stall)."""
    result = planar_exact.run(sa.Scene(_diagonal(), x0=(0.0, 0.0), periods=100_000), OPTIONS)
    assert result.reason is Reason.PERIODS and np.isfinite(result.x_end).all() and np.isfinite(result.v_end).all()
    assert result.sticks >= 100_000 and result.t_end == pytest.approx(100_000 * 1.05, rel=1e-15)


def test_the_event_budget_an_overflow_and_bad_scenes_end_clearly():
    """MAX_EVENTS ends a run with its message; an overflow ends it with NONFINITE at the last finite period start
    (not a NaN); a 1-D scene, strips and smooth profiles are refused with a ValueError naming what the closed-form
    planar solver needs."""
    short = planar_exact.run(sa.Scene(_diagonal(), x0=(0.0, 0.0), periods=10), {"max_events": 5})
    assert short.reason is Reason.MAX_EVENTS and "max_events = 5" in short.message
    record = sa.Record(series=("x",), samples_per_period=4)
    huge = planar_exact.run(sa.Scene(_diagonal(), x0=(0.0, 0.0), v0=(1e308, 1e308), periods=3, record=record),
                            OPTIONS)
    assert huge.reason is Reason.NONFINITE and huge.t_end == 1.05 and np.isfinite(huge.x_end).all()
    assert len(huge.samples) == 5 and np.isfinite(huge.samples["x"]).all()
    with pytest.raises(ValueError, match="planar scene"):
        planar_exact.run(sa.Scene(FIG18, periods=1), OPTIONS)
    with pytest.raises(ValueError, match="surface must be uniform"):
        planar_exact.run(sa.Scene(_diagonal(), sa.Strip((1.0, 0.0), 0.5, 0.05, 2.5), x0=(0.0, 0.0), periods=1),
                         OPTIONS)
    fourier = sa.PlanarProfile(x=sa.FourierProfile(1.0, [0.0, 0.01], [0.0, 0.0]))
    with pytest.raises(ValueError, match="piecewise constant"):
        planar_exact.run(sa.Scene(fourier, x0=(0.0, 0.0), periods=1), OPTIONS)


@pytest.mark.parametrize("offset", [0.25, 0.6])
def test_the_steady_drift_of_two_phase_shifted_profiles_converges(offset):
    """Steady drift (the paper's objective, Sect. 4.3, in the plane): for two three-phase profiles a phase offset
    apart, the displacement per period (the mean velocity times dt) converges from period to period, to 1e-12 after
    200 periods, and is finite and non-zero."""
    scene = sa.Scene(_diagonal(offset), x0=(0.0, 0.0), periods=220,
                     record=sa.Record(series=("x",), samples_per_period=2))
    x = planar_exact.run(scene, OPTIONS).samples["x"][::2]
    per_period = np.diff(x, axis=0)
    assert np.isfinite(per_period).all() and np.linalg.norm(per_period[-1]) > 1e-3
    assert np.max(np.abs(per_period[-1] - per_period[-2])) <= 1e-12
    assert np.max(np.abs(per_period[-1] - per_period[-10])) <= 1e-12


def test_moreau_time_stepping_converges_to_the_exact_planar_solution():
    """An independent check of the stepper's events in the plane (slip starts along -Y'', stops, curved slips):
    Moreau's scheme (first order in h, planar-model.md, "Moreau time-stepping with the friction disc") approaches
    the exact end state of 5 periods of a diagonal motion, its error falling more than 4-fold from 2000 to 16000
    steps per period, to below 1e-4."""
    scene = sa.Scene(_diagonal(), x0=(0.0, 0.0), v0=(0.2, -0.1), periods=5)
    exact = planar_exact.run(scene, OPTIONS)
    errors = []
    for steps in (2000, 16000):
        moreau = sa.simulate(scene, method="moreau", steps_per_period=steps)
        errors.append(max(np.max(np.abs(moreau.x_end - exact.x_end)), np.max(np.abs(moreau.v_end - exact.v_end))))
    assert errors[1] < 1e-4 and errors[1] < errors[0] / 4.0


def test_a_line_at_an_angle_is_the_1d_model_on_that_line_under_static_friction():
    """The collinear tie (planar-model.md, "Collinear slips": a velocity within 16 ulp of the line of Y'' slips on
    that line): a slip against the drive with mu < |Y''| <= r mu stops and sticks in 1-D, and does the same on a line
    turned by any angle: the end state is the turned 1-D one to 1e-12, and the part sticks."""
    law = sa.FrictionLaw("static_kinetic", 1.2)
    line = sa.PiecewiseConstantProfile([0.0, 0.5, 1.0], [-1.1, 1.1], 0.0, 0.55)
    base = planar_exact.run(_planar(line, friction=law, x0=(0.0, 0.0), v0=(-1.0, 0.0), periods=2), OPTIONS)
    assert base.sticks >= 1 and base.v_end.tolist() == [0.0, 0.0]
    for theta in (0.7, 2.0, -2.9):
        rot = sa.model.planar.rotation(theta)
        turned = sa.Scene(sa.PlanarProfile(x=line, angle=theta), friction=law, x0=(0.0, 0.0),
                          v0=tuple(rot @ [-1.0, 0.0]), periods=2)
        got = planar_exact.run(turned, OPTIONS)
        assert got.sticks == base.sticks and got.v_end.tolist() == [0.0, 0.0]
        assert np.max(np.abs(got.x_end - rot @ base.x_end)) <= 1e-12


def test_a_tiny_start_speed_followed_by_a_long_acceleration_stays_finite():
    """The terms of the closed form are integrals of decaying weights taken from both ends (planar-model.md, "The
    form that is computed"): a start speed of 1e-200 across the drive, accelerated for a unit time (y ~ 650, where
    a^2 underflows and e^{2(1-k)y} overflows), gives the slip from rest along -A to 1e-12."""
    acc, mu = np.array([-1.5, 0.8]), 0.5
    g = np.hypot(*acc)
    along = -acc / g
    rest = (0.5 * (g - mu) * along).tolist() + ((g - mu) * along).tolist()
    for angle in (0.3, 2.0, -1.2):
        v0 = 1e-200 * np.array([np.cos(angle), np.sin(angle)])
        assert S.slip_shape(*v0, *acc, mu) == S.CURVED
        assert S.slip_step(*v0, *acc, mu, 1.0) == pytest.approx(rest, abs=1e-12)
