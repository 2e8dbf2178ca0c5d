"""Moreau time-stepping of several parts on one table (``selfalign.solvers.parts_moreau``): the paper's
Sect. 4.1 scheme extended to unilateral contacts, impacts and Coulomb friction per part (Sect. 8,
recommendation 5; the model of ``selfalign.model.parts``).

References: the one-part Moreau solver ``simulate(scene, method="moreau")`` (the same step), a run of the
same scheme at a 32 times finer step (convergence), one part with the mass-weighted friction factor
(a cluster pushed together), and the closed-form impact of two or three parts (momentum and Newton's law).
"""

import math

import numpy as np
import pytest

import selfalign as sa
from selfalign.model.parts import Part
from selfalign.solvers.driver import simulate_batch
from selfalign.solvers.parts_moreau import moreau_parts

# Fig. 18 settings (Sect. 7.3): case 1 on the uniform surface (y2'' > 1, y3'' < 1).
PROFILE = sa.ThreePhaseProfile(1.05, 0.084, 2.2, 0.9)
W = 0.05                                     # Sect. 7.2: w = 0.05
ZONE = sa.StopZone(0.5, W, 2.5)              # Sect. 7.2: c_mu = 2.5
#: A table at rest (y'' = 0): parts coast, with a tiny friction factor, so impacts are seen alone.
AT_REST = sa.PiecewiseConstantProfile([0.0, 1.0], [0.0], y_start=0.0, yd_start=0.0)
#: A friction factor small enough that the friction impulse over a run (h k per step, 1e-9 per unit of
#: time) is far below the tolerances of the impact tests.
SLIPPERY = 1e-9


def one_part_moreau(scene, steps):
    """x_end, v_end of the one-part Moreau solver at ``steps`` steps per period, stepped through every period
    (no fast-forward of repeating periods)."""
    res = simulate_batch(scene.profile, scene.x0, scene.v0, surface=scene.surface, until="periods",
                         periods=scene.periods, method="moreau", steps_per_period=steps, fast_forward=False)
    return float(res.x_end[0]), float(res.v_end[0])


@pytest.mark.parametrize("profile, surface, x0, v0, periods", [
    (PROFILE, sa.Uniform(), 0.0, 0.0, 10),
    (PROFILE, sa.Uniform(), 0.3, -0.2, 7),
    (PROFILE, ZONE, 0.3, 0.0, 30),
    (sa.PolynomialProfile(1.0, 0.05), sa.Uniform(), 0.0, 0.1, 5),
    (sa.FourierProfile(1.0, [0.02, 0.004], [0.0, 0.003]), sa.Uniform(), 0.0, 0.0, 5),
    (sa.FiniteJerkProfile(1.05, 0.084, 2.2, 0.9, ramp=0.02), ZONE, 0.4, 0.0, 10),
])
def test_one_part_is_the_one_part_moreau_step(profile, surface, x0, v0, periods):
    """Sect. 4.1: with one part of width w = the zone's, mass 1 and friction factor 1 the step is the
    one-part scheme's (the same exact table impulse, midpoint friction and soft threshold), so the end
    state equals ``simulate(..., method="moreau")`` at the same step to 1e-12 (the two differ only in
    rounding: the one-part solver keeps x - x_mu, this one x).  The zone case stops in the transition
    region (eq. 41); the others walk; piecewise-constant, smooth and finite-jerk profiles.  Checked against
    both ``simulate`` and the batch driver stepping every period (no fast-forward)."""
    steps = 700
    scene = sa.Scene(profile, surface, x0=x0, v0=v0, periods=periods, method="moreau",
                     solver_options={"steps_per_period": steps})
    x_ref, v_ref = one_part_moreau(scene, steps)
    traj = sa.simulate(scene)                           # the same, with the fast-forward of repeating periods
    res = moreau_parts(profile, [Part(x0, v0, width=W)], surface=surface, periods=periods, steps_per_period=steps)
    assert res.steps == steps * periods and res.h == traj.options["h"] == profile.dt / steps
    assert abs(res.x_end[0] - x_ref) <= 1e-12 and abs(res.v_end[0] - v_ref) <= 1e-12, (res.x_end, x_ref)
    assert abs(res.x_end[0] - traj.x_end) <= 1e-12 and abs(res.v_end[0] - traj.v_end) <= 1e-12
    assert abs(res.x_end[0] - x0) > 0.01                 # it moved: the comparison is not of two rests


def test_one_part_of_any_mass_is_the_one_part_step():
    """Sect. 3.2: the mass drops out of a lone part's equation of motion (eq. 6), so a part of mass 3.7 runs
    as the one-part scheme to 1e-12 (the chain minimiser multiplies and divides by the mass: rounding)."""
    scene = sa.Scene(PROFILE, ZONE, x0=0.42, periods=20)
    x_ref, v_ref = one_part_moreau(scene, 500)
    res = moreau_parts(PROFILE, [Part(0.42, width=W, mass=3.7)], surface=ZONE, periods=20, steps_per_period=500)
    assert abs(res.x_end[0] - x_ref) <= 1e-12 and abs(res.v_end[0] - v_ref) <= 1e-12


def test_each_part_sees_the_stop_zone_over_its_own_width():
    """Sect. 3.3, eqs. 7-9: a part's mu_bar rises over its OWN width, not the zone's: one part 0.03 wide on
    StopZone(x_mu = 0.5, w = 0.05, c_mu = 2.5) runs as the one-part scheme on StopZone(0.5, 0.03, 2.5),
    to 1e-12, and not as on the 0.05 zone (the two end positions differ by more than 1e-3)."""
    narrow = sa.StopZone(0.5, 0.03, 2.5)
    x_ref, v_ref = one_part_moreau(sa.Scene(PROFILE, narrow, x0=0.35, periods=20), 500)
    x_wide, _ = one_part_moreau(sa.Scene(PROFILE, ZONE, x0=0.35, periods=20), 500)
    res = moreau_parts(PROFILE, [Part(0.35, width=0.03)], surface=ZONE, periods=20, steps_per_period=500)
    assert abs(res.x_end[0] - x_ref) <= 1e-12 and abs(res.v_end[0] - v_ref) <= 1e-12
    assert abs(x_wide - x_ref) > 1e-3


def test_parts_that_never_meet_move_alone():
    """Model: without contact (gaps that never close) every part moves by its own eq. (6): three parts
    about 1 apart, of widths 0.05, 0.03, 0.04, each equal to the
    one-part scheme on a zone of its width to 1e-12 (mass and friction factor 1); the front one stops in
    the zone."""
    widths, starts = (0.05, 0.03, 0.04), (-2.6, -1.5, 0.45)
    res = moreau_parts(PROFILE, [Part(x, width=w) for x, w in zip(starts, widths)], surface=ZONE, periods=25,
                       steps_per_period=400)
    assert res.max_overlap == 0.0
    for i, (x0, w) in enumerate(zip(starts, widths)):
        x_ref, v_ref = one_part_moreau(sa.Scene(PROFILE, sa.StopZone(0.5, w, 2.5), x0=x0, periods=25), 400)
        assert abs(res.x_end[i] - x_ref) <= 1e-12 and abs(res.v_end[i] - v_ref) <= 1e-12, i
    assert 0.5 < res.x_end[2] < 0.54 and res.v_end[2] == 0.0


#: Two parts on the Fig. 18 profile: the rear one (friction factor 0.7) walks faster than the front one,
#: catches it in every forward slip and pushes it, then slides back alone when y'' = 0.9 > 0.7.
CHASE = [Part(0.0, width=W, friction_factor=0.7), Part(0.06, width=W)]


@pytest.mark.parametrize("restitution", [0.0, 0.5])
def test_two_colliding_parts_converge_with_order_one(restitution):
    """Sect. 4.1: Moreau's scheme is first order in h, also through impacts and pushing contacts.  Two parts
    that collide in every one of 10 periods, and with e = 0 push each other on (checked at h = dt/4000:
    one velocity jump of the front part per period, and with e = 0 over 100 steps with a closed contact):
    the fitted slope of log(error envelope) over log(h), h = dt/250 ... dt/4000, lies in [0.8, 1.2],
    against the same scheme at h = dt/128000.  The envelope at each h is the largest end-position
    error over six steps in [h / 1.83, h], since the error constant of a first-order scheme oscillates
    with where the profile's switches and the impacts fall inside a step."""
    ref = moreau_parts(PROFILE, CHASE, restitution=restitution, periods=10, steps_per_period=128000)
    fine = moreau_parts(PROFILE, CHASE, restitution=restitution, periods=10, steps_per_period=4000, sample_every=1)
    period = np.floor(fine.t[1:] / PROFILE.dt + 1e-9)
    impacts = np.abs(np.diff(fine.v[:, 1])) > 0.01        # a step without impact changes v by < h (2.2 + 1)
    pushing = (fine.x[1:, 1] - W) - fine.x[1:, 0] <= 0.0
    for p in range(10):
        assert np.sum(impacts[period == p]) == 1, p
        assert restitution > 0.0 or np.sum(pushing[period == p]) > 100, p
    base = np.array([250, 500, 1000, 2000, 4000])
    envelope = []
    for n in base:
        envelope.append(max(np.max(np.abs(moreau_parts(PROFILE, CHASE, restitution=restitution, periods=10,
                                                       steps_per_period=int(n * (1 + j / 6))).x_end - ref.x_end))
                            for j in range(6)))
    order = np.polyfit(np.log(PROFILE.dt / base), np.log(envelope), 1)[0]
    assert 0.8 <= order <= 1.2, (order, envelope)
    assert envelope[-1] < 1e-3


@pytest.mark.parametrize("profile", [PROFILE, sa.ThreePhaseProfile(1.0, 0.084, 2.3, 1.3)])
def test_touching_identical_parts_move_as_one(profile):
    """Model (``chain_minimiser``): two identical parts that touch, at the same velocity, with e = 0 move as
    one part - the rear one as a lone part (the one-part scheme) and the front one a width ahead - at every
    sampled step to 1e-12: through stick and forward slip (Fig. 18 profile, case 1) and also backward slip
    (Sect. 7.2's (y2'', y3'') = (2.3, 1.3))."""
    steps, periods = 400, 5
    pair = moreau_parts(profile, [Part(0.1, 0.05, width=W), Part(0.1 + W, 0.05, width=W)], periods=periods,
                        steps_per_period=steps, sample_every=7)
    lone = moreau_parts(profile, [Part(0.1, 0.05, width=W)], periods=periods, steps_per_period=steps, sample_every=7)
    assert np.max(np.abs(pair.x[:, 0] - lone.x[:, 0])) <= 1e-12
    assert np.max(np.abs(pair.x[:, 1] - W - lone.x[:, 0])) <= 1e-12
    assert np.max(np.abs(pair.v - lone.v[:, :1])) <= 1e-12
    assert np.max(lone.v) > 0.1 and np.min(np.abs(lone.v)) == 0.0   # it slides and it sticks
    assert profile is PROFILE or np.min(lone.v) < -0.01              # and slides back


def test_a_chain_of_touching_identical_parts_moves_as_one():
    """Model (``chain_minimiser``): 30 identical touching parts (width 1/16, exact in binary, so that they
    touch exactly) at one velocity move as one part: part i at the lone part's position plus i widths, at
    every sample to 1e-12, through stick and slip in both directions ((y2'', y3'') = (2.3, 1.3))."""
    profile = sa.ThreePhaseProfile(1.0, 0.084, 2.3, 1.3)
    width = 1 / 16
    chain = moreau_parts(profile, [Part(i * width, 0.05, width=width) for i in range(30)], periods=4,
                         steps_per_period=300, sample_every=13)
    lone = moreau_parts(profile, [Part(0.0, 0.05, width=width)], periods=4, steps_per_period=300, sample_every=13)
    assert np.max(np.abs(chain.x - lone.x - width * np.arange(30))) <= 1e-12
    assert np.max(np.abs(chain.v - lone.v)) <= 1e-12
    assert np.min(lone.v) < -0.01 < 0.1 < np.max(lone.v)


def test_pushed_cluster_moves_with_the_mass_weighted_friction():
    """Model (``selfalign.model.parts``): parts pushed together move as one part with the mass-weighted
    friction factor sum m_i k_i / sum m_i.  Rear part m = 3, k = 0.8, front part m = 1, k = 1.4 (weighted
    0.95) on a three-phase profile whose backward push y3'' = 0.7 sticks both and whose forward push
    y2'' = 2.2 slides both: the rear part, which alone would slide farther, pushes the front one in every
    slip, and the rear part's path equals a lone part's with k = 0.95 to 1e-10 at every sample."""
    profile = sa.ThreePhaseProfile(1.05, 0.07, 2.2, 0.7)
    kw = {"periods": 5, "steps_per_period": 500, "sample_every": 11}
    pair = moreau_parts(profile, [Part(0.0, width=W, mass=3.0, friction_factor=0.8),
                                  Part(0.03, width=0.03, friction_factor=1.4)], **kw)
    lone = moreau_parts(profile, [Part(0.0, width=W, friction_factor=0.95)], **kw)
    assert np.max(np.abs(pair.x[:, 0] - lone.x[:, 0])) <= 1e-10
    assert np.max(np.abs(pair.x[:, 1] - 0.03 - lone.x[:, 0])) <= 1e-10
    assert lone.x_end[0] > 0.2


@pytest.mark.parametrize("x0", [0.3, 0.31, 0.32, 0.33])
def test_pushed_pair_stops_where_its_mean_friction_holds_it(x0):
    """Eq. 41 for a cluster: two identical touching parts (w = 0.05, e = 0) walk into the stop zone of
    Sect. 7.2 as one part with the mean friction (mu_bar_rear + mu_bar_front) / 2, and stop for good where
    it first reaches max|y''| = 2.2: the front one wholly on the high friction (2.5), the rear one's
    mu_bar = 1.9, i.e. its front at x_mu + 0.6 w (eq. 9).  After 60 periods from four starts: at rest
    there to 1e-9, the front part a width ahead to 1e-12."""
    res = moreau_parts(PROFILE, [Part(x0 - W, width=W), Part(x0, width=W)], surface=ZONE, periods=60,
                       steps_per_period=500)
    assert res.v_end.tolist() == [0.0, 0.0]
    assert abs(res.x_end[0] - (ZONE.x_mu + 0.6 * W)) <= 1e-9
    assert abs(res.x_end[1] - res.x_end[0] - W) <= 1e-12


@pytest.mark.parametrize("restitution, after", [(0.0, (0.25, 0.25)), (0.5, (-0.125, 0.375)), (1.0, (-0.5, 0.5))])
def test_impact_conserves_momentum_and_obeys_newtons_law(restitution, after):
    """Model (``impact_velocities``): masses 1 and 3, velocities (1, 0), on a table at rest with friction
    factor 1e-9: the impact conserves momentum (1 to 1e-8) and leaves the relative velocity e times the
    approach speed, the textbook velocities ((1 - 3 e) / 4, (1 + e) / 4) to 1e-8; e = 1 keeps the kinetic
    energy (1/2 to 1e-8)."""
    parts = [Part(0.0, 1.0, width=W, friction_factor=SLIPPERY), Part(0.1, width=W, mass=3.0,
                                                                    friction_factor=SLIPPERY)]
    res = moreau_parts(AT_REST, parts, restitution=restitution, periods=1, steps_per_period=1000)
    assert abs(res.v_end[0] + 3.0 * res.v_end[1] - 1.0) <= 1e-8
    assert np.max(np.abs(res.v_end - after)) <= 1e-8, res.v_end
    if restitution == 1.0:
        assert abs(0.5 * res.v_end[0] ** 2 + 1.5 * res.v_end[1] ** 2 - 0.5) <= 1e-8


def test_simultaneous_impact_of_three_touching_parts():
    """Model (``impact_velocities``, Newton's cradle): three equal touching parts hit with v = (1, 0, 0) and
    e = 1 leave with the simultaneous law's (-1/3, 2/3, 2/3) to 1e-8, not the cradle's (0, 0, 1): momentum
    and energy are kept, no wave runs through the chain."""
    parts = [Part(W * i, 1.0 if i == 0 else 0.0, width=W, friction_factor=SLIPPERY) for i in range(3)]
    res = moreau_parts(AT_REST, parts, restitution=1.0, periods=1, steps_per_period=1000)
    assert np.max(np.abs(res.v_end - [-1 / 3, 2 / 3, 2 / 3])) <= 1e-8, res.v_end


@pytest.mark.parametrize("restitution", [0.0, 0.5, 1.0])
def test_impact_between_sliding_parts_converges_to_the_closed_form(restitution):
    """Eqs. 2, 6 on a table at rest (y'' = 0), friction factor 1: a part sliding at v = 1 decelerates at 1,
    x(t) = t - t^2 / 2, and hits a part of mass 2 at rest g = 0.1 ahead at speed v_c = sqrt(1 - 2 g);
    Newton's law leaves (v_c (1 - 2 e) / 3, v_c (1 + e) / 3), and each part then slides to rest over
    u |u| / 2.  The end positions of Moreau's scheme converge to these with order 1: fitted slope of
    log(error envelope) over log(h), h = dt/125 ... dt/8000, in [0.8, 1.2] (envelope as in the
    convergence test above: the impact falls anywhere inside a step)."""
    g = 0.1
    v_c = math.sqrt(1.0 - 2.0 * g)
    rear, front = v_c * (1.0 - 2.0 * restitution) / 3.0, v_c * (1.0 + restitution) / 3.0
    exact = np.array([g + rear * abs(rear) / 2.0, g + W + front * front / 2.0])
    parts = [Part(0.0, 1.0, width=W), Part(g + W, width=W, mass=2.0)]
    base = np.array([125, 250, 500, 1000, 2000, 4000, 8000])
    envelope = [max(np.max(np.abs(moreau_parts(AT_REST, parts, restitution=restitution, periods=2,
                                               steps_per_period=int(n * (1 + j / 6))).x_end - exact))
                    for j in range(6)) for n in base]
    order = np.polyfit(np.log(AT_REST.dt / base), np.log(envelope), 1)[0]
    assert 0.8 <= order <= 1.2, (order, envelope)
    assert envelope[-1] < 2e-4


@pytest.mark.parametrize("steps", [100, 1000, 10000])
def test_overlap_is_below_h_times_the_approach_speed(steps):
    """Module docstring: contacts are decided at the midpoint and kept at the velocity level, so parts
    overlap, by less than h times the approach speed (1 here; masses 1 and 1, e = 0, table at rest), and
    the overlap is kept, not undone, while they stay together (end gap = -max_overlap to 1e-12)."""
    parts = [Part(0.0, 1.0, width=W, friction_factor=SLIPPERY), Part(0.1234567, width=W, friction_factor=SLIPPERY)]
    res = moreau_parts(AT_REST, parts, periods=1, steps_per_period=steps)
    assert 0.0 <= res.max_overlap < res.h * 1.0
    assert abs(((res.x_end[1] - W) - res.x_end[0]) + res.max_overlap) <= 1e-12


def test_samples_hold_the_start_and_the_end():
    """:class:`PartsMoreauResult`: samples every k steps from t = 0, the first the start state, the last (k
    dividing the step count) the end state; times k h apart."""
    res = moreau_parts(PROFILE, CHASE, periods=2, steps_per_period=100, sample_every=10)
    assert res.x.shape == (21, 2) and res.v.shape == (21, 2) and res.t.shape == (21,)
    assert res.x[0].tolist() == [0.0, 0.06] and res.v[0].tolist() == [0.0, 0.0]
    assert res.x[-1].tolist() == res.x_end.tolist() and res.v[-1].tolist() == res.v_end.tolist()
    assert math.isclose(res.t[-1], res.t_end, rel_tol=1e-12)
    assert res.x_end.flags.writeable is False


GOOD = {"profile": PROFILE, "parts": CHASE, "periods": 1}


@pytest.mark.parametrize("change, error, words", [
    ({"profile": "three-phase"}, TypeError, "profile must be"),
    ({"parts": Part(0.0, width=W)}, TypeError, "parts must be a sequence"),
    ({"parts": []}, ValueError, "at least one Part"),
    ({"parts": [Part(0.0, width=W), Part(0.02, width=W)]}, ValueError, "overlaps"),
    ({"parts": [Part(0.0, width=W), 1.0]}, TypeError, "parts[1]"),
    ({"surface": "uniform"}, TypeError, "surface must be"),
    ({"restitution": 1.5}, ValueError, "restitution"),
    ({"restitution": "0"}, TypeError, "restitution"),
    ({"periods": 0}, ValueError, "periods"),
    ({"periods": 2.5}, ValueError, "periods"),
    ({"periods": None}, TypeError, "periods"),
    ({"steps_per_period": 0}, ValueError, "steps_per_period"),
    ({"steps_per_period": 10**8}, ValueError, "steps_per_period"),
    ({"steps_per_period": 1}, ValueError, "too coarse"),
    ({"periods": 10**8, "steps_per_period": 1000}, ValueError, "1e+10"),
    ({"sample_every": 0}, ValueError, "sample_every"),
    ({"sample_every": 1, "periods": 10**6, "steps_per_period": 10**3}, ValueError, "GiB"),
    ({"friction": sa.FrictionLaw("stribeck", 1.3, v_s=0.1)}, ValueError, "not Stribeck"),
    ({"friction": "coulomb"}, TypeError, "friction must be"),
])
def test_bad_input_is_refused_before_any_work(change, error, words, monkeypatch):
    """House rule: bad input raises TypeError or ValueError naming the argument, before any stepping (the
    stepper is replaced by one that fails if reached)."""
    import selfalign.solvers.parts_moreau as module

    monkeypatch.setattr(module, "_stepper", lambda: pytest.fail("the stepper ran"))
    kwargs = {**GOOD, **change}
    with pytest.raises(error) as info:
        moreau_parts(kwargs.pop("profile"), kwargs.pop("parts"), **kwargs)
    assert words in str(info.value)
