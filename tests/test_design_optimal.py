"""The design tool's optimal family (docs/tutorials/design-station.md, "Two profile families";
docs/explanation/optimal-motion.md): its designs keep the guarantee, the gain it reports is the
simulated one, the paper's family alone is today's search, and bad family names are refused."""

from __future__ import annotations

import json
import math

import numpy as np
import pytest

import selfalign as sa
from selfalign.analysis.design import design
from selfalign.io.design_spec import DesignSpecError, design_spec_from_dict
from selfalign.model.design_spec import DesignGrid
from selfalign.model.friction import StopZone, stick_limit
from selfalign.model.profiles import PiecewiseConstantProfile
from selfalign.model.units import SIScale

GRID = DesignGrid(periods=2, strokes=1, accelerations=4, c_mu=1, mu_samples=3, max_verified=4)
BASE = dict(mu=0.2, mu_uncertainty=0.05, c_mu=(3.0, 3.0), width=2e-3, max_stroke=1e-3, max_acceleration=8.0,
            period=(0.01, 0.1), distance=4e-3, tolerance=250e-6, grid=GRID)
BOTH = ("three_phase", "optimal")


@pytest.fixture(scope="module")
def both():
    """The small station of the ``design`` docstring, both families searched."""
    return design(sa.DesignSpec(**BASE, families=BOTH), progress="quiet")


@pytest.fixture(scope="module")
def accumulating():
    """The same station asking for accumulation, the optimal family alone."""
    return design(sa.DesignSpec(**BASE, accumulation=True, families=("optimal",)), progress="quiet")


def _profile(result, mu):
    """The chosen motion at ``mu`` in the model's units, rebuilt here from its SI pieces (Sect. 3.2)."""
    s = SIScale(mu=mu, g=result.spec.g, L=result.spec.width)
    breaks, accels = result.motion.breaks / s.T, result.motion.accels / s.unit("acceleration")
    v = np.concatenate([[0.0], np.cumsum(accels * np.diff(breaks))])
    return PiecewiseConstantProfile(breaks, accels, y_start=0.0, yd_start=-float(np.sum(
        (v[:-1] + 0.5 * accels * np.diff(breaks)) * np.diff(breaks))) / breaks[-1])


def _entries(result, mu, n=24):
    """(status, end [m]) of ``n`` runs from rest at phases spread over a few periods before the strip."""
    profile = _profile(result, mu)
    x0 = -np.linspace(0.5, 4.0, n) * result.vbar * result.period / result.spec.width
    res = sa.simulate_batch([profile], x0, 0.0, surface=StopZone(0.0, 1.0, result.c_mu), until="rest",
                            max_periods=3000)
    return res.statuses(), res.x_end * result.spec.width


def test_optimal_family_wins_and_is_named(both):
    """Hypothesis: under |y''| <= a the motion -a, +a, +r beats the paper's family (optimal-motion.md,
    up to 1.5x), so on the docstring's station the optimal design is chosen and named, the paper's kept
    as ``other``."""
    assert both.found and both.family == "optimal" and both.motion is not None
    assert both.other is not None and both.other.family == "three_phase" and both.other.found
    assert both.vbar > both.other.vbar
    assert both.gain["arrive_ratio"] > 1.0 and both.gain["rest_ratio"] > 1.0


@pytest.mark.parametrize("where", [0.0, 0.25, 0.5, 1.0])
def test_optimal_design_rests_within_tolerance(both, where):
    """Hypothesis: the guarantee (package docstring of selfalign.analysis.design) holds for the optimal
    family: at any mu of [mu (1 - delta), mu (1 + delta)], also between the mu samples (where = 0.25),
    every entry comes to rest for good in the strip (|y''| <= mu_bar there, eq. 41) within the tolerance
    of x_d; checked by runs of the exact solver independent of the tool's own."""
    lo, hi = both.spec.mu_range
    statuses, ends = _entries(both, lo + where * (hi - lo))
    assert all(s in (sa.Status.REST, sa.Status.ACCUMULATION) for s in statuses)
    assert np.all(np.abs(ends - both.x_d) <= both.spec.tolerance + 1e-12)
    assert np.all(ends >= both.x_d - both.error - 1e-12)


@pytest.mark.parametrize("where", [0.0, 0.5, 1.0])
def test_optimal_design_accumulates_where_asked(accumulating, where):
    """Hypothesis: with accumulation asked for, the optimal family's design makes every entry accumulate
    (Sect. 7: the forward slip under -a outlasts the backward one under +a, so the steps shrink
    geometrically to x_stick_min, eq. 41), at x_stick_min within the tolerance of x_d at every mu."""
    assert accumulating.found and accumulating.family == "optimal"
    lo, hi = accumulating.spec.mu_range
    mu = lo + where * (hi - lo)
    statuses, ends = _entries(accumulating, mu)
    assert all(s == sa.Status.ACCUMULATION for s in statuses)
    x_stick_min = stick_limit(accumulating.y2 / (mu * accumulating.spec.g), 1.0, accumulating.c_mu) \
        * accumulating.spec.width
    assert np.all(np.abs(ends - x_stick_min) <= 1e-6)
    assert np.all(np.abs(ends - accumulating.x_d) <= accumulating.spec.tolerance)


def test_reported_gain_matches_direct_simulation(both):
    """Hypothesis: the gain is simulated (docs/tutorials/design-station.md): each family's time to first
    arrival within the tolerance of x_d and to rest, from rest at the distance D at t = 0, worst over the mu
    samples, equals a direct run of the exact solver (rtol 1e-6), and the ratios are their quotients."""
    gain = both.gain
    for result in (both, both.other):
        arrive, rest = [], []
        for mu in result.verification.mu:
            s = SIScale(mu=float(mu), g=result.spec.g, L=result.spec.width)
            profile = _profile(result, mu) if result.family == "optimal" else sa.ThreePhaseProfile(
                result.period / s.T, result.stroke / s.L, result.y2 / s.unit("acceleration"),
                result.y3 / s.unit("acceleration"))
            res = sa.simulate_batch([profile], -result.spec.distance / s.L, 0.0,
                                    surface=StopZone(0.0, 1.0, result.c_mu),
                                    levels=[(result.x_d - result.spec.tolerance) / s.L], until="rest",
                                    max_periods=20_000)
            arrive.append(float(res.crossing_time(2)[0]) * result.period)
            rest.append(float(res.t_end_periods[0]) * result.period)
        assert math.isclose(gain[result.family]["t_arrive"], max(arrive), rel_tol=1e-6)
        assert math.isclose(gain[result.family]["t_rest"], max(rest), rel_tol=1e-6)
    assert math.isclose(gain["arrive_ratio"], gain["three_phase"]["t_arrive"] / gain["optimal"]["t_arrive"])
    assert math.isclose(gain["rest_ratio"], gain["three_phase"]["t_rest"] / gain["optimal"]["t_rest"])


def test_paper_family_alone_is_todays_design(both):
    """Hypothesis: a spec restricted to the paper's family (the default) runs today's search unchanged: the
    numbers of the ``design`` docstring (10 Hz, y2'' = y3'' = 4 m/s^2, x_d = 1044 um +- 102 um, arrival
    within 3.18 s) and the same three-phase design as the one kept beside the optimal one."""
    grid = DesignGrid(periods=2, strokes=1, accelerations=2, c_mu=1, mu_samples=3, max_verified=1)
    paper = design(sa.DesignSpec(**{**BASE, "grid": grid}, families=("three_phase",)), progress="quiet")
    assert paper.family == "three_phase" and paper.other is None and paper.gain is None
    assert (paper.found, paper.frequency, paper.case, paper.margin) == (True, 10.0, 3, 0.32)
    assert paper.y2 == paper.y3 == 4.0
    assert f"{1e6 * paper.x_d:.4g} {1e6 * paper.error:.3g} {paper.t_arrive:.3g}" == "1044 102 3.18"
    default = sa.DesignSpec(**BASE)
    assert default.families == ("three_phase",)
    alone = design(sa.DesignSpec(**BASE, families=("three_phase",)), progress="quiet")
    kept = both.other
    assert (alone.period, alone.stroke, alone.y2, alone.y3, alone.c_mu, alone.t_arrive, alone.x_d) == \
        (kept.period, kept.stroke, kept.y2, kept.y3, kept.c_mu, kept.t_arrive, kept.x_d)


@pytest.mark.parametrize("families", [("fastest",), (), "optimal", ("optimal", "optimal"), ("three_phase", 3)])
def test_bad_families_refused(families):
    """Hypothesis: bad input gets a clear error before any work: a family name other than three_phase and
    optimal, none, a bare string or a repeat is refused with a ValueError naming profile.families."""
    with pytest.raises(ValueError, match=r"profile\.families must be a non-empty list of distinct names among "
                                         r"three_phase, optimal"):
        sa.DesignSpec(**BASE, families=families)


def test_bad_family_in_a_spec_file_refused():
    """Hypothesis: the schema lists the families (selfalign/io/schemas/design.schema.yaml), so a spec file
    naming another is refused with a one-line DesignSpecError naming the key."""
    data = {"machine": {"mu": 0.2, "c_mu": 3.0}, "part": {"width": 2e-3},
            "actuator": {"stroke": 1e-3, "acceleration": 8.0, "frequency": {"min": 10.0, "max": 100.0}},
            "task": {"distance": 1e-2, "tolerance": 2.5e-4}, "profile": {"families": ["bang_bang"]}}
    with pytest.raises(DesignSpecError, match=r"profile\.families"):
        design_spec_from_dict(data, source="x.yaml")
    data["profile"]["families"] = ["optimal", "three_phase"]
    assert design_spec_from_dict(data, source="x.yaml").families == ("optimal", "three_phase")


def test_cli_and_result_file_name_the_family_and_the_gain(tmp_path):
    """Hypothesis: the family of the chosen design and the gain reach the user (the tutorial's "Two profile
    families"): `selfalign design --json` gives them, the report ends with the families line and the result
    file has the attribute family and the group gain with the simulated times."""
    from click.testing import CliRunner

    from selfalign.cli.commands import selfalign as cli
    from selfalign.io.hdf5 import read_h5

    spec = tmp_path / "station.yaml"
    spec.write_text("machine: {mu: 0.2, mu_uncertainty: 0.05, c_mu: 3.0}\npart: {width: 2.0e-3}\n"
                    "actuator: {stroke: 1.0e-3, acceleration: 8.0, period: {min: 0.01, max: 0.1}}\n"
                    "task: {distance: 4.0e-3, tolerance: 250.0e-6}\nprofile: {families: [three_phase, optimal]}\n"
                    "search: {periods: 2, strokes: 1, accelerations: 4, c_mu: 1, mu_samples: 3, max_verified: 4}\n")
    out = tmp_path / "design.h5"
    answer = CliRunner().invoke(cli, ["design", str(spec), "--json", "-o", str(out)])
    assert answer.exit_code == 0, answer.output
    summary = json.loads(answer.output[:answer.output.rindex("}") + 1])
    assert summary["family"] == "optimal" and summary["gain"]["three_phase"]["found"]
    assert summary["gain"]["arrive_ratio"] > 1.0
    stored = read_h5(out)
    assert stored["attrs"]["family"] == "optimal"
    gain = stored["groups"]["gain"]["datasets"]
    assert gain["t_arrive"][1] == pytest.approx(summary["t_arrive_s"], rel=1e-12)
    assert "families (simulated" in stored["attrs"]["report"].splitlines()[-1]


def test_design_figure_puts_only_a_paper_family_design_on_the_map(both, tmp_path):
    """Hypothesis: panel c of the design figure is the design map over (y2'', y3'') of the best three-phase
    design (Sect. 7.3); an optimal-family design has no (y2'', y3''), so it is not drawn on the map and the
    legend says the chosen design is of the optimal family, shown in a only; a three-phase design keeps its
    star on the map."""
    from selfalign.analysis.design import design_map
    from selfalign.io.hdf5 import read_h5, write_h5
    from selfalign.plots.design import figure_design
    from selfalign.plots.style import print_check
    from selfalign.stages.design import design_content

    assert both.family == "optimal" and both.other is not None and both.other.family == "three_phase"
    chart = design_map(both.other, refine=1, entries=4, progress="quiet")
    for result in (both, both.other):
        write_h5(tmp_path / f"{result.family}.h5", *design_content(result, chart))
        fig = figure_design(read_h5(tmp_path / f"{result.family}.h5"))
        assert print_check(fig) == []
        panel = fig.axes[2]
        assert panel.get_title(loc="left") == "c"
        stars = [line for line in panel.lines if line.get_marker() == "*"]
        legend = "\n".join(t.get_text() for ax in fig.axes if ax.get_legend() for t in ax.get_legend().texts)
        if result.family == "optimal":
            assert not stars and "optimal family" in legend
        else:
            assert len(stars) == 1 and "optimal family" not in legend
