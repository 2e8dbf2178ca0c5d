"""Several parts through the public API (docs/explanation/several-parts.md): ``Scene(parts=..., restitution=...)``,
scene files with ``parts:`` and ``restitution:``, and ``simulate`` returning arrays of shape (N,) from the
solver of several parts that the method names; a scene that a method cannot simulate is refused when it is
built or loaded, naming what is wrong."""

import numpy as np
import pytest

import selfalign as sa
from selfalign.solvers.parts_exact import simulate_parts
from selfalign.solvers.parts_moreau import moreau_parts

#: The Fig. 18 profile (Sect. 7.3).
PROFILE = sa.ThreePhaseProfile(dt=1.05, dy=0.084, y2=2.2, y3=0.9)
W = 0.05
PARTS = (sa.Part(0.0, width=W, friction_factor=0.7), sa.Part(0.06, width=W))


def test_simulate_runs_the_solver_of_several_parts_the_method_names():
    """Hypothesis: simulate is a thin door to the solvers of several parts: its x_end, v_end (shape (N,))
    are bit for bit those of simulate_parts (exact) and moreau_parts (moreau) on the same scene, with the
    status, the periods and the event counts carried over."""
    scene = sa.Scene(PROFILE, parts=PARTS, restitution=0.5, periods=6)
    traj = sa.simulate(scene)
    direct = simulate_parts(PROFILE, PARTS, restitution=0.5, periods=6)
    assert traj.x_end.shape == traj.v_end.shape == (2,)
    assert traj.x_end.tolist() == direct.x_end.tolist() and traj.v_end.tolist() == direct.v_end.tolist()
    assert (traj.status, traj.reason, traj.period_end, traj.tau_end) == (sa.Status.HORIZON, sa.Reason.PERIODS, 6, 0.0)
    assert traj.stats["events"] == direct.events and traj.info["impacts"] == direct.impacts >= 5
    assert "2 parts" in traj.message
    moreau = sa.simulate(scene, "moreau", steps_per_period=400)
    direct = moreau_parts(PROFILE, PARTS, restitution=0.5, periods=6, steps_per_period=400)
    assert moreau.x_end.tolist() == direct.x_end.tolist() and moreau.stats["steps"] == 2400
    assert moreau.options["h"] == pytest.approx(PROFILE.dt / 400, rel=1e-15)
    assert moreau.info["max_overlap"] == direct.max_overlap


def test_one_part_through_parts_is_the_papers_single_part():
    """Hypothesis (the invariant of the model: with one part it is eq. 6): a scene with one Part gives the
    single-part scene's end state to 1e-12 (exact solver, 20 periods)."""
    traj = sa.simulate(sa.Scene(PROFILE, parts=[sa.Part(0.1, 0.2, width=W)], periods=20))
    single = sa.simulate(sa.Scene(PROFILE, x0=0.1, v0=0.2, periods=20))
    assert abs(traj.x_end[0] - single.x_end) <= 1e-12 and abs(traj.v_end[0] - single.v_end) <= 1e-12


def test_scene_files_take_parts_and_round_trip():
    """A scene file's ``parts`` and ``restitution`` build the same scene as the Python API; on a stop zone a
    part's width defaults to body.width; ``to_dict`` writes a layout that loads back to the same scene (the
    same layout)."""
    layout = {"profile": {"kind": "three_phase", "dt": 1.05, "dy": 0.084, "y2": 2.2, "y3": 0.9},
              "horizon": {"periods": 4}, "restitution": 0.5,
              "parts": [{"x0": 0.0, "width": W, "friction_factor": 0.7}, {"x0": 0.06, "width": W}]}
    scene = sa.scene_from_dict(layout)
    assert scene.to_dict() == sa.Scene(PROFILE, parts=PARTS, restitution=0.5, periods=4).to_dict()
    assert scene.parts == PARTS
    assert sa.scene_from_dict(scene.to_dict()).to_dict() == scene.to_dict()
    zone = sa.scene_from_dict({**layout, "surface": {"kind": "stop_zone", "x_mu": 0.5, "c_mu": 2.5},
                               "body": {"width": W}, "solver": {"method": "moreau"},
                               "parts": [{"x0": 0.0}, {"x0": 0.06, "mass": 2.0}]})
    assert [p.width for p in zone.parts] == [W, W] and zone.parts[1].mass == 2.0
    assert sa.scene_from_dict(zone.to_dict()).to_dict() == zone.to_dict()


@pytest.mark.parametrize("change, words", [
    ({"x0": 0.1}, "each Part carries its own start"),
    ({"parts": []}, "at least one Part"),
    ({"parts": [sa.Part(0.0, width=W), sa.Part(0.02, width=W)]}, r"parts\[1\] overlaps parts\[0\]"),
    ({"restitution": 1.5}, r"restitution must be a number in \[0, 1\]"),
    ({"parts": None, "restitution": 0.5}, "acts between parts"),
    ({"friction": sa.FrictionLaw("static_kinetic", 1.3)}, "Coulomb friction only"),
    ({"record": sa.Record(events=True)}, "keeps the end state only"),
    ({"surface": sa.StopZone(0.5, 0.1, 2.5)}, r"parts\[0\].width = 0.05: on a stop zone"),
])
def test_a_scene_with_parts_refuses_what_it_cannot_have(change, words):
    """Bad input is refused when the scene is built, naming the parameter (and the part) and what is
    allowed."""
    with pytest.raises(sa.SceneError, match=words):
        sa.Scene(**{"profile": PROFILE, "parts": PARTS, "periods": 3, **change})


@pytest.mark.parametrize("method, options, surface, words", [
    ("ivp", {}, sa.Uniform(), "method 'ivp' cannot simulate several parts"),
    ("exact", {"accumulation_tol": 1e-12}, sa.Uniform(), r"option\(s\) \['accumulation_tol'\] do nothing"),
    ("moreau", {"iteration": "exact"}, sa.Uniform(), r"option\(s\) \['iteration'\] do nothing"),
])
def test_a_method_that_cannot_take_the_parts_refuses_them_before_any_work(method, options, surface, words):
    """A solver that cannot simulate a scene of several parts refuses it before any work starts, at simulate
    and when a scene file is loaded."""
    scene = sa.Scene(PROFILE, surface, parts=PARTS, periods=3)
    with pytest.raises(ValueError, match=words):
        sa.simulate(scene, method, **options)
    layout = {**scene.to_dict(), "solver": {"method": method, "options": options}}
    with pytest.raises(sa.SceneError, match=words):
        sa.scene_from_dict(layout)


def test_scene_files_refuse_keys_that_do_nothing():
    """A scene file with ``restitution`` but no parts, or a start x0 beside parts, is refused (it would be
    ignored); a part without width on a uniform surface is refused naming it."""
    base = {"profile": {"kind": "three_phase", "dt": 1.05, "dy": 0.084, "y2": 2.2, "y3": 0.9},
            "horizon": {"periods": 4}}
    with pytest.raises(sa.SceneError, match="restitution: does nothing without parts"):
        sa.scene_from_dict({**base, "restitution": 0.5})
    with pytest.raises(sa.SceneError, match="start.x0, start.v0: do nothing with parts"):
        sa.scene_from_dict({**base, "start": {"x0": 0.1}, "parts": [{"x0": 0.0, "width": W}]})
    with pytest.raises(sa.SceneError, match=r"parts\[1\].width is required on a uniform surface"):
        sa.scene_from_dict({**base, "parts": [{"x0": 0.0, "width": W}, {"x0": 0.1}]})
    with pytest.raises(sa.SceneError, match="restitution"):
        sa.scene_from_dict({**base, "parts": [{"x0": 0.0, "width": W}], "restitution": 2})
    with pytest.raises(sa.SceneError, match=r"parts\.1\.x0: must be a finite number"):
        sa.scene_from_dict({**base, "parts": [{"x0": 0.0, "width": W}, {"x0": float("nan"), "width": W}]})


def test_parts_at_rest_end_the_run():
    """Hypothesis (the rest decision of the exact solver of several parts): parts whose friction factors
    exceed max|y''| = 2.2 stick for good; with until='rest' the run ends at once with status REST, the parts
    where they started."""
    parts = [sa.Part(0.0, width=W, friction_factor=3.0), sa.Part(0.05, width=W, friction_factor=2.5)]
    traj = sa.simulate(sa.Scene(PROFILE, parts=parts, until="rest", max_periods=10))
    assert (traj.status, traj.reason, traj.period_end) == (sa.Status.REST, sa.Reason.REST, 0)
    assert traj.x_end.tolist() == [0.0, 0.05] and np.all(traj.v_end == 0.0)
    # A fixed horizon is simulated whole: at rest for good, nothing moves after the rest decision.
    traj = sa.simulate(sa.Scene(PROFILE, parts=parts, periods=10))
    assert (traj.status, traj.reason, traj.period_end) == (sa.Status.HORIZON, sa.Reason.PERIODS, 10)
    assert traj.x_end.tolist() == [0.0, 0.05]


def test_a_pushed_pair_comes_to_rest_in_the_stop_zone_through_simulate():
    """Hypothesis (docs, "Accuracy and speed": the two-part analogue of eq. 41): two equal parts pushed into
    a stop zone (c_mu = 2.5) by the Fig. 18 profile end at rest where the mean of their coefficients reaches
    y2'' = 2.2, the rear part 0.6 w into its transition, the exact solver deciding rest for good there (the
    pooled stick bound); Moreau's scheme ends there to its first-order error at dt/2000."""
    zone = sa.StopZone(0.5, W, 2.5)
    pair = [sa.Part(0.35, width=W), sa.Part(0.40, width=W)]
    exact = sa.simulate(sa.Scene(PROFILE, zone, parts=pair, until="rest", max_periods=400))
    assert exact.status is sa.Status.REST
    assert exact.x_end[0] == pytest.approx(0.5 + 0.6 * W, abs=1e-12)
    moreau = sa.simulate(sa.Scene(PROFILE, zone, parts=pair, periods=exact.period_end + 1, method="moreau",
                                  solver_options={"steps_per_period": 2000}))
    assert np.max(np.abs(moreau.x_end - exact.x_end)) < 1e-3


def test_the_cli_simulates_a_scene_file_of_several_parts(tmp_path):
    """``selfalign simulate`` takes a scene file with parts: its summary lists the end state of every part,
    and the HDF5 result stores them (rear-most first) and reads back as the Trajectory simulate returns."""
    from click.testing import CliRunner

    from selfalign.cli.commands import selfalign as cli
    from selfalign.io.hdf5 import read_h5
    from selfalign.io.simulation_result import trajectory_from_result

    scene = sa.Scene(PROFILE, sa.StopZone(0.5, W, 2.5), parts=[sa.Part(0.35, width=W), sa.Part(0.40, width=W)],
                     until="rest", max_periods=400, name="pair")
    path, out = tmp_path / "pair.yaml", tmp_path / "pair.h5"
    path.write_text(__import__("yaml").safe_dump(scene.to_dict(), sort_keys=False))
    result = CliRunner().invoke(cli, ["simulate", str(path), "-o", str(out)])
    assert result.exit_code == 0, result.output
    assert "status rest" in result.output and "x_end = [0.53, 0.58]" in result.output
    stored = trajectory_from_result(read_h5(out))
    expected = sa.simulate(scene)
    assert stored.x_end.tolist() == expected.x_end.tolist() and stored.status is sa.Status.REST
    assert stored.info["part_sticks"].tolist() == expected.info["part_sticks"].tolist()
    assert stored.info["sticks"] == expected.info["sticks"] > 0


def test_a_start_phase_shifts_both_solvers_of_several_parts():
    """Hypothesis (Scene.phase: the parts' x0, v0 hold at t = phase dt, period boundaries there): parts far
    apart started at phase 0.3 end as the single part started at phase 0.3 does, each, to 1e-12 (exact)
    and to Moreau's first-order error (dt/2000); the end time is the single part's too.  Started at another
    phase the end state differs, so the phase reaches the solvers."""
    parts = [sa.Part(0.0, width=W), sa.Part(5.0, 0.1, width=W)]
    for method, options, tol in (("exact", {}, 1e-12), ("moreau", {"steps_per_period": 2000}, 2e-3)):
        traj = sa.simulate(sa.Scene(PROFILE, parts=parts, periods=7, phase=0.3, method=method,
                                    solver_options=options))
        for part, x, v in zip(parts, traj.x_end, traj.v_end):
            alone = sa.simulate(sa.Scene(PROFILE, x0=part.x0, v0=part.v0, periods=7, phase=0.3))
            assert abs(x - alone.x_end) <= tol and abs(v - alone.v_end) <= tol, (method, x, alone.x_end)
        assert (traj.period_end, traj.tau_end) == (7, pytest.approx(0.3 * PROFILE.dt, rel=1e-15))
        other = sa.simulate(sa.Scene(PROFILE, parts=parts, periods=7, phase=0.6, method=method,
                                     solver_options=options))
        assert np.max(np.abs(other.x_end - traj.x_end)) > 10 * tol


def test_events_per_part_reach_the_trajectory():
    """The exact solver's events per part (docs/explanation/several-parts.md, "Outcomes") are in the
    Trajectory's info as arrays of shape (N,): a pushed pair on a uniform surface sticks together, so both
    parts count every stick of the run, and every contact event counts for both of its parts."""
    traj = sa.simulate(sa.Scene(PROFILE, parts=[sa.Part(0.0, width=W), sa.Part(0.05, width=W)], periods=5))
    assert traj.info["part_sticks"].tolist() == [traj.info["sticks"]] * 2 and traj.info["sticks"] >= 5
    assert traj.info["part_impacts"].shape == traj.info["part_crossings"].shape == (2,)
    apart = sa.simulate(sa.Scene(PROFILE, parts=PARTS, restitution=0.5, periods=6))
    assert apart.info["part_impacts"].tolist() == [apart.info["impacts"]] * 2 and apart.info["impacts"] >= 5


def test_the_parts_held_for_good_are_flagged_part_by_part():
    """Hypothesis (docs/explanation/several-parts.md, "Outcomes": the rest decision cluster by cluster): a part
    whose factor k = 3 exceeds max|y''| = 2.2 is held for good where it starts; a part of factor 1 far
    behind it walks on (not held); parts held for good when the whole run ends with REST are all flagged, and
    a pushed pair resting in the stop zone (the pooled bound) is flagged as a whole."""
    parts = [sa.Part(0.0, width=W), sa.Part(5.0, width=W, friction_factor=3.0)]
    traj = sa.simulate(sa.Scene(PROFILE, parts=parts, periods=4))
    assert traj.info["part_held"].tolist() == [False, True] and traj.x_end[1] == 5.0
    pair = sa.simulate(sa.Scene(PROFILE, sa.StopZone(0.5, W, 2.5), parts=[sa.Part(0.35, width=W),
                                                                          sa.Part(0.40, width=W)],
                                until="rest", max_periods=400))
    assert pair.status is sa.Status.REST and pair.info["part_held"].tolist() == [True, True]
