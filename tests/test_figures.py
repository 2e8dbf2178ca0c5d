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
import matplotlib.text
import numpy as np
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


@pytest.fixture(scope="module")
def classification_figure(repo, tmp_path_factory):
    """Figure name -> the figure as :func:`build_classification_figure` draws it from fresh data,
    built once per module: the tests that take it only read it."""
    built = {}

    def get(name):
        if name not in built:
            built[name] = build_classification_figure(name, repo, tmp_path_factory.mktemp(name))
        return built[name]

    return get


@pytest.mark.parametrize("name", CLASSIFICATION_FIGURES)
def test_classification_figure_data_matches_reference(name, repo, classification_figure, update_figure_refs, dpi):
    """Figs. 4, 5 (Sect. 4.4.1), 8 (Sect. 5.1) and 10, 11 (Sect. 5.2) show the same numbers as
    the committed references, rtol 1e-9."""
    assert_data_matches(repo, classification_figure(name), name,
                        update_figure_refs, dpi)


@pytest.mark.parametrize("name", CLASSIFICATION_FIGURES)
def test_classification_figure_pixels_match_committed_png(name, repo, classification_figure, tmp_path, dpi):
    """The committed figures/<fig>.png is what the current code draws (RMS <= 1 of 255)."""
    assert_pixels_match(repo, classification_figure(name), name, tmp_path, dpi)


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


# The figure standard on the steady-state and stability figures (selfalign.plots.style): print
# size, special values each in their one encoding, nothing that misleads.

def marked_cells(ax, kind, y2, y3) -> float:
    """How many map cells ``ax`` draws in the special-value encoding ``kind`` (the area of its
    patch over the area of one cell; the grids are uniform)."""
    from matplotlib.colors import to_rgba
    from matplotlib.patches import PathPatch

    from selfalign.plots.style import SPECIAL, cell_edges

    encoding = SPECIAL[kind]
    face = to_rgba("none" if encoding["facecolor"] == "none" else encoding["facecolor"])
    patches = [p for p in ax.patches if isinstance(p, PathPatch) and (p.get_hatch() or "") == encoding["hatch"]
               and p.get_facecolor() == face]
    if not patches:
        return 0.0
    (patch,) = patches
    corners = patch.get_path().vertices.reshape(-1, 5, 2)
    area = np.sum((corners[:, 1, 0] - corners[:, 0, 0]) * (corners[:, 2, 1] - corners[:, 1, 1]))
    e2, e3 = cell_edges(y2), cell_edges(y3)
    return float(area / ((e2[1] - e2[0]) * (e3[1] - e3[0])))


def closed_form_map(repo, name):
    """The closed-form map ``name`` (fig10, fig11) of the workflow config, as figure_map reads it."""
    from selfalign.stages.classification import gather_map, map_shard
    from selfalign.stages.common import range_values

    stage, figures = classification_config(repo)
    m = stage["maps"][name]
    y2, y3 = range_values(m["y2"]), range_values(m["y3"])
    datasets, attrs = gather_map(m["dt"], m["dy"], y2, y3,
                                 [map_shard(m["dt"], m["dy"], y2, y3, slice(0, y2.size), simulate=False)])
    return {"datasets": datasets, "attrs": attrs}, figures[name]["f_max"]


@pytest.mark.parametrize("name", CLASSIFICATION_FIGURES)
def test_classification_figures_meet_the_print_standard(name, classification_figure):
    """Figs. 4, 5, 8, 10 and 11 are one or two columns wide, no text below 7 pt, no title but
    panel letters, no ASCII mathematics (selfalign.plots.style.print_check)."""
    from selfalign.plots.style import print_check

    assert print_check(classification_figure(name)) == []


def test_fig11_draws_pure_stick_as_infinite_not_as_a_large_f(repo):
    """Sect. 5.2, Table 1: in case 5 (pure stick) v̄ = 0 and f = 1/(c v̄²) = inf.  Fig. 11 (a)
    draws exactly those cells in the encoding "f_infinite" (black), leaves them out of the
    colour map (NaN in the mesh, not the colour of f_max), names them in the legend, and its
    colour bar says that finite values >= f_max are clipped ("extend max")."""
    from selfalign.plots.classification import figure_map
    from selfalign.plots.style import SPECIAL

    result, f_max = closed_form_map(repo, "fig11")
    d = result["datasets"]
    fig = figure_map(result, f_max)
    ax = fig.axes[0]
    infinite = np.isposinf(d["f"])
    assert infinite.sum() == np.count_nonzero(d["case"] == 5) > 100
    assert marked_cells(ax, "f_infinite", d["y2"], d["y3"]) == pytest.approx(infinite.sum(), abs=1e-6)
    mesh = ax.collections[0]
    assert np.all(np.ma.getmaskarray(mesh.get_array()).reshape(d["y3"].size, d["y2"].size).T[infinite])
    assert mesh.colorbar.extend == "max"
    legend = [t.get_text() for t in fig.legends[0].get_texts()]
    assert SPECIAL["f_infinite"]["label"] in legend and SPECIAL["v_negative"]["label"] in legend


def test_objective_panel_is_logarithmic_and_marks_every_special_value(repo):
    """objective_panel (Figs. 10, 11 and 17 (a)): f on a logarithmic colour scale from the
    smallest f of the map to f_max (so values far below the clip are told apart), values >=
    f_max clipped to the top colour with an "extend max" bar, and case 0, f = inf and v̄ < 0
    each drawn on exactly their cells, with a legend handle each besides the line v̄ = 0.  The
    check can fail: on a map without case 0 the case-0 handle is left out."""
    from matplotlib.colors import LogNorm

    from selfalign.plots.classification import objective_panel
    from selfalign.plots.style import SPECIAL, new_figure

    result, f_max = closed_form_map(repo, "fig11")
    d = result["datasets"]
    ax = new_figure("single", 80).subplots()
    handles = objective_panel(ax, d["y2"], d["y3"], d["f"], d["vbar"], f_max)
    norm = ax.collections[0].norm
    assert isinstance(norm, LogNorm) and norm.vmax == f_max
    assert norm.vmin == pytest.approx(np.min(d["f"][np.isfinite(d["f"])]), rel=1e-12)
    assert ax.collections[0].colorbar.extend == "max"
    for kind, mask in (("non_physical", d["case"] == 0), ("f_infinite", np.isposinf(d["f"])),
                       ("v_negative", d["vbar"] < 0)):
        assert marked_cells(ax, kind, d["y2"], d["y3"]) == pytest.approx(np.count_nonzero(mask), abs=1e-6), kind
    assert [h.get_label() for h in handles] == [r"$\bar v = 0$"] + [SPECIAL[kind]["label"] for kind in
                                                                     ("non_physical", "f_infinite", "v_negative")]
    inner = (slice(60, None), slice(60, None))  # y2'', y3'' > 1: cases 3 and 4 only
    assert set(np.unique(d["case"][inner])) <= {3, 4}
    ax = new_figure("single", 80).subplots()
    labels = [h.get_label() for h in objective_panel(ax, d["y2"][inner[0]], d["y3"][inner[1]], d["f"][inner],
                                                     d["vbar"][inner], f_max)]
    assert SPECIAL["non_physical"]["label"] not in labels and SPECIAL["f_infinite"]["label"] not in labels


def test_fig10_magnifies_the_few_backward_cells(repo):
    """Sect. 5.2 (Fig. 10): v̄ < 0 occurs only in 21 slip-slip cells next to case 0, about
    1.4 mm wide at print size, too narrow for the hatch.  Panel (c) magnifies a window holding
    every one of them and draws them hatched there (and in (a)); Fig. 11, where v̄ < 0 covers
    a large region, has no such panel."""
    from selfalign.plots.classification import figure_map

    result, f_max = closed_form_map(repo, "fig10")
    d = result["datasets"]
    backward = d["vbar"] < 0
    assert np.count_nonzero(backward) == 21
    fig = figure_map(result, f_max)
    zoom = fig.axes[2]
    i, j = np.nonzero(backward)
    (x0, x1), (z0, z1) = zoom.get_xlim(), zoom.get_ylim()
    assert x0 < d["y2"][i].min() and d["y2"][i].max() < x1 and z0 < d["y3"][j].min() and d["y3"][j].max() < z1
    assert (x1 - x0) < 0.1 * (d["y2"][-1] - d["y2"][0])
    for ax in (fig.axes[0], zoom):
        assert marked_cells(ax, "v_negative", d["y2"], d["y3"]) == pytest.approx(21, abs=1e-6)
    result11, f_max11 = closed_form_map(repo, "fig11")
    assert [ax.get_title(loc="left") for ax in figure_map(result11, f_max11).axes if ax.get_title(loc="left")] \
        == ["a", "b"]


@pytest.mark.parametrize("name", ["fig04", "fig05"])
def test_sweep_differences_at_rounding_level_are_drawn_on_the_floor(name, classification_figure):
    """Figs. 4, 5 (b): where time-stepping lands on the exact steady motion the relative
    difference of f is rounding (1e-13 .. 1e-11, captions); such points are drawn as triangles on
    the floor 1e-6 of the axis, the others at their values above it, so no point lies outside
    the axis and none is hidden."""
    from selfalign.plots.classification import ROUNDING_FLOOR

    fig = classification_figure(name)
    ax = fig.axes[1]
    above, floor = ax.lines[0].get_ydata(), ax.lines[1].get_ydata()
    assert np.all(above >= ROUNDING_FLOOR) and np.all(floor == ROUNDING_FLOOR)
    assert above.size + floor.size == fig.axes[0].lines[1].get_xdata().size
    assert ax.get_ylim()[0] < ROUNDING_FLOOR


def test_fig13_meets_the_print_standard(fig13_setup, tmp_path):
    """Fig. 13 is one column wide, with panel letters and no text below 7 pt."""
    from selfalign.plots.style import print_check

    fig = build_fig13(*fig13_setup, tmp_path)
    assert print_check(fig) == [] and round(fig.get_figwidth() * 25.4) == 84


@pytest.mark.blas
def test_fig06_meets_the_print_standard_and_leaves_the_paper_value_to_the_caption(fig06):
    """Fig. 6 is two columns wide with no text below 7 pt; it prints f of eq. (11) only (the
    paper's f = 56 is discussed in the caption, docs/explanation/stability.md)."""
    from selfalign.plots.style import print_check

    assert print_check(fig06) == [] and round(fig06.get_figwidth() * 25.4) == 174
    texts = [t.get_text() for t in fig06.findobj(matplotlib.text.Text)]
    assert not any("56" in t for t in texts)


# The second Floquet multiplier over the plane of Fig. 17 (Sect. 6.1, eq. 33).

def eq33(y2, y3, case):
    """lambda2 of eq. (33): c4 = (y2'' - 1)(y3'' - 1)/((y2'' + 1)(y3'' + 1)) in case 4, 0 in the
    other physical cases, on the grid [i_y2, i_y3]."""
    g2, g3 = np.meshgrid(y2, y3, indexing="ij")
    return np.where(case == 4, (g2 - 1) * (g3 - 1) / ((g2 + 1) * (g3 + 1)), 0.0)


@pytest.fixture(scope="module")
def floquet_grid(repo, tmp_path_factory):
    """The stability grid of Fig. 17's plane with the workflow config's settings, through HDF5."""
    from selfalign.stages.common import range_values
    from selfalign.stages.stability import stability_grid

    g = yaml.safe_load((repo / "workflow/config/config.yaml").read_text())["stages"]["stability"]["grids"]["fig17"]
    datasets, attrs = stability_grid(g["dt"], g["dy"], range_values(g["y2"]), range_values(g["y3"]),
                                     g["moreau_steps"])
    return read_h5(write_h5(tmp_path_factory.mktemp("grid") / "grid_fig17.h5", datasets, attrs))


def drawn_lambda2(fig, y2, y3):
    """lambda2 as panel (a) draws it, [i_y2, i_y3] (NaN where no value is drawn)."""
    mesh = fig.axes[0].collections[0]
    return np.ma.filled(np.ma.asarray(mesh.get_array(), dtype=float), np.nan).reshape(y3.size, y2.size).T


#: Tolerance of the drawn lambda2 against eq. (33): the analytic linearisation evaluates the
#: same closed form, so only rounding may differ.
EQ33_ATOL = 1e-15


def test_floquet_map_draws_eq33(floquet_grid):
    """Sect. 6.1, eq. (33): panel (a) of floquet_fig17 draws lambda2 = c4 in case 4 (slip-slip)
    and 0 in the other cases (atol 1e-15), nothing in case 0 (drawn grey); the plane holds cases
    0-4.  Panels (b)-(d) draw |lambda2 - eq. (33)| of the other methods, floored at 1e-17."""
    from selfalign.plots.stability import DIFFERENCE_FLOOR
    from selfalign.plots.style import print_check
    from selfalign.stages.figures import draw

    d = floquet_grid["datasets"]
    fig = draw("floquet_fig17", [floquet_grid])
    assert print_check(fig) == []
    case = d["case"]
    assert set(np.unique(case)) == {0, 1, 2, 3, 4}
    expected = np.where(case > 0, eq33(d["y2"], d["y3"], case), np.nan)
    np.testing.assert_allclose(drawn_lambda2(fig, d["y2"], d["y3"]), expected, rtol=0, atol=EQ33_ATOL)
    assert marked_cells(fig.axes[0], "non_physical", d["y2"], d["y3"]) == pytest.approx(np.sum(case == 0), abs=1e-6)
    for k, ax in zip(range(1, 4), fig.axes[1:4]):
        drawn = np.ma.filled(np.ma.asarray(ax.collections[0].get_array(), dtype=float), np.nan)
        shown = np.maximum(np.abs(d["multipliers"][k, ..., 1] - expected), DIFFERENCE_FLOOR)
        np.testing.assert_allclose(drawn.reshape(d["y3"].size, d["y2"].size).T, shown, rtol=1e-12)


def test_floquet_map_check_catches_a_wrong_multiplier(floquet_grid):
    """The check can fail: a result whose analytic lambda2 is off by 1e-12 in one case-4 cell
    is drawn off eq. (33) by more than the tolerance."""
    from selfalign.stages.figures import draw

    d = dict(floquet_grid["datasets"])
    i, j = np.argwhere(d["case"] == 4)[0]
    d["multipliers"] = d["multipliers"].copy()
    d["multipliers"][0, i, j, 1] += 1e-12
    fig = draw("floquet_fig17", [{"datasets": d, "attrs": floquet_grid["attrs"]}])
    error = np.abs(drawn_lambda2(fig, d["y2"], d["y3"]) - eq33(d["y2"], d["y3"], d["case"]))
    assert np.nanmax(error) > EQ33_ATOL


def test_floquet_map_data_matches_reference(repo, floquet_grid, update_figure_refs, dpi):
    """floquet_fig17 shows the same numbers as the committed reference, rtol 1e-9."""
    from selfalign.stages.figures import draw

    assert_data_matches(repo, draw("floquet_fig17", [floquet_grid]), "floquet_fig17", update_figure_refs, dpi)


def test_floquet_map_pixels_match_committed_png(repo, floquet_grid, tmp_path, dpi):
    """The committed figures/floquet_fig17.png is what the current code draws (RMS <= 1 of 255)."""
    from selfalign.stages.figures import draw

    assert_pixels_match(repo, draw("floquet_fig17", [floquet_grid]), "floquet_fig17", tmp_path, dpi)


def test_map_plots_refuse_bad_input_before_drawing():
    """A colour limit that is not a number > 0, and arrays not shaped like the grid, are
    ValueErrors naming the argument, raised before anything is drawn."""
    from selfalign.plots.classification import objective_panel
    from selfalign.plots.stability import floquet_map
    from selfalign.plots.style import new_figure

    ax = new_figure("single", 60).subplots()
    grid = np.ones((2, 2))
    with pytest.raises(ValueError, match="f_max must be a finite number > 0"):
        objective_panel(ax, [1.0, 2.0], [1.0, 2.0], grid, grid, 0.0)
    assert not ax.collections
    fig = new_figure("double", 100)
    with pytest.raises(ValueError, match=r"eq33 must be shaped \(len\(y2\), len\(y3\)\) = \(2, 2\)"):
        floquet_map(fig, [1.0, 2.0], [1.0, 2.0], grid, {"analytic": grid}, np.ones((2, 3)))
    assert not fig.axes
