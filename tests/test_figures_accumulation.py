"""Figure regression for the stopping figures (Figs. 14-18, Sect. 7).

Same pattern as tests/test_figures.py: each figure is rebuilt from freshly
computed data (the accumulation stage's library calls with the workflow
config's settings, through HDF5 as in the pipeline) and the numbers it shows
are compared with ``tests/figure_refs/<fig>.json`` (rtol 1e-9); the pixels with
the committed ``figures/<fig>.png`` only under the pinned matplotlib series.
``--update-figure-refs`` rewrites both.

Fig. 17's full grid (101 x 101 settings x 64 entries) takes ~25 s, so the test
draws it from a coarse grid (COARSE_AXIS settings per axis, COARSE_ENTRIES
entries): its reference is that coarse figure, and the committed
``figures/fig17.png`` (the workflow's full grid) is not compared.
"""


import numpy as np
import pytest
import yaml
from figcheck import compare_figure_data, figure_data, load_reference
from test_figures import ATOL, RTOL, assert_data_matches, assert_pixels_match

from selfalign.io.hdf5 import read_h5, write_h5
from selfalign.model.profiles import ThreePhaseProfile
from selfalign.stages.accumulation import fig16_content, fig17_content, fig18_content
from selfalign.stages.figures import draw

FIGURES = ("fig14", "fig15", "fig16", "fig17", "fig18")
#: Figures whose committed PNG is drawn from the same data the test computes.
PIXEL_FIGURES = ("fig14", "fig15", "fig16", "fig18")
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
    """Figs. 14-16 (Sects. 7.1-7.2), 17 (Sect. 7.2, coarse grid) and 18 (Sect. 7.3) show the
    same numbers as their committed references, rtol 1e-9."""
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
    panel_d = draw("fig17", [result, fig18_result(p, tmp_path)]).axes[3]
    assert panel_d.get_title(loc="left") == "D" and panel_d.get_xlabel() == "$y_2''$"
    # The mesh is drawn with y2'' along x, so its array is the [i_y2, i_y3] layout transposed.
    shown = np.ma.filled(np.ma.asarray(panel_d.collections[0].get_array(), dtype=float), np.nan).T
    assert shown.shape == d["dx_d"].shape
    assert not np.isfinite(shown[unsettled]).any()
    np.testing.assert_array_equal(shown[at_rest], d["dx_d"][at_rest])
