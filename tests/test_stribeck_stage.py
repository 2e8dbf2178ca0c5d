"""The Stribeck study of the stage "effects": vbar, accumulation and Delta x_d against
the Stribeck velocity v_s, from the result file's contents to its figure (docs/explanation/stopping.md
)."""

import numpy as np
import pytest

from selfalign.analysis.finite_jerk import stopping
from selfalign.analysis.steady_simulation import simulated_steady_state
from selfalign.io.hdf5 import read_dataset_attrs, read_h5, write_h5
from selfalign.model.profiles import ThreePhaseProfile
from selfalign.plots.style import print_check
from selfalign.stages.effects import friction_law, stribeck_content
from selfalign.stages.figures import draw

RATIO, DELTA, STEPS = 1.3, 2.0, 10_000
STEADY = {"dt": 1.38, "dy": 0.064, "settings": [[2.0, 0.5], [2.5, 1.2]]}
ENTRIES = {"dt": 1.0, "dy": 0.084, "w": 0.05, "c_mu": 2.5, "settings": [[2.3, 1.3], [2.4, 2.0]], "n_entries": 16,
           "max_periods": 1000}
#: v_s / velocity swing: the study's small end and its large end.
FRACTIONS = [1.0e-3, 1.0]
#: First-order convergence of Stribeck to static/kinetic friction: docs/explanation/solvers.md measures an
#: end-position error of 0.19 v_s (Fig. 18 profile); twice that bounds each end position (so
#: Delta x_d) and vbar, whose error per unit v_s is 0.04 to 0.21 on Fig. 11's plane.
FIRST_ORDER = 2 * 0.19


@pytest.fixture(scope="module")
def content():
    return stribeck_content(FRACTIONS, ratio=RATIO, delta=DELTA, steps_per_period=STEPS, steady=STEADY,
                            entries=ENTRIES)


def test_small_v_s_end_agrees_with_static_kinetic_friction(content):
    """At v_s = 1e-3 velocity swings, vbar, the accumulating fraction and Delta x_d equal their
    exact static/kinetic values up to the first-order Stribeck error FIRST_ORDER v_s plus the
    Moreau error of the static/kinetic law itself at the same step (measured here)."""
    _, _, groups = content
    steady, entries = groups["stribeck_steady"]["datasets"], groups["stribeck_stopping"]["datasets"]
    for k, (y2, y3) in enumerate(STEADY["settings"]):
        profile = ThreePhaseProfile(STEADY["dt"], STEADY["dy"], y2, y3)
        moreau = simulated_steady_state([profile], "moreau", steps_per_period=STEPS, progress="quiet",
                                        friction=friction_law(RATIO)).vbar[0]
        step_error = abs(moreau - steady["vbar_static_kinetic"][k])
        v_s = FRACTIONS[0] * steady["velocity_swing"][k]
        assert abs(steady["vbar"][k, 0] - steady["vbar_static_kinetic"][k]) <= FIRST_ORDER * v_s + step_error
    for k, (y2, y3) in enumerate(ENTRIES["settings"]):
        profile = ThreePhaseProfile(ENTRIES["dt"], ENTRIES["dy"], y2, y3)
        moreau = stopping(profile, w=ENTRIES["w"], c_mu=ENTRIES["c_mu"], n_entries=ENTRIES["n_entries"],
                          steps_per_period=STEPS, max_periods=ENTRIES["max_periods"], friction=friction_law(RATIO))
        step_error = abs(moreau.dx_d - entries["dx_d_static_kinetic"][k])
        v_s = FRACTIONS[0] * entries["velocity_swing"][k]
        assert entries["frac_accumulate"][k, 0] == entries["frac_accumulate_static_kinetic"][k] == 0.0
        assert abs(entries["dx_d"][k, 0] - entries["dx_d_static_kinetic"][k]) <= FIRST_ORDER * v_s + step_error


def test_large_v_s_brings_accumulation_back(content):
    """At v_s = one velocity swing some (not all) entries of both Fig. 17 settings accumulate,
    which accumulate under Coulomb friction and never under static/kinetic friction; every
    entry ends at rest or accumulates, and Delta x_d falls below its static/kinetic value."""
    _, _, groups = content
    entries = groups["stribeck_stopping"]["datasets"]
    assert entries["frac_accumulate_coulomb"].tolist() == [1.0, 1.0]
    assert np.all((entries["frac_accumulate"][:, 1] > 0.0) & (entries["frac_accumulate"][:, 1] < 1.0))
    assert entries["frac_accumulate"][:, 1] + entries["frac_rest"][:, 1] == pytest.approx([1.0, 1.0], abs=0.0)
    assert np.all(entries["dx_d"][:, 1] < entries["dx_d_static_kinetic"])


def test_result_file_is_documented_and_draws(content, tmp_path):
    """Every dataset of stribeck.h5 gets units and a description, and the figure has the vbar,
    accumulation and Delta x_d panels a, b, c with v_s / velocity swing on a log axis, at print size
    (print_check empty)."""
    path = write_h5(tmp_path / "stribeck.h5", *content)
    assert all(meta["units"] and meta["description"] for meta in read_dataset_attrs(path).values())
    fig = draw("stribeck_friction", [read_h5(path)])
    assert print_check(fig) == []
    panels = [ax for ax in fig.axes if ax.axison]
    assert [ax.get_title(loc="left") for ax in panels] == ["a", "b", "c"]
    for ax in panels:
        assert ax.get_xscale() == "log"
        assert ax.lines[0].get_xdata().tolist() == pytest.approx(FRACTIONS)


def test_friction_needs_moreau_steady_state():
    """simulated_steady_state refuses a friction law with the exact method before simulating."""
    with pytest.raises(ValueError, match="method 'moreau' only"):
        simulated_steady_state([ThreePhaseProfile(1.0, 0.084, 2.3, 1.3)], "exact", friction=friction_law(RATIO))


@pytest.mark.parametrize("fractions, ratio, delta, match", [([0.0, 1.0], RATIO, DELTA, "v_s_fractions"),
                                                           ([], RATIO, DELTA, "v_s_fractions"),
                                                           ([0.1], 0.9, DELTA, "mu_s_over_mu_k"),
                                                           ([0.1], RATIO, 0.0, "delta")])
def test_bad_study_input_is_refused_up_front(fractions, ratio, delta, match):
    """A v_s fraction that is not > 0, an empty list, r < 1 or delta <= 0 stops the study with an
    error naming the parameter, before any profile is built (the settings here are invalid too)."""
    with pytest.raises(ValueError, match=match):
        stribeck_content(fractions, ratio=ratio, delta=delta, steps_per_period=STEPS, steady={}, entries={})
