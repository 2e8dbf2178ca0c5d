"""The simulation stage: trajectories to HDF5 and back, rerun recordings, the Fig. 9 scenes.

The stage's library steps (``selfalign.io.simulation_result``) are tested directly;
one test runs the stage's Snakemake rules for one scene in a temporary copy of
the workflow.
"""

import shutil
import subprocess
import sys

import numpy as np
import pytest

from selfalign import EventKind, Status, load_scene, simulate
from selfalign.analysis.classification import classify
from selfalign.io.hdf5 import read_h5, write_h5
from selfalign.io.recording import read_recording, write_recording
from selfalign.io.simulation_result import (
    RERUN_ENTITIES,
    event_datasets,
    scene_from_result,
    simulation_recording,
    trajectory_content,
    trajectory_from_result,
)
from selfalign.solvers.records import EVENT_DTYPE


def round_trip(traj, scene, tmp_path):
    path = tmp_path / f"{scene.name}.h5"
    write_h5(path, *trajectory_content(traj, scene))
    return read_h5(path)


def assert_same_trajectory(back, traj):
    for key in ("x_end", "v_end", "period_end", "tau_end", "status", "message", "method", "options",
                "stats", "info"):
        assert getattr(back, key) == getattr(traj, key), key
    assert set(back.series) == set(traj.series)
    for name, values in traj.series.items():
        np.testing.assert_array_equal(back.series[name], values, err_msg=name)
    if traj.events is None:
        assert back.events is None
    else:
        assert back.events.dtype == EVENT_DTYPE
        np.testing.assert_array_equal(back.events, traj.events)


@pytest.fixture
def fig12(repo):
    scene = load_scene(repo / "workflow/scenes/fig12.yaml")
    return scene, simulate(scene)


def test_round_trip_with_event_log_and_series(fig12, tmp_path):
    """An exact run with every series and the event log comes back from HDF5 unchanged (bit for bit),
    with the scene it was computed from."""
    scene, traj = fig12
    assert traj.events is not None and traj.events.size > 0 and set(traj.series) >= {"t", "x", "friction"}
    result = round_trip(traj, scene, tmp_path)
    assert_same_trajectory(trajectory_from_result(result), traj)
    assert scene_from_result(result).to_dict() == scene.to_dict()
    a = result["attrs"]
    assert a["t_end"] == traj.period_end * scene.profile.dt + traj.tau_end
    ev = result["groups"]["events"]
    np.testing.assert_array_equal(ev["datasets"]["t"], traj.events["period"] * scene.profile.dt + traj.events["tau"])
    assert ev["attrs"]["kinds"]["STICK"] == EventKind.STICK


@pytest.mark.parametrize("scene_name, changes", [
    ("fig03", {}),                                     # Moreau (fixed-point), no event log
    ("stop_zone", {"method": "ivp"}),                  # solve_ivp with events and series
    ("stop_zone", {}),                                 # exact, until rest: accumulation info
])
def test_round_trip_every_method(repo, tmp_path, scene_name, changes):
    """Every method's Trajectory (options, stats, info, outcome) survives the HDF5 round trip."""
    scene = load_scene(repo / f"workflow/scenes/{scene_name}.yaml")
    if changes:
        scene = scene.replace(until="periods", periods=3, **changes)
    traj = simulate(scene)
    assert traj.success, traj.message
    assert_same_trajectory(trajectory_from_result(round_trip(traj, scene, tmp_path)), traj)


def test_accumulation_outcome_is_stored(repo, tmp_path):
    """The stop-zone scene ends in accumulation at x_stick_min = x_mu + w (2.2 - 1)/(2.5 - 1) = 0.54
    (eq. 41, to 1e-12); the stored status and info say so."""
    scene = load_scene(repo / "workflow/scenes/stop_zone.yaml")
    back = trajectory_from_result(round_trip(simulate(scene), scene, tmp_path))
    assert back.status is Status.ACCUMULATION
    assert back.x_end == pytest.approx(0.54, abs=1e-12) and back.info["limit"] == pytest.approx(0.54, abs=1e-12)


def test_event_columns_reject_a_plain_array():
    with pytest.raises(ValueError, match="EVENT_DTYPE"):
        event_datasets(np.zeros(3), dt=1.0)


def test_rerun_recording_holds_every_series(fig12, tmp_path):
    """The rrd of a run holds x, y, x', y', y'', friction and mode under their entity paths, at the
    run's times (rounded to 1 ns), with the run's values."""
    scene, traj = fig12
    path = write_recording(tmp_path / "fig12.rrd", simulation_recording(round_trip(traj, scene, tmp_path)))
    back = read_recording(path)
    assert {RERUN_ENTITIES[n] for n in ("x", "y", "v", "yd", "ydd", "friction", "mode")} <= set(back)
    order = np.argsort(traj.t, kind="stable")
    for name in ("x", "y", "v", "yd", "ydd", "friction", "mode"):
        t, values = back[RERUN_ENTITIES[name]]
        np.testing.assert_allclose(t, traj.t[order], rtol=0, atol=1e-9)
        np.testing.assert_array_equal(values, np.asarray(traj.series[name], dtype=float)[order])


def test_rerun_needs_series(fig12, tmp_path):
    scene, traj = fig12
    traj.series = {}
    with pytest.raises(ValueError, match="record.series"):
        simulation_recording(round_trip(traj, scene, tmp_path))


def test_fig12_stick_time_is_eq_21(fig12):
    """Fig. 12 marks the stick time of the event log: t_{x'=0} = t2 + x'(t2) / (1 + y3''), with
    x'(t2) = (y2'' - 1)(t2 - t1) (eqs. 15-21, Sect. 5.1), to 1e-12."""
    scene, traj = fig12
    p = scene.profile
    stick = traj.events[traj.events["kind"] == EventKind.STICK]
    expected = p.t2 + (p.y2 - 1.0) * (p.t2 - p.t1) / (1.0 + p.y3)
    assert stick.size == 1 and stick["tau"][0] == pytest.approx(expected, abs=1e-12)


@pytest.mark.parametrize("case", [1, 2, 3, 4, 5])
def test_fig09_scene_shows_its_case(repo, case):
    """Each Fig. 9 scene is the case of Table 1 it is named after (a priori, Fig. 8), and its
    simulated steady state (last three of ten periods) has that case's sign pattern of x':
    1: x' >= 0 with stick; 2: x' <= 0 with stick; 3: both signs with stick; 4: both signs,
    never stuck for a sampling interval (slip-slip); 5: x' = 0 throughout."""
    scene = load_scene(repo / f"workflow/scenes/fig09_case{case}.yaml")
    assert classify(scene.profile) == case
    traj = simulate(scene)
    last = traj.t >= traj.t[-1] - 3 * scene.profile.dt * (1 + 1e-12)
    v = traj.v[last]
    stuck_interval = np.any((v[:-1] == 0.0) & (v[1:] == 0.0))
    forward, backward = np.any(v > 0), np.any(v < 0)
    expected = {1: (True, False, True), 2: (False, True, True), 3: (True, True, True),
                4: (True, True, False), 5: (False, False, True)}[case]
    assert (forward, backward, stuck_interval) == expected


def test_stage_rules_write_result_recording_and_figure(repo, tmp_path):
    """The stage's rules (simulate_scene, record_rerun, plot_fig12) run for the Fig. 12 scene in a
    copy of the workflow and write the HDF5 result, the rrd and the PNG."""
    shutil.copy(repo / "Snakefile", tmp_path / "Snakefile")
    shutil.copytree(repo / "workflow", tmp_path / "workflow")
    targets = ["results/simulation/fig12.h5", "results/rerun/fig12.rrd", "figures/fig12.png"]
    proc = subprocess.run([sys.executable, "-m", "snakemake", "-c1", *targets], cwd=tmp_path,
                          capture_output=True, text=True, timeout=300)
    assert proc.returncode == 0, proc.stdout + proc.stderr
    back = trajectory_from_result(read_h5(tmp_path / targets[0]))
    assert back.method == "exact" and back.events is not None
    assert "friction/force" in read_recording(tmp_path / targets[1])
    assert (tmp_path / targets[2]).read_bytes()[:8] == b"\x89PNG\r\n\x1a\n"


def test_result_layout_is_documented(repo, fig12):
    """Every attribute, group and dataset of a simulation result is on the result-file page of the docs."""
    text = (repo / "docs/reference/results.md").read_text()
    scene, traj = fig12
    _, attrs, groups = trajectory_content(traj, scene)
    names = list(attrs) + [f"group `{g}`" for g in groups]
    names += [n for g in ("series", "events") for n in groups[g]["datasets"]]
    for name in names:
        assert (name if name.startswith("group") else f"`{name}`") in text, name
