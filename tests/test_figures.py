"""Figure regression: figures rebuilt from fresh data match the committed references.

The numbers a figure shows are compared with ``tests/figure_refs/<fig>.json``
(``figcheck.figure_data``; rtol 1e-9); the pixels with the committed
``figures/<fig>.png`` and the drawing with the committed ``figures/<fig>.pdf``
(``figcheck.compare_pdf``: every stream but the fonts, numbers within 0.01 pt)
only under the pinned matplotlib series, whose rendering the files were made with.
After an intended change, rewrite them with
``python -m pytest tests/test_figures.py --update-figure-refs`` and review the diff.
"""

import re
import shutil
import tomllib

import matplotlib
import pytest
import yaml
from figcheck import compare_figure_data, compare_pdf, compare_pixels, figure_data, load_reference, save_reference

from selfalign import load_scene
from selfalign.io.hdf5 import read_h5, write_h5
from selfalign.model.profiles import ThreePhaseProfile
from selfalign.plots.profile import figure_07
from selfalign.stages.common import save_figure
from selfalign.stages.trajectory import profile_samples

#: Relative tolerance on figure data: the numbers come from closed forms, so only rounding differs.
RTOL = 1e-9
#: Absolute tolerance, for values that are zero up to rounding (min y = 0).
ATOL = 1e-12
#: RMS pixel difference (0..255) tolerated under the pinned matplotlib series.
PIXEL_TOL = 1.0


def pinned_matplotlib_series(repo):
    """"3.11" from the dependency "matplotlib==3.11.*" of the `plots` extra in pyproject.toml."""
    deps = tomllib.loads((repo / "pyproject.toml").read_text())["project"]["optional-dependencies"]["plots"]
    pins = [m.group(1) for d in deps if (m := re.fullmatch(r"matplotlib\s*==\s*(\d+\.\d+)\.\*", d))]
    assert len(pins) == 1, f"pyproject.toml must pin matplotlib as ==X.Y.*, got {deps}"
    return pins[0]

def assert_pixels_match(repo, fig, name, tmp_path, dpi):
    """figures/<name>.png is what ``fig`` draws (RMS <= PIXEL_TOL of 255), and figures/<name>.pdf
    draws the same strokes and text (figcheck.compare_pdf); compared under the pinned matplotlib
    series only, since other FreeType/matplotlib versions move pixels and points."""
    series = pinned_matplotlib_series(repo)
    if not matplotlib.__version__.startswith(series + "."):
        pytest.skip(f"pixels are compared under matplotlib {series}.* only; this is {matplotlib.__version__}")
    fresh = save_figure(fig, tmp_path / f"{name}.png", dpi=dpi)
    committed = tmp_path / f"{name}-committed.png"
    shutil.copyfile(repo / f"figures/{name}.png", committed)
    rms = compare_pixels(fresh, committed, tol=PIXEL_TOL)
    assert rms is None, f"figures/{name}.png differs from the current drawing: RMS {rms}"
    diffs = compare_pdf(save_figure(fig, tmp_path / f"{name}.pdf"), repo / f"figures/{name}.pdf")
    assert not diffs, f"figures/{name}.pdf differs from the current drawing: " + "; ".join(diffs[:5])

def assert_data_matches(repo, fig, name, update, dpi=None, rtol=RTOL):
    """The plotted data of ``fig`` equal tests/figure_refs/<name>.json (rtol ``rtol``, default RTOL; atol ATOL).

    With ``--update-figure-refs`` (``update``) the reference is rewritten instead, and so are
    figures/<name>.png and .pdf when ``dpi`` is given (figures whose committed files are drawn here)."""
    ref_path = repo / f"tests/figure_refs/{name}.json"
    data = figure_data(fig)
    if update:
        save_reference(data, ref_path)
        if dpi is not None:
            save_figure(fig, repo / f"figures/{name}.png", dpi=dpi)
            save_figure(fig, repo / f"figures/{name}.pdf")
        pytest.skip("figure references rewritten")
    diffs = compare_figure_data(data, load_reference(ref_path), rtol=rtol, atol=ATOL)
    assert not diffs, "\n".join(diffs[:20])


def build_fig07(scene, tmp_path):
    """The pipeline's steps without Snakemake: scene -> HDF5 -> figure."""
    h5 = tmp_path / f"{scene.name}.h5"
    write_h5(h5, *profile_samples(scene))
    return figure_07(read_h5(h5))


@pytest.fixture
def fig07_scene(repo):
    return load_scene(repo / "workflow/scenes/fig07.yaml")


@pytest.fixture
def dpi(repo):
    return yaml.safe_load((repo / "workflow/config/config.yaml").read_text())["figures"]["dpi"]


def test_fig07_data_matches_reference(repo, fig07_scene, tmp_path, update_figure_refs, dpi):
    """Fig. 7 (Sect. 4.4.3) shows the same numbers as the committed reference, rtol 1e-9."""
    assert_data_matches(repo, build_fig07(fig07_scene, tmp_path), "fig07", update_figure_refs,
                        dpi)


def test_fig07_pixels_match_committed_png(repo, fig07_scene, tmp_path, dpi):
    """The committed figures/fig07.png is what the current code draws (RMS <= 1 of 255)."""
    assert_pixels_match(repo, build_fig07(fig07_scene, tmp_path), "fig07", tmp_path, dpi)


def test_fig07_comparison_catches_stroke_change(repo, fig07_scene, tmp_path):
    """The check can fail: a stroke 1 % larger (dy 0.084 -> 0.08484) is reported, on the y data."""
    p = fig07_scene.profile
    changed = fig07_scene.replace(profile=ThreePhaseProfile(p.dt, p.dy * 1.01, p.y2, p.y3))
    diffs = compare_figure_data(figure_data(build_fig07(changed, tmp_path)),
                                load_reference(repo / "tests/figure_refs/fig07.json"), rtol=RTOL, atol=ATOL)
    assert any(d.startswith("figure.axes[0].lines[0].y") for d in diffs), diffs


def test_fig07_meets_the_print_standard(fig07_scene, tmp_path):
    """Fig. 7 prints one column wide (84 mm) with no text below 7 pt, no title but the panel letters
    a, b, c and no ASCII mathematics (selfalign.plots.style.print_check); the equal areas of items 5
    and 6 (Sect. 4.4.3) are shaded in Okabe-Ito blue and vermillion, not tab:blue and tab:red; the
    times t0 ... t3 are named on the top axis, clear of the panel letter."""
    from matplotlib.colors import to_hex

    from selfalign.plots import style

    fig = build_fig07(fig07_scene, tmp_path)
    assert style.print_check(fig) == []
    assert round(fig.get_figwidth() / style.MM) == 84
    panels = [ax for ax in fig.axes if ax.get_title("left")]
    assert [ax.get_title("left") for ax in panels] == ["a", "b", "c"]
    for ax in panels[1:]:
        assert [to_hex(c.get_facecolor()[0], keep_alpha=False) for c in ax.collections] == [
            style.OKABE_ITO["blue"].lower(), style.OKABE_ITO["vermillion"].lower()]
    (top,) = panels[0].child_axes
    assert [t.get_text() for t in top.get_xticklabels()] == [
        "$t_0$", "$t_1$", "$t_{y'=0,1}$", "$t_2$", "$t_{y'=0,2}$", "$t_3$"]
    assert panels[0].texts[0].get_text() == r"$y_{\mathrm{ini}}$" and panels[0].texts[0].get_ha() == "left"


def build_fig13(scene, v20, tmp_path):
    """The convergence stage's steps without Snakemake: scene -> HDF5 -> figure."""
    from selfalign.plots.stability import figure_13
    from selfalign.stages.convergence import convergence_result

    h5 = tmp_path / f"{scene.name}.h5"
    write_h5(h5, *convergence_result(scene, v20))
    return figure_13(read_h5(h5))


@pytest.fixture
def fig13_setup(repo):
    """The Fig. 13 scene and its second initial velocity, as the workflow config names them."""
    config = yaml.safe_load((repo / "workflow/config/config.yaml").read_text())
    name = config["figures"]["fig13"]["scene"]
    return load_scene(repo / f"workflow/scenes/{name}.yaml"), config["stages"]["convergence"]["v20"][name]


def test_fig13_data_matches_reference(repo, fig13_setup, tmp_path, update_figure_refs, dpi):
    """Fig. 13 (Sect. 6.2) shows the same numbers as the committed reference, rtol 1e-9."""
    assert_data_matches(repo, build_fig13(*fig13_setup, tmp_path), "fig13", update_figure_refs,
                        dpi)


def test_fig13_pixels_match_committed_png(repo, fig13_setup, tmp_path, dpi):
    """The committed figures/fig13.png is what the current code draws (RMS <= 1 of 255)."""
    assert_pixels_match(repo, build_fig13(*fig13_setup, tmp_path), "fig13", tmp_path, dpi)


def test_fig13_comparison_catches_start_change(repo, fig13_setup, tmp_path):
    """The check can fail: a second initial velocity 1 % larger is reported, on v2."""
    scene, v20 = fig13_setup
    diffs = compare_figure_data(figure_data(build_fig13(scene, v20 * 1.01, tmp_path)),
                                load_reference(repo / "tests/figure_refs/fig13.json"), rtol=RTOL, atol=ATOL)
    assert any(d.startswith("figure.axes[0].lines[1].y") for d in diffs), diffs


# Classification stage (Figs. 4, 5, 6, 8, 10, 11): the stage's library steps with the
# workflow config's settings, through HDF5 as in the pipeline.

def classification_config(repo):
    config = yaml.safe_load((repo / "workflow/config/config.yaml").read_text())
    return config["stages"]["classification"], config["figures"]


def build_classification_figure(name, repo, tmp_path, change=None):
    """Figure ``name`` rebuilt from fresh data; ``change`` (a factor) scales the stroke dy
    (sweeps, maps) or, for Fig. 8, swaps the branches of the last decision."""
    from dataclasses import replace

    from selfalign.analysis.classification import DECISION_TREE, DecisionTree
    from selfalign.plots.classification import figure_04, figure_05, figure_08, figure_map
    from selfalign.stages.classification import gather_map, map_shard, polynomial_sweep
    from selfalign.stages.common import range_values

    stage, figures = classification_config(repo)
    h5 = tmp_path / f"{name}.h5"
    if name in ("fig04", "fig05"):
        sweep, poly = dict(stage["sweeps"][name]), stage["polynomial"]
        values = {k: range_values(v) if isinstance(v, dict) else v for k, v in sweep.items()}
        values["dy"] = values["dy"] * (change or 1.0)
        write_h5(h5, *polynomial_sweep(values["dt"], values["dy"], forward_fraction=poly["forward_fraction"],
                                       steps_per_period=poly["moreau_steps_per_period"],
                                       iteration=poly["moreau_iteration"]))
        return (figure_04 if name == "fig04" else figure_05)(read_h5(h5))
    if name in ("fig10", "fig11"):
        m = stage["maps"][name]
        y2, y3 = range_values(m["y2"]), range_values(m["y3"])
        dy = m["dy"] * (change or 1.0)
        shard = map_shard(m["dt"], dy, y2, y3, slice(0, y2.size), simulate=False)
        write_h5(h5, *gather_map(m["dt"], dy, y2, y3, [shard]))
        return figure_map(read_h5(h5), figures[name]["f_max"])
    tree = DECISION_TREE
    if change:
        node = tree["restick"]
        tree = DecisionTree(tree.root, [replace(node, yes=node.no, no=node.yes) if n == "restick" else tree[n]
                                        for n, _ in tree.nodes()])
    return figure_08(tree)


CLASSIFICATION_FIGURES = ["fig04", "fig05", "fig08", "fig10", "fig11"]
#: Where a changed input must show up: a 1 % larger stroke (Fig. 8: swapped branches).
CHANGE_SHOWS_IN = {"fig04": "figure.axes[0].lines[0].y", "fig05": "figure.axes[0].lines[0].x",
                   "fig08": "figure.axes[0].texts", "fig10": "figure.axes[0].collections[0].array",
                   "fig11": "figure.axes[0].collections[0].array"}


@pytest.mark.parametrize("name", CLASSIFICATION_FIGURES)
def test_classification_figure_data_matches_reference(name, repo, tmp_path, update_figure_refs, dpi):
    """Figs. 4, 5 (Sect. 4.4.1), 8 (Sect. 5.1) and 10, 11 (Sect. 5.2) show the same numbers as
    the committed references, rtol 1e-9."""
    assert_data_matches(repo, build_classification_figure(name, repo, tmp_path), name,
                        update_figure_refs, dpi)


@pytest.mark.parametrize("name", CLASSIFICATION_FIGURES)
def test_classification_figure_pixels_match_committed_png(name, repo, tmp_path, dpi):
    """The committed figures/<fig>.png is what the current code draws (RMS <= 1 of 255)."""
    assert_pixels_match(repo, build_classification_figure(name, repo, tmp_path), name, tmp_path, dpi)


@pytest.mark.parametrize("name", CLASSIFICATION_FIGURES)
def test_classification_figure_comparison_catches_a_change(name, repo, tmp_path):
    """The check can fail: a 1 % larger stroke (Fig. 8: a decision with swapped branches) is
    reported where it shows."""
    diffs = compare_figure_data(figure_data(build_classification_figure(name, repo, tmp_path, change=1.01)),
                                load_reference(repo / f"tests/figure_refs/{name}.json"), rtol=RTOL, atol=ATOL)
    assert any(d.startswith(CHANGE_SHOWS_IN[name]) for d in diffs), diffs


def build_fig06(repo, tmp_path):
    """Fig. 6 from fig06_results with the workflow config's settings (the full optimisation)."""
    from selfalign.stages.classification import fig06_results
    from selfalign.stages.figures import draw

    p = classification_config(repo)[0]["fourier"]
    datasets, attrs, _ = fig06_results(p["dt"], p["dy"], p["yd_max"], p["ydd_max"], order=p["order"],
                                       max_iter=p["max_iter"])
    h5 = write_h5(tmp_path / "fig06.h5", datasets, attrs)
    return draw("fig06", [read_h5(h5)])


@pytest.fixture(scope="module")
def fig06(repo, tmp_path_factory):
    return build_fig06(repo, tmp_path_factory.mktemp("fig06"))


@pytest.mark.blas
def test_fig06_data_matches_reference(repo, fig06, update_figure_refs, dpi):
    """Fig. 6 (Sect. 4.4.2), the workflow's full optimisation, shows the numbers of the
    committed reference to rtol 1e-9.  So tight a tolerance on an optimiser's path is
    sound here only because the path never goes through BLAS or LAPACK (analysis.sqp) and
    is the same bits under every kernel; .ci/run reruns this test under OPENBLAS_CORETYPE=Prescott
    and 1 and 2 threads."""
    assert_data_matches(repo, fig06, "fig06", update_figure_refs, dpi)


@pytest.mark.blas
def test_fig06_pixels_match_committed_png(repo, fig06, tmp_path, dpi):
    """The committed figures/fig06.png is what the workflow's optimisation draws (RMS <= 1 of 255)."""
    assert_pixels_match(repo, fig06, "fig06", tmp_path, dpi)


def test_fig06_comparison_catches_stroke_change(repo, fig06):
    """The check can fail: the optimised y drawn 1 % larger (a 1 % larger stroke) is reported."""
    data = figure_data(fig06)
    line = data["axes"][0]["lines"][0]
    line["y"] = [value * 1.01 for value in line["y"]]
    diffs = compare_figure_data(data, load_reference(repo / "tests/figure_refs/fig06.json"), rtol=RTOL, atol=ATOL)
    assert any(d.startswith("figure.axes[0].lines[0].y: 1001 of 1001 values differ") for d in diffs), diffs
