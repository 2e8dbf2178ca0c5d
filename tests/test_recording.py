import subprocess
import sys
from pathlib import Path

import numpy as np
import pytest
import rerun as rr
from rerun.chunk import RrdReader

from selfalign.io.recording import content_id, default_groups, read_recording, write_recording


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


def _view_names(path):
    reader = RrdReader(path)
    (blueprint,) = reader.blueprints()
    names = []
    for chunk in reader.stream(store=blueprint).to_chunks():
        batch = chunk.to_record_batch()
        if "ViewBlueprint:display_name" in batch.schema.names:
            names += batch.column("ViewBlueprint:display_name").flatten().to_pylist()
    return sorted(names)


def test_round_trip(tmp_path, no_viewer):
    t, series = _series()
    path = write_recording(tmp_path / "run.rrd", t, series)
    got = read_recording(path)
    assert set(got) == set(series)
    for name, values in series.items():
        times, stored = got[name]
        np.testing.assert_allclose(times, t, rtol=0, atol=1e-12)
        np.testing.assert_allclose(stored, values, rtol=0, atol=1e-12)
    assert [p.name for p in tmp_path.iterdir()] == ["run.rrd"]


def test_default_blueprint_has_one_view_per_group(tmp_path):
    t, series = _series(10)
    assert default_groups(series) == {"position": ["position/table", "position/part"],
                                      "force": ["force"], "mode": ["mode"]}
    path = write_recording(tmp_path / "run.rrd", t, series)
    assert _view_names(path) == ["force", "mode", "position"]


def test_custom_blueprint_and_timeline(tmp_path):
    t, series = _series(10)
    groups = {"kinematics": ["position/table", "position/part"], "other": ["force", "mode"]}
    path = write_recording(tmp_path / "run.rrd", t, series, timeline="tau", blueprint_groups=groups)
    assert _view_names(path) == ["kinematics", "other"]
    assert read_recording(path) == {}
    assert set(read_recording(path, timeline="tau")) == set(series)


@pytest.mark.parametrize("series, blueprint_groups, message", [
    ({"x": np.zeros(3)}, None, "shape"),
    ({"bad name": np.zeros(4)}, None, "series name"),
    ({"/x": np.zeros(4)}, None, "series name"),
    ({"x": np.zeros(4)}, {"v": ["y"]}, "not recorded"),
])
def test_invalid_input_is_rejected(tmp_path, series, blueprint_groups, message):
    with pytest.raises(ValueError, match=message):
        write_recording(tmp_path / "r.rrd", np.arange(4.0), series, blueprint_groups=blueprint_groups)
    assert list(tmp_path.iterdir()) == []


def test_failure_mid_write_leaves_nothing(tmp_path, monkeypatch):
    target = tmp_path / "run.rrd"
    t, series = _series(10)
    write_recording(target, t, series)
    before = target.read_bytes()

    def broken(**kwargs):
        raise RuntimeError("encoder failed")
    monkeypatch.setattr(rr.Scalars, "columns", broken)
    with pytest.raises(RuntimeError, match="encoder failed"):
        write_recording(target, t, series)
    assert target.read_bytes() == before
    assert [p.name for p in tmp_path.iterdir()] == ["run.rrd"]


def test_heavy_libraries_load_lazily():
    code = ("import sys, selfalign, selfalign.io.hdf5, selfalign.io.recording, figcheck; "
            "print(sorted(m for m in ('rerun', 'matplotlib') if m in sys.modules))")
    out = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True, check=True,
                         cwd=Path(__file__).parent)
    assert out.stdout.strip() == "[]"


def test_recording_id_follows_the_content(tmp_path):
    """Issue 11.1: two writes of the same series carry the same recording id (derived from the
    content, not random), and other values give another id."""
    t, series = _series(10)
    first = content_id("selfalign", "time", t, series)
    assert first == content_id("selfalign", "time", t.copy(), {k: v.copy() for k, v in series.items()})
    changed = {k: v + (k == sorted(series)[0]) * 1e-12 for k, v in series.items()}
    assert content_id("selfalign", "time", t, changed) != first
    for name in ("a.rrd", "b.rrd"):
        write_recording(tmp_path / name, t, series)
    ids = [[e.recording_id for e in RrdReader(tmp_path / name).recordings()] for name in ("a.rrd", "b.rrd")]
    assert ids == [[str(first)], [str(first)]]
