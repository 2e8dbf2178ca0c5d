"""Floquet multipliers of the steady state by three methods (Sect. 6.1, eqs. 25-33).

The analytic monodromy (closed-form one-period map), the saltation-matrix product over
the exact solver's events, and finite differences of the period map must agree; the
structure of eqs. (30) and (33) is checked case by case."""

import re

import numpy as np
import pytest

from selfalign import (
    FourierProfile,
    PolynomialProfile,
    Record,
    Scene,
    StopZone,
    ThreePhaseProfile,
    load_scene,
    simulate,
)
from selfalign.analysis.floquet import EXACT_EPS, floquet, monodromy_from_record, periodic_motion, saltation_matrix
from selfalign.analysis.steady_state import steady_state_grid
from selfalign.solvers.outcomes import EventKind
from selfalign.stages.stability import stability_grid, stability_result

#: Grids of three-phase settings (dt, dy, y2'' = y3'' axis): Fig. 17's setting holds cases 1-4,
#: Fig. 11's cases 1, 2, 3, 5 (see tests/test_steady_state.py); dt = 1, dy = 0.2 adds a
#: case 4 region with lambda2 up to ~0.4.
GRIDS = [(1.0, 0.084, np.linspace(0.3, 6.0, 11)), (1.38, 0.064, np.linspace(0.1, 3.0, 11)),
         (1.0, 0.2, np.linspace(1.5, 8.0, 6))]


def grid_profiles():
    """(case, profile) for every feasible point of GRIDS."""
    out = []
    for dt, dy, axis in GRIDS:
        y2, y3 = np.meshgrid(axis, axis, indexing="ij")
        case = steady_state_grid(dt, dy, y2, y3).case
        out += [(int(c), ThreePhaseProfile(dt, dy, a, b)) for c, a, b in zip(case.ravel(), y2.ravel(), y3.ravel())
                if c > 0]
    return out


@pytest.fixture(scope="module")
def profiles():
    found = grid_profiles()
    assert {c for c, _ in found} == {1, 2, 3, 4, 5}
    return found


@pytest.fixture(scope="module")
def analytic(profiles):
    return [floquet(p, "analytic") for _, p in profiles]


def test_saltation_equals_analytic_for_every_case(profiles, analytic):
    """Sect. 6.1: "The analysis using Saltation matrices to compute the Monodromy matrix gives
    identical results" as the analytic linearisation, for all five cases: monodromy entries
    and multipliers agree to 1e-10."""
    for (case, p), a in zip(profiles, analytic):
        s = floquet(p, "saltation")
        assert np.abs(s.monodromy - a.monodromy).max() <= 1e-10, (case, p, s.monodromy, a.monodromy)
        assert np.abs(s.multipliers - a.multipliers).max() <= 1e-10, (case, p)


def test_numeric_exact_equals_analytic(profiles, analytic):
    """Sect. 6.1, method 3 with the exact solver: central differences (eps = 1e-7) of the
    period map agree with the analytic monodromy to 1e-6 (error O(eps) where a stick kinks
    the map, O(eps^2) elsewhere)."""
    for (case, p), a in zip(profiles, analytic):
        n = floquet(p, "numeric")
        assert n.info == {"solver": "exact", "eps": EXACT_EPS}
        assert np.abs(n.monodromy - a.monodromy).max() <= 1e-6, (case, p, n.monodromy, a.monodromy)


def test_monodromy_structure_eqs_30_33(profiles, analytic):
    """Eqs. (30), (33): M = [[1, m12], [0, lambda2]].  lambda1 = 1 with eigenvector [1, 0] (the
    freedom in position) in every case; lambda2 = 0 in cases 1, 2, 3 and in pure stick (case 5,
    not treated in the paper); lambda2 = c4 = (y2-1)(y3-1)/((y2+1)(y3+1)) in case 4, in (0, 1);
    in case 1 (and 5), started in stick at t0, m12 = 0 and v2 = [0, 1] (eq. 30).  Exact to 1e-12."""
    for (case, p), a in zip(profiles, analytic):
        m = a.monodromy
        np.testing.assert_allclose(m[:, 0], [1.0, 0.0], atol=1e-12)
        assert a.multipliers[0] == pytest.approx(1.0, abs=1e-12)
        v1 = a.eigenvectors[:, 0]
        np.testing.assert_allclose(np.abs(v1), [1.0, 0.0], atol=1e-12)
        c4 = (p.y2 - 1) * (p.y3 - 1) / ((p.y2 + 1) * (p.y3 + 1))
        lam2 = c4 if case == 4 else 0.0
        assert a.multipliers[1] == pytest.approx(lam2, abs=1e-12), (case, p)
        if case == 4:
            assert 0.0 < lam2 < 1.0
            v2 = a.eigenvectors[:, 1] / a.eigenvectors[1, 1]
            np.testing.assert_allclose(v2, [m[0, 1] / (lam2 - 1.0), 1.0], rtol=1e-12)
        if case in (1, 5) and p.t1 > 0:
            assert m[0, 1] == 0.0
            np.testing.assert_allclose(np.abs(a.eigenvectors[:, 1]), [0.0, 1.0], atol=1e-12)


def one_period(profile, v0):
    """One period from x'(0) = v0 with arcs and events recorded."""
    return simulate(Scene(profile, v0=v0, periods=1, record=Record(events=True, arcs=True)))


def test_case4_lambda2_is_the_slope_ratio_product():
    """Eq. (33) by hand for y2'' = 5, y3'' = 3: lambda2 = (4 * 2) / (6 * 4) = 1/3, and the two
    REVERSAL saltation entries are the slope ratios (y2 - 1)/(y2 + 1) = 2/3 and
    (y3 - 1)/(y3 + 1) = 1/2 (to 1e-15)."""
    p = ThreePhaseProfile(1.0, 0.2, 5.0, 3.0)
    s = floquet(p, "saltation")
    assert s.multipliers[1] == pytest.approx(1.0 / 3.0, rel=1e-15)
    step = one_period(p, s.motion.v0)
    ratios = sorted(saltation_matrix(e["kind"], e["v"], e["acc_before"], e["acc_after"])[1, 1]
                    for e in step.events if e["kind"] == EventKind.REVERSAL)
    np.testing.assert_allclose(ratios, [0.5, 2.0 / 3.0], rtol=1e-15)


def test_saltation_matrix_per_event_kind():
    """Saltation matrices (Leine & Nijmeijer, ref. [11]): time events (SWITCH, SLIP) identity;
    STICK [[1, 0], [0, 0]] (the sliding mode x' = 0 absorbs velocity perturbations); REVERSAL
    diag(1, a+/a-); ZONE [[1, 0], [(a+ - a-)/v, 1]], identity when x'' is continuous; a
    grazing event (x'' = 0 before x' = 0, or a zone crossing at x' = 0) raises."""
    np.testing.assert_array_equal(saltation_matrix(EventKind.SWITCH, 0.3, 1.2, -1.9), np.eye(2))
    np.testing.assert_array_equal(saltation_matrix(EventKind.SLIP, 0.0, 0.0, 1.2), np.eye(2))
    np.testing.assert_array_equal(saltation_matrix(EventKind.STICK, 0.0, -1.9, 0.0), [[1, 0], [0, 0]])
    np.testing.assert_array_equal(saltation_matrix(EventKind.REVERSAL, 0.0, -6.0, -4.0), [[1, 0], [0, 4 / 6]])
    np.testing.assert_array_equal(saltation_matrix(EventKind.ZONE, 0.2, -1.5, -1.5), np.eye(2))
    np.testing.assert_array_equal(saltation_matrix(EventKind.ZONE, 0.5, -1.0, -2.0), [[1, 0], [-2, 1]])
    with pytest.raises(ValueError, match="grazes"):
        saltation_matrix(EventKind.STICK, 0.0, 0.0, 0.0)
    with pytest.raises(ValueError, match="grazes"):
        saltation_matrix(EventKind.ZONE, 0.0, -1.0, -1.0)


def test_saltation_needs_the_reversal_matrix():
    """The REVERSAL saltation matrices carry lambda2 of case 4 (eq. 33): with the identity in
    their place the arcs alone give lambda2 = 1 (perturbations of x' would never decay), so
    the agreement with the analytic result is not automatic."""
    p = ThreePhaseProfile(1.0, 0.2, 5.0, 3.0)
    motion = periodic_motion(p)
    step = one_period(p, motion.v0)
    m, info = monodromy_from_record(step.arcs, step.events)
    assert info["events"]["reversal"] == 2 and info["grazing_events"] == 0
    identity = step.events.copy()
    reversal = identity["kind"] == EventKind.REVERSAL
    identity["acc_after"][reversal] = identity["acc_before"][reversal]
    wrong, _ = monodromy_from_record(step.arcs, identity)
    np.testing.assert_allclose(m, floquet(p, "analytic").monodromy, atol=1e-12)
    assert wrong[1, 1] == 1.0


@pytest.fixture
def zone_scene(repo):
    return load_scene(repo / "workflow/scenes/stability_zone.yaml")


def test_periodic_motion_inside_the_stop_zone(zone_scene):
    """Beyond the five cases: a periodic motion inside the transition zone (Sect. 7 surface,
    eq. 9).  Found by simulation; saltation and numeric (exact solver) monodromies agree to
    1e-6; with mu_bar depending on x there is no position freedom, so both multipliers lie
    strictly inside the unit circle (|lambda| < 0.1 here): the motion is asymptotically stable."""
    s = floquet(zone_scene, "saltation")
    n = floquet(zone_scene, "numeric")
    m = s.motion
    assert zone_scene.surface.x_mu < m.x0 < zone_scene.surface.x_end and m.periods == 1 and m.advance == 0.0
    assert s.info["events"]["zone"] == 0 and s.info["events"]["reversal"] == 1
    assert np.abs(n.monodromy - s.monodromy).max() <= 1e-6
    assert np.all(np.abs(s.multipliers) < 0.1)
    assert abs(s.monodromy[1, 0]) > 1e-2          # x enters the dynamics through mu_bar(x)


def test_zone_crossing_orbit():
    """A periodic motion that crosses the end of the transition zone, x_mu + w, twice every
    period (ZONE events, where the arc changes from harmonic/hyperbolic to quadratic):
    saltation agrees with the numeric monodromy to 1e-6."""
    scene = Scene(ThreePhaseProfile(1.05, 0.084, 3.0, 3.5), StopZone(0.5, 1.0, 2.0), until="rest")
    s = floquet(scene, "saltation", max_periods=3000)
    n = floquet(scene, "numeric", max_periods=3000)
    assert s.info["events"]["zone"] == 2, s.info
    assert np.abs(n.monodromy - s.monodromy).max() <= 1e-6, (s.monodromy, n.monodromy)


@pytest.mark.parametrize("profile", [PolynomialProfile(0.05, 0.02), PolynomialProfile(1.0, 0.1, 0.7),
                                     FourierProfile(1.0, [0.05, 0.01], [0.0, 0.02])],
                         ids=["polynomial-slip-slip", "polynomial-stick-slip", "fourier"])
def test_saltation_for_other_profiles(profile):
    """Method 2 is general: for the polynomial (Sect. 4.2) and Fourier (Sect. 4.4.2) profiles
    the saltation monodromy agrees with finite differences of the exact solver to 1e-6 and
    has the position multiplier 1 with eigenvector [1, 0] on the uniform surface."""
    s = floquet(profile, "saltation")
    n = floquet(profile, "numeric")
    assert np.abs(n.monodromy - s.monodromy).max() <= 1e-6
    assert s.multipliers[0] == pytest.approx(1.0, abs=1e-12)
    np.testing.assert_allclose(np.abs(s.eigenvectors[:, 0]), [1.0, 0.0], atol=1e-12)
    assert 0.0 <= s.multipliers[1] < 1.0


def test_moreau_estimate_is_limited_by_the_step():
    """Method 3 with Moreau time stepping (case 4, lambda2 = 1/3).  The scheme's period map
    v0 -> v(dt) is a continuous staircase at the scale of one step: where a reversal's
    velocity lands in the stick window |v*| <= h mu_bar of the implicit friction impulse the
    perturbation is erased (slope 0), elsewhere the steps pass it on unchanged (slope 1).
    So the local derivative (eps << h) is 0 or 1, never lambda2; the share of slope-1 stairs
    is lambda2 (to 1 % over 40 h); and a secant over eps >> h averages the stairs with an
    error below h / eps (h = 1e-3 and 1e-4, eps = 1e-2)."""
    from selfalign.solvers.driver import simulate_batch

    p = ThreePhaseProfile(1.0, 0.2, 5.0, 3.0)
    local = floquet(p, "numeric", solver="moreau", h=1e-3, eps=1e-7).multipliers[1]
    assert min(abs(local), abs(local - 1.0)) <= 1e-8, local
    v = floquet(p, "analytic").motion.v0 + np.linspace(-0.02, 0.02, 40001)
    ends = simulate_batch(p, 0.0, v, until="periods", periods=1, method="moreau", h=1e-3, fast_forward=False).v_end
    slopes = np.diff(ends) / np.diff(v)
    assert np.max(np.abs(np.diff(ends))) <= 2e-6                   # continuous: no jumps
    assert np.mean(np.abs(slopes - 1.0) <= 1e-6) == pytest.approx(1 / 3, rel=0.01)
    for h in (1e-3, 1e-4):
        error = abs(floquet(p, "numeric", solver="moreau", h=h, eps=1e-2).multipliers[1] - 1 / 3)
        assert error <= h / 1e-2, (h, error)


def test_one_period_map_is_a_fixed_point(profiles):
    """The monodromy is taken about the steady state: x'(t0 + dt) = x'(t0) for the closed-form
    start (to 1e-12), and the simulated periodic motion of a Fourier profile repeats bit for bit."""
    for _, p in profiles[::7]:
        m = periodic_motion(p)
        assert one_period(p, m.v0).v_end == pytest.approx(m.v0, abs=1e-12)
    f = FourierProfile(1.0, [0.05, 0.01], [0.0, 0.02])
    m = periodic_motion(f)
    again = simulate(Scene(f, v0=m.v0, periods=m.periods))
    assert again.v_end == m.v0 and m.source.startswith("simulated")


@pytest.mark.parametrize("call, error, message", [
    (lambda p: floquet(p, "exact"), ValueError, "method must be one of"),
    (lambda p: floquet(p, "saltation", eps=1e-3), ValueError, "unknown option"),
    (lambda p: floquet(p, "numeric", solver="ivp"), ValueError, "option solver"),
    (lambda p: floquet(p, "numeric", h=1e-3), ValueError, "applies to solver='moreau' only"),
    (lambda p: floquet(p, "numeric", eps=0.0), ValueError, "option eps"),
    (lambda p: floquet(p, "saltation", max_periods=0), ValueError, "option max_periods"),
    (lambda p: floquet(Scene(p, StopZone(0.5, 0.05, 3.0), periods=1), "analytic"), ValueError,
     "needs a ThreePhaseProfile"),
    (lambda p: floquet(PolynomialProfile(1.0, 0.1), "analytic"), ValueError, "needs a ThreePhaseProfile"),
    (lambda p: floquet((1.0, 0.2, 5.0, 3.0), "analytic"), TypeError, "profile or Scene"),
])
def test_bad_input_is_rejected(call, error, message):
    """Bad input raises a one-line ValueError naming the quantity (TypeError for a tuple where a
    profile or Scene is expected)."""
    with pytest.raises(error, match=re.escape(message)):
        call(ThreePhaseProfile(1.0, 0.2, 5.0, 3.0))


def test_no_periodic_motion_is_reported():
    """An accumulation towards x_stick_min (Sect. 7.3) has no periodic motion: within 10
    periods the stick positions still creep up, and a clear ValueError says so instead of
    returning a monodromy of a motion that is not periodic."""
    scene = Scene(ThreePhaseProfile(1.05, 0.084, 2.2, 0.9), StopZone(0.5, 0.05, 2.5), until="rest")
    with pytest.raises(ValueError, match="no periodic motion found"):
        floquet(scene, "saltation", max_periods=10)


def test_stability_result_layout(repo):
    """The stage's per-scene result: every method, the reference first, and differences from it."""
    scene = load_scene(repo / "workflow/scenes/stability_case4.yaml")
    d, a = stability_result(scene, moreau_steps=(100,), moreau_eps=(1e-2,))
    assert d["methods"].tolist() == ["analytic", "saltation", "numeric_exact", "numeric_moreau"]
    assert d["monodromy"].shape == (4, 2, 2) and d["multipliers"].shape == (4, 2)
    assert d["monodromy_error"][0] == 0.0 and d["monodromy_error"][1] <= 1e-10 and d["monodromy_error"][2] <= 1e-6
    assert d["moreau_multipliers"].shape == (1, 1, 2) and a["case"] == 4 and a["reference"] == "analytic"


def test_stability_grid_layout():
    """The stage's grid result: NaN for case 0, agreement of saltation (1e-10) and numeric
    exact (1e-6) with the analytic monodromy over the grid."""
    d, a = stability_grid(1.0, 0.084, np.array([0.5, 2.0, 5.0]), np.array([0.9, 3.0]), moreau_steps=100)
    assert d["monodromy"].shape == (4, 3, 2, 2, 2) and d["case"].shape == (3, 2)
    infeasible = d["case"] == 0
    assert infeasible.any() and np.isnan(d["monodromy"][:, infeasible]).all()
    assert a["max_monodromy_error"]["saltation"] <= 1e-10 and a["max_monodromy_error"]["numeric_exact"] <= 1e-6


def documented_stability_rows(text):
    """Rows of the multiplier table of the docs' stability page: scene -> (lambda2 by analytic,
    saltation, numeric exact, numeric Moreau)."""
    rows = {}
    for line in text.splitlines():
        cells = [c.strip() for c in line.strip().strip("|").split("|")]
        if len(cells) == 8 and cells[0].startswith("`"):
            rows[cells[0].strip("`")] = cells
    return rows


def test_documented_table_matches_the_code(repo):
    """The docs' table of multipliers (Sect. 6.1, docs/explanation/stability.md) is what the code
    computes, to the printed digits."""
    rows = documented_stability_rows((repo / "docs/explanation/stability.md").read_text())
    assert {"fig09_case1", "fig09_case4", "stability_case4", "stability_zone", "polynomial"} <= set(rows)
    for name, cells in rows.items():
        scene = load_scene(repo / f"workflow/scenes/{name}.yaml")
        printed = {"analytic": cells[3], "saltation": cells[4], "numeric": cells[5], "moreau": cells[6]}
        for label, text in printed.items():
            if text == "—":
                continue
            method, opts = {"analytic": ("analytic", {}), "saltation": ("saltation", {}),
                            "numeric": ("numeric", {}), "moreau": ("numeric", {"solver": "moreau"})}[label]
            lam = floquet(scene, method, **opts).multipliers
            shown = [float(v) for v in text.split(",")]
            digits = [len(v.strip().split(".")[1]) if "." in v else 0 for v in text.split(",")]
            for value, want, k in zip(lam.real, shown, digits):
                assert abs(value - want) <= 0.5 * 10.0 ** -k + 1e-15, (name, label, lam, text)
