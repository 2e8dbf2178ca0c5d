import math
import time

import h5py
import numpy as np
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st

import selfalign
from selfalign.io import hdf5 as results
from selfalign.io.hdf5 import atomic_path, atomic_write, read_h5, write_h5


def test_round_trip_datasets_attrs_groups(tmp_path):
    # Dataset names from the registry (write_h5 refuses others), one per kind of array.
    datasets = {
        "t": np.linspace(0.0, 1.0, 7).reshape(7, 1),
        "moreau_steps": np.arange(5, dtype=np.int32),
        "valid": np.array([True, False]),
        "methods": np.array(["stick", "slip"]),
        "dt": 2.5,
        "switch_times": np.zeros(0),
    }
    attrs = {
        "int": 3, "float": 0.25, "str": "exact", "bool": True, "ints": [1, 2, 3], "floats": [0.5, 1.5],
        "dict": {"kind": "three_phase", "dt": 1.0, "nested": {"a": [1, 2]}}, "none": None, "empty": [],
        "mixed": [1, 2.5], "strings": ["a", "b"], "nested": [[1, 2], [3]], "tricky": "json:not json",
        "huge": 2**70, "bools": [True, False], "unicode": "μ = 0.3", "tuple": (1, 2),
    }
    groups = {
        "events": {"datasets": {"t": np.array([0.1, 0.2])}, "attrs": {"count": 2},
                   "groups": {"inner": {"attrs": {"note": None}}}},
        "bare": {},
    }
    path = write_h5(tmp_path / "run.h5", datasets, attrs, groups)
    got = read_h5(path)

    assert set(got["datasets"]) == set(datasets)
    for name, value in datasets.items():
        assert np.array_equal(got["datasets"][name], np.asarray(value)), name
        assert got["datasets"][name].shape == np.shape(value), name
    assert got["datasets"]["moreau_steps"].dtype == np.int32
    assert got["datasets"]["methods"].tolist() == ["stick", "slip"]

    expected = {**attrs, "tuple": [1, 2], results.VERSION_ATTR: selfalign.__version__,
                results.COMMIT_ATTR: results.source_commit()}
    assert got["attrs"] == expected
    assert all(type(got["attrs"][k]) is type(expected[k]) for k in expected)

    events = got["groups"]["events"]
    assert np.array_equal(events["datasets"]["t"], [0.1, 0.2])
    assert events["attrs"] == {"count": 2}
    assert events["groups"]["inner"] == {"datasets": {}, "attrs": {"note": None}, "groups": {}}
    assert got["groups"]["bare"] == {"datasets": {}, "attrs": {}, "groups": {}}


def test_native_storage_of_simple_attrs(tmp_path):
    """Simple values stay readable by any HDF5 tool; only the rest is JSON."""
    path = write_h5(tmp_path / "a.h5", {}, {"ints": [1, 2], "x": 1.5, "d": {"k": 1}})
    with h5py.File(path) as f:
        assert f.attrs["ints"].dtype == np.int64
        assert f.attrs["x"] == 1.5
        assert f.attrs["d"] == 'json:{"k": 1}'


def test_non_finite_attrs(tmp_path):
    attrs = {"nan": math.nan, "inf": -math.inf, "in_dict": {"v": math.nan}}
    got = read_h5(write_h5(tmp_path / "a.h5", {}, attrs))["attrs"]
    assert math.isnan(got["nan"]) and got["inf"] == -math.inf and math.isnan(got["in_dict"]["v"])


json_values = st.recursive(
    st.none() | st.booleans() | st.integers() | st.floats(allow_nan=False) | st.text(),
    lambda inner: st.lists(inner, max_size=4) | st.dictionaries(st.text(), inner, max_size=4),
    max_leaves=12,
)


@settings(max_examples=60, deadline=None)
@given(value=json_values)
def test_any_json_attr_round_trips(tmp_path_factory, value):
    path = tmp_path_factory.mktemp("h") / "a.h5"
    assert read_h5(write_h5(path, {}, {"v": value}))["attrs"]["v"] == value


def test_version_is_reserved(tmp_path):
    with pytest.raises(ValueError, match="reserved"):
        write_h5(tmp_path / "a.h5", {}, {results.VERSION_ATTR: "1"})


@pytest.mark.parametrize("kwargs", [
    {"datasets": {"a/b": [1]}},
    {"datasets": {"t": [1]}, "groups": {"t": {}}},
    {"datasets": {}, "groups": {"g": {"dataset": {}}}},
])
def test_invalid_layout_is_rejected(tmp_path, kwargs):
    with pytest.raises(ValueError):
        write_h5(tmp_path / "a.h5", **kwargs)
    assert list(tmp_path.iterdir()) == []


def test_identical_inputs_give_identical_bytes(tmp_path):
    content = ({"t": np.arange(10.0)}, {"p": {"dt": 1.0}}, {"g": {"datasets": {"y": [1, 2]}}})
    a = write_h5(tmp_path / "a.h5", *content)
    # HDF5 timestamps have one-second resolution: make sure a second boundary passes.
    time.sleep(1.0 - time.time() % 1.0 + 0.01)
    b = write_h5(tmp_path / "b.h5", *content)
    assert a.read_bytes() == b.read_bytes()
    with h5py.File(a) as f:
        assert h5py.h5o.get_info(f["t"].id).ctime == 0
        assert h5py.h5o.get_info(f["g/y"].id).ctime == 0


def test_temporary_file_is_hidden_and_beside_target(tmp_path):
    seen = []

    def writer(tmp):
        seen.append(tmp)
        tmp.write_text("ok")

    target = tmp_path / "sub" / "out.txt"
    assert atomic_write(target, writer) == target
    assert target.read_text() == "ok"
    (tmp,) = seen
    assert tmp.parent == target.parent and tmp.name.startswith(".") and tmp.name.endswith(".tmp")
    assert not tmp.exists()


def _fail_midway(tmp):
    tmp.write_bytes(b"partial")
    raise RuntimeError("disk full")


def test_failed_write_leaves_nothing(tmp_path):
    with pytest.raises(RuntimeError, match="disk full"):
        atomic_write(tmp_path / "out.h5", _fail_midway)
    assert list(tmp_path.iterdir()) == []


def test_failed_write_keeps_existing_file(tmp_path):
    target = write_h5(tmp_path / "out.h5", {"t": [1.0, 2.0]})
    before = target.read_bytes()
    with pytest.raises(RuntimeError):
        with atomic_path(target) as tmp:
            _fail_midway(tmp)
    with pytest.raises(TypeError):
        write_h5(target, {"t": [3.0]}, {"bad": object()})
    assert target.read_bytes() == before
    assert [p.name for p in tmp_path.iterdir()] == ["out.h5"]


def test_successful_write_replaces_existing_file(tmp_path):
    target = write_h5(tmp_path / "out.h5", {"t": [1.0]})
    write_h5(target, {"t": [2.0, 3.0]})
    assert read_h5(target)["datasets"]["t"].tolist() == [2.0, 3.0]
    assert [p.name for p in tmp_path.iterdir()] == ["out.h5"]
