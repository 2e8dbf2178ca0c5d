"""The work-precision study (selfalign.analysis.accuracy) on small settings: orders and agreement, no timings.

CPU times are measured but never asserted (they go to results/accuracy and
results/benchmarks); the tests check the fitted Moreau order, the agreement of
solve_ivp with the exact solver and the study's bookkeeping.
"""

import math

import numpy as np
import pytest

from selfalign import load_scene, simulate
from selfalign.analysis.accuracy import StudySettings, fit_loglog, loglog_interpolate, study
from selfalign.analysis.steady_state import steady_state
from selfalign.io.hdf5 import read_h5, write_h5

#: solve_ivp forms its Runge-Kutta stages with np.dot (BLAS): .ci/run reruns these under other kernels.
pytestmark = pytest.mark.blas

#: Small settings: Moreau n = 100 .. 1e5 steps per period (3 decades, 13 values), solve_ivp at
#: three tolerances, every run timed once.
SMALL = StudySettings(moreau_steps_per_period=(100, 100_000, 13), ivp_rtol=(1e-4, 1e-8, 3),
                      fit_min_steps_per_period=100, min_timing=1e-9)


@pytest.fixture(scope="module")
def studies():
    from conftest import REPO

    out = {}
    for name in ("accuracy_steady", "accuracy_stop"):
        scene = load_scene(REPO / f"workflow/scenes/{name}.yaml")
        out[name] = (scene, study(scene, SMALL))
    return out


@pytest.mark.parametrize("name", ["accuracy_steady", "accuracy_stop"])
def test_moreau_is_first_order(studies, name):
    """Moreau's midpoint time-stepping (Sect. 4.1) is first order at the nonsmooth events: the fitted
    order of the end-position error (Theil-Sen over h = dt/100 .. dt/1e5) lies in [0.8, 1.2], with a
    uniform surface and with accumulation in a stop zone; likewise the error of vbar."""
    _, (_, attrs, groups) = studies[name]
    assert 0.8 <= attrs["moreau_order"] <= 1.2, attrs["moreau_order"]
    assert 0.8 <= attrs["moreau_order_vbar"] <= 1.2, attrs["moreau_order_vbar"]
    assert attrs["moreau_fit_points"] >= 10
    err = groups["moreau"]["datasets"]["err_end_position"]
    assert err[-1] < err[0] / 100  # three decades of h buy at least two of error


@pytest.mark.parametrize("name", ["accuracy_steady", "accuracy_stop"])
def test_ivp_agrees_with_exact_to_its_tolerance(studies, name):
    """solve_ivp (DOP853, atol = rtol / 100) agrees with the exact solver to the tolerance asked for:
    end-position error <= rtol at rtol = 1e-4, 1e-6, 1e-8 (positions are O(0.1)).  On a uniform
    surface every arc is a quadratic (eqs. 15-20), which DOP853 integrates exactly, so there the
    error is at the rounding level; the stop zone's harmonic arcs (eq. 42) are truly approximated."""
    _, (_, attrs, groups) = studies[name]
    ivp = groups["ivp"]["datasets"]
    np.testing.assert_allclose(ivp["rtol"], [1e-4, 1e-6, 1e-8], rtol=1e-12)
    assert np.all(ivp["err_end_position"] <= ivp["rtol"]), ivp["err_end_position"]
    assert attrs["ivp_max_err_over_rtol"] <= 1.0
    assert set(ivp["status"]) == {"horizon"}


def test_vbar_of_the_reference_is_the_closed_form(studies):
    """The study's vbar (displacement over the last period / dt, eq. 10) of the exact reference equals
    the closed-form steady-state vbar of Sect. 5.1 for the case 1 scene (steady from the start), to 1e-12."""
    scene, (_, attrs, _) = studies["accuracy_steady"]
    assert attrs["vbar_ref"] == pytest.approx(steady_state(scene.profile).vbar, rel=1e-12)


def test_stop_scene_ends_inside_the_accumulation(studies):
    """The stop scene's reference ends in the accumulation: inside the transition zone, below the
    limit x_stick_min = x_mu + w (2.2 - 1)/(2.5 - 1) (eq. 41) by less than 1e-3."""
    scene, (_, attrs, _) = studies["accuracy_stop"]
    limit = scene.surface.x_stick_min(scene.profile.max_abs_acceleration)
    assert limit - 1e-3 < attrs["x_ref_end"] < limit


def test_every_method_is_timed_with_the_same_fast_forward(studies):
    """The CPU times compare methods on equal terms: every method runs under the one driver, whose
    fast-forward skips the same periods of a steady state (docs/explanation/solvers.md).  The case 1
    scene is periodic from t = 0 (Sect. 5.1), so every run of its 4 periods simulates 1 and skips
    3; the stop scene accumulates (no cycle), so no run skips any."""
    for name, skipped in (("accuracy_steady", 3), ("accuracy_stop", 0)):
        _, (_, attrs, groups) = studies[name]
        assert groups["exact"]["attrs"]["fast_forward_periods"] == skipped
        for method in ("moreau", "ivp"):
            assert set(groups[method]["datasets"]["fast_forward_periods"].tolist()) == {skipped}, (name, method)


def test_study_round_trips_through_hdf5(studies, tmp_path):
    """The study's layout is stored and read back unchanged (the figure reads the file)."""
    _, (datasets, attrs, groups) = studies["accuracy_stop"]
    write_h5(tmp_path / "a.h5", datasets, attrs, groups)
    back = read_h5(tmp_path / "a.h5")
    assert back["attrs"]["moreau_order"] == attrs["moreau_order"]
    for method in ("moreau", "ivp"):
        for key, values in groups[method]["datasets"].items():
            np.testing.assert_array_equal(back["groups"][method]["datasets"][key], values)
    assert back["groups"]["exact"]["attrs"] == groups["exact"]["attrs"]


def test_theil_sen_fit_ignores_a_lucky_point():
    """The order fit recovers the slope of a power law (1.0, to 1e-12) despite one point whose error
    cancelled by a factor 1000; a least-squares fit would not."""
    h = np.geomspace(1e-5, 1e-2, 10)
    err = 0.1 * h
    err[3] /= 1000.0
    slope, intercept, low, high = fit_loglog(h, err)
    assert slope == pytest.approx(1.0, abs=1e-12) and math.exp(intercept) == pytest.approx(0.1, rel=1e-12)
    assert abs(np.polyfit(np.log(h), np.log(err), 1)[0] - 1.0) > 0.05


def test_loglog_interpolation_is_exact_for_power_laws():
    x = np.array([1.0, 10.0, 100.0])
    assert loglog_interpolate(31.6, x, x ** -1.5)[0] == pytest.approx(31.6 ** -1.5, rel=1e-12)
    assert loglog_interpolate(31.6, x, x ** -1.5)[1] is True
    value, inside = loglog_interpolate(1000.0, x, 2 * x)
    assert value == pytest.approx(2000.0, rel=1e-12) and inside is False


@pytest.mark.parametrize("kwargs, message", [
    ({"moreau_steps_per_period": (10, 1000, 1)}, "moreau_steps_per_period"),
    ({"ivp_rtol": (1e-3, 10.0, 3)}, "ivp_rtol must be < 1"),
    ({"target_error": 0.0}, "target_error"),
])
def test_bad_settings_are_rejected(kwargs, message):
    with pytest.raises(ValueError, match=message):
        StudySettings(**kwargs)


def test_settings_from_config_reject_unknown_keys():
    cfg = {"moreau_steps_per_period": {"from": 10, "to": 1000, "count": 3}, "rtol": 1e-3}
    with pytest.raises(ValueError, match="unknown accuracy setting"):
        StudySettings.from_config(cfg)
    ok = StudySettings.from_config({"moreau_steps_per_period": {"from": 10, "to": 1000, "count": 3}})
    np.testing.assert_array_equal(ok.steps_per_period(), [10, 100, 1000])


@pytest.mark.parametrize("name", ["accuracy_static", "accuracy_stribeck"])
def test_moreau_order_under_static_and_stribeck_friction(repo, name):
    """Under static/kinetic and Stribeck friction (mu_s = 1.3 mu_k, the mass enters a stop zone and
    rests) Moreau stays about first order: the fitted order over h = dt/100 .. dt/1e5 lies in
    [0.7, 1.2] (the stick decisions at r mu_bar scatter single errors by up to a factor ~10)."""
    _, attrs, groups = study(load_scene(repo / f"workflow/scenes/{name}.yaml"), SMALL)
    assert 0.7 <= attrs["moreau_order"] <= 1.2, attrs["moreau_order"]
    err = groups["moreau"]["datasets"]["err_end_position"]
    assert err[-1] < err[0] / 100


def test_a_scene_exact_refuses_takes_its_reference_from_its_solver_block(repo):
    """The exact solver refuses Stribeck friction, so the study's reference is the scene's own solver
    block (ivp at rtol 1e-13): the reference run is that simulation, and the attribute says so."""
    scene = load_scene(repo / "workflow/scenes/accuracy_stribeck.yaml")
    _, attrs, groups = study(scene, SMALL)
    assert attrs["reference"] == "ivp rtol=1e-13 atol=1e-15"
    assert attrs["x_ref_end"] == simulate(scene).x_end == groups["exact"]["attrs"]["x_end"]


def test_a_scene_without_a_reference_is_rejected_before_any_work(repo):
    """A Stribeck scene whose solver block names the exact solver leaves the study no reference: one
    error naming the scene, the refusal and what to do."""
    scene = load_scene(repo / "workflow/scenes/accuracy_stribeck.yaml").replace(method="exact", solver_options={})
    with pytest.raises(ValueError, match="'accuracy_stribeck': the accuracy study has no reference, method 'exact' "
                                         "cannot simulate Stribeck.*name the reference in the scene's solver block"):
        study(scene, SMALL)


def test_until_rest_scene_is_rejected_before_any_work(repo):
    scene = load_scene(repo / "workflow/scenes/stop_zone.yaml")
    with pytest.raises(ValueError, match="horizon.periods >= 2"):
        study(scene, SMALL)


def test_result_layout_is_documented(repo, studies):
    """Every attribute, group and dataset of an accuracy result is on the result-file page of the docs."""
    text = (repo / "docs/reference/results.md").read_text()
    _, (datasets, attrs, groups) = studies["accuracy_stop"]
    names = list(datasets) + list(attrs) + list(groups["exact"]["attrs"])
    names += [n for g in ("moreau", "ivp", "exact") for n in groups[g]["datasets"]]
    for name in names:
        assert f"`{name}`" in text, name
    for group in groups:
        assert f"group `{group}`" in text or f"`{group}`" in text, group
