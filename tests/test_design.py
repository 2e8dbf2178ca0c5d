"""The design tool (selfalign.analysis.design, docs/tutorials/design-station.md).

The tool is checked against brute force and independent simulation: the brute force below
simulates every design of a coarse grid with its own entry sampling (zone placed one maximal
period advance ahead, not positioning's Delta_x; other offsets), so it shares only the
compiled solver with the tool.
"""

from __future__ import annotations

import json
from pathlib import Path

import numpy as np
import pytest
import yaml

import selfalign as sa
from selfalign.analysis.design import Candidates, design, dimensionless, mu_values, search_grid, verify
from selfalign.analysis.steady_state import steady_state_grid
from selfalign.io.design_spec import design_spec_from_dict, load_design_spec
from selfalign.model.design_spec import DesignGrid, DesignSpec
from selfalign.model.friction import FrictionLaw, StopZone
from selfalign.model.scene import Scene
from selfalign.solvers.driver import simulate_batch
from selfalign.solvers.outcomes import STATUS_CODES, Status
from selfalign.solvers.tables import three_phase_table

ROOT = Path(__file__).resolve().parents[1]
REST, ACCUMULATION = STATUS_CODES[Status.REST], STATUS_CODES[Status.ACCUMULATION]

#: A coarse problem: 3 periods x 3 strokes x 6 x 6 accelerations = 324 designs.
COARSE = dict(mu=0.2, mu_uncertainty=0.05, c_mu=(2.5, 2.5), width=2e-3, max_stroke=1e-3, max_acceleration=6.0,
              period=(0.02, 0.08), distance=5e-3, tolerance=150e-6, name="coarse",
              grid=DesignGrid(periods=3, strokes=3, accelerations=6, entries=256, mu_samples=3))


def entry_outcomes(spec: DesignSpec, cand: Candidates, mu: float, n_entries: int, offset: float):
    """Independent entries at ``mu`` for every candidate (rows): status and end position past the
    strip's edge [m].  The zone starts v_max dt after the start, beyond any advance within the
    first period; offsets s over one steady period, x' = v0 at t = 0."""
    dt, dy, y2, y3 = dimensionless(spec, cand, mu)
    ss = steady_state_grid(dt, dy, y2, y3)
    x_mu = ss.v_max * dt + 1e-9
    s = (ss.vbar * dt)[:, None] * ((np.arange(n_entries) + offset) / n_entries)[None, :]
    member = np.repeat(np.arange(len(cand)), n_entries)
    res = simulate_batch(three_phase_table(dt, dy, y2, y3), -s.ravel(), ss.v0[member], profile_index=member,
                         x_mu=x_mu[member], w=np.ones(member.size), c_mu=cand.c_mu[member], until="rest",
                         max_periods=1000)
    shape = (len(cand), n_entries)
    return res.status.reshape(shape), (res.x_end - x_mu[member]).reshape(shape) * spec.width


def process_time(spec: DesignSpec, cand: Candidates, mu: float, level: np.ndarray) -> np.ndarray:
    """Time [s] from rest at distance D before the strip (t = 0) to the first x >= ``level`` [m]."""
    dt, dy, y2, y3 = dimensionless(spec, cand, mu)
    n = len(cand)
    res = simulate_batch(three_phase_table(dt, dy, y2, y3), -spec.distance / spec.width, 0.0, 0.0,
                         profile_index=np.arange(n), x_mu=np.zeros(n), w=np.ones(n), c_mu=cand.c_mu,
                         levels=(level / spec.width)[:, None], until="rest", max_periods=5000)
    return res.crossing_time(2) * cand.period


def brute_force(spec: DesignSpec, n_entries: int = 128):
    """Simulate every design of the grid that gives a physical profile moving forward at every mu
    sample; return (candidates, worst arrival time [s], guaranteed)."""
    cand = search_grid(spec)
    mus = mu_values(spec, spec.grid.mu_samples)
    moving = np.ones(len(cand), bool)
    for mu in mus:
        physical = sa.model.profiles.three_phase_feasibility(*dimensionless(spec, cand, mu)) <= 1.0
        ss = steady_state_grid(*(np.where(physical, a, 1.0) for a in dimensionless(spec, cand, mu)))
        moving &= physical & (ss.case > 0) & (ss.vbar > 0)
    cand = cand.take(np.flatnonzero(moving))
    ends, good = [], np.ones(len(cand), bool)
    for mu in mus:
        status, end = entry_outcomes(spec, cand, mu, n_entries, offset=0.37)
        wanted = (status == ACCUMULATION) if spec.accumulation else np.isin(status, (REST, ACCUMULATION))
        good &= wanted.all(axis=1)
        ends.append(end)
    ends = np.concatenate(ends, axis=1)
    lo, hi = ends.min(axis=1), ends.max(axis=1)
    good &= 0.5 * (hi - lo) <= spec.tolerance
    level = 0.5 * (lo + hi) - spec.tolerance
    times = np.max([process_time(spec, cand, mu, level) for mu in mus], axis=0)
    return cand, np.where(good, times, np.inf), good


@pytest.mark.parametrize("accumulation", [False, True])
def test_optimum_matches_brute_force(accumulation):
    """Hypothesis: on a coarse grid the tool's design is within 1 % of the fastest design that
    exhaustive simulation of every grid design (independent entries) finds guaranteed."""
    spec = DesignSpec(**COARSE, accumulation=accumulation)
    result = design(spec, progress="quiet")
    cand, times, good = brute_force(spec)
    assert good.any() and result.found
    best = float(times[good].min())
    assert abs(result.t_arrive - best) <= 0.01 * best, (result.t_arrive, best)


def test_guarantee_holds_under_independent_simulation():
    """Hypothesis: every design the tool calls guaranteed (the chosen one and the guaranteed members
    of the time-error front; accumulation asked for) accumulates from 1024 independent steady-state
    entries at mu_min, the middle and mu_max, within the tolerance of its x_d; the chosen one also
    from entries run by the scalar exact solver."""
    spec = DesignSpec(**COARSE, accumulation=True)
    result = design(spec, progress="quiet")
    assert result.found and result.verification.guaranteed[0]
    front = result.front_time_error
    good = np.flatnonzero(front["guaranteed"])
    assert good.size >= 2
    cand = Candidates(*(np.concatenate([[getattr(result, k)], front[k][good]])
                        for k in ("period", "stroke", "y2", "y3", "c_mu")))
    lo, hi = spec.mu_range
    ends = []
    for mu in (lo, 0.5 * (lo + hi), hi):
        status, end = entry_outcomes(spec, cand, mu, 1024, offset=0.61)
        assert np.all(status == ACCUMULATION)
        ends.append(end)
    ends = np.concatenate(ends, axis=1)
    assert np.all(0.5 * (ends.max(axis=1) - ends.min(axis=1)) <= spec.tolerance)
    assert np.all(np.abs(ends[0] - result.x_d) <= spec.tolerance)
    for mu in (lo, 0.5 * (lo + hi), hi):
        profile = result.profile_at(mu)
        ss = sa.steady_state(profile)
        for s in np.linspace(0.05, 0.95, 3) * ss.vbar * profile.dt:
            traj = sa.simulate(Scene(profile, StopZone(x_mu=ss.v_max * profile.dt, w=1.0, c_mu=result.c_mu),
                                     x0=-s, v0=ss.v0, phase=0.0, until="rest", max_periods=1000))
            assert traj.status is Status.ACCUMULATION
            assert abs((traj.x_end - ss.v_max * profile.dt) * spec.width - result.x_d) <= spec.tolerance


def test_mu_changes_the_dimensionless_profile():
    """Hypothesis: the fixed SI profile seen at mu has accelerations y/(mu g) and period P sqrt(mu g / w)
    (Sect. 3.2 with L = w), so doubling mu halves y2 and y3 and stretches dt by sqrt(2)."""
    result = design(DesignSpec(**COARSE), progress="quiet")
    a, b = result.profile_at(0.2), result.profile_at(0.4)
    assert b.y2 == pytest.approx(a.y2 / 2) and b.y3 == pytest.approx(a.y3 / 2)
    assert b.dt == pytest.approx(a.dt * np.sqrt(2)) and b.dy == a.dy
    assert a.y2 == pytest.approx(result.y2 / (0.2 * 9.81))


def test_accumulation_impossible_on_the_cam_drive_says_why():
    """Hypothesis: with a fixed 10 mm stroke at 3.3-10 Hz no design accumulates; the tool returns
    none and explains it with the slip window of Sect. 7.3."""
    spec = load_design_spec(ROOT / "workflow/designs/cam_drive.yaml")
    result = design(spec, progress="quiet")
    assert not result.found
    assert "omega (t2 - t1) < pi/2" in result.explanation and "0 of the" in result.explanation
    assert not result.verification.guaranteed[0]


@pytest.mark.parametrize("change, words", [
    ({"max_acceleration": 1.5}, "y2'' > mu (1 + delta) g = 2.06"),
    ({"c_mu": (1.05, 1.05)}, "c_mu must exceed (1 + delta)/(1 - delta) = 1.105"),
    ({"accumulation": True, "tolerance": 1e-6}, "widen the tolerance"),
])
def test_binding_constraint_is_named(change, words):
    """Hypothesis: when a closed-form constraint leaves no design, the explanation names it with
    the numbers of the spec (mu_max g = 0.21 * 9.81 = 2.06 m/s^2; 1.05 / 0.95 = 1.105)."""
    result = design(DesignSpec(**{**COARSE, **change}), progress="quiet")
    assert not result.found and words in result.explanation


SPEC = {"machine": {"mu": 0.2, "mu_uncertainty": 0.05, "c_mu": 2.5}, "part": {"width": 2e-3},
        "actuator": {"stroke": 1e-3, "acceleration": 6.0, "frequency": {"min": 12.5, "max": 50}},
        "task": {"distance": 5e-3, "tolerance": 150e-6},
        "search": {"periods": 3, "strokes": 3, "accelerations": 6, "mu_samples": 3}}


@pytest.mark.parametrize("path, value, message", [
    (("actuator", "acceleration"), -3, "actuator.acceleration: must be > 0, got -3"),
    (("machine", "frction"), 1, "machine: unknown key 'frction'"),
    (("actuator", "period"), {"min": 0.02, "max": 0.08}, "actuator: give exactly one of frequency and period"),
    (("task", "objective"), "robustness", "objective 'robustness' needs task.max_process_time"),
    (("search", "entries"), 64, "search.entries: must be >= 256, got 64"),
    (("machine", "c_mu"), {"min": 3, "max": 2}, "c_mu must satisfy 1 < low <= high"),
])
def test_bad_spec_is_one_line_naming_the_key(path, value, message):
    """Hypothesis: a bad spec stops before any work with one line naming the file and the key."""
    data = json.loads(json.dumps(SPEC))
    data[path[0]][path[1]] = value
    with pytest.raises(ValueError) as info:
        design_spec_from_dict(data, source="x.yaml")
    text = str(info.value)
    assert "\n" not in text and text.startswith("x.yaml: ") and message in text, text


@pytest.mark.parametrize("block, value, message", [
    ("search", {"accelerations": 10_000}, "search grid of 14,400,000,000 designs (search.periods x strokes x "
     "accelerations^2 x c_mu) needs about 3.6e+03 GB, more than the 4,000,000 designs allowed"),
    ("search", {"periods": 10_000}, "search grid of 192,000,000 designs"),
    ("search", {"entries": 10_000, "mu_samples": 9_999}, "search.entries x search.mu_samples x (search.max_verified "
     "+ 12 designs of the front) = 10,000 x 9,999 x 60 = 5,999,400,000 entry runs to simulate, more than the 500,000 "
     "allowed"),
    ("task", {"distance": 1e300, "tolerance": 150e-6}, "task.distance must be <= 10 m"),
    ("task", {"distance": 5e-3, "tolerance": 6e-3}, "task.tolerance must be smaller than task.distance"),
    ("friction", {"kind": "static_kinetic"}, "friction.mu_s_over_mu_k: required with kind static_kinetic"),
    ("friction", {"kind": "stribeck", "v_s": 1e-3}, "friction.mu_s_over_mu_k: required with kind stribeck"),
])
def test_spec_beyond_the_limits_is_one_line_before_any_work(block, value, message):
    """Hypothesis: a search whose work (designs x their screening memory, entry runs) or a task
    (distance, tolerance) beyond the documented limits (selfalign.model.design_spec), or a
    friction law without its ratio mu_s/mu_k, is refused while the spec is read, with one line
    naming the spec key, the value and what is allowed."""
    data = json.loads(json.dumps(SPEC))
    data[block] = value
    with pytest.raises(ValueError) as info:
        design_spec_from_dict(data, source="x.yaml")
    text = str(info.value)
    assert "\n" not in text and text.startswith("x.yaml: ") and message in text, text


def test_spec_file_reads_frequency_as_period(tmp_path):
    """Hypothesis: a frequency range [f1, f2] Hz becomes the period range [1/f2, 1/f1] s, a fixed c_mu
    a range of one value, and the name defaults to the file stem."""
    path = tmp_path / "station.yaml"
    path.write_text(yaml.safe_dump(SPEC))
    spec = load_design_spec(path)
    assert spec.period == (0.02, 0.08) and spec.c_mu == (2.5, 2.5) and spec.name == "station"


def test_command_line_design(tmp_path):
    """Hypothesis: `selfalign design` prints the guarantee, states in --json the effects and the
    method that checked it, writes an HDF5 file whose datasets carry SI units, and exits 1 (with
    the reason) when no design meets the spec."""
    click_testing = pytest.importorskip("click.testing")
    from selfalign.cli.commands import selfalign as command
    from selfalign.io.hdf5 import read_dataset_attrs

    path, out = tmp_path / "station.yaml", tmp_path / "station.h5"
    path.write_text(yaml.safe_dump(SPEC))
    run = click_testing.CliRunner().invoke(command, ["design", str(path), "-o", str(out)], standalone_mode=False)
    assert run.exception is None and run.return_value == 0, run.output
    assert "guarantee: yes" in run.output
    run = click_testing.CliRunner().invoke(command, ["design", str(path), "--json"], standalone_mode=False)
    summary = json.loads(run.output)
    assert summary["guaranteed"] is True and summary["method"].startswith("exact"), summary
    assert summary["effects"] == "none"  # the paper's model: Coulomb friction, no ramps
    attrs = read_dataset_attrs(out)
    assert attrs["profile/period"]["units"] == "s (SI)" and attrs["verification/dx_d"]["units"] == "m (SI)"
    bad = json.loads(json.dumps(SPEC))
    bad["actuator"]["acceleration"] = 1.5
    path.write_text(yaml.safe_dump(bad))
    run = click_testing.CliRunner().invoke(command, ["design", str(path), "--json"], standalone_mode=False)
    assert run.return_value == 1 and json.loads(run.output)["found"] is False


def test_stage_writes_result_figure_and_recording(tmp_path):
    """Hypothesis: the stage's steps run without Snakemake on a small spec: the result file holds the
    chosen profile in SI with the design map, the figure draws from it, and the recorded stop of the
    chosen design ends in accumulation at the x_d the design reported."""
    pytest.importorskip("matplotlib")
    from selfalign.io.hdf5 import read_h5, write_h5
    from selfalign.stages.design import design_results, stop_recording, stop_scene
    from selfalign.stages.figures import draw

    path = tmp_path / "station.yaml"
    path.write_text(yaml.safe_dump({**SPEC, "task": {**SPEC["task"], "accumulation": True}}))
    content, result = design_results(path, map_refine=1, map_entries=8, progress="quiet")
    write_h5(tmp_path / "station.h5", *content)
    stored = read_h5(tmp_path / "station.h5")
    assert stored["groups"]["profile"]["datasets"]["period"] == result.period
    assert stored["groups"]["map"]["datasets"]["case"].shape == (6, 6)
    fig = draw("design_station", [stored])
    assert len(fig.axes) == 5  # three panels, the case colour bar and the legend
    recording = stop_recording(stored)
    assert recording.times.size > 100 and "position/events/accumulation_limit" in recording.markers
    scene = stop_scene(stored)
    end = sa.simulate(scene)
    assert end.status is Status.ACCUMULATION
    assert abs(end.x_end * result.spec.width - result.x_d) <= result.spec.tolerance


def test_robustness_objective_trades_time_for_margin():
    """Hypothesis: asked for the largest mu margin within a process time, the tool returns a design
    with a margin at least that of the fastest design and a simulated process time within the limit."""
    fastest = design(DesignSpec(**COARSE, accumulation=True), progress="quiet")
    limit = 3.0 * fastest.t_arrive
    robust = design(DesignSpec(**COARSE, accumulation=True, objective="robustness", max_process_time=limit),
                    progress="quiet")
    assert robust.found and robust.margin >= fastest.margin and robust.t_arrive <= limit
    assert robust.margin > fastest.margin or robust.t_arrive == fastest.t_arrive


def test_static_friction_takes_the_accumulation_guarantee_away():
    """Hypothesis (docs/explanation/stopping.md: no accumulation for any mu_s/mu_k > 1): the
    design guaranteed to accumulate under Coulomb friction, verified again with the spec's friction
    block set to static/kinetic r = 1.3, has no entry that accumulates at any mu sample, so it is
    not guaranteed, and the reason says that accumulation fails; a design search under r = 1.3 with
    accumulation asked for finds nothing."""
    coulomb = design(DesignSpec(**COARSE, accumulation=True), progress="quiet")
    assert coulomb.found and coulomb.verification.accumulates[0]
    static = DesignSpec(**COARSE, accumulation=True, friction=FrictionLaw("static_kinetic", 1.3))
    cand = Candidates(*(np.array([getattr(coulomb, k)]) for k in ("period", "stroke", "y2", "y3", "c_mu")))
    checked = verify(static, cand)
    assert np.all(checked.frac_accumulate == 0.0) and checked.stops[0]
    assert not checked.accumulates[0] and not checked.guaranteed[0]
    assert "static friction mu_s/mu_k = 1.3 > 1 leaves no accumulation" in checked.failure[0]
    assert not design(static, progress="quiet").found


def test_spec_friction_block_is_read():
    """Hypothesis: a spec file's friction block reaches the spec (static/kinetic r = 1.3; Stribeck in
    tests/test_design_effects.py)."""
    data = yaml.safe_load((ROOT / "workflow/designs/smd_steel_table.yaml").read_text())
    data["friction"] = {"kind": "static_kinetic", "mu_s_over_mu_k": 1.3}
    assert design_spec_from_dict(data, "spec.yaml").friction == FrictionLaw("static_kinetic", 1.3)
