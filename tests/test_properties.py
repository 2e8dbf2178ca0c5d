"""Property-based tests over random feasible scenes (docs/explanation/robustness.md).

Hypothesis profiles: ``ci`` (the default; derandomized, so every run draws the same
examples, bounded max_examples, no deadline on a loaded machine) and ``dev`` (random,
more examples): ``HYPOTHESIS_PROFILE=dev pytest tests/test_properties.py``.

Scenes: a feasible three-phase profile (q = sqrt(8 dy (1/y2 + 1/y3)) / dt drawn in
[0.05, 1], docs/explanation/model.md) on a uniform surface or a stop zone, from a
random start state and phase, for a few periods.
"""

import math
import os

import numpy as np
from hypothesis import HealthCheck, given, settings
from hypothesis import strategies as st

import selfalign as sa
from selfalign.solvers.outcomes import STICK

settings.register_profile("ci", derandomize=True, database=None, max_examples=60, deadline=None,
                          suppress_health_check=[HealthCheck.too_slow])
settings.register_profile("dev", max_examples=300, deadline=None)
settings.load_profile(os.environ.get("HYPOTHESIS_PROFILE", "ci"))

PERIODS = 3


@st.composite
def scenes(draw, record=sa.Record()):
    dt = draw(st.floats(0.3, 3.0))
    y2 = draw(st.floats(0.3, 5.0))
    y3 = draw(st.floats(0.3, 5.0))
    q = draw(st.floats(0.05, 1.0))
    dy = (q * dt) ** 2 / (8.0 * (1.0 / y2 + 1.0 / y3))
    profile = sa.ThreePhaseProfile(dt, dy, y2, y3)
    if draw(st.booleans()):
        surface = sa.StopZone(draw(st.floats(-0.05, 0.2)), draw(st.floats(0.01, 0.3)), draw(st.floats(1.0, 6.0)))
    else:
        surface = sa.Uniform()
    return sa.Scene(profile, surface, x0=draw(st.floats(-0.1, 0.1)), v0=draw(st.floats(-0.5, 0.5)),
                    phase=draw(st.floats(0.0, 0.999)), periods=PERIODS, record=record)


def motion_scale(scene):
    """Largest relative displacement the scene can reach: velocity swing times the horizon."""
    p = scene.profile
    return (abs(scene.v0) + 2.0 * (p.max_abs_acceleration + 1.0) * p.dt) * p.dt * PERIODS


def assert_finite(traj):
    assert math.isfinite(traj.x_end) and math.isfinite(traj.v_end) and math.isfinite(traj.tau_end)
    for name, values in traj.series.items():
        assert np.all(np.isfinite(values)), name


@given(scenes())
def test_exact_and_ivp_agree(scene):
    """The exact solver and the solve_ivp baseline (rtol 1e-12, atol 1e-14) agree on the end
    state to 1e-10 of the motion scale (exact vs ivp at rtol 1e-10); no NaN."""
    exact = sa.simulate(scene, "exact")
    ivp = sa.simulate(scene, "ivp", rtol=1e-12, atol=1e-14)
    assert_finite(exact)
    assert_finite(ivp)
    assert exact.status is ivp.status is sa.Status.HORIZON, (exact.message, ivp.message)
    scale = motion_scale(scene)
    assert abs(exact.x_end - ivp.x_end) <= 1e-10 * (scale + abs(scene.x0))
    v_scale = (scene.profile.max_abs_acceleration + 1.0) * scene.profile.dt
    assert abs(exact.v_end - ivp.v_end) <= 1e-10 * v_scale


@given(scenes())
def test_moreau_within_first_order_of_exact(scene):
    """Moreau with h = dt/2000 stays within O(h) of the exact solution: |dx| <= 20 periods h
    (1 + max|y''|) (a first-order scheme; the constant allows for a stick/slip decision
    shifted by one step at each of the few events per period); no NaN."""
    exact = sa.simulate(scene, "exact")
    h = scene.profile.dt / 2000
    moreau = sa.simulate(scene, "moreau", h=h)
    assert_finite(moreau)
    bound = 20 * PERIODS * h * (1.0 + scene.profile.max_abs_acceleration)
    assert abs(exact.x_end - moreau.x_end) <= bound, (exact.x_end, moreau.x_end, bound)


SERIES = sa.Record(series=("x", "v", "ydd", "friction", "mode"), samples_per_period=100, events=True)


@given(scenes(record=SERIES), st.sampled_from(["exact", "moreau", "ivp"]))
def test_friction_dissipates_and_sticks_only_when_allowed(scene, method):
    """Coulomb friction never does positive work on the relative motion: the recorded
    ``friction`` is the paper's F_f = -(x'' + y'') in mu_bar Sign(x') (eq. 5), the force on the
    mass is -F_f, so its power -F_f x' is <= 0 at every sample, and |F_f| <= mu_bar(x).  The
    mass is recorded stuck only with v = 0 where the stick condition |y''| <= mu_bar(x) holds
    (Sect. 3.2; ties stick).  No NaN."""
    traj = sa.simulate(scene, method)
    assert_finite(traj)
    F, v, mode, ydd, x = traj.friction, traj.v, traj.mode, traj.ydd, traj.x
    mu = scene.surface.coefficient(x)
    assert np.all(-F * v <= 1e-12 * np.abs(v)), (-F * v).max()
    assert np.all(np.abs(F) <= mu * (1 + 1e-12))
    stuck = mode == STICK
    assert np.all(v[stuck] == 0.0)
    assert np.all(np.abs(ydd[stuck]) <= mu[stuck] * (1 + 1e-12))


@given(scenes(record=SERIES), st.sampled_from(["exact", "moreau", "ivp"]))
def test_bit_for_bit_deterministic(scene, method):
    """The same scene gives bit-identical end states, series and event logs on every run."""
    a, b = sa.simulate(scene, method), sa.simulate(scene, method)
    assert (a.x_end, a.v_end, a.period_end, a.tau_end, a.status) == (b.x_end, b.v_end, b.period_end,
                                                                        b.tau_end, b.status)
    assert a.series.keys() == b.series.keys()
    for name in a.series:
        np.testing.assert_array_equal(a.series[name], b.series[name])
    if a.events is not None:
        assert a.events.tobytes() == b.events.tobytes()
