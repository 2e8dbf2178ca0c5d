"""The stage "effects": accumulation and Delta x_d under static friction mu_s = r mu_k,
from the result file's contents to its figure (docs/explanation/stopping.md)."""

import numpy as np
import pytest

from selfalign.analysis.positioning import positioning
from selfalign.io.hdf5 import read_dataset_attrs, read_h5, write_h5
from selfalign.model.profiles import ThreePhaseProfile
from selfalign.plots.style import print_check
from selfalign.stages.effects import friction_law, static_friction_content
from selfalign.stages.figures import draw

ZONE = {"dt": 1.0, "dy": 0.084, "w": 0.05, "c_mu": 2.5}


@pytest.fixture(scope="module")
def content():
    """A 3 x 3 grid around the Fig. 16 setting (2.3, 1.3), where every entry accumulates under
    Coulomb friction, at r = 1 and 1.3; the sweep of that setting over r - 1 = 0.01, 0.1."""
    axis = np.array([2.1, 2.3, 2.5]), np.array([1.1, 1.3, 1.5])
    return static_friction_content(*axis, [1.0, 1.3], [[2.3, 1.3]], [0.01, 0.1], n_entries=8, sweep_entries=8,
                                   max_periods=1000, **ZONE)


def test_accumulation_region_empties_and_dx_d_grows_with_r(content):
    """The region of Fig. 17 where entries accumulate is not empty at r = 1 and empty at r = 1.3;
    the swept setting accumulates at r = 1 (Delta x_d = 0) and rests at r > 1 with a Delta x_d
    that grows with r."""
    _, _, groups = content
    maps, sweep = groups["maps"]["datasets"], groups["sweep"]["datasets"]
    assert np.nanmax(maps["frac_accumulate"][0]) == 1.0
    assert np.nanmax(maps["frac_accumulate"][1]) == 0.0
    assert sweep["ratio"].tolist() == [1.0, 1.01, 1.1]
    assert sweep["frac_accumulate"][0].tolist() == [1.0, 0.0, 0.0]
    assert sweep["dx_d"][0, 0] == 0.0 and 0.0 < sweep["dx_d"][0, 1] < sweep["dx_d"][0, 2]


def test_sweep_equals_positioning_of_the_setting(content):
    """Each sweep column is the positioning of its setting under that friction law (the batched
    grid and the one-setting function agree bit for bit)."""
    _, _, groups = content
    sweep = groups["sweep"]["datasets"]
    profile = ThreePhaseProfile(ZONE["dt"], ZONE["dy"], 2.3, 1.3)
    for k, r in enumerate(sweep["ratio"]):
        pos = positioning(profile, w=ZONE["w"], c_mu=ZONE["c_mu"], n_entries=8, friction=friction_law(r))
        assert sweep["dx_d"][0, k] == pos.dx_d and sweep["frac_accumulate"][0, k] == pos.frac_accumulate


def test_result_file_is_documented_and_draws(content, tmp_path):
    """Every dataset of the file gets units and a description, and the figure (at print size,
    print_check empty) has one map per r, lettered a, b, plus the Delta x_d panel c, whose log axes
    show the swept r - 1; each map counts the settings where some entry accumulates."""
    path = write_h5(tmp_path / "static_friction.h5", *content)
    assert all(meta["units"] and meta["description"] for meta in read_dataset_attrs(path).values())
    fig = draw("static_friction", [read_h5(path)])
    assert print_check(fig) == []
    panels = [ax for ax in fig.axes if ax.axison]
    assert [ax.get_title(loc="left") for ax in panels] == ["a", "b", "c"]
    sweep_ax = panels[-1]
    assert sweep_ax.get_xscale() == "log" and sweep_ax.get_yscale() == "log"
    assert sweep_ax.lines[0].get_xdata().tolist() == pytest.approx([0.01, 0.1])
    assert [t.get_text() for t in panels[1].texts] == ["some accumulate:\n0 of 9"]
