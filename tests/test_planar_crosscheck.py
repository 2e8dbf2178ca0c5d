"""Cross-checks of the three planar methods on random scenes (docs/explanation/planar-model.md; the paper's
Sect. 8, recommendation (4), general planar motion of the part; the model of its Sects. 3.2-3.3, eqs. 6-9,
with the disc Sign2 in place of Sign).

The scenes: random pairs of the paper's three-phase profiles (Sect. 4.4.3, Appendix) of one period, the y
motion lagging by a random offset, the pair rotated by a random angle, random start states (at rest or
moving) and start phases, 6 periods.  The exact method is the reference: its closed-form planar slip on a
uniform surface, its general stepper (an accurate local solution) on strips.
"""

from __future__ import annotations

import math

import numpy as np
import pytest

import selfalign as sa
from selfalign.model.planar import PlanarProfile, Strip

#: Random scenes of each check.
SCENES = 10
PERIODS = 6
#: ivp's tolerances in the agreement check; its end positions are within IVP_AGREEMENT of the exact ones.
IVP_RTOL, IVP_ATOL = 1e-10, 1e-12
#: 10 rtol: measured at most 9.6e-11 over the ten scenes (rtol 1e-10, atol 1e-12).
IVP_AGREEMENT = 10 * IVP_RTOL
#: Moreau's steps per period, h = dt/250 ... dt/16000.
MOREAU_LEVELS = (250, 500, 1000, 2000, 4000, 8000, 16000)


def _component(rng, dt):
    while True:
        try:
            return sa.ThreePhaseProfile(dt, rng.uniform(0.03, 0.1), rng.uniform(0.6, 2.4), rng.uniform(0.3, 1.6))
        except (ValueError, sa.SceneError):
            continue


def random_scene(rng, strips=0, periods=PERIODS):
    """A random planar scene (module docstring) on a uniform surface or on ``strips`` random strips (normal
    angle, x_mu in [0.05, 0.3], w in [0.03, 0.1], c_mu in [1.5, 3])."""
    dt = rng.uniform(0.8, 1.2)
    profile = PlanarProfile(_component(rng, dt), _component(rng, dt), offset=float(rng.uniform(0.0, 1.0)),
                            angle=float(rng.uniform(0.0, 2.0 * math.pi)))
    surface = []
    for _ in range(strips):
        theta = rng.uniform(0.0, 2.0 * math.pi)
        surface.append(Strip((math.cos(theta), math.sin(theta)), rng.uniform(0.05, 0.3), rng.uniform(0.03, 0.1),
                             rng.uniform(1.5, 3.0)))
    x0 = tuple(rng.uniform(-0.05, 0.05, 2))
    v0 = tuple(rng.uniform(-0.3, 0.3, 2)) if rng.uniform() < 0.5 else (0.0, 0.0)
    return sa.Scene(profile, surface=surface or sa.Uniform(), x0=x0, v0=v0, periods=periods,
                    phase=float(rng.uniform(0.0, 1.0)))


def scenes(seed=1, count=SCENES, strips=lambda i: 0):
    rng = np.random.default_rng(seed)
    return [random_scene(rng, strips(i)) for i in range(count)]


def end(trajectory):
    assert trajectory.status == "horizon", trajectory.message
    return np.asarray(trajectory.x_end, dtype=float)


def test_ivp_agrees_with_exact_on_random_scenes():
    """Hypothesis: solve_ivp mode by mode (the stop located as a zero of v along the driving force) and
    the closed-form exact method solve the same planar inclusion (Sect. 3.2 with Sign2), so on ten random
    scenes their end positions after 6 periods agree within 10 rtol (rtol 1e-10, atol 1e-12; measured: at
    most 9.6e-11)."""
    worst = 0.0
    for scene in scenes():
        exact = sa.simulate(scene)
        ivp = sa.simulate(scene, method="ivp", rtol=IVP_RTOL, atol=IVP_ATOL)
        worst = max(worst, float(np.max(np.abs(end(ivp) - end(exact)))))
    assert worst <= IVP_AGREEMENT


def test_ivp_error_follows_rtol():
    """Hypothesis: ivp's error against the exact method falls with rtol: on the first random scenes the
    largest end-position error at rtol 1e-6 (atol 1e-8) is larger than at rtol 1e-10 (measured 3.6e-8
    against 3.1e-12), and stays below 1e3 rtol at each."""
    errors = {}
    for rtol in (1e-6, 1e-10):
        errors[rtol] = max(float(np.max(np.abs(end(sa.simulate(s, method="ivp", rtol=rtol, atol=rtol * 1e-2))
                                               - end(sa.simulate(s))))) for s in scenes(count=3))
        assert errors[rtol] <= 1e3 * rtol
    assert errors[1e-6] > errors[1e-10]


def test_ivp_one_d_reduction_with_a_strip():
    """Hypothesis: a planar scene moving along x only (PlanarProfile(x=p), y0 = v0_y = 0) on a strip of
    normal (1, 0) is the 1-D scene on StopZone(x_mu, w, c_mu) (docs/explanation/planar-model.md, the 1-D
    reduction): ivp's end position matches the 1-D exact solver within 10 rtol (measured 1.8e-13 at rtol
    1e-10) and y stays exactly 0."""
    p = sa.ThreePhaseProfile(1.05, 0.084, 2.2, 0.9)
    one_d = sa.simulate(sa.Scene(p, sa.StopZone(0.3, 0.05, 2.5), x0=0.0, periods=10))
    planar = sa.simulate(sa.Scene(PlanarProfile(p), surface=Strip((1.0, 0.0), 0.3, 0.05, 2.5), x0=(0.0, 0.0),
                                  periods=10), method="ivp", rtol=IVP_RTOL, atol=IVP_ATOL)
    x = end(planar)
    assert x[1] == 0.0
    assert abs(x[0] - float(one_d.x_end)) <= IVP_AGREEMENT


def fitted_order(scene):
    """The least-squares slope of log(Moreau's end-position error against exact) over log h."""
    exact = end(sa.simulate(scene))
    errors = [float(np.max(np.abs(end(sa.simulate(scene, method="moreau", steps_per_period=n)) - exact)))
              for n in MOREAU_LEVELS]
    return float(np.polyfit(-np.log(MOREAU_LEVELS), np.log(errors), 1)[0]), errors


@pytest.mark.parametrize("index", range(3))
def test_moreau_converges_to_exact_with_order_one(index):
    """Hypothesis: Moreau's time-stepping with the disc projection (Sect. 4.1) is first order on these
    scenes, the events falling inside steps: the slope of log(error) over log h for h = dt/250 ... dt/16000
    is 1 within 0.25 (measured 0.93, 0.93, 1.03 on the first three scenes), and the error at dt/16000 is
    below 1e-3 (measured 5.5e-5 ... 7.4e-5)."""
    order, errors = fitted_order(scenes(count=3)[index])
    assert abs(order - 1.0) <= 0.25
    assert errors[-1] <= 1e-3


def test_the_three_methods_agree_on_strips():
    """Hypothesis: on random scenes with one or two strips (eqs. 7-9 along each strip's normal, mu_bar the
    largest), the exact method (its general stepper: an accurate local solution, events located on it), ivp
    (rtol 1e-10, atol 1e-12) and Moreau at h = dt/16000 solve the same inclusion: exact and ivp agree within
    10 rtol (measured: at most 4.5e-11 on these six scenes), and Moreau within 2e-4 of both, ten times its
    first-order error at that step on the uniform scenes (measured: at most 4.1e-5)."""
    worst_ivp = worst_moreau = 0.0
    for scene in scenes(seed=1, count=9, strips=lambda i: i % 3)[1::3] + scenes(seed=1, count=9,
                                                                              strips=lambda i: i % 3)[2::3]:
        exact = end(sa.simulate(scene))
        ivp = end(sa.simulate(scene, method="ivp", rtol=IVP_RTOL, atol=IVP_ATOL))
        moreau = end(sa.simulate(scene, method="moreau", steps_per_period=16000))
        worst_ivp = max(worst_ivp, float(np.max(np.abs(ivp - exact))))
        worst_moreau = max(worst_moreau, float(np.max(np.abs(moreau - exact))))
    assert worst_ivp <= IVP_AGREEMENT
    assert worst_moreau <= 2e-4


def test_ivp_is_isotropic():
    """Hypothesis: rotating the table motion and the start state by theta rotates the solution by theta
    (docs/explanation/planar-model.md, isotropy of the disc Sign2): ivp's end positions agree after the
    rotation within 10 rtol (measured 5.9e-12 at rtol 1e-10, theta = 0.7)."""
    p = sa.ThreePhaseProfile(1.05, 0.084, 2.2, 0.9)
    profile = PlanarProfile(p, p, offset=0.25)
    theta = 0.7
    rotation = np.array([[math.cos(theta), -math.sin(theta)], [math.sin(theta), math.cos(theta)]])
    x0, v0 = np.array([0.01, 0.02]), np.array([0.1, -0.2])
    plain = sa.Scene(profile, x0=tuple(x0), v0=tuple(v0), periods=5)
    turned = sa.Scene(profile.rotated(theta), x0=tuple(rotation @ x0), v0=tuple(rotation @ v0), periods=5)
    a, b = (end(sa.simulate(s, method="ivp", rtol=IVP_RTOL, atol=IVP_ATOL)) for s in (plain, turned))
    assert np.max(np.abs(rotation @ a - b)) <= IVP_AGREEMENT


def test_the_three_methods_come_to_rest_at_a_strip_corner():
    """Hypothesis: a part walking into the corner of two strips (normals (1, 0) and (0, 1), c_mu = 4 >
    max|Y''| = 2.38) comes to rest for good (REST) with every method, at end positions within 10 rtol of the
    exact one for ivp (measured 3.1e-12) and within 2e-4 for Moreau at dt/16000 (its first-order error;
    measured 5.0e-6 from ivp's)."""
    p = sa.ThreePhaseProfile(1.05, 0.084, 2.2, 0.9)
    scene = sa.Scene(PlanarProfile(p, p, offset=0.25),
                     surface=[Strip((1.0, 0.0), 0.2, 0.05, 4.0), Strip((0.0, 1.0), 0.2, 0.05, 4.0)],
                     until="rest", max_periods=40)
    exact = sa.simulate(scene)
    ivp = sa.simulate(scene, method="ivp", rtol=IVP_RTOL, atol=IVP_ATOL)
    moreau = sa.simulate(scene, method="moreau", steps_per_period=16000)
    assert exact.status == ivp.status == moreau.status == "rest"
    assert np.max(np.abs(np.asarray(ivp.x_end) - np.asarray(exact.x_end))) <= IVP_AGREEMENT
    assert np.max(np.abs(np.asarray(moreau.x_end) - np.asarray(exact.x_end))) <= 2e-4
