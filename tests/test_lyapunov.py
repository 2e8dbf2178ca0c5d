"""Convergence of velocity solutions (Sect. 6.2, eqs. 34-37, Fig. 13): the claims of the
section, checked on exact trajectories (event-driven solver, V exact at every event)."""

import numpy as np
import pytest

from selfalign import FourierProfile, PolynomialProfile, Scene, StopZone, ThreePhaseProfile, load_scene
from selfalign.analysis.lyapunov import lyapunov_trace, scene_trace
from selfalign.analysis.steady_state import steady_state
from selfalign.io.hdf5 import read_h5, write_h5
from selfalign.io.recording import read_recording, write_recording
from selfalign.solvers.driver import simulate_batch
from selfalign.stages.convergence import convergence_recording, convergence_result

EPS = np.finfo(float).eps

#: One profile per case of Table 1 (the settings of the fig09 and stability_case4 scenes).
CASES = {
    1: ThreePhaseProfile(1.05, 0.084, 2.2, 0.9),
    2: ThreePhaseProfile(1.05, 0.084, 0.9, 2.2),
    3: ThreePhaseProfile(1.05, 0.084, 2.2, 1.8),
    4: ThreePhaseProfile(1.0, 0.2, 5.0, 3.0),
    5: ThreePhaseProfile(1.38, 0.064, 0.8, 0.8),
}
#: Pairs of initial velocities: same sign, opposite signs, one at rest, far apart.
PAIRS = [(1.5, 0.3), (0.8, -0.6), (0.0, -1.2), (3.0, -2.5)]


def test_cases_are_as_labelled():
    """The settings of CASES are the cases of Table 1 they stand for (classification, Fig. 8)."""
    assert {c: steady_state(p).case for c, p in CASES.items()} == {c: c for c in CASES}


@pytest.fixture(scope="module")
def traces():
    """(case, v10, v20, trace) over every case and pair, 8 periods."""
    return [(c, a, b, lyapunov_trace(p, a, b, 8, samples_per_period=50))
            for c, p in CASES.items() for a, b in PAIRS]


def test_V_never_increases(traces):
    """Eq. (36): V' <= 0, so V(t) is non-increasing: at every sample (grid and all events)
    V(t_k+1) <= V(t_k) up to rounding, 8 eps V(0)."""
    for case, a, b, tr in traces:
        assert np.all(np.diff(tr.V) <= 8 * EPS * tr.V[0]), (case, a, b)


def test_V_derivative_on_equal_and_different_intervals(traces):
    """Sect. 6.2, Fig. 13: "in the time intervals where v1^ = v2^ ... V' = 0", "where
    v1^ != v2^, the solutions converge to each other and V' < 0".  With v^ the selected
    element of Sign(v) (the slip direction, or -y'' in stick): on every "=" sub-interval
    V' = (v1 - v2)(x1'' - x2'') is exactly 0 at both ends; on every "!=" sub-interval with
    V > 0 it is < 0 at the start and V drops strictly across it.  Both kinds occur."""
    for case, a, b, tr in traces:
        eq, ne = tr.sub_equal, ~tr.sub_equal
        assert np.all(tr.dV_start[eq] == 0.0) and np.all(tr.dV_end[eq] == 0.0), (case, a, b)
        Vs, Ve = tr.V[np.searchsorted(tr.t, tr.sub_start)], tr.V[np.searchsorted(tr.t, tr.sub_end)]
        live = ne & (Vs > 0.0)
        assert np.all(tr.dV_start[live] < 0.0), (case, a, b)
        assert np.all(Ve[live] < Vs[live]), (case, a, b)
        assert np.all(tr.dV_end[live] <= 0.0)
    assert any((~tr.sub_equal).any() and tr.sub_equal.any() for *_, tr in traces)


def test_labels_follow_the_selected_sign():
    """The label of v = 0: a mass in stick selects v^ = -y'' (|y''| <= 1), so one stuck and one
    slipping trajectory are "!=" (V' < 0), and two stuck ones are "=" with v1 = v2 = 0."""
    tr = lyapunov_trace(CASES[1], 0.0, 0.5, 1, samples_per_period=20)
    first = tr.sub_start == 0.0
    assert tr.s1[first][0] == 0.0 and tr.s2[first][0] == 1.0 and not tr.sub_equal[first][0]
    both_stuck = tr.sub_equal & (np.abs(tr.s1) < 1.0)
    assert both_stuck.any()
    t_mid = 0.5 * (tr.sub_start + tr.sub_end)[both_stuck]
    np.testing.assert_array_equal(tr.s1[both_stuck], -CASES[1].acceleration(t_mid))


@pytest.mark.parametrize("case", [1, 2, 3, 5])
def test_V_reaches_zero_in_finite_time(traces, case):
    """Sect. 6.2: "for cases 1-3 solutions, in finite time a point will be reached at which
    v1 = v2 = 0"; from then on the velocities are identical (V = 0 exactly, bit for bit).
    Also for pure stick (case 5)."""
    for c, a, b, tr in traces:
        if c != case:
            continue
        assert np.isfinite(tr.converged_time), (a, b)
        after = tr.t >= tr.converged_time
        assert np.all(tr.V[after] == 0.0) and np.all(tr.v1[after] == tr.v2[after])
        assert tr.V[0] > 0.0 and tr.converged_time < tr.t[-1]


def test_case4_decays_geometrically_at_lambda2_squared(traces):
    """Case 4 (slip-slip): the mass never sticks, V > 0 for all t, and V -> 0 only as
    t -> infinity.  Precisely: once both trajectories pass their reversals in the same phases,
    v1 - v2 is multiplied by lambda2 = (y2-1)(y3-1)/((y2+1)(y3+1)) = 1/3 (eq. 33) every
    period, so V(t + dt) = lambda2^2 V(t) = V(t) / 9 -- at the period boundaries and at every
    other phase (rtol 1e-8, 50 phases per period, from the sixth period on: the initial
    velocities here are up to 10 times the steady one, so the transient lasts ~5 periods)."""
    spp = 50
    for c, a, b, tr in traces:
        if c != 4:
            continue
        assert np.all(tr.V > 0.0) and np.isnan(tr.converged_time)
        grid = np.arange(8 * spp + 1) / spp
        idx = np.searchsorted(tr.t, grid)
        np.testing.assert_array_equal(tr.t[idx], grid)
        ratio = tr.V[idx][spp:] / tr.V[idx][:-spp]
        np.testing.assert_allclose(ratio[5 * spp:], 1.0 / 9.0, rtol=1e-8)
        np.testing.assert_allclose(tr.period_V[6:] / tr.period_V[5:-1], 1.0 / 9.0, rtol=1e-8)


@pytest.mark.parametrize("case", sorted(CASES))
def test_steady_velocity_is_unique(case):
    """Sect. 6.2: "the steady-state solution in terms of velocity is unique and is independent
    of the initial velocity".  From 41 initial velocities in [-3, 3] the velocity at the
    period boundary after 40 periods is the same to machine precision (4 eps of the velocity
    swing; bit-identical where the steady state sticks), and equals the closed-form v0."""
    p = CASES[case]
    ends = simulate_batch(p, 0.0, np.linspace(-3.0, 3.0, 41), until="periods", periods=40).v_end
    scale = max(p.y2 * (p.t2 - p.t1), 1.0)
    if case == 4:
        assert np.ptp(ends) <= 4 * EPS * scale
    else:
        assert np.ptp(ends) == 0.0
    assert ends[0] == pytest.approx(steady_state(p).v0, abs=4 * EPS * scale)


def test_other_profiles_converge_too():
    """The argument of Sect. 6.2 uses only the zero mean of y'' over a period (eq. 37): V never
    increases and reaches 0 also for the polynomial and a Fourier profile."""
    for p in (PolynomialProfile(1.0, 0.1, 0.7), FourierProfile(1.0, [0.05, 0.01], [0.0, 0.02])):
        tr = lyapunov_trace(p, 1.0, -0.7, 6, samples_per_period=40)
        assert np.all(np.diff(tr.V) <= 8 * EPS * tr.V[0])
        assert np.isfinite(tr.converged_time)
        assert np.all(tr.dV_start[tr.sub_equal] == 0.0)


def test_convergence_result_and_recording(repo, tmp_path):
    """The stage's outputs: results/convergence/<scene>.h5 holds t, v1, v2, V and the labelled
    intervals (contiguous, covering the horizon); the rerun recording holds v1, v2 and V."""
    scene = load_scene(repo / "workflow/scenes/fig13.yaml")
    h5 = tmp_path / "fig13.h5"
    write_h5(h5, *convergence_result(scene, 0.3))
    result = read_h5(h5)
    d, a = result["datasets"], result["attrs"]
    assert {"t", "v1", "v2", "V", "interval_start", "interval_end", "interval_equal"} <= set(d)
    assert d["interval_start"][0] == 0.0 and d["interval_end"][-1] == pytest.approx(3 * 1.05, rel=1e-15)
    np.testing.assert_array_equal(d["interval_start"][1:], d["interval_end"][:-1])
    assert np.all(d["interval_equal"][1:] != d["interval_equal"][:-1])
    assert (a["v10"], a["v20"], a["case"]) == (1.5, 0.3, 1) and 0 < a["converged_time"] < 3 * 1.05
    np.testing.assert_array_equal(d["V"], 0.5 * (d["v1"] - d["v2"]) ** 2)
    rrd = write_recording(tmp_path / "fig13.rrd", convergence_recording(result))
    rec = read_recording(rrd)
    assert set(rec) == {"velocity/v1", "velocity/v2", "lyapunov/V"}
    np.testing.assert_array_equal(rec["lyapunov/V"][1], d["V"])


@pytest.mark.parametrize("call, error, message", [
    (lambda: scene_trace(Scene(CASES[1], StopZone(0.5, 0.05, 2.5), periods=2), 0.1), ValueError, "uniform surface"),
    (lambda: scene_trace(Scene(CASES[1], until="rest"), 0.1), ValueError, "horizon.periods"),
    (lambda: lyapunov_trace(CASES[1], 0.0, float("nan"), 2), ValueError, "v20 must be a finite number"),
    (lambda: lyapunov_trace(CASES[1], 0.0, 1.0, 0), ValueError, "periods must be an integer >= 1"),
    (lambda: lyapunov_trace(CASES[1], 0.0, 1.0, 2, phase=1.0), ValueError, "phase must lie in [0, 1)"),
    (lambda: lyapunov_trace("profile", 0.0, 1.0, 2), TypeError, "profile or Scene"),
])
def test_bad_input_is_rejected(call, error, message):
    """Bad input raises a one-line ValueError naming the quantity (TypeError for a string where a
    profile or Scene is expected)."""
    with pytest.raises(error, match=message.replace("[", r"\[").replace("(", r"\(").replace(")", r"\)")):
        call()
