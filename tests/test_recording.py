"""Rerun recordings: what :class:`Recording` holds comes back from the rrd file, with its blueprint,
its id following its content; a simulation result's recording carries its events and scene."""

import subprocess
import sys
from pathlib import Path

import numpy as np
import pytest
import rerun as rr
import yaml
from rerun.chunk import RrdReader

from selfalign import EventKind, Status, load_scene, simulate
from selfalign.io.hdf5 import read_h5, write_h5
from selfalign.io.recording import (
    PERIOD_TIMELINE,
    LogEntries,
    Recording,
    content_id,
    default_groups,
    read_documents,
    read_logs,
    read_recording,
    write_recording,
)
from selfalign.io.simulation_result import simulation_recording, trajectory_content


@pytest.fixture
def no_viewer(monkeypatch):
    """Fail loudly if anything tries to start a rerun viewer."""
    def refuse(*args, **kwargs):
        raise AssertionError("a viewer was spawned")
    monkeypatch.setattr(rr, "spawn", refuse)
    monkeypatch.setattr(rr.RecordingStream, "spawn", refuse)


def _series(n=2001):
    t = np.arange(n) * 1e-3 + 0.25
    return t, {
        "position/table": np.sin(2 * np.pi * t),
        "position/part": np.cos(t),
        "force": np.where(t > 1.0, np.nan, -0.3 * np.sign(t - 0.5)),
        "mode": (t > 0.5).astype(float),
    }


def _layout(path) -> list[list[tuple[str, str, str]]]:
    """The blueprint's containers that hold views, in layout order (depth first from the root
    container): each a list of (view class, name, origin) in order."""
    reader = RrdReader(path)
    (blueprint,) = reader.blueprints()
    views, containers = {}, {}
    for chunk in reader.stream(store=blueprint).to_chunks():
        batch = chunk.to_record_batch()
        columns = {n: batch.column(n).flatten().to_pylist() for n in batch.schema.names if ":" in n}
        entity = chunk.entity_path.lstrip("/")
        if "ViewBlueprint:class_identifier" in columns:
            views[entity] = tuple(columns[f"ViewBlueprint:{key}"][0] for key in
                                  ("class_identifier", "display_name", "space_origin"))
        if "ContainerBlueprint:contents" in columns:
            containers[entity] = columns["ContainerBlueprint:contents"]
    (root,) = set(containers) - {item for contents in containers.values() for item in contents}

    def columns_of(container):
        contents = containers[container]
        if all(item in views for item in contents):
            return [[views[item] for item in contents]]
        return [column for item in contents for column in columns_of(item)]
    return columns_of(root)


def _view_names(path):
    return sorted(name for column in _layout(path) for _, name, _ in column)


def test_round_trip(tmp_path, no_viewer):
    """Every series comes back at its times (1 ns rounding, far below 1e-12 s here) with its values,
    NaN included, and the write leaves only the target file."""
    t, series = _series()
    path = write_recording(tmp_path / "run.rrd", Recording(t, series))
    got = read_recording(path)
    assert set(got) == set(series)
    for name, values in series.items():
        times, stored = got[name]
        np.testing.assert_allclose(times, t, rtol=0, atol=1e-12)
        np.testing.assert_allclose(stored, values, rtol=0, atol=1e-12)
    assert [p.name for p in tmp_path.iterdir()] == ["run.rrd"]


def test_default_blueprint_has_one_view_per_group(tmp_path):
    """Without titles, one time-series view per first path segment, rooted there, in one column."""
    t, series = _series(10)
    assert default_groups(series) == {"position": ["position/table", "position/part"],
                                      "force": ["force"], "mode": ["mode"]}
    path = write_recording(tmp_path / "run.rrd", Recording(t, series))
    assert _layout(path) == [[("TimeSeries", g, f"/{g}") for g in ("position", "force", "mode")]]


def test_titles_order_the_views_and_markers_join_their_plot(tmp_path):
    """Titled plots come first in the order of the titles; markers, logs and documents sit in their
    plot, the text-log view and document views; another timeline name holds all the data."""
    t, series = _series(10)
    recording = Recording(t, series, timeline="tau", view_titles={"mode": "slip mode", "position": "x and y"},
                          markers={"position/events/stick": (t[[2, 5]], np.zeros(2))},
                          logs={"events": LogEntries(t[[2, 5]], ["a", "b"], ["INFO", "WARN"])},
                          documents={"notes": ("# notes", "text/markdown")})
    path = write_recording(tmp_path / "run.rrd", recording)
    assert _layout(path) == [
        [("TimeSeries", "slip mode", "/mode"), ("TimeSeries", "x and y", "/position"),
         ("TimeSeries", "force", "/force")],
        [("TextDocument", "notes", "/notes"), ("TextLog", "log", "/")],
    ]
    assert read_recording(path) == {}
    back = read_recording(path, timeline="tau")
    assert set(back) == {*series, "position/events/stick"}
    np.testing.assert_array_equal(back["position/events/stick"][0], t[[2, 5]])
    logs = read_logs(path, timeline="tau")["events"]
    assert (logs.texts, logs.levels) == (["a", "b"], ["INFO", "WARN"])
    assert read_documents(path) == {"notes": "# notes"}


def test_period_timeline_numbers_every_sample_and_log_line(tmp_path):
    """With a period, each sample and log line also carries floor(t / period) on the sequence
    timeline "period", beside its time."""
    t, series = _series(50)
    period = 0.013
    recording = Recording(t, series, period=period, logs={"events": LogEntries(t[[0, 49]], ["a", "b"], ["INFO"] * 2)})
    path = write_recording(tmp_path / "run.rrd", recording)
    numbers, values = read_recording(path, timeline=PERIOD_TIMELINE)["position/part"]
    np.testing.assert_array_equal(numbers, np.floor(t / period))
    assert numbers.dtype.kind == "i" and numbers[-1] > numbers[0]
    np.testing.assert_array_equal(values, series["position/part"])
    np.testing.assert_array_equal(read_logs(path, timeline=PERIOD_TIMELINE)["events"].times, numbers[[0, -1]])


@pytest.mark.parametrize("extra, message", [
    ({"series": {"x": np.zeros(3)}}, "shape"),
    ({"series": {"bad name": np.zeros(4)}}, "series name"),
    ({"series": {"/x": np.zeros(4)}}, "series name"),
    ({"view_titles": {"v": "velocity"}}, "not recorded"),
    ({"markers": {"x/stick": (np.zeros(2), np.zeros(3))}}, "marker 'x/stick' has 3 values at 2 times"),
    ({"markers": {"x": (np.zeros(1), np.zeros(1))}}, "used twice"),
    ({"logs": {"log": LogEntries(np.zeros(1), ["a"], ["LOUD"])}}, "unknown level"),
    ({"logs": {"log": LogEntries(np.zeros(2), ["a"], ["INFO"])}}, "2 times, 1 texts"),
    ({"documents": {"doc": ("text", "text/html")}}, "media type"),
    ({"period": 0.0}, "period must be a positive"),
])
def test_invalid_input_is_rejected(tmp_path, extra, message):
    """Each malformed part is named before anything is written."""
    fields = {"series": {"x": np.zeros(4)}, **extra}
    with pytest.raises(ValueError, match=message):
        write_recording(tmp_path / "r.rrd", Recording(np.arange(4.0), **fields))
    with pytest.raises(TypeError, match="needs a Recording"):
        write_recording(tmp_path / "r.rrd", {"x": np.zeros(4)})
    assert list(tmp_path.iterdir()) == []


def test_failure_mid_write_leaves_nothing(tmp_path, monkeypatch):
    """An error while encoding keeps the previous file and leaves no temporary file."""
    target = tmp_path / "run.rrd"
    recording = Recording(*_series(10))
    write_recording(target, recording)
    before = target.read_bytes()

    def broken(**kwargs):
        raise RuntimeError("encoder failed")
    monkeypatch.setattr(rr.Scalars, "columns", broken)
    with pytest.raises(RuntimeError, match="encoder failed"):
        write_recording(target, recording)
    assert target.read_bytes() == before
    assert [p.name for p in tmp_path.iterdir()] == ["run.rrd"]


def test_heavy_libraries_load_lazily():
    """Importing the package, the HDF5 and recording modules loads neither rerun nor matplotlib."""
    code = ("import sys, selfalign, selfalign.io.hdf5, selfalign.io.recording, selfalign.io.simulation_result, "
            "figcheck; print(sorted(m for m in ('rerun', 'matplotlib') if m in sys.modules))")
    out = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True, check=True,
                         cwd=Path(__file__).parent)
    assert out.stdout.strip() == "[]"


def test_recording_id_follows_the_content(tmp_path):
    """Two writes of the same recording carry the same recording id (derived from the
    content, not random), and any other value, log text or period gives another id."""
    t, series = _series(10)
    logs = {"events": LogEntries(t[:1], ["a"], ["INFO"])}
    first = content_id(Recording(t, series, logs=logs))
    assert first == content_id(Recording(t.copy(), {k: v.copy() for k, v in series.items()}, logs=dict(logs)))
    changed = {k: v + (k == sorted(series)[0]) * 1e-12 for k, v in series.items()}
    other_log = {"events": LogEntries(t[:1], ["b"], ["INFO"])}
    others = [Recording(t, changed, logs=logs), Recording(t, series, logs=other_log),
              Recording(t, series, logs=logs, period=1.0)]
    assert len({first, *map(content_id, others)}) == 4
    for name in ("a.rrd", "b.rrd"):
        write_recording(tmp_path / name, Recording(t, series, logs=logs))
    ids = [[e.recording_id for e in RrdReader(tmp_path / name).recordings()] for name in ("a.rrd", "b.rrd")]
    assert ids == [[str(first)], [str(first)]]


@pytest.fixture(scope="module")
def stop_zone(repo, tmp_path_factory):
    """The stop-zone scene (stick, slip and a zone entry, ending in an accumulation) simulated with its
    event log, stored as HDF5 and read back, and its recording written twice."""
    scene = load_scene(repo / "workflow/scenes/stop_zone.yaml")
    folder = tmp_path_factory.mktemp("stop_zone")
    write_h5(folder / "stop_zone.h5", *trajectory_content(simulate(scene), scene))
    result = read_h5(folder / "stop_zone.h5")
    paths = [write_recording(folder / name, simulation_recording(read_h5(folder / "stop_zone.h5")))
             for name in ("a.rrd", "b.rrd")]
    return scene, result, paths


def test_simulation_recording_logs_every_event(stop_zone):
    """The text log "events" has one line per event of the HDF5 log, at its time, in order; the
    mass's events are marked on the x and x' plots at their times and values, by label."""
    scene, result, (path, _) = stop_zone
    events = result["groups"]["events"]["datasets"]
    kinds = np.bincount(events["kind"], minlength=len(EventKind))
    assert kinds[EventKind.STICK] > 1 and kinds[EventKind.SLIP] > 1 and kinds[EventKind.ZONE] == 1
    logs = read_logs(path)
    np.testing.assert_allclose(logs["events"].times, events["t"], rtol=0, atol=1e-9)
    assert [text.split(": ", 1)[1].split(" ")[0] for text in logs["events"].texts] == [
        {0: "table", 1: "stick", 2: "slip", 4: "zone"}[k] for k in events["kind"]]
    assert logs["events"].levels == ["DEBUG" if k == EventKind.SWITCH else "INFO" for k in events["kind"]]
    back = read_recording(path)
    for label, kind in (("stick", EventKind.STICK), ("slip_forward", EventKind.SLIP), ("zone_entry", EventKind.ZONE)):
        chosen = events["kind"] == kind
        for plot, column in (("position", "x"), ("velocity", "v")):
            times, values = back[f"{plot}/events/{label}"]
            np.testing.assert_allclose(times, events["t"][chosen], rtol=0, atol=1e-9)
            np.testing.assert_array_equal(values, events[column][chosen])
    assert not any("switch" in name for name in back)


def test_simulation_recording_ends_at_the_accumulation_limit(stop_zone):
    """The outcome is logged at t_end and marked at the accumulation limit x_stick_min = 0.54 (eq. 41),
    where mu_bar(x) of the recorded friction plot reaches max|y''| = 2.2."""
    scene, result, (path, _) = stop_zone
    attrs = result["attrs"]
    assert Status(attrs["status"]) is Status.ACCUMULATION
    outcome = read_logs(path)["outcome"]
    assert outcome.texts == [attrs["message"]] and outcome.times == pytest.approx([attrs["t_end"]], abs=1e-9)
    back = read_recording(path)
    times, limit = back["position/events/accumulation_limit"]
    assert limit.tolist() == [attrs["x_end"]] and attrs["x_end"] == pytest.approx(0.54, abs=1e-12)
    x, mu = back["position/x"][1], back["friction/mu_bar"][1]
    assert np.all(mu[x <= scene.surface.x_mu] == 1.0) and mu[-1] == pytest.approx(2.2, abs=1e-9)


def test_simulation_recording_shows_scene_and_plots(stop_zone):
    """The scene document is the stored scene YAML, the parameters table names the profile and the
    outcome; x, x', y'' and friction are stacked in this order beside documents and log; every sample
    has its period on the "period" timeline."""
    scene, result, (path, _) = stop_zone
    docs = read_documents(path)
    assert docs["scene"] == result["attrs"]["scene"] and yaml.safe_load(docs["scene"])["name"] == "stop_zone"
    assert "| profile | kind = three_phase, dt = 1.05" in docs["parameters"]
    assert f"| outcome | accumulation: {result['attrs']['message']} |" in docs["parameters"]
    plots, side = _layout(path)
    assert [origin for _, _, origin in plots] == ["/position", "/velocity", "/acceleration", "/friction", "/mode"]
    assert {kind for kind, _, _ in plots} == {"TimeSeries"}
    assert side == [("TextDocument", "scene", "/scene"), ("TextDocument", "parameters", "/parameters"),
                    ("TextLog", "log", "/")]
    t = result["groups"]["series"]["datasets"]["t"]
    numbers = read_recording(path, timeline=PERIOD_TIMELINE)["position/x"][0]
    np.testing.assert_array_equal(numbers, np.floor(np.sort(t) / scene.profile.dt))
    assert numbers[-1] == result["attrs"]["period_end"]


def test_simulation_recording_id_is_reproducible(stop_zone):
    """Two recordings of one result carry the same recording id and the same series and logs."""
    _, _, (first, second) = stop_zone
    ids = [[e.recording_id for e in RrdReader(path).recordings()] for path in (first, second)]
    assert ids[0] == ids[1] and len(ids[0]) == 1
    series = [read_recording(path) for path in (first, second)]
    assert set(series[0]) == set(series[1])
    for name, (times, values) in series[0].items():
        np.testing.assert_array_equal(series[1][name][0], times)
        np.testing.assert_array_equal(series[1][name][1], values)
    logs = [read_logs(path) for path in (first, second)]
    assert {name: (entries.texts, entries.times.tolist()) for name, entries in logs[0].items()} == {
        name: (entries.texts, entries.times.tolist()) for name, entries in logs[1].items()}
