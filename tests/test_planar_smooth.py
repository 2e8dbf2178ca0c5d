"""The general exact planar stepper (:mod:`selfalign.solvers.planar_smooth`; docs/explanation/planar-model.md,
"General stepper: accurate local solution"): an explicit Runge-Kutta method of order 8 with events located on
the step's own local solution, on strips, finite-jerk and Fourier profiles."""

import math

import mpmath as mp
import numpy as np
import pytest

import selfalign as sa
from selfalign.solvers import planar_smooth
from selfalign.solvers.outcomes import EventKind, Reason

OPTIONS = {"max_events": 100_000}
THREE = sa.ThreePhaseProfile(dt=1.05, dy=0.084, y2=2.2, y3=0.9)
JERK = sa.FiniteJerkProfile(dt=1.05, dy=0.084, y2=2.2, y3=0.9, ramp=0.02)
FOURIER = sa.FourierProfile(1.0, [0.02, 0.0], [0.0, 0.006])
ZONE = {"x_mu": 0.5, "w": 0.05, "c_mu": 2.5}


def run(scene, **options):
    return planar_smooth.run(scene, {**OPTIONS, **options})


def rotate(vector, theta):
    c, s = math.cos(theta), math.sin(theta)
    return np.array([c * vector[0] - s * vector[1], s * vector[0] + c * vector[1]])


@pytest.mark.parametrize("profile, surface, x0, v0, horizon", [
    (JERK, False, 0.1, 0.0, {"periods": 5}),
    (FOURIER, False, 0.1, 0.0, {"periods": 5}),
    (FOURIER, False, 0.1, 0.3, {"periods": 5}),
    (THREE, True, 0.45, 0.0, {"periods": 20}),
    (JERK, True, 0.45, 0.0, {"periods": 20}),
    (JERK, True, 0.45, 0.0, {"until": "rest", "max_periods": 200}),
], ids=["jerk-uniform", "fourier-uniform", "fourier-moving", "three-phase-strip", "jerk-strip", "jerk-strip-rest"])
def test_reduces_to_the_1d_model(profile, surface, x0, v0, horizon):
    """docs/explanation/planar-model.md (1-D reduction): a table moving along the first axis, a part starting on
    it and a strip of normal (1, 0) give the 1-D exact solution (Sects. 3.2-3.3, eqs. 6 and 38) to 1e-12 in the
    end state and in the dense output, with y and y' exactly 0."""
    planar = sa.Scene(sa.PlanarProfile(profile), sa.Strip((1.0, 0.0), **ZONE) if surface else sa.Uniform(),
                      x0=(x0, 0.0), v0=(v0, 0.0), record=sa.Record(series=("x", "v"), samples_per_period=20),
                      **horizon)
    line = sa.Scene(profile, sa.StopZone(**ZONE) if surface else sa.Uniform(), x0=x0, v0=v0,
                    record=sa.Record(series=("x", "v"), samples_per_period=20), **horizon)
    result, reference = run(planar), sa.simulate(line)
    assert result.reason is reference.reason
    assert abs(result.x_end[0] - reference.x_end) <= 1e-12 and abs(result.v_end[0] - reference.v_end) <= 1e-12
    assert result.x_end[1] == 0.0 and result.v_end[1] == 0.0
    t = reference.series["t"]
    at = np.searchsorted(t, result.samples["t"] - 1e-12)         # the 1-D series adds the events' times
    assert len(result.samples) == 20 * reference.period_end + 1 or result.reason is not Reason.PERIODS
    assert np.max(np.abs(t[at] - result.samples["t"])) <= 1e-12
    assert np.max(np.abs(result.samples["x"][:, 0] - reference.series["x"][at])) <= 1e-12
    assert np.max(np.abs(result.samples["v"][:, 0] - reference.series["v"][at])) <= 1e-12
    assert np.all(result.samples["x"][:, 1] == 0.0) and np.all(result.samples["v"][:, 1] == 0.0)


def test_fig18_scene_accumulates_at_x_stick_min():
    """Sect. 7.3, Fig. 18 and eq. (41): the three-phase profile (1.05, 0.084, 2.2, 0.9) entering the strip
    (0.5, 0.05, 2.5) along its normal accumulates at x_stick_min = 0.5 + 0.05 (2.2 - 1) / 1.5 = 0.54; the planar
    run reports ACCUMULATION at the strip's rest line within 1e-12 of it, as the 1-D run does."""
    scene = sa.Scene(sa.PlanarProfile(THREE), sa.Strip((1.0, 0.0), **ZONE), x0=(0.45, 0.0), until="rest",
                     max_periods=200)
    result = run(scene)
    assert result.reason is Reason.ACCUMULATION
    assert abs(result.x_end[0] - 0.54) <= 1e-12 and result.x_end[1] == 0.0
    reference = sa.simulate(sa.Scene(THREE, sa.StopZone(**ZONE), x0=0.45, until="rest", max_periods=200))
    assert reference.reason is Reason.ACCUMULATION and abs(reference.x_end - 0.54) <= 1e-12


@pytest.mark.parametrize("theta", [0.7, -2.3])
def test_rotating_the_scene_rotates_the_trajectory(theta):
    """docs/explanation/planar-model.md (isotropy): friction is isotropic, so turning the profile (its angle) and
    every strip normal (and the start) by theta turns x(t) and v(t) by theta, to 1e-12."""
    profile = sa.PlanarProfile(JERK, FOURIER.__class__(1.05, [0.01], [0.004]), offset=0.3, angle=0.2)
    strips = [sa.Strip((math.cos(0.4), math.sin(0.4)), 0.05, 0.05, 2.5), sa.Strip((0.0, -1.0), 0.02, 0.03, 1.8)]
    record = sa.Record(series=("x", "v"), samples_per_period=10)
    x0, v0 = np.array([0.01, -0.02]), np.array([0.05, 0.1])
    base = run(sa.Scene(profile, strips, x0=tuple(x0), v0=tuple(v0), periods=4, record=record))
    turned = run(sa.Scene(profile.rotated(theta), [s.rotated(theta) for s in strips], x0=tuple(rotate(x0, theta)),
                          v0=tuple(rotate(v0, theta)), periods=4, record=record))
    assert base.reason is turned.reason is Reason.PERIODS
    assert base.crossings > 0 and base.sticks > 0
    assert (base.sticks, base.slips, base.crossings) == (turned.sticks, turned.slips, turned.crossings)
    assert np.max(np.abs(rotate(base.x_end, theta) - turned.x_end)) <= 1e-12
    assert np.max(np.abs(rotate(base.v_end, theta) - turned.v_end)) <= 1e-12
    assert np.max(np.abs(rotate(base.samples["x"].T, theta).T - turned.samples["x"])) <= 1e-12


def test_a_strip_parallel_to_the_motion_never_stops_the_part():
    """docs/explanation/planar-model.md: a strip whose normal is perpendicular to the table's acceleration, the
    part starting outside it, is never reached: the run equals the one on a uniform surface exactly and ends
    at the horizon (MAX_PERIODS), never at rest."""
    profile = sa.PlanarProfile(JERK, angle=0.5)
    normal = (-math.sin(0.5), math.cos(0.5))
    strip = run(sa.Scene(profile, sa.Strip(normal, 0.01, 0.05, 3.0), until="rest", max_periods=20))
    uniform = run(sa.Scene(profile, until="rest", max_periods=20))
    assert strip.reason is Reason.MAX_PERIODS and strip.crossings == 0
    assert np.array_equal(strip.x_end, uniform.x_end) and np.hypot(*strip.x_end) > 1.0


def _incline(a, mu, v0, e):
    """Stop time and displacement of x'' = -a e - mu v/|v| (|e| = 1, a < mu) from x = 0, v0, in closed form: with
    psi the angle of v to -e and u = tan(psi / 2), |v| = C u^k / sin(psi), k = mu / a (the block on an incline)."""
    a, mu = mp.mpf(a), mp.mpf(mu)
    e = [mp.mpf(e[0]), mp.mpf(e[1])]
    v = [mp.mpf(v0[0]), mp.mpf(v0[1])]
    along = -(v[0] * e[0] + v[1] * e[1])
    side = [v[0] + along * e[0], v[1] + along * e[1]]
    size = mp.sqrt(side[0] ** 2 + side[1] ** 2)
    psi = mp.atan2(size, along)
    k, u = mu / a, mp.tan(psi / 2)
    c = mp.sqrt(v[0] ** 2 + v[1] ** 2) * mp.sin(psi) / u ** k
    t = c / (2 * a) * (u ** (k - 1) / (k - 1) + u ** (k + 1) / (k + 1))
    par = c ** 2 / (4 * a) * (u ** (2 * k - 2) / (2 * k - 2) - u ** (2 * k + 2) / (2 * k + 2))
    perp = c ** 2 / (2 * a) * (u ** (2 * k - 1) / (2 * k - 1) + u ** (2 * k + 1) / (2 * k + 1))
    return float(t), np.array([float(-par * e[i] + perp * side[i] / size) for i in (0, 1)])


@pytest.mark.parametrize("a, theta, v0", [(0.3, 0.4, (0.1, 0.25)), (0.8, 1.0, (-0.1, 0.05)),
                                          (0.05, 2.0, (0.2, -0.3)), (0.6, -0.7, (0.3, 0.0))])
def test_the_stop_matches_the_closed_form_on_a_uniform_surface(a, theta, v0):
    """docs/explanation/planar-model.md (stick event): under a constant Y'' of size a < mu = 1 the slip turns
    towards -Y'' and stops in finite time, with v not smooth at the stop (its angle to -Y'' decays as a power
    a / (1 - a) of the time left); the located stop time and position match the closed form to 1e-14."""
    profile = sa.PlanarProfile(sa.PiecewiseConstantProfile([0.0, 0.5, 1.0], [a, -a], 0.0, 0.0), angle=theta)
    result = run(sa.Scene(profile, v0=v0, periods=1, record=sa.Record(events=True)))
    t_stop, x_stop = _incline(a, 1.0, v0, (math.cos(theta), math.sin(theta)))
    stop = result.log[result.log["kind"] == int(EventKind.STICK)][0]
    assert t_stop < 0.5
    assert abs(stop["t"] - t_stop) <= 1e-14 and np.max(np.abs(stop["x"] - x_stop)) <= 1e-14


def test_a_slip_matches_a_high_precision_referee():
    """docs/explanation/planar-model.md (accuracy): a slip under an elliptical Fourier motion inside a wide
    strip band (mu_bar affine in x) matches mpmath's Taylor integrator of the same equation at 20 digits to
    1e-14 after 0.2 periods."""
    mp.mp.dps = 20
    n = (math.cos(0.7), math.sin(0.7))
    profile = sa.PlanarProfile(sa.FourierProfile(1.0, [0.05], [0.0]), sa.FourierProfile(1.0, [0.0], [0.03]),
                               angle=0.3)
    x0, v0 = (0.1, -0.2), (1.5, 1.0)

    def field(t, y):
        ax, ay = -(2 * mp.pi) ** 2 * mp.mpf("0.05") * mp.cos(2 * mp.pi * t), \
            -(2 * mp.pi) ** 2 * mp.mpf("0.03") * mp.sin(2 * mp.pi * t)
        c, s = mp.cos(mp.mpf(0.3)), mp.sin(mp.mpf(0.3))
        ax, ay = c * ax - s * ay, s * ax + c * ay
        mu = 1 + 2 * (n[0] * y[0] + n[1] * y[1] + 5) / 10
        speed = mp.sqrt(y[2] ** 2 + y[3] ** 2)
        return [y[2], y[3], -ax - mu * y[2] / speed, -ay - mu * y[3] / speed]
    referee = mp.odefun(field, 0, [mp.mpf(x0[0]), mp.mpf(x0[1]), mp.mpf(v0[0]), mp.mpf(v0[1])])(mp.mpf("0.2"))
    scene = sa.Scene(profile, sa.Strip(n, -5.0, 10.0, 3.0), x0=x0, v0=v0, periods=1,
                     record=sa.Record(series=("x", "v"), samples_per_period=5))
    sample = run(scene).samples[1]
    assert sample["t"] == pytest.approx(0.2, abs=1e-15)
    assert np.max(np.abs(sample["x"] - [float(referee[0]), float(referee[1])])) <= 1e-14
    assert np.max(np.abs(sample["v"] - [float(referee[2]), float(referee[3])])) <= 1e-14


def test_a_part_parked_on_a_strip_corner_moves_symmetrically():
    """docs/explanation/planar-model.md (hard cases): a part stuck exactly on the corner of two strips (normals
    (1, 0) and (0, 1), the same x_mu, w, c_mu), the table moving along the diagonal, belongs to both bands it
    moves into (tie rule 5 of the 1-D engine: no crossing is counted) and stays on the diagonal (x = y to 1e-15 at every
    event), ending on both strips' rest line (eq. 41) to 1e-12."""
    profile = sa.PlanarProfile(THREE, angle=math.pi / 4)
    strips = [sa.Strip((1.0, 0.0), 0.0, 0.05, 2.5), sa.Strip((0.0, 1.0), 0.0, 0.05, 2.5)]
    result = run(sa.Scene(profile, strips, until="rest", max_periods=200, record=sa.Record(events=True)))
    assert result.reason in (Reason.REST, Reason.ACCUMULATION)
    assert np.max(np.abs(result.log["x"][:, 0] - result.log["x"][:, 1])) <= 1e-15
    assert result.crossings == 0 and result.sticks > 1           # on both boundaries: in the bands it moves into
    limit = 0.05 * (2.2 - 1.0) / 1.5
    assert np.max(np.abs(result.x_end - limit)) <= 1e-12


def test_grazing_the_stick_disc_sticks():
    """docs/explanation/planar-model.md (tie rule): |Y''| = r mu_bar exactly counts as stick.  A slip along -e under
    Y'' = e (|Y''| = 1 = mu: it keeps its speed 0.1) meets Y'' = -e, stops after 0.05 at x = -0.05 - 0.0025 and,
    with |Y''| = 1 on the disc's edge, sticks there for good (REST); a circular table motion with |Y''| = 1 at all
    times never moves a part at rest."""
    square = sa.PlanarProfile(sa.PiecewiseConstantProfile([0.0, 0.5, 1.0], [1.0, -1.0], 0.0, 0.0), angle=0.3)
    result = run(sa.Scene(square, v0=tuple(rotate((-0.1, 0.0), 0.3)), until="rest", max_periods=5))
    assert result.reason is Reason.REST and result.sticks == 1 and result.slips == 0
    assert np.max(np.abs(result.x_end - rotate((-0.0525, 0.0), 0.3))) <= 1e-15
    radius = 1.0 / (2.0 * math.pi) ** 2
    circle = sa.PlanarProfile(sa.FourierProfile(1.0, [radius], [0.0]), sa.FourierProfile(1.0, [0.0], [radius]))
    result = run(sa.Scene(circle, x0=(0.3, 0.1), periods=3))
    assert result.reason is Reason.PERIODS and result.slips == 0 and tuple(result.x_end) == (0.3, 0.1)


def test_the_event_budget_and_the_records():
    """The run ends with MAX_EVENTS and a message naming the budget once max_events events were counted; its
    samples lie at tau0 + k dt / samples_per_period up to the end and its log holds the events counted."""
    scene = sa.Scene(sa.PlanarProfile(JERK, angle=0.4), phase=0.3, periods=4,
                     record=sa.Record(series=("x",), samples_per_period=8, events=True))
    full = run(scene)
    assert full.reason is Reason.PERIODS
    times = scene.phase * JERK.dt + np.arange(4 * 8 + 1) * (JERK.dt / 8)
    assert np.max(np.abs(full.samples["t"] - times)) <= 1e-14
    kinds = full.log["kind"]
    assert (np.sum(kinds == int(EventKind.STICK)), np.sum(kinds == int(EventKind.SLIP))) == (full.sticks, full.slips)
    short = run(scene, max_events=3)
    assert short.reason is Reason.MAX_EVENTS and "max_events = 3" in short.message
    assert short.sticks + short.slips + short.crossings == 3 and short.t_end < full.t_end


def test_moreau_converges_to_it_at_first_order():
    """docs/explanation/planar-model.md (cross-check): Moreau's midpoint scheme with the friction disc is first
    order in h (Sect. 4.1), so its end state after 10 periods of a two-axis finite-jerk motion over a slanted strip
    approaches this solver's with a fitted order in [0.8, 1.2]."""
    profile = sa.PlanarProfile(JERK, JERK, offset=0.25, angle=0.3)
    scene = sa.Scene(profile, sa.Strip((math.cos(0.5), math.sin(0.5)), 0.3, 0.05, 2.5), periods=10)
    exact = run(scene)
    assert exact.crossings > 0
    steps = np.array([1000, 2000, 4000, 8000])
    errors = [np.hypot(*(sa.simulate(scene, method="moreau", steps_per_period=int(n)).x_end - exact.x_end))
              for n in steps]
    order = -np.polyfit(np.log(steps), np.log(errors), 1)[0]
    assert 0.8 <= order <= 1.2 and errors[-1] < 1e-3


def test_bad_scenes_are_refused_before_the_run():
    """Bad input gets a clear error before any work: a 1-D scene, and Stribeck friction (docs/explanation/
    planar-model.md: the planar model takes Coulomb and static/kinetic friction)."""
    with pytest.raises(ValueError, match="planar scene"):
        run(sa.Scene(JERK, periods=1))
    stribeck = sa.FrictionLaw("stribeck", mu_s_over_mu_k=1.5, v_s=0.1)
    scene = sa.Scene(sa.PlanarProfile(JERK), periods=1)
    object.__setattr__(scene, "friction", stribeck)          # the scene refuses it itself; the solver too
    with pytest.raises(ValueError, match="friction.kind"):
        run(scene)
