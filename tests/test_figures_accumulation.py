"""Figure regression and the figure standard for the stop zone (Fig. 2, Sect. 3.3) and the
stopping figures (Figs. 14-18, Sect. 7).

Same pattern as tests/test_figures.py: each figure is rebuilt from freshly
computed data (the accumulation stage's library calls with the workflow
config's settings, through HDF5 as in the pipeline) and the numbers it shows
are compared with ``tests/figure_refs/<fig>.json`` (rtol 1e-9); the pixels with
the committed ``figures/<fig>.png`` only under the pinned matplotlib series.
``--update-figure-refs`` rewrites both.

Fig. 17's full grid (101 x 101 settings x 64 entries) takes ~25 s, so the test
draws it from a coarse grid (COARSE_AXIS settings per axis, COARSE_ENTRIES
entries): its reference is that coarse figure, and the committed
``figures/fig17.png`` (the workflow's full grid) is not compared.  Fig. 2 needs no result: it
is drawn from the workflow's stop zone (``stages.accumulation.zone``) and the model's own
friction coefficient.
"""


import numpy as np
import pytest
import yaml
from figcheck import compare_figure_data, figure_data, load_reference
from matplotlib.colors import LogNorm, to_hex, to_rgb
from matplotlib.legend import Legend
from matplotlib.patches import PathPatch
from test_figures import ATOL, RTOL, assert_data_matches, assert_pixels_match

from selfalign.io.hdf5 import read_h5, write_h5
from selfalign.model.friction import StopZone
from selfalign.model.profiles import ThreePhaseProfile
from selfalign.plots import colour_vision, style
from selfalign.stages.accumulation import fig16_content, fig17_content, fig18_content, setting_group
from selfalign.stages.figures import draw

FIGURES = ("fig02", "fig14", "fig15", "fig16", "fig17", "fig18")
#: Figures whose committed PNG is drawn from the same data the test computes.
PIXEL_FIGURES = ("fig02", "fig14", "fig15", "fig16", "fig18")
#: The coarse Fig. 17 grid of the test: settings per axis (same range as the config), entries per setting.
COARSE_AXIS, COARSE_ENTRIES = 9, 8


def config(repo):
    return yaml.safe_load((repo / "workflow/config/config.yaml").read_text())


def stage(repo, **changes):
    """The config's ``stages.accumulation`` with the blocks in ``changes`` replaced."""
    return {**config(repo)["stages"]["accumulation"], **changes}


def coarse_fig17_result(p, tmp_path):
    """fig17.h5 of the coarse test grid (COARSE_AXIS settings per axis, COARSE_ENTRIES entries)
    with the stage's settings ``p``, read back."""
    zone, pos = p["zone"], p["positioning"]
    axis = np.linspace(pos["y2"]["from"], pos["y2"]["to"], COARSE_AXIS)
    h5 = tmp_path / "fig17.h5"
    write_h5(h5, *fig17_content(axis, axis, dt=pos["dt"], dy=pos["dy"], w=zone["w"], c_mu=zone["c_mu"],
                                n_entries=COARSE_ENTRIES, max_periods=pos["max_periods"], levels=pos["levels"]))
    return read_h5(h5)


def fig18_result(p, tmp_path):
    """fig18.h5 with the stage's settings ``p``, read back."""
    s, zone = p["stick_map"], p["zone"]
    h5 = tmp_path / "fig18.h5"
    write_h5(h5, *fig18_content(ThreePhaseProfile(s["dt"], s["dy"], s["y2"], s["y3"]), w=zone["w"],
                                c_mu=zone["c_mu"], points=s["points"]))
    return read_h5(h5)


def build(name, p, tmp_path):
    """Figure ``name`` from the stage's library steps with settings ``p`` (scene -> HDF5 -> figure),
    drawn as the workflow's plot rules draw it."""
    zone, pos = p["zone"], p["positioning"]
    if name == "fig02":
        # The workflow gives Fig. 2 the accumulation stage's zone (workflow/rules/figures.smk).
        return draw(name, [], zone=zone)
    if name == "fig17":
        # Fig. 17 marks the setting of Fig. 18, read from its result (workflow/rules/figures.smk).
        return draw(name, [coarse_fig17_result(p, tmp_path), fig18_result(p, tmp_path)])
    if name == "fig18":
        return draw(name, [fig18_result(p, tmp_path)])
    h5 = tmp_path / f"{name}.h5"
    settings = p["portraits"]["settings"]
    write_h5(h5, *fig16_content([tuple(pair) for pair in settings], dt=pos["dt"], dy=pos["dy"], w=zone["w"],
                                c_mu=zone["c_mu"], n_entries=p["portraits"]["n_entries"]))
    # Figs. 14 and 15 show the last setting of Fig. 16, as the workflow's figure registry says.
    options = {"settings": settings} if name == "fig16" else {"setting": settings[-1]}
    return draw(name, [read_h5(h5)], **options)


@pytest.mark.parametrize("name", FIGURES)
def test_figure_data_matches_reference(repo, tmp_path, update_figure_refs, name):
    """Figs. 2 (Sect. 3.3), 14-16 (Sects. 7.1-7.2), 17 (Sect. 7.2, coarse grid) and 18 (Sect. 7.3)
    show the same numbers as their committed references, rtol 1e-9."""
    assert_data_matches(repo, build(name, stage(repo), tmp_path), name, update_figure_refs,
                        config(repo)["figures"]["dpi"] if name in PIXEL_FIGURES else None)


@pytest.mark.parametrize("name", FIGURES)
def test_figure_pixels_match_committed_png(repo, tmp_path, name):
    """The committed figures/<name>.png is what the current code draws (RMS <= 1 of 255)."""
    if name not in PIXEL_FIGURES:
        pytest.skip(f"figures/{name}.png is the workflow's full 101 x 101 grid; the test draws a "
                    f"{COARSE_AXIS} x {COARSE_AXIS} grid, so only its data are compared")
    assert_pixels_match(repo, build(name, stage(repo), tmp_path), name, tmp_path,
                        config(repo)["figures"]["dpi"])


def test_fig18_comparison_catches_friction_change(repo, tmp_path):
    """The check can fail: c_mu 1 % larger (2.5 -> 2.525) is reported on the eq. (59) line of Fig. 18."""
    zone = stage(repo)["zone"]
    changed = build("fig18", stage(repo, zone={**zone, "c_mu": zone["c_mu"] * 1.01}), tmp_path)
    diffs = compare_figure_data(figure_data(changed), load_reference(repo / "tests/figure_refs/fig18.json"),
                                rtol=RTOL, atol=ATOL)
    assert any(d.startswith("figure.axes[0].lines[0].y") for d in diffs), diffs


def test_fig16_comparison_catches_setting_change(repo, tmp_path):
    """The check can fail: y3'' of the lower Fig. 16 panel 1 % larger (1.1 -> 1.111) is reported
    on its phase portrait."""
    portraits = stage(repo)["portraits"]
    settings = [list(pair) for pair in portraits["settings"]]
    settings[-1][1] *= 1.01
    changed = build("fig16", stage(repo, portraits={**portraits, "settings": settings}), tmp_path)
    diffs = compare_figure_data(figure_data(changed), load_reference(repo / "tests/figure_refs/fig16.json"),
                                rtol=RTOL, atol=ATOL)
    # Two panels per setting (phase portrait, sticks): the lower portrait is axes[2].
    assert any(d.startswith(f"figure.axes[{2 * (len(settings) - 1)}].lines[0].x") for d in diffs), diffs


#: A small Fig. 17 grid across the band y3'' ~ y2'' where some entries stop and others never stop
#: or stay undecided (there the result holds a finite Delta x_d over the stopped entries only),
#: beside settings where every entry stops or accumulates; ENTRIES_AT_BAND entries per setting.
BAND_Y2, BAND_Y3, ENTRIES_AT_BAND = (1.5, 1.74, 2.0, 2.3), (1.2, 1.84, 2.12), 16


def test_fig17_shows_dx_d_only_where_every_entry_ends_at_rest(repo, tmp_path):
    """Panel D of Fig. 17 shows Delta x_d only for settings whose entries all stop or accumulate:
    where some entry never stops or stays undecided, Delta x_d would span only the entries that
    stopped (down to 1 of 64), so no value is shown there; every setting whose entries all end
    at rest shows its value.  The grid holds settings of both kinds, and a finite Delta x_d in
    some settings that must stay empty, so drawing the result unfiltered fails this test."""
    p = stage(repo)
    zone, pos = p["zone"], p["positioning"]
    h5 = tmp_path / "band.h5"
    write_h5(h5, *fig17_content(np.array(BAND_Y2), np.array(BAND_Y3), dt=pos["dt"], dy=pos["dy"], w=zone["w"],
                                c_mu=zone["c_mu"], n_entries=ENTRIES_AT_BAND, max_periods=pos["max_periods"],
                                levels=pos["levels"]))
    result = read_h5(h5)
    d = result["datasets"]
    unsettled = (d["frac_never_stop"] > 0) | (d["frac_undecided"] > 0)
    at_rest = (d["frac_never_stop"] == 0) & (d["frac_undecided"] == 0)
    assert at_rest.any() and np.isfinite(d["dx_d"][unsettled]).any(), "the grid must hold settings of both kinds"
    panel_d = draw("fig17", [result, fig18_result(p, tmp_path)]).axes[PANEL_D]
    assert panel_d.get_title(loc="left") == "d" and panel_d.get_xlabel() == "$y_2''$"
    shown = mesh_values(panel_d)
    assert shown.shape == d["dx_d"].shape
    assert not np.isfinite(shown[unsettled]).any()
    positive = at_rest & (d["dx_d"] > 0)
    assert positive.any()
    np.testing.assert_array_equal(shown[positive], d["dx_d"][positive])
    # The unsettled settings are marked in panels c and d, in the encoding "unsettled".
    for ax in (draw("fig17", [result]).axes[i] for i in (PANEL_C, PANEL_D)):
        np.testing.assert_array_equal(marked_cells(ax, d["y2"], d["y3"], "unsettled"), unsettled)


#: Indices of panels c and d of Fig. 17 in ``fig.axes`` (the maps a-d come first, then their colour bars).
PANEL_C, PANEL_D = 2, 3


def mesh_values(ax):
    """The values of the first map of ``ax`` as [i_y2, i_y3] (the mesh is drawn with y2'' along x,
    so its array is that layout transposed), NaN where nothing is shown."""
    return np.ma.filled(np.ma.asarray(ax.collections[0].get_array(), dtype=float), np.nan).T


def marked_cells(ax, y2, y3, kind):
    """[i_y2, i_y3] mask of the cells drawn in the special-value encoding ``kind`` on ``ax``:
    the cell centres inside the patch of that face colour and hatch (style.mark_cells)."""
    encoding = style.SPECIAL[kind]
    patches = [p for p in ax.patches if isinstance(p, PathPatch) and (p.get_hatch() or "") == encoding["hatch"]
               and (encoding["facecolor"] == "none" or to_hex(p.get_facecolor()) == to_hex(encoding["facecolor"]))
               and (encoding["facecolor"] != "none" or p.get_facecolor()[3] == 0)]
    centres = np.array([(a, b) for a in y2 for b in y3])
    mask = np.zeros(centres.shape[0], dtype=bool)
    for patch in patches:
        mask |= patch.get_path().contains_points(centres)
    return mask.reshape(len(y2), len(y3))


def test_fig17_draws_exact_zeros_in_their_own_encoding(repo, tmp_path):
    """Sect. 7.2: "the occurrence of accumulation results in ... Delta x_d = 0".  Panel d draws
    the settings with Delta x_d = 0 exactly (every entry accumulates) in the encoding "dx_zero",
    and only them, and the positive values on a log scale of the Delta x_d map, so that the two
    can be told apart: on the coarse grid, both kinds occur, the marked cells are exactly the
    zeros (where panel c shows "all accumulate") and the map shows no zero.  Drawing zeros in the
    map (as its darkest colour) fails this test."""
    p = stage(repo)
    result = coarse_fig17_result(p, tmp_path)
    d = result["datasets"]
    settled = (d["frac_never_stop"] == 0) & (d["frac_undecided"] == 0)
    zero = settled & (d["dx_d"] == 0)
    assert zero.any() and (settled & (d["dx_d"] > 0)).any(), "the grid must hold zeros and positive values"
    fig = draw("fig17", [result])
    panel_c, panel_d = fig.axes[PANEL_C], fig.axes[PANEL_D]
    np.testing.assert_array_equal(marked_cells(panel_d, d["y2"], d["y3"], "dx_zero"), zero)
    np.testing.assert_array_equal(mesh_values(panel_c)[zero], 2.0)  # "all accumulate"
    shown = mesh_values(panel_d)
    assert np.all(np.isnan(shown[zero])) and np.nanmin(shown) > 0
    assert isinstance(panel_d.collections[0].norm, LogNorm)
    assert panel_d.collections[0].get_cmap().name == style.QUANTITY_CMAPS["dx_d"]
    labels = [t.get_text() for legend in fig.legends for t in legend.get_texts()]
    assert style.SPECIAL["dx_zero"]["label"] in labels


def test_fig17_classes_in_the_fraction_colours(repo, tmp_path):
    """Panel c draws none / some / all of the entries accumulating in the fraction classes of the
    figure standard (style.FRACTION_COLORS, in that order)."""
    fig = draw("fig17", [coarse_fig17_result(stage(repo), tmp_path)])
    cmap = fig.axes[PANEL_C].collections[0].get_cmap()
    assert [to_hex(cmap(i)) for i in range(cmap.N)] == [to_hex(c) for c in style.FRACTION_COLORS]


def test_fig17_marks_the_fig18_setting_only_in_its_own_plane(repo, tmp_path):
    """Fig. 18's setting (y2'', y3'') = (2.2, 0.9) is at Delta t = 1.05, where it is case 1; in
    Fig. 17's plane (Delta t = 1) the same accelerations are case 0, so the setting is not a point
    of that plane and is not marked.  Were Fig. 18 at the grid's Delta t, it would be marked on
    every panel."""
    p = stage(repo)
    result, stick_map = coarse_fig17_result(p, tmp_path), fig18_result(p, tmp_path)
    assert stick_map["attrs"]["dt"] != result["attrs"]["dt"]
    label = "Fig. 18 setting"
    fig = draw("fig17", [result, stick_map])
    assert not any(line.get_label() == label for ax in fig.axes for line in ax.lines)
    same_plane = {**stick_map, "attrs": {**stick_map["attrs"], "dt": result["attrs"]["dt"]}}
    fig = draw("fig17", [result, same_plane])
    marked = [ax for ax in fig.axes if any(line.get_label() == label for line in ax.lines)]
    assert len(marked) == 4


@pytest.mark.parametrize("name", FIGURES)
def test_figure_meets_the_print_standard_with_legends_off_the_data(repo, tmp_path, name):
    """Every figure passes style.print_check (print width, text >= 7 pt, lowercase panel
    letters, no titles, mathtext) and no legend overlaps an axes (legends off the data)."""
    fig = build(name, stage(repo), tmp_path)
    assert style.print_check(fig) == []
    assert overlapping_legends(fig) == []


def overlapping_legends(fig):
    """(legend, axes index) of every legend drawn over an axes of ``fig`` by more than a pixel."""
    fig.draw_without_rendering()
    found = []
    for legend in fig.findobj(Legend):
        box = legend.get_window_extent()
        for k, ax in enumerate(fig.axes):
            a = ax.get_window_extent()
            width = min(box.x1, a.x1) - max(box.x0, a.x0)
            height = min(box.y1, a.y1) - max(box.y0, a.y0)
            if width > 1 and height > 1:
                found.append(([t.get_text() for t in legend.get_texts()][:1], k))
    return found


def test_legend_check_can_fail(repo, tmp_path):
    """The legend check reports a legend drawn inside the axes."""
    fig = build("fig15", stage(repo), tmp_path)
    fig.axes[0].legend(["end positions"], loc="upper left")
    assert overlapping_legends(fig) == [(["end positions"], 0)]


@pytest.mark.parametrize("name", FIGURES)
def test_figure_draws_lines_and_text_in_okabe_ito_or_grey(repo, tmp_path, name):
    """Lines, markers and texts are drawn in Okabe-Ito colours (style.OKABE_ITO, colour-blind
    safe) or in greys; a "tab:" colour (the previous default cycle) fails this."""
    fig = build(name, stage(repo), tmp_path)
    allowed = {to_hex(c) for c in style.OKABE_ITO.values()}
    colours = [line.get_color() for ax in fig.axes for line in ax.lines]
    colours += [text.get_color() for ax in fig.axes for text in ax.texts]
    off = {to_hex(c) for c in colours if to_hex(c) not in allowed and not is_grey(c)}
    assert not off, off


def is_grey(colour) -> bool:
    """Red, green and blue equal (black, white and the greys)."""
    r, g, b = to_rgb(colour)
    return r == g == b


def test_colour_check_can_fail():
    """The colour check tells a "tab:" colour from Okabe-Ito blue and a grey."""
    assert not is_grey("tab:blue") and to_hex("tab:blue") not in {to_hex(c) for c in style.OKABE_ITO.values()}
    assert is_grey("0.5") and is_grey("k")


def test_fig18_runs_in_colours_every_reader_tells_apart(repo, tmp_path):
    """The two stick sequences of Fig. 18 (accumulating, resting) are drawn in Okabe-Ito colours
    that stay at least colour_vision.MIN_DELTA_E apart under protanopia, deuteranopia and
    tritanopia (green and red, Delta E 7.3 for a deuteranope, fail this)."""
    fig = build("fig18", stage(repo), tmp_path)
    colours = [line.get_color() for line in fig.axes[0].lines if line.get_label().startswith("stick positions")]
    assert len(colours) == 2 and {to_hex(c) for c in colours} <= {to_hex(c) for c in style.OKABE_ITO.values()}
    for vision in colour_vision.DEFICIENCIES:
        assert colour_vision.delta_e(*colours, vision) >= colour_vision.MIN_DELTA_E, vision


def test_fig14_marks_the_transition_zone(repo, tmp_path):
    """Fig. 14 shows the transition zone x_mu <= x <= x_mu + w of eqs. (7)-(9): the friction
    gradient spans exactly that interval and both of its ends are marked and named."""
    p = stage(repo)
    fig = build("fig14", p, tmp_path)
    ax = fig.axes[0]
    result = read_h5(tmp_path / "fig14.h5")
    x_mu, w = result["groups"][setting_group(*p["portraits"]["settings"][-1])]["attrs"]["x_mu"], p["zone"]["w"]
    (image,) = ax.images
    np.testing.assert_allclose(image.get_extent()[:2], [x_mu, x_mu + w], rtol=1e-12)
    marks = {t.get_text(): t.get_position()[0] for t in ax.texts}
    assert marks[r"$x_\mu$"] == pytest.approx(x_mu, rel=1e-12)
    assert marks[r"$x_\mu + w$"] == pytest.approx(x_mu + w, rel=1e-12)


def eq7_coefficient(x, x_mu, w, c_mu):
    """mu_bar / mu of eqs. (7) and (8), written out here: z = min(max(x - x_mu, 0), w),
    mu_bar = (w + (c_mu - 1) z) / w."""
    z = np.minimum(np.maximum(np.asarray(x) - x_mu, 0.0), w)
    return (w + (c_mu - 1.0) * z) / w


def friction_curve(fig):
    """(x, mu_bar) of the friction curve of Fig. 2 b."""
    (line,) = [line for line in fig.axes[1].lines if line.get_label().startswith(r"$\bar\mu(x)$")]
    return line.get_xdata(), line.get_ydata()


def test_fig02_draws_the_models_friction_coefficient(repo, tmp_path):
    """Fig. 2 b is mu_bar(x) of eqs. (7)-(9) (Sect. 3.3) as the model computes it
    (StopZone.coefficient, exactly) and as eqs. (7)-(8) give it (rtol 1e-12), across the whole
    transition x_mu <= x <= x_mu + w (both ends drawn) and beyond it on either side, for the
    workflow's zone."""
    zone = stage(repo)["zone"]
    model = StopZone(x_mu=0.0, w=zone["w"], c_mu=zone["c_mu"])
    x, y = friction_curve(build("fig02", stage(repo), tmp_path))
    np.testing.assert_array_equal(y, model.coefficient(x))
    np.testing.assert_allclose(y, eq7_coefficient(x, 0.0, zone["w"], zone["c_mu"]), rtol=1e-12, atol=0)
    assert x.min() < 0.0 and x.max() > zone["w"] and {0.0, zone["w"]} <= set(x.tolist())
    assert y.min() == 1.0 and y.max() == zone["c_mu"]


def test_fig02_check_catches_another_friction(repo, tmp_path):
    """The check can fail: Fig. 2 drawn for c_mu 1 % larger (2.5 -> 2.525) differs from eq. (7)
    of the workflow's zone by more than the tolerance, and its reference reports the change."""
    p = stage(repo)
    zone = p["zone"]
    changed = build("fig02", stage(repo, zone={**zone, "c_mu": zone["c_mu"] * 1.01}), tmp_path)
    x, y = friction_curve(changed)
    assert not np.allclose(y, eq7_coefficient(x, 0.0, zone["w"], zone["c_mu"]), rtol=1e-12, atol=0)
    diffs = compare_figure_data(figure_data(changed), load_reference(repo / "tests/figure_refs/fig02.json"),
                                rtol=RTOL, atol=ATOL)
    assert any(d.startswith("figure.axes[1].lines[0].y") for d in diffs), diffs


@pytest.mark.parametrize("vision", sorted(colour_vision.DEFICIENCIES))
def test_fig17_exact_zeros_stand_apart_from_every_positive_value(vision):
    """In Fig. 17 d the encoding of Delta x_d = 0 (sky blue) stays at least MIN_DELTA_E from every
    colour of the Delta x_d map (cividis, 101 samples) under protanopia, deuteranopia,
    tritanopia and normal vision (measured: at least 39), so no positive value can be read as
    an exact zero.  The check can fail: zeros drawn in the map's own darkest colour come closer
    than MIN_DELTA_E to the smallest positive values."""
    from matplotlib import colormaps

    cmap = colormaps[style.QUANTITY_CMAPS["dx_d"]]
    samples = [cmap(t)[:3] for t in np.linspace(0.0, 1.0, 101)]

    def closest(zero):
        return min(colour_vision.delta_e(zero, c, vision) for c in samples if c != zero)

    assert closest(style.SPECIAL["dx_zero"]["facecolor"]) >= colour_vision.MIN_DELTA_E
    assert closest(samples[0]) < colour_vision.MIN_DELTA_E
