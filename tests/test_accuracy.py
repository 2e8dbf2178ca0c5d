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


@pytest.fixture(scope="module")
def parts_studies():
    """The studies of the two scenes with several parts on the small settings."""
    from conftest import REPO

    return {name: study(load_scene(REPO / f"workflow/scenes/{name}.yaml"), SMALL)
            for name in ("accuracy_parts", "accuracy_parts_zone")}


@pytest.mark.parametrize("name, band", [("accuracy_parts_zone", (0.8, 1.2)), ("accuracy_parts", (0.7, 1.2))])
def test_moreau_of_several_parts_is_first_order(parts_studies, name, band):
    """Moreau's time-stepping of several parts is first order (Sect. 4.1; docs/explanation/several-parts.md,
    "Accuracy and speed": its end positions converge to the exact solver's with order 1).  The study fits
    single grids h = dt/100 .. dt/1e5, whose error constant scatters with where the breaks and impacts fall
    inside a step (the cross-check of tests/test_parts_crosscheck.py takes the envelope over six grids per
    level instead): the fitted order of the largest end-position error over the parts lies in [0.8, 1.2]
    for three parts pushed into the stop zone (measured 0.95) and in [0.7, 1.2] for two parts with 10
    impacts at e = 0.5 on a uniform surface (measured 0.79; 0.90 over the pipeline's 21 grids, 1.0 over
    dt/100 .. dt/1e6).  Three decades of h buy at least two of error."""
    _, attrs, groups = parts_studies[name]
    assert band[0] <= attrs["moreau_order"] <= band[1], attrs["moreau_order"]
    assert attrs["moreau_fit_points"] >= 10
    err = groups["moreau"]["datasets"]["err_end_position"]
    assert np.all(np.isfinite(err)) and np.all(err > 0)
    assert err[-1] < err[0] / 100


@pytest.mark.parametrize("name, parts", [("accuracy_parts", 2), ("accuracy_parts_zone", 3)])
def test_study_of_several_parts_takes_the_largest_error_over_the_parts(parts_studies, name, parts):
    """The study of a scene with several parts stores each part's end position (one column per part), the
    reference's per part, and as the error the largest |x_i(N) - x_i,ref(N)| over the parts (the maximum
    norm, docs/explanation/solvers.md), recomputed here exactly."""
    _, attrs, groups = parts_studies[name]
    moreau = groups["moreau"]["datasets"]
    assert attrs["parts"] == parts and len(attrs["x_ref_end"]) == parts and len(attrs["vbar_ref"]) == parts
    assert moreau["x_end"].shape == (moreau["h"].size, parts)
    np.testing.assert_array_equal(moreau["err_end_position"],
                                  np.max(np.abs(moreau["x_end"] - attrs["x_ref_end"]), axis=1))
    np.testing.assert_array_equal(moreau["err_vbar"], np.max(np.abs(moreau["vbar"] - attrs["vbar_ref"]), axis=1))
    assert set(moreau["status"]) == {"horizon"} and set(moreau["fast_forward_periods"].tolist()) == {0}


def test_study_of_several_parts_runs_no_ivp_and_says_why(parts_studies):
    """solve_ivp cannot simulate several parts: the result has no group ivp and states the reason; the
    exact solver's own CPU time and its events are stored as for one part."""
    _, attrs, groups = parts_studies["accuracy_parts"]
    assert "ivp" not in groups and "ivp_max_err_over_rtol" not in attrs
    assert attrs["ivp_not_run"].startswith("solve_ivp is not run: method 'ivp' cannot simulate several parts")
    assert groups["exact"]["datasets"]["cpu_time"] > 0
    assert groups["exact"]["attrs"]["events"] == groups["exact"]["attrs"]["events_run_events"] > 0


def test_result_of_several_parts_holds_their_count_and_units(parts_studies, tmp_path):
    """The result file of a study of several parts holds the number of parts and the unit of every dataset
    (docs/reference/results.md: lengths in L, velocities in L/T, CPU times in s, marked as measurements)."""
    import h5py

    datasets, attrs, groups = parts_studies["accuracy_parts_zone"]
    path = write_h5(tmp_path / "parts.h5", datasets, attrs, groups)
    back = read_h5(path)
    assert back["attrs"]["parts"] == 3 and "ivp" not in back["groups"]
    np.testing.assert_array_equal(back["attrs"]["x_ref_end"], attrs["x_ref_end"])
    with h5py.File(path) as f:
        units = {name: f[name].attrs["units"].split()[0] for name in ("moreau/x_end", "moreau/err_end_position",
                                                           "moreau/err_vbar", "moreau/cpu_time", "exact/cpu_time")}
        assert f["moreau/x_end"].shape == (groups["moreau"]["datasets"]["h"].size, 3)
        assert bool(f["moreau/cpu_time"].attrs["measurement"])
    assert units == {"moreau/x_end": "L", "moreau/err_end_position": "L", "moreau/err_vbar": "L/T",
                     "moreau/cpu_time": "s", "exact/cpu_time": "s"}


def test_study_of_several_parts_is_reproducible_apart_from_its_cpu_times(repo, tmp_path):
    """A study of several parts run twice gives files equal up to the datasets marked as measurements (the
    CPU times and what is computed from them; docs/reference/results.md), as for one part."""
    from selfalign.io.hdf5 import measured_datasets, reproducible_bytes

    tiny = StudySettings(moreau_steps_per_period=(10, 1000, 3), fit_min_steps_per_period=10, min_timing=1e-3)
    scene = load_scene(repo / "workflow/scenes/accuracy_parts_zone.yaml")
    paths = [write_h5(tmp_path / f"{run}.h5", *study(scene, tiny, progress="quiet")) for run in ("a", "b")]
    assert measured_datasets(paths[0]) == sorted(
        ["exact/cpu_time", "exact/events_run_cpu_time", "exact_events_per_second", "moreau/cpu_time",
         "moreau_cpu_at_target", "speed_ratio_at_target"])
    assert reproducible_bytes(paths[0]) == reproducible_bytes(paths[1])


def test_figure_of_several_parts_says_ivp_was_not_run(studies, parts_studies, tmp_path):
    """The figure accuracy_parts draws the studies of several parts with the same builder as accuracy_cost:
    Moreau only, a panel per scene that says the errors are the largest over the parts and that solve_ivp
    was not run; studies of one part and of several parts are not mixed in one figure."""
    from selfalign.plots.simulation import figure_accuracy_cost

    results = []
    for name in ("accuracy_parts", "accuracy_parts_zone"):
        results.append(read_h5(write_h5(tmp_path / f"{name}.h5", *parts_studies[name])))
    fig = figure_accuracy_cost(results)
    texts = [t.get_text() for ax in fig.axes for t in ax.texts]
    assert "errors: largest of 2 parts\nsolve_ivp: not run" in texts[0]
    assert "errors: largest of 3 parts\nsolve_ivp: not run" in texts[1]
    assert [ax.get_ylabel() for ax in fig.axes if ax.get_label() == "<colorbar>"] == [
        r"Moreau: steps per period $n = \Delta t / h$"]
    one = read_h5(write_h5(tmp_path / "one.h5", *studies["accuracy_steady"][1]))
    with pytest.raises(ValueError, match="not both"):
        figure_accuracy_cost([one, *results])


@pytest.fixture(scope="module")
def planar_studies():
    """The studies of the two planar scenes on the small settings."""
    from conftest import REPO

    return {name: study(load_scene(REPO / f"workflow/scenes/{name}.yaml"), SMALL)
            for name in ("accuracy_planar", "accuracy_planar_strip")}


@pytest.mark.parametrize("name", ["accuracy_planar", "accuracy_planar_strip"])
def test_planar_study_runs_every_method_and_takes_the_largest_coordinate_error(planar_studies, name):
    """A planar study (docs/explanation/planar-model.md) runs all three planar methods against the exact one:
    Moreau with the friction disc is first order (Sect. 4.1: fitted order in [0.8, 1.25]; measured 1.02 and 1.05
    over the pipeline's 21 grids), solve_ivp's error stays within 10 rtol (measured at most 5.1 rtol, at rtol 1e-3
    on the strip, over the pipeline's rtol 1e-3 ... 1e-11) and falls below 1e-7 at rtol 1e-8 (at rtol 1e-4 on the
    strip its steps shrink at a stop in the transition and it ends with an error status, a known limit of
    docs/explanation/planar-model.md; from rtol 1e-6 on every run reaches the horizon); the stored error is the
    larger over the two coordinates, recomputed here exactly, and the attribute planar says so."""
    _, attrs, groups = planar_studies[name]
    assert attrs["planar"] is True and attrs["parts"] == 1 and len(attrs["x_ref_end"]) == 2
    assert 0.8 <= attrs["moreau_order"] <= 1.25, attrs["moreau_order"]
    moreau, ivp = groups["moreau"]["datasets"], groups["ivp"]["datasets"]
    assert moreau["x_end"].shape == (moreau["h"].size, 2)
    np.testing.assert_array_equal(moreau["err_end_position"],
                                  np.max(np.abs(moreau["x_end"] - attrs["x_ref_end"]), axis=1))
    assert attrs["ivp_max_err_over_rtol"] <= 10.0
    assert ivp["err_end_position"][-1] <= 1e-7
    assert set(moreau["status"]) == set(ivp["status"][ivp["rtol"] <= 1e-6]) == {"horizon"}


def test_figure_of_planar_studies_says_the_errors_are_over_the_coordinates(planar_studies, tmp_path):
    """The figure accuracy_planar draws the planar studies with the builder of accuracy_cost (Moreau and
    solve_ivp against the exact solver); each panel says its errors are the larger over the two coordinates, and
    the panels are lettered a-d (the caption names each scene, with its strip, by its panels)."""
    from selfalign.plots.simulation import figure_accuracy_cost

    results = [read_h5(write_h5(tmp_path / f"{name}.h5", *planar_studies[name])) for name in planar_studies]
    fig = figure_accuracy_cost(results)
    texts = [t.get_text() for ax in fig.axes for t in ax.texts]
    assert "errors: largest of 2 coordinates" in texts[0] and "errors: largest of 2 coordinates" in texts[1]
    assert [ax.get_title("left") for ax in fig.axes if ax.get_title("left")] == list("abcd")
