"""Friction beyond the paper's Coulomb law: static/kinetic and Stribeck friction.

References are closed forms computed here (the case-1 motion of Sect. 5.1 with kinetic
arcs and a static stick limit) and the limits in which each effect is the paper's model.
"""

import math
import re

import numpy as np
import pytest

import selfalign as sa
from selfalign.analysis.positioning import positioning
from selfalign.io.scene_files import scene_from_dict
from selfalign.model.errors import SceneError
from selfalign.model.friction import FrictionLaw
from selfalign.solvers.jit import kernel

FIG18 = sa.ThreePhaseProfile(1.05, 0.084, 2.2, 0.9)
ZONE = sa.StopZone(0.15, 0.05, 2.5)
IVP_TIGHT = {"rtol": 1e-11, "atol": 1e-13}


def _scene(friction, surface=ZONE, profile=FIG18, **kw):
    kw = kw or {"until": "rest", "max_periods": 200}
    return sa.Scene(profile=profile, surface=surface, friction=friction, **kw)


@pytest.mark.parametrize("method,options", [("exact", {}), ("moreau", {"h": 1.05 / 3000}), ("ivp", {})])
@pytest.mark.parametrize("surface", [ZONE, sa.Uniform()], ids=["stop_zone", "uniform"])
def test_equal_coefficients_are_the_paper_model(method, options, surface):
    """mu_s = mu_k (static_kinetic with ratio 1) is the paper's Coulomb friction: every method
    gives the same end state, status and event count bit for bit as a scene without a friction block."""
    kw = {"until": "rest", "max_periods": 200} if surface is ZONE else {"periods": 7}
    plain = sa.simulate(_scene(FrictionLaw(), surface, **kw), method, **options)
    equal = sa.simulate(_scene(FrictionLaw("static_kinetic", 1.0), surface, **kw), method, **options)
    assert (equal.x_end, equal.v_end, equal.status, equal.stats["events"]) == \
        (plain.x_end, plain.v_end, plain.status, plain.stats["events"])


def test_static_stick_holds_where_coulomb_slips_back():
    """Case 1 of Sect. 5.1 with 1 < y3'' <= mu_s/mu_k: the slip from t1 follows the kinetic arcs
    (eqs. 16-21) and stops at t_x'=0 in the y3'' phase, where static friction holds the mass (a
    Coulomb mass slips back there), so each period advances x2 + v2^2 / (2 (1 + y3'')) (eq. 20)."""
    p = sa.ThreePhaseProfile(1.05, 0.084, 2.2, 1.2)
    v2 = (p.y2 - 1.0) * (p.t2 - p.t1)
    assert p.t2 + v2 / (1.0 + p.y3) < p.t3
    advance = (p.y2 - 1.0) * (p.t2 - p.t1) ** 2 / 2.0 + v2 * v2 / (2.0 * (1.0 + p.y3))
    periods = 4
    static = _scene(FrictionLaw("static_kinetic", 1.3), sa.Uniform(), p, periods=periods)
    exact = sa.simulate(static, "exact")
    assert exact.x_end == pytest.approx(periods * advance, rel=1e-13)
    assert sa.simulate(static, "ivp", **IVP_TIGHT).x_end == pytest.approx(periods * advance, rel=1e-9)
    assert sa.simulate(static, "moreau", h=p.dt / 20000).x_end == pytest.approx(periods * advance, rel=1e-3)
    coulomb = sa.simulate(_scene(FrictionLaw(), sa.Uniform(), p, periods=periods), "exact")
    assert abs(coulomb.x_end - periods * advance) > 1e-3


def test_stick_needs_static_limit_to_start_slipping():
    """A stuck mass stays stuck while |y''| <= mu_s/mu_k mu_bar: with mu_s/mu_k above max|y''| the
    mass never slips on a uniform surface (REST at the start), with Coulomb friction it moves."""
    law = FrictionLaw("static_kinetic", 2.3)
    for method in ("exact", "ivp", "moreau"):
        run = sa.simulate(_scene(law, sa.Uniform(), until="rest", max_periods=10), method)
        assert run.status is sa.Status.REST and run.x_end == 0.0
    assert sa.simulate(_scene(FrictionLaw(), sa.Uniform(), periods=2), "exact").x_end > 0.1


@pytest.mark.parametrize("ratio", [1.1, 1.3, 1.5])
def test_no_accumulation_with_static_friction(ratio):
    """With mu_s > mu_k the stick map is not continuous at x_stick_min (eq. 41 for max|y''| / r):
    a mass stuck just below it starts to slip against a kinetic friction y2''/r < y2'' and jumps a
    finite distance, so the sticks never converge; at (y2'', y3'') = (2.3, 1.3), where all Coulomb
    entries accumulate, every entry now rests for good at or beyond x_stick_min, and Delta_x_d > 0."""
    profile = sa.ThreePhaseProfile(1.0, 0.084, 2.3, 1.3)
    assert positioning(profile, w=0.05, c_mu=2.5, n_entries=16).frac_accumulate == 1.0
    pos = positioning(profile, w=0.05, c_mu=2.5, n_entries=16, friction=FrictionLaw("static_kinetic", ratio))
    assert pos.frac_accumulate == 0.0 and pos.frac_stop == 1.0
    assert pos.x_stick_min - pos.x_mu == pytest.approx(0.05 * (2.3 / ratio - 1.0) / 1.5, rel=1e-12)
    assert np.all(pos.x_end >= pos.x_stick_min) and pos.dx_d > 0.0


def test_exact_refuses_stribeck_at_load():
    """The exact solver has no closed-form arcs for Stribeck friction: loading such a scene with
    method exact fails with one line naming the effect and the methods that can simulate it."""
    data = {"profile": {"kind": "three_phase", "dt": 1.05, "dy": 0.084, "y2": 2.2, "y3": 0.9},
            "friction": {"kind": "stribeck", "mu_s_over_mu_k": 1.3, "v_s": 0.01},
            "horizon": {"periods": 3}}
    with pytest.raises(SceneError, match="cannot simulate Stribeck friction.*'ivp' or 'moreau'"):
        scene_from_dict({**data, "solver": {"method": "exact"}})
    with pytest.raises(SceneError, match="fixed_point.*Stribeck"):
        scene_from_dict({**data, "solver": {"method": "moreau", "options": {"iteration": "fixed_point"}}})
    assert scene_from_dict({**data, "solver": {"method": "ivp"}}).friction.stribeck


@pytest.mark.parametrize("block,message", [
    ({"kind": "static_kinetic", "mu_s_over_mu_k": 0.9}, "mu_s_over_mu_k"),
    ({"kind": "static_kinetic"}, "mu_s_over_mu_k"),
    ({"kind": "stribeck", "mu_s_over_mu_k": 1.2}, "v_s"),
    ({"kind": "static_kinetic", "mu_s_over_mu_k": 1.2, "v_s": 0.1}, "v_s"),
    ({"kind": "viscous"}, "kind"),
])
def test_bad_friction_block_is_refused(block, message):
    """A friction block with a ratio below 1, a missing or misplaced parameter or an unknown kind
    is refused at load with the key named."""
    data = {"profile": {"kind": "three_phase", "dt": 1.05, "dy": 0.084, "y2": 2.2, "y3": 0.9},
            "friction": block, "horizon": {"periods": 3}}
    with pytest.raises(SceneError, match=message):
        scene_from_dict(data)


def test_friction_block_round_trips():
    """A scene with a friction block is written back by to_dict and read again unchanged; a
    scene without one writes none (files of the paper's model stay as they were)."""
    scene = _scene(FrictionLaw("stribeck", 1.3, 0.02, 1.5), method="ivp", until="rest", max_periods=50)
    again = scene_from_dict(scene.to_dict())
    assert again.friction == scene.friction
    assert "friction" not in _scene(FrictionLaw()).to_dict()


def test_moreau_stribeck_step_solves_the_implicit_equation():
    """Moreau's implicit step under Stribeck friction returns the slip speed c of c + h mu_bar
    f(c) = u to rounding (f the Stribeck factor), for steep and gentle laws alike."""
    kernel()                                # loads the engine: formulas registered, cache set
    from selfalign.solvers.engine.timestepping import _stribeck_speed as speed

    for u, bound, ratio, v_s, delta in [(1e-3, 1e-4, 1.3, 1e-3, 2.0), (0.5, 1e-3, 1.5, 1e-2, 1.0),
                                        (2e-4, 1e-4, 1.5, 1e-5, 0.5), (1.0, 0.2, 1.1, 0.3, 2.0)]:
        c = speed(u, bound, ratio, v_s, delta)
        f = 1.0 + (ratio - 1.0) * math.exp(-((c / v_s) ** delta))
        assert 0.0 < c <= u - bound
        assert abs(c + bound * f - u) <= 8 * np.finfo(float).eps * u


def test_stribeck_converges_to_static_kinetic():
    """As v_s -> 0 the Stribeck law tends to static/kinetic friction (mu(v) -> mu_k for every v
    != 0, mu(0) = mu_s): the end position of the stop-zone run (ivp, Moreau) converges to the
    exact solver's static/kinetic one, the error shrinking in proportion to v_s (first order: the
    slip loses ~v_s of travel to the extra friction near v = 0)."""
    reference = sa.simulate(_scene(FrictionLaw("static_kinetic", 1.3)), "exact").x_end
    v_s = np.array([1e-2, 1e-3, 1e-4])
    errors = []
    for value in v_s:
        run = sa.simulate(_scene(FrictionLaw("stribeck", 1.3, value)), "ivp", **IVP_TIGHT)
        assert run.status is sa.Status.REST
        errors.append(abs(run.x_end - reference))
    order = np.polyfit(np.log(v_s), np.log(errors), 1)[0]
    assert 0.9 <= order <= 1.1 and errors[-1] < v_s[-1]    # less than v_s times one time unit
    moreau = sa.simulate(_scene(FrictionLaw("stribeck", 1.3, 1e-3)), "moreau", h=1.05 / 20000)
    assert moreau.x_end == pytest.approx(sa.simulate(_scene(FrictionLaw("stribeck", 1.3, 1e-3)), "ivp",
                                                     **IVP_TIGHT).x_end, abs=1e-4)


@pytest.mark.parametrize("rtol", [1e-4, 1e-5, 1e-6, 3e-7, 1e-7, 1e-8])
def test_ivp_keeps_its_tolerance_under_stribeck_friction(rtol):
    """solve_ivp keeps to the tolerance asked for under Stribeck friction: the first period of the
    accuracy_stribeck motion (a slip of speed 0.3 coming to rest, where mu rises from mu_k to mu_s
    within |v| ~ v_s = 0.01) ends within rtol of the same solver at rtol 1e-12.  Fails if a step
    may cross that speed band with no stage inside it: its error estimate then sees kinetic
    friction only, and the stick comes out far off (1.5e-3 at rtol 1e-7, 1e4 rtol)."""
    scene = _scene(FrictionLaw("stribeck", 1.3, 0.01), periods=1)
    reference = sa.simulate(scene, "ivp", rtol=1e-12, atol=1e-14).x_end
    assert abs(sa.simulate(scene, "ivp", rtol=rtol, atol=1e-2 * rtol).x_end - reference) <= rtol


@pytest.mark.parametrize("method", ["exact", "moreau", "ivp"])
def test_rest_message_reports_the_static_limit(method):
    """A mass stuck at x = 0.03 in the zone (mu_bar = 1.9 < max|y''| = 2.2 <= 1.3 mu_bar) rests there
    for good only because of static friction: the REST message names and prints r mu_bar = 2.47, the
    coefficient that holds it, and so states an inequality that is true."""
    zone = sa.StopZone(x_mu=0.0, w=0.05, c_mu=2.5)
    traj = sa.simulate(_scene(FrictionLaw("static_kinetic", 1.3), zone, x0=0.03, until="rest", max_periods=10),
                       method)
    assert traj.status is sa.Status.REST and traj.x_end == 0.03
    held = re.search(r"where mu_s = r mu_bar \(r = mu_s/mu_k = 1\.3\) = (\S+) >= max\|y''\| = (\S+)$", traj.message)
    assert held, traj.message
    assert float(held[1]) == pytest.approx(1.3 * float(zone.coefficient(0.03)), rel=1e-15)
    assert float(held[1]) >= float(held[2]) == 2.2
