"""Figure regression for the simulation figures (Figs. 3, 9, 12) and the work-precision figure.

Same pattern as tests/test_figures.py: each figure is rebuilt from freshly
simulated data (library calls, scene -> HDF5 -> figure) and the numbers it shows
are compared with ``tests/figure_refs/<fig>.json`` (rtol 1e-9); the pixels with
the committed ``figures/<fig>.png`` only under the pinned matplotlib series.
``--update-figure-refs`` rewrites both.

The work-precision figure plots CPU times, which differ from run to run: only
its errors (the y data, from a small study) are compared, and its PNG (written
by the workflow from the full study) is not.
"""


import numpy as np
import pytest
import yaml
from figcheck import compare_figure_data, figure_data, load_reference, save_reference
from test_figures import ATOL, RTOL, assert_data_matches, assert_pixels_match

from selfalign import load_scene, simulate
from selfalign.analysis.accuracy import StudySettings, study
from selfalign.analysis.classification import CASE_LABELS, classify
from selfalign.io.hdf5 import read_h5, write_h5
from selfalign.io.simulation_result import trajectory_content
from selfalign.model.profiles import ThreePhaseProfile
from selfalign.plots.simulation import figure_03, figure_09, figure_12, figure_accuracy_cost

FIGURES = ("fig03", "fig09", "fig12")


def config(repo):
    return yaml.safe_load((repo / "workflow/config/config.yaml").read_text())


def simulated(scene, tmp_path):
    """The stage's steps without Snakemake: scene -> simulate -> HDF5 -> read back."""
    path = tmp_path / f"{scene.name}.h5"
    write_h5(path, *trajectory_content(simulate(scene), scene))
    return read_h5(path)


def fig09_scenes(repo):
    return [load_scene(repo / f"workflow/scenes/{n}.yaml") for n in config(repo)["figures"]["fig09"]["scenes"]]


def build_fig09(repo, scenes, tmp_path):
    results = [simulated(s, tmp_path) for s in scenes]
    return figure_09(results, [classify(s.profile) for s in scenes], CASE_LABELS,
                     periods=config(repo)["figures"]["fig09"]["periods"])


def build(name, repo, tmp_path):
    figs = config(repo)["figures"]
    if name == "fig09":
        return build_fig09(repo, fig09_scenes(repo), tmp_path)
    scene = load_scene(repo / f"workflow/scenes/{figs[name]['scene']}.yaml")
    return {"fig03": figure_03, "fig12": figure_12}[name](simulated(scene, tmp_path))


@pytest.mark.parametrize("name", FIGURES)
def test_figure_data_matches_reference(repo, tmp_path, update_figure_refs, name):
    """Figs. 3, 9 and 12 show the same numbers as their committed references, rtol 1e-9."""
    assert_data_matches(repo, build(name, repo, tmp_path), name, update_figure_refs,
                        config(repo)["figures"]["dpi"])


@pytest.mark.parametrize("name", FIGURES)
def test_figure_pixels_match_committed_png(repo, tmp_path, name):
    """The committed figures/<name>.png is what the current code draws (RMS <= 1 of 255)."""
    assert_pixels_match(repo, build(name, repo, tmp_path), name, tmp_path, config(repo)["figures"]["dpi"])


def test_fig09_comparison_catches_acceleration_change(repo, tmp_path):
    """The check can fail: y3'' of the case 3 panel 1 % larger (1.8 -> 1.818) is reported on its x' data
    (axes[4]: each case has an x' and a y'' axis)."""
    scenes = fig09_scenes(repo)
    p = scenes[2].profile
    assert classify(p) == 3
    scenes[2] = scenes[2].replace(profile=ThreePhaseProfile(p.dt, p.dy, p.y2, p.y3 * 1.01))
    diffs = compare_figure_data(figure_data(build_fig09(repo, scenes, tmp_path)),
                                load_reference(repo / "tests/figure_refs/fig09.json"), rtol=RTOL, atol=ATOL)
    assert any(d.startswith("figure.axes[4].lines[0].y") for d in diffs), diffs


#: A small study of two scenes for the work-precision figure's data (errors only).
SMALL = StudySettings(moreau_steps_per_period=(10, 10_000, 7), ivp_rtol=(1e-4, 1e-8, 3), min_timing=1e-9)


def without_cpu_times(data):
    """figure_data with the CPU-time axis left out: line x data, marker x offsets and x limits,
    and the slope guide, whose height is set by the CPU times too."""
    for ax in data["axes"]:
        ax["xlim"] = None
        for line in ax["lines"]:
            line["x"] = None
            if line["label"].startswith("slope"):
                line["y"] = None
        for collection in ax["collections"]:
            collection["offsets"] = [y for _, y in collection["offsets"]]
    return data


#: Tolerance of the work-precision figure's y-limits, in decades (log10): 0.1 pixel at 16 decades per axis.
YLIM_DECADES = 5e-3


@pytest.mark.blas
def test_accuracy_cost_errors_match_reference(repo, tmp_path, update_figure_refs):
    """The work-precision figure draws the study's errors (end position and vbar, Moreau and ivp, on
    two scenes), the same as the committed reference; CPU times are not compared, nor anything
    drawn from them.  Errors compare at rtol 1e-9 with atol 1e-12: ivp's smallest errors
    (~1e-11) move by ~1e-17 with the BLAS kernel (solve_ivp's stages go through np.dot), far below
    atol.  The log-scaled y-limits, autoscaled from those errors, compare to YLIM_DECADES in
    log10 (they moved by up to 1.2e-3 decades between the AVX-512 and Prescott kernels)."""
    results = []
    for name in ("accuracy_steady", "accuracy_stop"):
        write_h5(tmp_path / f"{name}.h5", *study(load_scene(repo / f"workflow/scenes/{name}.yaml"), SMALL))
        results.append(read_h5(tmp_path / f"{name}.h5"))
    data = without_cpu_times(figure_data(figure_accuracy_cost(results)))
    ref_path = repo / "tests/figure_refs/accuracy_cost.json"
    if update_figure_refs:
        save_reference(data, ref_path)
        pytest.skip("figure reference rewritten")
    reference = load_reference(ref_path)
    ylims, ref_ylims = ([ax.pop("ylim") for ax in d["axes"]] for d in (data, reference))
    np.testing.assert_allclose(np.log10(ylims), np.log10(ref_ylims), rtol=0, atol=YLIM_DECADES)
    diffs = compare_figure_data(data, reference, rtol=RTOL, atol=ATOL)
    assert not diffs, "\n".join(diffs[:20])


def test_accuracy_panel_titles_name_each_effect_with_its_size(repo):
    """A work-precision panel's title says what its scene adds to the paper's model and how much: the
    finite-jerk scene its y'' ramps as % of the period (accuracy_jerk: 5 %), the friction-law scenes
    mu_s/mu_k (and v_s for Stribeck); the paper's scenes name none of them."""
    from selfalign.plots.simulation import _study_title

    def title(name):
        return _study_title(load_scene(repo / f"workflow/scenes/{name}.yaml")).split("\n")[0]
    assert "$y''$ ramps 5 % of $\\Delta t$" in title("accuracy_jerk")
    assert "$\\mu_s/\\mu_k$ = 1.3" in title("accuracy_static")
    assert "$\\mu_s/\\mu_k$ = 1.3, $v_s$ = 0.01" in title("accuracy_stribeck")
    for paper in ("accuracy_steady", "accuracy_stop", "accuracy_long"):
        assert not any(word in title(paper) for word in ("ramps", "jerk", "mu_s", "v_s"))
