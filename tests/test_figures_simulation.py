"""Figure regression for the simulation figures (Figs. 3, 9, 12) and the work-precision figures, and
their print standard (docs/explanation/figures.md, selfalign.plots.style).

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
from selfalign.analysis.classification import classify
from selfalign.io.hdf5 import read_h5, write_h5
from selfalign.io.simulation_result import trajectory_content
from selfalign.model.profiles import ThreePhaseProfile
from selfalign.plots import style
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
    cases = [classify(s.profile) for s in scenes]
    return figure_09(results, cases, periods=config(repo)["figures"]["fig09"]["periods"])


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
        for text in ax["texts"]:
            text["position"] = None  # a note goes to a free place, which the CPU times move
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


# The print standard (docs/explanation/figures.md): print size and fonts, lettered panels, Okabe-Ito
# line colours and the case colours of Table 1.

#: Colours a line of these figures may have: the Okabe-Ito palette and greys (zero lines, guides).
PALETTE = {colour.lower() for colour in style.OKABE_ITO.values()}


def line_colours(fig):
    """The colours of every line drawn, as hex (greys as "grey")."""
    from matplotlib.colors import to_hex, to_rgb

    colours = set()
    for ax in fig.axes:
        for line in ax.lines:
            r, g, b = to_rgb(line.get_color())
            colours.add("grey" if r == g == b and 0 < r < 1 else to_hex((r, g, b)))
    return colours


@pytest.fixture(scope="module")
def simulation_figures(repo, tmp_path_factory):
    tmp_path = tmp_path_factory.mktemp("simulation_figures")
    return {name: build(name, repo, tmp_path) for name in FIGURES}


@pytest.mark.parametrize("name", FIGURES)
def test_simulation_figures_meet_the_print_standard(simulation_figures, name):
    """Figs. 3, 9 and 12 print at a journal width with no text below 7 pt, no title but the panel
    letters (a, b, ... in reading order) and no ASCII mathematics (selfalign.plots.style.print_check),
    and every line is Okabe-Ito or grey (no "tab:" colour: tab:red and tab:green, which the friction
    bounds and tables used, fail for deuteranopes)."""
    fig = simulation_figures[name]
    assert style.print_check(fig) == []
    letters = [ax.get_title("left") for ax in fig.axes if ax.get_title("left")]
    assert letters == list("abcde"[:len(letters)]) and len(letters) >= 2, letters
    assert line_colours(fig) <= PALETTE | {"grey"}, line_colours(fig)


def test_fig09_names_each_case_in_its_colour(repo, simulation_figures):
    """Fig. 9 (Sect. 5.1, Table 1) names the case of each panel by a swatch in its case colour
    (style.CASE_COLORS, as in the case maps) and its label of Table 1 in mathtext (style.case_label, the
    case maps' colour-bar ticks): case 1 reads "x' >= 0" as $x' \\geq 0$."""
    from matplotlib.colors import to_hex

    fig = simulation_figures["fig09"]
    legends = [ax.get_legend() for ax in fig.axes if ax.get_legend() is not None]
    cases = [classify(s.profile) for s in fig09_scenes(repo)]
    assert cases == [1, 2, 3, 4, 5]
    assert [to_hex(legend.legend_handles[0].get_facecolor()) for legend in legends] == [
        to_hex(style.CASE_COLORS[case]) for case in cases]
    assert legends[0].get_texts()[0].get_text() == "case 1 stick-slip, $x' \\geq 0$"


def test_fig12_force_panel_draws_minus_ydd_equal_to_friction_in_stick(repo, simulation_figures, tmp_path):
    """Fig. 12 draws -y'' on the force axis, as the paper writes the model (eq. 5, -F_f = x'' + y''):
    where the mass sticks (x'' = 0) the friction force is F_f = -y'', so the two lines coincide there
    (to 1e-12), and where it slips forward F_f = +1 while -y'' is 2.2 (between t1 and t2, Sect. 5.1)."""
    from selfalign.io.simulation_result import trajectory_from_result

    scene = load_scene(repo / f"workflow/scenes/{config(repo)['figures']['fig12']['scene']}.yaml")
    traj = trajectory_from_result(simulated(scene, tmp_path))
    inertial, friction = simulation_figures["fig12"].axes[0].lines[:2]
    np.testing.assert_array_equal(inertial.get_ydata(), -np.asarray(traj.ydd))
    stick = (np.asarray(traj.v) == 0.0) & (np.abs(traj.ydd) <= 1.0)  # x' = 0 and |y''| <= 1: stick (Sect. 3.2)
    assert stick.sum() > 100
    np.testing.assert_allclose(friction.get_ydata()[stick], inertial.get_ydata()[stick], rtol=0, atol=1e-12)
    slip = np.asarray(traj.v) > 0.0
    assert np.all(friction.get_ydata()[slip] == 1.0) and np.max(inertial.get_ydata()[slip]) == pytest.approx(2.2)


# The work-precision figures: one per family of scenes, at most three columns at print width.

def accuracy_figures(repo):
    """Work-precision figure -> its scenes, as the workflow groups them (workflow/rules/figures.smk)."""
    from selfalign.stages.figures import accuracy_figure

    groups = {}
    for name in config(repo)["stages"]["accuracy"]["scenes"]:
        groups.setdefault(accuracy_figure(load_scene(repo / f"workflow/scenes/{name}.yaml")), []).append(name)
    return groups


def test_accuracy_scenes_split_into_figures_of_at_most_three_columns(repo):
    """The ten accuracy scenes (docs/explanation/solvers.md) go to four figures by family: the paper's
    model (accuracy_cost), effects beyond it (friction laws, finite jerk: accuracy_effects), several
    parts and planar motion; none has more than three columns, which print at 174 mm."""
    assert accuracy_figures(repo) == {
        "accuracy_cost": ["accuracy_steady", "accuracy_stop", "accuracy_long"],
        "accuracy_effects": ["accuracy_jerk", "accuracy_static", "accuracy_stribeck"],
        "accuracy_parts": ["accuracy_parts", "accuracy_parts_zone"],
        "accuracy_planar": ["accuracy_planar", "accuracy_planar_strip"]}


def test_accuracy_captions_name_every_scene_of_their_figure_with_its_panels(repo):
    """Each work-precision caption names the scenes its figure draws, in column order, each with its
    panel letters (column k: the k-th letter of the top row and of the bottom row), and no scene of
    another figure: the caption of a figure of three scenes does not describe six."""
    import string

    groups = accuracy_figures(repo)
    every = {scene for scenes in groups.values() for scene in scenes}
    for name, scenes in groups.items():
        caption = " ".join((repo / f"workflow/report/{name}.rst").read_text().split())
        named = [scene for scene in every if f"``{scene}``" in caption]
        assert sorted(named) == sorted(scenes), (name, named)
        at = [caption.index(f"``{scene}``") for scene in scenes]
        assert at == sorted(at), name
        for k, scene in enumerate(scenes):
            top, bottom = string.ascii_lowercase[k], string.ascii_lowercase[k + len(scenes)]
            assert f"({top}, {bottom}) ``{scene}``" in caption, (name, scene)


def test_accuracy_figure_takes_at_most_three_studies():
    """figure_accuracy_cost refuses more than three studies (a 174 mm figure holds three columns of
    log-log panels) before drawing, naming the split into several figures."""
    with pytest.raises(ValueError, match="1 to 3 studies.*split them"):
        figure_accuracy_cost([{}] * 4)
    with pytest.raises(ValueError, match="1 to 3 studies"):
        figure_accuracy_cost([])


def synthetic_study(reference_cpu_time):
    """A study as work_precision draws it: Moreau first order from (1e-5 s, 1e-1) to (1e-1 s, 1e-5),
    solve_ivp at 1e-2 s, the reference's line at ``reference_cpu_time``."""
    cpu = np.logspace(-5, -1, 9)
    moreau = {"cpu_time": cpu, "err_end_position": 1e-6 / cpu, "err_vbar": 1e-7 / cpu,
              "steps_per_period": np.logspace(1, 5, 9)}
    ivp = {"cpu_time": np.full(3, 1e-2), "err_end_position": np.array([1e-8, 1e-11, 1e-14]),
           "err_vbar": np.array([1e-9, 1e-12, 1e-15]), "rtol": np.array([1e-4, 1e-7, 1e-10])}
    return {"target_error": 1e-6, "moreau_order": 1.0, "note": "", "rounding_level_position": 1e-16,
            "rounding_level_vbar": 1e-16, "moreau": moreau, "ivp": ivp, "reference": ("exact", {}),
            "reference_cpu_time": reference_cpu_time}


def crossings(ax, text):
    """The lines and marker groups of ``ax`` that ``text`` covers, in display coordinates."""
    box = text.get_window_extent()
    hit = [line.get_label() for line in ax.lines
           if line.get_transform().transform_path(line.get_path()).intersects_bbox(box, filled=False)]
    hit += [c.get_label() for c in ax.collections
            if box.padded(2.0 * ax.figure.dpi / 72).count_contains(c.get_offset_transform().transform(c.get_offsets()))]
    return hit


@pytest.mark.parametrize("reference_cpu_time", [1.2e-5, 6e-2, 2e-3])
def test_work_precision_notes_cover_no_data(reference_cpu_time):
    """The "Moreau order" note of a work-precision panel covers no line or marker wherever the
    reference's CPU time falls: at the left edge (the exact solver), at the right (a slow reference,
    solve_ivp at rtol 1e-13 under Stribeck friction, whose line struck through the note in the top
    right corner) and in the middle."""
    from selfalign.plots.simulation import work_precision

    fig = work_precision(style.new_figure("double", 135), [synthetic_study(reference_cpu_time)] * 3)
    for ax in fig.axes[:3]:
        (note,) = ax.texts
        assert note.get_text() == "Moreau order 1.00"
        assert crossings(ax, note) == [], (reference_cpu_time, note.get_position())


@pytest.fixture(scope="module")
def stribeck_result(repo, tmp_path_factory):
    """The study of accuracy_stribeck on tiny settings: its reference is solve_ivp (the scene's solver block)."""
    tiny = StudySettings(moreau_steps_per_period=(10, 1000, 3), ivp_rtol=(1e-4, 1e-6, 2), fit_min_steps_per_period=10,
                         min_timing=1e-9)
    path = tmp_path_factory.mktemp("stribeck") / "accuracy_stribeck.h5"
    write_h5(path, *study(load_scene(repo / "workflow/scenes/accuracy_stribeck.yaml"), tiny, progress="quiet"))
    return read_h5(path)


def test_work_precision_labels_the_reference_by_what_it_is(stribeck_result):
    """The vertical line at the reference's CPU time is labelled by the reference it is: for the Stribeck
    scene (docs/explanation/solvers.md: "Reference") solve_ivp at rtol 1e-13, atol 1e-15, not the exact
    solver, which cannot simulate Stribeck friction; the figure meets the print standard."""
    fig = figure_accuracy_cost([stribeck_result])
    assert style.print_check(fig) == []
    labels = [line.get_label() for ax in fig.axes for line in ax.lines if "(reference)" in line.get_label()]
    assert set(labels) == {"solve_ivp DOP853, rtol $10^{-13}$, atol $10^{-15}$ (reference): its CPU time"}
    legend = [text.get_text() for text in fig.legends[0].get_texts()]
    assert not any("exact" in text for text in legend), legend
    assert [ax.get_title("left") for ax in fig.axes if ax.get_title("left")] == ["a", "b"]


def test_fig09_lines_take_no_case_colour(simulation_figures):
    """In Fig. 9 a case colour (style.CASE_COLORS) means a case of Table 1 only: no line (x', y'', the
    friction bounds) is drawn in one, so the vermillion of case 2 is not also the friction bounds'."""
    from matplotlib.colors import to_hex

    cases = {to_hex(colour) for colour in style.CASE_COLORS.values()}
    assert line_colours(simulation_figures["fig09"]).isdisjoint(cases)
